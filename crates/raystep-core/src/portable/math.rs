//! Portable elementary functions: `sin`, `cos`, `exp`, `ln`, `atan2` (and [`pow`]) computed by the same
//! f32 steps on the CPU and on the GPU, so that a sample's direction has the same bits on both.
//!
//! Rust's `f32::sin` calls the platform's libm and WGSL's `sin` is whatever the driver does
//! (Vulkan allows an absolute error of 2⁻¹¹ on [−π, π]); the two disagree in the last bits, and
//! a direction that differs by one ulp can hit a different triangle. These use only `+`, `−`,
//! `×`, `floor`, comparisons and bit casts — operations that are exactly rounded everywhere —
//! so where the GPU does not contract `a·b + c` into an FMA (the exact compute path's
//! `NoContraction`, see `gpu::exact`) the results are identical. The WGSL twin,
//! `math.wgsl` beside this file ([`super::MATH_WGSL`]), repeats them line for line; `pow`'s is
//! `pow.wgsl` ([`super::POW_WGSL`]).
//!
//! The methods are Cody and Waite's range reduction followed by Cephes' single-precision
//! polynomials (S. L. Moshier, *Cephes Math Library*, `sinf.c`, `expf.c`, `logf.c`, `atanf.c`; see
//! docs/SOURCES.md). Accuracy, measured against f64's `sin`, `cos`, `exp` and `ln` in this
//! module's tests:
//!
//! * [`sin_cos`]: within 2 ulp (of the correctly rounded f32) for |x| ≤ 8192, except that near a
//!   zero of the function the error is bounded by 2⁻²⁶ absolute instead (the reduction's
//!   three-part π/2 is good to 2⁻⁴⁸). Beyond 8192 the reduction loses accuracy (results
//!   stay in [−1, 1]); sampling calls it with 0 ≤ x < 2π.
//! * [`exp`]: within 1 ulp; results below `f32::MIN_POSITIVE` are 0 (GPUs may flush subnormals,
//!   so none is made), above `f32::MAX` +∞.
//! * [`ln`]: within 1 ulp for normal positive x; 0 and subnormals give −∞, negative x and NaN
//!   give NaN, +∞ gives +∞.
//! * [`atan`]: within 2 ulp (Cephes `atanf`); [`atan2`] within 3 ulp, the quotient's rounding
//!   included (a sphere's texture coordinates, `trace::texture`). Their WGSL twin is
//!   `atan.wgsl`, which divides with the tracer's exact `fdiv`.

// The coefficients are Cephes' published decimals, kept verbatim so they can be checked against
// the source (each rounds to the f32 it names; the WGSL twin writes the same decimals).
#![allow(clippy::excessive_precision)]

/// `x^y` for `x ≥ 0` and finite `y ≥ 0`, by the same steps on the CPU and on the GPU (the
/// tracer's WGSL `fpow` repeats them), so the specular highlight has the same bits on both:
/// `x^⌊y⌋` by squaring, then for each binary digit of the fraction (at most 24) a repeated square
/// root `x^(2^-k)` multiplied in. Only multiplications and correctly rounded square roots, where
/// `powf` and WGSL's `pow` (`exp2(y·log2 x)` at reduced precision) differ from platform to
/// platform. Within about 2·y ulp of the true power. Other inputs (negative or NaN `x`, negative,
/// infinite or NaN `y`) give 0: Phong calls it with r·e > 0 and a validated positive shininess.
pub fn pow(x: f32, y: f32) -> f32 {
    if x.is_nan() || x < 0.0 || !y.is_finite() || y < 0.0 {
        return 0.0;
    }
    let whole = y.floor();
    let mut frac = y - whole;
    let mut n = if whole < 4_294_967_040.0 {
        whole as u32
    } else {
        u32::MAX
    };
    let (mut result, mut base) = (1.0f32, x);
    while n > 0 {
        if n & 1 == 1 {
            result *= base;
        }
        n >>= 1;
        if n > 0 {
            base *= base;
        }
    }
    let mut root = x;
    let mut k = 0;
    while k < 24 && frac != 0.0 {
        root = root.sqrt();
        frac *= 2.0;
        if frac >= 1.0 {
            result *= root;
            frac -= 1.0;
        }
        k += 1;
    }
    result
}

/// π/2 in three parts: the first two with few enough significant bits (7 and 11) that `k·part`
/// is exact for |k| < 2¹³; their sum is π/2 within 2⁻⁴⁸.
const PIO2_1: f32 = 1.570_312_5;
const PIO2_2: f32 = 4.837_512_969_970_703e-4;
const PIO2_3: f32 = 7.549_790_126_404_332e-8;
/// 2/π rounded to f32.
const TWO_OVER_PI: f32 = 0.636_619_75;

