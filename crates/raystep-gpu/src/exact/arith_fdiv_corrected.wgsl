// a / b correctly rounded: the driver's division, then one fma residual step.
fn fdiv(a: f32, b: f32) -> f32 {
    let q = a / b;
    let r = fma(-q, b, a);
    let c = fma(r, 1.0 / b, q);
    if q != 0.0 && is_finite_f(q) && is_finite_f(r) && is_finite_f(c) {
        return c;
    }
    return q;
}

