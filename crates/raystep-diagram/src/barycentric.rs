//! The barycentric view of one recorded ray–triangle test: the triangle drawn in its own plane
//! (P0 at the origin, E1 = P1 − P0 along the x axis), the edge vectors E1 and E2, the allowed
//! region u ≥ 0, v ≥ 0, u + v ≤ 1 shaded, and the point P = P0 + u·E1 + v·E2 placed by the
//! test's recorded u and v — inside the region for a hit, outside for a miss. A panel gives the
//! test's numbers and where it stopped; a strip lists the steps with the ones the test reached.
//!
//! The 2D frame is built from the vertices stored in the trace; u and v are the kernel's own, so
//! the picture shows exactly what the renderer decided (no intersection is recomputed here).

use super::canvas::{Rgba, clip_segment, with_alpha};
use super::text::{
    Placer, Rich, draw_panel, fitting_panel_width, interval_at, ray_name, rich, rich_width,
};
use super::{Anchor, Canvas, ViewOptions, pick_step, title, title_first_fitting};
use crate::record::number::{Style, fmt64, num};
use crate::record::{Step, Trace};
use crate::shapes::{TriangleMethod, TriangleTest};

/// Where the barycentric diagram puts things, from the trace alone (tests check the drawing
/// against the record with it).
#[derive(Debug, Clone, PartialEq)]
pub struct BarycentricLayout {
    /// Index of the explained step in [`Trace::timeline`].
    pub step: usize,
    /// The triangle's name.
    pub name: String,
    /// The ray that ran the test (e.g. "primary ray").
    pub ray: String,
    /// The recorded vertices P0, P1, P2.
    pub vertices: [[f32; 3]; 3],
    /// The recorded test.
    pub test: TriangleTest<f32>,
    /// The ray's interval (t_min, t_max) when the test ran.
    pub interval: (f32, f32),
    /// P0, P1, P2 in the triangle's plane, scene units: P0 = (0, 0), P1 on the +x axis. Mirrored
    /// when the ray sees the triangle's back, so the drawing is as the ray sees it.
    pub plane: [[f64; 2]; 3],
    /// P0, P1, P2 on the canvas, pixels.
    pub vertex_px: [[f32; 2]; 3],
    /// P = P0 + u·E1 + v·E2 on the canvas, when the test computed both u and v.
    pub point_px: Option<[f32; 2]>,
    /// Whether P lies in the view (false when it is so far out that it is only pointed at).
    pub point_in_view: bool,
    /// The drawing area [x0, y0, x1, y1].
    pub drawing: [f32; 4],
    /// The number panel [x0, y0, x1, y1].
    pub panel: [f32; 4],
    /// The steps strip [x0, y0, x1, y1].
    pub strip: [f32; 4],
    /// Scene units → pixels.
    pub scale: f32,
}

impl BarycentricLayout {
    /// Whether the test hit (reached step 12).
    pub fn hit(&self) -> bool {
        self.test.stopped_at == 12 && self.test.t.is_some()
    }

    /// A point of the triangle's plane given by barycentric (u, v), on the canvas.
    pub fn at(&self, u: f64, v: f64) -> [f32; 2] {
        let [a, b, c] = self.vertex_px;
        let (u, v) = (u as f32, v as f32);
        [
            a[0] + u * (b[0] - a[0]) + v * (c[0] - a[0]),
            a[1] + u * (b[1] - a[1]) + v * (c[1] - a[1]),
        ]
    }
}

fn sub3(a: [f32; 3], b: [f32; 3]) -> [f64; 3] {
    [
        a[0] as f64 - b[0] as f64,
        a[1] as f64 - b[1] as f64,
        a[2] as f64 - b[2] as f64,
    ]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: [f64; 3]) -> Option<[f64; 3]> {
    let l = dot(a, a).sqrt();
    (l > 0.0 && l.is_finite()).then(|| [a[0] / l, a[1] / l, a[2] / l])
}

/// An orthonormal frame of the triangle's plane: x along E1 (or E2 if E1 is zero), y in the plane
/// on E2's side, mirrored when `dir` (the ray) looks at the back of the triangle.
fn plane_frame(p: [[f32; 3]; 3], dir: [f32; 3]) -> ([f64; 3], [f64; 3]) {
    let e1 = sub3(p[1], p[0]);
    let e2 = sub3(p[2], p[0]);
    let x = unit(e1).or_else(|| unit(e2)).unwrap_or([1.0, 0.0, 0.0]);
    let n = cross(e1, e2);
    let y = match unit(n) {
        Some(n) => cross(n, x),
        // Degenerate (collinear) triangle: any direction perpendicular to x.
        None => {
            let helper = if x[0].abs() < 0.9 {
                [1.0, 0.0, 0.0]
            } else {
                [0.0, 1.0, 0.0]
            };
            unit(cross(x, helper)).unwrap_or([0.0, 1.0, 0.0])
        }
    };
    let d = [dir[0] as f64, dir[1] as f64, dir[2] as f64];
    // Seen from the ray's origin the triangle's front (n towards the viewer) has d·n < 0; for
    // the back, mirror so the picture is as the ray sees it.
    if dot(d, n) > 0.0 {
        ([-x[0], -x[1], -x[2]], y)
    } else {
        (x, y)
    }
}

