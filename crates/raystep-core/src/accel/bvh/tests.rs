//! The SIMD box and triangle tests against the recorded scalar tests.

use super::*;
use proptest::prelude::*;

/// Coordinates that make the hard cases likely: zeros of both signs, coincident values (a ray
/// lying in a face plane, a flat box), and arbitrary numbers.
fn coordinate() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(0.0f32),
        Just(-0.0f32),
        Just(1.0f32),
        Just(-1.0f32),
        Just(2.5f32),
        -4.0f32..4.0,
    ]
}

/// Direction components for the ordered test (which needs finite reciprocals).
fn nonzero() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(1.0f32),
        Just(-1.0f32),
        Just(2.5f32),
        -4.0f32..-1e-3,
        1e-3f32..4.0,
    ]
}

fn vec3() -> impl Strategy<Value = Vec3> {
    (coordinate(), coordinate(), coordinate()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn ray_to(origin: Vec3, dir: Vec3, t_max: f32) -> Ray<f32> {
    Ray {
        origin,
        dir,
        t_min: 0.0,
        t_max,
    }
}

/// A leaf whose box has corners `p` and `q`.
fn leaf_box(p: Vec3, q: Vec3) -> Node {
    Node {
        min: Vec3A::from(p.min(q)),
        max: Vec3A::from(p.max(q)),
        first: 0,
        count: 1,
        pack: NO_PACK,
    }
}

/// Both SIMD box tests the traversal uses give the recorded scalar test's decision and its
/// (t_near, t_far) — the ordered one whenever the traversal would choose it.
fn check(origin: Vec3, dir: Vec3, a: Vec3, b: Vec3, t_max: f32) -> Result<(), TestCaseError> {
    let (min, max) = (a.min(b), a.max(b));
    let ray = ray_to(origin, dir, t_max);
    let inv = Vec3::ONE / dir;
    let node = leaf_box(a, b);
    let scalar = slab_robust(&ray, inv, min, max);
    let fast = FastRay::new(&ray, inv);
    let t_max_v = Vec3A::splat(t_max);
    let mut tests = vec![fast.interval::<false>(&node, t_max_v)];
    if inv.is_finite() && dir.is_finite() {
        tests.push(fast.interval::<true>(&node, t_max_v));
    }
    for (near, far) in tests {
        prop_assert_eq!(near <= far, scalar.hit, "decision, ray {:?}", ray);
        // Equal as numbers (the sign of a zero t decides nothing).
        prop_assert!(
            near == scalar.t_near,
            "t_near {} vs {}",
            near,
            scalar.t_near
        );
        prop_assert!(far == scalar.t_far, "t_far {} vs {}", far, scalar.t_far);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]
    #[test]
    fn simd_box_tests_agree_with_the_recorded_test(
        origin in vec3(),
        dir in vec3(),
        a in vec3(),
        b in vec3(),
        t_max in prop_oneof![Just(f32::INFINITY), 0.5f32..10.0],
    ) {
        prop_assume!(dir != Vec3::ZERO);
        check(origin, dir, a, b, t_max)?;
    }
}

/// The AVX pair test gives each box's ordered interval bit for bit.
#[cfg(target_arch = "x86_64")]
fn check_pair(origin: Vec3, dir: Vec3, boxes: [Vec3; 4], t_max: f32) -> Result<(), TestCaseError> {
    if !std::arch::is_x86_feature_detected!("avx") {
        return Ok(());
    }
    let ray = ray_to(origin, dir, t_max);
    let inv = Vec3::ONE / dir;
    let (a, b) = (leaf_box(boxes[0], boxes[1]), leaf_box(boxes[2], boxes[3]));
    let fast = FastRay::new(&ray, inv);
    let t_max_v = Vec3A::splat(t_max);
    #[allow(unsafe_code)]
    // SAFETY: AVX was detected above.
    let (pa, pb) = unsafe { ray_box::wide::interval_pair(&fast, &a, &b, t_max_v) };
    let (sa, sb) = (
        fast.interval::<true>(&a, t_max_v),
        fast.interval::<true>(&b, t_max_v),
    );
    let bits = |(n, f): (f32, f32)| (n.to_bits(), f.to_bits());
    prop_assert_eq!(bits(pa), bits(sa));
    prop_assert_eq!(bits(pb), bits(sb));
    Ok(())
}

#[cfg(target_arch = "x86_64")]
proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]
    #[test]
    fn the_avx_pair_test_equals_two_single_tests(
        origin in vec3(),
        dir in (nonzero(), nonzero(), nonzero()).prop_map(|(x, y, z)| Vec3::new(x, y, z)),
        p in vec3(), q in vec3(), r in vec3(), s in vec3(),
        t_max in prop_oneof![Just(f32::INFINITY), 0.5f32..10.0],
    ) {
        check_pair(origin, dir, [p, q, r, s], t_max)?;
    }
}

