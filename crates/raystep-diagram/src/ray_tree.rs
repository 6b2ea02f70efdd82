//! The ray tree: primary → reflection / refraction rays, each box with its kind, depth, what it
//! hit, its shadow rays' verdicts and the colour it contributed; each edge with the weight the
//! child's colour is multiplied by.
//!
//! The boxes are laid out as a tidy tree (Reingold and Tilford, "Tidier drawings of trees",
//! 1981): one row per depth, each subtree placed as close to its left sibling as their contours
//! allow, parents centred over their children. Boxes never overlap, and a chain of rays does not
//! widen the tree as a leaf-per-column layout would. When the tree is larger than the canvas
//! everything (boxes, text, gaps) shrinks by one factor, so the picture stays free of overlaps.
//! (Hand-written: the layout crates on crates.io lay out general graphs, not boxes of one size
//! in depth rows, and this is a few dozen lines.)

use super::canvas::{Anchor, Canvas, Rgba};
use super::{ViewOptions, title};
use crate::record::number::{Style, fmt};
use crate::record::{RayKind, RayRecord, Trace};
use crate::render::image::srgb8;
use std::collections::HashMap;

/// One ray box as drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct RayBox {
    /// Depth-first index of the ray among the colour rays (0 = primary).
    pub index: usize,
    /// Index of the parent ray.
    pub parent: Option<usize>,
    /// The centre of the box's top edge.
    pub pos: [f32; 2],
    /// The box: [x0, y0, x1, y1].
    pub rect: [f32; 4],
    /// Whether the ray had started by the focused step.
    pub shown: bool,
    /// Whether it owns the focused step.
    pub current: bool,
}

/// Sizes shared by every box (they shrink together when the tree does not fit).
#[derive(Debug, Clone, Copy)]
struct Metrics {
    /// Text size inside the boxes.
    text: f32,
    /// Box width and height.
    bw: f32,
    bh: f32,
    /// Gap between neighbouring boxes of a row, and between rows.
    hgap: f32,
    vgap: f32,
}

/// The colour rays (shadow rays are folded into their parent's box), their parents and depths.
fn colour_rays(trace: &Trace) -> (Vec<&RayRecord>, Vec<Option<usize>>, Vec<usize>) {
    let rays: Vec<&RayRecord> = trace
        .rays()
        .into_iter()
        .filter(|r| r.kind != RayKind::Shadow)
        .collect();
    let index: HashMap<*const RayRecord, usize> = rays
        .iter()
        .enumerate()
        .map(|(i, r)| (*r as *const RayRecord, i))
        .collect();
    let mut parent = vec![None; rays.len()];
    let mut depth = vec![0usize; rays.len()];
    // Pre-order: a parent comes before its children, so its depth is known.
    for (i, r) in rays.iter().enumerate() {
        for c in &r.children {
            if let Some(&j) = index.get(&(c as *const RayRecord)) {
                parent[j] = Some(i);
                depth[j] = depth[i] + 1;
            }
        }
    }
    (rays, parent, depth)
}

/// A subtree's contour: per depth below its root (0 = the root's row), the leftmost and the
/// rightmost box edge, relative to the root's centre.
struct Contour {
    left: Vec<f32>,
    right: Vec<f32>,
}

/// Reingold–Tilford: the x offset of every node from its parent (`rel`), in units where a box
/// is `bw` wide and neighbours keep `gap` apart; returns the contour of the subtree at `i`.
fn tidy(i: usize, kids: &[Vec<usize>], bw: f32, gap: f32, rel: &mut [f32]) -> Contour {
    let half = bw / 2.0;
    let children = &kids[i];
    if children.is_empty() {
        return Contour {
            left: vec![-half],
            right: vec![half],
        };
    }
    let mut pos: Vec<f32> = Vec::with_capacity(children.len());
    let mut acc = Contour {
        left: vec![],
        right: vec![],
    };
    for &k in children {
        let ck = tidy(k, kids, bw, gap, rel);
        // As far left as the rows both subtrees reach allow.
        let x = if pos.is_empty() {
            0.0
        } else {
            acc.right
                .iter()
                .zip(&ck.left)
                .map(|(r, l)| r + gap - l)
                .fold(f32::NEG_INFINITY, f32::max)
        };
        for (d, (l, r)) in ck.left.iter().zip(&ck.right).enumerate() {
            if d < acc.left.len() {
                acc.right[d] = x + r;
            } else {
                acc.left.push(x + l);
                acc.right.push(x + r);
            }
        }
        pos.push(x);
    }
    let mid = (pos[0] + pos[pos.len() - 1]) / 2.0;
    for (&k, &x) in children.iter().zip(&pos) {
        rel[k] = x - mid;
    }
    let mut out = Contour {
        left: vec![-half],
        right: vec![half],
    };
    out.left.extend(acc.left.iter().map(|x| x - mid));
    out.right.extend(acc.right.iter().map(|x| x - mid));
    out
}

