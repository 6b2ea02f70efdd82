//! The BVH tree and ray tree diagrams: their layout follows the trace, focus builds the picture
//! up step by step, only the kinds a trace contains are offered, and golden images guard the look.

use crate::common;
use common::assert_golden;

use raystep::accel::SceneAccel;
use raystep::diagram::{self, DiagramKind, ViewOptions, bvh_tree, ray_tree};
use raystep::record::{NodeAction, RayKind, Step, Trace};
use raystep::scene::{AccelChoice, Scene, load_file, load_str};
use raystep::trace::Tracer;
use std::path::Path;

fn scene(name: &str) -> Scene {
    load_file(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes")
            .join(name),
    )
    .unwrap()
}

fn trace(scene: &Scene, x: u32, y: u32) -> Trace {
    let (accel, _) = SceneAccel::build(scene);
    Tracer::new(scene, &accel).record(x, y, 0)
}

/// 40 spheres on a grid: enough for a BVH several levels deep.
fn grid_scene() -> Scene {
    let mut t = String::from(
        "[camera]\nfrom = [0, 0, -20]\nwidth = 64\nheight = 48\n[[light]]\nposition = [-10, 10, -20]\n",
    );
    for i in 0..40 {
        let (x, y) = ((i % 8) as f32 - 3.5, (i / 8) as f32 - 2.0);
        t += &format!(
            "[[sphere]]\nname = \"s{i}\"\ncenter = [{}, {}, 0]\nradius = 0.4\n",
            x * 1.2,
            y * 1.2
        );
    }
    let mut s = load_str(&t, "grid.toml", None).unwrap();
    s.settings.accel = AccelChoice::Bvh;
    s
}

#[test]
fn bvh_tree_shows_every_visit_in_order() {
    let s = grid_scene();
    let tr = trace(&s, 32, 24);
    let visits: Vec<_> = tr
        .root
        .steps
        .iter()
        .filter_map(|st| {
            if let Step::Node(v) = &st.step {
                Some(v.clone())
            } else {
                None
            }
        })
        .collect();
    assert!(visits.len() > 4, "a deep enough traversal");
    let opts = ViewOptions::default();
    let lay = bvh_tree::layout(&tr, &opts, 60.0);
    for (k, v) in visits.iter().enumerate() {
        let n = &lay.nodes[&v.node];
        assert_eq!(
            n.visit,
            Some((k + 1, v.action)),
            "node {} is visit {}",
            v.node,
            k + 1
        );
        assert_eq!(n.depth, v.depth);
    }
    // Every edge goes down one level, and the root is on top.
    for (p, c) in &lay.edges {
        assert_eq!(lay.nodes[c].depth, lay.nodes[p].depth + 1);
        assert!(lay.nodes[c].pos[1] > lay.nodes[p].pos[1]);
    }
    let root = &lay.nodes[&0];
    assert!(lay.nodes.values().all(|n| n.pos[1] >= root.pos[1]));
    // Focusing on the 3rd step of the primary ray shows only the visits made by then.
    let tl = tr.timeline();
    let k = tl
        .iter()
        .position(|(r, s)| std::ptr::eq(*r, &tr.root) && matches!(s.step, Step::Node(_)))
        .unwrap()
        + 2;
    let focused = bvh_tree::layout(
        &tr,
        &ViewOptions {
            focus: Some(k),
            ..opts
        },
        60.0,
    );
    let shown = focused.nodes.values().filter(|n| n.visit.is_some()).count();
    let expected = tl[..=k]
        .iter()
        .filter(|(r, s)| std::ptr::eq(*r, &tr.root) && matches!(s.step, Step::Node(_)))
        .count();
    assert_eq!(shown, expected);
    // A culled node is drawn as culled.
    if let Some(c) = visits.iter().find(|v| v.action == NodeAction::Culled) {
        assert_eq!(lay.nodes[&c.node].visit.unwrap().1, NodeAction::Culled);
    }
}

#[test]
fn ray_tree_follows_the_trace() {
    let s = scene("mirror-glass.toml");
    // Find a pixel whose trace has both reflection and refraction rays.
    let tr = (0..320)
        .step_by(8)
        .flat_map(|x| (0..240).step_by(8).map(move |y| (x, y)))
        .map(|(x, y)| trace(&s, x, y))
        .find(|t| {
            let r = t.rays();
            r.iter().any(|r| r.kind == RayKind::Refraction)
                && r.iter().any(|r| r.kind == RayKind::Reflection)
        })
        .expect("mirror-glass has a glass pixel");
    let colour_rays: Vec<_> = tr
        .rays()
        .into_iter()
        .filter(|r| r.kind != RayKind::Shadow)
        .collect();
    let opts = ViewOptions::default();
    let boxes = ray_tree::layout(&tr, &opts, 60.0);
    assert_eq!(boxes.len(), colour_rays.len());
    for b in &boxes {
        if let Some(p) = b.parent {
            assert!(b.pos[1] > boxes[p].pos[1], "children below parents");
            assert!(
                colour_rays[p]
                    .children
                    .iter()
                    .any(|c| std::ptr::eq(c, colour_rays[b.index]))
            );
        }
    }
    // At step 0 only the primary ray has started.
    let early = ray_tree::layout(
        &tr,
        &ViewOptions {
            focus: Some(0),
            ..opts.clone()
        },
        60.0,
    );
    assert_eq!(early.iter().filter(|b| b.shown).count(), 1);
    assert!(early[0].current);
    // At the last step every ray has started.
    let last = tr.timeline().len() - 1;
    let late = ray_tree::layout(
        &tr,
        &ViewOptions {
            focus: Some(last),
            ..opts
        },
        60.0,
    );
    assert!(late.iter().all(|b| b.shown));
}

