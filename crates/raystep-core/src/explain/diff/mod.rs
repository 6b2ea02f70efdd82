//! Comparing two recorded traces step by step (`raystep diff`).
//!
//! Both traces are walked as JSON trees (their own serialization, so every field the format has
//! is compared, including fields added later), in timeline order: a ray's own fields where it is
//! spawned, then its steps, a child ray's steps where its parent spawned it, then the ray's
//! result (hit, weight, colour). Steps are aligned by their kind, so a missing or extra step
//! (a shadow ray that one trace has and the other has not) is reported as such, in words, and
//! the steps after it are still compared. Every difference names the ray path, the timeline step
//! index (as [`Trace::timeline`] numbers them, 0-based), the step and the field.
//!
//! Numbers a and b (floats) agree when |a − b| ≤ max(abs, rel·max(|a|, |b|)) (a [`Tolerance`] with
//! the [`relative_to_larger`](Tolerance::relative_to_larger) rule); NaN equals NaN and ±∞ equals
//! only the same infinity. Integers (ids, indices, counts) and everything else (names,
//! methods, decisions such as hit or miss, which root, blocked, total internal reflection) must
//! be equal. The header (format and raystep versions, scene name and hash, pixel, sample,
//! settings) is compared exactly but reported as information only: comparing two settings' traces
//! is often the point.

use super::describe;
use crate::record::number::{Style, fmt64};
use crate::record::{Tolerance, Trace};
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};
use std::collections::HashMap;
use std::fmt::Write;
use std::ops::Range;

mod json;
mod walk;

use json::{J, NULL};
use walk::Walker;

/// `0`, `1e-6`, or `abs 1e-6, rel 1e-4`: a tolerance as the report names it.
fn describe_tolerance(t: &Tolerance) -> String {
    if t.abs == t.rel {
        small(t.abs)
    } else {
        format!("abs {}, rel {}", small(t.abs), small(t.rel))
    }
}

/// What kind of difference.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum DiffKind {
    /// Two numbers that differ by more than the tolerance.
    Number,
    /// Any other value: a name, a method, a decision, an id, a count.
    Value,
    /// Steps (or a ray, or an object) the expected trace has and the actual trace lacks.
    Missing,
    /// Steps (or a ray, or an object) the actual trace has and the expected trace lacks.
    Extra,
    /// Different steps in the same place.
    Replaced,
}

/// One difference between the traces.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Difference {
    /// What kind.
    pub kind: DiffKind,
    /// The timeline step index in the expected trace, when the difference is at a step.
    pub step: Option<usize>,
    /// The timeline step index in the actual trace (differs from `step` after a missing or
    /// extra step).
    pub actual_step: Option<usize>,
    /// Where: the ray path (`primary ray → shadow ray 0`), or `header`, `camera`, `objects`, … .
    pub place: String,
    /// The pipeline stage of the step.
    pub stage: Option<String>,
    /// The step or record, e.g. `sphere "mirror"`.
    pub subject: Option<String>,
    /// The field, e.g. `discriminant`, `direction[1]`.
    pub field: Option<String>,
    /// The expected value (as in the JSON).
    pub expected: Value,
    /// The actual value.
    pub actual: Value,
    /// |expected − actual| for two finite numbers.
    pub difference: Option<f64>,
    /// The whole difference in words.
    pub message: String,
}

/// The result of comparing two traces.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// The tolerance used (the [`relative_to_larger`](Tolerance::relative_to_larger) rule).
    pub tolerance: Tolerance,
    /// Header differences (information, not divergences).
    pub header: Vec<Difference>,
    /// The differences, in timeline order, then the final colour and the scene data (camera,
    /// lights, objects, BVH outline). At most [`MAX_KEPT`] are kept; `count` has them all.
    pub differences: Vec<Difference>,
    /// How many differences there are.
    pub count: usize,
    /// How many of them are numeric.
    pub numeric_count: usize,
    /// The first numeric difference (it may come after the first `MAX_KEPT`).
    pub first_numeric: Option<Difference>,
    /// How many pairs of numbers were compared.
    pub numbers_compared: usize,
    /// The largest nonzero difference that the tolerance accepted, and where.
    pub largest_accepted: Option<(f64, String)>,
    /// The first divergence's step described in full in each trace (`[stage] description`).
    pub first_steps: (Option<String>, Option<String>),
}

