//! The Monte Carlo core: the random numbers every sample draws, the sampling routines that turn
//! them into points and directions with their densities, the BSDFs, the lights, and the
//! distribution and path integrators ([`integrator`]).
//!
//! Every random number is a stateless hash of (pixel, sample, dimension, seed)
//! ([`random::uniform`]), as the antialiasing jitter already is: a sample can be traced again, on
//! the CPU or the GPU, or given to a student's program, and draws the same numbers. Each sampler
//! takes its uniform numbers as arguments and returns what it made with the density (pdf) of
//! making it, in the measure it names (solid angle, area, or the disk's area); `tests/samplers.rs`
//! checks each against its own pdf with a χ² goodness-of-fit test.

pub mod bsdf;
pub mod integrator;
pub mod lights;
pub mod portable;
pub mod random;
pub(crate) mod record;
pub mod sample;
