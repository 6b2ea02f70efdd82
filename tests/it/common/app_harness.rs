//! The app under egui_kittest, rendered through wgpu (shared by `tests/it/app/` and
//! `tests/it/app_scene3d.rs`).

use egui_kittest::Harness;
use raystep::app::RaystepApp;
use raystep::app::state::Prefs;
use std::path::PathBuf;

/// Whether wgpu finds an adapter (lavapipe on a machine without a GPU).
pub fn have_adapter() -> bool {
    let instance = eframe::wgpu::Instance::new(
        eframe::wgpu::InstanceDescriptor::new_without_display_handle_from_env(),
    );
    !pollster::block_on(instance.enumerate_adapters(eframe::wgpu::Backends::all())).is_empty()
}

/// The whole app rendered through wgpu at 1400×860 on `file` (with the GPU view when
/// `gpu_view`), or None — after saying why — where wgpu finds no adapter. Under CI a missing
/// adapter fails the test: .ci/run installs lavapipe.
pub fn wgpu_harness(
    test: &str,
    file: Option<PathBuf>,
    gpu_view: bool,
) -> Option<Harness<'static, RaystepApp>> {
    if !have_adapter() {
        assert!(
            std::env::var("CI").is_err(),
            "CI must run {test}: install Mesa's lavapipe (mesa-vulkan-drivers)"
        );
        eprintln!("SKIPPED {test}: wgpu found no adapter (install mesa-vulkan-drivers)");
        return None;
    }
    Some(
        Harness::builder()
            .with_size(egui::vec2(1400.0, 860.0))
            .wgpu_setup(raystep::app::gpu_view_device(
                egui_kittest::wgpu::default_wgpu_setup(),
            ))
            .build_eframe(move |cc| {
                let app = RaystepApp::with_context(&cc.egui_ctx, Prefs::default(), file.clone());
                if gpu_view {
                    app.with_wgpu(cc.wgpu_render_state.clone())
                } else {
                    app
                }
            }),
    )
}
