//! Exact f32 on a GPU: the same bits as the CPU, where the driver allows it.
//!
//! Three things make a GPU's f32 differ from the CPU's, even when the WGSL repeats the CPU's
//! operations one for one (measured on an NVIDIA H200 and on lavapipe, see the README):
//!
//! 1. **Contraction.** A shader compiler may fuse `a*b + c` into one FMA (one rounding instead of
//!    two) and evaluate `dot` as an FMA chain. WGSL cannot forbid it; SPIR-V can: the
//!    `NoContraction` decoration on an arithmetic result. [`spirv_no_contraction`] compiles the
//!    generated WGSL to SPIR-V with naga and decorates every float arithmetic result, and the
//!    tracer loads it through wgpu's passthrough (`Features::PASSTHROUGH_SHADERS`) where the
//!    adapter offers it.
//! 2. **Approximate division and square root.** Vulkan allows `/` and `sqrt` to be a few ulp off
//!    (the H200's are ≤ 2 and ≤ 1). Where the FMA is truly fused, one residual step makes them
//!    correctly rounded ([`corrected_div`], [`corrected_sqrt`]); where the division is already
//!    exact (lavapipe) that step would *break* it, so it is applied only where the probe below
//!    shows it helps.
//! 3. **An unfused `fma`.** WGSL's `fma` may be a plain multiply and add (lavapipe's is). The
//!    watertight triangle test needs Rust's `mul_add`; where the probe finds `fma` unfused it is
//!    computed exactly from Dekker's two-product instead ([`fma_emulated`]).
//!
//! `pow` is the fourth: WGSL's is `exp2(y·log2(x))` at reduced precision. The CPU and the GPU
//! both use [`crate::trace::shading::portable_pow`] instead (multiplications and square roots
//! only).
//!
//! [`Arithmetic`] is what a device gets: a tiny probe kernel ([`probe_wgsl`]) runs once on known
//! hard inputs, and its answers ([`Probe`]) decide the variant ([`ArithConfig`]) the tracer's
//! WGSL is generated with ([`arith_wgsl`]). The fragment path stays inexact by design: its ray
//! directions are interpolated by the rasterizer, not computed as on the CPU.

/// SPIR-V opcodes of float arithmetic whose results are decorated `NoContraction`.
const FLOAT_ARITHMETIC: [u32; 12] = [
    127, // OpFNegate
    129, // OpFAdd
    131, // OpFSub
    133, // OpFMul
    136, // OpFDiv
    137, // OpFRem
    141, // OpFMod
    142, // OpVectorTimesScalar
    143, // OpMatrixTimesScalar
    144, // OpVectorTimesMatrix
    145, // OpMatrixTimesVector
    148, // OpDot
];
const OP_EXT_INST: u32 = 12;
const OP_TYPE_FLOAT: u32 = 22;
const OP_TYPE_VECTOR: u32 = 23;
const OP_DECORATE: u32 = 71;
const OP_MEMBER_DECORATE: u32 = 72;
const NO_CONTRACTION: u32 = 42;

/// Compiles WGSL to SPIR-V 1.3 (1.4 with ray queries) with naga, all entry points, and decorates
/// every float arithmetic result `NoContraction` ([`decorate_no_contraction`]). Returns the
/// words and the number of decorations added.
pub fn spirv_no_contraction(wgsl: &str) -> Result<(Vec<u32>, usize), String> {
    let mut words = spirv(wgsl)?;
    let n = decorate_no_contraction(&mut words)?;
    Ok((words, n))
}

/// One SPIR-V instruction: its word offset, opcode and words.
type Instruction<'a> = (usize, u32, &'a [u32]);

/// A SPIR-V module's instructions after its 5-word header: (word offset, opcode, the
/// instruction's words). Errors on a module that is not SPIR-V or an instruction that runs past
/// its end.
fn instructions(words: &[u32]) -> Result<Vec<Instruction<'_>>, String> {
    if words.len() < 5 || words[0] != 0x0723_0203 {
        return Err("not a SPIR-V module".into());
    }
    let mut out = vec![];
    let mut at = 5;
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        if count == 0 || at + count > words.len() {
            return Err(format!("malformed SPIR-V instruction at word {at}"));
        }
        out.push((at, words[at] & 0xffff, &words[at..at + count]));
        at += count;
    }
    Ok(out)
}

