//! The diagrams never panic: every kind draws at every size from 1×1 to the 8192×8192 limit,
//! for every step of traced pixels of every shipped scene, and for scenes whose geometry is
//! astronomically large; the ray tree is a tidy tree (no box on another, every edge drawn from
//! parent to child); each root's label sits by its own dot, under the lessons' names.

use proptest::prelude::*;
use raystep::accel::SceneAccel;
use raystep::diagram::canvas::{Canvas, Theme};
use raystep::diagram::{self, DiagramKind, MAX_SIDE, ViewOptions, quadratic, ray_tree};
use raystep::explain::formula::explain;
use raystep::record::{RayKind, RayRecord, Step, Trace};
use raystep::scene::{Scene, load_file};
use raystep::trace::Tracer;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Every shipped scene (scenes/*.toml), by file name.
fn shipped() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    assert!(v.len() >= 8, "the shipped scenes: {v:?}");
    v
}

fn record(scene: &Scene, x: u32, y: u32) -> Trace {
    let (accel, _) = SceneAccel::build(scene);
    Tracer::new(scene, &accel).record(x, y, 0)
}

/// Several pixels of a scene: the centre, the four quarter points and a corner.
fn pixels(scene: &Scene) -> Vec<(u32, u32)> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    vec![
        (w / 2, h / 2),
        (w / 4, h / 4),
        (3 * w / 4, h / 4),
        (w / 4, 3 * h / 4),
        (3 * w / 4, 3 * h / 4),
        (0, h - 1),
    ]
}

/// The traces of [`pixels`] of every shipped scene (traced once per test binary).
fn traces() -> &'static Vec<(String, Trace)> {
    static T: OnceLock<Vec<(String, Trace)>> = OnceLock::new();
    T.get_or_init(|| {
        shipped()
            .iter()
            .flat_map(|p| {
                let scene = load_file(p).unwrap_or_else(|e| panic!("{e}"));
                let name = p.file_name().unwrap().to_string_lossy().into_owned();
                pixels(&scene)
                    .into_iter()
                    .map(move |(x, y)| (format!("{name} ({x}, {y})"), record(&scene, x, y)))
                    .collect::<Vec<_>>()
            })
            .collect()
    })
}

fn opts(w: u32, h: u32, focus: Option<usize>, scale: f32) -> ViewOptions {
    ViewOptions {
        width: w,
        height: h,
        focus,
        scale,
        ..ViewOptions::default()
    }
}

/// Odd sizes cycled through below: degenerate, thin, small, the app's, large.
const SIZES: [(u32, u32); 9] = [
    (1, 1),
    (2, 700),
    (700, 3),
    (17, 300),
    (64, 64),
    (150, 90),
    (333, 999),
    (520, 380),
    (1280, 720),
];

#[test]
fn every_kind_draws_every_step_of_shipped_traces() {
    let mut drawn = 0usize;
    for (name, tr) in traces() {
        let kinds = diagram::available(tr);
        let n = tr.timeline().len();
        for k in 0..n {
            for (i, kind) in kinds.iter().enumerate() {
                let (w, h) = SIZES[(k + i) % SIZES.len()];
                let scale = [1.0, 1.6, 0.5][(k + 2 * i) % 3];
                let c = diagram::draw(tr, *kind, &opts(w, h, Some(k), scale))
                    .unwrap_or_else(|e| panic!("{name} step {k} {kind:?}: {e}"));
                assert_eq!((c.pixmap.width(), c.pixmap.height()), (w, h));
                drawn += 1;
            }
        }
    }
    assert!(drawn > 1000, "only {drawn} diagrams drawn");
}

#[test]
fn every_kind_draws_at_the_largest_and_smallest_sizes() {
    // One trace per kind that has it.
    let all = traces();
    for kind in DiagramKind::ALL {
        let (name, tr) = all
            .iter()
            .find(|(_, t)| diagram::available(t).contains(&kind))
            .unwrap_or_else(|| panic!("no shipped trace has a {kind:?} diagram"));
        let last = tr.timeline().len() - 1;
        for (w, h) in [(MAX_SIDE, MAX_SIDE), (1, MAX_SIDE), (MAX_SIDE, 1), (1, 1)] {
            let c = diagram::draw(tr, kind, &opts(w, h, Some(last), 1.0))
                .unwrap_or_else(|e| panic!("{name} {kind:?}: {e}"));
            assert_eq!((c.pixmap.width(), c.pixmap.height()), (w, h));
        }
        // Beyond the limit: drawn at the limit, no panic, no 32-GiB pixmap.
        let c = diagram::draw(tr, kind, &opts(u32::MAX, 100_000, None, f32::NAN)).unwrap();
        assert_eq!((c.pixmap.width(), c.pixmap.height()), (MAX_SIDE, MAX_SIDE));
        let c = diagram::draw(tr, kind, &opts(0, 0, None, 1e30)).unwrap();
        assert_eq!((c.pixmap.width(), c.pixmap.height()), (1, 1));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Any trace, step, kind, size up to 2048 and scale.
    #[test]
    fn any_size_any_step_any_kind(
        t in 0usize..1000,
        step in 0.0f64..1.0,
        kind in 0usize..5,
        w in prop_oneof![1u32..64, 64u32..2048],
        h in prop_oneof![1u32..64, 64u32..2048],
        scale in 0.2f32..4.0,
        angle in -180.0f32..180.0,
        top_down in any::<bool>(),
    ) {
        let all = traces();
        let (name, tr) = &all[t % all.len()];
        let kinds = diagram::available(tr);
        let kind = kinds[kind % kinds.len()];
        let n = tr.timeline().len();
        let focus = ((n as f64 * step) as usize).min(n - 1);
        let o = ViewOptions {
            slice_angle: angle,
            top_down,
            ..opts(w, h, Some(focus), scale)
        };
        let c = diagram::draw(tr, kind, &o).map_err(|e| TestCaseError::fail(format!("{name}: {e}")))?;
        prop_assert_eq!((c.pixmap.width(), c.pixmap.height()), (w, h));
    }
}

/// A scene file with one huge sphere around the camera, written to a temporary folder.
fn huge_sphere_scene(dir: &Path, radius: &str) -> PathBuf {
    let p = dir.join(format!("huge-{radius}.toml"));
    std::fs::write(&p, format!("[[sphere]]\nradius = {radius}\n")).unwrap();
    p
}

#[test]
fn a_sphere_of_radius_1e18_around_the_camera_draws() {
    let dir = tempfile::tempdir().unwrap();
    for radius in ["2e15", "1e18", "1e19"] {
        let path = huge_sphere_scene(dir.path(), radius);
        let scene = load_file(&path).unwrap_or_else(|e| panic!("{e}"));
        let tr = record(&scene, 160, 120);
        for kind in diagram::available(&tr) {
            for (w, h) in [(800, 600), (64, 64), (1, 1)] {
                for top_down in [false, true] {
                    let o = ViewOptions {
                        top_down,
                        ..opts(w, h, None, 1.0)
                    };
                    diagram::draw(&tr, kind, &o).unwrap();
                }
            }
        }
        // And the command the report used.
        let out = dir.path().join(format!("slice-{radius}.png"));
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_raystep"))
            .args(["diagram", "--pixel", "160,120", "-o"])
            .arg(&out)
            .arg(&path)
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "radius {radius}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        let png = image::open(&out).unwrap().to_rgba8();
        assert_eq!(png.dimensions(), (800, 600));
    }
}

#[test]
fn a_circle_far_larger_than_the_canvas_is_drawn_where_it_is() {
    // A circle of radius 10⁷ px whose top is at y = 50 (both exact in f32): on a 200×100
    // canvas its edge is the line y = 50 to within 0.001 px (the sag over 100 px is
    // 100²/(2·10⁷)).
    let fill = [200, 0, 0, 255];
    let mut c = Canvas::new(200, 100, Theme::LIGHT);
    c.circle([100.0, 10_000_050.0], 10_000_000.0, Some(fill), None, 0.0);
    assert_eq!(c.pixel(100, 40), Some(Theme::LIGHT.background));
    assert_eq!(c.pixel(5, 40), Some(Theme::LIGHT.background));
    assert_eq!(c.pixel(100, 60), Some(fill));
    assert_eq!(c.pixel(195, 60), Some(fill));
    // Covering the canvas entirely; and wholly outside it.
    let mut c = Canvas::new(50, 50, Theme::LIGHT);
    c.circle([25.0, 25.0], 1e30, Some(fill), Some(fill), 3.0);
    assert_eq!(c.pixel(0, 0), Some(fill));
    assert_eq!(c.pixel(49, 49), Some(fill));
    let mut c = Canvas::new(50, 50, Theme::LIGHT);
    c.circle([1e30, 25.0], 1e29, Some(fill), Some(fill), 3.0);
    assert_eq!(c.pixel(25, 25), Some(Theme::LIGHT.background));
    // A line from far outside to far outside crosses the canvas where it should: y = x.
    let mut c = Canvas::new(50, 50, Theme::LIGHT);
    c.line([-1e30, -1e30], [1e30, 1e30], fill, 3.0);
    assert_eq!(c.pixel(25, 25), Some(fill));
    assert_eq!(c.pixel(40, 10), Some(Theme::LIGHT.background));
    // A dashed one, a polygon and a rectangle with huge corners draw without hanging.
    c.dashed([-1e30, 5.0], [1e30, 5.0], fill, 0.5);
    c.polygon(
        &[[-1e35, -1e35], [1e35, -1e35], [0.0, 1e35]],
        Some(fill),
        Some(fill),
        2.0,
    );
    assert_eq!(c.pixel(40, 10), Some(fill));
    c.rect(-1e38, -1e38, 3e38, 3e38, fill);
}

/// Traces of mirror-glass at depth 5 whose ray trees have at least `min` colour rays.
fn deep_traces(min: usize) -> Vec<Trace> {
    let mut scene = load_file(&root().join("scenes/mirror-glass.toml")).unwrap();
    scene.settings.max_depth = 5;
    let (accel, _) = SceneAccel::build(&scene);
    let tracer = Tracer::new(&scene, &accel);
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut out: Vec<Trace> = vec![];
    for y in (4..h).step_by(12) {
        for x in (4..w).step_by(12) {
            let t = tracer.record(x, y, 0);
            let n = t
                .rays()
                .iter()
                .filter(|r| r.kind != RayKind::Shadow)
                .count();
            if n >= min {
                out.push(t);
            }
        }
    }
    out
}

/// The colour rays of a trace in depth-first order (what the ray tree's indices count).
fn colour_rays(t: &Trace) -> Vec<&RayRecord> {
    t.rays()
        .into_iter()
        .filter(|r| r.kind != RayKind::Shadow)
        .collect()
}

#[test]
fn the_ray_tree_is_tidy_and_its_edges_join_parent_to_child() {
    let deep = deep_traces(6);
    assert!(deep.len() >= 10, "only {} deep traces", deep.len());
    let deepest = deep
        .iter()
        .map(|t| colour_rays(t).iter().map(|r| r.depth).max().unwrap_or(0))
        .max()
        .unwrap();
    assert_eq!(deepest, 5, "mirror-glass at depth 5 has depth-5 rays");
    let theme = Theme::LIGHT;
    for t in &deep {
        let rays = colour_rays(t);
        for (w, h, scale) in [
            (420, 320, 1.0),
            (640, 480, 1.0),
            (900, 700, 1.0),
            (900, 700, 1.6),
        ] {
            let o = opts(w, h, None, scale);
            let boxes = ray_tree::layout(t, &o, 40.0);
            assert_eq!(boxes.len(), rays.len());
            for (i, a) in boxes.iter().enumerate() {
                let r = a.rect;
                assert!(
                    r[0] >= -0.01 && r[2] <= w as f32 + 0.01 && r[3] <= h as f32 + 0.01,
                    "{r:?} off a {w}×{h} canvas"
                );
                for b in &boxes[i + 1..] {
                    let q = b.rect;
                    let apart = r[2] <= q[0] || q[2] <= r[0] || r[3] <= q[1] || q[3] <= r[1];
                    assert!(
                        apart,
                        "boxes {} and {} overlap: {r:?} {q:?}",
                        a.index, b.index
                    );
                }
            }
            // The parent of each box is the ray that spawned it, one row up.
            for b in &boxes {
                if let Some(p) = b.parent {
                    assert!(
                        rays[p]
                            .children
                            .iter()
                            .any(|c| std::ptr::eq(c, rays[b.index]))
                    );
                    assert!(
                        boxes[p].rect[3] < b.rect[1],
                        "a child sits below its parent"
                    );
                } else {
                    assert_eq!(b.index, 0, "only the primary ray has no parent");
                }
            }
            // Every edge is drawn from the parent's bottom to the child's top in the child's kind
            // colour.
            let c = diagram::draw(t, DiagramKind::Raytree, &o).unwrap();
            let boxes = ray_tree::layout(t, &o, title_bottom(&c));
            for b in &boxes {
                let Some(p) = b.parent else { continue };
                let from = [boxes[p].pos[0], boxes[p].rect[3]];
                let to = [b.pos[0], b.rect[1]];
                let want = match rays[b.index].kind {
                    RayKind::Reflection => theme.reflect,
                    RayKind::Refraction => theme.refract,
                    k => panic!("a {k:?} ray as a child"),
                };
                // Sampled at tenths of its length: the weight's label may cover a little of it.
                let near = (1..10)
                    .filter(|k| {
                        let f = *k as f32 / 10.0;
                        let at = [
                            from[0] + (to[0] - from[0]) * f,
                            from[1] + (to[1] - from[1]) * f,
                        ];
                        (-1i32..=1)
                            .flat_map(|dx| (-1i32..=1).map(move |dy| (dx, dy)))
                            .any(|(dx, dy)| {
                                c.pixel((at[0] as i32 + dx) as u32, (at[1] as i32 + dy) as u32)
                                    .is_some_and(|px| (0..3).all(|k| px[k].abs_diff(want[k]) < 60))
                            })
                    })
                    .count()
                    >= 5;
                let at = [(from[0] + to[0]) / 2.0, (from[1] + to[1]) / 2.0];
                if !near {
                    let keep = std::env::temp_dir().join("raystep-raytree-edge.png");
                    std::fs::write(&keep, c.png()).unwrap();
                    panic!(
                        "pixel {:?}: no {:?} edge at {at:?} ({w}×{h} ×{scale}; drawn to {})",
                        t.pixel,
                        rays[b.index].kind,
                        keep.display()
                    );
                }
            }
        }
    }
}

/// Where the ray tree's rows start: below the title line, as `draw` computes it (the title's
/// height + 0.4 text sizes).
fn title_bottom(c: &Canvas) -> f32 {
    let ts = c.text_size;
    ts * 0.6 + ts * 1.15 * 1.5 + ts * 0.4
}

/// The names the lesson on ray–sphere intersection gives the two roots, read from its text:
/// "two roots X < Y".
fn lesson_root_names() -> (String, String) {
    let text = std::fs::read_to_string(root().join("lessons/02-ray-sphere.md")).unwrap();
    let at = text
        .find("two roots ")
        .expect("the lesson names the two roots");
    let rest = &text[at + "two roots ".len()..];
    let mut words = rest.split_whitespace();
    let a = words.next().unwrap().to_string();
    assert_eq!(words.next(), Some("<"));
    let b = words
        .next()
        .unwrap()
        .trim_end_matches([':', ','])
        .to_string();
    (a, b)
}

#[test]
fn roots_have_the_lessons_names_in_the_math_panel_and_the_diagram() {
    let (r0, r1) = lesson_root_names();
    assert_eq!((r0.as_str(), r1.as_str()), ("t₀", "t₁"));
    // The diagram writes t₀ as the markup t_0.
    let markup = |name: &str| {
        let sub: String = name
            .chars()
            .skip(1)
            .map(|c| char::from_digit(c as u32 - '₀' as u32, 10).unwrap())
            .collect();
        format!("t_{{{sub}}}")
    };
    let (m0, m1) = (markup(&r0), markup(&r1));
    let mut checked = 0;
    for (name, tr) in traces() {
        for (k, (ray, s)) in tr.timeline().into_iter().enumerate() {
            let Step::Sphere { test, .. } = &s.step else {
                continue;
            };
            let Some([_, _]) = test.roots else { continue };
            // The math panel (textbook or stable: either way the two roots are named).
            let e = explain(tr, ray, &s.step);
            let names: Vec<&str> = e.lines.iter().map(|l| l.name.as_str()).collect();
            assert!(
                names.iter().any(|n| n.contains(&r0)) && names.iter().any(|n| n.contains(&r1)),
                "{name} step {k}: math panel lines {names:?}"
            );
            assert!(!names.iter().any(|n| n.contains("t₂")), "{names:?}");
            // The diagram: each root's label nearer its own dot than the other's.
            for (w, h, scale) in [
                (400, 300, 1.0),
                (800, 600, 1.0),
                (520, 700, 1.6),
                (300, 200, 1.0),
            ] {
                let o = opts(w, h, Some(k), scale);
                let Some(l) = quadratic::layout(tr, &o.sane()) else {
                    continue;
                };
                let Some([p0, p1]) = l.roots else { continue };
                if (p0[0] - p1[0]).abs() < 1.0 {
                    continue; // a double root: one dot, one label "t₀ = t₁"
                }
                let (_, labels) = quadratic::draw_labelled(tr, &o);
                for (mark, own, other) in [(&m0, p0, p1), (&m1, p1, p0)] {
                    let Some(lab) = labels.iter().find(|l| l.text.starts_with(mark.as_str()))
                    else {
                        panic!("{name} step {k} ({w}×{h}): no {mark} label in {labels:?}")
                    };
                    let d = |p: [f32; 2]| {
                        let r = lab.rect;
                        let dx = (r[0] - p[0]).max(p[0] - r[2]).max(0.0);
                        let dy = (r[1] - p[1]).max(p[1] - r[3]).max(0.0);
                        dx.hypot(dy)
                    };
                    assert!(
                        d(own) < d(other),
                        "{name} step {k} ({w}×{h}): {} at {:?} is nearer the other root's dot {other:?} than its own {own:?}",
                        lab.text,
                        lab.rect
                    );
                }
                checked += 1;
            }
        }
    }
    assert!(checked > 20, "only {checked} labelled plots checked");
}

#[test]
fn text_grows_with_the_ui_scale() {
    // At scale 1 labels are at least 13 px, however small the canvas; at the presentation
    // scale 1.6 they are 1.6 times that.
    let a = Canvas::scaled(400, 300, Theme::LIGHT, 1.0);
    let b = Canvas::scaled(400, 300, Theme::LIGHT, 1.6);
    assert!(a.text_size * 0.8 >= 12.8, "{}", a.text_size);
    assert!((b.text_size / a.text_size - 1.6).abs() < 1e-4);
    let big = Canvas::scaled(1920, 1080, Theme::LIGHT, 1.0);
    assert!(big.text_size * 0.85 >= 13.0, "{}", big.text_size);
}
