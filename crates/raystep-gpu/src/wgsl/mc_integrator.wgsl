// ---- Monte Carlo: the distribution and path integrators of crates/raystep-core/src/trace/ (distribution.rs, path.rs, monte_carlo.rs), with the
// lights of crates/raystep-core/src/mc/lights.rs and the BSDFs of crates/raystep-core/src/mc/bsdf.rs, step for step (the same random
// numbers from the same dimensions, the same operations in the same order), so that on the exact
// compute path a sample has the CPU's bits. The CPU recurses; here the radiance of each bounce is
// kept and folded back in the CPU's order (l + weight · Li, from the deepest bounce up). ----

// After the TLAS where there is one: Vulkan's descriptor bindings are packed (the SPIR-V loaded
// through passthrough names them as they are), so the scene's bindings have no gap.
//#if RAY_QUERY
@group(0) @binding(8) var<storage, read> mc: array<u32>;
//#else
@group(0) @binding(7) var<storage, read> mc: array<u32>;
//#endif

fn mcf(i: u32) -> f32 {
    return bitcast<f32>(mc[i]);
}

fn mcv(i: u32) -> vec3f {
    return vec3f(mcf(i), mcf(i + 1u), mcf(i + 2u));
}

// The header (crates/raystep-gpu/src/buffers.rs `mc_data`).
fn mc_integrator() -> u32 { return mc[MC_H_INTEGRATOR]; }
fn mc_strategy() -> u32 { return mc[MC_H_STRATEGY]; }
fn mc_stratified() -> bool { return mc[MC_H_STRATIFIED] != 0u; }
fn mc_rr_depth() -> u32 { return mc[MC_H_RR_DEPTH]; }
fn mc_n_lights() -> u32 { return mc[MC_H_N_LIGHTS]; }
fn mc_n_groups() -> u32 { return mc[MC_H_N_GROUPS]; }

// The slots of a bounce's block of dimensions (crates/raystep-core/src/trace/monte_carlo.rs `slot`).

fn mc_dimension(depth: u32, slot: u32) -> u32 {
    return DIMENSION_FIRST_BOUNCE + depth * DIMENSIONS_PER_BOUNCE + slot;
}

// The sample being traced.
var<private> s_pixel: vec2u;
var<private> s_sample: u32;

fn draw(dimension: u32) -> f32 {
    return mc_uniform(s_pixel, s_sample, dimension, params.seed);
}

fn draw_pair(dimension: u32) -> vec2f {
    let u = vec2f(draw(dimension), draw(dimension + 1u));
    if !mc_stratified() {
        return u;
    }
    return stratified_pair(s_pixel, s_sample, params.spp, dimension, params.seed, u);
}

fn max3(v: vec3f) -> f32 {
    return max(v.x, max(v.y, v.z));
}

// glam's normalize: v · (1/|v|).
fn g_normalize(v: vec3f) -> vec3f {
    return v * fdiv(1.0, flen(v));
}

// glam's normalize_or_zero.
fn g_normalize_or_zero(v: vec3f) -> vec3f {
    let rcp = fdiv(1.0, flen(v));
    if is_finite_f(rcp) && rcp > 0.0 {
        return v * rcp;
    }
    return vec3f(0.0);
}

// The CPU's Ray::new: finite origin and direction, a non-zero finite d·d.
fn ray_ok(o: vec3f, d: vec3f) -> bool {
    let dd = fdot(d, d);
    return finite(o.x) && finite(o.y) && finite(o.z) && finite(d.x) && finite(d.y) && finite(d.z)
        && dd != 0.0 && finite(dd);
}

// ---- materials ----


struct McMaterial {
    kind: u32,
    c: vec3f,       // albedo or tint
    param: f32,     // ior or alpha
    emission: vec3f,
    roughness: f32, // the material's, which a roughness texture scales
}

fn mc_material(object: u32) -> McMaterial {
    let i = mc[MC_H_OFF_MATERIALS] + MC_H_MATERIAL_WORDS * objects[object].material;
    return McMaterial(mc[i], mcv(i + 1u), mcf(i + 4u), mcv(i + 5u), mcf(i + 8u));
}

