//! Drawing the cut objects: BVH boxes, spheres, triangles and planes.

use super::*;

impl Drawer<'_, '_> {
    pub(super) fn boxes(&mut self) {
        let i = self.info.box_ray();
        if !self.info.visible(i) {
            return;
        }
        let visits = node_visits(self.info, i, true);
        let focus_step = self.info.focused_step();
        let bc = box_color(self.c);
        let u = self.u;
        let faded_all = self.info.faded(i);
        for (n, (j, v)) in visits.iter().enumerate() {
            let is_focus = focus_step.is_some_and(|(fi, s)| {
                fi == i && std::ptr::eq(s, &self.info.rays[i].ray.steps[*j].step)
            });
            let (poly, cut) = box_outline(self.lay, v3(v.test.min), v3(v.test.max));
            if poly.len() < 2 {
                continue;
            }
            let culled = v.action == NodeAction::Culled;
            let mut col = if culled { self.c.theme.faded } else { bc };
            if faded_all && !is_focus {
                col = self.faded(col);
            }
            let width = if is_focus { 2.6 * u } else { 1.3 * u };
            if !culled && cut {
                self.c.polygon(
                    &poly,
                    Some(with_alpha(col, if is_focus { 40 } else { 16 })),
                    None,
                    0.0,
                );
            }
            let mut closed = poly.clone();
            closed.push(poly[0]);
            self.c.polyline(&closed, col, width, culled || !cut);
            // The number at the top-left corner of the outline.
            let corner = poly
                .iter()
                .copied()
                .min_by(|a, b| (a[0] + a[1]).total_cmp(&(b[0] + b[1])))
                .unwrap_or(poly[0]);
            let text = if culled {
                format!("{} ×", n + 1)
            } else {
                format!("{}", n + 1)
            };
            let tcol = if culled { self.c.theme.muted } else { col };
            if shown_of(n + 1, visits.len()) || is_focus {
                self.label(corner, text, tcol, &[SE, E, S, NE]);
            }
        }
    }

    /// The uniform grid where the cutting plane crosses it (faint lines under the walked cells):
    /// every cell boundary plane meets the cutting plane in a line, drawn across the grid's box.
    /// An axis whose lines would fall closer than 4 pixels apart is left out (too dense to read),
    /// and so is an axis whose boundary planes are parallel to the cutting plane.
    pub(super) fn grid_cut(&mut self) {
        let Some(g) = &self.trace.grid else {
            return;
        };
        let i = self.info.box_ray();
        if !self.info.visible(i) {
            return;
        }
        let (lo, hi) = (v3(g.min), v3(g.max));
        let f = self.lay.frame;
        let col = with_alpha(box_color(self.c), if self.info.faded(i) { 40 } else { 80 });
        let width = 0.7 * self.u;
        for (a, cells) in g.cells.iter().copied().enumerate() {
            for (p, q) in grid_lines(&f, lo, hi, a, cells, self.lay.scale) {
                if let Some((p, q)) = clip_to_rect(self.lay.plot, self.lay.px(p), self.lay.px(q)) {
                    self.c.line(p, q, col, width);
                }
            }
        }
    }

