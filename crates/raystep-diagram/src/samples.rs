//! The pixel's samples: each sample's value (its luminance, Rec. 709) as a dot in its own
//! colour, sample by sample, with the running mean after each — the estimate converging — and
//! the pixel (the mean of all of them) as a dashed line. The traced sample is ringed. Drawn from
//! the trace's Monte Carlo record ([`crate::record::samples::McRecord`]).

use super::canvas::{Anchor, Canvas, with_alpha};
use super::quadratic::{tick_label, ticks};
use super::{ViewOptions, title_first_fitting};
use crate::record::Trace;
use crate::record::number::{Style, fmt};
use crate::record::samples::{McRecord, luminance};
use crate::render::image::srgb8;

/// Where the plot puts things, in canvas pixels.
#[derive(Debug, Clone, PartialEq)]
pub struct SamplesLayout {
    /// The plot area: [left, top, right, bottom].
    pub area: [f32; 4],
    /// The luminance at the top of the plot (the bottom is 0).
    pub top_value: f32,
    /// Each kept sample's dot centre (None for a sample that is not finite).
    pub dots: Vec<Option<[f32; 2]>>,
    /// The running mean's points, one per sample.
    pub running: Vec<[f32; 2]>,
    /// The height of the pixel's line (the mean of all kept samples).
    pub mean_y: f32,
}

/// The plot's layout for `trace` on a canvas of `opts`'s size, or None without a Monte Carlo
/// record.
pub fn layout(trace: &Trace, opts: &ViewOptions) -> Option<SamplesLayout> {
    let mc = trace.monte_carlo.as_ref()?;
    let c = Canvas::for_view(opts);
    Some(layout_on(&c, mc))
}

fn layout_on(c: &Canvas, mc: &McRecord) -> SamplesLayout {
    let ts = c.text_size;
    let area = [
        ts * 4.5,
        ts * 3.2,
        c.width() - ts * 1.2,
        c.height() - ts * 5.8,
    ];
    let lum: Vec<f32> = mc.samples.iter().map(|s| luminance(s.color)).collect();
    let max = lum
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0f32, f32::max);
    let top_value = if max > 0.0 { max * 1.08 } else { 1.0 };
    let n = mc.samples.len().max(1);
    let x = |i: usize| area[0] + (i as f32 + 0.5) / n as f32 * (area[2] - area[0]);
    let y = |v: f32| area[3] - (v / top_value).clamp(0.0, 1.0) * (area[3] - area[1]);
    let dots = lum
        .iter()
        .enumerate()
        .map(|(i, v)| v.is_finite().then(|| [x(i), y(*v)]))
        .collect();
    let (mut sum, mut running) = (0.0f64, vec![]);
    for (i, v) in lum.iter().enumerate() {
        if v.is_finite() {
            sum += *v as f64;
        }
        running.push([x(i), y((sum / (i + 1) as f64) as f32)]);
    }
    SamplesLayout {
        area,
        top_value,
        dots,
        running,
        mean_y: y(luminance(mc.mean())),
    }
}

