//! The ray–sphere quadratic: f(t) = a t² + b t + c of one recorded sphere test, plotted over a t
//! range that shows t = 0 (the ray's origin) and both roots, with the allowed interval of the ray
//! shaded, the roots marked and the chosen root highlighted, next to a panel of the test's
//! numbers and the reason for its decision.
//!
//! Everything is read from the [`SphereTest`] record: the curve is f evaluated from the recorded
//! a, b, c (drawing, not intersecting), the roots and the choice are the kernel's own.

use super::canvas::{Rgba, with_alpha};
pub use super::text::PlacedLabel;
use super::text::{
    Placer, Rich, draw_panel, fitting_panel_width, interval_at, label_box, ray_name, rect_dist,
    rich, short_eq,
};
use super::{Anchor, Canvas, ViewOptions, pick_step, title, title_first_fitting};
use crate::record::number::{Style, fmt64, num};
use crate::record::words;
use crate::record::{Step, Trace};
use crate::shapes::{RootChoice, SphereCase, SphereMethod, SphereTest};

/// Chooses "nice" tick positions (1, 2, 5 × 10ᵏ) covering [lo, hi]; returns them with the number
/// of decimals their labels need.
pub(crate) fn ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, usize) {
    let span = hi - lo;
    if !span.is_finite() || span <= 0.0 {
        return (vec![], 0);
    }
    let raw = span / target.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let decimals = (-(step.log10().floor())).max(0.0) as usize;
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    // At most a few hundred ticks, whatever the rounding of first and last.
    let out = (first..=last).take(500).map(|k| k as f64 * step).collect();
    (out, decimals.min(9))
}

pub(crate) fn tick_label(v: f64, decimals: usize) -> String {
    let v = if v.abs() < 1e-12 { 0.0 } else { v };
    if v != 0.0 && (v.abs() >= 1e6 || v.abs() < 1e-4) {
        fmt64(v, Style::Label)
    } else {
        format!("{v:.decimals$}")
    }
}

// ---------------------------------------------------------------------------------------------
// The quadratic diagram.

/// Maps the plot's data coordinates (t, f(t)) to canvas pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlotFrame {
    /// Left edge of the plot area, pixels.
    pub left: f32,
    /// Top edge of the plot area, pixels.
    pub top: f32,
    /// Right edge of the plot area, pixels.
    pub right: f32,
    /// Bottom edge of the plot area, pixels.
    pub bottom: f32,
    /// The t range shown, left to right.
    pub t_range: [f64; 2],
    /// The f range shown, bottom to top.
    pub f_range: [f64; 2],
}

impl PlotFrame {
    /// The x pixel of parameter t.
    pub fn x(&self, t: f64) -> f32 {
        let [a, b] = self.t_range;
        self.left + ((t - a) / (b - a)) as f32 * (self.right - self.left)
    }

    /// The y pixel of the value f.
    pub fn y(&self, f: f64) -> f32 {
        let [a, b] = self.f_range;
        self.bottom - ((f - a) / (b - a)) as f32 * (self.bottom - self.top)
    }

    /// The parameter t at pixel column x.
    pub fn t_at(&self, x: f32) -> f64 {
        let [a, b] = self.t_range;
        a + ((x - self.left) / (self.right - self.left)) as f64 * (b - a)
    }
}

/// What the quadratic diagram draws, and where: the test it explains and the positions of its
/// markers (so tests can check the drawing against the record).
#[derive(Debug, Clone, PartialEq)]
pub struct QuadraticLayout {
    /// Index of the explained step in [`Trace::timeline`].
    pub step: usize,
    /// The sphere's name.
    pub name: String,
    /// The ray that ran the test (e.g. "shadow ray (depth 1)").
    pub ray: String,
    /// Its kind (a shadow ray's t_max is where it reaches the light, not a closest hit).
    pub kind: crate::record::RayKind,
    /// The recorded test.
    pub test: SphereTest<f32>,
    /// The ray's interval (t_min, t_max) when the test ran.
    pub interval: (f32, f32),
    /// The plot area and its mapping; None when the coefficients cannot be plotted (not finite).
    pub frame: Option<PlotFrame>,
    /// Pixel positions of the roots t₀, t₁ on the t axis (f = 0), when there are roots.
    pub roots: Option<[[f32; 2]; 2]>,
    /// Pixel position of the chosen root (the hit), when the test hit.
    pub chosen: Option<[f32; 2]>,
    /// The right-hand text panel: [x0, y0, x1, y1]; empty (x1 < x0) when the canvas is too
    /// short for it, and then left out.
    pub panel: [f32; 4],
}