const OP_EXTENSION: u32 = 10;
const OP_ENTRY_POINT: u32 = 15;
const OP_EXECUTION_MODE: u32 = 16;
const OP_CAPABILITY: u32 = 17;
const CAPABILITY_DENORM_PRESERVE: u32 = 4464;
const EXECUTION_MODE_DENORM_PRESERVE: u32 = 4459;

/// Asks for 32-bit subnormals to be kept (`SPV_KHR_float_controls`: capability
/// `DenormPreserve`, execution mode `DenormPreserve 32` on every entry point), as the CPU keeps
/// them. A driver that cannot may still flush them: the probe, compiled the same way, says
/// whether it did ([`Probe::subnormals_kept`]). Only used where the probe without it found
/// subnormals flushed and the probe with it found them kept and nothing else worse.
pub fn preserve_denormals(words: &mut Vec<u32>) -> Result<(), String> {
    let (mut after_capabilities, mut after_entry_points) = (None, None);
    let mut entries = vec![];
    for (at, op, ins) in instructions(words)? {
        match op {
            OP_CAPABILITY => after_capabilities = Some(at + ins.len()),
            OP_ENTRY_POINT => {
                entries.push(ins[2]);
                after_entry_points = Some(at + ins.len());
            }
            _ => {}
        }
    }
    let (Some(caps), Some(eps)) = (after_capabilities, after_entry_points) else {
        return Err("a SPIR-V module without capabilities or entry points".into());
    };
    let mut modes = vec![];
    for e in entries {
        modes.extend([
            (4 << 16) | OP_EXECUTION_MODE,
            e,
            EXECUTION_MODE_DENORM_PRESERVE,
            32,
        ]);
    }
    // The extension's name, NUL-terminated, in little-endian words.
    let mut name = b"SPV_KHR_float_controls".to_vec();
    name.resize(name.len() / 4 * 4 + 4, 0);
    let mut head = vec![(2 << 16) | OP_CAPABILITY, CAPABILITY_DENORM_PRESERVE];
    head.push(((1 + name.len() as u32 / 4) << 16) | OP_EXTENSION);
    head.extend(
        name.chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
    );
    // Entry points come after the capabilities: insert the later position first.
    words.splice(eps..eps, modes);
    words.splice(caps..caps, head);
    Ok(())
}

/// Compiles WGSL to SPIR-V 1.3 (1.4 with ray queries) with naga, all entry points, without any
/// `NoContraction` decoration.
pub fn spirv(wgsl: &str) -> Result<Vec<u32>, String> {
    let module = naga::front::wgsl::parse_str(wgsl).map_err(|e| e.emit_to_string(wgsl))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default() | naga::valid::Capabilities::RAY_QUERY,
    )
    .validate(&module)
    .map_err(|e| e.emit_to_string(wgsl))?;
    let ray_query = wgsl.starts_with("enable wgpu_ray_query");
    let options = naga::back::spv::Options {
        lang_version: if ray_query { (1, 4) } else { (1, 3) },
        flags: naga::back::spv::WriterFlags::ADJUST_COORDINATE_SPACE
            | naga::back::spv::WriterFlags::LABEL_VARYINGS,
        // No binding map: each resource keeps its WGSL group and binding.
        fake_missing_bindings: true,
        bounds_check_policies: naga::proc::BoundsCheckPolicies {
            index: naga::proc::BoundsCheckPolicy::Restrict,
            buffer: naga::proc::BoundsCheckPolicy::Restrict,
            image_load: naga::proc::BoundsCheckPolicy::Restrict,
            binding_array: naga::proc::BoundsCheckPolicy::Unchecked,
        },
        ..Default::default()
    };
    naga::back::spv::write_vec(&module, &info, &options, None)
        .map_err(|e| format!("naga's SPIR-V writer: {e}"))
}

