//! The app, driven through egui_kittest as a user would: open a shipped scene, click a pixel,
//! step, read the math panel by its accessible labels, flip a setting, open a bad scene, save
//! and reopen a trace. The expected numbers come from raystep's tracer run directly (the
//! library the app wraps) or from hand computation, never from the app itself.

use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT as _, Queryable as _};
use raystep::app::RaystepApp;
use raystep::app::state::{Command, Document, Prefs, StepMove};
use raystep::gpu::GpuPath;
use raystep::record::Step;
use raystep::record::number::num;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::common::app_harness;
use app_harness::wgpu_harness;

fn harness(file: Option<&Path>) -> Harness<'static, RaystepApp> {
    let file = file.map(Path::to_path_buf);
    Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .build_eframe(move |cc| {
            RaystepApp::with_context(&cc.egui_ctx, Prefs::default(), file.clone())
        })
}

/// Steps the UI until `done` holds (the render runs on other threads), at most 60 s.
fn wait_for(h: &mut Harness<'static, RaystepApp>, what: &str, done: impl Fn(&RaystepApp) -> bool) {
    let start = Instant::now();
    while !done(h.state()) {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "timed out waiting for {what}"
        );
        h.step();
        std::thread::sleep(Duration::from_millis(5));
    }
    h.step();
}

fn rendered(app: &RaystepApp) -> bool {
    !app.state.busy() && app.state.rendered.is_some()
}

/// Clicks pixel `p` of the render view.
fn click_pixel(h: &mut Harness<'static, RaystepApp>, p: [u32; 2]) {
    let (rect, scale) = h
        .state()
        .render
        .image_rect
        .expect("the render view was drawn");
    let pos = rect.min + egui::vec2(p[0] as f32 + 0.5, p[1] as f32 + 0.5) * scale;
    h.hover_at(pos);
    h.step();
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        });
        h.step();
    }
    // A click selects once the double-click time (0.3 s) has passed without a second click.
    for _ in 0..40 {
        if h.state().state.pixel == Some(p) {
            break;
        }
        h.step();
    }
}

/// The text of every label on screen.
fn labels(h: &Harness<'static, RaystepApp>) -> Vec<String> {
    h.query_all_by_role(Role::Label)
        .filter_map(|n| n.accesskit_node().value())
        .collect()
}

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
}

/// The reference trace, recorded by the library directly.
fn reference(path: &Path, p: [u32; 2]) -> raystep::record::Trace {
    let scene = raystep::scene::load_file(path).unwrap();
    let (accel, _) = raystep::accel::SceneAccel::build(&scene);
    raystep::trace::Tracer::new(&scene, &accel).record(p[0], p[1], 0)
}

#[test]
fn click_a_pixel_step_and_read_the_math() {
    let path = scene_path("three-spheres.toml");
    let mut h = harness(Some(&path));
    wait_for(&mut h, "the first render", rendered);
    // The middle sphere sits in the image centre; pick a pixel a little off it.
    let p = [150, 110];
    click_pixel(&mut h, p);
    assert_eq!(
        h.state().state.pixel,
        Some(p),
        "the click selected its pixel"
    );
    let want = reference(&path, p);
    let s = h.state().state.stepping.as_ref().expect("a trace");
    assert_eq!(
        s.trace.to_json(),
        want.to_json(),
        "the app's trace is the tracer's"
    );
    assert_eq!(h.state().state.step, 0);

    // Step with the keyboard and the buttons.
    h.key_press(egui::Key::ArrowRight);
    h.step();
    assert_eq!(h.state().state.step, 1);
    h.get_by_label("Next ▶").click();
    h.step();
    h.step();
    assert_eq!(h.state().state.step, 2);
    h.get_by_label("◀ Previous").click();
    h.step();
    h.step();
    assert_eq!(h.state().state.step, 1);
    h.key_press(egui::Key::End);
    h.step();
    let n = want.timeline().len();
    assert_eq!(h.state().state.step, n - 1);
    h.key_press(egui::Key::Home);
    h.step();
    assert_eq!(h.state().state.step, 0);

    // Go to the first sphere test and read Δ and the roots from the math panel.
    let (k, test) = want
        .timeline()
        .iter()
        .enumerate()
        .find_map(|(k, (_, s))| match &s.step {
            Step::Sphere { test, .. } => Some((k, *test)),
            _ => None,
        })
        .expect("a sphere test");
    h.state_mut().state.apply(Command::Step(StepMove::To(k)));
    h.step();
    h.step();
    let lines = labels(&h);
    assert!(
        lines.iter().any(
            |l| l.starts_with("Δ = ") && l.ends_with(&format!(" = {}", num(test.discriminant)))
        ),
        "a math line gives Δ = the recorded discriminant {}: {lines:#?}",
        num(test.discriminant)
    );
    for (name, v) in [("a", test.a), ("c", test.c)] {
        assert!(
            lines
                .iter()
                .any(|l| l.starts_with(&format!("{name} = "))
                    && l.ends_with(&format!(" = {}", num(v)))),
            "the math panel gives {name} = {}: {lines:#?}",
            num(v)
        );
    }
}

