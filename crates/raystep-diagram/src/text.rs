//! The diagrams' text toolkit: lines with subscripts ([`Rich`]), word wrapping, labels placed
//! so that they stay inside a region and do not cover each other ([`Placer`]), compact numbers
//! for drawings, and text panels of values. Shared by the quadratic and barycentric diagrams.

use super::Canvas;
use super::canvas::{Anchor, Rgba, with_alpha};
use crate::record::number::label;
use crate::record::{RayKind, RayRecord, Step, StepRecord};

/// A line of text with subscripts: `'_'` followed by one character, or by `{…}`, is a subscript
/// (`t_0`, `t_{min}`); names are appended with [`Rich::plain`] so that their underscores stay.
#[derive(Debug, Clone, Default)]
pub(super) struct Rich(Vec<(String, bool)>);

impl Rich {
    /// Parses markup.
    pub(super) fn new(markup: &str) -> Rich {
        Rich::default().push(markup)
    }

    /// Appends markup.
    pub(super) fn push(mut self, markup: &str) -> Rich {
        let mut chars = markup.chars().peekable();
        let mut run = String::new();
        while let Some(ch) = chars.next() {
            if ch == '_' && chars.peek().is_some() {
                if !run.is_empty() {
                    self.0.push((std::mem::take(&mut run), false));
                }
                let mut sub = String::new();
                if chars.peek() == Some(&'{') {
                    chars.next();
                    for c in chars.by_ref() {
                        if c == '}' {
                            break;
                        }
                        sub.push(c);
                    }
                } else if let Some(c) = chars.next() {
                    sub.push(c);
                }
                self.0.push((sub, true));
            } else {
                run.push(ch);
            }
        }
        if !run.is_empty() {
            self.0.push((run, false));
        }
        self
    }

    /// Appends literal text (no markup).
    pub(super) fn plain(mut self, text: &str) -> Rich {
        self.0.push((text.to_string(), false));
        self
    }
}

/// Subscripts are this fraction of the text size.
const SUB: f32 = 0.72;
/// The bundled Hack font's ascent + descent, in ems.
const LINE_EMS: f32 = 1.164;

/// The width of `r` at `size` pixels.
pub(super) fn rich_width(c: &Canvas, r: &Rich, size: f32) -> f32 {
    r.0.iter()
        .map(|(s, sub)| c.text_width(s, if *sub { size * SUB } else { size }))
        .sum()
}

/// The top-left corner of a `w`×`h` box anchored at (x, y).
fn anchored(x: f32, y: f32, w: f32, h: f32, anchor: Anchor) -> (f32, f32) {
    anchor.top_left(x, y, w, h)
}

/// Draws `r` at `size` pixels anchored at (x, y); returns its width.
pub(super) fn rich(
    c: &mut Canvas,
    x: f32,
    y: f32,
    size: f32,
    r: &Rich,
    color: Rgba,
    anchor: Anchor,
) -> f32 {
    let w = rich_width(c, r, size);
    let (mut cx, y0) = anchored(x, y, w, size * LINE_EMS, anchor);
    for (s, sub) in &r.0 {
        cx += if *sub {
            c.text(cx, y0 + size * 0.47, size * SUB, s, color, Anchor::TopLeft)
        } else {
            c.text(cx, y0, size, s, color, Anchor::TopLeft)
        };
    }
    w
}

/// The box `[x0, y0, x1, y1]` a label of `r` anchored at (x, y) covers.
pub(super) fn label_box(
    c: &Canvas,
    x: f32,
    y: f32,
    size: f32,
    r: &Rich,
    anchor: Anchor,
) -> [f32; 4] {
    let w = rich_width(c, r, size);
    let h = size * 1.25;
    let (x0, y0) = anchored(x, y, w, h, anchor);
    [x0 - 3.0, y0 - 1.0, x0 + w + 3.0, y0 + h + 1.0]
}

/// Draws `r` on a box of the background colour, so it reads over lines.
pub(super) fn rich_label(
    c: &mut Canvas,
    x: f32,
    y: f32,
    size: f32,
    r: &Rich,
    color: Rgba,
    anchor: Anchor,
) {
    let b = label_box(c, x, y, size, r, anchor);
    let bg = with_alpha(c.theme.background, 225);
    c.rect(b[0], b[1], b[2] - b[0], b[3] - b[1], bg);
    rich(
        c,
        b[0] + 3.0,
        b[1] + 1.0 + size * 0.05,
        size,
        r,
        color,
        Anchor::TopLeft,
    );
}

