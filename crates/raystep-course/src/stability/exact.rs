//! Exact references: every input is a float, so every input is a rational number, and planes,
//! boxes and triangles are solved *exactly* in rationals (`num-rational` over `num-bigint`).
//! Spheres need one square root: its sign question (hit or miss) is answered exactly from the
//! rational discriminant, and the root itself is computed with a big-integer square root to at
//! least 200 bits (docs/NUMERICS.md, "Exact references") — far beyond f64's 53.
//!
//! Each reference also says whether the ray lies in the *rounding band* of its precision: an
//! exact answer so close to a decision boundary (tangency, an edge, t = 0) that rounding the
//! inputs by a few units in the last place could flip it. Outside the band a kernel must agree
//! with the reference; inside, either answer is legitimate (docs/NUMERICS.md: "below the input's own
//! rounding no formula helps"). The band of each primitive is defined next to its reference.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{Signed, ToPrimitive, Zero};

/// A real number as an unevaluated sum hi + lo of two f64 (a "double-double", ≈ 106 bits):
/// enough to measure an f64 result's error to a small fraction of an ulp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dd {
    /// The f64 nearest the value.
    pub hi: f64,
    /// The rest, value − hi, rounded to f64.
    pub lo: f64,
}

impl Dd {
    /// The exact value `x` as a double-double.
    pub fn of(x: &BigRational) -> Dd {
        let hi = to_f64(x);
        let lo = if hi.is_finite() {
            to_f64(&(x - q(hi)))
        } else {
            0.0
        };
        Dd { hi, lo }
    }

    /// |y − self|, computed without losing y's distance to the reference: y − hi is exact when
    /// y is within a factor 2 of hi (Sterbenz), which is where it matters.
    pub fn abs_error(&self, y: f64) -> f64 {
        ((y - self.hi) - self.lo).abs()
    }
}

/// A finite f64 as an exact rational.
pub fn q(x: f64) -> BigRational {
    BigRational::from_float(x).unwrap_or_else(BigRational::zero)
}

/// Rational to f64 (correctly rounded by num-rational; ±∞ beyond the range).
pub fn to_f64(x: &BigRational) -> f64 {
    x.to_f64().unwrap_or(if x.is_negative() {
        f64::NEG_INFINITY
    } else {
        f64::INFINITY
    })
}

type Q3 = [BigRational; 3];

