//! What the 3D view draws, as plain data: the scene's objects (triangles and sphere instances),
//! the lights, the camera with its image plane and pixel grid, and the rays of a recorded trace
//! up to a step. A pure function of the scene, the trace and the options — the GPU pass only
//! draws it, and the tests check it without a GPU.

use super::camera::Bounds;
use crate::diagram::Theme;
use crate::record::{RayKind, RayRecord, Step, Trace};
use crate::scene::camera::CameraRays;
use crate::scene::{Scene, Shape};
use glam::Vec3;

/// A vertex of a shaded triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriVertex {
    /// Position.
    pub pos: [f32; 3],
    /// Normal (the shader lights both sides).
    pub normal: [f32; 3],
    /// Display colour and opacity.
    pub color: [f32; 4],
}

/// A sphere drawn from one shared tessellated sphere: the unit sphere scaled by the radius,
/// carried by `axes` (the identity for a round sphere; an instance's linear part, so a sphere
/// under a non-uniform scale is drawn as the ellipsoid the tracer sees), then moved to the centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereInstance {
    /// Centre.
    pub center: [f32; 3],
    /// Radius.
    pub radius: f32,
    /// Display colour and opacity.
    pub color: [f32; 4],
    /// The columns of the linear map after the radius (M's, on an instance).
    pub axes: [[f32; 3]; 3],
}

impl SphereInstance {
    /// A round sphere.
    pub fn round(center: Vec3, radius: f32, color: [f32; 4]) -> SphereInstance {
        SphereInstance {
            center: center.to_array(),
            radius,
            color,
            axes: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
    }
}

/// A line segment drawn `width` pixels wide.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line3 {
    /// One end.
    pub a: [f32; 3],
    /// The other end.
    pub b: [f32; 3],
    /// Display colour and opacity.
    pub color: [f32; 4],
    /// Width on screen, in pixels.
    pub width: f32,
}

/// A ray of the trace as the view draws it.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawnRay {
    /// Its kind.
    pub kind: RayKind,
    /// Depth in the ray tree.
    pub depth: u32,
    /// Where it starts.
    pub origin: Vec3,
    /// Its unit direction.
    pub dir: Vec3,
    /// How far it is drawn.
    pub length: f32,
    /// Whether it ends at a hit (a hit point is drawn there), or at a light, or runs off.
    pub end: RayEnd,
    /// Whether it is the ray the current step belongs to.
    pub current: bool,
}

/// How a drawn ray ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RayEnd {
    /// At the closest hit found so far.
    Hit,
    /// A shadow ray at its light (not blocked).
    Light,
    /// A shadow ray at the object that blocks it.
    Blocked,
    /// No hit (yet): drawn to the edge of the scene.
    Open,
}

/// Everything the 3D view draws.
#[derive(Debug, Clone, Default)]
pub struct Geometry {
    /// Opaque triangles.
    pub tris: Vec<TriVertex>,
    /// Opaque spheres.
    pub spheres: Vec<SphereInstance>,
    /// Translucent triangles (drawn last, without writing depth).
    pub clear_tris: Vec<TriVertex>,
    /// Translucent spheres.
    pub clear_spheres: Vec<SphereInstance>,
    /// Lines.
    pub lines: Vec<Line3>,
    /// The rays drawn (also as lines), for the tests and the legend.
    pub rays: Vec<DrawnRay>,
    /// The hit points drawn, with the normal there.
    pub hits: Vec<(Vec3, Vec3)>,
    /// The sphere around the scene the view fits.
    pub bounds: Bounds,
    /// The box planes are cut to ([`scene_box`]).
    pub scene_box: (Vec3, Vec3),
}

/// What to draw besides the scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Draw the rays up to this timeline step (None: all of them).
    pub step: Option<usize>,
    /// Draw the BVH boxes the current ray visited so far.
    pub bvh: bool,
    /// Draw every object translucent, to see the rays inside.
    pub see_through: bool,
    /// The selected object group (drawn highlighted).
    pub selected: Option<u32>,
    /// The colours.
    pub theme: Theme,
    /// Where the eye is: a plane between it and the scene is drawn as an outline only.
    pub eye: Option<[f32; 3]>,
    /// Draw the scene's camera (eye, frustum, image plane); off when looking through it.
    pub camera: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            step: None,
            bvh: false,
            see_through: false,
            selected: None,
            theme: Theme::DARK,
            eye: None,
            camera: true,
        }
    }
}

