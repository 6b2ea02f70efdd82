//! Degenerate scenes against the accelerators, and corrupt grid and sphere-tree traces against
//! the loader (issue 39's accelerator and trace findings):
//!
//! - primitives at one point: the BVH gathers them into one leaf (its build was quadratic and
//!   its tree as deep as the primitives were many), so a trace of them loads back, and every
//!   accelerator renders what brute force renders;
//! - one huge sphere around many small ones: the grid keeps it outside, as it keeps the planes,
//!   instead of growing to its size and crowding the rest into one cell; primitives that all
//!   span the scene are all kept outside unless they are few;
//! - a cell step or a mailbox skip without a grid, a sphere-tree node outside a trace of the
//!   sphere tree, a cell axis of 7, a bounding sphere of radius NaN or −1 and a cell corner at
//!   ∞ are refused, the file and the field named.
//!
//! No test here is timed: the sizes are small enough that the old code is only slower, not
//! hopeless, and each test asserts what the old code got wrong (a tree deeper than a trace may
//! record, a trace refused, a grid the size of the huge sphere, a planted field accepted). The
//! slice's sample of a planted walk of thousands of cells is tested in
//! `crates/raystep-diagram/src/slice/draw_objects.rs`, the depth cut of a deeper tree in
//! `crates/raystep-core/src/accel/bvh/build.rs`, the grid's mailbox in `crates/raystep-core/src/accel/grid.rs`.

use assert_cmd::Command;
use glam::Vec3;
use raystep::PreparedScene;
use raystep::accel::{Accelerator, BruteForce, Bvh, Grid, SphereTree};
use raystep::math::Ray;
use raystep::record::validate::MAX_BVH_DEPTH;
use raystep::record::{Counter, Silent, Step, Trace, TraceError};
use raystep::render::{RenderOptions, render};
use raystep::scene::{AccelChoice, Scene, load_file, load_str};
use serde_json::Value;
use std::path::Path;

use crate::common::rng;
use rng::{Rng, fmt};

const CAMERA: &str = "[camera]\nfrom = [0, 0, -5]\nat = [0, 0, 0]\nfov = 60\nwidth = 40\nheight = 30\n\n[[light]]\nposition = [-10, 10, -10]\n\n";

/// The TOML of `n` unit spheres centred on the origin (and `extra` TOML after them).
fn coincident_toml(n: usize, extra: &str) -> String {
    let mut t = String::from(CAMERA);
    for _ in 0..n {
        t += "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\n";
    }
    t + extra
}

/// `n` unit spheres centred on the origin (and `extra` TOML after them).
fn coincident(n: usize, extra: &str) -> Scene {
    load_str(&coincident_toml(n, extra), "coincident.toml", None).expect("the scene loads")
}

/// The image rendered with `accel`, as linear floats.
fn image(scene: &Scene, accel: AccelChoice) -> Vec<Vec3> {
    let mut s = scene.clone();
    s.settings.accel = accel;
    let prepared = PreparedScene::new(s);
    let opts = RenderOptions {
        threads: Some(2),
        ..Default::default()
    };
    render(&prepared.tracer(), &opts).expect("renders").pixels
}

/// Every pixel of the images `accels` render equals brute force's, bit for bit.
fn same_as_brute_force(scene: &Scene, accels: &[AccelChoice]) {
    let brute = image(scene, AccelChoice::None);
    for &a in accels {
        let img = image(scene, a);
        let differ = img.iter().zip(&brute).filter(|(a, b)| a != b).count();
        assert_eq!(differ, 0, "{a:?}: {differ} pixels differ from brute force");
    }
}

/// The deepest BVH or sphere-tree node a trace records.
fn deepest_node(trace: &Trace) -> Option<u32> {
    trace
        .timeline()
        .iter()
        .filter_map(|(_, s)| match &s.step {
            Step::Node(v) => Some(v.depth),
            Step::SphereNode { depth, .. } => Some(*depth),
            _ => None,
        })
        .max()
}

