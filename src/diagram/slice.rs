//! The scene slice: the scene cut by a plane that contains the primary ray, seen face on, with
//! everything the trace did drawn into it — the eye and the image plane with the pixel, the rays
//! with their hits and normals, shadow rays to the lights (blocked ones crossed out), reflection
//! and refraction rays with their angles, and the BVH boxes the ray visited, numbered in order.
//!
//! **Which plane.** Where the primary ray's hit spawns a reflection or refraction, the *plane of
//! incidence* there: the plane spanned by the ray and the surface normal. Reflection and
//! refraction happen inside it (r and t are combinations of d and n), so their angles are drawn at
//! true size; for a sphere it goes through the centre, so the cut is a great circle and every
//! later bounce inside the same sphere (or a concentric one, like mirror-glass's bubble) stays in
//! the plane too. Otherwise the vertical plane through the ray — a side view, with floors level
//! and the world's up pointing up the page — falling back to the camera's up axis, then the x and
//! z axes, when the ray is vertical.
//! `slice_angle` turns the plane about the ray; the 2D frame turns with it, so the ray and its hit
//! stay where they are on the page while the scene turns around them. Rays and lights off the
//! plane are projected onto it; so are the spheres and boxes it misses (dashed), and each
//! triangle is shown faintly projected behind its cut.
//!
//! `top_down` instead projects everything onto the x–z plane, seen from above, turned so that the
//! camera looks up the page (the image's left is the page's left).
//!
//! **Purity.** Nothing here intersects anything: hit points, normals and directions are the
//! trace's records. The only geometry computed is the drawing's own — where the view plane cuts
//! the recorded shapes (circles, lines, segments, box polygons) and where points project.
//!
//! **Fit.** The view fits the eye, the hits of the first two generations of rays (deeper bounces
//! may leave it), the objects they hit and those tested close by, the visited BVH boxes and the
//! lights that are near; far lights sit on the border with an arrow and their distance. Rays
//! deeper than that are drawn thin and light unless they lead to the focused step (or, unfocused,
//! to the shallowest total internal reflection), so deep trees do not bury the first bounces. The fit depends on neither the focus nor `slice_angle` (it is made in the
//! unturned plane), so stepping through a trace or turning the plane never moves the ray.

use super::canvas::{Rgba, with_alpha};
use super::{Anchor, Canvas, ViewOptions, title};
use crate::scene::Shape;
use crate::trace::camera::CameraRays;
use crate::trace::record::TraceObject;
use crate::trace::{NodeAction, NodeVisit, RayKind, RayRecord, Step, Trace};
use glam::{Quat, Vec3};

/// A point on the page, in pixels (x to the right, y down).
pub type Px = [f32; 2];

/// Where the slice draws things, in pixels: what [`draw`] draws, for tests and for the app (to
/// put tooltips over hits, for example).
#[derive(Debug, Clone, PartialEq)]
pub struct SliceLayout {
    /// Whether this is the view from above.
    pub top_down: bool,
    /// The plot area: x, y, width, height.
    pub plot: [f32; 4],
    /// Pixels per scene unit (the same along both axes).
    pub scale: f32,
    /// The eye.
    pub eye: Px,
    /// The pixel's centre on the image plane (one unit in front of the eye).
    pub pixel: Px,
    /// The image plane's cut (or, from above, the pixel's row), end to end.
    pub image_plane: [Px; 2],
    /// Every ray of the trace in the order it was traced (the primary ray first).
    pub rays: Vec<RayLayout>,
    /// The spheres: their cuts by the plane (or, from above, their outlines).
    pub circles: Vec<CircleLayout>,
    /// The lights.
    pub lights: Vec<LightLayout>,
    frame: Frame,
    center: [f32; 2],
    center_px: Px,
}

/// One ray on the page.
#[derive(Debug, Clone, PartialEq)]
pub struct RayLayout {
    /// Kind.
    pub kind: RayKind,
    /// Recursion depth.
    pub depth: u32,
    /// Its origin.
    pub start: Px,
    /// Where the drawn ray ends: its hit, its light, its blocker, or the plot's border (a miss,
    /// or a ray still being traced at the focus).
    pub end: Px,
    /// The hit point (Surface step), when the ray has one and it is shown at the focus.
    pub hit: Option<Px>,
    /// The object hit (for shadow rays: the blocker).
    pub hit_object: Option<String>,
    /// Shadow rays: whether something blocks the light.
    pub blocked: bool,
    /// Whether the ray is drawn at all at the focus (rays after the focus are not).
    pub visible: bool,
    /// Whether the ray owns the focused step (drawn strongly; the others faded).
    pub current: bool,
}

/// A sphere on the page.
#[derive(Debug, Clone, PartialEq)]
pub struct CircleLayout {
    /// The object's name.
    pub name: String,
    /// Centre.
    pub center: Px,
    /// Radius in pixels.
    pub radius: f32,
    /// True for a cut by the plane, or from above the sphere's outline (drawn solid); false
    /// for the outline of a sphere the plane misses, projected onto it (drawn dashed).
    pub cut: bool,
}

/// A light on the page.
#[derive(Debug, Clone, PartialEq)]
pub struct LightLayout {
    /// Name.
    pub name: String,
    /// Where its glyph is drawn.
    pub at: Px,
    /// True when the light lies outside the view and is drawn on the border, towards it.
    pub on_border: bool,
}

impl SliceLayout {
    /// Where the scene point `p` lands on the page (projected onto the view plane).
    pub fn project(&self, p: [f32; 3]) -> Px {
        self.px(Vec3::from_array(p))
    }

    /// The primary ray.
    pub fn primary(&self) -> &RayLayout {
        &self.rays[0]
    }

    fn px(&self, p: Vec3) -> Px {
        self.px2(self.frame.to2(p))
    }

    fn px2(&self, q: [f32; 2]) -> Px {
        [
            self.center_px[0] + self.scale * (q[0] - self.center[0]),
            self.center_px[1] - self.scale * (q[1] - self.center[1]),
        ]
    }

    /// A scene direction as a page direction (not normalized; y down).
    fn dpx(&self, d: Vec3) -> Px {
        [d.dot(self.frame.x), -d.dot(self.frame.y)]
    }
}

/// Computes where everything goes, without drawing.
pub fn layout(trace: &Trace, opts: &ViewOptions) -> SliceLayout {
    let c = Canvas::for_view(opts);
    let info = RayInfos::new(trace, opts.focus);
    let legend = legend_entries(trace, &info, opts);
    let (legend_rows, _) = legend_flow(&c, &legend);
    compute_layout(&c, trace, opts, &info, legend_rows)
}