//#if TEXTURES
// The texture's colour multiplies a diffuse BSDF's albedo and a mirror's or glossy BSDF's tint;
// glass is not tinted (crates/raystep-core/src/scene/mod.rs Material::bsdf_textured).
// `ray` and `depth`: the ray that hit, for a trilinear image's ray cone.
fn mc_texture(m: ptr<function, McMaterial>, hit: Hit, it: Interaction, ray: Ray, depth: u32) {
    let distance = cone_reach(depth, hit, ray);
    let mat = materials[objects[hit.object].material];
    var texel = vec3f(1.0);
    if mat.texture != NO_TEXTURE {
        let th = texture_at(hit, it, mat.texture, ray, distance);
//#if TRACE
        log_texture(hit, th, mat.color * th.texel);
//#endif
        texel = th.texel;
    }
    // A glossy BSDF's roughness texture: roughness × its green channel, α = roughness², a mirror
    // below the least roughness (Material::bsdf_textured). Read after the colour's texture, as
    // the CPU's tracer reads them.
    if mat.roughness_texture != NO_TEXTURE && (*m).kind == BSDF_GLOSSY {
        let tr = texture_at(hit, it, mat.roughness_texture, ray, distance);
        let r = (*m).roughness * tr.texel.y;
//#if TRACE
        log_open();
        log_f(r);
        log_close(EV_ROUGHNESS);
        log_texture(hit, tr, vec3f(r));
//#endif
        if r < mcf(MC_H_MIN_ROUGHNESS) {
            (*m).kind = BSDF_MIRROR;
        } else {
            (*m).param = r * r;
        }
    }
    if mat.texture != NO_TEXTURE && (*m).kind != BSDF_GLASS {
        (*m).c = (*m).c * texel;
    }
}
//#endif

fn is_delta(m: McMaterial) -> bool {
    return m.kind == BSDF_MIRROR || m.kind == BSDF_GLASS;
}

// ---- BSDFs (crates/raystep-core/src/mc/bsdf.rs) ----

fn bsdf_mirror(wo: vec3f, n: vec3f) -> vec3f {
    return (2.0 * fdot(wo, n)) * n - wo;
}

fn smith_g1(alpha: f32, cos_v: f32) -> f32 {
    if cos_v <= 0.0 {
        return 0.0;
    }
    let cos2 = cos_v * cos_v;
    let tan2 = max(fdiv(1.0 - cos2, cos2), 0.0);
    return fdiv(2.0, 1.0 + fsqrt(1.0 + alpha * alpha * tan2));
}

fn bsdf_eval(m: McMaterial, wo: vec3f, wi: vec3f, n: vec3f) -> vec3f {
    let cos_o = fdot(wo, n);
    let cos_i = fdot(wi, n);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return vec3f(0.0);
    }
    if m.kind == BSDF_DIFFUSE {
        return fdiv3(m.c, MC_PI);
    }
    if m.kind == BSDF_GLOSSY {
        let h = g_normalize_or_zero(wo + wi);
        if all(h == vec3f(0.0)) {
            return vec3f(0.0);
        }
        let d = ggx_d(m.param, fdot(h, n), sin2_between(h, n));
        let g = smith_g1(m.param, cos_o) * smith_g1(m.param, cos_i);
        return m.c * fdiv(d * g, 4.0 * cos_o * cos_i);
    }
    return vec3f(0.0);
}

fn bsdf_pdf(m: McMaterial, wo: vec3f, wi: vec3f, n: vec3f) -> f32 {
    let cos_o = fdot(wo, n);
    let cos_i = fdot(wi, n);
    if cos_o <= 0.0 || cos_i <= 0.0 {
        return 0.0;
    }
    if m.kind == BSDF_DIFFUSE {
        return fdiv(cos_i, MC_PI);
    }
    if m.kind == BSDF_GLOSSY {
        let h = g_normalize_or_zero(wo + wi);
        let wo_h = fdot(wo, h);
        if all(h == vec3f(0.0)) || wo_h <= 0.0 {
            return 0.0;
        }
        let cos_h = fdot(h, n);
        return fdiv(ggx_d(m.param, cos_h, sin2_between(h, n)) * cos_h, 4.0 * wo_h);
    }
    return 0.0;
}

// A sampled direction (crates/raystep-core/src/mc/bsdf.rs BsdfSample): value is f (a delta's weight), cos |wi·n|,
// lobe 0 reflection, 1 transmission.
struct BsdfS {
    ok: bool,
    wi: vec3f,
    has_pdf: bool,
    pdf: f32,
    weight: vec3f,
    value: vec3f,
    cos: f32,
    lobe: u32,
}

fn no_bsdf_sample() -> BsdfS {
    return BsdfS(false, vec3f(0.0), false, 0.0, vec3f(0.0), vec3f(0.0), 0.0, 0u);
}

