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
//! Numbers a and b (floats) agree when |a − b| ≤ max(abs, rel·max(|a|, |b|)); NaN equals NaN and
//! ±∞ equals only the same infinity. Integers (ids, indices, counts) and everything else (names,
//! methods, decisions such as hit or miss, which root, blocked, total internal reflection) must
//! be equal. The header (format and raystep versions, scene name and hash, pixel, sample,
//! settings) is compared exactly but reported as information only: comparing two settings' traces
//! is often the point.

use super::describe;
use super::record::Trace;
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};
use std::collections::HashMap;
use std::fmt::Write;
use std::ops::Range;

/// A JSON tree that keeps the fields in the order they were written (the struct's declaration
/// order), so that within a step the first differing field is the first in the record
/// (serde_json's `Value` sorts keys).
#[derive(Debug, Clone, PartialEq)]
enum J {
    Null,
    Bool(bool),
    Num(serde_json::Number),
    Str(String),
    Arr(Vec<J>),
    Obj(Vec<(String, J)>),
}

static NULL: J = J::Null;

impl J {
    fn get(&self, key: &str) -> Option<&J> {
        match self {
            J::Obj(m) => m.iter().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }
    fn as_str(&self) -> Option<&str> {
        match self {
            J::Str(s) => Some(s),
            _ => None,
        }
    }
    fn as_array(&self) -> Option<&Vec<J>> {
        match self {
            J::Arr(a) => Some(a),
            _ => None,
        }
    }
    fn as_object(&self) -> Option<&Vec<(String, J)>> {
        match self {
            J::Obj(m) => Some(m),
            _ => None,
        }
    }
    fn as_u64(&self) -> Option<u64> {
        match self {
            J::Num(n) => n.as_u64(),
            _ => None,
        }
    }
    fn is_null(&self) -> bool {
        matches!(self, J::Null)
    }
    fn is_integer(&self) -> bool {
        matches!(self, J::Num(n) if n.is_u64() || n.is_i64())
    }
    fn to_value(&self) -> Value {
        match self {
            J::Null => Value::Null,
            J::Bool(b) => Value::Bool(*b),
            J::Num(n) => Value::Number(n.clone()),
            J::Str(s) => Value::String(s.clone()),
            J::Arr(a) => Value::Array(a.iter().map(J::to_value).collect()),
            J::Obj(m) => Value::Object(m.iter().map(|(k, v)| (k.clone(), v.to_value())).collect()),
        }
    }
}

impl std::fmt::Display for J {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "{}", self.to_value())
    }
}

impl std::ops::Index<&str> for J {
    type Output = J;
    fn index(&self, key: &str) -> &J {
        self.get(key).unwrap_or(&NULL)
    }
}

impl<'de> Deserialize<'de> for J {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<J, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = J;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("JSON")
            }
            fn visit_unit<E>(self) -> Result<J, E> {
                Ok(J::Null)
            }
            fn visit_none<E>(self) -> Result<J, E> {
                Ok(J::Null)
            }
            fn visit_bool<E>(self, b: bool) -> Result<J, E> {
                Ok(J::Bool(b))
            }
            fn visit_u64<E>(self, x: u64) -> Result<J, E> {
                Ok(J::Num(x.into()))
            }
            fn visit_i64<E>(self, x: i64) -> Result<J, E> {
                Ok(J::Num(x.into()))
            }
            fn visit_f64<E>(self, x: f64) -> Result<J, E> {
                Ok(serde_json::Number::from_f64(x).map_or(J::Null, J::Num))
            }
            fn visit_str<E>(self, s: &str) -> Result<J, E> {
                Ok(J::Str(s.into()))
            }
            fn visit_string<E>(self, s: String) -> Result<J, E> {
                Ok(J::Str(s))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut a: A) -> Result<J, A::Error> {
                let mut v = vec![];
                while let Some(x) = a.next_element()? {
                    v.push(x);
                }
                Ok(J::Arr(v))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut a: A) -> Result<J, A::Error> {
                let mut m = vec![];
                while let Some((k, v)) = a.next_entry::<String, J>()? {
                    m.push((k, v));
                }
                Ok(J::Obj(m))
            }
        }
        d.deserialize_any(V)
    }
}

