//! The slice's colours (materials, boxes, the theme) and its legend's entries and flow.

use super::*;

pub(super) fn mix(a: Rgba, b: Rgba, t: f32) -> Rgba {
    let m = |x: u8, y: u8| (x as f32 + (y as f32 - x as f32) * t).round() as u8;
    [m(a[0], b[0]), m(a[1], b[1]), m(a[2], b[2]), m(a[3], b[3])]
}

pub(super) fn luminance(c: Rgba) -> f32 {
    (0.2126 * c[0] as f32 + 0.7152 * c[1] as f32 + 0.0722 * c[2] as f32) / 255.0
}

pub(super) fn dark_theme(c: &Canvas) -> bool {
    luminance(c.theme.background) < 0.5
}

/// The least contrast ratio of text against the background (WCAG 2's AA level for body text):
/// every text the slice draws is made at least this distinct from the background by
/// [`readable`].
pub(super) const MIN_CONTRAST: f32 = 4.5;

/// WCAG 2's relative luminance of an sRGB colour (alpha ignored).
fn relative_luminance(c: Rgba) -> f32 {
    let lin = |v: u8| {
        let s = v as f32 / 255.0;
        if s <= 0.040_45 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    };
    0.2126 * lin(c[0]) + 0.7152 * lin(c[1]) + 0.0722 * lin(c[2])
}

/// WCAG 2's contrast ratio of two colours, 1 … 21.
pub(super) fn contrast(a: Rgba, b: Rgba) -> f32 {
    let (la, lb) = (relative_luminance(a), relative_luminance(b));
    (la.max(lb) + 0.05) / (la.min(lb) + 0.05)
}

