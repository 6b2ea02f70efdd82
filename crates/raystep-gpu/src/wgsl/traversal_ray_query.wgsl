// ---- traversal: hardware ray queries (wgpu's EXPERIMENTAL_RAY_QUERY) ----
//
// The finite objects are procedural primitives (their bounding boxes) in one bottom-level
// acceleration structure: the hardware walks its own tree and reports each box the ray enters as
// a candidate; raystep's intersection functions decide the hit (so the numbers are the CPU's) and
// rayQueryGenerateIntersection commits it. Planes stay outside, tested first, as on the CPU.
// leaf_objects[i] is the object of primitive i; params.n_nodes counts the primitives.

@group(0) @binding(7) var tlas: acceleration_structure;

fn rq_desc(r: Ray, flags: u32) -> RayDesc {
    return RayDesc(flags, 0xffu, r.t_min, min(r.t_max, 3.4028235e38), r.origin, r.dir);
}

fn rq_closest(ray: Ray) -> Hit {
    var r = ray;
    var best = planes_closest(r);
    if best.object != NO_OBJECT {
        r.t_max = best.t;
    }
    if params.n_nodes == 0u {
        return best;
    }
//#if TRACE
    log_open();
    log_u(params.n_nodes);
    log_close(EV_HARDWARE);
//#endif
    var rq: ray_query;
    rayQueryInitialize(&rq, tlas, rq_desc(r, RAY_FLAG_NONE));
    while rayQueryProceed(&rq) {
        let candidate = rayQueryGetCandidateIntersection(&rq);
        let id = leaf_objects[candidate.primitive_index];
        let c = intersection(id, r);
        if any_hit(c) {
            // Bound before the stores below: naga 30 does not emit an expression that first
            // appears as this call's argument ("used before it was introduced").
            let t_hit = c.t;
//#if TRACE
            log_accept(id, t_hit, r.t_max);
//#endif
            r.t_max = t_hit;
            best = Hit(id, t_hit, c.u, c.v, c.aux);
            rayQueryGenerateIntersection(&rq, t_hit);
        }
    }
    return best;
}

//#if SHADOWS
fn rq_any(r: Ray) -> bool {
    if planes_any(r) {
        return true;
    }
    if params.n_nodes == 0u {
        return false;
    }
//#if TRACE
    log_open();
    log_u(params.n_nodes);
    log_close(EV_HARDWARE);
//#endif
    var rq: ray_query;
    rayQueryInitialize(&rq, tlas, rq_desc(r, RAY_FLAG_TERMINATE_ON_FIRST_HIT));
    while rayQueryProceed(&rq) {
        let candidate = rayQueryGetCandidateIntersection(&rq);
        let id = leaf_objects[candidate.primitive_index];
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