/// f(t) = a t² + b t + c from the recorded coefficients, in f64 for a smooth curve.
pub fn f_of(test: &SphereTest<f32>, t: f64) -> f64 {
    let (a, b, c) = (test.a as f64, test.b as f64, test.c as f64);
    (a * t + b) * t + c
}

/// The t and f ranges shown: t = 0, both roots (or the vertex −b/2a when there are none) and,
/// when a root was refused for lying beyond it, t_max, with a margin; f from just below the
/// lowest point to a top that keeps the dip below the axis visible.
fn ranges(test: &SphereTest<f32>, interval: (f32, f32)) -> Option<([f64; 2], [f64; 2])> {
    let (a, b) = (test.a as f64, test.b as f64);
    if !a.is_finite() || a <= 0.0 || !b.is_finite() || !test.c.is_finite() {
        return None;
    }
    let vertex = -b / (2.0 * a);
    let fv = f_of(test, vertex);
    let mut pts = vec![0.0, vertex];
    match test.roots {
        Some([r0, r1]) if r0.is_finite() && r1.is_finite() => pts.extend([r0 as f64, r1 as f64]),
        _ => {
            // No roots: show the parabola symmetrically about its vertex.
            pts.push(2.0 * vertex);
            let w = (fv.abs() / a).sqrt();
            pts.extend([vertex - w, vertex + w]);
        }
    }
    if test.choice == RootChoice::BeyondTMax && interval.1.is_finite() {
        pts.push(interval.1 as f64);
    }
    let lo = pts.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = pts.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let span = if hi - lo > 0.0 {
        hi - lo
    } else {
        lo.abs().max(1.0)
    };
    let t_range = [lo - 0.12 * span, hi + 0.12 * span];
    if !t_range[0].is_finite() || !t_range[1].is_finite() || t_range[1] <= t_range[0] {
        return None;
    }
    // f over the range: the ends and (if inside) the vertex.
    let ends = [f_of(test, t_range[0]), f_of(test, t_range[1])];
    let f_lo = if vertex > t_range[0] && vertex < t_range[1] {
        fv
    } else {
        ends[0].min(ends[1])
    };
    let mut f_hi = ends[0].max(ends[1]);
    let mut f_lo = f_lo.min(0.0);
    if f_lo < 0.0 {
        // A dip of depth |f_v| next to a c of thousands would be a hairline: keep the dip at
        // least a ninth of the height; the curve leaves through the top.
        f_hi = f_hi.min(-f_lo * 8.0).max(-f_lo * 0.5);
    }
    f_hi = f_hi.max(0.0);
    if f_hi - f_lo <= 0.0 {
        f_hi = f_lo + 1.0;
    }
    let pad = 0.08 * (f_hi - f_lo);
    // With no roots the curve stays above the axis: leave room below it to say so.
    f_lo -= if test.roots.is_none() { 2.0 * pad } else { pad };
    f_hi += pad;
    (f_lo.is_finite() && f_hi.is_finite()).then_some((t_range, [f_lo, f_hi]))
}

