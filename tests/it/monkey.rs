//! A monkey test: the real app, driven through egui_kittest by a seeded random sequence of
//! events — clicks and drags anywhere, clicks on any button, checkbox, tab or radio button the
//! app shows (menus, lessons, exercises, the lab, the GPU tabs), keys, the mouse wheel, window
//! sizes from 320×240 to 3840×2160, panel toggles, presentation mode — on every shipped scene,
//! and nothing may panic. A failure prints the seed, the scene and the last events, and
//! `RAYSTEP_MONKEY_SEED=…` replays it. `RAYSTEP_MONKEY_EVENTS` sets the number of events in all
//! (default 2400, spread over the scenes).

use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT as _, Queryable as _};
use raystep::app::RaystepApp;
use raystep::app::state::{Command, Prefs};
use std::path::{Path, PathBuf};

/// xorshift64*: small, seeded, the same on every machine.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n.max(1)
    }
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn coin(&mut self) -> bool {
        self.next() & 1 == 1
    }
}

fn scenes() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    assert!(!v.is_empty(), "no shipped scenes in {}", dir.display());
    v
}

/// Buttons the monkey leaves alone: they write files into the working folder or close the app.
const LEFT_ALONE: [&str; 3] = ["Save", "Quit", "Open"];

// No Enter: in a save dialog's path field it would write a file into the working folder.
const KEYS: [egui::Key; 11] = [
    egui::Key::ArrowLeft,
    egui::Key::ArrowRight,
    egui::Key::ArrowUp,
    egui::Key::ArrowDown,
    egui::Key::Home,
    egui::Key::End,
    egui::Key::Space,
    egui::Key::Escape,
    egui::Key::F11,
    egui::Key::Tab,
    egui::Key::Backspace,
];

/// One random event; returns what it was, for the failure report.
fn one_event(h: &mut Harness<'static, RaystepApp>, rng: &mut Rng) -> String {
    let size = h
        .state()
        .panels
        .window_rect
        .map_or(egui::vec2(800.0, 600.0), |r| r.size());
    let mut pos = || egui::pos2(rng.unit() * size.x, rng.unit() * size.y);
    let (a, b) = (pos(), pos());
    match rng.below(100) {
        0..=24 => {
            // A widget the app shows, found through accessibility as a user would see it.
            let nodes: Vec<_> = h
                .query_all_by_role(Role::Button)
                .chain(h.query_all_by_role(Role::CheckBox))
                .chain(h.query_all_by_role(Role::RadioButton))
                .chain(h.query_all_by_role(Role::Tab))
                .filter(|n| {
                    let l = n.accesskit_node().label().unwrap_or_default();
                    !LEFT_ALONE.contains(&l.as_str()) && !l.starts_with("Quit")
                })
                .collect();
            if nodes.is_empty() {
                return "no widget to click".into();
            }
            let node = &nodes[rng.below(nodes.len() as u64) as usize];
            let label = node.accesskit_node().label().unwrap_or_default();
            node.click();
            format!("click widget {label:?}")
        }
        25..=44 => {
            h.hover_at(a);
            for pressed in [true, false] {
                h.event(egui::Event::PointerButton {
                    pos: a,
                    button: egui::PointerButton::Primary,
                    pressed,
                    modifiers: egui::Modifiers::NONE,
                });
            }
            format!("click at {a:?}")
        }
        45..=54 => {
            h.drag_at(a);
            h.step();
            h.hover_at(b);
            h.step();
            h.drop_at(b);
            format!("drag {a:?} → {b:?}")
        }
        55..=69 => {
            let k = KEYS[rng.below(KEYS.len() as u64) as usize];
            h.key_press(k);
            format!("key {k:?}")
        }
        70..=77 => {
            h.hover_at(a);
            let d = egui::vec2(0.0, (rng.unit() - 0.5) * 400.0);
            h.event(egui::Event::MouseWheel {
                unit: egui::MouseWheelUnit::Point,
                delta: d,
                phase: egui::TouchPhase::Move,
                source: egui::MouseWheelSource::Wheel,
                modifiers: egui::Modifiers::NONE,
            });
            format!("wheel {d:?} at {a:?}")
        }
        78..=85 => {
            let w = 320.0 + rng.unit() * (3840.0 - 320.0);
            let hh = 240.0 + rng.unit() * (2160.0 - 240.0);
            h.set_size(egui::vec2(w.round(), hh.round()));
            format!("window {w:.0}×{hh:.0}")
        }
        86..=93 => {
            let mut p = h.state().state.prefs.clone();
            let what = match rng.below(6) {
                0 => {
                    p.presentation = !p.presentation;
                    "presentation"
                }
                1 => {
                    p.show_learn = !p.show_learn;
                    "lessons panel"
                }
                2 => {
                    p.show_settings = !p.show_settings;
                    "settings panel"
                }
                3 => {
                    p.show_tree = !p.show_tree;
                    "tree panel"
                }
                4 => {
                    p.layout.tree_collapsed = !p.layout.tree_collapsed;
                    "tree fold"
                }
                _ => {
                    p.scale = 0.75 + rng.unit() * 2.25;
                    "scale"
                }
            };
            h.state_mut().state.apply(Command::SetPrefs(p));
            format!("toggle {what}")
        }
        94..=96 => {
            use raystep::app::gpu_view::CentralTab;
            let tab =
                [CentralTab::Cpu, CentralTab::Gpu, CentralTab::Difference][rng.below(3) as usize];
            h.state_mut().panels.gpu.tab = tab;
            format!("tab {tab:?}")
        }
        _ => {
            let lab = &mut h.state_mut().panels.lab;
            lab.open = !lab.open;
            if rng.coin() {
                h.state_mut()
                    .state
                    .apply(Command::Learn(raystep::app::learn::LearnCmd::Tab(
                        raystep::app::learn::LearnTab::Exercises,
                    )));
            }
            "lab window / exercises".into()
        }
    }
}