#[test]
fn a_setting_restarts_the_render_and_retraces() {
    let path = scene_path("three-spheres.toml");
    let mut h = harness(Some(&path));
    wait_for(&mut h, "the first render", rendered);
    let before = h.state().state.renders_started;
    h.get_by_label("textbook").click();
    h.step();
    assert_eq!(
        h.state().state.renders_started,
        before + 1,
        "the render restarted"
    );
    assert_eq!(
        h.state().state.settings.sphere_method,
        raystep::shapes::SphereMethod::Textbook
    );
    wait_for(&mut h, "the second render", rendered);
    let s = h.state().state.stepping.as_ref().expect("a trace");
    assert_eq!(
        s.trace.settings.sphere_method,
        raystep::shapes::SphereMethod::Textbook,
        "the selected pixel was traced again with the new method"
    );
    // Settings that do not apply are left out: three spheres have no triangles.
    assert!(h.query_by_label("Möller–Trumbore").is_none());
    assert!(h.query_by_label("watertight").is_none());
}

#[test]
fn a_bad_scene_shows_its_error_and_keeps_the_old_one() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "[[sphere]]\ncenter = [0, 0, 0]\nradius = -1\n").unwrap();
    let mut h = harness(Some(&scene_path("first-sphere.toml")));
    wait_for(&mut h, "the first render", rendered);
    // Through the Open dialog, as a user would.
    h.get_by_label("File").click();
    h.run_steps(3);
    h.get_by_label("Open…").click();
    h.run_steps(3);
    h.get_by_role_and_label(Role::TextInput, "Path").focus();
    h.step();
    // Replace the prefilled path (the open file's): select all, then type.
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::A);
    h.step();
    h.get_by_role_and_label(Role::TextInput, "Path")
        .type_text(&bad.display().to_string());
    h.step();
    assert!(
        matches!(&h.state().state.dialog, Some(raystep::app::state::Dialog::Open { path }) if *path == bad.display().to_string()),
        "the typed path replaced the prefilled one: {:?}",
        h.state().state.dialog
    );
    h.get_by_label("Open").click();
    wait_for(&mut h, "the load error", |a| a.state.load_error.is_some());
    let err = h.state().state.load_error.clone().expect("an error");
    assert!(err.contains("bad.toml:3:"), "file and line in {err:?}");
    assert!(err.contains("radius"), "the field in {err:?}");
    assert!(
        h.query_by_label_contains("bad.toml:3:").is_some(),
        "the error is on screen"
    );
    assert!(
        matches!(&h.state().state.doc, Document::Scene { path: Some(p), .. } if p.ends_with("first-sphere.toml")),
        "the previous scene stays open"
    );
    // Fixing the file on disk reloads it by itself.
    std::thread::sleep(Duration::from_millis(1100));
    std::fs::write(
        &bad,
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\n[[light]]\nposition = [-10, 10, -10]\n",
    )
    .unwrap();
    wait_for(&mut h, "the reload", |a| a.state.load_error.is_none());
    assert!(
        matches!(&h.state().state.doc, Document::Scene { path: Some(p), .. } if p.ends_with("bad.toml"))
    );
}

