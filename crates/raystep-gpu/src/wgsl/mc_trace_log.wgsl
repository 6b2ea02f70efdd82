// ---- the GPU's own step trace of a Monte Carlo sample (`raystep trace --gpu` on a distribution
// or path scene): the records of the steps of crates/raystep-core/src/trace/distribution.rs and path.rs, written by mc_integrator.wgsl
// (crates/raystep-gpu/src/trace_log/mc.rs reads them), and the pixel's sample summaries. Compiled only into the
// trace shader of a Monte Carlo scene. ----
//
// After the traced sample's records and its pixel record, every sample of the pixel (the first
// MAX_PIXEL_SAMPLES) is traced again in summary mode: only the records the CPU's summary keeps
// (the camera ray's surface, its light samples, its BSDF sample) are written, then a sample
// record with its value and the object the camera ray hit.


// Summary mode: the log is off but for the records a summary keeps.
var<private> summary: bool;
// This invocation writes the log (on the fragment path, only the traced pixel's fragment does).
var<private> sum_active: bool;
// The object the camera ray of the sample being summarised hit.
var<private> sum_object: u32;

// Turns the log on for a record a summary keeps (at the camera ray's hit, depth 0); true when it
// did (sum_close turns it off again).
fn sum_open(depth: u32) -> bool {
    if summary && sum_active && depth == 0u && !log_full {
        log_on = true;
        return true;
    }
    return false;
}

fn sum_close(opened: bool) {
    if opened {
        log_on = false;
    }
}

fn log_draws(d: Draws) {
    log_u(d.n);
    log_u(d.d.x);
    log_u(d.d.y);
    log_u(d.d.z);
    log_v(d.v);
}

fn log_miss(background: vec3f) {
    log_open();
    log_v(background);
    log_close(EV_MISS);
}

fn log_mc_surface(it: Interaction, hit: Hit, depth: u32) {
    if depth == 0u {
        sum_object = hit.object;
    }
//#if INSTANCES
    // Not in a sample's summary: only the traced sample's steps.
    log_instance_hit(hit, it);
//#endif
    let g = sum_open(depth);
    log_open();
    log_v(it.point);
    log_v(it.normal);
    log_b(it.inside);
    log_v(it.error);
    log_v(spawn_origin(it, it.normal));
    log_close(EV_SURFACE);
    sum_close(g);
//#if SMOOTH
    // Not in a sample's summary: only the traced sample's steps.
    log_shading_normal(hit, it);
//#endif
}

fn log_lens(u: vec2f, lens_point: vec3f, focus: vec3f, pdf: f32, dir: vec3f) {
    log_open();
    log_u(LENS_DIMENSION);
    log_u(LENS_DIMENSION + 1u);
    log_f(u.x);
    log_f(u.y);
    log_v(lens_point);
    log_v(focus);
    log_f(pdf);
    log_v(dir);
    log_close(EV_LENS);
}

fn log_emitted(object: u32, radiance: vec3f, light_pdf: f32, bsdf_pdf: f32, w: f32, contribution: vec3f) {
    log_open();
    log_u(object);
    log_v(radiance);
    log_f(light_pdf);
    log_f(bsdf_pdf);
    log_f(w);
    log_v(contribution);
    log_close(EV_EMITTED);
}

fn log_light_sample(index: u32, draws: Draws, lp: LightPoint, select_pdf: f32, pdf: f32, f: vec3f, c: f32, bsdf_pdf: f32, w: f32, blocked: bool, by: u32, contribution: vec3f) {
    log_open();
    log_u(index);
    log_draws(draws);
    log_v(lp.point);
    log_v(lp.wi);
    log_f(lp.distance);
    log_f(select_pdf);
    log_f(pdf);
    log_v(lp.radiance);
    log_v(f);
    log_f(c);
    log_f(bsdf_pdf);
    log_f(w);
    log_b(blocked);
    log_u(by);
    log_v(contribution);
    log_close(EV_LIGHT_SAMPLE);
}

fn log_bsdf_sample(m: McMaterial, bs: BsdfS, draws: Draws, throughput: vec3f) {
    log_open();
    log_u(m.kind);
    log_u(bs.lobe);
    log_draws(draws);
    log_v(bs.wi);
    log_b(bs.has_pdf);
    log_f(bs.pdf);
    log_v(bs.value);
    log_f(bs.cos);
    log_v(bs.weight);
    log_v(throughput);
    log_close(EV_BSDF_SAMPLE);
}

fn log_roulette(dimension: u32, u: f32, q: f32, survived: bool, throughput: vec3f) {
    log_open();
    log_u(dimension);
    log_f(u);
    log_f(q);
    log_b(survived);
    log_v(throughput);
    log_close(EV_ROULETTE);
}

