//! The GPU view: the same scene traced on the GPU with wgpu, by a WGSL tracer generated for the
//! scene, and compared with the CPU render.
//!
//! - [`shader`]: the WGSL, assembled from the pieces in `crates/raystep-gpu/src/wgsl/` (one per stage of a
//!   hardware ray-tracing pipeline: ray generation, traversal, intersection, any-hit,
//!   closest-hit, miss) according to the scene's [`crate::scene::Features`]; [`generated_wgsl`]
//!   and [`full_wgsl`] return it, [`shader::validate`] checks it with naga without a GPU.
//! - [`GpuTracer`]: the scene uploaded (objects, materials, lights, the BVH flattened into
//!   storage buffers), two ways to make primary rays ([`GpuPath::Fragment`]: a full-screen
//!   triangle whose ray directions the rasterizer interpolates; [`GpuPath::Compute`]: one
//!   invocation per pixel), frame timing, readback and the [debug pixel](GpuTracer::debug_pixel).
//! - [`difference`]: CPU against GPU — RMSE, max error, differing pixels, a difference image.
//!
//! The tracer is software ray tracing in WGSL on any adapter. Where the device has hardware ray
//! queries (`EXPERIMENTAL_RAY_QUERY`; [`GpuContext::headless`] requests it where the adapter
//! offers it), the finite objects go into a BLAS as procedural boxes under a one-instance TLAS,
//! and `traversal_closest`/`traversal_any` become ray queries whose candidates are decided by the
//! same WGSL intersection functions (so the numbers stay the CPU's); planes are tested first as
//! on the CPU. [`GpuTracer::adapter_line`] says which traversal runs, and which arithmetic.
//! Mesa 25's lavapipe offers ray queries (CI runs the tests on it); the debug pixel's BVH node
//! count is 0 there and [`PixelDebug::hardware_traversal`] says why (the hardware's traversal is
//! not observable).
//!
//! # How the app should use this
//!
//! ```ignore
//! // Once, in the app's constructor (cc: &eframe::CreationContext):
//! let rs = cc.wgpu_render_state.as_ref().expect("the wgpu backend");
//! let ctx = GpuContext::from_device(
//!     rs.device.clone(), rs.queue.clone(), rs.adapter.get_info(), rs.adapter.features());
//! let mut gpu = GpuTracer::new(ctx, &scene, ShaderVariant::Generated)?;
//! // Each path's pipeline is compiled on its first frame (or by gpu.prepare(path)): a driver
//! // compiles the whole tracer for each, and lavapipe takes seconds to do it.
//! // Per frame (or when the scene or camera changed): trace, then show the texture.
//! gpu.set_camera(&camera)?;                  // optional: another view or size
//! let time = gpu.trace(GpuPath::Fragment)?;  // blocks until done; or gpu.encode(&mut encoder, path)
//! let id = rs.renderer.write().register_native_texture(
//!     &rs.device, gpu.display_view(), wgpu::FilterMode::Nearest);
//! // (re-register after set_camera changed the size; otherwise update_egui_texture_from_wgpu_texture)
//! ui.label(gpu.adapter_line(GpuPath::Fragment));
//! ui.code(gpu.wgsl());                        // the generated shader
//! let pick = gpu.debug_pixel(x, y)?;         // hit object, t, u, v, discriminant, BVH nodes
//! // CPU against GPU: render both and compare the linear images.
//! let frame = gpu.render(GpuPath::Compute)?;   // linear pixels; gpu.read_display() gives the RGBA8
//! let diff = difference(frame.width, frame.height, &cpu.pixels, &frame.pixels)?;
//! ```
//!
//! Headless (the command line, the tests): [`GpuContext::headless`] opens its own device; it fails
//! with [`GpuError::NoAdapter`], whose message says what to install, when wgpu finds no adapter.
//!
//! # How GPU and CPU differ
//!
//! The WGSL repeats the CPU's f32 arithmetic operation for operation (the stable sphere formula,
//! the watertight triangle test, the robust slab test, pbrt-v4's ray offsets, the same γₙ
//! constants, one portable `pow`). Where the adapter takes SPIR-V passthrough, the compute path
//! is loaded as SPIR-V with every float result decorated `NoContraction`, and a start-up probe
//! picks correctly rounded division and square root and an exact `mul_add` ([`exact`]): the
//! compute path then computes the CPU's image ([`GpuTracer::exact`]; the linear sums of reflected
//! and refracted colours are added in the ray stack's order, so those may differ in the last bit
//! of the linear value, not in the 8-bit image). Elsewhere the images differ where the GPU rounds
//! differently:
//! - The GPU compiler may fuse a·b + c into an FMA and evaluate `dot` in its own order, and its
//!   `/` and `sqrt` may be a few ulp off: last-bit differences, visible only where they flip a
//!   decision (a silhouette pixel, a shadow-ray hit at grazing angles, acne, a leaky edge).
//! - The fragment path's ray direction is interpolated by the rasterizer across the full-screen
//!   triangle, not computed per pixel: it is inexact by design, whatever the arithmetic.
//! - The watertight triangle test's fallback for an edge function of exactly 0 uses Dekker's
//!   exact products instead of f64 (WGSL has no f64): same sign, value within about an ulp.
//! - With spp > 1, both sides place samples identically (the same PCG hash in WGSL); the fragment
//!   path offsets them from the interpolated centre direction.
//! - A Monte Carlo scene (`distribution` or `path`) is traced by `wgsl/mc_integrator.wgsl` with the
//!   CPU's random numbers ([`crate::portable::random::uniform`], the same dimensions) and the portable
//!   `sin`/`cos` of [`crate::portable::math`]: on the exact compute path the CPU's image bit for bit,
//!   also when rendered progressively ([`GpuTracer::render_progressive`]). On the fragment path
//!   each sample's path leaves the CPU's after its first bounce (the interpolated direction), so
//!   only the image's statistics agree.
#![deny(unsafe_code)]
#![warn(missing_docs)]

// The layers below, by the names the modules use for them.
use raystep_core::{accel, math, mc, platform, record, render, scene, shapes, trace};
use raystep_diagram as diagram;

pub mod view3d;

mod buffers;
pub mod compare;
mod context;
mod error;
pub mod exact;
pub mod interface;
pub mod shader;
pub mod trace_log;
mod tracer;

pub use compare::{Difference, difference};
pub use context::{KernelForm, NOT_IN_BROWSER, Readback, TextureReadback};
pub use error::GpuError;
pub use shader::{ShaderConfig, ShaderVariant, full_wgsl, generated_wgsl};
pub use trace_log::GpuTrace;
pub use tracer::{
    DISPLAY_FORMAT, GpuContext, GpuFrame, GpuPath, GpuTracer, PendingTrace, PixelDebug, linear_from,
};
