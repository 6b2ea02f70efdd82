//! The app's layout at the sizes a classroom has (1024×768 to 3840×2160), normal and in
//! presentation mode, driven through egui_kittest: the render keeps its share of the window,
//! no panel overlaps another or leaves the window, the panels follow the window and never creep
//! by themselves, presentation mode gives the layout back exactly, the trace tree follows the
//! current step, every key press is a step, a double-click fits without selecting, and the idle
//! app asks for no repaint. The shares asserted (40 % of the width for the render's space) are
//! the design's, stated in the book (book/app.md), not read from the app.

use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT as _, Queryable as _};
use raystep::app::RaystepApp;
use raystep::app::learn::{LearnCmd, LearnTab};
use raystep::app::state::{Command, Prefs, StepMove};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
}

fn harness_at(size: [f32; 2], file: &Path, prefs: Prefs) -> Harness<'static, RaystepApp> {
    let file = file.to_path_buf();
    // Frames 1/60 s apart, as on a screen (kittest's default is 1/4 s: two clicks one frame
    // apart would be too slow for a double-click). The accessibility check is left to
    // tests/it/app/: the lessons panel's own widgets are checked there.
    Harness::builder()
        .with_size(egui::vec2(size[0], size[1]))
        .with_step_dt(1.0 / 60.0)
        .with_accessibility_check(false)
        .build_eframe(move |cc| {
            RaystepApp::with_context(&cc.egui_ctx, prefs.clone(), Some(file.clone()))
        })
}

fn wait_for(h: &mut Harness<'static, RaystepApp>, what: &str, done: impl Fn(&RaystepApp) -> bool) {
    let start = Instant::now();
    while !done(h.state()) {
        assert!(
            start.elapsed() < Duration::from_secs(90),
            "timed out waiting for {what}"
        );
        h.step();
        std::thread::sleep(Duration::from_millis(5));
    }
    h.step();
}

fn ready(app: &RaystepApp) -> bool {
    !app.state.busy() && app.state.rendered.is_some() && app.state.stepping.is_some()
}

/// What one layout measures: the window, the render's space and the image drawn in it.
#[derive(Debug, Clone, Copy)]
struct Measure {
    window: egui::Rect,
    centre: egui::Rect,
    image: egui::Rect,
}

impl Measure {
    fn of(h: &Harness<'static, RaystepApp>) -> Measure {
        let (p, v) = (&h.state().panels, &h.state().render);
        Measure {
            window: p.window_rect.expect("a frame was drawn"),
            centre: p.centre_rect.expect("a frame was drawn"),
            image: v.image_rect.expect("the render was drawn").0,
        }
    }

    fn width_share(&self) -> f32 {
        self.centre.width() / self.window.width()
    }

    fn image_share(&self) -> f32 {
        let shown = self.image.intersect(self.centre);
        shown.area() / self.window.area()
    }
}

/// Checks the invariants of one laid-out frame and returns its measure.
fn check_layout(h: &Harness<'static, RaystepApp>, what: &str) -> Measure {
    let m = Measure::of(h);
    assert!(
        m.centre.width() >= 0.4 * m.window.width() - 1.0,
        "{what}: the render's space is {:.0} of {:.0} points wide",
        m.centre.width(),
        m.window.width()
    );
    let panels = &h.state().panels.panel_rects;
    let inside = m.window.expand(0.5);
    for (name, r) in panels {
        assert!(
            inside.contains_rect(*r),
            "{what}: panel {name} {r:?} leaves the window {:?}",
            m.window
        );
        let overlap = r.intersect(m.centre);
        assert!(
            overlap.width() <= 0.5 || overlap.height() <= 0.5,
            "{what}: panel {name} {r:?} covers the render's space {:?}",
            m.centre
        );
    }
    for (i, (a, ra)) in panels.iter().enumerate() {
        for (b, rb) in &panels[i + 1..] {
            let o = ra.intersect(*rb);
            assert!(
                o.width() <= 0.5 || o.height() <= 0.5,
                "{what}: panels {a} {ra:?} and {b} {rb:?} overlap"
            );
        }
    }
    // The render is shown whole (fitted) inside its space.
    assert!(
        m.centre.expand(1.0).contains_rect(m.image),
        "{what}: the image {:?} spills out of its space {:?}",
        m.image,
        m.centre
    );
    m
}

