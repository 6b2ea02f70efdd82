//! Image-level error against run time (`raystep converge`): a scene rendered at spp = 1, 2, 4, …
//! with K independent seeds, each image compared with a reference rendered at ≥ 16× the top spp
//! (docs/NUMERICS.md, "Reporting error against run time").
//!
//! Per level and seed: trace seconds (the renderer's own [`RenderStats::trace`], which excludes
//! loading and building the accelerator — both reported once, separately), MSE, RMSE,
//! relMSE = mean((x − r)² / (r² + ε)) with ε = [`REL_EPSILON`], and NaN/∞ pixel counts. FLIP is
//! not computed (it needs the nv-flip crate; the report says so).
//!
//! Under the Monte Carlo integrators the errors are measured over the pixels that do not see a
//! light source directly ([`direct_emitters`]): at a lamp's edge the error is aliasing, not the
//! estimator's noise, and it would swamp the rest. The MSE over every pixel is kept beside them
//! (`mse_all`). The reference renders in [`REFERENCE_STEPS`] passes, each reported to the
//! observer, so that a long reference shows its progress wherever the report goes.
//!
//! [`RenderStats::trace`]: crate::render::RenderStats::trace

use super::plot::{PALETTE, Plot, Series, draw};
use super::report::num;
use crate::render::{RenderOptions, render};
use crate::scene::Scene;
use crate::trace::PreparedScene;
use glam::Vec3;
use serde::Serialize;
use std::fmt::Write as _;

mod mask;
mod strategies;
pub use mask::{MASK_SAMPLES, direct_emitters};
pub use strategies::{
    Reach, StrategyRun, Target, default_target, reach, run_strategies, strategies_csv,
    strategies_markdown, strategies_plots, strategy_name, strategy_table, target_words,
    time_to_relmse,
};

/// ε of relMSE (stated in every report).
pub const REL_EPSILON: f64 = 0.01;

/// What `converge` renders.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvergeOptions {
    /// The largest spp (levels are 1, 2, 4, … up to it; rounded down to a power of two).
    pub max_spp: u32,
    /// Independent seeds per level.
    pub seeds: u32,
    /// The reference renders at `reference_factor` × `max_spp` (at least 16).
    pub reference_factor: u32,
    /// Worker threads (None: all cores).
    pub threads: Option<usize>,
    /// Show the renderer's progress bar while each pass of the reference renders (on stderr,
    /// and only when stderr is a terminal; the observer hears of every pass whatever this is).
    pub progress: bool,
    /// A reference already rendered (several strategies measured against one truth): used
    /// instead of rendering one.
    pub reference: Option<std::sync::Arc<Reference>>,
}

/// A reference image: what every level is compared with.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    /// Its samples per pixel.
    pub spp: u32,
    /// Its linear pixels, row-major.
    pub pixels: Vec<Vec3>,
    /// Its trace seconds.
    pub seconds: f64,
}

impl Default for ConvergeOptions {
    fn default() -> Self {
        ConvergeOptions {
            max_spp: 16,
            seeds: 4,
            reference_factor: 16,
            threads: None,
            progress: false,
            reference: None,
        }
    }
}

/// The passes the reference renders in: the observer is told after each (a progress line on
/// the command line), so a long reference is never silent.
pub const REFERENCE_STEPS: u32 = 16;

/// The most samples per pixel the reference may take (the top level's spp × the reference
/// factor); more is refused before anything renders.
pub const MAX_REFERENCE_SPP: u32 = 1 << 20;

/// How far a run has got: given to the observer of [`run_observed`] after the first render
/// (when the first estimate can be made), after each pass of the reference, and after each
/// level.
#[derive(Debug, Clone, PartialEq)]
pub struct Progress {
    /// What has just finished, in words: "the first render (1 spp, seed 1)", "the reference (256
    /// spp)", "level 4 spp (4 seeds)".
    pub finished: String,
    /// Renders done, and in all (the reference and every level's seeds; on another device, the
    /// CPU render that measures the reference's speed too).
    pub renders: [usize; 2],
    /// Samples traced so far, and in all (spp × pixels, summed over the renders).
    pub samples: [u64; 2],
    /// Trace seconds so far (the renderers' own figures: loading and building are left out).
    pub seconds: f64,
    /// The trace seconds still to come, estimated from the speeds measured so far: the
    /// reference's from the CPU's renders, the levels' from the levels'.
    pub seconds_left: f64,
}

