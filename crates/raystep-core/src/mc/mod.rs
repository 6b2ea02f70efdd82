//! The Monte Carlo samplers: the sampling routines that turn uniform numbers into points and
//! directions with their densities ([`sample`]), the BSDFs ([`bsdf`]) and the lights
//! ([`lights`]). The integrators that draw from them are in [`crate::trace`] (`distribution.rs`,
//! `path.rs`), beside Whitted's.
//!
//! Every random number is a stateless hash of (pixel, sample, dimension, seed)
//! ([`crate::portable::random::uniform`]), as the antialiasing jitter already is: a sample can be traced again, on
//! the CPU or the GPU, or given to a student's program, and draws the same numbers. Each sampler
//! takes its uniform numbers as arguments and returns what it made with the density (pdf) of
//! making it, in the measure it names (solid angle, area, or the disk's area); `crates/raystep-core/tests/it/samplers.rs`
//! checks each against its own pdf with a χ² goodness-of-fit test.

pub mod bsdf;
pub mod lights;
pub mod sample;
