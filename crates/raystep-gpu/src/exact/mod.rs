//! Exact f32 on a GPU: the same bits as the CPU, where the driver allows it.
//!
//! Three things make a GPU's f32 differ from the CPU's, even when the WGSL repeats the CPU's
//! operations one for one (measured on an NVIDIA H200 and on lavapipe, see book/gpu.md):
//!
//! 1. **Contraction.** A shader compiler may fuse `a*b + c` into one FMA (one rounding instead of
//!    two) and evaluate `dot` as an FMA chain. WGSL cannot forbid it; SPIR-V can: the
//!    `NoContraction` decoration on an arithmetic result. [`spirv_no_contraction`] compiles the
//!    generated WGSL to SPIR-V with naga and decorates every float arithmetic result, and the
//!    tracer loads it through wgpu's passthrough (`Features::PASSTHROUGH_SHADERS`) where the
//!    adapter offers it.
//! 2. **Approximate division and square root.** Vulkan allows `/` and `sqrt` to be a few ulp off
//!    (the H200's are ≤ 2 and ≤ 1). Where the FMA is truly fused, one residual step and an exact
//!    decision at the midpoint next to its result make them correctly rounded ([`corrected_div`],
//!    [`corrected_sqrt`]); where the division is already
//!    exact (lavapipe) that step would *break* it, so it is applied only where the probe below
//!    shows it helps.
//! 3. **An unfused `fma`.** WGSL's `fma` may be a plain multiply and add (lavapipe's is). The
//!    watertight triangle test needs Rust's `mul_add`; where the probe finds `fma` unfused it is
//!    computed exactly from Dekker's two-product instead ([`fma_emulated`]).
//!
//! `pow` is the fourth: WGSL's is `exp2(y·log2(x))` at reduced precision. The CPU and the GPU
//! both use [`raystep_core::portable::math::pow`] instead (multiplications and square roots
//! only).
//!
//! [`Arithmetic`] is what a device gets: a tiny probe kernel ([`probe_wgsl`]) runs once on known
//! hard inputs, and its answers ([`Probe`]) decide the variant ([`ArithConfig`]) the tracer's
//! WGSL is generated with ([`arith_wgsl`]). The fragment path stays inexact by design: its ray
//! directions are interpolated by the rasterizer, not computed as on the CPU.
//!
//! One job a file: `spirv.rs` (SPIR-V with `NoContraction`), `dekker.rs` (the CPU's model of the
//! arithmetic), `arith.rs` with its `arith*.wgsl` (the WGSL the tracer is generated with),
//! `probe.rs` (the start-up probe); the [`Arithmetic`] a device gets is here.

mod arith;
mod dekker;
mod probe;
mod spirv;

pub use arith::*;
pub use dekker::*;
pub use probe::*;
pub use spirv::*;

/// The arithmetic a device runs the compute path with.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Arithmetic {
    /// The tracer is loaded as SPIR-V with `NoContraction` (the adapter offers passthrough).
    pub spirv: bool,
    /// The SPIR-V also asks for subnormals to be kept ([`preserve_denormals`]).
    pub float_controls: bool,
    /// The probe's answers, in the same form (SPIR-V or WGSL) the tracer is loaded in.
    pub probe: Probe,
}

impl Arithmetic {
    /// The WGSL variant the tracer is generated with.
    pub fn config(&self) -> ArithConfig {
        self.probe.config()
    }

    /// Whether the compute path computes the CPU's bits: SPIR-V with `NoContraction` and every
    /// probed operation as on the CPU.
    pub fn exact(&self) -> bool {
        self.spirv && self.probe.exact()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_probe_compiles_to_spirv_with_no_contraction_decorations() {
        let (words, n) = spirv_no_contraction(&probe_wgsl()).unwrap();
        assert!(n > 20, "{n} decorations");
        let decorations = words
            .windows(3)
            .filter(|w| w[0] == (3 << 16) | OP_DECORATE && w[2] == NO_CONTRACTION)
            .count();
        assert!(decorations >= n, "{decorations} of {n}");
    }
}
