fn fdiv3(v: vec3f, d: f32) -> vec3f {
    return vec3f(fdiv(v.x, d), fdiv(v.y, d), fdiv(v.z, d));
}

// glam's length: √(v·v).
fn flen(v: vec3f) -> f32 {
    return fsqrt(fdot(v, v));
}

// glam's cross product, term for term.
fn fcross(a: vec3f, b: vec3f) -> vec3f {
    return vec3f(a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y);
}

