//! The lab's report as text: a Markdown summary and table, a CSV with one row per
//! method × precision × case, and a CSV of the Monte Carlo cases ([`mc_csv`]).

use super::{Primitive, Report};
use std::fmt::Write as _;

/// The CSV header, in column order.
pub const CSV_COLUMNS: [&str; 21] = [
    "case",
    "title",
    "primitive",
    "method",
    "precision",
    "rays",
    "exact_hits",
    "in_band",
    "misclassified",
    "leak_rays",
    "leaks",
    "self_hits",
    "nonfinite",
    "compared",
    "t_max_ulps",
    "t_p99_ulps",
    "t_max_rel",
    "t_p99_rel",
    "uv_max_ulps",
    "uv_p99_ulps",
    "ns_per_test",
];

/// The Monte Carlo CSV's header (`stability-mc.csv`), in column order.
pub const MC_CSV_COLUMNS: [&str; 14] = [
    "case",
    "title",
    "quantity",
    "method",
    "precision",
    "samples",
    "misclassified",
    "nonfinite",
    "compared",
    "max_rel",
    "p99_rel",
    "max_ulps",
    "p99_ulps",
    "ns_per_sample",
];

/// A number in at most 4 significant digits, switching to exponent form when very large or small.
pub fn num(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if !x.is_finite() {
        format!("{x}")
    } else if x.abs() >= 1e5 || x.abs() < 1e-3 {
        format!("{x:.2e}")
    } else {
        let s = format!("{x:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        // Keep about 4 significant digits.
        let digits = s.chars().filter(|c| c.is_ascii_digit()).count();
        if digits > 5 {
            format!(
                "{:.*}",
                (3 - x.abs().log10().floor() as i32).max(0) as usize,
                x
            )
        } else {
            s.to_string()
        }
    }
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The CSV: a header line ([`CSV_COLUMNS`]) and one line per row. Floats are written in full
/// (`{}`), empty where a column does not apply.
pub fn csv(report: &Report) -> String {
    let mut out = CSV_COLUMNS.join(",");
    out.push('\n');
    let opt = |x: Option<f64>| x.map(|v| format!("{v}")).unwrap_or_default();
    for r in &report.rows {
        let fields = [
            r.case.to_string(),
            csv_field(r.title),
            r.primitive.name().into(),
            r.method.name().into(),
            r.precision.name().into(),
            r.rays.to_string(),
            r.exact_hits.to_string(),
            r.in_band.to_string(),
            r.misclassified.to_string(),
            r.leak_rays.to_string(),
            r.leaks.to_string(),
            r.self_hits.to_string(),
            r.nonfinite.to_string(),
            r.compared.to_string(),
            format!("{}", r.t_max_ulps),
            format!("{}", r.t_p99_ulps),
            format!("{}", r.t_max_rel),
            format!("{}", r.t_p99_rel),
            opt(r.uv_max_ulps),
            opt(r.uv_p99_ulps),
            format!("{}", r.ns_per_test),
        ];
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    out
}

/// The Monte Carlo CSV: a header line ([`MC_CSV_COLUMNS`]) and one line per row of
/// [`Report::mc`], floats in full.
pub fn mc_csv(report: &Report) -> String {
    let mut out = MC_CSV_COLUMNS.join(",");
    out.push('\n');
    for r in &report.mc {
        let fields = [
            r.case.to_string(),
            csv_field(r.title),
            csv_field(r.quantity),
            r.method.name().into(),
            r.precision.name().into(),
            r.samples.to_string(),
            r.misclassified.to_string(),
            r.nonfinite.to_string(),
            r.compared.to_string(),
            format!("{}", r.max_rel),
            format!("{}", r.p99_rel),
            format!("{}", r.max_ulps),
            format!("{}", r.p99_ulps),
            format!("{}", r.ns_per_sample),
        ];
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    out
}

/// The Markdown report: a summary per primitive × method × precision (the plots' points), then
/// every row.
pub fn markdown(report: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# raystep stability lab{}\n",
        if report.quick { " (quick suite)" } else { "" }
    );
    let _ = writeln!(
        s,
        "{} rays, every applicable method in f32 and f64, each answer against an exact rational \
         reference; {:.1} s. *Misclassified*: hit/miss (or sphere root) differs from the exact \
         answer outside the rounding band. *Leaks*: rays aimed exactly at a shared edge or vertex \
         that hit no triangle. *Self-hits*: spawned rays hitting their own surface. t errors in \
         ulps of the exact t in the row's precision; u, v errors in ulps of 1. Cost in ns per \
         test on the row's own inputs (a debug build's figures are not comparable with release).\n",
        report.rays, report.seconds
    );
    let _ = writeln!(s, "## Summary\n");
    let _ = writeln!(
        s,
        "| primitive | method | precision | ns/test | p99 t err (ulps) | max t err (ulps) | misclassified | leaks | self-hits | NaN/∞ |"
    );
    let _ = writeln!(s, "|---|---|---|---:|---:|---:|---:|---:|---:|---:|");
    for p in &report.points {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            p.primitive.name(),
            p.method.name(),
            p.precision.name(),
            num(p.ns_per_test),
            num(p.p99_ulps),
            num(p.max_ulps),
            p.misclassified,
            p.leaks,
            p.self_hits,
            p.nonfinite
        );
    }
    for prim in Primitive::ALL {
        let rows: Vec<_> = report.rows.iter().filter(|r| r.primitive == prim).collect();
        if rows.is_empty() {
            continue;
        }
        let _ = writeln!(s, "\n## {}\n", prim.name());
        let _ = writeln!(
            s,
            "| case | method | prec | rays | in band | misclassified | leaks | self-hits | NaN/∞ | t max (ulps) | t p99 (ulps) | t max rel | uv max (ulps) | ns/test |"
        );
        let _ = writeln!(
            s,
            "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
        );
        let mut last_case = "";
        for r in rows {
            let case = if r.case != last_case {
                last_case = r.case;
                format!("{} {}", r.case, r.title)
            } else {
                String::new()
            };
            let leaks = if r.leak_rays > 0 {
                format!("{}/{}", r.leaks, r.leak_rays)
            } else {
                "–".into()
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                case,
                r.method.name(),
                r.precision.name(),
                r.rays,
                r.in_band,
                r.misclassified,
                leaks,
                r.self_hits,
                r.nonfinite,
                num(r.t_max_ulps),
                num(r.t_p99_ulps),
                num(r.t_max_rel),
                r.uv_max_ulps.map(num).unwrap_or_else(|| "–".into()),
                num(r.ns_per_test)
            );
        }
    }
    if !report.mc.is_empty() {
        mc_markdown(&mut s, report);
    }
    s
}

/// The Monte Carlo section of the Markdown report.
fn mc_markdown(s: &mut String, report: &Report) {
    let _ = writeln!(s, "\n## Monte Carlo sampling (S26–S29)\n");
    let _ = writeln!(
        s,
        "{} samples, each quantity in its textbook and stable formulation, against an exact \
         reference (rationals, 200-bit square roots). *Misclassified*: zero, negative, ∞ or NaN \
         where the exact value is a positive number the precision holds (a dropped light, a \
         density that is none, a direction collapsed onto its axis); those are left out of the \
         error columns. Relative error |y − exact|/exact; ulps of the exact value in the row's \
         precision. Cost in ns per sample (all of the case's quantities).\n",
        report.mc_samples
    );
    let _ = writeln!(
        s,
        "| case | quantity | method | prec | samples | misclassified | NaN/∞ | max rel | p99 rel | max ulps | p99 ulps | ns/sample |"
    );
    let _ = writeln!(
        s,
        "|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    let mut last_case = "";
    for r in &report.mc {
        let case = if r.case != last_case {
            last_case = r.case;
            format!("{} {}", r.case, r.title)
        } else {
            String::new()
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            case,
            r.quantity,
            r.method.name(),
            r.precision.name(),
            r.samples,
            r.misclassified,
            r.nonfinite,
            num(r.max_rel),
            num(r.p99_rel),
            num(r.max_ulps),
            num(r.p99_ulps),
            num(r.ns_per_sample)
        );
    }
}
