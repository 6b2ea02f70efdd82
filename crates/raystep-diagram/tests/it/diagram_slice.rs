//! The scene slice: golden images (light theme, 400×300) and checks of the drawing's geometry
//! against the recorded trace — hits on their rays and on their circles, true angles in the plane
//! of incidence, a plane that turns about a fixed ray, focus that builds the picture up.
//!
//! Regenerate the golden images with `UPDATE_GOLDEN=1 cargo test -p raystep-diagram --test it diagram_slice::` and look
//! at every one before committing it.

use crate::common;
use common::assert_golden;

use raystep_core::accel::SceneAccel;
use raystep_core::record::{RayKind, RayRecord, Step, Trace};
use raystep_core::scene::{AccelChoice, Scene, load_file};
use raystep_core::trace::Tracer;
use raystep_diagram::slice::{self, Px, SliceLayout};
use raystep_diagram::{self as diagram, DiagramKind, Theme, ViewOptions};
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn scene(name: &str) -> Scene {
    load_file(&root().join("scenes").join(name)).expect("shipped scene loads")
}

fn trace_of(s: &Scene, x: u32, y: u32) -> Trace {
    Tracer::new(s, &SceneAccel::build(s).0).record(x, y, 0)
}

fn trace(name: &str, x: u32, y: u32) -> Trace {
    trace_of(&scene(name), x, y)
}

fn bvh_trace(name: &str, x: u32, y: u32) -> Trace {
    let mut s = scene(name);
    s.settings.accel = AccelChoice::Bvh;
    trace_of(&s, x, y)
}

fn opts() -> ViewOptions {
    ViewOptions {
        width: 400,
        height: 300,
        theme: Theme::LIGHT,
        ..ViewOptions::default()
    }
}

fn hit_name(r: &RayRecord) -> Option<&str> {
    r.hit.as_ref().map(|h| h.name.as_str())
}

fn surface(r: &RayRecord) -> Option<([f32; 3], [f32; 3])> {
    r.steps.iter().find_map(|s| match s.step {
        Step::Surface { point, normal, .. } => Some((point, normal)),
        _ => None,
    })
}

/// The timeline index of the total internal reflection made by the shallowest ray.
fn shallowest_tir(t: &Trace) -> usize {
    t.timeline()
        .iter()
        .enumerate()
        .filter(|(_, (_, s))| {
            matches!(
                s.step,
                Step::Refract {
                    total_internal_reflection: true,
                    ..
                }
            )
        })
        .min_by_key(|(_, (r, _))| r.depth)
        .map(|(k, _)| k)
        .expect("the trace has a total internal reflection")
}

// The pixels the tests draw (checked below to show what they are meant to show).
const SHADOW: (u32, u32) = (160, 120); // three-spheres: "middle", lit by "key"
const MIRROR: (u32, u32) = (90, 150); // three-spheres: "mirror", reflecting the floor
const REFRACT: (u32, u32) = (250, 190); // mirror-glass: into "glass" and out, missing the bubble
const TIR: (u32, u32) = (250, 150); // mirror-glass: through "glass" onto the bubble: TIR
const BOXES: (u32, u32) = (200, 115); // triangles with a BVH: an icosahedron face

// ---------------------------------------------------------------------------------------------
// Golden images.

#[test]
fn golden_sphere_hit_with_shadow_ray() {
    let t = trace("three-spheres.toml", SHADOW.0, SHADOW.1);
    assert_eq!(hit_name(&t.root), Some("middle"));
    let shadow = t
        .root
        .children
        .iter()
        .find(|c| c.kind == RayKind::Shadow)
        .expect("a shadow ray");
    assert!(shadow.hit.is_none(), "the light is visible");
    let c = diagram::draw(&t, DiagramKind::Slice, &opts()).unwrap();
    assert_golden(&c, "slice-three-spheres-shadow");
}

#[test]
fn golden_mirror_reflection() {
    let t = trace("three-spheres.toml", MIRROR.0, MIRROR.1);
    assert_eq!(hit_name(&t.root), Some("mirror"));
    let refl = t
        .root
        .children
        .iter()
        .find(|c| c.kind == RayKind::Reflection)
        .expect("a reflection ray");
    assert_eq!(hit_name(refl), Some("floor"));
    assert_golden(&slice::draw(&t, &opts()), "slice-three-spheres-mirror");
}