#[test]
fn save_a_trace_and_replay_it_without_the_scene() {
    let path = scene_path("mirror-glass.toml");
    let dir = tempfile::tempdir().unwrap();
    let saved = dir.path().join("t.json");
    let mut h = harness(Some(&path));
    wait_for(&mut h, "the first render", rendered);
    let p = h.state().state.pixel.expect("the centre pixel is selected");
    let want = reference(&path, p);
    h.state_mut().state.apply(Command::Save(
        raystep::app::state::SaveKind::Trace,
        saved.clone(),
    ));
    h.step();
    let msg = h.state().state.message.clone().expect("a status message");
    assert!(!msg.error, "{}", msg.text);
    h.state_mut().state.apply(Command::Open(saved.clone()));
    h.step();
    h.step();
    assert!(matches!(h.state().state.doc, Document::Trace { .. }));
    let s = h
        .state()
        .state
        .stepping
        .as_ref()
        .expect("the replayed trace");
    assert_eq!(s.trace.to_json(), want.to_json());
    assert!(
        h.query_by_label("Replaying a saved trace").is_some(),
        "the render view says it is a replay"
    );
    h.key_press(egui::Key::ArrowRight);
    h.step();
    assert_eq!(h.state().state.step, 1, "stepping works without the scene");
    // A saved diagram export is a PNG.
    let png = dir.path().join("d.png");
    h.state_mut().state.apply(Command::Save(
        raystep::app::state::SaveKind::DiagramPng,
        png.clone(),
    ));
    let bytes = std::fs::read(&png).expect("the PNG was written");
    assert_eq!(&bytes[1..4], b"PNG");
}

/// Forgets the panels' remembered sizes and lays the window out again: a panel's default size is
/// taken from the frame it first appears in, which depends on how far the background render had
/// got (the step controls appear only once a pixel is traced), so a snapshot must not depend on
/// that timing.
fn settle_layout(h: &mut Harness<'static, RaystepApp>) {
    h.ctx.memory_mut(|m| m.data.clear());
    h.run_steps(6);
}