/// Where everything goes.
pub fn layout(trace: &Trace, opts: &ViewOptions) -> Option<BarycentricLayout> {
    let (k, step) = pick_step(trace, opts.focus, |s| matches!(s, Step::Triangle { .. }))?;
    let Step::Triangle {
        name,
        vertices,
        test,
        ..
    } = step
    else {
        return None;
    };
    let tl = trace.timeline();
    let (ray, record) = tl[k];
    let interval = interval_at(ray, record);
    let c = Canvas::for_view(opts);
    let (w, h, s) = (c.width(), c.height(), c.text_size);
    let small = (s * 0.85).max(13.0 * c.scale);

    // Regions: title, then drawing | panel, then the steps strip across the bottom.
    let top = s * 0.6 + s * 1.15 * 1.5;
    let rows = if test.method == TriangleMethod::MollerTrumbore {
        6.0
    } else {
        4.0
    };
    let strip_size = strip_text_size(&c, test.method, w, small);
    let strip_h = rows * strip_size * 1.3 + strip_size * 0.8;
    let strip = [s * 0.6, h - strip_h - s * 0.3, w - s * 0.6, h - s * 0.3];
    // The number panel where its lines, wrapped to its width, fit at the labels' size; else
    // it is left out and the drawing takes the width (the app's math panel shows the same
    // numbers, large).
    let panel_w = fitting_panel_width(
        &c,
        (&number_heading(name), &number_rows(test, interval, &c)),
        small,
        (w * 0.36).max(140.0).min(w * 0.5),
        strip[1] - s * 0.4 - top,
    );
    let panel = [w - panel_w, top, w - s * 0.5, strip[1] - s * 0.4];
    let right = if panel_w > 0.0 {
        panel[0] - s * 0.8
    } else {
        w - s * 0.6
    };
    let drawing = [s * 0.6, top, right, strip[1] - s * 0.4];

    // The plane frame and the 2D points.
    let (xa, ya) = plane_frame(*vertices, ray.direction);
    let to2 = |q: [f64; 3]| [dot(q, xa), dot(q, ya)];
    let e1 = to2(sub3(vertices[1], vertices[0]));
    let e2 = to2(sub3(vertices[2], vertices[0]));
    let plane = [[0.0, 0.0], e1, e2];
    let uv = match (test.u, test.v) {
        (Some(u), Some(v)) if u.is_finite() && v.is_finite() => Some((u as f64, v as f64)),
        _ => None,
    };
    let at2 = |u: f64, v: f64| [u * e1[0] + v * e2[0], u * e1[1] + v * e2[1]];
    // What must be in view: the triangle, P (unless absurdly far), the foot of the u-line.
    let mut pts: Vec<[f64; 2]> = plane.to_vec();
    let min = |i: usize, p: &[[f64; 2]]| p.iter().map(|q| q[i]).fold(f64::INFINITY, f64::min);
    let max = |i: usize, p: &[[f64; 2]]| p.iter().map(|q| q[i]).fold(f64::NEG_INFINITY, f64::max);
    let size = (max(0, &pts) - min(0, &pts))
        .max(max(1, &pts) - min(1, &pts))
        .max(1e-12);
    let near = |q: [f64; 2]| {
        q[0] > min(0, &plane) - 3.0 * size
            && q[0] < max(0, &plane) + 3.0 * size
            && q[1] > min(1, &plane) - 3.0 * size
            && q[1] < max(1, &plane) + 3.0 * size
    };
    let mut point_in_view = false;
    if let Some((u, v)) = uv {
        let q = at2(u, v);
        if near(q) {
            pts.push(q);
            point_in_view = true;
        }
    } else if let (Some(u), None) = (test.u, test.v)
        && u.is_finite()
    {
        let q = at2(u as f64, 0.0);
        if near(q) {
            pts.push(q);
        }
    }
    let (x0, x1, y0, y1) = (min(0, &pts), max(0, &pts), min(1, &pts), max(1, &pts));
    // Room for labels around the shapes, and for the line saying why there is no P; a smooth
    // triangle's hit leaves a fifth of the room more for its vertex normals, which lean outwards.
    let smooth = test.t.is_some()
        && ray.hit.as_ref().is_some_and(|h| &h.name == name)
        && ray
            .steps
            .iter()
            .any(|s| matches!(s.step, Step::ShadingNormal { .. }));
    let margin = if smooth {
        small * 2.6 + 0.1 * (drawing[2] - drawing[0]).min(drawing[3] - drawing[1])
    } else {
        small * 2.6
    };
    let fit = if uv.is_none() {
        [drawing[0], drawing[1], drawing[2], drawing[3] - small * 1.6]
    } else {
        drawing
    };
    let aw = (fit[2] - fit[0] - 2.0 * margin).max(10.0);
    let ah = (fit[3] - fit[1] - 2.0 * margin).max(10.0);
    let scale = ((aw as f64 / (x1 - x0).max(1e-12)).min(ah as f64 / (y1 - y0).max(1e-12))) as f32;
    let cx = (fit[0] + fit[2]) / 2.0;
    let cy = (fit[1] + fit[3]) / 2.0;
    let (mx, my) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let px = |q: [f64; 2]| {
        [
            cx + ((q[0] - mx) as f32) * scale,
            cy - ((q[1] - my) as f32) * scale,
        ]
    };
    let vertex_px = [px(plane[0]), px(plane[1]), px(plane[2])];
    let mut out = BarycentricLayout {
        step: k,
        name: name.clone(),
        ray: ray_name(ray),
        vertices: *vertices,
        test: *test,
        interval,
        plane,
        vertex_px,
        point_px: None,
        point_in_view,
        drawing,
        panel,
        strip,
        scale,
    };
    // P from the canvas vertices, so that P = P0 + u·(P1 − P0) + v·(P2 − P0) holds on the canvas.
    out.point_px = uv.map(|(u, v)| out.at(u, v));
    Some(out)
}

