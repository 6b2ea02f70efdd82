//! `raystep bench --section mc`: every Monte Carlo scene path-traced by raystep and by Mitsuba 3
//! (`scalar_rgb`), one thread each, side by side: the time per sample, the error against a
//! shared reference over several independent renders, and the efficiency 1 / (MSE × time).
//!
//! An independent render is one with another `[render] seed` (Mitsuba's `seed`): the same scene
//! and sample count, other random numbers, so its noise is another draw of the same estimator
//! (the jittered samples of the course notes' chapter 10 slides and the Monte Carlo estimators of
//! the papers named in docs/SOURCES.md, "Beyond the notes"). Efficiency — the inverse of error
//! times time — is pbrt's (4th edition, chapter 2) measure of a Monte Carlo estimator, with the
//! MSE against the reference in place of the variance, so that a bias would count too.
//!
//! Both renderers path-trace the same scene (`raystep scene mitsuba`'s export: Mitsuba's `path`
//! integrator with raystep's depth), so a scene whose own integrator is the distribution tracer
//! is path-traced here, and says so. The reference is Mitsuba's, at [`REFERENCE_SPP`] samples per
//! pixel on every core; each render has [`SPP`] samples per pixel, by each renderer.

use super::path::{mitsuba, ours};
use crate::scene::{Integrator, Scene, Shape};
use glam::Vec3;

/// The image's width; its height keeps the scene's aspect.
const WIDTH: u32 = 96;
/// Samples per pixel of each timed render.
const SPP: u32 = 64;
/// Samples per pixel of the reference.
const REFERENCE_SPP: u32 = 1024;

/// The mean squared error per channel of `a` against `b`.
fn mse(a: &[Vec3], b: &[Vec3]) -> f64 {
    super::path::rmse(a, b).powi(2)
}

/// The mean of `xs`.
fn mean(xs: &[f64]) -> f64 {
    xs.iter().sum::<f64>() / xs.len().max(1) as f64
}

/// How far an infinite plane reaches in this section: its stand-in triangle holds the disc of
/// this radius about the camera's foot on the plane.
const PLANE_REACH: f32 = 1000.0;

/// The scene as this section renders it: path-traced, [`WIDTH`] pixels wide, each infinite
/// plane replaced by one large triangle ([`plane_triangle`]), which both renderers trace (Mitsuba
/// has no infinite plane).
fn bench_scene(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.settings.integrator = Integrator::Path;
    let (w, h) = (s.camera.width.max(1), s.camera.height.max(1));
    s.camera.width = WIDTH;
    // A scene of any shape stays a benchmark's size: at most eight times as tall as wide.
    s.camera.height = ((WIDTH as f64 * h as f64 / w as f64).round() as u32).clamp(1, 8 * WIDTH);
    let eye = s.camera.from;
    let mut replaced = 0;
    for o in &mut s.objects {
        let (normal, offset) = match o.shape {
            Shape::Plane { normal, offset } => (normal, offset),
            Shape::AxisPlane { axis, offset } => (Vec3::AXES[axis.min(2)], offset),
            _ => continue,
        };
        o.shape = Shape::Triangle {
            p: plane_triangle(normal, offset, eye, PLANE_REACH),
        };
        replaced += 1;
    }
    // The counts the loader made, each plane now a triangle (the rest, instances included, stay).
    s.features.planes = s.features.planes.saturating_sub(replaced);
    s.features.triangles += replaced;
    s
}

/// The equilateral triangle in the plane X·n = offset, centred on the foot of `eye`, whose
/// inscribed circle has radius `reach` (its circumradius is twice that), wound so that its
/// geometric normal faces `eye` (Mitsuba's BSDFs are one-sided).
fn plane_triangle(normal: Vec3, offset: f32, eye: Vec3, reach: f32) -> [Vec3; 3] {
    // The scene's plane normals are unit vectors; `height` is the eye's signed distance.
    let n0 = normal.normalize_or(Vec3::Y);
    let height = eye.dot(n0) - offset;
    let foot = eye - n0 * height;
    let n = if height < 0.0 { -n0 } else { n0 };
    let (a, b) = n.any_orthonormal_pair();
    let corner = |k: f32| {
        let angle = k * std::f32::consts::TAU / 3.0;
        foot + (a * angle.cos() + b * angle.sin()) * (2.0 * reach)
    };
    let p = [corner(0.0), corner(1.0), corner(2.0)];
    if (p[1] - p[0]).cross(p[2] - p[0]).dot(n) < 0.0 {
        [p[0], p[2], p[1]]
    } else {
        p
    }
}

