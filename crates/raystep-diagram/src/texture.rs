//! The texture view of one recorded texture lookup. On the left, the texture around the point:
//! for an image, a window of texels — the ones the lookup read filled with the colours it read,
//! each with its (column, row) and weight, their neighbours outlined — with the point at its
//! texel position x = u·w, y = (1 − v)·h, and for bilinear filtering the square of the four
//! texel centres it blends between; for a checker, the squares around the point in their two
//! colours, the point's square outlined. On the right, a panel of the numbers: (u, v) and where
//! it came from, the texel position, the weights, the texture's colour T and the surface's C.
//!
//! Everything is read from the `Texture` step (no texture is read again here), so a saved trace
//! draws the same as a live one.

use super::canvas::{Rgba, with_alpha};
use super::text::{Rich, draw_panel, fitting_panel_width};
use super::{Anchor, Canvas, ViewOptions, pick_step, title};
use crate::record::number::{num, v3};
use crate::record::texturing::{Texel, TexelLookup};
use crate::record::{Step, Trace};
use crate::render::image::srgb8_rgb;
use crate::scene::Filter;

/// Where the texture diagram puts things (tests check the drawing against the record with it).
#[derive(Debug, Clone, PartialEq)]
pub struct TextureLayout {
    /// Index of the explained step in [`Trace::timeline`].
    pub step: usize,
    /// The texture's name.
    pub name: String,
    /// The window's first column and row (texel or checker-square units; a checker's rows
    /// count v downwards, negated, so that v points up).
    pub first: [i64; 2],
    /// Columns and rows shown.
    pub cells: [u32; 2],
    /// Pixels per texel (or square).
    pub cell_px: f32,
    /// The window's top-left corner on the canvas.
    pub origin: [f32; 2],
    /// The point on the canvas.
    pub point_px: [f32; 2],
    /// The number panel [x0, y0, x1, y1] (zero-width when it does not fit).
    pub panel: [f32; 4],
}

impl TextureLayout {
    /// The canvas position of texel-space point (x, y) (for a checker, (u·s₁, −v·s₂)).
    pub fn at(&self, x: f64, y: f64) -> [f32; 2] {
        [
            self.origin[0] + ((x - self.first[0] as f64) as f32) * self.cell_px,
            self.origin[1] + ((y - self.first[1] as f64) as f32) * self.cell_px,
        ]
    }
}

/// Whether the trace holds a texture lookup.
pub fn has_texture(trace: &Trace) -> bool {
    trace
        .timeline()
        .iter()
        .any(|(_, s)| matches!(s.step, Step::Texture { .. }))
}

/// The point in the window's units: the texel position for an image, (u·s₁, −v·s₂) for a checker.
/// Held to ±1e15 (a far plane's coordinates, or a loaded trace's, may be any number): the
/// window's integer cells then stay far from i64's range, and f32 has no fraction there anyway.
fn point_of(uv: [f32; 2], lookup: &TexelLookup) -> [f64; 2] {
    let p = match lookup {
        TexelLookup::Image { address, .. } => [f64::from(address[0]), f64::from(address[1])],
        TexelLookup::Checker { squares, .. } => [
            f64::from(uv[0]) * f64::from(squares[0]),
            -(f64::from(uv[1]) * f64::from(squares[1])),
        ],
    };
    p.map(|c| {
        if c.is_nan() {
            0.0
        } else {
            c.clamp(-1e15, 1e15)
        }
    })
}