    /// The other accelerators' visits of the same ray: the grid cells it walked (numbered in
    /// walk order) and the bounding spheres it tested (culled ones faded and dashed).
    pub(super) fn accel_visits(&mut self) {
        let i = self.info.box_ray();
        if !self.info.visible(i) {
            return;
        }
        let bc = box_color(self.c);
        let u = self.u;
        let faded_all = self.info.faded(i);
        let ray = self.info.rays[i].ray;
        let focus_step = self.info.focused_step();
        let mut cells = 0;
        let total_cells = ray
            .steps
            .iter()
            .enumerate()
            .filter(|(j, s)| matches!(s.step, Step::Cell { .. }) && self.info.shown(i, *j))
            .count();
        for (j, s) in ray.steps.iter().enumerate() {
            if !self.info.shown(i, j) {
                continue;
            }
            let is_focus = focus_step.is_some_and(|(fi, st)| fi == i && std::ptr::eq(st, &s.step));
            let width = if is_focus { 2.6 * u } else { 1.3 * u };
            match &s.step {
                Step::Cell { min, max, .. } => {
                    cells += 1;
                    if !(shown_of(cells, total_cells) || is_focus) {
                        continue;
                    }
                    let (poly, cut) = box_outline(self.lay, v3(*min), v3(*max));
                    if poly.len() < 2 {
                        continue;
                    }
                    let mut col = bc;
                    if faded_all && !is_focus {
                        col = self.faded(col);
                    }
                    if cut {
                        let fill = with_alpha(col, if is_focus { 40 } else { 12 });
                        self.c.polygon(&poly, Some(fill), None, 0.0);
                    }
                    let mut closed = poly.clone();
                    closed.push(poly[0]);
                    self.c.polyline(&closed, col, width, !cut);
                    let corner = poly
                        .iter()
                        .copied()
                        .min_by(|a, b| (a[0] + a[1]).total_cmp(&(b[0] + b[1])))
                        .unwrap_or(poly[0]);
                    self.label(corner, format!("{cells}"), col, &[SE, E, S, NE]);
                }
                Step::SphereNode {
                    center,
                    radius,
                    action,
                    ..
                } => {
                    // The sphere's circle in the cutting plane (its silhouette when the plane
                    // misses it or looking from above).
                    let c = v3(*center);
                    let f = &self.lay.frame;
                    let dd = f.dist(c);
                    let (cen, rad, cut) = if !self.lay.top_down && dd.abs() < *radius {
                        (c - f.m * dd, (radius * radius - dd * dd).sqrt(), true)
                    } else {
                        (c, *radius, false)
                    };
                    let culled = *action == NodeAction::Culled;
                    let mut col = if culled { self.c.theme.faded } else { bc };
                    if faded_all && !is_focus {
                        col = self.faded(col);
                    }
                    let p = self.lay.px(cen);
                    let r = rad * self.lay.scale;
                    let fill =
                        (!culled && cut).then(|| with_alpha(col, if is_focus { 40 } else { 12 }));
                    self.c.circle(p, r, fill, Some(col), width);
                }
                _ => {}
            }
        }
    }

