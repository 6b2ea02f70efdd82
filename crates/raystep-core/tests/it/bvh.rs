//! The BVH finds exactly what brute force finds (random rays and the stiff cases S21–S23),
//! agrees with obvhs's own traversal, and a traced pixel equals the rendered pixel bit for bit.

use glam::{Vec3, Vec3A};
use raystep_core::accel::{Accelerator, BruteForce, Bvh, SceneAccel};
use raystep_core::math::Ray;
use raystep_core::record::{NodeAction, Recorder, Silent, Step};
use raystep_core::render::{RenderOptions, render};
use raystep_core::scene::{Scene, load_str};
use raystep_core::trace::Tracer;

use crate::common::rng;
use rng::{Rng, fmt};
/// A scene of random spheres and triangles (and a plane), as TOML.
fn random_scene(seed: u64, spheres: usize, triangles: usize, scale: f32) -> Scene {
    let mut r = Rng(seed);
    let mut t =
        String::from("[[plane]]\naxis = \"y\"\noffset = ") + &format!("{:e}\n", -12.0 * scale);
    for _ in 0..spheres {
        t += &format!(
            "[[sphere]]\ncenter = {}\nradius = {:e}\n",
            fmt(r.vec(-10.0, 10.0) * scale),
            r.range(0.1, 1.5) * scale
        );
    }
    for _ in 0..triangles {
        let c = r.vec(-10.0, 10.0);
        let p: Vec<Vec3> = (0..3).map(|_| (c + r.vec(-2.0, 2.0)) * scale).collect();
        t += &format!(
            "[[triangle]]\nvertices = [{}, {}, {}]\n",
            fmt(p[0]),
            fmt(p[1]),
            fmt(p[2])
        );
    }
    load_str(&t, "random.toml", None).unwrap()
}

fn random_rays(seed: u64, n: usize, scale: f32) -> Vec<Ray<f32>> {
    let mut r = Rng(seed);
    (0..n)
        .map(|_| {
            let o = r.vec(-20.0, 20.0) * scale;
            let target = r.vec(-10.0, 10.0) * scale;
            Ray::infinite(o, target - o).unwrap()
        })
        .collect()
}

fn assert_same(scene: &Scene, bvh: &Bvh, rays: &[Ray<f32>]) {
    let mut hits = 0;
    for (k, ray) in rays.iter().enumerate() {
        let a = BruteForce.closest(scene, ray, &mut Silent);
        let b = bvh.closest(scene, ray, &mut Silent);
        // The same kernel on the same ray gives bit-identical t; ties at equal t go to the
        // lower id in every accelerator, so the whole hit is the same.
        assert_eq!(a, b, "ray {k}: {ray:?}");
        hits += a.is_some() as usize;
        let sa = BruteForce.any(scene, ray, &mut Silent).is_some();
        let sb = bvh.any(scene, ray, &mut Silent).is_some();
        assert_eq!(sa, sb, "any-hit differs for ray {k}");
    }
    assert!(
        hits > rays.len() / 10,
        "too few hits ({hits}) for the test to mean much"
    );
}

#[test]
fn bvh_equals_brute_force_on_random_rays() {
    for (seed, spheres, tris) in [
        (1, 200, 0),
        (2, 0, 300),
        (3, 150, 150),
        (4, 1, 0),
        (5, 0, 2),
    ] {
        let scene = random_scene(seed, spheres, tris, 1.0);
        let bvh = Bvh::build(&scene);
        assert_same(&scene, &bvh, &random_rays(seed + 100, 3000, 1.0));
    }
}

/// Each leaf's objects, walking the tree from the root.
fn leaves(bvh: &Bvh) -> Vec<(Vec3A, Vec3A, Vec<u32>)> {
    let mut out = vec![];
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        let n = &bvh.nodes[i];
        if n.is_leaf() {
            let r = n.first as usize..(n.first + n.count) as usize;
            out.push((n.min, n.max, bvh.leaf_objects[r].to_vec()));
        } else {
            stack.extend([n.first as usize, n.first as usize + 1]);
        }
    }
    out
}