/// Where everything goes, from the trace alone.
pub fn layout(trace: &Trace, opts: &ViewOptions) -> Option<QuadraticLayout> {
    let (k, step) = pick_step(trace, opts.focus, |s| matches!(s, Step::Sphere { .. }))?;
    let Step::Sphere { name, test, .. } = step else {
        return None;
    };
    let tl = trace.timeline();
    let (ray, record) = tl[k];
    let interval = interval_at(ray, record);
    let c = Canvas::for_view(opts);
    let (w, h, s) = (c.width(), c.height(), c.text_size);
    let top = s * 0.6 + s * 1.15 * 1.5;
    let small = (s * 0.85).max(13.0 * c.scale);
    // The panel of values is drawn where its lines, wrapped to its width, fit at the labels'
    // size; on a canvas too short for them it is left out and the plot takes the whole width,
    // rather than printing them too small to read (in the app the math panel shows the same
    // values, large).
    let panel_w = fitting_panel_width(
        &c,
        (
            &panel_heading(name),
            &panel_rows(test, interval, ray.kind, &c),
        ),
        small,
        (w * 0.37).max(150.0).min(w * 0.5),
        h - top - s * 0.5,
    );
    let panel = [w - panel_w, top, w - s * 0.5, h - s * 0.5];
    let ytick_w = c.text_width("-0000.0", small);
    let left = s * 0.6 + ytick_w + s * 0.3;
    // On a canvas too small for the plot and the panel the frame shrinks to a pixel (never to a
    // negative size: everything below maps t and f through it).
    let right = if panel_w > 0.0 {
        panel[0] - s * 1.2
    } else {
        w - s * 0.8
    }
    .max(left + 1.0);
    let plot_top = top + small * 1.6;
    let bottom = (h - small * 2.6).max(plot_top + 1.0);
    let frame = ranges(test, interval).map(|(t_range, f_range)| PlotFrame {
        left,
        top: plot_top,
        right,
        bottom,
        t_range,
        f_range,
    });
    let roots = frame.and_then(|f| {
        let [r0, r1] = test.roots?;
        Some([[f.x(r0 as f64), f.y(0.0)], [f.x(r1 as f64), f.y(0.0)]])
    });
    let chosen = frame.and_then(|f| test.t.map(|t| [f.x(t as f64), f.y(0.0)]));
    Some(QuadraticLayout {
        step: k,
        name: name.clone(),
        ray: ray_name(ray),
        kind: ray.kind,
        test: *test,
        interval,
        frame,
        roots,
        chosen,
        panel,
    })
}

/// The visible runs of the curve: f sampled across the frame, clipped to the f range.
fn curve_runs(test: &SphereTest<f32>, f: &PlotFrame) -> Vec<Vec<[f32; 2]>> {
    let n = ((f.right - f.left) as usize).clamp(64, 1200);
    let [lo, hi] = f.f_range;
    let mut runs: Vec<Vec<[f32; 2]>> = vec![];
    let mut cur: Vec<[f32; 2]> = vec![];
    let mut prev: Option<(f64, f64)> = None;
    for i in 0..=n {
        let t = f.t_range[0] + (f.t_range[1] - f.t_range[0]) * i as f64 / n as f64;
        let v = f_of(test, t);
        let inside = v >= lo && v <= hi;
        if let Some((pt, pv)) = prev {
            let was_inside = pv >= lo && pv <= hi;
            if was_inside != inside {
                // Where the segment crosses the band's edge.
                let edge = if inside {
                    if pv > hi { hi } else { lo }
                } else if v > hi {
                    hi
                } else {
                    lo
                };
                let s = (edge - pv) / (v - pv);
                let tc = pt + s * (t - pt);
                cur.push([f.x(tc), f.y(edge)]);
                if !inside {
                    runs.push(std::mem::take(&mut cur));
                }
            }
        }
        if inside {
            cur.push([f.x(t), f.y(v)]);
        }
        prev = Some((t, v));
    }
    if cur.len() > 1 {
        runs.push(cur);
    }
    runs
}

/// What the diagram calls the chosen root.
fn chosen_root(test: &SphereTest<f32>) -> &'static str {
    match test.choice {
        RootChoice::NearRoot => "t_0, the near root",
        RootChoice::FarRoot => "t_1, the far root",
        RootChoice::NoRoots | RootChoice::Behind | RootChoice::BeyondTMax => "none: miss",
    }
}

/// The diagram's titles, longest first ([`super::test_titles`]): the object and ray, the
/// step's number and which ray–sphere test of the trace it is.
pub fn titles(trace: &Trace, l: &QuadraticLayout) -> Vec<String> {
    super::test_titles(
        trace,
        "Ray–sphere quadratic",
        &l.name,
        &l.ray,
        l.step,
        |s| matches!(s, Step::Sphere { .. }),
    )
}

/// Draws the diagram.
pub fn draw(trace: &Trace, opts: &ViewOptions) -> Canvas {
    draw_labelled(trace, opts).0
}

