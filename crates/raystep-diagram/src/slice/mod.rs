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
//! **Fit.** The view frames what the step is about: the eye, the image plane and the primary
//! ray's hit with the object hit, and the current ray — its origin, its hit, the object it hits
//! and the objects it tests (unfocused: the first bounces). Anything farther from the eye-to-hit
//! box than three quarters of its size is left out of the fit: a ray that ends there leaves the
//! frame with an arrowhead at the edge and its t ("→ wall, t = 114.8"), objects there are drawn
//! clipped, far lights sit on the border with an arrow and their distance. A current ray that
//! starts that far away (or, once its hit point is found, ends that far away) is framed on its
//! own, around that point, at about the same scale. Rays deeper than the first bounces are drawn
//! thin and light unless they lead to the focused step (or, unfocused, to the shallowest total
//! internal reflection), so deep trees do not bury the first bounces. The fit is made in the
//! unturned plane, so turning the plane never moves the ray; stepping keeps the view while the
//! steps are about the same ray (and, when its hit is far, the same end of it).
//!
//! **Labels** are placed most important first (the step's own marks, then hits and angles, the
//! camera and lights, object names, box numbers), each where it overlaps no label before it and
//! no plane's line; one that finds no such place is left out. Every text is drawn in a colour
//! with a contrast ratio of at least 4.5:1 against the background (WCAG AA).

use super::canvas::{Rgba, with_alpha};
use super::{Anchor, Canvas, ViewOptions, title};
use crate::record::TraceObject;
use crate::record::number::{Style, fmt, label};
use crate::record::{NodeAction, NodeVisit, RayKind, RayRecord, Step, Trace};
use crate::scene::Shape;
use crate::scene::camera::CameraRays;
use glam::{Quat, Vec3};

mod captions;
mod chrome;
mod draw_objects;
mod draw_rays;
mod geom2d;
mod layout;
mod style;
use self::{captions::*, geom2d::*, layout::*, style::*};

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
    /// The planes: where each crosses the plot (planes parallel to the view are left out).
    pub planes: Vec<PlaneLayout>,
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
    /// Where the ray leaves the plot when the point it ends at (its hit, its light, its
    /// blocker) lies outside it: the ray is drawn to this point on the border, with an
    /// arrowhead and, for a prominent ray, its t. None when it ends inside the plot, runs on to
    /// the border (a miss, a ray still searching) or never crosses the plot.
    pub exit: Option<Px>,
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

/// A plane on the page: its cut by the view plane, across the plot.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneLayout {
    /// The object's name.
    pub name: String,
    /// The line's ends on the plot's border, the left one first.
    pub line: [Px; 2],
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

/// A text the slice drew: a label placed beside what it names, or a line of the chrome (the
/// caption, the legend, the scale bar, the axes).
#[derive(Debug, Clone, PartialEq)]
pub struct SliceText {
    /// The text.
    pub text: String,
    /// Its box (for a label, the backing box drawn under it): x, y, width, height.
    pub rect: [f32; 4],
    /// Its colour.
    pub color: Rgba,
    /// Its size in pixels.
    pub size: f32,
    /// True for a label in the plot, placed so that it overlaps no other label and no plane's
    /// line; false for the chrome's text.
    pub label: bool,
}

/// Computes where everything goes, without drawing.
pub fn layout(trace: &Trace, opts: &ViewOptions) -> SliceLayout {
    let world = world_only(trace);
    let trace = world.as_ref().unwrap_or(trace);
    let c = Canvas::for_view(opts);
    let info = RayInfos::new(trace, opts.focus);
    let legend = fitting_legend(&c, trace, &info, opts);
    let (legend_height, _) = legend_flow(&c, &legend);
    compute_layout(&c, trace, opts, &info, legend_height)
}

/// Draws the slice.
pub fn draw(trace: &Trace, opts: &ViewOptions) -> Canvas {
    draw_annotated(trace, opts).0
}

/// Draws the slice, and says which texts it drew where (for tests and for the app). Labels that
/// found no free place are left out, so the list holds only what can be read.
pub fn draw_annotated(trace: &Trace, opts: &ViewOptions) -> (Canvas, Vec<SliceText>) {
    let world = world_only(trace);
    let trace = world.as_ref().unwrap_or(trace);
    let mut c = Canvas::for_view(opts);
    let info = RayInfos::new(trace, opts.focus);
    let legend = fitting_legend(&c, trace, &info, opts);
    let (legend_height, _) = legend_flow(&c, &legend);
    let lay = compute_layout(&c, trace, opts, &info, legend_height);
    let mut d = Drawer::new(&mut c, &lay, trace, &info);
    d.scene();
    d.chrome(opts, &legend);
    let texts = std::mem::take(&mut d.texts);
    (c, texts)
}

