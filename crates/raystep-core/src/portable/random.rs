//! Random numbers as a stateless hash: uniform(pixel, sample, dimension, seed) in [0, 1), and the
//! PCG hash beneath it, which the antialiasing jitter (`trace::sampling`) uses too. The WGSL
//! twin is `random.wgsl` beside this file ([`super::RANDOM_WGSL`]), line for line.

/// The PCG hash of Jarzynski and Olano, "Hash Functions for GPU Rendering" (JCGT 2020): a
/// stateless 32-bit hash with good avalanche, written the same way in WGSL for the GPU view.
#[inline(always)]
pub fn pcg_hash(input: u32) -> u32 {
    let state = input.wrapping_mul(747796405).wrapping_add(2891336453);
    let word = ((state >> ((state >> 28).wrapping_add(4))) ^ state).wrapping_mul(277803737);
    (word >> 22) ^ word
}

/// A uniform float in [0, 1) from a hash (the top 24 bits, so the value is exact in f32).
#[inline(always)]
pub fn unit_float(h: u32) -> f32 {
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

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
    uniform_keyed(sample_key(pixel, sample, seed), dimension)
}

/// The part of [`uniform`]'s hash chain that all of one sample's dimensions share: the seed,
/// the sample and the pixel folded together. A path draws dozens of numbers for one sample;
/// hashing this once and each dimension into it ([`uniform_keyed`]) gives the same numbers with
/// one hash a draw instead of five.
#[inline]
pub fn sample_key(pixel: [u32; 2], sample: u32, seed: u32) -> u32 {
    pcg_hash(pixel[0] ^ pcg_hash(pixel[1] ^ pcg_hash(sample ^ pcg_hash(seed))))
}

/// [`uniform`] from its sample's [`sample_key`]: `uniform(pixel, sample, dimension, seed)` is
/// `uniform_keyed(sample_key(pixel, sample, seed), dimension)`, bit for bit.
#[inline(always)]
pub fn uniform_keyed(key: u32, dimension: u32) -> f32 {
    unit_float(pcg_hash(dimension ^ key))
}

/// Two consecutive dimensions, `dimension` and `dimension + 1`: the pair a 2D sampler takes.
#[inline]
pub fn uniform2(pixel: [u32; 2], sample: u32, dimension: u32, seed: u32) -> [f32; 2] {
    [
        uniform(pixel, sample, dimension, seed),
        uniform(pixel, sample, dimension.wrapping_add(1), seed),
    ]
}

/// Where `jitter` ∈ [0, 1)² lands in cell `k` of the grid that splits [0, 1)² into `n` cells of
/// equal area (the pixel's samples, `trace::sampling`, and the stratified sampler's squares).
///
/// The grid has ⌈√n⌉ columns and ⌈n / columns⌉ rows, cell k in column k mod columns and row
/// k div columns. When that is n cells exactly (n a square, or 2, 6, 12, 20, 30 …) they are the
/// grid's equal rectangles. Otherwise the last row holds fewer cells, m = n − columns × (rows −
/// 1): every row is then as tall as its cells' share of the square (a full row columns / n, the
/// last m / n) and the last row's m cells are 1 / m wide, so each cell still has area 1 / n
/// and the cells cover the square. (Rows of equal height, as this once had, left the last row's
/// missing cells never sampled: 4 of the 36 cells for 32 samples, a bias in every pixel with
/// such a sample count.)
#[inline(always)]
pub fn grid_point(k: u32, n: u32, jitter: [f32; 2]) -> [f32; 2] {
    let cols = (n as f32).sqrt().ceil() as u32;
    let rows = n.div_ceil(cols);
    let (cx, cy) = (k % cols, k / cols);
    // In u64: for n near u32::MAX the product passes it (scenes stop at 65,536 samples).
    if u64::from(cols) * u64::from(rows) == u64::from(n) {
        return [
            (cx as f32 + jitter[0]) / cols as f32,
            (cy as f32 + jitter[1]) / rows as f32,
        ];
    }
    // The cells in this cell's row: all the columns, or the last row's m.
    let width = if cy + 1 >= rows {
        n - cols * (rows - 1)
    } else {
        cols
    };
    [
        ((cx as f32 + jitter[0]) / width as f32).min(ONE_BELOW),
        (((cy * cols) as f32 + jitter[1] * width as f32) / n as f32).min(ONE_BELOW),
    ]
}

/// The largest f32 below 1 (a point stays in [0, 1)).
pub const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_keyed_draw_is_the_hash_chain_written_out() {
        // The chain of the doc comment, written out here by hand, against the keyed form.
        for (pixel, sample, dimension, seed) in [
            ([0, 0], 0, 0, 0),
            ([3, 4], 5, 6, 7),
            ([1919, 1079], 65_535, 16 + 1024 * 23 + 5, u32::MAX),
        ] {
            let chain = pcg_hash(
                dimension
                    ^ pcg_hash(pixel[0] ^ pcg_hash(pixel[1] ^ pcg_hash(sample ^ pcg_hash(seed)))),
            );
            let key = sample_key(pixel, sample, seed);
            assert_eq!(
                uniform_keyed(key, dimension),
                (chain >> 8) as f32 / 16_777_216.0
            );
            assert_eq!(
                uniform(pixel, sample, dimension, seed),
                uniform_keyed(key, dimension)
            );
        }
    }

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

    #[test]
    fn pcg_hash_reference_values() {
        // From the published algorithm: state = 0·747796405 + 2891336453 = 2891336453;
        // computed by hand with 64-bit arithmetic reduced mod 2³² in a separate script.
        let state: u64 = 2891336453;
        let shift = (state >> 28) + 4;
        let word = (((state >> shift) ^ state) * 277803737) & 0xffff_ffff;
        let expect = ((word >> 22) ^ word) as u32;
        assert_eq!(pcg_hash(0), expect);
    }
}
