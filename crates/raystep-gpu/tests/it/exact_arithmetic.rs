//! Exact arithmetic (crates/raystep-gpu/src/exact/): the corrections proved on the CPU, where a
//! driver's inexact division and square root are emulated (lavapipe's are exact, so they cannot
//! show it), and their WGSL twin run on the test adapter with the same emulated errors.

use proptest::prelude::*;
use raystep_gpu::exact::{corrected_div, corrected_sqrt, fma_emulated, two_prod};

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
        let got = raystep_core::portable::math::pow(x, y) as f64;
        let want = (x as f64).powf(y as f64);
        let tol = (2.0 * y as f64 + 30.0) * f64::from(f32::EPSILON) * want
            + f64::from(f32::MIN_POSITIVE);
        prop_assert!((got - want).abs() <= tol, "{}^{}: {} vs {}", x, y, got, want);
    }
}

/// Every `x` of [1, 4) — the range that all of them reduce to, as √(4x) = 2√x — whose root one
/// residual step alone rounded wrong, for some root and some `0.5/s` within 2 ulp (found by a
/// search through every float of [1, 4)), as offsets in floats from 1.0.
const ROOTS_NEXT_TO_A_MIDPOINT: [u32; 20] = [
    1, 3, 5, 7, 3_196_611, 3_722_342, 4_932_073, 8_130_890, 9_429_058, 12_291_626, 12_696_654,
    13_966_783, 14_344_251, 15_635_314, 15_835_780, 16_777_207, 16_777_209, 16_777_211, 16_777_213,
    16_777_215,
];

/// Every root within 2 ulp and every `0.5/s` within 2 ulp of `x`'s: the corrected square root is
/// `f32::sqrt` (IEEE 754's, correctly rounded), bit for bit.
fn assert_sqrt_corrected(x: f32) {
    let want = x.sqrt();
    for k in -2..=2 {
        let s = ulps(want, k);
        for j in -2..=2 {
            let half_inv = ulps(0.5 / s, j);
            let got = corrected_sqrt(s, x, half_inv, f32::mul_add);
            assert_eq!(
                got.to_bits(),
                want.to_bits(),
                "√{x:e} from {s:e} ({k} ulp), 0.5/s {j} ulp"
            );
        }
    }
}

/// Every quotient and every reciprocal within 2 ulp of `a / b`'s and `1 / b`'s: the corrected
/// division is IEEE's `a / b`, bit for bit.
fn assert_div_corrected(a: f32, b: f32) {
    let want = a / b;
    for k in -2..=2 {
        for j in -2..=2 {
            let (q, inv_b) = (ulps(want, k), ulps(1.0 / b, j));
            let got = corrected_div(q, a, b, inv_b, f32::mul_add);
            assert_eq!(
                got.to_bits(),
                want.to_bits(),
                "{a:e}/{b:e}: {k} ulp, 1/b {j}"
            );
        }
    }
}

/// The square roots next to a midpoint, at every scale from 2⁻⁶⁰ to 2⁶²: one residual step left
/// them one ulp off (√(2¹⁴ + 2⁻⁹) came out as 128 + 2⁻¹⁶ instead of 128); the exact midpoint
/// decision gets each right.
#[test]
fn square_roots_next_to_a_midpoint_are_rounded_correctly() {
    let one = 1.0f32.to_bits();
    assert_eq!(f32::from_bits(one + 1) * 16384.0, 16384.002);
    for offset in ROOTS_NEXT_TO_A_MIDPOINT {
        let x = f32::from_bits(one + offset);
        for e in -30..=31 {
            assert_sqrt_corrected(x * 4f32.powi(e));
        }
    }
}

/// A stride through [1, 4), and its first and last 2,000 floats (where √x is next to 1 and to
/// 2): every one corrected exactly.
#[test]
fn square_roots_through_one_to_four_are_rounded_correctly() {
    let (one, four) = (1.0f32.to_bits(), 4.0f32.to_bits());
    let ends = (one..one + 2000).chain(four - 2000..four);
    for bits in (one..four).step_by(97).chain(ends) {
        assert_sqrt_corrected(f32::from_bits(bits));
    }
}