/// Adds `OpDecorate <id> NoContraction` for the result of every float arithmetic instruction
/// (OpFNegate, OpFAdd, OpFSub, OpFMul, OpFDiv, OpFRem, OpFMod, the vector and matrix products,
/// OpDot, and extended instructions — Fma, Sqrt, … — whose result is a float or float vector),
/// inserted before the module's first decoration. Returns how many were added.
pub fn decorate_no_contraction(words: &mut Vec<u32>) -> Result<usize, String> {
    let mut float_types = std::collections::HashSet::new();
    let mut targets = vec![];
    let mut first_decoration = None;
    for (at, op, ins) in instructions(words)? {
        let count = ins.len();
        match op {
            OP_TYPE_FLOAT => {
                float_types.insert(ins[1]);
            }
            OP_TYPE_VECTOR if float_types.contains(&ins[2]) => {
                float_types.insert(ins[1]);
            }
            OP_DECORATE | OP_MEMBER_DECORATE if first_decoration.is_none() => {
                first_decoration = Some(at);
            }
            _ if count >= 3
                && (FLOAT_ARITHMETIC.contains(&op) || op == OP_EXT_INST)
                && float_types.contains(&ins[1]) =>
            {
                targets.push(ins[2]);
            }
            _ => {}
        }
    }
    let at = first_decoration.ok_or("the SPIR-V module has no decorations section")?;
    let decorations: Vec<u32> = targets
        .iter()
        .flat_map(|&id| [(3 << 16) | OP_DECORATE, id, NO_CONTRACTION])
        .collect();
    words.splice(at..at, decorations);
    Ok(targets.len())
}

// ---------------------------------------------------------------------------------------------
// The CPU's model of the GPU arithmetic (the WGSL in `arith_wgsl` repeats these step by step)
// ---------------------------------------------------------------------------------------------

/// Knuth's TwoSum: `(s, e)` with `s = a + b` rounded and `s + e = a + b` exactly (no overflow).
pub fn two_sum(a: f32, b: f32) -> (f32, f32) {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    (s, e)
}

/// Veltkamp's split: `a = hi + lo`, each half with at most 12 significant bits.
pub fn split(a: f32) -> (f32, f32) {
    let c = 4097.0 * a;
    let hi = c - (c - a);
    (hi, a - hi)
}

/// Dekker's two-product: `(p, e)` with `p = a·b` rounded and `p + e = a·b` exactly, with plain
/// multiplications and additions only (valid when nothing is contracted, nothing overflows and
/// `e` is not subnormal).
pub fn two_prod(a: f32, b: f32) -> (f32, f32) {
    let p = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    let e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
    (p, e)
}

/// `a·b + c` rounded once, as `f32::mul_add`, without a fused multiply-add: the product split
/// exactly by [`two_prod`], summed by [`two_sum`], the low part rounded to odd before the last
/// addition (Boldo and Melquiond's trick, so the two roundings make one). Not finite: `a*b + c`.
pub fn fma_emulated(a: f32, b: f32, c: f32) -> f32 {
    let (p, e) = two_prod(a, b);
    let (s, t) = two_sum(p, c);
    let (u, v) = two_sum(t, e);
    let r = s + round_to_odd(u, v);
    if r.is_finite() && e.is_finite() {
        r
    } else {
        a * b + c
    }
}

/// `u` (the rounded `u + v`, `v` its exact error) rounded to odd: unchanged when exact or odd,
/// otherwise one ulp towards `v`.
fn round_to_odd(u: f32, v: f32) -> f32 {
    let bits = u.to_bits();
    if v == 0.0 || bits & 1 == 1 {
        return u;
    }
    if (u > 0.0) == (v > 0.0) {
        f32::from_bits(bits + 1)
    } else {
        f32::from_bits(bits - 1)
    }
}

/// One residual step on an approximate quotient `q ≈ a / b` (`inv_b ≈ 1 / b`, also
/// approximate), with a fused `fma`: `fma(fma(−q, b, a), inv_b, q)`. Correctly rounds a `q`
/// within 2 ulp (tested with an emulated divider). Left as `q` where the step cannot help: a zero,
/// infinite or NaN quotient or residual.
pub fn corrected_div(
    q: f32,
    a: f32,
    b: f32,
    inv_b: f32,
    fma: impl Fn(f32, f32, f32) -> f32,
) -> f32 {
    let r = fma(-q, b, a);
    let c = fma(r, inv_b, q);
    if q != 0.0 && q.is_finite() && r.is_finite() && c.is_finite() {
        c
    } else {
        q
    }
}

