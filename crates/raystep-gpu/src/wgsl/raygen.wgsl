// ---- ray generation: the camera's primary rays, the ray stack, and the shader entry points ----

// One ray still to trace: `weight` is its share of the pixel (the product of the weights from the
// camera: what the cut-off compares), `kind` how its parent adds its colour (FOLD_*).
struct Task {
    ray: Ray,
    depth: u32,
    weight: f32,
//#if REFRACTION
    media: Media,
//#endif
    kind: u32,
}

// How a ray's colour reaches its parent's: the primary is the sample; a reflection ray's colour
// is multiplied by `reflective` (and Schlick's R when glass blends), a refraction ray's by
// `transparency` (and 1 − R).
const FOLD_PRIMARY: u32 = 0u;
const FOLD_REFLECTION: u32 = 1u;
const FOLD_REFRACTION: u32 = 2u;

// The colour of each ray on the path from the primary to the ray being traced (one per depth:
// depth-first order finishes a ray's children before any other ray of its depth starts), summed
// in the CPU's order (crates/raystep-core/src/trace/whitted.rs `shade`: surface + reflected + refracted, each child
// multiplied as it comes back), so that the linear image is the CPU's bit for bit.
struct Fold {
    // The ray's own colour, then each finished child's term added in order.
    acc: vec3f,
    // Children pushed and not yet finished.
    pending: u32,
    // How its parent adds it (FOLD_*).
    kind: u32,
    // The hit's reflective, transparency, Schlick's R and 1 if the two are blended by R.
    coef: vec4f,
}
var<private> folds: array<Fold, RAY_STACK>;
// What closest_hit leaves for trace(): the coefficients of the hit it shaded (Fold.coef).
var<private> hit_coef: vec4f;

// The recursion of the CPU's Whitted tracer, made iterative: each hit pushes at most one
// reflection and one refraction ray, and depth-first order needs at most max_depth + 1 entries.
var<private> ray_stack: array<Task, RAY_STACK>;
var<private> ray_sp: u32;
//#if TRACE
// Beside each stacked ray: its id, its parent's, its kind and the weight its parent multiplies
// its colour by (set by take_ray_id before the push).
var<private> ray_info: array<vec4u, RAY_STACK>;
var<private> pending_ray: vec4u;
// What the camera computed for the primary ray: the offset in the pixel and the screen position.
var<private> camera_offset: vec2f;
var<private> camera_screen: vec2f;
//#endif

//#if REFRACTION
fn push_ray(r: Ray, depth: u32, weight: f32, media: Media, kind: u32) {
    if ray_sp < RAY_STACK {
//#if TRACE
        ray_info[ray_sp] = pending_ray;
//#endif
        ray_stack[ray_sp] = Task(r, depth, weight, media, kind);
        ray_sp += 1u;
        if depth > 0u {
            folds[depth - 1u].pending += 1u;
        }
    }
}
//#else
fn push_ray(r: Ray, depth: u32, weight: f32, kind: u32) {
    if ray_sp < RAY_STACK {
//#if TRACE
        ray_info[ray_sp] = pending_ray;
//#endif
        ray_stack[ray_sp] = Task(r, depth, weight, kind);
        ray_sp += 1u;
        if depth > 0u {
            folds[depth - 1u].pending += 1u;
        }
    }
}
//#endif

// Ray `depth` is finished: adds its colour to its parent's as the CPU's `shade` does
// (reflected · reflective [· R], then refracted · transparency [· (1 − R)]), and so on up while
// a parent has no child left to trace.
fn fold_up(depth: u32) {
    var k = depth;
    while k > 0u && folds[k].pending == 0u {
        let p = k - 1u;
        let coef = folds[p].coef;
        var term: vec3f;
        if folds[k].kind == FOLD_REFLECTION {
            term = folds[k].acc * coef.x;
            if coef.w != 0.0 {
                term = term * coef.z;
            }
        } else {
            term = folds[k].acc * coef.y;
            if coef.w != 0.0 {
                term = term * (1.0 - coef.z);
            }
        }
        folds[p].acc = folds[p].acc + term;
        folds[p].pending -= 1u;
        k = p;
    }
}

// What the debug pixel keeps of the primary ray (the first sample).
struct DebugRecord {
    object: u32,
    nodes: u32,
    t: f32,
    u: f32,
    v: f32,
    discriminant: f32,
    instance: u32,
    pad1: u32,
    color: vec4f,
}
var<private> debug_record: DebugRecord;

// pcg_hash and unit_float: crates/raystep-core/src/portable/random.wgsl.

