// ---- traversal: hardware ray queries (wgpu's EXPERIMENTAL_RAY_QUERY) ----
//
// The finite objects are procedural primitives (their bounding boxes) in one bottom-level
// acceleration structure: the hardware walks its own tree and reports each box the ray enters as
// a candidate; raystep's intersection functions decide the hit (so the numbers are the CPU's) and
// rayQueryGenerateIntersection commits it. Planes stay outside, tested first, as on the CPU.
// leaf_objects[i] is the object of primitive i; params.n_nodes counts the primitives.
//
// With instances, the TLAS holds the world's BLAS once (custom index 0) and each instance of its
// prototype's BLAS with the instance's matrix (custom index i + 1): the hardware carries the ray
// into object space itself to walk that BLAS; raystep carries it again with M⁻¹ in its own
// written order (the numbers the CPU uses) and tests the candidate with that ray. The instance's
// first record names where its prototype's primitives' object ids start in leaf_objects.

@group(0) @binding(7) var tlas: acceleration_structure;

fn rq_desc(r: Ray, flags: u32) -> RayDesc {
    return RayDesc(flags, 0xffu, r.t_min, min(r.t_max, 3.4028235e38), r.origin, r.dir);
}

// A candidate's object and the ray to test it with: the world ray, or on an instance the ray
// carried into its object space (logged, as the compute path's walk logs entering it).
struct RqCandidate {
    object: u32,
    instance: u32,
    ray: Ray,
}

fn rq_candidate(c: RayIntersection, r: Ray) -> RqCandidate {
//#if INSTANCES
    if c.instance_custom_data != 0u {
        let i = c.instance_custom_data - 1u;
        let rec = objects[params.inst_at + 2u * i];
        let local = instance_ray(i, r);
//#if TRACE
        log_instance(i, local);
//#endif
        return RqCandidate(leaf_objects[rec.material + c.primitive_index], i, local);
    }
//#endif
    return RqCandidate(leaf_objects[c.primitive_index], NO_INSTANCE, r);
}

fn rq_closest(ray: Ray) -> Hit {
    var r = ray;
    var best = planes_closest(r);
    if best.object != NO_OBJECT {
        r.t_max = best.t;
    }
    if params.n_nodes == 0u && params.n_instances == 0u {
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
        let candidate = rq_candidate(rayQueryGetCandidateIntersection(&rq), r);
        var tested = candidate.ray;
        tested.t_max = r.t_max;
        let id = candidate.object;
        let c = intersection(id, tested);
        if any_hit(c) {
            // Bound before the stores below: naga 30 does not emit an expression that first
            // appears as this call's argument ("used before it was introduced").
            let t_hit = c.t;
//#if TRACE
            log_accept(id, t_hit, r.t_max);
//#endif
            r.t_max = t_hit;
            best = Hit(id, t_hit, c.u, c.v, c.aux, candidate.instance);
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
    if params.n_nodes == 0u && params.n_instances == 0u {
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
        let candidate = rq_candidate(rayQueryGetCandidateIntersection(&rq), r);
        let id = candidate.object;
        let c = intersection(id, candidate.ray);
        if any_hit(c) {
//#if TRACE
            current_instance = candidate.instance;
            log_blocker(id, c, r.t_max);
            current_instance = NO_INSTANCE;
//#endif
            return true;
        }
    }
    return false;
}
//#endif
