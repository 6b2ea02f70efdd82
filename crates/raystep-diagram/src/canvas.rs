//! The drawing surface every diagram uses: a tiny-skia pixmap, a theme, and real text
//! (ab_glyph with the Hack font shipped inside the `epaint_default_fonts` crate; no system fonts).

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use tiny_skia::{
    Color, FillRule, LineCap, Paint, PathBuilder, Pixmap, Rect, Stroke, StrokeDash, Transform,
};

/// An RGBA colour (straight alpha).
pub type Rgba = [u8; 4];

/// The colours of a diagram. Both themes are chosen to read on a classroom projector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Theme {
    /// Background.
    pub background: Rgba,
    /// Main text and outlines.
    pub ink: Rgba,
    /// Secondary text, axes, grid.
    pub muted: Rgba,
    /// Faded elements (earlier steps, culled nodes).
    pub faded: Rgba,
    /// The current ray, the current step.
    pub ray: Rgba,
    /// Hit points and the chosen root.
    pub hit: Rgba,
    /// Normals.
    pub normal: Rgba,
    /// Shadow rays that reach their light.
    pub shadow: Rgba,
    /// Blocked shadow rays.
    pub blocked: Rgba,
    /// Reflection rays.
    pub reflect: Rgba,
    /// Refraction rays.
    pub refract: Rgba,
    /// Monte Carlo bounces off diffuse surfaces.
    pub diffuse: Rgba,
    /// Monte Carlo bounces off glossy surfaces.
    pub glossy: Rgba,
    /// Lights.
    pub light: Rgba,
    /// Shaded regions (the t > 0 half, the barycentric region).
    pub region: Rgba,
    /// Object outlines and fills.
    pub object: Rgba,
}

impl Theme {
    /// Dark ink on white.
    pub const LIGHT: Theme = Theme {
        background: [255, 255, 255, 255],
        ink: [20, 20, 28, 255],
        muted: [110, 110, 125, 255],
        faded: [200, 200, 210, 255],
        ray: [220, 50, 40, 255],
        hit: [230, 120, 0, 255],
        normal: [30, 140, 60, 255],
        shadow: [170, 140, 0, 255],
        blocked: [90, 90, 90, 255],
        reflect: [40, 90, 220, 255],
        refract: [0, 150, 170, 255],
        diffuse: [150, 60, 170, 255],
        glossy: [200, 70, 130, 255],
        light: [240, 180, 0, 255],
        region: [60, 130, 230, 45],
        object: [70, 80, 110, 255],
    };
    /// Light ink on near-black.
    pub const DARK: Theme = Theme {
        background: [18, 18, 24, 255],
        ink: [235, 235, 240, 255],
        muted: [150, 150, 165, 255],
        faded: [70, 70, 82, 255],
        ray: [255, 95, 80, 255],
        hit: [255, 170, 40, 255],
        normal: [90, 220, 120, 255],
        shadow: [240, 210, 60, 255],
        blocked: [140, 140, 150, 255],
        reflect: [110, 160, 255, 255],
        refract: [60, 220, 230, 255],
        diffuse: [205, 140, 255, 255],
        glossy: [255, 130, 190, 255],
        light: [255, 220, 60, 255],
        region: [90, 160, 255, 60],
        object: [170, 180, 210, 255],
    };
}

/// Which way text is anchored to its position.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    /// (x, y) is the top-left corner.
    TopLeft,
    /// (x, y) is the top centre.
    TopCenter,
    /// (x, y) is the top-right corner.
    TopRight,
    /// (x, y) is the centre.
    Center,
    /// (x, y) is the left end of the middle line.
    MiddleLeft,
    /// (x, y) is the right end of the middle line.
    MiddleRight,
}

impl Anchor {
    /// The top-left corner of a `w`×`h` box anchored at (x, y) this way.
    pub fn top_left(self, x: f32, y: f32, w: f32, h: f32) -> (f32, f32) {
        match self {
            Anchor::TopLeft => (x, y),
            Anchor::TopCenter => (x - w / 2.0, y),
            Anchor::TopRight => (x - w, y),
            Anchor::Center => (x - w / 2.0, y - h / 2.0),
            Anchor::MiddleLeft => (x, y - h / 2.0),
            Anchor::MiddleRight => (x - w, y - h / 2.0),
        }
    }
}

