// ---- traversal: the BVH, flattened into storage buffers (crates/raystep-core/src/accel/bvh.rs) ----
//
// The same loop as the CPU's: planes first (they tighten t_max), then the root box; from there,
// both children of a node are tested, the nearer is visited first, the farther is pushed on a
// small stack (or visited next when the nearer one is a leaf or missed). Leaves test their
// objects with the intersection functions.

// The ray prepared for slab tests: true IEEE reciprocals (±∞ for a zero component, keeping its sign).
struct SlabRay {
    origin: vec3f,
    inv: vec3f,
    negative: vec3<bool>,
}

fn slab_ray(r: Ray) -> SlabRay {
    let signed_inf = bitcast<vec3f>((bitcast<vec3u>(r.dir) & vec3u(0x80000000u)) | vec3u(0x7f800000u));
    let inv = select(vec3f(fdiv(1.0, r.dir.x), fdiv(1.0, r.dir.y), fdiv(1.0, r.dir.z)), signed_inf, r.dir == vec3f(0.0));
    return SlabRay(r.origin, inv, inv < vec3f(0.0));
}

fn is_nan3(v: vec3f) -> vec3<bool> {
    return (bitcast<vec3u>(v) & vec3u(0x7fffffffu)) > vec3u(0x7f800000u);
}

//#if TRACE
// A box test's intermediates, for the node's record: the two plane distances per axis, and the
// entry and exit distances before a NaN is replaced.
struct BoxLog {
    t0: vec3f,
    t1: vec3f,
    entry: vec3f,
    exit: vec3f,
}
var<private> last_box: BoxLog;

fn select_box(f: BoxLog, t: BoxLog, c: bool) -> BoxLog {
    if c {
        return t;
    }
    return f;
}

const ACTION_CULLED: u32 = 0u;
const ACTION_DESCEND: u32 = 1u;
const ACTION_PUSHED: u32 = 2u;
const ACTION_TEST: u32 = 3u;

// tag: EV_NODE (a BVH's node: the world's, or an instance's BLAS, named by current_instance) or
// EV_TLAS_NODE.
fn log_node(tag: u32, s: SlabRay, id: u32, depth: u32, n: Node, b: BoxLog, interval: vec2f, action: u32) {
    log_open();
    log_u(id);
    log_u(depth);
    log_v(n.min);
    log_v(n.max);
    log_v(s.inv);
    log_v(b.t0);
    log_v(b.t1);
    log_v(b.entry);
    log_v(b.exit);
    log_f(interval.x);
    log_f(interval.y);
    log_b(n.count > 0u);
    log_u(n.first);
    log_u(action);
    log_u(select(current_instance, NO_INSTANCE, tag == EV_TLAS_NODE));
    log_close(tag);
}
//#endif

// (t_near, t_far) of a node's box: the robust slab test (docs/NUMERICS.md), t_far enlarged by 1 + 2γ₃,
// a NaN slab distance (a ray lying in a face plane, 0·∞) imposing no limit.
fn box_interval(s: SlabRay, node: Node, t_min: f32, t_max: f32) -> vec2f {
    node_visits += 1u;
    let t0 = (node.min - s.origin) * s.inv;
    let t1 = (node.max - s.origin) * s.inv;
    var entry = select(t0, t1, s.negative);
    var exit = select(t1, t0, s.negative) * BOX_ENLARGE;
//#if TRACE
    last_box = BoxLog(t0, t1, entry, exit);
//#endif
    entry = select(entry, vec3f(-params.inf), is_nan3(entry));
    exit = select(exit, vec3f(params.inf), is_nan3(exit));
    let e = max(entry.x, max(entry.y, entry.z));
    let x = min(exit.x, min(exit.y, exit.z));
    return vec2f(select(t_min, e, e > t_min), select(t_max, x, x < t_max));
}

// Tests a leaf's objects in leaf order. Closest hit: a hit shrinks t_max and becomes the best so
// far. Any hit (a shadow ray): the first hit is kept and ends the walk (returns false).
fn bvh_leaf(r: ptr<function, Ray>, best: ptr<function, Hit>, n: Node, leaves: u32, any: bool) -> bool {
    for (var k = n.first; k < n.first + n.count; k++) {
        let id = leaf_objects[leaves + k];
        let c = intersection(id, *r);
        if any_hit(c) {
//#if TRACE
            log_accept(id, c.t, (*r).t_max);
//#endif
            *best = Hit(id, c.t, c.u, c.v, c.aux, NO_INSTANCE);
            if any {
                return false;
            }
            (*r).t_max = c.t;
        }
    }
    return true;
}

