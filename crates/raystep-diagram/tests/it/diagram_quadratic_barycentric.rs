//! The quadratic and barycentric diagrams: golden images (light theme, 400×300) and geometry
//! checks of the drawing against the recorded trace.
//!
//! Regenerate the golden images with `UPDATE_GOLDEN=1 cargo test -p raystep-diagram --test it diagram_quadratic_barycentric::`
//! and look at every one before committing it.

use crate::common;
use common::assert_golden;

use raystep_core::accel::SceneAccel;
use raystep_core::record::{Step, Trace};
use raystep_core::scene::{Scene, load_file};
use raystep_core::shapes::{RootChoice, SphereCase, TriangleMethod, TriangleTest};
use raystep_core::trace::Tracer;
use raystep_diagram::canvas::Rgba;
use raystep_diagram::{
    self as diagram, Canvas, DiagramKind, Theme, ViewOptions, barycentric, quadratic,
};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn scene(name: &str, triangle_method: Option<TriangleMethod>) -> Scene {
    let mut s = load_file(&root().join("scenes").join(name)).expect("shipped scene loads");
    if let Some(m) = triangle_method {
        s.settings.triangle_method = m;
    }
    s
}

fn trace(s: &Scene, x: u32, y: u32) -> Trace {
    Tracer::new(s, &SceneAccel::build(s).0).record(x, y, 0)
}

fn opts(focus: Option<usize>) -> ViewOptions {
    ViewOptions {
        width: 400,
        height: 300,
        theme: Theme::LIGHT,
        focus,
        ..ViewOptions::default()
    }
}

/// The timeline index of the first triangle test `pick` accepts.
fn triangle_step(t: &Trace, pick: impl Fn(&TriangleTest<f32>) -> bool) -> usize {
    t.timeline()
        .iter()
        .position(|(_, s)| matches!(&s.step, Step::Triangle { test, .. } if pick(test)))
        .expect("the trace has such a triangle test")
}

// ---------------------------------------------------------------------------------------------
// Golden images.

fn golden_path_exists(name: &str) -> bool {
    Path::new(&root().join("tests/golden").join(format!("{name}.png"))).exists()
}

#[test]
fn golden_quadratic_hit() {
    let t = trace(&scene("first-sphere.toml", None), 160, 120);
    let c = diagram::draw(&t, DiagramKind::Quadratic, &opts(None)).unwrap();
    assert_golden(&c, "quadratic_hit");
}

/// The panel of values is drawn where its text fits at the labels' size (the command line's
/// 800×600) and left out on a canvas too short for it, whose plot then takes the width.
#[test]
fn quadratic_panel_only_where_its_text_is_readable() {
    let t = trace(&scene("first-sphere.toml", None), 160, 120);
    let big = quadratic::layout(
        &t,
        &ViewOptions {
            width: 800,
            height: 600,
            ..opts(None)
        },
    )
    .unwrap();
    assert!(big.panel[2] - big.panel[0] > 150.0, "{:?}", big.panel);
    let small = quadratic::layout(&t, &opts(None)).unwrap();
    assert!(small.panel[2] < small.panel[0], "{:?}", small.panel);
    let f = small.frame.unwrap();
    assert!(f.right > 0.9 * 400.0, "the plot takes the width: {f:?}");
}

#[test]
fn golden_quadratic_miss() {
    let t = trace(&scene("first-sphere.toml", None), 10, 10);
    let l = quadratic::layout(&t, &opts(None)).unwrap();
    assert_eq!(
        l.test.case,
        SphereCase::Miss,
        "pixel (10, 10) should miss the ball"
    );
    let c = diagram::draw(&t, DiagramKind::Quadratic, &opts(None)).unwrap();
    assert_golden(&c, "quadratic_miss");
}

#[test]
fn golden_barycentric_hit() {
    let t = trace(
        &scene("triangles.toml", Some(TriangleMethod::MollerTrumbore)),
        100,
        120,
    );
    let k = triangle_step(&t, |x| x.stopped_at == 12);
    let c = diagram::draw(&t, DiagramKind::Barycentric, &opts(Some(k))).unwrap();
    assert_golden(&c, "barycentric_hit");
}

