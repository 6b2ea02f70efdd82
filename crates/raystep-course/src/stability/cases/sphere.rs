//! Stiff cases of the ray–sphere test.

use super::*;

pub(super) fn far_sphere(
    id: &'static str,
    title: &'static str,
    opts: &Options,
    rng: &mut Rng,
    n: usize,
    distances: &[f64],
) -> Case {
    let mut q = vec![];
    for dist in pick(opts, distances) {
        for _ in 0..n {
            // Orthographic rays along w across a unit sphere `dist` away: origins spread over
            // ±1.3 radii, so about half the rays hit.
            let w = rng.unit();
            let (e1, e2) = basis(w);
            let center = v32(scale(w, dist));
            let o = v32(add(
                scale(e1, rng.range(-1.3, 1.3)),
                scale(e2, rng.range(-1.3, 1.3)),
            ));
            q.push(query(
                Geometry::Sphere {
                    center,
                    radius: 1.0,
                },
                o,
                v32(w),
            ));
        }
    }
    rays(id, title, Primitive::Sphere, Kind::Classify, q)
}

pub(super) fn ground_sphere(
    id: &'static str,
    title: &'static str,
    opts: &Options,
    rng: &mut Rng,
    n: usize,
    sizes: &[(f64, f64)],
) -> Case {
    let mut q = vec![];
    for (big_r, h) in pick(opts, sizes) {
        for _ in 0..n {
            // The sphere's top is at y = 0, the origin h above it; rays go downward at slopes
            // from steep to grazing. Inputs are not rounded to f32 here: f32 rounds h away at
            // the floor (S4), and gets its own reference.
            let center = [0.0, -big_r, 0.0];
            let o = [rng.range(-0.5, 0.5) * h, h, rng.range(-0.5, 0.5) * h];
            let d = [
                rng.range(-1.0, 1.0),
                -rng.range(0.02, 1.0),
                rng.range(-1.0, 1.0),
            ];
            q.push(query(
                Geometry::Sphere {
                    center,
                    radius: big_r,
                },
                o,
                d,
            ));
        }
    }
    rays(id, title, Primitive::Sphere, Kind::Classify, q)
}

pub(super) fn on_sphere(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    // Points exactly on spheres: Pythagorean quadruples (3,4,0)/5, (1,2,2)/3, (2,3,6)/7 scaled by
    // powers of two, around integer centres: f·f − r² is exactly 0.
    let triples: [([f64; 3], f64); 3] =
        [([3., 4., 0.], 5.), ([1., 2., 2.], 3.), ([2., 3., 6.], 7.)];
    let mut q = vec![];
    for k in pick(opts, &[-10, 0, 10, 20]) {
        let s = 2f64.powi(k);
        for _ in 0..n {
            let (p, r) = triples[rng.int(0, 2) as usize];
            let mut p = p;
            for c in p.iter_mut() {
                if rng.f() < 0.5 {
                    *c = -*c;
                }
            }
            let rot = rng.int(0, 2) as usize;
            p.rotate_left(rot);
            let center = scale(rng.ints(-100, 100), s);
            let o = add(center, scale(p, s));
            q.push(query(
                Geometry::Sphere {
                    center,
                    radius: r * s,
                },
                o,
                v32(rng.unit()),
            ));
        }
    }
    rays(
        "S5",
        "origin exactly on the surface",
        Primitive::Sphere,
        Kind::Classify,
        q,
    )
}

pub(super) fn tangent_sphere(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for delta in pick(opts, &[1e-3, 1e-6, 1e-9]) {
        for _ in 0..n {
            // Rays passing at ρ = r(1 ± δ) from the centre.
            let center = v32(scale(rng.unit(), rng.range(0.0, 10.0)));
            let r = r32(rng.range(0.5, 2.0));
            let w = rng.unit();
            let (e1, _) = basis(w);
            let rho = r * (1.0 + if rng.f() < 0.5 { delta } else { -delta });
            let o = v32(add(center, add(scale(w, -5.0 * r), scale(e1, rho))));
            q.push(query(Geometry::Sphere { center, radius: r }, o, v32(w)));
        }
    }
    for _ in 0..n / 4 + 1 {
        // The origin at the tangent point, the direction tangent: q = 0 (0/0 in c/q).
        let mut o = [0.0, 0.0, 0.0];
        let axis = rng.int(0, 2) as usize;
        o[axis] = if rng.f() < 0.5 { 1.0 } else { -1.0 };
        let mut d = v32(rng.unit());
        d[axis] = 0.0;
        if d == [0.0; 3] {
            d[(axis + 1) % 3] = 1.0;
        }
        q.push(query(
            Geometry::Sphere {
                center: [0.0; 3],
                radius: 1.0,
            },
            o,
            d,
        ));
    }
    rays(
        "S6",
        "tangent rays ρ = r(1 ± δ), δ 1e-3…1e-9; q = 0",
        Primitive::Sphere,
        Kind::Classify,
        q,
    )
}

pub(super) fn inside_sphere(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    // Origin just inside a glass sphere (depth ε·r), rays at the critical angle of glass
    // (n = 1.5: 41.81°) to the normal, ±1°: the exit root, never the entry one.
    let mut q = vec![];
    for eps in pick(opts, &[1e-2, 1e-4, 1e-6]) {
        for _ in 0..n {
            let center = v32(scale(rng.unit(), rng.range(0.0, 10.0)));
            let r = r32(rng.range(0.5, 2.0));
            let nrm = rng.unit();
            let (t1, _) = basis(nrm);
            let theta = (41.81 + rng.range(-1.0, 1.0)).to_radians();
            let d = add(scale(nrm, theta.cos()), scale(t1, theta.sin()));
            let o = v32(add(center, scale(nrm, r * (1.0 - eps))));
            q.push(query(Geometry::Sphere { center, radius: r }, o, v32(d)));
        }
    }
    rays(
        "S8",
        "origin inside, rays at the critical angle",
        Primitive::Sphere,
        Kind::Classify,
        q,
    )
}