// The random numbers a step used, for its trace record: n of them, (dimension, value).
struct Draws {
    n: u32,
    d: vec3u,
    v: vec3f,
}

fn no_draws() -> Draws {
    return Draws(0u, vec3u(0u), vec3f(0.0));
}

// Glass's two lobes: x = the Fresnel reflectance; the reflection; the transmission (ok false under
// total internal reflection).
struct GlassLobes {
    fr: f32,
    reflection: BsdfS,
    transmission: BsdfS,
}

fn glass_lobes(ior: f32, wo: vec3f, n: vec3f, inside: bool) -> GlassLobes {
    let cos_o = fdot(wo, n);
    var eta = ior;
    if inside {
        eta = fdiv(1.0, ior);
    }
    let f = fresnel_dielectric(cos_o, eta);
    let reflection = BsdfS(true, bsdf_mirror(wo, n), false, 0.0, vec3f(1.0), vec3f(1.0), cos_o, 0u);
    var transmission = no_bsdf_sample();
    if f.y >= 0.0 {
        let cos_t = f.y;
        let w = vec3f(fdiv(1.0, eta * eta));
        let wi = g_normalize(fdiv3(-wo, eta) + (fdiv(cos_o, eta) - cos_t) * n);
        transmission = BsdfS(true, wi, false, 0.0, w, w, cos_t, 1u);
    }
    return GlassLobes(f.x, reflection, transmission);
}

fn bsdf_sample(m: McMaterial, wo: vec3f, n: vec3f, inside: bool, u_lobe: f32, u: vec2f) -> BsdfS {
    let cos_o = fdot(wo, n);
    if cos_o <= 0.0 {
        return no_bsdf_sample();
    }
    switch m.kind {
        case 0u: {
            let s = cosine_hemisphere(u);
            let wi = g_normalize(frame_to_world(frame_new(n), s.xyz));
            let c = fdot(wi, n);
            if c <= 0.0 || s.w <= 0.0 {
                return no_bsdf_sample();
            }
            let f = fdiv3(m.c, MC_PI);
            return BsdfS(true, wi, true, s.w, fdiv3(f * c, s.w), f, c, 0u);
        }
        case 3u: {
            let h = g_normalize(frame_to_world(frame_new(n), ggx_normal(m.param, u).xyz));
            let wi = bsdf_mirror(wo, h);
            let c = fdot(wi, n);
            if c <= 0.0 {
                return no_bsdf_sample();
            }
            let p = bsdf_pdf(m, wo, wi, n);
            let f = bsdf_eval(m, wo, wi, n);
            if p <= 0.0 || !is_finite_f(p) {
                return no_bsdf_sample();
            }
            return BsdfS(true, wi, true, p, fdiv3(f * c, p), f, c, 0u);
        }
        case 1u: {
            return BsdfS(true, bsdf_mirror(wo, n), false, 0.0, m.c, m.c, cos_o, 0u);
        }
        default: {
            let g = glass_lobes(m.param, wo, n, inside);
            if g.transmission.ok && u_lobe >= g.fr {
                return g.transmission;
            }
            return g.reflection;
        }
    }
}

// ---- lights (crates/raystep-core/src/mc/lights.rs) ----


fn light_at(index: u32) -> u32 {
    return mc[MC_H_OFF_LIGHTS] + MC_H_LIGHT_WORDS * index;
}

fn light_kind(index: u32) -> u32 {
    return mc[light_at(index)];
}

// (index, probability) picked from a running sum with u; ok false for none.
struct Pick {
    ok: bool,
    index: u32,
    p: f32,
}

fn pick_cdf(off: u32, n: u32, u: f32) -> Pick {
    if n == 0u {
        return Pick(false, 0u, 0.0);
    }
    let total = mcf(off + n - 1u);
    if !(total > 0.0) {
        return Pick(false, 0u, 0.0);
    }
    let goal = u * total;
    var i = 0u;
    while i < n && mcf(off + i) <= goal {
        i++;
    }
    i = min(i, n - 1u);
    var before = 0.0;
    if i > 0u {
        before = mcf(off + i - 1u);
    }
    let p = fdiv(mcf(off + i) - before, total);
    return Pick(p > 0.0, i, p);
}

fn lights_empty() -> bool {
    let n = mc_n_lights();
    return n == 0u || mcf(mc[MC_H_OFF_CDF] + n - 1u) <= 0.0;
}