/// No leaf holds both triangles and balls: the Cornell box's two balls, which obvhs's builder
/// left in leaves with two wall triangles each (so every ray entering those leaves tested a
/// ball), have leaves of their own with the ball's own box; a leaf of primitives gathered by
/// their common centre is split too; on random scenes of both kinds every leaf is of one kind
/// and every object is in exactly one leaf.
#[test]
fn no_leaf_mixes_triangles_and_balls() {
    let is_triangle = |s: &Scene, id: u32| {
        matches!(
            s.objects[id as usize].shape,
            raystep_core::scene::Shape::Triangle { .. }
        )
    };
    let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes"))
        .join("cornell-area.toml");
    let cornell = raystep_core::scene::load_file(&path).unwrap();
    let bvh = Bvh::build(&cornell);
    for name in ["white ball", "mirror ball"] {
        let id = (0..cornell.objects.len())
            .find(|&id| cornell.object_name(id as u32) == name)
            .unwrap();
        let raystep_core::scene::Shape::Sphere { center, radius } = cornell.objects[id].shape
        else {
            panic!("{name} is a ball");
        };
        let leaf = leaves(&bvh)
            .into_iter()
            .find(|l| l.2.contains(&(id as u32)))
            .unwrap();
        // Balls only (the two share a leaf since every node is offered for reinsertion).
        assert!(
            leaf.2.iter().all(|&o| !is_triangle(&cornell, o)),
            "{name}'s leaf {:?} holds a triangle",
            leaf.2
        );
        // The box: the balls' own, centre ± radius each corner rounded one float outwards.
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for &o in &leaf.2 {
            let raystep_core::scene::Shape::Sphere { center, radius } =
                cornell.objects[o as usize].shape
            else {
                panic!("a ball");
            };
            let (l, h) = (
                (center - radius).to_array().map(f32::next_down),
                (center + radius).to_array().map(f32::next_up),
            );
            for k in 0..3 {
                lo[k] = lo[k].min(l[k]);
                hi[k] = hi[k].max(h[k]);
            }
        }
        let own = (center - radius).to_array().map(f32::next_down);
        assert!((0..3).all(|k| lo[k] <= own[k]), "{name} inside its leaf");
        assert_eq!(
            (leaf.0.to_array(), leaf.1.to_array()),
            (lo, hi),
            "{name}'s leaf box"
        );
    }
    // A ball and sixteen triangles whose boxes share its centre: raystep gathers primitives
    // with one centre into one leaf (no split of obvhs's could part them), here the root; split,
    // the root is an inner node over the sixteen triangles and the ball, and the answers are
    // brute force's.
    let mut text = String::from("[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\n");
    for k in 0..16 {
        let a = 1.0 + k as f32 / 10.0;
        text += &format!(
            "[[triangle]]\nvertices = [[{}, {}, 0], [{a}, {}, 0], [0, {a}, 0]]\n",
            -a, -a, -a
        );
    }
    let gathered = load_str(&text, "gathered.toml", None).unwrap();
    let bvh = Bvh::build(&gathered);
    assert!(!bvh.nodes[0].is_leaf(), "the root's leaf was split");
    let mut parts: Vec<Vec<u32>> = leaves(&bvh).into_iter().map(|l| l.2).collect();
    parts.sort();
    assert_eq!(parts, vec![vec![0], (1..=16).collect::<Vec<u32>>()]);
    assert_same(&gathered, &bvh, &random_rays(7, 2000, 0.2));
    for seed in 0..6 {
        let s = random_scene(seed, 40, 60, 1.0);
        let bvh = Bvh::build(&s);
        let mut seen = vec![];
        for (_, _, ids) in leaves(&bvh) {
            let kinds: Vec<bool> = ids.iter().map(|&id| is_triangle(&s, id)).collect();
            assert!(
                kinds.iter().all(|&k| k == kinds[0]),
                "seed {seed}: a mixed leaf {ids:?}"
            );
            seen.extend(ids);
        }
        seen.sort_unstable();
        // Every finite object once (object 0 is the plane, outside the tree).
        assert_eq!(
            seen,
            (1..s.objects.len() as u32).collect::<Vec<_>>(),
            "seed {seed}"
        );
    }
}

