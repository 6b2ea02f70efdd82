// ---- Monte Carlo sampling: crates/raystep-core/src/mc/sample.rs, the stratified pairs and the power heuristic of
// crates/raystep-core/src/trace/monte_carlo.rs, and the exact Fresnel reflectance of crates/raystep-core/src/mc/bsdf.rs, step for step (the
// same operations in the same order, `fdiv`/`fsqrt` where the CPU divides and takes roots, the
// portable p_sin_cos where it takes sines), so that on the exact compute path the GPU samples the
// CPU's directions bit for bit. ----

// Rust's std::f32::consts, written as the exact decimal of each f32.
const MC_PI: f32 = 3.1415927410125732;
const MC_FRAC_PI_4: f32 = 0.7853981852531433;
const MC_FRAC_PI_2: f32 = 1.5707963705062866;
// The largest f32 below 1.
const MC_ONE_BELOW: f32 = 0.9999999403953552;

// A sampled direction (xyz) and its density (w).
// Shirley and Chiu's concentric map of the unit square onto the unit disk.
fn concentric_disk(u: vec2f) -> vec2f {
    let a = 2.0 * u.x - 1.0;
    let b = 2.0 * u.y - 1.0;
    if a == 0.0 && b == 0.0 {
        return vec2f(0.0, 0.0);
    }
    var r: f32;
    var theta: f32;
    if abs(a) > abs(b) {
        r = a;
        theta = MC_FRAC_PI_4 * fdiv(b, a);
    } else {
        r = b;
        theta = MC_FRAC_PI_2 - MC_FRAC_PI_4 * fdiv(a, b);
    }
    let sc = p_sin_cos(theta);
    return vec2f(r * sc.y, r * sc.x);
}

// Malley's cosine-weighted hemisphere: (direction, pdf).
fn cosine_hemisphere(u: vec2f) -> vec4f {
    let d = concentric_disk(u);
    // crates/raystep-core/src/mc/sample.rs: z² = (1 − r)(1 + r) with r the disk point's radius.
    let r = max(abs(2.0 * u.x - 1.0), abs(2.0 * u.y - 1.0));
    let z = fsqrt(max((1.0 - r) * (1.0 + r), 0.0));
    return vec4f(d.x, d.y, z, fdiv(z, MC_PI));
}

// Uniform on the sphere: (direction, pdf).
fn uniform_sphere(u: vec2f) -> vec4f {
    let z = 1.0 - 2.0 * u.x;
    let r = fsqrt(max(1.0 - z * z, 0.0));
    let sc = p_sin_cos(2.0 * MC_PI * u.y);
    return vec4f(r * sc.y, r * sc.x, z, fdiv(1.0, 4.0 * MC_PI));
}

// Barycentric weights of a point uniform on a triangle.
fn uniform_triangle(u: vec2f) -> vec2f {
    let s = fsqrt(u.x);
    return vec2f(s * (1.0 - u.y), s * u.y);
}

// crates/raystep-core/src/mc/sample.rs cone_one_minus_cos: (1 − cos θ_max, cos θ_max) without the cancellation.
fn cone_one_minus_cos(distance: f32, radius: f32) -> vec2f {
    let q = fdiv(radius, distance);
    let sin2_max = q * q;
    let cos_max = fsqrt(max(1.0 - sin2_max, 0.0));
    return vec2f(fdiv(sin2_max, 1.0 + cos_max), cos_max);
}

// Uniform in the cone a sphere (radius, at `distance`) subtends: (direction, pdf); pdf 0 where
// the CPU returns None.
fn sphere_cone(distance: f32, radius: f32, u: vec2f) -> vec4f {
    if !(distance > radius && radius > 0.0) {
        return vec4f(0.0);
    }
    let one_minus_cos_max = cone_one_minus_cos(distance, radius).x;
    let x = u.x * one_minus_cos_max;
    let cos_t = 1.0 - x;
    let sin_t = fsqrt(max(x * (2.0 - x), 0.0));
    let sc = p_sin_cos(2.0 * MC_PI * u.y);
    let solid_angle = 2.0 * MC_PI * one_minus_cos_max;
    if !(solid_angle > 0.0) {
        return vec4f(0.0);
    }
    return vec4f(sin_t * sc.y, sin_t * sc.x, cos_t, fdiv(1.0, solid_angle));
}

// GGX's D(h) from cos θ_h and sin²θ_h (crates/raystep-core/src/mc/sample.rs ggx_d: the stable denominator).
fn ggx_d(alpha: f32, cos_h: f32, sin2_h: f32) -> f32 {
    if cos_h <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let t = a2 * (cos_h * cos_h) + sin2_h;
    return fdiv(a2, MC_PI * t * t);
}

