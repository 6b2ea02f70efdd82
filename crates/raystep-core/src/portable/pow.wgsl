// x^y for x ≥ 0, y ≥ 0 as crates/raystep-core/src/portable/math.rs `pow`: x^⌊y⌋ by squaring, then x^(2^-k)
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
