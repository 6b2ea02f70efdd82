//! The 2D diagrams: pure functions of a recorded [`Trace`] (plus [`ViewOptions`]) drawn with
//! tiny-skia. They never run a kernel or look at a scene: everything they show — geometry,
//! numbers, decisions — comes from the trace, so a saved trace draws the same as a live one.
//!
//! Every diagram takes an optional *focus*: an index into [`Trace::timeline`]. The step at the
//! focus is highlighted; steps before it are drawn faded, steps after it are not drawn (the
//! slice and the trees), so stepping through a trace builds the picture up.
//!
//! ```
//! use raystep_core::PreparedScene;
//! use raystep_diagram::{DiagramKind, ViewOptions, available, draw};
//!
//! let trace = PreparedScene::new(raystep_core::scene::default_scene()).record(160, 120, 0);
//! assert!(available(&trace).contains(&DiagramKind::Quadratic));
//! let opts = ViewOptions { width: 400, height: 300, ..ViewOptions::default() };
//! let canvas = draw(&trace, DiagramKind::Slice, &opts).unwrap();
//! assert_eq!((canvas.width(), canvas.height()), (400.0, 300.0));
//! assert!(canvas.png().starts_with(b"\x89PNG"));
//! ```
#![deny(unsafe_code)]
#![warn(missing_docs)]

// The layer below, by the names the modules use for it.
use raystep_core::{explain, mc, record, render, scene, shapes};

pub mod area_light;
pub mod barycentric;
pub mod bvh_tree;
pub mod canvas;
pub mod heatmap;
pub mod hemisphere;
pub mod quadratic;
pub mod ray_tree;
pub mod samples;
pub mod slice;
mod text;
pub mod texture;
pub mod two_level;

pub use canvas::{Anchor, Canvas, MAX_SIDE, Theme};

use crate::record::{RayRecord, Step, Trace};
use serde::{Deserialize, Serialize};

/// The kinds of diagram.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum DiagramKind {
    /// The scene cut by a plane containing the ray: objects, rays, hits, normals, lights, boxes.
    Slice,
    /// f(t) = at² + bt + c of a ray–sphere test.
    Quadratic,
    /// The triangle in its own plane with the barycentric point of a Möller–Trumbore test.
    Barycentric,
    /// The BVH (or the bounding-sphere tree) as a node-link tree with the visited path.
    Bvh,
    /// Instances: the TLAS walk above, each entered instance's BLAS below it (after AMD's Radeon
    /// Raytracing Analyzer), every visit numbered across both levels.
    Tlas,
    /// Primary → shadow / reflection / refraction rays with weights and colours (and a Monte
    /// Carlo sample's path: diffuse and glossy bounces, light samples).
    Raytree,
    /// Monte Carlo: the hemisphere at a hit — the BSDF's lobe and pdf, the sampled direction,
    /// the lights' angles, the directions the pixel's samples took.
    Hemisphere,
    /// Monte Carlo: an area light with the points the pixel's samples drew on it, blocked ones
    /// marked, and the focused point's pdf.
    AreaLight,
    /// Monte Carlo: the pixel's samples, their values and the running mean.
    Samples,
    /// A texture lookup: the texels (or checker squares) around the point, the ones read with
    /// their weights, and the point at its texel position.
    Texture,
}

impl DiagramKind {
    /// All kinds, in menu order.
    pub const ALL: [DiagramKind; 10] = [
        DiagramKind::Slice,
        DiagramKind::Quadratic,
        DiagramKind::Barycentric,
        DiagramKind::Texture,
        DiagramKind::Bvh,
        DiagramKind::Tlas,
        DiagramKind::Raytree,
        DiagramKind::Hemisphere,
        DiagramKind::AreaLight,
        DiagramKind::Samples,
    ];