/// The steps, each with the step number of Bailey's notes it stands for.
fn steps(method: TriangleMethod) -> Vec<(u8, &'static str)> {
    match method {
        TriangleMethod::MollerTrumbore => vec![
            (1, "E_1 = P_1−P_0, E_2 = P_2−P_0"),
            (2, "D_0 = det(−Q,E_1,E_2); 0 → stop"),
            (3, "T = S − P_0"),
            (4, "D_t = det(T,E_1,E_2)"),
            (5, "t* = D_t/D_0; out of range → stop"),
            (6, "D_u = det(−Q,T,E_2)"),
            (7, "u* = D_u/D_0"),
            (8, "u* < 0 or u* > 1 → stop"),
            (9, "D_v = det(−Q,E_1,T)"),
            (10, "v* = D_v/D_0"),
            (11, "v* < 0 or u*+v* > 1 → stop"),
            (12, "hit at t*"),
        ],
        // Watertight's own order, tagged with Bailey's numbers its stops map onto.
        TriangleMethod::Watertight => vec![
            (1, "shear: ray along +z"),
            (1, "edge functions e_0, e_1, e_2"),
            (8, "mixed signs → stop (8)"),
            (2, "det = e_0+e_1+e_2; 0 → stop (2)"),
            (4, "t* = Σ e_iz_i / det"),
            (5, "t* out of range → stop (5)"),
            (5, "t* ≤ its error → stop (5)"),
            (12, "hit: u* = e_1/det, v* = e_2/det"),
        ],
    }
}

/// How far down the list the test got, and which item it stopped at.
fn reached(test: &TriangleTest<f32>, interval: (f32, f32)) -> usize {
    match test.method {
        TriangleMethod::MollerTrumbore => (test.stopped_at as usize).clamp(1, 12) - 1,
        TriangleMethod::Watertight => match test.stopped_at {
            8 => 2,
            2 => 3,
            5 => {
                let in_range = test
                    .t_star
                    .is_some_and(|t| t > interval.0 && t < interval.1);
                if in_range { 6 } else { 5 }
            }
            _ => 7,
        },
    }
}

/// A step as listed: Bailey's number for Möller–Trumbore, a bullet for watertight (whose
/// items carry the number they map onto).
fn step_line(method: TriangleMethod, i: usize, text: &str) -> String {
    match method {
        TriangleMethod::MollerTrumbore => format!("{:>2}. {text}", i + 1),
        TriangleMethod::Watertight => format!("• {text}"),
    }
}

fn strip_text_size(c: &Canvas, method: TriangleMethod, width: f32, small: f32) -> f32 {
    let col_w = (width - c.text_size * 1.2) / 2.0 - 8.0;
    let widest = steps(method)
        .iter()
        .enumerate()
        .map(|(i, (_, t))| rich_width(c, &Rich::new(&step_line(method, i, t)), 1.0))
        .fold(0.0, f32::max);
    (col_w / widest).min(small).max(7.0)
}

