//! Drawing the camera, the rays with their hits and normals, the angles of reflection and refraction, the focused step's marks and the lights.

use super::*;

impl Drawer<'_, '_> {
    pub(super) fn camera(&mut self) {
        let lay = self.lay;
        let t = self.c.theme;
        let u = self.u;
        let fade = self.info.current.is_some_and(|c| c != 0);
        let ink = if fade { self.faded(t.ink) } else { t.ink };
        let [a, b] = lay.image_plane;
        // The field of view in this plane: from the eye through the image plane's ends.
        for e in [a, b] {
            if let Some(dir) = unit(sub(e, lay.eye)) {
                let far = add(lay.eye, mul(dir, len(sub(e, lay.eye)) * 1.6));
                self.c
                    .dashed(lay.eye, far, with_alpha(t.muted, 110), 0.9 * u);
            }
        }
        self.c.line(a, b, ink, 2.0 * u);
        // The pixel.
        let s = 3.2 * u;
        let pc = if fade { self.faded(t.ray) } else { t.ray };
        self.c
            .rect(lay.pixel[0] - s, lay.pixel[1] - s, 2.0 * s, 2.0 * s, pc);
        self.c.rect_outline(
            lay.pixel[0] - s,
            lay.pixel[1] - s,
            2.0 * s,
            2.0 * s,
            ink,
            0.8 * u,
            false,
        );
        // The eye: an almond with a pupil, looking along the ray.
        let dir = unit(sub(lay.pixel, lay.eye)).unwrap_or([1.0, 0.0]);
        let nrm = perp(dir);
        let (w, h) = (9.0 * u, 5.0 * u);
        let mut almond = vec![];
        for k in 0..=24 {
            let x = -1.0 + 2.0 * k as f32 / 24.0;
            almond.push(add(
                lay.eye,
                add(mul(dir, x * w), mul(nrm, h * (1.0 - x * x))),
            ));
        }
        for k in (0..=24).rev() {
            let x = -1.0 + 2.0 * k as f32 / 24.0;
            almond.push(add(
                lay.eye,
                add(mul(dir, x * w), mul(nrm, -h * (1.0 - x * x))),
            ));
        }
        self.c
            .polygon(&almond, Some(t.background), Some(ink), 1.4 * u);
        self.c.circle(lay.eye, 2.8 * u, Some(ink), None, 0.0);
        let [x, y] = self.trace.pixel;
        self.label_p(Prio::Scene, lay.eye, "eye", t.muted, &[S, SW, N, W]);
        self.label_p(
            Prio::Scene,
            lay.pixel,
            format!("pixel ({x}, {y})"),
            if fade { self.faded(t.ink) } else { t.ink },
            &[N, NE, NW, S, SE],
        );
        let mid = if len(sub(a, lay.pixel)) > len(sub(b, lay.pixel)) {
            a
        } else {
            b
        };
        self.label_p(Prio::Scene, mid, "image plane", t.muted, &[W, NW, SW, E]);
    }