// The CPU's walk (crates/raystep-core/src/accel/bvh/mod.rs): the root box, then both children of a node at a time,
// the nearer visited first (for a shadow ray, `any`, the farther: as the CPU's AnyHit), the other
// visited next or pushed on a small stack. The tree's nodes start at nodes[base] and its leaves'
// entries at leaf_objects[leaves] (the world's tree at 0 and 0; an instance's BLAS after them):
// a node's `first` counts from there, as in the CPU's own tree.
fn bvh_walk(base: u32, leaves: u32, ray: Ray, start: Hit, any: bool) -> Hit {
    var r = ray;
    var best = start;
    if best.object != NO_OBJECT {
        r.t_max = best.t;
    }
    let s = slab_ray(r);
    let root = nodes[base];
    let ir = box_interval(s, root, r.t_min, r.t_max);
    let root_hit = ir.x <= ir.y;
//#if TRACE
    log_node(EV_NODE, s, 0u, 0u, root, last_box, ir, select(ACTION_CULLED, select(ACTION_DESCEND, ACTION_TEST, root.count > 0u), root_hit));
//#endif
    if !root_hit {
        return best;
    }
    if root.count > 0u {
        bvh_leaf(&r, &best, root, leaves, any);
        return best;
    }
    var stack: array<u32, BVH_STACK>;
    var sp = 0u;
    var current = root.first;
//#if TRACE
    var depths: array<u32, BVH_STACK>;
    var depth = 1u;
//#endif
    loop {
        let a = nodes[base + current];
        let b = nodes[base + current + 1u];
        let ia = box_interval(s, a, r.t_min, r.t_max);
//#if TRACE
        let box_a = last_box;
//#endif
        let ib = box_interval(s, b, r.t_min, r.t_max);
//#if TRACE
        let box_b = last_box;
//#endif
        let a_first = (ia.x <= ib.x) != any;
        var near = a;
        var far = b;
        if !a_first {
            near = b;
            far = a;
        }
        let near_t = select(ib, ia, a_first);
        let far_t = select(ia, ib, a_first);
        var has_next = false;
        var next = 0u;
//#if TRACE
        let near_id = select(current + 1u, current, a_first);
        let far_id = select(current, current + 1u, a_first);
        let near_box = select_box(box_b, box_a, a_first);
        let far_box = select_box(box_a, box_b, a_first);
//#endif
        // The nearer child.
        let near_hit = near_t.x <= near_t.y && near_t.x <= r.t_max;
//#if TRACE
        log_node(EV_NODE, s, near_id, depth, near, near_box, near_t, select(ACTION_CULLED, select(ACTION_DESCEND, ACTION_TEST, near.count > 0u), near_hit));
//#endif
        if near_hit {
            if near.count > 0u {
                if !bvh_leaf(&r, &best, near, leaves, any) {
                    return best;
                }
            } else {
                next = near.first;
                has_next = true;
            }
        }
        // The farther child, re-checked against t_max (the nearer leaf may have shrunk it).
        let far_hit = far_t.x <= far_t.y && far_t.x <= r.t_max;
//#if TRACE
        log_node(EV_NODE, s, far_id, depth, far, far_box, far_t, select(ACTION_CULLED, select(select(ACTION_PUSHED, ACTION_DESCEND, !has_next), ACTION_TEST, far.count > 0u), far_hit));
//#endif
        if far_hit {
            if far.count > 0u {
                if !bvh_leaf(&r, &best, far, leaves, any) {
                    return best;
                }
            } else if !has_next {
                next = far.first;
                has_next = true;
            } else if sp < BVH_STACK {
                stack[sp] = far.first;
//#if TRACE
                depths[sp] = depth + 1u;
//#endif
                sp += 1u;
            }
        }
        if has_next {
            current = next;
//#if TRACE
            depth += 1u;
//#endif
        } else if sp > 0u {
            sp -= 1u;
            current = stack[sp];
//#if TRACE
            depth = depths[sp];
//#endif
        } else {
            break;
        }
    }
    return best;
}

fn bvh_closest(r: Ray) -> Hit {
    let planes = planes_closest(r);
    if params.n_nodes == 0u {
        return planes;
    }
    return bvh_walk(0u, 0u, r, planes, false);
}

//#if SHADOWS
fn bvh_any(r: Ray) -> bool {
    if planes_any(r) {
        return true;
    }
    if params.n_nodes == 0u {
        return false;
    }
    let found = bvh_walk(0u, 0u, r, no_hit(), true);
//#if TRACE
    if found.object != NO_OBJECT {
        blocker = found;
    }
//#endif
    return found.object != NO_OBJECT;
}
//#endif
