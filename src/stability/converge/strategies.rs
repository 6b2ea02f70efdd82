//! Comparing the path tracer's estimators of direct light (`raystep converge --strategy`, and the
//! app's lab): each strategy's levels against one reference rendered once with multiple
//! importance sampling, a summary row per strategy with its time to a target error, and the
//! plots with a series each.

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
    let reference = std::sync::Arc::new(render_reference(&mis, &base, spp, opts)?);
    let pixels = u64::from(scene.camera.width) * u64::from(scene.camera.height);
    observe(&Progress {
        finished: format!("the reference ({spp} spp, MIS)"),
        renders: [1, 1],
        samples: [pixels * u64::from(spp), pixels * u64::from(spp)],
        seconds: reference.seconds,
        seconds_left: 0.0,
    });
    let mut out = vec![];
    for &strategy in strategies {
        let mut s = scene.clone();
        s.settings.strategy = strategy;
        let o = ConvergeOptions {
            reference: Some(std::sync::Arc::clone(&reference)),
            ..opts.clone()
        };
        let name = strategy_name(strategy);
        let mut named = |p: &Progress| {
            let mut q = p.clone();
            q.finished = format!("{name}: {}", p.finished);
            observe(&q)
        };
        let report = run_levels_with(&s, &o, None, &mut named)?;
        out.push(StrategyRun { strategy, report });
    }
    Ok(out)
}

/// The trace seconds a report's estimator takes to reach `target` relMSE (median over seeds)
/// for good: from the first level after which every level stays at or below it (a heavy-tailed
/// estimator can dip below early and rise again), interpolated on the log–log line between that
/// level and the one before; the first level's time if every level is there; None if the last
/// level is above it.
pub fn time_to_relmse(r: &ConvergeReport, target: f64) -> Option<f64> {
    let above = r.levels.iter().rposition(|l| l.relmse[1] > target);
    let i = above.map_or(0, |k| k + 1);
    if i >= r.levels.len() {
        return None;
    }
    let b = &r.levels[i];
    if i == 0 {
        return Some(b.seconds);
    }
    let a = &r.levels[i - 1];
    let (ea, eb) = (a.relmse[1].ln(), b.relmse[1].max(1e-300).ln());
    let (ta, tb) = (a.seconds.max(1e-9).ln(), b.seconds.max(1e-9).ln());
    if (ea - eb).abs() < 1e-12 {
        return Some(b.seconds);
    }
    Some((ta + (target.ln() - ea) * (tb - ta) / (eb - ea)).exp())
}

/// The target error of a comparison when none is given: the largest top-level relMSE among
/// the strategies (the least converged one's final error), so every strategy reaches it.
pub fn default_target(runs: &[StrategyRun]) -> f64 {
    runs.iter()
        .filter_map(|r| r.report.levels.last().map(|l| l.relmse[1]))
        .fold(0.0, f64::max)
}

/// The comparison's Markdown: one row per strategy (its error at the top level, its MSE slope,
/// its time to the target error), then each strategy's own tables.
pub fn strategies_markdown(runs: &[StrategyRun], target: f64, load_seconds: f64) -> String {
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
         seconds on {}.\n",
        r0.scene,
        r0.size[0],
        r0.size[1],
        r0.reference_spp,
        r0.reference_seconds,
        REL_EPSILON,
        r0.device
    );
    let (head, rows) = strategy_table(runs, target);
    let _ = writeln!(s, "| {} |", head.join(" | "));
    let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|");
    for row in rows {
        let _ = writeln!(s, "| {} |", row.join(" | "));
    }
    let _ = writeln!(
        s,
        "\nThe MSE slope is the least-squares slope of log MSE against log spp (independent \
         samples give −1). The time to the target is interpolated on the log–log line between \
         the two levels around it.\n"
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
/// MSE slope, seconds at the top level and time to the target relMSE.
pub fn strategy_table(runs: &[StrategyRun], target: f64) -> ([String; 6], Vec<[String; 6]>) {
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
        format!("time to relMSE {}", num(target)),
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
                time_to_relmse(&r.report, target)
                    .map_or_else(|| "not reached".into(), |t| format!("{} s", num(t))),
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
pub fn strategies_plots(runs: &[StrategyRun], target: f64) -> (Vec<u8>, Vec<u8>) {
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
        "relMSE, median over seeds, band p10–p90; one MIS reference; target relMSE {}",
        num(target)
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
