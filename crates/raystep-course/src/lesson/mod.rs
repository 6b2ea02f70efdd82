//! Exercises with checked answers: an exercise sheet (TOML) asks for quantities of a traced
//! pixel, every student gets their own variant of each question, and answers are marked against
//! what raystep's tracer computes **when the sheet is checked** — a sheet never contains answers.
//! The lessons themselves (Markdown with a TOML front matter) are read by [`load_lessons`].
//!
//! The sheet format — questions, parameters, variants, quantities, answers, feedback, the
//! answers file and the class CSV — is specified for users in `docs/EXERCISE-SHEETS.md`; the
//! book's *Exercises* chapter (book/exercises.md) shows it in short.
//!
//! # From a sheet to a mark
//!
//! ```
//! use raystep_course::lesson::{Answer, mark, parse_exercise_sheet};
//!
//! let sheet = parse_exercise_sheet(
//!     r#"
//! [[question]]
//! id = "disc"
//! text = "What is the discriminant of pixel ({x}, {y})'s primary ray against the ball?"
//! scene_toml = '''
//! [camera]
//! from = [0, 0, -5]
//! width = 64
//! height = 48
//! [render]
//! sphere_method = "textbook"
//! [[sphere]]
//! name = "ball"
//! radius = {r}
//! '''
//! pixel = { x = [28, 36], y = [20, 28] }
//! params = { r = [0.8, 1.6] }
//! quantity = "discriminant"
//! object = "ball"
//! "#,
//!     "sheet.toml",
//!     None,
//!     "example",
//! )
//! .unwrap();
//! let q = &sheet.questions[0];
//! let v = sheet.variant(q, "alice"); // alice's own pixel and radius
//! let Answer::Number(d) = sheet.expected(q, &v).unwrap() else { panic!() };
//! let right = mark(&Answer::Number(d), q.quantity.kind(), Some(&d.to_string()), q.tolerance);
//! assert!(right.right);
//! let wrong = mark(&Answer::Number(d), q.quantity.kind(), Some("banana"), q.tolerance);
//! assert!(!wrong.right);
//! ```

mod answer;
mod extract;
mod grade;
mod lessons;
pub mod mistakes;
mod premise;
mod sheet;

pub use answer::{Answer, AnswerKind, Feedback, Mark, mark, parse_answers, short, show};
pub use extract::{explaining_step, extract};
pub use grade::{GradeReport, grade_answers_csv};
pub use lessons::{Lesson, LessonSettings, lessons_dir, load_lessons, parse_lesson};
pub use mistakes::Mistake;
pub use premise::{PathVertex, Premise};
pub use sheet::{
    Coord, ExerciseSheet, Param, ParamValue, Question, SceneSource, SheetError,
    load_exercise_sheet, parse_exercise_sheet,
};

use crate::record::Tolerance;
use crate::trace::PreparedScene;
use crate::variant::{draw, pick_int, uniform};
use serde::Deserialize;

