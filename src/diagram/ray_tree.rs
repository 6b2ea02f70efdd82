//! The ray tree: primary → shadow / reflection / refraction rays, each with its kind, depth,
//! weight and the colour it contributed, laid out by depth.

use super::bvh_tree::kind_name;
use super::canvas::{Anchor, Canvas, Rgba};
use super::{ViewOptions, title};
use crate::render::image::srgb8;
use crate::trace::describe::num;
use crate::trace::{RayKind, RayRecord, Trace};

/// One ray box as drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct RayBox {
    /// Depth-first index of the ray in the trace (0 = primary).
    pub index: usize,
    /// Index of the parent ray.
    pub parent: Option<usize>,
    /// Box centre.
    pub pos: [f32; 2],
    /// Whether the ray had started by the focused step.
    pub shown: bool,
    /// Whether it owns the focused step.
    pub current: bool,
}

/// Lays out the colour rays (shadow rays are folded into their parent's box): one row per
/// depth, leaves spread evenly, parents centred over their children.
pub fn layout(trace: &Trace, opts: &ViewOptions, top: f32) -> Vec<RayBox> {
    let all = trace.rays();
    let rays: Vec<&RayRecord> = all
        .iter()
        .copied()
        .filter(|r| r.kind != RayKind::Shadow)
        .collect();
    let tl = trace.timeline();
    let first_step = |r: &RayRecord| tl.iter().position(|(rr, _)| std::ptr::eq(*rr, r));
    let focus_ray = opts
        .focus
        .and_then(|k| tl.get(k))
        .map(|(r, _)| *r as *const RayRecord);
    let mut parent = vec![None; rays.len()];
    let mut depth = vec![0usize; rays.len()];
    for (i, r) in rays.iter().enumerate() {
        for c in &r.children {
            if let Some(j) = rays.iter().position(|x| std::ptr::eq(*x, c)) {
                parent[j] = Some(i);
                depth[j] = depth[i] + 1;
            }
        }
    }
    let mut xs = vec![0.0f32; rays.len()];
    let mut order = 0usize;
    fn place(i: usize, parent: &[Option<usize>], xs: &mut [f32], order: &mut usize) -> f32 {
        let kids: Vec<usize> = (0..parent.len())
            .filter(|j| parent[*j] == Some(i))
            .collect();
        let x = if kids.is_empty() {
            *order += 1;
            *order as f32 - 1.0
        } else {
            let v: Vec<f32> = kids.iter().map(|k| place(*k, parent, xs, order)).collect();
            v.iter().sum::<f32>() / v.len() as f32
        };
        xs[i] = x;
        x
    }
    place(0, &parent, &mut xs, &mut order);
    let slots = order.max(1) as f32;
    let max_depth = depth.iter().copied().max().unwrap_or(0).max(1) as f32;
    let (w, h) = (opts.width as f32, opts.height as f32);
    let bottom = h * 0.78;
    rays.iter()
        .enumerate()
        .map(|(i, r)| {
            let shown = match (opts.focus, first_step(r)) {
                (Some(k), Some(f)) => f <= k,
                (Some(_), None) => false,
                (None, _) => true,
            };
            // A shadow ray's steps count as its parent's for highlighting.
            let owns_focus = focus_ray == Some(*r as *const RayRecord)
                || r.children
                    .iter()
                    .any(|c| c.kind == RayKind::Shadow && focus_ray == Some(c as *const RayRecord));
            RayBox {
                index: i,
                parent: parent[i],
                pos: [
                    w * 0.04 + (xs[i] + 0.5) / slots * w * 0.92,
                    top + depth[i] as f32 / max_depth * (bottom - top),
                ],
                shown,
                current: owns_focus,
            }
        })
        .collect()
}

fn kind_color(c: &Canvas, k: RayKind) -> Rgba {
    match k {
        RayKind::Primary => c.theme.ray,
        RayKind::Shadow => c.theme.shadow,
        RayKind::Reflection => c.theme.reflect,
        RayKind::Refraction => c.theme.refract,
    }
}

/// Shortens `text` with an ellipsis until it fits `width` at `size`.
fn fit(c: &Canvas, text: &str, size: f32, width: f32) -> String {
    let mut line = text.to_string();
    while c.text_width(&line, size) > width && line.chars().count() > 2 {
        line.pop();
        line.pop();
        line.push('…');
    }
    line
}