/// The most triangles the view draws of meshes; above it, every k-th triangle is left out and the
/// view says so (a million-triangle terrain would take seconds a frame on a software rasterizer).
pub const MAX_DRAWN_TRIANGLES: usize = 400_000;

/// The most pixels per side the image plane's grid draws; a larger image gets a coarser grid
/// (one line every k pixels).
pub const MAX_GRID_LINES: u32 = 32;

fn rgba(c: [u8; 4]) -> [f32; 4] {
    c.map(|v| f32::from(v) / 255.0)
}

fn with_alpha(c: [f32; 4], a: f32) -> [f32; 4] {
    [c[0], c[1], c[2], a]
}

/// The box the view is built around: the finite objects, the lights and the camera (eye and
/// look-at point), stretched to take in each axis-aligned plane lying near it (so a Cornell
/// box's walls bound it). Planes are drawn cut to it.
pub fn scene_box(scene: &Scene) -> (Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    let mut add = |p: Vec3| {
        if p.is_finite() {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    };
    for (_, o) in scene.placed() {
        match o.shape {
            Shape::Sphere { center, radius } => {
                add(center - Vec3::splat(radius));
                add(center + Vec3::splat(radius));
            }
            Shape::Triangle { p } => p.iter().for_each(|&v| add(v)),
            Shape::Plane { .. } | Shape::AxisPlane { .. } => {}
        }
    }
    for l in &scene.lights {
        add(l.position);
    }
    add(scene.camera.from);
    add(scene.camera.at);
    if !(lo.is_finite() && hi.is_finite()) {
        return (scene.camera.from - Vec3::ONE, scene.camera.from + Vec3::ONE);
    }
    let reach = (hi - lo).max_element().max(1e-3);
    for o in &scene.objects {
        if let Some((axis, offset)) = axis_plane(&o.shape)
            && offset >= lo[axis] - reach
            && offset <= hi[axis] + reach
        {
            lo[axis] = lo[axis].min(offset);
            hi[axis] = hi[axis].max(offset);
        }
    }
    // Never flat: a scene of one flat triangle still gets some depth.
    let pad = Vec3::splat((hi - lo).max_element().max(1e-3) * 0.02);
    (lo - pad, hi + pad)
}

/// A plane perpendicular to a coordinate axis, as (axis, offset along it).
fn axis_plane(s: &Shape) -> Option<(usize, f32)> {
    match *s {
        Shape::AxisPlane { axis, offset } => Some((axis.min(2), offset)),
        Shape::Plane { normal, offset } => {
            let a = normal.abs();
            let axis = if a.x >= a.y && a.x >= a.z {
                0
            } else if a.y >= a.z {
                1
            } else {
                2
            };
            let n = normal[axis];
            (a[axis] > 1.0 - 1e-6 && n != 0.0).then(|| (axis, offset / n))
        }
        _ => None,
    }
}

/// The sphere around [`scene_box`].
pub fn bounds(scene: &Scene) -> Bounds {
    let (lo, hi) = scene_box(scene);
    Bounds {
        center: (lo + hi) * 0.5,
        radius: ((hi - lo).length() * 0.5).max(1e-3),
    }
}

/// The distance from the camera to its drawn image plane: a quarter of the way to the look-at
/// point, so the plane sits in front of the scene without hiding it.
pub fn image_plane_distance(scene: &Scene) -> f32 {
    ((scene.camera.at - scene.camera.from).length() * 0.25).max(1e-3)
}

/// The image plane's corners (top-left, top-right, bottom-right, bottom-left) as drawn: at
/// distance `d` along the view direction, spanning ±half_width·d along u and ±half_height·d
/// along v — the points the primary rays through the image's corners pass.
pub fn image_plane_corners(scene: &Scene, d: f32) -> [Vec3; 4] {
    let c = CameraRays::new(&scene.camera);
    let at = |sx: f32, sy: f32| {
        c.origin + (c.u * (sx * c.half_width) + c.v * (sy * c.half_height) - c.w) * d
    };
    [at(-1.0, 1.0), at(1.0, 1.0), at(1.0, -1.0), at(-1.0, -1.0)]
}

/// The point of pixel (x, y) at offset (ox, oy) inside it on the drawn image plane.
pub fn image_plane_point(scene: &Scene, d: f32, x: f32, y: f32) -> Vec3 {
    let c = CameraRays::new(&scene.camera);
    let sx = 2.0 * x / c.width as f32 - 1.0;
    let sy = 1.0 - 2.0 * y / c.height as f32;
    c.origin + (c.u * (sx * c.half_width) + c.v * (sy * c.half_height) - c.w) * d
}

/// Builds what the view draws: `trace` (the selected pixel's) up to `options.step`, and
/// `fan` (other pixels' traces, drawn whole and thin) — the camera's fan of rays.
pub fn build(scene: &Scene, trace: Option<&Trace>, fan: &[Trace], options: &Options) -> Geometry {
    let b = bounds(scene);
    let mut g = Geometry {
        bounds: b,
        scene_box: scene_box(scene),
        ..Default::default()
    };
    let theme = &options.theme;
    let testing = trace.and_then(|t| tested_object(t, options.step));
    objects(scene, options, testing, &mut g);
    lights(scene, &b, theme, &mut g);
    if options.camera {
        camera(scene, trace, &b, theme, &mut g);
    }
    for t in fan {
        rays(t, None, &b, theme, false, &mut g);
    }
    if let Some(t) = trace {
        rays(t, options.step, &b, theme, true, &mut g);
        if options.bvh {
            bvh_boxes(t, options.step, theme, &mut g);
        }
    }
    g
}

/// The object the step under `step` tests (highlighted while it is tested).
fn tested_object(t: &Trace, step: Option<usize>) -> Option<u32> {
    let k = step?;
    let timeline = t.timeline();
    let (_, s) = timeline.get(k)?;
    match &s.step {
        Step::Sphere { object, .. }
        | Step::Plane { object, .. }
        | Step::Triangle { object, .. } => Some(*object),
        Step::Accept { object, .. } => Some(*object),
        _ => None,
    }
}

fn objects(scene: &Scene, options: &Options, testing: Option<u32>, g: &mut Geometry) {
    let theme = &options.theme;
    let finite_tris = scene
        .placed()
        .filter(|(_, o)| matches!(o.shape, Shape::Triangle { .. }))
        .count();
    let keep_every = finite_tris.div_ceil(MAX_DRAWN_TRIANGLES).max(1);
    let mut tri_index = 0usize;
    for (id, placer, o) in scene.placed_by() {
        let m = scene.materials.get(o.material as usize);
        let base = m.map_or([0.8, 0.8, 0.8], |m| linear_to_display(m.color));
        let transparency = m.map_or(0.0, |m| m.transparency);
        let mut alpha = 1.0 - 0.65 * transparency.clamp(0.0, 1.0);
        if options.see_through {
            alpha = alpha.min(0.3);
        }
        let mut color = [base[0], base[1], base[2], alpha];
        if options.selected == Some(o.group) {
            color = mix(color, rgba(theme.hit), 0.45);
        }
        if testing == Some(id) {
            color = mix(color, rgba(theme.ray), 0.55);
            color[3] = color[3].max(0.6);
        }
        let clear = color[3] < 0.999;
        match o.shape {
            Shape::Sphere { center, radius } => {
                let mut s = SphereInstance::round(center, radius, color);
                // On an instance: the prototype's own radius, carried by M's linear part.
                if let (Some(inst), Some(Shape::Sphere { radius, .. })) =
                    (placer, scene.objects.get(id as usize).map(|p| p.shape))
                {
                    let m = &inst.to_world.0;
                    s.radius = radius;
                    s.axes = [0, 1, 2].map(|k| [m[0][k], m[1][k], m[2][k]]);
                }
                if clear {
                    g.clear_spheres.push(s)
                } else {
                    g.spheres.push(s)
                }
            }
            Shape::Triangle { p } => {
                tri_index += 1;
                if !(tri_index - 1).is_multiple_of(keep_every) && options.selected != Some(o.group)
                {
                    continue;
                }
                let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or(Vec3::Y);
                let out = if clear {
                    &mut g.clear_tris
                } else {
                    &mut g.tris
                };
                for v in p {
                    out.push(TriVertex {
                        pos: v.to_array(),
                        normal: n.to_array(),
                        color,
                    });
                }
            }
            Shape::Plane { normal, offset } => {
                plane(&o.shape, normal, offset, options, color, clear, g)
            }
            Shape::AxisPlane { axis, offset } => {
                let mut n = Vec3::ZERO;
                n[axis.min(2)] = 1.0;
                plane(&o.shape, n, offset, options, color, clear, g)
            }
        }
    }
}

/// An infinite plane n·X = offset, cut to the scene's box (a plane perpendicular to an axis: the
/// box's cross-section; any other: a square around the box's centre), with a faint grid. A plane
/// between the eye and the scene is drawn as its outline only, so it never hides the scene.
fn plane(
    shape: &Shape,
    n: Vec3,
    offset: f32,
    options: &Options,
    color: [f32; 4],
    clear: bool,
    g: &mut Geometry,
) {
    let theme = &options.theme;
    let (lo, hi) = g.scene_box;
    let n = n.normalize_or(Vec3::Y);
    let mid = (lo + hi) * 0.5;
    let (center, e1, e2) = match axis_plane(shape) {
        Some((axis, at)) => {
            let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
            let mut c = mid;
            c[axis] = at;
            let mut e1 = Vec3::ZERO;
            e1[a1] = (hi[a1] - lo[a1]) * 0.5;
            let mut e2 = Vec3::ZERO;
            e2[a2] = (hi[a2] - lo[a2]) * 0.5;
            (c, e1, e2)
        }
        None => {
            let c = mid - n * (n.dot(mid) - offset);
            let h = (hi - lo).length() * 0.5;
            let e1 = n.any_orthonormal_vector();
            (c, e1 * h, n.cross(e1) * h)
        }
    };
    if !(center.is_finite() && e1.is_finite() && e2.is_finite()) {
        return;
    }
    let corner = |s: f32, t: f32| center + e1 * s + e2 * t;
    let quad = [
        corner(-1.0, -1.0),
        corner(1.0, -1.0),
        corner(1.0, 1.0),
        corner(-1.0, 1.0),
    ];
    let side = |p: Vec3| n.dot(p) - offset;
    let hides = options
        .eye
        .map(Vec3::from)
        .is_some_and(|eye| side(eye) * side(mid) < 0.0);
    if hides {
        for i in 0..4 {
            g.lines.push(Line3 {
                a: quad[i].to_array(),
                b: quad[(i + 1) % 4].to_array(),
                color: with_alpha(color, 0.6),
                width: 1.5,
            });
        }
        return;
    }
    let out = if clear {
        &mut g.clear_tris
    } else {
        &mut g.tris
    };
    for i in [0, 1, 2, 0, 2, 3] {
        out.push(TriVertex {
            pos: quad[i].to_array(),
            normal: n.to_array(),
            color,
        });
    }
    let line = with_alpha(rgba(theme.muted), 0.35);
    let lift = n * ((hi - lo).length() * 5e-4) * side(mid).signum();
    for k in 0..=8 {
        let s = -1.0 + 2.0 * k as f32 / 8.0;
        g.lines.push(Line3 {
            a: (corner(s, -1.0) + lift).to_array(),
            b: (corner(s, 1.0) + lift).to_array(),
            color: line,
            width: 1.0,
        });
        g.lines.push(Line3 {
            a: (corner(-1.0, s) + lift).to_array(),
            b: (corner(1.0, s) + lift).to_array(),
            color: line,
            width: 1.0,
        });
    }
}

fn lights(scene: &Scene, b: &Bounds, theme: &Theme, g: &mut Geometry) {
    let c = rgba(theme.light);
    let r = b.radius * 0.025;
    for l in &scene.lights {
        let p = l.position;
        g.spheres.push(SphereInstance::round(p, r, c));
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            g.lines.push(Line3 {
                a: (p - axis * r * 2.5).to_array(),
                b: (p + axis * r * 2.5).to_array(),
                color: c,
                width: 2.0,
            });
        }
    }
}

