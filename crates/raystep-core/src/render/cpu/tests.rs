//! The parallel render's own unit tests: tile order, bands and work stealing, the helpers' waits.

use super::super::pool::{AWAKE, await_helpers, bands, drain, steal};
use super::{TILE, tile_rows};
use crate::platform::Instant;
use crossbeam_deque::Stealer;
use proptest::prelude::*;
use std::sync::atomic::AtomicUsize;

/// A helper that never reports: the calling thread's awake wait gives up, no sooner than
/// `AWAKE`, and leaves the waiting to rayon.
#[test]
fn the_calling_thread_gives_up_waiting_awake_after_awake() {
    let t = Instant::now();
    await_helpers(&AtomicUsize::new(1));
    assert!(t.elapsed() >= AWAKE);
}

/// Once its own band is done, a thread takes from the far end of the band with the most
/// left (the later band on a tie), one item at a time: two bands of 0–4 and 5–9 give
/// 9, 4, 8, 3, … (worked out by hand), then nothing.
#[test]
fn thieves_take_from_the_far_end_of_the_longest_band() {
    let bands = bands((0..10).collect(), 2);
    let thieves: Vec<Stealer<i32>> = bands.iter().map(|b| b.stealer()).collect();
    let taken: Vec<i32> = std::iter::from_fn(|| steal(&thieves)).collect();
    assert_eq!(taken, [9, 4, 8, 3, 7, 2, 6, 1, 5, 0]);
    assert_eq!(steal(&thieves), None);
}

proptest! {
    /// Every tile gets exactly its own pixels, row by row: the pieces hold the indices a
    /// tile at (x0, y0) covers, min(TILE, edge) wide and high, the tiles in row-major order,
    /// and together they cover the image once.
    #[test]
    fn tiles_get_exactly_their_own_pixels(width in 1u32..70, height in 1u32..70) {
        let mut image: Vec<usize> = (0..(width * height) as usize).collect();
        let tiles = tile_rows(&mut image, width);
        let mut expected = vec![];
        for y0 in (0..height).step_by(TILE as usize) {
            for x0 in (0..width).step_by(TILE as usize) {
                let rows: Vec<Vec<usize>> = (y0..(y0 + TILE).min(height))
                    .map(|y| ((x0..(x0 + TILE).min(width)).map(|x| (y * width + x) as usize)).collect())
                    .collect();
                expected.push(((x0, y0), rows));
            }
        }
        let got: Vec<_> = tiles
            .iter()
            .map(|(t, rows)| ((t.x0, t.y0), rows.iter().map(|r| r.to_vec()).collect()))
            .collect();
        prop_assert_eq!(got, expected);
    }

    /// The bands are the items in order, cut into `threads` runs of at most
    /// ⌈n ÷ threads⌉, each popped front first by its owner.
    #[test]
    fn bands_are_consecutive_runs_in_order(n in 0usize..300, threads in 0usize..6) {
        let bands = bands((0..n).collect(), threads);
        prop_assert_eq!(bands.len(), threads.max(1));
        let popped: Vec<Vec<usize>> =
            bands.iter().map(|b| std::iter::from_fn(|| b.pop()).collect()).collect();
        let most = n.div_ceil(threads.max(1));
        for run in &popped {
            prop_assert!(run.len() <= most);
            prop_assert!(run.windows(2).all(|w| w[1] == w[0] + 1));
        }
        prop_assert_eq!(popped.concat(), (0..n).collect::<Vec<_>>());
    }

    /// Threads draining their bands and stealing from each other's do every item exactly
    /// once, however the work is shared out.
    #[test]
    fn every_item_is_done_exactly_once(n in 0usize..400, threads in 1usize..5) {
        let bands = bands((0..n).collect::<Vec<usize>>(), threads);
        let thieves: Vec<Stealer<usize>> = bands.iter().map(|b| b.stealer()).collect();
        let thieves = &thieves[..];
        // Uneven work (item i spins i % 7 × 50 times), so that the threads get out of step.
        let work = |i: usize| {
            (0..(i % 7) * 50).for_each(|k| {
                std::hint::black_box(k);
            });
            i
        };
        let mut done: Vec<usize> = std::thread::scope(|s| {
            let handles: Vec<_> = bands
                .into_iter()
                .map(|own| s.spawn(move || drain(own, thieves, work)))
                .collect();
            handles.into_iter().flat_map(|h| h.join().unwrap_or_default()).collect()
        });
        done.sort_unstable();
        prop_assert_eq!(done, (0..n).collect::<Vec<_>>());
    }
}
