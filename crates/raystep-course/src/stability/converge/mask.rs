//! Which pixels `converge` measures: every pixel but those that see a light source directly.
//!
//! A pixel whose footprint holds the edge of a lamp seen by the camera averages a radiance of
//! hundreds (the lamp) with one of about one (what lies around it). Its error at a few samples
//! per pixel is how many of its camera samples happened to land on the lamp: the aliasing of
//! the edge, thousands of times larger than the noise of the light estimate anywhere else, and
//! the same whatever sampler estimates the light. Left in, those few pixels are the image's MSE
//! (on `scenes/soft-shadows.toml` the MSE then rises from 1 to 2 samples per pixel and does not
//! tell stratified from independent samples). So the Monte Carlo integrators' errors are
//! measured over the other pixels; the MSE over every pixel is still reported beside it.
//!
//! The pixels left out are found by tracing the scene's own camera samples (pixel jitter and,
//! with a thin lens, lens points) and keeping those whose first hit emits, then adding their
//! eight neighbours: a lamp covering a sliver of a pixel too small for any traced sample to
//! land on lies beside a pixel where one did.

use crate::record::observer::Observer;
use crate::record::{HitRecord, RayKind};
use crate::trace::PreparedScene;
use glam::Vec3;

/// Camera samples per pixel traced to find the pixels that see a light source.
pub const MASK_SAMPLES: u32 = 16;

/// Seeds of [`MASK_SAMPLES`] camera samples each (the levels use seeds 1, 2, …).
const MASK_SEEDS: u32 = 2;

/// Keeps whether the camera ray's first hit is one of the emitting objects.
struct FirstHit<'a> {
    emits: &'a [bool],
    open: usize,
    seen: bool,
}

impl Observer for FirstHit<'_> {
    const RECORDS: bool = false;
    fn begin_ray(&mut self, _: RayKind, _: u32, _: &crate::math::Ray<f32>, _: f32) {
        self.open += 1;
    }
    fn end_ray(&mut self, hit: impl FnOnce() -> Option<HitRecord>, _: Vec3) {
        if self.open == 1
            && let Some(h) = hit()
        {
            self.seen |= self.emits.get(h.object as usize).copied().unwrap_or(false);
        }
        self.open = self.open.saturating_sub(1);
    }
}

/// Per pixel (row-major), whether `converge` leaves it out: it sees a light source directly, or
/// lies next to one that does. Nothing is left out under Whitted (it does not show emission)
/// or in a scene with nothing that emits.
/// `base` is the scene prepared once (its accelerator is reused).
pub fn direct_emitters(base: &PreparedScene) -> Vec<bool> {
    let scene = base.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let n = (w as usize) * (h as usize);
    let emits: Vec<bool> = (0..scene.objects.len() as u32)
        .map(|id| scene.material_of(id).emission.max_element() > 0.0)
        .collect();
    if !scene.settings.integrator.is_monte_carlo() || !emits.iter().any(|e| *e) {
        return vec![false; n];
    }
    let mut seen = vec![false; n];
    for seed in 1..=MASK_SEEDS {
        // Only the camera rays matter: no bounce is followed.
        let mut settings = scene.settings.clone();
        settings.spp = MASK_SAMPLES;
        settings.seed = seed;
        settings.max_depth = 0;
        let prepared = PreparedScene::with_settings(base.scene_arc(), &settings, Some(base));
        let tracer = prepared.tracer();
        for y in 0..h {
            for x in 0..w {
                let i = (y * w + x) as usize;
                if seen[i] {
                    continue;
                }
                for k in 0..MASK_SAMPLES {
                    let mut obs = FirstHit {
                        emits: &emits,
                        open: 0,
                        seen: false,
                    };
                    tracer.trace_sample(x, y, k, &mut obs);
                    if obs.seen {
                        seen[i] = true;
                        break;
                    }
                }
            }
        }
    }
    // With the eight neighbours.
    let mut out = seen.clone();
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            if !seen[(y * w as i64 + x) as usize] {
                continue;
            }
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (xx, yy) = (x + dx, y + dy);
                    if xx >= 0 && yy >= 0 && xx < w as i64 && yy < h as i64 {
                        out[(yy * w as i64 + xx) as usize] = true;
                    }
                }
            }
        }
    }
    out
}