/// Runs `events` random events from `seed` on `scene`; on a panic, prints how to replay it.
fn run(seed: u64, scene: &Path, events: usize, gpu: bool) {
    let file = scene.to_path_buf();
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut rng = Rng(seed | 1);
        let mut log: Vec<String> = vec![];
        let builder = Harness::builder().with_size(egui::vec2(1280.0, 800.0));
        let builder = if gpu { builder.wgpu() } else { builder };
        let mut h = builder.build_eframe(move |cc| {
            let app = RaystepApp::with_context(&cc.egui_ctx, Prefs::default(), Some(file.clone()));
            app.with_wgpu(cc.wgpu_render_state.clone())
        });
        // The lab's suite, should the monkey start it, runs a small sample.
        h.state_mut().state.lab.options.rays = 4;
        for i in 0..events {
            let what = one_event(&mut h, &mut rng);
            log.push(format!("{i}: {what}"));
            if log.len() > 12 {
                log.remove(0);
            }
            LAST.with(|l| *l.borrow_mut() = log.clone());
            h.step();
        }
        // Let a render that the last events started finish, then a few quiet frames.
        h.run_steps(3);
    }));
    if let Err(e) = outcome {
        let last = LAST.with(|l| l.borrow().join("\n  "));
        eprintln!(
            "MONKEY FAILED: seed {seed}, scene {}, last events:\n  {last}\nreplay: \
             RAYSTEP_MONKEY_SEED={seed} cargo test --test it monkey::",
            scene.display()
        );
        std::panic::resume_unwind(e);
    }
}

thread_local! {
    static LAST: std::cell::RefCell<Vec<String>> = const { std::cell::RefCell::new(vec![]) };
}

fn total_events() -> usize {
    std::env::var("RAYSTEP_MONKEY_EVENTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2400)
}

fn base_seed() -> u64 {
    std::env::var("RAYSTEP_MONKEY_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5eed_2026)
}

/// Every shipped scene, the events spread evenly over them, each scene its own seed.
#[test]
fn the_monkey_does_not_crash_the_app() {
    let scenes = scenes();
    let per = (total_events() / scenes.len()).max(1);
    let base = base_seed();
    let start = std::time::Instant::now();
    for (i, s) in scenes.iter().enumerate() {
        let seed = base.wrapping_add(i as u64);
        run(seed, s, per, false);
        eprintln!(
            "monkey: {} events on {} (seed {seed}) — {:.1} s so far",
            per,
            s.file_name().unwrap().to_string_lossy(),
            start.elapsed().as_secs_f64()
        );
    }
    eprintln!(
        "monkey: {} events in all on {} scenes, base seed {base}, {:.1} s",
        per * scenes.len(),
        scenes.len(),
        start.elapsed().as_secs_f64()
    );
}

/// The same with eframe's wgpu device, so that the GPU tabs (and their fragment/compute paths)
/// are among what the monkey clicks; skipped where wgpu finds no adapter.
#[test]
fn the_monkey_does_not_crash_the_gpu_view() {
    let instance = eframe::wgpu::Instance::new(
        eframe::wgpu::InstanceDescriptor::new_without_display_handle_from_env(),
    );
    if pollster::block_on(instance.enumerate_adapters(eframe::wgpu::Backends::all())).is_empty() {
        assert!(
            std::env::var("CI").is_err(),
            "CI must run the GPU monkey: install Mesa's lavapipe (mesa-vulkan-drivers)"
        );
        eprintln!("SKIPPED: wgpu found no adapter");
        return;
    }
    let base = base_seed().wrapping_add(1000);
    let events = (total_events() / 8).max(1);
    // Copies of the scenes: the 3D view's editor can change a scene, and a save (never clicked
    // here, but a copy costs nothing) must not touch the repository's files.
    let dir = tempfile::tempdir().unwrap();
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for e in std::fs::read_dir(&shipped).unwrap().flatten() {
        // The scene files and their meshes (not the folder of texture images: the two scenes
        // opened here have none).
        if e.path().is_file() {
            std::fs::copy(e.path(), dir.path().join(e.file_name())).unwrap();
        }
    }
    for (i, name) in ["three-spheres.toml", "triangles.toml"].iter().enumerate() {
        let path = dir.path().join(name);
        run(base.wrapping_add(i as u64), &path, events, true);
        eprintln!(
            "gpu monkey: {events} events on {name} (seed {})",
            base.wrapping_add(i as u64)
        );
    }
}
