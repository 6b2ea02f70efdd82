// ---- the GPU's own step trace (`raystep trace --gpu`): one invocation appends every step it
// takes to a bounded log, which crates/raystep-gpu/src/trace_log.rs reads back into raystep's trace format.
// Compiled only into the trace shader: the shaders that render are the same without it. ----
//
// trace_log[0]: words written; [1]: 1 when the log ran out of room (the steps after that point
// were not kept); from LOG_HEADER on, records: a header word (tag << 16 | payload words), then
// the payload (f32 stored as their bits).

@group(1) @binding(0) var<storage, read_write> trace_log: array<u32>;

// No record is longer than this (the longest, a triangle test, has 44 words).
// A scratch slot the kernel did not reach (read back as "not computed"): a NaN's bits. A
// private variable, not a constant: a bitcast of a constant is evaluated when the shader is
// compiled, and WGSL has no constant NaN (Chrome's compiler rejects it).
var<private> NOT_COMPUTED: u32 = 0x7fc0deadu;

// Monte Carlo (crates/raystep-gpu/src/wgsl/mc_trace_log.wgsl).

// Ray kinds, as crates/raystep-core/src/record/steps.rs RayKind.

var<private> log_on: bool;
// The log ran out of room (nothing more is written).
var<private> log_full: bool;
var<private> log_at: u32;
var<private> log_head: u32;

// The intermediates of the intersection kernel that ran last (slot meanings per kernel in
// crates/raystep-gpu/src/trace_log.rs).
var<private> scratch: array<f32, 32>;

// Ray ids: the primary ray is 0; each spawned ray takes the next.
var<private> next_ray_id: u32;
var<private> current_ray: u32;

// The instance whose BLAS is being walked (its node visits and hits name it), or NO_INSTANCE.
var<private> current_instance: u32 = NO_INSTANCE;

fn scratch_clear() {
    for (var i = 0u; i < 32u; i++) {
        scratch[i] = bitcast<f32>(NOT_COMPUTED);
    }
}

fn log_open() {
    if !log_on {
        return;
    }
    if log_at + LOG_RECORD_MAX > arrayLength(&trace_log) {
        trace_log[1] = 1u;
        log_on = false;
        log_full = true;
        return;
    }
    log_head = log_at;
    log_at += 1u;
}

fn log_u(x: u32) {
    if log_on {
        trace_log[log_at] = x;
        log_at += 1u;
    }
}

fn log_f(x: f32) {
    log_u(bitcast<u32>(x));
}

fn log_v(v: vec3f) {
    log_f(v.x);
    log_f(v.y);
    log_f(v.z);
}

fn log_b(b: bool) {
    log_u(select(0u, 1u, b));
}

fn log_close(tag: u32) {
    if log_on {
        trace_log[log_head] = (tag << 16u) | (log_at - log_head - 1u);
        trace_log[0] = log_at;
    }
}

// A ray starts: its id, its parent's, kind, depth, the ray, and the weight its parent multiplies
// its colour by.
fn log_ray(id: u32, parent: u32, kind: u32, depth: u32, r: Ray, weight: f32) {
    log_open();
    log_u(id);
    log_u(parent);
    log_u(kind);
    log_u(depth);
    log_v(r.origin);
    log_v(r.dir);
    log_f(r.t_min);
    log_f(r.t_max);
    log_f(weight);
    log_close(EV_RAY);
}

fn log_accept(id: u32, t: f32, previous: f32) {
    log_open();
    log_u(id);
    log_f(t);
    log_f(previous);
    log_close(EV_ACCEPT);
}

fn log_spawn(child: u32) {
    log_open();
    log_u(child);
    log_close(EV_SPAWN);
}

fn log_end(hit: Hit) {
    log_open();
    log_u(hit.object);
    log_f(hit.t);
    log_f(hit.u);
    log_f(hit.v);
    log_u(hit.instance);
    log_close(EV_END);
}

fn log_color(c: vec3f) {
    log_open();
    log_v(c);
    log_close(EV_COLOR);
}

// The blocker a shadow ray found (its end record names it).
var<private> blocker: Hit;

fn log_blocker(id: u32, c: Cand, t_max: f32) {
    log_accept(id, c.t, t_max);
    blocker = Hit(id, c.t, c.u, c.v, c.aux, current_instance);
}

//#if SMOOTH
// Smooth shading's step (crates/raystep-core/src/trace/tracer.rs `surface`: after the surface, on a
// triangle with vertex normals): the object, u, v, the shading normal, the geometric normal and
// the point rays leave from on the ray's side.
fn log_shading_normal(hit: Hit, it: Interaction) {
    if objects[hit.object].normals == NO_NORMALS {
        return;
    }
    // On an instance, the blend in object space, as the interaction computed it before M⁻ᵀ
    // carried it out (crates/raystep-core/src/trace/tracer.rs `surface`).
    var shading = it.shading;
    var geometric = it.normal;
    if hit.instance != NO_INSTANCE {
        geometric = it.object_normal;
        shading = blend_normals(objects[params.n_objects + objects[hit.object].normals], hit.u, hit.v, geometric).xyz;
    }
    log_open();
    log_u(hit.object);
    log_f(hit.u);
    log_f(hit.v);
    log_v(shading);
    log_v(geometric);
    log_v(it.lifted);
    log_close(EV_SHADING_NORMAL);
}
//#endif

//#if INSTANCES
// The hit carried back from an instance's object space (before the surface's record): the
// instance, the point and normal in object space, M·point, M⁻ᵀ·normal renormalised, and M·normal
// renormalised (the classic mistake, shown beside it).
fn log_instance_hit(hit: Hit, it: Interaction) {
    if hit.instance == NO_INSTANCE {
        return;
    }
    let wrong = aff_vector(instance_to_world(hit.instance), it.object_normal);
    log_open();
    log_u(hit.instance);
    log_v(it.object_point);
    log_v(it.object_normal);
    log_v(it.point);
    log_v(it.normal);
    log_v(fdiv3(wrong, flen(wrong)));
    log_close(EV_INSTANCE_HIT);
}
//#endif