/// Draws the slice.
pub fn draw(trace: &Trace, opts: &ViewOptions) -> Canvas {
    let mut c = Canvas::for_view(opts);
    let info = RayInfos::new(trace, opts.focus);
    let legend = legend_entries(trace, &info, opts);
    let (legend_rows, legend_h) = legend_flow(&c, &legend);
    let lay = compute_layout(&c, trace, opts, &info, legend_rows);
    let mut d = Drawer {
        c: &mut c,
        lay: &lay,
        trace,
        info: &info,
        labels: vec![],
        strokes: vec![],
        u: 1.0,
    };
    d.u = d.c.text_size / 11.0;
    d.scene();
    d.chrome(opts, &legend, legend_h);
    c
}

// ---------------------------------------------------------------------------------------------
// The frame: the view plane and its 2D axes.

#[derive(Debug, Clone, Copy, PartialEq)]
struct Frame {
    /// The 2D origin (the primary ray's origin).
    o: Vec3,
    /// Page right.
    x: Vec3,
    /// Page up.
    y: Vec3,
    /// The view plane's normal (towards the viewer).
    m: Vec3,
    /// A point of the cutting plane (= o for the slice; at the hit's height from above).
    cut_o: Vec3,
    /// The primary ray's unit direction (the axis the slice turns about).
    d: Vec3,
    top_down: bool,
}

impl Frame {
    fn to2(&self, p: Vec3) -> [f32; 2] {
        let q = p - self.o;
        [q.dot(self.x), q.dot(self.y)]
    }

    /// Signed distance of `p` from the cutting plane.
    fn dist(&self, p: Vec3) -> f32 {
        (p - self.cut_o).dot(self.m)
    }

    fn new(trace: &Trace, opts: &ViewOptions) -> Frame {
        let root = &trace.root;
        let o = v3(root.origin);
        let d = v3(root.direction).try_normalize().unwrap_or(Vec3::Z);
        let cam = CameraRays::new(&trace.camera);
        let hit_point = surface(root).map(|(p, _)| p);
        if opts.top_down {
            // Looking down −y; the camera's forward points up the page.
            let f = -cam.w;
            let mut fh = Vec3::new(f.x, 0.0, f.z);
            if fh.length() < 0.05 {
                fh = Vec3::new(cam.v.x, 0.0, cam.v.z);
            }
            let y = fh.try_normalize().unwrap_or(Vec3::Z);
            let x = y.cross(Vec3::Y);
            let h = hit_point.map_or(o.y, |p| p.y);
            return Frame {
                o,
                x,
                y,
                m: Vec3::Y,
                cut_o: Vec3::new(o.x, h, o.z),
                d,
                top_down: true,
            };
        }
        // The plane of incidence where the hit spawns reflection or refraction; otherwise the
        // vertical plane through the ray (a side view: floors level, up is up).
        let normal = surface(root).map(|(_, n)| n).filter(|_| bends(root));
        let candidates = normal.into_iter().chain([Vec3::Y, cam.v, Vec3::X, Vec3::Z]);
        let e = candidates
            .filter_map(|c| {
                let p = c - d * c.dot(d);
                (p.length() > 0.05 * c.length()).then(|| p.normalize())
            })
            .next()
            .unwrap_or(Vec3::Y);
        let mut m = d.cross(e).normalize();
        // Page up: the world's up as seen in the plane (so floors are level in a vertical cut).
        let mut y = Vec3::Y - m * Vec3::Y.dot(m);
        if y.length() < 0.05 {
            y = e;
        }
        y = y.normalize();
        let mut x = y.cross(m);
        if x.dot(d) < 0.0 {
            // Look at the plane from its other side, so the ray goes to the right.
            m = -m;
            x = -x;
        }
        let q = Quat::from_axis_angle(d, opts.slice_angle.to_radians());
        Frame {
            o,
            x: q * x,
            y: q * y,
            m: q * m,
            cut_o: o,
            d,
            top_down: false,
        }
    }
}

fn v3(a: [f32; 3]) -> Vec3 {
    Vec3::from_array(a)
}

/// Whether a ray's hit spawns a reflection or refraction (its angles are worth true size).
fn bends(r: &RayRecord) -> bool {
    r.steps
        .iter()
        .any(|s| matches!(s.step, Step::Reflect { .. } | Step::Refract { .. }))
}

/// The Surface step of a ray: hit point and normal.
fn surface(r: &RayRecord) -> Option<(Vec3, Vec3)> {
    r.steps.iter().find_map(|s| match &s.step {
        Step::Surface { point, normal, .. } => Some((v3(*point), v3(*normal))),
        _ => None,
    })
}

// ---------------------------------------------------------------------------------------------
// Rays and the timeline: which ray owns which step, when each ray appears.

/// One ray with its place in the timeline.
struct RayInfo<'t> {
    ray: &'t RayRecord,
    parent: Option<usize>,
    /// Timeline index of each of the ray's steps.
    idx: Vec<usize>,
    /// The timeline index from which the ray is drawn: the parent's ShadowRay / Reflect /
    /// Refract step that announced it, else its Spawn step (0 for the primary ray).
    appear: usize,
    /// The parent's Spawn step (0 for the primary ray).
    spawn: usize,
    /// Shadow rays: the light they go to.
    light: Option<usize>,
}

struct RayInfos<'t> {
    rays: Vec<RayInfo<'t>>,
    /// The focus (None: everything).
    focus: Option<usize>,
    /// The ray drawn strongly at the focus.
    current: Option<usize>,
    /// Total timeline length.
    len: usize,
    /// Rays never drawn as minor (see [`RayInfos::minor`]).
    keep: Vec<usize>,
    /// The shallowest ray with a total internal reflection.
    first_tir: Option<usize>,
}