/// Draws the samples diagram (a note in its place without a Monte Carlo record).
pub fn draw(trace: &Trace, opts: &ViewOptions) -> Canvas {
    let mut c = Canvas::for_view(opts);
    let th = c.theme;
    let ts = c.text_size;
    let Some(mc) = trace.monte_carlo.as_ref() else {
        c.text(
            ts,
            ts,
            ts,
            "no samples: this trace is Whitted's",
            th.muted,
            Anchor::TopLeft,
        );
        return c;
    };
    let l = layout_on(&c, mc);
    let mean = mc.mean();
    let [x, y] = trace.pixel;
    let kept = mc.samples.len();
    let of = if kept < mc.spp as usize {
        format!("the first {kept} of {} samples", mc.spp)
    } else {
        format!("{kept} sample{}", if kept == 1 { "" } else { "s" })
    };
    title_first_fitting(
        &mut c,
        &[
            format!(
                "Pixel ({x}, {y}): {of} · the pixel's mean {} (luminance {})",
                rgb(mean),
                fmt(luminance(mean), Style::Label)
            ),
            format!("Pixel ({x}, {y}): {of}"),
            format!("Pixel ({x}, {y})"),
        ],
    );
    let [left, top, right, bottom] = l.area;
    // Axes and ticks.
    c.line([left, bottom], [right, bottom], th.muted, 1.0);
    c.line([left, top], [left, bottom], th.muted, 1.0);
    let small = ts * 0.8;
    let (yt, dec) = ticks(0.0, l.top_value as f64, 5);
    for v in yt {
        let py = bottom - (v as f32 / l.top_value) * (bottom - top);
        c.line([left - ts * 0.3, py], [left, py], th.muted, 1.0);
        c.line([left, py], [right, py], with_alpha(th.faded, 120), 1.0);
        c.text(
            left - ts * 0.4,
            py,
            small,
            &tick_label(v, dec),
            th.muted,
            Anchor::MiddleRight,
        );
    }
    let n = kept.max(1);
    let (xt, _) = ticks(0.0, (n - 1) as f64, 6);
    for v in xt.into_iter().filter(|v| v.fract() == 0.0) {
        let px = left + (v as f32 + 0.5) / n as f32 * (right - left);
        c.line([px, bottom], [px, bottom + ts * 0.3], th.muted, 1.0);
        c.text(
            px,
            bottom + ts * 0.4,
            small,
            &format!("{v}"),
            th.muted,
            Anchor::TopCenter,
        );
    }
    c.text(
        (left + right) / 2.0,
        bottom + ts * 1.5,
        small,
        "sample index",
        th.muted,
        Anchor::TopCenter,
    );
    // The pixel, the running mean, the dots.
    c.dashed([left, l.mean_y], [right, l.mean_y], th.ink, 1.5);
    c.polyline(&l.running, th.ray, 2.0, false);
    let r = ((right - left) / n as f32 * 0.35).clamp(1.5 * c.scale, 5.0 * c.scale);
    let bad = l.dots.iter().filter(|d| d.is_none()).count();
    // Samples after the traced one are faded: playing the samples one at a time, they fill in.
    for (s, d) in mc.samples.iter().zip(&l.dots) {
        let Some(p) = *d else { continue };
        let alpha = if s.sample <= trace.sample { 255 } else { 60 };
        let fill = [
            srgb8(s.color[0]),
            srgb8(s.color[1]),
            srgb8(s.color[2]),
            alpha,
        ];
        c.circle(p, r, Some(fill), Some(with_alpha(th.muted, alpha)), 1.0);
    }
    let this = trace.sample as usize;
    let mut legend_note = String::new();
    if let Some(Some(p)) = l.dots.get(this) {
        c.circle(*p, r + 4.0 * c.scale, None, Some(th.hit), 2.5);
        let v = mc.samples[this].color;
        legend_note = format!(
            "this trace is sample {this}: {} (luminance {})",
            rgb(v),
            fmt(luminance(v), Style::Label)
        );
    }
    // Legend.
    let ly = c.height() - ts * 1.5;
    let mut lx = ts * 0.6;
    c.circle(
        [lx + small * 0.5, ly + small * 0.6],
        small * 0.35,
        Some(th.faded),
        Some(th.muted),
        1.0,
    );
    lx += small * 1.3;
    lx += c.text(lx, ly, small, "one sample", th.ink, Anchor::TopLeft) + small;
    // The two lines' legend entries: a short stroke (solid or dashed), then its words.
    for (words, colour, width, dashed) in [
        ("running mean", th.ray, 2.0, false),
        ("the pixel", th.ink, 1.5, true),
    ] {
        let mid = ly + small * 0.6;
        c.polyline(&[[lx, mid], [lx + small * 1.5, mid]], colour, width, dashed);
        lx += small * 1.9;
        lx += c.text(lx, ly, small, words, th.ink, Anchor::TopLeft) + small;
    }
    let mut note = legend_note;
    if bad > 0 {
        note = format!("{note} · {bad} not finite (left out)");
    }
    if !note.is_empty() {
        let shown = c.elide(&note, small, c.width() - ts * 1.2);
        c.text(
            ts * 0.6,
            ly - small * 1.4,
            small,
            &shown,
            th.ink,
            Anchor::TopLeft,
        );
    }
    c
}

fn rgb(c: [f32; 3]) -> String {
    crate::record::number::v3_in(c, Style::Decimals(3))
}
