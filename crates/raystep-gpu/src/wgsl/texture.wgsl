// ---- closest-hit, part 1b: the texture at the hit (crates/raystep-core/src/trace/texture.rs) ----
//
// The texture records live in the objects buffer after the objects (crates/raystep-gpu/src/buffers.rs):
// - a triangle's texture coordinates: objects[o.axis] holds t₀ in a.xy, t₁ in a.zw, t₂ in b.xy
//   (o.axis is NO_UVS for a triangle without them);
// - a texture: objects[material.texture]: kind (TEX_CHECKER, TEX_IMAGE); a checker's colours in
//   a.xyz and b.xyz, its squares in a.w and b.w; an image's width, height and number of mip
//   levels in c.x, c.y and c.z, its filter in `material`, its wrap in `axis`, its first texel
//   record in `normals`;
// - an image's texels, row 0 at the top, four to a record: a.xyz, b.xyz, c.xyz, (a.w, b.w, c.w);
//   a trilinear image's mip levels follow its own texels, each level's after the one below.
// Every number is the CPU's operation in the CPU's order.

const TEX_PI: f32 = 3.1415927;
const TEX_FRAC_1_PI: f32 = 0.31830987;
const TEX_FRAC_1_2PI: f32 = 0.15915494;
const TEX_TWO_PI_SQUARED: f32 = 19.739208;
const TEX_LOG2_E: f32 = 1.442695;

// The path length from the eye to each depth's hit (the CPU's Interaction::distance): a ray at
// depth k is a child of the hit at depth k − 1, and depth-first order shades every child of a
// hit before another hit of that hit's depth.
var<private> cone_distance: array<f32, RAY_STACK>;

// The path length from the eye to `hit` of ray `r` at `depth`, kept for its children.
fn cone_reach(depth: u32, hit: Hit, r: Ray) -> f32 {
    var travelled = 0.0;
    if depth > 0u {
        travelled = cone_distance[depth - 1u];
    }
    let d = travelled + hit.t * flen(r.dir);
    cone_distance[depth] = d;
    return d;
}

// A trilinear lookup's level of detail (texture.rs LevelOfDetail).
struct TexLod {
    width: f32,
    cos: f32,
    ratio: f32,
    footprint: f32,
    lambda: f32,
    levels: vec2u,
    count: u32,
    fraction: f32,
    addresses: array<vec2f, 2>,
    colors: array<vec3f, 2>,
    distance: f32,
}

