//! The portable sin, cos, exp and ln (src/mc/portable.rs) and their WGSL twin
//! (src/gpu/wgsl/portable.wgsl): on the exact compute path (SPIR-V with `NoContraction`) the GPU
//! returns the CPU's bits for every input; as plain WGSL (which a driver may contract) within a
//! few ulp.

use raystep::gpu::{KernelForm, shader::PORTABLE_WGSL};
use raystep::mc::portable;

#[path = "common/gpu.rs"]
#[allow(dead_code)]
mod gpu_common;
use gpu_common::{context, one_at_a_time};

/// A kernel that writes, for each input (x, y, z, _), sin x, cos x, exp y and ln z.
fn kernel() -> String {
    format!(
        "{PORTABLE_WGSL}
@group(0) @binding(0) var<storage, read> inputs: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> outputs: array<u32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3u) {{
    let i = gid.x;
    if i >= arrayLength(&inputs) {{
        return;
    }}
    let v = inputs[i];
    let sc = p_sin_cos(v.x);
    outputs[4u * i] = bitcast<u32>(sc.x);
    outputs[4u * i + 1u] = bitcast<u32>(sc.y);
    outputs[4u * i + 2u] = bitcast<u32>(p_exp(v.y));
    outputs[4u * i + 3u] = bitcast<u32>(p_ln(v.z));
}}
"
    )
}

/// Inputs: sin/cos on [0, 2π) (where sampling calls it: φ = 2πu and the concentric map's
/// angles) and ±[0, 100]; exp on [−90, 90]; ln over every binade and the special values.
fn inputs() -> Vec<[f32; 4]> {
    let n = 1 << 16;
    let mut v = Vec::with_capacity(n + 8);
    for i in 0..n {
        let t = i as f32 / n as f32;
        let x = if i % 4 == 3 {
            (t - 0.5) * 200.0
        } else {
            2.0 * std::f32::consts::PI * t
        };
        let y = -90.0 + 180.0 * t;
        // Spread over the exponents: 2^(−126 … 127) times a mantissa from the index.
        let z = f32::from_bits(
            ((1 + (i * 254) / n) as u32) << 23 | ((i as u32).wrapping_mul(2_654_435_761) >> 9),
        );
        v.push([x, y, z, 0.0]);
    }
    v.push([f32::NAN, f32::NAN, f32::NAN, 0.0]);
    v.push([f32::INFINITY, 100.0, 0.0, 0.0]);
    v.push([-0.0, -100.0, -1.0, 0.0]);
    v.push([1e-30, 88.7, f32::INFINITY, 0.0]);
    v
}

fn cpu(x: [f32; 4]) -> [f32; 4] {
    let (s, c) = portable::sin_cos(x[0]);
    [s, c, portable::exp(x[1]), portable::ln(x[2])]
}

/// Same bits, with any NaN equal to any NaN.
fn same(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

#[test]
fn the_wgsl_twin_returns_the_cpus_bits_on_the_exact_path() {
    let _gpu = one_at_a_time();
    let test = "the_wgsl_twin_returns_the_cpus_bits_on_the_exact_path";
    let Some(ctx) = context(test) else {
        return;
    };
    let inputs = inputs();
    let bytes: Vec<u8> = inputs
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let wgsl = kernel();
    let run = |form: KernelForm| -> Vec<[f32; 4]> {
        let out = ctx
            .run_kernel(&wgsl, &bytes, inputs.len() * 4, form)
            .unwrap();
        out.chunks_exact(4)
            .map(|c| [0, 1, 2, 3].map(|k| f32::from_bits(c[k])))
            .collect()
    };
    // As plain WGSL: the driver may contract; within 4 ulp (or 2^-22 absolute near a zero).
    let plain = run(KernelForm::Wgsl);
    let mut differ = 0;
    for (x, g) in inputs.iter().zip(&plain) {
        let w = cpu(*x);
        for k in 0..4 {
            if same(g[k], w[k]) {
                continue;
            }
            differ += 1;
            let ulps = (g[k].to_bits() as i64 - w[k].to_bits() as i64).abs();
            assert!(
                ulps <= 4 || (g[k] - w[k]).abs() <= 2f32.powi(-22),
                "input {x:?}, output {k}: GPU {:e} vs CPU {:e}",
                g[k],
                w[k]
            );
        }
    }
    eprintln!(
        "{}: as WGSL, {differ} of {} results differ from the CPU's bits (all within 4 ulp)",
        ctx.adapter_name(),
        inputs.len() * 4
    );
    if !ctx.passthrough {
        eprintln!(
            "SKIPPED the exact half of {test}: {} takes no SPIR-V passthrough",
            ctx.adapter_name()
        );
        return;
    }
    let exact = run(KernelForm::SpirvNoContraction);
    let wrong: Vec<_> = inputs
        .iter()
        .zip(&exact)
        .flat_map(|(x, g)| {
            let w = cpu(*x);
            (0..4)
                .filter(move |&k| !same(g[k], w[k]))
                .map(move |k| (*x, k, g[k], w[k]))
        })
        .collect();
    assert!(
        wrong.is_empty(),
        "{} of {} differ, first: {:?}",
        wrong.len(),
        inputs.len() * 4,
        &wrong[..wrong.len().min(5)]
    );
}
