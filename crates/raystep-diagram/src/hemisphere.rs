//! The hemisphere at a Monte Carlo hit, drawn in the plane through the normal and the direction
//! back to the eye (ωo): the tangent plane, the normal, ωo, the BSDF's sampling density
//! p(ωi) as a polar curve (its lobe: a circle through the point for a diffuse surface, a lobe
//! about the mirror direction for a glossy one, a spike for a mirror or glass), the direction
//! the focused step sampled, the angle each light's shape covers, and the directions the pixel's
//! samples so far took at their first hit (ticks on the rim).
//!
//! A direction out of the drawing's plane is drawn by its projection; the panel says how far
//! out it is. Everything comes from the trace: the hit from its `surface` step, the sample from
//! its `bsdf-sample` or `light-sample` step, the BSDF and the lights from its Monte Carlo record
//! ([`crate::record::samples::McRecord`]); the curve is [`crate::mc::bsdf::pdf`] evaluated along
//! the plane (drawing, not sampling).

use super::canvas::{Anchor, Canvas, Rgba, with_alpha};
pub use super::text::PlacedLabel;
use super::text::{Placer, Rich};
use super::{ViewOptions, pick_step, title_first_fitting};
use crate::mc::bsdf;
use crate::mc::lights::LightShape;
use crate::record::number::{Style, fmt};
use crate::record::samples::{McRecord, TraceLight};
use crate::record::{RayRecord, Step, Trace};
use crate::scene::Bsdf;
use glam::Vec3;
use std::f32::consts::PI;

/// Whether a step is one the hemisphere explains.
pub fn is_sample_step(s: &Step) -> bool {
    matches!(s, Step::LightSample { .. } | Step::BsdfSample { .. })
}

/// The shading frame the diagram draws in: the hit, its normal, the tangent towards the eye.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneFrame {
    /// The hit point.
    pub point: Vec3,
    /// The unit normal (up in the drawing).
    pub normal: Vec3,
    /// The unit tangent in the plane of the normal and ωo (right in the drawing).
    pub tangent: Vec3,
    /// ωo: the unit direction back along the incoming ray.
    pub wo: Vec3,
}

impl PlaneFrame {
    /// The frame for a hit with this normal seen along `incoming` (the ray's direction);
    /// `fallback` gives the plane when ωo lies along the normal.
    pub fn new(point: Vec3, normal: Vec3, incoming: Vec3, fallback: Vec3) -> PlaneFrame {
        let n = normal.normalize_or(Vec3::Y);
        let wo = (-incoming).normalize_or(n);
        let along = |v: Vec3| (v - n * n.dot(v)).normalize_or_zero();
        let mut t = along(wo);
        if t == Vec3::ZERO {
            t = along(fallback);
        }
        if t == Vec3::ZERO {
            t = n.any_orthonormal_vector();
        }
        PlaneFrame {
            point,
            normal: n,
            tangent: t,
            wo,
        }
    }

    /// The direction at angle `theta` from the normal, towards the tangent for θ > 0.
    pub fn direction(&self, theta: f32) -> Vec3 {
        self.normal * theta.cos() + self.tangent * theta.sin()
    }

    /// A direction's angle in the drawing's plane (from the normal, towards the tangent) and
    /// how far out of the plane it points (degrees).
    pub fn angle(&self, d: Vec3) -> (f32, f32) {
        let d = d.normalize_or_zero();
        let (x, y) = (d.dot(self.tangent), d.dot(self.normal));
        let out = d.dot(self.normal.cross(self.tangent)).clamp(-1.0, 1.0);
        (x.atan2(y), out.asin().to_degrees())
    }
}

/// The BSDF's density along the drawing's plane: (θ, p(ωo, ωi(θ))) for θ from −90° to 90°.
pub fn lobe(b: &Bsdf, f: &PlaneFrame, steps: usize) -> Vec<(f32, f32)> {
    let steps = steps.max(2);
    (0..=steps)
        .map(|i| {
            let theta = -PI / 2.0 + PI * i as f32 / steps as f32;
            (
                theta,
                bsdf::pdf(b, f.wo, f.direction(theta), f.normal).max(0.0),
            )
        })
        .collect()
}