struct TexHit {
    mapping: u32,
    uv: vec2f,
    direction: vec3f,
    cell: vec2f,
    odd: bool,
    wrapped: vec2f,
    address: vec2f,
    count: u32,
    at: array<vec2u, 8>,
    colors: array<vec3f, 8>,
    weights: array<f32, 8>,
    texel: vec3f,
    trilinear: bool,
    lod: TexLod,
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

fn tex_fetch(first: u32, offset: u32, width: u32, x: u32, y: u32) -> vec3f {
    let k = offset + y * width + x;
    let r = objects[first + k / 4u];
    switch k % 4u {
        case 0u: { return r.a.xyz; }
        case 1u: { return r.b.xyz; }
        case 2u: { return r.c.xyz; }
        default: { return vec3f(r.a.w, r.b.w, r.c.w); }
    }
}

// Level-0 texels per unit of surface area (texture.rs texels_per_area).
fn tex_ratio(o: Object, th: TexHit, size: vec2f) -> f32 {
    let texels = size.x * size.y;
    if o.kind == 3u {
        var uv_area = 1.0;
        if o.axis != NO_UVS {
            let t = objects[o.axis];
            let a = vec2f(t.a.z - t.a.x, t.a.w - t.a.y);
            let b = vec2f(t.b.x - t.a.x, t.b.y - t.a.y);
            uv_area = abs(a.x * b.y - a.y * b.x);
        }
        let area = flen(fcross(o.b.xyz - o.a.xyz, o.c.xyz - o.a.xyz));
        return fdiv(texels * uv_area, area);
    }
    if o.kind == 0u {
        let d = th.direction;
        let sin = fsqrt(d.x * d.x + d.z * d.z);
        return fdiv(texels, TEX_TWO_PI_SQUARED * (o.a.w * o.a.w) * sin);
    }
    return texels;
}

// One level of an image at the wrapped (u, v), nearest or bilinear: its texels into th from
// `first_slot`; returns (x, y) in .xy of the result's address and the colour.
struct TexLevel {
    address: vec2f,
    color: vec3f,
    n: u32,
}

fn tex_read_level(th: ptr<function, TexHit>, h: Object, level: u32, bilinear: bool, uv: vec2f, first_slot: u32) -> TexLevel {
    // The level's size and where its texels start (texture.rs mip_levels).
    var w = u32(h.c.x);
    var hh = u32(h.c.y);
    var offset = 0u;
    for (var k = 0u; k < level; k++) {
        offset += w * hh;
        w = max(w / 2u, 1u);
        hh = max(hh / 2u, 1u);
    }
    let wrap = h.axis;
    let x = uv.x * f32(w);
    let y = (1.0 - uv.y) * f32(hh);
    var out: TexLevel;
    out.address = vec2f(x, y);
    if !bilinear {
        let at = vec2u(tex_index(wrap, floor(x), w), tex_index(wrap, floor(y), hh));
        let c = tex_fetch(h.normals, offset, w, at.x, at.y);
        (*th).at[first_slot] = at;
        (*th).colors[first_slot] = c;
        (*th).weights[first_slot] = 1.0;
        out.color = c;
        out.n = 1u;
        return out;
    }
    let xs = x - 0.5;
    let ys = y - 0.5;
    let x0 = floor(xs);
    let y0 = floor(ys);
    let fx = xs - x0;
    let fy = ys - y0;
    let cols = vec2u(tex_index(wrap, x0, w), tex_index(wrap, x0 + 1.0, w));
    let rows = vec2u(tex_index(wrap, y0, hh), tex_index(wrap, y0 + 1.0, hh));
    let weights = vec4f((1.0 - fx) * (1.0 - fy), fx * (1.0 - fy), (1.0 - fx) * fy, fx * fy);
    var sum = vec3f(0.0);
    for (var k = 0u; k < 4u; k++) {
        let at = vec2u(cols[k & 1u], rows[k >> 1u]);
        let c = tex_fetch(h.normals, offset, w, at.x, at.y);
        (*th).at[first_slot + k] = at;
        (*th).colors[first_slot + k] = c;
        (*th).weights[first_slot + k] = weights[k];
        sum = sum + c * weights[k];
    }
    out.color = sum;
    out.n = 4u;
    return out;
}

// `distance`: the path length from the eye to the hit (cone_reach), for a trilinear image's
// ray cone.
fn texture_at(hit: Hit, it: Interaction, header: u32, r: Ray, distance: f32) -> TexHit {
    var th: TexHit;
    let o = objects[hit.object];
    // The texture coordinates.
    switch o.kind {
        case 0u: {
            var d = it.object_normal;
            if it.inside {
                d = -it.object_normal;
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
            th.uv = vec2f(fdot(it.object_point, a[0]), fdot(it.object_point, a[1]));
        }
        case 2u: {
            th.mapping = UV_PLANE;
            if o.axis == 0u {
                th.uv = it.object_point.yz;
            } else if o.axis == 1u {
                th.uv = it.object_point.xz;
            } else {
                th.uv = it.object_point.xy;
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
    let wrap = h.axis;
    let u = tex_wrap(wrap, th.uv.x);
    let v = tex_wrap(wrap, th.uv.y);
    th.wrapped = vec2f(u, v);
    if h.material == FILTER_TRILINEAR {
        // The ray cone's level of detail (texture.rs level_of_detail).
        th.trilinear = true;
        let n_levels = u32(h.c.z);
        var lod: TexLod;
        lod.distance = distance;
        lod.width = params.spread * distance;
        let d = fdiv3(r.dir, flen(r.dir));
        lod.cos = abs(fdot(it.normal, d));
        lod.ratio = tex_ratio(o, th, h.c.xy);
//#if INSTANCES
        // Per unit of world area: the prototype's density over M's stretch of the area
        // (instance.rs Affine::area_scale).
        if hit.instance != NO_INSTANCE {
            lod.ratio = fdiv(lod.ratio, aff_area_scale(instance_to_object(hit.instance), it.object_normal));
        }
//#endif
        lod.footprint = fdiv(lod.width * fsqrt(lod.ratio), lod.cos);
        lod.lambda = p_ln(lod.footprint) * TEX_LOG2_E;
        let last = f32(n_levels - 1u);
        var held = 0.0;
        if lod.lambda > 0.0 {
            held = min(lod.lambda, last);
        }
        let l0 = floor(held);
        lod.fraction = held - l0;
        lod.levels = vec2u(u32(l0), min(u32(l0) + 1u, n_levels - 1u));
        lod.count = select(1u, 2u, lod.fraction > 0.0);
        var count = 0u;
        for (var k = 0u; k < lod.count; k++) {
            let rl = tex_read_level(&th, h, lod.levels[k], true, vec2f(u, v), count);
            lod.addresses[k] = rl.address;
            lod.colors[k] = rl.color;
            count += rl.n;
        }
        th.count = count;
        th.address = lod.addresses[0];
        if lod.count == 2u {
            th.texel = lod.colors[0] * (1.0 - lod.fraction) + lod.colors[1] * lod.fraction;
        } else {
            th.texel = lod.colors[0];
        }
        th.lod = lod;
        return th;
    }
    let rl = tex_read_level(&th, h, 0u, h.material != FILTER_NEAREST, vec2f(u, v), 0u);
    th.address = rl.address;
    th.texel = rl.color;
    th.count = rl.n;
    return th;
}

//#if TRACE
// The Texture step (trace_log.rs texture_step): the hit's barycentrics, then everything the
// lookup computed.
fn log_texture(hit: Hit, th: TexHit, color: vec3f) {
    if th.trilinear {
        // The level of detail and the second level's texels first (trace_log.rs reads them
        // into the Texture record that follows).
        log_open();
        log_f(params.spread);
        log_f(th.lod.distance);
        log_f(th.lod.width);
        log_f(th.lod.cos);
        log_f(th.lod.ratio);
        log_f(th.lod.footprint);
        log_f(th.lod.lambda);
        log_u(th.lod.levels.x);
        log_u(th.lod.levels.y);
        log_u(th.lod.count);
        log_f(th.lod.fraction);
        for (var k = 0u; k < 2u; k++) {
            log_f(th.lod.addresses[k].x);
            log_f(th.lod.addresses[k].y);
            log_v(th.lod.colors[k]);
        }
        for (var k = 4u; k < 8u; k++) {
            log_u(th.at[k].x);
            log_u(th.at[k].y);
            log_v(th.colors[k]);
            log_f(th.weights[k]);
        }
        log_close(EV_TEXTURE_LOD);
    }
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
    log_u(min(th.count, 4u));
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