/// One render: a level's spp with one seed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sample {
    /// Samples per pixel.
    pub spp: u32,
    /// The jitter seed.
    pub seed: u32,
    /// Trace seconds.
    pub seconds: f64,
    /// Mean squared error over the measured pixels' channels (linear RGB): every pixel but
    /// those that see a light source directly ([`direct_emitters`]).
    pub mse: f64,
    /// √MSE.
    pub rmse: f64,
    /// mean((x − r)² / (r² + ε)), ε = [`REL_EPSILON`], over the measured pixels.
    pub relmse: f64,
    /// The MSE over every pixel, those that see a light source included.
    pub mse_all: f64,
    /// Pixels with a NaN channel.
    pub nan: usize,
    /// Pixels with an infinite channel.
    pub inf: usize,
}

/// A level's seeds summarized: median and the p10–p90 range.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Level {
    /// Samples per pixel.
    pub spp: u32,
    /// Median trace seconds.
    pub seconds: f64,
    /// MSE: [p10, median, p90] over seeds.
    pub mse: [f64; 3],
    /// RMSE: [p10, median, p90].
    pub rmse: [f64; 3],
    /// relMSE: [p10, median, p90].
    pub relmse: [f64; 3],
    /// The MSE over every pixel: [p10, median, p90].
    pub mse_all: [f64; 3],
    /// NaN pixels over all seeds.
    pub nan: usize,
    /// Infinite pixels over all seeds.
    pub inf: usize,
}

/// Everything `converge` measured.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConvergeReport {
    /// The scene's name.
    pub scene: String,
    /// What rendered the levels: "CPU" or the GPU's adapter line (the reference is always the
    /// CPU's).
    pub device: String,
    /// Image size.
    pub size: [u32; 2],
    /// Seconds to build the accelerator (BVH or brute force), once.
    pub build_seconds: f64,
    /// The reference's spp.
    pub reference_spp: u32,
    /// The reference's trace seconds.
    pub reference_seconds: f64,
    /// The pixels the errors are measured over.
    pub measured_pixels: usize,
    /// The pixels left out: they see a light source directly, or lie next to one that does.
    pub left_out_pixels: usize,
    /// Every render.
    pub samples: Vec<Sample>,
    /// Per level.
    pub levels: Vec<Level>,
    /// Least-squares slope of log median MSE (over the measured pixels) against log spp (≈ −1
    /// for independent samples; steeper where stratification helps, e.g. at edges).
    pub mse_slope: f64,
    /// The top level's image with seed 1 (linear, row-major): the picture of the estimator.
    #[serde(skip)]
    pub image: Vec<Vec3>,
}

fn quantiles(mut v: Vec<f64>) -> [f64; 3] {
    v.sort_by(|a, b| a.total_cmp(b));
    let q = |p: f64| {
        if v.is_empty() {
            return 0.0;
        }
        // Linear interpolation between order statistics.
        let x = p * (v.len() - 1) as f64;
        let (i, f) = (x.floor() as usize, x - x.floor());
        let j = (i + 1).min(v.len() - 1);
        v[i] * (1.0 - f) + v[j] * f
    };
    [q(0.1), q(0.5), q(0.9)]
}

/// An image's errors against the reference.
struct Errors {
    /// Over the pixels not `left_out`.
    mse: f64,
    relmse: f64,
    /// Over every pixel.
    mse_all: f64,
    nan: usize,
    inf: usize,
}

/// The errors of `img` against `reference`, the pixels `left_out` (true) left out of the MSE
/// and relMSE but not of `mse_all`. A NaN or infinite pixel is counted, not summed.
fn errors(img: &[Vec3], reference: &[Vec3], left_out: &[bool]) -> Errors {
    let (mut se, mut rel, mut se_all) = (0.0, 0.0, 0.0);
    let (mut nan, mut inf, mut measured) = (0, 0, 0usize);
    for (i, (x, r)) in img.iter().zip(reference).enumerate() {
        let out = left_out.get(i).copied().unwrap_or(false);
        measured += usize::from(!out);
        if x.is_nan() {
            nan += 1;
            continue;
        }
        if !x.is_finite() {
            inf += 1;
            continue;
        }
        for k in 0..3 {
            let d = (x[k] - r[k]) as f64;
            se_all += d * d;
            if !out {
                se += d * d;
                rel += d * d / ((r[k] as f64).powi(2) + REL_EPSILON);
            }
        }
    }
    let n = (measured * 3).max(1) as f64;
    Errors {
        mse: se / n,
        relmse: rel / n,
        mse_all: se_all / (img.len() * 3).max(1) as f64,
        nan,
        inf,
    }
}