/// The diagram's titles, longest first ([`super::test_titles`]): the object and ray, the
/// step's number and which ray–triangle test of the trace it is.
pub fn titles(trace: &Trace, l: &BarycentricLayout) -> Vec<String> {
    super::test_titles(trace, "Barycentric", &l.name, &l.ray, l.step, |s| {
        matches!(s, Step::Triangle { .. })
    })
}

/// Draws the diagram.
pub fn draw(trace: &Trace, opts: &ViewOptions) -> Canvas {
    let mut c = Canvas::for_view(opts);
    let Some(l) = layout(trace, opts) else {
        title(&mut c, "barycentric: this trace has no ray–triangle test");
        return c;
    };
    let s = c.text_size;
    let small = (s * 0.85).max(13.0 * c.scale);
    title_first_fitting(&mut c, &titles(trace, &l));
    draw_triangle(&mut c, &l, small);
    let mut extra = vec![];
    if let Some(n) = smooth_normals(trace, &l) {
        draw_normals(&mut c, &l, &n, small);
        let th = c.theme;
        extra = vec![
            (String::new(), th.ink),
            ("arrows: n_0, n_1, n_2 and n_s,".to_string(), th.normal),
            ("their parts along the plane,".to_string(), th.muted),
            ("enlarged (the rest points out)".to_string(), th.muted),
        ];
    }
    draw_numbers(&mut c, &l, small, &extra);
    draw_steps(&mut c, &l, small);
    c
}

/// A smooth triangle's normals as the diagram draws them: the parts of n₀, n₁, n₂ and of their
/// blend n_s along the triangle's plane (x, y of its frame; the rest points out of the plane),
/// from the `ShadingNormal` step of the ray whose closest hit this test found.
#[derive(Debug, Clone, PartialEq)]
pub struct SmoothNormals {
    /// n₀, n₁, n₂ in the plane's frame.
    pub vertex: [[f64; 2]; 3],
    /// n_s in the plane's frame.
    pub blend: [f64; 2],
}

/// [`SmoothNormals`] for the layout's test, when it hit a smooth triangle.
pub fn smooth_normals(trace: &Trace, l: &BarycentricLayout) -> Option<SmoothNormals> {
    if !l.hit() {
        return None;
    }
    let tl = trace.timeline();
    let (ray, _) = tl[l.step];
    if ray.hit.as_ref()?.name != l.name {
        return None;
    }
    let (vertex_normals, normal) = ray.steps.iter().find_map(|s| match &s.step {
        Step::ShadingNormal {
            vertex_normals,
            normal,
            ..
        } => Some((*vertex_normals, *normal)),
        _ => None,
    })?;
    let (xa, ya) = plane_frame(l.vertices, ray.direction);
    let along = |n: [f32; 3]| {
        let n = [n[0] as f64, n[1] as f64, n[2] as f64];
        [dot(n, xa), dot(n, ya)]
    };
    Some(SmoothNormals {
        vertex: vertex_normals.map(along),
        blend: along(normal),
    })
}

/// The normals' parts along the plane, as arrows from the vertices and from P, all enlarged by
/// one factor: the longest a sixth of the shortest side, less where a tip would leave the
/// drawing and its margins.
fn draw_normals(c: &mut Canvas, l: &BarycentricLayout, n: &SmoothNormals, small: f32) {
    let th = c.theme;
    let v = l.vertex_px;
    let side = |a: [f32; 2], b: [f32; 2]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
    let shortest = side(v[0], v[1]).min(side(v[1], v[2])).min(side(v[2], v[0]));
    let len = |q: [f64; 2]| (q[0] * q[0] + q[1] * q[1]).sqrt();
    let longest = n
        .vertex
        .iter()
        .map(|q| len(*q))
        .fold(len(n.blend), f64::max);
    if !(longest > 1e-9 && shortest > 4.0) {
        return;
    }
    let mut arrows: Vec<([f32; 2], [f64; 2], &str, Rgba)> = (0..3)
        .map(|i| (v[i], n.vertex[i], ["n_0", "n_1", "n_2"][i], th.normal))
        .collect();
    if let Some(p) = l.point_px {
        arrows.push((p, n.blend, "n_s", th.hit));
    }
    // Pixels per unit of the normals' in-plane part (the canvas's y points down), shrunk until
    // every tip, with room for its label, lies in the drawing.
    // The drawing's box, with the margins around it (not the title, the panel or the strip).
    let [x0, y0, x1, y1] = [
        small * 0.5,
        l.drawing[1] - small * 0.5,
        l.drawing[2] + small * 0.5,
        l.drawing[3] + small * 0.3,
    ];
    let pad = small * 1.5;
    let mut k = shortest / 6.0 / longest as f32;
    for (from, q, _, _) in &arrows {
        for (d, lo, hi, f) in [
            (q[0] as f32, x0 + pad, x1 - pad, from[0]),
            (-q[1] as f32, y0 + pad, y1 - pad, from[1]),
        ] {
            if d > 0.0 && f + d * k > hi {
                k = k.min(((hi - f) / d).max(0.0));
            } else if d < 0.0 && f + d * k < lo {
                k = k.min(((lo - f) / d).max(0.0));
            }
        }
    }
    let lw = 2.0 * c.scale;
    for (from, q, name, colour) in arrows {
        let t = [from[0] + q[0] as f32 * k, from[1] - q[1] as f32 * k];
        c.arrow(from, t, colour, lw);
        // The label past the tip, on the arrow's side.
        let anchor = if q[0] >= 0.0 {
            Anchor::MiddleLeft
        } else {
            Anchor::MiddleRight
        };
        let gap = if q[0] >= 0.0 { 4.0 } else { -4.0 };
        rich(c, t[0] + gap, t[1], small, &Rich::new(name), colour, anchor);
    }
}