#[test]
fn only_kinds_the_trace_contains_are_offered() {
    let sphere_only = trace(&scene("first-sphere.toml"), 160, 120);
    let kinds = diagram::available(&sphere_only);
    assert!(kinds.contains(&DiagramKind::Quadratic));
    assert!(!kinds.contains(&DiagramKind::Barycentric));
    assert!(
        !kinds.contains(&DiagramKind::Bvh),
        "one sphere: brute force, no BVH"
    );
    let err = diagram::draw(
        &sphere_only,
        DiagramKind::Barycentric,
        &ViewOptions::default(),
    )
    .err()
    .unwrap();
    assert!(err.contains("barycentric"), "{err}");
    let bvh = trace(&grid_scene(), 32, 24);
    assert!(diagram::available(&bvh).contains(&DiagramKind::Bvh));
}

#[test]
fn golden_tree_diagrams() {
    let opts = ViewOptions {
        width: 400,
        height: 300,
        ..Default::default()
    };
    let bvh = trace(&grid_scene(), 32, 24);
    assert_golden(
        &diagram::draw(&bvh, DiagramKind::Bvh, &opts).unwrap(),
        "bvh-grid",
    );
    let three = trace(&scene("three-spheres.toml"), 60, 150);
    assert_golden(
        &diagram::draw(&three, DiagramKind::Raytree, &opts).unwrap(),
        "raytree-three-spheres",
    );
    let mg = trace(&scene("mirror-glass.toml"), 240, 140);
    assert_golden(
        &diagram::draw(&mg, DiagramKind::Raytree, &opts).unwrap(),
        "raytree-mirror-glass",
    );
}

#[test]
fn diagram_command_animates_every_step_and_reads_saved_traces() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/first-sphere.toml");
    let run = |args: &[&str]| {
        let out = assert_cmd::Command::cargo_bin("raystep")
            .unwrap()
            .args(args)
            .output()
            .unwrap();
        (
            out.status.success(),
            String::from_utf8_lossy(&out.stderr).to_string(),
        )
    };
    let gif = dir.path().join("steps.gif");
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    let (ok, err) = run(&[
        "diagram",
        scene.to_str().unwrap(),
        "--pixel",
        "160,120",
        "--animate",
        "--frames",
        frames.to_str().unwrap(),
        "-o",
        gif.to_str().unwrap(),
        "--size",
        "200x150",
    ]);
    assert!(ok, "{err}");
    let steps = trace(&self::scene("first-sphere.toml"), 160, 120)
        .timeline()
        .len();
    assert_eq!(std::fs::read_dir(&frames).unwrap().count(), steps);
    let decoder = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(
        std::fs::File::open(&gif).unwrap(),
    ))
    .unwrap();
    use image::AnimationDecoder;
    assert_eq!(decoder.into_frames().count(), steps);
    // The same diagram from the scene and from a saved trace is the same image.
    let saved = dir.path().join("t.json");
    assert!(
        run(&[
            "trace",
            scene.to_str().unwrap(),
            "--pixel",
            "160,120",
            "--save",
            saved.to_str().unwrap()
        ])
        .0
    );
    let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
    assert!(
        run(&[
            "diagram",
            scene.to_str().unwrap(),
            "--pixel",
            "160,120",
            "--kind",
            "raytree",
            "-o",
            a.to_str().unwrap()
        ])
        .0
    );
    assert!(
        run(&[
            "diagram",
            saved.to_str().unwrap(),
            "--kind",
            "raytree",
            "-o",
            b.to_str().unwrap()
        ])
        .0
    );
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    // Bad requests are clear errors, and write nothing.
    let c = dir.path().join("c.png");
    let (ok, err) = run(&[
        "diagram",
        scene.to_str().unwrap(),
        "--pixel",
        "160,120",
        "--kind",
        "barycentric",
        "-o",
        c.to_str().unwrap(),
    ]);
    assert!(!ok && err.contains("no barycentric diagram"), "{err}");
    let (ok, err) = run(&[
        "diagram",
        scene.to_str().unwrap(),
        "--pixel",
        "160,120",
        "--step",
        "9999",
        "-o",
        c.to_str().unwrap(),
    ]);
    assert!(!ok && err.contains("--step 9999"), "{err}");
    let (ok, err) = run(&[
        "diagram",
        scene.to_str().unwrap(),
        "--pixel",
        "160,120",
        "-o",
        dir.path().join("c.gif").to_str().unwrap(),
    ]);
    assert!(!ok && err.contains(".png"), "{err}");
    assert!(!c.exists());
}
