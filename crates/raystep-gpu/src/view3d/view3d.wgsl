// raystep's 3D scene view: shaded triangles, instanced spheres and wide lines, depth-tested.
// Colours arrive in display (sRGB-encoded) values and are written as they are.

struct Globals {
    view_proj: mat4x4<f32>,
    // xyz: the eye; w unused.
    eye: vec4<f32>,
    // xy: the picture's size in pixels; z: how far lines are pulled towards the eye, as a
    // fraction of their distance (so a ray lying on a surface is not hidden by it).
    viewport: vec4<f32>,
};

@group(0) @binding(0) var<uniform> g: Globals;

struct Shaded {
    @builtin(position) pos: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) color: vec4<f32>,
    @location(2) world: vec3<f32>,
};

@vertex
fn vs_tri(
    @location(0) pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
) -> Shaded {
    var out: Shaded;
    out.pos = g.view_proj * vec4<f32>(pos, 1.0);
    out.normal = normal;
    out.color = color;
    out.world = pos;
    return out;
}

// The unit sphere scaled by the radius and carried by the linear map L with columns a0, a1, a2
// (the identity, or an instance's M: an ellipsoid), then moved to the centre. Its normal is
// L⁻ᵀ·unit, up to a factor: u.x·(a1 × a2) + u.y·(a2 × a0) + u.z·(a0 × a1) (the rows of L⁻¹
// times det L; the fragment shader normalizes and lights both sides alike).
@vertex
fn vs_sphere(
    @location(0) unit: vec3<f32>,
    @location(1) center_radius: vec4<f32>,
    @location(2) color: vec4<f32>,
    @location(3) a0: vec4<f32>,
    @location(4) a1: vec4<f32>,
    @location(5) a2: vec4<f32>,
) -> Shaded {
    var out: Shaded;
    let s = unit * center_radius.w;
    let world = center_radius.xyz + a0.xyz * s.x + a1.xyz * s.y + a2.xyz * s.z;
    out.pos = g.view_proj * vec4<f32>(world, 1.0);
    out.normal = cross(a1.xyz, a2.xyz) * unit.x + cross(a2.xyz, a0.xyz) * unit.y
        + cross(a0.xyz, a1.xyz) * unit.z;
    out.color = color;
    out.world = world;
    return out;
}

// A headlight: the light sits at the eye, so every surface facing the viewer is lit and the
// shape reads from any orbit; both sides of a surface are lit alike.
@fragment
fn fs_shaded(in: Shaded) -> @location(0) vec4<f32> {
    var n = in.normal;
    if (dot(n, n) < 1e-12) {
        n = vec3<f32>(0.0, 1.0, 0.0);
    }
    n = normalize(n);
    let l = normalize(g.eye.xyz - in.world);
    let shade = 0.35 + 0.65 * abs(dot(n, l));
    return vec4<f32>(in.color.rgb * shade, in.color.a);
}

struct Flat {
    @builtin(position) pos: vec4<f32>,
    @location(0) color: vec4<f32>,
};

// A line segment as a screen-aligned quad `width` pixels wide (both ends are in front of the
// eye: the CPU clips segments to the near plane first).
@vertex
fn vs_line(
    @builtin(vertex_index) vi: u32,
    @location(0) a: vec3<f32>,
    @location(1) b: vec3<f32>,
    @location(2) color: vec4<f32>,
    @location(3) width: f32,
) -> Flat {
    var ends = array<f32, 6>(0.0, 0.0, 1.0, 1.0, 0.0, 1.0);
    var sides = array<f32, 6>(-1.0, 1.0, -1.0, -1.0, 1.0, 1.0);
    let keep = 1.0 - g.viewport.z;
    let ca = g.view_proj * vec4<f32>(g.eye.xyz + (a - g.eye.xyz) * keep, 1.0);
    let cb = g.view_proj * vec4<f32>(g.eye.xyz + (b - g.eye.xyz) * keep, 1.0);
    let half = g.viewport.xy * 0.5;
    let sa = ca.xy / ca.w * half;
    let sb = cb.xy / cb.w * half;
    var dir = sb - sa;
    if (dot(dir, dir) < 1e-12) {
        dir = vec2<f32>(1.0, 0.0);
    }
    dir = normalize(dir);
    let perp = vec2<f32>(-dir.y, dir.x) * (width * 0.5);
    let i = min(vi, 5u);
    let c = mix(ca, cb, ends[i]);
    let offset = perp * sides[i] / half * c.w;
    var out: Flat;
    out.pos = vec4<f32>(c.xy + offset, c.z, c.w);
    out.color = color;
    return out;
}

@fragment
fn fs_flat(in: Flat) -> @location(0) vec4<f32> {
    return in.color;
}
