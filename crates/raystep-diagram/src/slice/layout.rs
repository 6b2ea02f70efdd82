//! The slice's layout: the cutting plane, the view's bounds and where every ray, circle and light lands in the picture.

use super::*;

pub(super) fn compute_layout(
    c: &Canvas,
    trace: &Trace,
    opts: &ViewOptions,
    info: &RayInfos,
    legend_height: f32,
) -> SliceLayout {
    let frame = Frame::new(trace, opts);
    // The fit is made in the unturned plane and kept as the plane turns: the ray and its hit
    // have the same 2D coordinates in both (the turn is about the ray), so they stay put.
    let frame0 = Frame::new(
        trace,
        &ViewOptions {
            slice_angle: 0.0,
            ..opts.clone()
        },
    );
    let ts = c.text_size;
    let (w, h) = (c.width(), c.height());
    let top = header_height(c);
    let bottom = legend_height + ts * 0.5;
    let margin = ts * 0.8;
    let plot = [
        margin,
        top,
        (w - 2.0 * margin).max(8.0),
        (h - top - bottom).max(8.0),
    ];

    let cam = CameraRays::new(&trace.camera);
    let core = framing_core(trace, info, &frame0, &cam);
    // Near things: tested objects and visited boxes close to the core; lights that are near.
    let near = core.grown(0.25);
    let mut fit = core;
    for o in &trace.objects {
        if let Some((cen, rad)) = bounding_sphere(&o.shape) {
            let mut b = Bounds::EMPTY;
            frame0.fit(&mut b, cen, rad);
            if near.overlaps(&b) {
                frame0.fit(&mut fit, cen, rad);
            }
        }
    }
    for (_, n) in node_visits(info, info.box_ray(), false) {
        if n.test.hit {
            let (pts, _) = box_points(&frame0, v3(n.test.min), v3(n.test.max));
            let mut b = Bounds::EMPTY;
            for p in &pts {
                frame0.fit(&mut b, *p, 0.0);
            }
            if near.overlaps(&b) {
                fit.add(b.min);
                fit.add(b.max);
            }
        }
    }
    let light_near = core.grown(0.2);
    for l in &trace.lights {
        let mut b = Bounds::EMPTY;
        frame0.fit(&mut b, l.position, 0.0);
        if light_near.contains(b.min) && light_near.contains(b.max) {
            fit.add(b.min);
            fit.add(b.max);
        }
    }
    if fit.is_empty() {
        fit.add([0.0, 0.0]);
    }
    // Never thinner than a fifth of its length, never smaller than one unit.
    let s = fit.size();
    let want = [s[0].max(s[1] * 0.2).max(1.0), s[1].max(s[0] * 0.2).max(1.0)];
    let center = [
        (fit.min[0] + fit.max[0]) * 0.5,
        (fit.min[1] + fit.max[1]) * 0.5,
    ];
    let pad = ts * 1.2;
    let scale = ((plot[2] - 2.0 * pad) / want[0])
        .min((plot[3] - 2.0 * pad) / want[1])
        .max(1e-6);
    let center_px = [plot[0] + plot[2] * 0.5, plot[1] + plot[3] * 0.5];

    let mut lay = SliceLayout {
        top_down: frame.top_down,
        plot,
        scale,
        eye: [0.0; 2],
        pixel: [0.0; 2],
        image_plane: [[0.0; 2]; 2],
        rays: vec![],
        circles: vec![],
        planes: vec![],
        lights: vec![],
        frame,
        center,
        center_px,
    };
    lay.eye = lay.px(cam.origin);
    let camera_step = trace.root.steps.iter().find_map(|s| match s.step {
        Step::Camera { screen, .. } => Some(screen),
        _ => None,
    });
    let [sx, sy] = camera_step.unwrap_or([0.0, 0.0]);
    let pixel3 =
        cam.origin + cam.u * (sx * cam.half_width) + cam.v * (sy * cam.half_height) - cam.w;
    lay.pixel = lay.px(pixel3);
    let ends = image_plane_ends(&frame, &cam, sy);
    lay.image_plane = [lay.px(ends[0]), lay.px(ends[1])];

    for (i, r) in info.rays.iter().enumerate() {
        let o = v3(r.ray.origin);
        let dir = v3(r.ray.direction);
        let t = end_t(info, i);
        let start = lay.px(o);
        // Whether the ray has a point to end at (a hit, a light, a blocker, the closest hit so
        // far), rather than running on to the border.
        let ends = r.ray.kind == RayKind::Shadow || t.is_finite();
        let end = if r.ray.kind == RayKind::Shadow && r.ray.hit.is_none() {
            let target = r
                .light
                .and_then(|l| trace.lights.get(l))
                .map_or(o + dir, |l| l.position);
            lay.px(target)
        } else if t.is_finite() {
            lay.px(o + dir * t)
        } else {
            border_point(&lay, start, lay.dpx(dir)).unwrap_or(start)
        };
        let hit = if r.ray.kind == RayKind::Shadow {
            None
        } else {
            info.find(i, |s| matches!(s, Step::Surface { .. }))
                .filter(|(j, _)| info.shown(i, *j))
                .and_then(|(_, s)| match s {
                    Step::Surface { point, .. } => Some(lay.px(v3(*point))),
                    _ => None,
                })
        };
        lay.rays.push(RayLayout {
            kind: r.ray.kind,
            depth: r.ray.depth,
            start,
            end,
            hit,
            hit_object: r.ray.hit.as_ref().map(|h| h.name.clone()),
            blocked: r.ray.kind == RayKind::Shadow && r.ray.hit.is_some(),
            visible: info.visible(i),
            current: info.current == Some(i),
            exit: if ends && !in_rect(plot, end) {
                clip_to_rect(plot, start, end).map(|(_, b)| b)
            } else {
                None
            },
        });
    }

    for o in &trace.objects {
        if let Shape::Sphere { center, radius } = o.shape {
            let (cen, rad, cut) = if frame.top_down {
                (center, radius, false)
            } else {
                let dd = frame.dist(center);
                if dd.abs() < radius {
                    (
                        center - frame.m * dd,
                        (radius * radius - dd * dd).sqrt(),
                        true,
                    )
                } else {
                    (center, radius, false)
                }
            };
            lay.circles.push(CircleLayout {
                name: o.name.clone(),
                center: lay.px(cen),
                radius: rad * scale,
                cut: cut || frame.top_down,
            });
        }
    }
    for o in &trace.objects {
        if let Some((n, offset)) = plane_of(&o.shape)
            && let Some((a, b)) = plane_cut(&lay, n, offset)
        {
            lay.planes.push(PlaneLayout {
                name: o.name.clone(),
                line: [a, b],
            });
        }
    }
    // Lights: at their place, or on the border towards them.
    let reference = info.rays[0].ray.hit.as_ref().map_or(cam.origin, |h| {
        v3(trace.root.origin) + v3(trace.root.direction) * h.t
    });
    for l in &trace.lights {
        let p = lay.px(l.position);
        let inset = inset_rect(plot, ts * 1.6);
        let (at, on_border) = if in_rect(inset, p) {
            (p, false)
        } else {
            // Towards it from the primary hit (kept inside the inset border), or from the
            // view's centre when that is out of the view too.
            let mut from = lay.px(reference);
            if in_rect(plot, from) {
                from = [
                    from[0].clamp(inset[0], inset[0] + inset[2]),
                    from[1].clamp(inset[1], inset[1] + inset[3]),
                ];
            } else {
                from = [plot[0] + plot[2] * 0.5, plot[1] + plot[3] * 0.5];
            }
            let mut at = clip_to_rect(inset, from, p).map_or(p, |(_, b)| b);
            // Not on the axes glyph: beside it.
            let ab = axes_box(plot, ts);
            if in_rect(ab, at) {
                if at[1] - ab[1] < at[0] - ab[0] {
                    at[0] = ab[0] - ts * 0.6;
                } else {
                    at[1] = ab[1] + ab[3] + ts * 0.6;
                }
            }
            (at, true)
        };
        lay.lights.push(LightLayout {
            name: l.name.clone(),
            at,
            on_border,
        });
    }
    lay
}

