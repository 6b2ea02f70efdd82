//! Stiff cases of the slab (box) test.

use super::*;

pub(super) fn signed_zero(rng: &mut Rng) -> f64 {
    if rng.f() < 0.5 { 0.0 } else { -0.0 }
}

pub(super) fn box_signed_zero(rng: &mut Rng, n: usize) -> Case {
    let (lo, hi) = ([-1.0; 3], [1.0; 3]);
    let mut q = vec![];
    for k in 0..n {
        let sgn = |r: &mut Rng| if r.f() < 0.5 { 1.0 } else { -1.0 };
        let (o, d) = match k % 3 {
            // Origin on the face x = ±1, direction in the face plane (d_x = ±0).
            0 => (
                [
                    sgn(rng),
                    r32(rng.range(-0.9, 0.9)),
                    r32(rng.range(-0.9, 0.9)),
                ],
                [signed_zero(rng), r32(rng.range(-1.0, 1.0)), 1.0],
            ),
            // Along an edge: x = ±1, y = ±1, direction along z.
            1 => (
                [sgn(rng), sgn(rng), r32(rng.range(-5.0, -2.0))],
                [signed_zero(rng), signed_zero(rng), 1.0],
            ),
            // From outside towards a corner, along the diagonal.
            _ => {
                let c = [sgn(rng), sgn(rng), sgn(rng)];
                (scale(c, 3.0), scale(c, -1.0))
            }
        };
        q.push(query(Geometry::Aabb { lo, hi }, o, d));
    }
    rays(
        "S20",
        "box: origin on a face, along an edge, at a corner; d = ±0",
        Primitive::Box,
        Kind::Classify,
        q,
    )
}

pub(super) fn box_near_parallel(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    let (lo, hi) = ([-1.0; 3], [1.0; 3]);
    let mut q = vec![];
    for tiny in pick(opts, &[1e-9, 1e-20, 1e-38, 1e-45]) {
        for _ in 0..n {
            let o = [r32(rng.range(-0.9, 0.9)), r32(rng.range(-0.9, 0.9)), -5.0];
            let d = [r32(tiny * rng.range(-1.0, 1.0)), signed_zero(rng), 1.0];
            q.push(query(Geometry::Aabb { lo, hi }, o, d));
        }
    }
    rays(
        "S21",
        "box, near-parallel d = (1e-9…1e-45, 0, 1)",
        Primitive::Box,
        Kind::Classify,
        q,
    )
}

pub(super) fn box_flat(rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for _ in 0..n {
        // A zero-thickness box (the quad z = 0.25), oblique rays through its interior.
        let (lo, hi) = ([-1.0, -1.0, 0.25], [1.0, 1.0, 0.25]);
        let target = [rng.range(-0.9, 0.9), rng.range(-0.9, 0.9), 0.25];
        let o = v32(add(
            target,
            scale(add([0.0, 0.0, -1.0], scale(rng.unit(), 0.7)), 3.0),
        ));
        q.push(query(Geometry::Aabb { lo, hi }, o, v32(sub(target, o))));
    }
    rays(
        "S22",
        "zero-thickness box, oblique rays",
        Primitive::Box,
        Kind::Classify,
        q,
    )
}