/// Runs frames until a check's expected answer has come back from its background thread.
fn wait_for_check(h: &mut Harness<'static, RaystepApp>) {
    for _ in 0..2000 {
        if h.state().state.learn.checking.is_none() {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
        h.run_steps(1);
    }
    panic!("the check did not finish in 10 s");
}

/// Where the timing figures are (they change every run), in points: the render's in the status
/// bar, to the window's right edge, and the trace's in the tree panel.
fn timing_rects(h: &Harness<'static, RaystepApp>) -> Vec<egui::Rect> {
    let right = h.ctx.content_rect().right();
    ["rendered in", "recorded in"]
        .iter()
        .filter_map(|l| h.query_by_label_contains(l).map(|n| (*l, n.rect())))
        .map(|(l, r)| match l {
            "rendered in" => {
                egui::Rect::from_min_max(r.min, egui::pos2(right.max(r.max.x), r.max.y))
            }
            _ => r,
        })
        .collect()
}

/// Masks the timing figures (they change every run) in the next snapshot; returns how many.
/// The status bar's mask runs to the window's right edge: the label's own width changes with
/// its digits (a busy machine's "trace 156 ms" is wider than "trace 56 ms"), and a mask of that
/// width would too.
pub(crate) fn mask_timings(h: &mut Harness<'static, RaystepApp>) -> usize {
    let masks = timing_rects(h);
    let n = masks.len();
    for r in masks {
        h.mask(r);
    }
    n
}

/// Snapshots of the main views rendered with wgpu on the software adapter. The thresholds
/// tolerate driver noise in antialiased edges but catch a moved or missing panel; the timing
/// figures (which change every run) are masked.
#[test]
fn snapshots_of_the_main_views() {
    let mut failures = vec![];
    for (scene, name, pixel, kind) in [
        (
            "three-spheres.toml",
            "app-three-spheres-quadratic",
            [150, 110],
            "Sphere",
        ),
        (
            "triangles.toml",
            "app-triangles-barycentric",
            [160, 120],
            "Triangle",
        ),
    ] {
        // A relative path (tests run in the crate root): the window title shows it, and an
        // absolute one would differ between checkouts.
        let path = Path::new("scenes").join(scene);
        let Some(mut h) = wgpu_harness("snapshots_of_the_main_views", Some(path.clone()), false)
        else {
            return;
        };
        wait_for(&mut h, "the render", rendered);
        h.state_mut().state.apply(Command::SelectPixel(pixel));
        // Show the first test of the wanted kind.
        let want = reference(&path, pixel);
        let k = want
            .timeline()
            .iter()
            .position(|(_, s)| match kind {
                "Sphere" => matches!(s.step, Step::Sphere { .. }),
                _ => matches!(s.step, Step::Triangle { .. }),
            })
            .expect("the step kind is in the trace");
        h.state_mut().state.apply(Command::Step(StepMove::To(k)));
        settle_layout(&mut h);
        assert_eq!(
            mask_timings(&mut h),
            2,
            "the timing labels are there to mask"
        );
        if let Err(e) = h.try_snapshot_options(
            name,
            &egui_kittest::SnapshotOptions::new()
                .threshold(2.0)
                .max_failed_pixels(200),
        ) {
            failures.push(e.to_string());
        }
    }
    assert!(
        failures.is_empty(),
        "snapshots differ:\n{}",
        failures.join("\n")
    );
}

/// Playback advances one step per 1/speed seconds of the UI clock and stops at the last step;
/// driven through the state alone, with a simulated clock.
#[test]
fn playback_advances_with_the_clock_and_stops_at_the_end() {
    use raystep::app::state::AppState;
    let mut st = AppState::new(
        Prefs {
            speed: 10.0,
            ..Prefs::default()
        },
        || {},
    );
    st.open(&scene_path("first-sphere.toml"));
    let start = Instant::now();
    while st.stepping.is_none() {
        assert!(start.elapsed() < Duration::from_secs(30), "no trace");
        st.tick(Instant::now());
        std::thread::sleep(Duration::from_millis(5));
    }
    let n = st.stepping.as_ref().unwrap().len();
    assert!(n > 3);
    st.apply(Command::TogglePlay);
    assert!(st.playing);
    let t0 = Instant::now();
    st.tick(t0);
    assert_eq!(st.step, 0, "the first tick only starts the clock");
    st.tick(t0 + Duration::from_millis(50));
    assert_eq!(st.step, 0, "half an interval at 10 steps/s is not a step");
    st.tick(t0 + Duration::from_millis(100));
    assert_eq!(st.step, 1);
    let mut t = t0 + Duration::from_millis(100);
    for _ in 0..n + 5 {
        t += Duration::from_millis(100);
        st.tick(t);
    }
    assert_eq!(st.step, n - 1, "playback ends on the last step");
    assert!(!st.playing, "and stops there");
    // Play from the end starts over.
    st.apply(Command::TogglePlay);
    assert_eq!(st.step, 0);
}

/// "One sample at a time": the traced sample advances one per 1/speed seconds and stops at the
/// pixel's last; each step's trace is that sample, its record the same pixel, and the running
/// estimate over samples 0…k is their plain mean (checked by hand from the recorded values).
#[test]
fn samples_play_one_at_a_time_and_the_estimate_follows() {
    use raystep::app::state::AppState;
    use raystep::explain::describe::running_estimate;
    let mut st = AppState::new(
        Prefs {
            speed: 10.0,
            ..Prefs::default()
        },
        || {},
    );
    st.open(&scene_path("soft-shadows.toml"));
    let start = Instant::now();
    while st.prepared.is_none() {
        assert!(start.elapsed() < Duration::from_secs(60), "no scene");
        st.tick(Instant::now());
        std::thread::sleep(Duration::from_millis(5));
    }
    let mut s = st.settings.clone();
    s.spp = 4;
    st.apply(Command::SetSettings(s));
    st.apply(Command::SelectPixel([100, 150]));
    // The new settings' scene is prepared in the background; then the pixel is traced.
    while st
        .stepping
        .as_ref()
        .is_none_or(|s| s.trace.settings.spp != 4)
    {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no trace at 4 spp"
        );
        st.tick(Instant::now());
        std::thread::sleep(Duration::from_millis(5));
    }
    st.apply(Command::ToggleSamplePlay);
    assert!(st.sample_playing);
    let t0 = Instant::now();
    st.tick(t0);
    assert_eq!(st.sample, 0, "the first tick only starts the clock");
    let mut t = t0;
    for k in 1..4 {
        t += Duration::from_millis(100);
        st.tick(t);
        assert_eq!(st.sample, k);
        let trace = &st.stepping.as_ref().unwrap().trace;
        assert_eq!(trace.sample, k);
        let mc = trace.monte_carlo.as_ref().unwrap();
        let e = running_estimate(mc, k as usize + 1);
        let by_hand: f64 = mc.samples[..=k as usize]
            .iter()
            .map(|s| f64::from(s.color[0]))
            .sum::<f64>()
            / (k + 1) as f64;
        assert!((e.mean[0] - by_hand).abs() < 1e-12);
        assert_eq!(e.n, k as usize + 1);
    }
    t += Duration::from_millis(100);
    st.tick(t);
    assert_eq!(st.sample, 3, "it stops on the last sample");
    assert!(!st.sample_playing);
    // Playing again from the last sample starts over.
    st.apply(Command::ToggleSamplePlay);
    assert_eq!(st.sample, 0);
}