/// One residual step on an approximate square root `s ≈ √x` (`half_inv ≈ 0.5 / s`):
/// `fma(fma(−s, s, x), half_inv, s)`. Left as `s` for a zero, infinite or NaN root.
pub fn corrected_sqrt(s: f32, x: f32, half_inv: f32, fma: impl Fn(f32, f32, f32) -> f32) -> f32 {
    let r = fma(-s, s, x);
    let c = fma(r, half_inv, s);
    if s > 0.0 && s.is_finite() && c.is_finite() {
        c
    } else {
        s
    }
}

// ---------------------------------------------------------------------------------------------
// The WGSL the tracer is generated with
// ---------------------------------------------------------------------------------------------

/// Which arithmetic the generated WGSL uses (decided by the [`Probe`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ArithConfig {
    /// `fma` is truly fused: `fmaf` is WGSL's `fma`; otherwise [`fma_emulated`].
    pub fma_fused: bool,
    /// `/` gets the residual step ([`corrected_div`]).
    pub div_fix: bool,
    /// `sqrt` gets the residual step ([`corrected_sqrt`]).
    pub sqrt_fix: bool,
    /// A planted divergence, for tests: `fdot` as a chain of fused multiply-adds (what NVIDIA's
    /// driver makes of WGSL's `dot`) instead of glam's sum. Never chosen by the probe.
    pub fused_dot: bool,
}

/// The arithmetic helpers every tracer shader starts with: `fmaf` (Rust's `mul_add`), `fdiv`,
/// `fdiv3`, `fsqrt`, `flen` (glam's `length`: √(v·v)), `fcross` (glam's order) and `fpow`
/// ([`crate::trace::shading::portable_pow`]), in the variant `c` picks.
pub fn arith_wgsl(c: ArithConfig) -> String {
    let mut s = String::from(
        "// ---- arithmetic: the CPU's f32 operations (src/gpu/exact.rs) ----\n\n\
fn is_finite_f(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

// Knuth's TwoSum: s + e = a + b exactly.
fn two_sum(a: f32, b: f32) -> vec2f {
    let s = a + b;
    let bb = s - a;
    let e = (a - (s - bb)) + (b - bb);
    return vec2f(s, e);
}

// Veltkamp's split into two 12-bit halves.
fn split_f(a: f32) -> vec2f {
    let c = 4097.0 * a;
    let hi = c - (c - a);
    return vec2f(hi, a - hi);
}

// Dekker's two-product: p + e = a·b exactly (nothing may be contracted).
fn two_prod(a: f32, b: f32) -> vec2f {
    let p = a * b;
    let x = split_f(a);
    let y = split_f(b);
    let e = ((x.x * y.x - p) + x.x * y.y + x.y * y.x) + x.y * y.y;
    return vec2f(p, e);
}

// a·b + c rounded once without a fused FMA: two-product, TwoSum, round to odd, one addition.
fn fma_emulated(a: f32, b: f32, c: f32) -> f32 {
    let pe = two_prod(a, b);
    let st = two_sum(pe.x, c);
    let uv = two_sum(st.y, pe.y);
    var u = uv.x;
    let bits = bitcast<u32>(u);
    if uv.y != 0.0 && (bits & 1u) == 0u {
        if (u > 0.0) == (uv.y > 0.0) {
            u = bitcast<f32>(bits + 1u);
        } else {
            u = bitcast<f32>(bits - 1u);
        }
    }
    let r = st.x + u;
    if is_finite_f(r) && is_finite_f(pe.y) {
        return r;
    }
    return a * b + c;
}

",
    );
    s += if c.fma_fused {
        "// Rust's mul_add: the driver's fma is fused (the probe checked).\n\
         fn fmaf(a: f32, b: f32, c: f32) -> f32 {\n    return fma(a, b, c);\n}\n\n"
    } else {
        "// Rust's mul_add: the driver's fma is not fused (the probe checked), so it is emulated.\n\
         fn fmaf(a: f32, b: f32, c: f32) -> f32 {\n    return fma_emulated(a, b, c);\n}\n\n"
    };
    s += if c.div_fix {
        "// a / b correctly rounded: the driver's division, then one fma residual step.\n\
fn fdiv(a: f32, b: f32) -> f32 {
    let q = a / b;
    let r = fma(-q, b, a);
    let c = fma(r, 1.0 / b, q);
    if q != 0.0 && is_finite_f(q) && is_finite_f(r) && is_finite_f(c) {
        return c;
    }
    return q;
}

"
    } else {
        "// a / b: the driver's division is correctly rounded (the probe checked) or cannot be fixed.\n\
         fn fdiv(a: f32, b: f32) -> f32 {\n    return a / b;\n}\n\n"
    };
    s += if c.sqrt_fix {
        "// √x correctly rounded: the driver's sqrt, then one fma residual step.\n\
fn fsqrt(x: f32) -> f32 {
    let s = sqrt(x);
    let r = fma(-s, s, x);
    let c = fma(r, 0.5 / s, s);
    if s > 0.0 && is_finite_f(s) && is_finite_f(c) {
        return c;
    }
    return s;
}