    pub(super) fn ray(&mut self, i: usize) {
        let rl = &self.lay.rays[i];
        let r = self.info.rays[i].ray;
        let (col, width) = self.ray_style(i);
        let u = self.u;
        let t = self.c.theme;
        let Some((a, b)) = clip_to_rect(self.lay.plot, rl.start, rl.end) else {
            return;
        };
        let reaches_end = len(sub(b, rl.end)) < 0.5;
        if r.kind == RayKind::Shadow {
            if rl.blocked && end_t(self.info, i) < 1.0 {
                // Dashed up to the blocker, crossed out there; a faint dotted rest to the light.
                self.c.dashed(a, b, col, width);
                if let Some(light) = self.info.rays[i]
                    .light
                    .and_then(|l| self.trace.lights.get(l))
                {
                    let lp = self.lay.px(light.position);
                    if let Some((p, q)) = clip_to_rect(self.lay.plot, rl.end, lp) {
                        self.c.dashed(p, q, with_alpha(col, 70), 0.8 * u);
                    }
                }
                let s = 5.0 * u;
                let quiet = self.info.faded(i) || self.info.minor(i);
                let xc = if quiet { col } else { t.ray };
                let s = if self.info.minor(i) { s * 0.6 } else { s };
                self.c
                    .line(sub(rl.end, [s, s]), add(rl.end, [s, s]), xc, 2.2 * u);
                self.c
                    .line(sub(rl.end, [s, -s]), add(rl.end, [s, -s]), xc, 2.2 * u);
                if !quiet {
                    let name = r.hit.as_ref().map_or(String::new(), |h| h.name.clone());
                    match rl.exit {
                        // The blocker lies beyond the frame: said at the edge.
                        Some(x) => {
                            self.c.arrow(a, x, col, width);
                            let inward = self.inward(x);
                            self.label_p(
                                Prio::Marks,
                                x,
                                format!("→ blocked by {name}"),
                                t.blocked,
                                &inward,
                            );
                        }
                        None => self.label_p(
                            Prio::Marks,
                            rl.end,
                            format!("blocked by {name}"),
                            t.blocked,
                            &[NE, NW, SE, SW, N],
                        ),
                    }
                }
            } else {
                self.c.arrow(a, b, col, width);
                // Towards a light the view does not show: said at the edge.
                if let Some(x) = rl.exit
                    && !self.info.faded(i)
                    && !self.info.minor(i)
                    && let Some(li) = self.info.rays[i].light
                    && let (Some(light), Some(shown)) =
                        (self.trace.lights.get(li), self.lay.lights.get(li))
                    && !in_rect(self.lay.plot, shown.at)
                {
                    let inward = self.inward(x);
                    self.label_p(
                        Prio::Marks,
                        x,
                        format!("→ light {}", light.name),
                        col,
                        &inward,
                    );
                }
            }
            return;
        }
        if reaches_end && rl.end != rl.start && end_t(self.info, i).is_finite() {
            self.c.line(a, b, col, width);
            // An arrowhead part-way, pointing along the ray.
            let mid = add(a, mul(sub(b, a), 0.55));
            if len(sub(b, a)) > 30.0 * u
                && let Some(d) = unit(sub(b, a))
            {
                let tip = add(mid, mul(d, 4.0 * u));
                self.c.arrow(sub(tip, mul(d, 1.0)), tip, col, width);
            }
        } else if let Some(x) = rl.exit {
            // Its end lies beyond the frame: drawn to the edge, with an arrowhead there and,
            // for a prominent ray, where it ends.
            self.c.arrow(a, x, col, width);
            if !self.info.faded(i) && !self.info.minor(i) {
                let t_end = end_t(self.info, i);
                let text = match (&rl.hit, &r.hit) {
                    (Some(_), Some(h)) => format!("→ {}, t = {}", h.name, label(t_end)),
                    _ => format!("→ t = {}", label(t_end)),
                };
                let inward = self.inward(x);
                self.label_p(Prio::Focus, x, text, col, &inward);
            }
        } else {
            // A miss, or a ray still searching: on to the border.
            self.c.arrow(a, b, col, width);
            let done = self
                .info
                .find(i, |s| matches!(s, Step::Miss { .. }))
                .is_some_and(|(j, _)| self.info.shown(i, j));
            if done && !self.info.faded(i) && !self.info.minor(i) {
                self.label_p(Prio::Marks, b, "miss → background", col, &[SW, NW, W, S, N]);
            }
        }
    }

    pub(super) fn hit(&mut self, i: usize) {
        let rl = &self.lay.rays[i];
        let Some(h) = rl.hit else { return };
        let r = self.info.rays[i].ray;
        let t = self.c.theme;
        let u = self.u;
        let faded = self.info.faded(i);
        if self.info.minor(i) {
            let hc = with_alpha(if faded { self.faded(t.hit) } else { t.hit }, 170);
            self.c.circle(h, 2.2 * u, Some(hc), None, 0.0);
            return;
        }
        let Some((_, Step::Surface { normal, .. })) =
            self.info.find(i, |s| matches!(s, Step::Surface { .. }))
        else {
            return;
        };
        let n = v3(*normal);
        let ncol = if faded {
            self.faded(t.normal)
        } else {
            t.normal
        };
        if let Some(n2) = unit(self.lay.dpx(n)) {
            let l = len(self.lay.dpx(n)).min(1.0) * 30.0 * u;
            self.c.arrow(
                h,
                add(h, mul(n2, l)),
                ncol,
                if faded { 1.2 * u } else { 1.8 * u },
            );
            if !faded {
                self.strokes.push((h, add(h, mul(n2, l))));
            }
            if !faded && (self.info.current == Some(i) || (self.info.focus.is_none() && i == 0)) {
                self.label_p(
                    Prio::Marks,
                    add(h, mul(n2, l)),
                    "n",
                    t.normal,
                    &[perp(n2), mul(perp(n2), -1.0), n2],
                );
            }
        }
        // Smooth shading: the shading normal that lit this point, dashed beside the flat one.
        if let Some((_, Step::ShadingNormal { normal: ns, .. })) = self
            .info
            .find(i, |s| matches!(s, Step::ShadingNormal { .. }))
            && let Some(n2) = unit(self.lay.dpx(v3(*ns)))
        {
            let l = len(self.lay.dpx(v3(*ns))).min(1.0) * 30.0 * u;
            let tip = add(h, mul(n2, l));
            let w = if faded { 1.2 * u } else { 1.8 * u };
            self.c.dashed(h, tip, ncol, w);
            self.c.arrow(add(h, mul(n2, 0.7 * l)), tip, ncol, w);
            if !faded && (self.info.current == Some(i) || (self.info.focus.is_none() && i == 0)) {
                self.label_p(
                    Prio::Marks,
                    tip,
                    "n_s",
                    t.normal,
                    &[mul(perp(n2), -1.0), perp(n2), n2],
                );
            }
        }
        let hc = if faded { self.faded(t.hit) } else { t.hit };
        self.c.circle(
            h,
            3.6 * u,
            Some(hc),
            Some(if faded { self.faded(t.ink) } else { t.ink }),
            0.9 * u,
        );
        if !faded
            && (self.info.current == Some(i) || (self.info.focus.is_none() && i == 0))
            && let Some(hr) = &r.hit
        {
            self.label_p(
                Prio::Marks,
                h,
                format!("hit {} · t = {}", hr.name, label(hr.t)),
                t.ink,
                &[SW, SE, NW, NE, S, N],
            );
        }
    }