impl<'t> RayInfos<'t> {
    fn new(trace: &'t Trace, focus: Option<usize>) -> RayInfos<'t> {
        fn walk<'t>(
            ray: &'t RayRecord,
            parent: Option<usize>,
            (appear, spawn): (usize, usize),
            light: Option<usize>,
            n: &mut usize,
            out: &mut Vec<RayInfo<'t>>,
        ) {
            let me = out.len();
            out.push(RayInfo {
                ray,
                parent,
                idx: vec![],
                appear,
                spawn,
                light,
            });
            let mut pending: Option<(usize, Option<usize>)> = None;
            for s in &ray.steps {
                let k = *n;
                *n += 1;
                out[me].idx.push(k);
                match &s.step {
                    Step::ShadowRay { light, .. } => pending = Some((k, Some(*light as usize))),
                    Step::Reflect { .. } | Step::Refract { .. } => pending = Some((k, None)),
                    Step::Spawn { child } => {
                        let (appear, light) = pending.take().unwrap_or((k, None));
                        if let Some(c) = ray.children.get(*child as usize) {
                            walk(c, Some(me), (appear, k), light, n, out);
                        }
                    }
                    _ => pending = None,
                }
            }
        }
        let mut rays = vec![];
        let mut n = 0;
        walk(&trace.root, None, (0, 0), None, &mut n, &mut rays);
        let len = n;
        let focus = focus.map(|k| k.min(len.saturating_sub(1)));
        let current = focus.map(|k| {
            // A ray announced at k is the news; otherwise the owner of k.
            rays.iter()
                .position(|r| r.parent.is_some() && (r.appear == k || r.spawn == k))
                .or_else(|| rays.iter().position(|r| r.idx.contains(&k)))
                .unwrap_or(0)
        });
        // The rays kept prominent however deep: the current ray (else the first total internal
        // reflection, the event worth seeing), its ancestors and its children.
        let tir = |r: &RayInfo| {
            r.ray.steps.iter().any(|s| {
                matches!(
                    s.step,
                    Step::Refract {
                        total_internal_reflection: true,
                        ..
                    }
                )
            })
        };
        let first_tir = rays
            .iter()
            .enumerate()
            .filter(|(_, r)| tir(r))
            .min_by_key(|(_, r)| r.ray.depth)
            .map(|(k, _)| k);
        let star = current.or(first_tir);
        let mut keep = vec![];
        if let Some(s) = star {
            let mut c = Some(s);
            while let Some(k) = c {
                keep.push(k);
                c = rays[k].parent;
            }
            keep.extend(
                rays.iter()
                    .enumerate()
                    .filter(|(_, r)| r.parent == Some(s))
                    .map(|(k, _)| k),
            );
        }
        RayInfos {
            rays,
            focus,
            current,
            len,
            keep,
            first_tir,
        }
    }

    /// The last timeline index shown.
    fn upto(&self) -> usize {
        self.focus.unwrap_or(usize::MAX)
    }

    fn visible(&self, i: usize) -> bool {
        self.rays[i].appear <= self.upto()
    }

    /// Whether step `j` of ray `i` has happened at the focus.
    fn shown(&self, i: usize, j: usize) -> bool {
        self.rays[i].idx[j] <= self.upto()
    }

    fn faded(&self, i: usize) -> bool {
        self.current.is_some_and(|c| c != i)
    }

    /// Deep rays (depth ≥ 2) that are not the current ray or its ancestors: drawn thin and
    /// light, without labels or normals, so that a deep tree does not bury the first bounces.
    fn minor(&self, i: usize) -> bool {
        self.rays[i].ray.depth >= 2 && !self.keep.contains(&i)
    }

    /// The step at the focus, with its ray.
    fn focused_step(&self) -> Option<(usize, &'t Step)> {
        let k = self.focus?;
        self.rays.iter().enumerate().find_map(|(i, r)| {
            r.idx
                .iter()
                .position(|&x| x == k)
                .map(|j| (i, &r.ray.steps[j].step))
        })
    }

    /// Step `j`'s timeline position within ray `i`, for a step matching `f`.
    fn find(&self, i: usize, f: impl Fn(&Step) -> bool) -> Option<(usize, &'t Step)> {
        let r = &self.rays[i];
        r.ray
            .steps
            .iter()
            .enumerate()
            .find(|(_, s)| f(&s.step))
            .map(|(j, s)| (j, &s.step))
    }

    /// The ray whose BVH visits are drawn: the current one, else the primary ray.
    fn box_ray(&self) -> usize {
        self.current.unwrap_or(0)
    }
}

/// The ray's closest t at the focus (∞ while searching or on a miss); for shadow rays the end
/// of their interval (the light) unless something blocks them.
fn end_t(info: &RayInfos, i: usize) -> f32 {
    let r = &info.rays[i];
    let mut t = if r.ray.kind == RayKind::Shadow {
        r.ray.t_max.unwrap_or(1.0).min(1.0)
    } else {
        f32::INFINITY
    };
    for (j, s) in r.ray.steps.iter().enumerate() {
        if !info.shown(i, j) {
            break;
        }
        if let Step::Accept { t: a, .. } = s.step {
            t = a;
        }
    }
    if r.ray.kind == RayKind::Shadow && r.ray.hit.is_none() {
        // Unblocked: the ray reaches its light (t = 1 with the unnormalized direction).
        return 1.0;
    }
    t
}

// ---------------------------------------------------------------------------------------------
// Bounds and the fit.

#[derive(Debug, Clone, Copy)]
struct Bounds {
    min: [f32; 2],
    max: [f32; 2],
}

impl Bounds {
    const EMPTY: Bounds = Bounds {
        min: [f32::INFINITY; 2],
        max: [f32::NEG_INFINITY; 2],
    };

    fn add(&mut self, p: [f32; 2]) {
        if p[0].is_finite() && p[1].is_finite() {
            for (k, v) in p.into_iter().enumerate() {
                self.min[k] = self.min[k].min(v);
                self.max[k] = self.max[k].max(v);
            }
        }
    }

    fn is_empty(&self) -> bool {
        self.min[0] > self.max[0] || self.min[0].is_nan()
    }

    fn size(&self) -> [f32; 2] {
        [self.max[0] - self.min[0], self.max[1] - self.min[1]]
    }

    fn grown(&self, f: f32) -> Bounds {
        let s = self.size();
        let g = f * s[0].max(s[1]);
        Bounds {
            min: [self.min[0] - g, self.min[1] - g],
            max: [self.max[0] + g, self.max[1] + g],
        }
    }

    fn overlaps(&self, o: &Bounds) -> bool {
        !(o.is_empty() || self.is_empty())
            && o.min[0] <= self.max[0]
            && o.max[0] >= self.min[0]
            && o.min[1] <= self.max[1]
            && o.max[1] >= self.min[1]
    }

    fn contains(&self, p: [f32; 2]) -> bool {
        p[0] >= self.min[0] && p[0] <= self.max[0] && p[1] >= self.min[1] && p[1] <= self.max[1]
    }
}

impl Frame {
    /// Adds `p` (± `r` around it, a sphere's or box's extent) as seen in this frame; a sphere
    /// the plane cuts adds only its cut circle.
    fn fit(&self, b: &mut Bounds, p: Vec3, r: f32) {
        let dd = self.dist(p);
        let r = if !self.top_down && dd.abs() < r {
            (r * r - dd * dd).sqrt()
        } else {
            r
        };
        let q = self.to2(p);
        b.add([q[0] - r, q[1] - r]);
        b.add([q[0] + r, q[1] + r]);
    }
}

/// Whether a shape is a horizontal plane (seen from above it covers everything).
fn horizontal(shape: &Shape) -> bool {
    match shape {
        Shape::AxisPlane { axis, .. } => *axis == 1,
        Shape::Plane { normal, .. } => normal.y.abs() > 0.999,
        _ => false,
    }
}

