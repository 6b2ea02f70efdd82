// ---- intersection: ray–triangle, Möller–Trumbore as Cramer's rule (crates/raystep-core/src/shapes/triangle.rs) ----

fn det3(a: vec3f, b: vec3f, c: vec3f) -> f32 {
    return fdot(a, fcross(b, c));
}

fn intersect_triangle(r: Ray, p0: vec3f, p1: vec3f, p2: vec3f) -> Cand {
    let e1 = p1 - p0;                      // step 1
    let e2 = p2 - p0;
    let nq = -r.dir;
    let d0 = det3(nq, e1, e2);             // step 2 (no ε)
//#if TRACE
    scratch[0] = e1.x; scratch[1] = e1.y; scratch[2] = e1.z;
    scratch[3] = e2.x; scratch[4] = e2.y; scratch[5] = e2.z;
    scratch[6] = d0; scratch[26] = 2.0;
//#endif
    if d0 == 0.0 || !finite(d0) {
        return no_cand(d0);
    }
    let tv = r.origin - p0;                // steps 3–5
    let dt = det3(tv, e1, e2);
    let t = fdiv(dt, d0);
//#if TRACE
    scratch[7] = tv.x; scratch[8] = tv.y; scratch[9] = tv.z;
    scratch[10] = dt; scratch[11] = t; scratch[26] = 5.0;
//#endif
    if !accepts(r, t) {
        return no_cand(d0);
    }
    let du = det3(nq, tv, e2);             // steps 6–8
    let u = fdiv(du, d0);
//#if TRACE
    scratch[12] = du; scratch[13] = u; scratch[26] = 8.0;
//#endif
    if u < 0.0 || u > 1.0 {
        return no_cand(d0);
    }
    let dv = det3(nq, e1, tv);             // steps 9–11
    let v = fdiv(dv, d0);
//#if TRACE
    scratch[14] = dv; scratch[15] = v; scratch[26] = 11.0;
//#endif
    if v < 0.0 || u + v > 1.0 {
        return no_cand(d0);
    }
//#if TRACE
    scratch[26] = 12.0;
//#endif
    return Cand(true, t, u, v, d0);        // step 12
}