#[test]
fn golden_refraction() {
    let t = trace("mirror-glass.toml", REFRACT.0, REFRACT.1);
    assert_eq!(hit_name(&t.root), Some("glass"));
    assert!(
        t.root
            .children
            .iter()
            .any(|c| c.kind == RayKind::Refraction)
    );
    assert!(
        !t.rays().iter().any(|r| hit_name(r) == Some("bubble")),
        "this one misses the bubble"
    );
    assert_golden(&slice::draw(&t, &opts()), "slice-mirror-glass-refraction");
}

#[test]
fn golden_total_internal_reflection_focused() {
    let t = trace("mirror-glass.toml", TIR.0, TIR.1);
    let k = shallowest_tir(&t);
    let o = ViewOptions {
        focus: Some(k),
        ..opts()
    };
    assert_golden(&slice::draw(&t, &o), "slice-mirror-glass-tir");
}

#[test]
fn golden_bvh_boxes() {
    let t = bvh_trace("triangles.toml", BOXES.0, BOXES.1);
    assert!(hit_name(&t.root).is_some_and(|n| n.starts_with("icosahedron")));
    assert!(t.root.steps.iter().any(|s| matches!(s.step, Step::Node(_))));
    assert_golden(&slice::draw(&t, &opts()), "slice-triangles-bvh");
}

#[test]
fn golden_top_down() {
    let t = trace("three-spheres.toml", MIRROR.0, MIRROR.1);
    let o = ViewOptions {
        top_down: true,
        ..opts()
    };
    assert_golden(&slice::draw(&t, &o), "slice-three-spheres-top-down");
}

// ---------------------------------------------------------------------------------------------
// Geometry.

fn dist(a: Px, b: Px) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

/// Distance from `p` to the segment a–b.
fn dist_to_segment(p: Px, a: Px, b: Px) -> f32 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let s = if l2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, [a[0] + s * dx, a[1] + s * dy])
}

fn primary_hit(lay: &SliceLayout) -> Px {
    lay.primary().hit.expect("the primary ray's hit is drawn")
}

#[test]
fn the_hit_lies_on_the_drawn_ray_and_the_ray_is_drawn_there() {
    for (scene_name, (x, y)) in [
        ("three-spheres.toml", SHADOW),
        ("three-spheres.toml", MIRROR),
        ("mirror-glass.toml", REFRACT),
    ] {
        let t = trace(scene_name, x, y);
        for o in [
            opts(),
            ViewOptions::default(),
            ViewOptions {
                top_down: true,
                ..opts()
            },
        ] {
            let lay = slice::layout(&t, &o);
            let p = lay.primary();
            let hit = primary_hit(&lay);
            let d = dist_to_segment(hit, p.start, p.end);
            assert!(
                d < 1.5,
                "{scene_name} ({x}, {y}): hit {hit:?} is {d} px off the ray {:?} → {:?}",
                p.start,
                p.end
            );
            assert!(dist(hit, p.end) < 1.5, "the primary ray ends at its hit");
            assert!(
                dist(p.start, lay.eye) < 0.5,
                "the primary ray starts at the eye"
            );
            // The recorded hit point projects onto the drawn one.
            let (point, _) = surface(&t.root).unwrap();
            assert!(dist(lay.project(point), hit) < 0.5);

            // The canvas has the ray's colour on the segment just before the hit (the hit dot
            // covers the hit itself).
            let c = slice::draw(&t, &o);
            let ray = o.theme.ray;
            let (dx, dy) = (p.start[0] - hit[0], p.start[1] - hit[1]);
            let l = (dx * dx + dy * dy).sqrt();
            // (Up to 80 px: a normal nearly along the ray covers its last few dozen pixels.)
            let found = (8..80).any(|k| {
                let q = [hit[0] + dx / l * k as f32, hit[1] + dy / l * k as f32];
                c.pixel(q[0].round() as u32, q[1].round() as u32)
                    .is_some_and(|px| (0..3).all(|ch| px[ch].abs_diff(ray[ch]) <= 40))
            });
            assert!(
                found,
                "{scene_name} ({x}, {y}): no ray-coloured pixel just before the hit at {hit:?}"
            );
        }
    }
}

