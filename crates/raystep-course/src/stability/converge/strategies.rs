//! Comparing the path tracer's estimators of direct light (`raystep converge --strategy`, and the
//! app's lab): each strategy's levels against one reference rendered once with multiple
//! importance sampling, a summary row per strategy with its time to a target error, and the
//! plots with a series each.
//!
//! The target error is given, or by default one that every strategy crosses between its first
//! and its last level ([`default_target`]): each then has a time interpolated between two of
//! its levels, so the column compares like with like. When no error is crossed by all (one
//! strategy's last level is still above another's first), there is no default and the table
//! says so; a given target is shown for each strategy as crossed (between which levels),
//! already met at the first level (at most that time), or not reached.

use super::{
    CSV_COLUMNS, ConvergeOptions, ConvergeReport, PALETTE, Plot, Progress, REL_EPSILON,
    band_series, csv, draw, markdown, num, reference_spp, render_reference, run_levels_with,
};
use crate::scene::Scene;
use crate::trace::PreparedScene;
use std::fmt::Write as _;

/// One estimator's convergence in a comparison of strategies.
#[derive(Debug, Clone, PartialEq)]
pub struct StrategyRun {
    /// The strategy.
    pub strategy: crate::scene::Strategy,
    /// Its levels against the shared reference.
    pub report: ConvergeReport,
}

/// A strategy's name as the scene format and the command line spell it.
pub fn strategy_name(s: crate::scene::Strategy) -> String {
    clap::ValueEnum::to_possible_value(&s).map_or_else(String::new, |p| p.get_name().to_string())
}

/// Veach's comparison from a real run: the path-traced `scene` rendered with each of
/// `strategies` at the levels of `opts`, every level against one reference (rendered once, by
/// multiple importance sampling at the reference's spp: every strategy converges to it).
pub fn run_strategies(
    scene: &Scene,
    opts: &ConvergeOptions,
    strategies: &[crate::scene::Strategy],
    observe: &mut dyn FnMut(&Progress),
) -> Result<Vec<StrategyRun>, String> {
    use crate::scene::{Integrator, Strategy};
    if scene.settings.integrator != Integrator::Path {
        return Err(
            "--strategy compares the path tracer's estimators: give --integrator path (or set \
             integrator = \"path\" in the scene)"
                .into(),
        );
    }
    let spp = reference_spp(opts)?;
    let mut mis = scene.clone();
    mis.settings.strategy = Strategy::Mis;
    let base = PreparedScene::new(mis.clone());
    // The whole run's work, for one progress line over all of it: the reference, then each
    // strategy's levels (1 + 2 + … + top = 2·top − 1 samples per pixel and seed).
    let pixels = u64::from(scene.camera.width) * u64::from(scene.camera.height);
    let top = 1u64 << (31 - opts.max_spp.max(1).leading_zeros());
    let per_strategy = pixels * u64::from(opts.seeds) * (2 * top - 1);
    let renders_per_strategy = (top.ilog2() as usize + 1) * opts.seeds as usize;
    let n = strategies.len() as u64;
    let reference_samples = pixels * u64::from(spp);
    let all_renders = 1 + renders_per_strategy * strategies.len();
    let total_samples = reference_samples + n * per_strategy;
    let reference = std::sync::Arc::new(render_reference(
        &mis,
        &base,
        spp,
        opts,
        &mut |done, seconds| {
            let samples = pixels * u64::from(done);
            // Until a strategy has run, its levels are estimated at the reference's speed.
            let rate = seconds / samples.max(1) as f64;
            observe(&Progress {
                finished: if done == spp {
                    format!("the reference ({spp} spp, MIS)")
                } else {
                    format!("{done} of the MIS reference's {spp} spp")
                },
                renders: [usize::from(done == spp), all_renders],
                samples: [samples, total_samples],
                seconds,
                seconds_left: (total_samples - samples) as f64 * rate,
            })
        },
    )?);
    let mut out = vec![];
    let mut seconds_before = reference.seconds;
    for (i, &strategy) in strategies.iter().enumerate() {
        let mut s = scene.clone();
        s.settings.strategy = strategy;
        let o = ConvergeOptions {
            reference: Some(std::sync::Arc::clone(&reference)),
            ..opts.clone()
        };
        let name = strategy_name(strategy);
        let later = (n - 1 - i as u64) * per_strategy;
        let mut named = |p: &Progress| {
            // This strategy's progress within the whole run; the strategies still to come are
            // estimated at this one's speed.
            let rate = p.seconds / p.samples[0].max(1) as f64;
            observe(&Progress {
                finished: format!("{name}: {}", p.finished),
                renders: [1 + renders_per_strategy * i + p.renders[0], all_renders],
                samples: [
                    reference_samples + per_strategy * i as u64 + p.samples[0],
                    total_samples,
                ],
                seconds: seconds_before + p.seconds,
                seconds_left: p.seconds_left + later as f64 * rate,
            })
        };
        let report = run_levels_with(&s, &o, None, &mut named)?;
        seconds_before += report.samples.iter().map(|x| x.seconds).sum::<f64>();
        out.push(StrategyRun { strategy, report });
    }
    Ok(out)
}