/// One renderer's figures on one scene: seconds per render and MSE, one per seed.
#[derive(Default)]
struct Runs {
    secs: Vec<f64>,
    mse: Vec<f64>,
    /// The renders' images summed (their mean's error bounds the renderer's bias).
    sum: Vec<Vec3>,
}

impl Runs {
    fn add(&mut self, secs: f64, pixels: &[Vec3], reference: &[Vec3]) {
        self.secs.push(secs);
        self.mse.push(mse(pixels, reference));
        if self.sum.is_empty() {
            self.sum = pixels.to_vec();
        } else {
            self.sum.iter_mut().zip(pixels).for_each(|(s, p)| *s += *p);
        }
    }
    /// The MSE of the renders' mean image: the noise divided by the renders, plus the squared
    /// bias.
    fn mean_image_mse(&self, reference: &[Vec3]) -> f64 {
        let n = self.secs.len().max(1) as f32;
        let m: Vec<Vec3> = self.sum.iter().map(|s| *s / n).collect();
        mse(&m, reference)
    }
}

/// The section: every scene of `scenes` with a Monte Carlo integrator, rendered `seeds` times
/// with seeds 0, 1, … by each renderer.
pub fn mc(scenes: &[Scene], seeds: usize) -> Result<(), String> {
    let seeds = seeds.max(2);
    let mc: Vec<&Scene> = scenes
        .iter()
        .filter(|s| s.settings.integrator != Integrator::Whitted)
        .collect();
    if mc.is_empty() {
        return Err(
            "--section mc needs Monte Carlo scenes (integrator = \"path\" or \
                    \"distribution\"), e.g. scenes/cornell-area.toml"
                .into(),
        );
    }
    crate::io::outln!(
        "Monte Carlo against Mitsuba 3 (scalar_rgb): each scene path-traced at {WIDTH} pixels wide, \
         {SPP} spp, {seeds} renders with seeds 0–{} (other random numbers), one thread each, raystep \
         counting nothing (as Mitsuba; `raystep render` counts rays and tests for its figures); MSE \
         against Mitsuba at {REFERENCE_SPP} spp (every core); time per sample = render time / \
         (pixels × spp); efficiency = 1 / (MSE × time)",
        seeds - 1
    );
    crate::io::outln!(
        "  {:<28} {:>10} {:>10} {:>7} {:>10} {:>10} {:>9} {:>9} {:>7}",
        "scene",
        "raystep",
        "Mitsuba",
        "time ×",
        "MSE ours",
        "MSE Mi",
        "eff ours",
        "eff Mi",
        "eff ×"
    );
    let (mut time_ratios, mut eff_ratios) = (vec![], vec![]);
    for scene in mc {
        let s = bench_scene(scene);
        let label = if scene.settings.integrator == Integrator::Path {
            s.name.clone()
        } else {
            format!("{} (path-traced)", s.name)
        };
        let reference = match mitsuba(&s, REFERENCE_SPP, 1_000_003, 0) {
            Ok((_, px)) => px,
            Err(e) => {
                crate::io::outln!("  {label}: skipped ({e})");
                continue;
            }
        };
        let (mut r, mut m) = (Runs::default(), Runs::default());
        for seed in 0..seeds as u32 {
            let (t, px, _) = ours(&s, SPP, seed, 1, false)?;
            r.add(t, &px, &reference);
            let (t, px) = mitsuba(&s, SPP, seed, 1)?;
            m.add(t, &px, &reference);
        }
        let samples = f64::from(s.camera.width) * f64::from(s.camera.height) * f64::from(SPP);
        let (tr, tm) = (mean(&r.secs), mean(&m.secs));
        let (er, em) = (mean(&r.mse), mean(&m.mse));
        let (fr, fm) = (1.0 / (er * tr), 1.0 / (em * tm));
        time_ratios.push(tr / tm);
        eff_ratios.push(fr / fm);
        crate::io::outln!(
            "  {:<28} {:>7.0} ns {:>7.0} ns {:>6.2}× {er:>10.3e} {em:>10.3e} {fr:>9.0} {fm:>9.0} {:>6.2}×",
            label,
            tr / samples * 1e9,
            tm / samples * 1e9,
            tr / tm,
            fr / fm
        );
        crate::io::outln!(
            "  {:<28} the mean of the {seeds} renders: MSE {:.3e} (raystep), {:.3e} (Mitsuba) — noise / {seeds} + bias²",
            "",
            r.mean_image_mse(&reference),
            m.mean_image_mse(&reference)
        );
        // Where raystep's time goes, on one thread (`raystep render --profile`'s method).
        let mut small = s.clone();
        small.settings.spp = 4;
        let prepared = crate::PreparedScene::new(small);
        let st = crate::bench::measure_stages(prepared.scene(), prepared.accel(), 1);
        let [c, tv, te, sh] = st.shares();
        crate::io::outln!(
            "  {:<28} raystep's time: camera rays {c}, traversal {tv}, primitive tests {te}, shading, sampling and spawning {sh}",
            ""
        );
    }
    if !time_ratios.is_empty() {
        let worst = |v: &[f64], f: fn(f64, f64) -> f64, init: f64| v.iter().copied().fold(init, f);
        crate::io::outln!(
            "  raystep / Mitsuba: time per sample {:.2}× to {:.2}× (goal ≤ 1), efficiency {:.2}× to {:.2}× (goal ≥ 1.5)",
            worst(&time_ratios, f64::min, f64::INFINITY),
            worst(&time_ratios, f64::max, 0.0),
            worst(&eff_ratios, f64::min, f64::INFINITY),
            worst(&eff_ratios, f64::max, 0.0),
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bench_scene_keeps_the_aspect_and_path_traces() {
        let mut s = crate::scene::default_scene();
        s.camera.width = 320;
        s.camera.height = 200;
        s.settings.integrator = Integrator::Distribution;
        let b = bench_scene(&s);
        assert_eq!((b.camera.width, b.camera.height), (96, 60));
        assert_eq!(b.settings.integrator, Integrator::Path);
        // A strip a pixel wide and a million tall: 96 wide and 768 (8 × 96) tall, not 96 million.
        s.camera.width = 1;
        s.camera.height = 1_000_000;
        let b = bench_scene(&s);
        assert_eq!((b.camera.width, b.camera.height), (96, 768));
    }

    #[test]
    fn a_plane_becomes_a_triangle_in_it_that_faces_the_eye_and_covers_the_reach() {
        // The floor y = 0 seen from above, and the same plane written with the normal down.
        let eye = Vec3::new(3.0, 2.0, -5.0);
        for (normal, offset) in [(Vec3::Y, 0.0), (-Vec3::Y, 0.0)] {
            let p = plane_triangle(normal, offset, eye, 10.0);
            assert!(p.iter().all(|q| q.y.abs() < 1e-5), "{p:?}");
            // Wound towards the eye: the normal by hand is +y.
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
            assert!((n - Vec3::Y).length() < 1e-5, "{n}");
            // The centroid is the eye's foot, (3, 0, −5); every corner 20 from it (the
            // circumradius of an incircle of radius 10).
            let c = (p[0] + p[1] + p[2]) / 3.0;
            assert!((c - Vec3::new(3.0, 0.0, -5.0)).length() < 1e-4, "{c}");
            assert!(p.iter().all(|q| ((*q - c).length() - 20.0).abs() < 1e-3));
        }
        // A tilted plane x + y = 2 (n = (1, 1, 0)/√2, offset √2), the eye below it at the origin.
        let n = Vec3::new(1.0, 1.0, 0.0).normalize();
        let p = plane_triangle(n, 2f32.sqrt(), Vec3::ZERO, 5.0);
        assert!(p.iter().all(|q| (q.x + q.y - 2.0).abs() < 1e-4), "{p:?}");
        let m = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
        assert!((m + n).length() < 1e-5, "faces the origin: {m}");
    }

    #[test]
    fn a_scenes_planes_are_traced_as_triangles_by_both_renderers() {
        let s = crate::scene::load_file(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/scenes/depth-of-field.toml"
        )))
        .unwrap();
        assert!(s.features.planes > 0);
        let b = bench_scene(&s);
        assert_eq!(b.features.planes, 0);
        assert_eq!(
            b.features.triangles,
            s.features.triangles + s.features.planes
        );
        assert_eq!(b.objects.len(), s.objects.len());
        assert!(crate::scene::mitsuba::to_mitsuba(&b, 4, "scene").is_ok());
    }

    #[test]
    fn the_error_is_per_channel_and_the_mean_images_error_falls_with_the_renders() {
        let reference = vec![Vec3::splat(1.0); 2];
        // By hand: (0.5² + 0 + 0) / 3 and 0, averaged over the two pixels.
        assert!(
            (mse(&[Vec3::new(1.5, 1.0, 1.0), Vec3::ONE], &reference) - 0.25 / 6.0).abs() < 1e-12
        );
        let mut r = Runs::default();
        r.add(1.0, &[Vec3::splat(1.5), Vec3::splat(0.5)], &reference);
        r.add(1.0, &[Vec3::splat(0.5), Vec3::splat(1.5)], &reference);
        assert!((mean(&r.mse) - 0.25).abs() < 1e-12);
        // Opposite errors cancel in the mean image.
        assert_eq!(r.mean_image_mse(&reference), 0.0);
    }
}