/// "Watch it converge": the render starts again and holds each pass (1, 1, 2, 4 samples per
/// pixel at 8 spp) on screen for `CONVERGE_PACE`, so the run takes at least three holds (none
/// after the last pass); every pass's samples count is seen on the way, and the finished image
/// is the unpaced render's, bit for bit.
#[test]
fn watch_it_converge_holds_each_pass_and_renders_the_same_image() {
    use raystep::app::state::{AppState, CONVERGE_PACE};
    use std::sync::atomic::Ordering;
    // A small copy of the scene: an unpaced pass takes milliseconds, so the holds are what
    // the run's length measures.
    let dir = tempfile::tempdir().unwrap();
    let small = dir.path().join("soft-shadows-small.toml");
    let text = std::fs::read_to_string(scene_path("soft-shadows.toml"))
        .unwrap()
        .replace("width = 320", "width = 48")
        .replace("height = 240", "height = 36");
    std::fs::write(&small, text).unwrap();
    let mut st = AppState::new(Prefs::default(), || {});
    st.open(&small);
    let start = Instant::now();
    let settle = |st: &mut AppState, what: &str| {
        while st.busy() || st.rendered.is_none() {
            assert!(start.elapsed() < Duration::from_secs(120), "{what}");
            st.tick(Instant::now());
            std::thread::sleep(Duration::from_millis(2));
        }
    };
    settle(&mut st, "no first render");
    let mut s = st.settings.clone();
    s.spp = 8;
    st.apply(Command::SetSettings(s));
    settle(&mut st, "no render at 8 spp");
    let fast = st.rendered.as_ref().unwrap().output.pixels.clone();
    assert!(
        st.rendered.as_ref().unwrap().wall < CONVERGE_PACE,
        "the unpaced render should be quick"
    );
    st.apply(Command::WatchConverge);
    let t0 = Instant::now();
    assert!(
        st.job
            .as_ref()
            .is_some_and(|j| j.pace == Some(CONVERGE_PACE))
    );
    let mut seen = vec![];
    while st.busy() || st.rendered.is_none() {
        assert!(
            t0.elapsed() < Duration::from_secs(120),
            "the paced render did not end"
        );
        if let Some(j) = &st.job {
            let done = j.live.samples_done.load(Ordering::Relaxed);
            if seen.last() != Some(&done) {
                seen.push(done);
            }
        }
        st.tick(Instant::now());
        std::thread::sleep(Duration::from_millis(2));
    }
    let took = t0.elapsed();
    assert!(took >= CONVERGE_PACE * 3, "{took:?}");
    for k in [1, 2, 4] {
        assert!(
            seen.contains(&k),
            "{k} samples per pixel never shown: {seen:?}"
        );
    }
    assert!(st.rendered.as_ref().unwrap().output.pixels == fast);
}