/// The box text size and sizes for a canvas: text as large as the canvas's labels, boxes wide
/// enough for their widest line (within limits).
fn metrics(c: &Canvas, rays: &[&RayRecord]) -> Metrics {
    let text = (c.text_size * 0.85).max(13.0 * c.scale);
    let widest = rays
        .iter()
        .flat_map(|r| box_lines(r))
        .map(|(s, _)| c.text_width(&s, text))
        .fold(0.0, f32::max);
    let bw = (widest + text).clamp(text * 9.0, text * 20.0);
    let lights = rays.iter().map(|r| shadow_lines(r)).max().unwrap_or(0);
    Metrics {
        text,
        bw,
        bh: box_height(text, lights),
        hgap: text * 1.0,
        vgap: text * 1.9,
    }
}

/// Box height for `lights` shadow lines: header, hit line, the lights, the colour line (the
/// line pitches of [`draw`]).
fn box_height(text: f32, lights: usize) -> f32 {
    text * (0.15 + HEADER + LINE * (1 + lights) as f32 + 1.3)
}

/// The header band's height and the pitch of the lines below it, in text sizes.
const HEADER: f32 = 1.45;
const LINE: f32 = 1.2;

/// How many shadow-ray lines a box shows (at most three).
fn shadow_lines(r: &RayRecord) -> usize {
    r.children
        .iter()
        .filter(|c| c.kind == RayKind::Shadow)
        .count()
        .min(3)
}

/// The lines of a box's text (after the header), with whether each is a shadow line.
fn box_lines(r: &RayRecord) -> Vec<(String, bool)> {
    let mut out = vec![(format!("{} · depth {}", r.kind.name(), r.depth), false)];
    out.push((
        match &r.hit {
            Some(h) => format!("{} t={}", h.name, fmt(h.t, Style::Decimals(3))),
            None => "miss: background".into(),
        },
        false,
    ));
    for sh in r
        .children
        .iter()
        .filter(|c| c.kind == RayKind::Shadow)
        .take(3)
    {
        out.push((
            match &sh.hit {
                Some(h) => format!("light blocked by {}", h.name),
                None => "light visible".into(),
            },
            true,
        ));
    }
    out.push((format!("■ {}", colour_text(r.color)), false));
    out
}

/// The RGB weight the parent multiplied `child`'s colour by, from the parent's steps: the BSDF
/// sample recorded before the child was spawned (f · cos / pdf, a colour: a red wall's bounce
/// keeps red), divided by the Russian roulette's probability if the path survived one there.
/// None when the steps do not give it (a Whitted ray, whose weight is a number) or disagree
/// with the ray's recorded weight (the mean of the channels).
pub fn rgb_weight(parent: &RayRecord, child: &RayRecord) -> Option<[f32; 3]> {
    let k = parent
        .children
        .iter()
        .position(|c| std::ptr::eq(c, child))? as u32;
    let spawn = parent
        .steps
        .iter()
        .position(|s| matches!(s.step, crate::record::Step::Spawn { child } if child == k))?;
    let mut weight = None;
    let mut roulette = 1.0f32;
    for s in parent.steps[..spawn].iter().rev() {
        match &s.step {
            crate::record::Step::RussianRoulette {
                probability,
                survived: true,
                ..
            } if weight.is_none() => roulette = *probability,
            crate::record::Step::BsdfSample { weight: w, .. } => {
                weight = Some(*w);
                break;
            }
            crate::record::Step::Spawn { .. } => break,
            _ => {}
        }
    }
    let w = weight?.map(|c| c / roulette);
    let mean = (w[0] + w[1] + w[2]) / 3.0;
    ((mean - child.weight).abs() <= 1e-5 * child.weight.abs().max(1e-30)).then_some(w)
}

/// The label on the edge to `child`: its RGB weight when its channels differ (`× (0.62, 0.06,
/// 0.06)`), else the one number.
pub fn weight_label(parent: Option<&RayRecord>, child: &RayRecord) -> String {
    match parent.and_then(|p| rgb_weight(p, child)) {
        Some(w) if w[0] != w[1] || w[1] != w[2] => {
            format!("× {}", crate::record::number::v3_in(w, Style::Decimals(3)))
        }
        _ => format!("× {}", fmt(child.weight, Style::Decimals(3))),
    }
}

fn colour_text(c: [f32; 3]) -> String {
    crate::record::number::v3_in(c, Style::Decimals(3))
}