// The kind of ray a sampled direction makes (crates/raystep-core/src/trace/monte_carlo.rs `bsdf_step`).
fn bsdf_ray_kind(m: McMaterial, bs: BsdfS) -> u32 {
    if bs.lobe == 1u {
        return KIND_REFRACTION;
    }
    if m.kind == BSDF_DIFFUSE {
        return KIND_DIFFUSE;
    }
    if m.kind == BSDF_GLOSSY {
        return KIND_GLOSSY;
    }
    return KIND_REFLECTION;
}

// A child ray begins: its spawn and ray records (its weight in the trace is the mean of its
// three channels, as the CPU's); returns its id, now the current ray.
fn log_child(kind: u32, depth: u32, r: Ray, weight: vec3f) -> u32 {
    let id = next_ray_id;
    next_ray_id += 1u;
    log_spawn(id);
    log_ray(id, current_ray, kind, depth, r, fdiv(weight.x + weight.y + weight.z, 3.0));
    current_ray = id;
    return id;
}

// ---- the distribution tracer's frames: the CPU records a branch's BSDF sample just before its
// ray (and a second branch's after the first one's whole subtree), so each frame keeps its
// branches until their turn ----

const D_FOLLOW: u32 = 0u;
const D_CUT: u32 = 1u;
const D_NO_RAY: u32 = 2u;

struct DBranch {
    m: McMaterial,
    bs: BsdfS,
    draws: Draws,
    next: vec3f,
    status: u32,
}

var<private> d_branches: array<array<DBranch, 2>, RAY_STACK>;
var<private> d_n_branches: array<u32, RAY_STACK>;
var<private> d_logged: array<u32, RAY_STACK>;
var<private> d_hit: array<Hit, RAY_STACK>;
var<private> d_id: array<u32, RAY_STACK>;

fn d_begin(slot: u32, hit: Hit) {
    d_n_branches[slot] = 0u;
    d_logged[slot] = 0u;
    d_hit[slot] = hit;
}

fn d_keep_branch(slot: u32, m: McMaterial, bs: BsdfS, draws: Draws, next: vec3f, status: u32) {
    let k = d_n_branches[slot];
    if k < 2u {
        d_branches[slot][k] = DBranch(m, bs, draws, next, status);
        d_n_branches[slot] = k + 1u;
    }
}

// Writes frame `slot`'s branches not written yet, up to the next one it follows when `to_next`.
fn d_log_branches(slot: u32, depth: u32, to_next: bool) {
    while d_logged[slot] < d_n_branches[slot] {
        let b = d_branches[slot][d_logged[slot]];
        d_logged[slot] += 1u;
        let g = sum_open(depth);
        log_bsdf_sample(b.m, b.bs, b.draws, b.next);
        sum_close(g);
        if b.status == D_CUT {
            log_cutoff(bsdf_ray_kind(b.m, b.bs), max3(b.next));
        }
        if b.status == D_FOLLOW && to_next {
            return;
        }
    }
}

// The ray of the branch of frame `slot` written last begins; returns its id.
fn d_log_followed(slot: u32, depth: u32, r: Ray) -> u32 {
    let b = d_branches[slot][max(d_logged[slot], 1u) - 1u];
    return log_child(bsdf_ray_kind(b.m, b.bs), depth, r, b.bs.weight);
}

// The trace shader's pixel: sample params.trace_sample with every step, its value, then the
// summaries of the pixel's samples. `writes`: this invocation writes the log.
// One loop with one call of the integrator for both (i = 0 is the traced sample, i = k + 1 is
// sample k's summary): a shader compiler inlines every call, and a second call doubled the code
// lavapipe compiles (docs/ARCHITECTURE.md, *Lavapipe's shader cache*).
fn mc_trace_pixel(p: vec2u, centre: vec3f, exact: bool, writes: bool) -> vec3f {
    summary = false;
    sum_active = writes;
    let kept = min(max(params.spp, 1u), MAX_PIXEL_SAMPLES);
    var c = vec3f(0.0);
    for (var i = 0u; i <= kept; i++) {
        var k = params.trace_sample;
        if i > 0u {
            k = i - 1u;
            log_on = false;
            sum_object = NO_OBJECT;
        }
        let v = mc_sample(p, k, ray_generation(p, k, centre, exact));
        if i == 0u {
            c = v;
            log_open();
            log_v(c);
            log_close(EV_PIXEL);
            summary = true;
        } else if sum_active && !log_full {
            log_on = true;
            log_open();
            log_u(k);
            log_v(v);
            log_u(sum_object);
            log_close(EV_SAMPLE);
        }
    }
    log_on = false;
    summary = false;
    return c;
}
