//! Stiff cases of the ray–plane test.

use super::*;

pub(super) fn plane_parallel(rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for k in 0..n {
        // y = c, direction with d_y = +0 or −0, origin on the plane or 1 above: a miss, never NaN.
        let c = if k % 2 == 0 { 0.0 } else { 1.0 };
        let dy = if (k / 2) % 2 == 0 { 0.0 } else { -0.0 };
        let oy = if (k / 4) % 2 == 0 { c } else { c + 1.0 };
        let o = [r32(rng.range(-5.0, 5.0)), oy, r32(rng.range(-5.0, 5.0))];
        let d = [r32(rng.range(-1.0, 1.0)), dy, 1.0];
        q.push(query(
            Geometry::Plane {
                normal: [0.0, 1.0, 0.0],
                offset: c,
                axis: Some(1),
            },
            o,
            d,
        ));
    }
    rays(
        "S9",
        "ray parallel to a plane, d·n = ±0",
        Primitive::Plane,
        Kind::Classify,
        q,
    )
}

pub(super) fn plane_grazing(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for slope in pick(opts, &[1e-7, 1e-20, 1e-40]) {
        for _ in 0..n {
            // Origin 0.5…2 above y = 0, falling at `slope`: t ≈ h/slope, beyond f32's range at
            // 1e-40 (then a clean miss is the right f32 answer).
            let o = [0.0, r32(rng.range(0.5, 2.0)), 0.0];
            let d = [
                1.0,
                r32(-slope * rng.range(1.0, 2.0)),
                r32(rng.range(-0.5, 0.5)),
            ];
            q.push(query(
                Geometry::Plane {
                    normal: [0.0, 1.0, 0.0],
                    offset: 0.0,
                    axis: Some(1),
                },
                o,
                d,
            ));
        }
    }
    rays(
        "S10",
        "grazing slopes 1e-7, 1e-20, 1e-40",
        Primitive::Plane,
        Kind::Classify,
        q,
    )
}

pub(super) fn plane_far(rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    let p = [1e6, 1e6, 1e6];
    for k in 0..n {
        if k % 2 == 0 {
            // General plane through (1e6, 1e6, 1e6) with a tilted normal, origin 1e-3 above
            // (not representable in f32 at 1e6: f32 gets its own reference).
            let nrm = v32(rng.unit());
            let offset = r32(dot(p, nrm));
            let o = add(add(p, scale(nrm, 1e-3)), scale(rng.unit(), 1e-3));
            let mut d = rng.unit();
            if dot(d, nrm) > 0.0 {
                d = scale(d, -1.0);
            }
            q.push(query(
                Geometry::Plane {
                    normal: nrm,
                    offset,
                    axis: None,
                },
                o,
                v32(d),
            ));
        } else {
            // The axis-aligned plane y = 1e6, origin 1e-3 above.
            let o = [rng.range(-1.0, 1.0), 1e6 + 1e-3, rng.range(-1.0, 1.0)];
            let d = [
                rng.range(-1.0, 1.0),
                -rng.range(0.05, 1.0),
                rng.range(-1.0, 1.0),
            ];
            q.push(query(
                Geometry::Plane {
                    normal: [0.0, 1.0, 0.0],
                    offset: 1e6,
                    axis: Some(1),
                },
                o,
                v32(d),
            ));
        }
    }
    rays(
        "S11",
        "plane through (1e6,1e6,1e6), origin 1e-3 above",
        Primitive::Plane,
        Kind::Classify,
        q,
    )
}