/// What a question asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// The discriminant b² − 4ac of the ray's test against `object`.
    Discriminant,
    /// The smaller root of that test.
    NearRoot,
    /// The larger root of that test.
    FarRoot,
    /// The t of the ray's closest hit.
    ClosestT,
    /// The name of the object the ray hits (or none).
    HitObject,
    /// The closest hit's point.
    HitPoint,
    /// The closest hit's unit normal (facing the ray).
    Normal,
    /// A smooth triangle's shading normal at the closest hit (none on a flat surface).
    ShadingNormal,
    /// The texture coordinate u at the closest hit (its material must have a texture).
    TextureU,
    /// The texture coordinate v at the closest hit.
    TextureV,
    /// The column of the texel the texture lookup read (nearest), of the first of the four it
    /// blended (bilinear: the one whose centre is up and to the left of the point), or a
    /// checker's square i.
    TexelColumn,
    /// The row of that texel (row 0 at the top of the image), or a checker's square j.
    TexelRow,
    /// The texture's colour T at the closest hit (linear RGB).
    TextureColor,
    /// A trilinear texture's ray cone width W = γ·d at the closest hit.
    ConeWidth,
    /// A trilinear texture's level of detail λ = log₂ L at the closest hit.
    MipLambda,
    /// The (first) mip level a trilinear lookup read: ⌊λ⌋ held to the pyramid.
    MipLevel,
    /// The barycentric u (weight of P1) of a triangle test.
    TriangleU,
    /// The barycentric v (weight of P2) of a triangle test.
    TriangleV,
    /// The number of BVH nodes whose box the ray tested.
    BvhNodesVisited,
    /// Whether the shadow ray to `light` is blocked.
    ShadowBlocked,
    /// The reflected direction.
    ReflectedDirection,
    /// The refracted direction.
    RefractedDirection,
    /// Whether Snell's law gives total internal reflection.
    TotalInternalReflection,
    /// The ray's colour (linear RGB).
    Color,
    /// Monte Carlo: the density, per steradian, of the direction the ray's BSDF sampled at its
    /// hit (none for a mirror or glass: a delta).
    BsdfPdf,
    /// Monte Carlo: the direction the ray's BSDF sampled.
    SampleDirection,
    /// Monte Carlo: the path's throughput after the BSDF sample at the ray's hit.
    Throughput,
    /// Monte Carlo: the density, per steradian with the light's pick, of the first point the
    /// ray's hit sampled on a light.
    LightPdf,
    /// Monte Carlo: that light sample's MIS weight.
    MisWeight,
    /// Monte Carlo: what that light sample adds to the pixel.
    LightContribution,
    /// Monte Carlo: the probability that Russian roulette lets the path go on at the ray's hit.
    RouletteProbability,
    /// Instances: the ray's origin carried into the object space of the instance its closest
    /// hit lies on, S′ = M⁻¹·S.
    ObjectOrigin,
    /// Instances: the ray's direction carried into that object space, Q′ = M⁻¹·Q (not
    /// renormalised).
    ObjectDirection,
}

impl Quantity {
    /// The name used in sheets.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Discriminant => "discriminant",
            Quantity::NearRoot => "near_root",
            Quantity::FarRoot => "far_root",
            Quantity::ClosestT => "closest_t",
            Quantity::HitObject => "hit_object",
            Quantity::HitPoint => "hit_point",
            Quantity::Normal => "normal",
            Quantity::ShadingNormal => "shading_normal",
            Quantity::TextureU => "texture_u",
            Quantity::TextureV => "texture_v",
            Quantity::TexelColumn => "texel_column",
            Quantity::TexelRow => "texel_row",
            Quantity::TextureColor => "texture_color",
            Quantity::ConeWidth => "cone_width",
            Quantity::MipLambda => "mip_lambda",
            Quantity::MipLevel => "mip_level",
            Quantity::TriangleU => "triangle_u",
            Quantity::TriangleV => "triangle_v",
            Quantity::BvhNodesVisited => "bvh_nodes_visited",
            Quantity::ShadowBlocked => "shadow_blocked",
            Quantity::ReflectedDirection => "reflected_direction",
            Quantity::RefractedDirection => "refracted_direction",
            Quantity::TotalInternalReflection => "total_internal_reflection",
            Quantity::Color => "color",
            Quantity::BsdfPdf => "bsdf_pdf",
            Quantity::SampleDirection => "sample_direction",
            Quantity::Throughput => "throughput",
            Quantity::LightPdf => "light_pdf",
            Quantity::MisWeight => "mis_weight",
            Quantity::LightContribution => "light_contribution",
            Quantity::RouletteProbability => "roulette_probability",
            Quantity::ObjectOrigin => "object_origin",
            Quantity::ObjectDirection => "object_direction",
        }
    }

    /// Whether the quantity needs `object`.
    pub fn needs_object(self) -> bool {
        matches!(
            self,
            Quantity::Discriminant | Quantity::NearRoot | Quantity::FarRoot
        )
    }

    /// The kind of answer expected.
    pub fn kind(self) -> AnswerKind {
        match self {
            Quantity::HitObject => AnswerKind::Name,
            Quantity::ShadowBlocked | Quantity::TotalInternalReflection => AnswerKind::YesNo,
            Quantity::HitPoint
            | Quantity::Normal
            | Quantity::ShadingNormal
            | Quantity::TextureColor
            | Quantity::ReflectedDirection
            | Quantity::RefractedDirection
            | Quantity::Color
            | Quantity::SampleDirection
            | Quantity::Throughput
            | Quantity::LightContribution
            | Quantity::ObjectOrigin
            | Quantity::ObjectDirection => AnswerKind::Vector,
            _ => AnswerKind::Number,
        }
    }
}

