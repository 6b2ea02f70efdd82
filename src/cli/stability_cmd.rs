//! `raystep stability`: the numerical stability lab (every method × precision × stiff case).

use crate::stability::{Options, Precision, Primitive, plot, report, run};
use std::path::PathBuf;

/// Arguments of `raystep stability`.
#[derive(Debug, clap::Args)]
pub struct StabilityArgs {
    /// The CI suite: every case at fewer scales and rays (seconds instead of minutes).
    #[arg(long)]
    pub quick: bool,
    /// Directory for stability.md, stability.csv, stability-mc.csv (the Monte Carlo cases) and
    /// one error-vs-time PNG per primitive (created if missing).
    #[arg(long, default_value = "stability")]
    pub out: PathBuf,
    /// Rays per case and scale (default: 200 quick, 4000 full).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
    pub rays: Option<u64>,
    /// Seed of the ray generators.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Runs `raystep stability`.
pub fn run_cmd(args: &StabilityArgs) -> Result<(), String> {
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("{}: cannot create the directory: {e}", args.out.display()))?;
    let mut opts = if args.quick {
        Options::quick()
    } else {
        Options::full()
    };
    if let Some(n) = args.rays {
        opts.rays = n as usize;
    }
    opts.seed = args.seed;
    let rep = run(&opts);
    let md = report::markdown(&rep);
    crate::io::write_atomic(&args.out.join("stability.md"), md.as_bytes())?;
    crate::io::write_atomic(
        &args.out.join("stability.csv"),
        report::csv(&rep).as_bytes(),
    )?;
    crate::io::write_atomic(
        &args.out.join("stability-mc.csv"),
        report::mc_csv(&rep).as_bytes(),
    )?;
    let mut written = vec![
        "stability.md".to_string(),
        "stability.csv".to_string(),
        "stability-mc.csv".to_string(),
    ];
    for prim in Primitive::ALL {
        if let Some(png) = plot::cost_plot(&rep.points, prim, rep.quick) {
            let name = format!("stability-{}.png", prim.name());
            crate::io::write_atomic(&args.out.join(&name), &png)?;
            written.push(name);
        }
    }
    let mut summary = String::new();
    for p in &rep.points {
        summary += &format!(
            "{:9} {:19} {}  {:>9} ns/test  p99 {:>9} ulps  misclassified {:>5}  leaks {:>5}  self-hits {:>5}  NaN/∞ {}\n",
            p.primitive.name(),
            p.method.name(),
            p.precision.name(),
            report::num(p.ns_per_test),
            report::num(p.p99_ulps),
            p.misclassified,
            p.leaks,
            p.self_hits,
            p.nonfinite
        );
    }
    summary += "\nMonte Carlo (f32): quantity, method, max and p99 relative error, misclassified\n";
    for r in rep.mc.iter().filter(|r| r.precision == Precision::F32) {
        summary += &format!(
            "{:4} {:13} {:9} max {:>9}  p99 {:>9}  misclassified {:>5}\n",
            r.case,
            r.quantity,
            r.method.name(),
            report::num(r.max_rel),
            report::num(r.p99_rel),
            r.misclassified
        );
    }
    summary += &format!(
        "\n{} rays and {} Monte Carlo samples in {:.1} s; wrote {} in {}\n",
        rep.rays,
        rep.mc_samples,
        rep.seconds,
        written.join(", "),
        super::full_path(&args.out)
    );
    super::emit(&summary)
}
