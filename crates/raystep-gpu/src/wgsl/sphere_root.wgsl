// The nearer root inside (t_min, t_max), else the farther one (the origin is inside the sphere).
fn sphere_root(r: Ray, t0: f32, t1: f32, disc: f32) -> Cand {
    let lo = select(t1, t0, t0 <= t1);
    let hi = select(t0, t1, t0 <= t1);
    if lo > r.t_min {
        if lo < r.t_max {
            return Cand(true, lo, 0.0, 0.0, disc);
        }
    } else if hi > r.t_min && hi < r.t_max {
        return Cand(true, hi, 0.0, 0.0, disc);
    }
    return no_cand(disc);
}
