//! Reading an exercise sheet: TOML with located errors, validated into [`ExerciseSheet`].

use super::{DEFAULT_TOLERANCE, Feedback, Quantity, RaySel};
use crate::record::Tolerance;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;

/// A sheet that could not be read: where (file, line, column, question and field) and why.
pub type SheetError = crate::scene::LocatedError;

/// Where a question's scene comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneSource {
    /// A scene file (resolved against the sheet's directory).
    File(PathBuf),
    /// Inline scene TOML, with `{placeholders}` filled from the variant.
    Inline(String),
}

/// How a pixel coordinate is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coord {
    /// Always this value.
    Fixed(u32),
    /// Uniformly from this inclusive range, per student.
    Range(u32, u32),
}

/// A value a parameter can take.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamValue {
    /// An integer.
    Int(i64),
    /// A number (already rounded to the parameter's decimals).
    Float(f64),
    /// A string (e.g. an object name).
    Str(String),
}

impl std::fmt::Display for ParamValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ParamValue::Int(i) => write!(f, "{i}"),
            // `{}` on f64 prints the shortest text that reads back to the same number, and a
            // number rounded to a few decimals prints with at most those decimals.
            ParamValue::Float(x) => write!(f, "{x}"),
            ParamValue::Str(s) => f.write_str(s),
        }
    }
}

/// A parameter of a question, drawn per student.
#[derive(Debug, Clone, PartialEq)]
pub enum Param {
    /// An integer in an inclusive range (`[lo, hi]` with integer bounds).
    Int(i64, i64),
    /// A number in `[lo, hi]`, rounded to `decimals` places (`[lo, hi]` with a float bound, or
    /// `{ range = [lo, hi], decimals = 3 }`).
    Float {
        /// Lower bound.
        lo: f64,
        /// Upper bound.
        hi: f64,
        /// Decimal places kept.
        decimals: u32,
    },
    /// One of a list (`{ one_of = [...] }`).
    OneOf(Vec<ParamValue>),
}

/// One question of a sheet.
#[derive(Debug, Clone, PartialEq)]
pub struct Question {
    /// The id (a CSV column and an answers-file key).
    pub id: String,
    /// The text, with `{placeholders}`.
    pub text: String,
    /// The scene.
    pub scene: SceneSource,
    /// The pixel's x and y.
    pub pixel: [Coord; 2],
    /// What is asked.
    pub quantity: Quantity,
    /// The object the quantity refers to (`discriminant`, `near_root`, `far_root`; optional for
    /// `triangle_u` / `triangle_v`).
    pub object: Option<String>,
    /// Which ray of the trace.
    pub ray: RaySel,
    /// The light (for `shadow_blocked`).
    pub light: u32,
    /// How close an answer must be: the sheet's `tolerance`, always the
    /// [`within_either`](Tolerance::within_either) rule.
    pub tolerance: Tolerance,
    /// Parameters, in name order.
    pub params: Vec<(String, Param)>,
    /// Hints, revealed one at a time.
    pub hints: Vec<String>,
    /// Points for a right answer.
    pub points: f64,
    /// Questions of one group share their variant: the same parameter names and pixel ranges
    /// draw the same values (the group name salts the draw instead of the question id).
    pub group: Option<String>,
    /// What the question's pixel must show (`require`): the variant generator draws only pixels
    /// whose trace satisfies it.
    pub require: Option<super::Premise>,
    /// Classic mistakes the question must tell apart from the right answer (`mistakes`): only
    /// pixels where each one's answer is at least [`super::mistakes::MIN_APART`] away are drawn.
    pub mistakes: Vec<super::Mistake>,
    /// 1-based line of the question's `[[question]]` header.
    pub line: usize,
}

