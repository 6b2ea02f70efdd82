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

/// A pixmap with drawing helpers.
pub struct Canvas {
    /// The pixels.
    pub pixmap: Pixmap,
    /// The colours.
    pub theme: Theme,
    /// Base text size in pixels (scales with the canvas).
    pub text_size: f32,
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
    /// A blank canvas of `width`×`height` pixels (at least 16×16).
    pub fn new(width: u32, height: u32, theme: Theme) -> Canvas {
        let (w, h) = (width.max(16), height.max(16));
        let mut pixmap = Pixmap::new(w, h).expect("non-zero size");
        pixmap.fill(color(theme.background));
        let font = FontRef::try_from_slice(epaint_default_fonts::HACK_REGULAR)
            .expect("the bundled font parses");
        Canvas {
            pixmap,
            theme,
            text_size: (w.min(h * 4 / 3) as f32 / 42.0).clamp(11.0, 40.0),
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
        let Some(path) = path_through(pts, false) else {
            return;
        };
        let mut stroke = Stroke {
            width,
            line_cap: LineCap::Round,
            ..Default::default()
        };
        if dashed {
            stroke.dash = StrokeDash::new(vec![width * 3.0, width * 2.5], 0.0);
        }
        self.pixmap
            .stroke_path(&path, &paint(c), &stroke, Transform::identity(), None);
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
        let Some(path) = path_through(pts, true) else {
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
        let Some(path) = PathBuilder::from_circle(c[0], c[1], r) else {
            return;
        };
        self.fill_and_stroke(&path, fill, stroke, width);
    }

    /// A filled axis-aligned rectangle.
    pub fn rect(&mut self, x: f32, y: f32, w: f32, h: f32, fill: Rgba) {
        if let Some(r) = Rect::from_xywh(x, y, w.max(0.01), h.max(0.01)) {
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

    /// Draws `text` at `size` pixels anchored at (x, y); returns its width.
    pub fn text(&mut self, x: f32, y: f32, size: f32, text: &str, c: Rgba, anchor: Anchor) -> f32 {
        let w = self.text_width(text, size);
        let scaled = self.font.as_scaled(PxScale::from(size));
        let h = scaled.ascent() - scaled.descent();
        let (x0, y0) = anchor.top_left(x, y, w, h);
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

    /// Draws text on a rounded-ish label box so it stays readable over lines.
    pub fn label(&mut self, x: f32, y: f32, size: f32, text: &str, c: Rgba, anchor: Anchor) {
        let w = self.text_width(text, size);
        let h = size * 1.2;
        let (x0, y0) = anchor.top_left(x, y, w, h);
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

    /// Encodes the canvas as PNG.
    pub fn png(&self) -> Vec<u8> {
        self.pixmap.encode_png().expect("an in-memory PNG encodes")
    }

    /// Converts to an RGBA image (for animated GIFs and comparisons).
    pub fn to_rgba_image(&self) -> image::RgbaImage {
        let data = self.pixmap.clone().take_demultiplied();
        image::RgbaImage::from_raw(self.pixmap.width(), self.pixmap.height(), data)
            .expect("sizes match")
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

/// A colour with its alpha replaced.
pub fn with_alpha(c: Rgba, a: u8) -> Rgba {
    [c[0], c[1], c[2], a]
}
