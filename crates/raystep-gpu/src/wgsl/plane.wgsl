// ---- intersection: ray–plane, general X·n = c and axis-aligned X_axis = c (crates/raystep-core/src/shapes/plane.rs) ----

fn plane_root(r: Ray, numerator: f32, denominator: f32) -> Cand {
//#if TRACE
    scratch[0] = numerator; scratch[1] = denominator;
//#endif
    // Either sign of zero: parallel, a miss (docs/NUMERICS.md S9). An overflowing t fails `accepts`.
    if denominator == 0.0 {
        return no_cand(denominator);
    }
    let t = fdiv(numerator, denominator);
//#if TRACE
    scratch[2] = t;
//#endif
    if accepts(r, t) {
        return Cand(true, t, 0.0, 0.0, denominator);
    }
    return no_cand(denominator);
}

fn intersect_plane(r: Ray, normal: vec3f, offset: f32) -> Cand {
    return plane_root(r, offset - fdot(r.origin, normal), fdot(r.dir, normal));
}

fn intersect_axis_plane(r: Ray, axis: u32, offset: f32) -> Cand {
    return plane_root(r, offset - r.origin[axis], r.dir[axis]);
}