#[test]
fn golden_barycentric_stopped_at_11() {
    let t = trace(
        &scene("triangles.toml", Some(TriangleMethod::MollerTrumbore)),
        100,
        120,
    );
    let k = triangle_step(&t, |x| x.stopped_at == 11);
    let c = diagram::draw(&t, DiagramKind::Barycentric, &opts(Some(k))).unwrap();
    assert_golden(&c, "barycentric_stopped_at_11");
}

#[test]
fn golden_barycentric_stopped_at_8() {
    let t = trace(
        &scene("triangles.toml", Some(TriangleMethod::MollerTrumbore)),
        200,
        120,
    );
    let k = triangle_step(&t, |x| x.stopped_at == 8);
    let c = diagram::draw(&t, DiagramKind::Barycentric, &opts(Some(k))).unwrap();
    assert_golden(&c, "barycentric_stopped_at_8");
}

#[test]
fn golden_barycentric_watertight_outside() {
    let t = trace(
        &scene("triangles.toml", Some(TriangleMethod::Watertight)),
        100,
        120,
    );
    let k = triangle_step(&t, |x| x.stopped_at == 8);
    let c = diagram::draw(&t, DiagramKind::Barycentric, &opts(Some(k))).unwrap();
    assert_golden(&c, "barycentric_watertight_outside");
}

