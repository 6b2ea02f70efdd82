// a / b correctly rounded: the driver's division, then one fma residual step and the midpoint
// decision.
fn fdiv(a: f32, b: f32) -> f32 {
    return corrected_div(a / b, a, b, 1.0 / b);
}