/// Which ray of the trace a question is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RaySel {
    /// The primary ray.
    #[default]
    Primary,
    /// The first shadow ray.
    Shadow,
    /// The first reflection ray.
    Reflection,
    /// The first refraction ray.
    Refraction,
    /// The first Monte Carlo bounce off a diffuse surface (the path's second segment, when the
    /// camera's ray hit a diffuse surface).
    Diffuse,
    /// The first Monte Carlo bounce off a glossy surface.
    Glossy,
}

/// How close an answer must be unless the question says otherwise: [`Tolerance`]'s
/// [`within_either`](Tolerance::within_either) rule — right when |answer − expected| ≤ 0.001, or
/// |answer − expected| / |expected| ≤ 0.001 (0.1 %).
pub const DEFAULT_TOLERANCE: Tolerance = Tolerance::within_either(1e-3, 1e-3);

/// One student's version of one question.
#[derive(Debug, Clone, PartialEq)]
pub struct Variant {
    /// The parameters' values, in name order.
    pub values: Vec<(String, ParamValue)>,
    /// The pixel.
    pub pixel: [u32; 2],
    /// The text with its placeholders filled.
    pub text: String,
    /// The inline scene with its placeholders filled, for `scene_toml` questions.
    pub scene_toml: Option<String>,
}

/// Replaces `{name}` for every known name; other braces stay.
pub fn fill(template: &str, values: &[(String, String)]) -> String {
    let mut out = String::with_capacity(template.len());
    let mut rest = template;
    while let Some(open) = rest.find('{') {
        out += &rest[..open];
        let after = &rest[open + 1..];
        let replaced = after.find('}').and_then(|close| {
            let name = &after[..close];
            values
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, v)| (v, close))
        });
        match replaced {
            Some((v, close)) => {
                out += v;
                rest = &after[close + 1..];
            }
            None => {
                out.push('{');
                rest = after;
            }
        }
    }
    out + rest
}

/// The pixels drawn so far for questions with premises, by (question, student): drawing one
/// traces candidate pixels, and the app asks for a variant at every frame. Shared by a sheet's
/// clones; never part of a sheet's equality.
#[derive(Clone, Default)]
pub struct DrawnPixels(std::sync::Arc<std::sync::Mutex<PixelsByStudent>>);

/// (question id, student) → pixel.
type PixelsByStudent = std::collections::HashMap<(String, String), Option<[u32; 2]>>;

impl std::fmt::Debug for DrawnPixels {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("DrawnPixels")
    }
}

impl PartialEq for DrawnPixels {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// How many pixels [`ExerciseSheet::variant`] draws for a question with premises before it
/// scans the pixel range in order.
const PREMISE_DRAWS: u32 = 96;

/// How many pixels of its range, in order, a question with premises tries after its draws.
const PREMISE_SCAN: u64 = 16384;

/// How many pixels a sheet's load draws to check a question's premises, and how many of them
/// must satisfy them (a range where fewer do is refused: too few variants, and a sign that the
/// range and the premise disagree).
const PREMISE_CHECKS: u32 = 48;
const PREMISE_MIN: u32 = 6;

impl Question {
    /// Whether drawing the question's pixel checks it (a `require` or listed `mistakes`).
    pub fn has_premises(&self) -> bool {
        self.require.is_some() || !self.mistakes.is_empty()
    }

