// ---- intersection: ray–sphere, the course notes' textbook quadratic (docs/SOURCES.md) (crates/raystep-core/src/shapes/sphere.rs) ----

fn intersect_sphere(r: Ray, center: vec3f, radius: f32) -> Cand {
    let f = r.origin - center;
    let a = fdot(r.dir, r.dir);
    let b = 2.0 * fdot(f, r.dir);
    let c = fdot(f, f) - radius * radius;
    let disc = b * b - 4.0 * a * c;
//#if TRACE
    scratch[0] = f.x; scratch[1] = f.y; scratch[2] = f.z; scratch[3] = a; scratch[4] = b;
    scratch[5] = c; scratch[6] = disc;
//#endif
    if !(disc >= 0.0) {
        return no_cand(disc);
    }
    let sq = fsqrt(disc);
    let t0 = fdiv(-b - sq, 2.0 * a);
    let t1 = fdiv(-b + sq, 2.0 * a);
//#if TRACE
    scratch[12] = sq; scratch[14] = t0; scratch[15] = t1;
//#endif
    return sphere_root(r, t0, t1, disc);
}