/// The largest side of a diagram in pixels: a larger request is drawn at this size (8192 × 8192
/// RGBA is 256 MiB, and tiny-skia's rasterizer works in tiles of up to 8191 pixels).
pub const MAX_SIDE: u32 = 8192;

/// The smallest base text size at UI scale 1, in pixels: labels (0.8–0.85 of it) stay at about
/// 13 px, readable on a classroom screen, however small the diagram.
pub const MIN_TEXT: f32 = 16.0;

/// A pixmap with drawing helpers.
pub struct Canvas {
    /// The pixels.
    pub pixmap: Pixmap,
    /// The colours.
    pub theme: Theme,
    /// Base text size in pixels (scales with the canvas and with [`Canvas::scale`]).
    pub text_size: f32,
    /// The UI scale the diagram is drawn for (the app's pixels per point): text and lines grow
    /// with it.
    pub scale: f32,
    font: FontRef<'static>,
}

fn color(c: Rgba) -> Color {
    Color::from_rgba8(c[0], c[1], c[2], c[3])
}

fn paint(c: Rgba) -> Paint<'static> {
    let mut p = Paint::default();
    p.set_color(color(c));
    p.anti_alias = true;
    p
}

impl Canvas {
    /// A blank canvas of `width`×`height` pixels at UI scale 1.
    pub fn new(width: u32, height: u32, theme: Theme) -> Canvas {
        Canvas::scaled(width, height, theme, 1.0)
    }

    /// A blank canvas for a diagram's view options (size, theme and UI scale).
    pub fn for_view(opts: &super::ViewOptions) -> Canvas {
        Canvas::scaled(opts.width, opts.height, opts.theme, opts.scale)
    }

