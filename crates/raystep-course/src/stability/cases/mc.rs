//! Generators of the Monte Carlo stiff cases S26–S29 (every input rounded to f32, so that the
//! f32 and f64 rows see the same inputs and share one exact reference).

use super::*;
use crate::stability::mc::{GgxInput, GrazingInput, McCase, McData};

/// A uniform number in (0, 1) exact in f32, never 0 (whose sample is exactly on the axis).
fn uniform(rng: &mut Rng) -> f64 {
    loop {
        let u = r32(rng.f());
        if u > 0.0 && u < 1.0 {
            return u;
        }
    }
}

/// S26: sphere lights subtending 1e-2 … 1e-8 sr, at distances 1 … 1e4.
pub(super) fn sphere_lights(opts: &Options, rng: &mut Rng, n: usize) -> McCase {
    let mut v = vec![];
    for omega in pick(opts, &[1e-2, 1e-4, 1e-6, 1e-8]) {
        for _ in 0..n {
            // Ω = 2π(1 − cos θmax) ≈ π r²/d² for a small cone.
            let d = r32(10f64.powf(rng.range(0.0, 4.0)));
            let r = r32(d * (omega / std::f64::consts::PI).sqrt() * rng.range(0.8, 1.25));
            v.push([d, r, uniform(rng)]);
        }
    }
    McCase {
        id: "S26",
        title: "sphere light cone, solid angle 1e-2…1e-8 sr",
        f64_rows: true,
        data: McData::Cone(v),
    }
}

/// S27: GGX half vectors at roughness 0.05 … 0.001 (α = roughness²), seen from directions at
/// least 11.5° above the horizon.
pub(super) fn ggx_near_mirror(opts: &Options, rng: &mut Rng, n: usize) -> McCase {
    let mut v = vec![];
    for rough in pick(opts, &[0.05, 0.02, 0.01, 0.005, 0.001]) {
        for _ in 0..n {
            let phi = rng.range(0.0, std::f64::consts::TAU);
            let wo = loop {
                let w = rng.unit();
                let w = [w[0], w[1], w[2].abs()];
                if w[2] >= 0.2 {
                    break v32(w);
                }
            };
            v.push(GgxInput {
                alpha: r32(rough * rough),
                u: uniform(rng),
                cphi: r32(phi.cos()),
                sphi: r32(phi.sin()),
                wo,
            });
        }
    }
    McCase {
        id: "S27",
        title: "near-mirror GGX, roughness 0.05…0.001",
        f64_rows: true,
        data: McData::Ggx(v),
    }
}

/// A unit direction at cos θ within a factor 2 of `cos` to `n` (after rounding to f32, which moves
/// cos θ by about 1e-7: the generator retries until the rounded vector is in range), on the side
/// of `n` that `sign` says, of length `scale_to`.
fn grazing_dir(rng: &mut Rng, n: [f64; 3], cos: f64, sign: f64, scale_to: f64) -> [f64; 3] {
    let (e1, e2) = basis(n);
    for _ in 0..10_000 {
        let a = rng.range(0.0, std::f64::consts::TAU);
        let t = add(scale(e1, a.cos()), scale(e2, a.sin()));
        let c = cos * rng.range(0.8, 1.25);
        let w = v32(scale(
            add(scale(n, sign * c), scale(t, (1.0 - c * c).sqrt())),
            scale_to,
        ));
        // f32 inputs: their products are exact in f64, the sum good to 1e-16 of |w|.
        let got = sign * dot(w, n) / dot(w, w).sqrt();
        if got >= 0.5 * cos && got <= 2.0 * cos {
            return w;
        }
    }
    // Unreachable in practice (about half the tries succeed at cos θ = 1e-7).
    v32(scale(add(scale(n, sign * cos), e1), scale_to))
}

