//! The area light a light sample aimed at, with the points the pixel's samples drew on it: a
//! triangle light (and the other triangles of its object) in its own plane, a sphere light as
//! its disc seen from the shading point. A point whose shadow ray reached the shading point is a
//! dot in the light's colour, a blocked one a grey ✕; the focused step's point is ringed, with
//! its density. Drawn from the trace's Monte Carlo record.

use super::canvas::{Anchor, Canvas, with_alpha};
use super::{ViewOptions, pick_step, title_first_fitting};
use crate::mc::lights::LightShape;
use crate::record::number::{Style, fmt};
use crate::record::samples::{McRecord, TraceLight};
use crate::record::{Step, Trace};
use glam::{Vec2, Vec3};

/// Whether a step is a light sample on an area light the trace keeps.
fn on_area_light(mc: &McRecord, s: &Step) -> bool {
    matches!(s, Step::LightSample { light, .. }
        if mc.light(*light).is_some_and(|l| !matches!(l.shape, LightShape::Point { .. })))
}

/// Whether the trace has a light sample on an area light.
pub fn has_area_light(trace: &Trace) -> bool {
    trace
        .monte_carlo
        .as_ref()
        .is_some_and(|mc| pick_step(trace, None, |s| on_area_light(mc, s)).is_some())
}

/// How a sampled point is marked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mark {
    /// Its shadow ray reached the shading point: a dot.
    Reached,
    /// Something was in the way: a cross.
    Blocked,
    /// It added nothing without a shadow ray (below the shading point's horizon, or the
    /// light's back faces it): a ring.
    Nothing,
}

/// Whether two lights are triangles in one plane, facing the same way.
fn coplanar(a: &LightShape, b: &LightShape) -> bool {
    let (
        LightShape::Triangle {
            p: pa, normal: na, ..
        },
        LightShape::Triangle {
            p: pb, normal: nb, ..
        },
    ) = (a, b)
    else {
        return false;
    };
    let size = (pa[1] - pa[0]).length().max((pa[2] - pa[0]).length());
    na.dot(*nb) > 0.9999
        && pb
            .iter()
            .all(|q| na.dot(*q - pa[0]).abs() <= 1e-4 * size.max(1e-6))
}

/// The plane the light is drawn in: an origin and two unit axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightPlane {
    /// The origin (a triangle's first vertex, a sphere's centre).
    pub origin: Vec3,
    /// Right in the drawing.
    pub u: Vec3,
    /// Up in the drawing.
    pub v: Vec3,
}

impl LightPlane {
    /// For a triangle, its own plane; for a sphere, the plane through its centre facing `eye`.
    pub fn new(shape: &LightShape, eye: Vec3) -> LightPlane {
        match *shape {
            LightShape::Triangle { p, normal, .. } => {
                let u = (p[1] - p[0]).normalize_or(normal.any_orthonormal_vector());
                LightPlane {
                    origin: p[0],
                    u,
                    v: normal.cross(u).normalize_or(u.any_orthonormal_vector()),
                }
            }
            LightShape::Sphere { center, .. } | LightShape::Point { position: center } => {
                let axis = (center - eye).normalize_or(Vec3::Z);
                let u = axis.any_orthonormal_vector();
                LightPlane {
                    origin: center,
                    u,
                    v: axis.cross(u),
                }
            }
        }
    }

    /// A point's coordinates in the plane (projected along its normal).
    pub fn project(&self, p: Vec3) -> Vec2 {
        let d = p - self.origin;
        Vec2::new(d.dot(self.u), d.dot(self.v))
    }
}