const SIZES: [[f32; 2]; 4] = [
    [1024.0, 768.0],
    [1280.0, 720.0],
    [1920.0, 1080.0],
    [3840.0, 2160.0],
];

/// The layout at every size, normal (with Lessons off and on) and in presentation mode; prints
/// the table of shares that the book (book/app.md) quotes.
#[test]
fn the_render_keeps_its_share_at_every_size_and_mode() {
    let mut table = vec![];
    for size in SIZES {
        for mode in ["normal", "lessons", "presentation"] {
            let prefs = Prefs {
                show_learn: mode == "lessons",
                show_settings: mode != "lessons",
                ..Prefs::default()
            };
            let mut h = harness_at(size, &scene_path("cornell.toml"), prefs);
            wait_for(&mut h, "the render", ready);
            if mode == "presentation" {
                let mut p = h.state().state.prefs.clone();
                p.presentation = true;
                h.state_mut().state.apply(Command::SetPrefs(p));
            }
            h.run_steps(4);
            let what = format!("{}×{} {mode}", size[0], size[1]);
            let m = check_layout(&h, &what);
            // Nor does any control or text run past the window's right edge (in presentation
            // mode at 1024×768 the step bar's description did, and the timeline with it).
            nothing_runs_past(&h, m.window, &what);
            table.push(format!(
                "| {}×{} | {mode} | {:.0} % | {:.0} % |",
                size[0],
                size[1],
                m.width_share() * 100.0,
                m.image_share() * 100.0
            ));
        }
    }
    eprintln!(
        "| window | mode | render's space, share of the width | image, share of the window's area |\n|---|---|---|---|\n{}",
        table.join("\n")
    );
}

/// Every button, label, text field and chooser that starts inside `panel` (a panel, or the
/// whole window) ends inside it.
fn nothing_runs_past(h: &Harness<'static, RaystepApp>, panel: egui::Rect, what: &str) {
    let mut seen = 0;
    for role in [Role::Button, Role::Label, Role::ComboBox, Role::TextInput] {
        for node in h.query_all_by_role(role) {
            let r = node.rect();
            if panel.contains(r.min + egui::vec2(0.5, 0.5)) {
                seen += 1;
                assert!(
                    r.max.x <= panel.max.x + 1.0,
                    "{what}: {role:?} {:?} at {r:?} runs past {panel:?}",
                    node.accesskit_node().label()
                );
            }
        }
    }
    assert!(seen > 3, "{what}: only {seen} widgets found in the panel");
}

/// Nothing widens by itself: 200 idle frames with the lessons panel open leave every panel where
/// it was; turning Lessons off gives the other panels their widths back.
#[test]
fn panels_do_not_creep_and_lessons_off_gives_the_width_back() {
    let mut h = harness_at(
        [1024.0, 768.0],
        &scene_path("first-sphere.toml"),
        Prefs::default(),
    );
    wait_for(&mut h, "the render", ready);
    h.run_steps(3);
    let before = h.state().panels.panel_rects.clone();
    h.get_by_label("Lessons").click();
    h.run_steps(3);
    let with_lessons = h.state().panels.panel_rects.clone();
    for _ in 0..200 {
        h.step();
    }
    assert_eq!(
        h.state().panels.panel_rects,
        with_lessons,
        "the panels stay put"
    );
    check_layout(&h, "1024×768 with lessons");
    // Nothing in the lessons panel is wider than the panel (a wide button or chooser would
    // widen the lesson's text too, which the panel then cuts off): a lesson, then a question.
    let learn = with_lessons
        .iter()
        .find(|(name, _)| *name == "learn")
        .map(|(_, r)| *r)
        .expect("the lessons panel is shown");
    nothing_runs_past(&h, learn, "a lesson");
    let sheet = Path::new("lessons/exercises/02-sphere.toml").to_path_buf();
    for c in [
        LearnCmd::Tab(LearnTab::Exercises),
        LearnCmd::OpenSheet(sheet),
        LearnCmd::Student("alice".into()),
    ] {
        h.state_mut().state.apply(Command::Learn(c));
    }
    h.run_steps(4);
    nothing_runs_past(&h, learn, "a question");
    h.state_mut()
        .state
        .apply(Command::Learn(LearnCmd::Tab(LearnTab::Lesson)));
    h.run_steps(3);
    h.get_by_label("Lessons").click();
    h.run_steps(3);
    assert_eq!(
        h.state().panels.panel_rects,
        before,
        "Lessons off: the panels are as they were"
    );
}