    /// Incidence, reflection and refraction angles; the critical angle; TIR.
    pub(super) fn angles(&mut self) {
        let info = self.info;
        let mut which: Vec<usize> = vec![];
        match info.current {
            None => {
                which.push(0);
                // The shallowest total internal reflection: the event worth seeing.
                which.extend(info.first_tir);
            }
            Some(c) => {
                which.push(c);
                // A child just announced (or spawned) by its parent: the angles at
                // the parent's hit are what that step is about.
                if let Some(p) = info.rays[c].parent
                    && matches!(
                        info.rays[c].ray.kind,
                        RayKind::Reflection | RayKind::Refraction
                    )
                    && (info.focus == Some(info.rays[c].appear)
                        || info.focus == Some(info.rays[c].spawn))
                {
                    which.push(p);
                }
            }
        }
        which.dedup();
        for i in which {
            self.angles_at(i);
        }
    }

    pub(super) fn angles_at(&mut self, i: usize) {
        let info = self.info;
        let r = info.rays[i].ray;
        let Some(h) = self.lay.rays[i].hit else {
            return;
        };
        let Some((_, Step::Surface { normal, .. })) =
            info.find(i, |s| matches!(s, Step::Surface { .. }))
        else {
            return;
        };
        let refl = info
            .find(i, |s| matches!(s, Step::Reflect { .. }))
            .filter(|(j, _)| info.shown(i, *j));
        let refr = info
            .find(i, |s| matches!(s, Step::Refract { .. }))
            .filter(|(j, _)| info.shown(i, *j));
        if refl.is_none() && refr.is_none() {
            return;
        }
        let t = self.c.theme;
        let u = self.u;
        let n = v3(*normal);
        let d = v3(r.direction).normalize_or_zero();
        let top_down = self.lay.top_down;
        let (Some(n2), Some(back2)) = (unit(self.lay.dpx(n)), unit(self.lay.dpx(-d))) else {
            return;
        };
        let nl = 60.0 * u;
        if top_down {
            // Angles do not survive the projection: only the verdict.
            if let Some((
                _,
                Step::Refract {
                    total_internal_reflection: true,
                    ..
                },
            )) = refr
            {
                self.label_p(Prio::Focus, h, "TIR", t.refract, &[n2, N, S]);
            }
            return;
        }
        // The normal line through the surface.
        self.c.dashed(
            add(h, mul(n2, -nl)),
            add(h, mul(n2, nl)),
            with_alpha(t.muted, 200),
            1.0 * u,
        );
        let theta_i = match refr {
            Some((_, Step::Refract { cos_i, .. })) => cos_i.clamp(-1.0, 1.0).acos().to_degrees(),
            _ => (-d).dot(n).clamp(-1.0, 1.0).acos().to_degrees(),
        };
        let rad = 34.0 * u;
        let incoming = self.ray_style(i).0;
        self.arc(h, rad, back2, n2, incoming, 1.6 * u);
        self.label_p(
            Prio::Marks,
            add(h, mul(bisect(back2, n2), rad + 4.0 * u)),
            format!("θi = {}°", fmt(theta_i, Style::Decimals(1))),
            incoming,
            &[bisect(back2, n2), N, S],
        );
        if let Some((_, Step::Reflect { direction, .. })) = refl
            && let Some(r2) = unit(self.lay.dpx(v3(*direction)))
        {
            self.arc(h, rad * 0.8, n2, r2, t.reflect, 1.4 * u);
        }
        if let Some((
            _,
            Step::Refract {
                n1,
                n2: n2i,
                sin2_t,
                critical_angle_deg,
                total_internal_reflection,
                direction,
                ..
            },
        )) = refr
        {
            let inward = mul(n2, -1.0);
            if let Some(dir) = direction
                && let Some(t2) = unit(self.lay.dpx(v3(*dir)))
            {
                let theta_t = sin2_t.clamp(0.0, 1.0).sqrt().asin().to_degrees();
                self.arc(h, rad, inward, t2, t.refract, 1.6 * u);
                self.label_p(
                    Prio::Marks,
                    add(h, mul(bisect(inward, t2), rad + 4.0 * u)),
                    format!("θt = {}°", fmt(theta_t, Style::Decimals(1))),
                    t.refract,
                    &[bisect(inward, t2), S, N],
                );
            }
            if let Some(crit) = critical_angle_deg
                && n1 > n2i
            {
                // The critical direction: θc from the normal, on the incoming side.
                let a = crit.to_radians();
                let cands = [rot(n2, a), rot(n2, -a)];
                let cd = if dot(cands[0], back2) >= dot(cands[1], back2) {
                    cands[0]
                } else {
                    cands[1]
                };
                let tip = add(h, mul(cd, nl));
                self.c.dashed(h, tip, with_alpha(t.refract, 170), 1.2 * u);
                self.strokes.push((h, tip));
                self.label_p(
                    Prio::Marks,
                    tip,
                    format!("θc = {}°", fmt(*crit, Style::Decimals(1))),
                    t.refract,
                    &[cd, N, S],
                );
            }
            if *total_internal_reflection {
                // All the light reflects: the reflected direction, drawn boldly.
                if let Some((_, Step::Reflect { direction, .. })) =
                    info.find(i, |s| matches!(s, Step::Reflect { .. }))
                    && let Some(r2) = unit(self.lay.dpx(v3(*direction)))
                {
                    self.c.arrow(h, add(h, mul(r2, nl)), t.reflect, 2.6 * u);
                    self.strokes.push((h, add(h, mul(r2, nl))));
                }
                let size = self.c.text_size * 1.05;
                let at = add(h, mul(n2, nl + 6.0 * u));
                self.labels.push(Label {
                    at,
                    text: format!(
                        "TIR: θi {}° > θc {}°",
                        fmt(theta_i, Style::Decimals(1)),
                        critical_angle_deg.map_or("?".into(), |d| fmt(d, Style::Decimals(1)))
                    ),
                    color: t.refract,
                    size,
                    prefs: vec![n2, N, S, E, W],
                    gap: 4.0 * u,
                    prio: Prio::Focus,
                });
            }
        }
    }