/// A text colour that reads on `bg`: `c`, opaque, moved towards `ink` (else black or white)
/// just far enough to reach [`MIN_CONTRAST`] against `bg`; colours that already reach it keep
/// their hue and shade, so an orange hit label stays orange, only darker on white.
pub(super) fn readable(c: Rgba, bg: Rgba, ink: Rgba) -> Rgba {
    let c = [c[0], c[1], c[2], 255];
    if contrast(c, bg) >= MIN_CONTRAST {
        return c;
    }
    let target = if contrast(ink, bg) >= MIN_CONTRAST + 1.0 {
        [ink[0], ink[1], ink[2], 255]
    } else if relative_luminance(bg) > 0.18 {
        [0, 0, 0, 255]
    } else {
        [255, 255, 255, 255]
    };
    // The least mix that reaches it: contrast grows along the way (towards the far end of
    // the luminance scale), so a bisection finds it; the rounding to bytes is checked at the end.
    let (mut lo, mut hi) = (0.0_f32, 1.0_f32);
    for _ in 0..20 {
        let mid = 0.5 * (lo + hi);
        if contrast(mix(c, target, mid), bg) >= MIN_CONTRAST {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let mut t = hi;
    while t < 1.0 && contrast(mix(c, target, t), bg) < MIN_CONTRAST {
        t = (t + 0.01).min(1.0);
    }
    mix(c, target, t)
}

/// The size of secondary text (labels, the caption, the legend, the scale bar, the axes): 16 px
/// at 800×600 and UI scale 1, never under 13.6 px at scale 1 however small the canvas.
pub(super) fn label_size(c: &Canvas) -> f32 {
    c.text_size * 0.85
}

/// A material's linear colour, sRGB-encoded and pushed away from the background so that a
/// white floor still shows on white paper (and a black ball on black).
pub(super) fn material_color(c: &Canvas, lin: [f32; 3]) -> Rgba {
    let enc = |x: f32| {
        let x = x.clamp(0.0, 1.0);
        let s = if x <= 0.003_130_8 {
            12.92 * x
        } else {
            1.055 * x.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0).round() as u8
    };
    let rgb: Rgba = [enc(lin[0]), enc(lin[1]), enc(lin[2]), 255];
    let l = luminance(rgb);
    if dark_theme(c) {
        if l < 0.45 {
            mix(rgb, [255, 255, 255, 255], (0.45 - l) / (1.0 - l).max(0.01))
        } else {
            rgb
        }
    } else if l > 0.55 {
        let k = 0.55 / l;
        [
            (rgb[0] as f32 * k) as u8,
            (rgb[1] as f32 * k) as u8,
            (rgb[2] as f32 * k) as u8,
            255,
        ]
    } else {
        rgb
    }
}

/// BVH boxes: violet, apart from every ray colour.
pub(super) fn box_color(c: &Canvas) -> Rgba {
    if dark_theme(c) {
        [200, 150, 255, 255]
    } else {
        [130, 60, 190, 255]
    }
}

// ---------------------------------------------------------------------------------------------
// Legend and header.

#[derive(Debug, Clone, Copy)]
pub(super) enum Sample {
    Line(Rgba, bool),
    Arrow(Rgba),
    Dot(Rgba),
    Light,
    /// A box outline: the BVH colour (None) or a given one, dashed or not.
    Box(Option<Rgba>, bool),
}

pub(super) fn legend_entries(
    trace: &Trace,
    info: &RayInfos,
    opts: &ViewOptions,
) -> Vec<(Sample, String)> {
    let t = &opts.theme;
    let rays = &info.rays;
    let any = |f: &dyn Fn(&RayRecord) -> bool| rays.iter().any(|r| f(r.ray));
    let mut e = vec![(Sample::Line(t.ray, false), "primary ray".to_string())];
    if any(&|r| r.kind == RayKind::Shadow && r.hit.is_none()) {
        e.push((Sample::Line(t.shadow, false), "shadow ray".into()));
    }
    if any(&|r| r.kind == RayKind::Shadow && r.hit.is_some()) {
        e.push((Sample::Line(t.blocked, true), "blocked".into()));
    }
    if any(&|r| r.kind == RayKind::Reflection) {
        e.push((Sample::Line(t.reflect, false), "reflection".into()));
    }
    if any(&|r| r.kind == RayKind::Refraction) {
        e.push((Sample::Line(t.refract, false), "refraction".into()));
    }
    if any(&|r| r.kind != RayKind::Shadow && r.hit.is_some()) {
        e.push((Sample::Dot(t.hit), "hit".into()));
        e.push((Sample::Arrow(t.normal), "normal".into()));
    }
    if !trace.lights.is_empty() {
        e.push((Sample::Light, "light".into()));
    }
    let nodes = node_visits(info, info.box_ray(), false);
    if nodes.iter().any(|(_, n)| n.action != NodeAction::Culled) {
        e.push((Sample::Box(None, false), "BVH box (visit order)".into()));
    }
    let steps = &info.rays[info.box_ray()].ray.steps;
    if steps.iter().any(|s| matches!(s.step, Step::Cell { .. })) {
        e.push((Sample::Box(None, false), "grid cell (walk order)".into()));
    }
    if steps
        .iter()
        .any(|s| matches!(s.step, Step::SphereNode { action, .. } if action != NodeAction::Culled))
    {
        e.push((Sample::Box(None, false), "bounding sphere".into()));
    }
    if nodes.iter().any(|(_, n)| n.action == NodeAction::Culled)
        || steps.iter().any(|s| {
            matches!(
                s.step,
                Step::SphereNode {
                    action: NodeAction::Culled,
                    ..
                }
            )
        })
    {
        e.push((Sample::Box(Some(t.faded), true), "culled".into()));
    }
    if opts.focus.is_some() {
        e.push((
            Sample::Line(mix(t.ray, t.faded, 0.72), false),
            "earlier".into(),
        ));
    }
    e
}

/// The legend's entries if they fit in a third of the canvas's height, else none: on a small
/// canvas (a narrow panel, a small window) the picture comes first, and a legend wrapped to one
/// entry per row would leave it a strip.
pub(super) fn fitting_legend(
    c: &Canvas,
    trace: &Trace,
    info: &RayInfos,
    opts: &ViewOptions,
) -> Vec<(Sample, String)> {
    let entries = legend_entries(trace, info, opts);
    let (height, _) = legend_flow(c, &entries);
    if height > c.height() / 3.0 {
        vec![]
    } else {
        entries
    }
}

pub(super) fn legend_size(c: &Canvas) -> f32 {
    label_size(c)
}

/// Lays the legend out in rows; returns (the rows' total height, the row count).
pub(super) fn legend_flow(c: &Canvas, entries: &[(Sample, String)]) -> (f32, f32) {
    let size = legend_size(c);
    let rows = legend_rows(c, entries).len() as f32;
    (rows * size * 1.5 + size * 0.4, rows)
}

pub(super) fn legend_rows(c: &Canvas, entries: &[(Sample, String)]) -> Vec<Vec<usize>> {
    let size = legend_size(c);
    let avail = c.width() - size * 2.0;
    let mut rows: Vec<Vec<usize>> = vec![vec![]];
    let mut x = 0.0;
    for (i, (_, text)) in entries.iter().enumerate() {
        let w = legend_item_width(c, text);
        if x + w > avail && !rows.last().is_some_and(|r| r.is_empty()) {
            rows.push(vec![]);
            x = 0.0;
        }
        rows.last_mut().expect("a row").push(i);
        x += w;
    }
    rows
}

pub(super) fn legend_item_width(c: &Canvas, text: &str) -> f32 {
    let size = legend_size(c);
    size * 2.2 + size * 0.4 + c.text_width(text, size) + size * 1.2
}

pub(super) fn header_height(c: &Canvas) -> f32 {
    let ts = c.text_size;
    ts * 0.6 + ts * 1.15 * 1.5 + ts * 0.85 * 1.4
}

// ---------------------------------------------------------------------------------------------
// Drawing.