/// How an estimator reaches a target error (its median relMSE over seeds, for good: from the
/// first level after which every level stays at or below it — a heavy-tailed estimator can dip
/// below early and rise again).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reach {
    /// Above it at level `spp[0]`, at or below from `spp[1]` on: the trace seconds interpolated
    /// on the log–log line between the two.
    Crossed {
        /// The interpolated time.
        seconds: f64,
        /// The levels around it.
        spp: [u32; 2],
    },
    /// At or below it from the first level on: it took at most that level's time.
    AtFirst {
        /// The first level's time.
        seconds: f64,
        /// The first level's spp.
        spp: u32,
    },
    /// Still above it at the last level.
    NotReached {
        /// The last level's spp.
        spp: u32,
    },
}

impl Reach {
    /// The time (the first level's for [`Reach::AtFirst`]); None if not reached.
    pub fn seconds(&self) -> Option<f64> {
        match *self {
            Reach::Crossed { seconds, .. } | Reach::AtFirst { seconds, .. } => Some(seconds),
            Reach::NotReached { .. } => None,
        }
    }

    /// The table's cell: the time, and how it was found.
    pub fn cell(&self) -> String {
        match *self {
            Reach::Crossed { seconds, spp } => {
                format!("{} s (between {} and {} spp)", num(seconds), spp[0], spp[1])
            }
            Reach::AtFirst { seconds, spp } => {
                format!("≤ {} s (already at {spp} spp)", num(seconds))
            }
            Reach::NotReached { spp } => format!("not reached by {spp} spp"),
        }
    }
}

/// How the report's estimator reaches `target` relMSE ([`Reach`]).
pub fn reach(r: &ConvergeReport, target: f64) -> Reach {
    let above = r.levels.iter().rposition(|l| l.relmse[1] > target);
    let i = above.map_or(0, |k| k + 1);
    let Some(b) = r.levels.get(i) else {
        return Reach::NotReached {
            spp: r.levels.last().map_or(0, |l| l.spp),
        };
    };
    if i == 0 {
        return Reach::AtFirst {
            seconds: b.seconds,
            spp: b.spp,
        };
    }
    let a = &r.levels[i - 1];
    let (ea, eb) = (a.relmse[1].ln(), b.relmse[1].max(1e-300).ln());
    let (ta, tb) = (a.seconds.max(1e-9).ln(), b.seconds.max(1e-9).ln());
    let seconds = if (ea - eb).abs() < 1e-12 {
        b.seconds
    } else {
        (ta + (target.ln() - ea) * (tb - ta) / (eb - ea)).exp()
    };
    Reach::Crossed {
        seconds,
        spp: [a.spp, b.spp],
    }
}

/// The trace seconds a report's estimator takes to reach `target` relMSE ([`reach`]): the
/// interpolated time, the first level's if it is there already, None if the last level is
/// above it.
pub fn time_to_relmse(r: &ConvergeReport, target: f64) -> Option<f64> {
    reach(r, target).seconds()
}

/// The target error of a comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// Given (`--target-relmse`).
    Given(f64),
    /// None given: the default ([`default_target`]), crossed by every strategy between its
    /// levels.
    Default(f64),
    /// None given, and no error is crossed by every strategy between its levels.
    Missing,
}

