//! The start-up probe: a tiny kernel run once on known hard inputs, whose answers decide the
//! arithmetic the tracer is generated with.

use super::*;

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
    outputs[o + 3u] = bitcast<u32>(corrected_div(q, a, b, 1.0 / b));
    let s = sqrt(x);
    outputs[o + 4u] = bitcast<u32>(s);
    outputs[o + 5u] = bitcast<u32>(corrected_sqrt(s, x, 0.5 / s));
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
