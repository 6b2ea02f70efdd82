//! The app's 3D view, driven like a user: it opens, orbiting changes the picture, stepping
//! changes the rays drawn, dragging an object's arrow moves it (the traced pixel's numbers and
//! the render change), undo restores them bit for bit, and save writes a TOML that loads to the
//! edited scene and keeps the user's comments. Rendered through wgpu on the software adapter
//! (lavapipe); skipped, saying so, where wgpu finds no adapter (never under CI).

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use raystep::app::RaystepApp;
use raystep::app::gpu_view::CentralTab;
use raystep::app::state::editing::EditCmd;
use raystep::app::state::{Command, StepMove};
use raystep::scene::Shape;
use raystep::scene::edit::Edit;
use raystep::view3d::Viewpoint;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::common::app_harness;

/// The whole app with the GPU view on `file` (None where wgpu finds no adapter, outside CI).
fn harness(test: &str, file: PathBuf) -> Option<Harness<'static, RaystepApp>> {
    app_harness::wgpu_harness(test, Some(file), true)
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
    h.run_steps(3);
}

fn settled(app: &RaystepApp) -> bool {
    !app.state.busy() && app.state.rendered.is_some() && app.state.stepping.is_some()
}

/// The Cornell box copied into a fresh folder, with a comment of the user's on top.
fn cornell_copy(dir: &Path) -> PathBuf {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell.toml");
    let text = std::fs::read_to_string(src).unwrap();
    let path = dir.join("my-cornell.toml");
    std::fs::write(&path, format!("# my own notes: keep me\n{text}")).unwrap();
    path
}

fn trace_json(h: &Harness<'static, RaystepApp>) -> String {
    h.state().state.stepping.as_ref().unwrap().trace.to_json()
}

fn render_pixels(h: &Harness<'static, RaystepApp>) -> Vec<[u32; 3]> {
    let r = h.state().state.rendered.as_ref().unwrap();
    r.output
        .pixels
        .iter()
        .map(|c| [c.x.to_bits(), c.y.to_bits(), c.z.to_bits()])
        .collect()
}

fn mirror_center(app: &RaystepApp) -> glam::Vec3 {
    let s = app.state.scene().unwrap();
    let g = s.groups.iter().find(|g| g.name == "mirror ball").unwrap();
    match s.objects[g.first as usize].shape {
        Shape::Sphere { center, .. } => center,
        _ => panic!("the mirror ball is a sphere"),
    }
}

