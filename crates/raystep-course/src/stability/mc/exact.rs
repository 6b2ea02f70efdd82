//! Exact references for the Monte Carlo cases: every input is a float, so a rational number; the
//! formulas are rational but for square roots (taken to at least 200 bits by
//! [`crate::stability::exact::sqrt`]) and π (a 62-digit rational). Each reference is
//! therefore exact to far beyond f64's 53 bits, and is carried as a double-double.

use crate::stability::exact::{Dd, q, sqrt};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

/// π to 62 decimals, as a rational (error below 1e-62).
pub fn pi() -> BigRational {
    let digits = "314159265358979323846264338327950288419716939937510582097494459";
    let n: BigInt = digits.parse().unwrap_or_default();
    BigRational::new(n, BigInt::from(10).pow(digits.len() as u32 - 1))
}

fn int(n: i64) -> BigRational {
    BigRational::from_integer(n.into())
}

fn q3(v: [f64; 3]) -> [BigRational; 3] {
    v.map(q)
}

fn dot(a: &[BigRational; 3], b: &[BigRational; 3]) -> BigRational {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

fn dd(x: &BigRational) -> Option<Dd> {
    Some(Dd::of(x))
}

/// S26: [1 − cos θmax, 1/(2π(1 − cos θmax)), cos θ, sin θ] for a sphere of radius `r` at
/// distance `d` and the uniform number `u`: with s = r²/d², 1 − cos θmax = s/(1 + √(1 − s)),
/// cos θ = 1 − u(1 − cos θmax), sin θ = √(x(2 − x)) with x = u(1 − cos θmax).
pub fn cone(d: f64, r: f64, u: f64) -> [Option<Dd>; 4] {
    let (d, r, u) = (q(d), q(r), q(u));
    let s = (&r * &r) / (&d * &d);
    let one = BigRational::one();
    let x = &s / (&one + sqrt(&(&one - &s)));
    let pdf = one.clone() / (int(2) * pi() * &x);
    let ux = &u * &x;
    let cos = &one - &ux;
    let sin = sqrt(&(&ux * (int(2) - &ux)));
    [dd(&x), dd(&pdf), dd(&cos), dd(&sin)]
}

/// S27: [sin θh, D(h), D(h)·cos θh/(4 ωo·h)] for GGX roughness α, the uniform number `u`, the
/// azimuth (cos φ, sin φ) and the direction `wo`: with t = tan²θh = α²u/(1 − u),
/// cos²θh = 1/(1 + t), sin²θh = t/(1 + t) and D = α²(1 + t)²/(π(α² + t)²).
pub fn ggx(alpha: f64, u: f64, cphi: f64, sphi: f64, wo: [f64; 3]) -> [Option<Dd>; 3] {
    let (a, u, cphi, sphi) = (q(alpha), q(u), q(cphi), q(sphi));
    let a2 = &a * &a;
    let one = BigRational::one();
    let t = &a2 * &u / (&one - &u);
    let one_t = &one + &t;
    let cos = sqrt(&(&one / &one_t));
    let sin = sqrt(&(&t / &one_t));
    let den = &a2 + &t;
    let d = &a2 * &one_t * &one_t / (pi() * &den * &den);
    let h = [&sin * &cphi, &sin * &sphi, cos.clone()];
    let wo_h = dot(&q3(wo), &h);
    let pdf = (!wo_h.is_zero()).then(|| &d * &cos / (int(4) * &wo_h));
    [dd(&sin), dd(&d), pdf.as_ref().and_then(dd)]
}

/// S28: [(w·n)/π, |d|³/(area·(−d·n)), √(1 − r²)] — the cosine-hemisphere pdf of the direction
/// `w` at the normal `n`; the pdf per steradian of a point on an emitting triangle (normal `n`,
/// area `area`) at offset `d`, |d|²/(area·cos θl) with cos θl = −(d·n)/|d|; and the cos θ of the
/// cosine-weighted direction the uniform numbers `u` make, whose concentric-disk point has radius
/// r = max(|2u₀ − 1|, |2u₁ − 1|).
pub fn grazing(w: [f64; 3], n: [f64; 3], d: [f64; 3], area: f64, u: [f64; 2]) -> [Option<Dd>; 3] {
    let (w, n, d) = (q3(w), q3(n), q3(d));
    let cos = dot(&w, &n) / pi();
    let dd2 = dot(&d, &d);
    let dn = -dot(&d, &n);
    let light = (!dn.is_zero()).then(|| &dd2 * sqrt(&dd2) / (q(area) * dn));
    let [a, b] = u.map(|x| (int(2) * q(x) - int(1)).abs());
    let r = if a > b { a } else { b };
    let z = sqrt(&(int(1) - &r * &r));
    [dd(&cos), light.as_ref().and_then(dd), dd(&z)]
}

/// S29: the area ½|(P1 − P0) × (P2 − P0)|.
pub fn area(p: [[f64; 3]; 3]) -> Option<Dd> {
    let [p0, p1, p2] = p.map(q3);
    let e1 = [&p1[0] - &p0[0], &p1[1] - &p0[1], &p1[2] - &p0[2]];
    let e2 = [&p2[0] - &p0[0], &p2[1] - &p0[1], &p2[2] - &p0[2]];
    let c = [
        &e1[1] * &e2[2] - &e1[2] * &e2[1],
        &e1[2] * &e2[0] - &e1[0] * &e2[2],
        &e1[0] * &e2[1] - &e1[1] * &e2[0],
    ];
    let a = sqrt(&dot(&c, &c)) / int(2);
    (!a.is_negative()).then(|| Dd::of(&a))
}