    pub(super) fn objects(&mut self) {
        let lay = self.lay;
        let u = self.u;
        let focus_obj = match self.info.focused_step() {
            Some((
                _,
                Step::Sphere { object, .. }
                | Step::Plane { object, .. }
                | Step::Triangle { object, .. }
                | Step::Accept { object, .. },
            )) => Some(*object),
            _ => None,
        };
        let hit_objs: Vec<u32> = self
            .info
            .rays
            .iter()
            .filter_map(|r| r.ray.hit.as_ref().map(|h| h.object))
            .collect();
        let mut named_groups: Vec<String> = vec![];
        let circles: std::collections::HashMap<&str, &CircleLayout> =
            lay.circles.iter().map(|c| (c.name.as_str(), c)).collect();
        // Only what the view shows is drawn: a trace of a brute-force loop over 200,000
        // objects names them all. Objects the cutting plane misses (drawn as faint outlines)
        // and labels of objects no ray hit are left out when there are many.
        let plot = lay.plot;
        let in_view = |b: [f32; 4]| {
            b[2] >= plot[0]
                && b[0] <= plot[0] + plot[2]
                && b[3] >= plot[1]
                && b[1] <= plot[1] + plot[3]
        };
        let crowded = self.trace.objects.len() > CROWDED;
        // Planes first (under), then triangles, then spheres.
        let mut objs: Vec<&TraceObject> = self
            .trace
            .objects
            .iter()
            .filter(|o| {
                if focus_obj == Some(o.id) || hit_objs.contains(&o.id) {
                    return true;
                }
                match o.shape {
                    Shape::Sphere { .. } => circles.get(o.name.as_str()).is_some_and(|c| {
                        let r = c.radius;
                        (c.cut || !crowded)
                            && in_view([
                                c.center[0] - r,
                                c.center[1] - r,
                                c.center[0] + r,
                                c.center[1] + r,
                            ])
                    }),
                    Shape::Triangle { p } => {
                        let proj: Vec<Px> = p.iter().map(|v| lay.px(*v)).collect();
                        let b = proj.iter().fold(
                            [
                                f32::INFINITY,
                                f32::INFINITY,
                                f32::NEG_INFINITY,
                                f32::NEG_INFINITY,
                            ],
                            |b, q| {
                                [
                                    b[0].min(q[0]),
                                    b[1].min(q[1]),
                                    b[2].max(q[0]),
                                    b[3].max(q[1]),
                                ]
                            },
                        );
                        in_view(b)
                            && (!crowded || lay.top_down || triangle_cut(&lay.frame, p).is_some())
                    }
                    Shape::Plane { .. } | Shape::AxisPlane { .. } => true,
                }
            })
            .collect();
        objs.sort_by_key(|o| match o.shape {
            Shape::Plane { .. } | Shape::AxisPlane { .. } => 0,
            Shape::Triangle { .. } => 1,
            Shape::Sphere { .. } => 2,
        });
        for o in objs {
            let col = material_color(self.c, o.color);
            let focus = focus_obj == Some(o.id);
            let width = if focus { 3.2 * u } else { 1.8 * u };
            let stroke = if focus { self.c.theme.hit } else { col };
            let fill = with_alpha(col, if dark_theme(self.c) { 50 } else { 40 });
            // Mesh triangles "name[i]" are labelled once, by the mesh's name.
            let group = o.name.split('[').next().unwrap_or(&o.name).to_string();
            let label_name = if hit_objs.contains(&o.id) || focus || !o.name.contains('[') {
                o.name.clone()
            } else {
                group.clone()
            };
            let mut label_at: Option<(Px, Vec<Px>)> = None;
            match o.shape {
                Shape::Sphere { center, radius } => {
                    let Some(circ) = circles.get(o.name.as_str()).copied() else {
                        continue;
                    };
                    if circ.cut {
                        self.c
                            .circle(circ.center, circ.radius, Some(fill), Some(stroke), width);
                    } else {
                        // The plane misses it: its outline projected, dashed.
                        let pc = lay.px(center);
                        let pts: Vec<Px> = (0..=72)
                            .map(|k| {
                                let a = k as f32 / 72.0 * std::f32::consts::TAU;
                                [
                                    pc[0] + radius * lay.scale * a.cos(),
                                    pc[1] + radius * lay.scale * a.sin(),
                                ]
                            })
                            .collect();
                        self.c
                            .polyline(&pts, with_alpha(stroke, 170), width * 0.7, true);
                    }
                    let a = -std::f32::consts::FRAC_PI_4;
                    let edge = [
                        circ.center[0] + circ.radius * a.cos() * 0.98,
                        circ.center[1] + circ.radius * a.sin() * 0.98,
                    ];
                    label_at = Some((edge, vec![NE, E, N, SE, NW]));
                }
                Shape::Triangle { p } => {
                    let proj: Vec<Px> = p.iter().map(|v| lay.px(*v)).collect();
                    if lay.top_down {
                        self.c.polygon(&proj, Some(fill), Some(stroke), width * 0.8);
                        label_at = Some((proj[0], vec![NE, NW, SE, SW]));
                    } else {
                        // Faint: the triangle projected onto the plane. Solid: its cut.
                        let outline = if focus {
                            self.c.theme.hit
                        } else {
                            with_alpha(col, 60)
                        };
                        let fill = with_alpha(col, if focus { 40 } else { 14 });
                        let w = if focus { 1.6 * u } else { 0.8 * u };
                        self.c.polygon(&proj, Some(fill), Some(outline), w);
                        if focus {
                            label_at = Some((proj[0], vec![NE, NW, SE, SW]));
                        }
                        if let Some(seg) = triangle_cut(&lay.frame, p) {
                            let (a, b) = (lay.px(seg[0]), lay.px(seg[1]));
                            self.c.line(a, b, stroke, width * 1.3);
                            label_at = Some((if a[1] < b[1] { a } else { b }, vec![NE, NW, E, W]));
                        }
                    }
                }
                Shape::Plane { .. } | Shape::AxisPlane { .. } => {
                    let (n, offset) = match o.shape {
                        Shape::Plane { normal, offset } => (normal, offset),
                        Shape::AxisPlane { axis, offset } => (Vec3::AXES[axis.min(2)], offset),
                        _ => unreachable!("matched above"),
                    };
                    // None when the plane lies parallel to the view (a floor seen from above).
                    if self.plane(n, offset, stroke, width).is_some() {
                        label_at = self.plane_label_point(n, offset);
                    }
                }
            }
            if crowded && !focus && !hit_objs.contains(&o.id) {
                continue;
            }
            if let Some((at, prefs)) = label_at {
                if label_name != o.name {
                    if named_groups.contains(&label_name) {
                        continue;
                    }
                    named_groups.push(label_name.clone());
                }
                let tc = if focus {
                    self.c.theme.ink
                } else {
                    mix(col, self.c.theme.ink, 0.35)
                };
                self.label_p(Prio::Names, at, label_name, tc, &prefs);
            }
        }
    }