    /// Whether `trace` (of a candidate pixel) satisfies the question's premises, and every listed
    /// mistake's answer is at least [`mistakes::MIN_APART`] from the right one; why not, if not.
    pub fn premises_hold(&self, trace: &crate::record::Trace) -> Result<(), String> {
        if let Some(p) = &self.require {
            p.check(trace, self)?;
        }
        if self.mistakes.is_empty() {
            return Ok(());
        }
        let right = extract(trace, self);
        if right == Answer::None {
            return Err(format!("the tracer computes no {}", self.quantity.name()));
        }
        for m in &self.mistakes {
            if let Some(a) = m.answer(trace, self) {
                let d = mistakes::relative_distance(&right, &a).unwrap_or(f64::INFINITY);
                if d < mistakes::MIN_APART
                    || mark(
                        &right,
                        self.quantity.kind(),
                        Some(&a.to_string()),
                        self.tolerance,
                    )
                    .right
                {
                    return Err(format!(
                        "the mistake \"{}\" is only {:.2} % away from the right answer",
                        m.id(),
                        d * 100.0
                    ));
                }
            }
        }
        Ok(())
    }
}

impl ExerciseSheet {
    /// The variant of question `q` for `student` (deterministic). For a question with premises
    /// (`require`, `mistakes`) the pixel is the first of the student's draws whose trace
    /// satisfies them (the scene is traced; the result is kept), and where none of
    /// [`PREMISE_DRAWS`] does, the first pixel of the range that does, counted from the first
    /// draw.
    pub fn variant(&self, q: &Question, student: &str) -> Variant {
        let base = self.base_variant(q, student);
        if !q.has_premises() {
            return base;
        }
        let student = student.trim();
        let pixel = self
            .premise_pixel_cached(q, student, &base)
            .unwrap_or(base.pixel);
        if pixel == base.pixel {
            return base;
        }
        self.with_pixel(q, base.values, pixel)
    }

    /// The k-th pixel draw of a student (k = 0: the draw of a question without premises).
    fn draw_pixel(&self, q: &Question, student: &str, k: u32) -> [u32; 2] {
        let salt = q.group.as_deref().unwrap_or(&q.id);
        let coord = |c: Coord, name: &str| match c {
            Coord::Fixed(v) => v,
            Coord::Range(lo, hi) => {
                let name = if k == 0 {
                    name.to_string()
                } else {
                    format!("{name} #{k}")
                };
                pick_int(draw(&self.id, salt, student, &name), lo as i64, hi as i64) as u32
            }
        };
        [coord(q.pixel[0], "pixel x"), coord(q.pixel[1], "pixel y")]
    }

    /// The pixel of a question with premises (see [`ExerciseSheet::variant`]); None when the
    /// scene does not load or no pixel of the range satisfies them.
    fn premise_pixel(&self, q: &Question, student: &str, base: &Variant) -> Option<[u32; 2]> {
        let scene = self.scene_of(q, base).ok()?;
        let (w, h) = (scene.camera.width, scene.camera.height);
        let prepared = PreparedScene::new(scene);
        // The questions of a group share their pixel: it must satisfy all of their premises.
        let group: Vec<&Question> = match &q.group {
            Some(g) => self
                .questions
                .iter()
                .filter(|o| o.group.as_ref() == Some(g) && o.pixel == q.pixel)
                .collect(),
            None => vec![q],
        };
        let holds = |[x, y]: [u32; 2]| {
            if x >= w || y >= h {
                return false;
            }
            let trace = prepared.record(x, y, 0);
            group.iter().all(|o| o.premises_hold(&trace).is_ok())
        };
        for k in 0..PREMISE_DRAWS {
            let p = self.draw_pixel(q, student, k);
            if holds(p) {
                return Some(p);
            }
        }
        // The range (inside the image) in order from the first draw, at most PREMISE_SCAN pixels.
        let range = |c: Coord, size: u32| match c {
            Coord::Fixed(v) => (v, v),
            Coord::Range(lo, hi) => (lo, hi.min(size.saturating_sub(1))),
        };
        let ((x0, x1), (y0, y1)) = (range(q.pixel[0], w), range(q.pixel[1], h));
        if x1 < x0 || y1 < y0 {
            return None;
        }
        let (nx, ny) = ((x1 - x0) as u64 + 1, (y1 - y0) as u64 + 1);
        let start = (base.pixel[1].saturating_sub(y0) as u64) * nx
            + base.pixel[0].saturating_sub(x0) as u64;
        (0..(nx * ny).min(PREMISE_SCAN))
            .map(|i| {
                let j = (start + i) % (nx * ny);
                [x0 + (j % nx) as u32, y0 + (j / nx) as u32]
            })
            .find(|p| holds(*p))
    }

