//! Exact arithmetic (crates/raystep-gpu/src/exact/): the corrections proved on the CPU, where a
//! driver's inexact division and square root are emulated (lavapipe's are exact, so they cannot
//! show it).

use proptest::prelude::*;
use raystep::gpu::exact::{corrected_div, corrected_sqrt, fma_emulated, two_prod};

/// `x` moved `k` ulps (k may be negative) along the floats: an emulated inexact operation.
fn ulps(x: f32, k: i32) -> f32 {
    let mut y = x;
    for _ in 0..k.unsigned_abs() {
        y = if k > 0 { y.next_up() } else { y.next_down() };
    }
    y
}

/// A float with any significand and sign, exponent 2^lo … 2^hi.
fn float(lo: i32, hi: i32) -> impl Strategy<Value = f32> {
    (0u32..1 << 23, lo..=hi, any::<bool>()).prop_map(|(m, e, neg)| {
        let bits = ((e + 127) as u32) << 23 | m;
        let x = f32::from_bits(bits);
        if neg { -x } else { x }
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    /// A divider and a reciprocal each off by up to 2 ulp: one fma residual step gives the
    /// correctly rounded quotient.
    #[test]
    fn one_residual_step_rounds_a_division_off_by_two_ulp_correctly(
        a in float(-40, 40), b in float(-40, 40), k in -2i32..=2, j in -2i32..=2,
    ) {
        let want = a / b;
        let q = ulps(want, k);
        let inv_b = ulps(1.0 / b, j);
        let got = corrected_div(q, a, b, inv_b, f32::mul_add);
        prop_assert_eq!(got.to_bits(), want.to_bits(), "q = {} ({} ulp)", q, k);
    }

    /// A square root off by up to 2 ulp (and 0.5/s off by 2 more): one step rounds it
    /// correctly.
    #[test]
    fn one_residual_step_rounds_a_square_root_off_by_two_ulp_correctly(
        x in float(-60, 60), k in -2i32..=2, j in -2i32..=2,
    ) {
        let x = x.abs();
        let want = x.sqrt();
        let s = ulps(want, k);
        let half_inv = ulps(0.5 / s, j);
        let got = corrected_sqrt(s, x, half_inv, f32::mul_add);
        prop_assert_eq!(got.to_bits(), want.to_bits(), "s = {} ({} ulp)", s, k);
    }

    /// Dekker's two-product is exact: p + e = a·b (checked in f64, where the product of two
    /// f32 is exact).
    #[test]
    fn dekkers_two_product_is_exact(a in float(-50, 50), b in float(-50, 50)) {
        let (p, e) = two_prod(a, b);
        prop_assert_eq!(p, a * b);
        prop_assert_eq!(p as f64 + e as f64, a as f64 * b as f64);
    }

    /// The emulated fma is Rust's mul_add, bit for bit — also where c cancels the product
    /// (the watertight triangle test's difference of products).
    #[test]
    fn the_emulated_fma_is_mul_add(
        a in float(-40, 40), b in float(-40, 40), c in float(-80, 80), cancel in any::<bool>(),
        k in -3i32..=3,
    ) {
        let c = if cancel { ulps(-(a * b), k) } else { c };
        prop_assert_eq!(fma_emulated(a, b, c).to_bits(), a.mul_add(b, c).to_bits());
    }

    /// The portable pow is within its documented bound of the true power (f64's powf).
    #[test]
    fn portable_pow_is_close_to_the_true_power(x in 0.0f32..1.0, y in 0.5f32..400.0) {
        let got = raystep::portable::math::pow(x, y) as f64;
        let want = (x as f64).powf(y as f64);
        let tol = (2.0 * y as f64 + 30.0) * f64::from(f32::EPSILON) * want
            + f64::from(f32::MIN_POSITIVE);
        prop_assert!((got - want).abs() <= tol, "{}^{}: {} vs {}", x, y, got, want);
    }
}

/// Where the driver's division is already exact, the step is not applied: the probe only
/// picks it where it got strictly more inputs right, and only with a fused fma.
#[test]
fn a_correction_is_never_chosen_where_it_makes_things_worse() {
    use raystep::gpu::exact::Probe;
    let n = 4096;
    let base = Probe {
        inputs: n,
        fma: n,
        fma_emulated: n,
        div: n,
        div_corrected: 3600,
        sqrt: n,
        sqrt_corrected: n,
        sum_of_products: n,
        subnormals: n,
    };
    assert!(!base.config().div_fix && base.exact());
    let inexact = Probe {
        div: 2900,
        div_corrected: n,
        sqrt: 3400,
        sqrt_corrected: n,
        ..base
    };
    let c = inexact.config();
    assert!(c.div_fix && c.sqrt_fix && c.fma_fused && inexact.exact());
    // Unfused fma (lavapipe): no residual step, whatever the counts say.
    let unfused = Probe { fma: 0, ..inexact };
    assert!(!unfused.config().div_fix && !unfused.exact());
    // A step that does not help is not taken.
    let useless = Probe {
        div: 2900,
        div_corrected: 2800,
        ..base
    };
    assert!(!useless.config().div_fix && !useless.exact());
}