/// How many differences a [`Comparison`] keeps.
pub const MAX_KEPT: usize = 1000;

impl Comparison {
    /// Whether the traces agree within the tolerance (header differences aside).
    pub fn is_equal(&self) -> bool {
        self.count == 0
    }

    /// The first divergence.
    pub fn first(&self) -> Option<&Difference> {
        self.differences.first()
    }

    /// How many distinct steps differ.
    pub fn differing_steps(&self) -> usize {
        let mut steps: Vec<(Option<usize>, Option<usize>)> = self
            .differences
            .iter()
            .filter(|d| d.step.is_some() || d.actual_step.is_some())
            .map(|d| (d.step, d.actual_step))
            .collect();
        steps.sort();
        steps.dedup();
        steps.len()
    }

    /// The report in words. `names` are the two files (or any labels).
    pub fn to_text(&self, expected: &Trace, actual: &Trace, names: [&str; 2]) -> String {
        let mut out = String::new();
        let head = |t: &Trace| {
            format!(
                "scene \"{}\", pixel ({}, {}), sample {}, raystep {}",
                t.scene, t.pixel[0], t.pixel[1], t.sample, t.raystep
            )
        };
        let _ = writeln!(out, "expected: {} ({})", names[0], head(expected));
        let _ = writeln!(out, "actual:   {} ({})", names[1], head(actual));
        if !self.header.is_empty() {
            out += "the headers differ (information, not a divergence):\n";
            for d in &self.header {
                let _ = writeln!(out, "  {}", d.message);
            }
        }
        let tol = describe_tolerance(&self.tolerance);
        match self.first() {
            None => {
                if self.tolerance == Tolerance::EXACT {
                    let _ = writeln!(
                        out,
                        "the traces are equal: {} numbers compared, all exactly equal",
                        self.numbers_compared
                    );
                } else {
                    let _ = write!(
                        out,
                        "the traces are equal within tolerance {tol}: {} numbers compared",
                        self.numbers_compared
                    );
                    match &self.largest_accepted {
                        Some((d, at)) => {
                            let _ = writeln!(out, ", the largest difference {} ({at})", small(*d));
                        }
                        None => out += ", all exactly equal\n",
                    }
                }
            }
            Some(first) => {
                let _ = writeln!(out, "first divergence: {}", first.message);
                if let Some(s) = &self.first_steps.0 {
                    let _ = writeln!(out, "  expected: {s}");
                }
                if let Some(s) = &self.first_steps.1 {
                    let _ = writeln!(out, "  actual:   {s}");
                }
                if let Some(n) = &self.first_numeric
                    && first.kind != DiffKind::Number
                {
                    let _ = writeln!(out, "first numeric divergence: {}", n.message);
                }
                let _ = writeln!(
                    out,
                    "the traces differ: {} difference{} ({} numeric) in {} step{}; tolerance {tol}",
                    self.count,
                    plural(self.count),
                    self.numeric_count,
                    self.differing_steps(),
                    plural(self.differing_steps()),
                );
            }
        }
        out
    }

    /// The machine-readable result.
    pub fn to_json(&self, expected: &Trace, actual: &Trace, names: [&str; 2]) -> Value {
        let head = |t: &Trace, file: &str| {
            json!({
                "file": file,
                "scene": t.scene,
                "scene_hash": t.scene_hash,
                "pixel": t.pixel,
                "sample": t.sample,
                "raystep": t.raystep,
                "version": t.version,
            })
        };
        json!({
            "equal": self.is_equal(),
            "tolerance": self.tolerance,
            "expected": head(expected, names[0]),
            "actual": head(actual, names[1]),
            "header_differences": self.header,
            "first_divergence": self.first(),
            "first_numeric_divergence": self.first_numeric,
            "differences": self.count,
            "numeric_differences": self.numeric_count,
            "differing_steps": self.differing_steps(),
            "numbers_compared": self.numbers_compared,
            "largest_accepted_difference": self.largest_accepted.as_ref().map(|(d, at)| json!({"difference": d, "at": at})),
            "all": self.differences,
        })
    }
}

