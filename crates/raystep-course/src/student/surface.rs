//! The `surface` stage: a student's shading normal, texture coordinates, texel and texture colour
//! against raystep's, with the classic mistakes of lessons 17–19 named — a flat normal where
//! the vertex normals should blend, the blend's weights on the wrong vertices, v flipped, texel
//! centres off by half, an image's sRGB values used as linear.

use super::compare::{Divergence, TracerTolerances, dist, len, n, unit, v};
use super::expected::{Expected, ImageRead, Misread, SurfaceFacts, to_srgb};
use super::format::Pixel;
use super::stage::{Stage, in_scope, ray_name};
use crate::scene::{Filter, Wrap};

fn v2(x: [f64; 2]) -> String {
    format!("({}, {})", n(x[0]), n(x[1]))
}

fn i2(x: [i64; 2]) -> String {
    format!("({}, {})", x[0], x[1])
}

/// The first place the student's `surface` records differ from raystep's, in words.
pub(super) fn surface(
    e: &Expected,
    s: &Pixel,
    m: &[Option<usize>],
    upto: Stage,
    tol: &TracerTolerances,
) -> Divergence {
    for (i, er) in e.pixel.rays.iter().enumerate() {
        let Some(es) = &er.surface else { continue };
        if !in_scope(&er.kind, upto) {
            continue;
        }
        let Some(sr) = m.get(i).copied().flatten().and_then(|k| s.rays.get(k)) else {
            continue;
        };
        let Some(ss) = &sr.surface else { continue };
        let step = e
            .surface_step
            .get(i)
            .copied()
            .flatten()
            .or(e.ray_step.get(i).copied());
        let facts = e.surfaces.get(i).cloned().unwrap_or_default();
        let name = ray_name(&e.pixel, i);
        let tol = &tol.at_depth(er.depth);
        if let (Some(y), Some(w)) = (ss.normal, es.normal)
            && !tol.close3(y, w, tol.abs * 10.0)
        {
            return Some((
                format!(
                    "{name}: your shading normal is {}, raystep's is {}{}",
                    v(y),
                    v(w),
                    normal_hint(y, &facts, tol)
                ),
                step,
            ));
        }
        if let (Some(y), Some(w)) = (ss.uv, es.uv)
            && !uv_close(y, w, tol)
        {
            return Some((
                format!(
                    "{name}: your texture coordinates (u, v) are {}, raystep's are {}{}",
                    v2(y),
                    v2(w),
                    uv_hint(y, w, &facts, tol)
                ),
                step,
            ));
        }
        if let (Some(y), Some(w)) = (ss.texel, es.texel)
            && y != w
            && !texel_allowed(y, w, es.uv, &facts, tol)
        {
            let what = if facts.checker.is_some() {
                "checker square"
            } else {
                "texel (column, row)"
            };
            return Some((
                format!(
                    "{name}: your {what} is {}, raystep's is {}{}",
                    i2(y),
                    i2(w),
                    texel_hint(y, w, &facts)
                ),
                step,
            ));
        }
        if let (Some(y), Some(w)) = (ss.texture, es.texture)
            && !(0..3).all(|k| (y[k] - w[k]).abs() <= tol.color)
        {
            return Some((
                format!(
                    "{name}: your texture colour is {}, raystep's is {} (linear RGB){}",
                    v(y),
                    v(w),
                    color_hint(y, w, &facts, tol)
                ),
                step,
            ));
        }
    }
    None
}

fn uv_close(y: [f64; 2], w: [f64; 2], tol: &TracerTolerances) -> bool {
    tol.close(y[0], w[0]) && tol.close(y[1], w[1])
}

/// The three barycentric weights (1 − u − v, u, v) in every order but the right one.
fn wrong_orders(b: [f64; 2]) -> [[f64; 3]; 5] {
    let (w0, w1, w2) = (1.0 - b[0] - b[1], b[0], b[1]);
    [
        [w0, w2, w1],
        [w1, w0, w2],
        [w1, w2, w0],
        [w2, w0, w1],
        [w2, w1, w0],
    ]
}

const WEIGHTS: &str = "the weights are (1 − u − v, u, v) on (P0, P1, P2): u is the weight of the second vertex, v of the third (lesson 4)";

