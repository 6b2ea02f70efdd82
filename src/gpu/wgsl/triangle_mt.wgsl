// ---- intersection: ray–triangle, Möller–Trumbore as Cramer's rule (src/shapes/triangle.rs) ----

fn det3(a: vec3f, b: vec3f, c: vec3f) -> f32 {
    return dot(a, fcross(b, c));
}

fn intersect_triangle(r: Ray, p0: vec3f, p1: vec3f, p2: vec3f) -> Cand {
    let e1 = p1 - p0;                      // step 1
    let e2 = p2 - p0;
    let nq = -r.dir;
    let d0 = det3(nq, e1, e2);             // step 2 (no ε)
    if d0 == 0.0 || !finite(d0) {
        return no_cand(d0);
    }
    let tv = r.origin - p0;                // steps 3–5
    let t = fdiv(det3(tv, e1, e2), d0);
    if !accepts(r, t) {
        return no_cand(d0);
    }
    let u = fdiv(det3(nq, tv, e2), d0);         // steps 6–8
    if u < 0.0 || u > 1.0 {
        return no_cand(d0);
    }
    let v = fdiv(det3(nq, e1, tv), d0);         // steps 9–11
    if v < 0.0 || u + v > 1.0 {
        return no_cand(d0);
    }
    return Cand(true, t, u, v, d0);        // step 12
}
