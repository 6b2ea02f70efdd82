// √x correctly rounded: the driver's sqrt, then one fma residual step and the midpoint decision.
fn fsqrt(x: f32) -> f32 {
    let s = sqrt(x);
    return corrected_sqrt(s, x, 0.5 / s);
}

