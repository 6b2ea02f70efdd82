//! The scene slice on a projector (issue 37, item 5): the view frames what the step is about
//! instead of zooming out to the end of a 114-unit ray, a ray that ends beyond the frame is
//! marked at the edge, labels overlap neither each other nor a plane's line, every text reads
//! (WCAG contrast ≥ 4.5:1, at least 16 px at 800×600), and `--animate --steps A..B` draws exactly
//! the steps asked for.
//!
//! The reported case: `raystep diagram mirror-glass --pixel 240,140 --kind slice --step 30
//! --scale 1.6 --size 1280x720`. Step 30 is the depth-1 reflection ray (leaving "glass") testing
//! "glass"; the ray ends on "wall" at t = 114.8.

use raystep::accel::SceneAccel;
use raystep::diagram::slice::{self, Px, SliceLayout, SliceText};
use raystep::diagram::{Theme, ViewOptions};
use raystep::record::{RayKind, Step, Trace};
use raystep::scene::{AccelChoice, Scene, load_file};
use raystep::trace::Tracer;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
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

fn view(w: u32, h: u32, scale: f32, step: Option<usize>) -> ViewOptions {
    ViewOptions {
        width: w,
        height: h,
        scale,
        focus: step,
        theme: Theme::LIGHT,
        ..ViewOptions::default()
    }
}

/// The reported view: 1280×720 at scale 1.6, step 30.
fn reported() -> ViewOptions {
    view(1280, 720, 1.6, Some(REPORTED_STEP))
}

const REPORTED_STEP: usize = 30;

fn dist(a: Px, b: Px) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

fn in_plot(lay: &SliceLayout, p: Px) -> bool {
    let [x, y, w, h] = lay.plot;
    p[0] >= x && p[0] <= x + w && p[1] >= y && p[1] <= y + h
}

/// The primary ray's recorded hit point.
fn primary_hit_point(t: &Trace) -> [f32; 3] {
    t.root
        .steps
        .iter()
        .find_map(|s| match s.step {
            Step::Surface { point, .. } => Some(point),
            _ => None,
        })
        .expect("the primary ray hits")
}

/// Checks that step 30 of mirror-glass's pixel (240, 140) is what these tests say it is.
fn reported_trace() -> Trace {
    let t = trace("mirror-glass.toml", 240, 140);
    let tl = t.timeline();
    let (ray, step) = &tl[REPORTED_STEP];
    assert_eq!(ray.kind, RayKind::Reflection);
    assert_eq!(ray.depth, 1);
    assert!(
        matches!(&step.step, Step::Sphere { name, .. } if name == "glass"),
        "step 30 tests the glass ball"
    );
    let hit = ray.hit.as_ref().expect("the reflection ray hits");
    assert_eq!(hit.name, "wall");
    assert!(hit.t > 100.0, "a long ray: t = {}", hit.t);
    t
}

/// The index (in trace order, as `SliceLayout::rays` holds them) of the depth-1 reflection ray.
fn reflection_index(t: &Trace) -> usize {
    t.rays()
        .iter()
        .position(|r| r.kind == RayKind::Reflection && r.depth == 1)
        .expect("a reflection ray")
}

// ---------------------------------------------------------------------------------------------
// Framing.

/// Before: the view fitted the 114-unit ray, so the eye and the glass ball's hit were ~20 px
/// apart at 1280×720 (and ~15 px at 800×600). Now they are spread over the plot.
#[test]
fn the_reported_step_spreads_the_eye_and_the_hit_over_the_plot() {
    let t = reported_trace();
    let hit3 = primary_hit_point(&t);
    for (o, least) in [
        (reported(), 300.0),
        (view(800, 600, 1.0, Some(REPORTED_STEP)), 200.0),
        // Unfocused, the same: the far wall hit does not set the view either.
        (view(1280, 720, 1.6, None), 300.0),
    ] {
        let lay = slice::layout(&t, &o);
        let hit = lay.project(hit3);
        let apart = dist(lay.eye, hit);
        assert!(
            apart >= least,
            "{}×{}: the eye {:?} and the hit {hit:?} are {apart} px apart (want ≥ {least})",
            o.width,
            o.height,
            lay.eye
        );
        assert!(in_plot(&lay, lay.eye) && in_plot(&lay, hit));
    }
}