/// 300 spheres at one point made a BVH of depth 292: a trace wrote node visits at that depth,
/// which the loader (at most depth 256) then refused. Now they are one leaf: the trace of the
/// middle pixel, with the BVH, with the sphere tree over it and with the grid, loads back as
/// saved.
#[test]
fn a_trace_of_three_hundred_spheres_at_one_point_loads_back() {
    let scene = coincident(300, "");
    let bvh = Bvh::build(&scene);
    assert_eq!(bvh.max_depth, 0, "one leaf");
    for accel in [AccelChoice::Bvh, AccelChoice::Spheres, AccelChoice::Grid] {
        let mut s = scene.clone();
        s.settings.accel = accel;
        let trace = PreparedScene::new(s).record(20, 15, 0);
        if accel != AccelChoice::Grid {
            let depth = deepest_node(&trace).expect("the ray walks the tree");
            assert!(depth <= MAX_BVH_DEPTH, "{accel:?}: depth {depth}");
        }
        let back = Trace::from_json(&trace.to_json(), "t.json")
            .unwrap_or_else(|e| panic!("{accel:?}: the saved trace is refused: {e}"));
        assert_eq!(back, trace);
    }
}

/// A grid of no cells (a scene of planes only, or of primitives all tested first) wrote a
/// `grid` header of 0 cells per axis, which the loader (1 to 256) refused. Now such a trace has
/// no `grid` header (its walk records no cell), and loads back.
#[test]
fn a_trace_of_a_grid_of_no_cells_loads_back() {
    let mut scene = load_str(
        "[camera]\nwidth = 8\nheight = 6\n\n[[plane]]\n",
        "plane.toml",
        None,
    )
    .unwrap();
    scene.settings.accel = AccelChoice::Grid;
    let trace = PreparedScene::new(scene).record(4, 3, 0);
    assert_eq!(trace.grid, None);
    let back = Trace::from_json(&trace.to_json(), "t.json").expect("the saved trace loads");
    assert_eq!(back, trace);
}