/// The solid angle a light covers seen from `p` (steradians): a triangle's by Van Oosterom and
/// Strackee's formula, a sphere's cone 2π(1 − cos θmax); 0 for a point light.
pub fn solid_angle(shape: &LightShape, p: Vec3) -> f32 {
    match *shape {
        LightShape::Triangle { p: v, .. } => {
            let (a, b, c) = (v[0] - p, v[1] - p, v[2] - p);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let num = a.dot(b.cross(c)).abs();
            let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
            2.0 * num.atan2(den)
        }
        LightShape::Sphere { center, radius } => {
            let d = (center - p).length();
            if d <= radius {
                return 4.0 * PI;
            }
            let sin = radius / d;
            2.0 * PI * (1.0 - (1.0 - sin * sin).max(0.0).sqrt())
        }
        LightShape::Point { .. } => 0.0,
    }
}

/// The range of in-plane angles a light's shape covers, seen from the frame's point.
fn light_span(f: &PlaneFrame, l: &TraceLight) -> Option<(f32, f32)> {
    let angles: Vec<f32> = match l.shape {
        LightShape::Triangle { p, .. } => p.iter().map(|v| f.angle(*v - f.point).0).collect(),
        LightShape::Sphere { center, radius } => {
            let d = center - f.point;
            let dist = d.length();
            let (a, _) = f.angle(d);
            let half = if dist > radius {
                (radius / dist).asin()
            } else {
                PI
            };
            vec![a - half, a + half]
        }
        LightShape::Point { position } => vec![f.angle(position - f.point).0],
    };
    let lo = angles.iter().copied().fold(f32::INFINITY, f32::min);
    let hi = angles.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    (lo.is_finite() && hi.is_finite()).then_some((lo, hi))
}

/// What the diagram explains: the focused sample step, its ray, the hit's frame and BSDF.
struct Focus<'a> {
    step: &'a Step,
    ray: &'a RayRecord,
    frame: PlaneFrame,
    bsdf: Option<Bsdf>,
    object: String,
}

fn focus<'a>(trace: &'a Trace, opts: &ViewOptions) -> Option<Focus<'a>> {
    let mc = trace.monte_carlo.as_ref()?;
    let (k, step) = pick_step(trace, opts.focus, is_sample_step)?;
    let tl = trace.timeline();
    let ray = tl.get(k)?.0;
    let (point, normal) = ray.steps.iter().find_map(|s| match s.step {
        Step::Surface { point, normal, .. } => Some((Vec3::from(point), Vec3::from(normal))),
        _ => None,
    })?;
    let sampled = match step {
        Step::LightSample { direction, .. } | Step::BsdfSample { direction, .. } => {
            Vec3::from(*direction)
        }
        _ => Vec3::ZERO,
    };
    let frame = PlaneFrame::new(point, normal, Vec3::from(ray.direction), sampled);
    let hit = ray.hit.as_ref();
    Some(Focus {
        step,
        ray,
        frame,
        bsdf: hit.and_then(|h| mc.bsdf_of(h.object)).copied(),
        object: hit.map_or_else(String::new, |h| h.name.clone()),
    })
}

/// Whether the trace has a sample step to draw a hemisphere for.
pub fn has_hemisphere(trace: &Trace) -> bool {
    trace.monte_carlo.is_some() && pick_step(trace, None, is_sample_step).is_some()
}

/// Draws the hemisphere diagram for the focused (or first) light or BSDF sample.
pub fn draw(trace: &Trace, opts: &ViewOptions) -> Canvas {
    draw_labelled(trace, opts).0
}

