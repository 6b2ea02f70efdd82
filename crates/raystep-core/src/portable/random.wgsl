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