    /// A blank canvas of `width`×`height` pixels (each side kept within 1 … [`MAX_SIDE`]) whose
    /// text and lines are drawn for UI scale `scale` (kept within 0.25 … 8; 1 when not finite).
    pub fn scaled(width: u32, height: u32, theme: Theme, scale: f32) -> Canvas {
        let (w, h) = (width.clamp(1, MAX_SIDE), height.clamp(1, MAX_SIDE));
        let scale = sane_scale(scale);
        // Both sides are within 1 … 8192, which tiny-skia accepts.
        let mut pixmap = Pixmap::new(w, h)
            .or_else(|| Pixmap::new(1, 1))
            .unwrap_or_else(|| unreachable!("a 1×1 pixmap"));
        pixmap.fill(color(theme.background));
        let font = FontRef::try_from_slice(epaint_default_fonts::HACK_REGULAR)
            .unwrap_or_else(|_| unreachable!("the bundled font parses"));
        Canvas {
            pixmap,
            theme,
            text_size: text_size_for(w, h, scale),
            scale,
            font,
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> f32 {
        self.pixmap.width() as f32
    }

    /// Height in pixels.
    pub fn height(&self) -> f32 {
        self.pixmap.height() as f32
    }

    /// A line segment.
    pub fn line(&mut self, a: [f32; 2], b: [f32; 2], c: Rgba, width: f32) {
        self.polyline(&[a, b], c, width, false);
    }

    /// A dashed line segment.
    pub fn dashed(&mut self, a: [f32; 2], b: [f32; 2], c: Rgba, width: f32) {
        self.polyline(&[a, b], c, width, true);
    }

    /// An open polyline, solid or dashed.
    pub fn polyline(&mut self, pts: &[[f32; 2]], c: Rgba, width: f32, dashed: bool) {
        if pts.len() < 2 || pts.iter().any(|p| !p[0].is_finite() || !p[1].is_finite()) {
            return;
        }
        if !(width.is_finite() && width > 0.0) {
            return;
        }
        let width = width.min(self.width().max(self.height()));
        let mut stroke = Stroke {
            width,
            line_cap: LineCap::Round,
            ..Default::default()
        };
        if dashed {
            stroke.dash = StrokeDash::new(vec![width * 3.0, width * 2.5], 0.0);
        }
        let view = self.view(width);
        for run in clip_polyline(pts, view) {
            let Some(path) = path_through(&run, false) else {
                continue;
            };
            self.pixmap
                .stroke_path(&path, &paint(c), &stroke, Transform::identity(), None);
        }
    }

    /// The canvas grown by a margin wider than any stroke of `width` (so clipped ends and edges
    /// stay out of sight): everything handed to tiny-skia is first clipped to it, which keeps
    /// its fixed-point rasterizer within range whatever the geometry.
    fn view(&self, width: f32) -> [f64; 4] {
        let m = f64::from(width.max(1.0)) * 2.0 + 4.0;
        [
            -m,
            -m,
            f64::from(self.width()) + m,
            f64::from(self.height()) + m,
        ]
    }

    /// A line from `a` to `b` with an arrowhead at `b`.
    pub fn arrow(&mut self, a: [f32; 2], b: [f32; 2], c: Rgba, width: f32) {
        self.line(a, b, c, width);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = (dx * dx + dy * dy).sqrt();
        if len.is_nan() || len <= 1e-3 {
            return;
        }
        let (ux, uy) = (dx / len, dy / len);
        let head = (width * 4.0).max(8.0).min(len * 0.5);
        let base = [b[0] - ux * head, b[1] - uy * head];
        let half = head * 0.45;
        self.polygon(
            &[
                b,
                [base[0] - uy * half, base[1] + ux * half],
                [base[0] + uy * half, base[1] - ux * half],
            ],
            Some(c),
            None,
            0.0,
        );
    }

    /// A closed polygon, filled and/or outlined.
    pub fn polygon(
        &mut self,
        pts: &[[f32; 2]],
        fill: Option<Rgba>,
        stroke: Option<Rgba>,
        width: f32,
    ) {
        if pts.len() < 3 || pts.iter().any(|p| !p[0].is_finite() || !p[1].is_finite()) {
            return;
        }
        let pts: Vec<[f64; 2]> = pts
            .iter()
            .map(|p| [f64::from(p[0]), f64::from(p[1])])
            .collect();
        self.clipped_polygon(&pts, fill, stroke, width);
    }

    /// Draws a closed polygon given in f64 after clipping it to [`Canvas::view`].
    fn clipped_polygon(
        &mut self,
        pts: &[[f64; 2]],
        fill: Option<Rgba>,
        stroke: Option<Rgba>,
        width: f32,
    ) {
        let width = if width.is_finite() {
            width.clamp(0.0, self.width().max(self.height()))
        } else {
            0.0
        };
        let clipped = clip_polygon(pts, self.view(width));
        if clipped.len() < 3 {
            return;
        }
        let pts: Vec<[f32; 2]> = clipped.iter().map(|p| [p[0] as f32, p[1] as f32]).collect();
        let Some(path) = path_through(&pts, true) else {
            return;
        };
        self.fill_and_stroke(&path, fill, stroke, width);
    }

    /// Fills and/or outlines a closed path.
    fn fill_and_stroke(
        &mut self,
        path: &tiny_skia::Path,
        fill: Option<Rgba>,
        stroke: Option<Rgba>,
        width: f32,
    ) {
        if let Some(f) = fill {
            self.pixmap.fill_path(
                path,
                &paint(f),
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        }
        if let Some(s) = stroke {
            let st = Stroke {
                width,
                ..Default::default()
            };
            self.pixmap
                .stroke_path(path, &paint(s), &st, Transform::identity(), None);
        }
    }

    /// A circle, filled and/or outlined.
    pub fn circle(
        &mut self,
        c: [f32; 2],
        r: f32,
        fill: Option<Rgba>,
        stroke: Option<Rgba>,
        width: f32,
    ) {
        if r.is_nan() || r <= 0.0 || !c[0].is_finite() || !c[1].is_finite() || !r.is_finite() {
            return;
        }
        let width = if width.is_finite() {
            width.clamp(0.0, self.width().max(self.height()))
        } else {
            0.0
        };
        let view = self.view(width);
        let (cx, cy, r64) = (f64::from(c[0]), f64::from(c[1]), f64::from(r));
        // Nearest and farthest points of the view from the centre.
        let nx = cx.clamp(view[0], view[2]) - cx;
        let ny = cy.clamp(view[1], view[3]) - cy;
        let near = nx.hypot(ny);
        let fx = (cx - view[0]).abs().max((cx - view[2]).abs());
        let fy = (cy - view[1]).abs().max((cy - view[3]).abs());
        let far = fx.hypot(fy);
        if near > r64 {
            return; // the circle is all outside the view
        }
        if far < r64 {
            // The circle covers the whole view (its outline runs outside it, beyond the
            // margin that a stroke's half width cannot cross).
            if fill.is_some() {
                let v = view;
                let all = [[v[0], v[1]], [v[2], v[1]], [v[2], v[3]], [v[0], v[3]]];
                self.clipped_polygon(&all, fill, None, 0.0);
            }
            return;
        }
        let size = (view[2] - view[0]).max(view[3] - view[1]);
        if r64 <= 4.0 * size && cx.abs() <= 8.0 * size && cy.abs() <= 8.0 * size {
            let Some(path) = PathBuilder::from_circle(c[0], c[1], r) else {
                return;
            };
            self.fill_and_stroke(&path, fill, stroke, width);
            return;
        }
        // A circle far larger than the canvas: only an arc of it crosses the view, and at that
        // scale the arc is almost straight. Walk the arc around the point of the circle nearest
        // the view's centre, in a local frame (p0, along u towards the view, t along the arc)
        // where no large number is subtracted, then close the region inward and clip it.
        let (vx, vy) = ((view[0] + view[2]) / 2.0, (view[1] + view[3]) / 2.0);
        let (dx, dy) = (vx - cx, vy - cy);
        let d = dx.hypot(dy);
        let (ux, uy) = if d > 0.0 {
            (dx / d, dy / d)
        } else {
            (0.0, -1.0)
        };
        let (tx, ty) = (-uy, ux);
        // p0 = c + r·u, written as the view centre moved back by (d − r).
        let (p0x, p0y) = (vx - (d - r64) * ux, vy - (d - r64) * uy);
        let half = 2.0 * size;
        let n = 256;
        let mut pts: Vec<[f64; 2]> = (0..=n)
            .map(|k| {
                let s = -half + 2.0 * half * f64::from(k) / f64::from(n);
                let a = s / r64;
                // r(cos a − 1) = −2r sin²(a/2), without cancellation.
                let back = -2.0 * r64 * (a / 2.0).sin().powi(2);
                let side = r64 * a.sin();
                [p0x + back * ux + side * tx, p0y + back * uy + side * ty]
            })
            .collect();
        let inward = 4.0 * size;
        if let (Some(&last), Some(&first)) = (pts.last(), pts.first()) {
            pts.push([last[0] - inward * ux, last[1] - inward * uy]);
            pts.push([first[0] - inward * ux, first[1] - inward * uy]);
        }
        self.clipped_polygon(&pts, fill, stroke, width);
    }

    /// A filled axis-aligned rectangle.
    pub fn rect(&mut self, x: f32, y: f32, w: f32, h: f32, fill: Rgba) {
        if !(x.is_finite() && y.is_finite() && w.is_finite() && h.is_finite()) {
            return;
        }
        // Clipped to the canvas (plus a pixel) first: tiny-skia is not asked to fill 1e30 px.
        let (cw, ch) = (self.width() + 1.0, self.height() + 1.0);
        let (x0, y0) = (x.max(-1.0), y.max(-1.0));
        let (x1, y1) = ((x + w.max(0.01)).min(cw), (y + h.max(0.01)).min(ch));
        if x1 <= x0 || y1 <= y0 {
            return;
        }
        if let Some(r) = Rect::from_ltrb(x0, y0, x1, y1) {
            self.pixmap
                .fill_rect(r, &paint(fill), Transform::identity(), None);
        }
    }

    /// An outlined axis-aligned rectangle (optionally dashed).
    #[allow(clippy::too_many_arguments)] // a drawing primitive: position, size, colour, width, style
    pub fn rect_outline(
        &mut self,
        x: f32,
        y: f32,
        w: f32,
        h: f32,
        c: Rgba,
        width: f32,
        dashed: bool,
    ) {
        self.polyline(
            &[[x, y], [x + w, y], [x + w, y + h], [x, y + h], [x, y]],
            c,
            width,
            dashed,
        );
    }

    /// The width of `text` at `size` pixels.
    pub fn text_width(&self, text: &str, size: f32) -> f32 {
        let s = self.font.as_scaled(PxScale::from(size));
        text.chars().map(|ch| s.h_advance(s.glyph_id(ch))).sum()
    }

    /// `text` shortened with an ellipsis until it fits `width` at `size` (at least one
    /// character and the ellipsis are kept).
    pub fn elide(&self, text: &str, size: f32, width: f32) -> String {
        let mut line: Vec<char> = text.chars().collect();
        let mut out = text.to_string();
        while self.text_width(&out, size) > width && line.len() > 1 {
            line.truncate(line.len().saturating_sub(2).max(1));
            out = line.iter().collect::<String>() + "…";
        }
        out
    }

    /// Draws `text` at `size` pixels anchored at (x, y); returns its width.
    pub fn text(&mut self, x: f32, y: f32, size: f32, text: &str, c: Rgba, anchor: Anchor) -> f32 {
        let w = self.text_width(text, size);
        let scaled = self.font.as_scaled(PxScale::from(size));
        let h = scaled.ascent() - scaled.descent();
        let (x0, y0) = anchor.top_left(x, y, w, h);
        if !(size.is_finite() && size > 0.0 && x0.is_finite() && y0.is_finite())
            || x0 > self.width()
            || y0 > self.height()
            || x0 + w < 0.0
            || y0 + h < 0.0
            || size > 4.0 * MAX_SIDE as f32
        {
            return w; // nothing of it would show
        }
        let baseline = y0 + scaled.ascent();
        let mut caret = x0;
        let (pw, ph) = (self.pixmap.width() as i32, self.pixmap.height() as i32);
        for ch in text.chars() {
            let id = scaled.glyph_id(ch);
            let advance = scaled.h_advance(id);
            let Some(g) = self.glyph(ch, size, caret, baseline) else {
                caret += advance;
                continue;
            };
            caret += advance;
            let pixels = self.pixmap.pixels_mut();
            for (k, &cov8) in g.cached.coverage.iter().enumerate() {
                if cov8 == 0 {
                    continue;
                }
                let cov = cov8 as f32 / 255.0;
                let px = g.x + (k as u32 % g.w) as i32;
                let py = g.y + (k as u32 / g.w) as i32;
                if px < 0 || py < 0 || px >= pw || py >= ph {
                    continue;
                }
                let i = (py * pw + px) as usize;
                let dst = pixels[i];
                let a = cov.clamp(0.0, 1.0) * c[3] as f32 / 255.0;
                // Source-over on premultiplied pixels.
                let blend = |d: u8, s: u8| (s as f32 * a + d as f32 * (1.0 - a)).round() as u8;
                let da = dst.alpha();
                let out_a = (255.0 * a + da as f32 * (1.0 - a)).round() as u8;
                if let Some(p) = tiny_skia::PremultipliedColorU8::from_rgba(
                    blend(dst.red(), c[0]).min(out_a),
                    blend(dst.green(), c[1]).min(out_a),
                    blend(dst.blue(), c[2]).min(out_a),
                    out_a,
                ) {
                    pixels[i] = p;
                }
            }
        }
        w
    }

    /// The coverage of `ch` at `size` with its origin at (x, y), from a per-thread cache keyed by
    /// the character, the size and the origin's eighth-of-a-pixel fraction (so placement is within
    /// 1/16 px of exact). Rasterizing each glyph once makes text several times cheaper.
    fn glyph(&self, ch: char, size: f32, x: f32, y: f32) -> Option<PlacedGlyph> {
        let (ix, iy) = (x.floor(), y.floor());
        let (fx, fy) = (((x - ix) * 8.0).round(), ((y - iy) * 8.0).round());
        let key = (ch, size.to_bits(), fx as u8, fy as u8);
        let cached = GLYPHS.with(|cache| {
            let mut cache = cache.borrow_mut();
            // A few hundred bytes a glyph: at most ~30 MB before the cache starts over.
            if cache.len() > 100_000 {
                cache.clear();
            }
            cache
                .entry(key)
                .or_insert_with(|| {
                    let scaled = self.font.as_scaled(PxScale::from(size));
                    let glyph = scaled
                        .glyph_id(ch)
                        .with_scale_and_position(PxScale::from(size), point(fx / 8.0, fy / 8.0));
                    self.font.outline_glyph(glyph).map(|outline| {
                        let b = outline.px_bounds();
                        let (w, h) = (b.width() as u32, b.height() as u32);
                        let mut coverage = vec![0u8; (w * h) as usize];
                        outline.draw(|gx, gy, c| {
                            if gx < w && gy < h {
                                coverage[(gy * w + gx) as usize] =
                                    (c.clamp(0.0, 1.0) * 255.0).round() as u8;
                            }
                        });
                        std::rc::Rc::new(CachedGlyph {
                            dx: b.min.x as i32,
                            dy: b.min.y as i32,
                            w,
                            coverage,
                        })
                    })
                })
                .clone()
        })?;
        Some(PlacedGlyph {
            x: ix as i32 + cached.dx,
            y: iy as i32 + cached.dy,
            w: cached.w.max(1),
            cached,
        })
    }

    /// Draws text on a rounded-ish label box so it stays readable over lines, moved in from
    /// the canvas's edges so that it is whole (a label wider than the canvas starts at its left
    /// edge).
    pub fn label(&mut self, x: f32, y: f32, size: f32, text: &str, c: Rgba, anchor: Anchor) {
        let w = self.text_width(text, size);
        let h = size * 1.2;
        let (x0, y0) = anchor.top_left(x, y, w, h);
        let x0 = x0.min(self.width() - w - 3.0).max(3.0);
        let y0 = y0.min(self.height() - h - 1.0).max(1.0);
        let mut bg = self.theme.background;
        bg[3] = 215;
        self.rect(x0 - 3.0, y0 - 1.0, w + 6.0, h + 2.0, bg);
        self.text(x0, y0, size, text, c, Anchor::TopLeft);
    }

    /// The colour of the pixel at (x, y), straight alpha (for tests).
    pub fn pixel(&self, x: u32, y: u32) -> Option<Rgba> {
        self.pixmap.pixel(x, y).map(|p| {
            let c = p.demultiply();
            [c.red(), c.green(), c.blue(), c.alpha()]
        })
    }

    /// Encodes the canvas as PNG (empty only if the in-memory encoder failed, which it does
    /// not for a valid pixmap).
    pub fn png(&self) -> Vec<u8> {
        self.pixmap.encode_png().unwrap_or_default()
    }

    /// Converts to an RGBA image (for animated GIFs and comparisons).
    pub fn to_rgba_image(&self) -> image::RgbaImage {
        let (w, h) = (self.pixmap.width(), self.pixmap.height());
        let data = self.pixmap.clone().take_demultiplied();
        image::RgbaImage::from_raw(w, h, data).unwrap_or_else(|| image::RgbaImage::new(w, h))
    }
}

struct CachedGlyph {
    dx: i32,
    dy: i32,
    w: u32,
    coverage: Vec<u8>,
}

struct PlacedGlyph {
    x: i32,
    y: i32,
    w: u32,
    cached: std::rc::Rc<CachedGlyph>,
}

type GlyphKey = (char, u32, u8, u8);

thread_local! {
    static GLYPHS: std::cell::RefCell<std::collections::HashMap<GlyphKey, Option<std::rc::Rc<CachedGlyph>>>> =
        std::cell::RefCell::new(std::collections::HashMap::new());
}

/// A path through `pts` (closed or open); None when it has no length.
fn path_through(pts: &[[f32; 2]], close: bool) -> Option<tiny_skia::Path> {
    let mut pb = PathBuilder::new();
    pb.move_to(pts[0][0], pts[0][1]);
    for p in &pts[1..] {
        pb.line_to(p[0], p[1]);
    }
    if close {
        pb.close();
    }
    pb.finish()
}

/// The base text size of a `width`×`height` canvas at UI scale `scale`: a 42nd of the
/// canvas, at least [`MIN_TEXT`]·scale, at most 40·scale pixels.
pub fn text_size_for(width: u32, height: u32, scale: f32) -> f32 {
    let scale = sane_scale(scale);
    let (w, h) = (width.clamp(1, MAX_SIDE), height.clamp(1, MAX_SIDE));
    let fit = w.min(h.saturating_mul(4) / 3) as f32 / 42.0;
    fit.max(MIN_TEXT * scale).min(40.0 * scale.max(1.0))
}

/// A UI scale kept within 0.25 … 8 (1 when not finite).
pub fn sane_scale(scale: f32) -> f32 {
    if scale.is_finite() {
        scale.clamp(0.25, 8.0)
    } else {
        1.0
    }
}

/// The part of segment a→b inside `r` = [x0, y0, x1, y1], in f64. Segments with an end
/// beyond ±10⁶ are first re-based on the point of their line nearest the rectangle, so that one
/// from −10³⁰ to 10³⁰ still clips to the pixels it crosses instead of collapsing to a point.
pub fn clip_segment(r: [f64; 4], a: [f64; 2], b: [f64; 2]) -> Option<([f64; 2], [f64; 2])> {
    let d = [b[0] - a[0], b[1] - a[1]];
    if !(d[0].is_finite() && d[1].is_finite()) {
        return None;
    }
    if a.iter().chain(&b).all(|v| v.abs() <= 1e6) {
        return liang_barsky(r, a, d, 0.0, 1.0);
    }
    let l = d[0].hypot(d[1]);
    if !(l > 0.0 && l.is_finite()) {
        return None;
    }
    let u = [d[0] / l, d[1] / l];
    let n = [-u[1], u[0]];
    // The line is {p : n·p = c}; c from the end nearer the origin (less rounding).
    let near = if a[0].hypot(a[1]) <= b[0].hypot(b[1]) {
        a
    } else {
        b
    };
    let c = n[0] * near[0] + n[1] * near[1];
    let vc = [(r[0] + r[2]) / 2.0, (r[1] + r[3]) / 2.0];
    let off = c - (n[0] * vc[0] + n[1] * vc[1]);
    let p0 = [vc[0] + n[0] * off, vc[1] + n[1] * off];
    let s = |p: [f64; 2]| u[0] * (p[0] - p0[0]) + u[1] * (p[1] - p0[1]);
    liang_barsky(r, p0, u, s(a), s(b))
}

/// Liang–Barsky: the part of base + t·d, t in [t0, t1], inside `r` = [x0, y0, x1, y1].
fn liang_barsky(
    r: [f64; 4],
    base: [f64; 2],
    d: [f64; 2],
    t0: f64,
    t1: f64,
) -> Option<([f64; 2], [f64; 2])> {
    let (mut t0, mut t1) = (t0, t1);
    for (p, q) in [
        (-d[0], base[0] - r[0]),
        (d[0], r[2] - base[0]),
        (-d[1], base[1] - r[1]),
        (d[1], r[3] - base[1]),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    (t0 <= t1).then(|| {
        (
            [base[0] + d[0] * t0, base[1] + d[1] * t0],
            [base[0] + d[0] * t1, base[1] + d[1] * t1],
        )
    })
}

/// The runs of an open polyline inside `view`, each a polyline of its own.
fn clip_polyline(pts: &[[f32; 2]], view: [f64; 4]) -> Vec<Vec<[f32; 2]>> {
    let mut runs: Vec<Vec<[f32; 2]>> = vec![];
    let mut cur: Vec<[f32; 2]> = vec![];
    let to32 = |p: [f64; 2]| [p[0] as f32, p[1] as f32];
    for w in pts.windows(2) {
        let a = [f64::from(w[0][0]), f64::from(w[0][1])];
        let b = [f64::from(w[1][0]), f64::from(w[1][1])];
        match clip_segment(view, a, b) {
            Some((p, q)) => {
                let p = to32(p);
                if cur.last() != Some(&p) {
                    if cur.len() > 1 {
                        runs.push(std::mem::take(&mut cur));
                    }
                    cur.clear();
                    cur.push(p);
                }
                let q32 = to32(q);
                cur.push(q32);
                if q32 != w[1] {
                    runs.push(std::mem::take(&mut cur));
                }
            }
            None => {
                if cur.len() > 1 {
                    runs.push(std::mem::take(&mut cur));
                }
                cur.clear();
            }
        }
    }
    if cur.len() > 1 {
        runs.push(cur);
    }
    runs
}

/// Sutherland–Hodgman: a closed polygon clipped to the rectangle `r` = [x0, y0, x1, y1]. The
/// result fills the same pixels inside `r` for any simple polygon; outside it, edges run along
/// the rectangle (which the canvas's margin keeps out of sight).
pub fn clip_polygon(pts: &[[f64; 2]], r: [f64; 4]) -> Vec<[f64; 2]> {
    // Each edge: (axis, bound, keep the side >= bound?).
    let edges = [
        (0, r[0], true),
        (0, r[2], false),
        (1, r[1], true),
        (1, r[3], false),
    ];
    let mut poly: Vec<[f64; 2]> = pts
        .iter()
        .copied()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .collect();
    for (axis, bound, ge) in edges {
        if poly.is_empty() {
            break;
        }
        let inside = |p: &[f64; 2]| {
            if ge {
                p[axis] >= bound
            } else {
                p[axis] <= bound
            }
        };
        let mut out = Vec::with_capacity(poly.len() + 4);
        for i in 0..poly.len() {
            let a = poly[i];
            let b = poly[(i + 1) % poly.len()];
            let (ia, ib) = (inside(&a), inside(&b));
            if ia != ib {
                let t = (bound - a[axis]) / (b[axis] - a[axis]);
                let mut p = [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t];
                p[axis] = bound;
                out.push(p);
            }
            if ib {
                out.push(b);
            }
        }
        poly = out;
    }
    poly
}

/// A colour with its alpha replaced.
pub fn with_alpha(c: Rgba, a: u8) -> Rgba {
    [c[0], c[1], c[2], a]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The non-background pixels with x in `xs`.
    fn inked(c: &Canvas, xs: std::ops::Range<u32>) -> usize {
        let bg = c.pixel(0, 0).unwrap();
        xs.flat_map(|x| (0..c.pixmap.height()).map(move |y| (x, y)))
            .filter(|&(x, y)| c.pixel(x, y) != Some(bg))
            .count()
    }

    #[test]
    fn a_label_at_the_edge_is_moved_in_whole() {
        // Centred 40 pixels left of the canvas, a 10-character label would be drawn entirely
        // outside it; it is moved in to start 3 pixels from the left edge.
        let mut c = Canvas::new(240, 60, Theme::LIGHT);
        let w = c.text_width("ωi sampled", 14.0);
        c.label(-40.0, 30.0, 14.0, "ωi sampled", c.theme.ink, Anchor::Center);
        assert!(inked(&c, 3..(3.0 + w) as u32 + 1) > 20);
        assert_eq!(inked(&c, (4.0 + w) as u32 + 3..240), 0);
        // Past the right edge and below the bottom: moved in too.
        let mut c = Canvas::new(240, 60, Theme::LIGHT);
        c.label(400.0, 90.0, 14.0, "ωi sampled", c.theme.ink, Anchor::Center);
        assert!(inked(&c, (237.0 - w) as u32..237) > 20);
        assert_eq!(inked(&c, 0..(236.0 - w) as u32 - 3), 0);
    }
}