/// A whole exercise sheet: questions whose answers a student types, checked against the tracer
/// (`raystep exercise`). Not to be confused with [`crate::student::TracerSheet`], which grades a
/// student's own tracer.
#[derive(Debug, Clone, PartialEq)]
pub struct ExerciseSheet {
    /// The file it was read from (for messages).
    pub file: String,
    /// The sheet's id: salts every student's variants (the `id` key, else the file stem).
    pub id: String,
    /// Display title.
    pub title: String,
    /// The questions in order.
    pub questions: Vec<Question>,
    /// What a wrong answer is told (the `feedback` key).
    pub feedback: Feedback,
    /// Whether `raystep exercise` prints, beside each question, the `raystep trace` command that
    /// shows its numbers (the `trace_command` key, default true; false for a graded quiz, where
    /// that command would print the answer).
    pub trace_command: bool,
    /// The pixels already drawn for questions with premises (drawing one traces the scene).
    pub(crate) drawn: super::DrawnPixels,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SheetFile {
    title: Option<String>,
    id: Option<String>,
    feedback: Option<Spanned<toml::Value>>,
    trace_command: Option<bool>,
    #[serde(default)]
    question: Vec<Spanned<QuestionDef>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct QuestionDef {
    id: Spanned<String>,
    text: String,
    scene: Option<Spanned<String>>,
    scene_toml: Option<Spanned<String>>,
    pixel: Spanned<toml::Value>,
    quantity: Spanned<Quantity>,
    object: Option<Spanned<String>>,
    #[serde(default)]
    ray: RaySel,
    light: Option<Spanned<i64>>,
    tolerance: Option<Spanned<ToleranceDef>>,
    #[serde(default)]
    params: BTreeMap<String, Spanned<toml::Value>>,
    #[serde(default)]
    hints: Vec<String>,
    points: Option<Spanned<f64>>,
    group: Option<String>,
    require: Option<Spanned<RequireDef>>,
    #[serde(default)]
    mistakes: Vec<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RequireDef {
    #[serde(default)]
    path: Vec<String>,
    sampled_light: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ToleranceDef {
    abs: Option<f64>,
    rel: Option<f64>,
}

/// Names a CSV file and an answers file can't use as question ids.
const RESERVED: [&str; 4] = ["student", "score", "out_of", "notes"];

/// Reads an exercise sheet file.
pub fn load_exercise_sheet(path: &Path) -> Result<ExerciseSheet, SheetError> {
    let file = path.display().to_string();
    let text =
        crate::io::read_text(path, crate::io::limits::SHEET, "exercise sheet").map_err(|e| {
            SheetError {
                file: file.clone(),
                line: None,
                column: None,
                field: None,
                message: format!("cannot read the exercise sheet: {e}"),
            }
        })?;
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "sheet".into());
    parse_exercise_sheet(&text, &file, path.parent(), &stem)
}

/// Parses a sheet from TOML text. `file` names it in errors, `base` is where scene paths start
/// from, `default_id` is the sheet's id when it has no `id` key.
pub fn parse_exercise_sheet(
    text: &str,
    file: &str,
    base: Option<&Path>,
    default_id: &str,
) -> Result<ExerciseSheet, SheetError> {
    let ctx = Ctx { text, file };
    let parsed: SheetFile = toml::from_str(text).map_err(|e| {
        let pos = e.span().map(|s| s.start);
        let (line, column) = pos.map(|p| ctx.line_col(p)).unzip();
        SheetError {
            file: file.into(),
            line,
            column,
            field: pos.and_then(|p| ctx.describe(p)),
            message: e.message().trim().to_string(),
        }
    })?;
    let id = parsed.id.unwrap_or_else(|| default_id.to_string());
    let title = parsed.title.unwrap_or_else(|| id.clone());
    let feedback = match &parsed.feedback {
        None => Feedback::default(),
        Some(f) => parse_feedback(f.get_ref())
            .map_err(|m| ctx.err(Some(f.span()), Some("feedback".into()), m))?,
    };
    if parsed.question.is_empty() {
        return Err(ctx.err(None, None, "the sheet has no [[question]]"));
    }
    let base = base.unwrap_or(Path::new("."));
    let mut questions: Vec<Question> = vec![];
    let mut spans = vec![];
    for q in parsed.question {
        let header = q.span();
        let q = q.into_inner();
        let qid = q.id.get_ref().trim().to_string();
        let what = format!("question \"{qid}\"");
        let at = |span: Range<usize>, field: &str, msg: String| {
            ctx.err(Some(span), Some(format!("{what} → {field}")), msg)
        };
        if qid.is_empty()
            || !qid
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        {
            return Err(at(
                q.id.span(),
                "id",
                format!("\"{qid}\" is not a usable id: use letters, digits, _ and - only"),
            ));
        }
        if RESERVED.contains(&qid.as_str()) {
            return Err(at(
                q.id.span(),
                "id",
                format!("\"{qid}\" is reserved for a column of the grades file"),
            ));
        }
        if questions.iter().any(|o| o.id == qid) {
            return Err(at(
                q.id.span(),
                "id",
                format!("\"{qid}\" is used by an earlier question"),
            ));
        }
        let scene = match (q.scene, q.scene_toml) {
            (Some(p), None) => {
                let path = base.join(p.get_ref());
                if !crate::platform::files::is_file(&path) {
                    return Err(at(
                        p.span(),
                        "scene",
                        format!(
                            "the scene file {} does not exist (paths are relative to the sheet)",
                            path.display()
                        ),
                    ));
                }
                SceneSource::File(path)
            }
            (None, Some(t)) => SceneSource::Inline(t.into_inner()),
            (Some(p), Some(_)) => {
                return Err(at(
                    p.span(),
                    "scene",
                    "give either `scene` (a file) or `scene_toml` (inline), not both".into(),
                ));
            }
            (None, None) => {
                return Err(at(
                    header,
                    "scene",
                    "missing: give `scene` (a file) or `scene_toml` (inline)".into(),
                ));
            }
        };
        let pixel = parse_pixel(q.pixel.get_ref()).map_err(|m| at(q.pixel.span(), "pixel", m))?;
        let quantity = *q.quantity.get_ref();
        if quantity.needs_object() && q.object.is_none() {
            return Err(at(
                q.quantity.span(),
                "object",
                format!(
                    "`{}` needs `object = \"name\"` (the object the ray is tested against)",
                    quantity.name()
                ),
            ));
        }
        let light = match &q.light {
            None => 0,
            Some(l) => u32::try_from(*l.get_ref()).map_err(|_| {
                at(
                    l.span(),
                    "light",
                    format!("must be a light index ≥ 0, got {}", l.get_ref()),
                )
            })?,
        };
        let tolerance = match &q.tolerance {
            None => DEFAULT_TOLERANCE,
            Some(t) => {
                let d = DEFAULT_TOLERANCE;
                let tol = Tolerance::within_either(
                    t.get_ref().abs.unwrap_or(if t.get_ref().rel.is_some() {
                        0.0
                    } else {
                        d.abs
                    }),
                    t.get_ref().rel.unwrap_or(if t.get_ref().abs.is_some() {
                        0.0
                    } else {
                        d.rel
                    }),
                );
                if !(tol.abs.is_finite() && tol.abs >= 0.0 && tol.rel.is_finite() && tol.rel >= 0.0)
                {
                    return Err(at(
                        t.span(),
                        "tolerance",
                        format!(
                            "abs and rel must be finite and not negative, got abs = {}, rel = {}",
                            tol.abs, tol.rel
                        ),
                    ));
                }
                tol
            }
        };
        let mut params = vec![];
        for (name, v) in &q.params {
            let field = format!("params → {name}");
            if !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                return Err(at(
                    v.span(),
                    &field,
                    "a parameter name uses letters, digits and _ only".into(),
                ));
            }
            if name == "x" || name == "y" {
                return Err(at(
                    v.span(),
                    &field,
                    "`x` and `y` are the pixel's placeholders; vary the pixel with `pixel = { x = [a, b], y = [c, d] }`".into(),
                ));
            }
            let p = parse_param(v.get_ref()).map_err(|m| at(v.span(), &field, m))?;
            params.push((name.clone(), p));
        }
        let points = match &q.points {
            None => 1.0,
            Some(p) if p.get_ref().is_finite() && *p.get_ref() >= 0.0 => *p.get_ref(),
            Some(p) => {
                return Err(at(
                    p.span(),
                    "points",
                    format!("must be a finite number ≥ 0, got {}", p.get_ref()),
                ));
            }
        };
        let require = match &q.require {
            None => None,
            Some(r) => {
                let mut path = vec![];
                for v in &r.get_ref().path {
                    path.push(
                        super::PathVertex::parse(v)
                            .map_err(|m| at(r.span(), "require → path", m))?,
                    );
                }
                Some(super::Premise {
                    path,
                    sampled_light: r.get_ref().sampled_light.clone(),
                })
            }
        };
        let mut mistakes = vec![];
        for m in &q.mistakes {
            let Some(found) = super::Mistake::from_id(m.get_ref()) else {
                let names: Vec<&str> = super::mistakes::ALL.iter().map(|m| m.id()).collect();
                return Err(at(
                    m.span(),
                    "mistakes",
                    format!(
                        "unknown mistake \"{}\"; expected one of {}",
                        m.get_ref(),
                        names.join(", ")
                    ),
                ));
            };
            if !found.applies_to(quantity) {
                return Err(at(
                    m.span(),
                    "mistakes",
                    format!(
                        "\"{}\" is not a mistake of `{}`",
                        found.id(),
                        quantity.name()
                    ),
                ));
            }
            mistakes.push(found);
        }
        let require_span = q.require.as_ref().map(|r| r.span());
        let object_span = q.object.as_ref().map(|o| o.span());
        let light_span = q.light.as_ref().map(|l| l.span());
        let question = Question {
            id: qid,
            text: q.text,
            scene,
            pixel,
            quantity,
            object: q.object.map(|o| o.into_inner()),
            ray: q.ray,
            light,
            tolerance,
            params,
            hints: q.hints,
            points,
            group: q.group,
            require,
            mistakes,
            line: ctx.line_col(header.start).0,
        };
        questions.push(question);
        spans.push((header, object_span, light_span, require_span));
    }
    let sheet = ExerciseSheet {
        file: file.into(),
        id,
        title,
        questions,
        feedback,
        trace_command: parsed.trace_command.unwrap_or(true),
        drawn: Default::default(),
    };
    for (q, (header, object_span, light_span, require_span)) in sheet.questions.iter().zip(spans) {
        let what = format!("question \"{}\"", q.id);
        let at = |span: Range<usize>, field: &str, msg: String| {
            ctx.err(Some(span), Some(format!("{what} → {field}")), msg)
        };
        let scene = sheet.first_scene(q).map_err(|m| {
            let field = match q.scene {
                SceneSource::File(_) => "scene",
                SceneSource::Inline(_) => "scene_toml",
            };
            at(header.clone(), field, m)
        })?;
        if let Some(o) = &q.object
            && !(0..scene.objects.len()).any(|i| scene.object_name(i as u32) == *o)
        {
            let names: Vec<&str> = scene.groups.iter().map(|g| g.name.as_str()).collect();
            return Err(at(
                object_span.unwrap_or(header.clone()),
                "object",
                format!(
                    "the scene has no object \"{o}\" (it has {})",
                    if names.is_empty() {
                        "none".into()
                    } else {
                        names.join(", ")
                    }
                ),
            ));
        }
        let needs_light = q.quantity == Quantity::ShadowBlocked || light_span.is_some();
        if needs_light && q.light as usize >= scene.lights.len() {
            return Err(at(
                light_span.unwrap_or(header.clone()),
                "light",
                format!(
                    "the scene has {} light{}, so there is no light {}",
                    scene.lights.len(),
                    if scene.lights.len() == 1 { "" } else { "s" },
                    q.light
                ),
            ));
        }
        if q.has_premises() {
            sheet.check_premises(q, &scene).map_err(|m| {
                at(
                    require_span.clone().unwrap_or(header.clone()),
                    if q.require.is_some() {
                        "require"
                    } else {
                        "mistakes"
                    },
                    m,
                )
            })?;
        }
    }
    Ok(sheet)
}

/// A sheet's `feedback`: `"right_wrong"`, `"direction"`, `"distance"` or `{ show_after = N }`.
fn parse_feedback(v: &toml::Value) -> Result<Feedback, String> {
    const EXPECTED: &str =
        "expected \"right_wrong\", \"direction\", \"distance\" or { show_after = N }";
    match v {
        toml::Value::String(s) => match s.as_str() {
            "right_wrong" => Ok(Feedback::RightWrong),
            "direction" => Ok(Feedback::Direction),
            "distance" => Ok(Feedback::Distance),
            other => Err(format!("unknown feedback \"{other}\"; {EXPECTED}")),
        },
        toml::Value::Table(t) if t.len() == 1 => match t.get("show_after") {
            Some(n) => n
                .as_integer()
                .and_then(|n| u32::try_from(n).ok())
                .filter(|n| *n >= 1)
                .map(Feedback::ShowAfter)
                .ok_or_else(|| format!("show_after: expected a number of tries ≥ 1, got {n}")),
            None => Err(EXPECTED.into()),
        },
        _ => Err(format!("{EXPECTED}, got {v}")),
    }
}

fn parse_coord(v: &toml::Value, axis: &str) -> Result<Coord, String> {
    let int = |v: &toml::Value| -> Result<u32, String> {
        v.as_integer()
            .and_then(|i| u32::try_from(i).ok())
            .ok_or_else(|| format!("{axis}: expected a pixel coordinate (an integer ≥ 0), got {v}"))
    };
    match v {
        toml::Value::Array(a) if a.len() == 2 => {
            let (lo, hi) = (int(&a[0])?, int(&a[1])?);
            if lo > hi {
                return Err(format!("{axis}: the range [{lo}, {hi}] is empty"));
            }
            Ok(Coord::Range(lo, hi))
        }
        toml::Value::Array(_) => Err(format!("{axis}: a range is [lowest, highest]")),
        v => Ok(Coord::Fixed(int(v)?)),
    }
}

fn parse_pixel(v: &toml::Value) -> Result<[Coord; 2], String> {
    match v {
        toml::Value::Array(a) if a.len() == 2 => {
            Ok([parse_coord(&a[0], "x")?, parse_coord(&a[1], "y")?])
        }
        toml::Value::Table(t) => {
            if let Some(k) = t.keys().find(|k| *k != "x" && *k != "y") {
                return Err(format!("unknown key `{k}`; expected `x` and `y`"));
            }
            let get = |k: &str| {
                t.get(k)
                    .ok_or_else(|| format!("missing `{k}`"))
                    .and_then(|v| parse_coord(v, k))
            };
            Ok([get("x")?, get("y")?])
        }
        _ => Err(format!(
            "expected [x, y] or {{ x = [a, b], y = [c, d] }}, got {v}"
        )),
    }
}

fn parse_range(v: &toml::Value, decimals: Option<u32>) -> Result<Param, String> {
    let toml::Value::Array(a) = v else {
        return Err(format!("expected a range [lowest, highest], got {v}"));
    };
    if a.len() != 2 {
        return Err("a range is [lowest, highest]".into());
    }
    if let (Some(lo), Some(hi), None) = (a[0].as_integer(), a[1].as_integer(), decimals) {
        if lo > hi {
            return Err(format!("the range [{lo}, {hi}] is empty"));
        }
        return Ok(Param::Int(lo, hi));
    }
    let num = |v: &toml::Value| {
        v.as_float()
            .or_else(|| v.as_integer().map(|i| i as f64))
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("expected a finite number, got {v}"))
    };
    let (lo, hi) = (num(&a[0])?, num(&a[1])?);
    if lo > hi {
        return Err(format!("the range [{lo}, {hi}] is empty"));
    }
    Ok(Param::Float {
        lo,
        hi,
        decimals: decimals.unwrap_or(2),
    })
}

fn parse_param(v: &toml::Value) -> Result<Param, String> {
    match v {
        toml::Value::Array(_) => parse_range(v, None),
        toml::Value::Table(t) => {
            if let Some(k) = t
                .keys()
                .find(|k| !["range", "decimals", "one_of"].contains(&k.as_str()))
            {
                return Err(format!(
                    "unknown key `{k}`; expected `range` (with `decimals`) or `one_of`"
                ));
            }
            match (t.get("range"), t.get("one_of")) {
                (Some(r), None) => {
                    let decimals = match t.get("decimals") {
                        None => None,
                        Some(d) => Some(
                            d.as_integer()
                                .and_then(|d| u32::try_from(d).ok())
                                .filter(|d| *d <= 9)
                                .ok_or_else(|| format!("decimals: expected 0 to 9, got {d}"))?,
                        ),
                    };
                    parse_range(r, decimals)
                }
                (None, Some(toml::Value::Array(items))) if !items.is_empty() => {
                    let mut out = vec![];
                    for it in items {
                        out.push(match it {
                            toml::Value::Integer(i) => ParamValue::Int(*i),
                            toml::Value::Float(x) if x.is_finite() => ParamValue::Float(*x),
                            toml::Value::String(s) => ParamValue::Str(s.clone()),
                            other => {
                                return Err(format!(
                                    "one_of: expected numbers or strings, got {other}"
                                ));
                            }
                        });
                    }
                    Ok(Param::OneOf(out))
                }
                (None, Some(_)) => Err("one_of: expected a non-empty list".into()),
                _ => Err("give either `range = [lo, hi]` or `one_of = [...]`".into()),
            }
        }
        _ => Err(format!(
            "expected [lo, hi], {{ range = [lo, hi], decimals = N }} or {{ one_of = [...] }}, got {v}"
        )),
    }
}

struct Ctx<'a> {
    text: &'a str,
    file: &'a str,
}