#[test]
fn a_ray_in_a_face_plane_is_inside_that_slab() {
    // Along +x in the plane y = 0, the box's bottom face: hit, from t = 1 to t = 2 (× 1 + 2γ₃).
    let r = check(
        Vec3::new(0.0, 0.0, 0.5),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(2.0, 1.0, 1.0),
        f32::INFINITY,
    );
    assert!(r.is_ok(), "{r:?}");
    let ray = Ray {
        origin: Vec3::new(0.0, 0.0, 0.5),
        dir: Vec3::new(1.0, -0.0, 0.0),
        t_min: 0.0,
        t_max: f32::INFINITY,
    };
    let inv = Vec3::ONE / ray.dir;
    let node = Node {
        min: Vec3A::new(1.0, 0.0, 0.0),
        max: Vec3A::new(2.0, 1.0, 1.0),
        first: 0,
        count: 1,
        pack: NO_PACK,
    };
    let (near, far) = FastRay::new(&ray, inv).interval::<false>(&node, Vec3A::INFINITY);
    assert_eq!(near, 1.0);
    assert!((2.0..2.0001).contains(&far), "{far}");
}

/// Triangle coordinates: the box tests' hard cases, plus magnitudes whose products overflow
/// (edge functions and scaled distances then become infinite or NaN).
fn tri_coordinate() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => coordinate(),
        1 => Just(1e20f32),
        1 => Just(-3e38f32),
        1 => Just(1e-30f32),
        1 => -1e6f32..1e6,
    ]
}