    /// Draws a plane's cut (a line across the plot, hatched on its back). None when the plane
    /// does not cut the view plane in a line (parallel to it).
    pub(super) fn plane(&mut self, n: Vec3, offset: f32, col: Rgba, width: f32) -> Option<()> {
        let (a, b) = self.plane_line(n, offset)?;
        let u = self.u;
        self.c.line(a, b, col, width);
        self.walls.push((a, b));
        // Hatching on the side the normal points away from (the solid side of a floor).
        let dir = unit(sub(b, a))?;
        let n2 = unit(self.lay.dpx(n))?;
        let back = mul(n2, -1.0);
        let step = 11.0 * u;
        let l = len(sub(b, a));
        let tick = add(mul(back, 7.0 * u), mul(dir, -5.0 * u));
        let hatch = with_alpha(col, 120);
        let mut s = step * 0.5;
        while s < l {
            let p = add(a, mul(dir, s));
            self.c.line(p, add(p, tick), hatch, 0.9 * u);
            s += step;
        }
        Some(())
    }

    /// The plane's line across the plot, in pixels.
    pub(super) fn plane_line(&self, n: Vec3, offset: f32) -> Option<(Px, Px)> {
        plane_cut(self.lay, n, offset)
    }

    /// Where a plane's name goes: near the right end of a level line (the eye is on the left),
    /// beside the upper part of a steep one.
    pub(super) fn plane_label_point(&self, n: Vec3, offset: f32) -> Option<(Px, Vec<Px>)> {
        let (a, b) = self.plane_line(n, offset)?;
        let d = sub(b, a);
        if d[1].abs() > d[0].abs() {
            let (top, bottom) = if a[1] < b[1] { (a, b) } else { (b, a) };
            Some((add(top, mul(sub(bottom, top), 0.3)), vec![W, E, NW, SW]))
        } else {
            Some((add(a, mul(d, 0.9)), vec![NE, SE, NW, SW]))
        }
    }
}

/// The most grid cells of one ray the slice draws and numbers, and the most BVH boxes of one ray
/// it numbers. A walk through raystep's grid crosses at most 3 × 256 − 2 = 766 cells (256 per
/// axis, [`crate::record::validate::MAX_GRID_CELLS_PER_AXIS`]), so only a planted trace has more.
/// Each number is placed clear of the ones before it, a pass over them all, and each cell drawn
/// fills its pixels again: drawing and numbering every cell of a planted walk of 99,000 took 13
/// minutes (`raystep diagram --kind slice` of it, debug build; 3 s with this bound).
pub(super) const MAX_SHOWN: usize = 1024;