#[test]
fn bvh_matches_obvhs_own_traversal() {
    // obvhs's `ray_traverse` over the same tree, with raystep's kernel as its intersection
    // callback: the closest t must agree. (Random rays here are far from parallel to any axis, so
    // obvhs's clamped reciprocals do not matter.)
    let scene = random_scene(7, 100, 200, 1.0);
    let bvh = Bvh::build(&scene);
    let finite: Vec<u32> = (0..scene.objects.len() as u32)
        .filter(|id| !bvh.planes.contains(id))
        .collect();
    for ray in random_rays(8, 3000, 1.0) {
        let mut theirs = obvhs::ray::RayHit::none();
        let oray = obvhs::ray::Ray::new(
            Vec3A::from(ray.origin),
            Vec3A::from(ray.dir),
            0.0,
            f32::INFINITY,
        );
        bvh.obvhs.ray_traverse(oray, &mut theirs, |r, slot| {
            let id = finite[bvh.obvhs.primitive_indices[slot] as usize];
            let ray = Ray {
                origin: Vec3::from(r.origin),
                dir: Vec3::from(r.direction),
                t_min: r.tmin,
                t_max: r.tmax,
            };
            raystep_core::accel::test_object(&scene, id, &ray, &mut Silent)
                .map_or(f32::INFINITY, |h| h.t)
        });
        // Compare without the plane (obvhs's tree holds only finite primitives).
        let mut ours = None;
        let mut r = ray;
        for &id in &finite {
            if let Some(h) = raystep_core::accel::test_object(&scene, id, &r, &mut Silent) {
                r.t_max = h.t;
                ours = Some(h.t);
            }
        }
        assert_eq!(ours.unwrap_or(f32::INFINITY), theirs.t);
    }
}

#[test]
fn s21_near_parallel_rays_never_miss() {
    // A grid of flat triangles in z = 5; rays along (1e-9, 0, 1) — obvhs's clamped reciprocal
    // (1/ε instead of 1e9) would misplace the x slabs; raystep's traversal must match brute force.
    let mut t = String::new();
    for i in 0..20 {
        let x = i as f32;
        t += &format!(
            "[[triangle]]\nvertices = [[{x}, 0, 5], [{}, 0, 5], [{x}, 1, 5]]\n",
            x + 1.0
        );
        t += &format!(
            "[[triangle]]\nvertices = [[{}, 0, 5], [{}, 1, 5], [{x}, 1, 5]]\n",
            x + 1.0,
            x + 1.0
        );
    }
    let scene = load_str(&t, "s21.toml", None).unwrap();
    let bvh = Bvh::build(&scene);
    let rays: Vec<Ray<f32>> = (0..400)
        .map(|k| {
            Ray::infinite(
                Vec3::new(0.025 + k as f32 * 0.05, 0.5, 0.0),
                Vec3::new(1e-9, 0.0, 1.0),
            )
            .unwrap()
        })
        .collect();
    for ray in &rays {
        let a = BruteForce.closest(&scene, ray, &mut Silent);
        assert!(a.is_some());
        assert_eq!(
            a.map(|h| h.t),
            bvh.closest(&scene, ray, &mut Silent).map(|h| h.t)
        );
    }
}