    /// The pixel of a question with premises for `student`, drawn once and kept; None when no
    /// pixel of the range satisfies them (a sheet error, which [`ExerciseSheet::expected`]
    /// reports).
    fn premise_pixel_cached(
        &self,
        q: &Question,
        student: &str,
        base: &Variant,
    ) -> Option<[u32; 2]> {
        let key = (q.id.clone(), student.to_string());
        if let Some(p) = self.drawn.0.lock().ok().and_then(|m| m.get(&key).copied()) {
            return p;
        }
        let p = self.premise_pixel(q, student, base);
        if let Ok(mut m) = self.drawn.0.lock() {
            m.insert(key, p);
        }
        p
    }

    /// Checks, when a sheet is loaded, that a question's premises hold at enough of its pixels:
    /// [`PREMISE_MIN`] of [`PREMISE_CHECKS`] draws; the error names the premise and the most
    /// common reason it fails.
    pub(crate) fn check_premises(
        &self,
        q: &Question,
        scene: &crate::scene::Scene,
    ) -> Result<(), String> {
        let prepared = PreparedScene::new(scene.clone());
        let (w, h) = (scene.camera.width, scene.camera.height);
        let mut good = 0;
        let mut reasons: std::collections::BTreeMap<String, u32> = Default::default();
        for k in 0..PREMISE_CHECKS {
            let [x, y] = self.draw_pixel(q, &format!("premise check {k}"), 0);
            if x >= w || y >= h {
                *reasons
                    .entry(format!("pixel {x},{y} is outside the image"))
                    .or_default() += 1;
                continue;
            }
            match q.premises_hold(&prepared.record(x, y, 0)) {
                Ok(()) => good += 1,
                Err(why) => *reasons.entry(why).or_default() += 1,
            }
        }
        if good >= PREMISE_MIN {
            return Ok(());
        }
        let common = reasons
            .iter()
            .max_by_key(|(_, n)| **n)
            .map(|(r, n)| format!("; most often: {r} ({n} pixels)"))
            .unwrap_or_default();
        Err(format!(
            "only {good} of {PREMISE_CHECKS} pixels drawn from the question's range satisfy its premises ({}{}){common}: widen or move `pixel`, or change `require`",
            q.require
                .as_ref()
                .map_or("the quantity is computed".into(), |p| p.describe()),
            if q.mistakes.is_empty() {
                String::new()
            } else {
                format!(
                    ", and it tells {} apart by at least {} %",
                    q.mistakes
                        .iter()
                        .map(|m| m.id())
                        .collect::<Vec<_>>()
                        .join(", "),
                    mistakes::MIN_APART * 100.0
                )
            }
        ))
    }

    /// The expected answer and the classic mistakes' answers for the variant's pixel (see
    /// [`mistakes`]): what a wrong answer is compared with, to name its mistake.
    pub fn expected_and_mistakes(
        &self,
        q: &Question,
        v: &Variant,
    ) -> Result<mistakes::Key, String> {
        let trace = self.trace_of(q, v)?;
        let found = mistakes::ALL
            .iter()
            .filter_map(|m| Some((*m, m.answer(&trace, q)?)))
            .collect();
        Ok((extract(&trace, q), found))
    }

    /// The variant of a student with the parameters drawn and the pixel given (the texts filled
    /// anew).
    fn with_pixel(
        &self,
        q: &Question,
        values: Vec<(String, ParamValue)>,
        pixel: [u32; 2],
    ) -> Variant {
        let mut texts: Vec<(String, String)> = values
            .iter()
            .map(|(n, v)| (n.clone(), v.to_string()))
            .collect();
        texts.push(("x".into(), pixel[0].to_string()));
        texts.push(("y".into(), pixel[1].to_string()));
        Variant {
            text: fill(&q.text, &texts),
            scene_toml: match &q.scene {
                SceneSource::Inline(t) => Some(fill(t, &texts)),
                SceneSource::File(_) => None,
            },
            values,
            pixel,
        }
    }

