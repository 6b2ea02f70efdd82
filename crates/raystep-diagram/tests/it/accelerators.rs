//! The bounding-sphere hierarchy and the uniform grid find exactly what brute force finds:
//! random rays (closest and any hit), every shipped scene and SPD scenes rendered bit for bit,
//! the stiff cases (axis-parallel rays, rays along cell boundaries, flat scenes, rays starting
//! inside and outside the grid); the grid's recorded walk is checked against an independent
//! enumeration of the cells a segment crosses; every bounding sphere contains its primitives.

use glam::Vec3;
use raystep_core::accel::{Accelerator, BruteForce, Grid, SceneAccel, SphereTree};
use raystep_core::math::Ray;
use raystep_core::record::{NodeAction, Observer, Recorder, Silent, Step};
use raystep_core::render::{RenderOptions, render};
use raystep_core::scene::{AccelChoice, BvhQuality, Scene, Shape, load_file, load_str};
use raystep_core::trace::Tracer;
use std::path::Path;

use crate::common::rng;
use rng::{Rng, fmt};
/// A scene of random spheres and triangles (and a plane); `flat` puts everything in z = 0.
fn random_scene(seed: u64, spheres: usize, triangles: usize, flat: bool) -> Scene {
    let mut r = Rng(seed);
    let squash = |v: Vec3| if flat { Vec3::new(v.x, v.y, 0.0) } else { v };
    let mut t = String::from("[[plane]]\naxis = \"y\"\noffset = -12\n");
    for _ in 0..spheres {
        t += &format!(
            "[[sphere]]\ncenter = {}\nradius = {:e}\n",
            fmt(squash(r.vec(-10.0, 10.0))),
            r.range(0.1, 1.5)
        );
    }
    for _ in 0..triangles {
        let c = r.vec(-10.0, 10.0);
        let p: Vec<Vec3> = (0..3).map(|_| squash(c + r.vec(-2.0, 2.0))).collect();
        t += &format!(
            "[[triangle]]\nvertices = [{}, {}, {}]\n",
            fmt(p[0]),
            fmt(p[1]),
            fmt(p[2])
        );
    }
    load_str(&t, "random.toml", None).unwrap()
}

fn random_rays(seed: u64, n: usize) -> Vec<Ray<f32>> {
    let mut r = Rng(seed);
    (0..n)
        .map(|k| {
            // Every fourth ray starts inside the scene's box.
            let o = if k % 4 == 0 {
                r.vec(-8.0, 8.0)
            } else {
                r.vec(-20.0, 20.0)
            };
            let target = r.vec(-10.0, 10.0);
            Ray::infinite(o, target - o).unwrap()
        })
        .collect()
}

/// Closest and any hit agree with brute force for every ray.
fn assert_same(scene: &Scene, accel: &impl Accelerator, rays: &[Ray<f32>]) -> usize {
    let mut hits = 0;
    for (k, ray) in rays.iter().enumerate() {
        let a = BruteForce.closest(scene, ray, &mut Silent);
        let b = accel.closest(scene, ray, &mut Silent);
        // The same kernel on the same ray gives bit-identical t; ties at equal t go to the
        // lower id in every accelerator, so the whole hit is the same.
        assert_eq!(a, b, "{}: ray {k}: {ray:?}", accel.name());
        hits += a.is_some() as usize;
        let sa = BruteForce.any(scene, ray, &mut Silent).is_some();
        let sb = accel.any(scene, ray, &mut Silent).is_some();
        assert_eq!(
            sa,
            sb,
            "{}: any-hit differs for ray {k}: {ray:?}",
            accel.name()
        );
    }
    hits
}