/// Compares two traces.
pub fn compare(expected: &Trace, actual: &Trace, tolerance: Tolerance) -> Comparison {
    let ve = as_value(expected);
    let va = as_value(actual);
    let empty = Vec::new();
    let oe = ve.as_object().unwrap_or(&empty);
    let oa = va.as_object().unwrap_or(&empty);

    // The header, exactly, as information.
    let mut header = Walker::new(Tolerance::EXACT, &J::Null, &J::Null);
    let header_keys = [
        "version",
        "raystep",
        "scene",
        "scene_hash",
        "pixel",
        "sample",
        "settings",
    ];
    for key in header_keys {
        let loc = Loc::place("");
        header.values(&loc, key, get(oe, key), get(oa, key));
    }

    let mut w = Walker::new(tolerance, &ve["root"], &va["root"]);
    w.ray(
        &ve["root"],
        &va["root"],
        &mut vec![],
        &mut vec![],
        "primary ray".into(),
        None,
    );
    w.values(
        &Loc::place("the trace"),
        "color",
        &ve["color"],
        &va["color"],
    );
    w.values(&Loc::place("camera"), "", &ve["camera"], &va["camera"]);
    w.by_index(&ve["lights"], &va["lights"], "lights", "light");
    w.by_index(&ve["objects"], &va["objects"], "objects", "object");
    w.by_index(&ve["bvh"], &va["bvh"], "BVH outline", "node");
    let known = [
        "root",
        "color",
        "camera",
        "lights",
        "objects",
        "bvh",
        "version",
        "raystep",
        "scene",
        "scene_hash",
        "pixel",
        "sample",
        "settings",
    ];
    for key in union_keys(oe, oa) {
        if !known.contains(&key.as_str()) {
            w.values(&Loc::place("the trace"), &key, get(oe, &key), get(oa, &key));
        }
    }

    let first_steps = match w.diffs.first() {
        Some(d) => (
            d.step.and_then(|k| step_line(expected, k)),
            d.actual_step.and_then(|k| step_line(actual, k)),
        ),
        None => (None, None),
    };
    Comparison {
        tolerance,
        header: header.diffs,
        differences: w.diffs,
        count: w.count,
        numeric_count: w.numeric_count,
        first_numeric: w.first_numeric,
        numbers_compared: w.numbers,
        largest_accepted: w.largest,
        first_steps,
    }
}

fn step_line(t: &Trace, k: usize) -> Option<String> {
    let tl = t.timeline();
    let (r, s) = tl.get(k)?;
    Some(format!(
        "step {k}: [{}] {}",
        describe::stage_name(s.stage),
        describe::describe(&s.step, r.kind)
    ))
}

/// The trace as the JSON it saves as (so numbers read as their shortest f32 form).
fn as_value(t: &Trace) -> J {
    // Without serde_json's 128-level limit: a trace nests two levels a bounce (max_depth 64).
    crate::record::nesting::parse(&t.to_json()).expect("a trace's JSON parses")
}

fn get<'a>(o: &'a [(String, J)], key: &str) -> &'a J {
    o.iter().find(|(k, _)| k == key).map_or(&NULL, |(_, v)| v)
}

fn union_keys(a: &[(String, J)], b: &[(String, J)]) -> Vec<String> {
    let mut keys: Vec<String> = a.iter().map(|(k, _)| k.clone()).collect();
    keys.extend(
        b.iter()
            .map(|(k, _)| k)
            .filter(|k| !a.iter().any(|(ka, _)| ka == *k))
            .cloned(),
    );
    keys
}

fn plural(n: usize) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// A small positive number in two significant digits: `7e-6`, `1.4e-5`, `0`.
fn small(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    if !x.is_finite() {
        return fmt64(x, Style::Exact);
    }
    if (1e-3..1e5).contains(&x) {
        // Two significant digits as a plain decimal: 0.48, 3.1, 12.
        let decimals = (1 - x.log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.decimals$}");
        return if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').into()
        } else {
            s
        };
    }
    let s = format!("{x:.1e}");
    match s.split_once('e') {
        Some((m, e)) => {
            let m = m.trim_end_matches('0').trim_end_matches('.');
            format!("{m}e{e}")
        }
        None => s,
    }
}

/// A value in words: numbers as written, non-finite ones as ∞ / NaN, null as `none`.
fn show(v: &J) -> String {
    match v {
        J::Null => "none".into(),
        J::Str(s) => match special(s) {
            Some(x) => fmt64(x, Style::Exact),
            None => format!("\"{s}\""),
        },
        other => other.to_value().to_string(),
    }
}

