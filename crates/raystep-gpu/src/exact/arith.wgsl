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


// One residual step on q ≈ a / b (inv_b ≈ 1 / b) with the fused fma, then the exact decision at
// the midpoint next to it: corrected_div and round_quotient in dekker.rs, step for step.
fn corrected_div(q: f32, a: f32, b: f32, inv_b: f32) -> f32 {
    let r = fma(-q, b, a);
    let c = fma(r, inv_b, q);
    if !(q != 0.0 && is_finite_f(q) && is_finite_f(r) && c != 0.0 && is_finite_f(c)) {
        return q;
    }
    let bits = bitcast<u32>(c);
    let away = bitcast<f32>(bits + 1u);
    let toward = bitcast<f32>(bits - 1u);
    let half_gap_away = 0.5 * abs(away - c) * abs(b);
    let half_gap_toward = 0.5 * abs(c - toward) * abs(b);
    if half_gap_toward < 1.1754944e-38 {
        return c;
    }
    // The residual, signed so that positive means |a / b| > |c|.
    var rc = fma(-c, b, a);
    if a < 0.0 {
        rc = -rc;
    }
    if rc > half_gap_away {
        return away;
    }
    if rc < -half_gap_toward {
        return toward;
    }
    return c;
}

// One residual step on s ≈ √x (half_inv ≈ 0.5 / s) with the fused fma, then the exact decision
// at the midpoint next to it: corrected_sqrt and round_root in dekker.rs, step for step.
fn corrected_sqrt(s: f32, x: f32, half_inv: f32) -> f32 {
    let r = fma(-s, s, x);
    let c = fma(r, half_inv, s);
    if !(s > 0.0 && is_finite_f(s) && c > 0.0 && is_finite_f(c)) {
        return s;
    }
    let bits = bitcast<u32>(c);
    let above = bitcast<f32>(bits + 1u);
    let below = bitcast<f32>(bits - 1u);
    let gap_above = c * (above - c);
    let gap_below = c * (c - below);
    if gap_below < 1.1754944e-38 {
        return c;
    }
    let rc = fma(-c, c, x);
    if rc > gap_above {
        return above;
    }
    if rc <= -gap_below {
        return below;
    }
    return c;
}
