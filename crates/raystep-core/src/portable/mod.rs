//! Arithmetic the CPU and the GPU do step for step, so that the GPU's numbers are the CPU's bits:
//! each file here has its WGSL twin beside it, which raystep-gpu's shader generator includes
//! (the constants below), and a change to one is a change to both.
//!
//! - [`random`] (`random.wgsl`): the PCG hash and the Monte Carlo integrators' random numbers,
//!   a stateless hash of (pixel, sample, dimension, seed).
//! - [`math`] (`math.wgsl`, `pow.wgsl`): `sin`, `cos`, `exp`, `ln` and `pow` from operations that
//!   are exactly rounded everywhere (no platform `libm`, no driver `sin`).
//!
//! raystep-gpu's `gpu_portable` tests run both on a GPU and compare the bits.

pub mod math;
pub mod random;

/// The WGSL twin of [`random`]: `pcg_hash`, `unit_float` and `mc_uniform`.
pub const RANDOM_WGSL: &str = include_str!("random.wgsl");
/// The WGSL twin of [`math`]'s `sin_cos`, `exp` and `ln` (the Monte Carlo shaders include it).
pub const MATH_WGSL: &str = include_str!("math.wgsl");
/// The WGSL twin of [`math::pow`], `fpow` (every tracer shader's arithmetic ends with it; it
/// calls that arithmetic's `fsqrt` and `is_finite_f`).
pub const POW_WGSL: &str = include_str!("pow.wgsl");