/// The same from the command line: `raystep trace --save` writes the trace, and `raystep diff`
/// loads it back (exit 0: equal to itself; before, exit 2: the file was refused).
#[test]
fn raystep_trace_save_of_spheres_at_one_point_loads_back() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("coincident.toml");
    std::fs::write(&scene, coincident_toml(300, "")).unwrap();
    for accel in ["bvh", "spheres"] {
        let saved = dir.path().join(format!("{accel}.json"));
        Command::cargo_bin("raystep")
            .unwrap()
            .arg("trace")
            .arg(&scene)
            .args(["--pixel", "20,15", "--accel", accel, "--save"])
            .arg(&saved)
            .assert()
            .success();
        let out = Command::cargo_bin("raystep")
            .unwrap()
            .arg("diff")
            .arg(&saved)
            .arg(&saved)
            .output()
            .unwrap();
        assert_eq!(
            out.status.code(),
            Some(0),
            "{accel}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// 2,000 spheres at one point: the BVH was a chain of depth 1,992 (20,000 made one of depth
/// 19,992, built in 22 s). Now one leaf (the root) holds them all, the sphere tree over it
/// likewise, the grid tests them all first, and every accelerator renders what brute force
/// renders.
#[test]
fn two_thousand_spheres_at_one_point_make_one_leaf() {
    let scene = coincident(2_000, "");
    let bvh = Bvh::build(&scene);
    assert_eq!(bvh.max_depth, 0, "one leaf");
    assert_eq!(bvh.nodes.len(), 1);
    assert_eq!(bvh.nodes[0].count, 2_000);
    let mut ids = bvh.leaf_objects.clone();
    ids.sort_unstable();
    assert_eq!(ids, (0..2_000).collect::<Vec<u32>>());
    let tree = SphereTree::build(&scene);
    assert_eq!(tree.nodes.len(), 1);
    assert_eq!(tree.nodes[0].count, 2_000);
    let grid = Grid::build(&scene);
    assert_eq!(grid.outside(), (0..2_000).collect::<Vec<u32>>());
    assert_eq!(grid.references(), 0);
    same_as_brute_force(
        &scene,
        &[AccelChoice::Bvh, AccelChoice::Spheres, AccelChoice::Grid],
    );
}

/// Fifteen at one point are left to obvhs as they are (a short chain, as every mesh's shared
/// boxes make), sixteen are gathered into one leaf.
#[test]
fn sixteen_at_one_point_are_gathered_fifteen_are_not() {
    let fifteen = Bvh::build(&coincident(15, ""));
    assert!(fifteen.nodes.len() > 1, "{} nodes", fifteen.nodes.len());
    let sixteen = Bvh::build(&coincident(16, ""));
    assert_eq!(sixteen.nodes.len(), 1);
    assert_eq!(sixteen.nodes[0].count, 16);
}

/// A cluster at one point beside other objects: the cluster becomes one leaf among ordinary
/// ones, and the images still equal brute force's (every accelerator, with ties between the
/// coincident spheres going to the lowest id). The grid lists the cluster in the cells around
/// the origin, so a ray there tests its 1,000 spheres and its mailbox holds them all (a hash set
/// past 32).
#[test]
fn a_cluster_at_one_point_among_other_objects_renders_as_brute_force() {
    let mut extra = String::new();
    let mut r = Rng(3);
    for _ in 0..200 {
        extra += &format!(
            "[[sphere]]\ncenter = {}\nradius = 0.2\n",
            fmt(r.vec(-3.0, 3.0))
        );
    }
    // Concentric spheres of different sizes: one centre, different boxes.
    for k in 1..=50 {
        extra += &format!(
            "[[sphere]]\ncenter = [1, 1, 1]\nradius = {}\n",
            k as f32 * 0.01
        );
    }
    let scene = coincident(1_000, &extra);
    let bvh = Bvh::build(&scene);
    assert!(bvh.max_depth < 40, "depth {}", bvh.max_depth);
    // The cluster's 1,000 in one leaf, the 50 concentric ones in one leaf (obvhs may have put a
    // few neighbours in with either).
    let leaf_of = |id: u32| {
        bvh.nodes
            .iter()
            .filter(|n| n.count > 0)
            .find(|n| {
                bvh.leaf_objects[n.first as usize..(n.first + n.count) as usize].contains(&id)
            })
            .unwrap()
    };
    assert!(
        (1_000..1_008).contains(&leaf_of(0).count),
        "{}",
        leaf_of(0).count
    );
    assert!(
        (50..58).contains(&leaf_of(1_200).count),
        "{}",
        leaf_of(1_200).count
    );
    // The grid keeps them inside (they span a third of the scene, not half).
    assert_eq!(Grid::build(&scene).outside(), &[] as &[u32]);
    same_as_brute_force(
        &scene,
        &[AccelChoice::Bvh, AccelChoice::Spheres, AccelChoice::Grid],
    );
}

/// One sphere of radius 10⁹ around 5,000 small ones: the grid grew to the huge sphere's box and
/// put every small sphere in one cell, so every ray tested all of them. Now the huge sphere
/// stays outside the grid, tested first like a plane; the grid spans the small spheres only, a
/// ray tests a few of them (the observer counts the tests), and the image is brute force's.
#[test]
fn a_huge_sphere_stays_outside_the_grid() {
    let mut r = Rng(7);
    let mut t = String::from(CAMERA).replace("from = [0, 0, -5]", "from = [0, 0, -30]");
    t += "[[sphere]]\nname = \"huge\"\ncenter = [0, 0, 1000000010]\nradius = 1e9\n";
    for _ in 0..5_000 {
        t += &format!(
            "[[sphere]]\ncenter = {}\nradius = 0.1\n",
            fmt(r.vec(-10.0, 10.0))
        );
    }
    let scene = load_str(&t, "huge.toml", None).unwrap();
    let grid = Grid::build(&scene);
    assert!(
        (grid.max - grid.min).max_element() < 25.0,
        "the grid spans the small spheres only: {:?} to {:?}",
        grid.min,
        grid.max
    );
    assert_eq!(grid.outside(), &[0], "the huge sphere is tested first");
    // Primitive tests per ray, counted by the observer, against brute force's 5,001.
    let mut rays = vec![];
    for _ in 0..200 {
        let o = Vec3::new(0.0, 0.0, -30.0);
        rays.push(Ray::infinite(o, r.vec(-10.0, 10.0) - o).unwrap());
    }
    let mut counted = Counter::default();
    for ray in &rays {
        let a = BruteForce.closest(&scene, ray, &mut Silent);
        let b = grid.closest(&scene, ray, &mut counted);
        assert_eq!(a, b, "{ray:?}");
        assert_eq!(
            BruteForce.any(&scene, ray, &mut Silent).is_some(),
            grid.any(&scene, ray, &mut Silent).is_some(),
            "{ray:?}"
        );
    }
    let per_ray = counted.prim_tests as f64 / rays.len() as f64;
    assert!(per_ray < 200.0, "{per_ray} primitive tests per ray");
    same_as_brute_force(&scene, &[AccelChoice::Grid]);
}

/// A sphere that spans the scene stays in the grid when the rest do not fit a box half as wide:
/// it is then not what made the grid big.
#[test]
fn a_spanning_sphere_stays_in_the_grid_when_the_rest_spread_as_wide() {
    let mut t = String::from(CAMERA);
    t += "[[sphere]]\ncenter = [0, 0, 0]\nradius = 2\n";
    for c in ["[-1.9, -1.9, -1.9]", "[1.9, 1.9, 1.9]"] {
        t += &format!("[[sphere]]\ncenter = {c}\nradius = 0.1\n");
    }
    let scene = load_str(&t, "wide.toml", None).unwrap();
    let grid = Grid::build(&scene);
    assert_eq!(grid.outside(), &[] as &[u32]);
    same_as_brute_force(&scene, &[AccelChoice::Grid]);
}

/// Primitives that all span the whole scene (all at one point) are all tested first when there
/// are more than 8 (no cell could leave any out), and stay in the grid when there are at most 8,
/// so that a one-sphere scene still shows its walk.
#[test]
fn spanning_primitives_stay_in_the_grid_only_when_few() {
    for n in [1, 8] {
        let grid = Grid::build(&coincident(n, ""));
        assert!(grid.outside().is_empty(), "{n}");
        assert!(grid.references() >= n, "{n}");
    }
    for n in [9, 100] {
        let scene = coincident(n, "");
        let grid = Grid::build(&scene);
        assert_eq!(grid.references(), 0, "{n}");
        assert_eq!(grid.outside().len(), n);
        same_as_brute_force(&scene, &[AccelChoice::Grid]);
    }
}

fn mirror_glass(accel: AccelChoice) -> Trace {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/mirror-glass.toml");
    let mut scene = load_file(&path).unwrap();
    scene.settings.accel = accel;
    PreparedScene::new(scene).record(200, 150, 0)
}

fn json(t: &Trace) -> Value {
    serde_json::from_str(&t.to_json()).unwrap()
}

/// The root ray's steps, mutable.
fn root_steps(v: &mut Value) -> &mut Vec<Value> {
    v["root"]["steps"].as_array_mut().unwrap()
}

/// The error for a planted trace: an `Invalid` naming the file and `field`.
fn refused(v: &Value, field: &str) -> String {
    let Err(e) = Trace::from_json(&v.to_string(), "planted.json") else {
        panic!("the trace with `{field}` planted is accepted");
    };
    let text = e.to_string();
    assert!(matches!(e, TraceError::Invalid { .. }), "{text}");
    assert!(
        text.starts_with(&format!("planted.json: field `{field}`: ")),
        "names `{field}`: {text}"
    );
    text
}

/// The index of the first root step of type `ty`.
fn first(v: &mut Value, ty: &str) -> usize {
    root_steps(v)
        .iter()
        .position(|s| s["type"] == ty)
        .unwrap_or_else(|| panic!("a {ty} step"))
}

/// The unplanted traces load back, with each accelerator.
#[test]
fn traces_of_every_accelerator_load_back() {
    for accel in [
        AccelChoice::None,
        AccelChoice::Bvh,
        AccelChoice::Spheres,
        AccelChoice::Grid,
    ] {
        let t = mirror_glass(accel);
        let back =
            Trace::from_json(&t.to_json(), "t.json").unwrap_or_else(|e| panic!("{accel:?}: {e}"));
        assert_eq!(back, t);
    }
}

#[test]
fn cell_steps_without_a_grid_header_are_refused() {
    let mut v = json(&mirror_glass(AccelChoice::Grid));
    let k = first(&mut v, "cell");
    v.as_object_mut().unwrap().remove("grid");
    let text = refused(&v, &format!("root.steps[{k}]"));
    assert!(text.contains("no `grid` header"), "{text}");
}

#[test]
fn a_mailbox_skip_without_a_grid_header_is_refused() {
    let mut v = json(&mirror_glass(AccelChoice::None));
    let object = v["objects"][0]["id"].clone();
    let skip = serde_json::json!({
        "stage": "traversal",
        "type": "mailbox-skip",
        "object": object,
        "name": "planted",
    });
    // Check the planted step is well-formed: with a grid header it loads.
    let mut with_grid = v.clone();
    let grid = json(&mirror_glass(AccelChoice::Grid))["grid"].clone();
    with_grid["grid"] = grid;
    root_steps(&mut with_grid).insert(0, skip.clone());
    Trace::from_json(&with_grid.to_string(), "planted.json")
        .expect("a mailbox skip in a trace with a grid header loads");
    root_steps(&mut v).insert(0, skip);
    let text = refused(&v, "root.steps[0]");
    assert!(text.contains("no `grid` header"), "{text}");
}

#[test]
fn sphere_tree_nodes_outside_a_trace_of_the_sphere_tree_are_refused() {
    let mut spheres = json(&mirror_glass(AccelChoice::Spheres));
    let k = first(&mut spheres, "sphere-node");
    let node = root_steps(&mut spheres)[k].clone();
    for (accel, says) in [
        (AccelChoice::Grid, "grid"),
        (AccelChoice::Bvh, "BVH"),
        (AccelChoice::None, "none"),
    ] {
        let mut v = json(&mirror_glass(accel));
        root_steps(&mut v).insert(0, node.clone());
        let text = refused(&v, "root.steps[0]");
        assert!(text.contains(says), "{accel:?}: {text}");
    }
}

#[test]
fn a_bvh_node_in_a_grid_trace_is_refused() {
    let mut bvh = json(&mirror_glass(AccelChoice::Bvh));
    let k = first(&mut bvh, "node");
    let node = root_steps(&mut bvh)[k].clone();
    let mut v = json(&mirror_glass(AccelChoice::Grid));
    v["bvh"] = bvh["bvh"].clone();
    root_steps(&mut v).insert(0, node);
    let text = refused(&v, "root.steps[0]");
    assert!(
        text.contains("a BVH node in a trace of the uniform grid"),
        "{text}"
    );
}

#[test]
fn a_cell_axis_of_seven_is_refused() {
    let mut v = json(&mirror_glass(AccelChoice::Grid));
    let k = root_steps(&mut v)
        .iter()
        .position(|s| s["type"] == "cell" && s.get("axis").is_some())
        .expect("a cell entered along an axis");
    root_steps(&mut v)[k]["axis"] = 7.into();
    let text = refused(&v, &format!("root.steps[{k}].axis"));
    assert!(
        text.ends_with("must be 0, 1 or 2 (x, y, z), got 7"),
        "{text}"
    );
}

#[test]
fn a_bounding_sphere_of_radius_nan_or_minus_one_is_refused() {
    for (radius, got) in [
        (Value::from("nan"), "got NaN"),
        (Value::from(-1.0), "got -1"),
    ] {
        let mut v = json(&mirror_glass(AccelChoice::Spheres));
        let k = first(&mut v, "sphere-node");
        root_steps(&mut v)[k]["radius"] = radius.clone();
        let text = refused(&v, &format!("root.steps[{k}].radius"));
        assert!(text.ends_with(got), "{radius}: {text}");
    }
}

#[test]
fn a_bounding_sphere_centre_at_infinity_is_refused() {
    let mut v = json(&mirror_glass(AccelChoice::Spheres));
    let k = first(&mut v, "sphere-node");
    root_steps(&mut v)[k]["center"][1] = "-inf".into();
    refused(&v, &format!("root.steps[{k}].center"));
}

#[test]
fn a_cell_corner_at_infinity_is_refused() {
    for corner in ["min", "max"] {
        let mut v = json(&mirror_glass(AccelChoice::Grid));
        let k = first(&mut v, "cell");
        root_steps(&mut v)[k][corner][0] = "inf".into();
        refused(&v, &format!("root.steps[{k}].{corner}"));
    }
    // A max below the min.
    let mut v = json(&mirror_glass(AccelChoice::Grid));
    let k = first(&mut v, "cell");
    let below = v["root"]["steps"][k]["min"][1].as_f64().unwrap() - 1.0;
    root_steps(&mut v)[k]["max"][1] = below.into();
    let text = refused(&v, &format!("root.steps[{k}].max"));
    assert!(text.contains("must not be below the cell's min"), "{text}");
}

#[test]
fn a_cell_outside_the_grid_is_refused() {
    let mut v = json(&mirror_glass(AccelChoice::Grid));
    let k = first(&mut v, "cell");
    let cells = v["grid"]["cells"][2].clone();
    root_steps(&mut v)[k]["cell"][2] = cells;
    let text = refused(&v, &format!("root.steps[{k}].cell"));
    assert!(text.contains("outside the grid"), "{text}");
}