/// Whether the `n`th (from 1) of `total` cells or boxes is shown (drawn, for cells, and
/// numbered): every one up to [`MAX_SHOWN`]; beyond, the first, the last and every k-th between,
/// k chosen to show at most [`MAX_SHOWN`] + 1. (The focused one is shown whatever this says.)
pub(super) fn shown_of(n: usize, total: usize) -> bool {
    if total <= MAX_SHOWN {
        return true;
    }
    let every = total.div_ceil(MAX_SHOWN - 1);
    n == 1 || n == total || n.is_multiple_of(every)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::AccelChoice;

    #[test]
    fn a_long_walk_shows_a_bounded_sample_of_its_cells() {
        // A real walk is shown whole.
        assert!((1..=766).all(|n| shown_of(n, 766)));
        for total in [MAX_SHOWN + 1, 5_000, 99_000, 100_000] {
            let shown: Vec<usize> = (1..=total).filter(|&n| shown_of(n, total)).collect();
            assert!(shown.len() <= MAX_SHOWN + 1, "{total}: {}", shown.len());
            assert!(shown.len() >= MAX_SHOWN / 2, "{total}: {}", shown.len());
            assert_eq!(shown.first(), Some(&1));
            assert_eq!(shown.last(), Some(&total));
        }
    }

    /// Mirror-glass's trace of its middle pixel with `accel`, the first step of `kind` of its
    /// primary ray repeated so that the ray holds `extra` more of them (a planted trace: a walk
    /// through raystep's grid crosses at most 766 cells). Returns the trace and how many steps
    /// of that kind the primary ray holds.
    fn planted(accel: AccelChoice, kind: &str, extra: usize) -> (Trace, usize) {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/mirror-glass.toml");
        let mut scene = crate::scene::load_file(&path).expect("the shipped scene loads");
        scene.settings.accel = accel;
        let mut trace = raystep_core::PreparedScene::new(scene).record(200, 150, 0);
        let is_kind = |s: &Step| match s {
            Step::Cell { .. } => kind == "cell",
            Step::Node(_) => kind == "node",
            _ => false,
        };
        let steps = &mut trace.root.steps;
        let k = steps
            .iter()
            .position(|s| is_kind(&s.step))
            .expect("the primary ray has such a step");
        let copy = steps[k].clone();
        steps.splice(k..k, std::iter::repeat_n(copy, extra));
        let count = steps.iter().filter(|s| is_kind(&s.step)).count();
        (trace, count)
    }

    /// The numbers the slice places on `trace`'s BVH boxes and grid cells, focused on timeline
    /// step `focus` (None: the whole trace).
    fn numbers(trace: &Trace, focus: Option<usize>) -> Vec<String> {
        let opts = ViewOptions {
            width: 1200,
            height: 900,
            focus,
            ..ViewOptions::default()
        };
        let mut c = Canvas::for_view(&opts);
        let info = RayInfos::new(trace, opts.focus);
        let lay = compute_layout(&c, trace, &opts, &info, 0.0);
        let mut d = Drawer::new(&mut c, &lay, trace, &info);
        d.boxes();
        d.accel_visits();
        d.labels.iter().map(|l| l.text.clone()).collect()
    }

    #[test]
    fn a_planted_walk_of_five_thousand_cells_is_numbered_by_a_sample() {
        let (trace, cells) = planted(AccelChoice::Grid, "cell", 5_000);
        assert!(cells > 5_000);
        let labels = numbers(&trace, None);
        // Every number placed dodges those before it: numbering all of them was quadratic.
        assert!(
            (MAX_SHOWN / 2..=MAX_SHOWN + 1).contains(&labels.len()),
            "{} numbers for {cells} cells",
            labels.len()
        );
        let last = cells.to_string();
        assert!(labels.iter().any(|l| l == "1") && labels.contains(&last));
        // Focused on the 2,501st cell (it comes first in the walk, so at timeline step
        // first + 2,500): it is numbered, and nothing after it is.
        let first = trace
            .root
            .steps
            .iter()
            .position(|s| matches!(s.step, Step::Cell { .. }))
            .unwrap();
        let labels = numbers(&trace, Some(first + 2_500));
        assert!(labels.len() <= MAX_SHOWN + 1, "{}", labels.len());
        assert!(labels.iter().any(|l| l == "2501"), "{labels:?}");
        assert!(!labels.iter().any(|l| l == "2502"));
        // A real walk is numbered whole.
        let (trace, cells) = planted(AccelChoice::Grid, "cell", 0);
        assert_eq!(numbers(&trace, None).len(), cells);
    }

    #[test]
    fn a_planted_ray_of_five_thousand_boxes_is_numbered_by_a_sample() {
        let (trace, boxes) = planted(AccelChoice::Bvh, "node", 5_000);
        assert!(boxes > 5_000);
        let labels = numbers(&trace, None);
        assert!(
            (MAX_SHOWN / 2..=MAX_SHOWN + 1).contains(&labels.len()),
            "{} numbers for {boxes} boxes",
            labels.len()
        );
        let (trace, boxes) = planted(AccelChoice::Bvh, "node", 0);
        assert_eq!(numbers(&trace, None).len(), boxes);
    }
}
