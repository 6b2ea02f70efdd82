// ---- closest-hit, part 1: where the ray met the surface (crates/raystep-core/src/trace/interaction.rs `interact`) ----
//
// Each shape computes the point from its own parametrization, with pbrt-v4's error bound.

struct Interaction {
    point: vec3f,
    normal: vec3f,    // unit, facing the incoming ray
    eye: vec3f,       // unit, from the point back towards the ray's origin
    inside: bool,
    error: vec3f,
    shading: vec3f,   // unit shading normal: `normal`, or a smooth triangle's blended vertex normals
    lifted: vec3f,    // where rays on the side of `shading` leave from: `point`, or Hanika's P′
    lifted_error: vec3f,
    object_point: vec3f,  // the point in the object's own space: `point`, except on an instance
    object_normal: vec3f, // the normal (facing the ray) in the object's own space
}

//#if TRIANGLES
// crates/raystep-core/src/trace/interaction.rs unit_normal: E1 × E2 normalized, the edges first scaled by a power of
// two (exact) where |E1 × E2| overflows or underflows.
fn unit_normal(e1: vec3f, e2: vec3f) -> vec3f {
    let n = fcross(e1, e2);
    let len = flen(n);
    if is_finite_f(len) && len >= 1.17549435e-38 {
        return fdiv3(n, len);
    }
    let m = max(max(max(abs(e1.x), abs(e2.x)), max(abs(e1.y), abs(e2.y))), max(abs(e1.z), abs(e2.z)));
    let exponent = i32((bitcast<u32>(m) >> 23u) & 0xffu) - 127;
    if exponent < -126 || exponent > 127 {
        return fdiv3(n, len);
    }
    let k = bitcast<f32>(u32(127 - exponent) << 23u);
    let nk = fcross(e1 * k, e2 * k);
    return fdiv3(nk, flen(nk));
}
//#endif

//#if SMOOTH
// crates/raystep-core/src/trace/interaction.rs blend_normals: (1 − u − v)·n₀ + u·n₁ + v·n₂,
// normalized, turned to the side of `facing` (w: the sign, 1 or −1); `facing` itself where the
// blend vanishes (w = 0).
fn blend_normals(n: Object, u: f32, v: f32, facing: vec3f) -> vec4f {
    let b0 = 1.0 - u - v;
    let s = n.a.xyz * b0 + n.b.xyz * u + n.c.xyz * v;
    let len = flen(s);
    if !(is_finite_f(len) && len >= 1.17549435e-38) {
        return vec4f(facing, 0.0);
    }
    let unit = fdiv3(s, len);
    if fdot(unit, facing) < 0.0 {
        return vec4f(-unit, -1.0);
    }
    return vec4f(unit, 1.0);
}
//#endif

//#if HANIKA
// crates/raystep-core/src/trace/interaction.rs lift_point: Hanika's shift of the shading point
// onto the vertices' tangent planes, blended with the barycentrics.
fn raise(p: vec3f, n: vec3f, point: vec3f) -> vec3f {
    return n * min(fdot(point - p, n), 0.0);
}

fn lift_point(o: Object, nv: Object, u: f32, v: f32, point: vec3f, side: f32) -> vec3f {
    let b0 = 1.0 - u - v;
    let r0 = raise(o.a.xyz, nv.a.xyz * side, point);
    let r1 = raise(o.b.xyz, nv.b.xyz * side, point);
    let r2 = raise(o.c.xyz, nv.c.xyz * side, point);
    return point - (r0 * b0 + r1 * u + r2 * v);
}
//#endif