    /// The kind's name as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            DiagramKind::Slice => "slice",
            DiagramKind::Quadratic => "quadratic",
            DiagramKind::Barycentric => "barycentric",
            DiagramKind::Bvh => "bvh",
            DiagramKind::Tlas => "tlas",
            DiagramKind::Raytree => "raytree",
            DiagramKind::Hemisphere => "hemisphere",
            DiagramKind::AreaLight => "area-light",
            DiagramKind::Samples => "samples",
            DiagramKind::Texture => "texture",
        }
    }
}

/// How to draw.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Colours.
    pub theme: Theme,
    /// The highlighted step (index into [`Trace::timeline`]); None shows the whole trace.
    pub focus: Option<usize>,
    /// Slice: rotation of the cutting plane about the primary ray, degrees.
    pub slice_angle: f32,
    /// Slice: look from above (the world's y axis) instead of along the ray's plane.
    pub top_down: bool,
    /// The UI scale to draw text and lines for: the app passes its pixels per point (1.6 and
    /// more in presentation mode), so labels read as large as the app's own text. Kept within
    /// 0.25 … 8.
    pub scale: f32,
}

impl ViewOptions {
    /// These options with each side kept within 1 … [`MAX_SIDE`] pixels and the scale within
    /// 0.25 … 8: what [`draw`] actually draws.
    pub fn sane(&self) -> ViewOptions {
        ViewOptions {
            width: self.width.clamp(1, MAX_SIDE),
            height: self.height.clamp(1, MAX_SIDE),
            scale: canvas::sane_scale(self.scale),
            ..self.clone()
        }
    }
}

impl Default for ViewOptions {
    fn default() -> Self {
        ViewOptions {
            width: 800,
            height: 600,
            theme: Theme::LIGHT,
            focus: None,
            slice_angle: 0.0,
            top_down: false,
            scale: 1.0,
        }
    }
}

/// The diagram kinds this trace has something to show in (no barycentric view without a
/// triangle test, no BVH tree without node visits, no quadratic without a sphere test).
pub fn available(trace: &Trace) -> Vec<DiagramKind> {
    let tl = trace.timeline();
    let has = |f: &dyn Fn(&Step) -> bool| tl.iter().any(|(_, s)| f(&s.step));
    let mut out = vec![DiagramKind::Slice];
    if has(&|s| matches!(s, Step::Sphere { .. })) {
        out.push(DiagramKind::Quadratic);
    }
    if has(&|s| matches!(s, Step::Triangle { .. })) {
        out.push(DiagramKind::Barycentric);
    }
    if texture::has_texture(trace) {
        out.push(DiagramKind::Texture);
    }
    if has(&bvh_tree::is_node_visit) {
        out.push(DiagramKind::Bvh);
    }
    if two_level::has_two_level(trace) {
        out.push(DiagramKind::Tlas);
    }
    out.push(DiagramKind::Raytree);
    if hemisphere::has_hemisphere(trace) {
        out.push(DiagramKind::Hemisphere);
    }
    if area_light::has_area_light(trace) {
        out.push(DiagramKind::AreaLight);
    }
    if trace.monte_carlo.is_some() {
        out.push(DiagramKind::Samples);
    }
    out
}

/// The diagrams that explain timeline step `k`, the most specific first.
pub fn kinds_for_step(trace: &Trace, k: usize) -> Vec<DiagramKind> {
    let tl = trace.timeline();
    let Some((_, s)) = tl.get(k) else {
        return vec![DiagramKind::Slice];
    };
    let wanted = match s.step {
        Step::LightSample { .. } => vec![
            DiagramKind::AreaLight,
            DiagramKind::Hemisphere,
            DiagramKind::Slice,
        ],
        Step::BsdfSample { .. } => vec![
            DiagramKind::Hemisphere,
            DiagramKind::Raytree,
            DiagramKind::Slice,
        ],
        Step::Emitted { .. } | Step::RussianRoulette { .. } => vec![
            DiagramKind::Raytree,
            DiagramKind::Samples,
            DiagramKind::Slice,
        ],
        _ => return whitted_kinds_for_step(&s.step),
    };
    // A light sample on a point light has no area-light diagram.
    let have = available(trace);
    wanted.into_iter().filter(|k| have.contains(k)).collect()
}