"
    } else {
        "// √x: the driver's sqrt is correctly rounded (the probe checked) or cannot be fixed.\n\
         fn fsqrt(x: f32) -> f32 {\n    return sqrt(x);\n}\n\n"
    };
    s += if c.fused_dot {
        "// A planted divergence (tests only): the dot product as a chain of fused multiply-adds.\n\
         fn fdot(a: vec3f, b: vec3f) -> f32 {\n    return fmaf(a.z, b.z, fmaf(a.y, b.y, a.x * b.x));\n}\n\n"
    } else {
        "// glam's dot product, term for term: (a.x·b.x + a.y·b.y) + a.z·b.z. Not WGSL's dot(): NVIDIA's
// driver (580, H200) compiles OpDot as a chain of fused multiply-adds even when its result is
// decorated NoContraction (found with `raystep trace --gpu` and `raystep diff`: the first step
// to differ was a sphere test's a = d·d). Written out, each product and sum keeps NoContraction.
fn fdot(a: vec3f, b: vec3f) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

"
    };
    s += "fn fdiv3(v: vec3f, d: f32) -> vec3f {
    return vec3f(fdiv(v.x, d), fdiv(v.y, d), fdiv(v.z, d));
}

// glam's length: √(v·v).
fn flen(v: vec3f) -> f32 {
    return fsqrt(fdot(v, v));
}

// glam's cross product, term for term.
fn fcross(a: vec3f, b: vec3f) -> vec3f {
    return vec3f(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
}

// x^y for x ≥ 0, y ≥ 0 as src/trace/shading.rs portable_pow: x^⌊y⌋ by squaring, then x^(2^-k)
// for each binary digit of the fraction by repeated square roots.
fn fpow(x: f32, y: f32) -> f32 {
    if !(x >= 0.0) || !(y >= 0.0) || !is_finite_f(y) {
        return 0.0;
    }
    let whole = floor(y);
    var frac = y - whole;
    var n = 0xffffffffu;
    if whole < 4294967040.0 {
        n = u32(whole);
    }
    var result = 1.0;
    var base = x;
    while n > 0u {
        if (n & 1u) == 1u {
            result = result * base;
        }
        n = n >> 1u;
        if n > 0u {
            base = base * base;
        }
    }
    var root = x;
    for (var k = 0; k < 24 && frac != 0.0; k++) {
        root = fsqrt(root);
        frac = frac * 2.0;
        if frac >= 1.0 {
            result = result * root;
            frac = frac - 1.0;
        }
    }
    return result;
}

";
    s
}

// ---------------------------------------------------------------------------------------------
// The probe
// ---------------------------------------------------------------------------------------------

/// Results per probe input.
pub const PROBE_OUTPUTS: usize = 8;
/// 2⁻¹²⁶, the smallest normal f32 (`1.1754944e-38` in the probe's WGSL).
const SMALLEST_NORMAL: f32 = f32::MIN_POSITIVE;

