// ---- closest-hit, part 1b: the texture at the hit (crates/raystep-core/src/trace/texture.rs) ----
//
// The texture records live in the objects buffer after the objects (crates/raystep-gpu/src/buffers.rs):
// - a triangle's texture coordinates: objects[o.axis] holds t₀ in a.xy, t₁ in a.zw, t₂ in b.xy
//   (o.axis is NO_UVS for a triangle without them);
// - a texture: objects[material.texture]: kind (TEX_CHECKER, TEX_IMAGE); a checker's colours in
//   a.xyz and b.xyz, its squares in a.w and b.w; an image's width and height in c.x and c.y, its
//   filter in `material`, its wrap in `axis`, its first texel record in `normals`;
// - an image's texels, row 0 at the top, four to a record: a.xyz, b.xyz, c.xyz, (a.w, b.w, c.w).
// Every number is the CPU's operation in the CPU's order.

const TEX_PI: f32 = 3.1415927;
const TEX_FRAC_1_PI: f32 = 0.31830987;
const TEX_FRAC_1_2PI: f32 = 0.15915494;

struct TexHit {
    mapping: u32,
    uv: vec2f,
    direction: vec3f,
    cell: vec2f,
    odd: bool,
    wrapped: vec2f,
    address: vec2f,
    count: u32,
    at: array<vec2u, 4>,
    colors: array<vec3f, 4>,
    weights: vec4f,
    texel: vec3f,
}

// Duff et al.'s basis of the plane of unit normal n (texture.rs plane_axes).
fn tex_plane_axes(n: vec3f) -> array<vec3f, 2> {
    var s = -1.0;
    if n.z >= 0.0 {
        s = 1.0;
    }
    let a = fdiv(-1.0, s + n.z);
    let b = n.x * n.y * a;
    return array<vec3f, 2>(
        vec3f(1.0 + s * n.x * n.x * a, s * b, -s * n.x),
        vec3f(b, s + n.y * n.y * a, -n.y),
    );
}

fn tex_wrap(wrap: u32, t: f32) -> f32 {
    if wrap == WRAP_REPEAT {
        return t - floor(t);
    }
    if wrap == WRAP_CLAMP {
        return min(max(t, 0.0), 1.0);
    }
    let m = t - 2.0 * floor(t * 0.5);
    if m > 1.0 {
        return 2.0 - m;
    }
    return m;
}

fn tex_index(wrap: u32, i: f32, n: u32) -> u32 {
    let last = n - 1u;
    if i < 0.0 {
        return select(0u, last, wrap == WRAP_REPEAT);
    }
    if u32(i) > last {
        return select(last, 0u, wrap == WRAP_REPEAT);
    }
    return u32(i);
}

fn tex_fetch(first: u32, width: u32, x: u32, y: u32) -> vec3f {
    let k = y * width + x;
    let r = objects[first + k / 4u];
    switch k % 4u {
        case 0u: { return r.a.xyz; }
        case 1u: { return r.b.xyz; }
        case 2u: { return r.c.xyz; }
        default: { return vec3f(r.a.w, r.b.w, r.c.w); }
    }
}