/// Where everything goes.
pub fn layout(trace: &Trace, opts: &ViewOptions) -> Option<TextureLayout> {
    let (k, step) = pick_step(trace, opts.focus, |s| matches!(s, Step::Texture { .. }))?;
    let Step::Texture {
        texture,
        uv,
        lookup,
        ..
    } = step
    else {
        return None;
    };
    let c = Canvas::for_view(opts);
    let (w, h, s) = (c.width(), c.height(), c.text_size);
    let small = (s * 0.85).max(13.0 * c.scale);
    let top = s * 0.6 + s * 1.15 * 1.5;
    let (heading, rows) = panel_rows(step, &c);
    let panel_w = fitting_panel_width(
        &c,
        (&heading, &rows),
        small,
        (w * 0.42).max(160.0).min(w * 0.55),
        h - top - s * 0.6,
    );
    let panel = [w - panel_w, top, w - s * 0.5, h - s * 0.6];
    let right = if panel_w > 0.0 {
        panel[0] - s * 0.8
    } else {
        w - s * 0.6
    };
    let area = [s * 0.6, top, right, h - s * 0.6];
    let p = point_of(*uv, lookup);
    // The window: a 4 × 4 texels around a bilinear read's four, 3 × 3 around a nearest one,
    // 5 × 5 squares around a checker's.
    let (first, cells) = match lookup {
        TexelLookup::Image { filter, .. } => match filter {
            Filter::Bilinear | Filter::Trilinear => (
                [
                    (p[0] - 0.5).floor() as i64 - 1,
                    (p[1] - 0.5).floor() as i64 - 1,
                ],
                [4, 4],
            ),
            Filter::Nearest => ([p[0].floor() as i64 - 1, p[1].floor() as i64 - 1], [3, 3]),
        },
        TexelLookup::Checker { .. } => ([p[0].floor() as i64 - 2, p[1].floor() as i64 - 2], [5, 5]),
    };
    let aw = (area[2] - area[0]).max(1.0);
    let ah = (area[3] - area[1] - s * 1.5).max(1.0);
    let cell_px = (aw / cells[0] as f32).min(ah / cells[1] as f32).max(1.0);
    let origin = [
        area[0] + (aw - cell_px * cells[0] as f32) / 2.0,
        area[1] + (ah - cell_px * cells[1] as f32) / 2.0,
    ];
    let mut l = TextureLayout {
        step: k,
        name: texture.clone(),
        first,
        cells,
        cell_px,
        origin,
        point_px: [0.0; 2],
        panel,
    };
    l.point_px = l.at(p[0], p[1]);
    Some(l)
}

/// A trilinear read's footprint in the texels of the level drawn: L / 2^level, the cone's
/// footprint in level-0 texels scaled down to that level.
pub fn footprint_side(lookup: &TexelLookup) -> Option<f64> {
    let TexelLookup::Image { lod: Some(lod), .. } = lookup else {
        return None;
    };
    let level = lod.levels.first()?.level;
    let side = f64::from(lod.footprint) / 2f64.powi(level.min(60) as i32);
    side.is_finite().then_some(side.max(0.0))
}

/// The colour to draw a linear texel with (sRGB-encoded, as the rendered image shows it).
fn shown(c: [f32; 3]) -> Rgba {
    let [r, g, b] = srgb8_rgb(glam::Vec3::from(c));
    [r, g, b, 255]
}

/// Black or white, whichever reads on `fill`.
fn ink_on(fill: Rgba) -> Rgba {
    let l = 0.2126 * f32::from(fill[0]) + 0.7152 * f32::from(fill[1]) + 0.0722 * f32::from(fill[2]);
    if l > 140.0 {
        [0, 0, 0, 255]
    } else {
        [255, 255, 255, 255]
    }
}