/// The camera: its eye, the frustum to the image plane's corners, the image plane with its
/// pixel grid (coarser for large images) and the selected pixel filled.
fn camera(scene: &Scene, trace: Option<&Trace>, b: &Bounds, theme: &Theme, g: &mut Geometry) {
    let d = image_plane_distance(scene);
    let corners = image_plane_corners(scene, d);
    let eye = scene.camera.from;
    let ink = rgba(theme.ink);
    let muted = with_alpha(rgba(theme.muted), 0.8);
    g.spheres
        .push(SphereInstance::round(eye, b.radius * 0.015, ink));
    for (i, c) in corners.iter().enumerate() {
        g.lines.push(Line3 {
            a: eye.to_array(),
            b: c.to_array(),
            color: muted,
            width: 1.5,
        });
        g.lines.push(Line3 {
            a: c.to_array(),
            b: corners[(i + 1) % 4].to_array(),
            color: ink,
            width: 2.0,
        });
    }
    let (w, h) = (scene.camera.width, scene.camera.height);
    let step = w.max(h).div_ceil(MAX_GRID_LINES).max(1);
    let grid = with_alpha(rgba(theme.muted), 0.45);
    let mut x = step;
    while x < w {
        g.lines.push(Line3 {
            a: image_plane_point(scene, d, x as f32, 0.0).to_array(),
            b: image_plane_point(scene, d, x as f32, h as f32).to_array(),
            color: grid,
            width: 1.0,
        });
        x += step;
    }
    let mut y = step;
    while y < h {
        g.lines.push(Line3 {
            a: image_plane_point(scene, d, 0.0, y as f32).to_array(),
            b: image_plane_point(scene, d, w as f32, y as f32).to_array(),
            color: grid,
            width: 1.0,
        });
        y += step;
    }
    // The image plane itself, faintly filled, and the selected pixel (at least one grid cell wide,
    // so it can be seen on a large image).
    let fill = with_alpha(rgba(theme.muted), 0.12);
    for i in [0, 1, 2, 0, 2, 3] {
        g.clear_tris.push(TriVertex {
            pos: corners[i].to_array(),
            normal: scene.camera.from.to_array(),
            color: fill,
        });
    }
    if let Some(t) = trace {
        let [px, py] = t.pixel;
        // At least a twentieth of the image wide, so it shows on the plane from afar.
        let cell = (step as f32).max(w.max(h) as f32 / 20.0);
        let half = (cell - 1.0) * 0.5;
        let (x0, x1) = (px as f32 - half, px as f32 + 1.0 + half);
        let (y0, y1) = (py as f32 - half, py as f32 + 1.0 + half);
        let q = [
            image_plane_point(scene, d, x0, y0),
            image_plane_point(scene, d, x1, y0),
            image_plane_point(scene, d, x1, y1),
            image_plane_point(scene, d, x0, y1),
        ];
        let c = rgba(theme.ray);
        for i in [0, 1, 2, 0, 2, 3] {
            g.tris.push(TriVertex {
                pos: q[i].to_array(),
                normal: (-CameraRays::new(&scene.camera).w).to_array(),
                color: c,
            });
        }
    }
}

