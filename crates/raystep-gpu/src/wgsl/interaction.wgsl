// ---- closest-hit, part 1: where the ray met the surface (crates/raystep-core/src/trace/interaction.rs `interact`) ----
//
// Each shape computes the point from its own parametrization, with pbrt-v4's error bound.

struct Interaction {
    point: vec3f,
    normal: vec3f,    // unit, facing the incoming ray
    eye: vec3f,       // unit, from the point back towards the ray's origin
    inside: bool,
    error: vec3f,
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

fn interact(hit: Hit, r: Ray) -> Interaction {
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
    return Interaction(point, select(outward, -outward, inside), eye, inside, error);
}