#[test]
fn a_sphere_hit_lies_on_its_drawn_circle_whatever_the_angle() {
    for (scene_name, (x, y), sphere) in [
        ("three-spheres.toml", SHADOW, "middle"),
        ("three-spheres.toml", MIRROR, "mirror"),
        ("mirror-glass.toml", REFRACT, "glass"),
        ("mirror-glass.toml", TIR, "glass"),
    ] {
        let t = trace(scene_name, x, y);
        assert_eq!(hit_name(&t.root), Some(sphere));
        for angle in [0.0, 25.0, 90.0, -140.0] {
            let lay = slice::layout(
                &t,
                &ViewOptions {
                    slice_angle: angle,
                    ..opts()
                },
            );
            let hit = primary_hit(&lay);
            let circle = lay
                .circles
                .iter()
                .find(|c| c.name == sphere)
                .expect("the hit sphere is drawn");
            assert!(
                circle.cut,
                "a plane through the ray cuts the sphere the ray hits"
            );
            let off = (dist(hit, circle.center) - circle.radius).abs();
            assert!(
                off < 1.5,
                "{sphere} at {angle}°: the hit is {off} px off its circle"
            );
        }
    }
}

#[test]
fn in_the_plane_of_incidence_the_angles_are_true() {
    // Reflection and refraction: the drawn angle between the reversed ray and the normal is θi.
    for (scene_name, (x, y)) in [
        ("three-spheres.toml", MIRROR),
        ("mirror-glass.toml", REFRACT),
    ] {
        let t = trace(scene_name, x, y);
        let lay = slice::layout(&t, &opts());
        let (point, normal) = surface(&t.root).unwrap();
        let h = lay.project(point);
        let n = lay.project([
            point[0] + normal[0],
            point[1] + normal[1],
            point[2] + normal[2],
        ]);
        let e = lay.primary().start;
        let a = |p: Px| (p[1] - h[1]).atan2(p[0] - h[0]);
        let mut drawn = (a(n) - a(e)).abs().to_degrees();
        if drawn > 180.0 {
            drawn = 360.0 - drawn;
        }
        let d = t.root.direction;
        let cos_i = -(d[0] * normal[0] + d[1] * normal[1] + d[2] * normal[2]);
        let true_angle = cos_i.acos().to_degrees();
        assert!(
            (drawn - true_angle).abs() < 0.3,
            "{scene_name}: drawn θi {drawn}° vs {true_angle}°"
        );
        // The normal is drawn at full length: it lies in the plane.
        assert!((dist(h, n) - lay.scale).abs() < 0.01 * lay.scale);
    }
    // The refracted ray leaves the hit in the recorded direction.
    let t = trace("mirror-glass.toml", REFRACT.0, REFRACT.1);
    let lay = slice::layout(&t, &opts());
    let k = t
        .rays()
        .iter()
        .position(|r| r.kind == RayKind::Refraction && r.depth == 1)
        .unwrap();
    let r = &lay.rays[k];
    assert!(
        dist(r.start, primary_hit(&lay)) < 1.5,
        "the refraction ray starts at the hit"
    );
    let dir = t
        .root
        .steps
        .iter()
        .find_map(|s| match s.step {
            Step::Refract { direction, .. } => direction,
            _ => None,
        })
        .unwrap();
    let (o, p) = (
        lay.project(t.rays()[k].origin),
        lay.project([
            t.rays()[k].origin[0] + dir[0],
            t.rays()[k].origin[1] + dir[1],
            t.rays()[k].origin[2] + dir[2],
        ]),
    );
    let (drawn, want) = (
        (r.end[1] - r.start[1]).atan2(r.end[0] - r.start[0]),
        (p[1] - o[1]).atan2(p[0] - o[0]),
    );
    assert!(
        (drawn - want).abs() < 0.01,
        "the refraction ray is drawn along the recorded direction"
    );
}