/// The triangle, its edge vectors, the region and P.
fn draw_triangle(c: &mut Canvas, l: &BarycentricLayout, small: f32) {
    let th = c.theme;
    let s = c.text_size;
    let test = &l.test;
    let [p0, p1, p2] = l.vertex_px;
    let lw = (s / 8.0).max(1.5);
    let d = l.drawing;
    let mut placer = Placer::new([d[0], d[1], d[2], d[3]]);

    // The allowed region u ≥ 0, v ≥ 0, u + v ≤ 1 is the triangle itself.
    c.polygon(&[p0, p1, p2], Some(th.region), Some(th.object), lw);
    let centroid = [(p0[0] + p1[0] + p2[0]) / 3.0, (p0[1] + p1[1] + p2[1]) / 3.0];

    // The u-line when only u was computed (Möller–Trumbore stopped at step 8): every point with
    // that u, whatever v.
    let only_u = match (test.u, test.v) {
        (Some(u), None) if u.is_finite() => Some(u),
        _ => None,
    };
    if let Some(u) = only_u {
        let a = l.at(u as f64, 0.0);
        let dir = [p2[0] - p0[0], p2[1] - p0[1]];
        let len = (dir[0] * dir[0] + dir[1] * dir[1]).sqrt().max(1e-6);
        let reach = (d[2] - d[0]).max(d[3] - d[1]) * 2.0 / len;
        let (from, to) = (
            [a[0] - dir[0] * reach, a[1] - dir[1] * reach],
            [a[0] + dir[0] * reach, a[1] + dir[1] * reach],
        );
        let wide = |p: [f32; 2]| [p[0] as f64, p[1] as f64];
        if let Some((from, to)) = clip_segment(d.map(f64::from), wide(from), wide(to)) {
            let narrow = |p: [f64; 2]| [p[0] as f32, p[1] as f32];
            c.dashed(narrow(from), narrow(to), th.ray, lw);
        }
    }

    // Watertight stopped at step 8: the edges the ray passes outside of (e_i belongs to the edge
    // opposite P_i).
    let odd_edges = outside_edges(test);

    // How P is built: P0 → P0 + u·E1 → P.
    if let (Some(p), Some(u), true) = (l.point_px, test.u, l.point_in_view) {
        let a = l.at(u as f64, 0.0);
        c.dashed(p0, a, with_alpha(th.normal, 170), lw);
        c.dashed(a, p, with_alpha(th.reflect, 170), lw);
    }

    // Edge vectors along the edges from P0.
    c.arrow(p0, p1, th.normal, lw * 1.6);
    c.arrow(p0, p2, th.reflect, lw * 1.6);

    // Those edges, marked just outside the triangle (the arrows stay visible).
    for &i in &odd_edges {
        let (a, b) = ([p0, p1, p2][(i + 1) % 3], [p0, p1, p2][(i + 2) % 3]);
        let (nx, ny) = outward(a, b, centroid);
        let o = lw * 3.0;
        c.line(
            [a[0] + nx * o, a[1] + ny * o],
            [b[0] + nx * o, b[1] + ny * o],
            th.ray,
            lw * 2.0,
        );
    }

    // Vertex dots (labels come after the most important label, P's).
    let r = (s * 0.28).max(3.5);
    for p in [p0, p1, p2] {
        c.circle(p, r, Some(th.ink), Some(th.background), 1.5);
        placer.block([p[0] - r, p[1] - r, p[0] + r, p[1] + r]);
    }

    // P.
    let hit = l.hit();
    let inside_uv =
        matches!((test.u, test.v), (Some(u), Some(v)) if u >= 0.0 && v >= 0.0 && u + v <= 1.0);
    let p_col = if hit { th.hit } else { th.ray };
    if let Some(p) = l.point_px {
        if l.point_in_view {
            c.circle(p, r * 2.2, Some(with_alpha(p_col, 60)), None, 0.0);
            c.circle(p, r * 1.3, Some(p_col), Some(th.background), 2.0);
            placer.block([
                p[0] - r * 2.2,
                p[1] - r * 2.2,
                p[0] + r * 2.2,
                p[1] + r * 2.2,
            ]);
            let text = if hit {
                "P: hit"
            } else if inside_uv {
                "P: inside, but t* out of range"
            } else {
                "P: outside, miss"
            };
            let g = r * 2.4;
            placer.place(
                c,
                &[
                    (p[0] + g, p[1] - g, Anchor::MiddleLeft),
                    (p[0] - g, p[1] - g, Anchor::MiddleRight),
                    (p[0] + g, p[1] + g, Anchor::MiddleLeft),
                    (p[0] - g, p[1] + g, Anchor::MiddleRight),
                    (p[0], p[1] - g * 1.3, Anchor::Center),
                    (p[0], p[1] + g * 1.3, Anchor::Center),
                ],
                small,
                &Rich::new(text),
                p_col,
            );
        } else {
            // Too far out to draw at this scale: point at it from the centre.
            let dir = [p[0] - centroid[0], p[1] - centroid[1]];
            let len = (dir[0] * dir[0] + dir[1] * dir[1]).sqrt().max(1e-6);
            let reach = ((d[2] - d[0]).min(d[3] - d[1]) * 0.45).max(20.0);
            let tip = [
                centroid[0] + dir[0] / len * reach,
                centroid[1] + dir[1] / len * reach,
            ];
            c.arrow(centroid, tip, p_col, lw * 1.5);
            placer.place(
                c,
                &[
                    (tip[0], tip[1] - small, Anchor::Center),
                    (tip[0], tip[1] + small, Anchor::Center),
                ],
                small,
                &Rich::new("P: far outside, this way"),
                p_col,
            );
        }
    }
    if let Some(u) = only_u {
        // Beside the line, somewhere along it.
        let mut cands = vec![];
        for v in [0.5, 0.8, 0.2, 1.1, -0.1, 1.4, -0.4] {
            let a = l.at(u as f64, v);
            cands.push((a[0] + 8.0, a[1], Anchor::MiddleLeft));
            cands.push((a[0] - 8.0, a[1], Anchor::MiddleRight));
        }
        placer.place(
            c,
            &cands,
            small,
            &Rich::new(&format!(
                "u* = {}: P is on this line",
                fmt64(u as f64, Style::Label)
            )),
            th.ray,
        );
    }

    for &i in &odd_edges {
        let (a, b) = ([p0, p1, p2][(i + 1) % 3], [p0, p1, p2][(i + 2) % 3]);
        let e = test.edges.map_or(0.0, |e| e[i]);
        let r = Rich::new(&format!(
            "outside: e_{i} {} 0",
            if e < 0.0 { "<" } else { ">" }
        ));
        let cands = beside(
            a,
            b,
            centroid,
            &[0.5, 0.3, 0.7],
            small * 0.4,
            label_wh(c, &r, small),
        );
        placer.place(c, &cands, small, &r, th.ray);
    }

    // Vertex labels, away from the centroid.
    for (i, p) in [p0, p1, p2].into_iter().enumerate() {
        let (dx, dy) = away(centroid, p);
        let g = r + small * 0.9;
        let name = Rich::new(&format!("P_{i}"));
        let q = [p[0] + dx * g, p[1] + dy * g];
        placer.place(
            c,
            &[
                (q[0], q[1], Anchor::Center),
                (p[0] + g, p[1], Anchor::MiddleLeft),
                (p[0] - g, p[1], Anchor::MiddleRight),
                (p[0], p[1] - g, Anchor::Center),
                (p[0], p[1] + g, Anchor::Center),
            ],
            small * 1.05,
            &name,
            th.ink,
        );
    }

    // Edge-vector names beside their arrows (outside first); then the edges' equations.
    for (name, a, b, col) in [("E_1", p0, p1, th.normal), ("E_2", p0, p2, th.reflect)] {
        let r = Rich::new(name);
        let cands = beside(
            a,
            b,
            centroid,
            &[0.5, 0.35, 0.65, 0.2, 0.8],
            small * 0.4,
            label_wh(c, &r, small * 1.05),
        );
        placer.place(c, &cands, small * 1.05, &r, col);
    }
    for (eq, a, b) in [("v = 0", p0, p1), ("u = 0", p0, p2), ("u+v = 1", p1, p2)] {
        let r = Rich::new(eq);
        let mut cands = beside(
            a,
            b,
            centroid,
            &[0.8, 0.65, 0.5, 0.35],
            small * 0.3,
            label_wh(c, &r, small * 0.85),
        );
        // Only outside: inside, an equation would read as a label of the region.
        cands.truncate(4);
        placer.place_if_free(c, &cands, small * 0.85, &r, th.muted);
    }

    // No point to place: say why, at the bottom of the drawing.
    if l.point_px.is_none() {
        let why = match (test.u, test.v) {
            (Some(_), None) => "v was never computed: no point P",
            _ => "u and v were never computed: no point P",
        };
        let r = Rich::new(why);
        let size = small.min(small * (d[2] - d[0] - 8.0) / rich_width(c, &r, small).max(1.0));
        rich(
            c,
            (d[0] + d[2]) / 2.0,
            d[3] - small * 0.8,
            size,
            &r,
            th.ray,
            Anchor::Center,
        );
    }

    // What the picture means, where there is room.
    let legend = [
        Rich::new("P = P_0 + u*·E_1 + v*·E_2"),
        Rich::new("shaded: u, v ≥ 0, u+v ≤ 1"),
    ];
    let lh = small * 0.85 * 1.35;
    for (i, r) in legend.iter().enumerate() {
        let y = d[1] + small * 0.6 + i as f32 * lh;
        let w = rich_width(c, r, small * 0.85);
        placer.place_if_free(
            c,
            &[
                (d[0] + 4.0, y, Anchor::MiddleLeft),
                (d[2] - w - 4.0, y, Anchor::MiddleLeft),
            ],
            small * 0.85,
            r,
            th.muted,
        );
    }
}