fn q3(v: [f64; 3]) -> Q3 {
    [q(v[0]), q(v[1]), q(v[2])]
}
fn sub(a: &Q3, b: &Q3) -> Q3 {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}
fn dot(a: &Q3, b: &Q3) -> BigRational {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}
fn cross(a: &Q3, b: &Q3) -> Q3 {
    [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ]
}
fn det(a: &Q3, b: &Q3, c: &Q3) -> BigRational {
    dot(a, &cross(b, c))
}
fn neg(a: &Q3) -> Q3 {
    [-&a[0], -&a[1], -&a[2]]
}
fn norm_f64(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}
fn sub_f64(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// √x for a rational x ≥ 0, as a rational with at least 200 correct bits: √(n/m) = √(n·m)/m,
/// and √(n·m) is taken as the integer square root of n·m·4ᵏ, with k chosen so that the integer
/// has ≥ 400 bits (its root ≥ 200).
pub fn sqrt(x: &BigRational) -> BigRational {
    if x.is_zero() {
        return BigRational::zero();
    }
    let nm: BigInt = x.numer() * x.denom();
    let bits = nm.bits();
    let k = if bits >= 400 { 0 } else { (400 - bits) / 2 + 1 };
    let scaled: BigInt = nm << (2 * k as usize);
    let root = scaled.sqrt();
    BigRational::new(root, x.denom() << (k as usize))
}

/// The exact answer for one ray against one sphere, with t_min = 0 and t_max = ∞.
#[derive(Debug, Clone, PartialEq)]
pub struct SphereRef {
    /// Whether a root lies in (0, ∞).
    pub hit: bool,
    /// The root taken (the smaller positive one).
    pub t: Option<Dd>,
    /// The other root, when the line meets the sphere in two points (to detect wrong-root picks).
    pub other: Option<Dd>,
    /// In the rounding band (see [`sphere`]).
    pub band: bool,
}

/// Ray O + t·d against the sphere |X − G| = r, exactly.
///
/// With f = O − G, a = d·d, b′ = −f·d, c = f·f − r²: the reduced discriminant D = b′² − a·c is
/// rational, so hit or miss is exact. The roots use the stable pairing q = b′ + sign(b′)·√D,
/// t = c/q and q/a (so an exactly-zero root, c = 0, stays exactly zero).
///
/// The band, for unit roundoff `u` and S = max(|O|, |G|, |f|):
/// - *tangency*: |Δ′| ≤ 16·u·(S·(r + ρ) + r²), where Δ′ = D/a = r² − ρ² and ρ is the distance
///   from G to the ray's line. Rounding f = O − G moves ρ by about u·S (docs/NUMERICS.md: the stable
///   form keeps r², so its error in ρ is of that order); 16 covers the handful of operations.
/// - *origin near the surface*: 0 < ||f| − r| ≤ u·S — the origin lies within the rounding of
///   f = O − G itself (u·|f| per component) of the surface, so which side it is on, and so
///   which root is the first, is below the input's own rounding (docs/NUMERICS.md S4). An origin
///   exactly on the surface (c = 0, S5) is *not* in the band: that is exact, and the kernel
///   must get it right.
pub fn sphere(center: [f64; 3], radius: f64, o: [f64; 3], d: [f64; 3], u: f64) -> SphereRef {
    let (gq, oq, dq, r) = (q3(center), q3(o), q3(d), q(radius));
    let f = sub(&oq, &gq);
    let a = dot(&dq, &dq);
    let bh = -dot(&f, &dq);
    let c = dot(&f, &f) - &r * &r;
    let disc = &bh * &bh - &a * &c;
    let s_mag = norm_f64(o)
        .max(norm_f64(center))
        .max(norm_f64(sub_f64(o, center)));
    let delta_prime = to_f64(&(&disc / &a));
    let rho = (radius * radius - delta_prime).max(0.0).sqrt();
    let tangency_band =
        delta_prime.abs() <= 16.0 * u * (s_mag * (radius.abs() + rho) + radius * radius);
    if disc.is_negative() {
        return SphereRef {
            hit: false,
            t: None,
            other: None,
            band: tangency_band,
        };
    }
    let root = sqrt(&disc);
    let qq = if bh.is_negative() {
        &bh - &root
    } else {
        &bh + &root
    };
    let (t0, t1) = if qq.is_zero() {
        (BigRational::zero(), BigRational::zero())
    } else {
        (&c / &qq, &qq / &a)
    };
    let (lo, hi) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    // The origin's distance from the surface, |f| − r = c/(|f| + r).
    let fl = norm_f64(sub_f64(o, center));
    let near_surface = !c.is_zero() && to_f64(&c).abs() / (fl + radius.abs()) <= u * s_mag;
    let band = tangency_band || near_surface;
    let zero = BigRational::zero();
    let distinct = lo != hi;
    let (t, other) = if lo > zero {
        (Some(Dd::of(&lo)), distinct.then(|| Dd::of(&hi)))
    } else if hi > zero {
        (Some(Dd::of(&hi)), distinct.then(|| Dd::of(&lo)))
    } else {
        (None, None)
    };
    SphereRef {
        hit: t.is_some(),
        t,
        other,
        band,
    }
}

/// The exact answer for one ray against one triangle (closed: points on an edge belong to it).
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleRef {
    /// Whether the ray meets the closed triangle at t > 0.
    pub hit: bool,
    /// t at the plane (when the plane is not parallel and t > 0).
    pub t: Option<Dd>,
    /// Barycentric u (weight of P1) at the plane.
    pub u: Option<Dd>,
    /// Barycentric v (weight of P2) at the plane.
    pub v: Option<Dd>,
    /// In the rounding band (see [`triangle`]).
    pub band: bool,
    /// Which edges the band comes from: edge i is the one opposite vertex i.
    pub band_edges: [bool; 3],
}

/// Ray O + t·d against the triangle P0 P1 P2, exactly: Cramer's rule in rationals,
/// D0 = det(−d, E1, E2), t = det(T, E1, E2)/D0, u = det(−d, T, E2)/D0, v = det(−d, E1, T)/D0
/// with E1 = P1 − P0, E2 = P2 − P0, T = O − P0. D0 = 0 (degenerate, or the ray parallel to the
/// plane) is a miss.
///
/// The band: barycentric bᵢ (b0 = 1 − u − v, b1 = u, b2 = v) times D0 is the edge function
/// eᵢ = ±d·((Pⱼ − O) × (Pₖ − O)) of the watertight test (Woop et al. 2013): the 2D cross product
/// of the two vertices' positions *across* the ray. Translating by O and shearing along the ray
/// err by about u·(lateral + axial distance) per coordinate (pbrt-v4 §6.8.4 bounds the edge
/// functions from the same terms), so eᵢ is uncertain by a few u times
/// Mᵢ = |d|·(2·lⱼ·lₖ + aⱼ·lₖ + aₖ·lⱼ), with l a vertex's distance from the ray's line and a its
/// distance along it. A ray is in the band when |eᵢ| ≤ 16·u·Mᵢ for some i: within rounding of
/// an edge.
pub fn triangle(p: [[f64; 3]; 3], o: [f64; 3], d: [f64; 3], u: f64) -> TriangleRef {
    let pq = [q3(p[0]), q3(p[1]), q3(p[2])];
    let (oq, dq) = (q3(o), q3(d));
    let e1 = sub(&pq[1], &pq[0]);
    let e2 = sub(&pq[2], &pq[0]);
    let nd = neg(&dq);
    let d0 = det(&nd, &e1, &e2);
    if d0.is_zero() {
        return TriangleRef {
            hit: false,
            t: None,
            u: None,
            v: None,
            band: false,
            band_edges: [false; 3],
        };
    }
    let tv = sub(&oq, &pq[0]);
    let t = det(&tv, &e1, &e2) / &d0;
    let bu = det(&nd, &tv, &e2) / &d0;
    let bv = det(&nd, &e1, &tv) / &d0;
    let b0 = BigRational::from_integer(1.into()) - &bu - &bv;
    let zero = BigRational::zero();
    let hit = t > zero && bu >= zero && bv >= zero && b0 >= zero;
    let dlen = norm_f64(d);
    let dh = [d[0] / dlen, d[1] / dlen, d[2] / dlen];
    // Each vertex relative to the origin: its distance along the ray (axial) and from the ray's
    // line (lateral).
    let (mut axial, mut lateral) = ([0.0; 3], [0.0; 3]);
    for k in 0..3 {
        let w = sub_f64(p[k], o);
        let a = w[0] * dh[0] + w[1] * dh[1] + w[2] * dh[2];
        axial[k] = a.abs();
        lateral[k] = norm_f64(sub_f64(w, [a * dh[0], a * dh[1], a * dh[2]]));
    }
    let d0f = to_f64(&d0).abs();
    let bary = [to_f64(&b0), to_f64(&bu), to_f64(&bv)];
    let band_edges: [bool; 3] = std::array::from_fn(|i| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let m =
            dlen * (2.0 * lateral[j] * lateral[k] + axial[j] * lateral[k] + axial[k] * lateral[j]);
        bary[i].abs() * d0f <= 16.0 * u * m
    });
    let band = band_edges.iter().any(|b| *b);
    let pos = t > zero;
    TriangleRef {
        hit,
        t: pos.then(|| Dd::of(&t)),
        u: pos.then(|| Dd::of(&bu)),
        v: pos.then(|| Dd::of(&bv)),
        band,
        band_edges,
    }
}