/// The strings `crate::jsonf` writes for non-finite floats.
fn special(s: &str) -> Option<f64> {
    match s {
        "inf" => Some(f64::INFINITY),
        "-inf" => Some(f64::NEG_INFINITY),
        "nan" => Some(f64::NAN),
        _ => None,
    }
}

/// Keys whose strings are names, never numbers.
const NAME_KEYS: [&str; 7] = [
    "name",
    "blocker",
    "scene",
    "material",
    "raystep",
    "scene_hash",
    "kind",
];

fn float_of(v: &J, key: &str) -> Option<f64> {
    match v {
        J::Num(n) => n.as_f64(),
        J::Str(s) if !NAME_KEYS.contains(&key) => special(s),
        _ => None,
    }
}

fn is_integer(v: &J) -> bool {
    v.is_integer()
}

/// Where a difference is.
#[derive(Debug, Clone, Default)]
struct Loc {
    place: String,
    step: Option<usize>,
    actual_step: Option<usize>,
    stage: Option<String>,
    subject: Option<String>,
}

impl Loc {
    fn place(p: &str) -> Loc {
        Loc {
            place: p.into(),
            ..Loc::default()
        }
    }

    fn prefix(&self) -> String {
        let mut s = match (self.step, self.actual_step) {
            (Some(e), Some(a)) if e == a => format!("step {e} ("),
            (Some(e), Some(a)) => format!("step {e} (step {a} in the actual trace; "),
            (Some(e), None) => format!("step {e} of the expected trace ("),
            (None, Some(a)) => format!("step {a} of the actual trace ("),
            (None, None) => String::new(),
        };
        s += &self.place;
        if self.step.is_some() || self.actual_step.is_some() {
            if let Some(st) = &self.stage {
                let _ = write!(s, ", {st}");
            }
            s += ")";
        }
        if let Some(sub) = &self.subject {
            let _ = write!(s, ": {sub}");
        }
        s
    }
}

/// A field path as shown: `test.` dropped (`test.discriminant` → `discriminant`).
fn field_name(path: &str) -> String {
    path.strip_prefix("test.").unwrap_or(path).to_string()
}

fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.into()
    } else {
        format!("{path}.{key}")
    }
}

enum Op {
    Match(usize, usize),
    Gap(Range<usize>, Range<usize>),
}

/// Aligns two sequences of step keys: common prefix and suffix, then a longest common
/// subsequence of the middle (when it is small enough; otherwise the middle is one gap).
fn align(e: &[String], a: &[String]) -> Vec<Op> {
    let mut p = 0;
    while p < e.len() && p < a.len() && e[p] == a[p] {
        p += 1;
    }
    let mut s = 0;
    while s < e.len() - p && s < a.len() - p && e[e.len() - 1 - s] == a[a.len() - 1 - s] {
        s += 1;
    }
    let mut ops: Vec<Op> = (0..p).map(|i| Op::Match(i, i)).collect();
    let (me, ma) = (&e[p..e.len() - s], &a[p..a.len() - s]);
    let (n, m) = (me.len(), ma.len());
    if n > 0 || m > 0 {
        if n.saturating_mul(m) <= 4_000_000 {
            // dp[i][j] = LCS length of me[i..] and ma[j..].
            let w = m + 1;
            let mut dp = vec![0u32; (n + 1) * w];
            for i in (0..n).rev() {
                for j in (0..m).rev() {
                    dp[i * w + j] = if me[i] == ma[j] {
                        dp[(i + 1) * w + j + 1] + 1
                    } else {
                        dp[(i + 1) * w + j].max(dp[i * w + j + 1])
                    };
                }
            }
            let (mut i, mut j) = (0, 0);
            let (mut gi, mut gj) = (0, 0);
            let flush = |ops: &mut Vec<Op>, gi: usize, i: usize, gj: usize, j: usize| {
                if gi < i || gj < j {
                    ops.push(Op::Gap(p + gi..p + i, p + gj..p + j));
                }
            };
            while i < n && j < m {
                if me[i] == ma[j] && dp[i * w + j] == dp[(i + 1) * w + j + 1] + 1 {
                    flush(&mut ops, gi, i, gj, j);
                    ops.push(Op::Match(p + i, p + j));
                    i += 1;
                    j += 1;
                    (gi, gj) = (i, j);
                } else if dp[(i + 1) * w + j] >= dp[i * w + j + 1] {
                    i += 1;
                } else {
                    j += 1;
                }
            }
            flush(&mut ops, gi, n, gj, m);
        } else {
            ops.push(Op::Gap(p..p + n, p..p + m));
        }
    }
    ops.extend((0..s).map(|k| Op::Match(e.len() - s + k, a.len() - s + k)));
    ops
}