/// The box of the axes glyph in the plot's top-right corner (see [`Drawer::axes`]), for a
/// base text size `ts`.
pub(super) fn axes_box(plot: [f32; 4], ts: f32) -> [f32; 4] {
    let u = ts / 11.0;
    let [px, py, pw, _] = plot;
    let l = 20.0 * u;
    let o = [px + pw - l - 14.0 * u, py + l + 10.0 * u];
    let r = l + 6.0 * u + ts * 0.85 * 0.7;
    [o[0] - r, o[1] - r, 2.0 * r, 2.0 * r]
}

/// The image plane's ends in the view: where the cutting plane crosses the image rectangle (one
/// unit in front of the eye), or, from above, the pixel's row.
pub(super) fn image_plane_ends(frame: &Frame, cam: &CameraRays, sy: f32) -> [Vec3; 2] {
    let center = cam.origin - cam.w;
    let (hw, hh) = (cam.half_width, cam.half_height);
    if frame.top_down {
        let row = center + cam.v * (sy * hh);
        return [row - cam.u * hw, row + cam.u * hw];
    }
    // Points a·u + b·v of the rectangle with (center + a·u + b·v − cut_o)·m = 0.
    let (ku, kv, k0) = (cam.u.dot(frame.m), cam.v.dot(frame.m), frame.dist(center));
    let mut pts = vec![];
    for (fixed_u, val) in [(true, -hw), (true, hw), (false, -hh), (false, hh)] {
        // Edge a = ±hw (b free) or b = ±hh (a free).
        let (a, b) = if fixed_u {
            if kv.abs() < 1e-9 {
                continue;
            }
            (val, -(k0 + ku * val) / kv)
        } else {
            if ku.abs() < 1e-9 {
                continue;
            }
            (-(k0 + kv * val) / ku, val)
        };
        if a.abs() <= hw * 1.0001 && b.abs() <= hh * 1.0001 {
            pts.push(center + cam.u * a + cam.v * b);
        }
    }
    if pts.len() < 2 {
        return [center - cam.v * hh, center + cam.v * hh];
    }
    // The two farthest apart (corners can repeat).
    let mut best = (0, 1, -1.0);
    for i in 0..pts.len() {
        for j in i + 1..pts.len() {
            let dd = (pts[i] - pts[j]).length();
            if dd > best.2 {
                best = (i, j, dd);
            }
        }
    }
    [pts[best.0], pts[best.1]]
}

