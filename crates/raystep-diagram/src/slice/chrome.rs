//! Drawing what frames the picture: title, caption, legend, scale bar, axes and the placed labels.

use super::*;

impl Drawer<'_, '_> {
    /// Title, subtitle, legend, scale bar, axes; then the labels.
    pub(super) fn chrome(&mut self, opts: &ViewOptions, legend: &[(Sample, String)]) {
        let t = self.c.theme;
        let [px, py, pw, ph] = self.lay.plot;
        let (w, h) = (self.c.width(), self.c.height());
        // Cover what spilled out of the plot.
        let bg = t.background;
        self.c.rect(0.0, 0.0, w, py, bg);
        self.c.rect(0.0, py + ph, w, h - py - ph, bg);
        self.c.rect(0.0, py, px, ph, bg);
        self.c.rect(px + pw, py, w - px - pw, ph, bg);
        self.c
            .rect_outline(px, py, pw, ph, with_alpha(t.faded, 160), 1.0, false);

        self.scale_bar();
        self.axes();
        self.place_labels();

        let [x, y] = self.trace.pixel;
        let heading = format!("Scene slice · pixel ({x}, {y})");
        let heading_w = self.c.text_width(&heading, self.c.text_size * 1.15);
        let y0 = title(self.c, &heading);
        let sub_size = label_size(self.c);
        let plane = if let Some((i, step)) = self.info.focused_step() {
            step_caption(self.info.rays[i].ray, step)
        } else if opts.top_down {
            let flat: Vec<&str> = self
                .trace
                .objects
                .iter()
                .filter(|o| horizontal(&o.shape))
                .map(|o| o.name.as_str())
                .collect();
            if flat.is_empty() {
                "seen from above, projected onto x–z".to_string()
            } else {
                format!(
                    "seen from above, projected onto x–z; not shown: {} (horizontal)",
                    flat.join(", ")
                )
            }
        } else {
            let base = if surface(&self.trace.root).is_some() && bends(&self.trace.root) {
                "plane of incidence: the ray and the normal at its hit"
            } else {
                "vertical plane through the ray"
            };
            if opts.slice_angle != 0.0 {
                format!(
                    "{base}, turned {}° about the ray",
                    fmt(opts.slice_angle, Style::Decimals(1))
                )
            } else {
                base.to_string()
            }
        };
        let plane = self.c.elide(&plane, sub_size, w - self.c.text_size * 1.6);
        self.chrome_text(
            [self.c.text_size * 0.8, y0 - self.c.text_size * 0.45],
            sub_size,
            &plane,
            t.muted,
            Anchor::TopLeft,
        );
        if let Some(k) = self.info.focus {
            let text = crate::record::words::step_of(k, self.info.len);
            let ts = self.c.text_size;
            // On a narrow canvas the counter would be drawn over the title: leave it out (the
            // app's step bar and the GIF's frame order say which step it is).
            if ts * 0.8 + heading_w + ts + self.c.text_width(&text, ts) + ts * 0.8 <= w {
                self.chrome_text([w - ts * 0.8, ts * 0.6], ts, &text, t.ink, Anchor::TopRight);
            }
        }
        self.legend(legend);
    }

    pub(super) fn legend(&mut self, entries: &[(Sample, String)]) {
        let size = legend_size(self.c);
        let rows = legend_rows(self.c, entries);
        let t = self.c.theme;
        let u = self.u;
        let top = self.lay.plot[1] + self.lay.plot[3] + size * 0.5;
        for (ri, row) in rows.iter().enumerate() {
            let total: f32 = row
                .iter()
                .map(|&i| legend_item_width(self.c, &entries[i].1))
                .sum();
            let mut x = (self.c.width() - total) * 0.5 + size * 0.6;
            let y = top + ri as f32 * size * 1.5 + size * 0.6;
            for &i in row {
                let (sample, text) = &entries[i];
                let (a, b) = ([x, y], [x + size * 2.2, y]);
                match *sample {
                    Sample::Line(c, dashed) => self.c.polyline(&[a, b], c, 2.0 * u, dashed),
                    Sample::Arrow(c) => self.c.arrow(a, b, c, 1.8 * u),
                    Sample::Dot(c) => {
                        self.c
                            .circle([x + size * 1.1, y], 3.6 * u, Some(c), Some(t.ink), 0.9 * u)
                    }
                    Sample::Light => sun(self.c, [x + size * 1.1, y], 3.6 * u, t.light, t.ink, u),
                    Sample::Box(c, dashed) => {
                        let c = c.unwrap_or_else(|| box_color(self.c));
                        self.c.rect_outline(
                            x + size * 0.4,
                            y - size * 0.45,
                            size * 1.4,
                            size * 0.9,
                            c,
                            1.3 * u,
                            dashed,
                        );
                    }
                }
                x += size * 2.6;
                self.chrome_text([x, y], size, text, t.ink, Anchor::MiddleLeft);
                x += self.c.text_width(text, size) + size * 1.2 + size * 0.2;
            }
        }
    }