/// Why a shading normal may be off: not normalized, on the wrong side, flat, or blended with the
/// weights on the wrong vertices.
fn normal_hint(y: [f64; 3], f: &SurfaceFacts, tol: &TracerTolerances) -> String {
    let abs = tol.abs * 10.0;
    let l = len(y);
    let Some(ns) = f.vertex_normals else {
        return String::new();
    };
    // raystep's normal, to compare each candidate with.
    let want = |c: [f64; 3]| -> Option<[f64; 3]> {
        let g = f.geometric?;
        let u = unit(c);
        Some(if super::compare::dot(u, g) < 0.0 {
            u.map(|x| -x)
        } else {
            u
        })
    };
    if (l - 1.0).abs() > 1e-3 && l > 0.0 {
        let yu = unit(y);
        if let Some(b) = f.barycentric {
            let blend = blend3(ns, [1.0 - b[0] - b[1], b[0], b[1]]);
            if want(blend).is_some_and(|w| tol.close3(yu, w, abs)) {
                return format!(
                    " — your normal has length {}: normalize the blend (a blend of unit vectors is shorter than 1)",
                    n(l)
                );
            }
        }
    }
    if let Some(g) = f.geometric
        && tol.close3(y, g, abs)
    {
        return " — that is the triangle's flat (geometric) normal: blend its vertex normals with the hit's barycentrics, (1 − u − v)·n₀ + u·n₁ + v·n₂, and normalize".into();
    }
    if let Some(b) = f.barycentric {
        let right = blend3(ns, [1.0 - b[0] - b[1], b[0], b[1]]);
        if let Some(w) = want(right)
            && tol.close3(y.map(|x| -x), w, abs)
        {
            return " — it points away from the ray: turn the blended normal to the side the ray came from (the side of the geometric normal)".into();
        }
        for ws in wrong_orders(b) {
            let c = unit(blend3(ns, ws));
            if tol.close3(y, c, abs) || tol.close3(y.map(|x| -x), c, abs) {
                return format!(" — {WEIGHTS}");
            }
        }
    }
    String::new()
}

fn blend3(ns: [[f64; 3]; 3], w: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|k| w[0] * ns[0][k] + w[1] * ns[1][k] + w[2] * ns[2][k])
}

/// Why (u, v) may be off: v flipped, the barycentrics where the vertices' coordinates should
/// blend, or the weights on the wrong vertices.
fn uv_hint(y: [f64; 2], w: [f64; 2], f: &SurfaceFacts, tol: &TracerTolerances) -> String {
    if tol.close(y[0], w[0]) && tol.close(y[1], 1.0 - w[1]) {
        return " — your v is 1 − v: v runs up the texture here; an image's row is flipped only when the texel is found, y = (1 − v)·h".into();
    }
    let (Some(b), Some(ts)) = (f.barycentric, f.vertex_uvs) else {
        return String::new();
    };
    if uv_close(y, b, tol) {
        return " — those are the hit's barycentrics: blend the vertices' texture coordinates with them, (1 − u − v)·t₀ + u·t₁ + v·t₂".into();
    }
    for ws in wrong_orders(b) {
        let c: [f64; 2] =
            std::array::from_fn(|k| ws[0] * ts[0][k] + ws[1] * ts[1][k] + ws[2] * ts[2][k]);
        if uv_close(y, c, tol) {
            return format!(" — {WEIGHTS}");
        }
    }
    String::new()
}

/// An index past the edge of a level of `size` texels, as the wrap mode reads it: repeat wraps to
/// the other edge, clamp and mirror keep the edge texel (raystep's `wrap_index`, in f64).
fn wrap_index(wrap: Wrap, i: f64, size: u32) -> i64 {
    let last = i64::from(size.max(1)) - 1;
    let i = i.floor() as i64;
    match wrap {
        Wrap::Repeat => i.rem_euclid(last + 1),
        Wrap::Clamp | Wrap::Mirror => i.clamp(0, last),
    }
}

/// The texel (column, row) an image read would start from at (x, y) in texel units: the texel
/// the point falls in (nearest), or the first of the four around it (bilinear, trilinear).
fn first_texel(r: &ImageRead, at: [f64; 2]) -> [i64; 2] {
    let half = if r.filter == Filter::Nearest {
        0.0
    } else {
        0.5
    };
    [
        wrap_index(r.wrap, at[0] - half, r.size[0]),
        wrap_index(r.wrap, at[1] - half, r.size[1]),
    ]
}

/// Whether the student's texel differs from raystep's only because the point lies within
/// rounding of a texel's edge (the two tracers round (u, v) differently): each index must be one
/// of those the point gives when moved by the uv tolerance, in texel units.
fn texel_allowed(
    y: [i64; 2],
    w: [i64; 2],
    uv: Option<[f64; 2]>,
    f: &SurfaceFacts,
    tol: &TracerTolerances,
) -> bool {
    let Some(uv) = uv else { return false };
    let slack = |k: usize| tol.abs + tol.rel * uv[k].abs();
    if let Some(r) = &f.image {
        (0..2).all(|k| {
            let d = slack(k) * f64::from(r.size[k]);
            let mut at = r.address;
            [-d, d].iter().any(|&dd| {
                at[k] = r.address[k] + dd;
                first_texel(r, at)[k] == y[k]
            }) || y[k] == w[k]
        })
    } else if let Some(sq) = f.checker {
        (0..2).all(|k| {
            let c = uv[k] * f64::from(sq[k]);
            let d = slack(k) * f64::from(sq[k]);
            y[k] == w[k] || (c - d).floor() as i64 == y[k] || (c + d).floor() as i64 == y[k]
        })
    } else {
        false
    }
}