#[test]
fn spheres_and_grid_equal_brute_force_on_random_rays() {
    for (seed, spheres, tris, flat) in [
        (1, 200, 0, false),
        (2, 0, 300, false),
        (3, 150, 150, false),
        (4, 1, 0, false),
        (5, 0, 2, false),
        // Flat: every primitive in z = 0, which is a cell boundary of the grid (two cells thick).
        (6, 60, 60, true),
    ] {
        let scene = random_scene(seed, spheres, tris, flat);
        let rays = random_rays(seed + 100, 2000);
        let h1 = assert_same(&scene, &SphereTree::build(&scene), &rays);
        let h2 = assert_same(&scene, &Grid::build(&scene), &rays);
        assert_eq!(h1, h2);
        assert!(h1 > rays.len() / 10, "too few hits ({h1}) to mean much");
    }
}

/// Exact ties: every sphere and triangle appears twice (the copies scattered through the file,
/// so an accelerator often meets the higher id first). Each accelerator returns the same hit as
/// brute force, object id included: at equal t the lower id wins everywhere.
#[test]
fn ties_at_equal_t_go_to_the_lower_id_in_every_accelerator() {
    let base = random_scene(8, 80, 80, false);
    // The scene's TOML rebuilt from its objects: every object twice, in a shuffled order.
    let mut r = Rng(99);
    let mut blocks = vec![];
    for o in &base.objects {
        let b = match o.shape {
            Shape::Sphere { center, radius } => format!(
                "[[sphere]]\ncenter = {}\nradius = {:e}\n",
                fmt(center),
                radius
            ),
            Shape::Triangle { p } => format!(
                "[[triangle]]\nvertices = [{}, {}, {}]\n",
                fmt(p[0]),
                fmt(p[1]),
                fmt(p[2])
            ),
            _ => continue,
        };
        blocks.push(b.clone());
        blocks.push(b);
    }
    for i in (1..blocks.len()).rev() {
        let j = (r.range(0.0, (i + 1) as f32) as usize).min(i);
        blocks.swap(i, j);
    }
    let scene = load_str(&blocks.concat(), "twice.toml", None).unwrap();
    let rays = random_rays(123, 3000);
    let h = assert_same(&scene, &raystep_core::accel::bvh::Bvh::build(&scene), &rays);
    assert!(h > rays.len() / 10, "too few hits ({h})");
    assert_same(&scene, &SphereTree::build(&scene), &rays);
    assert_same(&scene, &Grid::build(&scene), &rays);
}

/// The math panel says how a tie was decided: two spheres at the same place (ids 0 and 1), the
/// BVH listing them in one leaf. Whichever it tests second, its explanation compares
/// against the closest t with the comparison the kernel made: "<" for the higher id, "≤" (the
/// tie kept, the lower id wins) for the lower; and the pixel's hit is object 0 either way.
#[test]
fn the_math_panel_explains_a_tie_at_equal_t() {
    let toml = "[camera]\nfrom = [0, 0, -5]\nat = [0, 0, 0]\nwidth = 8\nheight = 8\n\
        [[sphere]]\nname = \"a\"\ncenter = [0, 0, 0]\nradius = 1\n\
        [[sphere]]\nname = \"b\"\ncenter = [0, 0, 0]\nradius = 1\n";
    let mut scene = load_str(toml, "tie.toml", None).unwrap();
    scene.settings.accel = AccelChoice::Bvh;
    let trace = raystep_core::PreparedScene::new(scene).record(4, 4, 0);
    let steps = &trace.root.steps;
    let hit = trace.root.hit.as_ref().expect("a hit");
    assert_eq!(hit.name, "a");
    // The second sphere test, after the first one's Accept.
    let tests: Vec<usize> = (0..steps.len())
        .filter(|&i| matches!(steps[i].step, Step::Sphere { .. }))
        .collect();
    assert_eq!(tests.len(), 2, "{steps:#?}");
    let second = &steps[tests[1]].step;
    let Step::Sphere { object, .. } = second else {
        unreachable!()
    };
    let e = raystep_core::explain::formula::explain(&trace, &trace.root, second);
    let t_line = e
        .lines
        .iter()
        .find(|l| l.name == "t")
        .unwrap_or_else(|| panic!("{e:#?}"));
    if *object == 0 {
        assert!(t_line.symbolic.contains("≤ t_max"), "{t_line:?}");
        let t: f32 = t_line.value.parse().unwrap();
        assert_eq!(t, hit.t, "the tie kept at the closest t");
    } else {
        assert!(t_line.symbolic.contains("≥ t_max"), "{t_line:?}");
        assert_eq!(t_line.value, "none", "the higher id does not take the tie");
    }
}