/// When two numbers are equal enough.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Tolerance {
    /// Absolute tolerance.
    pub abs: f64,
    /// Relative tolerance (a fraction of the larger magnitude).
    pub rel: f64,
}

impl Tolerance {
    /// Exact comparison.
    pub const EXACT: Tolerance = Tolerance { abs: 0.0, rel: 0.0 };

    /// One value used as both the absolute and the relative tolerance (`--tolerance T`).
    pub fn uniform(t: f64) -> Tolerance {
        Tolerance { abs: t, rel: t }
    }

    /// Whether a and b agree: |a − b| ≤ max(abs, rel·max(|a|, |b|)); NaN equals NaN; ±∞ equals
    /// only the same infinity.
    pub fn allows(&self, a: f64, b: f64) -> bool {
        if a.is_nan() || b.is_nan() {
            return a.is_nan() && b.is_nan();
        }
        if a.is_infinite() || b.is_infinite() {
            return a == b;
        }
        (a - b).abs() <= self.abs.max(self.rel * a.abs().max(b.abs()))
    }

    /// `0`, `1e-6`, or `abs 1e-6, rel 1e-4`.
    pub fn describe(&self) -> String {
        if self.abs == self.rel {
            small(self.abs)
        } else {
            format!("abs {}, rel {}", small(self.abs), small(self.rel))
        }
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
    /// The tolerance used.
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
        let tol = self.tolerance.describe();
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
    let (_, s) = tl.get(k)?;
    Some(format!(
        "step {k}: [{}] {}",
        describe::stage_name(s.stage),
        describe::describe(&s.step)
    ))
}

/// The trace as the JSON it saves as (so numbers read as their shortest f32 form).
fn as_value(t: &Trace) -> J {
    serde_json::from_str(&t.to_json()).expect("a trace's JSON parses")
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
        return show_f64(x);
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

fn show_f64(x: f64) -> String {
    if x.is_nan() {
        "NaN".into()
    } else if x == f64::INFINITY {
        "∞".into()
    } else if x == f64::NEG_INFINITY {
        "-∞".into()
    } else {
        format!("{x}")
    }
}

/// A value in words: numbers as written, non-finite ones as ∞ / NaN, null as `none`.
fn show(v: &J) -> String {
    match v {
        J::Null => "none".into(),
        J::Str(s) => match special(s) {
            Some(x) => show_f64(x),
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

struct Walker {
    tol: Tolerance,
    diffs: Vec<Difference>,
    count: usize,
    numeric_count: usize,
    first_numeric: Option<Difference>,
    numbers: usize,
    largest: Option<(f64, String)>,
    tl_e: HashMap<Vec<usize>, Vec<usize>>,
    tl_a: HashMap<Vec<usize>, Vec<usize>>,
}

impl Walker {
    fn new(tol: Tolerance, root_e: &J, root_a: &J) -> Walker {
        Walker {
            tol,
            diffs: vec![],
            count: 0,
            numeric_count: 0,
            first_numeric: None,
            numbers: 0,
            largest: None,
            tl_e: timeline_map(root_e),
            tl_a: timeline_map(root_a),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn push(
        &mut self,
        loc: &Loc,
        kind: DiffKind,
        field: Option<&str>,
        e: &J,
        a: &J,
        difference: Option<f64>,
        body: String,
    ) {
        let mut message = loc.prefix();
        if !message.is_empty() {
            message += ": ";
        }
        message += &body;
        let d = Difference {
            kind,
            step: loc.step,
            actual_step: loc.actual_step,
            place: loc.place.clone(),
            stage: loc.stage.clone(),
            subject: loc.subject.clone(),
            field: field.map(field_name),
            expected: e.to_value(),
            actual: a.to_value(),
            difference,
            message,
        };
        self.count += 1;
        if kind == DiffKind::Number {
            self.numeric_count += 1;
            if self.first_numeric.is_none() {
                self.first_numeric = Some(d.clone());
            }
        }
        if self.diffs.len() < MAX_KEPT {
            self.diffs.push(d);
        }
    }

    /// Compares two JSON values field by field.
    fn values(&mut self, loc: &Loc, path: &str, e: &J, a: &J) {
        let key = path.rsplit(['.', '[']).next().unwrap_or(path);
        match (e, a) {
            (J::Obj(me), J::Obj(ma)) => {
                for k in union_keys(me, ma) {
                    self.values(loc, &join(path, &k), get(me, &k), get(ma, &k));
                }
            }
            (J::Arr(ve), J::Arr(va)) if ve.len() == va.len() => {
                for (i, (x, y)) in ve.iter().zip(va).enumerate() {
                    self.values(loc, &format!("{path}[{i}]"), x, y);
                }
            }
            (J::Arr(ve), J::Arr(va)) => {
                let body = format!("{}: {} entries vs {}", field_name(path), ve.len(), va.len());
                self.push(loc, DiffKind::Value, Some(path), e, a, None, body);
            }
            _ if is_integer(e) && is_integer(a) => {
                if e != a {
                    let body = format!("{} {} vs {}", field_name(path), show(e), show(a));
                    self.push(loc, DiffKind::Value, Some(path), e, a, None, body);
                }
            }
            _ => match (float_of(e, key), float_of(a, key)) {
                (Some(x), Some(y)) => self.number(loc, path, e, a, x, y),
                _ => {
                    if e != a {
                        let body = format!("{} {} vs {}", field_name(path), show(e), show(a));
                        self.push(loc, DiffKind::Value, Some(path), e, a, None, body);
                    }
                }
            },
        }
    }

    fn number(&mut self, loc: &Loc, path: &str, e: &J, a: &J, x: f64, y: f64) {
        self.numbers += 1;
        let d = (x - y).abs();
        if self.tol.allows(x, y) {
            if d > 0.0 && self.largest.as_ref().is_none_or(|(m, _)| d > *m) {
                let at = format!("{}: {}", loc.prefix(), field_name(path));
                self.largest = Some((d, at));
            }
            return;
        }
        let finite = x.is_finite() && y.is_finite();
        let mut body = format!("{} {} vs {}", field_name(path), show(e), show(a));
        if finite {
            let _ = write!(
                body,
                " (differs by {}, tolerance {})",
                small(d),
                self.tol.describe()
            );
        }
        let diff = finite.then_some(d);
        self.push(loc, DiffKind::Number, Some(path), e, a, diff, body);
    }

    /// Compares two arrays entry by entry (lights, objects, the BVH outline); entries only one
    /// trace has are reported as missing or extra.
    fn by_index(&mut self, e: &J, a: &J, place: &str, what: &str) {
        let empty = vec![];
        let ve = e.as_array().unwrap_or(&empty);
        let va = a.as_array().unwrap_or(&empty);
        let label = |v: &J, i: usize| match v.get("name").and_then(J::as_str) {
            Some(n) => format!("{what} \"{n}\""),
            None => format!("{what} {i}"),
        };
        for i in 0..ve.len().max(va.len()) {
            match (ve.get(i), va.get(i)) {
                (Some(x), Some(y)) => {
                    let loc = Loc {
                        subject: Some(label(x, i)),
                        ..Loc::place(place)
                    };
                    self.values(&loc, "", x, y);
                }
                (Some(x), None) => {
                    let body = format!(
                        "the expected trace has {} here; the actual trace has none",
                        label(x, i)
                    );
                    self.push(
                        &Loc::place(place),
                        DiffKind::Missing,
                        None,
                        x,
                        &J::Null,
                        None,
                        body,
                    );
                }
                (None, Some(y)) => {
                    let body = format!(
                        "the actual trace has {} here; the expected trace has none",
                        label(y, i)
                    );
                    self.push(
                        &Loc::place(place),
                        DiffKind::Extra,
                        None,
                        &J::Null,
                        y,
                        None,
                        body,
                    );
                }
                (None, None) => {}
            }
        }
    }

    /// Compares two rays: their own fields (at `start`, the spawn step, if any), their steps in
    /// order with the children where they were spawned, then their result.
    fn ray(
        &mut self,
        e: &J,
        a: &J,
        path_e: &mut Vec<usize>,
        path_a: &mut Vec<usize>,
        label: String,
        start: Option<Loc>,
    ) {
        let empty_map = Vec::new();
        let oe = e.as_object().unwrap_or(&empty_map);
        let oa = a.as_object().unwrap_or(&empty_map);
        let start = start.unwrap_or_else(|| Loc::place(&label));
        let start = Loc {
            subject: Some(format!("the {label}")),
            ..start
        };
        let later = ["steps", "children", "hit", "weight", "color"];
        for k in union_keys(oe, oa) {
            if later.contains(&k.as_str()) {
                continue;
            }
            // t_max: null is ∞.
            let fix = |v: &J| {
                if k == "t_max" && v.is_null() {
                    J::Str("inf".into())
                } else {
                    v.clone()
                }
            };
            self.values(&start, &k, &fix(get(oe, &k)), &fix(get(oa, &k)));
        }

        let empty = vec![];
        let se = e.get("steps").and_then(J::as_array).unwrap_or(&empty);
        let sa = a.get("steps").and_then(J::as_array).unwrap_or(&empty);
        let ke: Vec<String> = se.iter().map(|s| step_key(s, e)).collect();
        let ka: Vec<String> = sa.iter().map(|s| step_key(s, a)).collect();
        let tl_e = self
            .tl_e
            .get(path_e.as_slice())
            .cloned()
            .unwrap_or_default();
        let tl_a = self
            .tl_a
            .get(path_a.as_slice())
            .cloned()
            .unwrap_or_default();
        let mut spawned_e = vec![];
        let mut spawned_a = vec![];
        for op in align(&ke, &ka) {
            match op {
                Op::Match(i, j) => {
                    let (x, y) = (&se[i], &sa[j]);
                    let loc = Loc {
                        place: label.clone(),
                        step: tl_e.get(i).copied(),
                        actual_step: tl_a.get(j).copied(),
                        stage: x.get("stage").and_then(J::as_str).map(String::from),
                        subject: Some(subject(x)),
                    };
                    let (mx, my) = match (x.as_object(), y.as_object()) {
                        (Some(mx), Some(my)) => (mx, my),
                        _ => {
                            self.values(&loc, "", x, y);
                            continue;
                        }
                    };
                    let is_spawn = str_of(x, "type") == "spawn";
                    for k in union_keys(mx, my) {
                        if k == "type" || (is_spawn && k == "child") {
                            continue;
                        }
                        self.values(&loc, &k, get(mx, &k), get(my, &k));
                    }
                    if is_spawn
                        && let (Some(ci), Some(cj)) = (child_index(x), child_index(y))
                        && let (Some(cx), Some(cy)) = (child_of(x, e), child_of(y, a))
                    {
                        spawned_e.push(ci);
                        spawned_a.push(cj);
                        path_e.push(ci);
                        path_a.push(cj);
                        let child = format!("{label} → {}", child_label(e, ci));
                        let spawn_loc = Loc {
                            place: child.clone(),
                            ..loc
                        };
                        self.ray(cx, cy, path_e, path_a, child, Some(spawn_loc));
                        path_e.pop();
                        path_a.pop();
                    }
                }
                Op::Gap(re, ra) => {
                    // The gap's own spawned rays are part of it, not loose children.
                    spawned_e.extend(se[re.clone()].iter().filter_map(child_index));
                    spawned_a.extend(sa[ra.clone()].iter().filter_map(child_index));
                    let first = if re.is_empty() {
                        sa.get(ra.start)
                    } else {
                        se.get(re.start)
                    };
                    let loc = Loc {
                        place: label.clone(),
                        step: tl_e.get(re.start).copied(),
                        actual_step: tl_a.get(ra.start).copied(),
                        stage: first
                            .and_then(|f| f.get("stage"))
                            .and_then(J::as_str)
                            .map(String::from),
                        subject: None,
                    };
                    let ev = J::Arr(se[re.clone()].to_vec());
                    let av = J::Arr(sa[ra.clone()].to_vec());
                    let (kind, body) = match (re.is_empty(), ra.is_empty()) {
                        (false, true) => (
                            DiffKind::Missing,
                            format!(
                                "the expected trace has {}; the actual trace has none",
                                phrases(se, &re, e)
                            ),
                        ),
                        (true, false) => (
                            DiffKind::Extra,
                            format!(
                                "the actual trace has {}; the expected trace has none",
                                phrases(sa, &ra, a)
                            ),
                        ),
                        _ => (
                            DiffKind::Replaced,
                            format!(
                                "the expected trace has {}; the actual trace has {} instead",
                                phrases(se, &re, e),
                                phrases(sa, &ra, a)
                            ),
                        ),
                    };
                    self.push(&loc, kind, None, &ev, &av, None, body);
                }
            }
        }

        // Children no step spawned (not in the timeline): compared in order.
        let ce = e.get("children").and_then(J::as_array).unwrap_or(&empty);
        let ca = a.get("children").and_then(J::as_array).unwrap_or(&empty);
        let loose_e: Vec<usize> = (0..ce.len()).filter(|i| !spawned_e.contains(i)).collect();
        let loose_a: Vec<usize> = (0..ca.len()).filter(|i| !spawned_a.contains(i)).collect();
        for k in 0..loose_e.len().max(loose_a.len()) {
            match (loose_e.get(k), loose_a.get(k)) {
                (Some(&i), Some(&j)) => {
                    path_e.push(i);
                    path_a.push(j);
                    let child = format!("{label} → {} (not spawned by a step)", child_label(e, i));
                    self.ray(&ce[i], &ca[j], path_e, path_a, child, None);
                    path_e.pop();
                    path_a.pop();
                }
                (Some(&i), None) => {
                    let body = format!(
                        "the expected trace has a {} that no step spawned; the actual trace has none",
                        child_label(e, i)
                    );
                    let loc = Loc::place(&label);
                    self.push(&loc, DiffKind::Missing, None, &ce[i], &J::Null, None, body);
                }
                (None, Some(&j)) => {
                    let body = format!(
                        "the actual trace has a {} that no step spawned; the expected trace has none",
                        child_label(a, j)
                    );
                    let loc = Loc::place(&label);
                    self.push(&loc, DiffKind::Extra, None, &J::Null, &ca[j], None, body);
                }
                (None, None) => {}
            }
        }

        // The result.
        let end = Loc {
            subject: Some("result".into()),
            ..Loc::place(&label)
        };
        let (he, ha) = (get(oe, "hit"), get(oa, "hit"));
        if he.is_null() != ha.is_null() {
            let shadow = str_of(e, "kind") == "shadow";
            let words = |h: &J| match (h.is_null(), shadow) {
                (true, true) => "nothing in the way".to_string(),
                (true, false) => "hits nothing".to_string(),
                (false, true) => format!(
                    "blocked by \"{}\" at t = {}",
                    str_of(h, "name"),
                    show(h.get("t").unwrap_or(&J::Null))
                ),
                (false, false) => format!(
                    "hits \"{}\" at t = {}",
                    str_of(h, "name"),
                    show(h.get("t").unwrap_or(&J::Null))
                ),
            };
            let body = format!(
                "the expected ray {}; the actual ray {}",
                words(he),
                words(ha)
            );
            self.push(&end, DiffKind::Value, Some("hit"), he, ha, None, body);
        } else {
            self.values(&end, "hit", he, ha);
        }
        self.values(&end, "weight", get(oe, "weight"), get(oa, "weight"));
        self.values(&end, "color", get(oe, "color"), get(oa, "color"));
    }
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
        let t = Tolerance::uniform(1e-6);
        assert!(t.allows(1.0, 1.0 + 1e-6));
        assert!(!t.allows(1.0, 1.0 + 3e-6));
        assert!(t.allows(1e6, 1e6 + 0.5)); // relative
        assert!(t.allows(f64::NAN, f64::NAN));
        assert!(!t.allows(f64::NAN, 1.0));
        assert!(t.allows(f64::INFINITY, f64::INFINITY));
        assert!(!t.allows(f64::INFINITY, f64::NEG_INFINITY));
        assert!(!Tolerance::uniform(1e30).allows(f64::INFINITY, 1.0));
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