#[test]
fn turning_the_plane_keeps_the_ray_and_its_hit_in_place() {
    for (scene_name, (x, y)) in [
        ("three-spheres.toml", SHADOW),
        ("three-spheres.toml", MIRROR),
        ("mirror-glass.toml", TIR),
    ] {
        let t = trace(scene_name, x, y);
        let base = slice::layout(&t, &opts());
        let mut moved_something = false;
        for angle in [15.0, 60.0, 90.0, 200.0] {
            let lay = slice::layout(
                &t,
                &ViewOptions {
                    slice_angle: angle,
                    ..opts()
                },
            );
            assert!(
                dist(lay.primary().start, base.primary().start) < 0.5,
                "{angle}°: the eye moved"
            );
            assert!(
                dist(primary_hit(&lay), primary_hit(&base)) < 0.5,
                "{angle}°: the hit moved"
            );
            assert!(
                dist(lay.pixel, base.pixel) < 0.5,
                "{angle}°: the pixel moved"
            );
            assert_eq!(lay.scale, base.scale, "{angle}°: the scale changed");
            // ... while the scene turns around them.
            moved_something |=
                lay.circles.iter().zip(&base.circles).any(|(a, b)| {
                    dist(a.center, b.center) > 2.0 || (a.radius - b.radius).abs() > 2.0
                });
        }
        assert!(
            moved_something,
            "{scene_name}: turning the plane changed nothing"
        );
    }
}

#[test]
fn focus_builds_the_picture_up() {
    let t = trace("three-spheres.toml", MIRROR.0, MIRROR.1);
    let tl = t.timeline();
    let surface_k = tl
        .iter()
        .position(|(r, s)| r.kind == RayKind::Primary && matches!(s.step, Step::Surface { .. }))
        .unwrap();
    let focus = |k| {
        slice::layout(
            &t,
            &ViewOptions {
                focus: Some(k),
                ..opts()
            },
        )
    };

    // Before the surface step the hit is not drawn, and the ray runs on to the border.
    let before = focus(surface_k - 1);
    assert!(before.primary().hit.is_none());
    assert!(
        before.rays.iter().skip(1).all(|r| !r.visible),
        "no child ray before the primary hit"
    );
    assert!(before.primary().current);
    let at = focus(surface_k);
    assert!(at.primary().hit.is_some());

    // At the camera step, the primary ray has no closest hit yet: it runs to the plot's border.
    let first = focus(0);
    let [x, y, w, h] = first.plot;
    let e = first.primary().end;
    let on_border = [
        (e[0] - x).abs(),
        (e[0] - x - w).abs(),
        (e[1] - y).abs(),
        (e[1] - y - h).abs(),
    ]
    .iter()
    .any(|d| *d < 1.0);
    assert!(
        on_border,
        "the searching ray ends on the border: {e:?} in {:?}",
        first.plot
    );

    // A child ray appears at the step that announces it and is then the current one.
    let refl_k = tl
        .iter()
        .position(|(_, s)| matches!(s.step, Step::Reflect { .. }))
        .unwrap();
    let k = t
        .rays()
        .iter()
        .position(|r| r.kind == RayKind::Reflection)
        .unwrap();
    assert!(!focus(refl_k - 1).rays[k].visible);
    let l = focus(refl_k);
    assert!(l.rays[k].visible && l.rays[k].current && !l.primary().current);

    // Unfocused: everything, nothing current.
    let all = slice::layout(&t, &opts());
    assert!(all.rays.iter().all(|r| r.visible && !r.current));

    // Focused pictures differ from step to step, and every step draws.
    let a = slice::draw(
        &t,
        &ViewOptions {
            focus: Some(surface_k - 1),
            ..opts()
        },
    )
    .png();
    let b = slice::draw(
        &t,
        &ViewOptions {
            focus: Some(surface_k),
            ..opts()
        },
    )
    .png();
    assert_ne!(a, b);
    for k in 0..tl.len() {
        let _ = slice::draw(
            &t,
            &ViewOptions {
                focus: Some(k),
                width: 200,
                height: 150,
                ..opts()
            },
        );
    }
}