/// Least-squares slope of y against x.
pub fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    if points.len() < 2 {
        return 0.0;
    }
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx == 0.0 { 0.0 } else { sxy / sxx }
}

/// Renders the levels and the reference on the CPU and measures every level's error.
pub fn run(scene: &Scene, opts: &ConvergeOptions) -> Result<ConvergeReport, String> {
    run_levels_with(scene, opts, None, &mut |_| {})
}

/// A renderer of the levels other than the CPU's: `(spp, seed)` → the linear image (row-major,
/// the scene camera's size) and its trace seconds. `raystep converge --gpu` passes the GPU.
pub type LevelRenderer<'a> = dyn FnMut(u32, u32) -> Result<(Vec<Vec3>, f64), String> + 'a;

/// As [`run`], with the levels rendered by `levels` (`device` names it) instead of the CPU; the
/// reference stays the CPU's, so both devices are measured against the same truth.
pub fn run_on(
    scene: &Scene,
    opts: &ConvergeOptions,
    device: &str,
    levels: &mut LevelRenderer<'_>,
) -> Result<ConvergeReport, String> {
    run_levels_with(scene, opts, Some((device, levels)), &mut |_| {})
}

/// As [`run`] (with `levels` None) or [`run_on`], telling `observe` how far the run has got and
/// how long the rest should take ([`Progress`]). The first render (1 spp, seed 1) is made
/// before the reference so that an estimate comes at once, not after the reference's hours.
pub fn run_observed(
    scene: &Scene,
    opts: &ConvergeOptions,
    levels: Option<(&str, &mut LevelRenderer<'_>)>,
    observe: &mut dyn FnMut(&Progress),
) -> Result<ConvergeReport, String> {
    run_levels_with(scene, opts, levels, observe)
}

/// The reference's spp for `opts` (the top level, a power of two, × the factor), or the
/// refusal that states the limit.
pub fn reference_spp(opts: &ConvergeOptions) -> Result<u32, String> {
    let factor = opts.reference_factor.max(16);
    let top = 1u32 << (31 - opts.max_spp.max(1).leading_zeros());
    top.checked_mul(factor)
        .filter(|s| *s <= MAX_REFERENCE_SPP)
        .ok_or_else(|| {
            format!(
                "a reference at {factor} × {top} spp is too many samples: the reference takes \
                 at most {MAX_REFERENCE_SPP} samples per pixel (--max-spp, rounded down to a \
                 power of two, × --reference-factor); lower --max-spp or --reference-factor"
            )
        })
}

/// Trace seconds and samples measured so far on one device.
#[derive(Debug, Clone, Copy, Default)]
struct Rate {
    seconds: f64,
    samples: u64,
}

impl Rate {
    fn add(&mut self, seconds: f64, samples: u64) {
        self.seconds += seconds;
        self.samples += samples;
    }

    /// Seconds per sample, if anything was measured.
    fn per_sample(&self) -> Option<f64> {
        (self.samples > 0).then(|| self.seconds / self.samples as f64)
    }
}

/// Counts what is done and estimates what is left, for the observer of [`run_observed`].
struct Tracker<'o> {
    done: Progress,
    /// The CPU's speed (the reference's, and the levels' when they render on the CPU).
    cpu: Rate,
    /// The other device's speed, when the levels render elsewhere.
    device: Option<Rate>,
    /// Samples still to trace: the reference's and the levels'.
    reference_left: u64,
    levels_left: u64,
    observe: &'o mut dyn FnMut(&Progress),
}

