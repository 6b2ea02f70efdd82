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
/// approximate), with a fused `fma`: `c = fma(fma(−q, b, a), inv_b, q)`, then
/// [`round_quotient`] on `c`. Correctly rounds a `q` within 2 ulp and an `inv_b` within 2 ulp
/// (tested with an emulated divider) wherever the residuals are normal. Left as `q` where the step
/// cannot help: a zero, infinite or NaN quotient or residual.
pub fn corrected_div(
    q: f32,
    a: f32,
    b: f32,
    inv_b: f32,
    fma: impl Fn(f32, f32, f32) -> f32,
) -> f32 {
    let r = fma(-q, b, a);
    let c = fma(r, inv_b, q);
    if q != 0.0 && q.is_finite() && r.is_finite() && c != 0.0 && c.is_finite() {
        round_quotient(c, a, b, fma)
    } else {
        q
    }
}

/// The residual step alone leaves `c` one ulp off where `a / b` lies within a hair of the
/// midpoint between two floats (about 1 in 4 million inputs with a 2-ulp reciprocal): this
/// decides the midpoint exactly. With `g` the gap from `c` to its neighbour on one side, `a / b`
/// lies past the midpoint `c ± g/2` exactly when the residual `a − c·b` (away from zero) exceeds
/// `g·|b|/2`. Both are exact: the residual of a quotient within one ulp is representable (`fma`
/// gives it exactly) and `g·|b|/2` only scales `b` by a power of two. Left as `c` where that
/// bound is subnormal (it would not be exact).
fn round_quotient(c: f32, a: f32, b: f32, fma: impl Fn(f32, f32, f32) -> f32) -> f32 {
    let (away, toward) = neighbours(c);
    let half_gap_away = 0.5 * (away - c).abs() * b.abs();
    let half_gap_toward = 0.5 * (c - toward).abs() * b.abs();
    if half_gap_toward < f32::MIN_POSITIVE {
        return c;
    }
    // The residual, signed so that positive means |a / b| > |c|.
    let r = fma(-c, b, a);
    let r = if a < 0.0 { -r } else { r };
    if r > half_gap_away {
        away
    } else if r < -half_gap_toward {
        toward
    } else {
        c
    }
}

/// One residual step on an approximate square root `s ≈ √x` (`half_inv ≈ 0.5 / s`):
/// `c = fma(fma(−s, s, x), half_inv, s)`, then [`round_root`] on `c`. Correctly rounds an `s`
/// within 2 ulp and a `half_inv` within 2 ulp (tested exhaustively on [1, 4), which covers every
/// `x` from 2⁻⁷⁶ up by scaling by 4). Left as `s` for a zero, infinite or NaN root.
pub fn corrected_sqrt(s: f32, x: f32, half_inv: f32, fma: impl Fn(f32, f32, f32) -> f32) -> f32 {
    let r = fma(-s, s, x);
    let c = fma(r, half_inv, s);
    if s > 0.0 && s.is_finite() && c > 0.0 && c.is_finite() {
        round_root(c, x, fma)
    } else {
        s
    }
}

/// The exact midpoint decision for a square root `c` within one ulp of `√x` (the residual step
/// alone misses it about 1 in 4 million times, for example `x = 2¹⁴ + 2⁻⁹`, whose root 128 it
/// rounded up to 128 + 2⁻¹⁶). With `g` the gap from `c` to its neighbour, `√x` lies past the
/// midpoint `c ± g/2` exactly when `x − c²` passes `±(c·g + g²/4)`. The residual `x − c²` is
/// exact (`fma`) and a whole multiple of `g²`, as is `c·g`, so the `g²/4` can be dropped: above
/// when `x − c² > c·g`, below when `x − c² ≤ −c·g`. Left as `c` where `c·g` is subnormal.
fn round_root(c: f32, x: f32, fma: impl Fn(f32, f32, f32) -> f32) -> f32 {
    let (above, below) = neighbours(c);
    let gap_above = c * (above - c);
    let gap_below = c * (c - below);
    if gap_below < f32::MIN_POSITIVE {
        return c;
    }
    let r = fma(-c, c, x);
    if r > gap_above {
        above
    } else if r <= -gap_below {
        below
    } else {
        c
    }
}

/// The floats next to a nonzero finite `c`: one step away from zero and one towards it (the
/// largest float's step away is infinite).
fn neighbours(c: f32) -> (f32, f32) {
    let bits = c.to_bits();
    (f32::from_bits(bits + 1), f32::from_bits(bits - 1))
}