/// The probe kernel: for each input `(a, b, c, x)` it writes `fma(a, b, c)`, the emulated fma,
/// `a / b`, the corrected division, `sqrt(x)`, the corrected square root and the hand-written
/// sum of products `a*b + c*x + b*c`, as raw bits.
pub fn probe_wgsl() -> String {
    let mut s = arith_wgsl(ArithConfig::default());
    s += "@group(0) @binding(0) var<storage, read> inputs: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> outputs: array<u32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3u) {
    let i = gid.x;
    if i >= arrayLength(&inputs) {
        return;
    }
    let v = inputs[i];
    let a = v.x;
    let b = v.y;
    let c = v.z;
    let x = v.w;
    let o = i * 8u;
    outputs[o] = bitcast<u32>(fma(a, b, c));
    outputs[o + 1u] = bitcast<u32>(fma_emulated(a, b, c));
    let q = a / b;
    outputs[o + 2u] = bitcast<u32>(q);
    let r = fma(-q, b, a);
    let qc = fma(r, 1.0 / b, q);
    outputs[o + 3u] = bitcast<u32>(select(q, qc, q != 0.0 && is_finite_f(q) && is_finite_f(r) && is_finite_f(qc)));
    let s = sqrt(x);
    outputs[o + 4u] = bitcast<u32>(s);
    let rs = fma(-s, s, x);
    let sc = fma(rs, 0.5 / s, s);
    outputs[o + 5u] = bitcast<u32>(select(s, sc, s > 0.0 && is_finite_f(s) && is_finite_f(sc)));
    outputs[o + 6u] = bitcast<u32>(a * b + c * x + b * c);
    outputs[o + 7u] = bitcast<u32>(x * 1.1754944e-38);
}
";
    s
}

/// A small xorshift generator for the probe's inputs (deterministic, no dependency).
struct XorShift(u32);

impl XorShift {
    fn next(&mut self) -> u32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        x
    }

    /// A float with a random significand, sign and an exponent in 2^-12 … 2^12.
    fn float(&mut self) -> f32 {
        let m = self.next() & 0x007f_ffff;
        let e = 127 - 12 + self.next() % 25;
        let s = self.next() & 0x8000_0000;
        f32::from_bits(s | (e << 23) | m)
    }
}

/// The probe's inputs `(a, b, c, x)`: random significands (a driver's approximate division is
/// off for about a third of them), `c = −(a·b rounded)` for three in four (so that an unfused
/// `fma` returns 0 where the fused one returns the product's rounding error), `x = |a|`.
pub fn probe_inputs() -> Vec<[f32; 4]> {
    let mut rng = XorShift(0x9e37_79b9);
    let mut v: Vec<[f32; 4]> = vec![
        // (1 + 2⁻¹²)² = 1 + 2⁻¹¹ + 2⁻²⁴: the last term is the product's rounding error.
        [
            1.0 + 1.0 / 4096.0,
            1.0 + 1.0 / 4096.0,
            -(1.0 + 1.0 / 2048.0),
            2.0,
        ],
        [3.0, 7.0, 0.1, 3.0],
        [1.0, 3.0, 0.0, 0.5],
    ];
    for k in 0..4093 {
        let a = rng.float();
        let b = rng.float();
        let c = if k % 4 == 3 { rng.float() } else { -(a * b) };
        v.push([a, b, c, a.abs()]);
    }
    v
}

/// The probe's answers on one device: how many of its inputs each operation got exactly as the
/// CPU computes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Probe {
    /// Inputs tried.
    pub inputs: usize,
    /// `fma(a, b, c)` equal to `f32::mul_add`.
    pub fma: usize,
    /// The emulated fma equal to `f32::mul_add`.
    pub fma_emulated: usize,
    /// `a / b` correctly rounded.
    pub div: usize,
    /// The corrected division correctly rounded.
    pub div_corrected: usize,
    /// `sqrt` correctly rounded.
    pub sqrt: usize,
    /// The corrected square root correctly rounded.
    pub sqrt_corrected: usize,
    /// `a*b + c*x + b*c` equal to the CPU's unfused sum (no contraction).
    pub sum_of_products: usize,
    /// `x·2⁻¹²⁶` (subnormal for x < 1) equal to the CPU's: subnormal results kept, not flushed
    /// to zero.
    pub subnormals: usize,
}