    pub(super) fn arc(&mut self, c: Px, r: f32, from: Px, to: Px, col: Rgba, width: f32) {
        let a0 = from[1].atan2(from[0]);
        let mut da = to[1].atan2(to[0]) - a0;
        while da > std::f32::consts::PI {
            da -= std::f32::consts::TAU;
        }
        while da < -std::f32::consts::PI {
            da += std::f32::consts::TAU;
        }
        let pts: Vec<Px> = (0..=24)
            .map(|k| {
                let a = a0 + da * k as f32 / 24.0;
                [c[0] + r * a.cos(), c[1] + r * a.sin()]
            })
            .collect();
        self.c.polyline(&pts, col, width, false);
        for w in pts.windows(6).step_by(5) {
            self.strokes.push((w[0], w[5]));
        }
    }

    /// What the focused step adds: candidate points on the ray, the slab interval of a node.
    pub(super) fn focus_marks(&mut self) {
        let Some((i, step)) = self.info.focused_step() else {
            return;
        };
        let r = self.info.rays[i].ray;
        let o = v3(r.origin);
        let d = v3(r.direction);
        let t = self.c.theme;
        let u = self.u;
        let at = |tt: f32| self.lay.px(o + d * tt);
        let mut marks: Vec<(f32, String)> = vec![];
        match step {
            Step::Sphere { test, .. } => {
                if let Some([t0, t1]) = test.roots {
                    marks.push((t0, format!("t0 = {}", label(t0))));
                    if t1 != t0 {
                        marks.push((t1, format!("t1 = {}", label(t1))));
                    }
                }
            }
            Step::Plane { test, .. } => {
                if let Some(tr) = test.t_raw {
                    marks.push((tr, format!("t = {}", label(tr))));
                }
            }
            Step::Triangle { test, .. } => {
                if let Some(ts) = test.t_star {
                    marks.push((ts, format!("t* = {}", label(ts))));
                }
            }
            // A box's interval along the ray: t means the same point in an instance's object
            // space, so a BLAS node's interval is drawn on the world ray as it is.
            Step::Node(v) | Step::TlasNode(v) => {
                if v.test.t_near.is_finite()
                    && v.test.t_far.is_finite()
                    && v.test.t_near <= v.test.t_far
                {
                    let (a, b) = (at(v.test.t_near), at(v.test.t_far));
                    if let Some((a, b)) = clip_to_rect(self.lay.plot, a, b) {
                        self.c
                            .line(a, b, with_alpha(box_color(self.c), 150), 7.0 * u);
                    }
                }
                let p = at(if v.test.t_near.is_finite() {
                    v.test.t_near
                } else {
                    0.0
                });
                let what = match v.action {
                    NodeAction::Culled => "culled",
                    NodeAction::Descend => "descend",
                    NodeAction::Pushed => "pushed",
                    NodeAction::TestPrimitives => "test leaf",
                };
                self.label_p(
                    Prio::Focus,
                    p,
                    format!("node {}: {what}", v.node),
                    box_color(self.c),
                    &[N, NW, NE, S],
                );
            }
            Step::Accept { t: ta, .. } => {
                let p = at(*ta);
                self.c.circle(p, 5.5 * u, None, Some(t.hit), 2.2 * u);
                self.label_p(
                    Prio::Focus,
                    p,
                    format!("closest t = {}", label(*ta)),
                    t.hit,
                    &[N, NE, NW, S],
                );
            }
            _ => {}
        }
        for (tt, text) in marks {
            let p = at(tt);
            if !in_rect(self.lay.plot, p) {
                continue;
            }
            if tt < 0.0 {
                // Behind the origin: the line the test solves on, dashed back to the root.
                self.c
                    .dashed(self.lay.px(o), p, with_alpha(t.muted, 160), 1.0 * u);
            }
            self.c
                .circle(p, 4.5 * u, Some(t.background), Some(t.hit), 2.0 * u);
            self.label_p(Prio::Focus, p, text, t.hit, &[N, S, NE, SE, NW, SW]);
        }
    }