/// Each ray with the timeline indices of its own steps (a ray's steps are not contiguous in the
/// timeline: its children's steps follow each spawn), in timeline order.
struct RaySpan<'a> {
    ray: &'a RayRecord,
    at: Vec<usize>,
}

impl RaySpan<'_> {
    fn first(&self) -> usize {
        self.at.first().copied().unwrap_or(0)
    }
    fn last(&self) -> usize {
        self.at.last().copied().unwrap_or(0)
    }
    /// How many of the ray's own steps are at or before timeline step `k`.
    fn done_by(&self, k: usize) -> usize {
        self.at.partition_point(|&i| i <= k)
    }
}

fn spans(t: &Trace) -> Vec<RaySpan<'_>> {
    let mut out: Vec<RaySpan> = vec![];
    // Each ray's place in `out`, by address (a long trace has thousands of rays).
    let mut index: std::collections::HashMap<*const RayRecord, usize> = Default::default();
    for (k, (r, _)) in t.timeline().into_iter().enumerate() {
        let i = *index.entry(std::ptr::from_ref(r)).or_insert_with(|| {
            out.push(RaySpan { ray: r, at: vec![] });
            out.len() - 1
        });
        out[i].at.push(k);
    }
    out
}

/// The rays of `t` up to timeline step `step` (all of them when None). With `main`, the rays
/// are drawn wide with their hit points and normals; a fan's rays are thin.
fn rays(t: &Trace, step: Option<usize>, b: &Bounds, theme: &Theme, main: bool, g: &mut Geometry) {
    let open_length = |o: Vec3, d: Vec3| {
        // To where the ray leaves a sphere twice the scene's size (at least the scene's radius).
        let f = o - b.center;
        let r = b.radius * 2.0;
        let bq = f.dot(d);
        let c = f.length_squared() - r * r;
        let disc = bq * bq - c;
        let t = if disc > 0.0 { -bq + disc.sqrt() } else { r };
        t.max(b.radius * 0.5)
    };
    let timeline_step = step;
    for s in spans(t) {
        let r = s.ray;
        if timeline_step.is_some_and(|k| k < s.first()) {
            continue;
        }
        let done = timeline_step.is_none_or(|k| k >= s.last());
        let current = timeline_step.is_some_and(|k| s.at.binary_search(&k).is_ok());
        let origin = Vec3::from(r.origin);
        let raw = Vec3::from(r.direction);
        let dir = raw.normalize_or(Vec3::Z);
        if !origin.is_finite() || !dir.is_finite() {
            continue;
        }
        // The recorded t values count in units of the recorded direction, which need not be a
        // unit vector: a shadow ray's is the vector to its light (t_max just under 1).
        let scale = match raw.length() {
            l if l.is_finite() && l > 0.0 => l,
            _ => 1.0,
        };
        // The closest t accepted so far, read from the ray's own steps up to the current one.
        let upto = match timeline_step {
            Some(k) if !done => s.done_by(k),
            _ => r.steps.len(),
        };
        let mut accepted: Option<f32> = None;
        for st in r.steps.iter().take(upto) {
            if let Step::Accept { t, .. } = st.step {
                accepted = Some(t);
            }
        }
        let hit_t = if done {
            r.hit.as_ref().map(|h| h.t).or(accepted)
        } else {
            accepted
        }
        .map(|t| t * scale);
        let (length, end) = match (r.kind, hit_t) {
            (RayKind::Shadow, Some(t)) => (t, RayEnd::Blocked),
            (RayKind::Shadow, None) if done => (
                r.t_max
                    .map_or_else(|| open_length(origin, dir), |t| t * scale),
                RayEnd::Light,
            ),
            (_, Some(t)) => (t, RayEnd::Hit),
            (_, None) => (open_length(origin, dir), RayEnd::Open),
        };
        let length = if length.is_finite() && length > 0.0 {
            length
        } else {
            open_length(origin, dir)
        };
        let color = match (r.kind, end) {
            (RayKind::Primary, _) => rgba(theme.ray),
            (RayKind::Shadow, RayEnd::Blocked) => rgba(theme.blocked),
            (RayKind::Shadow, _) => rgba(theme.shadow),
            (RayKind::Reflection, _) => rgba(theme.reflect),
            (RayKind::Refraction, _) => rgba(theme.refract),
            (RayKind::Diffuse, _) => rgba(theme.diffuse),
            (RayKind::Glossy, _) => rgba(theme.glossy),
        };
        let (width, color) = match (main, end) {
            (false, _) => (1.0, with_alpha(color, 0.55)),
            (true, RayEnd::Open) if !done => (3.0, with_alpha(color, 0.8)),
            (true, _) => (if current { 4.0 } else { 3.0 }, color),
        };
        let endp = origin + dir * length;
        g.lines.push(Line3 {
            a: origin.to_array(),
            b: endp.to_array(),
            color,
            width,
        });
        if main && end == RayEnd::Blocked {
            // A cross where the blocker stops the shadow ray.
            let k = b.radius * 0.02;
            let side = dir.any_orthonormal_vector();
            let other = dir.cross(side);
            for a in [side + other, side - other] {
                g.lines.push(Line3 {
                    a: (endp - a * k).to_array(),
                    b: (endp + a * k).to_array(),
                    color: rgba(theme.blocked),
                    width: 3.0,
                });
            }
        }
        g.rays.push(DrawnRay {
            kind: r.kind,
            depth: r.depth,
            origin,
            dir,
            length,
            end,
            current: main && current,
        });
        if !main || end != RayEnd::Hit {
            continue;
        }
        // The hit point, and its normal once the surface step is reached.
        let surface = r.steps.iter().take(upto).find_map(|st| match st.step {
            Step::Surface { point, normal, .. } => Some((Vec3::from(point), Vec3::from(normal))),
            _ => None,
        });
        g.spheres.push(SphereInstance::round(
            endp,
            b.radius * 0.008,
            rgba(theme.hit),
        ));
        if let Some((p, n)) = surface
            && p.is_finite()
            && n.is_finite()
        {
            g.lines.push(Line3 {
                a: p.to_array(),
                b: (p + n * b.radius * 0.12).to_array(),
                color: rgba(theme.normal),
                width: 2.5,
            });
            g.hits.push((p, n));
        }
    }
}