/// Axis-parallel rays, and rays running exactly along the grid's cell boundaries (x and y on a
/// cell corner), from outside and from inside the grid.
#[test]
fn axis_parallel_rays_and_rays_along_cell_boundaries() {
    let scene = random_scene(11, 120, 120, false);
    let grid = Grid::build(&scene);
    let size = (grid.max - grid.min)
        / Vec3::new(
            grid.dims[0] as f32,
            grid.dims[1] as f32,
            grid.dims[2] as f32,
        );
    let mut rays = vec![];
    for i in 0..=grid.dims[0] {
        for j in 0..=grid.dims[1] {
            let x = grid.min.x + size.x * i as f32;
            let y = grid.min.y + size.y * j as f32;
            for (oz, dz) in [(-30.0, 1.0), (30.0, -1.0), (0.0, 1.0), (0.0, -1.0)] {
                rays.push(Ray::infinite(Vec3::new(x, y, oz), Vec3::new(0.0, 0.0, dz)).unwrap());
            }
        }
    }
    let mut r = Rng(5);
    for _ in 0..500 {
        let o = r.vec(-15.0, 15.0);
        let axis = (r.next() * 3.0) as usize % 3;
        let mut d = Vec3::ZERO;
        d[axis] = if r.next() < 0.5 { 1.0 } else { -1.0 };
        rays.push(Ray::infinite(o, d).unwrap());
    }
    let hits = assert_same(&scene, &grid, &rays);
    assert!(hits > 50, "{hits}");
    assert_same(&scene, &SphereTree::build(&scene), &rays);
}

/// Every cell the segment from `o` along `d` over (t0, t1) crosses, found independently: sample
/// the segment very finely and collect the cells of the sample points (a crossing shorter than
/// the sampling step would be missed, so the recorded walk may only add such sliver cells).
fn cells_by_sampling(grid: &Grid, o: Vec3, d: Vec3, t0: f32, t1: f32) -> Vec<[u32; 3]> {
    let size = (grid.max - grid.min)
        / Vec3::new(
            grid.dims[0] as f32,
            grid.dims[1] as f32,
            grid.dims[2] as f32,
        );
    let mut out: Vec<[u32; 3]> = vec![];
    let n = 20_000;
    for k in 0..=n {
        let t = t0 as f64 + (t1 as f64 - t0 as f64) * k as f64 / n as f64;
        let p = o.as_dvec3() + d.as_dvec3() * t;
        let c = [0, 1, 2].map(|a| {
            let f = ((p[a] - grid.min[a] as f64) / size[a] as f64).floor();
            f.clamp(0.0, (grid.dims[a] - 1) as f64) as u32
        });
        if out.last() != Some(&c) {
            out.push(c);
        }
    }
    out
}

