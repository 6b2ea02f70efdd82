//! Stiff cases of the ray–triangle tests: leaks at shared edges and vertices, slopes, degenerate, tiny and needle triangles.

use super::*;

/// Rounds each component of `v` to 11 significant bits (the mantissa of an f16; the exponent
/// range is not modelled): the lossy edge storage of compressed BVH triangles (docs/NUMERICS.md S24).
pub(super) fn f16ish(v: [f64; 3]) -> [f64; 3] {
    v.map(|x| {
        if x == 0.0 {
            return 0.0;
        }
        let e = x.abs().log2().floor();
        let step = 2f64.powf(e - 10.0);
        (x / step).round() * step
    })
}

/// Stores a triangle as P0 plus f16 edges (each triangle relative to its own first vertex, so
/// shared vertices no longer agree).
pub(super) fn compress(t: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    [
        t[0],
        add(t[0], f16ish(sub(t[1], t[0]))),
        add(t[0], f16ish(sub(t[2], t[0]))),
    ]
}

/// A random f32 vector in [−1, 1)³.
pub(super) fn rvec(rng: &mut Rng) -> Vec3 {
    Vec3::new(
        rng.range(-1.0, 1.0) as f32,
        rng.range(-1.0, 1.0) as f32,
        rng.range(-1.0, 1.0) as f32,
    )
}

pub(super) fn f64x3(v: Vec3) -> [f64; 3] {
    [v.x as f64, v.y as f64, v.z as f64]
}

#[allow(clippy::too_many_arguments)]
pub(super) fn edge_leaks(
    id: &'static str,
    title: &'static str,
    opts: &Options,
    rng: &mut Rng,
    n: usize,
    scales: &[(f64, f64)],
    compressed: bool,
) -> Case {
    let mut q = vec![];
    for (base, s) in pick(opts, scales) {
        let base = Vec3::new(base as f32, (base * 0.75) as f32, (base * 0.5) as f32);
        let s = s as f32;
        for _ in 0..n {
            // As in crates/raystep-core/tests/it/stiff.rs (and docs/NUMERICS.md's measurement): triangles (A, B, C1) and
            // (B, A, C2) share the edge A–B; the ray is aimed at A + r(B − A), computed in f32 —
            // on the edge up to that rounding, so the exact reference always hits at least one
            // of the two, and a ray that hits neither is a leak.
            let a = base + rvec(rng) * s;
            let b = base + rvec(rng) * s;
            let e = b - a;
            let side = e.cross(rvec(rng));
            if e == Vec3::ZERO || side.length() == 0.0 {
                continue;
            }
            let mid = (a + b) * 0.5;
            let side = side.normalize() * s;
            let (c1, c2) = (mid + side, mid - side);
            let target = a + e * rng.f() as f32;
            let normal = e.cross(c1 - a).normalize();
            let sign = if rng.f() < 0.5 { 1.0 } else { -1.0 };
            let origin = target + (normal * (2.0 * sign) + rvec(rng) * 0.5) * s;
            let d = target - origin;
            let mut tris = vec![
                [f64x3(a), f64x3(b), f64x3(c1)],
                [f64x3(b), f64x3(a), f64x3(c2)],
            ];
            if compressed {
                tris = tris.into_iter().map(compress).collect();
            }
            q.push(query(Geometry::Triangles(tris), f64x3(origin), f64x3(d)));
        }
    }
    let kind = if compressed { Kind::Crack } else { Kind::Leak };
    rays(id, title, Primitive::Triangle, kind, q)
}

pub(super) fn vertex_leaks(
    id: &'static str,
    title: &'static str,
    opts: &Options,
    rng: &mut Rng,
    n: usize,
    compressed: bool,
) -> Case {
    let mut q = vec![];
    let scales: &[f32] = if compressed {
        &[1.0]
    } else {
        &[1e-3, 1.0, 1e3, 1e5]
    };
    for s in pick(opts, scales) {
        for _ in 0..n {
            // A fan of 6 triangles around V (as in crates/raystep-core/tests/it/stiff.rs); rays aimed at V.
            let v = rvec(rng) * s;
            let nrm = rvec(rng);
            if nrm.length() < 1e-3 {
                continue;
            }
            let nrm = nrm.normalize();
            let t1 = nrm.any_orthonormal_vector();
            let t2 = nrm.cross(t1);
            let rim: Vec<Vec3> = (0..6)
                .map(|k| {
                    let ang = k as f32 * std::f32::consts::TAU / 6.0;
                    v + (t1 * ang.cos() + t2 * ang.sin()) * s
                })
                .collect();
            let sign = if rng.f() < 0.5 { 1.0 } else { -1.0 };
            let origin = v + (nrm * (2.0 * sign) + rvec(rng) * 0.5) * s;
            let mut tris: Vec<[[f64; 3]; 3]> = (0..6)
                .map(|k| [f64x3(v), f64x3(rim[k]), f64x3(rim[(k + 1) % 6])])
                .collect();
            if compressed {
                tris = tris.into_iter().map(compress).collect();
            }
            q.push(query(
                Geometry::Triangles(tris),
                f64x3(origin),
                f64x3(v - origin),
            ));
        }
    }
    let kind = if compressed { Kind::Crack } else { Kind::Leak };
    rays(id, title, Primitive::Triangle, kind, q)
}

