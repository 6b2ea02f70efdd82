// ---- intersection: ray–sphere, the stable form (Ray Tracing Gems ch. 7; src/shapes/sphere.rs) ----

fn intersect_sphere(r: Ray, center: vec3f, radius: f32) -> Cand {
    let f = r.origin - center;
    let d = r.dir;
    let a = dot(d, d);
    let fd = dot(f, d);
    let b_half = -fd;
    let c = dot(f, f) - radius * radius;
    // The squared distance from the centre to the ray's line, from a vector difference.
    let l = f + d * fdiv(b_half, a);
    let delta_prime = radius * radius - dot(l, l);
    let disc = 4.0 * a * delta_prime;
    if !(delta_prime >= 0.0) {
        return no_cand(disc);
    }
    let sign = select(-1.0, 1.0, b_half >= 0.0);
    let q = b_half + sign * fsqrt(a * delta_prime);
    var t0 = 0.0;
    var t1 = 0.0;
    // q = 0: a tangent ray starting at the tangent point (c/q would be 0/0): the root is t = 0.
    if q != 0.0 {
        t0 = fdiv(c, q);
        t1 = fdiv(q, a);
    }
    return sphere_root(r, t0, t1, disc);
}