#[test]
fn the_long_ray_leaves_the_frame_marked_with_its_t() {
    let t = reported_trace();
    let k = reflection_index(&t);
    let (canvas, texts) = slice::draw_annotated(&t, &reported());
    let lay = slice::layout(&t, &reported());
    let r = &lay.rays[k];
    assert!(r.visible && r.current);
    // Its end (the wall, 114.8 along) is beyond the plot; it is drawn to the border.
    assert!(!in_plot(&lay, r.end), "the wall hit lies outside the view");
    let exit = r
        .exit
        .expect("the reflection ray is marked as leaving the frame");
    let [x, y, w, h] = lay.plot;
    let on_border = [
        (exit[0] - x).abs(),
        (exit[0] - x - w).abs(),
        (exit[1] - y).abs(),
        (exit[1] - y - h).abs(),
    ]
    .iter()
    .any(|d| *d < 1.0);
    assert!(
        on_border,
        "it leaves at the border: {exit:?} in {:?}",
        lay.plot
    );
    // On the way out: from its origin towards its end.
    let along = (exit[0] - r.start[0]) * (r.end[0] - r.start[0])
        + (exit[1] - r.start[1]) * (r.end[1] - r.start[1]);
    assert!(along > 0.0);
    // The edge says how far it goes: t with one decimal, from the trace.
    let t_end = t.rays()[k].hit.as_ref().unwrap().t;
    let want = format!("{t_end:.1}");
    let mark = texts
        .iter()
        .find(|s| s.label && s.text.starts_with('→') && s.text.contains(&want))
        .unwrap_or_else(|| panic!("a \"→ … t = {want}\" label in {texts:#?}"));
    let c = [
        mark.rect[0] + mark.rect[2] * 0.5,
        mark.rect[1] + mark.rect[3] * 0.5,
    ];
    assert!(
        dist(c, exit) < mark.rect[2] * 0.5 + 4.0 * mark.rect[3],
        "the mark {:?} sits by the exit {exit:?}",
        mark.rect
    );
    // The ray's colour reaches the border near the exit (the arrowhead is drawn there).
    let ray_col = t_colour_reflect();
    let found = (2..40).any(|s| {
        let d = [r.start[0] - exit[0], r.start[1] - exit[1]];
        let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let q = [exit[0] + d[0] / l * s as f32, exit[1] + d[1] / l * s as f32];
        canvas
            .pixel(q[0].round() as u32, q[1].round() as u32)
            .is_some_and(|px| (0..3).all(|ch| px[ch].abs_diff(ray_col[ch]) <= 40))
    });
    assert!(
        found,
        "the reflection ray is drawn up to the border at {exit:?}"
    );
}

fn t_colour_reflect() -> [u8; 4] {
    Theme::LIGHT.reflect
}

/// A ray whose end is inside the view is not marked as leaving, and a far hit, once found, is
/// shown: the Surface step of the 114-unit ray frames the wall hit itself.
#[test]
fn near_ends_are_not_marked_and_a_far_hit_is_shown_when_found() {
    let t = reported_trace();
    let lay = slice::layout(&t, &view(800, 600, 1.0, None));
    let refr = t
        .rays()
        .iter()
        .position(|r| r.kind == RayKind::Refraction && r.depth == 1)
        .unwrap();
    assert!(in_plot(&lay, lay.rays[refr].end));
    assert_eq!(lay.rays[refr].exit, None);
    assert_eq!(lay.primary().exit, None);

    let k = reflection_index(&t);
    let surface = t
        .timeline()
        .iter()
        .position(|(r, s)| {
            r.kind == RayKind::Reflection && r.depth == 1 && matches!(s.step, Step::Surface { .. })
        })
        .unwrap();
    let lay = slice::layout(&t, &view(800, 600, 1.0, Some(surface)));
    let hit = lay.rays[k]
        .hit
        .expect("the wall hit is drawn at its Surface step");
    assert!(in_plot(&lay, hit), "the wall hit {hit:?} is in view");
    assert_eq!(lay.rays[k].exit, None);
    let wall = lay
        .planes
        .iter()
        .find(|p| p.name == "wall")
        .expect("the wall is drawn");
    assert!(
        dist_to_segment(hit, wall.line[0], wall.line[1]) < 1.5,
        "the hit lies on the wall's line"
    );
}

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

// ---------------------------------------------------------------------------------------------
// Labels.