    /// The variant as drawn without looking at the scene (the pixel of draw 0).
    fn base_variant(&self, q: &Question, student: &str) -> Variant {
        let student = student.trim();
        let salt = q.group.as_deref().unwrap_or(&q.id);
        let values: Vec<(String, ParamValue)> = q
            .params
            .iter()
            .map(|(name, p)| {
                let bits = draw(&self.id, salt, student, name);
                let v = match p {
                    Param::Int(lo, hi) => ParamValue::Int(pick_int(bits, *lo, *hi)),
                    Param::Float { lo, hi, decimals } => {
                        let scale = 10f64.powi(*decimals as i32);
                        let x = lo + uniform(bits) * (hi - lo);
                        let r = ((x * scale).round() / scale).clamp(*lo, *hi);
                        ParamValue::Float(r)
                    }
                    Param::OneOf(items) => items[(bits % items.len() as u64) as usize].clone(),
                };
                (name.clone(), v)
            })
            .collect();
        let pixel = self.draw_pixel(q, student, 0);
        self.with_pixel(q, values, pixel)
    }

    /// The answer raystep's tracer gives for a variant: loads the scene, builds the accelerator
    /// the renderer would use, records sample 0 of the pixel and reads the quantity. An error
    /// means the sheet (not the student) is wrong: a scene that doesn't load, a pixel outside it.
    pub fn expected(&self, q: &Question, v: &Variant) -> Result<Answer, String> {
        Ok(extract(&self.trace_of(q, v)?, q))
    }

    /// Sample 0 of the variant's pixel, recorded (see [`ExerciseSheet::expected`]). An error
    /// too when the question has premises that no pixel of its range satisfies for this variant.
    fn trace_of(&self, q: &Question, v: &Variant) -> Result<crate::record::Trace, String> {
        let scene = self.scene_of(q, v)?;
        let [x, y] = v.pixel;
        let c = &scene.camera;
        if x >= c.width || y >= c.height {
            return Err(self.question_err(
                q,
                "pixel",
                &format!(
                    "pixel {x},{y} is outside the {}×{} image",
                    c.width, c.height
                ),
            ));
        }
        let trace = PreparedScene::new(scene).record(x, y, 0);
        if q.has_premises()
            && let Err(why) = q.premises_hold(&trace)
        {
            return Err(self.question_err(
                q,
                "require",
                &format!(
                    "no pixel of the question's range satisfies its premises for this variant (pixel {x},{y}: {why})"
                ),
            ));
        }
        Ok(trace)
    }

    /// The scene of question `q` as one student's variant has it, without locating an error
    /// (what [`parse_exercise_sheet`] checks a question's `object` and `light` against).
    pub(crate) fn first_scene(&self, q: &Question) -> Result<crate::scene::Scene, String> {
        let v = self.base_variant(q, "");
        match (&q.scene, &v.scene_toml) {
            (SceneSource::File(p), _) => crate::scene::load_file(p).map_err(|e| e.to_string()),
            (SceneSource::Inline(template), filled) => {
                let text = filled.as_deref().unwrap_or(template);
                let name = format!("{} (question \"{}\", scene_toml)", self.file, q.id);
                let base = std::path::Path::new(&self.file).parent();
                crate::scene::load_str(text, &name, base).map_err(|e| e.to_string())
            }
        }
    }

    /// The scene of a variant, its errors naming the sheet and question.
    fn scene_of(&self, q: &Question, v: &Variant) -> Result<crate::scene::Scene, String> {
        Ok(match (&q.scene, &v.scene_toml) {
            (SceneSource::File(p), _) => {
                crate::scene::load_file(p).map_err(|e| self.question_err(q, "scene", &e))?
            }
            (SceneSource::Inline(template), filled) => {
                let text = filled.as_deref().unwrap_or(template);
                let name = format!("{} (question \"{}\", scene_toml)", self.file, q.id);
                let base = std::path::Path::new(&self.file).parent();
                crate::scene::load_str(text, &name, base)
                    .map_err(|e| self.question_err(q, "scene_toml", &e))?
            }
        })
    }

    fn question_err(&self, q: &Question, field: &str, e: &dyn std::fmt::Display) -> String {
        format!(
            "{}:{}: question \"{}\" → {field}: {e}",
            self.file, q.line, q.id
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fill_replaces_known_names_only() {
        let v = vec![("r".to_string(), "1.5".to_string())];
        assert_eq!(fill("r = {r}, {z} {", &v), "r = 1.5, {z} {");
    }
}