// Where sample `k` lies inside pixel `p`, in [0, 1)² (crates/raystep-core/src/trace/sampling.rs `sample_offset`).
fn sample_offset(p: vec2u, k: u32) -> vec2f {
    let spp = params.spp;
    if spp <= 1u {
        return vec2f(0.5, 0.5);
    }
    let h1 = pcg_hash(p.x ^ pcg_hash(p.y ^ pcg_hash(k ^ pcg_hash(params.seed))));
    let h2 = pcg_hash(h1);
    return grid_point(k, spp, vec2f(unit_float(h1), unit_float(h2)));
}

// The camera (crates/raystep-core/src/trace/camera.rs): sx·half_width·u + sy·half_height·v − w, not yet normalized.
fn camera_dir(sx: f32, sy: f32) -> vec3f {
    return params.u * (sx * params.half_width) + params.v * (sy * params.half_height) - params.w;
}

// The primary ray of sample `k` of pixel `p`. `centre` is the rasterizer's interpolated direction
// through the pixel centre (fragment path); `exact` recomputes it per pixel as the CPU does
// (compute path, debug pixel).
fn ray_generation(p: vec2u, k: u32, centre: vec3f, exact: bool) -> Ray {
    let o = sample_offset(p, k);
    var d: vec3f;
//#if TRACE
    camera_offset = o;
    camera_screen = vec2f(bitcast<f32>(NOT_COMPUTED));
//#endif
    if exact {
        let sx = fdiv(2.0 * (f32(p.x) + o.x), f32(params.width)) - 1.0;
        let sy = 1.0 - fdiv(2.0 * (f32(p.y) + o.y), f32(params.height));
//#if TRACE
        camera_screen = vec2f(sx, sy);
//#endif
        d = camera_dir(sx, sy);
    } else {
        // Off-centre samples move along the image plane from the interpolated centre direction.
        let dx = fdiv(2.0 * (o.x - 0.5), f32(params.width));
        let dy = fdiv(-2.0 * (o.y - 0.5), f32(params.height));
        d = centre + params.u * (dx * params.half_width) + params.v * (dy * params.half_height);
    }
    return Ray(params.origin, unit(d), 0.0, params.inf);
}

// Traces one primary ray and everything it spawns; returns the sample's linear colour.
fn trace(primary: Ray, capture: bool) -> vec3f {
    var color = vec3f(0.0);
    ray_sp = 0u;
//#if TRACE
    next_ray_id = 1u;
    pending_ray = vec4u(0u, NO_OBJECT, KIND_PRIMARY, bitcast<u32>(1.0));
//#endif
//#if REFRACTION
    var air: Media;
    air.len = 0u;
    push_ray(primary, 0u, 1.0, air, FOLD_PRIMARY);
//#else
    push_ray(primary, 0u, 1.0, FOLD_PRIMARY);
//#endif
    var first = capture;
    while ray_sp > 0u {
        ray_sp -= 1u;
        let task = ray_stack[ray_sp];
//#if TRACE
        let info = ray_info[ray_sp];
        current_ray = info.x;
        log_ray(info.x, info.y, info.z, task.depth, task.ray, bitcast<f32>(info.w));
        if info.x == 0u {
            log_open();
            log_u(params.debug_pixel.x);
            log_u(params.debug_pixel.y);
            log_u(params.trace_sample);
            log_f(camera_offset.x);
            log_f(camera_offset.y);
            log_f(camera_screen.x);
            log_f(camera_screen.y);
            log_v(task.ray.dir);
            log_close(EV_CAMERA);
        }
//#endif
        node_visits = 0u;
        let d = task.depth;
        folds[d] = Fold(vec3f(0.0), 0u, task.kind, vec4f(0.0));
        let hit = traversal_closest(task.ray);
        if first {
            first = false;
            debug_record.object = hit.object;
            debug_record.nodes = node_visits;
            debug_record.t = hit.t;
            debug_record.u = hit.u;
            debug_record.v = hit.v;
            debug_record.discriminant = hit.aux;
            debug_record.instance = hit.instance;
        }
        if hit.object == NO_OBJECT {
//#if TRACE
            log_open();
            log_v(miss());
            log_close(EV_MISS);
            log_color(miss());
//#endif
            folds[d].acc = miss();
        } else {
            // Pushes the hit's children, counting them in folds[d].pending.
            let own = closest_hit(hit, task);
//#if TRACE
            log_color(own);
//#endif
            folds[d].acc = own;
            folds[d].coef = hit_coef;
        }
//#if TRACE
        log_end(hit);
//#endif
        fold_up(d);
    }
    // Every ray has been added to its parent's colour: the primary's is the sample's.
    color = folds[0].acc;
    return color;
}