#[test]
fn goldens_are_committed() {
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        return;
    }
    for name in [
        "quadratic_hit",
        "quadratic_miss",
        "barycentric_hit",
        "barycentric_stopped_at_11",
        "barycentric_stopped_at_8",
        "barycentric_watertight_outside",
    ] {
        assert!(
            golden_path_exists(name),
            "tests/golden/{name}.png is missing"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Geometry: the drawing agrees with the record.

fn near(a: Rgba, b: Rgba, tol: u8) -> bool {
    (0..3).all(|i| a[i].abs_diff(b[i]) <= tol)
}

/// Whether some pixel within `r` of (x, y) has colour `want` (± tol).
fn colour_near(c: &Canvas, p: [f32; 2], r: i32, want: Rgba, tol: u8) -> bool {
    (-r..=r).any(|dy| {
        (-r..=r).any(|dx| {
            let (x, y) = (p[0].round() as i32 + dx, p[1].round() as i32 + dy);
            x >= 0
                && y >= 0
                && c.pixel(x as u32, y as u32)
                    .is_some_and(|px| near(px, want, tol))
        })
    })
}

#[test]
fn quadratic_chosen_root_sits_at_recorded_t_on_the_axis() {
    let t = trace(&scene("first-sphere.toml", None), 160, 120);
    for (w, h) in [(400, 300), (800, 600)] {
        let o = ViewOptions {
            width: w,
            height: h,
            ..opts(None)
        };
        let l = quadratic::layout(&t, &o).unwrap();
        let test = l.test;
        assert_eq!(test.choice, RootChoice::NearRoot);
        let f = l.frame.expect("finite coefficients plot");
        let t_hit = test.t.expect("pixel (160, 120) hits the ball");
        let p = l.chosen.expect("a hit has a chosen-root marker");
        // On the t axis, at the recorded t, inside the plot.
        assert!(
            (p[0] - f.x(t_hit as f64)).abs() < 1e-3 && (p[1] - f.y(0.0)).abs() < 1e-3,
            "{p:?}"
        );
        assert!((f.t_at(p[0]) - t_hit as f64).abs() < 1e-4 * (f.t_range[1] - f.t_range[0]));
        assert!(
            p[0] > f.left && p[0] < f.right && p[1] > f.top && p[1] < f.bottom,
            "{p:?} outside {f:?}"
        );
        // f(t) = 0 there, relative to the size of its terms.
        let (a, b, c) = (test.a as f64, test.b as f64, test.c as f64);
        let th = t_hit as f64;
        let scale = (a * th * th).abs() + (b * th).abs() + c.abs();
        assert!(
            quadratic::f_of(&test, th).abs() <= 1e-5 * scale,
            "f({th}) = {}",
            quadratic::f_of(&test, th)
        );
        // The range shows t = 0 and both roots.
        let [r0, r1] = test.roots.unwrap();
        for v in [0.0, r0 as f64, r1 as f64] {
            assert!(
                v > f.t_range[0] && v < f.t_range[1],
                "{v} not in {:?}",
                f.t_range
            );
        }
        // The chosen root is t₀ and its marker is drawn in the hit colour; the other root's is not.
        assert_eq!(t_hit, r0);
        let canvas = diagram::draw(&t, DiagramKind::Quadratic, &o).unwrap();
        assert!(
            colour_near(&canvas, p, 1, Theme::LIGHT.hit, 40),
            "no hit-coloured marker at {p:?}"
        );
        let q = l.roots.unwrap()[1];
        assert!(!near(
            canvas.pixel(q[0] as u32, q[1] as u32).unwrap(),
            Theme::LIGHT.hit,
            40
        ));
        // The curve goes through the plotted points: at the vertex, below the axis.
        let tv = -b / (2.0 * a);
        let pv = [f.x(tv), f.y(quadratic::f_of(&test, tv))];
        assert!(pv[1] > f.y(0.0), "the vertex of a hit lies below the axis");
        assert!(
            colour_near(&canvas, pv, 2, Theme::LIGHT.reflect, 60),
            "no curve at the vertex {pv:?}"
        );
    }
}

#[test]
fn quadratic_miss_has_no_roots_and_shows_the_vertex_above_the_axis() {
    let t = trace(&scene("first-sphere.toml", None), 10, 10);
    let l = quadratic::layout(&t, &opts(None)).unwrap();
    assert_eq!(
        (l.test.roots, l.test.t, l.chosen, l.roots),
        (None, None, None, None)
    );
    let f = l.frame.unwrap();
    let (a, b) = (l.test.a as f64, l.test.b as f64);
    let tv = -b / (2.0 * a);
    assert!(tv > f.t_range[0] && tv < f.t_range[1] && 0.0 > f.t_range[0]);
    let fv = quadratic::f_of(&l.test, tv);
    assert!(fv > 0.0 && f.y(fv) < f.y(0.0) && f.y(fv) > f.top);
    let canvas = quadratic::draw(&t, &opts(None));
    assert!(
        !colour_near(&canvas, [f.x(tv), f.y(0.0)], 3, Theme::LIGHT.hit, 40),
        "a miss marks no hit"
    );
}

#[test]
fn quadratic_focus_picks_the_shadow_rays_test() {
    let t = trace(&scene("first-sphere.toml", None), 160, 120);
    let tl = t.timeline();
    let shadow = tl
        .iter()
        .position(|(r, s)| r.depth == 1 && matches!(s.step, Step::Sphere { .. }))
        .expect("the shadow ray tests the ball");
    let l = quadratic::layout(&t, &opts(Some(shadow))).unwrap();
    assert_eq!(l.step, shadow);
    assert_eq!(l.ray, "shadow ray (depth 1)");
    assert_eq!(l.test.choice, RootChoice::Behind);
    assert!(l.interval.1.is_finite(), "a shadow ray ends at its light");
    // A later focus on a non-sphere step keeps the last sphere test before it.
    let after = quadratic::layout(&t, &opts(Some(tl.len() - 1))).unwrap();
    assert_eq!(after.step, shadow);
    // The primary ray's test shows its interval shrinking to nothing before it: (0, ∞).
    let first = quadratic::layout(&t, &opts(None)).unwrap();
    assert_eq!(first.interval, (0.0, f32::INFINITY));
    assert_eq!(first.ray, "primary ray");
}

/// Whether p lies inside triangle abc (either winding).
fn inside(p: [f32; 2], [a, b, c]: [[f32; 2]; 3]) -> bool {
    let cross = |o: [f32; 2], u: [f32; 2], v: [f32; 2]| {
        (u[0] - o[0]) * (v[1] - o[1]) - (u[1] - o[1]) * (v[0] - o[0])
    };
    let (d0, d1, d2) = (cross(a, b, p), cross(b, c, p), cross(c, a, p));
    (d0 >= 0.0 && d1 >= 0.0 && d2 >= 0.0) || (d0 <= 0.0 && d1 <= 0.0 && d2 <= 0.0)
}

fn dist(a: [f32; 2], b: [f32; 2]) -> f64 {
    (((a[0] - b[0]) as f64).powi(2) + ((a[1] - b[1]) as f64).powi(2)).sqrt()
}

fn dist3(a: [f64; 3], b: [f32; 3]) -> f64 {
    (0..3)
        .map(|i| (a[i] - b[i] as f64).powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn barycentric_point_is_inside_the_region_exactly_when_the_test_hit() {
    let s = scene("triangles.toml", Some(TriangleMethod::MollerTrumbore));
    let mut checked = [0, 0];
    for (x, y) in [
        (100, 120),
        (90, 110),
        (80, 130),
        (100, 100),
        (200, 120),
        (230, 130),
        (250, 120),
    ] {
        let t = trace(&s, x, y);
        let tl = t.timeline();
        for (k, (ray, rec)) in tl.iter().enumerate() {
            let Step::Triangle { vertices, test, .. } = &rec.step else {
                continue;
            };
            let l = barycentric::layout(&t, &opts(Some(k))).unwrap();
            assert_eq!(l.step, k);
            let (Some(u), Some(v)) = (test.u, test.v) else {
                assert!(
                    l.point_px.is_none(),
                    "({x}, {y}) step {k}: no P without u and v"
                );
                continue;
            };
            // Every Möller–Trumbore test that computed v stopped at 11 or hit.
            assert!(matches!(test.stopped_at, 11 | 12));
            let p = l.point_px.unwrap();
            // P = P0 + u·(P1 − P0) + v·(P2 − P0) on the canvas.
            let [a, b, c] = l.vertex_px;
            let want = [
                a[0] + u * (b[0] - a[0]) + v * (c[0] - a[0]),
                a[1] + u * (b[1] - a[1]) + v * (c[1] - a[1]),
            ];
            assert!(dist(p, want) < 1e-2, "{p:?} vs {want:?}");
            // Inside the drawn triangle exactly when the test hit.
            let hit = test.stopped_at == 12;
            assert_eq!(
                inside(p, l.vertex_px),
                hit,
                "({x}, {y}) step {k}: u = {u}, v = {v}"
            );
            assert_eq!(l.hit(), hit);
            checked[hit as usize] += 1;
            // The drawing is the triangle's plane without distortion: each vertex's distance to
            // the point where the ray meets the plane (S + t*·Q) is the drawn distance / scale.
            let ts = test.t_star.unwrap() as f64;
            let q = [0, 1, 2].map(|i| ray.origin[i] as f64 + ts * ray.direction[i] as f64);
            let size = dist3(
                [
                    vertices[0][0] as f64,
                    vertices[0][1] as f64,
                    vertices[0][2] as f64,
                ],
                vertices[1],
            );
            if l.point_in_view {
                for (i, vp) in l.vertex_px.iter().enumerate() {
                    let drawn = dist(p, *vp) / l.scale as f64;
                    let real = dist3(q, vertices[i]);
                    assert!(
                        (drawn - real).abs() < 2e-3 * size.max(real),
                        "vertex {i}: {drawn} vs {real}"
                    );
                }
                let d = l.drawing;
                assert!(
                    p[0] >= d[0] && p[0] <= d[2] && p[1] >= d[1] && p[1] <= d[3],
                    "P off the drawing"
                );
                // P is drawn in the hit colour for a hit, in the ray colour for a miss.
                let canvas = barycentric::draw(&t, &opts(Some(k)));
                let col = if hit {
                    Theme::LIGHT.hit
                } else {
                    Theme::LIGHT.ray
                };
                assert!(
                    colour_near(&canvas, p, 1, col, 40),
                    "({x}, {y}) step {k}: P not drawn in {col:?}"
                );
            }
        }
    }
    assert!(
        checked[0] >= 3 && checked[1] >= 3,
        "too few cases: {checked:?} (misses, hits)"
    );
}

#[test]
fn barycentric_stopped_early_places_no_point() {
    let s = scene("triangles.toml", Some(TriangleMethod::MollerTrumbore));
    let t = trace(&s, 200, 120);
    let k = triangle_step(&t, |x| x.stopped_at == 8);
    let l = barycentric::layout(&t, &opts(Some(k))).unwrap();
    assert!(l.test.u.is_some() && l.test.v.is_none());
    assert_eq!(l.point_px, None);
    let canvas = barycentric::draw(&t, &opts(Some(k)));
    let d = l.drawing;
    let hit_pixels = (d[1] as u32..d[3] as u32)
        .flat_map(|y| (d[0] as u32..d[2] as u32).map(move |x| (x, y)))
        .filter(|&(x, y)| near(canvas.pixel(x, y).unwrap(), Theme::LIGHT.hit, 30))
        .count();
    assert_eq!(hit_pixels, 0, "a test that stopped at 8 draws no hit point");
    // Watertight, stopped at 8: neither u nor v.
    let t = trace(
        &scene("triangles.toml", Some(TriangleMethod::Watertight)),
        100,
        120,
    );
    let k = triangle_step(&t, |x| x.stopped_at == 8);
    let l = barycentric::layout(&t, &opts(Some(k))).unwrap();
    assert!(l.test.edges.is_some() && l.test.u.is_none());
    assert_eq!(l.point_px, None);
}

#[test]
fn every_step_draws_in_both_themes_and_sizes() {
    let cases = [
        ("first-sphere.toml", 160, 120, None),
        ("mirror-glass.toml", 160, 120, None),
        ("triangles.toml", 100, 120, Some(TriangleMethod::Watertight)),
        (
            "triangles.toml",
            200,
            120,
            Some(TriangleMethod::MollerTrumbore),
        ),
    ];
    for (name, x, y, m) in cases {
        let t = trace(&scene(name, m), x, y);
        let kinds: Vec<DiagramKind> = diagram::available(&t)
            .into_iter()
            .filter(|k| matches!(k, DiagramKind::Quadratic | DiagramKind::Barycentric))
            .collect();
        assert!(!kinds.is_empty(), "{name}");
        let n = t.timeline().len();
        for kind in kinds {
            for k in (0..n).step_by((n / 12).max(1)) {
                for (theme, w, h) in [(Theme::LIGHT, 400, 300), (Theme::DARK, 800, 600)] {
                    let o = ViewOptions {
                        width: w,
                        height: h,
                        theme,
                        focus: Some(k),
                        ..ViewOptions::default()
                    };
                    let c = diagram::draw(&t, kind, &o).unwrap();
                    assert_eq!((c.width() as u32, c.height() as u32), (w, h));
                    // Something was drawn in ink besides the title.
                    let inked = (0..h)
                        .step_by(2)
                        .flat_map(|yy| (0..w).step_by(2).map(move |xx| (xx, yy)))
                        .filter(|&(xx, yy)| near(c.pixel(xx, yy).unwrap(), theme.ink, 60))
                        .count();
                    assert!(
                        inked > 80,
                        "{name} {kind:?} step {k}: almost blank ({inked})"
                    );
                }
            }
        }
    }
}

/// The quadratic and barycentric titles number the step as the app and `raystep trace` do
/// ("step K of 0–N"), then which test of the trace it is; at the command line's 800×600 (the
/// size of `--animate`'s frames) the step's number is in the title that is drawn, and on a
/// narrow canvas the title drops its details rather than being cut at "(…".
#[test]
fn titles_number_the_step_as_the_app_does() {
    // Lesson 2's pixel: the app lists steps 0–15, and step 11 is the shadow ray's test of
    // "middle", the 4th of its 6 sphere tests (steps 3, 5, 6, 11, 12, 13).
    let t = trace(&scene("three-spheres.toml", None), 150, 110);
    let l = quadratic::layout(&t, &opts(Some(11))).unwrap();
    let titles = quadratic::titles(&t, &l);
    assert!(
        titles[0].ends_with(" · step 11 of 0–15 · test 4 of 6"),
        "{titles:?}"
    );
    assert!(titles[1].ends_with(" · step 11 of 0–15"), "{titles:?}");
    assert!(!titles[2].contains("step"), "{titles:?}");
    let wide = Canvas::new(800, 600, Theme::LIGHT);
    assert!(
        diagram::first_fitting(&wide, &titles).contains(" · step 11 of 0–15"),
        "{titles:?}"
    );
    let wider = Canvas::new(1280, 720, Theme::LIGHT);
    assert_eq!(diagram::first_fitting(&wider, &titles), titles[0]);
    let narrow = Canvas::new(400, 300, Theme::LIGHT);
    assert_eq!(diagram::first_fitting(&narrow, &titles), titles[2]);

    // Lesson 4's pixel with Möller–Trumbore: step 9 is "pyramid south", the 4th triangle test.
    let t = trace(
        &scene("triangles.toml", Some(TriangleMethod::MollerTrumbore)),
        80,
        130,
    );
    let l = barycentric::layout(&t, &opts(Some(9))).unwrap();
    assert_eq!(l.name, "pyramid south");
    let titles = barycentric::titles(&t, &l);
    let n = t.timeline().len();
    assert!(
        titles[0].contains(&format!(" · step 9 of 0–{} · test 4 of ", n - 1)),
        "{titles:?}"
    );
    assert!(diagram::first_fitting(&wide, &titles).contains("step 9 of 0–"));
}

// ---------------------------------------------------------------------------------------------
// A smooth triangle's normals.

/// On the smooth sphere the barycentric view also draws n₀, n₁, n₂ and n_s: their parts along
/// the triangle's plane, whose lengths are √(1 − (n·N)²) for the face's unit normal N, computed
/// here in f64 from the recorded vertices. A flat triangle has none.
#[test]
fn a_smooth_triangle_shows_its_normals_parts_along_its_plane() {
    let s = scene("smooth-shading.toml", None);
    let t = trace(&s, 215, 77);
    let ray = &t.root;
    let hit = ray.hit.as_ref().unwrap().name.clone();
    assert_eq!(hit, "smooth sphere[39]");
    // The primary ray's test of the triangle it hits.
    let tl = t.timeline();
    let k = tl
        .iter()
        .position(|(r, s)| {
            std::ptr::eq(*r, ray)
                && matches!(&s.step, Step::Triangle { name, test, .. } if *name == hit && test.t.is_some())
        })
        .unwrap();
    let Step::Triangle { vertices, .. } = &tl[k].1.step else {
        unreachable!()
    };
    let l = barycentric::layout(&t, &opts(Some(k))).unwrap();
    let n = barycentric::smooth_normals(&t, &l).expect("the smooth sphere's normals");
    let (vn, ns) = ray
        .steps
        .iter()
        .find_map(|s| match &s.step {
            Step::ShadingNormal {
                vertex_normals,
                normal,
                ..
            } => Some((*vertex_normals, *normal)),
            _ => None,
        })
        .unwrap();
    let p = vertices.map(|v| v.map(f64::from));
    let e1 = [0, 1, 2].map(|i| p[1][i] - p[0][i]);
    let e2 = [0, 1, 2].map(|i| p[2][i] - p[0][i]);
    let c = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    let len = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
    let face = c.map(|x| x / len);
    let part = |n: [f32; 3]| {
        let d: f64 = (0..3).map(|i| f64::from(n[i]) * face[i]).sum();
        (1.0 - d * d).max(0.0).sqrt()
    };
    for (got, want) in n.vertex.iter().zip(vn) {
        let g = (got[0] * got[0] + got[1] * got[1]).sqrt();
        assert!((g - part(want)).abs() < 1e-6, "{g} vs {}", part(want));
        assert!(
            g > 0.05,
            "a vertex normal of a coarse sphere leans off the face: {g}"
        );
    }
    let g = (n.blend[0] * n.blend[0] + n.blend[1] * n.blend[1]).sqrt();
    assert!((g - part(ns)).abs() < 1e-6);
    let canvas = diagram::draw(&t, DiagramKind::Barycentric, &opts(Some(k))).unwrap();
    assert_eq!(canvas.width(), 400.0);
    // A flat triangle: nothing to draw.
    let flat = scene("triangles.toml", None);
    let ft = trace(&flat, 160, 120);
    let fk = triangle_step(&ft, |x| x.stopped_at == 12 && x.t.is_some());
    let fl = barycentric::layout(&ft, &opts(Some(fk))).unwrap();
    assert!(barycentric::smooth_normals(&ft, &fl).is_none());
}
