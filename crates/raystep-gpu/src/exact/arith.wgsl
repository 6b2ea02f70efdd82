// ---- arithmetic: the CPU's f32 operations (crates/raystep-gpu/src/exact/) ----

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