/// The trace without its prototypes' objects, when it has any: they lie in their object space,
/// and the slice is a cut through the world (the rays, which are drawn, reach the instances).
fn world_only(trace: &Trace) -> Option<Trace> {
    trace.objects.iter().any(|o| o.prototype).then(|| Trace {
        objects: trace
            .objects
            .iter()
            .filter(|o| !o.prototype)
            .cloned()
            .collect(),
        ..trace.clone()
    })
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
            // World-space boxes: the world tree's and the TLAS's (a BLAS's are in its
            // prototype's object space).
            Step::Node(n) if n.instance.is_none() => Some((j, n)),
            Step::TlasNode(n) => Some((j, n)),
            _ => None,
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// 2D helpers.

/// A label waiting to be placed: drawn last, by priority (in order within one), each where it
/// overlaps no label placed before it.
struct Label {
    at: Px,
    text: String,
    color: Rgba,
    size: f32,
    /// Preferred directions from `at`, in order (unit-ish vectors, page coordinates).
    prefs: Vec<Px>,
    gap: f32,
    prio: Prio,
}

/// Which labels are placed first, and so get the best places (the last may find none).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Prio {
    /// What the focused step is about: its t marks, its node, TIR, the current ray's end.
    Focus,
    /// Hits, angles, normals, blocked and missed rays.
    Marks,
    /// The eye, the pixel, the image plane, the lights.
    Scene,
    /// Object names.
    Names,
    /// Box and cell numbers.
    Detail,
}

struct Drawer<'a, 't> {
    c: &'a mut Canvas,
    lay: &'a SliceLayout,
    trace: &'t Trace,
    info: &'a RayInfos<'t>,
    labels: Vec<Label>,
    /// Strokes labels should not cover (normals, angle marks, the TIR arrow).
    strokes: Vec<(Px, Px)>,
    /// Lines no label may cross: the planes' cuts (a floor, a wall).
    walls: Vec<(Px, Px)>,
    /// Boxes no label may cover: the scale bar, the axes.
    furniture: Vec<[f32; 4]>,
    /// The texts drawn, for [`draw_annotated`].
    texts: Vec<SliceText>,
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

impl<'a, 't> Drawer<'a, 't> {
    /// A drawer of `trace` on `c` by `lay`, nothing placed yet; line widths follow the text size.
    fn new(
        c: &'a mut Canvas,
        lay: &'a SliceLayout,
        trace: &'t Trace,
        info: &'a RayInfos<'t>,
    ) -> Self {
        let u = c.text_size / 11.0;
        Drawer {
            c,
            lay,
            trace,
            info,
            labels: vec![],
            strokes: vec![],
            walls: vec![],
            furniture: vec![],
            texts: vec![],
            u,
        }
    }
}

impl Drawer<'_, '_> {
    /// A box or cell number (placed last).
    fn label(&mut self, at: Px, text: impl Into<String>, color: Rgba, prefs: &[Px]) {
        self.label_p(Prio::Detail, at, text, color, prefs);
    }

    fn label_p(&mut self, prio: Prio, at: Px, text: impl Into<String>, color: Rgba, prefs: &[Px]) {
        let size = label_size(self.c);
        self.labels.push(Label {
            at,
            text: text.into(),
            color,
            size,
            prefs: prefs.to_vec(),
            gap: 5.0 * self.u,
            prio,
        });
    }

    /// Directions from a point on the plot's border into the plot: towards its centre first.
    fn inward(&self, x: Px) -> Vec<Px> {
        let [px, py, pw, ph] = self.lay.plot;
        let d = unit(sub([px + pw * 0.5, py + ph * 0.5], x)).unwrap_or(S);
        vec![d, rot(d, 0.6), rot(d, -0.6), perp(d), mul(perp(d), -1.0)]
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
            RayKind::Diffuse => t.diffuse,
            RayKind::Glossy => t.glossy,
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
        self.grid_cut();
        self.accel_visits();
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