/// Draws the ray tree.
pub fn draw(trace: &Trace, opts: &ViewOptions) -> Canvas {
    let mut c = Canvas::new(opts.width, opts.height, opts.theme);
    let th = c.theme;
    let ts = c.text_size;
    let top = title(
        &mut c,
        &format!(
            "Ray tree of pixel ({}, {}), sample {}",
            trace.pixel[0], trace.pixel[1], trace.sample
        ),
    ) + ts * 1.2;
    let rays: Vec<&RayRecord> = trace
        .rays()
        .into_iter()
        .filter(|r| r.kind != RayKind::Shadow)
        .collect();
    let boxes = layout(trace, opts, top);
    let leaves = boxes
        .iter()
        .filter(|b| !boxes.iter().any(|o| o.parent == Some(b.index)))
        .count()
        .max(1);
    let levels = boxes
        .iter()
        .map(|b| b.pos[1])
        .fold(Vec::<f32>::new(), |mut v, y| {
            if !v.iter().any(|u| (u - y).abs() < 0.5) {
                v.push(y);
            }
            v
        });
    // Boxes shrink to fit the columns and rows; text shrinks with them.
    let col_w = opts.width as f32 * 0.92 / leaves as f32;
    let row_h = if levels.len() > 1 {
        (opts.height as f32 * 0.78 - top) / (levels.len() - 1) as f32
    } else {
        ts * 6.0
    };
    let small = (ts * 0.72).min(col_w / 11.0).min(row_h / 5.2).max(6.0);
    let bw = (col_w * 0.92).min(small * 17.0);
    let max_lights = rays
        .iter()
        .map(|r| {
            r.children
                .iter()
                .filter(|c| c.kind == RayKind::Shadow)
                .count()
        })
        .max()
        .unwrap_or(0);
    // Header 1.45, hit line 1.2, a line per light 1.1, the colour swatch 1.3 (in text heights).
    let bh = small * (4.3 + 1.1 * max_lights.min(3) as f32);
    let top_of = |b: &RayBox| b.pos[1] - small * 0.2;
    for b in &boxes {
        if let Some(p) = b.parent
            && b.shown
        {
            let (a, z) = (boxes[p].pos, b.pos);
            let col = kind_color(&c, rays[b.index].kind);
            c.arrow(
                [a[0], top_of(&boxes[p]) + bh],
                [z[0], top_of(b)],
                col,
                (small / 5.0).max(1.2),
            );
            let w = rays[b.index].weight;
            if w != 0.0 && w != 1.0 {
                let mid = [
                    (a[0] + z[0]) / 2.0,
                    (top_of(&boxes[p]) + bh + top_of(b)) / 2.0,
                ];
                c.label(
                    mid[0],
                    mid[1],
                    small * 0.95,
                    &format!("× {}", short(w)),
                    col,
                    Anchor::Center,
                );
            }
        }
    }
    for b in boxes.iter().filter(|b| b.shown) {
        let r = rays[b.index];
        let col = kind_color(&c, r.kind);
        let (x0, y0) = (b.pos[0] - bw / 2.0, top_of(b));
        c.rect(x0, y0, bw, bh, th.background);
        c.rect_outline(
            x0,
            y0,
            bw,
            bh,
            if b.current { th.ink } else { col },
            if b.current { 3.0 } else { 1.5 },
            false,
        );
        c.rect(x0, y0, bw, small * 1.45, col);
        let head = fit(
            &c,
            &format!("{} · depth {}", kind_name(r.kind), r.depth),
            small,
            bw - 4.0,
        );
        c.text(
            b.pos[0],
            y0 + small * 0.18,
            small,
            &head,
            th.background,
            Anchor::TopCenter,
        );
        let what = match &r.hit {
            Some(h) => format!("{} t={}", h.name, short(h.t)),
            None => "miss: background".into(),
        };
        let line = fit(&c, &what, small, bw - 6.0);
        c.text(
            b.pos[0],
            y0 + small * 1.65,
            small,
            &line,
            th.ink,
            Anchor::TopCenter,
        );
        let mut y = y0 + small * 2.85;
        for sh in r
            .children
            .iter()
            .filter(|c| c.kind == RayKind::Shadow)
            .take(3)
        {
            let (mark, mc) = match &sh.hit {
                Some(h) => (format!("light blocked by {}", h.name), th.blocked),
                None => ("light visible".to_string(), th.shadow),
            };
            let t = fit(&c, &mark, small * 0.9, bw - 6.0);
            c.text(b.pos[0], y, small * 0.9, &t, mc, Anchor::TopCenter);
            y += small * 1.1;
        }
        let sw = small;
        let rgb = [srgb8(r.color[0]), srgb8(r.color[1]), srgb8(r.color[2]), 255];
        let label = fit(
            &c,
            &format!(
                "({}, {}, {})",
                short(r.color[0]),
                short(r.color[1]),
                short(r.color[2])
            ),
            small * 0.9,
            bw - sw - 10.0,
        );
        let tw = c.text_width(&label, small * 0.9);
        let x = b.pos[0] - (sw + 4.0 + tw) / 2.0;
        c.rect(x, y, sw, sw, rgb);
        c.rect_outline(x, y, sw, sw, th.muted, 1.0, false);
        c.text(
            x + sw + 4.0,
            y,
            small * 0.9,
            &label,
            th.muted,
            Anchor::TopLeft,
        );
    }
    // Legend and the final colour.
    let y = opts.height as f32 - ts * 1.6;
    let mut x = ts;
    for k in [RayKind::Primary, RayKind::Reflection, RayKind::Refraction] {
        let col = kind_color(&c, k);
        c.rect(x, y + ts * 0.15, ts * 0.8, ts * 0.8, col);
        x += ts * 1.1;
        x += c.text(x, y, ts * 0.8, kind_name(k), th.ink, Anchor::TopLeft) + ts * 1.0;
    }
    let col = trace.color;
    c.text(
        opts.width as f32 - ts,
        y,
        ts * 0.8,
        &format!(
            "pixel colour ({}, {}, {})",
            short(col[0]),
            short(col[1]),
            short(col[2])
        ),
        th.ink,
        Anchor::TopRight,
    );
    c
}

/// A number to 3 decimals for labels (the panels show the exact values).
fn short(x: f32) -> String {
    if x.is_finite() {
        let s = format!("{x:.3}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if s == "-0" { "0".into() } else { s.into() }
    } else {
        num(x)
    }
}