// Adds samples [first, first + count) of pixel p, in order, onto `start`: the CPU's
// accumulate_samples (a sample that is not finite is left out of the sum).
fn accumulate(p: vec2u, centre: vec3f, exact: bool, capture: bool, first: u32, count: u32, start: vec3f) -> vec3f {
    var sum = start;
    for (var k = first; k < first + count; k++) {
//#if MC
        if capture && k == 0u {
            // The debug pixel's record: the primary ray's hit.
            _ = trace(ray_generation(p, k, centre, exact), true);
        }
        let c = mc_sample(p, k, ray_generation(p, k, centre, exact));
//#else
        let c = trace(ray_generation(p, k, centre, exact), capture && k == 0u);
//#endif
        if finite(c.x) && finite(c.y) && finite(c.z) {
            sum += c;
        }
    }
    return sum;
}

// The pixel's colour: the sum of its finite samples over spp.
fn render_pixel(p: vec2u, centre: vec3f, exact: bool, capture: bool) -> vec3f {
    let spp = max(params.spp, 1u);
    return fdiv3(accumulate(p, centre, exact, capture, 0u, spp, vec3f(0.0)), f32(spp));
}

// ---- fragment path: a full-screen triangle; the rasterizer interpolates the ray direction ----

struct VertexOut {
    @builtin(position) position: vec4f,
    @location(0) dir: vec3f,
}

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> VertexOut {
    // (−1, −1), (3, −1), (−1, 3): one triangle covering the screen. Clip space y points up like
    // the camera's sy, so sx, sy are the clip coordinates themselves.
    let xy = vec2f(f32((i << 1u) & 2u) * 2.0 - 1.0, f32(i & 2u) * 2.0 - 1.0);
    var out: VertexOut;
    out.position = vec4f(xy, 0.0, 1.0);
    out.dir = camera_dir(xy.x, xy.y);
    return out;
}

//#if TRACE
// ---- the trace shader's one entry point: one invocation traces sample params.trace_sample of
// params.debug_pixel and logs every step (crates/raystep-gpu/src/trace_log.rs reads the log) ----

@compute @workgroup_size(1)
fn trace_main() {
    log_at = LOG_HEADER;
    log_on = true;
//#if MC
    _ = mc_trace_pixel(params.debug_pixel, vec3f(0.0), true, true);
//#else
    let c = trace(ray_generation(params.debug_pixel, params.trace_sample, vec3f(0.0), true), false);
    log_open();
    log_v(c);
    log_close(EV_PIXEL);
//#endif
}

// The fragment path's trace: the same full-screen triangle, so the rasterizer interpolates the
// same direction for the pixel (the pass is scissored to it); that fragment logs its steps.
@fragment
fn fs_trace(in: VertexOut) -> @location(0) vec4f {
    let p = vec2u(floor(in.position.xy));
    if all(p == params.debug_pixel) {
        log_at = LOG_HEADER;
        log_on = true;
    }
//#if MC
    let c = mc_trace_pixel(p, in.dir, false, log_on);
//#else
    let c = trace(ray_generation(p, params.trace_sample, in.dir, false), false);
    log_open();
    log_v(c);
    log_close(EV_PIXEL);
//#endif
    return vec4f(c, 1.0);
}
//#else
// As the compute path's cs_main: the pass's samples added to the pixel's running sum (`running`,
// bound for the fragment pipeline too), the running mean written.
@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4f {
    let p = vec2u(floor(in.position.xy));
    let i = p.y * params.width + p.x;
    var sum = vec3f(0.0);
    if params.first_sample > 0u {
        sum = running[i].xyz;
    }
    sum = accumulate(p, in.dir, false, false, params.first_sample, params.pass_samples, sum);
    running[i] = vec4f(sum, 0.0);
    return vec4f(fdiv3(sum, f32(params.first_sample + params.pass_samples)), 1.0);
}

// ---- compute path: one invocation per pixel, the primary ray computed as on the CPU ----

@group(1) @binding(0) var output: texture_storage_2d<rgba32float, write>;
@group(1) @binding(1) var<storage, read_write> debug_out: DebugRecord;
// Each pixel's running sum of samples (a progressive render adds a pass at a time).
@group(1) @binding(2) var<storage, read_write> running: array<vec4f>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) gid: vec3u) {
    if gid.x >= params.width || gid.y >= params.height {
        return;
    }
    let i = gid.y * params.width + gid.x;
    var sum = vec3f(0.0);
    if params.first_sample > 0u {
        sum = running[i].xyz;
    }
    sum = accumulate(gid.xy, vec3f(0.0), true, false, params.first_sample, params.pass_samples, sum);
    running[i] = vec4f(sum, 0.0);
    textureStore(output, gid.xy, vec4f(fdiv3(sum, f32(params.first_sample + params.pass_samples)), 1.0));
}

// ---- the debug pixel: one invocation traces params.debug_pixel and keeps its primary ray ----

@compute @workgroup_size(1)
fn debug_main() {
    debug_record.object = NO_OBJECT;
    debug_record.instance = NO_INSTANCE;
    let c = render_pixel(params.debug_pixel, vec3f(0.0), true, true);
    debug_record.color = vec4f(c, 1.0);
    debug_out = debug_record;
}
//#endif
