//! The seam between raystep and the machine it runs on: the one place that knows whether it runs
//! natively or in a browser (`wasm32`). Everything else asks here for a clock, a background job,
//! a wait, or the number of threads, and never names `std::thread` or `std::time::Instant`.
//!
//! | need | native | browser |
//! |---|---|---|
//! | a clock ([`Instant`]) | `std::time::Instant` | the page's `performance.now()` (std's panics) |
//! | a background job ([`spawn`]) | a thread | run at once, on the page's only thread |
//! | a long job in steps ([`spawn_steps`]) | a thread | a few steps between frames ([`run_steps`]) |
//! | a repaint ticker ([`spawn_ticker`]) | a thread | none: the job has finished when it returns |
//! | a pause ([`sleep`]) | `std::thread::sleep` | none (the page cannot block) |
//! | threads for a render ([`threads`]) | the cores | one |
//! | workers for a render in steps ([`workers`], [`spawn_worker`]) | rayon's pool, the cores | Web Workers where the page is cross-origin isolated ([`set_browser_workers`]), else none |
//! | waiting on a future ([`block_on`]) | `pollster` | polled once: only futures that are ready |
//!
//! | files ([`files`]) | the disk | the page's memory: built-in files, files opened or dropped |
//!
//! The command line, the benchmarks, the fuzzing entry points and grading student programs are
//! native-only modules as a whole (`cli`, `bench`, `fuzzing`, `student`).

/// Writing files whole or not at all (native; `io::write_atomic` is its door).
#[cfg(not(target_arch = "wasm32"))]
pub mod atomic;
pub mod browser;
pub mod files;

pub use web_time::{Duration, Instant};

/// Runs `job` in the background: on its own thread natively, at once in the browser (the caller
/// then finds its results waiting, as if the thread had been very quick).
pub fn spawn(job: impl FnOnce() + Send + 'static) {
    #[cfg(not(target_arch = "wasm32"))]
    {
        std::thread::spawn(job);
    }
    #[cfg(target_arch = "wasm32")]
    job();
}

/// Runs a long job in steps: `step` is called until it returns `false`. Natively on a thread of
/// its own, one step after the other. In the browser the steps run between frames
/// ([`run_steps`]), so the page keeps drawing: a render is a step per band of tiles.
pub fn spawn_steps(mut step: impl FnMut() -> bool + Send + 'static) {
    #[cfg(not(target_arch = "wasm32"))]
    {
        std::thread::spawn(move || while step() {});
    }
    #[cfg(target_arch = "wasm32")]
    STEPS.with(|s| s.borrow_mut().push(Box::new(move || step())));
}

