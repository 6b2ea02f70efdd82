//! What can go wrong on the GPU side, for every part of this crate.

/// What went wrong on the GPU side. Every variant is a plain message for the user.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GpuError {
    /// wgpu found no adapter at all.
    #[error(
        "no GPU adapter: wgpu found no Vulkan, Metal, DX12 or GL device ({0}). On Linux without a \
         GPU, install Mesa's software Vulkan driver lavapipe (Debian/Ubuntu package \
         mesa-vulkan-drivers)"
    )]
    NoAdapter(String),
    /// The device could not be created, or reported an error.
    #[error("GPU device error: {0}")]
    Device(String),
    /// The generated shader was rejected (a bug in raystep: please report it).
    #[error("the generated WGSL was rejected: {0}")]
    Shader(String),
    /// The scene cannot be traced on the GPU.
    #[error("{0}")]
    Scene(String),
}