/// Positions for a label of size `wh` beside segment a–b at the given fractions along it: first
/// all on the side away from `inside`, then all on the inside; each far enough that the label's
/// box clears the line.
fn beside(
    a: [f32; 2],
    b: [f32; 2],
    inside: [f32; 2],
    fractions: &[f32],
    gap: f32,
    wh: [f32; 2],
) -> Vec<(f32, f32, Anchor)> {
    let (nx, ny) = outward(a, b, inside);
    let [w, h] = wh;
    let off = gap + nx.abs() * w / 2.0 + ny.abs() * h / 2.0;
    let mut out = vec![];
    for side in [1.0, -1.0] {
        for &f in fractions {
            let m = [a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f];
            out.push((
                m[0] + side * nx * off,
                m[1] + side * ny * off,
                Anchor::Center,
            ));
        }
    }
    out
}

/// Watertight tests that stopped at step 8: the edges (numbered by the opposite vertex) whose
/// edge function's sign differs from the sign of their sum — the sign det would have had — i.e.
/// whose barycentric weight eᵢ/det is negative: P lies outside those edges.
fn outside_edges(test: &TriangleTest<f32>) -> Vec<usize> {
    let Some(e) = test.edges else { return vec![] };
    if test.stopped_at != 8 {
        return vec![];
    }
    let sum: f64 = e.iter().map(|&x| x as f64).sum();
    if sum == 0.0 || !sum.is_finite() {
        return vec![];
    }
    (0..3).filter(|&i| (e[i] as f64) * sum < 0.0).collect()
}