#[test]
fn shadow_rays_end_at_their_light_or_their_blocker() {
    // Triangles through the BVH, pixel on the floor behind the icosahedron: "key" is blocked.
    let t = bvh_trace("triangles.toml", 200, 140);
    let lay = slice::layout(&t, &ViewOptions::default());
    let mut blocked = 0;
    for (r, l) in t.rays().iter().zip(&lay.rays) {
        if r.kind != RayKind::Shadow {
            continue;
        }
        assert!(dist(l.start, lay.project(r.origin)) < 0.5);
        match &r.hit {
            Some(h) => {
                blocked += 1;
                assert!(l.blocked);
                let p = [
                    r.origin[0] + r.direction[0] * h.t,
                    r.origin[1] + r.direction[1] * h.t,
                    r.origin[2] + r.direction[2] * h.t,
                ];
                assert!(
                    dist(l.end, lay.project(p)) < 0.5,
                    "a blocked shadow ray ends at its blocker"
                );
                assert_eq!(l.hit_object.as_deref(), Some(h.name.as_str()));
            }
            None => {
                assert!(!l.blocked);
                let target = [
                    r.origin[0] + r.direction[0],
                    r.origin[1] + r.direction[1],
                    r.origin[2] + r.direction[2],
                ];
                assert!(
                    dist(l.end, lay.project(target)) < 1.0,
                    "an open shadow ray ends at its light"
                );
            }
        }
    }
    assert!(blocked > 0, "this pixel has a blocked shadow ray");
    // Lights far away are drawn on the border, inside the plot.
    for l in &lay.lights {
        let [x, y, w, h] = lay.plot;
        assert!(
            l.at[0] >= x && l.at[0] <= x + w && l.at[1] >= y && l.at[1] <= y + h,
            "{} is drawn inside the plot",
            l.name
        );
    }
    assert!(lay.lights.iter().any(|l| l.on_border));
}

#[test]
fn the_slice_is_a_pure_function_of_the_trace() {
    // The same trace, through JSON (no scene in sight), draws the same picture.
    for (scene_name, (x, y), bvh) in [
        ("three-spheres.toml", MIRROR, false),
        ("triangles.toml", BOXES, true),
    ] {
        let t = if bvh {
            bvh_trace(scene_name, x, y)
        } else {
            trace(scene_name, x, y)
        };
        let back = Trace::from_json(&t.to_json(), "t.json").unwrap();
        for o in [
            opts(),
            ViewOptions {
                focus: Some(7),
                theme: Theme::DARK,
                ..opts()
            },
            ViewOptions {
                top_down: true,
                ..opts()
            },
        ] {
            assert_eq!(slice::draw(&t, &o).png(), slice::draw(&back, &o).png());
            assert_eq!(slice::layout(&t, &o), slice::layout(&back, &o));
        }
    }
}

#[test]
fn top_down_shows_spheres_whole_and_the_camera_looking_up_the_page() {
    let t = trace("three-spheres.toml", SHADOW.0, SHADOW.1);
    let lay = slice::layout(
        &t,
        &ViewOptions {
            top_down: true,
            ..opts()
        },
    );
    assert!(lay.top_down);
    // Every sphere at its full radius, centred on its projected centre.
    for o in &t.objects {
        if let raystep_core::scene::Shape::Sphere { center, radius } = o.shape {
            let c = lay.circles.iter().find(|c| c.name == o.name).unwrap();
            assert!((c.radius - radius * lay.scale).abs() < 0.01);
            assert!(dist(c.center, lay.project(center.to_array())) < 0.01);
        }
    }
    // The camera looks along +z: up the page; the image's right (−x here) is the page's right.
    assert!(primary_hit(&lay)[1] < lay.eye[1]);
    let a = lay.project([1.0, 0.0, 0.0]);
    let b = lay.project([-1.0, 0.0, 0.0]);
    assert!(b[0] > a[0], "−x is to the right, as in the picture");
}

#[test]
fn a_miss_runs_to_the_border_and_every_size_and_theme_draws() {
    let t = trace("three-spheres.toml", 160, 5); // sky
    assert!(t.root.hit.is_none());
    let lay = slice::layout(&t, &opts());
    let e = lay.primary().end;
    let [x, y, w, h] = lay.plot;
    assert!(
        [
            (e[0] - x).abs(),
            (e[0] - x - w).abs(),
            (e[1] - y).abs(),
            (e[1] - y - h).abs()
        ]
        .iter()
        .any(|d| *d < 1.0)
    );
    for (w, h) in [(64, 64), (400, 300), (800, 600), (1600, 500)] {
        for theme in [Theme::LIGHT, Theme::DARK] {
            let c = slice::draw(
                &t,
                &ViewOptions {
                    width: w,
                    height: h,
                    theme,
                    ..ViewOptions::default()
                },
            );
            assert_eq!((c.pixmap.width(), c.pixmap.height()), (w, h));
        }
    }
}