/// The bounding sphere of a bounded shape.
fn bounding_sphere(shape: &Shape) -> Option<(Vec3, f32)> {
    match shape {
        Shape::Sphere { center, radius } => Some((*center, *radius)),
        Shape::Triangle { p } => {
            let c = (p[0] + p[1] + p[2]) / 3.0;
            Some((c, p.iter().map(|v| (*v - c).length()).fold(0.0, f32::max)))
        }
        _ => None,
    }
}

fn compute_layout(
    c: &Canvas,
    trace: &Trace,
    opts: &ViewOptions,
    info: &RayInfos,
    legend_rows: f32,
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
    let bottom = legend_rows + ts * 0.5;
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
fn image_plane_ends(frame: &Frame, cam: &CameraRays, sy: f32) -> [Vec3; 2] {
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

/// Above this many objects in a trace, the slice draws only the objects its plane cuts (and the
/// ones hit) and labels only the ones hit.
const CROWDED: usize = 300;

fn object(trace: &Trace, id: u32) -> Option<&TraceObject> {
    trace.objects.iter().find(|o| o.id == id)
}

/// The BVH node visits of ray `i` shown at the focus (all of them with `all`), with their step
/// positions in the ray.
fn node_visits<'t>(info: &RayInfos<'t>, i: usize, shown_only: bool) -> Vec<(usize, &'t NodeVisit)> {
    let r = &info.rays[i];
    r.ray
        .steps
        .iter()
        .enumerate()
        .filter(|(j, _)| !shown_only || info.shown(i, *j))
        .filter_map(|(j, s)| match &s.step {
            Step::Node(n) => Some((j, n)),
            _ => None,
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// 2D helpers.

fn sub(a: Px, b: Px) -> Px {
    [a[0] - b[0], a[1] - b[1]]
}

fn add(a: Px, b: Px) -> Px {
    [a[0] + b[0], a[1] + b[1]]
}

fn mul(a: Px, k: f32) -> Px {
    [a[0] * k, a[1] * k]
}

fn len(a: Px) -> f32 {
    (a[0] * a[0] + a[1] * a[1]).sqrt()
}

fn unit(a: Px) -> Option<Px> {
    let l = len(a);
    (l > 1e-6 && l.is_finite()).then(|| [a[0] / l, a[1] / l])
}

fn perp(a: Px) -> Px {
    [-a[1], a[0]]
}

fn in_rect(r: [f32; 4], p: Px) -> bool {
    p[0] >= r[0] && p[0] <= r[0] + r[2] && p[1] >= r[1] && p[1] <= r[1] + r[3]
}

fn inset_rect(r: [f32; 4], k: f32) -> [f32; 4] {
    [
        r[0] + k,
        r[1] + k,
        (r[2] - 2.0 * k).max(1.0),
        (r[3] - 2.0 * k).max(1.0),
    ]
}

/// The part of segment a→b inside `r` = [x, y, width, height]: the canvas's one line clipper.
fn clip_to_rect(r: [f32; 4], a: Px, b: Px) -> Option<(Px, Px)> {
    let f = |v: f32| f64::from(v);
    let rect = [f(r[0]), f(r[1]), f(r[0] + r[2]), f(r[1] + r[3])];
    let (p, q) = super::canvas::clip_segment(rect, [f(a[0]), f(a[1])], [f(b[0]), f(b[1])])?;
    Some(([p[0] as f32, p[1] as f32], [q[0] as f32, q[1] as f32]))
}

/// Where the half-line from `from` along `dir` leaves the plot.
fn border_point(lay: &SliceLayout, from: Px, dir: Px) -> Option<Px> {
    let u = unit(dir)?;
    let far = add(from, mul(u, 4.0 * (lay.plot[2] + lay.plot[3])));
    clip_to_rect(lay.plot, from, far).map(|(_, b)| b)
}

/// The convex hull of points (gift wrapping is plenty for ≤ 12 points).
fn convex_hull(mut pts: Vec<Px>) -> Vec<Px> {
    pts.retain(|p| p[0].is_finite() && p[1].is_finite());
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    pts.dedup_by(|a, b| len(sub(*a, *b)) < 1e-3);
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: Px, a: Px, b: Px| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut lower: Vec<Px> = vec![];
    for &p in &pts {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0.0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<Px> = vec![];
    for &p in pts.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0.0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

// ---------------------------------------------------------------------------------------------
// Colours.

fn mix(a: Rgba, b: Rgba, t: f32) -> Rgba {
    let m = |x: u8, y: u8| (x as f32 + (y as f32 - x as f32) * t).round() as u8;
    [m(a[0], b[0]), m(a[1], b[1]), m(a[2], b[2]), m(a[3], b[3])]
}

fn luminance(c: Rgba) -> f32 {
    (0.2126 * c[0] as f32 + 0.7152 * c[1] as f32 + 0.0722 * c[2] as f32) / 255.0
}

fn dark_theme(c: &Canvas) -> bool {
    luminance(c.theme.background) < 0.5
}

/// A material's linear colour, sRGB-encoded and pushed away from the background so that a
/// white floor still shows on white paper (and a black ball on black).
fn material_color(c: &Canvas, lin: [f32; 3]) -> Rgba {
    let enc = |x: f32| {
        let x = x.clamp(0.0, 1.0);
        let s = if x <= 0.003_130_8 {
            12.92 * x
        } else {
            1.055 * x.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0).round() as u8
    };
    let rgb: Rgba = [enc(lin[0]), enc(lin[1]), enc(lin[2]), 255];
    let l = luminance(rgb);
    if dark_theme(c) {
        if l < 0.45 {
            mix(rgb, [255, 255, 255, 255], (0.45 - l) / (1.0 - l).max(0.01))
        } else {
            rgb
        }
    } else if l > 0.55 {
        let k = 0.55 / l;
        [
            (rgb[0] as f32 * k) as u8,
            (rgb[1] as f32 * k) as u8,
            (rgb[2] as f32 * k) as u8,
            255,
        ]
    } else {
        rgb
    }
}

/// BVH boxes: violet, apart from every ray colour.
fn box_color(c: &Canvas) -> Rgba {
    if dark_theme(c) {
        [200, 150, 255, 255]
    } else {
        [130, 60, 190, 255]
    }
}

// ---------------------------------------------------------------------------------------------
// Legend and header.

#[derive(Debug, Clone, Copy)]
enum Sample {
    Line(Rgba, bool),
    Arrow(Rgba),
    Dot(Rgba),
    Light,
    /// A box outline: the BVH colour (None) or a given one, dashed or not.
    Box(Option<Rgba>, bool),
}

fn legend_entries(trace: &Trace, info: &RayInfos, opts: &ViewOptions) -> Vec<(Sample, String)> {
    let t = &opts.theme;
    let rays = &info.rays;
    let any = |f: &dyn Fn(&RayRecord) -> bool| rays.iter().any(|r| f(r.ray));
    let mut e = vec![(Sample::Line(t.ray, false), "primary ray".to_string())];
    if any(&|r| r.kind == RayKind::Shadow && r.hit.is_none()) {
        e.push((Sample::Line(t.shadow, false), "shadow ray".into()));
    }
    if any(&|r| r.kind == RayKind::Shadow && r.hit.is_some()) {
        e.push((Sample::Line(t.blocked, true), "blocked".into()));
    }
    if any(&|r| r.kind == RayKind::Reflection) {
        e.push((Sample::Line(t.reflect, false), "reflection".into()));
    }
    if any(&|r| r.kind == RayKind::Refraction) {
        e.push((Sample::Line(t.refract, false), "refraction".into()));
    }
    if any(&|r| r.kind != RayKind::Shadow && r.hit.is_some()) {
        e.push((Sample::Dot(t.hit), "hit".into()));
        e.push((Sample::Arrow(t.normal), "normal".into()));
    }
    if !trace.lights.is_empty() {
        e.push((Sample::Light, "light".into()));
    }
    let nodes = node_visits(info, info.box_ray(), false);
    if nodes.iter().any(|(_, n)| n.action != NodeAction::Culled) {
        e.push((Sample::Box(None, false), "BVH box (visit order)".into()));
    }
    if nodes.iter().any(|(_, n)| n.action == NodeAction::Culled) {
        e.push((Sample::Box(Some(t.faded), true), "culled".into()));
    }
    if opts.focus.is_some() {
        e.push((
            Sample::Line(mix(t.ray, t.faded, 0.72), false),
            "earlier".into(),
        ));
    }
    e
}

fn legend_size(c: &Canvas) -> f32 {
    c.text_size * 0.85
}

/// Lays the legend out in rows; returns the rows' total height and the row count.
fn legend_flow(c: &Canvas, entries: &[(Sample, String)]) -> (f32, f32) {
    let size = legend_size(c);
    let rows = legend_rows(c, entries).len() as f32;
    (rows * size * 1.5 + size * 0.4, rows)
}

fn legend_rows(c: &Canvas, entries: &[(Sample, String)]) -> Vec<Vec<usize>> {
    let size = legend_size(c);
    let avail = c.width() - size * 2.0;
    let mut rows: Vec<Vec<usize>> = vec![vec![]];
    let mut x = 0.0;
    for (i, (_, text)) in entries.iter().enumerate() {
        let w = legend_item_width(c, text);
        if x + w > avail && !rows.last().is_some_and(|r| r.is_empty()) {
            rows.push(vec![]);
            x = 0.0;
        }
        rows.last_mut().expect("a row").push(i);
        x += w;
    }
    rows
}

fn legend_item_width(c: &Canvas, text: &str) -> f32 {
    let size = legend_size(c);
    size * 2.2 + size * 0.4 + c.text_width(text, size) + size * 1.2
}

fn header_height(c: &Canvas) -> f32 {
    let ts = c.text_size;
    ts * 0.6 + ts * 1.15 * 1.5 + ts * 0.85 * 1.4
}

// ---------------------------------------------------------------------------------------------
// Drawing.

/// A label waiting to be placed: drawn last, in order, dodging the ones before it.
struct Label {
    at: Px,
    text: String,
    color: Rgba,
    size: f32,
    /// Preferred directions from `at`, in order (unit-ish vectors, page coordinates).
    prefs: Vec<Px>,
    gap: f32,
}

struct Drawer<'a, 't> {
    c: &'a mut Canvas,
    lay: &'a SliceLayout,
    trace: &'t Trace,
    info: &'a RayInfos<'t>,
    labels: Vec<Label>,
    /// Strokes labels should not cover (normals, angle marks, the TIR arrow).
    strokes: Vec<(Px, Px)>,
    /// Line-width unit (1 at the smallest text size).
    u: f32,
}

const NE: Px = [0.8, -0.8];
const NW: Px = [-0.8, -0.8];
const SE: Px = [0.8, 0.8];
const SW: Px = [-0.8, 0.8];
const N: Px = [0.0, -1.0];
const S: Px = [0.0, 1.0];
const E: Px = [1.0, 0.0];
const W: Px = [-1.0, 0.0];

impl Drawer<'_, '_> {
    fn label(&mut self, at: Px, text: impl Into<String>, color: Rgba, prefs: &[Px]) {
        let size = self.c.text_size * 0.85;
        self.labels.push(Label {
            at,
            text: text.into(),
            color,
            size,
            prefs: prefs.to_vec(),
            gap: 5.0 * self.u,
        });
    }

    fn faded(&self, c: Rgba) -> Rgba {
        mix(c, self.c.theme.faded, 0.72)
    }

    /// A ray's colour and width at the focus.
    fn ray_style(&self, i: usize) -> (Rgba, f32) {
        let r = self.info.rays[i].ray;
        let t = self.c.theme;
        let col = match r.kind {
            RayKind::Primary => t.ray,
            RayKind::Shadow if r.hit.is_some() => t.blocked,
            RayKind::Shadow => t.shadow,
            RayKind::Reflection => t.reflect,
            RayKind::Refraction => t.refract,
        };
        let depth_k = if self.info.current == Some(i) {
            1.0
        } else {
            (1.0 - 0.12 * r.depth as f32).max(0.5)
        };
        let base = if r.kind == RayKind::Shadow { 1.4 } else { 2.0 } * self.u * depth_k;
        if self.info.minor(i) {
            let c = if self.info.faded(i) {
                self.faded(col)
            } else {
                col
            };
            (with_alpha(c, 120), base * 0.6)
        } else if self.info.faded(i) {
            (self.faded(col), base * 0.8)
        } else if self.info.current == Some(i) {
            (col, base * 1.35)
        } else {
            (col, base)
        }
    }

    fn scene(&mut self) {
        self.boxes();
        self.objects();
        self.camera();
        let order: Vec<usize> = {
            let mut v: Vec<usize> = (0..self.info.rays.len())
                .filter(|&i| self.info.visible(i))
                .collect();
            // Faded first, the current ray last (on top); shadow rays under the others.
            v.sort_by_key(|&i| {
                (
                    !self.info.faded(i),
                    self.info.current == Some(i),
                    self.info.rays[i].ray.kind != RayKind::Shadow,
                )
            });
            v
        };
        for &i in &order {
            self.ray(i);
        }
        for &i in &order {
            self.hit(i);
        }
        self.angles();
        self.focus_marks();
        self.lights();
    }

    fn boxes(&mut self) {
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
            self.label(corner, text, tcol, &[SE, E, S, NE]);
        }
    }

    fn objects(&mut self) {
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
                self.label(at, label_name, tc, &prefs);
            }
        }
    }

    /// Draws a plane's cut (a line across the plot, hatched on its back). None when the plane
    /// does not cut the view plane in a line (parallel to it).
    fn plane(&mut self, n: Vec3, offset: f32, col: Rgba, width: f32) -> Option<()> {
        let (a, b) = self.plane_line(n, offset)?;
        let u = self.u;
        self.c.line(a, b, col, width);
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
    fn plane_line(&self, n: Vec3, offset: f32) -> Option<(Px, Px)> {
        let f = &self.lay.frame;
        // Points X of the cutting plane with X·n = offset: q·(x·n, y·n) = offset − cut point·n,
        // in the cutting plane's own 2D coordinates (through cut_o).
        let base = f.cut_o;
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
        let span = 4.0 * (self.lay.plot[2] + self.lay.plot[3]) / self.lay.scale;
        let a = self.lay.px(p0 + (f.x * dir[0] + f.y * dir[1]) * span);
        let b = self.lay.px(p0 - (f.x * dir[0] + f.y * dir[1]) * span);
        let (a, b) = clip_to_rect(self.lay.plot, a, b)?;
        let (a, b) = if a[0] <= b[0] { (a, b) } else { (b, a) };
        (len(sub(b, a)) > 1.0).then_some((a, b))
    }

    /// Where a plane's name goes: near the right end of a level line (the eye is on the left),
    /// beside the upper part of a steep one.
    fn plane_label_point(&self, n: Vec3, offset: f32) -> Option<(Px, Vec<Px>)> {
        let (a, b) = self.plane_line(n, offset)?;
        let d = sub(b, a);
        if d[1].abs() > d[0].abs() {
            let (top, bottom) = if a[1] < b[1] { (a, b) } else { (b, a) };
            Some((add(top, mul(sub(bottom, top), 0.3)), vec![W, E, NW, SW]))
        } else {
            Some((add(a, mul(d, 0.9)), vec![NE, SE, NW, SW]))
        }
    }

    fn camera(&mut self) {
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
        self.label(lay.eye, "eye", t.muted, &[S, SW, N, W]);
        self.label(
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
        self.label(mid, "image plane", t.muted, &[W, NW, SW, E]);
    }

    fn ray(&mut self, i: usize) {
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
                    self.label(
                        rl.end,
                        format!("blocked by {name}"),
                        t.blocked,
                        &[NE, NW, SE, SW, N],
                    );
                }
            } else {
                self.c.arrow(a, b, col, width);
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
        } else {
            // A miss, or a ray still searching: on to the border.
            self.c.arrow(a, b, col, width);
            let done = self
                .info
                .find(i, |s| matches!(s, Step::Miss { .. }))
                .is_some_and(|(j, _)| self.info.shown(i, j));
            if done && !self.info.faded(i) && !self.info.minor(i) {
                self.label(b, "miss → background", col, &[SW, NW, W, S, N]);
            }
        }
    }

    fn hit(&mut self, i: usize) {
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
                self.label(
                    add(h, mul(n2, l)),
                    "n",
                    t.normal,
                    &[perp(n2), mul(perp(n2), -1.0), n2],
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
            self.label(
                h,
                format!("hit {} · t = {}", hr.name, fmt(hr.t)),
                t.ink,
                &[SW, SE, NW, NE, S, N],
            );
        }
    }

    /// Incidence, reflection and refraction angles; the critical angle; TIR.
    fn angles(&mut self) {
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

    fn angles_at(&mut self, i: usize) {
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
                self.label(h, "TIR", t.refract, &[n2, N, S]);
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
        self.label(
            add(h, mul(bisect(back2, n2), rad + 4.0 * u)),
            format!("θi = {}°", deg(theta_i)),
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
                self.label(
                    add(h, mul(bisect(inward, t2), rad + 4.0 * u)),
                    format!("θt = {}°", deg(theta_t)),
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
                self.label(tip, format!("θc = {}°", deg(*crit)), t.refract, &[cd, N, S]);
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
                        deg(theta_i),
                        critical_angle_deg.map_or("?".into(), deg)
                    ),
                    color: t.refract,
                    size,
                    prefs: vec![n2, N, S, E, W],
                    gap: 4.0 * u,
                });
            }
        }
    }

    fn arc(&mut self, c: Px, r: f32, from: Px, to: Px, col: Rgba, width: f32) {
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
    fn focus_marks(&mut self) {
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
                    marks.push((t0, format!("t0 = {}", fmt(t0))));
                    if t1 != t0 {
                        marks.push((t1, format!("t1 = {}", fmt(t1))));
                    }
                }
            }
            Step::Plane { test, .. } => {
                if let Some(tr) = test.t_raw {
                    marks.push((tr, format!("t = {}", fmt(tr))));
                }
            }
            Step::Triangle { test, .. } => {
                if let Some(ts) = test.t_star {
                    marks.push((ts, format!("t* = {}", fmt(ts))));
                }
            }
            Step::Node(v) => {
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
                self.label(
                    p,
                    format!("node {}: {what}", v.node),
                    box_color(self.c),
                    &[N, NW, NE, S],
                );
            }
            Step::Accept { t: ta, .. } => {
                let p = at(*ta);
                self.c.circle(p, 5.5 * u, None, Some(t.hit), 2.2 * u);
                self.label(
                    p,
                    format!("closest t = {}", fmt(*ta)),
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
            self.label(p, text, t.hit, &[N, S, NE, SE, NW, SW]);
        }
    }

    fn lights(&mut self) {
        let t = self.c.theme;
        let u = self.u;
        let lay = self.lay;
        let reference = lay.rays[0].hit.unwrap_or(lay.eye);
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
                // How far, from the primary hit (where the story is), else from the eye.
                let from = surface(&self.trace.root).map_or(v3(self.trace.root.origin), |(p, _)| p);
                let text = format!(
                    "{} ({} away)",
                    l.name,
                    fmt_short((self.trace.lights[li].position - from).length())
                );
                let inward = mul(dir, -1.0);
                self.label(
                    l.at,
                    text,
                    mix(t.light, t.ink, 0.45),
                    &[inward, perp(inward), mul(perp(inward), -1.0)],
                );
            } else {
                self.label(
                    l.at,
                    l.name.clone(),
                    mix(t.light, t.ink, 0.45),
                    &[NE, NW, SE, SW],
                );
            }
        }
    }

    /// Title, subtitle, legend, scale bar, axes; then the labels.
    fn chrome(&mut self, opts: &ViewOptions, legend: &[(Sample, String)], legend_h: f32) {
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
        let sub_size = self.c.text_size * 0.85;
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
                    fmt_short(opts.slice_angle)
                )
            } else {
                base.to_string()
            }
        };
        self.c.text(
            self.c.text_size * 0.8,
            y0 - self.c.text_size * 0.45,
            sub_size,
            &plane,
            t.muted,
            Anchor::TopLeft,
        );
        if let Some(k) = self.info.focus {
            let text = format!("step {k} of {}", self.info.len.saturating_sub(1));
            let ts = self.c.text_size;
            // On a narrow canvas the counter would be drawn over the title: leave it out (the
            // app's step bar and the GIF's frame order say which step it is).
            if ts * 0.8 + heading_w + ts + self.c.text_width(&text, ts) + ts * 0.8 <= w {
                self.c
                    .text(w - ts * 0.8, ts * 0.6, ts, &text, t.ink, Anchor::TopRight);
            }
        }
        self.legend(legend, legend_h);
    }

    fn legend(&mut self, entries: &[(Sample, String)], _legend_h: f32) {
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
                self.c.text(x, y, size, text, t.ink, Anchor::MiddleLeft);
                x += self.c.text_width(text, size) + size * 1.2 + size * 0.2;
            }
        }
    }

    fn scale_bar(&mut self) {
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
        let size = self.c.text_size * 0.8;
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
        self.c.text(
            x0 + l * 0.5,
            y0 - size * 0.8,
            size,
            &format!("{} {unit_word}", fmt_short(nice)),
            t.ink,
            Anchor::Center,
        );
    }

    /// The world axes, as they lie on the page (short ones are nearly perpendicular to it).
    fn axes(&mut self) {
        let t = self.c.theme;
        let u = self.u;
        let [px, py, pw, _] = self.lay.plot;
        let l = 20.0 * u;
        let o = [px + pw - l - 14.0 * u, py + l + 10.0 * u];
        for (name, v) in [("x", Vec3::X), ("y", Vec3::Y), ("z", Vec3::Z)] {
            let d = self.lay.dpx(v);
            if len(d) < 0.3 {
                continue;
            }
            let tip = add(o, mul(d, l));
            self.c.arrow(o, tip, t.muted, 1.2 * u);
            let lbl = add(tip, mul(unit(d).unwrap_or([1.0, 0.0]), 6.0 * u));
            let size = self.c.text_size * 0.75;
            self.c
                .text(lbl[0], lbl[1], size, name, t.muted, Anchor::Center);
        }
    }

    fn place_labels(&mut self) {
        let labels = std::mem::take(&mut self.labels);
        let plot = self.lay.plot;
        let u = self.u;
        let mut placed: Vec<[f32; 4]> = vec![];
        // Keep clear of the glyphs: eye, pixel, hits, lights.
        let mut glyphs: Vec<[f32; 4]> = vec![];
        let around = |p: Px, r: f32| [p[0] - r, p[1] - r, 2.0 * r, 2.0 * r];
        glyphs.push(around(self.lay.eye, 9.0 * u));
        glyphs.push(around(self.lay.pixel, 4.0 * u));
        // The axes glyph in the plot's top-right corner (see `axes`).
        let (ax, l) = ([plot[0] + plot[2] - 34.0 * u, plot[1] + 30.0 * u], 20.0 * u);
        glyphs.push(around(ax, l + 10.0 * u));
        for l in &self.lay.lights {
            glyphs.push(around(l.at, 9.0 * u));
        }
        // ... and of the rays drawn strongly.
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
            }
        }
        for l in labels {
            let w = self.c.text_width(&l.text, l.size) + 6.0;
            let h = l.size * 1.2 + 2.0;
            let mut best: Option<([f32; 4], f32)> = None;
            let mut cands: Vec<Px> = l.prefs.clone();
            cands.extend([NE, SE, NW, SW, N, S, E, W]);
            for (ring, extra) in [0.0, 1.0, 2.5].into_iter().enumerate() {
                for (k, dir) in cands.iter().enumerate() {
                    let dir = unit(*dir).unwrap_or([1.0, 0.0]);
                    let g = l.gap + extra * h;
                    // The box's side facing `at` touches the point at + g·dir.
                    let cx = l.at[0] + dir[0] * g + dir[0] * w * 0.5;
                    let cy = l.at[1] + dir[1] * g + dir[1] * h * 0.5;
                    let r = [cx - w * 0.5, cy - h * 0.5, w, h];
                    let inside = r[0] >= plot[0]
                        && r[1] >= plot[1]
                        && r[0] + r[2] <= plot[0] + plot[2]
                        && r[1] + r[3] <= plot[1] + plot[3];
                    if !inside {
                        continue;
                    }
                    let score = 10.0 * placed.iter().filter(|p| overlap(**p, r)).count() as f32
                        + 8.0 * glyphs.iter().filter(|p| overlap(**p, r)).count() as f32
                        + 2.0
                            * segments
                                .iter()
                                .filter(|(a, b)| clip_to_rect(r, *a, *b).is_some())
                                .count() as f32
                        + ring as f32 * 1.5
                        + k as f32 * 0.01;
                    if best.is_none_or(|(_, s)| score < s) {
                        best = Some((r, score));
                    }
                }
                if best.is_some_and(|(_, s)| s < 1.0) {
                    break;
                }
            }
            let Some((r, _)) = best else { continue };
            placed.push(r);
            self.c.label(
                r[0] + 3.0,
                r[1] + 1.0,
                l.size,
                &l.text,
                l.color,
                Anchor::TopLeft,
            );
        }
    }
}