/// The diagrams the label and text checks look at: the reported step and its neighbours, a
/// shadow ray, a refraction, the whole trace, a primary ray on first-sphere, a side view with a
/// floor, a BVH with numbered boxes, from above; at 1280×720 ×1.6 and 800×600.
fn cases() -> Vec<(String, Trace, ViewOptions)> {
    let mg = reported_trace();
    let first = trace("first-sphere.toml", 160, 120);
    let three = trace("three-spheres.toml", 90, 150);
    let mut s = scene("triangles.toml");
    s.settings.accel = AccelChoice::Bvh;
    let boxes = trace_of(&s, 200, 115);
    let mut out = vec![];
    for (w, h, k) in [(1280, 720, 1.6), (800, 600, 1.0)] {
        for step in [
            None,
            Some(18),
            Some(28),
            Some(30),
            Some(35),
            Some(48),
            Some(61),
        ] {
            out.push((
                format!("mirror-glass {step:?} {w}×{h}"),
                mg.clone(),
                view(w, h, k, step),
            ));
        }
        for step in [None, Some(1), Some(3), Some(6)] {
            out.push((
                format!("first-sphere {step:?} {w}×{h}"),
                first.clone(),
                view(w, h, k, step),
            ));
        }
        for step in [None, Some(5), Some(12)] {
            out.push((
                format!("three-spheres {step:?} {w}×{h}"),
                three.clone(),
                view(w, h, k, step),
            ));
        }
        for step in [None, Some(4)] {
            out.push((
                format!("triangles bvh {step:?} {w}×{h}"),
                boxes.clone(),
                view(w, h, k, step),
            ));
        }
        out.push((
            format!("three-spheres from above {w}×{h}"),
            three.clone(),
            ViewOptions {
                top_down: true,
                ..view(w, h, k, None)
            },
        ));
    }
    out
}

fn intersect(a: [f32; 4], b: [f32; 4]) -> bool {
    // Boxes that only touch do not intersect.
    a[0] < b[0] + b[2] - 0.01
        && b[0] < a[0] + a[2] - 0.01
        && a[1] < b[1] + b[3] - 0.01
        && b[1] < a[1] + a[3] - 0.01
}

/// Whether the segment a–b passes through the inside of `r`, by walking it in 0.25 px steps.
fn crosses(r: [f32; 4], a: Px, b: Px) -> bool {
    let n = (dist(a, b) * 4.0).ceil().max(1.0) as usize;
    (0..=n).any(|i| {
        let s = i as f32 / n as f32;
        let p = [a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s];
        p[0] > r[0] + 0.5
            && p[0] < r[0] + r[2] - 0.5
            && p[1] > r[1] + 0.5
            && p[1] < r[1] + r[3] - 0.5
    })
}

fn labels(texts: &[SliceText]) -> Vec<&SliceText> {
    texts.iter().filter(|s| s.label).collect()
}

#[test]
fn labels_overlap_neither_each_other_nor_a_plane() {
    for (name, t, o) in cases() {
        let (_, texts) = slice::draw_annotated(&t, &o);
        let lay = slice::layout(&t, &o);
        let ls = labels(&texts);
        assert!(!ls.is_empty(), "{name}: no labels at all");
        for (i, a) in ls.iter().enumerate() {
            for b in &ls[i + 1..] {
                assert!(
                    !intersect(a.rect, b.rect),
                    "{name}: {:?} {:?} overlaps {:?} {:?}",
                    a.text,
                    a.rect,
                    b.text,
                    b.rect
                );
            }
            let [x, y, w, h] = lay.plot;
            assert!(
                a.rect[0] >= x - 0.01
                    && a.rect[1] >= y - 0.01
                    && a.rect[0] + a.rect[2] <= x + w + 0.01
                    && a.rect[1] + a.rect[3] <= y + h + 0.01,
                "{name}: {:?} {:?} is inside the plot {:?}",
                a.text,
                a.rect,
                lay.plot
            );
            for p in &lay.planes {
                assert!(
                    !crosses(a.rect, p.line[0], p.line[1]),
                    "{name}: {:?} {:?} is cut by {}'s line {:?}",
                    a.text,
                    a.rect,
                    p.name,
                    p.line
                );
            }
        }
    }
}