#[test]
fn recorded_cell_walk_matches_an_independent_enumeration() {
    let scene = random_scene(21, 80, 80, false);
    let grid = Grid::build(&scene);
    let mut r = Rng(77);
    let mut walks = 0;
    for _ in 0..200 {
        let o = r.vec(-25.0, 25.0);
        let d = (r.vec(-10.0, 10.0) - o).normalize();
        // No primitive may end the walk early: an empty scene with the same grid would do, but
        // the walk itself is what is checked, so walk the grid directly.
        let mut ray = Ray::infinite(o, d).unwrap();
        let mut cells = vec![];
        let mut last = (f32::NAN, f32::NAN);
        grid.walk(&mut ray, |_, c, t_in, t_out, _, _, _| {
            cells.push(c);
            last = (t_in, t_out);
            true
        });
        if cells.is_empty() {
            continue;
        }
        walks += 1;
        // Consecutive cells are neighbours across one face.
        for w in cells.windows(2) {
            let steps: u32 = (0..3).map(|a| w[0][a].abs_diff(w[1][a])).sum();
            assert_eq!(steps, 1, "{w:?}");
        }
        // The entry and exit of the segment inside the grid.
        let inv = Vec3::ONE / d;
        let t0 = ((grid.min - o) * inv)
            .min((grid.max - o) * inv)
            .max_element()
            .max(0.0);
        let t1 = ((grid.min - o) * inv)
            .max((grid.max - o) * inv)
            .min_element();
        let sampled = cells_by_sampling(&grid, o, d, t0, t1);
        // Every sampled cell is walked, in the same order.
        let mut i = 0;
        for c in &sampled {
            while i < cells.len() && cells[i] != *c {
                i += 1;
            }
            assert!(
                i < cells.len(),
                "cell {c:?} not walked: {cells:?} vs {sampled:?}"
            );
        }
        assert!(
            cells.len() <= sampled.len() + 3,
            "{} walked, {} sampled",
            cells.len(),
            sampled.len()
        );
    }
    assert!(walks > 100, "{walks}");
}

#[test]
fn every_bounding_sphere_contains_its_primitives() {
    let scene = random_scene(31, 150, 150, false);
    let tree = SphereTree::build(&scene);
    // Points every primitive reaches: sphere extremes along the axes, triangle vertices.
    let points = |id: u32| -> Vec<Vec3> {
        match scene.objects[id as usize].shape {
            Shape::Sphere { center, radius } => {
                [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z]
                    .iter()
                    .map(|&a| center + a * radius)
                    .collect()
            }
            Shape::Triangle { p } => p.to_vec(),
            _ => vec![],
        }
    };
    // The primitives under each node.
    fn under(tree: &SphereTree, i: usize, out: &mut Vec<u32>) {
        let n = tree.nodes[i];
        if n.is_leaf() {
            out.extend_from_slice(
                &tree.leaf_objects[n.first as usize..(n.first + n.count) as usize],
            );
        } else {
            under(tree, n.first as usize, out);
            under(tree, n.first as usize + 1, out);
        }
    }
    for (i, n) in tree.nodes.iter().enumerate() {
        let mut ids = vec![];
        under(&tree, i, &mut ids);
        for id in ids {
            for p in points(id) {
                let d = (p.as_dvec3() - n.center.as_dvec3()).length();
                assert!(
                    d <= n.radius as f64,
                    "node {i}: object {id} point {p} at {d} > r {}",
                    n.radius
                );
            }
        }
    }
}

fn shipped() -> Vec<Scene> {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("scenes");
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v.iter().map(|p| load_file(p).unwrap()).collect()
}

fn spd(kind: raystep_core::scene::spd::SpdScene, size: u32) -> Scene {
    let out = raystep_core::scene::spd::generate(kind, size).unwrap();
    let dir = tempfile::tempdir().unwrap();
    if let Some((name, obj)) = &out.obj {
        std::fs::write(dir.path().join(name), obj).unwrap();
    }
    load_str(&out.toml, "spd.toml", Some(dir.path())).unwrap()
}

fn render_with(scene: &Scene, accel: AccelChoice) -> Vec<[f32; 3]> {
    render_with_quality(scene, accel, BvhQuality::Medium)
}

fn render_with_quality(scene: &Scene, accel: AccelChoice, quality: BvhQuality) -> Vec<[f32; 3]> {
    let mut s = scene.clone();
    s.settings.accel = accel;
    s.settings.bvh_quality = quality;
    let (a, _) = SceneAccel::build(&s);
    render(&Tracer::new(&s, &a), &RenderOptions::default())
        .unwrap()
        .pixels
        .iter()
        .map(|p| p.to_array())
        .collect()
}

/// Every shipped scene and three small SPD scenes, at most 96×72 pixels.
fn small_scenes() -> Vec<Scene> {
    use raystep_core::scene::spd::SpdScene;
    let mut scenes = shipped();
    scenes.push(spd(SpdScene::Balls, 2));
    scenes.push(spd(SpdScene::Tetra, 3));
    scenes.push(spd(SpdScene::Mount, 3));
    for scene in &mut scenes {
        scene.camera.width = scene.camera.width.min(96);
        scene.camera.height = scene.camera.height.min(72);
    }
    scenes
}

