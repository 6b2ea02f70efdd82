//! Progressive GPU renders on the fragment path (issue 36 §4): the fragment shader adds each
//! pass's samples to every pixel's running sum (a storage buffer), in sample order, so passes of
//! 1, 1, 2 samples end on the fragment path's one-shot image. The compute path's twin is in
//! tests/it/gpu/ (`monte_carlo_scenes_on_the_gpu_are_the_cpus_image`).
//!
//! The expected image is the fragment path's own one-shot render (the fragment path is inexact
//! by design against the CPU: its ray directions are interpolated). Bit for bit where the
//! adapter compiles the two the same way (lavapipe: 0 pixels differ); the test prints the count.

use raystep_core::scene::{Integrator, load_file};
use raystep_core::trace::PreparedScene;
use raystep_gpu::{GpuPath, GpuTracer, ShaderVariant};

use crate::common::gpu as gpu_common;
use crate::common::scenes;
use gpu_common::{context, one_at_a_time};

fn bits(v: &[glam::Vec3]) -> Vec<[u32; 3]> {
    v.iter().map(|c| c.to_array().map(f32::to_bits)).collect()
}

#[test]
fn the_fragment_path_renders_progressively_to_its_one_shot_image() {
    let _gpu = one_at_a_time();
    let Some(ctx) = context("the_fragment_path_renders_progressively_to_its_one_shot_image") else {
        return;
    };
    let mut failures = vec![];
    for (name, integrator) in [
        ("cornell-area.toml", Integrator::Path),
        ("soft-shadows.toml", Integrator::Distribution),
    ] {
        let mut scene = load_file(&scenes::root().join("scenes").join(name)).unwrap();
        scene.camera.width = 48;
        scene.camera.height = 36;
        scene.settings.spp = 4;
        scene.settings.integrator = integrator;
        let prepared = PreparedScene::new(scene);
        let mut gpu = GpuTracer::new(ctx.clone(), &prepared, ShaderVariant::Generated).unwrap();
        let one_shot = gpu.render(GpuPath::Fragment).unwrap();
        let mut passes = vec![];
        let mut images = vec![];
        let last = gpu
            .render_progressive(GpuPath::Fragment, |done, frame| {
                passes.push(done);
                images.push(bits(&frame.pixels));
            })
            .unwrap();
        let differ = bits(&last.pixels)
            .iter()
            .zip(bits(&one_shot.pixels))
            .filter(|(a, b)| **a != *b)
            .count();
        eprintln!(
            "{name}: fragment path, passes ending at {passes:?}: {differ} of {} pixels differ from the one-shot image",
            last.pixels.len()
        );
        assert_eq!(passes, [1, 2, 4], "{name}");
        // The passes are images of their own (1 and 2 samples), not the final one repeated.
        assert_ne!(images[0], images[2], "{name}");
        if differ > 0 {
            failures.push(format!("{name}: {differ} pixels differ"));
        }
        // A pass a frame, as the app's GPU tab traces it: the display after the last pass is
        // the one-shot display, and after the first it is another image.
        gpu.trace(GpuPath::Fragment).unwrap();
        let display = gpu.read_display().unwrap();
        gpu.trace_pass(GpuPath::Fragment, 0, 1).unwrap();
        let first = gpu.read_display().unwrap();
        gpu.trace_pass(GpuPath::Fragment, 1, 1).unwrap();
        gpu.trace_pass(GpuPath::Fragment, 2, 2).unwrap();
        let end = gpu.read_display().unwrap();
        assert_ne!(first, display, "{name}: one sample is another image");
        if end != display {
            failures.push(format!(
                "{name}: trace_pass 1, 1, 2 does not end on the one-shot display"
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