/// How far the view reaches beyond its context (the eye, the image plane and the primary ray's
/// hit), as a fraction of the context's larger side (at least one unit): a hit, an object or a
/// ray's origin farther out is left out of the fit, and a ray to it leaves the frame, marked
/// at the edge with its t.
pub(super) const REACH: f32 = 0.75;

/// What the view frames, in the unturned plane (see the module's docs): the context (the eye,
/// the image plane, the primary ray's hit and the object hit) and the step's story — unfocused,
/// the first bounces (the non-shadow rays of depth 1); focused, the current ray: its origin, its
/// hit, the object hit and the objects it tests — each only if it lies within [`REACH`] of the
/// context. A current ray that starts beyond that reach (or, from the step that finds its hit
/// point on, whose hit lies beyond it) is framed on its own: a box of the context's size around
/// that point, with what lies within reach of it (so the scale stays).
pub(super) fn framing_core(
    trace: &Trace,
    info: &RayInfos,
    frame0: &Frame,
    cam: &CameraRays,
) -> Bounds {
    let root = info.rays[0].ray;
    let mut ctx = Bounds::EMPTY;
    frame0.fit(&mut ctx, cam.origin, 0.0);
    frame0.fit(&mut ctx, cam.origin - cam.w, 0.0);
    frame0.fit(&mut ctx, v3(root.origin), 0.0);
    match &root.hit {
        Some(h) => frame0.fit(&mut ctx, v3(root.origin) + v3(root.direction) * h.t, 0.0),
        None => {
            // A miss goes a little way (it is drawn on to the border): as far as the objects
            // it passes, at least as far as the context is large.
            let extent = ctx.size()[0].max(ctx.size()[1]);
            let d = v3(root.direction).try_normalize().unwrap_or(Vec3::Z);
            let tested = trace
                .objects
                .iter()
                .filter_map(|o| bounding_sphere(&o.shape))
                .map(|(cen, rad)| (cen - v3(root.origin)).dot(d) + rad)
                .fold(0.0_f32, f32::max);
            frame0.fit(
                &mut ctx,
                v3(root.origin) + d * tested.max(extent).max(2.0),
                0.0,
            );
        }
    }
    let reach = reach_of(&ctx);
    let mut core = ctx;
    if let Some(s) = root
        .hit
        .as_ref()
        .and_then(|h| object(trace, h.object))
        .and_then(|o| bounding_sphere(&o.shape))
    {
        add_within(frame0, &mut core, &reach, s);
    }
    let story: Vec<usize> = match info.current {
        Some(i) => vec![i],
        None => (0..info.rays.len())
            .filter(|&i| {
                let r = info.rays[i].ray;
                r.kind != RayKind::Shadow && r.depth <= 1
            })
            .collect(),
    };
    for i in story {
        let r = info.rays[i].ray;
        // Where the story stands: at the ray's origin while it searches, at its hit from the
        // step that finds the hit point on.
        let at_hit = info.focus.is_some()
            && info
                .find(i, |s| matches!(s, Step::Surface { .. }))
                .is_some_and(|(j, _)| info.shown(i, j));
        let anchor = match (&r.hit, at_hit) {
            (Some(h), true) => v3(r.origin) + v3(r.direction) * h.t,
            _ => v3(r.origin),
        };
        let mut reach = reach;
        let o = frame0.to2(anchor);
        if !reach.contains(o) {
            // Far from the eye: framed on its own, at the context's scale.
            let half = [ctx.size()[0] * 0.5, ctx.size()[1] * 0.5];
            core = Bounds {
                min: [o[0] - half[0], o[1] - half[1]],
                max: [o[0] + half[0], o[1] + half[1]],
            };
            reach = reach_of(&core);
        }
        core.add(o);
        let origin = (v3(r.origin), 0.0);
        for s in std::iter::once(origin).chain(story_parts(trace, info, i)) {
            add_within(frame0, &mut core, &reach, s);
        }
    }
    core
}

