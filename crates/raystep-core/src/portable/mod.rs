//! Arithmetic the CPU and the GPU do step for step, so that the GPU's numbers are the CPU's bits:
//! each file here has its WGSL twin beside it, which raystep-gpu's shader generator includes
//! (the constants below), and a change to one is a change to both.
//!
//! - [`random`] (`random.wgsl`): the PCG hash and the Monte Carlo integrators' random numbers,
//!   a stateless hash of (pixel, sample, dimension, seed), and the grid of equal cells the
//!   pixel's samples and the stratified sampler's pairs are placed in.
//! - [`math`] (`math.wgsl`, `pow.wgsl`, `atan.wgsl`): `sin`, `cos`, `exp`, `ln`, `atan2` and
//!   `pow` from operations that
//!   are exactly rounded everywhere (no platform `libm`, no driver `sin`).
//!
//! raystep-gpu's `gpu_portable` tests run both on a GPU and compare the bits.

pub mod math;
pub mod random;

/// The WGSL twin of [`random`]: `pcg_hash`, `unit_float` and `mc_uniform`.
pub const RANDOM_WGSL: &str = include_str!("random.wgsl");
/// The WGSL twin of [`math`]'s `sin_cos`, `exp` and `ln` (the Monte Carlo shaders include it).
pub const MATH_WGSL: &str = include_str!("math.wgsl");
/// The WGSL twin of [`math::atan`] and [`math::atan2`], `p_atan` and `p_atan2` (textured
/// shaders include it; it calls the tracer's exact `fdiv`).
pub const ATAN_WGSL: &str = include_str!("atan.wgsl");
/// The WGSL twin of [`math::pow`], `fpow` (every tracer shader's arithmetic ends with it; it
/// calls that arithmetic's `fsqrt` and `is_finite_f`).
pub const POW_WGSL: &str = include_str!("pow.wgsl");

#[cfg(test)]
mod tests {
    /// WGSL reads a float literal as an abstract float (f64) and then rounds it to f32; Rust
    /// rounds the decimal to f32 at once. The two agree for every literal the twins share (a
    /// literal whose two roundings differed would make the GPU's constant one ulp off).
    #[test]
    fn every_wgsl_float_literal_rounds_to_the_same_f32_both_ways() {
        let mut checked = 0;
        for source in [super::MATH_WGSL, super::ATAN_WGSL, super::POW_WGSL] {
            for word in source.split(|c: char| !(c.is_ascii_alphanumeric() || c == '.' || c == '-'))
            {
                let w = word.trim_start_matches('-');
                if w.contains('.') && w.starts_with(|c: char| c.is_ascii_digit()) {
                    let (Ok(a), Ok(b)) = (w.parse::<f32>(), w.parse::<f64>()) else {
                        continue;
                    };
                    assert_eq!(a.to_bits(), (b as f32).to_bits(), "{w}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 40, "{checked}");
    }
}