fn panel_rows(step: &Step, c: &Canvas) -> (Rich, Vec<(String, Rgba)>) {
    let th = c.theme;
    let Step::Texture {
        texture,
        mapping,
        uv,
        lookup,
        texel,
        color,
        roughness,
        ..
    } = step
    else {
        return (Rich::new(""), vec![]);
    };
    let mut rows = vec![
        (format!("(u, v) = ({}, {})", num(uv[0]), num(uv[1])), th.ink),
        (format!("from {}", mapping.name()), th.muted),
        (String::new(), th.ink),
    ];
    match lookup {
        TexelLookup::Checker {
            squares, cell, odd, ..
        } => {
            rows.push((
                format!("{} × {} squares per unit", squares[0], squares[1]),
                th.muted,
            ));
            rows.push((format!("i = ⌊u·{}⌋ = {}", squares[0], num(cell[0])), th.ink));
            rows.push((format!("j = ⌊v·{}⌋ = {}", squares[1], num(cell[1])), th.ink));
            rows.push((
                format!(
                    "i + j {}: colour {}",
                    if *odd { "odd" } else { "even" },
                    if *odd { 2 } else { 1 }
                ),
                th.ink,
            ));
        }
        TexelLookup::Image {
            size,
            filter,
            wrap,
            wrapped,
            address,
            texels,
            lod,
        } => {
            rows.push((
                format!(
                    "{} × {} texels, {}, {} wrap",
                    size[0],
                    size[1],
                    filter.name(),
                    wrap.name()
                ),
                th.muted,
            ));
            if *wrapped != *uv {
                rows.push((
                    format!("wrapped: ({}, {})", num(wrapped[0]), num(wrapped[1])),
                    th.ink,
                ));
            }
            if let Some(lod) = lod {
                rows.push((
                    format!(
                        "cone W = γ·d = {}·{} = {}",
                        num(lod.spread),
                        num(lod.distance),
                        num(lod.width)
                    ),
                    th.ink,
                ));
                rows.push((
                    format!("footprint L = {} texels", num(lod.footprint)),
                    th.ink,
                ));
                rows.push((format!("λ = log₂ L = {}", num(lod.lambda)), th.ink));
                for m in &lod.levels {
                    rows.push((
                        format!(
                            "level {} ({} × {}): weight {}",
                            m.level,
                            m.size[0],
                            m.size[1],
                            num(m.weight)
                        ),
                        th.muted,
                    ));
                }
            }
            let at_level = lod
                .as_ref()
                .and_then(|l| l.levels.first())
                .map_or(String::new(), |m| format!(" (level {})", m.level));
            rows.push((format!("x = u·w = {}{at_level}", num(address[0])), th.ink));
            rows.push((format!("y = (1 − v)·h = {}", num(address[1])), th.ink));
            for t in texels {
                let level = if lod.is_some() {
                    format!(" of level {}", t.level)
                } else {
                    String::new()
                };
                rows.push((
                    format!(
                        "texel ({}, {}){level}: w = {}",
                        t.at[0],
                        t.at[1],
                        num(t.weight)
                    ),
                    th.ink,
                ));
            }
        }
    }
    rows.push((String::new(), th.ink));
    rows.push((format!("T = {}", v3(*texel)), th.hit));
    match roughness {
        // A glossy BSDF's roughness texture: its green channel scales the roughness.
        Some(r) => rows.push((
            format!(
                "r = roughness × T_g = {} × {} = {}",
                num(r.material),
                num(texel[1]),
                num(r.roughness)
            ),
            th.ink,
        )),
        None => rows.push((format!("C = colour × T = {}", v3(*color)), th.ink)),
    }
    (Rich::new("texture ").plain(&format!("\"{texture}\"")), rows)
}

