//! The GPU tests' shared preamble (tests/it/gpu/, tests/it/gpu_trace.rs): one test at a time on the
//! GPU, and the headless context or a skip.

use raystep_gpu::{GpuContext, GpuError};

/// Holds the GPU for one test at a time where that is needed: NVIDIA's Vulkan driver (580, on
/// an H200) hangs when several tests of one binary create devices, or start `raystep --gpu`, at
/// the same time (one at a time tests/it/gpu/ runs in about 26 s there). Elsewhere (lavapipe, a
/// CPU adapter whose shader compiles take one core each) the tests run side by side: `None`.
/// `RAYSTEP_GPU_TESTS_SERIAL=1` asks for one at a time anyway.
pub fn one_at_a_time() -> Option<std::sync::MutexGuard<'static, ()>> {
    static GPU: std::sync::Mutex<()> = std::sync::Mutex::new(());
    static SERIAL: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let serial = *SERIAL.get_or_init(|| {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
        const NVIDIA: u32 = 0x10de;
        std::env::var_os("RAYSTEP_GPU_TESTS_SERIAL").is_some()
            || adapters.iter().any(|a| a.get_info().vendor == NVIDIA)
    });
    // A test that failed while holding it leaves it poisoned; the next still runs.
    serial.then(|| GPU.lock().unwrap_or_else(|e| e.into_inner()))
}

/// The headless context, or None (after printing why) where wgpu finds no adapter. Under CI
/// (the `CI` variable set) there must be one.
pub fn context(test: &str) -> Option<GpuContext> {
    match GpuContext::headless() {
        Ok(c) => Some(c),
        Err(GpuError::NoAdapter(e)) => {
            assert!(
                std::env::var("CI").is_err(),
                "CI must run the GPU tests: install Mesa's lavapipe (mesa-vulkan-drivers): {e}"
            );
            eprintln!("SKIPPED {test}: no wgpu adapter (install mesa-vulkan-drivers)");
            None
        }
        Err(e) => panic!("{e}"),
    }
}

/// [`context`], and its arithmetic, where the adapter has the exact compute path (SPIR-V
/// passthrough and the probe's exact arithmetic); `None`, saying why, where it has not.
#[allow(dead_code)]
pub fn exact_context(test: &str) -> Option<(GpuContext, raystep_gpu::exact::Arithmetic)> {
    let ctx = context(test)?;
    let arith = ctx.arithmetic().unwrap();
    if !ctx.passthrough || !arith.exact() {
        eprintln!(
            "SKIPPED {test}: {} has no exact compute path",
            ctx.adapter_name()
        );
        return None;
    }
    Some((ctx, arith))
}

/// A scene file, set to Whitted's integrator: the Whitted comparisons run every shipped scene
/// under it (the Monte Carlo integrators on the GPU have their own test in tests/it/gpu/).
#[allow(dead_code)]
pub fn load_whitted(path: &std::path::Path) -> raystep_core::scene::Scene {
    let mut scene = raystep_core::scene::load_file(path).unwrap();
    scene.settings.integrator = raystep_core::scene::Integrator::Whitted;
    scene
}