impl Target {
    /// The target for `runs`: `given`, else the default if there is one.
    pub fn of(runs: &[StrategyRun], given: Option<f64>) -> Target {
        match (given, default_target(runs)) {
            (Some(t), _) => Target::Given(t),
            (None, Some(t)) => Target::Default(t),
            (None, None) => Target::Missing,
        }
    }

    /// Its value, if there is one.
    pub fn value(&self) -> Option<f64> {
        match *self {
            Target::Given(t) | Target::Default(t) => Some(t),
            Target::Missing => None,
        }
    }
}

/// The target error of a comparison when none is given: one that every strategy crosses
/// between its first and its last level, so each strategy's time to it is measured between
/// two of its own levels — the geometric mean of the largest last-level relMSE and the
/// smallest first-level one. None when there is no such error (some strategy's last level is
/// above another's first) or a strategy has fewer than two levels.
pub fn default_target(runs: &[StrategyRun]) -> Option<f64> {
    let mut low = 0.0f64; // the largest last-level error
    let mut high = f64::INFINITY; // the smallest first-level error
    for r in runs {
        let levels = &r.report.levels;
        if levels.len() < 2 {
            return None;
        }
        low = low.max(levels[levels.len() - 1].relmse[1]);
        high = high.min(levels[0].relmse[1]);
    }
    (!runs.is_empty() && low > 0.0 && low < high && high.is_finite()).then(|| (low * high).sqrt())
}

