//! Deterministic antialiasing: jittered stratified samples seeded by (pixel, sample, seed), so a
//! render, a trace, a GPU frame and a recorded trace agree exactly (docs/ARCHITECTURE.md, invariant 3).

pub use crate::portable::random::{ONE_BELOW, grid_point};
use crate::portable::random::{pcg_hash, unit_float};

/// The position inside pixel (x, y) of sample `sample` out of `spp`, in [0, 1)².
///
/// spp = 1 is the pixel centre (0.5, 0.5). Otherwise the pixel is split into the grid of
/// [`grid_point`], sample k takes cell k, and a hashed jitter places it inside that cell.
#[inline(always)]
pub fn sample_offset(x: u32, y: u32, sample: u32, spp: u32, seed: u32) -> [f32; 2] {
    if spp <= 1 {
        return [0.5, 0.5];
    }
    let h1 = pcg_hash(x ^ pcg_hash(y ^ pcg_hash(sample ^ pcg_hash(seed))));
    let h2 = pcg_hash(h1);
    grid_point(sample, spp, [unit_float(h1), unit_float(h2)])
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

    /// The cells of a short grid, by hand. spp = 8: ⌈√8⌉ = 3 columns, 3 rows, the last with
    /// m = 8 − 3·2 = 2 cells; rows 3/8, 3/8 and 2/8 tall; cell 0 is [0, 1/3) × [0, 3/8), cell 4
    /// (column 1, row 1) [1/3, 2/3) × [3/8, 6/8), cell 7 (column 1 of the last row)
    /// [1/2, 1) × [6/8, 1).
    #[test]
    fn a_short_grid_by_hand() {
        let corners = |k: u32| (grid_point(k, 8, [0.0, 0.0]), grid_point(k, 8, [0.5, 0.5]));
        let (lo, mid) = corners(0);
        assert_eq!(lo, [0.0, 0.0]);
        assert_eq!(mid, [0.5 / 3.0, 1.5 / 8.0]);
        let (lo, mid) = corners(4);
        assert_eq!(lo, [1.0 / 3.0, 3.0 / 8.0]);
        assert_eq!(mid, [1.5 / 3.0, 4.5 / 8.0]);
        let (lo, mid) = corners(7);
        assert_eq!(lo, [0.5, 0.75]);
        assert_eq!(mid, [0.75, 0.875]);
        // A full grid keeps the equal rectangles: 30 = 6 × 5.
        assert_eq!(grid_point(29, 30, [0.5, 0.5]), [5.5 / 6.0, 4.5 / 5.0]);
        // The largest count a u32 holds: no overflow, a point in the square.
        for k in [0, 7, u32::MAX - 1] {
            let p = grid_point(k, u32::MAX, [0.5, 0.5]);
            assert!(p.iter().all(|c| (0.0..1.0).contains(c)), "{k}: {p:?}");
        }
    }

    /// For every n up to 300, the n cells split the unit square: each point of a 101 × 103
    /// lattice, shifted off the cells' edges (fractions with denominators up to 300), lies in
    /// exactly one cell, the cells being
    /// `grid_point`'s images of [0, 1)² (its corners with jitter 0 and the largest jitter below
    /// 1). With the rows of equal height this once had, the points under a short last row's
    /// missing cells lay in none.
    #[test]
    fn the_cells_cover_the_square_once() {
        let top = 1.0 - f32::EPSILON / 2.0;
        for n in 1..=300u32 {
            let cells: Vec<([f32; 2], [f32; 2])> = (0..n)
                .map(|k| (grid_point(k, n, [0.0, 0.0]), grid_point(k, n, [top, top])))
                .collect();
            for i in 0..101 {
                for j in 0..103 {
                    let p = [(i as f32 + 0.37) / 101.0, (j as f32 + 0.61) / 103.0];
                    let inside = cells
                        .iter()
                        .filter(|(lo, hi)| (0..2).all(|c| p[c] >= lo[c] && p[c] <= hi[c]))
                        .count();
                    assert_eq!(inside, 1, "n = {n}: the point {p:?} lies in {inside} cells");
                }
            }
        }
    }

    /// The pixel offsets of 32 samples (a short grid: 6 columns, 5 full rows and a row of 2)
    /// over 4,000 pixels are uniform on the pixel: χ² of their 8 × 8 histogram (128,000 points,
    /// 2,000 expected a bin, 63 degrees of freedom) below 131.4, the value a uniform sample
    /// exceeds with probability 10⁻⁶. The hashes are seeded, so the test gives the same χ² every
    /// run. (The old grid never sampled a fifth of the last row's height across two thirds of
    /// the width: χ² in the thousands.)
    #[test]
    fn a_short_grid_samples_the_pixel_uniformly() {
        let mut bins = [0u32; 64];
        for pixel in 0..4000u32 {
            for k in 0..32 {
                let [u, v] = sample_offset(pixel % 64, pixel / 64, k, 32, 7);
                assert!((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v));
                bins[(v * 8.0) as usize * 8 + (u * 8.0) as usize] += 1;
            }
        }
        let expected = 128_000.0 / 64.0;
        let chi2: f64 = bins
            .iter()
            .map(|&b| (f64::from(b) - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 131.4, "χ² = {chi2}: {bins:?}");
    }
}
