// ---- random numbers: random.rs beside this file (the twin) ----

// The PCG hash (Jarzynski & Olano 2020), as random.rs.
fn pcg_hash(input: u32) -> u32 {
    let state = input * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn unit_float(h: u32) -> f32 {
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

// The `dimension`-th uniform number of sample `sample` of `pixel` (random.rs `uniform`):
// a chain of PCG hashes, the top 24 bits.
fn mc_uniform(pixel: vec2u, sample: u32, dimension: u32, seed: u32) -> f32 {
    return unit_float(pcg_hash(dimension ^ pcg_hash(pixel.x ^ pcg_hash(pixel.y ^ pcg_hash(sample ^ pcg_hash(seed))))));
}

// Where `jitter` lands in cell `k` of the grid of `n` equal cells (random.rs `grid_point`):
// ⌈√n⌉ columns; when the rows do not hold n cells exactly, each row is as tall as its cells'
// share and the last row's m cells are 1/m wide. fsqrt and fdiv are the exact arithmetic every
// shader starts with. The pixel's jitter (raygen.wgsl) and the stratified pairs (mc_sample.wgsl)
// both call it.
fn grid_point(k: u32, n: u32, jitter: vec2f) -> vec2f {
    let cols = u32(ceil(fsqrt(f32(n))));
    let rows = (n + cols - 1u) / cols;
    let cx = k % cols;
    let cy = k / cols;
    if cols * rows == n {
        return vec2f(fdiv(f32(cx) + jitter.x, f32(cols)), fdiv(f32(cy) + jitter.y, f32(rows)));
    }
    var width = cols;
    if cy + 1u >= rows {
        width = n - cols * (rows - 1u);
    }
    return vec2f(
        min(fdiv(f32(cx) + jitter.x, f32(width)), 0.9999999403953552),
        min(fdiv(f32(cy * cols) + jitter.y * f32(width), f32(n)), 0.9999999403953552),
    );
}