/// Places labels so that they stay inside a region and do not cover each other.
pub(super) struct Placer {
    bounds: [f32; 4],
    taken: Vec<[f32; 4]>,
    /// Every label placed so far: its markup and its box.
    pub(super) placed: Vec<PlacedLabel>,
}

/// A label as drawn: its text (markup: `t_0` is t with subscript 0) and its box
/// [x0, y0, x1, y1] in pixels.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedLabel {
    /// The label's markup, e.g. `t_0 ≈ 4.000`.
    pub text: String,
    /// Its box [x0, y0, x1, y1].
    pub rect: [f32; 4],
}

impl Rich {
    /// The markup this text would be written with (subscripts as `_{…}`).
    pub(super) fn markup(&self) -> String {
        self.0
            .iter()
            .map(
                |(s, sub)| {
                    if *sub { format!("_{{{s}}}") } else { s.clone() }
                },
            )
            .collect()
    }
}

impl Placer {
    /// Labels must stay inside `bounds` = [x0, y0, x1, y1].
    pub(super) fn new(bounds: [f32; 4]) -> Placer {
        Placer {
            bounds,
            taken: vec![],
            placed: vec![],
        }
    }

    /// Marks a box as taken (a marker, a legend).
    pub(super) fn block(&mut self, b: [f32; 4]) {
        self.taken.push(b);
    }

    /// Like [`Placer::place`], but draws nothing when no candidate is free (for optional labels).
    pub(super) fn place_if_free(
        &mut self,
        c: &mut Canvas,
        candidates: &[(f32, f32, Anchor)],
        size: f32,
        r: &Rich,
        color: Rgba,
    ) -> Option<[f32; 4]> {
        let free = candidates.iter().position(|&(x, y, a)| {
            let b = label_box(c, x, y, size, r, a);
            self.inside(&b) && self.free(&b)
        })?;
        Some(self.place(c, &candidates[free..=free], size, r, color))
    }

    pub(super) fn inside(&self, b: &[f32; 4]) -> bool {
        b[0] >= self.bounds[0]
            && b[1] >= self.bounds[1]
            && b[2] <= self.bounds[2]
            && b[3] <= self.bounds[3]
    }

    fn free(&self, b: &[f32; 4]) -> bool {
        self.taken
            .iter()
            .all(|t| b[2] <= t[0] || b[0] >= t[2] || b[3] <= t[1] || b[1] >= t[3])
    }

    /// Draws `r` as a label at the first candidate position that fits (else the first); returns
    /// the box it took.
    pub(super) fn place(
        &mut self,
        c: &mut Canvas,
        candidates: &[(f32, f32, Anchor)],
        size: f32,
        r: &Rich,
        color: Rgba,
    ) -> [f32; 4] {
        let fits = |b: &[f32; 4]| self.inside(b);
        let free = |b: &[f32; 4]| self.free(b);
        let boxes: Vec<[f32; 4]> = candidates
            .iter()
            .map(|&(x, y, a)| label_box(c, x, y, size, r, a))
            .collect();
        // How far a box reaches outside the bounds (0 when it fits).
        let over = |b: &[f32; 4]| {
            (self.bounds[0] - b[0]).max(0.0)
                + (self.bounds[1] - b[1]).max(0.0)
                + (b[2] - self.bounds[2]).max(0.0)
                + (b[3] - self.bounds[3]).max(0.0)
        };
        let pick = (0..boxes.len())
            .find(|&i| fits(&boxes[i]) && free(&boxes[i]))
            .or_else(|| (0..boxes.len()).find(|&i| fits(&boxes[i])))
            .or_else(|| {
                (0..boxes.len()).min_by(|&i, &j| over(&boxes[i]).total_cmp(&over(&boxes[j])))
            })
            .unwrap_or(0);
        let Some(&(x, y, a)) = candidates.get(pick) else {
            return [0.0; 4];
        };
        rich_label(c, x, y, size, r, color, a);
        self.taken.push(boxes[pick]);
        self.placed.push(PlacedLabel {
            text: r.markup(),
            rect: boxes[pick],
        });
        boxes[pick]
    }
}

/// The distance from point `p` to the box `b` = [x0, y0, x1, y1] (0 inside it).
pub(super) fn rect_dist(b: [f32; 4], p: [f32; 2]) -> f32 {
    let dx = (b[0] - p[0]).max(p[0] - b[2]).max(0.0);
    let dy = (b[1] - p[1]).max(p[1] - b[3]).max(0.0);
    dx.hypot(dy)
}