    pub(super) fn lights(&mut self) {
        let t = self.c.theme;
        let u = self.u;
        let lay = self.lay;
        let [px, py, pw, ph] = lay.plot;
        let home = Some(lay.rays[0].hit.unwrap_or(lay.eye)).filter(|p| in_rect(lay.plot, *p));
        let reference = home.unwrap_or([px + pw * 0.5, py + ph * 0.5]);
        for (li, l) in lay.lights.iter().enumerate() {
            sun(self.c, l.at, 4.5 * u, t.light, t.ink, u);
            if l.on_border {
                let dir = unit(sub(l.at, reference)).unwrap_or([0.0, -1.0]);
                self.c.arrow(
                    add(l.at, mul(dir, 11.0 * u)),
                    add(l.at, mul(dir, 20.0 * u)),
                    t.light,
                    2.0 * u,
                );
                // How far, from the primary hit (where the story is), else from the eye; from
                // the view's centre when the view is elsewhere.
                let from = match home {
                    Some(_) => {
                        surface(&self.trace.root).map_or(v3(self.trace.root.origin), |(p, _)| p)
                    }
                    None => lay.frame.o + lay.frame.x * lay.center[0] + lay.frame.y * lay.center[1],
                };
                let text = format!(
                    "{} ({} away)",
                    l.name,
                    fmt(
                        (self.trace.lights[li].position - from).length(),
                        Style::Decimals(1)
                    )
                );
                let inward = mul(dir, -1.0);
                self.label_p(
                    Prio::Scene,
                    l.at,
                    text,
                    mix(t.light, t.ink, 0.45),
                    &[inward, perp(inward), mul(perp(inward), -1.0)],
                );
            } else {
                self.label_p(
                    Prio::Scene,
                    l.at,
                    l.name.clone(),
                    mix(t.light, t.ink, 0.45),
                    &[NE, NW, SE, SW],
                );
            }
        }
    }
}