/// The tree's layout on canvas `c` below `top`, above `bottom`: the boxes and the metrics they
/// were sized with.
fn layout_on(
    c: &Canvas,
    w: f32,
    trace: &Trace,
    opts: &ViewOptions,
    top: f32,
    bottom: f32,
) -> (Vec<RayBox>, Metrics) {
    let (rays, parent, depth) = colour_rays(trace);
    let mut m = metrics(c, &rays);
    let n = rays.len();
    let mut kids = vec![vec![]; n];
    for (j, p) in parent.iter().enumerate() {
        if let Some(p) = p {
            kids[*p].push(j);
        }
    }
    let mut rel = vec![0.0f32; n];
    let mut x = vec![0.0f32; n];
    if n > 0 {
        tidy(0, &kids, m.bw, m.hgap, &mut rel);
        // Pre-order: parents first.
        for (i, (p, r)) in parent.iter().zip(&rel).enumerate().skip(1) {
            x[i] = p.map_or(0.0, |p| x[p]) + r;
        }
    }
    let lo = x.iter().copied().fold(f32::INFINITY, f32::min) - m.bw / 2.0;
    let hi = x.iter().copied().fold(f32::NEG_INFINITY, f32::max) + m.bw / 2.0;
    let rows = depth.iter().copied().max().unwrap_or(0) as f32 + 1.0;
    let need_w = (hi - lo).max(m.bw);
    let need_h = rows * m.bh + (rows - 1.0) * m.vgap;
    let h = (bottom - top).max(1.0);
    let margin = m.text * 0.6;
    let k = ((w - 2.0 * margin).max(1.0) / need_w)
        .min(h / need_h)
        .min(1.0);
    m = Metrics {
        text: m.text * k,
        bw: m.bw * k,
        bh: m.bh * k,
        hgap: m.hgap * k,
        vgap: m.vgap * k,
    };
    // Centred across the canvas.
    let x0 = (w - need_w * k) / 2.0 - lo * k;
    let tl = trace.timeline();
    let first_step: HashMap<*const RayRecord, usize> = tl
        .iter()
        .enumerate()
        .rev()
        .map(|(k, (r, _))| (*r as *const RayRecord, k))
        .collect();
    let focus_ray = opts
        .focus
        .and_then(|k| tl.get(k))
        .map(|(r, _)| *r as *const RayRecord);
    let boxes = rays
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let ptr = *r as *const RayRecord;
            let shown = match (opts.focus, first_step.get(&ptr)) {
                (Some(k), Some(f)) => *f <= k,
                (Some(_), None) => false,
                (None, _) => true,
            };
            // A shadow ray's steps count as its parent's for highlighting.
            let current = focus_ray == Some(ptr)
                || r.children
                    .iter()
                    .any(|c| c.kind == RayKind::Shadow && focus_ray == Some(c as *const RayRecord));
            let cx = x0 + x[i] * k;
            let y = top + depth[i] as f32 * (m.bh + m.vgap);
            RayBox {
                index: i,
                parent: parent[i],
                pos: [cx, y],
                rect: [cx - m.bw / 2.0, y, cx + m.bw / 2.0, y + m.bh],
                shown,
                current,
            }
        })
        .collect();
    (boxes, m)
}

/// Lays out the colour rays below `top` on the canvas `opts` describes (the title's height,
/// the legend at the bottom): one row per depth, a tidy tree, boxes that never overlap.
pub fn layout(trace: &Trace, opts: &ViewOptions, top: f32) -> Vec<RayBox> {
    let opts = opts.sane();
    // Measuring text needs the font and sizes, not the pixels: a 1×1 canvas with this one's
    // text size.
    let mut c = Canvas::scaled(1, 1, opts.theme, opts.scale);
    c.text_size = super::canvas::text_size_for(opts.width, opts.height, opts.scale);
    let bottom = legend_top(&c, opts.height as f32);
    layout_on(&c, opts.width as f32, trace, &opts, top, bottom).0
}

/// Where the legend starts: everything above it is the tree's.
fn legend_top(c: &Canvas, height: f32) -> f32 {
    height - c.text_size * 2.0
}

fn kind_color(c: &Canvas, k: RayKind) -> Rgba {
    match k {
        RayKind::Primary => c.theme.ray,
        RayKind::Shadow => c.theme.shadow,
        RayKind::Reflection => c.theme.reflect,
        RayKind::Refraction => c.theme.refract,
        RayKind::Diffuse => c.theme.diffuse,
        RayKind::Glossy => c.theme.glossy,
    }
}