/// Splits `markup` into lines no wider than `width` at `size` (breaking at spaces).
pub(super) fn wrap(c: &Canvas, markup: &str, size: f32, width: f32) -> Vec<String> {
    let mut lines = vec![];
    let mut line = String::new();
    for word in markup.split(' ') {
        let candidate = if line.is_empty() {
            word.to_string()
        } else {
            format!("{line} {word}")
        };
        if !line.is_empty() && rich_width(c, &Rich::new(&candidate), size) > width {
            lines.push(std::mem::replace(&mut line, word.to_string()));
        } else {
            line = candidate;
        }
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// `name = value` for a drawing: `=` when the short form is exact, `≈` when it was rounded.
pub(super) fn short_eq(name: &str, x: f32) -> Rich {
    let s = label(x);
    let exact = s.parse::<f32>().is_ok_and(|p| p == x) || s.parse::<f64>() == Ok(x as f64);
    Rich::new(&format!("{name} {} {s}", if exact { "=" } else { "≈" }))
}

/// "primary ray", "shadow ray (depth 1)", …
pub(super) fn ray_name(r: &RayRecord) -> String {
    let kind = r.kind.name();
    if r.depth == 0 && r.kind == RayKind::Primary {
        format!("{kind} ray")
    } else {
        format!("{kind} ray (depth {})", r.depth)
    }
}

/// The ray's interval when a step ran: (t_min, t_max) with t_max shrunk by every closest-hit
/// update recorded on that ray before the step (∞ when none).
pub(super) fn interval_at(ray: &RayRecord, step: &StepRecord) -> (f32, f32) {
    let mut t_max = ray.t_max.unwrap_or(f32::INFINITY);
    for s in &ray.steps {
        if std::ptr::eq(s, step) {
            break;
        }
        if let Step::Accept { t, .. } = s.step {
            t_max = t;
        }
    }
    (ray.t_min, t_max)
}

/// A text panel's lines at `size` in a column `width` wide: the heading, then each row
/// wrapped (a gap, `true`, for an empty row).
pub(super) fn panel_lines(
    c: &Canvas,
    heading: &Rich,
    rows: &[(String, Rgba)],
    size: f32,
    width: f32,
) -> Vec<(Rich, Rgba, bool)> {
    let mut out = vec![(heading.clone(), c.theme.ink, false)];
    for (markup, col) in rows {
        if markup.is_empty() {
            out.push((Rich::default(), *col, true));
            continue;
        }
        for line in wrap(c, markup, size, width) {
            out.push((Rich::new(&line), *col, false));
        }
    }
    out
}

/// The height of a text panel's lines at `size`.
pub(super) fn lines_height(lines: &[(Rich, Rgba, bool)], size: f32) -> f32 {
    lines
        .iter()
        .map(|(_, _, gap)| if *gap { size * 0.6 } else { size * 1.32 })
        .sum()
}

/// Draws a text panel: a heading, then rows of markup, each wrapped to the panel's width (a row
/// that is one unbreakable value is squeezed instead); the text shrinks if the rows would run
/// off the bottom.
pub(super) fn draw_panel(
    c: &mut Canvas,
    panel: [f32; 4],
    size: f32,
    heading: Rich,
    rows: &[(String, Rgba)],
) {
    let [x0, y0, x1, y1] = panel;
    let width = x1 - x0;
    let layout = |c: &Canvas, size: f32| panel_lines(c, &heading, rows, size, width);
    let height = |n: &[(Rich, Rgba, bool)], size: f32| lines_height(n, size);
    let mut size = size;
    let mut lines = layout(c, size);
    for _ in 0..6 {
        let need = height(&lines, size);
        if need <= y1 - y0 || size <= 8.0 {
            break;
        }
        size = (size * ((y1 - y0) / need).max(0.85)).max(8.0);
        lines = layout(c, size);
    }
    let mut y = y0;
    for (r, col, gap) in &lines {
        if *gap {
            y += size * 0.6;
            continue;
        }
        let w = rich_width(c, r, size);
        let sz = if w > width { size * width / w } else { size };
        rich(c, x0, y + (size - sz) * 0.5, sz, r, *col, Anchor::TopLeft);
        y += size * 1.32;
    }
}

/// The width of a text panel of `heading` and `rows` (`wanted` points) if its lines, wrapped to
/// that width, fit `height` at `size`; else 0 (the panel is left out, and the drawing beside it
/// takes the width, rather than printing the values too small to read).
pub(super) fn fitting_panel_width(
    c: &Canvas,
    (heading, rows): (&Rich, &[(String, Rgba)]),
    size: f32,
    wanted: f32,
    height: f32,
) -> f32 {
    let lines = panel_lines(c, heading, rows, size, wanted - c.text_size * 0.5);
    if lines_height(&lines, size) <= height {
        wanted
    } else {
        0.0
    }
}