/// Bit-identical images: every shipped scene and three SPD scenes, each accelerator against
/// brute force.
#[test]
fn every_accelerator_renders_what_brute_force_renders() {
    for scene in small_scenes() {
        let brute = render_with(&scene, AccelChoice::None);
        for a in [AccelChoice::Bvh, AccelChoice::Spheres, AccelChoice::Grid] {
            let img = render_with(&scene, a);
            let diff = brute.iter().zip(&img).filter(|(x, y)| x != y).count();
            assert_eq!(
                diff, 0,
                "{:?} on \"{}\": {diff} pixels differ",
                a, scene.name
            );
        }
    }
}

/// The BVH's build qualities build different trees (fewer, larger boxes or more, tighter ones)
/// but every one of them renders what brute force renders, through the BVH and through the
/// sphere tree built over it.
#[test]
fn every_bvh_quality_renders_what_brute_force_renders() {
    for scene in small_scenes() {
        let brute = render_with(&scene, AccelChoice::None);
        for a in [AccelChoice::Bvh, AccelChoice::Spheres] {
            for q in [BvhQuality::Low, BvhQuality::High] {
                let img = render_with_quality(&scene, a, q);
                let diff = brute.iter().zip(&img).filter(|(x, y)| x != y).count();
                assert_eq!(
                    diff, 0,
                    "{a:?} {q:?} on \"{}\": {diff} pixels differ",
                    scene.name
                );
            }
        }
    }
}

/// A recorded pixel shows the accelerator's own steps: bounding spheres tested (with culled
/// ones), grid cells walked (the entry cell first, then cells entered along an axis).
#[test]
fn recorded_traces_show_sphere_nodes_and_cell_walks() {
    let scene = random_scene(41, 100, 0, false);
    let ray = Ray::infinite(Vec3::new(0.0, 0.0, -30.0), Vec3::new(0.01, 0.02, 1.0)).unwrap();
    let tree = SphereTree::build(&scene);
    let mut rec = Recorder::new();
    rec.begin_ray(raystep_core::record::RayKind::Primary, 0, &ray, 1.0);
    tree.closest(&scene, &ray, &mut rec);
    rec.end_ray(|| None, Vec3::ZERO);
    let steps = rec.finish().unwrap().steps;
    let nodes: Vec<_> = steps
        .iter()
        .filter_map(|s| match &s.step {
            Step::SphereNode { action, .. } => Some(*action),
            _ => None,
        })
        .collect();
    assert_eq!(nodes.first(), Some(&NodeAction::Descend), "{nodes:?}");
    assert!(nodes.contains(&NodeAction::Culled), "{nodes:?}");
    let grid = Grid::build(&scene);
    let mut rec = Recorder::new();
    rec.begin_ray(raystep_core::record::RayKind::Primary, 0, &ray, 1.0);
    grid.closest(&scene, &ray, &mut rec);
    rec.end_ray(|| None, Vec3::ZERO);
    let cells: Vec<_> = rec
        .finish()
        .unwrap()
        .steps
        .iter()
        .filter_map(|s| match &s.step {
            Step::Cell {
                axis,
                t_entry,
                t_exit,
                ..
            } => Some((*axis, *t_entry, *t_exit)),
            _ => None,
        })
        .collect();
    assert!(cells.len() > 2, "{cells:?}");
    assert_eq!(cells[0].0, None, "the entry cell");
    assert!(cells[1..].iter().all(|c| c.0.is_some()));
    for w in cells.windows(2) {
        assert_eq!(w[0].2, w[1].1, "a cell's exit is the next one's entry");
    }
}