fn lights_pick(u: f32) -> Pick {
    return pick_cdf(mc[MC_H_OFF_CDF], mc_n_lights(), u);
}

fn lights_pick_pdf(index: u32) -> f32 {
    let n = mc_n_lights();
    if n == 0u {
        return 0.0;
    }
    let total = mcf(mc[MC_H_OFF_CDF] + n - 1u);
    if !(total > 0.0) || index >= n {
        return 0.0;
    }
    return fdiv(mcf(light_at(index) + 19u), total);
}

fn light_of_object(object: u32) -> u32 {
    return mc[mc[MC_H_OFF_BY_OBJECT] + object];
}

fn pick_in_group(g: u32, u: f32) -> Pick {
    let at = mc[mc[MC_H_OFF_GROUPS] + 2u * g];
    let count = mc[mc[MC_H_OFF_GROUPS] + 2u * g + 1u];
    let k = pick_cdf(mc[MC_H_OFF_GROUP_CDF] + at, count, u);
    return Pick(k.ok, mc[mc[MC_H_OFF_MEMBERS] + at + k.index], k.p);
}

fn group_is_point(g: u32) -> bool {
    let at = mc[mc[MC_H_OFF_GROUPS] + 2u * g];
    let count = mc[mc[MC_H_OFF_GROUPS] + 2u * g + 1u];
    return count > 0u && light_kind(mc[mc[MC_H_OFF_MEMBERS] + at]) == LIGHT_POINT;
}

struct LightPoint {
    ok: bool,
    point: vec3f,
    wi: vec3f,
    pdf: f32,
    radiance: vec3f,
    distance: f32,
}

fn no_light_point() -> LightPoint {
    return LightPoint(false, vec3f(0.0), vec3f(0.0), 0.0, vec3f(0.0), 0.0);
}

fn light_sample_point(index: u32, p: vec3f, u: vec2f) -> LightPoint {
    let i = light_at(index);
    let kind = mc[i];
    let a = mcv(i + 2u);
    let radiance = mcv(i + 16u);
    if kind == LIGHT_TRIANGLE {
        let b = mcv(i + 5u);
        let c = mcv(i + 8u);
        let normal = mcv(i + 11u);
        let light_area = mcf(i + 14u);
        // Lights::sample: sample::triangle_point's point, with the light's area (f64 on the CPU)
        let bb = uniform_triangle(u);
        let q = a * (1.0 - bb.x - bb.y) + b * bb.x + c * bb.y;
        let d = q - p;
        let distance = flen(d);
        if !(distance > 0.0) {
            return no_light_point();
        }
        let wi = fdiv3(d, distance);
        let cos_l = -fdot(wi, normal);
        if cos_l > 0.0 {
            return LightPoint(true, q, wi, fdiv(distance * distance, light_area * cos_l), radiance, distance);
        }
        return LightPoint(true, q, wi, 0.0, vec3f(0.0), distance);
    }
    if kind == LIGHT_SPHERE {
        let radius = mcf(i + 15u);
        let to_center = a - p;
        let dc = flen(to_center);
        let s = sphere_cone(dc, radius, u);
        if !(s.w > 0.0) {
            return no_light_point();
        }
        let axis = fdiv3(to_center, dc);
        let wi = g_normalize(frame_to_world(frame_new(axis), s.xyz));
        let b = fdot(wi, to_center);
        let disc = max(radius * radius - (dc * dc - b * b), 0.0);
        let distance = b - fsqrt(disc);
        if !(distance > 0.0) {
            return no_light_point();
        }
        return LightPoint(true, p + wi * distance, wi, s.w, radiance, distance);
    }
    let d = a - p;
    let distance = flen(d);
    if !(distance > 0.0) {
        return no_light_point();
    }
    return LightPoint(true, a, fdiv3(d, distance), 0.0, fdiv3(radiance, distance * distance), distance);
}

fn light_pdf(index: u32, p: vec3f, q: vec3f) -> f32 {
    if index >= mc_n_lights() {
        return 0.0;
    }
    let i = light_at(index);
    let kind = mc[i];
    if kind == LIGHT_TRIANGLE {
        let normal = mcv(i + 11u);
        let area = mcf(i + 14u);
        let d = q - p;
        let d2 = fdot(d, d);
        let cos_l = abs(-fdot(g_normalize_or_zero(d), normal));
        if cos_l <= 0.0 {
            return 0.0;
        }
        return fdiv(d2, area * cos_l);
    }
    if kind == LIGHT_SPHERE {
        let radius = mcf(i + 15u);
        let dc = flen(mcv(i + 2u) - p);
        if dc <= radius {
            return 0.0;
        }
        return fdiv(1.0, 2.0 * MC_PI * cone_one_minus_cos(dc, radius).x);
    }
    return 0.0;
}