impl Tracker<'_> {
    /// Where a level's render is counted.
    fn level_rate(&mut self) -> &mut Rate {
        self.device.as_mut().unwrap_or(&mut self.cpu)
    }

    /// `renders` renders of `samples` samples in all took `seconds`: tells the observer.
    fn report(&mut self, finished: String, renders: usize, seconds: f64, samples: u64) {
        self.done.finished = finished;
        self.done.renders[0] += renders;
        self.done.samples[0] += samples;
        self.done.seconds += seconds;
        let cpu = self.cpu.per_sample();
        let device = self.device.and_then(|d| d.per_sample());
        let cpu_rate = cpu.or(device).unwrap_or(0.0);
        let level_rate = device.unwrap_or(cpu_rate);
        self.done.seconds_left =
            self.reference_left as f64 * cpu_rate + self.levels_left as f64 * level_rate;
        (self.observe)(&self.done);
    }
}

fn run_levels_with(
    scene: &Scene,
    opts: &ConvergeOptions,
    mut other: Option<(&str, &mut LevelRenderer<'_>)>,
    observe: &mut dyn FnMut(&Progress),
) -> Result<ConvergeReport, String> {
    if opts.max_spp == 0 || opts.seeds == 0 {
        return Err("converge needs --max-spp ≥ 1 and --seeds ≥ 1".into());
    }
    let top = 1u32 << (31 - opts.max_spp.leading_zeros());
    let reference_spp = match &opts.reference {
        Some(r) => r.spp,
        None => reference_spp(opts)?,
    };
    // One accelerator for every level: only the samples and the seed change.
    let base = PreparedScene::new(scene.clone());
    let build = base.build_time();
    let render_with =
        |spp: u32, seed: u32, progress: bool| render_at(scene, &base, spp, seed, opts, progress);
    let device_name = other.as_ref().map(|(d, _)| d.to_string());
    let mut render_level = |spp: u32, seed: u32| -> Result<(Vec<Vec3>, f64), String> {
        match &mut other {
            Some((_, f)) => f(spp, seed),
            None => {
                let out = render_with(spp, seed, false)?;
                Ok((out.pixels, out.stats.trace.as_secs_f64()))
            }
        }
    };

    // What the run will trace, to say how far it has got: per pixel, the reference's samples
    // and every level's (1 + 2 + … + top = 2·top − 1 per seed); on another device, also one
    // CPU render at 1 spp that times the CPU for the reference.
    let pixels = u64::from(scene.camera.width) * u64::from(scene.camera.height);
    let calibrate = u64::from(device_name.is_some());
    let levels_total = pixels * u64::from(opts.seeds) * (2 * u64::from(top) - 1);
    let reference_total = if opts.reference.is_some() {
        0
    } else {
        pixels * u64::from(reference_spp)
    };
    let mut tracker = Tracker {
        done: Progress {
            finished: String::new(),
            renders: [
                0,
                usize::from(opts.reference.is_none())
                    + calibrate as usize
                    + (top.ilog2() as usize + 1) * opts.seeds as usize,
            ],
            samples: [0, reference_total + levels_total + calibrate * pixels],
            seconds: 0.0,
            seconds_left: 0.0,
        },
        cpu: Rate::default(),
        device: device_name.as_ref().map(|_| Rate::default()),
        reference_left: reference_total,
        levels_left: levels_total,
        observe,
    };

    // The first level's first seed comes before the reference: its speed gives the first
    // estimate at once (the reference alone may take hours).
    let first = render_level(1, 1)?;
    tracker.levels_left -= pixels;
    tracker.level_rate().add(first.1, pixels);
    match &device_name {
        Some(d) => {
            tracker.report(
                format!("the first render (1 spp, seed 1) on {d}"),
                1,
                first.1,
                pixels,
            );
            let probe = render_with(1, 1, false)?;
            let seconds = probe.stats.trace.as_secs_f64();
            tracker.cpu.add(seconds, pixels);
            tracker.report(
                "a CPU render at 1 spp, to time the reference".into(),
                1,
                seconds,
                pixels,
            );
        }
        None => tracker.report(
            "the first render (1 spp, seed 1)".into(),
            1,
            first.1,
            pixels,
        ),
    }
    let mut first = Some(first);

    let reference = match &opts.reference {
        Some(r) => std::sync::Arc::clone(r),
        None => {
            let mut last = (0u32, 0.0f64);
            let r = render_reference(scene, &base, reference_spp, opts, &mut |done, seconds| {
                let samples = pixels * u64::from(done - last.0);
                let dt = seconds - last.1;
                last = (done, seconds);
                tracker.reference_left -= samples;
                tracker.cpu.add(dt, samples);
                let finished = if done == reference_spp {
                    format!("the reference ({reference_spp} spp)")
                } else {
                    format!("{done} of the reference's {reference_spp} spp")
                };
                tracker.report(finished, usize::from(done == reference_spp), dt, samples);
            })?;
            std::sync::Arc::new(r)
        }
    };
    let left_out = direct_emitters(&base);
    let measured_pixels = left_out.iter().filter(|o| !**o).count();
    let reference_seconds = reference.seconds;
    let (rn, ri) = reference.pixels.iter().fold((0, 0), |(n, i), p| {
        (
            n + p.is_nan() as usize,
            i + (!p.is_nan() && !p.is_finite()) as usize,
        )
    });
    if rn + ri > 0 {
        return Err(format!(
            "the reference render has {rn} NaN and {ri} infinite pixels: no error can be measured"
        ));
    }
    let mut samples = vec![];
    let mut levels = vec![];
    let mut image = vec![];
    let mut spp = 1;
    while spp <= top {
        let mut here = vec![];
        let (mut renders, mut level_seconds, mut level_samples) = (0, 0.0, 0);
        for seed in 1..=opts.seeds {
            // Level 1's seed 1 was rendered first (and counted then).
            let (pixels_out, seconds) = match first.take() {
                Some(made) => made,
                None => {
                    let made = render_level(spp, seed)?;
                    renders += 1;
                    level_seconds += made.1;
                    level_samples += pixels * u64::from(spp);
                    made
                }
            };
            if pixels_out.len() != reference.pixels.len() {
                return Err(format!(
                    "a level rendered {} pixels, the reference {}",
                    pixels_out.len(),
                    reference.pixels.len()
                ));
            }
            let e = errors(&pixels_out, &reference.pixels, &left_out);
            if spp == top && seed == 1 {
                image = pixels_out.clone();
            }
            here.push(Sample {
                spp,
                seed,
                seconds,
                mse: e.mse,
                rmse: e.mse.sqrt(),
                relmse: e.relmse,
                mse_all: e.mse_all,
                nan: e.nan,
                inf: e.inf,
            });
        }
        levels.push(Level {
            spp,
            seconds: quantiles(here.iter().map(|s| s.seconds).collect())[1],
            mse: quantiles(here.iter().map(|s| s.mse).collect()),
            rmse: quantiles(here.iter().map(|s| s.rmse).collect()),
            relmse: quantiles(here.iter().map(|s| s.relmse).collect()),
            mse_all: quantiles(here.iter().map(|s| s.mse_all).collect()),
            nan: here.iter().map(|s| s.nan).sum(),
            inf: here.iter().map(|s| s.inf).sum(),
        });
        samples.extend(here);
        tracker.levels_left -= level_samples;
        tracker.level_rate().add(level_seconds, level_samples);
        tracker.report(
            format!(
                "level {spp} spp ({} seed{})",
                opts.seeds,
                if opts.seeds == 1 { "" } else { "s" }
            ),
            renders,
            level_seconds,
            level_samples,
        );
        spp *= 2;
    }
    let pts: Vec<(f64, f64)> = levels
        .iter()
        .filter(|l| l.mse[1] > 0.0)
        .map(|l| ((l.spp as f64).ln(), l.mse[1].ln()))
        .collect();
    Ok(ConvergeReport {
        scene: scene.name.clone(),
        device: device_name.unwrap_or_else(|| "CPU".into()),
        size: [scene.camera.width, scene.camera.height],
        build_seconds: build.as_secs_f64(),
        reference_spp,
        reference_seconds,
        measured_pixels,
        left_out_pixels: left_out.len() - measured_pixels,
        samples,
        levels,
        mse_slope: slope(&pts),
        image,
    })
}

/// Renders `scene` on the CPU at `spp` samples per pixel with `seed`, on `base`'s accelerator.
fn render_at(
    scene: &Scene,
    base: &PreparedScene,
    spp: u32,
    seed: u32,
    opts: &ConvergeOptions,
    progress: bool,
) -> Result<crate::render::RenderOutput, String> {
    let mut settings = scene.settings.clone();
    settings.spp = spp;
    settings.seed = seed;
    let level = PreparedScene::with_settings(base.scene_arc(), &settings, Some(base));
    render(
        &level.tracer(),
        &RenderOptions {
            threads: opts.threads,
            progress,
            ..Default::default()
        },
    )
}

/// Renders the reference of `scene` at `spp` on the CPU with a seed no level uses (levels use
/// 1..=K), in [`REFERENCE_STEPS`] passes of samples added in order (the image is the one render
/// at `spp` makes, bit for bit); after each, `step(samples per pixel done, trace seconds so
/// far)`.
fn render_reference(
    scene: &Scene,
    base: &PreparedScene,
    spp: u32,
    opts: &ConvergeOptions,
    step: &mut dyn FnMut(u32, f64),
) -> Result<Reference, String> {
    let mut settings = scene.settings.clone();
    settings.spp = spp;
    settings.seed = 0x5EED_u32.wrapping_mul(7919);
    let prepared = PreparedScene::with_settings(base.scene_arc(), &settings, Some(base));
    let tracer = prepared.tracer();
    let chunk = spp.div_ceil(REFERENCE_STEPS).max(1);
    let (mut done, mut seconds, mut sums) = (0u32, 0.0f64, None);
    while done < spp {
        let end = done.saturating_add(chunk).min(spp);
        let out = render(
            &tracer,
            &RenderOptions {
                threads: opts.threads,
                progress: opts.progress,
                pass: Some(crate::render::Pass {
                    samples: done..end,
                    sums: sums.take(),
                }),
                ..Default::default()
            },
        )?;
        seconds += out.stats.trace.as_secs_f64();
        sums = Some(std::sync::Arc::new(out.pixels));
        done = end;
        step(done, seconds);
    }
    // The mean exactly as Tracer::trace_pixel divides it.
    let pixels = sums.map_or_else(Vec::new, |s| s.iter().map(|p| *p / spp as f32).collect());
    Ok(Reference {
        spp,
        pixels,
        seconds,
    })
}

/// Column names of [`csv`].
pub const CSV_COLUMNS: [&str; 9] = [
    "spp", "seed", "seconds", "mse", "rmse", "relmse", "nan", "inf", "mse_all",
];

/// One line per render (spp × seed).
pub fn csv(r: &ConvergeReport) -> String {
    let mut s = CSV_COLUMNS.join(",");
    s.push('\n');
    for x in &r.samples {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{}",
            x.spp, x.seed, x.seconds, x.mse, x.rmse, x.relmse, x.nan, x.inf, x.mse_all
        );
    }
    s
}

