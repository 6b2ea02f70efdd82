// ---- traversal: the BVH, flattened into storage buffers (src/accel/bvh.rs) ----
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

// (t_near, t_far) of a node's box: the robust slab test (docs/NUMERICS.md), t_far enlarged by 1 + 2γ₃,
// a NaN slab distance (a ray lying in a face plane, 0·∞) imposing no limit.
fn box_interval(s: SlabRay, node: Node, t_min: f32, t_max: f32) -> vec2f {
    node_visits += 1u;
    let t0 = (node.min - s.origin) * s.inv;
    let t1 = (node.max - s.origin) * s.inv;
    var entry = select(t0, t1, s.negative);
    var exit = select(t1, t0, s.negative) * BOX_ENLARGE;
    entry = select(entry, vec3f(-params.inf), is_nan3(entry));
    exit = select(exit, vec3f(params.inf), is_nan3(exit));
    let e = max(entry.x, max(entry.y, entry.z));
    let x = min(exit.x, min(exit.y, exit.z));
    return vec2f(select(t_min, e, e > t_min), select(t_max, x, x < t_max));
}

fn bvh_closest(ray: Ray) -> Hit {
    var r = ray;
    var best = planes_closest(r);
    if best.object != NO_OBJECT {
        r.t_max = best.t;
    }
    if params.n_nodes == 0u {
        return best;
    }
    let s = slab_ray(r);
    let root = nodes[0];
    let ir = box_interval(s, root, r.t_min, r.t_max);
    if !(ir.x <= ir.y) {
        return best;
    }
    if root.count > 0u {
        for (var k = root.first; k < root.first + root.count; k++) {
            let id = leaf_objects[k];
            let c = intersection(id, r);
            if any_hit(c) {
                r.t_max = c.t;
                best = Hit(id, c.t, c.u, c.v, c.aux);
            }
        }
        return best;
    }
    var stack: array<u32, BVH_STACK>;
    var sp = 0u;
    var current = root.first;
    loop {
        let a = nodes[current];
        let b = nodes[current + 1u];
        let ia = box_interval(s, a, r.t_min, r.t_max);
        let ib = box_interval(s, b, r.t_min, r.t_max);
        let a_first = ia.x <= ib.x;
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
        // The nearer child.
        if near_t.x <= near_t.y && near_t.x <= r.t_max {
            if near.count > 0u {
                for (var k = near.first; k < near.first + near.count; k++) {
                    let id = leaf_objects[k];
                    let c = intersection(id, r);
                    if any_hit(c) {
                        r.t_max = c.t;
                        best = Hit(id, c.t, c.u, c.v, c.aux);
                    }
                }
            } else {
                next = near.first;
                has_next = true;
            }
        }
        // The farther child, re-checked against t_max (the nearer leaf may have shrunk it).
        if far_t.x <= far_t.y && far_t.x <= r.t_max {
            if far.count > 0u {
                for (var k = far.first; k < far.first + far.count; k++) {
                    let id = leaf_objects[k];
                    let c = intersection(id, r);
                    if any_hit(c) {
                        r.t_max = c.t;
                        best = Hit(id, c.t, c.u, c.v, c.aux);
                    }
                }
            } else if !has_next {
                next = far.first;
                has_next = true;
            } else if sp < BVH_STACK {
                stack[sp] = far.first;
                sp += 1u;
            }
        }
        if has_next {
            current = next;
        } else if sp > 0u {
            sp -= 1u;
            current = stack[sp];
        } else {
            break;
        }
    }
    return best;
}

//#if SHADOWS
fn bvh_any(r: Ray) -> bool {
    if planes_any(r) {
        return true;
    }
    if params.n_nodes == 0u {
        return false;
    }
    let s = slab_ray(r);
    var stack: array<u32, BVH_STACK>;
    var sp = 0u;
    stack[0] = 0u;
    sp = 1u;
    // Here a stack entry is a node to test (not a child pair): order does not matter for "any".
    while sp > 0u {
        sp -= 1u;
        let n = nodes[stack[sp]];
        let i = box_interval(s, n, r.t_min, r.t_max);
        if !(i.x <= i.y) {
            continue;
        }
        if n.count > 0u {
            for (var k = n.first; k < n.first + n.count; k++) {
                if any_hit(intersection(leaf_objects[k], r)) {
                    return true;
                }
            }
        } else if sp + 2u <= BVH_STACK {
            stack[sp] = n.first + 1u;
            stack[sp + 1u] = n.first;
            sp += 2u;
        }
    }
    return false;
}
//#endif