fn str_of<'a>(v: &'a J, key: &str) -> &'a str {
    v.get(key).and_then(J::as_str).unwrap_or("?")
}

/// The alignment key of a step: its type, and for a spawn the child ray's kind.
fn step_key(step: &J, ray: &J) -> String {
    let ty = str_of(step, "type");
    if ty == "spawn" {
        let kind = child_of(step, ray).map_or("?", |c| str_of(c, "kind"));
        format!("spawn:{kind}")
    } else {
        ty.into()
    }
}

fn child_index(step: &J) -> Option<usize> {
    step.get("child")?.as_u64().map(|c| c as usize)
}

fn child_of<'a>(step: &J, ray: &'a J) -> Option<&'a J> {
    ray.get("children")?.as_array()?.get(child_index(step)?)
}

/// The step as a noun: `sphere "mirror"`, `light "key"`, `BVH node 3`, `surface`.
fn subject(step: &J) -> String {
    let ty = str_of(step, "type");
    let name = str_of(step, "name");
    match ty {
        "sphere" | "plane" | "triangle" => format!("{ty} \"{name}\""),
        "accept" => format!("accept \"{name}\""),
        "light" => format!("light \"{name}\""),
        "shadow-ray" => format!("shadow ray towards light \"{name}\""),
        "node" => format!("BVH node {}", step.get("node").unwrap_or(&J::Null)),
        "color" => "colour".into(),
        other => other.replace('-', " "),
    }
}

/// The light a shadow ray spawned at `steps[i]` goes towards (the shadow-ray step before it).
fn light_before(steps: &[J], i: usize) -> Option<&str> {
    steps[..i]
        .iter()
        .rev()
        .find(|s| str_of(s, "type") == "shadow-ray")
        .and_then(|s| s.get("name")?.as_str())
}

/// The step as a phrase for "the expected trace has … here".
fn phrase(steps: &[J], i: usize, ray: &J) -> String {
    let step = &steps[i];
    let name = str_of(step, "name");
    match str_of(step, "type") {
        "camera" => "the camera step".into(),
        "node" => format!(
            "a visit to BVH node {}",
            step.get("node").unwrap_or(&J::Null)
        ),
        ty @ ("sphere" | "plane" | "triangle") => format!("a test against {ty} \"{name}\""),
        "accept" => format!("a closest hit so far on \"{name}\""),
        "miss" => "a miss (the background colour)".into(),
        "surface" => "a surface interaction".into(),
        "shadow-ray" => format!("a shadow ray towards light \"{name}\""),
        "light" => format!("lighting from light \"{name}\""),
        "reflect" => "a reflection".into(),
        "refract" => {
            if step.get("total_internal_reflection") == Some(&J::Bool(true)) {
                "a refraction (total internal reflection)".into()
            } else {
                "a refraction".into()
            }
        }
        "schlick" => "a Schlick blend".into(),
        "depth-limit" => "the recursion limit".into(),
        "color" => "the final colour".into(),
        "spawn" => match child_of(step, ray).map(|c| str_of(c, "kind")) {
            Some("shadow") => match light_before(steps, i) {
                Some(l) => format!("a shadow ray towards light \"{l}\" (traced)"),
                None => "a shadow ray (traced)".into(),
            },
            Some(kind) => format!("a {kind} ray (traced)"),
            None => "a spawned ray".into(),
        },
        other => format!("a \"{other}\" step"),
    }
}

/// `X here` or `X here (and 2 more steps: Y, Z)`.
fn phrases(steps: &[J], r: &Range<usize>, ray: &J) -> String {
    let mut s = phrase(steps, r.start, ray) + " here";
    let more = r.len() - 1;
    if more > 0 {
        let rest: Vec<String> = (r.start + 1..r.end)
            .take(4)
            .map(|i| phrase(steps, i, ray))
            .collect();
        let _ = write!(
            s,
            " (and {more} more step{}: {}{})",
            plural(more),
            rest.join(", "),
            if more > 4 { ", …" } else { "" }
        );
    }
    s
}

