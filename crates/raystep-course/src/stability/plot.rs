//! Small log–log plots drawn on the diagrams' [`Canvas`] (tiny-skia + the bundled font): the
//! lab's error-vs-time scatter per primitive and `converge`'s error-vs-spp / error-vs-seconds
//! curves with a p10–p90 band. No plotting crate: the canvas already has lines, text and fills.

use super::{CostPoint, Precision, Primitive};
use crate::diagram::canvas::{Anchor, Canvas, Rgba, Theme, with_alpha};

/// One data series.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// (x, y) points.
    pub points: Vec<[f64; 2]>,
    /// Join the points with a line.
    pub line: bool,
    /// Filled markers (else hollow).
    pub filled: bool,
    /// Write the label beside each point instead of in the legend.
    pub label_points: bool,
    /// A shaded band: (x, y_low, y_high) per point.
    pub band: Option<Vec<[f64; 3]>>,
    /// Colour.
    pub color: Rgba,
}

/// A plot: axes (each linear or log), labels, series.
#[derive(Debug, Clone, PartialEq)]
pub struct Plot {
    /// Title, drawn at the top.
    pub title: String,
    /// A second line under the title.
    pub subtitle: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// The series.
    pub series: Vec<Series>,
}

/// A colour-blind-friendly palette (Okabe–Ito).
pub const PALETTE: [Rgba; 8] = [
    [0, 114, 178, 255],
    [213, 94, 0, 255],
    [0, 158, 115, 255],
    [204, 121, 167, 255],
    [230, 159, 0, 255],
    [86, 180, 233, 255],
    [0, 0, 0, 255],
    [240, 228, 66, 255],
];

/// Decade bounds [10^lo, 10^hi] covering the positive values.
fn decades(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| *v > 0.0 && v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let (mut a, mut b) = (lo.log10().floor(), hi.log10().ceil());
    if b <= a {
        b = a + 1.0;
    }
    if b - a < 2.0 {
        a -= 1.0;
    }
    (a, b)
}

fn tick_label(e: f64) -> String {
    let e = e as i32;
    match e {
        0 => "1".into(),
        1 => "10".into(),
        2 => "100".into(),
        -1 => "0.1".into(),
        -2 => "0.01".into(),
        _ => format!("1e{e}"),
    }
}

