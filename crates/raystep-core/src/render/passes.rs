//! The one pass schedule of a progressive Monte Carlo render: passes of 1, 1, 2, 4, … samples per
//! pixel, each doubling the samples so far, the last cut at the scene's spp. The CPU render
//! ([`super::Progressive`]), the GPU tracer's progressive render and the app's GPU tab (a pass a
//! frame) all follow it, so an image shown after n samples is the same n samples everywhere.

/// The samples per pixel after each pass: 1, 2, 4, … (powers of two below `spp`), then `spp`
/// (at least 1).
pub fn pass_ends(spp: u32) -> Vec<u32> {
    let spp = spp.max(1);
    let mut ends = vec![];
    let mut end = 1u32;
    while end < spp {
        ends.push(end);
        end = end.saturating_mul(2);
    }
    ends.push(spp);
    ends
}

/// The samples per pixel after the pass that follows `done` samples: 1 from none, else double,
/// at most `spp`. The pass traces samples `done .. next_pass_end(done, spp)`.
pub fn next_pass_end(done: u32, spp: u32) -> u32 {
    if done == 0 {
        1
    } else {
        done.saturating_mul(2).min(spp.max(1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_of_one_one_two_four() {
        assert_eq!(pass_ends(1), [1]);
        assert_eq!(pass_ends(0), [1]);
        assert_eq!(pass_ends(2), [1, 2]);
        assert_eq!(pass_ends(16), [1, 2, 4, 8, 16]);
        assert_eq!(pass_ends(100), [1, 2, 4, 8, 16, 32, 64, 100]);
        assert_eq!(pass_ends(u32::MAX).len(), 33);
        // Pass by pass, the two agree.
        for spp in [1, 2, 3, 16, 100, 4097] {
            let mut done = 0;
            let mut walked = vec![];
            while done < spp {
                done = next_pass_end(done, spp);
                walked.push(done);
            }
            assert_eq!(walked, pass_ends(spp), "spp {spp}");
        }
    }
}
