// ---- traversal: the lecture notes' naive loop (docs/SOURCES.md) over every object (crates/raystep-core/src/accel/brute.rs) ----

fn brute_closest(ray: Ray) -> Hit {
    var r = ray;
    var best = no_hit();
    for (var id = 0u; id < params.n_world; id++) {
        let c = intersection(id, r);
        if any_hit(c) {
//#if TRACE
            log_accept(id, c.t, r.t_max);
//#endif
            r.t_max = c.t;
            best = Hit(id, c.t, c.u, c.v, c.aux, NO_INSTANCE);
        }
    }
    return best;
}

//#if SHADOWS
fn brute_any(r: Ray) -> bool {
    for (var id = 0u; id < params.n_world; id++) {
        let c = intersection(id, r);
        if any_hit(c) {
//#if TRACE
            log_blocker(id, c, r.t_max);
//#endif
            return true;
        }
    }
    return false;
}
//#endif
