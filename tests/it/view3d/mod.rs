//! The 3D scene view (`raystep::view3d`, `raystep view`) against numbers that come from outside
//! it: the recorded trace (its rays, hit points and timeline), the camera convention of the
//! book's "The scene format" (book/scenes.md) (recomputed here in f64, with a basis written out by hand), the
//! scene's lights and object surfaces, and the PNGs the command line writes.
//!
//! The geometry tests need no GPU. The tests that draw (`raystep view` PNGs and the snapshot)
//! print "SKIPPED …" and return where wgpu finds no adapter — except under CI (the CI variable
//! set), where that is a failure: .ci/run installs Mesa's lavapipe.

use crate::common::scenes;

use assert_cmd::Command;
use glam::{DVec3, Vec3};
use raystep::gpu::{GpuContext, GpuError};
use raystep::record::{RayKind, RayRecord, Step, Trace};
use raystep::scene::{Camera, Scene, Shape, load_file, load_str};
use raystep::trace::PreparedScene;
use raystep::view3d::camera::ViewCamera;
use raystep::view3d::geometry::{self, DrawnRay, Geometry, Options, RayEnd};
use raystep::view3d::{fan_pixels, fan_traces};
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

fn prepared(path: &Path) -> PreparedScene {
    let scene = load_file(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    PreparedScene::new(scene)
}

fn name(path: &Path) -> String {
    path.file_name().unwrap().to_string_lossy().into_owned()
}

/// The pixels each scene is checked at: the four corners, the centre and two more.
fn pixels(c: &Camera) -> Vec<[u32; 2]> {
    let (w, h) = (c.width, c.height);
    let mut v = vec![
        [0, 0],
        [w - 1, 0],
        [0, h - 1],
        [w - 1, h - 1],
        [w / 2, h / 2],
        [w / 3, h / 2],
        [2 * w / 3, h / 3],
        [w / 2, 3 * h / 4],
    ];
    v.dedup();
    v
}

/// Every ray of the trace in the order the timeline first reaches it (its spawn order).
fn rays_in_timeline_order(t: &Trace) -> Vec<&RayRecord> {
    let mut out: Vec<&RayRecord> = vec![];
    for (r, _) in t.timeline() {
        if !out.iter().any(|o| std::ptr::eq(*o, r)) {
            out.push(r);
        }
    }
    out
}

/// The rays the timeline has reached by step `k` (inclusive), in spawn order.
fn rays_reached_by(t: &Trace, k: usize) -> Vec<&RayRecord> {
    let mut out: Vec<&RayRecord> = vec![];
    for (r, _) in t.timeline().into_iter().take(k + 1) {
        if !out.iter().any(|o| std::ptr::eq(*o, r)) {
            out.push(r);
        }
    }
    out
}

/// The ray's hit point, as its `Surface` step recorded it.
fn surface_point(r: &RayRecord) -> Option<Vec3> {
    r.steps.iter().find_map(|s| match s.step {
        Step::Surface { point, .. } => Some(Vec3::from(point)),
        _ => None,
    })
}

fn unit(v: [f32; 3]) -> DVec3 {
    Vec3::from(v).as_dvec3().normalize()
}

/// Whether a drawn ray is the recorded one: same kind, depth, origin and (unit) direction.
fn same_ray(d: &DrawnRay, r: &RayRecord) -> bool {
    d.kind == r.kind
        && d.depth == r.depth
        && d.origin == Vec3::from(r.origin)
        && (d.dir.as_dvec3() - unit(r.direction)).length() < 1e-6
}

/// The distance from `p` to the segment origin + dir·[0, length], in f64.
fn distance_to_segment(p: Vec3, d: &DrawnRay) -> f64 {
    let (o, dir, p) = (d.origin.as_dvec3(), d.dir.as_dvec3(), p.as_dvec3());
    let t = (p - o).dot(dir).clamp(0.0, f64::from(d.length));
    (o + dir * t - p).length()
}

fn drawn_end(d: &DrawnRay) -> DVec3 {
    d.origin.as_dvec3() + d.dir.as_dvec3() * f64::from(d.length)
}

/// How far `p` is from the surface of `shape` (for spheres and planes; for a triangle, from its
/// plane).
fn distance_to_surface(shape: &Shape, p: DVec3) -> f64 {
    match *shape {
        Shape::Sphere { center, radius } => {
            ((p - center.as_dvec3()).length() - f64::from(radius)).abs()
        }
        Shape::Plane { normal, offset } => {
            let n = normal.as_dvec3();
            (p.dot(n) / n.length() - f64::from(offset)).abs()
        }
        Shape::AxisPlane { axis, offset } => (p[axis] - f64::from(offset)).abs(),
        Shape::Triangle { p: v } => {
            let (a, b, c) = (v[0].as_dvec3(), v[1].as_dvec3(), v[2].as_dvec3());
            let n = (b - a).cross(c - a).normalize();
            (p - a).dot(n).abs()
        }
    }
}

/// The camera basis of book/scenes.md, "The scene format", in f64: w = normalize(from − at),
/// u = normalize(up × w), v = w × u, half_height = tan(fov/2), half_width = half_height·W/H.
struct Basis {
    from: DVec3,
    u: DVec3,
    v: DVec3,
    w: DVec3,
    half_width: f64,
    half_height: f64,
}

impl Basis {
    fn of(c: &Camera) -> Basis {
        let from = c.from.as_dvec3();
        let at = c.at.as_dvec3();
        let up = c.up.as_dvec3();
        let w = (from - at) / (from - at).length();
        // up × w, written out component by component.
        let cross = |a: DVec3, b: DVec3| {
            DVec3::new(
                a.y * b.z - a.z * b.y,
                a.z * b.x - a.x * b.z,
                a.x * b.y - a.y * b.x,
            )
        };
        let u0 = cross(up, w);
        let u = u0 / u0.length();
        let v = cross(w, u);
        let half_height = (f64::from(c.fov) * std::f64::consts::PI / 360.0).tan();
        Basis {
            from,
            u,
            v,
            w,
            half_width: half_height * f64::from(c.width) / f64::from(c.height),
            half_height,
        }
    }

    /// Where `p` lands in the camera's picture, in pixels from the top-left: the convention
    /// inverted, sx = (p·u)/(depth·half_width), sy = (p·v)/(depth·half_height) with p taken
    /// from the eye and depth = −p·w; x = (sx + 1)·W/2, y = (1 − sy)·H/2.
    fn pixel_of(&self, p: DVec3, c: &Camera) -> [f64; 2] {
        let p = p - self.from;
        let depth = -p.dot(self.w);
        let sx = p.dot(self.u) / depth / self.half_width;
        let sy = p.dot(self.v) / depth / self.half_height;
        [
            (sx + 1.0) * 0.5 * f64::from(c.width),
            (1.0 - sy) * 0.5 * f64::from(c.height),
        ]
    }

    /// The point at distance `d` along the view direction whose screen coordinates are (sx, sy).
    fn at(&self, sx: f64, sy: f64, d: f64) -> DVec3 {
        self.from
            + (self.u * (sx * self.half_width) + self.v * (sy * self.half_height) - self.w) * d
    }
}

/// Builds the geometry of `t` at `step` with the view's defaults.
fn build(scene: &Scene, t: &Trace, step: Option<usize>) -> Geometry {
    geometry::build(
        scene,
        Some(t),
        &[],
        &Options {
            step,
            ..Default::default()
        },
    )
}

/// The headless context's availability: false (after printing why) where wgpu finds no
/// adapter; under CI that fails the test instead.
fn have_adapter(test: &str) -> bool {
    match GpuContext::headless() {
        Ok(_) => true,
        Err(GpuError::NoAdapter(e)) => {
            assert!(
                std::env::var("CI").is_err(),
                "CI must run {test}: install Mesa's lavapipe (mesa-vulkan-drivers): {e}"
            );
            eprintln!("SKIPPED {test}: no wgpu adapter (install mesa-vulkan-drivers)");
            false
        }
        Err(e) => panic!("{e}"),
    }
}

fn raystep() -> Command {
    Command::cargo_bin("raystep").expect("the raystep binary is built")
}

fn scene_file(file: &str) -> PathBuf {
    scenes::root().join("scenes").join(file)
}

/// Runs `raystep view` with `args` (whitespace-separated) writing to `out`; expects success.
fn view(scene: &Path, args: &str, out: &Path) -> image::RgbaImage {
    let run = raystep()
        .arg("view")
        .arg(scene)
        .args(args.split_whitespace())
        .arg("-o")
        .arg(out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "raystep view {args} failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    image::open(out)
        .unwrap_or_else(|e| panic!("{}: {e}", out.display()))
        .to_rgba8()
}

/// A pixel of cornell.toml whose primary ray hits the mirror ball: its trace has a reflection
/// ray that hits something.
const CORNELL_MIRROR_PIXEL: [u32; 2] = [100, 210];

/// A pixel of cornell.toml whose primary ray hits the glass ball (reflection and refraction).
const CORNELL_GLASS_PIXEL: [u32; 2] = [216, 230];

// ---------------------------------------------------------------------------------------------
// 1. The drawn rays are the traced rays
// ---------------------------------------------------------------------------------------------

/// On every shipped scene and a few pixels, with the whole trace drawn: one drawn ray per
/// recorded ray, in spawn order, with the recorded origin and direction; each recorded hit point
/// (the `Surface` step) lies on its ray's drawn segment — at its end; an unblocked shadow ray is
/// drawn up to its light (the one its `ShadowRay` step names); a blocked one ends on the surface
/// of the object that blocks it.
#[test]
fn drawn_rays_are_the_traced_rays_and_end_at_their_hits() {
    let (mut hits, mut lit, mut blocked) = (0, 0, 0);
    for path in scenes::shipped_whitted() {
        let p = prepared(&path);
        let scene = p.scene();
        let c = &scene.camera;
        for [x, y] in pixels(c) {
            let t = p.record(x, y, 0);
            let what = format!("{} pixel {x},{y}", name(&path));
            let g = build(scene, &t, None);
            let order = rays_in_timeline_order(&t);
            if t.truncated_at().is_none() {
                assert_eq!(order.len(), t.rays().len(), "{what}: every ray is spawned");
            }
            assert_eq!(g.rays.len(), order.len(), "{what}: one drawn ray per ray");
            // Which light each shadow ray goes to: the parent's `ShadowRay` step just before the
            // spawn.
            let mut light_of: Vec<(*const RayRecord, u32)> = vec![];
            for r in t.rays() {
                let mut last_light = None;
                for s in &r.steps {
                    match s.step {
                        Step::ShadowRay { light, .. } => last_light = Some(light),
                        Step::Spawn { child } => {
                            let ch = &r.children[child as usize];
                            if ch.kind == RayKind::Shadow {
                                light_of.push((ch, last_light.expect("a ShadowRay step")));
                            }
                        }
                        _ => {}
                    }
                }
            }
            for (i, (d, r)) in g.rays.iter().zip(&order).enumerate() {
                let what = format!("{what}, ray {i} ({:?} depth {})", r.kind, r.depth);
                assert!(same_ray(d, r), "{what}: drawn {d:?} vs recorded {r:?}");
                assert!(
                    !d.current,
                    "{what}: no ray is current with the whole trace drawn"
                );
                // "Small relative to the scene": a 1e-4 of the distance from the eye to the
                // farthest thing involved.
                let size = |p: Vec3| {
                    let from = c.from.as_dvec3();
                    [
                        (c.at.as_dvec3() - from).length(),
                        (p.as_dvec3() - from).length(),
                        (d.origin.as_dvec3() - from).length(),
                        (p.as_dvec3() - d.origin.as_dvec3()).length(),
                    ]
                    .into_iter()
                    .fold(1e-3, f64::max)
                };
                if let Some(p) = surface_point(r) {
                    hits += 1;
                    let tol = 1e-4 * size(p);
                    let off = distance_to_segment(p, d);
                    assert!(
                        off <= tol,
                        "{what}: hit {p} is {off} off the drawn ray {d:?}"
                    );
                    let end = (drawn_end(d) - p.as_dvec3()).length();
                    assert!(
                        end <= tol,
                        "{what}: the drawn ray ends {end} from its hit {p}"
                    );
                    assert_eq!(d.end, RayEnd::Hit, "{what}");
                }
                if r.kind == RayKind::Shadow {
                    match &r.hit {
                        None => {
                            lit += 1;
                            let (_, l) = light_of
                                .iter()
                                .find(|(q, _)| std::ptr::eq(*q, *r))
                                .expect("the shadow ray's light");
                            let light = scene.lights[*l as usize].position;
                            let full = (light.as_dvec3() - d.origin.as_dvec3()).length();
                            let gap = (drawn_end(d) - light.as_dvec3()).length();
                            // The shadow ray stops just short of the light (so the light itself
                            // is never an occluder): within 0.1% of its length.
                            assert!(
                                gap <= 1e-3 * full + 1e-4 * size(light),
                                "{what}: the unblocked shadow ray ends {gap} from its light at \
                                 {light} ({full} away): {d:?}"
                            );
                            assert_eq!(d.end, RayEnd::Light, "{what}");
                        }
                        Some(h) => {
                            blocked += 1;
                            let mut end = drawn_end(d);
                            // An instance's blocker is measured in its object space, where its
                            // shape is (the end carried there by M⁻¹, in f32 as the tracer
                            // carries rays).
                            if let Some(inst) =
                                h.instance.and_then(|i| scene.instances.get(i as usize))
                            {
                                end = inst.to_object.point(end.as_vec3()).as_dvec3();
                            }
                            let off =
                                distance_to_surface(&scene.objects[h.object as usize].shape, end);
                            assert!(
                                off <= 1e-4 * size(end.as_vec3()),
                                "{what}: the blocked shadow ray ends {off} off its blocker \
                                 {}: {d:?}",
                                h.name
                            );
                            assert_eq!(d.end, RayEnd::Blocked, "{what}");
                        }
                    }
                }
            }
            // The hit points drawn are the recorded ones.
            let recorded: Vec<Vec3> = order.iter().filter_map(|r| surface_point(r)).collect();
            let drawn: Vec<Vec3> = g.hits.iter().map(|(p, _)| *p).collect();
            assert_eq!(drawn, recorded, "{what}: the hit points drawn");
        }
    }
    assert!(hits > 50, "only {hits} hit points checked");
    assert!(
        lit > 10 && blocked > 0,
        "shadow rays checked: {lit} lit, {blocked} blocked"
    );
}

// ---------------------------------------------------------------------------------------------
// 2. Looking through the camera
// ---------------------------------------------------------------------------------------------

/// Looking through the scene's camera, in a picture of the camera's own size: the primary ray's
/// hit point (from the trace) and the point at t = 1 on it project to the centre of the pixel
/// traced, within half a pixel, on every shipped scene, corners included — and `project` puts
/// each where the convention inverted in f64 does, to 0.01 px (before the projection worked
/// relative to the eye, acne.toml's camera 26 000 units out cost a third of a pixel); the view's
/// ray through that pixel centre is the primary ray.
#[test]
fn looking_through_the_camera_puts_each_primary_ray_on_its_pixel() {
    let (mut hits, mut worst) = (0, 0.0f32);
    for path in scenes::shipped_whitted() {
        let p = prepared(&path);
        let scene = p.scene();
        let c = &scene.camera;
        let cam = ViewCamera::look_through(c, &geometry::bounds(scene));
        let b = Basis::of(c);
        let (w, h) = (c.width as f32, c.height as f32);
        for [x, y] in pixels(c) {
            let t = p.record(x, y, 0);
            let want = [x as f32 + 0.5, y as f32 + 0.5];
            let what = format!("{} pixel {x},{y}", name(&path));
            let o = Vec3::from(t.root.origin);
            let dir = Vec3::from(t.root.direction);
            assert_eq!(o, c.from, "{what}: the primary ray starts at the eye");
            let mut points = vec![("the point at t = 1", o + dir)];
            if let Some(hit) = surface_point(&t.root) {
                hits += 1;
                points.push(("the hit point", hit));
            }
            for (which, q) in points {
                let got = cam
                    .project(q, w, h)
                    .unwrap_or_else(|| panic!("{what}: {which} {q} is behind the eye"));
                let err = (got[0] - want[0]).hypot(got[1] - want[1]);
                worst = worst.max(err);
                // And where the convention, inverted in f64, puts this very (f32) point: the
                // projection itself adds no error of its own.
                let exact = b.pixel_of(q.as_dvec3(), c);
                let own = (f64::from(got[0]) - exact[0]).hypot(f64::from(got[1]) - exact[1]);
                assert!(
                    own <= 0.01,
                    "{what}: {which} {q} projects to {got:?}, the convention in f64 to {exact:?}"
                );
                assert!(
                    err <= 0.5,
                    "{what}: {which} {q} projects to {got:?}, {err} px from {want:?}"
                );
            }
            // ray_through: the same ray, to a quarter of a pixel's angle.
            let (eye, d) = cam.ray_through(want, w, h);
            assert_eq!(eye, c.from, "{what}");
            let angle = d.as_dvec3().angle_between(dir.as_dvec3());
            let pixel_angle = f64::from(c.fov).to_radians() / f64::from(c.height);
            assert!(
                angle <= 0.25 * pixel_angle,
                "{what}: ray_through is {angle} rad off the primary ray (a pixel is {pixel_angle})"
            );
        }
    }
    eprintln!("{hits} hit points projected; the worst point is {worst} px off its pixel centre");
    assert!(hits >= 20, "only {hits} primary hits projected");
}

// ---------------------------------------------------------------------------------------------
// 3. The image plane
// ---------------------------------------------------------------------------------------------

/// The image plane's corners (top-left, top-right, bottom-right, bottom-left) are the camera
/// convention's screen corners (sx, sy) = (∓1, ±1) at distance d, computed here in f64 with our
/// own basis; and the drawn plane's pixel centre (x + ½, y + ½) lies on that pixel's traced
/// primary ray.
#[test]
fn the_image_plane_follows_the_camera_convention() {
    for path in scenes::shipped_whitted() {
        let p = prepared(&path);
        let scene = p.scene();
        let c = &scene.camera;
        let b = Basis::of(c);
        let plane_d = geometry::image_plane_distance(scene);
        assert!(
            plane_d > 0.0 && plane_d < (c.at - c.from).length(),
            "{}",
            name(&path)
        );
        for d in [plane_d, 1.0, 2.5] {
            let got = geometry::image_plane_corners(scene, d);
            let want = [
                b.at(-1.0, 1.0, f64::from(d)),
                b.at(1.0, 1.0, f64::from(d)),
                b.at(1.0, -1.0, f64::from(d)),
                b.at(-1.0, -1.0, f64::from(d)),
            ];
            let scale = b.from.length() + f64::from(d) * (1.0 + b.half_width + b.half_height);
            for (i, (g, w)) in got.iter().zip(want).enumerate() {
                let err = (g.as_dvec3() - w).length();
                assert!(
                    err <= 1e-5 * scale,
                    "{} d={d}: corner {i} is {g}, by hand {w} ({err} off)",
                    name(&path)
                );
            }
        }
        for [x, y] in pixels(c) {
            let t = p.record(x, y, 0);
            let q = geometry::image_plane_point(scene, plane_d, x as f32 + 0.5, y as f32 + 0.5)
                .as_dvec3();
            let o = Vec3::from(t.root.origin).as_dvec3();
            let dir = unit(t.root.direction);
            let along = (q - o).dot(dir);
            let off = (o + dir * along - q).length();
            assert!(
                along > 0.0 && off <= 1e-5 * (b.from.length() + along),
                "{} pixel {x},{y}: the drawn pixel centre {q} is {off} off the primary ray",
                name(&path)
            );
        }
    }
}

/// The convention worked out by hand for one camera: from (0, 0, −5) looking at the origin, up
/// +y, fov 90° (half_height = 1), 200×100 (half_width = 2). w = (0, 0, −1), u = up × w =
/// (−1, 0, 0) (+x is on the left of the picture), v = w × u = (0, 1, 0). At d = 1 the top-left
/// corner is from + (−1·2·u + 1·v − w) = (0, 0, −5) + (2, 0, 0) + (0, 1, 0) + (0, 0, 1).
#[test]
fn image_plane_corners_of_a_hand_worked_camera() {
    let scene = load_str(
        "[camera]\nfrom = [0, 0, -5]\nat = [0, 0, 0]\nup = [0, 1, 0]\nfov = 90\nwidth = 200\n\
         height = 100\n[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\n",
        "hand.toml",
        None,
    )
    .unwrap();
    let got = geometry::image_plane_corners(&scene, 1.0);
    let want = [
        Vec3::new(2.0, 1.0, -4.0),
        Vec3::new(-2.0, 1.0, -4.0),
        Vec3::new(-2.0, -1.0, -4.0),
        Vec3::new(2.0, -1.0, -4.0),
    ];
    for (g, w) in got.iter().zip(want) {
        assert!((*g - w).length() < 1e-5, "{got:?} vs {want:?}");
    }
    // Pixel (0, 0)'s centre: sx = 2·0.5/200 − 1 = −0.995, sy = 1 − 2·0.5/100 = 0.99.
    let q = geometry::image_plane_point(&scene, 1.0, 0.5, 0.5);
    assert!((q - Vec3::new(1.99, 0.99, -4.0)).length() < 1e-5, "{q}");
}

// ---------------------------------------------------------------------------------------------
// 4. Stepping
// ---------------------------------------------------------------------------------------------

/// Traces with several rays, stepped through: at step K the rays drawn are those the timeline
/// has reached by K, in the order it spawns them (so never more than at the last step, and only
/// the primary ray at step 0), and exactly one of them — the ray step K belongs to — is current.
#[test]
fn stepping_draws_the_rays_spawned_so_far() {
    let cases = [
        ("cornell.toml", CORNELL_MIRROR_PIXEL),
        ("cornell.toml", CORNELL_GLASS_PIXEL),
        ("mirror-glass.toml", [150, 150]),
        ("mirror-glass.toml", [250, 150]),
        ("three-spheres.toml", [160, 130]),
        ("triangles.toml", [160, 120]),
        ("teapot-stadium.toml", [160, 130]),
    ];
    let mut multi = 0;
    for (file, [x, y]) in cases {
        let p = prepared(&scene_file(file));
        let scene = p.scene();
        let t = p.record(x, y, 0);
        let what = format!("{file} pixel {x},{y}");
        let timeline = t.timeline();
        let last = build(scene, &t, Some(timeline.len() - 1));
        let all = rays_in_timeline_order(&t);
        if all.len() > 2 {
            multi += 1;
        }
        assert_eq!(
            last.rays.len(),
            all.len(),
            "{what}: every ray at the last step"
        );
        let whole = build(scene, &t, None);
        let mut previous = 0;
        // Every step of a short trace; a long one (BVH walks) every few steps and around each
        // spawn.
        let stride = (timeline.len() / 400).max(1);
        let ks: Vec<usize> = (0..timeline.len())
            .filter(|&k| {
                k % stride == 0
                    || k + 1 == timeline.len()
                    || matches!(timeline[k].1.step, Step::Spawn { .. })
                    || (k > 0 && matches!(timeline[k - 1].1.step, Step::Spawn { .. }))
            })
            .collect();
        for k in ks {
            let g = build(scene, &t, Some(k));
            let want = rays_reached_by(&t, k);
            assert_eq!(g.rays.len(), want.len(), "{what} step {k}: rays drawn");
            assert!(g.rays.len() <= last.rays.len(), "{what} step {k}");
            assert!(
                g.rays.len() >= previous,
                "{what} step {k}: a ray disappeared"
            );
            previous = g.rays.len();
            for (i, (d, r)) in g.rays.iter().zip(&want).enumerate() {
                assert!(
                    same_ray(d, r),
                    "{what} step {k}: ray {i} is {d:?}, not {r:?}"
                );
                // The drawn rays are a prefix of the whole trace's.
                assert!(same_ray(&whole.rays[i], r), "{what} step {k}: ray {i}");
            }
            let owner = timeline[k].0;
            let current: Vec<usize> = g
                .rays
                .iter()
                .enumerate()
                .filter(|(_, d)| d.current)
                .map(|(i, _)| i)
                .collect();
            let owner_at = want.iter().position(|r| std::ptr::eq(*r, owner)).unwrap();
            assert_eq!(
                current,
                vec![owner_at],
                "{what} step {k} ({:?}): the current ray",
                timeline[k].1.step
            );
            if k == 0 {
                assert_eq!(g.rays.len(), 1, "{what}: step 0 draws the primary ray only");
                assert_eq!(g.rays[0].kind, RayKind::Primary);
                assert_eq!(g.rays[0].depth, 0);
            }
        }
    }
    assert!(multi >= 4, "only {multi} traces with several rays");
}

// ---------------------------------------------------------------------------------------------
// 5. The fan of primary rays
// ---------------------------------------------------------------------------------------------

/// `fan_pixels(n)`: n×n distinct pixels inside the image, one in each cell of an n×n grid over
/// it, row by row; where the image is narrower (or lower) than n every column (row) is used
/// once; n is capped at 32.
#[test]
fn fan_pixels_spread_distinct_pixels_over_the_image() {
    let camera = |width: u32, height: u32| Camera {
        from: Vec3::new(0.0, 0.0, -5.0),
        at: Vec3::ZERO,
        up: Vec3::Y,
        fov: 60.0,
        width,
        height,
        aperture: 0.0,
        focus_distance: 1.0,
    };
    for (w, h) in [
        (1, 1),
        (3, 1),
        (7, 5),
        (9, 9),
        (5, 11),
        (33, 17),
        (101, 63),
        (320, 240),
    ] {
        for n in [1, 2, 3, 4, 5, 7, 8, 9, 12, 31, 32, 33, 40] {
            let c = camera(w, h);
            let got = fan_pixels(&c, n);
            let what = format!("{w}×{h}, n = {n}");
            let k = n.min(32);
            let (cols, rows) = (k.min(w), k.min(h));
            assert_eq!(got.len() as u32, cols * rows, "{what}: {got:?}");
            let mut sorted = got.clone();
            sorted.sort();
            sorted.dedup();
            assert_eq!(sorted.len(), got.len(), "{what}: distinct");
            for &[x, y] in &got {
                assert!(x < w && y < h, "{what}: {x},{y} outside the image");
            }
            let mut xs: Vec<u32> = got.iter().map(|p| p[0]).collect();
            xs.sort();
            xs.dedup();
            let mut ys: Vec<u32> = got.iter().map(|p| p[1]).collect();
            ys.sort();
            ys.dedup();
            assert_eq!(xs.len() as u32, cols, "{what}: columns {xs:?}");
            assert_eq!(ys.len() as u32, rows, "{what}: rows {ys:?}");
            // Along a side at least k pixels long, one column (row) in each of the k cells
            // [i·side/k, (i+1)·side/k); along a shorter side, every column (row).
            for (values, side) in [(&xs, w), (&ys, h)] {
                if k <= side {
                    for (i, &v) in values.iter().enumerate() {
                        let (lo, hi) = (i as u32 * side, (i as u32 + 1) * side);
                        assert!(v * k + k > lo && v * k < hi, "{what}: {values:?} cell {i}");
                    }
                } else {
                    assert_eq!(*values, (0..side).collect::<Vec<_>>(), "{what}");
                }
            }
            if k <= w && k <= h {
                // Row by row, each in its own cell [i·w/k, (i+1)·w/k) × [j·h/k, (j+1)·h/k).
                for (idx, &[x, y]) in got.iter().enumerate() {
                    let (i, j) = (idx as u32 % k, idx as u32 / k);
                    let (x, y) = (f64::from(x), f64::from(y));
                    let cell = |c: u32, side: u32| {
                        (
                            f64::from(c) * f64::from(side) / f64::from(k),
                            f64::from(c + 1) * f64::from(side) / f64::from(k),
                        )
                    };
                    let ((x0, x1), (y0, y1)) = (cell(i, w), cell(j, h));
                    assert!(
                        x + 1.0 > x0 && x < x1 && y + 1.0 > y0 && y < y1,
                        "{what}: pixel {idx} ({x},{y}) is not in cell ({i},{j})"
                    );
                }
            }
            // Row by row: y never decreases, and x increases along a row.
            for pair in got.windows(2) {
                let ([x0, y0], [x1, y1]) = (pair[0], pair[1]);
                assert!(y1 > y0 || (y1 == y0 && x1 > x0), "{what}: order {got:?}");
            }
        }
    }
    // The traces of the fan are those of its pixels.
    let p = prepared(&scene_file("three-spheres.toml"));
    let fan = fan_traces(&p, 3);
    assert_eq!(
        fan.iter().map(|t| t.pixel).collect::<Vec<_>>(),
        fan_pixels(&p.scene().camera, 3)
    );
    // Drawn thin, whole, before the selected pixel's rays: never current.
    let g = geometry::build(p.scene(), None, &fan, &Options::default());
    let n: usize = fan.iter().map(|t| rays_in_timeline_order(t).len()).sum();
    assert_eq!(g.rays.len(), n);
    assert!(g.rays.iter().all(|d| !d.current));
}

// ---------------------------------------------------------------------------------------------
// 6. `raystep view`
// ---------------------------------------------------------------------------------------------

mod cli;

/// A sphere placed under a non-uniform scale is drawn as the ellipsoid the tracer sees: on
/// `scenes/instances.toml` the egg (the unit sphere, `scale = [0.6, 1, 0.6]`, `translate =
/// [1.8, 1, 0.4]`) is the unit sphere carried by diag(0.6, 1, 0.6) and moved there, and the
/// marble (`scale = 0.35`, `translate = [0.9, 0.35, -0.6]`) by 0.35 in every direction — both
/// read by hand from the file — not a round sphere around either.
#[test]
fn a_stretched_instance_is_drawn_as_its_ellipsoid() {
    let scene = load_file(&scene_file("instances.toml")).unwrap();
    let g = geometry::build(&scene, None, &[], &Options::default());
    let drawn = |center: [f32; 3]| {
        g.spheres
            .iter()
            .find(|s| {
                s.center
                    .iter()
                    .zip(center)
                    .all(|(a, b)| (a - b).abs() < 1e-6)
            })
            .unwrap_or_else(|| panic!("no sphere drawn at {center:?}"))
    };
    for (center, scale) in [
        ([1.8, 1.0, 0.4], [0.6, 1.0, 0.6]),
        ([0.9, 0.35, -0.6], [0.35; 3]),
    ] {
        let s = drawn(center);
        assert_eq!(s.radius, 1.0);
        for (k, axis) in s.axes.iter().enumerate() {
            for (j, x) in axis.iter().enumerate() {
                let want = if j == k { scale[k] } else { 0.0 };
                assert!((x - want).abs() < 1e-6, "{center:?}: axes {:?}", s.axes);
            }
        }
    }
    // The prototype itself (the unit sphere at the origin) is not drawn.
    assert!(
        !g.spheres
            .iter()
            .any(|s| s.center == [0.0; 3] && s.radius == 1.0)
    );
}

/// The book's picture of the 3D view (`docs/view3d.png`, in book/app.md) is what `raystep view`
/// draws today with the command that made it: at most 0.5 % of its pixels differ by more than 16
/// in a channel (the diagrams' golden rule), so a changed view cannot leave a stale picture in
/// the book. `UPDATE_GOLDEN=1` redraws it.
#[test]
fn the_books_3d_view_picture_is_current() {
    if !have_adapter("the_books_3d_view_picture_is_current") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("view3d.png");
    let args = "--pixel 230,130 --orbit 40,20 --distance 0.22 --look-at -0.6,1,-1 --size 1200x675";
    let got = view(&scene_file("mirror-glass.toml"), args, &out);
    let path = scenes::root().join("docs/view3d.png");
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::copy(&out, &path).unwrap();
        return;
    }
    let want = image::open(&path).unwrap().to_rgba8();
    assert_eq!(want.dimensions(), got.dimensions());
    let (differing, total) = crate::common::golden::differing(&want, &got, |_, _| false);
    assert!(
        differing * 200 <= total,
        "docs/view3d.png: {differing} of {total} pixels differ from `raystep view scenes/mirror-glass.toml {args}` (redraw it with UPDATE_GOLDEN=1)"
    );
}