// sin²θ between unit vectors as |a × b|² (crates/raystep-core/src/mc/sample.rs sin2_between).
fn sin2_between(a: vec3f, b: vec3f) -> f32 {
    let c = fcross(a, b);
    return fdot(c, c);
}

// A GGX microfacet normal: (h, D(h) cos θ_h); sin θ_h = √tan²θ_h · cos θ_h.
fn ggx_normal(alpha: f32, u: vec2f) -> vec4f {
    let tan2 = fdiv(alpha * alpha * u.x, max(1.0 - u.x, F32_MIN_POSITIVE));
    let cos_t = fdiv(1.0, fsqrt(1.0 + tan2));
    let sin_t = fsqrt(tan2) * cos_t;
    let sc = p_sin_cos(2.0 * MC_PI * u.y);
    return vec4f(sin_t * sc.y, sin_t * sc.x, cos_t, ggx_d(alpha, cos_t, sin_t * sin_t) * cos_t);
}

// Duff et al.'s orthonormal frame around unit n: columns s, t, n.
struct Frame {
    s: vec3f,
    t: vec3f,
    n: vec3f,
}

fn frame_new(n: vec3f) -> Frame {
    var sign = 1.0;
    if (bitcast<u32>(n.z) >> 31u) == 1u {
        sign = -1.0;
    }
    let a = fdiv(-1.0, sign + n.z);
    let b = n.x * n.y * a;
    return Frame(
        vec3f(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vec3f(b, sign + n.y * n.y * a, -n.y),
        n,
    );
}

fn frame_to_world(f: Frame, v: vec3f) -> vec3f {
    return f.s * v.x + f.t * v.y + f.n * v.z;
}

fn frame_to_local(f: Frame, v: vec3f) -> vec3f {
    return vec3f(fdot(v, f.s), fdot(v, f.t), fdot(v, f.n));
}

// Veach's power heuristic (β = 2).
fn power_heuristic(a: f32, b: f32) -> f32 {
    let a2 = a * a;
    let b2 = b * b;
    if a2 + b2 <= 0.0 || !is_finite_f(a2 + b2) {
        if a > 0.0 {
            return 1.0;
        }
        return 0.0;
    }
    return fdiv(a2, a2 + b2);
}

// The exact Fresnel reflectance at a smooth dielectric: (reflectance, cos θₜ), cos θₜ < 0 for
// total internal reflection (the CPU's None).
fn fresnel_dielectric(cos_in: f32, eta: f32) -> vec2f {
    let cos_i = clamp(cos_in, 0.0, 1.0);
    let sin2_t = fdiv(1.0 - cos_i * cos_i, eta * eta);
    if sin2_t >= 1.0 {
        return vec2f(1.0, -1.0);
    }
    let cos_t = fsqrt(max(1.0 - sin2_t, 0.0));
    let parallel = fdiv(eta * cos_i - cos_t, eta * cos_i + cos_t);
    let perpendicular = fdiv(cos_i - eta * cos_t, cos_i + eta * cos_t);
    return vec2f(0.5 * (parallel * parallel + perpendicular * perpendicular), cos_t);
}

// (a + b) mod m without overflow, for a, b < m.
fn add_mod(a: u32, b: u32, m: u32) -> u32 {
    if a >= m - b {
        return a - (m - b);
    }
    return a + b;
}

// a·b mod m without 64-bit integers (WGSL has none), for a, b < m: by doubling.
fn mul_mod(a: u32, b: u32, m: u32) -> u32 {
    var r = 0u;
    for (var i = 31; i >= 0; i--) {
        r = add_mod(r, r, m);
        if ((b >> u32(i)) & 1u) == 1u {
            r = add_mod(r, a, m);
        }
    }
    return r;
}

fn gcd_u(a0: u32, b0: u32) -> u32 {
    var a = a0;
    var b = b0;
    while b != 0u {
        let t = a % b;
        a = b;
        b = t;
    }
    return a;
}

// The stratified pair of crates/raystep-core/src/trace/monte_carlo.rs `stratified_pair`.
fn stratified_pair(pixel: vec2u, sample: u32, spp: u32, dimension: u32, seed: u32, jitter: vec2f) -> vec2f {
    if spp <= 1u {
        return jitter;
    }
    let h0 = u32(mc_uniform(pixel, 0xffffffffu, dimension, seed) * f32(spp)) % spp;
    let h1 = u32(mc_uniform(pixel, 0xfffffffeu, dimension, seed) * f32(spp)) % spp;
    var a = max(h0, 1u);
    while gcd_u(a, spp) != 1u {
        a = a % spp + 1u;
    }
    let cell = add_mod(mul_mod(a, sample % spp, spp), h1, spp);
    let q = grid_point(cell, spp, jitter);
    return vec2f(min(q.x, MC_ONE_BELOW), min(q.y, MC_ONE_BELOW));
}
