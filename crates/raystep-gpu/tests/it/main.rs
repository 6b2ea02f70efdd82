//! raystep-gpu's integration tests, one test binary: the GPU's portable math and samplers bit
//! for bit against the CPU's, progressive renders, readbacks. They take the GPU tests' one lock
//! (`common::gpu::one_at_a_time`) and skip without an adapter (outside CI).

// Shared with the workspace's other GPU tests: the lock, the context, the shipped scenes.
#[path = "../../../../tests/it/common/gpu.rs"]
mod gpu;
#[path = "../../../../tests/it/common/scenes.rs"]
mod scenes;
mod common {
    pub(crate) use super::{gpu, scenes};
}

mod exact_arithmetic;
mod gpu_portable;
mod gpu_progressive;
mod gpu_readback;