#[test]
fn s22_zero_thickness_boxes_are_hit() {
    // Axis-aligned quads make flat node boxes (zero thickness in z).
    let scene = random_scene(11, 0, 0, 1.0);
    let _ = scene;
    let mut t = String::new();
    for i in 0..16 {
        let (x, y) = ((i % 4) as f32 * 2.0, (i / 4) as f32 * 2.0);
        t += &format!(
            "[[triangle]]\nvertices = [[{x}, {y}, 3], [{}, {y}, 3], [{x}, {}, 3]]\n",
            x + 2.0,
            y + 2.0
        );
    }
    let scene = load_str(&t, "s22.toml", None).unwrap();
    let bvh = Bvh::build(&scene);
    let mut r = Rng(5);
    for _ in 0..2000 {
        let target = Vec3::new(r.range(0.0, 8.0), r.range(0.0, 8.0), 3.0);
        let o = Vec3::new(r.range(-5.0, 13.0), r.range(-5.0, 13.0), -4.0);
        let ray = Ray::infinite(o, target - o).unwrap();
        assert_eq!(
            BruteForce.closest(&scene, &ray, &mut Silent).map(|h| h.t),
            bvh.closest(&scene, &ray, &mut Silent).map(|h| h.t)
        );
    }
}

#[test]
fn s23_tiny_scale_and_close_surfaces() {
    // The whole random scene scaled by 1e-5: no fixed t_min may creep into traversal.
    let scene = random_scene(21, 100, 100, 1e-5);
    let bvh = Bvh::build(&scene);
    assert_same(&scene, &bvh, &random_rays(22, 2000, 1e-5));
    // Two spheres whose surfaces are 5e-5 apart, ray leaving the inner one from its surface.
    let t = "[[sphere]]\nradius = 1\n[[sphere]]\nradius = 1.00005\n[[sphere]]\ncenter = [5, 0, 0]\n\
             [[sphere]]\ncenter = [-5, 0, 0]\n";
    let scene = load_str(t, "s23.toml", None).unwrap();
    let bvh = Bvh::build(&scene);
    let ray = Ray::new(Vec3::new(0.0, 0.0, 1.0), Vec3::Z, 1e-6, f32::INFINITY).unwrap();
    let a = BruteForce.closest(&scene, &ray, &mut Silent).unwrap();
    let b = bvh.closest(&scene, &ray, &mut Silent).unwrap();
    assert_eq!((a.object, a.t), (b.object, b.t));
    assert_eq!(a.object, 1, "the outer sphere, 5e-5 away, is found");
}

#[test]
fn recorded_traversal_shows_nodes_and_leaf_tests() {
    let scene = random_scene(31, 60, 0, 1.0);
    let bvh = Bvh::build(&scene);
    let ray = Ray::infinite(Vec3::new(0.0, 0.0, -30.0), Vec3::Z).unwrap();
    let mut rec = Recorder::new();
    rec_closest(&scene, &bvh, &ray, &mut rec);
    let root = rec.finish().unwrap();
    let nodes: Vec<_> = root
        .steps
        .iter()
        .filter_map(|s| {
            if let Step::Node(n) = &s.step {
                Some(n.clone())
            } else {
                None
            }
        })
        .collect();
    assert_eq!(nodes[0].node, 0, "the root is visited first");
    assert_eq!(nodes[0].depth, 0);
    // Every primitive test follows a leaf visit whose action is TestPrimitives.
    let mut in_leaf = false;
    for s in &root.steps {
        match &s.step {
            Step::Node(n) => in_leaf = n.action == NodeAction::TestPrimitives,
            Step::Sphere { .. } => assert!(in_leaf, "a sphere test outside a tested leaf"),
            _ => {}
        }
    }
    // Fewer sphere tests than spheres: the BVH culled some.
    let tests = root
        .steps
        .iter()
        .filter(|s| matches!(s.step, Step::Sphere { .. }))
        .count();
    assert!(tests < 60, "{tests} tests");
}