/// [`draw`], with the labels of the drawing (ωo, the sampled direction, the lobe's density)
/// where they were placed: each where it covers no other, inside the drawing's area when
/// anywhere there is room.
pub fn draw_labelled(trace: &Trace, opts: &ViewOptions) -> (Canvas, Vec<PlacedLabel>) {
    let mut c = Canvas::for_view(opts);
    let th = c.theme;
    let ts = c.text_size;
    let (Some(f), Some(mc)) = (focus(trace, opts), trace.monte_carlo.as_ref()) else {
        c.text(
            ts,
            ts,
            ts,
            "no light or BSDF sample in this trace",
            th.muted,
            Anchor::TopLeft,
        );
        return (c, vec![]);
    };
    let fr = f.frame;
    let what = match f.step {
        Step::LightSample { name, .. } => format!("a point sampled on \"{name}\""),
        Step::BsdfSample { bsdf, lobe, .. } => format!("the {bsdf} BSDF's {lobe} sample"),
        _ => String::new(),
    };
    let top = title_first_fitting(
        &mut c,
        &[
            format!(
                "Hemisphere at \"{}\" (depth {}): {what}",
                f.object, f.ray.depth
            ),
            format!("Hemisphere at \"{}\": {what}", f.object),
            format!("Hemisphere at \"{}\"", f.object),
        ],
    );
    // The drawing: a half disc on the tangent plane, the panel of numbers below it, each of
    // its lines wrapped to the canvas's width (a narrow panel in the app cuts none).
    let small = ts * 0.85;
    let panel_lines: Vec<String> = panel(&f, mc)
        .iter()
        .flat_map(|l| wrap_plain(&c, l, small, c.width() - ts * 1.6))
        .collect();
    let panel_h = small * 1.35 * panel_lines.len() as f32 + ts * 0.6;
    // The drawing gets at least 55 % of the height below the title (on a short, wide canvas —
    // a projector's diagram panel — the panel's last lines give way, not the drawing).
    let avail_h = (c.height() - top - panel_h - ts * 1.2)
        .max((c.height() - top) * 0.55)
        .max(ts * 4.0);
    let r = (avail_h / 1.25).min(c.width() * 0.36);
    let o = [c.width() / 2.0, top + r * 1.18];
    // The labels are placed where they cover no other label, inside the drawing's area.
    let mut labels = Placer::new([0.0, top, c.width(), o[1] - 2.0]);
    labels.block([o[0] - 8.0, o[1] - 8.0, o[0] + 8.0, o[1] + 8.0]);
    let at = |theta: f32, len: f32| [o[0] + theta.sin() * len, o[1] - theta.cos() * len];
    // The tangent plane and the unit hemisphere.
    c.line(
        [o[0] - r * 1.25, o[1]],
        [o[0] + r * 1.25, o[1]],
        th.object,
        2.0,
    );
    let rim: Vec<[f32; 2]> = (0..=64)
        .map(|i| at(-PI / 2.0 + PI * i as f32 / 64.0, r))
        .collect();
    c.polyline(&rim, th.faded, 1.0, true);
    // Each light's angle, as an arc just outside the rim.
    let focused_light = match f.step {
        Step::LightSample { light, .. } => Some(*light),
        _ => None,
    };
    for l in &mc.lights {
        let Some((lo, hi)) = light_span(&fr, l) else {
            continue;
        };
        let (lo, hi) = (lo.max(-PI / 2.0), hi.min(PI / 2.0));
        if lo > hi {
            continue;
        }
        let strong = focused_light == Some(l.index);
        let col = if strong {
            th.light
        } else {
            with_alpha(th.light, 110)
        };
        let arc: Vec<[f32; 2]> = (0..=24)
            .map(|i| at(lo + (hi - lo) * i as f32 / 24.0, r * 1.1))
            .collect();
        if arc.len() > 1 && (hi - lo) > 0.01 {
            c.polyline(&arc, col, if strong { 5.0 } else { 3.0 }, false);
        } else {
            c.circle(at(lo, r * 1.1), 4.0 * c.scale, Some(col), None, 1.0);
        }
    }
    // The lobe (its label is placed after the arrows').
    let mut pdf_label: Option<([f32; 2], String, Rgba)> = None;
    let lobe_col = match f.bsdf {
        Some(Bsdf::Glossy { .. }) => th.glossy,
        _ => th.diffuse,
    };
    match f.bsdf {
        Some(b) if !bsdf::is_delta(&b) => {
            // A fine lobe (a nearly smooth GGX surface) is narrower than the curve's 0.25° steps:
            // its mirror direction, where it peaks, is added to the curve.
            let mut pts = lobe(&b, &fr, 720);
            let (mirror, _) = fr.angle(bsdf::mirror(fr.wo, fr.normal));
            if mirror.abs() < PI / 2.0 {
                let p = bsdf::pdf(&b, fr.wo, fr.direction(mirror), fr.normal).max(0.0);
                let k = pts.partition_point(|q| q.0 < mirror);
                pts.insert(k, (mirror, p));
            }
            let max = pts.iter().map(|p| p.1).fold(0.0f32, f32::max);
            if max > 0.0 {
                let mut poly: Vec<[f32; 2]> = pts
                    .iter()
                    .map(|(t, p)| at(*t, r * 0.95 * p / max))
                    .collect();
                poly.push(o);
                c.polygon(&poly, Some(with_alpha(lobe_col, 60)), Some(lobe_col), 2.0);
                let peak = pts
                    .iter()
                    .max_by(|a, b| a.1.total_cmp(&b.1))
                    .map_or(0.0, |p| p.0);
                pdf_label = Some((
                    at(peak, r * 0.95),
                    format!("p(ωi) up to {} sr⁻¹", fmt(max, Style::Label)),
                    lobe_col,
                ));
            }
        }
        Some(_) => {
            // A delta BSDF: one direction, no density.
            let (t, _) = fr.angle(bsdf::mirror(fr.wo, fr.normal));
            c.line(o, at(t, r * 0.95), lobe_col, 4.0);
        }
        None => {}
    }
    // The pixel's samples so far: the directions they bounced to and aimed at lights.
    let upto = trace.sample as usize;
    for s in mc.samples.iter().take(upto + 1) {
        let Some(h) = s.hit else {
            continue;
        };
        if let Some(b) = s.bounce {
            let (t, _) = fr.angle(Vec3::from(b));
            if t.abs() <= PI / 2.0 {
                c.line(at(t, r * 0.98), at(t, r * 1.03), th.muted, 1.5);
            }
        }
        for lp in &s.light_samples {
            let d = Vec3::from(lp.point) - Vec3::from(h);
            let (t, _) = fr.angle(d);
            if t.abs() <= PI / 2.0 {
                let col = if lp.blocked { th.blocked } else { th.shadow };
                c.line(at(t, r * 1.15), at(t, r * 1.2), col, 1.5);
            }
        }
    }
    // The normal and ωo.
    c.arrow(o, at(0.0, r * 0.55), th.normal, 2.0);
    let n_at = [at(0.0, r * 0.55)[0] + ts * 0.3, at(0.0, r * 0.55)[1]];
    c.text(n_at[0], n_at[1], small, "n", th.normal, Anchor::TopLeft);
    labels.block([n_at[0], n_at[1], n_at[0] + small, n_at[1] + small * 1.2]);
    let (wo_t, _) = fr.angle(fr.wo);
    c.arrow(o, at(wo_t, r * 0.8), th.ray, 2.0);
    // The sampled direction.
    let (dir, col, name): (Vec3, Rgba, &str) = match f.step {
        Step::LightSample {
            direction, blocked, ..
        } => (
            Vec3::from(*direction),
            if *blocked { th.blocked } else { th.shadow },
            "ωi to the light",
        ),
        Step::BsdfSample { direction, .. } => (Vec3::from(*direction), th.hit, "ωi sampled"),
        _ => (fr.normal, th.ink, ""),
    };
    let (dt, out) = fr.angle(dir);
    c.arrow(o, at(dt, r * 0.9), col, 3.5);
    // Each label in the longest wording that has a free place, else in its shortest anyway.
    let mut wordings = if out.abs() > 3.0 {
        let short = name.split(' ').next().unwrap_or(name);
        vec![
            format!("{name} ({} out of this plane)", deg(out)),
            format!("{name} ({} out of plane)", deg(out)),
            format!("{short} ({} out of plane)", deg(out)),
        ]
    } else {
        vec![]
    };
    wordings.push(name.to_string());
    if let Some(short) = name.split(' ').next().filter(|s| *s != name) {
        wordings.push(short.to_string());
    }
    c.circle(o, 4.0 * c.scale, Some(th.hit), Some(th.ink), 1.0);
    // The places: along the arrow, centred on it, beside it, or centred but moved in from the
    // canvas's edges.
    let width = c.width();
    let along = |theta: f32, text_w: f32| {
        let half = text_w / 2.0 + 6.0;
        let mut v = vec![];
        for k in [0.85, 0.65, 1.05, 0.45, 0.3] {
            let p = at(theta, r * k);
            v.push((p[0], p[1], Anchor::Center));
            v.push((p[0] + small * 0.6, p[1], Anchor::MiddleLeft));
            v.push((p[0] - small * 0.6, p[1], Anchor::MiddleRight));
            if half * 2.0 < width {
                v.push((p[0].clamp(half, width - half), p[1], Anchor::Center));
            }
        }
        v
    };
    let mut place = |c: &mut Canvas, texts: &[String], theta: f32, colour: Rgba| {
        for t in texts {
            let at = along(theta, c.text_width(t, small));
            if labels
                .place_if_free(c, &at, small, &Rich::default().plain(t), colour)
                .is_some()
            {
                return;
            }
        }
        if let Some(t) = texts.last() {
            let at = along(theta, c.text_width(t, small));
            labels.place(c, &at, small, &Rich::default().plain(t), colour);
        }
    };
    place(
        &mut c,
        &["ωo (to the eye)".to_string(), "ωo".to_string()],
        wo_t,
        th.ray,
    );
    place(&mut c, &wordings, dt, col);
    if let Some((p, text, colour)) = pdf_label {
        let h = small * 1.3;
        let corner = ts * 0.6;
        let candidates = [
            (p[0], p[1] - h - ts * 0.2, Anchor::TopCenter),
            (p[0] + small * 0.6, p[1] - h * 0.5, Anchor::MiddleLeft),
            (p[0] - small * 0.6, p[1] - h * 0.5, Anchor::MiddleRight),
            (p[0], p[1] + ts * 0.3, Anchor::TopCenter),
            (corner, top + corner * 0.3, Anchor::TopLeft),
            (c.width() - corner, top + corner * 0.3, Anchor::TopRight),
            (corner, o[1] - h - 4.0, Anchor::TopLeft),
            (c.width() - corner, o[1] - h - 4.0, Anchor::TopRight),
        ];
        labels.place(
            &mut c,
            &candidates,
            small,
            &Rich::default().plain(&text),
            colour,
        );
    }
    // The panel.
    let mut y = o[1] + ts * 0.8;
    for line in panel_lines {
        if y + small * 1.2 > c.height() {
            break;
        }
        c.text(ts * 0.8, y, small, &line, th.ink, Anchor::TopLeft);
        y += small * 1.35;
    }
    (c, labels.placed)
}