/// Every float of [1, 4), with every root and every `0.5/s` within 2 ulp: 419 million corrected
/// square roots, each `f32::sqrt`'s. The search that found [`ROOTS_NEXT_TO_A_MIDPOINT`], about 10 s
/// in release: `cargo test --release -p raystep-gpu --test it -- --ignored exhaustive`.
#[test]
#[ignore = "exhaustive: about 10 s in release"]
fn exhaustive_square_roots_of_one_to_four() {
    for bits in 1.0f32.to_bits()..4.0f32.to_bits() {
        assert_sqrt_corrected(f32::from_bits(bits));
    }
}

/// Every third float `a` of [1, 2) over eight `b` of [1, 2) each (a fixed xorshift), with every
/// quotient and reciprocal within 2 ulp: 559 million corrected quotients, each IEEE's `a / b`.
/// The search that found [`QUOTIENTS_NEXT_TO_A_MIDPOINT`]; run as the one above.
#[test]
#[ignore = "exhaustive: about 10 s in release"]
fn exhaustive_quotients_of_one_to_two() {
    let mut state = 12345u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for bits in (1.0f32.to_bits()..2.0f32.to_bits()).step_by(3) {
        let a = f32::from_bits(bits);
        for _ in 0..8 {
            assert_div_corrected(a, f32::from_bits(0x3f80_0000 | (next() as u32 & 0x7f_ffff)));
        }
    }
}

/// Quotients one residual step alone rounded wrong (with a quotient and a reciprocal each within
/// 2 ulp), as `(a, b)` bits (found by a search through 559 million quotients of [1, 2)).
const QUOTIENTS_NEXT_TO_A_MIDPOINT: [(u32, u32); 12] = [
    (0x3f9a5aa3, 0x3f86f6b5),
    (0x3f9c3e18, 0x3fc61a3d),
    (0x3fa66d66, 0x3fdc31af),
    (0x3fa8c54b, 0x3f97635f),
    (0x3faa552f, 0x3fd81551),
    (0x3fb09aad, 0x3ff86855),
    (0x3fbac641, 0x3fd3f4d9),
    (0x3fbc053a, 0x3fd930bf),
    (0x3fc27fc5, 0x3faa4e87),
    (0x3fc9f362, 0x3fccfa4c),
    (0x3fca0478, 0x3fc1b794),
    (0x3fda2337, 0x3f9d6a23),
];

