// ---- traversal: the two levels (crates/raystep-core/src/accel/two_level.rs) ----
//
// After the world's own objects, the top-level BVH over the instances' world boxes is walked with
// the world ray; entering an instance carries the ray into its object space by M⁻¹ and walks the
// prototype's bottom-level BVH with it (bvh_walk, from the BLAS's root); a hit there is the
// closest so far and shortens the world ray the next TLAS boxes are tested against.
//
// Each instance has two records in `objects` from params.inst_at: [2i] holds M⁻¹'s three rows in
// a, b, c, its BLAS's root node (in `nodes`) in `kind` and the BLAS's first leaf entry (in
// `leaf_objects`) in `material`; [2i + 1] holds M's rows. The TLAS's nodes start at
// nodes[params.tlas_at], its leaves' instance lists at leaf_objects[params.tlas_leaves]; a node's
// `first` counts from there, as in the CPU's tree.

// A 3 × 4 affine matrix by rows (crates/raystep-core/src/scene/instance.rs `Affine`).
struct Affine {
    r0: vec4f,
    r1: vec4f,
    r2: vec4f,
}

fn instance_to_object(i: u32) -> Affine {
    let o = objects[params.inst_at + 2u * i];
    return Affine(o.a, o.b, o.c);
}

fn instance_to_world(i: u32) -> Affine {
    let o = objects[params.inst_at + 2u * i + 1u];
    return Affine(o.a, o.b, o.c);
}

// A point, each row ((m₀x + m₁y) + m₂z) + m₃ (Affine::point, in its order).
fn aff_point(m: Affine, p: vec3f) -> vec3f {
    return vec3f(
        m.r0.x * p.x + m.r0.y * p.y + m.r0.z * p.z + m.r0.w,
        m.r1.x * p.x + m.r1.y * p.y + m.r1.z * p.z + m.r1.w,
        m.r2.x * p.x + m.r2.y * p.y + m.r2.z * p.z + m.r2.w,
    );
}

// A direction: the linear part alone (Affine::vector).
fn aff_vector(m: Affine, v: vec3f) -> vec3f {
    return vec3f(
        m.r0.x * v.x + m.r0.y * v.y + m.r0.z * v.z,
        m.r1.x * v.x + m.r1.y * v.y + m.r1.z * v.z,
        m.r2.x * v.x + m.r2.y * v.y + m.r2.z * v.z,
    );
}

// A normal by the linear part's transpose (Affine::transpose_vector): with m = M⁻¹, M⁻ᵀ·n.
fn aff_transpose_vector(m: Affine, n: vec3f) -> vec3f {
    return vec3f(
        m.r0.x * n.x + m.r1.x * n.y + m.r2.x * n.z,
        m.r0.y * n.x + m.r1.y * n.y + m.r2.y * n.z,
        m.r0.z * n.x + m.r1.z * n.y + m.r2.z * n.z,
    );
}

// With m = M⁻¹ and n a unit object-space normal: |M⁻ᵀn| / |det M⁻¹|, det M⁻¹ = r₀·(r₁ × r₂)
// (Affine::area_scale, glam's cross and dot term for term).
fn aff_area_scale(m: Affine, n: vec3f) -> f32 {
    let det = fdot(m.r0.xyz, fcross(m.r1.xyz, m.r2.xyz));
    return fdiv(flen(aff_transpose_vector(m, n)), abs(det));
}

// The rounding-error bound of aff_point for a point carrying `error` (Affine::point_error).
fn aff_point_error(m: Affine, p: vec3f, error: vec3f) -> vec3f {
    return vec3f(
        aff_row_error(m.r0, p, error),
        aff_row_error(m.r1, p, error),
        aff_row_error(m.r2, p, error),
    );
}

fn aff_row_error(m: vec4f, p: vec3f, error: vec3f) -> f32 {
    let carried = abs(m.x) * error.x + abs(m.y) * error.y + abs(m.z) * error.z;
    let own = abs(m.x * p.x) + abs(m.y * p.y) + abs(m.z * p.z) + abs(m.w);
    return (GAMMA3 + 1.0) * carried + GAMMA3 * own;
}

