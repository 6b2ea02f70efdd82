//! Deterministic antialiasing: jittered stratified samples seeded by (pixel, sample, seed), so a
//! render, a trace, a GPU frame and a recorded trace agree exactly (docs/ARCHITECTURE.md, invariant 3).

use crate::portable::random::{pcg_hash, unit_float};

/// The position inside pixel (x, y) of sample `sample` out of `spp`, in [0, 1)².
///
/// spp = 1 is the pixel centre (0.5, 0.5). Otherwise the pixel is split into a grid of
/// ⌈√spp⌉ columns and ⌈spp / columns⌉ rows, sample k takes cell k, and a hashed jitter places it
/// inside that cell.
#[inline(always)]
pub fn sample_offset(x: u32, y: u32, sample: u32, spp: u32, seed: u32) -> [f32; 2] {
    if spp <= 1 {
        return [0.5, 0.5];
    }
    let cols = (spp as f32).sqrt().ceil() as u32;
    let rows = spp.div_ceil(cols);
    let (cx, cy) = (sample % cols, sample / cols);
    let h1 = pcg_hash(x ^ pcg_hash(y ^ pcg_hash(sample ^ pcg_hash(seed))));
    let h2 = pcg_hash(h1);
    [
        (cx as f32 + unit_float(h1)) / cols as f32,
        (cy as f32 + unit_float(h2)) / rows as f32,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_for_one_sample_and_strata_otherwise() {
        assert_eq!(sample_offset(3, 4, 0, 1, 0), [0.5, 0.5]);
        // 4 samples: a 2×2 grid, sample k in cell (k % 2, k / 2).
        for k in 0..4 {
            let [ox, oy] = sample_offset(7, 9, k, 4, 1);
            assert!(ox >= (k % 2) as f32 * 0.5 && ox < (k % 2 + 1) as f32 * 0.5);
            assert!(oy >= (k / 2) as f32 * 0.5 && oy < (k / 2 + 1) as f32 * 0.5);
        }
        assert_eq!(sample_offset(7, 9, 2, 4, 1), sample_offset(7, 9, 2, 4, 1));
        assert_ne!(sample_offset(7, 9, 2, 4, 1), sample_offset(7, 9, 2, 4, 2));
    }
}
