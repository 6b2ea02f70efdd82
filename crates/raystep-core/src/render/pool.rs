//! The parallel render's threads: the pool of helpers kept between renders, the bands of tiles
//! each thread starts from (work stealing), and the short waits that keep helpers awake.

use crate::platform::{Duration, Instant};
use crossbeam_deque::{Steal, Stealer, Worker};
use std::sync::Arc;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// How long a helper stays awake after a render, for the next one (see [`linger`]).
const LINGER: Duration = Duration::from_micros(200);

/// Keeps the pool's helpers awake for `LINGER` after a render, so that a render that follows at
/// once finds them awake: each of `helpers` empty-handed jobs looks for work in the pool (and
/// runs what it finds: the next render's share of tiles) until `LINGER` has passed, then lets its
/// helper sleep.
///
/// A helper with nothing to do sleeps after a few dozen yields (rayon's own idle loop), and
/// waking it costs more than a small render can spare: on the 2-core virtual machine raystep is
/// measured on, back-to-back two-thread renders of the 64×64 far sphere (a fifth of a
/// millisecond each) had the helper start its first tile 20 µs (median) after the tiles were
/// handed out; lingering, 1.5 µs, and the render went from 1.65× to 1.72× one thread's speed.
/// That is the way the app renders when a scene is edited, and the way `raystep bench` times
/// renders. The price is at most `LINGER` of a core after each render, spent yielding to any
/// thread that wants the core (crossbeam's `Backoff`).
pub(super) fn linger(pool: &rayon::ThreadPool, helpers: usize) {
    for _ in 0..helpers {
        pool.spawn(|| {
            let until = Instant::now() + LINGER;
            let backoff = crossbeam_utils::Backoff::new();
            while Instant::now() < until {
                match rayon::yield_now() {
                    // Not on one of the pool's threads (cannot happen: a job the pool runs).
                    None => return,
                    Some(rayon::Yield::Executed) => backoff.reset(),
                    Some(rayon::Yield::Idle) => backoff.snooze(),
                }
            }
        });
    }
}

/// How long the calling thread stays awake for the helpers' last tiles (see [`await_helpers`]).
pub(super) const AWAKE: Duration = Duration::from_micros(250);

/// Waits, awake, for the helpers still tracing their last tiles (`running` counts them down),
/// for at most `AWAKE`; after that the scope's own wait takes over.
///
/// Rayon's scope, entered from a thread outside its pool, waits on a condition variable: the
/// calling thread sleeps, and the helper that finishes last must wake it. On the 2-core virtual
/// machine raystep is measured on, that wake-up takes 15–24 µs (an empty `install` round trip),
/// paid by every render whose last tile ends on a helper — four in ten of the 64×64 far
/// sphere's two-thread renders, each a fifth of a millisecond. When the calling thread's own
/// drain ends every band is empty, so each helper has at most the tile it is tracing left and
/// the wait is short; past `AWAKE` the wake-up is under a tenth of the wait, not worth keeping
/// a core busy for. crossbeam's `Backoff` spins, then yields the core to any thread that wants
/// it.
pub(super) fn await_helpers(running: &AtomicUsize) {
    let until = Instant::now() + AWAKE;
    let backoff = crossbeam_utils::Backoff::new();
    while running.load(Ordering::Acquire) > 0 && Instant::now() < until {
        backoff.snooze();
    }
}

/// The renders' pool of `threads` helpers (the calling thread is each render's other thread),
/// started by the first render that asks for that many and kept for the next. A new pool per
/// render (new threads, cold stacks and caches) cost small scenes up to a third of their
/// two-thread speed: the 240×180 acne scene went from 1.2–1.5× to 1.8–2.0× one thread's speed
/// with this. Renders that overlap (the app cancelling one and starting the next) share it; a
/// cancelled render's remaining tiles return at once.
pub(super) fn render_pool(threads: usize) -> Result<Arc<rayon::ThreadPool>, String> {
    static POOL: Mutex<Option<(usize, Arc<rayon::ThreadPool>)>> = Mutex::new(None);
    // A poisoned lock only means a render panicked while holding it; the pool is still usable.
    let mut cached = POOL.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((n, pool)) = cached.as_ref()
        && *n == threads
    {
        return Ok(pool.clone());
    }
    let pool = Arc::new(
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("raystep-render-{i}"))
            .build()
            .map_err(|e| format!("cannot start the worker threads: {e}"))?,
    );
    *cached = Some((threads, pool.clone()));
    Ok(pool)
}

/// `work` cut into `threads` bands of consecutive items (at least one band; the last ones
/// shorter or empty), one deque each. A deque is last in, first out and filled back to front:
/// its owner pops the band in order and thieves take from the band's far end.
pub(super) fn bands<T>(work: Vec<T>, threads: usize) -> Vec<Worker<T>> {
    let threads = threads.max(1);
    let band = work.len().div_ceil(threads).max(1);
    let mut items = work.into_iter();
    (0..threads)
        .map(|_| {
            let own = Worker::new_lifo();
            let mine: Vec<T> = items.by_ref().take(band).collect();
            mine.into_iter().rev().for_each(|t| own.push(t));
            own
        })
        .collect()
}

/// Works through a thread's own band of tiles (`own`), then takes tiles from the other bands
/// (`thieves`) until none is left: `work` on each tile, the results in the order done.
pub(super) fn drain<T, R>(own: Worker<T>, thieves: &[Stealer<T>], work: impl Fn(T) -> R) -> Vec<R> {
    let mut done = vec![];
    while let Some(tile) = own.pop().or_else(|| steal(thieves)) {
        done.push(work(tile));
    }
    done
}

/// A tile from the far end of the band with the most left; `None` once every band is empty
/// (tiles are never added, so empty stays empty).
pub(super) fn steal<T>(thieves: &[Stealer<T>]) -> Option<T> {
    loop {
        let most = thieves.iter().max_by_key(|s| s.len())?;
        match most.steal() {
            Steal::Success(t) => return Some(t),
            Steal::Empty if thieves.iter().all(Stealer::is_empty) => return None,
            // Another thread took it first, or the band with the most changed: look again.
            Steal::Empty | Steal::Retry => continue,
        }
    }
}