fn whitted_kinds_for_step(step: &Step) -> Vec<DiagramKind> {
    match step {
        Step::Sphere { .. } => vec![DiagramKind::Quadratic, DiagramKind::Slice],
        Step::Triangle { .. } => vec![DiagramKind::Barycentric, DiagramKind::Slice],
        Step::Texture { .. } => vec![DiagramKind::Texture, DiagramKind::Slice],
        Step::Node(n) if n.instance.is_none() => vec![DiagramKind::Bvh, DiagramKind::Slice],
        Step::SphereNode { .. } => vec![DiagramKind::Bvh, DiagramKind::Slice],
        Step::TlasNode(_) | Step::Instance { .. } | Step::Node(_) | Step::InstanceHit { .. } => {
            vec![DiagramKind::Tlas, DiagramKind::Slice]
        }
        Step::Light { .. }
        | Step::ShadowRay { .. }
        | Step::Reflect { .. }
        | Step::Refract { .. }
        | Step::Schlick { .. } => {
            vec![DiagramKind::Slice, DiagramKind::Raytree]
        }
        _ => vec![DiagramKind::Slice],
    }
}

/// Draws one diagram of `trace`. Fails (with a message) only when the trace has nothing of that
/// kind to show, e.g. a barycentric view of a sphere-only trace. Any size draws: each side is
/// kept within 1 … [`MAX_SIDE`] pixels (see [`ViewOptions::sane`]).
pub fn draw(trace: &Trace, kind: DiagramKind, opts: &ViewOptions) -> Result<Canvas, String> {
    let opts = &opts.sane();
    if !available(trace).contains(&kind) {
        return Err(format!(
            "this trace has no {} diagram (it has: {})",
            kind.name(),
            available(trace)
                .iter()
                .map(|k| k.name())
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    Ok(match kind {
        DiagramKind::Slice => slice::draw(trace, opts),
        DiagramKind::Quadratic => quadratic::draw(trace, opts),
        DiagramKind::Barycentric => barycentric::draw(trace, opts),
        DiagramKind::Bvh => bvh_tree::draw(trace, opts),
        DiagramKind::Tlas => two_level::draw(trace, opts),
        DiagramKind::Raytree => ray_tree::draw(trace, opts),
        DiagramKind::Hemisphere => hemisphere::draw(trace, opts),
        DiagramKind::AreaLight => area_light::draw(trace, opts),
        DiagramKind::Samples => samples::draw(trace, opts),
        DiagramKind::Texture => texture::draw(trace, opts),
    })
}

/// The ray a diagram of one ray's walk shows: the one owning the focused step if `walked`
/// accepts it, else the first ray that `walked` accepts; with the number of its steps up to and
/// including the focused one (None: all of them).
pub(crate) fn shown_ray(
    trace: &Trace,
    focus: Option<usize>,
    walked: impl Fn(&RayRecord) -> bool,
) -> Option<(&RayRecord, Option<usize>)> {
    let tl = trace.timeline();
    if let Some(k) = focus
        && let Some((r, _)) = tl.get(k)
        && walked(r)
    {
        let upto = tl[..=k]
            .iter()
            .filter(|(rr, _)| std::ptr::eq(*rr, *r))
            .count();
        return Some((r, Some(upto)));
    }
    trace
        .rays()
        .into_iter()
        .find(|r| walked(r))
        .map(|r| (r, None))
}

/// The step of `trace` a focused diagram of some kind should explain: the step at `focus` if
/// `pick` accepts it, else the last accepted step before it, else the first accepted step of the
/// trace (for an unfocused view, the first).
pub fn pick_step(
    trace: &Trace,
    focus: Option<usize>,
    pick: impl Fn(&Step) -> bool,
) -> Option<(usize, &Step)> {
    let tl = trace.timeline();
    let accepted: Vec<(usize, &Step)> = tl
        .iter()
        .enumerate()
        .filter(|(_, (_, s))| pick(&s.step))
        .map(|(i, (_, s))| (i, &s.step))
        .collect();
    match focus {
        None => accepted.first().copied(),
        Some(k) => accepted
            .iter()
            .rev()
            .find(|(i, _)| *i <= k)
            .or(accepted.first())
            .copied(),
    }
}

/// Draws a title line at the top of a diagram; returns the y below it. A title too wide for
/// the canvas is drawn smaller (down to the body text's size), then cut with an ellipsis: it
/// never runs off the edge.
pub fn title(c: &mut Canvas, text: &str) -> f32 {
    let big = c.text_size * 1.15;
    let avail = c.width() - c.text_size * 1.6;
    let w = c.text_width(text, big);
    let size = if w > avail && w > 0.0 {
        (big * avail / w).max(c.text_size)
    } else {
        big
    };
    let shown = c.elide(text, size, avail);
    let ink = c.theme.ink;
    c.text(
        c.text_size * 0.8,
        c.text_size * 0.6,
        size,
        &shown,
        ink,
        Anchor::TopLeft,
    );
    c.text_size * 0.6 + big * 1.5
}

/// The first of `titles` that fits a title line of `c` whole (at the body text's size at
/// least), else the last one.
pub fn first_fitting<'a>(c: &Canvas, titles: &'a [String]) -> &'a str {
    let avail = c.width() - c.text_size * 1.6;
    titles
        .iter()
        .find(|t| c.text_width(t, c.text_size) <= avail)
        .or(titles.last())
        .map_or("", String::as_str)
}

/// Draws the first of `titles` that fits the canvas whole ([`first_fitting`]), else the last
/// one as [`title`] does (smaller, then cut): a title with details (`… · step 3 of 0–15 · test 1
/// of 4`) on a wide canvas, a shorter one on a narrow canvas rather than a cut `(…`. Returns
/// the y below it.
pub fn title_first_fitting(c: &mut Canvas, titles: &[String]) -> f32 {
    let text = first_fitting(c, titles).to_string();
    let big = c.text_size * 1.15;
    let avail = c.width() - c.text_size * 1.6;
    let w = c.text_width(&text, c.text_size);
    if w > avail || w <= 0.0 {
        return title(c, &text);
    }
    // It fits at the body size: drawn as large as fits, up to the title size, and never cut
    // (`title` would cut a text shrunk to exactly the width by a rounding error).
    let size = big.min(c.text_size * avail / w);
    let ink = c.theme.ink;
    c.text(
        c.text_size * 0.8,
        c.text_size * 0.6,
        size,
        &text,
        ink,
        Anchor::TopLeft,
    );
    c.text_size * 0.6 + big * 1.5
}

/// The titles of a diagram of one intersection test (`kind` names it: `Ray–sphere
/// quadratic`), longest first: its object and ray, then, each after a ` · ` as in the app's
/// step bar, the step's number as the app, `raystep trace` and `--step` count it and which test
/// of the trace it is (the `nth` of `tests`); then without the test's count; then the object
/// and ray alone.
/// Which test of the trace step `step` is: the tests are the timeline's steps `is_test` picks.
pub fn test_titles(
    trace: &Trace,
    kind: &str,
    object: &str,
    ray: &str,
    step: usize,
    is_test: impl Fn(&Step) -> bool,
) -> Vec<String> {
    let tl = trace.timeline();
    let tests = tl.iter().filter(|(_, s)| is_test(&s.step)).count();
    let nth = tl
        .iter()
        .take(step.saturating_add(1))
        .filter(|(_, s)| is_test(&s.step))
        .count();
    let name = format!("{kind}: \"{object}\", {ray}");
    let step = crate::record::words::step_of(step, tl.len());
    let mut titles = vec![];
    if tests > 1 {
        titles.push(format!("{name} · {step} · test {nth} of {tests}"));
    }
    titles.push(format!("{name} · {step}"));
    titles.push(name);
    titles
}

/// Timeline step `k` of `trace` drawn as one animation frame, focused on its step: of `kind`
/// when given, else of the kind that best explains that step ([`kinds_for_step`]).
pub fn frame(
    trace: &Trace,
    kind: Option<DiagramKind>,
    base: &ViewOptions,
    k: usize,
) -> Result<Canvas, String> {
    let kind = kind.unwrap_or_else(|| kinds_for_step(trace, k)[0]);
    draw(
        trace,
        kind,
        &ViewOptions {
            focus: Some(k),
            ..base.clone()
        },
    )
}

/// The GIF frame delay when none is chosen: 0.8 s per step.
pub const DEFAULT_DELAY_MS: u32 = 800;

/// The shortest and longest GIF frame delays, in ms (GIF counts hundredths of a second, and
/// many viewers show a delay below 20 ms as 100 ms).
pub const DELAY_RANGE_MS: std::ops::RangeInclusive<u32> = 20..=60_000;

/// Draws every step of `trace` in order, one frame at a time (only one is in memory: a trace of
/// thousands of steps needs no more memory than one of ten), and hands each frame with its
/// index to `each` (to write it as a PNG, say). With `gif_delay_ms`, each frame is also encoded
/// at once into an endlessly looping GIF that shows each step for that long (kept within
/// [`DELAY_RANGE_MS`]) and holds the last one for at least 3 s. Returns the GIF's bytes (empty
/// without a delay) and the number of frames.
pub fn animate(
    trace: &Trace,
    kind: Option<DiagramKind>,
    base: &ViewOptions,
    gif_delay_ms: Option<u32>,
    each: impl FnMut(usize, &Canvas) -> Result<(), String>,
) -> Result<(Vec<u8>, usize), String> {
    let n = trace.timeline().len();
    animate_steps(trace, kind, base, 0..n, gif_delay_ms, each)
}

/// [`animate`] for the timeline steps in `steps` only (`k` handed to `each` is still the step's
/// index in the whole timeline; the last step of the range is the one held). Fails, drawing
/// nothing, when the range reaches past the trace's last step.
pub fn animate_steps(
    trace: &Trace,
    kind: Option<DiagramKind>,
    base: &ViewOptions,
    steps: std::ops::Range<usize>,
    gif_delay_ms: Option<u32>,
    mut each: impl FnMut(usize, &Canvas) -> Result<(), String>,
) -> Result<(Vec<u8>, usize), String> {
    use image::codecs::gif::{GifEncoder, Repeat};
    let len = trace.timeline().len();
    if steps.end > len {
        return Err(format!(
            "steps {}..{} (end excluded): this trace has {len} steps",
            steps.start, steps.end
        ));
    }
    let n = steps.end;
    let mut bytes = vec![];
    {
        let mut enc = match gif_delay_ms {
            Some(_) => {
                let mut enc = GifEncoder::new_with_speed(&mut bytes, 10);
                enc.set_repeat(Repeat::Infinite)
                    .map_err(|e| format!("cannot encode GIF: {e}"))?;
                Some(enc)
            }
            None => None,
        };
        let delay = gif_delay_ms
            .unwrap_or(DEFAULT_DELAY_MS)
            .clamp(*DELAY_RANGE_MS.start(), *DELAY_RANGE_MS.end());
        for k in steps.clone() {
            let f = frame(trace, kind, base, k)?;
            each(k, &f)?;
            if let Some(enc) = enc.as_mut() {
                let ms = if k + 1 == n { delay.max(3000) } else { delay };
                let frame = image::Frame::from_parts(
                    f.to_rgba_image(),
                    0,
                    0,
                    image::Delay::from_numer_denom_ms(ms, 1),
                );
                enc.encode_frame(frame)
                    .map_err(|e| format!("cannot encode GIF: {e}"))?;
            }
        }
    }
    Ok((bytes, steps.len()))
}
