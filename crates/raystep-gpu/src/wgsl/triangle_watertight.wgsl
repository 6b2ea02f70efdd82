// ---- intersection: ray–triangle, watertight (Woop–Benthin–Wald 2013, pbrt-v4; crates/raystep-core/src/shapes/triangle.rs) ----

// a·b − c·d with the rounding of c·d recovered by an FMA (Kahan). `fmaf` is Rust's mul_add: the
// driver's fma where the probe found it fused, an exact emulation where not.
fn difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let dop = fmaf(a, b, -cd);
    let err = fmaf(-c, d, cd);
    return dop + err;
}

// a·b − c·d for an edge function that came out exactly 0. The CPU recomputes it in f64; WGSL has
// no f64, so the two products are split into exact (value, error) pairs (Dekker's two-product)
// instead, which gets the sign right and the value to within about an ulp of the f64 result.
fn exact_difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let pp = two_prod(a, b);
    let qq = two_prod(c, d);
    return (pp.x - qq.x) + (pp.y - qq.y);
}

fn permute(v: vec3f, k: vec3u) -> vec3f {
    return vec3f(v[k.x], v[k.y], v[k.z]);
}

fn intersect_triangle(r: Ray, p0: vec3f, p1: vec3f, p2: vec3f) -> Cand {
    // Translate to the origin; permute so z is the largest |dir| component.
    let ad = abs(r.dir);
    var kz = 2u;
    if ad.x > ad.y {
        if ad.x > ad.z {
            kz = 0u;
        }
    } else if ad.y > ad.z {
        kz = 1u;
    }
    let kx = select(kz + 1u, 0u, kz == 2u);
    let ky = select(kx + 1u, 0u, kx == 2u);
    let k = vec3u(kx, ky, kz);
    var q0 = permute(p0 - r.origin, k);
    var q1 = permute(p1 - r.origin, k);
    var q2 = permute(p2 - r.origin, k);
    let dp = permute(r.dir, k);
    // Shear so the ray runs along +z.
    let sx = fdiv(-dp.x, dp.z);
    let sy = fdiv(-dp.y, dp.z);
    let sz = fdiv(1.0, dp.z);
    q0.x = q0.x + sx * q0.z;
    q0.y = q0.y + sy * q0.z;
    q1.x = q1.x + sx * q1.z;
    q1.y = q1.y + sy * q1.z;
    q2.x = q2.x + sx * q2.z;
    q2.y = q2.y + sy * q2.z;
//#if TRACE
    scratch[0] = f32(kx); scratch[1] = f32(ky); scratch[2] = f32(kz);
    scratch[3] = sx; scratch[4] = sy; scratch[5] = sz;
    scratch[6] = q0.x; scratch[7] = q0.y; scratch[8] = q0.z;
    scratch[9] = q1.x; scratch[10] = q1.y; scratch[11] = q1.z;
    scratch[12] = q2.x; scratch[13] = q2.y; scratch[14] = q2.z;
    scratch[26] = 2.0;
//#endif
    // 2D edge functions.
    var e0 = difference_of_products(q1.x, q2.y, q1.y, q2.x);
    var e1 = difference_of_products(q2.x, q0.y, q2.y, q0.x);
    var e2 = difference_of_products(q0.x, q1.y, q0.y, q1.x);
    if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
        e0 = exact_difference_of_products(q1.x, q2.y, q1.y, q2.x);
        e1 = exact_difference_of_products(q2.x, q0.y, q2.y, q0.x);
        e2 = exact_difference_of_products(q0.x, q1.y, q0.y, q1.x);
    }
//#if TRACE
    scratch[15] = e0; scratch[16] = e1; scratch[17] = e2;
//#endif
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
//#if TRACE
        scratch[26] = 8.0;
//#endif
        return no_cand(0.0);
    }
    let det = e0 + e1 + e2;
//#if TRACE
    scratch[18] = det;
//#endif
    if det == 0.0 || !finite(det) {
        return no_cand(det);
    }
    let max_z_unscaled = max(abs(q0.z), max(abs(q1.z), abs(q2.z)));
    q0.z = q0.z * sz;
    q1.z = q1.z * sz;
    q2.z = q2.z * sz;
    let t_scaled = e0 * q0.z + e1 * q1.z + e2 * q2.z;
    let inv_det = fdiv(1.0, det);
    let t = t_scaled * inv_det;
    let b1 = e1 * inv_det;
    let b2 = e2 * inv_det;
//#if TRACE
    scratch[19] = q0.z; scratch[20] = q1.z; scratch[21] = q2.z;
    scratch[22] = t_scaled; scratch[23] = t; scratch[24] = b1; scratch[25] = b2;
    scratch[26] = 5.0;
//#endif
    if !accepts(r, t) {
        return no_cand(det);
    }
    // pbrt-v4's conservative bound: t must exceed its own rounding error.
    let max_zt = max(abs(q0.z), max(abs(q1.z), abs(q2.z)));
    let delta_z = GAMMA3 * max_zt;
    let max_xt = max(abs(q0.x), max(abs(q1.x), abs(q2.x)));
    let max_yt = max(abs(q0.y), max(abs(q1.y), abs(q2.y)));
    let delta_x = GAMMA5 * (max_xt + max_z_unscaled);
    let delta_y = GAMMA5 * (max_yt + max_z_unscaled);
    let delta_e = 2.0 * (GAMMA2 * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = max(abs(e0), max(abs(e1), abs(e2)));
    let delta_t = 3.0 * (GAMMA3 * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * abs(inv_det);
    if t <= delta_t {
        return no_cand(det);
    }
//#if TRACE
    scratch[26] = 12.0;
//#endif
    return Cand(true, t, b1, b2, det);
}