/// The exact answer for one ray against one plane.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneRef {
    /// Whether the ray meets the plane at t > 0 (a parallel ray never does).
    pub hit: bool,
    /// t, when hit.
    pub t: Option<Dd>,
    /// In the rounding band (see [`plane`]).
    pub band: bool,
}

/// Ray O + t·d against the plane X·n = c, exactly: t = (c − O·n)/(d·n); d·n = 0 is a miss.
///
/// The band: the origin within rounding of the plane, |c − O·n| ≤ 4·u·(|c| + |O|·|n|) — the
/// numerator's own cancellation (docs/NUMERICS.md S11), where the side the origin is on (and so the
/// sign of t) is below the inputs' rounding.
pub fn plane(normal: [f64; 3], offset: f64, o: [f64; 3], d: [f64; 3], u: f64) -> PlaneRef {
    let (nq, oq, dq) = (q3(normal), q3(o), q3(d));
    let den = dot(&dq, &nq);
    let num = q(offset) - dot(&oq, &nq);
    let band = to_f64(&num).abs() <= 4.0 * u * (offset.abs() + norm_f64(o) * norm_f64(normal));
    if den.is_zero() {
        return PlaneRef {
            hit: false,
            t: None,
            band: false,
        };
    }
    let t = num / den;
    let hit = t > BigRational::zero();
    PlaneRef {
        hit,
        t: hit.then(|| Dd::of(&t)),
        band,
    }
}

