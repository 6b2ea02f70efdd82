//! The WGSL arithmetic every tracer shader starts with, in the variant the probe picked: the
//! `arith*.wgsl` files beside this one, and `fpow` from raystep-core's portable math.

/// Which arithmetic the generated WGSL uses (decided by the [`Probe`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ArithConfig {
    /// `fma` is truly fused: `fmaf` is WGSL's `fma`; otherwise [`fma_emulated`].
    pub fma_fused: bool,
    /// `/` gets the residual step ([`corrected_div`]).
    pub div_fix: bool,
    /// `sqrt` gets the residual step ([`corrected_sqrt`]).
    pub sqrt_fix: bool,
    /// A planted divergence, for tests: `fdot` as a chain of fused multiply-adds (what NVIDIA's
    /// driver makes of WGSL's `dot`) instead of glam's sum. Never chosen by the probe.
    pub fused_dot: bool,
}

/// The arithmetic helpers every tracer shader starts with: `fmaf` (Rust's `mul_add`), `fdiv`,
/// `fdiv3`, `fsqrt`, `flen` (glam's `length`: √(v·v)), `fcross` (glam's order) and `fpow`
/// ([`raystep_core::portable::math::pow`]), in the variant `c` picks.
pub fn arith_wgsl(c: ArithConfig) -> String {
    let mut s = String::from(include_str!("arith.wgsl"));
    s += if c.fma_fused {
        "// Rust's mul_add: the driver's fma is fused (the probe checked).\n\
         fn fmaf(a: f32, b: f32, c: f32) -> f32 {\n    return fma(a, b, c);\n}\n\n"
    } else {
        "// Rust's mul_add: the driver's fma is not fused (the probe checked), so it is emulated.\n\
         fn fmaf(a: f32, b: f32, c: f32) -> f32 {\n    return fma_emulated(a, b, c);\n}\n\n"
    };
    s += if c.div_fix {
        include_str!("arith_fdiv_corrected.wgsl")
    } else {
        "// a / b: the driver's division is correctly rounded (the probe checked) or cannot be fixed.\n\
         fn fdiv(a: f32, b: f32) -> f32 {\n    return a / b;\n}\n\n"
    };
    s += if c.sqrt_fix {
        include_str!("arith_fsqrt_corrected.wgsl")
    } else {
        "// √x: the driver's sqrt is correctly rounded (the probe checked) or cannot be fixed.\n\
         fn fsqrt(x: f32) -> f32 {\n    return sqrt(x);\n}\n\n"
    };
    s += if c.fused_dot {
        "// A planted divergence (tests only): the dot product as a chain of fused multiply-adds.\n\
         fn fdot(a: vec3f, b: vec3f) -> f32 {\n    return fmaf(a.z, b.z, fmaf(a.y, b.y, a.x * b.x));\n}\n\n"
    } else {
        include_str!("arith_fdot.wgsl")
    };
    s += include_str!("arith_tail.wgsl");
    s.push_str(raystep_core::portable::POW_WGSL);
    s.push('\n');
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every variant the probe can pick (and the planted fused dot) is valid WGSL, with the
    /// probe kernel that calls the corrected division and square root directly.
    #[test]
    fn every_arithmetic_variant_validates() {
        for bits in 0u32..16 {
            let b = |k: u32| bits & (1 << k) != 0;
            let c = ArithConfig {
                fma_fused: b(0),
                div_fix: b(1),
                sqrt_fix: b(2),
                fused_dot: b(3),
            };
            let wgsl = arith_wgsl(c);
            assert_eq!(wgsl.contains("corrected_div(a / b"), c.div_fix, "{c:?}");
            assert_eq!(wgsl.contains("corrected_sqrt(s, x"), c.sqrt_fix, "{c:?}");
            crate::shader::validate(&wgsl).unwrap_or_else(|e| panic!("{c:?}:\n{e}"));
        }
        crate::shader::validate(&super::super::probe_wgsl()).unwrap();
    }
}
