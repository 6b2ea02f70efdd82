//! The CPU's model of the GPU arithmetic: Knuth's and Dekker's error-free transformations and
//! the corrected division and square root, which the WGSL of [`super::arith_wgsl`] repeats step
//! by step.

/// Knuth's TwoSum: `(s, e)` with `s = a + b` rounded and `s + e = a + b` exactly (no overflow).
pub fn two_sum(a: f32, b: f32) -> (f32, f32) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// Veltkamp's split: `a = hi + lo`, each half with at most 12 significant bits.
pub fn split(a: f32) -> (f32, f32) {
    let c = 4097.0 * a;
    let hi = c - (c - a);
    (hi, a - hi)
}

/// Dekker's two-product: `(p, e)` with `p = a·b` rounded and `p + e = a·b` exactly, with plain
/// multiplications and additions only (valid when nothing is contracted, nothing overflows and
/// `e` is not subnormal).
pub fn two_prod(a: f32, b: f32) -> (f32, f32) {
    let p = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    let e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    (p, e)
}

/// `a·b + c` rounded once, as `f32::mul_add`, without a fused multiply-add: the product split
/// exactly by [`two_prod`], summed by [`two_sum`], the low part rounded to odd before the last
/// addition (Boldo and Melquiond's trick, so the two roundings make one). Not finite: `a*b + c`.
pub fn fma_emulated(a: f32, b: f32, c: f32) -> f32 {
    let (p, e) = two_prod(a, b);
    let (s, t) = two_sum(p, c);
    let (u, v) = two_sum(t, e);
    let r = s + round_to_odd(u, v);
    if r.is_finite() && e.is_finite() {
        r
    } else {
        a * b + c
    }
}

/// `u` (the rounded `u + v`, `v` its exact error) rounded to odd: unchanged when exact or odd,
/// otherwise one ulp towards `v`.
fn round_to_odd(u: f32, v: f32) -> f32 {
    let bits = u.to_bits();
    if v == 0.0 || bits & 1 == 1 {
        return u;
    }
    if (u > 0.0) == (v > 0.0) {
        f32::from_bits(bits + 1)
    } else {
        f32::from_bits(bits - 1)
    }
}

/// One residual step on an approximate quotient `q ≈ a / b` (`inv_b ≈ 1 / b`, also
/// approximate), with a fused `fma`: `fma(fma(−q, b, a), inv_b, q)`. Correctly rounds a `q`
/// within 2 ulp (tested with an emulated divider). Left as `q` where the step cannot help: a zero,
/// infinite or NaN quotient or residual.
pub fn corrected_div(
    q: f32,
    a: f32,
    b: f32,
    inv_b: f32,
    fma: impl Fn(f32, f32, f32) -> f32,
) -> f32 {
    let r = fma(-q, b, a);
    let c = fma(r, inv_b, q);
    if q != 0.0 && q.is_finite() && r.is_finite() && c.is_finite() {
        c
    } else {
        q
    }
}

/// One residual step on an approximate square root `s ≈ √x` (`half_inv ≈ 0.5 / s`):
/// `fma(fma(−s, s, x), half_inv, s)`. Left as `s` for a zero, infinite or NaN root.
pub fn corrected_sqrt(s: f32, x: f32, half_inv: f32, fma: impl Fn(f32, f32, f32) -> f32) -> f32 {
    let r = fma(-s, s, x);
    let c = fma(r, half_inv, s);
    if s > 0.0 && s.is_finite() && c.is_finite() {
        c
    } else {
        s
    }
}
