// ---- miss: the ray hit nothing ----

fn miss() -> vec3f {
    return params.background;
}