/// Draws the area-light diagram for the focused (or first) light sample on an area light.
pub fn draw(trace: &Trace, opts: &ViewOptions) -> Canvas {
    let mut c = Canvas::for_view(opts);
    let th = c.theme;
    let ts = c.text_size;
    let found = trace.monte_carlo.as_ref().and_then(|mc| {
        let (k, step) = pick_step(trace, opts.focus, |s| on_area_light(mc, s))?;
        let ray = trace.timeline().get(k)?.0;
        Some((mc, step, ray))
    });
    let Some((
        mc,
        Step::LightSample {
            light,
            name,
            point,
            pdf,
            select_pdf,
            blocked,
            blocker,
            ..
        },
        ray,
    )) = found
    else {
        c.text(
            ts,
            ts,
            ts,
            "no light sample on an area light in this trace",
            th.muted,
            Anchor::TopLeft,
        );
        return c;
    };
    let Some(focused) = mc.light(*light) else {
        return c;
    };
    let shading = ray
        .steps
        .iter()
        .find_map(|s| match s.step {
            Step::Surface { point, .. } => Some(Vec3::from(point)),
            _ => None,
        })
        .unwrap_or(Vec3::from(ray.origin));
    // The light's object: lights of its name, and the triangles in its plane (a quad light is
    // two triangle objects).
    let group: Vec<&TraceLight> = mc
        .lights
        .iter()
        .filter(|l| l.name == *name || coplanar(&focused.shape, &l.shape))
        .collect();
    let plane = LightPlane::new(&focused.shape, shading);
    // The outlines to draw, in plane coordinates: the focused light's first, then at most
    // MAX_OUTLINES of its object (a mesh lamp of 100,000 triangles drew each one, about 0.7 ms
    // apiece: 70 s), the rest counted in the title.
    const MAX_OUTLINES: usize = 512;
    let mut drawn: Vec<&TraceLight> = vec![focused];
    drawn.extend(
        group
            .iter()
            .filter(|l| l.index != focused.index)
            .take(MAX_OUTLINES - 1),
    );
    let not_drawn = group.len().saturating_sub(drawn.len());
    let mut outlines: Vec<Vec<Vec2>> = vec![];
    for l in &drawn {
        match l.shape {
            LightShape::Triangle { p, .. } => {
                outlines.push(p.iter().map(|v| plane.project(*v)).collect());
            }
            LightShape::Sphere { center, radius } => {
                let c0 = plane.project(center);
                outlines.push(
                    (0..48)
                        .map(|i| {
                            let a = std::f32::consts::TAU * i as f32 / 48.0;
                            c0 + radius * Vec2::new(a.cos(), a.sin())
                        })
                        .collect(),
                );
            }
            LightShape::Point { .. } => {}
        }
    }
    // Every point the pixel's samples drew on this light's object.
    // A set: a hostile or huge trace holds 100,000 lights and as many points (each point
    // looked up in a list made that quadratic: 87 s for such a trace).
    let ids: std::collections::HashSet<u32> = group.iter().map(|l| l.index).collect();
    // The samples after the traced one are drawn faded: playing the samples one at a time, the
    // points build up.
    let upto = trace.sample;
    let points: Vec<(Vec2, Mark, bool)> = mc
        .samples
        .iter()
        .flat_map(|s| s.light_samples.iter().map(move |lp| (s.sample <= upto, lp)))
        .filter(|(_, lp)| ids.contains(&lp.light))
        .map(|(so_far, lp)| {
            let mark = if lp.blocked {
                Mark::Blocked
            } else if lp.contribution.iter().all(|c| *c == 0.0) {
                Mark::Nothing
            } else {
                Mark::Reached
            };
            (plane.project(Vec3::from(lp.point)), mark, so_far)
        })
        .collect();
    let n_blocked = points.iter().filter(|p| p.1 == Mark::Blocked).count();
    let others = group.iter().filter(|l| l.name != *name).count();
    let mut also = match others {
        0 => String::new(),
        1 => " and the light beside it".to_string(),
        n => format!(" and {n} lights in its plane"),
    };
    if not_drawn > 0 {
        also += &format!(" ({not_drawn} of its outlines not drawn)");
    }
    let top = title_first_fitting(
        &mut c,
        &[
            format!(
                "Light \"{name}\"{also}: {} points the pixel's {} samples drew on it, {n_blocked} blocked",
                points.len(),
                mc.samples.len()
            ),
            format!(
                "Light \"{name}\"{also}: {} points, {n_blocked} blocked",
                points.len()
            ),
            format!("Light \"{name}\""),
        ],
    );
    // Fit the outlines to the canvas, keeping the aspect.
    let small = ts * 0.85;
    let panel_h = small * 1.35 * 4.0 + ts * 0.8;
    let area = [
        ts * 1.5,
        top + ts * 0.5,
        c.width() - ts * 1.5,
        c.height() - panel_h,
    ];
    let all: Vec<Vec2> = outlines.iter().flatten().copied().collect();
    let lo = all
        .iter()
        .copied()
        .fold(Vec2::splat(f32::INFINITY), Vec2::min);
    let hi = all
        .iter()
        .copied()
        .fold(Vec2::splat(f32::NEG_INFINITY), Vec2::max);
    let span = (hi - lo).max(Vec2::splat(1e-6));
    let scale = ((area[2] - area[0]) / span.x).min((area[3] - area[1]) / span.y);
    if !(scale.is_finite() && scale > 0.0) {
        return c;
    }
    let mid = (lo + hi) / 2.0;
    let centre = [(area[0] + area[2]) / 2.0, (area[1] + area[3]) / 2.0];
    let to_px = |p: Vec2| {
        let d = (p - mid) * scale;
        [centre[0] + d.x, centre[1] - d.y]
    };
    for o in &outlines {
        let pts: Vec<[f32; 2]> = o.iter().map(|p| to_px(*p)).collect();
        c.polygon(&pts, Some(with_alpha(th.light, 50)), Some(th.light), 2.0);
    }
    let r = 3.5 * c.scale;
    for (p, m, so_far) in &points {
        let q = to_px(*p);
        let a = |col: super::canvas::Rgba| if *so_far { col } else { with_alpha(col, 70) };
        match m {
            Mark::Blocked => {
                let col = a(th.blocked);
                c.line([q[0] - r, q[1] - r], [q[0] + r, q[1] + r], col, 2.0);
                c.line([q[0] - r, q[1] + r], [q[0] + r, q[1] - r], col, 2.0);
            }
            Mark::Reached => c.circle(q, r, Some(a(th.shadow)), Some(a(th.ink)), 1.0),
            Mark::Nothing => c.circle(q, r, None, Some(a(th.muted)), 1.5),
        }
    }
    let q = to_px(plane.project(Vec3::from(*point)));
    c.circle(q, r * 2.6, None, Some(th.hit), 2.5);
    // The panel.
    let area_text = match focused.shape {
        LightShape::Triangle { area, .. } => format!(
            "sampled uniformly by area: 1/A = 1/{} per unit area",
            fmt(area, Style::Label)
        ),
        LightShape::Sphere { .. } => {
            "sampled uniformly in the cone it subtends from the shading point".to_string()
        }
        LightShape::Point { .. } => String::new(),
    };
    let this = if *blocked {
        format!(
            "ringed: this step's point, blocked by \"{}\"",
            blocker.clone().unwrap_or_default()
        )
    } else {
        "ringed: this step's point, which reached the shading point".to_string()
    };
    let lines = [
        this,
        area_text,
        format!(
            "pdf {} sr⁻¹, the light's pick ({}) included",
            fmt(*pdf, Style::Label),
            fmt(*select_pdf, Style::Label)
        ),
    ];
    let mut y = area[3] + ts * 0.5;
    // The legend: the marks as drawn, then their words.
    let mut x = ts * 0.8;
    let mid = y + small * 0.6;
    c.circle([x + r, mid], r, Some(th.shadow), Some(th.ink), 1.0);
    x += r * 2.0 + small * 0.4;
    x += c.text(x, y, small, "reached", th.ink, Anchor::TopLeft) + small;
    c.line([x, mid - r], [x + 2.0 * r, mid + r], th.blocked, 2.0);
    c.line([x, mid + r], [x + 2.0 * r, mid - r], th.blocked, 2.0);
    x += r * 2.0 + small * 0.4;
    x += c.text(x, y, small, "blocked", th.ink, Anchor::TopLeft) + small;
    c.circle([x + r, mid], r, None, Some(th.muted), 1.5);
    x += r * 2.0 + small * 0.4;
    let words = c.elide(
        "adds nothing (below the horizon, or the light's back)",
        small,
        (c.width() - x - ts * 0.6).max(0.0),
    );
    c.text(x, y, small, &words, th.ink, Anchor::TopLeft);
    y += small * 1.35;
    for line in lines {
        let shown = c.elide(&line, small, c.width() - ts * 1.6);
        c.text(ts * 0.8, y, small, &shown, th.ink, Anchor::TopLeft);
        y += small * 1.35;
    }
    c
}