/// Why an image's texel may be off: v flipped (row 0 is the image's top), or the texel centres
/// off by half.
fn texel_hint(y: [i64; 2], w: [i64; 2], f: &SurfaceFacts) -> String {
    let Some(r) = &f.image else {
        return if f.checker.is_some() {
            " — the square is (⌊u·s₀⌋, ⌊v·s₁⌋), s the checker's squares per unit".into()
        } else {
            String::new()
        };
    };
    let h = f64::from(r.size[1]);
    // Row from v·h (v flipped): the image's row 0 is its top, where v = 1.
    let flipped = first_texel(r, [r.address[0], r.wrapped[1] * h]);
    if y[1] != w[1] && y[1] == flipped[1] && y[0] == flipped[0] {
        return format!(
            " — v is flipped: row 0 is the top of the image, where v = 1, so the point is at y = (1 − v)·h = {}, not v·h",
            n(r.address[1])
        );
    }
    let bilinear = r.filter != Filter::Nearest;
    let off = if bilinear { 0.0 } else { 0.5 };
    let shifted = [
        wrap_index(r.wrap, r.address[0] - off, r.size[0]),
        wrap_index(r.wrap, r.address[1] - off, r.size[1]),
    ];
    let other_way = [
        wrap_index(r.wrap, r.address[0] + 0.5, r.size[0]),
        wrap_index(r.wrap, r.address[1] + 0.5, r.size[1]),
    ];
    let half_off = |c: [i64; 2]| (0..2).all(|k| y[k] == c[k] || y[k] == w[k]) && y != w;
    if bilinear && (half_off(shifted) || half_off(other_way)) {
        return format!(
            " — texel centres are at (i + ½, j + ½): the four texels around the point ({}, {}) start at (⌊x − ½⌋, ⌊y − ½⌋)",
            n(r.address[0]),
            n(r.address[1])
        );
    }
    if !bilinear && (half_off(shifted) || half_off(other_way)) {
        return format!(
            " — texel (i, j) covers [i, i + 1) × [j, j + 1): the point ({}, {}) falls in (⌊x⌋, ⌊y⌋); rounding to the nearest integer puts the texel centres off by half",
            n(r.address[0]),
            n(r.address[1])
        );
    }
    format!(
        " — the point in texel units is (u·w, (1 − v)·h) = ({}, {})",
        n(r.address[0]),
        n(r.address[1])
    )
}

const SRGB: &str = " — that is the image's stored (sRGB) value: decode each texel to linear before filtering, c ≤ 0.04045 ? c/12.92 : ((c + 0.055)/1.055)^2.4 (c in 0 … 1)";

fn color_hint(y: [f64; 3], w: [f64; 3], f: &SurfaceFacts, tol: &TracerTolerances) -> String {
    let near = |c: [f64; 3]| (0..3).all(|k| (y[k] - c[k]).abs() <= tol.color);
    if let Some((m, _)) = f.misreads.iter().find(|(_, c)| near(*c)) {
        return match m {
            Misread::VFlipped => " — that is the colour with v flipped: row 0 is the top of the image, where v = 1, so y = (1 − v)·h",
            Misread::HalfTexel => " — that is bilinear with the texel centres at integers: texel (i, j)'s centre is at (i + ½, j + ½), so the four texels start at (⌊x − ½⌋, ⌊y − ½⌋) and f = (x − ½) − x₀",
            Misread::Nearest => " — that is the nearest texel's colour: this texture is bilinear, the four texels around the point weighted by (1 − f_x)(1 − f_y), f_x(1 − f_y), (1 − f_x)f_y, f_x·f_y",
            Misread::Bilinear => " — that is a bilinear blend: this texture is `nearest`, the colour of the one texel the point falls in",
            Misread::NotDecoded => SRGB,
        }
        .into();
    }
    // A blend of encoded texels is not the encoding of the blend: a looser match.
    let slack = tol.color.max(0.02);
    if (0..3).all(|k| (y[k] - to_srgb(w[k])).abs() <= slack) && dist(y, w) > tol.color {
        return SRGB.into();
    }
    String::new()
}