#[cfg(target_arch = "wasm32")]
thread_local! {
    /// The browser's stepped jobs, oldest first.
    static STEPS: std::cell::RefCell<Vec<Box<dyn FnMut() -> bool>>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// Runs the stepped jobs ([`spawn_steps`]) for about `budget` (each at least one step), and
/// says whether any is left. Natively they run on their threads: nothing to do here.
///
/// In the browser the budget grows to the time the page spent outside the steps since the last
/// call (drawing the frame), up to four times `budget`: where a frame is slow to draw (a
/// software renderer), the jobs still get about half of the page's time.
pub fn run_steps(budget: Duration) -> bool {
    #[cfg(not(target_arch = "wasm32"))]
    {
        let _ = budget;
        false
    }
    #[cfg(target_arch = "wasm32")]
    {
        thread_local! {
            static LAST_RETURN: std::cell::Cell<Option<Instant>> = const { std::cell::Cell::new(None) };
        }
        let start = Instant::now();
        let outside = LAST_RETURN
            .with(|l| l.take())
            .map_or(Duration::ZERO, |t| start.duration_since(t));
        let budget = outside.clamp(budget, budget * 4);
        loop {
            // Taken out while they run: a step may start another job.
            let mut jobs = STEPS.with(|s| std::mem::take(&mut *s.borrow_mut()));
            if jobs.is_empty() {
                return false;
            }
            let mut busy = false;
            jobs.retain_mut(|step| {
                STEP_WAITS.with(|w| w.set(false));
                let more = step();
                busy |= !more || !STEP_WAITS.with(|w| w.get());
                more
            });
            STEPS.with(|s| {
                let mut s = s.borrow_mut();
                let started = std::mem::take(&mut *s);
                *s = jobs;
                s.extend(started);
            });
            // Every job only waits on its workers: the page may draw.
            ALL_WAITED.with(|w| w.set(!busy));
            if !busy || start.elapsed() >= budget {
                let left = STEPS.with(|s| !s.borrow().is_empty());
                if left {
                    LAST_RETURN.with(|l| l.set(Some(Instant::now())));
                }
                return left;
            }
        }
    }
}

/// Calls `tick` every `every` while `running()` holds, on a thread of its own (natively); the
/// app's repaint while a background job works. In the browser the job has finished before this
/// is reached, so nothing runs.
pub fn spawn_ticker(
    every: Duration,
    running: impl Fn() -> bool + Send + 'static,
    tick: impl FnMut() + Send + 'static,
) -> Option<Ticker> {
    #[cfg(not(target_arch = "wasm32"))]
    {
        let mut tick = tick;
        Some(Ticker(std::thread::spawn(move || {
            while running() {
                std::thread::sleep(every);
                tick();
            }
        })))
    }
    #[cfg(target_arch = "wasm32")]
    {
        let _ = (every, running, tick);
        None
    }
}

/// A running [`spawn_ticker`]; [`Ticker::join`] waits for it to stop.
#[derive(Debug)]
pub struct Ticker(#[cfg(not(target_arch = "wasm32"))] std::thread::JoinHandle<()>);

impl Ticker {
    /// Waits until the ticker has stopped.
    pub fn join(self) {
        #[cfg(not(target_arch = "wasm32"))]
        let _ = self.0.join();
    }
}

/// Pauses the calling (background) thread; nothing in the browser, where there is one thread.
pub fn sleep(d: Duration) {
    #[cfg(not(target_arch = "wasm32"))]
    std::thread::sleep(d);
    #[cfg(target_arch = "wasm32")]
    let _ = d;
}

/// How many threads a render may use: the machine's cores natively, one in the browser.
pub fn threads() -> usize {
    #[cfg(not(target_arch = "wasm32"))]
    {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    }
    #[cfg(target_arch = "wasm32")]
    1
}

/// The page's Web Workers for renders (0: none, the page renders on its own thread), set once
/// by the page's start-up ([`set_browser_workers`]).
#[cfg(target_arch = "wasm32")]
static WORKERS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// Why the page renders on one thread, when it does (for the render settings).
#[cfg(target_arch = "wasm32")]
static ONE_THREAD_WHY: std::sync::Mutex<String> = std::sync::Mutex::new(String::new());

/// Tells raystep, in the browser, how many Web Workers the page started for renders (rayon's
/// global pool on them, `wasm-bindgen-rayon`), or, with 0, why it has none (`why`: "the page
/// is not cross-origin isolated", …; the render settings show it). Natively it does nothing: the
/// workers are the cores.
pub fn set_browser_workers(workers: usize, why: &str) {
    #[cfg(target_arch = "wasm32")]
    {
        WORKERS.store(workers, std::sync::atomic::Ordering::Relaxed);
        *ONE_THREAD_WHY.lock().unwrap_or_else(|e| e.into_inner()) = why.to_string();
    }
    #[cfg(not(target_arch = "wasm32"))]
    let _ = (workers, why);
}

/// Why renders run on the page's one thread (`None` natively, and in a page with workers).
pub fn one_thread_why() -> Option<String> {
    #[cfg(target_arch = "wasm32")]
    {
        let why = ONE_THREAD_WHY.lock().unwrap_or_else(|e| e.into_inner());
        (WORKERS.load(std::sync::atomic::Ordering::Relaxed) == 0 && !why.is_empty())
            .then(|| why.clone())
    }
    #[cfg(not(target_arch = "wasm32"))]
    None
}

/// Threads that can trace a render in steps while the calling thread only gathers the tiles
/// ([`spawn_worker`]): natively the cores (rayon's global pool); in the browser the page's Web
/// Workers, 0 where it has none (then a render in steps traces bands on the page's thread).
pub fn workers() -> usize {
    #[cfg(not(target_arch = "wasm32"))]
    {
        rayon::current_num_threads()
    }
    #[cfg(target_arch = "wasm32")]
    WORKERS.load(std::sync::atomic::Ordering::Relaxed)
}

/// Runs `job` on one of the [`workers`] and returns at once, never waiting (the browser's page
/// may not wait): rayon's global pool, natively on threads, in the browser on the page's Web
/// Workers. Where there are none (a page without workers) it runs at once, on the calling
/// thread.
pub fn spawn_worker(job: impl FnOnce() + Send + 'static) {
    if workers() == 0 {
        job();
    } else {
        rayon::spawn(job);
    }
}

thread_local! {
    /// Set by a step that found nothing to do yet ([`step_waits`]).
    static STEP_WAITS: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    /// Whether the last [`run_steps`] returned because every job only waited.
    static ALL_WAITED: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether the last [`run_steps`] gave the page back because its jobs only wait on workers
/// (then the page need not draw again at once: nothing new is ready before some work is done).
pub fn steps_wait() -> bool {
    ALL_WAITED.with(|w| w.get())
}

/// Said by a stepped job's step ([`spawn_steps`]) that only waits for others (a render's tiles
/// on workers): when every step of a round says so, [`run_steps`] gives the page back at once
/// instead of calling them again and again until its budget has passed.
pub fn step_waits() {
    STEP_WAITS.with(|w| w.set(true));
}

/// Whether this build runs in a browser.
pub const IN_BROWSER: bool = cfg!(target_arch = "wasm32");

/// Waits for `f`: natively by blocking the thread; in the browser (which cannot block) by
/// polling once, so `None` means the future was not ready.
pub fn block_on<F: std::future::Future>(f: F) -> Option<F::Output> {
    #[cfg(not(target_arch = "wasm32"))]
    {
        Some(pollster::block_on(f))
    }
    #[cfg(target_arch = "wasm32")]
    {
        let mut f = std::pin::pin!(f);
        let mut cx = std::task::Context::from_waker(std::task::Waker::noop());
        match f.as_mut().poll(&mut cx) {
            std::task::Poll::Ready(v) => Some(v),
            std::task::Poll::Pending => None,
        }
    }
}

/// A progress bar on stderr while a long command works, shown only when stderr is a terminal
/// (natively; never in the browser).
#[derive(Debug)]
pub struct TerminalProgress {
    #[cfg(not(target_arch = "wasm32"))]
    bar: indicatif::ProgressBar,
}

impl TerminalProgress {
    /// A bar of `len` steps labelled `what`, or `None` where no terminal would show it.
    pub fn new(len: u64, what: &str) -> Option<TerminalProgress> {
        #[cfg(not(target_arch = "wasm32"))]
        {
            use std::io::IsTerminal;
            if !std::io::stderr().is_terminal() {
                return None;
            }
            let bar = indicatif::ProgressBar::new(len);
            let template =
                format!("{{spinner}} {what} [{{bar:40}}] {{percent}}% {{elapsed}} (eta {{eta}})");
            if let Ok(style) = indicatif::ProgressStyle::with_template(&template) {
                bar.set_style(style.progress_chars("=> "));
            }
            Some(TerminalProgress { bar })
        }
        #[cfg(target_arch = "wasm32")]
        {
            let _ = (len, what);
            None
        }
    }

    /// One more step done.
    pub fn inc(&self, n: u64) {
        #[cfg(not(target_arch = "wasm32"))]
        self.bar.inc(n);
        #[cfg(target_arch = "wasm32")]
        let _ = n;
    }

    /// Removes the bar.
    pub fn finish(self) {
        #[cfg(not(target_arch = "wasm32"))]
        self.bar.finish_and_clear();
    }
}