fn tri_vec3() -> impl Strategy<Value = Vec3> {
    (tri_coordinate(), tri_coordinate(), tri_coordinate()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// Each lane of the four-lane watertight test gives the scalar test's decision, t, u and v,
/// bit for bit — for a lane not left to the scalar test (an edge function exactly zero).
/// Returns how many lanes were decided by the four-lane test.
#[cfg(target_arch = "x86_64")]
fn check_tri4(ray: &Ray<f32>, tris: &[[Vec3; 3]]) -> Result<usize, TestCaseError> {
    use crate::shapes::triangle::{Shear, watertight_sheared};
    if !(std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma"))
    {
        return Ok(0);
    }
    let shear = Shear::of(ray);
    let pack = Tri4::pack(tris);
    #[allow(unsafe_code)]
    // SAFETY: AVX2 and FMA were detected above.
    let lanes = unsafe { tri4::test4(&tri4::Ray4::new(ray, &shear), &pack) };
    let mut decided = 0;
    for (j, p) in tris.iter().enumerate() {
        let scalar = watertight_sheared(ray, &shear, *p);
        if lanes.exact & (1 << j) != 0 {
            // An edge function was exactly zero: the traversal runs the scalar test (whose f64
            // recomputation decides) for this lane.
            continue;
        }
        decided += 1;
        let hit = lanes.pass & (1 << j) != 0 && lanes.t[j] < ray.t_max;
        prop_assert_eq!(
            hit,
            scalar.t.is_some(),
            "lane {}: {:?} vs scalar {:?}, ray {:?}, triangle {:?}",
            j,
            (lanes.t[j], lanes.pass),
            scalar,
            ray,
            p
        );
        if let Some(t) = scalar.t {
            prop_assert_eq!(lanes.t[j].to_bits(), t.to_bits());
            prop_assert_eq!(Some(lanes.u[j].to_bits()), scalar.u.map(f32::to_bits));
            prop_assert_eq!(Some(lanes.v[j].to_bits()), scalar.v.map(f32::to_bits));
        }
    }
    Ok(decided)
}

#[cfg(target_arch = "x86_64")]
proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]
    #[test]
    fn the_four_lane_triangle_test_equals_the_scalar_test(
        origin in vec3(),
        dir in vec3(),
        tris in proptest::collection::vec((tri_vec3(), tri_vec3(), tri_vec3()), 1..=4),
        t_max in prop_oneof![Just(f32::INFINITY), 0.5f32..10.0, Just(1e-3f32)],
        t_min in prop_oneof![Just(0.0f32), Just(1e-4f32)],
    ) {
        prop_assume!(dir != Vec3::ZERO);
        let ray = Ray { origin, dir, t_min, t_max };
        let tris: Vec<[Vec3; 3]> = tris.into_iter().map(|(a, b, c)| [a, b, c]).collect();
        check_tri4(&ray, &tris)?;
    }

    /// Rays aimed at a point inside the triangle (most are hits, so t, u and v are compared),
    /// at an edge or at a vertex.
    #[test]
    fn the_four_lane_test_agrees_on_rays_aimed_at_triangles(
        origin in tri_vec3(),
        tris in proptest::collection::vec((vec3(), vec3(), vec3()), 1..=4),
        weights in (0.0f32..1.0, 0.0f32..1.0),
        aim in 0usize..4,
        which in 0usize..4,
    ) {
        let tris: Vec<[Vec3; 3]> = tris.into_iter().map(|(a, b, c)| [a, b, c]).collect();
        let Some(p) = tris.get(which % tris.len()) else { return Ok(()) };
        let (a, b) = weights;
        let target = match aim {
            0 => p[0] + (p[1] - p[0]) * a * 0.5 + (p[2] - p[0]) * b * 0.5,
            1 => p[0] + (p[1] - p[0]) * a,
            2 => p[1],
            _ => (p[0] + p[1] + p[2]) / 3.0,
        };
        let dir = target - origin;
        prop_assume!(dir != Vec3::ZERO && dir.is_finite());
        let ray = Ray { origin, dir, t_min: 0.0, t_max: f32::INFINITY };
        check_tri4(&ray, &tris)?;
    }
}

/// The hand-made case: a ray down −z through (0.25, 0.25) of the triangle (0,0,0), (1,0,0),
/// (0,1,0) at z = 0 from z = 2 — t = 2, u = v = 0.25 (by hand) — in every lane, next to lanes
/// it misses (the triangle moved by 5 along x).
#[cfg(target_arch = "x86_64")]
#[test]
fn four_lanes_find_the_hand_computed_hit() {
    if !(std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma"))
    {
        return;
    }
    let hit = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let miss = hit.map(|v| v + Vec3::new(5.0, 0.0, 0.0));
    let ray = ray_to(Vec3::new(0.25, 0.25, 2.0), Vec3::NEG_Z, f32::INFINITY);
    let shear = crate::shapes::triangle::Shear::of(&ray);
    #[allow(unsafe_code)]
    // SAFETY: AVX2 and FMA were detected above.
    let lanes = unsafe {
        tri4::test4(
            &tri4::Ray4::new(&ray, &shear),
            &Tri4::pack(&[miss, hit, miss, hit]),
        )
    };
    assert_eq!(lanes.pass, 0b1010);
    assert_eq!(lanes.exact, 0);
    for j in [1, 3] {
        assert_eq!((lanes.t[j], lanes.u[j], lanes.v[j]), (2.0, 0.25, 0.25));
    }
}

/// raystep's nodes are obvhs's tree in the order obvhs's own `reorder_in_stack_traversal_order`
/// gives (an independent implementation of the same depth-first walk): node for node the same
/// boxes, counts and children — and so every subtree's pairs follow its second node.
#[test]
fn nodes_are_in_obvhs_depth_first_order() {
    for (kind, size) in [
        (crate::scene::spd::SpdScene::Balls, 2),
        (crate::scene::spd::SpdScene::Tetra, 4),
        (crate::scene::spd::SpdScene::Mount, 4),
    ] {
        let out = crate::scene::spd::generate(kind, size).unwrap();
        let dir = tempfile::tempdir().unwrap();
        if let Some((name, obj)) = &out.obj {
            std::fs::write(dir.path().join(name), obj).unwrap();
        }
        let scene = crate::scene::load_str(&out.toml, "spd.toml", Some(dir.path())).unwrap();
        let bvh = Bvh::build(&scene);
        let mut reference = bvh.obvhs.clone();
        reference.reorder_in_stack_traversal_order();
        assert_eq!(bvh.nodes.len(), reference.nodes.len(), "{kind:?}");
        assert_ne!(
            reference
                .nodes
                .iter()
                .map(|n| n.first_index)
                .collect::<Vec<_>>(),
            bvh.obvhs
                .nodes
                .iter()
                .map(|n| n.first_index)
                .collect::<Vec<_>>(),
            "{kind:?}: obvhs's builder order is not already depth-first"
        );
        for (i, (ours, theirs)) in bvh.nodes.iter().zip(&reference.nodes).enumerate() {
            let b = theirs.aabb();
            assert_eq!(
                (ours.min, ours.max, ours.first, ours.count),
                (b.min, b.max, theirs.first_index, theirs.prim_count),
                "{kind:?}, node {i}"
            );
        }
    }
}