/// The box a label of `r` at `size` takes (with its background margin).
fn label_wh(c: &Canvas, r: &Rich, size: f32) -> [f32; 2] {
    [rich_width(c, r, size) + 6.0, size * 1.25 + 2.0]
}

/// The unit direction from `from` to `to` (up if they coincide).
fn away(from: [f32; 2], to: [f32; 2]) -> (f32, f32) {
    let (dx, dy) = (to[0] - from[0], to[1] - from[1]);
    let l = (dx * dx + dy * dy).sqrt();
    if l > 1e-3 {
        (dx / l, dy / l)
    } else {
        (0.0, -1.0)
    }
}

/// The unit normal of segment a–b pointing away from `inside`.
fn outward(a: [f32; 2], b: [f32; 2], inside: [f32; 2]) -> (f32, f32) {
    let (dx, dy) = away(a, b);
    let (nx, ny) = (-dy, dx);
    let m = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
    if (inside[0] - m[0]) * nx + (inside[1] - m[1]) * ny > 0.0 {
        (-nx, -ny)
    } else {
        (nx, ny)
    }
}

/// The number panel (left out when the layout found no room for it).
fn draw_numbers(c: &mut Canvas, l: &BarycentricLayout, small: f32, extra: &[(String, Rgba)]) {
    if l.panel[2] > l.panel[0] {
        let mut rows = number_rows(&l.test, l.interval, c);
        rows.extend_from_slice(extra);
        draw_panel(c, l.panel, small, number_heading(&l.name), &rows);
    }
}

