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

    // The core: the eye, every non-shadow ray's origin and hit, the objects hit.
    let mut core = Bounds::EMPTY;
    let cam = CameraRays::new(&trace.camera);
    frame0.fit(&mut core, cam.origin, 0.0);
    frame0.fit(&mut core, cam.origin - cam.w, 0.0);
    let mut misses = vec![];
    for r in &info.rays {
        // Deeper rays may leave the view: the first bounces matter most.
        if r.ray.kind == RayKind::Shadow || r.ray.depth > 1 {
            continue;
        }
        frame0.fit(&mut core, v3(r.ray.origin), 0.0);
        match &r.ray.hit {
            Some(hit) => {
                frame0.fit(
                    &mut core,
                    v3(r.ray.origin) + v3(r.ray.direction) * hit.t,
                    0.0,
                );
                if let Some(o) = object(trace, hit.object)
                    && let Some((cen, rad)) = bounding_sphere(&o.shape)
                {
                    frame0.fit(&mut core, cen, rad);
                }
            }
            None => misses.push(r.ray),
        }
    }
    // Misses go a little way (they are drawn on to the border).
    let extent = if core.is_empty() {
        1.0
    } else {
        core.size()[0].max(core.size()[1])
    };
    for r in &misses {
        let d = v3(r.direction).try_normalize().unwrap_or(Vec3::Z);
        let tested = trace
            .objects
            .iter()
            .filter_map(|o| bounding_sphere(&o.shape))
            .map(|(cen, rad)| (cen - v3(r.origin)).dot(d) + rad)
            .fold(0.0_f32, f32::max);
        let len = if r.kind == RayKind::Primary {
            tested.max(extent).max(2.0)
        } else {
            (0.3 * extent).max(0.5)
        };
        frame0.fit(&mut core, v3(r.origin) + d * len, 0.0);
    }
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
            let from = lay.px(reference);
            (clip_to_rect(inset, from, p).map_or(p, |(_, b)| b), true)
        };
        lay.lights.push(LightLayout {
            name: l.name.clone(),
            at,
            on_border,
        });
    }
    lay
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