/// The Markdown report: setup, the equal-spp table and the equal-time table.
pub fn markdown(r: &ConvergeReport, load_seconds: f64) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# raystep converge: {}\n", r.scene);
    let _ = writeln!(
        s,
        "Levels rendered on: {} (the reference on the CPU).\n",
        r.device
    );
    let _ = writeln!(
        s,
        "{}×{} pixels. Load {:.3} s and accelerator build {:.3} s are excluded from the times \
         below (trace time only). Reference: {} spp ({:.2} s). relMSE = mean((x − r)²/(r² + ε)) \
         with ε = {}. Errors are medians over seeds, with the p10–p90 range. FLIP: not computed \
         (no nv-flip dependency).\n",
        r.size[0],
        r.size[1],
        load_seconds,
        r.build_seconds,
        r.reference_spp,
        r.reference_seconds,
        REL_EPSILON
    );
    let _ = writeln!(s, "{}\n", measured_words(r));
    let _ = writeln!(
        s,
        "MSE slope against spp (log–log least squares, on the measured pixels' MSE): **{:.2}** \
         (independent samples give −1).\n",
        r.mse_slope
    );
    let _ = writeln!(s, "## Equal spp\n");
    let _ = writeln!(
        s,
        "| spp | seconds | MSE | MSE p10–p90 | RMSE | relMSE | relMSE p10–p90 | MSE, every pixel | NaN | ∞ |"
    );
    let _ = writeln!(s, "|---:|---:|---:|---|---:|---:|---|---:|---:|---:|");
    for l in &r.levels {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {}–{} | {} | {} | {}–{} | {} | {} | {} |",
            l.spp,
            num(l.seconds),
            num(l.mse[1]),
            num(l.mse[0]),
            num(l.mse[2]),
            num(l.rmse[1]),
            num(l.relmse[1]),
            num(l.relmse[0]),
            num(l.relmse[2]),
            num(l.mse_all[1]),
            l.nan,
            l.inf
        );
    }
    let _ = writeln!(s, "\n## Equal time\n");
    let _ = writeln!(
        s,
        "For each time budget, the largest spp whose median trace time fits, and its error.\n"
    );
    let _ = writeln!(s, "| budget (s) | spp | MSE | relMSE |");
    let _ = writeln!(s, "|---:|---:|---:|---:|");
    let t0 = r.levels.first().map_or(0.0, |l| l.seconds).max(1e-6);
    let t1 = r.levels.last().map_or(0.0, |l| l.seconds);
    let mut budgets = vec![];
    let mut b = t0;
    while b < t1 {
        budgets.push(b);
        b *= 2.0;
    }
    budgets.push(t1);
    for budget in budgets {
        if let Some(l) = r.levels.iter().rev().find(|l| l.seconds <= budget) {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} |",
                num(budget),
                l.spp,
                num(l.mse[1]),
                num(l.relmse[1])
            );
        }
    }
    s
}