/// A trace recorded with each new accelerator saves, loads back (validated) unchanged, and every
/// step of it is described and explained.
#[test]
fn traces_with_sphere_nodes_and_cells_save_load_and_explain() {
    let path =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("scenes/mirror-glass.toml");
    for accel in [AccelChoice::Spheres, AccelChoice::Grid] {
        let mut scene = load_file(&path).unwrap();
        scene.settings.accel = accel;
        let prepared = raystep_core::PreparedScene::new(scene);
        let (w, h) = (
            prepared.scene().camera.width,
            prepared.scene().camera.height,
        );
        let trace = prepared.record(w / 2, h / 2, 0);
        let traversal = trace
            .timeline()
            .iter()
            .filter(|(_, s)| matches!(s.step, Step::SphereNode { .. } | Step::Cell { .. }))
            .count();
        assert!(traversal > 0, "{accel:?}");
        let back = raystep_core::record::Trace::from_json(&trace.to_json(), "t.json").unwrap();
        assert_eq!(back, trace);
        for (ray, s) in trace.timeline() {
            assert!(!raystep_core::explain::describe::describe(&s.step, ray.kind).is_empty());
            let e = raystep_core::explain::formula::explain(&trace, ray, &s.step);
            assert!(
                !e.title.is_empty() && !e.conclusion.is_empty(),
                "{:?}",
                s.step
            );
        }
    }
}

/// Every diagram draws every step of traces recorded with the sphere tree and the grid, at a
/// small and a large size; the slice shows the walked cells and the tested spheres (its legend
/// names them only when the trace has them).
#[test]
fn diagrams_draw_traces_of_every_accelerator() {
    use raystep_diagram::{ViewOptions, available, draw};
    let path =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("scenes/triangles.toml");
    for accel in [AccelChoice::Spheres, AccelChoice::Grid] {
        let mut scene = load_file(&path).unwrap();
        scene.settings.accel = accel;
        let trace = raystep_core::PreparedScene::new(scene).record(80, 130, 0);
        let steps = trace.timeline().len();
        for kind in available(&trace) {
            for (w, h) in [(120, 90), (1200, 900)] {
                for k in (0..steps).step_by(3) {
                    let opts = ViewOptions {
                        width: w,
                        height: h,
                        focus: Some(k),
                        ..ViewOptions::default()
                    };
                    let c = draw(&trace, kind, &opts).unwrap();
                    assert_eq!((c.width(), c.height()), (w as f32, h as f32));
                }
            }
        }
    }
}

/// The tree diagram draws the bounding-sphere tree from its recorded visits: every visited node
/// is numbered in the order of the trace's `sphere-node` steps (counted here from the steps, not
/// by the diagram's code), with the action the traversal took, and each drawn edge joins a node
/// to one of the children its visit names.
#[test]
fn the_tree_diagram_shows_the_sphere_trees_visits_in_order() {
    use raystep_diagram::{DiagramKind, ViewOptions, available, bvh_tree};
    let path =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("scenes/triangles.toml");
    let mut scene = load_file(&path).unwrap();
    scene.settings.accel = AccelChoice::Spheres;
    let trace = raystep_core::PreparedScene::new(scene).record(160, 120, 0);
    assert!(available(&trace).contains(&DiagramKind::Bvh));
    let visits: Vec<(u32, NodeAction, Option<[u32; 2]>)> = trace
        .root
        .steps
        .iter()
        .filter_map(|s| match &s.step {
            Step::SphereNode {
                node,
                action,
                children,
                ..
            } => Some((*node, *action, *children)),
            _ => None,
        })
        .collect();
    assert!(visits.len() >= 3, "{visits:?}");
    let lay = bvh_tree::layout(&trace, &ViewOptions::default(), 40.0);
    for (k, (node, action, _)) in visits.iter().enumerate() {
        let drawn = &lay.nodes[node];
        assert_eq!(drawn.visit, Some((k + 1, *action)), "node #{node}");
    }
    for (p, c) in &lay.edges {
        let named = visits
            .iter()
            .any(|(n, _, ch)| n == p && ch.is_some_and(|ch| ch.contains(c)));
        assert!(named, "edge #{p} → #{c} not named by a visit");
    }
}