/// S28: directions at cos θ = 1e-4 … 1e-7 to the normal: the cosine-hemisphere pdf of one, and a
/// light point on a triangle seen as nearly edge-on (cos θl alike), 1 … 100 away; and
/// cosine-weighted directions sampled as near the horizon as an f32 u allows.
pub(super) fn grazing(opts: &Options, rng: &mut Rng, n: usize) -> McCase {
    let mut v = vec![];
    for cos in pick(opts, &[1e-4, 1e-5, 1e-6, 1e-7]) {
        for _ in 0..n {
            let nrm = v32(rng.unit());
            let w = grazing_dir(rng, nrm, cos, 1.0, 1.0);
            let dist = rng.range(1.0, 100.0);
            let d = grazing_dir(rng, nrm, cos, -1.0, dist);
            // A disk point k·2⁻²³ from the rim, k = 1 … 1023 (log-uniform): the sampled
            // cos θ is about √(k·2⁻²²) = 2⁻¹¹√k, 4.9e-4 … 1.6e-2. An f32 u reaches hardly
            // closer to the horizon: 3.5e-4 at u = 2⁻²⁵, then 0.
            let k = 2f64.powf(rng.range(0.0, 10.0)).floor();
            let rim = k * 2f64.powi(-24);
            let rim = if rng.f() < 0.5 { rim } else { 1.0 - rim };
            let other = r32(rng.range(0.25, 0.75));
            let u = if rng.f() < 0.5 {
                [rim, other]
            } else {
                [other, rim]
            };
            v.push(GrazingInput {
                w,
                n: nrm,
                d,
                area: r32(rng.range(0.1, 10.0)),
                u,
            });
        }
    }
    McCase {
        id: "S28",
        title: "grazing directions, cos θ 1e-4…1e-7",
        f64_rows: true,
        data: McData::Grazing(v),
    }
}

/// S29: emitting triangles with edges 1e-13 … 1e-6 near the origin, and with vertices at corners
/// of the cubes ±1e9 and ±1e10 (f32: the squared length of the cross product underflows, or
/// overflows).
pub(super) fn emitter_areas(opts: &Options, rng: &mut Rng, n: usize) -> McCase {
    // (size, huge): tiny triangles have edges `size` near the origin; huge ones have their
    // vertices at corners of the cube ±size.
    let scales = [
        (1e-13, false),
        (1e-10, false),
        (1e-6, false),
        (1e9, true),
        (1e10, true),
    ];
    let mut v = vec![];
    for (size, huge) in pick(opts, &scales) {
        let mut k = 0;
        while k < n {
            let p: [[f64; 3]; 3] = if huge {
                // Three distinct corners of the cube [−size, size]³, each coordinate jittered
                // by ±10%: the cross product's length is at least about 2.6·size².
                let corners = loop {
                    let c = [rng.int(0, 7), rng.int(0, 7), rng.int(0, 7)];
                    if c[0] != c[1] && c[1] != c[2] && c[0] != c[2] {
                        break c;
                    }
                };
                corners.map(|c| {
                    v32(std::array::from_fn(|k| {
                        let s = if (c >> k) & 1 == 1 { 1.0 } else { -1.0 };
                        s * size * rng.range(0.9, 1.1)
                    }))
                })
            } else {
                let p0 = v32(scale(
                    [
                        rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                    ],
                    size,
                ));
                let e1 = scale(rng.unit(), size * rng.range(0.5, 1.0));
                let e2 = scale(rng.unit(), size * rng.range(0.5, 1.0));
                [p0, v32(add(p0, e1)), v32(add(p0, e2))]
            };
            // Skip (near-)degenerate triangles: not this case's subject.
            let c = cross(sub(p[1], p[0]), sub(p[2], p[0]));
            let e =
                dot(sub(p[1], p[0]), sub(p[1], p[0])).max(dot(sub(p[2], p[0]), sub(p[2], p[0])));
            if dot(c, c) > 1e-4 * e * e {
                v.push(p);
                k += 1;
            }
        }
    }
    McCase {
        id: "S29",
        title: "huge and tiny emitting triangles (area)",
        f64_rows: false,
        data: McData::Area(v),
    }
}
