// ---- intersection: ray–sphere, the stable form (Ray Tracing Gems ch. 7; crates/raystep-core/src/shapes/sphere.rs) ----

fn intersect_sphere(r: Ray, center: vec3f, radius: f32) -> Cand {
    let f = r.origin - center;
    let d = r.dir;
    let a = fdot(d, d);
    let fd = fdot(f, d);
    let b_half = -fd;
    let c = fdot(f, f) - radius * radius;
    // The squared distance from the centre to the ray's line, from a vector difference.
    let l = f + d * fdiv(b_half, a);
    let delta_prime = radius * radius - fdot(l, l);
    let disc = 4.0 * a * delta_prime;
//#if TRACE
    scratch[0] = f.x; scratch[1] = f.y; scratch[2] = f.z; scratch[3] = a; scratch[4] = fd;
    scratch[5] = c; scratch[6] = disc; scratch[7] = delta_prime; scratch[8] = b_half;
    scratch[9] = l.x; scratch[10] = l.y; scratch[11] = l.z;
//#endif
    if !(delta_prime >= 0.0) {
        return no_cand(disc);
    }
    let sign = select(-1.0, 1.0, b_half >= 0.0);
    let q = b_half + sign * fsqrt(a * delta_prime);
//#if TRACE
    scratch[13] = q;
//#endif
    var t0 = 0.0;
    var t1 = 0.0;
    // q = 0: a tangent ray starting at the tangent point (c/q would be 0/0): the root is t = 0.
    if q != 0.0 {
        t0 = fdiv(c, q);
        t1 = fdiv(q, a);
    }
//#if TRACE
    scratch[14] = t0; scratch[15] = t1;
//#endif
    return sphere_root(r, t0, t1, disc);
}