/// sin r for |r| ≤ π/4 (Cephes `sinf`).
fn sin_poly(r: f32) -> f32 {
    let z = r * r;
    ((-1.951_529_589_1e-4 * z + 8.332_160_873_6e-3) * z - 1.666_665_461_1e-1) * z * r + r
}

/// cos r for |r| ≤ π/4 (Cephes `cosf`).
fn cos_poly(r: f32) -> f32 {
    let z = r * r;
    let y = ((2.443_315_711_809_948e-5 * z - 1.388_731_625_493_765e-3) * z
        + 4.166_664_568_298_827e-2)
        * z
        * z;
    (y - 0.5 * z) + 1.0
}

/// `(sin x, cos x)`: x reduced to r = x − k·π/2 with |r| ≤ π/4 (k = ⌊x·2/π + ½⌋), then each
/// polynomial on r and the quadrant k mod 4 picks and signs them. NaN or infinite x gives NaN.
pub fn sin_cos(x: f32) -> (f32, f32) {
    if !x.is_finite() {
        return (f32::NAN, f32::NAN);
    }
    let k = (x * TWO_OVER_PI + 0.5).floor();
    let r = ((x - k * PIO2_1) - k * PIO2_2) - k * PIO2_3;
    let (s, c) = (sin_poly(r), cos_poly(r));
    // k is within i32 for |x| < 2³¹·π/2; beyond, the quadrant is meaningless anyway.
    let q = if k.abs() < 2_147_483_648.0 {
        (k as i32) & 3
    } else {
        0
    };
    match q {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// `sin x`: the first half of [`sin_cos`].
pub fn sin(x: f32) -> f32 {
    sin_cos(x).0
}

/// `cos x`: the second half of [`sin_cos`].
pub fn cos(x: f32) -> f32 {
    sin_cos(x).1
}

/// π/2, π/4 and π rounded to f32 (the WGSL twin, `atan.wgsl`, writes decimals that round to
/// the same f32s; a test checks it).
const ATAN_PIO2: f32 = std::f32::consts::FRAC_PI_2;
const ATAN_PIO4: f32 = std::f32::consts::FRAC_PI_4;
const ATAN_PI: f32 = std::f32::consts::PI;

/// atan x (Cephes `atanf`): |x| reduced to [0, tan π/8] by atan x = π/2 + atan(−1/x) above
/// tan 3π/8 and π/4 + atan((x − 1)/(x + 1)) above tan π/8, then an odd polynomial. Within
/// 2 ulp of atan for finite x; ±∞ gives ±π/2, NaN gives NaN.
pub fn atan(x: f32) -> f32 {
    let negative = x < 0.0;
    let mut a = x.abs();
    let mut y = 0.0;
    if a > 2.414_213_562_373_095 {
        y = ATAN_PIO2;
        a = -(1.0 / a);
    } else if a > 0.414_213_562_373_095_0 {
        y = ATAN_PIO4;
        a = (a - 1.0) / (a + 1.0);
    }
    let z = a * a;
    y += (((8.053_744_495_38e-2 * z - 1.387_768_560_32e-1) * z + 1.997_771_064_78e-1) * z
        - 3.333_294_915_39e-1)
        * z
        * a
        + a;
    if negative { -y } else { y }
}

/// atan2(y, x) (Cephes `atan2f`): the angle of the point (x, y) in (−π, π], from [`atan`] of
/// y/x and the quadrant; within 3 ulp (the quotient's rounding included). (0, 0) gives 0; the
/// sign of a zero is not looked at.
pub fn atan2(y: f32, x: f32) -> f32 {
    if x == 0.0 {
        return if y < 0.0 {
            -ATAN_PIO2
        } else if y == 0.0 {
            0.0
        } else {
            ATAN_PIO2
        };
    }
    if y == 0.0 {
        return if x < 0.0 { ATAN_PI } else { 0.0 };
    }
    let w = if x > 0.0 {
        0.0
    } else if y < 0.0 {
        -ATAN_PI
    } else {
        ATAN_PI
    };
    w + atan(y / x)
}

/// ln 2 in two parts (Cephes): `C1` has 9 significant bits, so `k·C1` is exact for |k| < 2¹⁵.
const LN2_HI: f32 = 0.693_359_375;
const LN2_LO: f32 = -2.121_944_4e-4;
/// log₂ e rounded to f32.
const LOG2_E: f32 = std::f32::consts::LOG2_E;

/// 2ᵏ for −126 ≤ k ≤ 127, built from its bits.
fn exp2i(k: i32) -> f32 {
    f32::from_bits(((k + 127) as u32) << 23)
}

/// `eˣ`: k = ⌊x·log₂e + ½⌋, r = x − k·ln 2 (two parts), e^r by Cephes' degree-7 polynomial,
/// scaled by 2ᵏ in two exact steps. Results below `f32::MIN_POSITIVE` are 0 and above `f32::MAX`
/// +∞; NaN gives NaN.
pub fn exp(x: f32) -> f32 {
    if x.is_nan() {
        return f32::NAN;
    }
    if x > 88.8 {
        return f32::INFINITY;
    }
    if x < -88.0 {
        return 0.0;
    }
    let k = (x * LOG2_E + 0.5).floor();
    let r = (x - k * LN2_HI) - k * LN2_LO;
    let z = r * r;
    let mut p = 1.987_569_15e-4 * r + 1.398_199_950_7e-3;
    p = p * r + 8.333_451_907_3e-3;
    p = p * r + 4.166_579_589_4e-2;
    p = p * r + 1.666_666_545_9e-1;
    p = p * r + 5.000_000_120_1e-1;
    let p = p * z;
    let y = (p + r) + 1.0;
    let k = k as i32;
    let half = k >> 1;
    let y = y * exp2i(half) * exp2i(k - half);
    if y < f32::MIN_POSITIVE { 0.0 } else { y }
}

/// √½, where Cephes' `logf` moves the mantissa's range to [√½, √2).
const SQRT_HALF: f32 = 0.707_106_77;

/// `ln x`: x = m·2ᵉ with m in [√½, √2) (from the bits), ln(1 + f) for f = m − 1 by Cephes'
/// polynomial, plus e·ln 2 in two parts. 0 and subnormal x give −∞ (a GPU may read a subnormal
/// as 0), negative x and NaN give NaN, +∞ gives +∞.
pub fn ln(x: f32) -> f32 {
    if x.is_nan() || x < 0.0 {
        return f32::NAN;
    }
    if x < f32::MIN_POSITIVE {
        return f32::NEG_INFINITY;
    }
    if x == f32::INFINITY {
        return x;
    }
    let bits = x.to_bits();
    let mut e = ((bits >> 23) & 0xff) as i32 - 126;
    // m in [½, 1).
    let m = f32::from_bits((bits & 0x007f_ffff) | (126 << 23));
    let f = if m < SQRT_HALF {
        e -= 1;
        (m + m) - 1.0
    } else {
        m - 1.0
    };
    let e = e as f32;
    let z = f * f;
    let mut p = 7.037_683_629_2e-2 * f - 1.151_461_031_0e-1;
    p = p * f + 1.167_699_874_0e-1;
    p = p * f - 1.242_014_084_6e-1;
    p = p * f + 1.424_932_278_7e-1;
    p = p * f - 1.666_805_766_5e-1;
    p = p * f + 2.000_071_476_5e-1;
    p = p * f - 2.499_999_399_3e-1;
    p = p * f + 3.333_333_117_4e-1;
    let y = p * f * z;
    let y = y + e * LN2_LO;
    let y = y - 0.5 * z;
    let r = f + y;
    r + e * LN2_HI
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in ulps between `got` and `want` rounded to f32 (both finite).
    fn ulps(got: f32, want: f64) -> u32 {
        let w = want as f32;
        let key = |v: f32| {
            let b = v.to_bits() as i32;
            if b < 0 { i32::MIN - b } else { b }
        };
        (key(got) as i64 - key(w) as i64).unsigned_abs() as u32
    }

    #[test]
    fn the_reduction_constants_are_pi_over_2_in_three_parts() {
        let sum = PIO2_1 as f64 + PIO2_2 as f64 + PIO2_3 as f64;
        assert!((sum - std::f64::consts::FRAC_PI_2).abs() < 4e-15, "{sum}");
        // k·part exact for |k| < 2^13: the parts' significands end in 12 zero bits.
        assert_eq!(PIO2_1.to_bits() & 0xfff, 0);
        assert_eq!(PIO2_2.to_bits() & 0xfff, 0);
        assert_eq!(LN2_HI.to_bits() & 0x7fff, 0);
        assert!(((LN2_HI as f64 + LN2_LO as f64) - std::f64::consts::LN_2).abs() < 1e-11);
    }

    /// atan over a sweep of f32s from 1e-6 to 1e7 (and their negatives): within 2 ulp of f64's.
    /// atan2 over the unit circle in 100 000 steps: within 3 ulp (the quotient y/x's rounding
    /// included), or 6e-8 absolute where the result is near zero. The quadrants and axes by hand.
    #[test]
    fn atan_and_atan2_are_within_2_ulp_of_f64() {
        let mut worst = 0;
        let mut x = 1e-6f32;
        while x < 1e7 {
            for v in [x, -x] {
                let u = ulps(atan(v), f64::from(v).atan());
                worst = worst.max(u);
            }
            x *= 1.000_37;
        }
        assert!(worst <= 2, "atan: {worst} ulp");
        for k in 0..100_000 {
            let a = (f64::from(k) / 100_000.0 - 0.5) * std::f64::consts::TAU;
            let (y, x) = (a.sin() as f32, a.cos() as f32);
            let want = f64::from(y).atan2(f64::from(x));
            let got = atan2(y, x);
            assert!(
                ulps(got, want) <= 3 || (f64::from(got) - want).abs() < 6e-8,
                "atan2({y}, {x}) = {got}, want {want}"
            );
        }
        assert_eq!(atan2(0.0, 1.0), 0.0);
        assert_eq!(atan2(0.0, -1.0), ATAN_PI);
        assert_eq!(atan2(1.0, 0.0), ATAN_PIO2);
        assert_eq!(atan2(-1.0, 0.0), -ATAN_PIO2);
        assert_eq!(atan2(0.0, 0.0), 0.0);
        assert!(atan(f32::NAN).is_nan());
        assert_eq!(atan(f32::INFINITY), ATAN_PIO2);
    }

    /// Every f32 in ±[0, 2π) at a stride of 679 ulp-steps (3.2 million values, dense near 0),
    /// and a sweep over ±8192: within 2 ulp, or 2⁻²⁶ absolute near a zero.
    #[test]
    fn sin_cos_is_within_2_ulp_of_f64() {
        let mut worst = (0u32, 0.0f32);
        let mut check = |x: f32| {
            let (s, c) = sin_cos(x);
            for (got, want) in [(s, (x as f64).sin()), (c, (x as f64).cos())] {
                let u = ulps(got, want);
                let abs = (got as f64 - want).abs();
                if u > 2 {
                    assert!(
                        abs <= 2f64.powi(-26),
                        "x = {x:e}: {got:e} vs {want:e} ({u} ulp)"
                    );
                } else if u > worst.0 {
                    worst = (u, x);
                }
            }
        };
        let two_pi = std::f32::consts::TAU;
        let mut b = 0u32;
        while f32::from_bits(b) < two_pi {
            check(f32::from_bits(b));
            check(-f32::from_bits(b));
            b += 7 * 97;
        }
        for i in -2_000_000..=2_000_000 {
            check(i as f32 * (8192.0 / 2_000_000.0));
        }
        eprintln!("sin_cos: worst {} ulp at {:e}", worst.0, worst.1);
        assert!(worst.0 <= 2);
    }

    #[test]
    fn sin_cos_at_known_angles() {
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        let (s, c) = sin_cos(std::f32::consts::FRAC_PI_2);
        assert!(ulps(s, 1.0) == 0 && c.abs() < 1e-7);
        let (s, c) = sin_cos(std::f32::consts::PI);
        assert!(s.abs() < 1e-7 && ulps(c, -1.0) == 0);
        assert!(sin(f32::NAN).is_nan() && cos(f32::INFINITY).is_nan());
    }

    /// A sweep over [−87.3, 88.7] (4 million points): within 1 ulp of f64's exp.
    #[test]
    fn exp_is_within_2_ulp_of_f64() {
        let mut worst = 0;
        let n = 4_000_000;
        for i in 0..=n {
            let x = -87.3 + (88.7 + 87.3) * (i as f64 / n as f64);
            let x = x as f32;
            let u = ulps(exp(x), (x as f64).exp());
            assert!(
                u <= 1,
                "exp({x:e}) = {:e} vs {:e}",
                exp(x),
                (x as f64).exp()
            );
            worst = worst.max(u);
        }
        eprintln!("exp: worst {worst} ulp");
        assert_eq!(exp(0.0), 1.0);
        assert_eq!(exp(100.0), f32::INFINITY);
        assert_eq!(exp(-100.0), 0.0);
        assert_eq!(exp(-87.5), 0.0, "a subnormal result is flushed");
        assert!(exp(f32::NAN).is_nan());
    }

    /// Every normal f32 at a stride of 251 ulp-steps (about 8.5 million values, all exponents):
    /// within 1 ulp of f64's ln.
    #[test]
    fn ln_is_within_2_ulp_of_f64() {
        let mut worst = 0;
        let mut b = f32::MIN_POSITIVE.to_bits();
        while b < f32::INFINITY.to_bits() {
            let x = f32::from_bits(b);
            let u = ulps(ln(x), (x as f64).ln());
            assert!(u <= 1, "ln({x:e}) = {:e} vs {:e}", ln(x), (x as f64).ln());
            worst = worst.max(u);
            b += 251;
        }
        eprintln!("ln: worst {worst} ulp");
        assert_eq!(ln(1.0), 0.0);
        assert_eq!(ln(0.0), f32::NEG_INFINITY);
        assert_eq!(ln(1e-40), f32::NEG_INFINITY, "a subnormal reads as 0");
        assert!(ln(-1.0).is_nan() && ln(f32::NAN).is_nan());
        assert_eq!(ln(f32::INFINITY), f32::INFINITY);
    }
}