pub(super) fn triangle_slopes(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    let tri = [[-1.0, -1.0, 0.0], [2.0, -1.0, 0.0], [-1.0, 2.0, 0.0]];
    let mut q = vec![];
    for slope in pick(opts, &[1e-3, 1e-6, 1e-9, 0.0]) {
        for _ in 0..n {
            // Rays at `slope` to the plane z = 0 aimed at an interior point; slope 0: in the plane.
            let p = [rng.range(-0.5, 0.5), rng.range(-0.5, 0.5), 0.0];
            let phi = rng.range(0.0, std::f64::consts::TAU);
            let len = 3.0;
            let o = v32([p[0] - len * phi.cos(), p[1] - len * phi.sin(), len * slope]);
            let d = v32(sub(p, o));
            q.push(query(Geometry::Triangles(vec![tri]), o, d));
        }
    }
    rays(
        "S14",
        "rays at slopes 1e-3…1e-9 to the plane; in-plane",
        Primitive::Triangle,
        Kind::Classify,
        q,
    )
}

pub(super) fn triangle_degenerate(rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for at in [1.0, 1e7] {
        for k in 0..n {
            let a = v32(add([at, at, at], rng.ints(-4, 4)));
            let b = v32(add(a, rng.ints(-4, 4)));
            let tri = match k % 3 {
                0 => [a, b, v32(add(a, scale(sub(b, a), 2.0)))],
                1 => [a, a, b],
                _ => [a, a, a],
            };
            let o = v32(add(a, scale(rng.unit(), 10.0)));
            let target = add(a, scale(sub(b, a), rng.range(0.0, 1.0)));
            q.push(query(
                Geometry::Triangles(vec![tri]),
                o,
                v32(sub(target, o)),
            ));
        }
    }
    rays(
        "S15",
        "degenerate triangles (collinear, repeated vertices), at 1 and 1e7",
        Primitive::Triangle,
        Kind::Classify,
        q,
    )
}

pub(super) fn triangle_tiny(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for s in pick(opts, &[1e-3, 1e-8, 1e-15, 1e-25]) {
        for _ in 0..n {
            // A triangle of edge ≈ s near the origin, seen from distance 1 along z, aimed at an
            // interior point.
            let p = [
                v32([0.0, 0.0, 0.0]),
                v32([s * rng.range(0.5, 1.0), 0.0, 0.0]),
                v32([s * rng.range(-0.2, 0.2), s * rng.range(0.5, 1.0), 0.0]),
            ];
            let (b1, b2) = (rng.range(0.05, 0.45), rng.range(0.05, 0.45));
            let target = add(scale(sub(p[1], p[0]), b1), scale(sub(p[2], p[0]), b2));
            let o = v32([rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), -1.0]);
            q.push(query(Geometry::Triangles(vec![p]), o, v32(sub(target, o))));
        }
    }
    rays(
        "S16",
        "tiny triangles, edges 1e-3…1e-25",
        Primitive::Triangle,
        Kind::Classify,
        q,
    )
}

pub(super) fn triangle_needle(rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for _ in 0..n {
        // Aspect 1e6: length 1, width 1e-6, randomly oriented; rays aimed at its bounding box.
        let w = rng.unit();
        let (e1, e2) = basis(w);
        let c = scale(rng.unit(), 2.0);
        let p = [
            v32(c),
            v32(add(c, e1)),
            v32(add(c, add(scale(e1, 0.5), scale(e2, 1e-6)))),
        ];
        let target = add(
            c,
            add(
                scale(e1, rng.range(0.0, 1.0)),
                scale(e2, rng.range(-0.5e-6, 1.5e-6)),
            ),
        );
        let o = v32(add(target, scale(add(w, scale(rng.unit(), 0.5)), 3.0)));
        q.push(query(Geometry::Triangles(vec![p]), o, v32(sub(target, o))));
    }
    rays(
        "S17",
        "needle triangles (aspect 1e6)",
        Primitive::Triangle,
        Kind::Classify,
        q,
    )
}