/// The placement keeps what matters: at the reported step the roots, the ray's end, the eye and
/// the ball being tested are all labelled (a placement that dropped labels to avoid overlaps
/// would pass the test above).
#[test]
fn the_reported_step_keeps_its_labels() {
    let t = reported_trace();
    for o in [reported(), view(800, 600, 1.0, Some(REPORTED_STEP))] {
        let (_, texts) = slice::draw_annotated(&t, &o);
        let ls = labels(&texts);
        for want in [
            "t0 = ",
            "t1 = ",
            "→ ",
            "eye",
            "glass",
            "pixel (240, 140)",
            "mirror",
        ] {
            assert!(
                ls.iter().any(|l| l.text.starts_with(want)),
                "{}×{}: no label {want:?} in {:?}",
                o.width,
                o.height,
                ls.iter().map(|l| &l.text).collect::<Vec<_>>()
            );
        }
    }
}

/// The floor line seen from the side is where the recorded floor hit is: the plane's line the
/// label test avoids is the one drawn.
#[test]
fn the_floor_line_goes_through_the_floor_hit() {
    // three-spheres (90, 150): the mirror ball reflects the floor; the reflection lies in the
    // plane of incidence, the view plane, so its floor hit lies on the floor's cut.
    let t = trace("three-spheres.toml", 90, 150);
    let refl = t
        .rays()
        .into_iter()
        .find(|r| r.kind == RayKind::Reflection)
        .unwrap();
    let h = refl.hit.as_ref().unwrap();
    assert_eq!(h.name, "floor");
    let p = [
        refl.origin[0] + refl.direction[0] * h.t,
        refl.origin[1] + refl.direction[1] * h.t,
        refl.origin[2] + refl.direction[2] * h.t,
    ];
    let lay = slice::layout(&t, &view(800, 600, 1.0, None));
    let floor = lay.planes.iter().find(|p| p.name == "floor").unwrap();
    let q = lay.project(p);
    assert!(
        dist_to_segment(q, floor.line[0], floor.line[1]) < 1.5,
        "floor hit {q:?} off the floor line {:?}",
        floor.line
    );
}

// ---------------------------------------------------------------------------------------------
// Contrast and size.

/// WCAG 2's relative luminance (https://www.w3.org/TR/WCAG21/#dfn-relative-luminance).
fn luminance(c: [u8; 4]) -> f64 {
    let lin = |v: u8| {
        let s = f64::from(v) / 255.0;
        if s <= 0.03928 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    };
    0.2126 * lin(c[0]) + 0.7152 * lin(c[1]) + 0.0722 * lin(c[2])
}

/// WCAG 2's contrast ratio (https://www.w3.org/TR/WCAG21/#dfn-contrast-ratio).
fn contrast(a: [u8; 4], b: [u8; 4]) -> f64 {
    let (la, lb) = (luminance(a), luminance(b));
    (la.max(lb) + 0.05) / (la.min(lb) + 0.05)
}

#[test]
fn the_formula_matches_wcag_examples() {
    // Black on white is 21:1; white on white 1:1; #767676 on white is the classic 4.54:1.
    assert!((contrast([0, 0, 0, 255], [255, 255, 255, 255]) - 21.0).abs() < 1e-9);
    assert!((contrast([255; 4], [255; 4]) - 1.0).abs() < 1e-9);
    assert!((contrast([118, 118, 118, 255], [255, 255, 255, 255]) - 4.54).abs() < 0.01);
}

/// Every text of every case — labels (greys, faded earlier steps, the orange hit marks, the
/// teal refraction angles) and the caption, legend, scale bar and axes — reaches 4.5:1 against
/// the background, in both themes, and is opaque.
#[test]
fn every_text_reaches_wcag_aa_contrast() {
    for (name, t, o) in cases() {
        for theme in [Theme::LIGHT, Theme::DARK] {
            let o = ViewOptions { theme, ..o.clone() };
            let (_, texts) = slice::draw_annotated(&t, &o);
            assert!(
                texts.iter().any(|s| !s.label),
                "{name}: chrome texts recorded"
            );
            for s in &texts {
                let c = contrast(s.color, theme.background);
                assert!(
                    c >= 4.5 && s.color[3] == 255,
                    "{name} ({}): {:?} in {:?} is {c:.2}:1 on {:?}",
                    if theme == Theme::LIGHT {
                        "light"
                    } else {
                        "dark"
                    },
                    s.text,
                    s.color,
                    theme.background
                );
            }
        }
    }
}

