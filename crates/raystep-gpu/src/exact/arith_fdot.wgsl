// glam's dot product, term for term: (a.x·b.x + a.y·b.y) + a.z·b.z. Not WGSL's dot(): NVIDIA's
// driver (580, H200) compiles OpDot as a chain of fused multiply-adds even when its result is
// decorated NoContraction (found with `raystep trace --gpu` and `raystep diff`: the first step
// to differ was a sphere test's a = d·d). Written out, each product and sum keeps NoContraction.
fn fdot(a: vec3f, b: vec3f) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