    pub(super) fn scale_bar(&mut self) {
        let t = self.c.theme;
        let u = self.u;
        let [px, py, _pw, ph] = self.lay.plot;
        let target = self.lay.plot[2] * 0.18 / self.lay.scale;
        let p10 = 10f32.powf(target.log10().floor());
        let nice = [5.0, 2.0, 1.0]
            .iter()
            .map(|m| m * p10)
            .find(|v| *v <= target)
            .unwrap_or(p10);
        let l = nice * self.lay.scale;
        let size = label_size(self.c);
        let x0 = px + size;
        let y0 = py + ph - size * 0.9;
        self.c.rect(
            x0 - 3.0,
            y0 - size * 1.5,
            l + 6.0 + size * 0.2,
            size * 2.1,
            with_alpha(t.background, 200),
        );
        self.c.line([x0, y0], [x0 + l, y0], t.ink, 1.6 * u);
        for x in [x0, x0 + l] {
            self.c
                .line([x, y0 - 4.0 * u], [x, y0 + 1.0 * u], t.ink, 1.6 * u);
        }
        let unit_word = if nice == 1.0 { "unit" } else { "units" };
        let text = format!("{} {unit_word}", fmt(nice, Style::Decimals(1)));
        let tw = self.c.text_width(&text, size);
        self.chrome_text(
            [x0 + l * 0.5, y0 - size * 0.8],
            size,
            &text,
            t.ink,
            Anchor::Center,
        );
        // No label over it.
        let right = (x0 + l + 3.0 + size * 0.2).max(x0 + l * 0.5 + tw * 0.5 + 3.0);
        self.furniture
            .push([x0 - 3.0, y0 - size * 1.5, right - (x0 - 3.0), size * 2.1]);
    }

    /// A line of the chrome's text, in a colour that reads on the background, recorded for
    /// [`draw_annotated`].
    fn chrome_text(&mut self, at: Px, size: f32, text: &str, color: Rgba, anchor: Anchor) {
        let t = self.c.theme;
        let color = readable(color, t.background, t.ink);
        let w = self.c.text_width(text, size);
        let h = size * 1.2;
        let (x0, y0) = anchor.top_left(at[0], at[1], w, h);
        self.c.text(at[0], at[1], size, text, color, anchor);
        self.texts.push(SliceText {
            text: text.to_string(),
            rect: [x0, y0, w, h],
            color,
            size,
            label: false,
        });
    }

    /// The world axes, as they lie on the page (short ones are nearly perpendicular to it).
    pub(super) fn axes(&mut self) {
        let t = self.c.theme;
        let u = self.u;
        let [px, py, pw, _] = self.lay.plot;
        let l = 20.0 * u;
        let o = [px + pw - l - 14.0 * u, py + l + 10.0 * u];
        // What it covers (no label goes there): the arrows and their letters.
        let pad = 3.0 * u;
        let mut b = [o[0] - pad, o[1] - pad, o[0] + pad, o[1] + pad];
        for (name, v) in [("x", Vec3::X), ("y", Vec3::Y), ("z", Vec3::Z)] {
            let d = self.lay.dpx(v);
            if len(d) < 0.3 {
                continue;
            }
            let tip = add(o, mul(d, l));
            self.c.arrow(o, tip, t.muted, 1.2 * u);
            let size = label_size(self.c);
            let lbl = add(
                tip,
                mul(unit(d).unwrap_or([1.0, 0.0]), 4.0 * u + size * 0.4),
            );
            self.chrome_text(lbl, size, name, t.muted, Anchor::Center);
            let r = self.c.text_width(name, size) * 0.5 + pad;
            for q in [tip, add(lbl, [-r, -size * 0.6]), add(lbl, [r, size * 0.6])] {
                b = [
                    b[0].min(q[0]),
                    b[1].min(q[1]),
                    b[2].max(q[0]),
                    b[3].max(q[1]),
                ];
            }
        }
        self.furniture.push([b[0], b[1], b[2] - b[0], b[3] - b[1]]);
    }