/// Siblings are visited nearer first by a closest-hit ray and farther first by a shadow ray
/// (any blocker will do; the nearer box mostly holds the surface a shadow ray leaves). Read from
/// the recorded scalar slab tests: after the root, each step of the walk records a sibling pair,
/// the one it visits first first.
#[test]
fn shadow_rays_visit_the_farther_sibling_first_closest_hits_the_nearer() {
    use raystep_core::record::{Observer, RayKind};
    let scene = random_scene(23, 80, 80, 1.0);
    let bvh = Bvh::build(&scene);
    let (mut compared, mut strictly) = ([0usize; 2], [0usize; 2]);
    for ray in random_rays(29, 300, 1.0) {
        for (k, kind) in [RayKind::Primary, RayKind::Shadow].into_iter().enumerate() {
            let mut rec = Recorder::new();
            rec.begin_ray(kind, 0, &ray, 1.0);
            let hit = if kind == RayKind::Shadow {
                bvh.any(&scene, &ray, &mut rec)
            } else {
                bvh.closest(&scene, &ray, &mut rec)
            };
            rec.end_ray(|| None, Vec3::ZERO);
            let _ = hit;
            let trace = rec.finish().unwrap();
            let nodes: Vec<_> = trace
                .steps
                .iter()
                .filter_map(|s| match &s.step {
                    Step::Node(n) => Some(n.clone()),
                    _ => None,
                })
                .collect();
            for pair in nodes.get(1..).unwrap_or_default().chunks(2) {
                let [first, second] = pair else { continue };
                assert_eq!(first.node.min(second.node) + 1, first.node.max(second.node));
                if !(first.test.hit && second.test.hit) {
                    continue;
                }
                let (a, b) = (first.test.t_near, second.test.t_near);
                if kind == RayKind::Shadow {
                    assert!(
                        a >= b,
                        "shadow ray: {} (t_near {a}) before {} ({b})",
                        first.node,
                        second.node
                    );
                } else {
                    assert!(
                        a <= b,
                        "closest hit: {} (t_near {a}) before {} ({b})",
                        first.node,
                        second.node
                    );
                }
                compared[k] += 1;
                strictly[k] += usize::from(a != b);
            }
        }
    }
    // Not vacuous: many pairs where both boxes were hit at different distances.
    assert!(
        strictly.iter().all(|&n| n > 50),
        "{compared:?} {strictly:?}"
    );
}

/// A full render of `tracer`'s scene on `threads` threads.
fn render_on(
    tracer: &Tracer<'_, SceneAccel>,
    threads: usize,
) -> raystep_core::render::RenderOutput {
    render(
        tracer,
        &RenderOptions {
            threads: Some(threads),
            ..Default::default()
        },
    )
    .unwrap()
}

fn rec_closest(scene: &Scene, bvh: &Bvh, ray: &Ray<f32>, rec: &mut Recorder) {
    use raystep_core::record::{Observer, RayKind};
    rec.begin_ray(RayKind::Primary, 0, ray, 1.0);
    let hit = bvh.closest(scene, ray, rec);
    rec.end_ray(|| None, Vec3::ZERO);
    let _ = hit;
}