/// Panels follow the window: the same fractions at two sizes; a spoiled remembered layout is
/// made valid on load; View → Reset layout puts the defaults back.
#[test]
fn panels_follow_the_window_and_spoiled_sizes_are_reset() {
    let mut prefs = Prefs::default();
    prefs.layout.explain = f32::NAN;
    prefs.layout.tree = 50.0;
    prefs.scale = -2.0;
    let mut h = harness_at([1920.0, 1080.0], &scene_path("first-sphere.toml"), prefs);
    wait_for(&mut h, "the render", ready);
    assert_eq!(
        h.state().state.prefs.layout,
        Prefs::default().layout,
        "a spoiled layout is replaced by the default"
    );
    assert_eq!(h.state().state.prefs.scale, 0.5, "the scale is clamped");
    let mut p = h.state().state.prefs.clone();
    p.scale = 1.0;
    h.state_mut().state.apply(Command::SetPrefs(p));
    h.run_steps(3);
    let wide = check_layout(&h, "1920×1080");
    let explain_wide = panel(&h, "explain").width();
    h.set_size(egui::vec2(2880.0, 1080.0));
    h.run_steps(3);
    let explain_wider = panel(&h, "explain").width();
    // The explain panel is 0.28 of the width at both sizes (nothing scaled: the side panels take
    // 0.14 + 0.16 + 0.28 = 0.58 < 0.6): 537 → 806 points.
    assert_eq!(explain_wide, (0.28f32 * 1920.0).floor());
    assert_eq!(explain_wider, (0.28f32 * 2880.0).floor());
    assert!(check_layout(&h, "2880×1080").centre.width() > wide.centre.width());

    // Drag the explain panel's edge 50 points to the left (the render keeps its 40 %: there is
    // room for 58 more), then reset.
    let edge = panel(&h, "explain").left();
    let y = panel(&h, "explain").center().y;
    h.drag_at(egui::pos2(edge, y));
    h.step();
    h.hover_at(egui::pos2(edge - 50.0, y));
    h.step();
    h.drop_at(egui::pos2(edge - 50.0, y));
    h.run_steps(3);
    let dragged = panel(&h, "explain").width();
    assert!(
        (dragged - (explain_wider + 50.0)).abs() <= 2.0,
        "the edge follows the pointer: {explain_wider} → {dragged}"
    );
    h.state_mut().state.apply(Command::ResetLayout);
    h.run_steps(3);
    assert_eq!(panel(&h, "explain").width(), explain_wider);
}

fn panel(h: &Harness<'static, RaystepApp>, name: &str) -> egui::Rect {
    h.state()
        .panels
        .panel_rects
        .iter()
        .find(|(n, _)| *n == name)
        .unwrap_or_else(|| panic!("no panel {name}"))
        .1
}