/// Draws the diagram (a message in place of it when the trace has no texture step).
pub fn draw(trace: &Trace, opts: &ViewOptions) -> Canvas {
    let mut c = Canvas::for_view(opts);
    let Some(l) = layout(trace, opts) else {
        let (w, h, s, ink) = (c.width(), c.height(), c.text_size, c.theme.muted);
        c.text(
            w / 2.0,
            h / 2.0,
            s,
            "no texture lookup in this trace",
            ink,
            Anchor::Center,
        );
        return c;
    };
    let tl = trace.timeline();
    let step = &tl[l.step].1.step;
    let Step::Texture { uv, lookup, .. } = step else {
        return c;
    };
    let th = c.theme;
    let s = c.text_size;
    let small = (s * 0.85).max(13.0 * c.scale);
    title(
        &mut c,
        &format!(
            "Texture \"{}\" · step {} · (u, v) = ({}, {})",
            l.name,
            l.step,
            num(uv[0]),
            num(uv[1])
        ),
    );
    let cp = l.cell_px;
    let cell_at = |i: i64, j: i64| l.at(i as f64, j as f64);
    match lookup {
        TexelLookup::Checker {
            cell, odd, colors, ..
        } => {
            // Square (i, j) of the checker is window cell (i, −j − 1): v points up.
            for dj in 0..l.cells[1] as i64 {
                for di in 0..l.cells[0] as i64 {
                    let (wi, wj) = (l.first[0] + di, l.first[1] + dj);
                    let (i, j) = (wi, -wj - 1);
                    let fill = shown(colors[(i + j).rem_euclid(2) as usize]);
                    let [x, y] = cell_at(wi, wj);
                    c.rect(x, y, cp, cp, fill);
                    c.rect_outline(x, y, cp, cp, th.muted, 1.0 * c.scale, false);
                    if i as f32 == cell[0] && j as f32 == cell[1] {
                        c.rect_outline(x, y, cp, cp, th.hit, 3.0 * c.scale, false);
                        let label = format!("({}, {})", num(cell[0]), num(cell[1]));
                        if c.text_width(&label, small) > cp * 0.9 {
                            // Too small a square to label: the panel names it.
                            continue;
                        }
                        let ink = ink_on(fill);
                        c.text(
                            x + cp / 2.0,
                            y + cp * 0.2,
                            small,
                            &label,
                            ink,
                            Anchor::TopCenter,
                        );
                        c.text(
                            x + cp / 2.0,
                            y + cp * 0.8,
                            small,
                            if *odd { "odd" } else { "even" },
                            ink,
                            Anchor::Center,
                        );
                    }
                }
            }
        }
        TexelLookup::Image { filter, texels, .. } => {
            // The neighbours, outlined.
            for dj in 0..l.cells[1] as i64 {
                for di in 0..l.cells[0] as i64 {
                    let [x, y] = cell_at(l.first[0] + di, l.first[1] + dj);
                    c.rect_outline(x, y, cp, cp, th.faded, 1.0 * c.scale, true);
                }
            }
            // The texels read, where they sit around the point (their indices may have wrapped).
            let p = point_of(*uv, lookup);
            let bilinear = *filter != Filter::Nearest;
            let (bx, by) = if bilinear {
                ((p[0] - 0.5).floor() as i64, (p[1] - 0.5).floor() as i64)
            } else {
                (p[0].floor() as i64, p[1].floor() as i64)
            };
            // A trilinear read: the first level's four texels (the panel lists the second's).
            for (k, t) in texels.iter().take(4).enumerate() {
                let (right, bottom) = (k & 1 == 1, k >> 1 == 1);
                let (wi, wj) = (bx + i64::from(right), by + i64::from(bottom));
                let weight = bilinear.then_some(t.weight);
                draw_texel(
                    &mut c,
                    cell_at(wi, wj),
                    cp,
                    t,
                    weight,
                    (right, bottom),
                    small,
                );
            }
            if bilinear {
                // The square of the four centres the point is blended between.
                let a = l.at(bx as f64 + 0.5, by as f64 + 0.5);
                c.rect_outline(a[0], a[1], cp, cp, th.ray, 2.0 * c.scale, true);
                for (dx, dy) in [(0.5, 0.5), (1.5, 0.5), (0.5, 1.5), (1.5, 1.5)] {
                    let q = l.at(bx as f64 + dx, by as f64 + dy);
                    c.circle(q, 3.0 * c.scale, Some(th.ray), None, 1.0);
                }
            }
            if let Some(side) = footprint_side(lookup) {
                // The ray cone's footprint at this level: L / 2^level texels across, about the
                // point (held to the window).
                let half = (side / 2.0).min(l.cells[0].max(l.cells[1]) as f64);
                let a = l.at(p[0] - half, p[1] - half);
                let px = (2.0 * half) as f32 * cp;
                c.rect_outline(a[0], a[1], px, px, th.hit, 2.0 * c.scale, true);
            }
        }
    }
    // The point.
    let ring = with_alpha(th.background, 230);
    c.circle(
        l.point_px,
        7.0 * c.scale,
        Some(ring),
        Some(th.hit),
        3.0 * c.scale,
    );
    c.circle(l.point_px, 2.5 * c.scale, Some(th.hit), None, 1.0);
    let below = l.origin[1] + l.cell_px * l.cells[1] as f32 + s * 0.4;
    let caption = match lookup {
        TexelLookup::Image { address, lod, .. } => {
            let level = lod
                .as_ref()
                .and_then(|l| l.levels.first())
                .map_or(String::new(), |m| {
                    format!(" of level {}; the cone's footprint dashed", m.level)
                });
            format!(
                "the point at (x, y) = ({}, {}) texels{level}",
                num(address[0]),
                num(address[1])
            )
        }
        TexelLookup::Checker { squares, .. } => {
            format!("the point at (u·{}, v·{}); v up", squares[0], squares[1])
        }
    };
    let muted = th.muted;
    let avail = (l.cell_px * l.cells[0] as f32).max(l.panel[0] - l.origin[0] - s * 0.8);
    let caption = c.elide(&caption, small, avail.max(s));
    c.text(
        l.origin[0] + l.cell_px * l.cells[0] as f32 / 2.0,
        below,
        small,
        &caption,
        muted,
        Anchor::TopCenter,
    );
    if l.panel[2] > l.panel[0] {
        let (heading, rows) = panel_rows(step, &c);
        draw_panel(&mut c, l.panel, small, heading, &rows);
    }
    c
}