/// Each strategy's relMSE from its first level to its last, in words: `light 9.1 → 2.5`.
fn ranges(runs: &[StrategyRun]) -> String {
    runs.iter()
        .filter_map(|r| {
            let (a, b) = (r.report.levels.first()?, r.report.levels.last()?);
            Some(format!(
                "{} {} → {}",
                strategy_name(r.strategy),
                num(a.relmse[1]),
                num(b.relmse[1])
            ))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// What the target is, in a sentence (the comparison's Markdown, and the app's lab).
pub fn target_words(runs: &[StrategyRun], target: Target) -> String {
    let (first, last) = runs
        .first()
        .and_then(|r| Some((r.report.levels.first()?.spp, r.report.levels.last()?.spp)))
        .unwrap_or((1, 1));
    match target {
        Target::Given(t) => format!(
            "The target relMSE {} was given. From {first} to {last} spp the strategies' relMSE \
             goes: {}.",
            num(t),
            ranges(runs)
        ),
        Target::Default(t) => format!(
            "The target relMSE {} is the default: every strategy crosses it between two of its \
             levels ({}), so each time is measured, not bounded.",
            num(t),
            ranges(runs)
        ),
        Target::Missing => format!(
            "No time to a common error: no relMSE is crossed by every strategy between {first} \
             and {last} spp ({}). Give --target-relmse E (each strategy is then shown as \
             crossing it, already below it at {first} spp, or not reaching it), or raise \
             --max-spp.",
            ranges(runs)
        ),
    }
}

/// The comparison's Markdown: one row per strategy (its error at the top level, its MSE slope,
/// its time to the target error), then each strategy's own tables.
pub fn strategies_markdown(runs: &[StrategyRun], target: Target, load_seconds: f64) -> String {
    let mut s = String::new();
    let Some(first) = runs.first() else {
        return s;
    };
    let r0 = &first.report;
    let _ = writeln!(
        s,
        "# raystep converge: {}, strategies compared\n\n{}×{} pixels, path tracer. Every strategy \
         is measured against one reference: {} spp by multiple importance sampling ({:.2} s). \
         relMSE = mean((x − r)²/(r² + ε)) with ε = {}; medians over seeds. Times are trace \
         seconds on {}. {}\n",
        r0.scene,
        r0.size[0],
        r0.size[1],
        r0.reference_spp,
        r0.reference_seconds,
        REL_EPSILON,
        r0.device,
        super::measured_words(r0)
    );
    let (head, rows) = strategy_table(runs, target);
    let _ = writeln!(s, "| {} |", head.join(" | "));
    let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|");
    for row in rows {
        let _ = writeln!(s, "| {} |", row.join(" | "));
    }
    let _ = writeln!(
        s,
        "\n{}\n\nThe MSE slope is the least-squares slope of log MSE against log spp (independent \
         samples give −1). The time to the target is interpolated on the log–log line between \
         the two levels around it.\n",
        target_words(runs, target)
    );
    for r in runs {
        let _ = writeln!(s, "\n## Strategy: {}\n", strategy_name(r.strategy));
        let body = markdown(&r.report, load_seconds);
        // The report's own title is replaced by the section's.
        s.push_str(body.split_once('\n').map_or(&body[..], |(_, rest)| rest));
    }
    s
}

/// The comparison's summary table, one row per strategy (the command line's Markdown and the
/// app's lab show it): its header, and per strategy its name, relMSE and MSE at the top level,
/// MSE slope, seconds at the top level and time to the target relMSE ([`Reach::cell`]; the
/// header says whether the target is the default or given, and the column is empty when there
/// is none).
pub fn strategy_table(runs: &[StrategyRun], target: Target) -> ([String; 6], Vec<[String; 6]>) {
    let top = runs
        .first()
        .and_then(|r| r.report.levels.last())
        .map_or(0, |l| l.spp);
    let head = [
        "strategy".to_string(),
        format!("relMSE at {top} spp"),
        format!("MSE at {top} spp"),
        "MSE slope".to_string(),
        format!("seconds at {top} spp"),
        match target {
            Target::Given(t) => format!("time to relMSE {} (given)", num(t)),
            Target::Default(t) => format!("time to relMSE {} (default)", num(t)),
            Target::Missing => "time to a common relMSE".to_string(),
        },
    ];
    let rows = runs
        .iter()
        .map(|r| {
            let l = r.report.levels.last();
            [
                strategy_name(r.strategy),
                l.map_or_else(String::new, |l| num(l.relmse[1])),
                l.map_or_else(String::new, |l| num(l.mse[1])),
                format!("{:.2}", r.report.mse_slope),
                l.map_or_else(String::new, |l| num(l.seconds)),
                target.value().map_or_else(
                    || "none: see below".to_string(),
                    |t| reach(&r.report, t).cell(),
                ),
            ]
        })
        .collect();
    (head, rows)
}

/// One line per render, with its strategy first.
pub fn strategies_csv(runs: &[StrategyRun]) -> String {
    let mut s = format!("strategy,{}\n", CSV_COLUMNS.join(","));
    for r in runs {
        let name = strategy_name(r.strategy);
        for line in csv(&r.report).lines().skip(1) {
            let _ = writeln!(s, "{name},{line}");
        }
    }
    s
}

/// The comparison's two log–log plots (relMSE against spp and against trace seconds), one
/// series per strategy.
pub fn strategies_plots(runs: &[StrategyRun], target: Target) -> (Vec<u8>, Vec<u8>) {
    let scene = runs
        .first()
        .map_or(String::new(), |r| r.report.scene.clone());
    let mut by_spp = vec![];
    let mut by_time = vec![];
    for (i, r) in runs.iter().enumerate() {
        let spp: Vec<f64> = r.report.levels.iter().map(|l| l.spp as f64).collect();
        let secs: Vec<f64> = r
            .report
            .levels
            .iter()
            .map(|l| l.seconds.max(1e-9))
            .collect();
        let rel: Vec<[f64; 3]> = r.report.levels.iter().map(|l| l.relmse).collect();
        let name = strategy_name(r.strategy);
        let colour = PALETTE[i % PALETTE.len()];
        by_spp.push(band_series(&name, &spp, &rel, colour));
        by_time.push(band_series(&name, &secs, &rel, colour));
    }
    let sub = format!(
        "relMSE, median over seeds, band p10–p90; one MIS reference; {}",
        match target {
            Target::Given(t) => format!("target relMSE {} (given)", num(t)),
            Target::Default(t) => format!("target relMSE {} (default)", num(t)),
            Target::Missing => "no target".to_string(),
        }
    );
    let a = Plot {
        title: format!("{scene}: each strategy's error against samples per pixel"),
        subtitle: sub.clone(),
        x_label: "samples per pixel (log)".into(),
        y_label: "relMSE (log)".into(),
        series: by_spp,
    };
    let b = Plot {
        title: format!("{scene}: each strategy's error against trace time"),
        subtitle: sub,
        x_label: "trace seconds (log; excludes load and BVH build)".into(),
        y_label: "relMSE (log)".into(),
        series: by_time,
    };
    (draw(&a, 900, 600), draw(&b, 900, 600))
}
