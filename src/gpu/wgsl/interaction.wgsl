// ---- closest-hit, part 1: where the ray met the surface (src/trace/whitted.rs `interact`) ----
//
// Each shape computes the point from its own parametrization, with pbrt-v4's error bound.

struct Interaction {
    point: vec3f,
    normal: vec3f,    // unit, facing the incoming ray
    eye: vec3f,       // unit, from the point back towards the ray's origin
    inside: bool,
    error: vec3f,
}

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
            let n = fcross(p1 - p0, p2 - p0);
            outward = fdiv3(n, flen(n));
        }
//#endif
        default: {}
    }
    let eye = fdiv3(-r.dir, flen(r.dir));
    let inside = fdot(outward, eye) < 0.0;
    return Interaction(point, select(outward, -outward, inside), eye, inside, error);
}