fn overlap(a: [f32; 4], b: [f32; 4]) -> bool {
    a[0] < b[0] + b[2] && b[0] < a[0] + a[2] && a[1] < b[1] + b[3] && b[1] < a[1] + a[3]
}

fn dot(a: Px, b: Px) -> f32 {
    a[0] * b[0] + a[1] * b[1]
}

fn rot(a: Px, ang: f32) -> Px {
    let (s, c) = ang.sin_cos();
    [a[0] * c - a[1] * s, a[0] * s + a[1] * c]
}

fn bisect(a: Px, b: Px) -> Px {
    unit(add(a, b)).unwrap_or(perp(a))
}

/// A sun: a disc with eight rays.
fn sun(c: &mut Canvas, p: Px, r: f32, fill: Rgba, ink: Rgba, u: f32) {
    for k in 0..8 {
        let a = k as f32 * std::f32::consts::FRAC_PI_4;
        let d = [a.cos(), a.sin()];
        c.line(
            add(p, mul(d, r * 1.45)),
            add(p, mul(d, r * 2.2)),
            mix(fill, ink, 0.25),
            1.5 * u,
        );
    }
    c.circle(p, r, Some(fill), Some(mix(fill, ink, 0.45)), 1.0 * u);
}

/// A box's outline in the view: its cut by the plane (a convex polygon; true) or, when the
/// plane misses it or looking from above, its projection (false).
fn box_outline(lay: &SliceLayout, lo: Vec3, hi: Vec3) -> (Vec<Px>, bool) {
    let (pts, cut) = box_points(&lay.frame, lo, hi);
    (convex_hull(pts.iter().map(|p| lay.px(*p)).collect()), cut)
}