impl Probe {
    /// Counts the matches in the probe kernel's output bits.
    pub fn from_outputs(inputs: &[[f32; 4]], out: &[u32]) -> Probe {
        let mut p = Probe {
            inputs: inputs.len(),
            fma: 0,
            fma_emulated: 0,
            div: 0,
            div_corrected: 0,
            sqrt: 0,
            sqrt_corrected: 0,
            sum_of_products: 0,
            subnormals: 0,
        };
        let same = |want: f32, got: u32| {
            let g = f32::from_bits(got);
            want.to_bits() == got || (want.is_nan() && g.is_nan())
        };
        for (i, &[a, b, c, x]) in inputs.iter().enumerate() {
            let Some(o) = out.get(i * PROBE_OUTPUTS..(i + 1) * PROBE_OUTPUTS) else {
                break;
            };
            let fma = a.mul_add(b, c);
            p.fma += usize::from(same(fma, o[0]));
            p.fma_emulated += usize::from(same(fma, o[1]));
            p.div += usize::from(same(a / b, o[2]));
            p.div_corrected += usize::from(same(a / b, o[3]));
            p.sqrt += usize::from(same(x.sqrt(), o[4]));
            p.sqrt_corrected += usize::from(same(x.sqrt(), o[5]));
            p.sum_of_products += usize::from(same(a * b + c * x + b * c, o[6]));
            p.subnormals += usize::from(same(x * SMALLEST_NORMAL, o[7]));
        }
        p
    }

    /// The variant these answers call for. A residual step is used only with a fused `fma`,
    /// where the plain operation is not exact and the step got strictly more inputs right: never
    /// a correction that makes things worse.
    pub fn config(&self) -> ArithConfig {
        let fma_fused = self.fma == self.inputs;
        ArithConfig {
            fused_dot: false,
            fma_fused,
            div_fix: fma_fused && self.div < self.inputs && self.div_corrected > self.div,
            sqrt_fix: fma_fused && self.sqrt < self.inputs && self.sqrt_corrected > self.sqrt,
        }
    }

    /// Whether every operation comes out as on the CPU with the chosen variant.
    pub fn exact(&self) -> bool {
        let c = self.config();
        let n = self.inputs;
        let pick = |fix: bool, plain: usize, fixed: usize| if fix { fixed } else { plain };
        (c.fma_fused || self.fma_emulated == n)
            && pick(c.div_fix, self.div, self.div_corrected) == n
            && pick(c.sqrt_fix, self.sqrt, self.sqrt_corrected) == n
            && self.sum_of_products == n
    }

    /// Whether subnormal results are kept as on the CPU. A driver that flushes them to zero
    /// still computes every normal result as the CPU does; results below 1.2e-38 (rare in a
    /// scene: a plane's numerator at a grazing hit) come out 0.
    pub fn subnormals_kept(&self) -> bool {
        self.subnormals == self.inputs
    }

    /// "fma fused: no (Dekker emulation exact), / exact, sqrt exact, sums of products not
    /// contracted": the answers in words.
    pub fn summary(&self) -> String {
        let c = self.config();
        let n = self.inputs;
        let share = |k: usize| format!("{k}/{n}");
        let op = |name: &str, fix: bool, plain: usize, fixed: usize| {
            if plain == n {
                format!("{name} correctly rounded")
            } else if fix {
                format!(
                    "{name} inexact ({} right), one fma step: {}",
                    share(plain),
                    if fixed == n {
                        "correctly rounded".to_string()
                    } else {
                        format!("{} right", share(fixed))
                    }
                )
            } else {
                format!("{name} inexact ({} right), no fix available", share(plain))
            }
        };
        format!(
            "fma fused: {}; {}; {}; sums of products {}; subnormals {}",
            if c.fma_fused {
                "yes".to_string()
            } else if self.fma_emulated == n {
                "no (emulated exactly with Dekker's two-product)".to_string()
            } else {
                format!("no (the emulation got {} right)", share(self.fma_emulated))
            },
            op("/", c.div_fix, self.div, self.div_corrected),
            op("sqrt", c.sqrt_fix, self.sqrt, self.sqrt_corrected),
            if self.sum_of_products == n {
                "not contracted".to_string()
            } else {
                format!("contracted ({} as on the CPU)", share(self.sum_of_products))
            },
            if self.subnormals_kept() {
                "kept".to_string()
            } else {
                format!(
                    "flushed to zero ({} as on the CPU; results below 1.2e-38 differ)",
                    share(self.subnormals)
                )
            }
        )
    }
}

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
