//! The exact references against hand computation: spheres, planes, triangles and boxes as exact
//! rationals.

use super::*;

#[test]
fn sphere_reference_matches_hand_computation() {
    let u = Precision::F32.unit_roundoff();
    // Sphere at the origin, radius 5; ray from (0,0,−10) along +z: |(0,0,−10+t)|² = 25 gives
    // t = 10 ∓ 5 = 5 and 15. The near root is taken, the far one is the "other".
    let r = exact::sphere([0.0; 3], 5.0, [0.0, 0.0, -10.0], [0.0, 0.0, 1.0], u);
    assert!(r.hit && !r.band);
    assert_eq!(r.t, Some(Dd { hi: 5.0, lo: 0.0 }));
    assert_eq!(r.other, Some(Dd { hi: 15.0, lo: 0.0 }));
    // From inside, at the centre: roots −5 and 5, the exit root 5 is taken.
    let r = exact::sphere([0.0; 3], 5.0, [0.0; 3], [0.0, 0.0, 1.0], u);
    assert_eq!(r.t.map(|t| t.hi), Some(5.0));
    // Direction (0,0,2): t halves (t·|d| is the distance): 2.5.
    let r = exact::sphere([0.0; 3], 5.0, [0.0, 0.0, -10.0], [0.0, 0.0, 2.0], u);
    assert_eq!(r.t.map(|t| t.hi), Some(2.5));
    // Passing at distance 6 > 5 from the centre: a miss, outside the band.
    let r = exact::sphere([0.0; 3], 5.0, [6.0, 0.0, -10.0], [0.0, 0.0, 1.0], u);
    assert!(!r.hit && !r.band);
    // Tangent (distance exactly 5): the double root t = 10, in the band.
    let r = exact::sphere([0.0; 3], 5.0, [5.0, 0.0, -10.0], [0.0, 0.0, 1.0], u);
    assert!(r.hit && r.band);
    assert_eq!(r.t.map(|t| t.hi), Some(10.0));
    // Irrational root: unit sphere 4100 away, ray 0.5 off axis: t = 4100 − √(1 − 0.25)
    // = 4100 − √3/2. The reference carries it to double-double precision: compare hi + lo with
    // √3/2 = 0.866025403784438646763723170752936183… by hand.
    let r = exact::sphere([0.0, 0.0, 4100.0], 1.0, [0.5, 0.0, 0.0], [0.0, 0.0, 1.0], u);
    let t = r.t.unwrap();
    let sqrt3_half_hi = 0.8660254037844386_f64;
    // The f64 written 0.8660254037844386 is exactly
    // 0.8660254037844385965883020617184229195117950439453125 (its binary expansion), so
    // √3/2 − that = 5.01754211090345132…e-17 (50-digit decimal arithmetic).
    let sqrt3_half_lo = 5.017_542_110_903_451e-17;
    assert_eq!(t.hi, 4100.0 - sqrt3_half_hi);
    // 4100 − √3/2 = hi + lo: lo is the rounding error of the f64 subtraction (recovered exactly
    // by Fast2Sum, |4100| ≥ |√3/2|) minus the part of √3/2 an f64 cannot hold.
    let rounding = (4100.0 - t.hi) - sqrt3_half_hi;
    let expected_lo = rounding - sqrt3_half_lo;
    assert!(
        (t.lo - expected_lo).abs() < 1e-25,
        "{} vs {expected_lo}",
        t.lo
    );
}

#[test]
fn plane_triangle_and_box_references_are_exact_rationals() {
    let u = Precision::F32.unit_roundoff();
    // Plane x + 2y + 2z = 3, ray from the origin along (1,1,1): t = 3/(1+2+2) = 3/5 — not a
    // binary fraction, so the double-double must be 0.6 to ~106 bits.
    let r = exact::plane([1.0, 2.0, 2.0], 3.0, [0.0; 3], [1.0, 1.0, 1.0], u);
    assert!(r.hit);
    assert_eq!(r.t, Some(Dd::of(&rat(3, 5))));
    assert_eq!(r.t.unwrap().hi, 0.6);
    // The same ray going away: t = −3/5, a miss. Parallel: d·n = 1·2 − 2·1 + 0 = 0, a miss.
    assert!(!exact::plane([1.0, 2.0, 2.0], 3.0, [0.0; 3], [-1.0, -1.0, -1.0], u).hit);
    assert!(!exact::plane([1.0, 2.0, 2.0], 3.0, [0.0; 3], [2.0, -1.0, 0.0], u).hit);
    // Triangle (0,0,0), (4,0,0), (0,4,0); ray from (1,1,3) along (0,0,−2): it meets z = 0 at
    // t = 3/2, at (1,1,0) = 0.25·P1 + 0.25·P2 → u = v = 1/4.
    let r = exact::triangle(
        [[0.0; 3], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]],
        [1.0, 1.0, 3.0],
        [0.0, 0.0, -2.0],
        u,
    );
    assert!(r.hit && !r.band);
    assert_eq!(r.t.map(|t| t.hi), Some(1.5));
    assert_eq!((r.u.unwrap().hi, r.v.unwrap().hi), (0.25, 0.25));
    // Aimed at (1, 3, 0): u + v = 1/4 + 3/4 = 1, exactly on the hypotenuse — a hit of the
    // closed triangle, and in the band.
    let r = exact::triangle(
        [[0.0; 3], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]],
        [1.0, 3.0, 3.0],
        [0.0, 0.0, -1.0],
        u,
    );
    assert!(r.hit && r.band);
    // Triangle (0,0,0), (3,0,0), (0,3,0), ray from (1,1,1) along (1,1,−3)·(1/1): the hit is at
    // t = 1/3 at (4/3, 4/3, 0): u = v = 4/9.
    let r = exact::triangle(
        [[0.0; 3], [3.0, 0.0, 0.0], [0.0, 3.0, 0.0]],
        [1.0, 1.0, 1.0],
        [1.0, 1.0, -3.0],
        u,
    );
    assert_eq!(r.t, Some(Dd::of(&rat(1, 3))));
    assert_eq!(r.u, Some(Dd::of(&rat(4, 9))));
    // Box [1,2]³ from the origin along (1,1,1): enters at t = 1.
    let r = exact::aabb([1.0; 3], [2.0; 3], [0.0; 3], [1.0, 1.0, 1.0], u);
    assert_eq!(r.t.map(|t| t.hi), Some(1.0));
    // Along (1, 3, 1): y enters at 1/3 and leaves at 2/3, x enters at 1: empty, a miss.
    assert!(!exact::aabb([1.0; 3], [2.0; 3], [0.0; 3], [1.0, 3.0, 1.0], u).hit);
    // Zero-thickness box z = 0.5, ray through it: t_near = t_far = 1/2, hit, not in the band.
    let r = exact::aabb(
        [0.0, 0.0, 0.5],
        [1.0, 1.0, 0.5],
        [0.5, 0.5, 0.0],
        [0.0, 0.0, 1.0],
        u,
    );
    assert!(r.hit && !r.band);
    assert_eq!(r.t.map(|t| t.hi), Some(0.5));
}