#[test]
fn the_3d_view_orbits_steps_edits_undoes_and_saves() {
    let dir = tempfile::tempdir().unwrap();
    let path = cornell_copy(dir.path());
    let Some(mut h) = harness(
        "the_3d_view_orbits_steps_edits_undoes_and_saves",
        path.clone(),
    ) else {
        return;
    };
    wait_for(&mut h, "the render", settled);
    // A pixel whose primary ray hits the mirror ball (left of centre, low).
    let pixel = [98, 214];
    h.state_mut().state.apply(Command::SelectPixel(pixel));
    wait_for(&mut h, "the trace", settled);
    assert_eq!(
        h.state()
            .state
            .stepping
            .as_ref()
            .unwrap()
            .trace
            .root
            .hit
            .as_ref()
            .unwrap()
            .name,
        "mirror ball"
    );

    // The tab opens and draws.
    h.get_by_label("3D view").click();
    h.run_steps(4);
    assert_eq!(h.state().panels.gpu.tab, CentralTab::Scene3d);
    assert!(h.state().panels.scene3d.draws > 0, "the 3D view was drawn");
    let first = h.render().expect("the window renders");

    // Orbiting (a drag on the picture) changes the viewpoint and the picture.
    let (_, rect) = h.state().panels.scene3d.last_view.expect("the picture");
    let c = rect.center();
    h.drag_at(c);
    h.step();
    h.hover_at(c + egui::vec2(60.0, 10.0));
    h.step();
    h.drop_at(c + egui::vec2(60.0, 10.0));
    h.run_steps(3);
    assert_ne!(h.state().panels.scene3d.viewpoint, Viewpoint::default());
    let orbited = h.render().unwrap();
    assert_ne!(
        first.as_raw(),
        orbited.as_raw(),
        "orbiting changes the picture"
    );

    // Stepping changes which rays are drawn: one at the start, the whole tree at the end.
    h.state_mut().state.apply(Command::Step(StepMove::First));
    h.run_steps(3);
    let at_start = h.state().panels.scene3d.drawn_rays;
    h.state_mut().state.apply(Command::Step(StepMove::Last));
    h.run_steps(3);
    let at_end = h.state().panels.scene3d.drawn_rays;
    assert_eq!(at_start, 1, "step 0 shows the primary ray alone");
    assert!(
        at_end > at_start,
        "the last step shows the ray tree ({at_end})"
    );

    // Select the mirror ball and drag its y arrow up: one gesture, the ball moves up.
    let group = {
        let s = h.state().state.scene().unwrap();
        s.groups
            .iter()
            .position(|g| g.name == "mirror ball")
            .unwrap() as u32
    };
    h.state_mut()
        .state
        .apply(Command::Edit(EditCmd::Select(Some(group))));
    h.run_steps(3);
    let before_trace = trace_json(&h);
    let before_render = render_pixels(&h);
    let before_center = mirror_center(h.state());
    let (centre, ends) = h
        .state()
        .panels
        .scene3d
        .gizmo
        .expect("the move arrows are drawn");
    let grab = centre + (ends[1] - centre) * 0.6;
    h.drag_at(grab);
    h.step();
    for k in 1..=6 {
        h.hover_at(grab + egui::vec2(0.0, -10.0 * k as f32));
        h.step();
    }
    h.drop_at(grab + egui::vec2(0.0, -60.0));
    h.run_steps(2);
    wait_for(&mut h, "the edited render", settled);
    let moved = mirror_center(h.state());
    assert!(moved.y > before_center.y + 0.1, "{before_center} → {moved}");
    assert_eq!(
        (moved.x, moved.z),
        (before_center.x, before_center.z),
        "moved along y only"
    );
    assert!(h.state().state.unsaved());
    assert_ne!(trace_json(&h), before_trace, "the pixel was traced again");
    assert_ne!(render_pixels(&h), before_render, "the render restarted");

    // One undo restores the scene, the trace and the render bit for bit.
    h.state_mut().state.apply(Command::Edit(EditCmd::Undo));
    wait_for(&mut h, "the restored render", settled);
    assert_eq!(mirror_center(h.state()), before_center);
    assert_eq!(trace_json(&h), before_trace);
    assert_eq!(render_pixels(&h), before_render);

    // An exact edit, then save: the file keeps the comment and loads to the edited scene.
    h.state_mut()
        .state
        .apply(Command::Edit(EditCmd::Apply(Edit::Move {
            group,
            by: [0.0, 2.0, 0.0],
        })));
    wait_for(&mut h, "the edited render", settled);
    h.state_mut()
        .state
        .apply(Command::Edit(EditCmd::Save(None)));
    h.run_steps(2);
    assert!(!h.state().state.unsaved(), "{:?}", h.state().state.message);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("# my own notes: keep me\n"), "{text}");
    let saved = raystep::scene::load_file(&path).unwrap();
    let g = saved
        .groups
        .iter()
        .find(|g| g.name == "mirror ball")
        .unwrap();
    match saved.objects[g.first as usize].shape {
        Shape::Sphere { center, .. } => assert_eq!(center, before_center + glam::Vec3::Y * 2.0),
        _ => unreachable!(),
    }
    assert_eq!(saved.objects, h.state().state.scene().unwrap().objects);
}

/// Looking through the camera: the picture takes the image's proportions, and the primary
/// ray's hit point lands on the selected pixel.
#[test]
fn looking_through_the_camera_matches_the_render() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/three-spheres.toml");
    let Some(mut h) = harness("looking_through_the_camera_matches_the_render", path) else {
        return;
    };
    wait_for(&mut h, "the render", settled);
    let pixel = [150, 110];
    h.state_mut().state.apply(Command::SelectPixel(pixel));
    wait_for(&mut h, "the trace", settled);
    h.get_by_label("3D view").click();
    h.run_steps(3);
    h.get_by_label("Look through the camera").click();
    h.run_steps(3);
    let v = &h.state().panels.scene3d;
    assert_eq!(v.viewpoint, Viewpoint::Camera);
    let (cam, rect) = v.last_view.unwrap();
    let scene = h.state().state.scene().unwrap().clone();
    let (w, hgt) = (scene.camera.width as f32, scene.camera.height as f32);
    assert!((rect.width() / rect.height() - w / hgt).abs() < 0.01);
    let trace = &h.state().state.stepping.as_ref().unwrap().trace;
    let hit = trace.root.steps.iter().find_map(|s| match s.step {
        raystep::record::Step::Surface { point, .. } => Some(glam::Vec3::from(point)),
        _ => None,
    });
    let p = cam.project(hit.unwrap(), w, hgt).unwrap();
    assert!(
        (p[0] - 150.5).abs() < 0.5 && (p[1] - 110.5).abs() < 0.5,
        "{p:?}"
    );
}