/// A counted render's per-pixel visits (the heatmap and the statistics) count each
/// accelerator's own visits: for every accelerator, a pixel's count equals the number of BVH
/// nodes, bounding spheres or grid cells its recorded trace holds (a different observer over
/// the same pixel), and the grid and sphere tree count some.
#[test]
fn counted_renders_count_every_accelerators_visits() {
    use raystep_core::render::{RenderOptions, render};
    let path =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("scenes/triangles.toml");
    for accel in [AccelChoice::Bvh, AccelChoice::Spheres, AccelChoice::Grid] {
        let mut scene = load_file(&path).unwrap();
        scene.settings.accel = accel;
        scene.camera.width = 40;
        scene.camera.height = 30;
        let prepared = raystep_core::PreparedScene::new(scene);
        let opts = RenderOptions {
            count: true,
            threads: Some(2),
            ..Default::default()
        };
        let out = render(&prepared.tracer(), &opts).unwrap();
        let visits = out.node_visits.expect("counted");
        assert!(visits.iter().any(|v| *v > 0), "{accel:?}");
        for (x, y) in [(0, 0), (20, 15), (13, 27), (39, 29)] {
            let trace = prepared.record(x, y, 0);
            let recorded = trace
                .timeline()
                .iter()
                .filter(|(_, s)| {
                    matches!(
                        s.step,
                        Step::Node(_) | Step::SphereNode { .. } | Step::Cell { .. }
                    )
                })
                .count();
            assert_eq!(
                visits[(y * 40 + x) as usize] as usize,
                recorded,
                "{accel:?} pixel ({x}, {y})"
            );
        }
        let total: u64 = visits.iter().map(|v| *v as u64).sum();
        assert_eq!(out.stats.counts.node_visits, total, "{accel:?}");
    }
}

/// A trace file whose sphere-tree node claims itself as its child, or whose mailbox names an
/// object the trace does not hold, is refused with the field named.
#[test]
fn corrupt_sphere_nodes_and_mailbox_skips_are_refused() {
    let path =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("scenes/mirror-glass.toml");
    let mut scene = load_file(&path).unwrap();
    scene.settings.accel = AccelChoice::Spheres;
    let trace = raystep_core::PreparedScene::new(scene).record(200, 150, 0);
    let json = trace.to_json();
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    // The first inner sphere node's children become [0, 0].
    let mut bad = v.clone();
    let steps = bad["root"]["steps"].as_array_mut().unwrap();
    let k = steps
        .iter()
        .position(|s| s["type"] == "sphere-node" && s.get("children").is_some())
        .expect("an inner sphere node");
    steps[k]["children"] = serde_json::json!([0, 0]);
    let err = raystep_core::record::Trace::from_json(&bad.to_string(), "bad.json").unwrap_err();
    assert!(err.to_string().contains("children"), "{err}");

    let mut scene = load_file(&path).unwrap();
    scene.settings.accel = AccelChoice::Grid;
    let trace = raystep_core::PreparedScene::new(scene).record(200, 150, 0);
    let mut v: serde_json::Value = serde_json::from_str(&trace.to_json()).unwrap();
    let skip = find_key(&mut v, "mailbox-skip").expect("a mailbox skip in this pixel's trace");
    skip["object"] = serde_json::json!(99_999);
    let err = raystep_core::record::Trace::from_json(&v.to_string(), "bad.json").unwrap_err();
    assert!(err.to_string().contains("object"), "{err}");

    // The grid's outline: a cell the walk names beyond the grid, no cells on an axis, an
    // inverted box.
    let v: serde_json::Value = serde_json::from_str(&trace.to_json()).unwrap();
    let cells = v["grid"]["cells"].clone();
    assert!(cells.as_array().is_some_and(|c| c.len() == 3), "{cells}");
    let mut bad = v.clone();
    let cell = find_key(&mut bad, "cell").expect("a cell step");
    cell["cell"] = serde_json::json!([cells[0], 0, 0]);
    let err = raystep_core::record::Trace::from_json(&bad.to_string(), "bad.json").unwrap_err();
    assert!(err.to_string().contains(".cell"), "{err}");
    let mut bad = v.clone();
    bad["grid"]["cells"] = serde_json::json!([0, 1, 1]);
    let err = raystep_core::record::Trace::from_json(&bad.to_string(), "bad.json").unwrap_err();
    assert!(err.to_string().contains("grid.cells"), "{err}");
    let mut bad = v.clone();
    bad["grid"]["max"] = serde_json::json!([-1e30, 0, 0]);
    let err = raystep_core::record::Trace::from_json(&bad.to_string(), "bad.json").unwrap_err();
    assert!(err.to_string().contains("grid.max"), "{err}");
}