/// `text` split at spaces into lines no wider than `width` at `size`; a line after the first is
/// indented. A word wider than `width` is cut (with `…`).
fn wrap_plain(c: &Canvas, text: &str, size: f32, width: f32) -> Vec<String> {
    let mut lines: Vec<String> = vec![];
    let mut line = String::new();
    for word in text.split(' ') {
        let candidate = if line.is_empty() {
            if lines.is_empty() {
                word.to_string()
            } else {
                format!("  {word}")
            }
        } else {
            format!("{line} {word}")
        };
        if !line.is_empty() && c.text_width(&candidate, size) > width {
            lines.push(std::mem::replace(&mut line, format!("  {word}")));
        } else {
            line = candidate;
        }
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines.iter().map(|l| c.elide(l, size, width)).collect()
}

fn deg(a: f32) -> String {
    format!("{}°", fmt(a, Style::Decimals(1)))
}

fn v3(c: [f32; 3]) -> String {
    crate::record::number::v3_in(c, Style::Label)
}

/// The numbers under the drawing.
fn panel(f: &Focus, mc: &McRecord) -> Vec<String> {
    let mut out = vec![];
    let bsdf_text = match f.bsdf {
        Some(Bsdf::Diffuse { albedo }) => {
            format!(
                "diffuse, albedo {}: p(ωi) = cos θ / π",
                v3(albedo.to_array())
            )
        }
        Some(Bsdf::Glossy { alpha, .. }) => format!(
            "glossy (GGX), α = {}: p(ωi) = D(h) cos θh / (4 ωo·h)",
            fmt(alpha, Style::Label)
        ),
        Some(Bsdf::Mirror { .. }) => "mirror: one direction (a delta, no density)".into(),
        Some(Bsdf::Glass { ior }) => format!(
            "glass, index {}: two directions (deltas)",
            fmt(ior, Style::Label)
        ),
        None => "BSDF not recorded".into(),
    };
    out.push(format!("BSDF: {bsdf_text}"));
    let (wo_t, _) = f.frame.angle(f.frame.wo);
    out.push(format!(
        "ωo is {} from the normal",
        deg(wo_t.abs().to_degrees())
    ));
    match f.step {
        Step::LightSample {
            name,
            light,
            pdf,
            select_pdf,
            bsdf_pdf,
            cos,
            mis_weight,
            blocked,
            blocker,
            contribution,
            ..
        } => {
            let omega = mc
                .lights
                .iter()
                .filter(|l| mc.light(*light).is_some_and(|m| m.name == l.name))
                .map(|l| solid_angle(&l.shape, f.frame.point))
                .sum::<f32>();
            out.push(format!(
                "light \"{name}\": Ω = {} sr from here, picked with probability {}",
                fmt(omega, Style::Label),
                fmt(*select_pdf, Style::Label)
            ));
            out.push(format!(
                "pdf {} sr⁻¹ (the pick included); the BSDF's pdf there {}",
                fmt(*pdf, Style::Label),
                fmt(*bsdf_pdf, Style::Label),
            ));
            out.push(format!(
                "cos θ {}; MIS weight {}",
                fmt(*cos, Style::Label),
                fmt(*mis_weight, Style::Label)
            ));
            out.push(if *blocked {
                format!(
                    "blocked by \"{}\": adds nothing",
                    blocker.clone().unwrap_or_default()
                )
            } else {
                format!("reached: adds {} to the pixel", v3(*contribution))
            });
        }
        Step::BsdfSample {
            pdf,
            value,
            cos,
            weight,
            throughput,
            ..
        } => {
            out.push(format!(
                "pdf {}; f {}; cos θ {}",
                pdf.map_or_else(|| "— (a delta)".into(), |p| fmt(p, Style::Label)),
                v3(*value),
                fmt(*cos, Style::Label)
            ));
            out.push(format!(
                "weight f·cos θ / pdf = {}; the path's throughput now {}",
                v3(*weight),
                v3(*throughput)
            ));
        }
        _ => {}
    }
    out.push("ticks on the rim: the pixel's samples so far — where they bounced (inner),".into());
    out.push("where they aimed at lights (outer; light colour: reached, grey: blocked)".into());
    out
}