/// Draws the diagram; returns it with the labels placed on the plot (for tests: which label
/// sits next to which marker).
pub fn draw_labelled(trace: &Trace, opts: &ViewOptions) -> (Canvas, Vec<PlacedLabel>) {
    let opts = &opts.sane();
    let mut c = Canvas::for_view(opts);
    let Some(l) = layout(trace, opts) else {
        title(&mut c, "quadratic: this trace has no ray–sphere test");
        return (c, vec![]);
    };
    let th = c.theme;
    let s = c.text_size;
    let small = (s * 0.85).max(13.0 * c.scale);
    title_first_fitting(&mut c, &titles(trace, &l));
    let test = &l.test;

    let mut labels = vec![];
    if let Some(f) = l.frame {
        labels = draw_plot(&mut c, &l, &f, small);
    } else {
        let r = Rich::new("cannot plot: the coefficients are not finite");
        let y = c.height() / 2.0;
        rich(&mut c, l.panel[0] / 2.0, y, s, &r, th.ray, Anchor::Center);
    }

    // The panel: exact values (the renderer's f32s), the case and the decision.
    let rows = panel_rows(test, l.interval, l.kind, &c);
    if l.panel[2] > l.panel[0] {
        draw_panel(&mut c, l.panel, small, panel_heading(&l.name), &rows);
    }
    (c, labels)
}

/// The heading of the quadratic's panel of values.
fn panel_heading(name: &str) -> Rich {
    Rich::new("sphere ").plain(&format!("\"{name}\""))
}

/// The quadratic's panel of values: exact values (the renderer's f32s), the case and the
/// decision, each row with its colour (an empty row is a gap).
fn panel_rows(
    test: &SphereTest<f32>,
    interval: (f32, f32),
    kind: crate::record::RayKind,
    c: &Canvas,
) -> Vec<(String, Rgba)> {
    let th = c.theme;
    let mut rows: Vec<(String, Rgba)> = vec![];
    let method = match test.method {
        SphereMethod::Textbook => "method: textbook",
        SphereMethod::Stable => "method: stable (RTG ch. 7)",
    };
    rows.push((method.into(), th.muted));
    rows.push(("f(t) = at² + bt + c".into(), th.muted));
    for (n, v) in [("a", test.a), ("b", test.b), ("c", test.c)] {
        rows.push((format!("{n} = {}", num(v)), th.ink));
    }
    match test.method {
        SphereMethod::Textbook => {
            rows.push((format!("Δ = b² − 4ac = {}", num(test.discriminant)), th.ink))
        }
        SphereMethod::Stable => {
            if let Some(dp) = test.delta_prime {
                rows.push((format!("Δ′ = {}", num(dp)), th.ink));
            }
            rows.push((format!("Δ = 4aΔ′ = {}", num(test.discriminant)), th.ink));
            if let Some(q) = test.q {
                rows.push((format!("q = {}", num(q)), th.ink));
            }
        }
    }
    rows.push((String::new(), th.ink));
    let case = words::sphere_case(test.case);
    rows.push((case.into(), th.ink));
    if let Some([r0, r1]) = test.roots {
        let col = |r: f32| if test.t == Some(r) { th.hit } else { th.ink };
        if test.case == SphereCase::Tangent || r0 == r1 {
            rows.push((format!("t_0 = t_1 = {}", num(r0)), col(r0)));
        } else {
            rows.push((format!("t_0 = {}", num(r0)), col(r0)));
            rows.push((format!("t_1 = {}", num(r1)), col(r1)));
        }
    }
    let (t_min, t_max) = interval;
    rows.push((
        format!("ray: t in ({}, {})", num(t_min), num(t_max)),
        th.muted,
    ));
    rows.push((String::new(), th.ink));
    let (chosen, why) = (chosen_root(test), words::root_choice_on(test.choice, kind));
    rows.push((
        format!("chosen: {chosen}"),
        if test.t.is_some() { th.hit } else { th.ray },
    ));
    rows.push((why.into(), th.muted));
    if test.inside {
        rows.push(("c < 0: the origin is inside the sphere".into(), th.muted));
    }
    rows
}