// ---- the integrators' steps ----

// Emission at the hit with its MIS weight against light sampling from the previous hit
// (has_prev: the ray was BSDF-sampled with density prev_pdf from prev_origin).
fn mc_emitted(object: u32, it: Interaction, m: McMaterial, has_prev: bool, prev_pdf: f32, prev_origin: vec3f, throughput: vec3f) -> vec3f {
    if max3(m.emission) <= 0.0 || it.inside {
        return vec3f(0.0);
    }
    var w = 1.0;
    var light_pdf_v = 0.0;
    if has_prev {
        let index = light_of_object(object);
        if index != 0xffffffffu {
            light_pdf_v = lights_pick_pdf(index) * light_pdf(index, prev_origin, it.point);
        }
        switch mc_strategy() {
            case STRATEGY_MIS: { w = power_heuristic(prev_pdf, light_pdf_v); }
            case STRATEGY_LIGHT: {
                if light_pdf_v > 0.0 {
                    w = 0.0;
                }
            }
            default: {}
        }
    }
//#if TRACE
    var b_pdf = 0.0;
    if has_prev {
        b_pdf = prev_pdf;
    }
    log_emitted(object, m.emission, light_pdf_v, b_pdf, w, throughput * m.emission * w);
//#endif
    return m.emission * w;
}

// Samples light `index` from the hit: f · L · cos · w / (pick · pdf).
fn mc_light_sample(it: Interaction, m: McMaterial, index: u32, select_pdf: f32, mis: bool, u: vec2f, depth: u32, throughput: vec3f, draws: Draws) -> vec3f {
    let lp = light_sample_point(index, it.point, u);
    if !lp.ok {
        return vec3f(0.0);
    }
    let delta = light_kind(index) == LIGHT_POINT;
    let f = bsdf_eval(m, it.eye, lp.wi, it.shading);
    let c = max(fdot(lp.wi, it.shading), 0.0);
    let b_pdf = bsdf_pdf(m, it.eye, lp.wi, it.shading);
    let pdf = select_pdf * lp.pdf;
    let useful = max3(lp.radiance) > 0.0 && max3(f) > 0.0 && c > 0.0;
    var blocked = false;
//#if TRACE
    var by = NO_OBJECT;
//#endif
    if useful {
        let o = spawn_origin(it, lp.wi);
        let d = lp.point - o;
        if ray_ok(o, d) {
//#if TRACE
            let parent = current_ray;
            let sid = next_ray_id;
            next_ray_id += 1u;
            log_spawn(sid);
            log_ray(sid, parent, KIND_SHADOW, depth + 1u, Ray(o, d, 0.0, SHADOW_T_MAX), 0.0);
            blocker = no_hit();
            current_ray = sid;
//#endif
            blocked = traversal_any(Ray(o, d, 0.0, SHADOW_T_MAX));
//#if TRACE
            log_end(blocker);
            current_ray = parent;
            by = blocker.object;
//#endif
        }
    }
    var w = 1.0;
    if !(delta || !mis || mc_strategy() != STRATEGY_MIS) {
        w = power_heuristic(pdf, b_pdf);
    }
    var estimate = vec3f(0.0);
    if useful && !blocked {
        var density = pdf;
        if delta {
            density = select_pdf;
        }
        if density > 0.0 {
            estimate = f * lp.radiance * fdiv(c * w, density);
        }
    }
//#if TRACE
    let g = sum_open(depth);
    log_light_sample(index, draws, lp, select_pdf, pdf, f, c, b_pdf, w, blocked, by, throughput * estimate);
    sum_close(g);
//#endif
    return estimate;
}

// ---- the path tracer ----

