//! The 2D diagrams: pure functions of a recorded [`Trace`] (plus [`ViewOptions`]) drawn with
//! tiny-skia. They never run a kernel or look at a scene: everything they show — geometry,
//! numbers, decisions — comes from the trace, so a saved trace draws the same as a live one.
//!
//! Every diagram takes an optional *focus*: an index into [`Trace::timeline`]. The step at the
//! focus is highlighted; steps before it are drawn faded, steps after it are not drawn (the
//! slice and the trees), so stepping through a trace builds the picture up.

pub mod barycentric;
pub mod bvh_tree;
pub mod canvas;
pub mod quadratic;
pub mod ray_tree;
pub mod slice;

pub use canvas::{Anchor, Canvas, Theme};

use crate::trace::{Step, Trace};
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
    /// The BVH as a node-link tree with the visited path.
    Bvh,
    /// Primary → shadow / reflection / refraction rays with weights and colours.
    Raytree,
}

impl DiagramKind {
    /// All kinds, in menu order.
    pub const ALL: [DiagramKind; 5] = [
        DiagramKind::Slice,
        DiagramKind::Quadratic,
        DiagramKind::Barycentric,
        DiagramKind::Bvh,
        DiagramKind::Raytree,
    ];

    /// The kind's name as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            DiagramKind::Slice => "slice",
            DiagramKind::Quadratic => "quadratic",
            DiagramKind::Barycentric => "barycentric",
            DiagramKind::Bvh => "bvh",
            DiagramKind::Raytree => "raytree",
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
    if has(&|s| matches!(s, Step::Node(_))) {
        out.push(DiagramKind::Bvh);
    }
    out.push(DiagramKind::Raytree);
    out
}

/// The diagrams that explain timeline step `k`, the most specific first.
pub fn kinds_for_step(trace: &Trace, k: usize) -> Vec<DiagramKind> {
    let tl = trace.timeline();
    let Some((_, s)) = tl.get(k) else {
        return vec![DiagramKind::Slice];
    };
    match s.step {
        Step::Sphere { .. } => vec![DiagramKind::Quadratic, DiagramKind::Slice],
        Step::Triangle { .. } => vec![DiagramKind::Barycentric, DiagramKind::Slice],
        Step::Node(_) => vec![DiagramKind::Bvh, DiagramKind::Slice],
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
/// kind to show, e.g. a barycentric view of a sphere-only trace.
pub fn draw(trace: &Trace, kind: DiagramKind, opts: &ViewOptions) -> Result<Canvas, String> {
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
        DiagramKind::Raytree => ray_tree::draw(trace, opts),
    })
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

/// Draws a title line at the top of a diagram; returns the y below it.
pub fn title(c: &mut Canvas, text: &str) -> f32 {
    let size = c.text_size * 1.15;
    let ink = c.theme.ink;
    c.text(
        c.text_size * 0.8,
        c.text_size * 0.6,
        size,
        text,
        ink,
        Anchor::TopLeft,
    );
    c.text_size * 0.6 + size * 1.5
}

/// Every step of `trace` drawn in order, one frame per timeline step, each focused on its step:
/// of `kind` when given, else of the kind that best explains that step ([`kinds_for_step`]).
pub fn frames(
    trace: &Trace,
    kind: Option<DiagramKind>,
    base: &ViewOptions,
) -> Result<Vec<Canvas>, String> {
    (0..trace.timeline().len())
        .map(|k| {
            let kind = kind.unwrap_or_else(|| kinds_for_step(trace, k)[0]);
            draw(
                trace,
                kind,
                &ViewOptions {
                    focus: Some(k),
                    ..base.clone()
                },
            )
        })
        .collect()
}

/// Encodes frames as an endlessly looping GIF, 0.8 s per step (the last held for 3 s).
pub fn gif(frames: &[Canvas]) -> Result<Vec<u8>, String> {
    use image::codecs::gif::{GifEncoder, Repeat};
    let mut bytes = vec![];
    {
        let mut enc = GifEncoder::new_with_speed(&mut bytes, 10);
        enc.set_repeat(Repeat::Infinite)
            .map_err(|e| format!("cannot encode GIF: {e}"))?;
        for (k, f) in frames.iter().enumerate() {
            let delay = if k + 1 == frames.len() { 3000 } else { 800 };
            let frame = image::Frame::from_parts(
                f.to_rgba_image(),
                0,
                0,
                image::Delay::from_numer_denom_ms(delay, 1),
            );
            enc.encode_frame(frame)
                .map_err(|e| format!("cannot encode GIF: {e}"))?;
        }
    }
    Ok(bytes)
}