// The world ray carried into instance i's object space (Affine::ray): origin as a point,
// direction as a vector, not renormalised, so t names the same point in both spaces.
fn instance_ray(i: u32, r: Ray) -> Ray {
    let m = instance_to_object(i);
    return Ray(aff_point(m, r.origin), aff_vector(m, r.dir), r.t_min, r.t_max);
}

//#if TRACE
fn log_instance(i: u32, local: Ray) {
    log_open();
    log_u(i);
    log_v(local.origin);
    log_v(local.dir);
    log_close(EV_INSTANCE);
}
//#endif

//#if TLAS_WALK
// Enters instance i (TwoLevel::enter): the ray into its object space, its BLAS walked. Returns
// whether it found a hit (the closest so far, for a closest-hit query).
fn instance_enter(i: u32, r: ptr<function, Ray>, best: ptr<function, Hit>, any: bool) -> bool {
    let local = instance_ray(i, *r);
    let rec = objects[params.inst_at + 2u * i];
//#if TRACE
    log_instance(i, local);
    current_instance = i;
//#endif
    var h = bvh_walk(rec.kind, rec.material, local, no_hit(), any);
//#if TRACE
    current_instance = NO_INSTANCE;
//#endif
    if h.object == NO_OBJECT {
        return false;
    }
    h.instance = i;
    (*r).t_max = h.t;
    *best = h;
    return true;
}

// How far along the ray a TLAS node's centre lies: ((min + max)·½ − S)·Q.
fn tlas_along(n: Node, r: Ray) -> f32 {
    return fdot((n.min + n.max) * 0.5 - r.origin, r.dir);
}

// The TLAS walk (TwoLevel::walk): a node is popped and its box tested; an inner node's two
// children are pushed, the one whose centre lies nearer along the ray on top (ties: the first);
// a leaf's instances are entered in order. `any`: the first hit ends the walk.
fn tlas_walk(ray: Ray, start: Hit, any: bool) -> Hit {
    var r = ray;
    var best = start;
    if best.object != NO_OBJECT {
        r.t_max = best.t;
    }
    if params.n_instances == 0u {
        return best;
    }
    let s = slab_ray(r);
    var stack: array<u32, TLAS_STACK>;
    stack[0] = 0u;
    var sp = 1u;
//#if TRACE
    var depths: array<u32, TLAS_STACK>;
    depths[0] = 0u;
//#endif
    while sp > 0u {
        sp -= 1u;
        let id = stack[sp];
        let node = nodes[params.tlas_at + id];
        let iv = box_interval(s, node, r.t_min, r.t_max);
        let hit = iv.x <= iv.y;
        let leaf = node.count > 0u;
//#if TRACE
        log_node(EV_TLAS_NODE, s, id, depths[sp], node, last_box, iv, select(ACTION_CULLED, select(ACTION_DESCEND, ACTION_TEST, leaf), hit));
        let depth = depths[sp];
//#endif
        if !hit {
            continue;
        }
        if leaf {
            for (var k = node.first; k < node.first + node.count; k++) {
                let i = leaf_objects[params.tlas_leaves + k];
                if instance_enter(i, &r, &best, any) && any {
                    return best;
                }
            }
        } else if sp + 2u <= TLAS_STACK {
            let a = node.first;
            let b = node.first + 1u;
            var top = a;
            var under = b;
            if !(tlas_along(nodes[params.tlas_at + a], r) <= tlas_along(nodes[params.tlas_at + b], r)) {
                top = b;
                under = a;
            }
            stack[sp] = under;
            stack[sp + 1u] = top;
//#if TRACE
            depths[sp] = depth + 1u;
            depths[sp + 1u] = depth + 1u;
//#endif
            sp += 2u;
        }
    }
    return best;
}

fn tlas_closest(world: Hit, r: Ray) -> Hit {
    return tlas_walk(r, world, false);
}

//#if SHADOWS
fn tlas_any(r: Ray) -> bool {
    let found = tlas_walk(r, no_hit(), true);
//#if TRACE
    if found.object != NO_OBJECT {
        blocker = found;
    }
//#endif
    return found.object != NO_OBJECT;
}
//#endif
//#endif