/// The exact answer for one ray against one closed box.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxRef {
    /// Whether [t_near, t_far] is non-empty (closed box, t ≥ 0).
    pub hit: bool,
    /// t_near = max(0, slab entries), when hit.
    pub t: Option<Dd>,
    /// In the rounding band (see [`aabb`]).
    pub band: bool,
}

/// Ray O + t·d against the closed box [lo, hi], exactly. A zero direction component makes that
/// slab all-or-nothing: the ray is inside it iff lo ≤ O ≤ hi (the documented ±0 policy of S20,
/// independent of the zero's sign).
///
/// The band: 0 < |t_far − t_near| ≤ 8·u·max(|t_near|, |t_far|) — a ray grazing an edge or a
/// corner within rounding (the robust test enlarges t_far by 1 + 2γ₃ for exactly this, pbrt-v4).
/// An exactly empty-or-touching interval (t_near = t_far, e.g. a zero-thickness box, S22) is not
/// in the band: it is exact, and a closed box must be hit.
pub fn aabb(lo: [f64; 3], hi: [f64; 3], o: [f64; 3], d: [f64; 3], u: f64) -> BoxRef {
    let zero = BigRational::zero();
    let mut t_near = zero.clone();
    let mut t_far: Option<BigRational> = None;
    for i in 0..3 {
        let (l, h, oi) = (q(lo[i]), q(hi[i]), q(o[i]));
        if d[i] == 0.0 {
            if oi < l || oi > h {
                return BoxRef {
                    hit: false,
                    t: None,
                    band: false,
                };
            }
            continue;
        }
        let di = q(d[i]);
        let (mut a, mut b) = ((&l - &oi) / &di, (&h - &oi) / &di);
        if a > b {
            std::mem::swap(&mut a, &mut b);
        }
        if a > t_near {
            t_near = a;
        }
        t_far = Some(match t_far {
            Some(f) if f < b => f,
            _ => b,
        });
    }
    let Some(t_far) = t_far else {
        // All three components zero cannot happen (rays are validated); treat as a miss.
        return BoxRef {
            hit: false,
            t: None,
            band: false,
        };
    };
    let hit = t_near <= t_far;
    let gap = to_f64(&(&t_far - &t_near)).abs();
    let mag = to_f64(&t_near).abs().max(to_f64(&t_far).abs());
    let band = gap > 0.0 && gap <= 8.0 * u * mag;
    BoxRef {
        hit,
        t: hit.then(|| Dd::of(&t_near)),
        band,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sqrt_has_200_bits() {
        let two = q(2.0);
        let s = sqrt(&two);
        let err = to_f64(&(&s * &s - &two)).abs();
        assert!(err < 1e-59, "{err}");
    }
}