/// The points whose hull is a box's outline: where the cutting plane crosses its 12 edges (true),
/// or its 8 corners when the plane misses it or looking from above (false).
fn box_points(f: &Frame, lo: Vec3, hi: Vec3) -> (Vec<Vec3>, bool) {
    let corner = |k: usize| {
        Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    };
    if !f.top_down {
        let mut pts = vec![];
        for a in 0..8 {
            for bit in [1, 2, 4] {
                let b = a | bit;
                if b == a {
                    continue;
                }
                let (pa, pb) = (corner(a), corner(b));
                let (da, db) = (f.dist(pa), f.dist(pb));
                if da == 0.0 {
                    pts.push(pa);
                }
                if (da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0) {
                    pts.push(pa + (pb - pa) * (da / (da - db)));
                }
                if db == 0.0 {
                    pts.push(pb);
                }
            }
        }
        if pts.len() >= 2 {
            return (pts, true);
        }
    }
    ((0..8).map(corner).collect(), false)
}

/// Where the cutting plane crosses a triangle: a segment, if it does.
fn triangle_cut(f: &Frame, p: [Vec3; 3]) -> Option<[Vec3; 2]> {
    let d: Vec<f32> = p.iter().map(|v| f.dist(*v)).collect();
    let mut pts = vec![];
    for k in 0..3 {
        let (a, b) = (k, (k + 1) % 3);
        if d[a] == 0.0 {
            pts.push(p[a]);
        }
        if (d[a] < 0.0 && d[b] > 0.0) || (d[a] > 0.0 && d[b] < 0.0) {
            pts.push(p[a] + (p[b] - p[a]) * (d[a] / (d[a] - d[b])));
        }
    }
    (pts.len() >= 2).then(|| [pts[0], pts[pts.len() - 1]])
}