fn mc_path(primary: Ray) -> vec3f {
    var ls: array<vec3f, RAY_STACK>;
    var ws: array<vec3f, RAY_STACK>;
//#if TRACE
    // Each bounce's ray id and hit, for the records written as the radiance is folded back.
    var ids: array<u32, RAY_STACK>;
    var hits: array<Hit, RAY_STACK>;
    ids[0] = current_ray;
//#endif
    var ray = primary;
    var throughput = vec3f(1.0);
    var has_prev = false;
    var prev_pdf = 0.0;
    var prev_origin = primary.origin;
    var depth = 0u;
    var tail = vec3f(0.0);
    loop {
        let hit = traversal_closest(ray);
//#if TRACE
        hits[depth] = hit;
//#endif
        if hit.object == NO_OBJECT {
            tail = params.background;
//#if TRACE
            log_miss(params.background);
//#endif
            break;
        }
        let it = interact(hit, ray);
//#if TRACE
        log_mc_surface(it, hit, depth);
//#endif
        var m = mc_material(hit.object);
//#if TEXTURES
        mc_texture(&m, hit, it, ray, depth);
//#endif
        var l = mc_emitted(hit.object, it, m, has_prev, prev_pdf, prev_origin, throughput);
        if depth >= params.max_depth {
//#if TRACE
            log_depth_limit();
//#endif
            tail = l;
            break;
        }
        if !is_delta(m) && !lights_empty() && mc_strategy() != STRATEGY_BSDF {
            let pick_dim = mc_dimension(depth, SLOT_LIGHT_PICK);
            let u_pick = draw(pick_dim);
            let pick = lights_pick(u_pick);
            if pick.ok {
                let point_dim = mc_dimension(depth, SLOT_LIGHT_POINT);
                let u = draw_pair(point_dim);
                let draws = Draws(3u, vec3u(pick_dim, point_dim, point_dim + 1u), vec3f(u_pick, u.x, u.y));
                l += mc_light_sample(it, m, pick.index, pick.p, true, u, depth, throughput, draws);
            }
        }
        let lobe_dim = mc_dimension(depth, SLOT_LOBE);
        let bsdf_dim = mc_dimension(depth, SLOT_BSDF);
        let lobe = draw(lobe_dim);
        let u = draw_pair(bsdf_dim);
        let bs = bsdf_sample(m, it.eye, it.shading, it.inside, lobe, u);
        if !bs.ok {
            tail = l;
            break;
        }
        var weight = bs.weight;
        var next = throughput * weight;
//#if TRACE
        // The numbers the BSDF used: glass its lobe's, a mirror none (it is deterministic).
        var draws = Draws(2u, vec3u(bsdf_dim, bsdf_dim + 1u, 0u), vec3f(u.x, u.y, 0.0));
        if m.kind == BSDF_GLASS {
            draws = Draws(3u, vec3u(lobe_dim, bsdf_dim, bsdf_dim + 1u), vec3f(lobe, u.x, u.y));
        } else if m.kind == BSDF_MIRROR {
            draws = no_draws();
        }
        let g = sum_open(depth);
        log_bsdf_sample(m, bs, draws, next);
        sum_close(g);
//#endif
        let o = spawn_origin(it, bs.wi);
        if !ray_ok(o, bs.wi) {
            tail = l;
            break;
        }
        if depth + 1u > mc_rr_depth() {
            let rr_dim = mc_dimension(depth, SLOT_ROULETTE);
            let ur = draw(rr_dim);
            let q = min(max3(next), 1.0);
            let survived = ur < q;
            if survived {
                weight = fdiv3(weight, q);
                next = fdiv3(next, q);
            }
//#if TRACE
            log_roulette(rr_dim, ur, q, survived, next);
//#endif
            if !survived {
                tail = l;
                break;
            }
        }
        ls[depth] = l;
        ws[depth] = weight;
        has_prev = bs.has_pdf;
        prev_pdf = bs.pdf;
        prev_origin = it.point;
        throughput = next;
        ray = Ray(o, bs.wi, 0.0, params.inf);
//#if TRACE
        ids[depth + 1u] = log_child(bsdf_ray_kind(m, bs), depth + 1u, ray, weight);
//#endif
        depth += 1u;
    }
    var li = tail;
//#if TRACE
    log_color(li);
    log_end(hits[depth]);
//#endif
    while depth > 0u {
        depth -= 1u;
        li = ls[depth] + ws[depth] * li;
//#if TRACE
        current_ray = ids[depth];
        log_color(li);
        log_end(hits[depth]);
//#endif
    }
    return li;
}

// ---- the distribution ray tracer: the CPU's recursion with an explicit stack of frames, each
// with up to two children (glass's reflection and transmission), folded in the CPU's order ----

struct DFrame {
    l: vec3f,
    depth: u32,
    cur: u32,
    n: u32,
    w0: vec3f,
    w1: vec3f,
    t0: vec3f,
    t1: vec3f,
    r0: Ray,
    r1: Ray,
}