/// One texel the lookup read: filled with its colour, its (column, row) and its bilinear weight
/// in the corner away from the point (`right`, `bottom`: which of the four it is).
fn draw_texel(
    c: &mut Canvas,
    at: [f32; 2],
    cp: f32,
    t: &Texel,
    weight: Option<f32>,
    (right, bottom): (bool, bool),
    size: f32,
) {
    let fill = shown(t.color);
    c.rect(at[0], at[1], cp, cp, fill);
    let ink = ink_on(fill);
    let th = c.theme;
    c.rect_outline(at[0], at[1], cp, cp, th.ink, 2.0 * c.scale, false);
    let pad = cp * 0.06;
    let (x, anchor) = if right {
        (at[0] + cp - pad, Anchor::TopRight)
    } else {
        (at[0] + pad, Anchor::TopLeft)
    };
    let mut lines = vec![format!("({}, {})", t.at[0], t.at[1])];
    if let Some(w) = weight {
        lines.push(format!("w = {w:.3}"));
    }
    // Labels only where they fit inside the texel (the panel lists every texel and weight).
    if lines.iter().any(|l| c.text_width(l, size) > cp * 0.9)
        || size * 1.25 * lines.len() as f32 > cp * 0.45
    {
        return;
    }
    let line_h = size * 1.25;
    let y0 = if bottom {
        at[1] + cp - pad - line_h * lines.len() as f32
    } else {
        at[1] + pad
    };
    for (k, text) in lines.iter().enumerate() {
        c.text(x, y0 + line_h * k as f32, size, text, ink, anchor);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::texturing::{RoughnessRead, UvMapping};

    /// A roughness texture's panel says what its texel scales (the roughness), not a surface
    /// colour; a colour texture's says C = colour × T.
    #[test]
    fn the_panel_names_what_the_texture_gives() {
        let c = Canvas::new(64, 64, crate::Theme::LIGHT);
        let step = |roughness| Step::Texture {
            texture: "t".into(),
            mapping: UvMapping::Plane,
            barycentric: None,
            vertex_uvs: None,
            direction: None,
            axes: None,
            uv: [0.25, 0.5],
            lookup: TexelLookup::Checker {
                squares: [1, 1],
                cell: [0.0, 0.0],
                odd: false,
                colors: [[1.0, 0.8, 1.0], [1.0, 0.02, 1.0]],
            },
            texel: [1.0, 0.8, 1.0],
            color: [0.4; 3],
            roughness,
        };
        let last = |s: &Step| panel_rows(s, &c).1.last().unwrap().0.clone();
        assert_eq!(last(&step(None)), "C = colour × T = (0.4, 0.4, 0.4)");
        let r = Some(RoughnessRead {
            material: 0.5,
            roughness: 0.4,
        });
        assert_eq!(last(&step(r)), "r = roughness × T_g = 0.5 × 0.8 = 0.4");
    }
}
