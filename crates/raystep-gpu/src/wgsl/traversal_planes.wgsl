// ---- traversal: the infinite planes, tested before the tree (a plane has no bounding box, so
// it stays out of the BVH and out of the hardware's acceleration structure, as on the CPU) ----

fn planes_closest(ray: Ray) -> Hit {
    var r = ray;
    var best = no_hit();
    for (var i = 0u; i < params.n_planes; i++) {
        let id = planes[i];
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
fn planes_any(r: Ray) -> bool {
    for (var i = 0u; i < params.n_planes; i++) {
        let c = intersection(planes[i], r);
        if any_hit(c) {
//#if TRACE
            log_blocker(planes[i], c, r.t_max);
//#endif
            return true;
        }
    }
    return false;
}
//#endif
