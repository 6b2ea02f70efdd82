// √x correctly rounded: the driver's sqrt, then one fma residual step.
fn fsqrt(x: f32) -> f32 {
    let s = sqrt(x);
    let r = fma(-s, s, x);
    let c = fma(r, 0.5 / s, s);
    if s > 0.0 && is_finite_f(s) && is_finite_f(c) {
        return c;
    }
    return s;
}

