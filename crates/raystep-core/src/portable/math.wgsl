// Portable sin, cos, exp and ln: math.rs beside this file, line for line (the same constants, the same
// order of operations), so that on the exact compute path (NoContraction) they return the CPU's
// bits. Cody–Waite reduction and Cephes' single-precision polynomials; see the Rust for bounds.

const PIO2_1: f32 = 1.5703125;
const PIO2_2: f32 = 4.837512969970703e-4;
const PIO2_3: f32 = 7.549790126404332e-8;
const TWO_OVER_PI: f32 = 0.63661975;
const LN2_HI: f32 = 0.693359375;
const LN2_LO: f32 = -2.1219444e-4;
const LOG2_E: f32 = 1.442695;
const SQRT_HALF: f32 = 0.70710677;
const F32_MIN_POSITIVE: f32 = 1.17549435e-38;

fn p_is_nan(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

fn p_is_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) < 0x7f800000u;
}

// A NaN's and infinity's bits in private variables, not constants: a bitcast of a constant is
// evaluated when the shader is compiled, and WGSL has no constant NaN or infinity (Chrome's
// compiler rejects them).
var<private> P_NAN_BITS: u32 = 0x7fc00000u;
var<private> P_INF_BITS: u32 = 0x7f800000u;

fn p_nan() -> f32 {
    return bitcast<f32>(P_NAN_BITS);
}

fn p_inf() -> f32 {
    return bitcast<f32>(P_INF_BITS);
}

fn p_sin_poly(r: f32) -> f32 {
    let z = r * r;
    return ((-1.9515295891e-4 * z + 8.3321608736e-3) * z - 1.6666654611e-1) * z * r + r;
}

fn p_cos_poly(r: f32) -> f32 {
    let z = r * r;
    let y = ((2.443315711809948e-5 * z - 1.388731625493765e-3) * z + 4.166664568298827e-2) * z * z;
    return (y - 0.5 * z) + 1.0;
}

// (sin x, cos x).
fn p_sin_cos(x: f32) -> vec2f {
    if !p_is_finite(x) {
        return vec2f(p_nan(), p_nan());
    }
    let k = floor(x * TWO_OVER_PI + 0.5);
    let r = ((x - k * PIO2_1) - k * PIO2_2) - k * PIO2_3;
    let s = p_sin_poly(r);
    let c = p_cos_poly(r);
    var q = 0;
    if abs(k) < 2147483648.0 {
        q = i32(k) & 3;
    }
    switch q {
        case 0: { return vec2f(s, c); }
        case 1: { return vec2f(c, -s); }
        case 2: { return vec2f(-s, -c); }
        default: { return vec2f(-c, s); }
    }
}

fn p_exp2i(k: i32) -> f32 {
    return bitcast<f32>(u32(k + 127) << 23u);
}

fn p_exp(x: f32) -> f32 {
    if p_is_nan(x) {
        return p_nan();
    }
    if x > 88.8 {
        return p_inf();
    }
    if x < -88.0 {
        return 0.0;
    }
    let kf = floor(x * LOG2_E + 0.5);
    let r = (x - kf * LN2_HI) - kf * LN2_LO;
    let z = r * r;
    var p = 1.98756915e-4 * r + 1.3981999507e-3;
    p = p * r + 8.3334519073e-3;
    p = p * r + 4.1665795894e-2;
    p = p * r + 1.6666665459e-1;
    p = p * r + 5.0000001201e-1;
    p = p * z;
    var y = (p + r) + 1.0;
    let k = i32(kf);
    let half = k >> 1u;
    y = y * p_exp2i(half) * p_exp2i(k - half);
    if y < F32_MIN_POSITIVE {
        return 0.0;
    }
    return y;
}

fn p_ln(x: f32) -> f32 {
    if p_is_nan(x) || x < 0.0 {
        return p_nan();
    }
    if x < F32_MIN_POSITIVE {
        return -p_inf();
    }
    if x == p_inf() {
        return x;
    }
    let bits = bitcast<u32>(x);
    var e = i32((bits >> 23u) & 0xffu) - 126;
    let m = bitcast<f32>((bits & 0x007fffffu) | (126u << 23u));
    var f: f32;
    if m < SQRT_HALF {
        e = e - 1;
        f = (m + m) - 1.0;
    } else {
        f = m - 1.0;
    }
    let ef = f32(e);
    let z = f * f;
    var p = 7.0376836292e-2 * f - 1.1514610310e-1;
    p = p * f + 1.1676998740e-1;
    p = p * f - 1.2420140846e-1;
    p = p * f + 1.4249322787e-1;
    p = p * f - 1.6668057665e-1;
    p = p * f + 2.0000714765e-1;
    p = p * f - 2.4999993993e-1;
    p = p * f + 3.3333331174e-1;
    var y = p * f * z;
    y = y + ef * LN2_LO;
    y = y - 0.5 * z;
    let r = f + y;
    return r + ef * LN2_HI;
}
