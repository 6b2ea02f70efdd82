//! The portable sin, cos, exp and ln (crates/raystep-core/src/portable/math.rs) and their WGSL twin
//! (crates/raystep-core/src/portable/math.wgsl): on the exact compute path (SPIR-V with `NoContraction`) the GPU
//! returns the CPU's bits for every input; as plain WGSL (which a driver may contract) within a
//! few ulp.

use raystep_core::portable::math as portable;
use raystep_gpu::{KernelForm, shader::PORTABLE_WGSL};

use crate::common::gpu as gpu_common;
use gpu_common::{context, exact_context, one_at_a_time};

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

/// The Monte Carlo sampling routines' WGSL (crates/raystep-gpu/src/wgsl/mc_sample.wgsl) against src/mc: for
/// 2^15 inputs, each routine's outputs are the CPU's bits on the exact compute path.
#[test]
fn the_wgsl_samplers_return_the_cpus_bits_on_the_exact_path() {
    use glam::Vec3;
    use raystep_core::mc::{bsdf, sample};
    use raystep_core::portable::random;
    use raystep_core::trace::monte_carlo as integrator;
    use raystep_gpu::exact::arith_wgsl;
    use raystep_gpu::shader::{MC_SAMPLE_WGSL, RANDOM_WGSL};
    let _gpu = one_at_a_time();
    let test = "the_wgsl_samplers_return_the_cpus_bits_on_the_exact_path";
    let Some((ctx, arith)) = exact_context(test) else {
        return;
    };
    const OUT: usize = 32;
    let wgsl = format!(
        "{}{PORTABLE_WGSL}{RANDOM_WGSL}{MC_SAMPLE_WGSL}
@group(0) @binding(0) var<storage, read> inputs: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> outputs: array<u32>;

fn put(i: u32, k: u32, v: f32) {{
    outputs[{OUT}u * i + k] = bitcast<u32>(v);
}}

fn put4(i: u32, k: u32, v: vec4f) {{
    put(i, k, v.x); put(i, k + 1u, v.y); put(i, k + 2u, v.z); put(i, k + 3u, v.w);
}}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3u) {{
    let i = gid.x;
    if i >= arrayLength(&inputs) {{
        return;
    }}
    let x = inputs[i];
    let u = x.xy;
    let d = concentric_disk(u);
    put(i, 0u, d.x); put(i, 1u, d.y);
    put4(i, 2u, cosine_hemisphere(u));
    let sphere = uniform_sphere(u);
    put4(i, 6u, sphere);
    let t = uniform_triangle(u);
    put(i, 10u, t.x); put(i, 11u, t.y);
    put4(i, 12u, sphere_cone(x.w, 1.0, u));
    put4(i, 16u, ggx_normal(x.z, u));
    let f = frame_new(sphere.xyz);
    let w = frame_to_world(f, cosine_hemisphere(u.yx).xyz);
    put(i, 20u, w.x); put(i, 21u, w.y); put(i, 22u, w.z);
    put(i, 23u, power_heuristic(u.x, u.y));
    let fr = fresnel_dielectric(u.x, 1.0 + x.z);
    put(i, 24u, fr.x); put(i, 25u, fr.y);
    let sp = stratified_pair(vec2u(i, 7u * i), i % 37u, 1u + i % 50u, i % 1000u, 7u, u);
    put(i, 26u, sp.x); put(i, 27u, sp.y);
    put(i, 28u, mc_uniform(vec2u(i, 3u), i, 17u, 5u));
    let l = frame_to_local(f, w);
    put(i, 29u, l.x); put(i, 30u, l.y); put(i, 31u, l.z);
}}
",
        arith_wgsl(arith.config())
    );
    let n = 1u32 << 15;
    let inputs: Vec<[f32; 4]> = (0..n)
        .map(|i| {
            let u0 = random::uniform([i, 1], 0, 0, 9);
            let u1 = random::uniform([i, 1], 0, 1, 9);
            let alpha = 0.01 + random::uniform([i, 1], 0, 2, 9);
            let distance = 0.5 + 4.0 * random::uniform([i, 1], 0, 3, 9);
            [u0, u1, alpha, distance]
        })
        .collect();
    let bytes: Vec<u8> = inputs
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let out = ctx
        .run_kernel(
            &wgsl,
            &bytes,
            inputs.len() * OUT,
            KernelForm::SpirvNoContraction,
        )
        .unwrap();
    let v4 = |s: sample::Sampled<Vec3>| [s.value.x, s.value.y, s.value.z, s.pdf];
    let mut wrong = vec![0usize; OUT];
    let mut first = None;
    for (i, x) in inputs.iter().enumerate() {
        let u = [x[0], x[1]];
        let mut want = [0.0f32; OUT];
        want[0..2].copy_from_slice(&sample::concentric_disk(u));
        want[2..6].copy_from_slice(&v4(sample::cosine_hemisphere(u)));
        let sphere = sample::uniform_sphere(u);
        want[6..10].copy_from_slice(&v4(sphere));
        want[10..12].copy_from_slice(&sample::uniform_triangle(u));
        want[12..16].copy_from_slice(&sample::sphere_cone(x[3], 1.0, u).map_or([0.0; 4], v4));
        want[16..20].copy_from_slice(&v4(sample::ggx_normal(x[2], u)));
        let f = sample::Frame::new(sphere.value);
        let w = f.to_world(sample::cosine_hemisphere([u[1], u[0]]).value);
        want[20..23].copy_from_slice(&w.to_array());
        want[23] = integrator::power_heuristic(u[0], u[1]);
        let (r, t) = bsdf::fresnel_dielectric(u[0], 1.0 + x[2]);
        want[24] = r;
        want[25] = t.unwrap_or(-1.0);
        let i = i as u32;
        let sp = integrator::stratified_pair([i, 7 * i], i % 37, 1 + i % 50, i % 1000, 7, u);
        want[26..28].copy_from_slice(&sp);
        want[28] = random::uniform([i, 3], i, 17, 5);
        want[29..32].copy_from_slice(&f.to_local(w).to_array());
        for k in 0..OUT {
            let got = f32::from_bits(out[i as usize * OUT + k]);
            if !same(got, want[k]) {
                wrong[k] += 1;
                first.get_or_insert((i, k, got, want[k]));
            }
        }
    }
    assert!(
        wrong.iter().all(|&w| w == 0),
        "results that differ, by output: {wrong:?}; first (input, output, GPU, CPU): {first:?}"
    );
}