/// The BVH boxes the current ray has visited up to `step`, as wireframes: culled ones faint.
fn bvh_boxes(t: &Trace, step: Option<usize>, theme: &Theme, g: &mut Geometry) {
    let Some(outline) = &t.bvh else {
        return;
    };
    let timeline = t.timeline();
    let k = step.unwrap_or(timeline.len().saturating_sub(1));
    let Some((current, _)) = timeline.get(k) else {
        return;
    };
    let current: &RayRecord = current;
    for (r, s) in timeline.iter().take(k + 1) {
        if !std::ptr::eq(*r, current) {
            continue;
        }
        let Step::Node(v) = &s.step else {
            continue;
        };
        let Some(node) = outline.iter().find(|n| n.node == v.node) else {
            continue;
        };
        let culled = matches!(v.action, crate::record::NodeAction::Culled);
        let color = if culled {
            with_alpha(rgba(theme.faded), 0.7)
        } else {
            rgba(theme.normal)
        };
        wire_box(Vec3::from(node.min), Vec3::from(node.max), color, g);
    }
}

fn wire_box(lo: Vec3, hi: Vec3, color: [f32; 4], g: &mut Geometry) {
    if !lo.is_finite() || !hi.is_finite() {
        return;
    }
    let c = |i: u32| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    for (a, b) in [
        (0, 1),
        (2, 3),
        (4, 5),
        (6, 7),
        (0, 2),
        (1, 3),
        (4, 6),
        (5, 7),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ] {
        g.lines.push(Line3 {
            a: c(a).to_array(),
            b: c(b).to_array(),
            color,
            width: 1.5,
        });
    }
}

/// A linear colour as the screen shows it (sRGB transfer, clamped).
pub fn linear_to_display(c: Vec3) -> [f32; 3] {
    // An infinite channel shows black here (an image clamps it to white).
    let f = |v: f32| crate::render::image::srgb(if v.is_finite() { v } else { 0.0 });
    [f(c.x), f(c.y), f(c.z)]
}

fn mix(a: [f32; 4], b: [f32; 4], k: f32) -> [f32; 4] {
    [
        a[0] + (b[0] - a[0]) * k,
        a[1] + (b[1] - a[1]) * k,
        a[2] + (b[2] - a[2]) * k,
        a[3],
    ]
}
