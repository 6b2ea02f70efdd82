//! The small statistics every part of the lab shares: a float's spacing, percentiles, and the
//! timing of a kernel per item.

use super::Precision;
use crate::platform::Instant;

/// The spacing of precision-p floats at |x|.
pub(crate) fn ulp(x: f64, p: Precision) -> f64 {
    let x = x.abs();
    match p {
        Precision::F32 => {
            let f = (x as f32).min(f32::MAX);
            (f.next_up() - f) as f64
        }
        Precision::F64 => {
            let f = x.min(f64::MAX);
            f.next_up() - f
        }
    }
}

pub(crate) fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    let k = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[k - 1]
}

/// How many times `min_s` a row is timed for.
const WINDOWS: u32 = 5;

/// The shortest timing window: far shorter than a scheduler time slice, far longer than the
/// clock's resolution and the cost of reading it.
const SHORT_WINDOW_S: f64 = 2e-5;

/// Times `f` over `n` items, in ns per item: after a warm-up pass, short windows of repeated
/// passes (each at least [`SHORT_WINDOW_S`]) for [`WINDOWS`] × `min_s` in all, and the
/// **fastest** window. The fastest, not the mean: a window during which the thread was
/// descheduled (in the app, by its own render threads and UI on the same cores; on a shared
/// machine, by anything) can only read slower — with long windows one preemption made whole rows
/// 10–40× too slow in the app — while windows shorter than a time slice are mostly clean. The
/// minimum is the kernel's own cost, the same on a busy machine as on an idle one.
pub(crate) fn time_per_item(n: usize, min_s: f64, mut f: impl FnMut()) -> f64 {
    if n == 0 {
        return 0.0;
    }
    f(); // warm up
    let total = Instant::now();
    let mut best = f64::INFINITY;
    loop {
        let start = Instant::now();
        let mut passes = 0u64;
        let el = loop {
            f();
            passes += 1;
            let el = start.elapsed().as_secs_f64();
            if el >= SHORT_WINDOW_S {
                break el;
            }
        };
        best = best.min(el * 1e9 / (passes as f64 * n as f64));
        if total.elapsed().as_secs_f64() >= min_s * WINDOWS as f64 {
            return best;
        }
    }
}