/// Draws the ray tree.
pub fn draw(trace: &Trace, opts: &ViewOptions) -> Canvas {
    let mut c = Canvas::for_view(opts);
    let th = c.theme;
    let ts = c.text_size;
    let top = title(
        &mut c,
        &format!(
            "Ray tree of pixel ({}, {}), sample {}",
            trace.pixel[0], trace.pixel[1], trace.sample
        ),
    ) + ts * 0.4;
    let (rays, _, _) = colour_rays(trace);
    let bottom = legend_top(&c, c.height());
    let (boxes, m) = layout_on(&c, c.width(), trace, opts, top, bottom);
    let small = m.text;
    let line_w = (small / 6.0).max(1.6);
    // Edges first, under the boxes; the weight on each edge's middle.
    for b in &boxes {
        let Some(p) = b.parent.and_then(|p| boxes.get(p)) else {
            continue;
        };
        if !b.shown {
            continue;
        }
        let col = kind_color(&c, rays[b.index].kind);
        let from = [p.pos[0], p.rect[3]];
        let to = [b.pos[0], b.rect[1]];
        c.arrow(from, to, col, line_w);
        let w = rays[b.index].weight;
        if w != 1.0 {
            let parent_ray = b.parent.map(|p| rays[p]);
            let text = weight_label(parent_ray, rays[b.index]);
            // Beside the edge's middle, on its outer side, so the edge stays in sight.
            let mid = [(from[0] + to[0]) / 2.0, (from[1] + to[1]) / 2.0];
            let (x, anchor) = if to[0] < from[0] {
                (mid[0] - small * 0.5 - 4.0, Anchor::MiddleRight)
            } else {
                (mid[0] + small * 0.5 + 4.0, Anchor::MiddleLeft)
            };
            c.label(x, mid[1], small * 0.95, &text, col, anchor);
        }
    }
    for b in boxes.iter().filter(|b| b.shown) {
        let r = rays[b.index];
        let col = kind_color(&c, r.kind);
        let [x0, y0, x1, y1] = b.rect;
        let (bw, bh) = (x1 - x0, y1 - y0);
        c.rect(x0, y0, bw, bh, th.background);
        c.rect(x0, y0, bw, small * HEADER, col);
        c.rect_outline(
            x0,
            y0,
            bw,
            bh,
            if b.current { th.ink } else { col },
            if b.current { line_w * 2.2 } else { line_w },
            false,
        );
        let lines = box_lines(r);
        let inner = bw - small * 0.6;
        let mut y = y0 + small * 0.15;
        for (i, (text, shadow)) in lines.iter().enumerate() {
            let (size, ink) = if i == 0 {
                (small, th.background)
            } else if *shadow {
                let blocked = text.starts_with("light blocked");
                (small * 0.92, if blocked { th.blocked } else { th.shadow })
            } else if i + 1 == lines.len() {
                (small * 0.92, th.muted)
            } else {
                (small, th.ink)
            };
            if i + 1 == lines.len() {
                // The colour line: a swatch of the ray's colour, then its numbers.
                let sw = small * 0.9;
                let label = c.elide(&colour_text(r.color), size, inner - sw - small * 0.4);
                let tw = c.text_width(&label, size);
                let x = b.pos[0] - (sw + small * 0.4 + tw) / 2.0;
                let rgb = [srgb8(r.color[0]), srgb8(r.color[1]), srgb8(r.color[2]), 255];
                let yy = y + small * 0.15;
                c.rect(x, yy, sw, sw, rgb);
                c.rect_outline(x, yy, sw, sw, th.muted, 1.0, false);
                c.text(x + sw + small * 0.4, y, size, &label, ink, Anchor::TopLeft);
            } else {
                let t = c.elide(text, size, inner);
                c.text(b.pos[0], y, size, &t, ink, Anchor::TopCenter);
            }
            y += if i == 0 { small * HEADER } else { small * LINE };
        }
    }
    // Legend and the final colour.
    let y = bottom + ts * 0.4;
    let mut x = ts * 0.6;
    let size = ts * 0.8;
    // The kinds of colour ray this trace has (Whitted's three always, so the legend is stable).
    let kinds = [
        RayKind::Primary,
        RayKind::Reflection,
        RayKind::Refraction,
        RayKind::Diffuse,
        RayKind::Glossy,
    ];
    let present = |k: &RayKind| {
        matches!(
            k,
            RayKind::Primary | RayKind::Reflection | RayKind::Refraction
        ) || trace.rays().iter().any(|r| r.kind == *k)
    };
    for k in kinds.into_iter().filter(present) {
        let col = kind_color(&c, k);
        c.rect(x, y + size * 0.15, size, size, col);
        x += size * 1.3;
        x += c.text(x, y, size, k.name(), th.ink, Anchor::TopLeft) + size;
    }
    let col = trace.color;
    let text = format!("pixel colour {}", colour_text(col));
    if x + c.text_width(&text, size) < c.width() - ts * 0.6 {
        c.text(
            c.width() - ts * 0.6,
            y,
            size,
            &text,
            th.ink,
            Anchor::TopRight,
        );
    }
    c
}
