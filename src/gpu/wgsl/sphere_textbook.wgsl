// ---- intersection: ray–sphere, the course notes' textbook quadratic (docs/SOURCES.md) (src/shapes/sphere.rs) ----

fn intersect_sphere(r: Ray, center: vec3f, radius: f32) -> Cand {
    let f = r.origin - center;
    let a = dot(r.dir, r.dir);
    let b = 2.0 * dot(f, r.dir);
    let c = dot(f, f) - radius * radius;
    let disc = b * b - 4.0 * a * c;
    if !(disc >= 0.0) {
        return no_cand(disc);
    }
    let sq = fsqrt(disc);
    let t0 = fdiv(-b - sq, 2.0 * a);
    let t1 = fdiv(-b + sq, 2.0 * a);
    return sphere_root(r, t0, t1, disc);
}