/// At 800×600 (scale 1) no text of the slice is smaller than 16 px: the axes' letters and the
/// scale bar were 14 and 15 px.
#[test]
fn every_text_is_at_least_16_px_at_800_by_600() {
    for (name, t, o) in cases() {
        if o.width != 800 {
            continue;
        }
        let (_, texts) = slice::draw_annotated(&t, &o);
        for s in &texts {
            assert!(s.size >= 16.0, "{name}: {:?} is {} px", s.text, s.size);
        }
        for axis in ["x", "y", "z"] {
            if let Some(s) = texts.iter().find(|s| s.text == axis) {
                assert!(s.size >= 16.0);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// `--animate --steps A..B`.

fn raystep(args: &[&str]) -> (bool, String) {
    let out = assert_cmd::Command::cargo_bin("raystep")
        .unwrap()
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).to_string(),
    )
}

fn gif_frames(path: &Path) -> usize {
    use image::AnimationDecoder as _;
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    image::codecs::gif::GifDecoder::new(file)
        .unwrap()
        .into_frames()
        .count()
}

#[test]
fn animate_draws_exactly_the_steps_asked_for() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/mirror-glass.toml");
    let scene = scene.to_str().unwrap();
    let len = reported_trace().timeline().len();
    let gif = dir.path().join("range.gif");
    let frames = dir.path().join("frames");
    for (range, want) in [
        ("20..40", 21),
        ("30..30", 1),
        ("..4", 5),
        (&format!("{}..", len - 3) as &str, 3),
    ] {
        let (ok, err) = raystep(&[
            "diagram",
            scene,
            "--pixel",
            "240,140",
            "--kind",
            "slice",
            "--size",
            "160x120",
            "--animate",
            "--steps",
            range,
            "-o",
            gif.to_str().unwrap(),
        ]);
        assert!(ok, "--steps {range}: {err}");
        assert_eq!(gif_frames(&gif), want, "--steps {range}");
    }
    // --frames writes the range's steps, named by their step numbers.
    let (ok, err) = raystep(&[
        "diagram",
        scene,
        "--pixel",
        "240,140",
        "--size",
        "160x120",
        "--frames",
        frames.to_str().unwrap(),
        "--steps",
        "28..30",
    ]);
    assert!(ok, "{err}");
    let mut names: Vec<String> = std::fs::read_dir(&frames)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    names.sort();
    assert_eq!(names, ["step-0028.png", "step-0029.png", "step-0030.png"]);
}

#[test]
fn bad_step_ranges_fail_naming_the_flag_and_the_valid_range() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/mirror-glass.toml");
    let scene = scene.to_str().unwrap();
    let last = reported_trace().timeline().len() - 1;
    let valid = format!("0 … {last}");
    let gif = dir.path().join("bad.gif");
    let frames = dir.path().join("frames");
    for (range, why) in [
        ("40..20", "runs backwards"),
        (&format!("20..{}", last + 1) as &str, "does not exist"),
        ("20..99999999999999999999999", "does not exist"),
        ("twenty..forty", "not a step range"),
        ("20-40", "not a step range"),
        ("7", "not a step range"),
        ("", "not a step range"),
    ] {
        let (ok, err) = raystep(&[
            "diagram",
            scene,
            "--pixel",
            "240,140",
            "--size",
            "160x120",
            "--animate",
            "--frames",
            frames.to_str().unwrap(),
            "--steps",
            range,
            "-o",
            gif.to_str().unwrap(),
        ]);
        assert!(!ok, "--steps {range:?} is refused");
        assert!(
            err.contains(&format!("--steps {range}")) && err.contains(why) && err.contains(&valid),
            "--steps {range:?}: {err}"
        );
        assert!(!gif.exists(), "--steps {range:?}: no GIF written");
        assert!(!frames.exists(), "--steps {range:?}: no frames folder made");
    }
    // A range without anything to animate is an error too, not silently ignored.
    let png = dir.path().join("one.png");
    let (ok, err) = raystep(&[
        "diagram",
        scene,
        "--pixel",
        "240,140",
        "--steps",
        "1..3",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert!(
        !ok && err.contains("--steps") && err.contains("--animate"),
        "{err}"
    );
    assert!(!png.exists());
}