/// "Large view": the diagram of the step, drawn over the render and the explain panel at that
/// size (here the area light of a light-sample step), following the step; "✕ Back to the panel"
/// puts it back.
#[test]
fn the_diagram_shows_large_and_follows_the_step() {
    let path = scene_path("soft-shadows.toml");
    let mut h = harness(Some(&path));
    wait_for(&mut h, "the first render", rendered);
    click_pixel(&mut h, [160, 120]);
    wait_for(&mut h, "the pixel's trace", |a| {
        rendered(a)
            && a.state
                .stepping
                .as_ref()
                .is_some_and(|s| s.trace.pixel == [160, 120])
    });
    h.run_steps(3);
    // Step 8 samples a point on "small light" (`raystep trace … --pixel 160,120`).
    h.state_mut().state.apply(Command::Step(StepMove::To(8)));
    h.step();
    assert!(h.query_by_label("Area light, large").is_none());
    h.step(); // the controls' layout settles (the slice's slider row goes)
    h.get_by_label("Large view").click();
    h.step();
    h.step();
    assert!(h.state().panels.diagram.enlarged);
    assert!(h.query_by_label("Area light, large").is_some());
    let big = h.get_by_label("Area light, large").rect();
    let centre = h.state().panels.centre_rect.unwrap();
    assert!(big.min.x <= centre.min.x + 20.0, "{big:?} over {centre:?}");
    // Step 0 (the camera): the diagram there is the scene slice.
    h.state_mut().state.apply(Command::Step(StepMove::To(0)));
    h.step();
    h.step();
    assert!(h.query_by_label("Slice, large").is_some());
    h.get_by_label("✕ Back to the panel").click();
    h.step();
    h.step();
    assert!(!h.state().panels.diagram.enlarged);
    assert!(h.query_by_label("Slice, large").is_none());
}

/// Presentation mode: high contrast (black panels, white text) and the presentation scale (in
/// proportion to the window's height below 1080 points); leaving it (Esc) restores the chosen
/// theme and scale.
#[test]
fn presentation_mode_is_high_contrast_and_large() {
    let mut h = harness(Some(&scene_path("first-sphere.toml")));
    wait_for(&mut h, "the first render", rendered);
    assert_eq!(h.ctx.zoom_factor(), 1.0);
    let mut p = h.state().state.prefs.clone();
    p.presentation = true;
    p.presentation_scale = 1.75;
    h.state_mut().state.apply(Command::SetPrefs(p));
    h.run_steps(3);
    // The scale is chosen for a screen 1080 points high: this window is 900, so 1.75 · 900/1080.
    assert!(
        (h.ctx.zoom_factor() - 1.46).abs() < 0.006,
        "zoom {}",
        h.ctx.zoom_factor()
    );
    let v = h.ctx.global_style().visuals.clone();
    assert_eq!(v.panel_fill, egui::Color32::BLACK);
    assert_eq!(v.override_text_color, Some(egui::Color32::WHITE));
    h.key_press(egui::Key::Escape);
    h.run_steps(3);
    assert!(!h.state().state.prefs.presentation);
    assert_eq!(h.ctx.zoom_factor(), 1.0);
    assert_ne!(
        h.ctx.global_style().visuals.panel_fill,
        egui::Color32::BLACK
    );
}

fn open_learn(h: &mut Harness<'static, RaystepApp>) {
    h.get_by_label("Lessons").click();
    h.run_steps(3);
    assert!(
        h.state().state.prefs.show_learn,
        "the Lessons button opens the panel"
    );
}

mod learn;
mod picture;
mod tabs;
