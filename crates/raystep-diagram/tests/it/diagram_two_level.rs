//! The TLAS/BLAS diagram drawn from a recorded two-level walk (scenes/instances.toml): every
//! recorded TLAS visit, instance entered and BLAS visit numbered in the trace's own order, each
//! entered instance's BLAS joined to the TLAS leaf that entered it, the trees laid out from the
//! visits.

use raystep_core::accel::SceneAccel;
use raystep_core::record::{NodeAction, Step, Trace};
use raystep_core::scene::load_file;
use raystep_core::trace::Tracer;
use raystep_diagram::two_level::{lay_out, walk};
use raystep_diagram::{DiagramKind, ViewOptions, available, draw, kinds_for_step};
use std::path::Path;

fn trace(file: &str, x: u32, y: u32) -> Trace {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(file);
    let scene = load_file(&path).unwrap();
    let (accel, _) = SceneAccel::build(&scene);
    Tracer::new(&scene, &accel).record(x, y, 0)
}

/// "gem near" at (130, 150): the TLAS walk enters instances, one of which the ray hits.
#[test]
fn the_walk_is_numbered_as_the_trace_records_it() {
    let t = trace("instances.toml", 130, 150);
    let w = walk(&t.root, None);
    // The numbers, in the order of the root ray's TLAS nodes, instances and BLAS nodes.
    let mut expected = vec![];
    let mut entered = vec![];
    for s in &t.root.steps {
        match &s.step {
            Step::TlasNode(v) => expected.push(("tlas", v.node)),
            Step::Instance { instance, .. } => {
                expected.push(("instance", *instance));
                entered.push(*instance);
            }
            Step::Node(v) if v.instance.is_some() => expected.push(("blas", v.node)),
            _ => {}
        }
    }
    let mut got: Vec<(usize, &str, u32)> =
        w.tlas.iter().map(|v| (v.number, "tlas", v.node)).collect();
    for e in &w.entered {
        got.push((e.number, "instance", e.instance));
        got.extend(e.blas.iter().map(|v| (v.number, "blas", v.node)));
    }
    got.sort();
    let numbers: Vec<usize> = got.iter().map(|g| g.0).collect();
    assert_eq!(numbers, (1..=expected.len()).collect::<Vec<_>>());
    assert_eq!(got.iter().map(|g| (g.1, g.2)).collect::<Vec<_>>(), expected);
    assert_eq!(
        w.entered.iter().map(|e| e.instance).collect::<Vec<_>>(),
        entered
    );
    assert!(!entered.is_empty());
    // Each instance was entered by a TLAS leaf the walk tested.
    for e in &w.entered {
        let leaf = e.leaf.expect("entered from a leaf");
        assert!(w.tlas.iter().any(|v| v.node == leaf
            && v.action == NodeAction::TestPrimitives
            && v.number < e.number));
    }
    // The hit instance's BLAS tests found its hit.
    let hit = t.root.hit.as_ref().and_then(|h| h.instance).unwrap();
    assert!(w.entered.iter().any(|e| e.instance == hit && e.hits > 0));
    assert!(available(&t).contains(&DiagramKind::Tlas));
    let k = t
        .timeline()
        .iter()
        .position(|(_, s)| matches!(s.step, Step::Instance { .. }))
        .unwrap();
    assert_eq!(kinds_for_step(&t, k)[0], DiagramKind::Tlas);
}

/// The layout: the root on top, each inner node over the middle of its two children, the
/// leaves left to right in depth-first order, every node inside its box.
#[test]
fn trees_are_laid_out_from_their_visits() {
    let t = trace("instances.toml", 130, 150);
    let w = walk(&t.root, None);
    let (nodes, edges) = lay_out(&w.tlas, [100.0, 500.0], [50.0, 250.0]);
    assert_eq!(nodes[&0].pos[1], 50.0);
    for v in &w.tlas {
        let n = &nodes[&v.node];
        assert!((100.0..=500.0).contains(&n.pos[0]) && (50.0..=250.0).contains(&n.pos[1]));
        if let Some([a, b]) = v.children {
            assert!(edges.contains(&(v.node, a)) && edges.contains(&(v.node, b)));
            let mid = (nodes[&a].pos[0] + nodes[&b].pos[0]) / 2.0;
            assert!((n.pos[0] - mid).abs() < 1e-3);
            assert!(nodes[&a].pos[0] < nodes[&b].pos[0]);
            assert!(nodes[&a].pos[1] > n.pos[1]);
        }
    }
}

/// Drawn at several sizes and at every step, focused or not, without a panic, and with ink
/// where the trees are; a trace with no instance has no such diagram.
#[test]
fn it_draws_at_every_step_and_size() {
    let t = trace("instances.toml", 130, 150);
    for (w, h) in [(320, 240), (800, 600), (1920, 1080), (60, 40)] {
        for focus in [
            None,
            Some(0),
            Some(5),
            Some(20),
            Some(t.timeline().len() - 1),
        ] {
            let o = ViewOptions {
                width: w,
                height: h,
                focus,
                ..ViewOptions::default()
            };
            let c = draw(&t, DiagramKind::Tlas, &o).unwrap();
            assert_eq!((c.width() as u32, c.height() as u32), (w, h));
        }
    }
    let plain = trace("three-spheres.toml", 100, 100);
    assert!(!available(&plain).contains(&DiagramKind::Tlas));
    assert!(draw(&plain, DiagramKind::Tlas, &ViewOptions::default()).is_err());
}