/// One line saying what a step did (the subtitle while stepping).
fn step_caption(ray: &RayRecord, step: &Step) -> String {
    let kind = match ray.kind {
        RayKind::Primary => "primary",
        RayKind::Shadow => "shadow",
        RayKind::Reflection => "reflection",
        RayKind::Refraction => "refraction",
    };
    let verdict =
        |t: Option<f32>| t.map_or("miss".to_string(), |t| format!("hit at t = {}", fmt(t)));
    match step {
        Step::Camera { .. } => "camera: the primary ray from the eye through the pixel".into(),
        Step::Node(n) => {
            let what = match n.action {
                NodeAction::Culled => "culled",
                NodeAction::Descend => "hit, descend",
                NodeAction::Pushed => "hit, pushed for later",
                NodeAction::TestPrimitives => "hit, test its primitives",
            };
            format!(
                "{kind} ray: BVH node {} (depth {}): {what}",
                n.node, n.depth
            )
        }
        Step::Sphere { name, test, .. } => {
            let roots = match test.roots {
                None => "no real roots".to_string(),
                Some([a, b]) if a == b => format!("touches at t = {}", fmt(a)),
                Some([a, b]) => format!("roots {} and {}", fmt(a), fmt(b)),
            };
            format!(
                "{kind} ray: sphere \"{name}\": {roots} → {}",
                verdict(test.t)
            )
        }
        Step::Plane { name, test, .. } => match test.t_raw {
            Some(t) => format!(
                "{kind} ray: plane \"{name}\": t = {} → {}",
                fmt(t),
                verdict(test.t)
            ),
            None => format!("{kind} ray: plane \"{name}\": parallel → miss"),
        },
        Step::Triangle { name, test, .. } => {
            format!("{kind} ray: triangle \"{name}\" → {}", verdict(test.t))
        }
        Step::Accept { name, t, .. } => {
            format!("{kind} ray: closest so far \"{name}\" at t = {}", fmt(*t))
        }
        Step::Miss { .. } => format!("{kind} ray: no hit → background"),
        Step::Surface { inside, .. } => {
            format!(
                "{kind} ray: hit point and normal{}",
                if *inside {
                    " (from inside: normal flipped)"
                } else {
                    ""
                }
            )
        }
        Step::ShadowRay { name, distance, .. } => {
            format!("shadow ray towards \"{name}\" ({} away)", fmt(*distance))
        }
        Step::Light {
            name,
            blocked,
            blocker,
            l_dot_n,
            ..
        } => {
            if *blocked {
                format!(
                    "light \"{name}\": blocked by \"{}\" → ambient only",
                    blocker.as_deref().unwrap_or("?")
                )
            } else if *l_dot_n <= 0.0 {
                format!("light \"{name}\": behind the surface → ambient only")
            } else {
                format!("light \"{name}\": visible, l·n = {}", fmt(*l_dot_n))
            }
        }
        Step::Reflect { reflective, .. } => {
            format!("reflect: r = d − 2(d·n)n, weight {}", fmt(*reflective))
        }
        Step::Refract {
            n1,
            n2,
            total_internal_reflection,
            sin2_t,
            ..
        } => {
            if *total_internal_reflection {
                format!(
                    "refract {} → {}: sin²θt = {} > 1: total internal reflection",
                    fmt(*n1),
                    fmt(*n2),
                    fmt(*sin2_t)
                )
            } else {
                format!(
                    "refract {} → {}: θt = {}°",
                    fmt(*n1),
                    fmt(*n2),
                    deg(sin2_t.clamp(0.0, 1.0).sqrt().asin().to_degrees())
                )
            }
        }
        Step::Schlick { reflectance } => format!("Schlick: reflectance R = {}", fmt(*reflectance)),
        Step::DepthLimit { max_depth } => format!("recursion limit {max_depth}: no secondary ray"),
        Step::WeightCutoff { .. } | Step::Truncated { .. } => {
            crate::trace::describe::describe(step)
        }
        Step::Spawn { .. } => format!("{kind} ray spawns a child ray"),
        Step::Color { .. } => format!("{kind} ray: colour summed"),
    }
}

/// A number as the slice prints it: four significant digits, no trailing zeros.
fn fmt(x: f32) -> String {
    if !x.is_finite() {
        return if x.is_nan() {
            "NaN".into()
        } else if x > 0.0 {
            "∞".into()
        } else {
            "−∞".into()
        };
    }
    let a = x.abs();
    let dec = if a >= 1000.0 {
        0
    } else if a >= 100.0 {
        1
    } else if a >= 10.0 {
        2
    } else {
        3
    };
    let s = format!("{x:.dec$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    s.replace('-', "−")
}

fn fmt_short(x: f32) -> String {
    let s = format!("{x:.1}");
    let s = s.trim_end_matches('0').trim_end_matches('.').to_string();
    if s.is_empty() {
        "0".into()
    } else {
        s.replace('-', "−")
    }
}

fn deg(x: f32) -> String {
    format!("{x:.1}")
}