/// What the errors are measured over, in a sentence.
pub fn measured_words(r: &ConvergeReport) -> String {
    if r.left_out_pixels == 0 {
        return format!(
            "MSE and relMSE are measured over every pixel ({}).",
            r.measured_pixels
        );
    }
    format!(
        "MSE and relMSE measure the Monte Carlo noise: they are taken over the {} pixels that do \
         not see a light source directly. The {} pixels that do, or lie next to one that does, \
         are left out: there the error is where the lamp's edge falls among the pixel's camera \
         samples (aliasing, hundreds of times the noise elsewhere), not the estimator's. \
         \"MSE, every pixel\" keeps them.",
        r.measured_pixels, r.left_out_pixels
    )
}

fn band_series(label: &str, xs: &[f64], q: &[[f64; 3]], color: [u8; 4]) -> Series {
    Series {
        label: label.into(),
        points: xs.iter().zip(q).map(|(x, q)| [*x, q[1]]).collect(),
        line: true,
        filled: true,
        label_points: false,
        band: Some(xs.iter().zip(q).map(|(x, q)| [*x, q[0], q[2]]).collect()),
        color,
    }
}

/// The two log–log plots as PNG bytes: error against spp, and error against trace seconds.
pub fn plots(r: &ConvergeReport) -> (Vec<u8>, Vec<u8>) {
    let spp: Vec<f64> = r.levels.iter().map(|l| l.spp as f64).collect();
    let secs: Vec<f64> = r.levels.iter().map(|l| l.seconds.max(1e-9)).collect();
    let mse: Vec<[f64; 3]> = r.levels.iter().map(|l| l.mse).collect();
    let rel: Vec<[f64; 3]> = r.levels.iter().map(|l| l.relmse).collect();
    // The 1/spp guide through the first level.
    let guide = |xs: &[f64]| -> Series {
        let y0 = r.levels.first().map_or(1.0, |l| l.mse[1]);
        Series {
            label: "slope −1".into(),
            points: xs.iter().map(|x| [*x, y0 * xs[0] / x]).collect(),
            line: true,
            filled: false,
            label_points: false,
            band: None,
            color: [150, 150, 160, 255],
        }
    };
    let sub = format!(
        "median over seeds, band p10–p90; reference {} spp; relMSE ε = {}; MSE slope {:.2}{}",
        r.reference_spp,
        REL_EPSILON,
        r.mse_slope,
        if r.left_out_pixels > 0 {
            format!(
                "; {} pixels that see a light source left out",
                r.left_out_pixels
            )
        } else {
            String::new()
        }
    );
    let a = Plot {
        title: format!("{}: error against samples per pixel", r.scene),
        subtitle: sub.clone(),
        x_label: "samples per pixel (log)".into(),
        y_label: "error (log)".into(),
        series: vec![
            band_series("MSE", &spp, &mse, PALETTE[0]),
            band_series("relMSE", &spp, &rel, PALETTE[1]),
            guide(&spp),
        ],
    };
    let b = Plot {
        title: format!("{}: error against trace time", r.scene),
        subtitle: sub,
        x_label: "trace seconds (log; excludes load and BVH build)".into(),
        y_label: "error (log)".into(),
        series: vec![
            band_series("MSE", &secs, &mse, PALETTE[0]),
            band_series("relMSE", &secs, &rel, PALETTE[1]),
        ],
    };
    (draw(&a, 900, 600), draw(&b, 900, 600))
}