fn texture_at(hit: Hit, it: Interaction, header: u32) -> TexHit {
    var th: TexHit;
    let o = objects[hit.object];
    // The texture coordinates.
    switch o.kind {
        case 0u: {
            var d = it.normal;
            if it.inside {
                d = -it.normal;
            }
            th.mapping = UV_SPHERE;
            th.direction = d;
            th.uv = vec2f(
                (p_atan2(-d.z, d.x) + TEX_PI) * TEX_FRAC_1_2PI,
                p_atan2(fsqrt(d.x * d.x + d.z * d.z), -d.y) * TEX_FRAC_1_PI,
            );
        }
        case 1u: {
            let a = tex_plane_axes(o.a.xyz);
            th.mapping = UV_PLANE;
            th.uv = vec2f(fdot(it.point, a[0]), fdot(it.point, a[1]));
        }
        case 2u: {
            th.mapping = UV_PLANE;
            if o.axis == 0u {
                th.uv = it.point.yz;
            } else if o.axis == 1u {
                th.uv = it.point.xz;
            } else {
                th.uv = it.point.xy;
            }
        }
        default: {
            th.mapping = UV_BARYCENTRIC;
            th.uv = vec2f(hit.u, hit.v);
            if o.axis != NO_UVS {
                let t = objects[o.axis];
                let b0 = 1.0 - hit.u - hit.v;
                th.mapping = UV_VERTEX_UVS;
                th.uv = vec2f(
                    t.a.x * b0 + t.a.z * hit.u + t.b.x * hit.v,
                    t.a.y * b0 + t.a.w * hit.u + t.b.y * hit.v,
                );
            }
        }
    }
    // The lookup.
    let h = objects[header];
    th.wrapped = th.uv;
    if h.kind == TEX_CHECKER {
        let i = floor(th.uv.x * h.a.w);
        let j = floor(th.uv.y * h.b.w);
        let s = i + j;
        th.cell = vec2f(i, j);
        th.odd = s - 2.0 * floor(s * 0.5) != 0.0;
        th.texel = select(h.a.xyz, h.b.xyz, th.odd);
        return th;
    }
    let width = u32(h.c.x);
    let height = u32(h.c.y);
    let wrap = h.axis;
    let u = tex_wrap(wrap, th.uv.x);
    let v = tex_wrap(wrap, th.uv.y);
    let x = u * h.c.x;
    let y = (1.0 - v) * h.c.y;
    th.wrapped = vec2f(u, v);
    th.address = vec2f(x, y);
    if h.material == FILTER_NEAREST {
        let at = vec2u(tex_index(wrap, floor(x), width), tex_index(wrap, floor(y), height));
        th.at[0] = at;
        th.colors[0] = tex_fetch(h.normals, width, at.x, at.y);
        th.weights = vec4f(1.0, 0.0, 0.0, 0.0);
        th.count = 1u;
        th.texel = th.colors[0];
        return th;
    }
    let xs = x - 0.5;
    let ys = y - 0.5;
    let x0 = floor(xs);
    let y0 = floor(ys);
    let fx = xs - x0;
    let fy = ys - y0;
    let cols = vec2u(tex_index(wrap, x0, width), tex_index(wrap, x0 + 1.0, width));
    let rows = vec2u(tex_index(wrap, y0, height), tex_index(wrap, y0 + 1.0, height));
    th.weights = vec4f((1.0 - fx) * (1.0 - fy), fx * (1.0 - fy), (1.0 - fx) * fy, fx * fy);
    var sum = vec3f(0.0);
    for (var k = 0u; k < 4u; k++) {
        let at = vec2u(cols[k & 1u], rows[k >> 1u]);
        let c = tex_fetch(h.normals, width, at.x, at.y);
        th.at[k] = at;
        th.colors[k] = c;
        sum = sum + c * th.weights[k];
    }
    th.count = 4u;
    th.texel = sum;
    return th;
}

//#if TRACE
// The Texture step (trace_log.rs texture_step): the hit's barycentrics, then everything the
// lookup computed.
fn log_texture(hit: Hit, th: TexHit, color: vec3f) {
    log_open();
    log_u(hit.object);
    log_f(hit.u);
    log_f(hit.v);
    log_u(th.mapping);
    log_f(th.uv.x);
    log_f(th.uv.y);
    log_v(th.direction);
    log_f(th.cell.x);
    log_f(th.cell.y);
    log_b(th.odd);
    log_f(th.wrapped.x);
    log_f(th.wrapped.y);
    log_f(th.address.x);
    log_f(th.address.y);
    log_u(th.count);
    for (var k = 0u; k < 4u; k++) {
        log_u(th.at[k].x);
        log_u(th.at[k].y);
        log_v(th.colors[k]);
        log_f(th.weights[k]);
    }
    log_v(th.texel);
    log_v(color);
    log_close(EV_TEXTURE);
}
//#endif
