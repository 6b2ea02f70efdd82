//! Reading the GPU's answers without waiting (what the app does in a web page, whose only thread
//! cannot wait): an answer asked for is not there before the GPU is polled, comes once, and is
//! the answer the waiting call gives; and the shaders keep to a rule of WebGPU's WGSL compilers
//! that naga does not check (no NaN or infinity as a constant).
//!
//! Tests that need an adapter print "SKIPPED: no wgpu adapter (install mesa-vulkan-drivers)" and
//! return when there is none — except on CI (the CI variable set), where that is a failure.

use raystep_core::trace::PreparedScene;
use raystep_gpu::{self as gpu, GpuPath, GpuTracer, ShaderConfig, ShaderVariant, shader};

use crate::common::gpu as gpu_common;
use gpu_common::{context, one_at_a_time};

fn scene(name: &str) -> PreparedScene {
    let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("scenes")
        .join(name);
    PreparedScene::new(raystep_core::scene::load_file(&path).unwrap())
}

/// The debug pixel, the linear image and the GPU's trace asked for without waiting: nothing
/// before the device is polled (wgpu runs a map's callback only in `poll` or `submit`), the
/// answer once after, and the same answer the waiting calls give.
#[test]
fn answers_come_once_after_a_poll_and_equal_the_waiting_calls() {
    let _gpu = one_at_a_time();
    let Some(ctx) = context("answers_come_once_after_a_poll_and_equal_the_waiting_calls") else {
        return;
    };
    let prepared = scene("three-spheres.toml");
    let mut tracer = GpuTracer::new(ctx.clone(), &prepared, ShaderVariant::Generated).unwrap();
    let (x, y) = (150, 110);

    let mut asked = tracer.start_debug_pixel(x, y).unwrap();
    assert!(asked.poll().is_none(), "the answer came before a poll");
    ctx.wait().unwrap();
    let bytes = asked.poll().expect("the answer after a poll").unwrap();
    assert!(asked.poll().is_none(), "an answer is given once");
    let later = tracer.debug_from([x, y], &bytes);
    let waited = tracer.debug_pixel(x, y).unwrap();
    assert_eq!(format!("{later:?}"), format!("{waited:?}"));
    assert!(later.object.is_some(), "the pixel hits the middle sphere");

    // A readback dropped unanswered leaves its buffer free to be mapped again (else wgpu would
    // panic: "buffer already mapped").
    drop(tracer.start_debug_pixel(x, y).unwrap());
    assert!(tracer.debug_pixel(x, y).is_ok());

    let waited = tracer.render(GpuPath::Compute).unwrap();
    let mut asked = tracer.start_read_linear().unwrap();
    assert_eq!(asked.size(), [320, 240]);
    ctx.wait().unwrap();
    let later = gpu::linear_from(&asked.poll().unwrap().unwrap());
    assert_eq!(later.len(), 320 * 240);
    assert!(
        later
            .iter()
            .zip(&waited.pixels)
            .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)),
        "the image read without waiting is the waiting read's, bit for bit"
    );

    let pending = tracer
        .start_trace_pixel(GpuPath::Compute, x, y, 0, 1 << 16)
        .unwrap();
    let waited = tracer.trace_pixel(x, y, 0, 1 << 16).unwrap();
    let mut readback = pending.readback;
    ctx.wait().unwrap();
    let bytes = readback.poll().unwrap().unwrap();
    // (The readback moved out: a trace is read from its bytes with the pixel it was asked for.)
    let again = tracer
        .start_trace_pixel(GpuPath::Compute, x, y, 0, 1 << 16)
        .unwrap();
    let later = tracer.finish_trace_of(&again, &bytes).unwrap();
    assert_eq!(later.trace.to_json(), waited.trace.to_json());
}

/// WebGPU's WGSL compilers (Chrome's Tint) evaluate a bitcast of a constant when the shader is
/// compiled and reject one whose value is a NaN or an infinity (WGSL has no such constants);
/// naga accepts it. Found in Chromium: the GPU trace shader failed to compile. No shader raystep
/// makes bitcasts a literal or a `const` to f32.
#[test]
fn no_shader_bitcasts_a_constant_to_a_float() {
    let mut shaders = vec![];
    for name in [
        "three-spheres.toml",
        "cornell-area.toml",
        "depth-of-field.toml",
        "veach-mis.toml",
        "mirror-glass.toml",
        "teapot-stadium.toml",
    ] {
        let p = scene(name);
        let config = ShaderConfig::for_scene(&p);
        let mut trace = config;
        trace.trace = true;
        shaders.push((format!("{name} (generated)"), gpu::generated_wgsl(&p)));
        shaders.push((format!("{name} (full)"), gpu::full_wgsl(&p)));
        shaders.push((format!("{name} (trace)"), shader::wgsl(&trace)));
    }
    // A literal's value: 0x7fc00000u, 1u, 2139095040u.
    let value = |lit: &str| {
        let lit = lit.trim().trim_end_matches(['u', 'i']);
        match lit.strip_prefix("0x") {
            Some(hex) => u32::from_str_radix(hex, 16).ok(),
            None => lit.parse::<u32>().ok(),
        }
    };
    let not_finite = |bits: u32| bits & 0x7f80_0000 == 0x7f80_0000;
    let mut bitcasts = 0;
    for (what, wgsl) in &shaders {
        // The constants: `const NAME: u32 = LITERAL;`.
        let constants: Vec<(&str, Option<u32>)> = wgsl
            .lines()
            .filter_map(|l| l.trim().strip_prefix("const "))
            .filter_map(|l| {
                let (name, rest) = l.split_once(':')?;
                let (_, lit) = rest.split_once('=')?;
                Some((name.trim(), value(lit.trim_end_matches(';'))))
            })
            .collect();
        for (i, _) in wgsl.match_indices("bitcast<f32>(") {
            let arg: String = wgsl[i + "bitcast<f32>(".len()..]
                .chars()
                .take_while(|c| *c != ')')
                .collect();
            let constant = value(&arg).or_else(|| {
                constants
                    .iter()
                    .find(|(n, _)| *n == arg.trim())
                    .and_then(|(_, v)| *v)
            });
            assert!(
                !constant.is_some_and(not_finite),
                "{what}: bitcast<f32>({arg}) is a constant NaN or infinity"
            );
            bitcasts += 1;
        }
    }
    assert!(bitcasts > 0, "the check saw no bitcast at all");
    assert!(shaders.len() >= 18);
}