/// Draws `plot` with both axes logarithmic (values ≤ 0 are drawn on the lower edge) and returns
/// the PNG bytes.
pub fn draw(plot: &Plot, width: u32, height: u32) -> Vec<u8> {
    let mut c = Canvas::new(width, height, Theme::LIGHT);
    let th = Theme::LIGHT;
    let ts = 15.0f32;
    let (w, h) = (c.width(), c.height());
    let (left, right, top, bottom) = (80.0f32, w - 30.0, 84.0f32, h - 60.0);
    c.text(w / 2.0, 10.0, 19.0, &plot.title, th.ink, Anchor::TopCenter);
    c.text(
        w / 2.0,
        34.0,
        13.0,
        &plot.subtitle,
        th.muted,
        Anchor::TopCenter,
    );
    let xs = plot
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p[0]));
    let ys = plot.series.iter().flat_map(|s| {
        s.points.iter().map(|p| p[1]).chain(
            s.band
                .iter()
                .flat_map(|b| b.iter().flat_map(|q| [q[1], q[2]])),
        )
    });
    let (x0, x1) = decades(xs);
    let (y0, y1) = decades(ys);
    let px = |x: f64| {
        let lx = if x > 0.0 { x.log10() } else { x0 };
        left + ((lx - x0) / (x1 - x0)) as f32 * (right - left)
    };
    let py = |y: f64| {
        let ly = if y > 0.0 { y.log10().max(y0) } else { y0 };
        bottom - ((ly - y0) / (y1 - y0)) as f32 * (bottom - top)
    };
    // Grid and decade ticks.
    for e in (x0 as i32)..=(x1 as i32) {
        let x = px(10f64.powi(e));
        c.line([x, top], [x, bottom], with_alpha(th.faded, 160), 1.0);
        c.text(
            x,
            bottom + 6.0,
            ts - 2.0,
            &tick_label(e as f64),
            th.muted,
            Anchor::TopCenter,
        );
    }
    for e in (y0 as i32)..=(y1 as i32) {
        let y = py(10f64.powi(e));
        c.line([left, y], [right, y], with_alpha(th.faded, 160), 1.0);
        c.text(
            left - 6.0,
            y,
            ts - 2.0,
            &tick_label(e as f64),
            th.muted,
            Anchor::MiddleRight,
        );
    }
    c.rect_outline(left, top, right - left, bottom - top, th.ink, 1.2, false);
    c.text(
        (left + right) / 2.0,
        h - 24.0,
        ts,
        &plot.x_label,
        th.ink,
        Anchor::TopCenter,
    );
    // The y label, horizontal above the axis (the canvas draws no rotated text).
    c.text(
        left - 70.0,
        top - 22.0,
        ts - 1.0,
        &plot.y_label,
        th.ink,
        Anchor::TopLeft,
    );
    let mut legend_y = top + 8.0;
    // Placed point labels, to keep later ones from overlapping earlier ones.
    let mut placed: Vec<[f32; 4]> = vec![];
    for s in &plot.series {
        if let Some(band) = &s.band {
            let mut poly: Vec<[f32; 2]> = band.iter().map(|q| [px(q[0]), py(q[2])]).collect();
            poly.extend(band.iter().rev().map(|q| [px(q[0]), py(q[1])]));
            if poly.len() >= 3 {
                c.polygon(&poly, Some(with_alpha(s.color, 50)), None, 0.0);
            }
        }
        let pts: Vec<[f32; 2]> = s.points.iter().map(|p| [px(p[0]), py(p[1])]).collect();
        if s.line {
            c.polyline(&pts, s.color, 2.0, false);
        }
        for (k, p) in pts.iter().enumerate() {
            let fill = s.filled.then_some(s.color);
            c.circle(*p, 5.5, fill, Some(s.color), 2.0);
            if s.label_points {
                // Try spots right and left of the point, nearest first, and take the first that
                // overlaps no earlier label and stays inside the plot.
                let size = ts - 3.0;
                let (lw, lh) = (c.text_width(&s.label, size) + 6.0, size * 1.2 + 2.0);
                let _ = k;
                let mut spot = None;
                'find: for dy in [-10.0f32, 10.0, -26.0, 26.0, -42.0, 42.0, -58.0, 58.0] {
                    for right_side in [true, false] {
                        let x0 = if right_side {
                            p[0] + 9.0
                        } else {
                            p[0] - 9.0 - lw
                        };
                        let y0 = p[1] + dy - lh / 2.0;
                        let r = [x0, y0, x0 + lw, y0 + lh];
                        let inside = r[0] >= left && r[2] <= right && r[1] >= top && r[3] <= bottom;
                        let free = placed
                            .iter()
                            .all(|o| r[2] <= o[0] || r[0] >= o[2] || r[3] <= o[1] || r[1] >= o[3]);
                        if inside && free {
                            spot = Some(r);
                            break 'find;
                        }
                    }
                }
                let r = spot.unwrap_or([
                    p[0] + 9.0,
                    p[1] - 10.0 - lh / 2.0,
                    p[0] + 9.0 + lw,
                    p[1] - 10.0 + lh / 2.0,
                ]);
                placed.push(r);
                c.label(
                    r[0] + 3.0,
                    r[1] + 1.0,
                    size,
                    &s.label,
                    s.color,
                    Anchor::TopLeft,
                );
            }
        }
        if !s.label_points {
            let lx = right - 12.0;
            c.label(
                lx,
                legend_y,
                ts - 2.0,
                &s.label,
                s.color,
                Anchor::MiddleRight,
            );
            legend_y += ts + 4.0;
        }
    }
    c.png()
}

/// The lab's error-vs-time plot for one primitive: one point per method × precision, ns per test
/// across, p99 t error in ulps up (0 drawn on the lower edge); filled f32, hollow f64. Each label
/// carries the method's misclassification and leak counts. `None` for a primitive without points.
pub fn cost_plot(points: &[CostPoint], prim: Primitive, quick: bool) -> Option<Vec<u8>> {
    let pts: Vec<&CostPoint> = points.iter().filter(|p| p.primitive == prim).collect();
    if pts.is_empty() {
        return None;
    }
    let spawn = prim == Primitive::Spawn;
    let mut series = vec![];
    for (k, p) in pts.iter().enumerate() {
        let y = if spawn {
            p.self_hits as f64 + p.misclassified as f64
        } else {
            p.p99_ulps
        };
        let mut label = p.label();
        if spawn {
            label += &format!(" ({} self-hits, {} skips)", p.self_hits, p.misclassified);
        } else if p.misclassified + p.leaks + p.nonfinite > 0 {
            label += &format!(
                " ({} miscl., {} leaks{})",
                p.misclassified,
                p.leaks,
                if p.nonfinite > 0 {
                    format!(", {} NaN", p.nonfinite)
                } else {
                    String::new()
                }
            );
        }
        series.push(Series {
            label,
            points: vec![[p.ns_per_test, y]],
            line: false,
            filled: p.precision == Precision::F32,
            label_points: true,
            band: None,
            color: PALETTE[(k / 2) % PALETTE.len()],
        });
    }
    let plot = Plot {
        title: format!("{}: error against cost", prim.name()),
        subtitle: format!(
            "one point per method × precision over every {} case{}; filled f32, hollow f64",
            prim.name(),
            if quick { " (quick suite)" } else { "" }
        ),
        x_label: "ns per test (log)".into(),
        y_label: if spawn {
            "self-hits + skipped surfaces (log; 0 on the lower edge)".into()
        } else {
            "p99 |t − t_exact| in ulps (log; 0 on the lower edge)".into()
        },
        series,
    };
    Some(draw(&plot, 900, 600))
}