/// The plot: shaded interval, grid and ticks, axes, curve, roots, vertex, chosen root.
fn draw_plot(c: &mut Canvas, l: &QuadraticLayout, f: &PlotFrame, small: f32) -> Vec<PlacedLabel> {
    let th = c.theme;
    let s = c.text_size;
    let test = &l.test;
    let (t_min, t_max) = l.interval;
    let line_w = (s / 9.0).max(1.5);

    // The allowed interval (t_min, t_max): in front of the origin, before the closest hit so far.
    // min/max, not clamp: on a narrow canvas the frame may be a single pixel wide.
    let within = |x: f32| x.max(f.left).min(f.right);
    let xa = within(f.x(t_min as f64));
    let xb = if t_max.is_finite() {
        within(f.x(t_max as f64))
    } else {
        f.right
    };
    if xb > xa {
        c.rect(xa, f.top, xb - xa, f.bottom - f.top, th.region);
    }

    // Grid and ticks.
    let target_x = ((f.right - f.left) / (s * 3.2)).max(2.0) as usize;
    let (tx, tdec) = ticks(f.t_range[0], f.t_range[1], target_x);
    let target_y = ((f.bottom - f.top) / (s * 3.0)).max(2.0) as usize;
    let (fy, fdec) = ticks(f.f_range[0], f.f_range[1], target_y);
    let grid = with_alpha(th.muted, 50);
    for &t in &tx {
        let x = f.x(t);
        c.line([x, f.top], [x, f.bottom], grid, 1.0);
        c.line([x, f.bottom], [x, f.bottom + s * 0.3], th.muted, 1.0);
        c.text(
            x,
            f.bottom + s * 0.4,
            small,
            &tick_label(t, tdec),
            th.muted,
            Anchor::TopCenter,
        );
    }
    for &v in &fy {
        let y = f.y(v);
        c.line([f.left, y], [f.right, y], grid, 1.0);
        c.line([f.left - s * 0.3, y], [f.left, y], th.muted, 1.0);
        c.text(
            f.left - s * 0.4,
            y,
            small,
            &tick_label(v, fdec),
            th.muted,
            Anchor::MiddleRight,
        );
    }
    c.rect_outline(
        f.left,
        f.top,
        f.right - f.left,
        f.bottom - f.top,
        th.muted,
        1.0,
        false,
    );
    rich(
        c,
        f.right,
        f.bottom + s * 0.4 + small * 1.2,
        small,
        &Rich::new("t"),
        th.ink,
        Anchor::TopRight,
    );
    rich(
        c,
        f.left,
        f.top - small * 0.8,
        small,
        &Rich::new("f(t)"),
        th.ink,
        Anchor::MiddleLeft,
    );

    // The t axis (f = 0) and the origin (t = 0).
    let y0 = f.y(0.0);
    c.line([f.left, y0], [f.right, y0], th.ink, line_w);
    let x0 = f.x(0.0);
    c.line([x0, f.top], [x0, f.bottom], th.muted, line_w);

    let mut placer = Placer::new([f.left + 2.0, f.top + 2.0, f.right - 2.0, f.bottom - 2.0]);

    // Interval edges other than t = 0.
    if t_min != 0.0 && t_min.is_finite() && (f.left..=f.right).contains(&f.x(t_min as f64)) {
        c.dashed(
            [f.x(t_min as f64), f.top],
            [f.x(t_min as f64), f.bottom],
            th.muted,
            1.0,
        );
    }
    let mut t_max_x = None;
    if t_max.is_finite() && (f.left..=f.right).contains(&f.x(t_max as f64)) {
        let x = f.x(t_max as f64);
        c.dashed([x, f.top], [x, f.bottom], th.ink, line_w * 0.8);
        t_max_x = Some(x);
    }

    // The curve.

    for run in curve_runs(test, f) {
        c.polyline(&run, th.reflect, line_w * 1.6, false);
        // Labels keep off the curve where they can.
        for p in &run {
            placer.block([p[0] - line_w, p[1] - line_w, p[0] + line_w, p[1] + line_w]);
        }
    }

    // Chosen root: a vertical line through the whole plot.
    if let Some(p) = l.chosen {
        c.dashed([p[0], f.top], [p[0], f.bottom], th.hit, line_w);
    }

    // Labels, the most important first (later ones give way): hit, roots, c, t = 0, t_max,
    // the interval.
    let top_row = f.top + small * 0.9;
    if let Some(p) = l.chosen {
        placer.place(
            c,
            &[
                (p[0], top_row, Anchor::Center),
                (p[0] + 4.0, top_row, Anchor::MiddleLeft),
                (p[0] - 4.0, top_row, Anchor::MiddleRight),
            ],
            small,
            &Rich::new("hit"),
            th.hit,
        );
    }

    // Roots, or the vertex when there are none.
    let r = (s * 0.32).max(4.0);
    match (test.roots, l.roots) {
        (Some([t0, t1]), Some([p0, p1])) => {
            let below = y0 + small * 1.0;
            let above = y0 - small * 1.0;
            let gap = r + 4.0;
            let tangent = test.case == SphereCase::Tangent || t0 == t1;
            let names: &[(f32, [f32; 2], &str)] = if tangent {
                &[(t0, p0, "t_0 = t_1")]
            } else {
                &[(t0, p0, "t_0"), (t1, p1, "t_1")]
            };
            for (i, &(t, p, name)) in names.iter().enumerate() {
                let chosen = test.t == Some(t);
                let col = if chosen { th.hit } else { th.ink };
                let label = short_eq(name, t);
                // t₀ prefers the left, t₁ the right: outside the dip, where the curve is above.
                let left = [
                    (p[0] - gap, below, Anchor::MiddleRight),
                    (p[0] - gap, above, Anchor::MiddleRight),
                ];
                let right = [
                    (p[0] + gap, below, Anchor::MiddleLeft),
                    (p[0] + gap, above, Anchor::MiddleLeft),
                ];
                let lower = [
                    (p[0], below + small * 1.4, Anchor::Center),
                    (p[0], below + small * 2.8, Anchor::Center),
                ];
                let (near, far) = if i == 0 && !tangent {
                    (left, right)
                } else {
                    (right, left)
                };
                // Near side first; then above the axis between the roots (the curve is below it
                // there); then lower down; the far side below the axis last. A label must sit
                // nearer its own dot than the other root's, or it reads as the other's name.
                let other = if tangent {
                    None
                } else {
                    Some(if i == 0 { p1 } else { p0 })
                };
                let own_side =
                    |lab: &Rich, extra: &[(f32, f32, Anchor)]| -> Vec<(f32, f32, Anchor)> {
                        near.iter()
                            .chain([&far[1]])
                            .chain(lower.iter())
                            .chain([&far[0]])
                            .chain(extra.iter())
                            .filter(|&&(x, y, a)| {
                                let b = label_box(c, x, y, small, lab, a);
                                other.is_none_or(|o| rect_dist(b, p) < rect_dist(b, o))
                            })
                            .cloned()
                            .collect()
                    };
                let cands = own_side(&label, &[]);
                let fits = cands
                    .iter()
                    .any(|&(x, y, a)| placer.inside(&label_box(c, x, y, small, &label, a)));
                if fits {
                    placer.place(c, &cands, small, &label, col);
                } else {
                    // No room by its own dot for name and value: the name alone (the panel
                    // has the value), right above or below the dot if need be.
                    let name_only = Rich::new(name);
                    let mut cands = own_side(
                        &name_only,
                        &[
                            (p[0], above - small * 0.2, Anchor::Center),
                            (p[0], below + small * 0.2, Anchor::Center),
                        ],
                    );
                    if cands.is_empty() {
                        cands.push(near[0]);
                    }
                    placer.place(c, &cands, small, &name_only, col);
                }
            }
            // Dots last so they sit on top.
            let dots: Vec<(f32, [f32; 2])> = if tangent {
                vec![(t0, p0)]
            } else {
                vec![(t0, p0), (t1, p1)]
            };
            for (t, p) in dots {
                if test.t == Some(t) {
                    c.circle(p, r * 1.9, Some(with_alpha(th.hit, 70)), None, 0.0);
                    c.circle(p, r * 1.25, Some(th.hit), Some(th.background), 2.0);
                } else {
                    c.circle(p, r, Some(th.ink), Some(th.background), 1.5);
                }
            }
        }
        _ => {
            let (a, b) = (test.a as f64, test.b as f64);
            let tv = -b / (2.0 * a);
            let fv = f_of(test, tv);
            let (xv, yv) = (f.x(tv), f.y(fv));
            c.dashed([xv, yv], [xv, y0], th.muted, line_w);
            c.circle([xv, yv], r * 0.8, Some(th.muted), None, 0.0);
            placer.block([xv - r, yv - r, xv + r, yv + r]);
            let mut vl = Rich::new("vertex −b/2a, ");
            vl = vl.push(&format!(
                "f {} {} > 0",
                if fmt64(fv, Style::Label).parse::<f64>() == Ok(fv) {
                    "="
                } else {
                    "≈"
                },
                fmt64(fv, Style::Label)
            ));
            let g = small * 1.1;
            placer.place(
                c,
                &[
                    (xv, yv - g, Anchor::Center),
                    (xv + r + 6.0, yv - g * 0.6, Anchor::MiddleLeft),
                    (xv - r - 6.0, yv - g * 0.6, Anchor::MiddleRight),
                    (xv + r + 6.0, yv, Anchor::MiddleLeft),
                    (xv - r - 6.0, yv, Anchor::MiddleRight),
                    (xv, yv - g * 2.0, Anchor::Center),
                ],
                small,
                &vl,
                th.muted,
            );
            // Below the axis, where the curve never goes.
            placer.place(
                c,
                &[
                    (xv, y0 + small * 0.95, Anchor::Center),
                    (xv, (yv + y0) / 2.0, Anchor::Center),
                    (xv + 6.0, (yv + y0) / 2.0, Anchor::MiddleLeft),
                    (xv - 6.0, (yv + y0) / 2.0, Anchor::MiddleRight),
                    (
                        (f.left + f.right) / 2.0,
                        f.top + small * 0.9,
                        Anchor::Center,
                    ),
                ],
                small,
                &Rich::new("no real roots"),
                th.ray,
            );
        }
    }

    // c = f(0): where the curve crosses the origin's line.
    let cv = test.c as f64;
    let clear_of_axis = (f.y(cv) - y0).abs() > small * 1.5;
    if (f.left..=f.right).contains(&x0) && cv >= f.f_range[0] && cv <= f.f_range[1] && clear_of_axis
    {
        let p = [x0, f.y(cv)];
        c.circle(p, r * 0.75, Some(th.reflect), Some(th.background), 1.5);
        placer.place(
            c,
            &[
                (x0 + r + 4.0, p[1], Anchor::MiddleLeft),
                (x0 - r - 4.0, p[1], Anchor::MiddleRight),
            ],
            small,
            &short_eq("f(0) = c", test.c),
            th.reflect,
        );
    }

    // The origin, t_max and the allowed interval.
    let origin_label = Rich::new("t = 0");
    if (f.left..=f.right).contains(&x0) {
        let row2 = top_row + small * 1.5;
        placer.place(
            c,
            &[
                (x0 - 4.0, f.bottom - small, Anchor::MiddleRight),
                (x0 + 4.0, f.bottom - small, Anchor::MiddleLeft),
                (x0 - 4.0, row2, Anchor::MiddleRight),
                (x0 + 4.0, row2, Anchor::MiddleLeft),
            ],
            small,
            &origin_label,
            th.muted,
        );
    }
    if let Some(x) = t_max_x {
        let row2 = top_row + small * 1.5;
        placer.place(
            c,
            &[
                (x + 4.0, row2, Anchor::MiddleLeft),
                (x - 4.0, row2, Anchor::MiddleRight),
                (x + 4.0, f.bottom - small, Anchor::MiddleLeft),
            ],
            small,
            &Rich::new("t_{max}"),
            th.ink,
        );
    }
    let legend = if t_max.is_finite() {
        Rich::new("allowed: t_{min} < t < t_{max}")
    } else if t_min == 0.0 {
        Rich::new("t > 0: in front of the origin")
    } else {
        Rich::new("allowed: t > t_{min}")
    };
    if xb > xa {
        let mid = (xa + xb) / 2.0;
        let bottom_row = f.bottom - small * 0.9;
        let top_row = f.top + small * 0.9;
        placer.place_if_free(
            c,
            &[
                (xb - 4.0, bottom_row, Anchor::MiddleRight),
                (xa + 4.0, bottom_row, Anchor::MiddleLeft),
                (mid, bottom_row, Anchor::Center),
                (xb - 4.0, top_row, Anchor::MiddleRight),
                (xa + 4.0, top_row, Anchor::MiddleLeft),
                (mid, top_row, Anchor::Center),
                (xb - 4.0, bottom_row - small * 1.5, Anchor::MiddleRight),
                (xa + 4.0, bottom_row - small * 1.5, Anchor::MiddleLeft),
            ],
            small * 0.95,
            &legend,
            th.reflect,
        );
    }
    placer.placed
}
