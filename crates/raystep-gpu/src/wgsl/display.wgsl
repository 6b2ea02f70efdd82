// Encodes the tracer's linear colour (rgba32float) as sRGB into the Rgba8Unorm texture the app
// shows, with the same transfer function as crates/raystep-core/src/render/image.rs `srgb8`.

@group(0) @binding(0) var linear_image: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4f {
    let xy = vec2f(f32((i << 1u) & 2u) * 2.0 - 1.0, f32(i & 2u) * 2.0 - 1.0);
    return vec4f(xy, 0.0, 1.0);
}

fn srgb(c: f32) -> f32 {
    let x = clamp(select(c, 0.0, c != c), 0.0, 1.0);
    if x <= 0.0031308 {
        return 12.92 * x;
    }
    return 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

@fragment
fn fs_main(@builtin(position) pos: vec4f) -> @location(0) vec4f {
    let c = textureLoad(linear_image, vec2i(floor(pos.xy)), 0).rgb;
    return vec4f(srgb(c.r), srgb(c.g), srgb(c.b), 1.0);
}