// In the hit object's own space (the world's, for an object not instanced).
fn interact_local(hit: Hit, r: Ray) -> Interaction {
    let raw = r.origin + r.dir * hit.t;
    let o = objects[hit.object];
    var point = raw;
    var outward = vec3f(0.0, 0.0, 1.0);
    var error = vec3f(0.0);
    switch o.kind {
//#if SPHERES
        case 0u: {
            // Re-projected onto the sphere.
            let center = o.a.xyz;
            let radius = o.a.w;
            var rel = raw - center;
            let len = flen(rel);
            if len > 0.0 {
                rel = rel * fdiv(radius, len);
            }
            point = center + rel;
            outward = fdiv3(rel, radius);
            error = GAMMA5 * abs(rel) + GAMMA2 * abs(point);
        }
//#endif
//#if PLANES
        case 1u: {
            let n = o.a.xyz;
            let offset = o.a.w;
            point = raw - n * (fdot(raw, n) - offset);
            error = GAMMA7 * (abs(point) + abs(n) * (fdot(abs(point), abs(n)) + abs(offset)));
            outward = n;
        }
        case 2u: {
            // The coordinate snapped exactly onto the plane: no error on that axis.
            point[o.axis] = o.a.x;
            outward = vec3f(0.0);
            outward[o.axis] = 1.0;
            error = GAMMA3 * abs(point);
            error[o.axis] = 0.0;
        }
//#endif
//#if TRIANGLES
        case 3u: {
            // From the barycentrics.
            let p0 = o.a.xyz;
            let p1 = o.b.xyz;
            let p2 = o.c.xyz;
            let b0 = 1.0 - hit.u - hit.v;
            point = p0 * b0 + p1 * hit.u + p2 * hit.v;
            error = GAMMA7 * (abs(p0 * b0) + abs(p1 * hit.u) + abs(p2 * hit.v));
            outward = unit_normal(p1 - p0, p2 - p0);
        }
//#endif
        default: {}
    }
    let eye = fdiv3(-r.dir, flen(r.dir));
    let inside = fdot(outward, eye) < 0.0;
    let normal = select(outward, -outward, inside);
    var shading = normal;
    var lifted = point;
    var lifted_error = error;
//#if SMOOTH
    if o.normals != NO_NORMALS {
        let nv = objects[params.n_objects + o.normals];
        let b = blend_normals(nv, hit.u, hit.v, normal);
        shading = b.xyz;
//#if HANIKA
        if b.w != 0.0 {
            let l = lift_point(o, nv, hit.u, hit.v, point, b.w);
            if any(l != point) {
                lifted = l;
                lifted_error = error + GAMMA1 * abs(l);
            }
        }
//#endif
    }
//#endif
    return Interaction(point, normal, eye, inside, error, shading, lifted, lifted_error, point, normal);
}

// On an instance the interaction is computed in the prototype's object space, with the ray
// carried there by M⁻¹ as the traversal carried it, then taken back (`to_world`).
fn interact(hit: Hit, r: Ray) -> Interaction {
//#if INSTANCES
    if hit.instance != NO_INSTANCE {
        return to_world(hit.instance, interact_local(hit, instance_ray(hit.instance, r)), r);
    }
//#endif
    return interact_local(hit, r);
}

//#if INSTANCES
// M⁻ᵀ·n renormalised; n itself where the product's length is zero, subnormal or not finite.
fn normal_to_world(inv: Affine, n: vec3f) -> vec3f {
    let w = aff_transpose_vector(inv, n);
    let len = flen(w);
    if is_finite_f(len) && len >= 1.17549435e-38 {
        return fdiv3(w, len);
    }
    return n;
}

// crates/raystep-core/src/trace/interaction.rs to_world: the points by M with their error bounds
// carried, the normals by M⁻ᵀ, the eye direction from the world ray.
fn to_world(i: u32, it: Interaction, r: Ray) -> Interaction {
    let m = instance_to_world(i);
    let inv = instance_to_object(i);
    let point = aff_point(m, it.point);
    let error = aff_point_error(m, it.point, it.error);
    var lifted = point;
    var lifted_error = error;
    if any(it.lifted != it.point) {
        lifted = aff_point(m, it.lifted);
        lifted_error = aff_point_error(m, it.lifted, it.lifted_error);
    }
    return Interaction(
        point,
        normal_to_world(inv, it.normal),
        fdiv3(-r.dir, flen(r.dir)),
        it.inside,
        error,
        normal_to_world(inv, it.shading),
        lifted,
        lifted_error,
        it.point,
        it.normal,
    );
}
//#endif