impl Ctx<'_> {
    fn line_col(&self, pos: usize) -> (usize, usize) {
        crate::text::line_col(self.text, pos)
    }

    fn err(
        &self,
        span: Option<Range<usize>>,
        field: Option<String>,
        msg: impl Into<String>,
    ) -> SheetError {
        let (line, column) = span.map(|s| self.line_col(s.start)).unzip();
        SheetError {
            file: self.file.into(),
            line,
            column,
            field,
            message: msg.into(),
        }
    }

    /// For a parse error's position: the question it sits in and the key on its line.
    fn describe(&self, pos: usize) -> Option<String> {
        let pos = pos.min(self.text.len());
        let before = &self.text[..pos];
        let mut in_question = None;
        let mut offset = 0;
        for line in before.split_inclusive('\n') {
            let t = line.trim();
            if t.starts_with('[') {
                in_question = (t == "[[question]]").then_some(offset);
            }
            offset += line.len();
        }
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let key = self.text[line_start..]
            .lines()
            .next()
            .and_then(|l| l.split_once('='))
            .map(|(k, _)| k.trim().trim_matches('"').to_string())
            .filter(|k| !k.is_empty() && !k.starts_with('['));
        let question = in_question.map(|start| {
            let body = &self.text[start..];
            let id = body
                .lines()
                .skip(1)
                .take_while(|l| !l.trim().starts_with('['))
                .find_map(|l| {
                    let (k, v) = l.split_once('=')?;
                    (k.trim() == "id").then(|| v.trim().trim_matches('"').to_string())
                });
            match id {
                Some(id) => format!("question \"{id}\""),
                None => "question".to_string(),
            }
        });
        match (question, key) {
            (Some(q), Some(k)) => Some(format!("{q} → {k}")),
            (Some(q), None) => Some(q),
            (None, k) => k,
        }
    }
}