/// Presentation mode: the tree folded, settings hidden, the high-contrast theme shown as such in
/// the View menu, and Esc gives back exactly the panels and sizes there were.
#[test]
fn presentation_mode_gives_the_layout_back() {
    let mut h = harness_at(
        [1440.0, 900.0],
        &scene_path("cornell.toml"),
        Prefs::default(),
    );
    wait_for(&mut h, "the render", ready);
    // A layout of the user's own first.
    let mut p = h.state().state.prefs.clone();
    p.layout.tree = 0.2;
    p.layout.math = 0.3;
    h.state_mut().state.apply(Command::SetPrefs(p));
    h.run_steps(3);
    let before_prefs = h.state().state.prefs.clone();
    let before = h.state().panels.panel_rects.clone();
    let mut p = before_prefs.clone();
    p.presentation = true;
    h.state_mut().state.apply(Command::SetPrefs(p));
    h.run_steps(4);
    let st = &h.state().state.prefs;
    assert!(st.layout.tree_collapsed && !st.show_settings && !st.show_learn);
    let m = check_layout(&h, "1440×900 presentation");
    assert!(
        m.width_share() >= 0.4,
        "the render keeps 40 % in presentation mode"
    );
    assert!(panel(&h, "tree").width() <= 31.0, "the tree is folded");
    h.get_by_label("View").click();
    h.run_steps(2);
    assert!(h.query_by_label("Theme (presentation mode)").is_some());
    let hc = h.get_by_label("High contrast");
    assert_eq!(
        hc.accesskit_node().toggled(),
        Some(egui::accesskit::Toggled::True),
        "the View menu shows the theme in force"
    );
    assert_eq!(
        h.get_by_label("Light").accesskit_node().toggled(),
        Some(egui::accesskit::Toggled::False)
    );
    h.key_press(egui::Key::Escape); // closes the menu
    h.run_steps(2);
    if h.state().state.prefs.presentation {
        h.key_press(egui::Key::Escape);
        h.run_steps(4);
    }
    assert!(!h.state().state.prefs.presentation);
    let mut after = h.state().state.prefs.clone();
    after.presentation_layout = before_prefs.presentation_layout;
    assert_eq!(after, before_prefs, "the preferences are as before");
    let xs = |r: &[(&'static str, egui::Rect)]| {
        r.iter()
            .map(|(n, r)| (*n, r.left(), r.right()))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        xs(&h.state().panels.panel_rects),
        xs(&before),
        "the panels are where they were"
    );
}

/// The status bar keeps to one line and to the window: in presentation mode at 1024×768 the
/// scene's summary, the render's figures and a message do not fit (the app under Xvfb at
/// 1440×900 cut a path-traced render's "2 threads" off at the window's edge), so the last is cut
/// short with "…". Wrapping instead moved the render whenever the pointer's pixel appeared in the
/// bar (web/check.py's click then landed six pixels off).
#[test]
fn the_status_bar_keeps_to_one_line_in_presentation_mode() {
    let mut h = harness_at(
        [1024.0, 768.0],
        &scene_path("cornell.toml"),
        Prefs::default(),
    );
    wait_for(&mut h, "the render", ready);
    let mut p = h.state().state.prefs.clone();
    p.presentation = true;
    h.state_mut().state.apply(Command::SetPrefs(p));
    let text = "wrote the trace to /home/student/traces/cornell-pixel-128-96.json";
    h.state_mut().state.message = Some(raystep::app::state::Message {
        text: text.into(),
        error: false,
    });
    h.run_steps(4);
    let window = h.state().panels.window_rect.expect("a frame was drawn");
    let mut bottoms = vec![];
    for label in ["primitives (", "rendered in", text] {
        let node = h
            .query_all_by_role(Role::Label)
            .find(|n| {
                let a = n.accesskit_node();
                (a.label().or(a.value())).is_some_and(|l| l.contains(label))
            })
            .unwrap_or_else(|| panic!("no status label with {label:?}"));
        let r = node.rect();
        assert!(
            r.min.x >= window.min.x - 1.0 && r.max.x <= window.max.x + 1.0,
            "the status label {label:?} at {r:?} runs past the window {window:?}"
        );
        bottoms.push(r.max.y);
    }
    assert!(
        bottoms.iter().all(|&b| (b - bottoms[0]).abs() <= 1.0),
        "the status bar keeps to one line (label bottoms {bottoms:?})"
    );
}

/// Twenty → presses in one frame are twenty steps.
#[test]
fn every_key_press_is_a_step() {
    let mut h = harness_at(
        [1280.0, 720.0],
        &scene_path("mirror-glass.toml"),
        Prefs::default(),
    );
    wait_for(&mut h, "the render", ready);
    let n = h.state().state.stepping.as_ref().unwrap().len();
    assert!(n > 20, "a trace long enough: {n}");
    h.state_mut().state.apply(Command::Step(StepMove::First));
    for pressed in std::iter::repeat_n([true, false], 20).flatten() {
        h.input_mut().events.push(egui::Event::Key {
            key: egui::Key::ArrowRight,
            physical_key: None,
            pressed,
            repeat: false,
            modifiers: egui::Modifiers::NONE,
        });
    }
    h.step();
    assert_eq!(h.state().state.step, 20, "20 presses in one frame");
    for _ in 0..5 {
        h.key_press(egui::Key::ArrowLeft);
    }
    h.step();
    assert_eq!(h.state().state.step, 15, "5 presses, one per frame");
}

/// On a long nested trace the tree scrolls so that the current step's row is on screen.
#[test]
fn the_trace_tree_follows_the_current_step() {
    let mut h = harness_at(
        [1024.0, 768.0],
        &scene_path("mirror-glass.toml"),
        Prefs::default(),
    );
    wait_for(&mut h, "the render", ready);
    // The pixel with the longest trace on the image's middle row.
    let scene = raystep::scene::load_file(&scene_path("mirror-glass.toml")).unwrap();
    let (accel, _) = raystep::accel::SceneAccel::build(&scene);
    let tracer = raystep::trace::Tracer::new(&scene, &accel);
    let y = scene.camera.height / 2;
    let (x, len) = (0..scene.camera.width)
        .step_by(4)
        .map(|x| (x, tracer.record(x, y, 0).timeline().len()))
        .max_by_key(|(_, n)| *n)
        .unwrap();
    assert!(len > 100, "a long trace: {len} steps");
    h.state_mut().state.apply(Command::SelectPixel([x, y]));
    h.run_steps(2);
    let tree = panel(&h, "tree");
    for k in [len * 3 / 4, len - 1, len / 2, 5] {
        h.state_mut().state.apply(Command::Step(StepMove::To(k)));
        h.run_steps(3);
        let prefix = format!("{k}. ");
        let row = h
            .query_all_by_role(egui::accesskit::Role::Button)
            .find(|n| {
                n.accesskit_node()
                    .label()
                    .is_some_and(|l| l.starts_with(&prefix))
            })
            .unwrap_or_else(|| {
                let shown: Vec<String> = h
                    .query_all_by_role(egui::accesskit::Role::Button)
                    .filter_map(|n| n.accesskit_node().label())
                    .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
                    .collect();
                panic!("the row of step {k} is laid out: {shown:?}")
            });
        let r = row.rect();
        assert!(
            r.top() >= tree.top() && r.bottom() <= tree.bottom(),
            "step {k}'s row {r:?} is inside the tree panel {tree:?}"
        );
    }
}

/// A double-click on the render fits it to the view and selects nothing; a single click selects
/// its pixel once the double-click time has passed.
#[test]
fn a_double_click_fits_without_selecting() {
    let mut h = harness_at(
        [1280.0, 720.0],
        &scene_path("three-spheres.toml"),
        Prefs::default(),
    );
    wait_for(&mut h, "the render", ready);
    let before = h.state().state.pixel;
    h.state_mut().render.zoom = 3.0;
    h.run_steps(2);
    let (rect, _) = h.state().render.image_rect.unwrap();
    let centre = h
        .state()
        .panels
        .centre_rect
        .unwrap()
        .intersect(rect)
        .center();
    let click = |h: &mut Harness<'static, RaystepApp>| {
        for pressed in [true, false] {
            h.event(egui::Event::PointerButton {
                pos: centre,
                button: egui::PointerButton::Primary,
                pressed,
                modifiers: egui::Modifiers::NONE,
            });
        }
        h.step();
    };
    h.hover_at(centre);
    h.step();
    click(&mut h);
    click(&mut h);
    for _ in 0..40 {
        h.step();
    }
    assert_eq!(
        h.state().render.zoom,
        1.0,
        "the double-click fitted the view"
    );
    assert_eq!(h.state().state.pixel, before, "and selected nothing");
    // One click selects, after the double-click delay.
    let (rect, scale) = h.state().render.image_rect.unwrap();
    let pos = rect.min + egui::vec2(10.5, 10.5) * scale;
    h.hover_at(pos);
    h.step();
    for pressed in [true, false] {
        h.event(egui::Event::PointerButton {
            pos,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: egui::Modifiers::NONE,
        });
    }
    h.step();
    // The pass that turns the click into a selection comes from a timer, with no input after
    // it: it must ask for another pass, or the new pixel is not drawn until the mouse moves.
    let mut steps = 0;
    while h.state().state.pixel != Some([10, 10]) {
        assert!(steps < 40, "the click selected its pixel");
        h.step();
        steps += 1;
    }
    assert_eq!(
        h.output().viewport_output[&egui::ViewportId::ROOT].repaint_delay,
        Duration::ZERO,
        "the selecting pass asks for a repaint to show the new pixel"
    );
}