#[test]
fn traced_pixel_equals_rendered_pixel_with_and_without_bvh() {
    let text = std::fs::read_to_string(concat!(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../.."),
        "/scenes/three-spheres.toml"
    ))
    .unwrap();
    for accel in ["none", "bvh"] {
        for spp in [1, 4] {
            let mut scene = load_str(&text, "three-spheres.toml", None).unwrap();
            scene.camera.width = 48;
            scene.camera.height = 36;
            scene.settings.accel = if accel == "bvh" {
                raystep_core::scene::AccelChoice::Bvh
            } else {
                raystep_core::scene::AccelChoice::None
            };
            scene.settings.spp = spp;
            let (a, _) = SceneAccel::build(&scene);
            let tracer = Tracer::new(&scene, &a);
            for threads in [1, 2] {
                let out = render_on(&tracer, threads);
                for y in (0..36).step_by(5) {
                    for x in (0..48).step_by(5) {
                        let mut sum = Vec3::ZERO;
                        for k in 0..spp {
                            sum += Vec3::from(tracer.record(x, y, k).color);
                        }
                        let traced = sum / spp as f32;
                        assert_eq!(
                            traced.to_array(),
                            out.pixels[(y * 48 + x) as usize].to_array(),
                            "({x}, {y})"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn render_is_identical_whatever_the_thread_count() {
    let scene = random_scene(41, 80, 80, 1.0);
    let mut scene = scene;
    scene.camera.width = 64;
    scene.camera.height = 48;
    scene.camera.from = Vec3::new(0.0, 2.0, -40.0);
    let (a, _) = SceneAccel::build(&scene);
    let tracer = Tracer::new(&scene, &a);
    let one = render_on(&tracer, 1);
    let two = render_on(&tracer, 2);
    let bits = |o: &raystep_core::render::RenderOutput| {
        o.pixels
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&one), bits(&two));
}

/// Every pixel of a render, whatever the image's size (tiles cut at the right and bottom
/// edges, images narrower or shorter than a tile) and the thread count, is what tracing that
/// pixel alone gives, bit for bit: the render writes each pixel of the image exactly once.
#[test]
fn every_pixel_of_any_size_is_the_pixel_traced_alone() {
    let base = random_scene(7, 30, 30, 1.0);
    for (width, height) in [(1, 1), (1, 37), (37, 1), (16, 16), (17, 33), (40, 23)] {
        let mut scene = base.clone();
        scene.camera.width = width;
        scene.camera.height = height;
        scene.camera.from = Vec3::new(0.0, 2.0, -40.0);
        let (a, _) = SceneAccel::build(&scene);
        let tracer = Tracer::new(&scene, &a);
        for threads in [1, 2, 3] {
            let out = render_on(&tracer, threads);
            assert_eq!(out.pixels.len(), (width * height) as usize);
            for y in 0..height {
                for x in 0..width {
                    let alone = tracer.trace_pixel(x, y, &mut Silent);
                    assert_eq!(
                        alone.to_array().map(f32::to_bits),
                        out.pixels[(y * width + x) as usize]
                            .to_array()
                            .map(f32::to_bits),
                        "{width}×{height}, {threads} threads, pixel ({x}, {y})"
                    );
                }
            }
        }
    }
}

/// A watched render (the app's) shows, when done, exactly the image it returns, converted as a
/// PNG is; a render cancelled before it starts says so and shows nothing.
#[test]
fn a_watched_render_shows_the_image_it_returns() {
    use raystep_core::render::{CANCELLED, LiveRender};
    use std::sync::Arc;
    use std::sync::atomic::Ordering;
    let mut scene = random_scene(11, 30, 30, 1.0);
    scene.camera.width = 45;
    scene.camera.height = 29;
    scene.camera.from = Vec3::new(0.0, 2.0, -40.0);
    let (a, _) = SceneAccel::build(&scene);
    let tracer = Tracer::new(&scene, &a);
    let live = Arc::new(LiveRender::new(45, 29));
    let out = render(
        &tracer,
        &RenderOptions {
            threads: Some(2),
            live: Some(Arc::clone(&live)),
            ..Default::default()
        },
    )
    .unwrap();
    let png = raystep_core::render::image::to_rgb8(45, 29, &out.pixels, false);
    let shown = live.pixels.lock().unwrap();
    for (i, (shown, p)) in shown.iter().zip(png.pixels()).enumerate() {
        assert_eq!(
            *shown,
            [p.0[0], p.0[1], p.0[2], 255],
            "pixel ({}, {})",
            i % 45,
            i / 45
        );
    }
    // 3 × 2 tiles of 16 × 16 or less.
    assert_eq!(live.tiles_total.load(Ordering::Relaxed), 6);
    assert_eq!(live.tiles_done.load(Ordering::Relaxed), 6);

    let cancelled = Arc::new(LiveRender::new(45, 29));
    cancelled.cancel.store(true, Ordering::Relaxed);
    let result = render(
        &tracer,
        &RenderOptions {
            threads: Some(2),
            live: Some(Arc::clone(&cancelled)),
            ..Default::default()
        },
    );
    assert_eq!(result.err().as_deref(), Some(CANCELLED));
    assert_eq!(cancelled.tiles_done.load(Ordering::Relaxed), 0);
    assert!(cancelled.pixels.lock().unwrap().iter().all(|p| p[3] == 0));
}

/// obvhs builds in parallel; the tree must not depend on the thread count (a recorded pixel
/// shows node ids, and a class comparing traces across machines must see the same ones).
#[test]
fn tree_is_the_same_whatever_the_thread_count() {
    let scene = random_scene(7, 40_000, 40_000, 10.0);
    let build = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| Bvh::build(&scene))
    };
    let one = build(1);
    for threads in [2, 3, 8] {
        let other = build(threads);
        assert_eq!(one.nodes, other.nodes, "{threads} threads");
        assert_eq!(one.leaf_objects, other.leaf_objects, "{threads} threads");
    }
}

/// A tree of one sphere is one leaf holding one primitive: SAH cost 1 (its area over itself,
/// times one test), whatever the quality.
#[test]
fn sah_cost_of_a_single_leaf_is_one() {
    for q in ["low", "medium", "high"] {
        let s = load_str(
            &format!(
                "[render]\nbvh_quality = \"{q}\"\n[[sphere]]\ncenter = [1, 2, 3]\nradius = 0.5\n"
            ),
            "one.toml",
            None,
        )
        .unwrap();
        let bvh = Bvh::build(&s);
        assert_eq!(bvh.nodes.len(), 1, "{q}");
        assert_eq!(bvh.sah_cost(), 1.0, "{q}");
    }
}

/// The scene file's `bvh_quality` picks obvhs's preset: on the 820-sphere flake the low preset
/// gives the worst tree and the high one the best (SAH costs measured with `raystep bench
/// --section build`: about 25, 21 and 20), and the app's settings change rebuilds the tree.
#[test]
fn bvh_quality_orders_the_trees_and_a_change_rebuilds() {
    use raystep_core::PreparedScene;
    use raystep_core::scene::BvhQuality;
    let out =
        raystep_core::scene::spd::generate(raystep_core::scene::spd::SpdScene::Balls, 3).unwrap();
    let mut scene = load_str(&out.toml, "balls.toml", None).unwrap();
    scene.settings.accel = raystep_core::scene::AccelChoice::Bvh;
    let base = std::sync::Arc::new(scene);
    let medium = PreparedScene::shared(std::sync::Arc::clone(&base));
    let mut settings = base.settings.clone();
    let mut cost = |q: BvhQuality| {
        settings.bvh_quality = q;
        let p = PreparedScene::with_settings(&base, &settings, Some(&medium));
        let bvh = p.bvh().expect("a BVH");
        (bvh.sah_cost(), bvh.nodes.len())
    };
    let (low, high) = (cost(BvhQuality::Low), cost(BvhQuality::High));
    let med = (
        medium.bvh().unwrap().sah_cost(),
        medium.bvh().unwrap().nodes.len(),
    );
    assert!(
        low.0 > med.0 && med.0 > high.0,
        "low {low:?}, medium {med:?}, high {high:?}"
    );
    // Reused, not rebuilt, when only the samples change.
    settings.bvh_quality = BvhQuality::Medium;
    settings.spp = 4;
    let same = PreparedScene::with_settings(&base, &settings, Some(&medium));
    assert!(std::ptr::eq(same.accel(), medium.accel()));
}
