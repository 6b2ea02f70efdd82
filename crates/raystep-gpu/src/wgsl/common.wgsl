// ---- common: the scene's data, as the CPU uploaded it (crates/raystep-gpu/src/buffers.rs writes these layouts) ----

struct Params {
    origin: vec3f,
    half_width: f32,
    u: vec3f,
    half_height: f32,
    v: vec3f,
    epsilon: f32,
    w: vec3f,
    seed: u32,
    background: vec3f,
    spp: u32,
    width: u32,
    height: u32,
    max_depth: u32,
    n_objects: u32,
    n_lights: u32,
    n_planes: u32,
    use_bvh: u32,
    n_nodes: u32,
    debug_pixel: vec2u,
    // +∞, uploaded from the CPU: WGSL has no infinity literal (a constant expression may not
    // overflow), and the slab test needs true IEEE infinities (docs/NUMERICS.md S20/S21).
    inf: f32,
    // The sample the trace shader traces (`raystep trace --gpu`); 0 when rendering.
    trace_sample: u32,
    // The compute path's pass: samples [first_sample, first_sample + pass_samples) are added to
    // each pixel's running sum (a progressive render); one pass of every sample otherwise.
    first_sample: u32,
    pass_samples: u32,
    // γ, the angle one pixel subtends at the eye: a ray cone's spread (CameraRays::spread).
    spread: f32,
    // The objects the world's own accelerator holds (brute force loops over these): every object
    // but the prototypes' (crates/raystep-core/src/scene/load/instances.rs moves those last).
    n_world: u32,
    // Instances (wgsl/traversal_instances.wgsl): their count, the first of their two records each
    // in `objects`, the TLAS's root in `nodes` and its first leaf entry in `leaf_objects`.
    n_instances: u32,
    inst_at: u32,
    tlas_at: u32,
    tlas_leaves: u32,
}

// kind: 0 sphere (a = centre, radius), 1 plane (a = normal, offset), 2 axis plane (axis, a.x =
// offset), 3 triangle (a, b, c = P0, P1, P2).
struct Object {
    a: vec4f,
    b: vec4f,
    c: vec4f,
    kind: u32,
    material: u32,
    // An axis plane's axis; a triangle's texture-coordinate record, objects[axis], or NO_UVS.
    axis: u32,
    // A smooth triangle's vertex normals: objects[params.n_objects + normals] holds n₀ n₁ n₂ in
    // a b c; NO_NORMALS for every other object.
    normals: u32,
}

struct Material {
    color: vec3f,
    ambient: f32,
    diffuse: f32,
    specular: f32,
    shininess: f32,
    reflective: f32,
    transparency: f32,
    refractive_index: f32,
    // The texture's record in the objects buffer (wgsl/texture.wgsl), or NO_TEXTURE.
    texture: u32,
    // A glossy BSDF's roughness texture's record, or NO_TEXTURE (Material::roughness_texture).
    roughness_texture: u32,
}

struct Light {
    position: vec3f,
    pad0: f32,
    color: vec3f,
    pad1: f32,
}

// A BVH node in raystep's layout (crates/raystep-core/src/accel/bvh.rs): a leaf has count > 0 objects starting at
// leaf_objects[first]; an inner node's children are nodes[first] and nodes[first + 1].
struct Node {
    min: vec3f,
    first: u32,
    max: vec3f,
    count: u32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> objects: array<Object>;
@group(0) @binding(2) var<storage, read> materials: array<Material>;
@group(0) @binding(3) var<storage, read> lights: array<Light>;
@group(0) @binding(4) var<storage, read> nodes: array<Node>;
@group(0) @binding(5) var<storage, read> leaf_objects: array<u32>;
@group(0) @binding(6) var<storage, read> planes: array<u32>;

// A ray p(t) = origin + t·dir, hits accepted in (t_min, t_max): the CPU's `Ray<f32>`.
struct Ray {
    origin: vec3f,
    dir: vec3f,
    t_min: f32,
    t_max: f32,
}

// A candidate from an intersection function. aux: the sphere's discriminant, the triangle's
// determinant or the plane's denominator (for the debug pixel).
struct Cand {
    hit: bool,
    t: f32,
    u: f32,
    v: f32,
    aux: f32,
}


// The closest hit so far. instance: the instance the object was met through (its object is then
// a prototype's, in object space), or NO_INSTANCE.
struct Hit {
    object: u32,
    t: f32,
    u: f32,
    v: f32,
    aux: f32,
    instance: u32,
}

fn no_hit() -> Hit {
    return Hit(NO_OBJECT, 0.0, 0.0, 0.0, 0.0, NO_INSTANCE);
}

fn no_cand(aux: f32) -> Cand {
    return Cand(false, 0.0, 0.0, 0.0, aux);
}

fn accepts(r: Ray, t: f32) -> bool {
    return t > r.t_min && t < r.t_max;
}

// Finite (neither ±∞ nor NaN), decided on the bits so no compiler can assume it away.
fn finite(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7f800000u) != 0x7f800000u;
}

fn is_nan(x: f32) -> bool {
    return (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u;
}

// The CPU's normalize: v / |v| (not WGSL's normalize, which may use an approximate inverse sqrt).
fn unit(v: vec3f) -> vec3f {
    return fdiv3(v, flen(v));
}

// v − 2(v·n)n, as crates/raystep-core/src/trace/shading.rs `reflect` (named apart from WGSL's built-in).
fn mirror_dir(v: vec3f, n: vec3f) -> vec3f {
    return v - n * (2.0 * fdot(v, n));
}

// BVH node visits of the ray being traced (read by the debug pixel).
var<private> node_visits: u32;
