//! Random numbers as a stateless hash: uniform(pixel, sample, dimension, seed) in [0, 1).

use crate::trace::sampling::{pcg_hash, unit_float};

/// The `dimension`-th uniform number of sample `sample` of `pixel`, with the scene's `seed`: in
/// [0, 1), a multiple of 2⁻²⁴ (exact in f32). A chain of PCG hashes (Jarzynski and Olano 2020,
/// [`pcg_hash`]) over the four inputs, each input folded into the hash of the ones before it, so
/// that neighbouring pixels, samples and dimensions draw unrelated numbers.
///
/// Dimensions are numbered by the integrator in the order it draws them (the camera's lens takes
/// two, each bounce its BSDF's two and the light's two, …); the trace records each number with
/// its dimension.
#[inline]
pub fn uniform(pixel: [u32; 2], sample: u32, dimension: u32, seed: u32) -> f32 {
    let h = pcg_hash(
        dimension ^ pcg_hash(pixel[0] ^ pcg_hash(pixel[1] ^ pcg_hash(sample ^ pcg_hash(seed)))),
    );
    unit_float(h)
}

/// Two consecutive dimensions, `dimension` and `dimension + 1`: the pair a 2D sampler takes.
#[inline]
pub fn uniform2(pixel: [u32; 2], sample: u32, dimension: u32, seed: u32) -> [f32; 2] {
    [
        uniform(pixel, sample, dimension, seed),
        uniform(pixel, sample, dimension.wrapping_add(1), seed),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_inputs_draw_the_same_number_and_each_input_matters() {
        let u = uniform([3, 4], 5, 6, 7);
        assert!((0.0..1.0).contains(&u));
        assert_eq!(u, uniform([3, 4], 5, 6, 7));
        for other in [
            uniform([4, 4], 5, 6, 7),
            uniform([3, 5], 5, 6, 7),
            uniform([3, 4], 6, 6, 7),
            uniform([3, 4], 5, 7, 7),
            uniform([3, 4], 5, 6, 8),
        ] {
            assert_ne!(u, other);
        }
        assert_eq!(uniform2([3, 4], 5, 6, 7), [u, uniform([3, 4], 5, 7, 7)]);
    }

    #[test]
    fn the_top_24_bits_of_the_hash_chain() {
        // By hand from the definition: the hash of the seed, folded into the sample's, the
        // row's, the column's and the dimension's.
        // (x ^ 0 is x: the zeros of pixel (0, 0), sample 0 and seed 0 leave the chain bare.)
        let h = pcg_hash(1 ^ pcg_hash(pcg_hash(pcg_hash(pcg_hash(0)))));
        assert_eq!(uniform([0, 0], 0, 1, 0), (h >> 8) as f32 / 16_777_216.0);
    }
}