/// Once the render is done and nothing plays, the app asks for no repaint at all.
#[test]
fn the_idle_app_does_not_repaint() {
    let mut h = harness_at(
        [1280.0, 720.0],
        &scene_path("first-sphere.toml"),
        Prefs::default(),
    );
    wait_for(&mut h, "the render", ready);
    h.run(); // panics if the UI keeps asking for immediate repaints
    h.step();
    assert_eq!(
        h.output().viewport_output[&egui::ViewportId::ROOT].repaint_delay,
        Duration::MAX,
        "no repaint is scheduled while idle"
    );
}

/// The error banner has a × that hides it, and a status message goes away by itself.
#[test]
fn the_error_banner_can_be_dismissed_and_messages_expire() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "[[sphere]]\ncenter = [0, 0, 0]\nradius = -1\n").unwrap();
    let mut h = harness_at(
        [1024.0, 768.0],
        &scene_path("first-sphere.toml"),
        Prefs::default(),
    );
    wait_for(&mut h, "the render", ready);
    h.state_mut().state.apply(Command::Open(bad));
    wait_for(&mut h, "the load error", |a| a.state.load_error.is_some());
    h.run_steps(2);
    let with_banner = Measure::of(&h);
    assert!(
        with_banner.centre.height() >= 0.5 * with_banner.window.height(),
        "the banner leaves the render most of the height"
    );
    h.get_by_label("×").click();
    h.run_steps(2);
    assert!(h.state().state.load_error.is_none());
    assert!(h.query_by_label("The file did not load").is_none());

    use raystep::app::state::Message;
    h.state_mut().state.message = Some(Message {
        text: "wrote something".into(),
        error: false,
    });
    h.step();
    assert!(h.state().state.message.is_some());
    let t = Instant::now() + Duration::from_secs(9);
    h.state_mut().state.tick(t);
    assert!(
        h.state().state.message.is_none(),
        "an 8 s message is gone after 9 s"
    );
}