/// The context grown by [`REACH`] of its larger side, at least one unit.
fn reach_of(b: &Bounds) -> Bounds {
    let s = b.size();
    let g = (REACH * s[0].max(s[1])).max(1.0);
    Bounds {
        min: [b.min[0] - g, b.min[1] - g],
        max: [b.max[0] + g, b.max[1] + g],
    }
}

/// Adds the sphere `(centre, radius)` (radius 0: a point) to `core` if it lies within `reach`.
fn add_within(frame0: &Frame, core: &mut Bounds, reach: &Bounds, (c, r): (Vec3, f32)) {
    let mut b = Bounds::EMPTY;
    frame0.fit(&mut b, c, r);
    if !b.is_empty() && reach.contains(b.min) && reach.contains(b.max) {
        core.add(b.min);
        core.add(b.max);
    }
}

/// What a ray's story is made of, as spheres (radius 0: points): where it ends (its hit; for a
/// shadow ray its blocker or its light), the object it hits and the objects it tests; a miss
/// goes a little way.
fn story_parts(trace: &Trace, info: &RayInfos, i: usize) -> Vec<(Vec3, f32)> {
    let r = info.rays[i].ray;
    let (o, d) = (v3(r.origin), v3(r.direction));
    let mut parts = vec![];
    match (&r.hit, r.kind) {
        (Some(h), _) => parts.push((o + d * h.t, 0.0)),
        (None, RayKind::Shadow) => parts.push((o + d, 0.0)),
        (None, _) => parts.push((o + d.try_normalize().unwrap_or(Vec3::Z) * 0.5, 0.0)),
    }
    let ids = r
        .hit
        .iter()
        .map(|h| h.object)
        .chain(r.steps.iter().filter_map(|s| match s.step {
            Step::Sphere { object, .. } | Step::Triangle { object, .. } => Some(object),
            _ => None,
        }));
    for id in ids {
        if let Some(s) = object(trace, id).and_then(|o| bounding_sphere(&o.shape)) {
            parts.push(s);
        }
    }
    parts
}

/// Where the plane X·n = offset crosses the plot, in pixels (left end first); None when it is
/// parallel to the view (a floor seen from above) or misses the plot.
pub(super) fn plane_cut(lay: &SliceLayout, n: Vec3, offset: f32) -> Option<(Px, Px)> {
    let f = &lay.frame;
    // Points X of the cutting plane with X·n = offset: q·(x·n, y·n) = offset − base·n, in the
    // cutting plane's own 2D coordinates through `base`: the point of the cutting plane at the
    // view's centre (the view may lie far from the eye).
    let c0 = f.to2(f.cut_o);
    let base = f.cut_o + f.x * (lay.center[0] - c0[0]) + f.y * (lay.center[1] - c0[1]);
    let (kx, ky) = (f.x.dot(n), f.y.dot(n));
    let k = (kx * kx + ky * ky).sqrt();
    if k < 1e-4 {
        return None;
    }
    let rhs = offset - base.dot(n);
    // Closest point to base, and the line direction.
    let q0 = [kx * rhs / (k * k), ky * rhs / (k * k)];
    let dir = [-ky / k, kx / k];
    let p0 = base + f.x * q0[0] + f.y * q0[1];
    let span = 4.0 * (lay.plot[2] + lay.plot[3]) / lay.scale;
    let a = lay.px(p0 + (f.x * dir[0] + f.y * dir[1]) * span);
    let b = lay.px(p0 - (f.x * dir[0] + f.y * dir[1]) * span);
    let (a, b) = clip_to_rect(lay.plot, a, b)?;
    let (a, b) = if a[0] <= b[0] { (a, b) } else { (b, a) };
    (len(sub(b, a)) > 1.0).then_some((a, b))
}

/// A plane's normal and offset (X·n = offset).
pub(super) fn plane_of(shape: &Shape) -> Option<(Vec3, f32)> {
    match *shape {
        Shape::Plane { normal, offset } => Some((normal, offset)),
        Shape::AxisPlane { axis, offset } => Some((Vec3::AXES[axis.min(2)], offset)),
        _ => None,
    }
}