var<private> d_stack: array<DFrame, RAY_STACK>;

// A child the frame follows (crates/raystep-core/src/trace/distribution.rs `follow`): a valid ray above the cut-off. The
// trace shader keeps every direction sampled (frame `slot`'s branches) for its records.
fn d_add_child(f: ptr<function, DFrame>, it: Interaction, m: McMaterial, bs: BsdfS, throughput: vec3f, slot: u32, draws: Draws) {
    let next = throughput * bs.weight;
    let o = spawn_origin(it, bs.wi);
//#if TRACE
    var status = D_FOLLOW;
    if !ray_ok(o, bs.wi) {
        status = D_NO_RAY;
    } else if max3(next) < WEIGHT_CUTOFF {
        status = D_CUT;
    }
    d_keep_branch(slot, m, bs, draws, next, status);
//#endif
    if !ray_ok(o, bs.wi) || max3(next) < WEIGHT_CUTOFF {
        return;
    }
    let r = Ray(o, bs.wi, 0.0, params.inf);
    if (*f).n == 0u {
        (*f).w0 = bs.weight;
        (*f).t0 = next;
        (*f).r0 = r;
    } else {
        (*f).w1 = bs.weight;
        (*f).t1 = next;
        (*f).r1 = r;
    }
    (*f).n += 1u;
}

// Shades `ray` at `depth`: its local radiance and its children in a frame (stack slot `slot`).
fn d_shade(ray: Ray, depth: u32, throughput: vec3f, slot: u32) -> DFrame {
    var f: DFrame;
    f.depth = depth;
    f.cur = 0u;
    f.n = 0u;
    let hit = traversal_closest(ray);
//#if TRACE
    d_begin(slot, hit);
//#endif
    if hit.object == NO_OBJECT {
        f.l = params.background;
//#if TRACE
        log_miss(params.background);
//#endif
        return f;
    }
    let it = interact(hit, ray);
//#if TRACE
    log_mc_surface(it, hit, depth);
//#endif
    var m = mc_material(hit.object);
//#if TEXTURES
    mc_texture(&m, hit, it, ray, depth);
//#endif
    var l = mc_emitted(hit.object, it, m, false, 0.0, vec3f(0.0), throughput);
    if !is_delta(m) {
        for (var g = 0u; g < mc_n_groups(); g++) {
            let point = group_is_point(g);
            if m.kind == BSDF_GLOSSY && !point {
                continue;
            }
            let base = SLOT_GROUP + 3u * g;
            let pick_dim = mc_dimension(depth, base);
            let pick = draw(pick_dim);
            let u = draw_pair(pick_dim + 1u);
            let k = pick_in_group(g, pick);
            if !k.ok {
                continue;
            }
            var draws = Draws(3u, vec3u(pick_dim, pick_dim + 1u, pick_dim + 2u), vec3f(pick, u.x, u.y));
            if point {
                draws = no_draws();
            }
            l += mc_light_sample(it, m, k.index, k.p, false, u, depth, throughput, draws);
        }
    }
    f.l = l;
    if m.kind == BSDF_DIFFUSE || depth >= params.max_depth {
//#if TRACE
        if m.kind != BSDF_DIFFUSE {
            log_depth_limit();
        }
//#endif
        return f;
    }
    if m.kind == BSDF_GLASS {
        let g = glass_lobes(m.param, it.eye, it.shading, it.inside);
        var reflection = g.reflection;
        reflection.weight = reflection.weight * g.fr;
        d_add_child(&f, it, m, reflection, throughput, slot, no_draws());
        if g.transmission.ok {
            var t = g.transmission;
            t.weight = t.weight * (1.0 - g.fr);
            d_add_child(&f, it, m, t, throughput, slot, no_draws());
        }
    } else {
        let bsdf_dim = mc_dimension(depth, SLOT_BSDF);
        let u = draw_pair(bsdf_dim);
        let bs = bsdf_sample(m, it.eye, it.shading, it.inside, 0.0, u);
        var draws = no_draws();
        if m.kind == BSDF_GLOSSY {
            draws = Draws(2u, vec3u(bsdf_dim, bsdf_dim + 1u, 0u), vec3f(u.x, u.y, 0.0));
        }
        if bs.ok {
            d_add_child(&f, it, m, bs, throughput, slot, draws);
        }
    }
    return f;
}