/// The quotients next to a midpoint at many scales and signs: the exact midpoint decision gets
/// each right.
#[test]
fn quotients_next_to_a_midpoint_are_rounded_correctly() {
    for (a, b) in QUOTIENTS_NEXT_TO_A_MIDPOINT {
        for (ea, eb) in [(0, 0), (-40, 7), (35, -30), (12, 40), (-20, -20)] {
            for (sa, sb) in [(1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
                assert_div_corrected(
                    sa * f32::from_bits(a) * 2f32.powi(ea),
                    sb * f32::from_bits(b) * 2f32.powi(eb),
                );
            }
        }
    }
}

/// Where the driver's division is already exact, the step is not applied: the probe only
/// picks it where it got strictly more inputs right, and only with a fused fma.
#[test]
fn a_correction_is_never_chosen_where_it_makes_things_worse() {
    use raystep_gpu::exact::Probe;
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

/// The WGSL twin (`corrected_div` and `corrected_sqrt` in crates/raystep-gpu/src/exact/arith.wgsl)
/// on the test adapter, with the driver's errors emulated as above (quotients, reciprocals and
/// roots up to 2 ulp off, passed in): every hard case above and 20,000 random ones of each come
/// back correctly rounded, bit for bit. The twin's `fma` is WGSL's, fused only where a GPU's is;
/// here it calls `fmaf`, which is that `fma` where the probe found it fused and the exact
/// emulation (lavapipe) elsewhere — the same function on a fused GPU.
#[test]
fn the_wgsl_corrections_round_correctly_on_the_test_adapter() {
    use crate::common::gpu::{exact_context, one_at_a_time};
    use raystep_gpu::{KernelForm, exact::arith_wgsl};
    let _gpu = one_at_a_time();
    let test = "the_wgsl_corrections_round_correctly_on_the_test_adapter";
    let Some((ctx, arith)) = exact_context(test) else {
        return;
    };
    let lib = arith_wgsl(arith.config());
    assert_eq!(
        lib.matches("= fma(").count(),
        6,
        "the corrections' six fma calls"
    );
    let wgsl = lib.replace("= fma(", "= fmaf(")
        + "@group(0) @binding(0) var<storage, read> inputs: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> outputs: array<u32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if i >= arrayLength(&inputs) {
        return;
    }
    let v = inputs[i];
    if i % 2u == 0u {
        outputs[i] = bitcast<u32>(corrected_div(v.x, v.y, v.z, v.w));
    } else {
        outputs[i] = bitcast<u32>(corrected_sqrt(v.x, v.y, v.z));
    }
}
";
    // (q, a, b, 1/b) for a / b, and (s, x, 0.5/s) for √x, each with its correctly rounded value.
    let mut div = vec![];
    let mut sqrt = vec![];
    let mut push_div = |a: f32, b: f32| {
        for k in -2..=2 {
            for j in -2..=2 {
                div.push(([ulps(a / b, k), a, b, ulps(1.0 / b, j)], a / b));
            }
        }
    };
    for (a, b) in QUOTIENTS_NEXT_TO_A_MIDPOINT {
        for (ea, eb) in [(0, 0), (-40, 7), (35, -30)] {
            let a = f32::from_bits(a) * 2f32.powi(ea);
            let b = f32::from_bits(b) * 2f32.powi(eb);
            push_div(a, b);
            push_div(-a, b);
            push_div(a, -b);
        }
    }
    let mut push_sqrt = |x: f32| {
        for k in -2..=2 {
            let s = ulps(x.sqrt(), k);
            for j in -2..=2 {
                sqrt.push(([s, x, ulps(0.5 / s, j), 0.0], x.sqrt()));
            }
        }
    };
    for offset in ROOTS_NEXT_TO_A_MIDPOINT {
        for e in [-30, -7, 0, 7, 31] {
            push_sqrt(f32::from_bits(1.0f32.to_bits() + offset) * 4f32.powi(e));
        }
    }
    // Random ones, as the proptests draw them (a fixed xorshift: the same inputs every run).
    let mut state = 0x2545_f491_u32;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state
    };
    let mut float = |lo: i32, span: u32| {
        let e = (lo + (next() % span) as i32 + 127) as u32;
        let x = f32::from_bits(e << 23 | next() >> 9);
        if next() & 1 == 1 { -x } else { x }
    };
    for _ in 0..800 {
        let (a, b, x) = (float(-40, 81), float(-40, 81), float(-60, 121));
        push_div(a, b);
        push_sqrt(x.abs());
    }
    let rows: Vec<([f32; 4], f32)> = (0..div.len().max(sqrt.len()))
        .flat_map(|i| [div[i % div.len()], sqrt[i % sqrt.len()]])
        .collect();
    let bytes: Vec<u8> = rows
        .iter()
        .flat_map(|(v, _)| v.iter().flat_map(|x| x.to_le_bytes()))
        .collect();
    let out = ctx
        .run_kernel(&wgsl, &bytes, rows.len(), KernelForm::SpirvNoContraction)
        .unwrap();
    let wrong: Vec<_> = rows
        .iter()
        .zip(&out)
        .filter(|((_, want), got)| want.to_bits() != **got)
        .map(|((v, want), got)| (*v, *want, f32::from_bits(*got)))
        .collect();
    assert!(
        wrong.is_empty(),
        "{} of {} wrong on {}, first (inputs, want, got): {:?}",
        wrong.len(),
        rows.len(),
        ctx.adapter_name(),
        &wrong[..wrong.len().min(4)]
    );
    eprintln!(
        "{}: {} corrections, all correctly rounded",
        ctx.adapter_name(),
        rows.len()
    );
}