/// The heading of the number panel.
fn number_heading(name: &str) -> Rich {
    Rich::new("triangle ").plain(&format!("\"{name}\""))
}

/// The number panel's rows: the test's values (the renderer's f32s), the ray's interval and
/// where the test stopped, each with its colour (an empty row is a gap).
fn number_rows(test: &TriangleTest<f32>, interval: (f32, f32), c: &Canvas) -> Vec<(String, Rgba)> {
    let th = c.theme;
    let val = |name: &str, x: Option<f32>| match x {
        Some(x) => (format!("{name} = {}", num(x)), th.ink),
        None => (format!("{name} = —"), th.faded),
    };
    let mut rows: Vec<(String, Rgba)> = vec![];
    match test.method {
        TriangleMethod::MollerTrumbore => {
            rows.push(("method: Möller–Trumbore (Cramer)".into(), th.muted));
            let det_reached = true;
            rows.push(val("D_0", det_reached.then_some(test.det)));
            rows.push(val("D_t", test.dt));
            rows.push(val("D_u", test.du));
            rows.push(val("D_v", test.dv));
            rows.push(val("t* = D_t/D_0", test.t_star));
            rows.push(val("u* = D_u/D_0", test.u));
            rows.push(val("v* = D_v/D_0", test.v));
        }
        TriangleMethod::Watertight => {
            rows.push(("method: watertight (Woop et al.)".into(), th.muted));
            let e = test.edges;
            rows.push(val("e_0", e.map(|e| e[0])));
            rows.push(val("e_1", e.map(|e| e[1])));
            rows.push(val("e_2", e.map(|e| e[2])));
            // det is only summed once the signs agree (the test stops at 8 before it).
            let det = (test.stopped_at != 8).then_some(test.det);
            rows.push(val("det = Σe_i", det));
            rows.push(val("t* = Σe_iz_i/det", test.t_star));
            rows.push(val("u* = e_1/det", test.u));
            rows.push(val("v* = e_2/det", test.v));
        }
    }
    let (t_min, t_max) = interval;
    rows.push((
        format!("ray: t in ({}, {})", num(t_min), num(t_max)),
        th.muted,
    ));
    rows.push((String::new(), th.ink));
    let hit = test.stopped_at == 12 && test.t.is_some();
    let stop_col = if hit { th.hit } else { th.ray };
    // Non-breaking spaces keep "[0, 1]" and "u + v" whole when the line wraps.
    let reason = test
        .stop_reason()
        .replace("[0, 1]", "[0,\u{a0}1]")
        .replace("u + v", "u\u{a0}+\u{a0}v");
    rows.push((
        format!("stopped at step {}: {reason}", test.stopped_at),
        stop_col,
    ));
    rows
}

/// The strip of steps: reached ones in ink, the rest faded, the stopping one highlighted.
fn draw_steps(c: &mut Canvas, l: &BarycentricLayout, small: f32) {
    let th = c.theme;
    let [x0, y0, x1, _] = l.strip;
    let list = steps(l.test.method);
    let stop = reached(&l.test, l.interval);
    let size = strip_text_size(c, l.test.method, c.width(), small);
    c.line([x0, y0], [x1, y0], th.faded, 1.0);
    let rows = list.len().div_ceil(2);
    let col_w = (x1 - x0) / 2.0;
    let line_h = size * 1.3;
    let stop_col = if l.hit() { th.hit } else { th.ray };
    for (i, (_, text)) in list.iter().enumerate() {
        let (col, row) = (i / rows, i % rows);
        let x = x0 + col as f32 * col_w + 4.0;
        let y = y0 + size * 0.45 + row as f32 * line_h;
        let line = Rich::new(&step_line(l.test.method, i, text));
        let color = if i == stop {
            let w = rich_width(c, &line, size);
            c.rect(
                x - 3.0,
                y - size * 0.1,
                w + 6.0,
                size * 1.25,
                with_alpha(stop_col, 45),
            );
            stop_col
        } else if i < stop {
            th.ink
        } else {
            th.faded
        };
        rich(c, x, y, size, &line, color, Anchor::TopLeft);
    }
}