/// Whether wgpu finds an adapter (lavapipe on a machine without a GPU).
fn have_adapter() -> bool {
    let instance = eframe::wgpu::Instance::new(
        eframe::wgpu::InstanceDescriptor::new_without_display_handle_from_env(),
    );
    !pollster::block_on(instance.enumerate_adapters(eframe::wgpu::Backends::all())).is_empty()
}

/// Snapshots at 1024×768, normal and in presentation mode (rendered with wgpu on the software
/// adapter; the timing figures, which change every run, are masked).
#[test]
fn snapshots_at_1024_by_768() {
    if !have_adapter() {
        assert!(
            std::env::var("CI").is_err(),
            "CI must run the layout snapshots: install Mesa's lavapipe (mesa-vulkan-drivers)"
        );
        eprintln!("SKIPPED: wgpu found no adapter");
        return;
    }
    let mut failures = vec![];
    for (name, presentation) in [
        ("layout-1024x768", false),
        ("layout-1024x768-presentation", true),
    ] {
        // A relative path: the window title shows it, an absolute one differs between checkouts.
        let path = Path::new("scenes").join("cornell.toml");
        let mut h = Harness::builder()
            .with_size(egui::vec2(1024.0, 768.0))
            .wgpu()
            .build_eframe(move |cc| {
                RaystepApp::with_context(&cc.egui_ctx, Prefs::default(), Some(path.clone()))
            });
        wait_for(&mut h, "the render", ready);
        // A pixel on the tall box: a triangle test with a barycentric diagram.
        h.state_mut().state.apply(Command::SelectPixel([200, 150]));
        h.state_mut().state.apply(Command::Step(StepMove::To(4)));
        if presentation {
            let mut p = h.state().state.prefs.clone();
            p.presentation = true;
            h.state_mut().state.apply(Command::SetPrefs(p));
        }
        h.run_steps(6);
        // The timings (the status bar's to the window's right edge: its width moves with the
        // digits), as the main views' snapshots mask them.
        crate::app::mask_timings(&mut h);
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