/// The first step object of type `ty` anywhere in a trace's JSON.
fn find_key<'a>(v: &'a mut serde_json::Value, ty: &str) -> Option<&'a mut serde_json::Value> {
    if v.get("type").and_then(|t| t.as_str()) == Some(ty) {
        return Some(v);
    }
    match v {
        serde_json::Value::Object(m) => m.values_mut().find_map(|x| find_key(x, ty)),
        serde_json::Value::Array(a) => a.iter_mut().find_map(|x| find_key(x, ty)),
        _ => None,
    }
}

/// Ten thousand large triangles, each spanning the whole scene: a grid fine enough for their
/// count would list each in tens of thousands of cells (hundreds of millions of references).
/// The grid coarsens until its lists fit, and still finds what brute force finds.
#[test]
fn a_grid_of_many_large_primitives_stays_within_its_reference_budget() {
    let mut r = Rng(9);
    let mut t = String::new();
    for _ in 0..10_000 {
        let z = r.range(-10.0, 10.0);
        let p = [
            Vec3::new(-10.0, -10.0, z),
            Vec3::new(10.0, -10.0, z + r.range(-1.0, 1.0)),
            Vec3::new(0.0, 10.0, z + r.range(-1.0, 1.0)),
        ];
        t += &format!(
            "[[triangle]]\nvertices = [{}, {}, {}]\n",
            fmt(p[0]),
            fmt(p[1]),
            fmt(p[2])
        );
    }
    let scene = load_str(&t, "big.toml", None).unwrap();
    let grid = Grid::build(&scene);
    assert!(grid.references() as u64 <= raystep_core::accel::grid::MAX_REFERENCES);
    assert!(grid.references() >= 10_000);
    let rays = random_rays(3, 200);
    let hits = assert_same(&scene, &grid, &rays);
    assert!(hits > 20, "{hits}");
}

/// The AVX2 + FMA build of the queries of the BVH, the bounding spheres and brute force (the
/// grid has only the baseline build) renders the same image as its baseline x86-64 build, bit for bit, with either
/// triangle test (on a CPU without AVX2 and FMA both runs take the baseline build and the test
/// still holds, trivially). It fails if an accelerator's two builds round a test differently.
#[test]
fn wide_instructions_render_what_the_baseline_build_renders() {
    use raystep_core::shapes::triangle::TriangleMethod;
    for mut scene in small_scenes() {
        for method in [TriangleMethod::Watertight, TriangleMethod::MollerTrumbore] {
            scene.settings.triangle_method = method;
            // Brute force where it takes a moment (its loop is the same on every scene).
            let brute = scene.objects.len() <= 300;
            let accels = [AccelChoice::Bvh, AccelChoice::Spheres, AccelChoice::None];
            for &accel in accels.iter().take(if brute { 3 } else { 2 }) {
                raystep_core::accel::set_baseline_only(true);
                let baseline = render_with(&scene, accel);
                raystep_core::accel::set_baseline_only(false);
                let wide = render_with(&scene, accel);
                let diff = baseline.iter().zip(&wide).filter(|(x, y)| x != y).count();
                assert_eq!(
                    diff, 0,
                    "{method:?} with {accel:?} on \"{}\": {diff} pixels differ",
                    scene.name
                );
            }
        }
    }
}
