// pbrt-v4 OffsetRayOrigin: move |n|·error along n to the side w leaves on, then one float further
// (never to within 2^-100 of zero).
fn next_up(x: f32) -> f32 {
    if is_nan(x) || (!finite(x) && x > 0.0) {
        return x;
    }
    if x == 0.0 {
        return bitcast<f32>(1u);
    }
    let b = bitcast<u32>(x);
    return bitcast<f32>(select(b - 1u, b + 1u, x > 0.0));
}

fn next_down(x: f32) -> f32 {
    return -next_up(-x);
}

fn spawn_origin(it: Interaction, w: vec3f) -> vec3f {
    let side = select(-1.0, 1.0, fdot(w, it.normal) >= 0.0);
    // Rays on the shading normal's side leave from the lifted point (the terminator's fix).
    let lifted = fdot(w, it.shading) >= 0.0;
    let point = select(it.point, it.lifted, lifted);
    let error = select(it.error, it.lifted_error, lifted);
    let n = it.normal * side;
    let d = fdot(abs(n), error);
    var o = point + n * d;
    // A step that ends within ±2^-100 of zero goes on to ±2^-100 (the CPU's `OFFSET_FLOOR`):
    // no subnormal origin, which a GPU may flush to 0 and a CPU computes with slowly.
    let offset_floor = bitcast<f32>(0x0D800000u);
    for (var i = 0u; i < 3u; i++) {
        if n[i] > 0.0 {
            o[i] = next_up(o[i]);
            if abs(o[i]) < offset_floor {
                o[i] = offset_floor;
            }
        } else if n[i] < 0.0 {
            o[i] = next_down(o[i]);
            if abs(o[i]) < offset_floor {
                o[i] = -offset_floor;
            }
        }
    }
    return o;
}
