// No offset: spawned rays start exactly at the hit point (shows shadow acne).
fn spawn_origin(it: Interaction, w: vec3f) -> vec3f {
    return select(it.point, it.lifted, fdot(w, it.shading) >= 0.0);
}
