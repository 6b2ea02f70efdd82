// The Ray Tracer Challenge's over_point / under_point: `epsilon` along the normal.
fn spawn_origin(it: Interaction, w: vec3f) -> vec3f {
    let side = select(-1.0, 1.0, fdot(w, it.normal) >= 0.0);
    let point = select(it.point, it.lifted, fdot(w, it.shading) >= 0.0);
    return point + it.normal * (params.epsilon * side);
}