fn mc_distribution(primary: Ray) -> vec3f {
    // The ray to shade next: the primary ray first, then each child a frame follows. d_shade is
    // called from one place: a shader compiler inlines every call, and each copy of d_shade holds
    // the (logged) traversal twice, for the hit and for the shadow rays; two copies took lavapipe
    // minutes to compile (docs/ARCHITECTURE.md, *Lavapipe's shader cache*).
    var ray = primary;
    var depth = 0u;
    var throughput = vec3f(1.0);
    var sp = 0u;
//#if TRACE
    d_id[0] = current_ray;
//#endif
    loop {
        d_stack[sp] = d_shade(ray, depth, throughput, sp);
        sp += 1u;
        // Finished frames give their radiance to their parents, until a frame has a child to
        // follow (or the primary ray's frame is done).
        loop {
            let top = sp - 1u;
            let f = d_stack[top];
            if f.cur >= f.n {
//#if TRACE
                current_ray = d_id[top];
                d_log_branches(top, f.depth, false);
                log_color(f.l);
                log_end(d_hit[top]);
//#endif
                // Done: its radiance goes to its parent, weighted as the parent followed it.
                sp -= 1u;
                if sp == 0u {
                    return f.l;
                }
                let parent = sp - 1u;
                var w = d_stack[parent].w0;
                if d_stack[parent].cur == 1u {
                    w = d_stack[parent].w1;
                }
                d_stack[parent].l = d_stack[parent].l + w * f.l;
                d_stack[parent].cur += 1u;
                continue;
            }
            var r = f.r0;
            var t = f.t0;
            if f.cur == 1u {
                r = f.r1;
                t = f.t1;
            }
            if sp >= RAY_STACK {
                // Cannot happen (depth ≤ max_depth < RAY_STACK); ends the branch as a miss would not.
                d_stack[top].cur += 1u;
                continue;
            }
//#if TRACE
            current_ray = d_id[top];
            d_log_branches(top, f.depth, true);
            d_id[sp] = d_log_followed(top, f.depth + 1u, r);
//#endif
            ray = r;
            depth = f.depth + 1u;
            throughput = t;
            break;
        }
    }
    return vec3f(0.0);
}

// One Monte Carlo sample of pixel p: the primary ray (through the thin lens when the camera has
// an aperture), then the scene's integrator.
fn mc_sample(p: vec2u, k: u32, primary: Ray) -> vec3f {
    s_pixel = p;
    s_sample = k;
    var ray = primary;
    let aperture = mcf(13u);
//#if TRACE
    var lens_used = false;
    var lens_u = vec2f(0.0);
    var lens_focus = vec3f(0.0);
//#endif
    if aperture > 0.0 {
        let u = draw_pair(LENS_DIMENSION);
        let d = concentric_disk(u);
        let disk = vec2f(aperture * d.x, aperture * d.y);
        let along = fdot(ray.dir, -params.w);
        if along > 0.0 && is_finite_f(aperture) {
            let focus = ray.origin + ray.dir * fdiv(mcf(14u), along);
            let origin = ray.origin + params.u * disk.x + params.v * disk.y;
            let dir = g_normalize_or_zero(focus - origin);
            if !all(dir == vec3f(0.0)) && finite(dir.x) && finite(dir.y) && finite(dir.z) {
                ray = Ray(origin, dir, 0.0, params.inf);
//#if TRACE
                lens_used = true;
                lens_u = u;
                lens_focus = focus;
//#endif
            }
        }
    }
//#if TRACE
    log_ray(0u, NO_OBJECT, KIND_PRIMARY, 0u, ray, 1.0);
    log_open();
    log_u(p.x);
    log_u(p.y);
    log_u(k);
    log_f(camera_offset.x);
    log_f(camera_offset.y);
    log_f(camera_screen.x);
    log_f(camera_screen.y);
    log_v(ray.dir);
    log_close(EV_CAMERA);
    if lens_used {
        log_lens(lens_u, ray.origin, lens_focus, fdiv(1.0, MC_PI * aperture * aperture), ray.dir);
    }
    current_ray = 0u;
    next_ray_id = 1u;
//#endif
    // Only the scene's integrator is compiled in, except in the full shader (ShaderConfig's
    // `path` and `distribution`).
//#if PATH
//#if DISTRIBUTION
    if mc_integrator() == MC_INTEGRATOR_PATH {
        return mc_path(ray);
    }
    return mc_distribution(ray);
//#else
    return mc_path(ray);
//#endif
//#else
    return mc_distribution(ray);
//#endif
}
