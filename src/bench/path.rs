//! `raystep bench --section path`: the path tracer's speed, and its time to a given error
//! beside Mitsuba 3's on the same scene and machine.

use crate::PreparedScene;
use crate::render::{RenderOptions, render};
use crate::scene::{Integrator, Scene};
use glam::Vec3;
use std::time::Instant;

pub(super) fn rmse(a: &[Vec3], b: &[Vec3]) -> f64 {
    let s: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (*x - *y).as_dvec3().length_squared() / 3.0)
        .sum();
    (s / a.len().max(1) as f64).sqrt()
}

/// Renders `scene` at `spp` with `threads`: (seconds, pixels, rays). With `count` false the
/// render takes the silent observer, as Mitsuba counts nothing (its rays are then 0): counting
/// rays, tests and box visits, as `raystep render` does for its statistics, costs the Cornell
/// box 7 % of its instructions.
pub(super) fn ours(
    scene: &Scene,
    spp: u32,
    seed: u32,
    threads: usize,
    count: bool,
) -> Result<(f64, Vec<Vec3>, u64), String> {
    let mut s = scene.clone();
    s.settings.spp = spp;
    s.settings.seed = seed;
    let prepared = PreparedScene::new(s);
    let t = Instant::now();
    let out = render(
        &prepared.tracer(),
        &RenderOptions {
            threads: Some(threads),
            count,
            ..Default::default()
        },
    )?;
    Ok((
        t.elapsed().as_secs_f64(),
        out.pixels,
        out.stats.counts.rays(),
    ))
}

/// Renders `scene` with Mitsuba 3 (`python3`, `scalar_rgb`) on `threads` threads (0: Mitsuba's
/// default, every core): (seconds of `mi.render`, pixels).
pub(super) fn mitsuba(
    scene: &Scene,
    spp: u32,
    seed: u32,
    threads: usize,
) -> Result<(f64, Vec<Vec3>), String> {
    let dir = std::env::temp_dir().join(format!("raystep-bench-mitsuba-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let m = crate::scene::mitsuba::to_mitsuba(scene, spp, "scene")?;
    m.write_files(&dir)?;
    std::fs::write(dir.join("scene.xml"), &m.xml).map_err(|e| e.to_string())?;
    // Mitsuba 3.9's OpenEXR reads and writes wait on Dr.Jit's thread pool and hang for good when
    // it has one thread: the scene (its textures) is loaded and the image written with every
    // core; only `mi.render` runs on `threads`.
    let script = "import sys, time, drjit as dr, mitsuba as mi\nmi.set_variant('scalar_rgb')\nscene = mi.load_file(sys.argv[1])\ncores = dr.thread_count()\nif int(sys.argv[4]) > 0:\n    dr.set_thread_count(int(sys.argv[4]))\nt = time.perf_counter()\nimg = mi.render(scene, seed=int(sys.argv[3]))\nprint(time.perf_counter() - t)\ndr.set_thread_count(cores)\nmi.util.write_bitmap(sys.argv[2], img, write_async=False)\n";
    let exr = dir.join("out.exr");
    let out = std::process::Command::new("python3")
        .args(["-c", script])
        .arg(dir.join("scene.xml"))
        .arg(&exr)
        .arg(seed.to_string())
        .arg(threads.to_string())
        .output()
        .map_err(|e| format!("cannot run python3: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "Mitsuba 3 did not render (python3 -m pip install mitsuba): {}",
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    let secs: f64 = String::from_utf8_lossy(&out.stdout)
        .trim()
        .parse()
        .map_err(|_| "Mitsuba printed no time".to_string())?;
    let (_, _, px) = crate::render::image::read_exr(&exr)?;
    let _ = std::fs::remove_dir_all(&dir);
    Ok((secs, px))
}

/// The section: the scene (a path-traced one; `cornell-area.toml` by default) at 128×128.
pub fn path(scene: &Scene, reps: usize) -> Result<(), String> {
    let mut s = scene.clone();
    s.settings.integrator = Integrator::Path;
    s.camera.width = 128;
    s.camera.height = 128;
    crate::io::outln!("path tracing: \"{}\" at 128×128", s.name);
    for threads in [1, 2] {
        let mut times = vec![];
        let mut rays = 0;
        for r in 0..reps.max(1) {
            let (t, _, n) = ours(&s, 16, r as u32, threads, true)?;
            times.push(t);
            rays = n;
        }
        times.sort_by(f64::total_cmp);
        let t = times[times.len() / 2];
        crate::io::outln!(
            "  {threads} thread{}: 16 spp in {:.0} ms, {:.2} Mrays/s (BVH; every ray counted: camera, shadow and bounce)",
            if threads == 1 { "" } else { "s" },
            t * 1e3,
            rays as f64 / t / 1e6
        );
    }
    // Time to equal error: a reference rendered by Mitsuba at 1024 spp; each renderer at 64 spp,
    // timed, its RMSE against the reference; Monte Carlo error falls as 1/√time, so the time to
    // reach an RMSE e is t · (rmse / e)².
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let (_, reference) = match mitsuba(&s, 1024, 99, 0) {
        Ok(r) => r,
        Err(e) => {
            crate::io::outln!("  against Mitsuba 3: skipped ({e})");
            return Ok(());
        }
    };
    let (tm, pm) = mitsuba(&s, 64, 1, 0)?;
    let (to, po, _) = ours(&s, 64, 1, threads, false)?;
    let (em, eo) = (rmse(&pm, &reference), rmse(&po, &reference));
    let target = em.min(eo);
    let (qm, qo) = (tm * (em / target).powi(2), to * (eo / target).powi(2));
    crate::io::outln!(
        "  against Mitsuba 3 scalar_rgb ({threads} threads each), reference Mitsuba 1024 spp:\n    64 spp: raystep {:.0} ms, RMSE {eo:.4}; Mitsuba {:.0} ms, RMSE {em:.4}\n    time to RMSE {target:.4}: raystep {:.0} ms, Mitsuba {:.0} ms (raystep {:.2}× Mitsuba's time)",
        to * 1e3,
        tm * 1e3,
        qo * 1e3,
        qm * 1e3,
        qo / qm
    );
    Ok(())
}