    /// Places the labels, most important first ([`Prio`]), each at the first free place
    /// around its point: inside the plot, over no label placed before it, the scale bar or the
    /// axes, and crossed by no plane's line; among free places, the one that covers the fewest
    /// glyphs, rays and outlines. Places are tried in rings farther and farther out (a label put
    /// far from its point gets a thin leader line back to it); a label that finds no free place
    /// is left out rather than drawn over another.
    ///
    /// Hand-written: the label-placement crates on crates.io place map labels (or need a solver
    /// and a geometry stack); this greedy search over a few dozen candidate boxes is the whole
    /// of what a slice needs, and keeps the drawing a pure function of the trace.
    pub(super) fn place_labels(&mut self) {
        let mut labels = std::mem::take(&mut self.labels);
        labels.sort_by_key(|l| l.prio);
        let plot = self.lay.plot;
        let u = self.u;
        let theme = self.c.theme;
        let mut placed: Vec<[f32; 4]> = vec![];
        let furniture = self.furniture.clone();
        let walls = self.walls.clone();
        // Keep clear of the glyphs: eye, pixel, hits, lights.
        let mut glyphs: Vec<[f32; 4]> = vec![];
        let around = |p: Px, r: f32| [p[0] - r, p[1] - r, 2.0 * r, 2.0 * r];
        glyphs.push(around(self.lay.eye, 9.0 * u));
        glyphs.push(around(self.lay.pixel, 4.0 * u));
        for l in &self.lay.lights {
            glyphs.push(around(l.at, 9.0 * u));
        }
        // ... and of the rays drawn strongly, and the objects' outlines.
        let mut segments: Vec<(Px, Px)> = self.strokes.clone();
        segments.push((self.lay.image_plane[0], self.lay.image_plane[1]));
        for (i, r) in self.lay.rays.iter().enumerate() {
            if !r.visible {
                continue;
            }
            if let Some(h) = r.hit {
                glyphs.push(around(h, 4.5 * u));
            }
            if !self.info.faded(i)
                && !self.info.minor(i)
                && let Some(seg) = clip_to_rect(plot, r.start, r.end)
            {
                segments.push(seg);
                if r.current {
                    // The step's own ray counts twice: the last thing to cover.
                    segments.push(seg);
                }
            }
        }
        let circles: Vec<(Px, f32)> = self
            .lay
            .circles
            .iter()
            .map(|c| (c.center, c.radius))
            .collect();
        let mut leaders: Vec<(Px, Px, Rgba)> = vec![];
        let mut boxes: Vec<([f32; 4], Label, Rgba)> = vec![];
        for l in labels {
            let w = self.c.text_width(&l.text, l.size) + 6.0;
            let h = l.size * 1.2 + 2.0;
            let mut best: Option<([f32; 4], f32, f32)> = None;
            let mut cands: Vec<Px> = l.prefs.clone();
            cands.extend([NE, SE, NW, SW, N, S, E, W]);
            cands.extend((0..8).map(|k| rot(E, (k as f32 + 0.5) * std::f32::consts::FRAC_PI_4)));
            // A box's number far from its corner would be read as another box's: it stays
            // close, or is left out.
            let rings: &[f32] = if l.prio == Prio::Detail {
                &[0.0, 0.6, 1.3]
            } else {
                &[0.0, 0.6, 1.3, 2.2, 3.5, 5.0]
            };
            for (ring, &extra) in rings.iter().enumerate() {
                for (k, dir) in cands.iter().enumerate() {
                    let dir = unit(*dir).unwrap_or([1.0, 0.0]);
                    let g = l.gap + extra * h;
                    // The box's side (or, diagonally, its corner) facing `at` touches the
                    // point at + g·dir.
                    let side = |v: f32| (v * std::f32::consts::SQRT_2).clamp(-1.0, 1.0);
                    let cx = l.at[0] + dir[0] * g + side(dir[0]) * w * 0.5;
                    let cy = l.at[1] + dir[1] * g + side(dir[1]) * h * 0.5;
                    let r = [cx - w * 0.5, cy - h * 0.5, w, h];
                    let inside = r[0] >= plot[0]
                        && r[1] >= plot[1]
                        && r[0] + r[2] <= plot[0] + plot[2]
                        && r[1] + r[3] <= plot[1] + plot[3];
                    let free = inside
                        && !placed.iter().any(|p| overlap(*p, r))
                        && !furniture.iter().any(|p| overlap(*p, r))
                        && !walls.iter().any(|(a, b)| clip_to_rect(r, *a, *b).is_some());
                    if !free {
                        continue;
                    }
                    let crossing = |(a, b): &(Px, Px)| clip_to_rect(r, *a, *b).is_some();
                    let score = 8.0 * glyphs.iter().filter(|p| overlap(**p, r)).count() as f32
                        + 4.0 * segments.iter().filter(|s| crossing(s)).count() as f32
                        + 1.5
                            * circles
                                .iter()
                                .filter(|(c, rad)| crosses_circle(r, *c, *rad))
                                .count() as f32
                        + ring as f32 * 1.5
                        + k as f32 * 0.01;
                    if best.is_none_or(|(_, s, _)| score < s) {
                        best = Some((r, score, g));
                    }
                }
                if best.is_some_and(|(_, s, _)| s < 1.0 + ring as f32 * 1.5) {
                    break;
                }
            }
            let Some((r, _, g)) = best else { continue };
            placed.push(r);
            let color = readable(l.color, theme.background, theme.ink);
            if g > 1.5 * h {
                // Far from its point: a thin line back to it.
                let near = [
                    l.at[0].clamp(r[0], r[0] + r[2]),
                    l.at[1].clamp(r[1], r[1] + r[3]),
                ];
                leaders.push((l.at, near, with_alpha(color, 150)));
            }
            boxes.push((r, l, color));
        }
        for (a, b, c) in leaders {
            self.c.line(a, b, c, 0.9 * u);
        }
        for (r, l, color) in boxes {
            self.c.label(
                r[0] + 3.0,
                r[1] + 1.0,
                l.size,
                &l.text,
                color,
                Anchor::TopLeft,
            );
            self.texts.push(SliceText {
                text: l.text,
                rect: r,
                color,
                size: l.size,
                label: true,
            });
        }
    }
}