/// The label of child `idx`: `shadow ray 0` (shadow rays are numbered among their siblings),
/// `reflection ray` (numbered only when there are several).
fn child_label(ray: &J, idx: usize) -> String {
    let empty = vec![];
    let children = ray.get("children").and_then(J::as_array).unwrap_or(&empty);
    let kind = children.get(idx).map_or("?", |c| str_of(c, "kind"));
    let same = |c: &&J| str_of(c, "kind") == kind;
    let ordinal = children[..idx.min(children.len())]
        .iter()
        .filter(same)
        .count();
    let total = children.iter().filter(same).count();
    if kind == "shadow" || total > 1 {
        format!("{kind} ray {ordinal}")
    } else {
        format!("{kind} ray")
    }
}

/// Timeline indices of every ray's steps, keyed by the ray's path of child indices (mirrors
/// [`Trace::timeline`]).
fn timeline_map(root: &J) -> HashMap<Vec<usize>, Vec<usize>> {
    fn walk(
        r: &J,
        path: &mut Vec<usize>,
        next: &mut usize,
        out: &mut HashMap<Vec<usize>, Vec<usize>>,
    ) {
        let mut idx = vec![];
        for s in r.get("steps").and_then(J::as_array).into_iter().flatten() {
            idx.push(*next);
            *next += 1;
            if str_of(s, "type") == "spawn"
                && let Some(c) = child_index(s)
                && let Some(child) = child_of(s, r)
            {
                path.push(c);
                walk(child, path, next, out);
                path.pop();
            }
        }
        out.insert(path.clone(), idx);
    }
    let mut out = HashMap::new();
    walk(root, &mut vec![], &mut 0, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn keys(s: &str) -> Vec<String> {
        s.chars().map(String::from).collect()
    }

    fn ops(e: &str, a: &str) -> String {
        align(&keys(e), &keys(a))
            .into_iter()
            .map(|o| match o {
                Op::Match(i, j) => format!("={i}{j}"),
                Op::Gap(r, q) => format!("-{}{}+{}{}", r.start, r.end, q.start, q.end),
            })
            .collect::<Vec<_>>()
            .join(" ")
    }

    #[test]
    fn alignment() {
        assert_eq!(ops("abc", "abc"), "=00 =11 =22");
        assert_eq!(ops("abxyc", "abc"), "=00 =11 -24+22 =42");
        assert_eq!(ops("abc", "abyc"), "=00 =11 -22+23 =23");
        assert_eq!(ops("axc", "ayc"), "=00 -12+12 =22");
        assert_eq!(ops("", "ab"), "-00+02");
        assert_eq!(ops("axbyc", "abc"), "=00 -12+11 =21 -34+22 =42");
    }

    #[test]
    fn tolerance_rule() {
        let t = Tolerance::relative_to_larger(1e-6, 1e-6);
        assert!(t.allows(1.0, 1.0 + 1e-6));
        assert!(!t.allows(1.0, 1.0 + 3e-6));
        assert!(t.allows(1e6, 1e6 + 0.5)); // relative
        assert!(t.allows(f64::NAN, f64::NAN));
        assert!(!t.allows(f64::NAN, 1.0));
        assert!(t.allows(f64::INFINITY, f64::INFINITY));
        assert!(!t.allows(f64::INFINITY, f64::NEG_INFINITY));
        assert!(!Tolerance::relative_to_larger(1e30, 1e30).allows(f64::INFINITY, 1.0));
        assert!(Tolerance::EXACT.allows(0.0, -0.0));
        assert!(!Tolerance::EXACT.allows(1.0, 1.0 + f64::EPSILON));
    }

    #[test]
    fn small_numbers() {
        assert_eq!(small(7e-6), "7e-6");
        assert_eq!(small(1.36e-5), "1.4e-5");
        assert_eq!(small(0.0), "0");
        assert_eq!(small(2.0), "2");
        assert_eq!(small(0.483), "0.48");
        assert_eq!(small(12.3), "12");
        assert_eq!(small(2e7), "2e7");
    }
}
