//! `raystep diff`: compare two saved traces step by step and report the first divergence.
//! Exit status: 0 equal (within the tolerance), 1 different, 2 bad input.

use crate::explain::diff::compare;
use crate::record::Tolerance;
use crate::record::Trace;
use std::path::PathBuf;
use std::process::ExitCode;

/// Arguments of `raystep diff`.
#[derive(Debug, clap::Args)]
pub struct DiffArgs {
    /// The reference trace (JSON from `raystep trace --save` or the app's File → Save trace).
    pub expected: PathBuf,
    /// The trace to compare with it.
    pub actual: PathBuf,
    /// Numbers a, b agree when |a − b| ≤ max(T, T·max(|a|, |b|)): T is both the absolute and the
    /// relative tolerance. 0 (the default) compares exactly. NaN equals NaN; ±∞ only itself.
    #[arg(long, default_value_t = 0.0, value_parser = parse_tolerance)]
    pub tolerance: f64,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
}

fn parse_tolerance(s: &str) -> Result<f64, String> {
    let t: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("\"{s}\" is not a number"))?;
    if !t.is_finite() || t < 0.0 {
        return Err(format!("must be a finite number ≥ 0, got {s}"));
    }
    Ok(t)
}

/// Runs `raystep diff`; returns the exit status itself (1 means "they differ", 2 bad input).
pub fn run(args: &DiffArgs) -> ExitCode {
    let bad = ExitCode::from(2);
    let expected = Trace::load(&args.expected);
    let actual = Trace::load(&args.actual);
    let (expected, actual) = match (expected, actual) {
        (Ok(e), Ok(a)) => (e, a),
        (e, a) => {
            for err in [e.err(), a.err()].into_iter().flatten() {
                eprintln!("error: {err}");
            }
            return bad;
        }
    };
    let cmp = compare(
        &expected,
        &actual,
        Tolerance::relative_to_larger(args.tolerance, args.tolerance),
    );
    let names = [
        args.expected.display().to_string(),
        args.actual.display().to_string(),
    ];
    let names = [names[0].as_str(), names[1].as_str()];
    let text = if args.json {
        let v = cmp.to_json(&expected, &actual, names);
        serde_json::to_string_pretty(&v).expect("JSON serializes") + "\n"
    } else {
        cmp.to_text(&expected, &actual, names)
    };
    if let Err(msg) = super::emit(&text) {
        eprintln!("error: {msg}");
        return bad;
    }
    if cmp.is_equal() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
