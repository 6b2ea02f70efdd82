//! A scene ready to trace: the validated scene, its settings applied, and its accelerator,
//! built once and shared read-only by everything that traces it — the command line, the app's
//! background render and stepped pixel, the lessons and exercises, and the GPU (which flattens
//! the same BVH instead of building its own).

use super::tracer::Tracer;
use crate::accel::{SceneAccel, bvh::Bvh};
use crate::record::Trace;
use crate::scene::{AccelChoice, Features, Scene, Settings};
use std::sync::Arc;
use std::time::Duration;

/// A scene with its accelerator built (see the [module documentation](self)).
///
/// ```
/// use raystep_core::PreparedScene;
/// use raystep_core::record::Silent;
///
/// let prepared = PreparedScene::new(raystep_core::scene::default_scene());
/// // The stepped pixel: every step recorded.
/// let trace = prepared.record(160, 120, 0);
/// // The render's pixel: the same tracer, nothing recorded.
/// let colour = prepared.tracer().trace_sample(160, 120, 0, &mut Silent);
/// assert_eq!(trace.color, colour.to_array());
/// ```
pub struct PreparedScene {
    scene: Arc<Scene>,
    accel: Arc<SceneAccel>,
    accel_choice: AccelChoice,
    build: Duration,
}

impl PreparedScene {
    /// Prepares `scene`: builds the accelerator its settings ask for (`auto` resolved by its
    /// primitive count).
    pub fn new(scene: Scene) -> PreparedScene {
        PreparedScene::shared(Arc::new(scene))
    }

    /// Prepares a scene already shared.
    pub fn shared(scene: Arc<Scene>) -> PreparedScene {
        let accel_choice = SceneAccel::resolve(&scene);
        let (accel, build) = SceneAccel::build(&scene);
        PreparedScene {
            scene,
            accel: Arc::new(accel),
            accel_choice,
            build,
        }
    }

    /// Prepares `base` with `settings`, reusing `previous`'s accelerator when it was built for
    /// the same geometry with the same resolved choice (changing a method or the samples per
    /// pixel does not rebuild the BVH of a million triangles).
    pub fn with_settings(
        base: &Arc<Scene>,
        settings: &Settings,
        previous: Option<&PreparedScene>,
    ) -> PreparedScene {
        let scene = if base.settings == *settings {
            Arc::clone(base)
        } else {
            let mut s = Scene::clone(base);
            s.settings = settings.clone();
            Arc::new(s)
        };
        let choice = SceneAccel::resolve(&scene);
        match previous {
            Some(p)
                if p.accel_choice == choice
                    && p.scene.settings.bvh_quality == scene.settings.bvh_quality
                    && same_geometry(&p.scene, &scene) =>
            {
                PreparedScene {
                    scene,
                    accel: Arc::clone(&p.accel),
                    accel_choice: choice,
                    build: Duration::ZERO,
                }
            }
            _ => PreparedScene::shared(scene),
        }
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The scene, shared.
    pub fn scene_arc(&self) -> &Arc<Scene> {
        &self.scene
    }

    /// The scene's features.
    pub fn features(&self) -> &Features {
        &self.scene.features
    }

    /// The accelerator.
    pub fn accel(&self) -> &SceneAccel {
        &self.accel
    }

    /// The accelerator built (`auto` resolved).
    pub fn accel_choice(&self) -> AccelChoice {
        self.accel_choice
    }

    /// The scene's BVH, when it uses one.
    pub fn bvh(&self) -> Option<&Bvh> {
        match self.accel.as_ref() {
            SceneAccel::Bvh(b) => Some(b),
            SceneAccel::TwoLevel(t) => match &t.world {
                SceneAccel::Bvh(b) => Some(b),
                _ => None,
            },
            SceneAccel::Brute(_) | SceneAccel::Spheres(_) | SceneAccel::Grid(_) => None,
        }
    }

    /// How long building the accelerator took (zero when it was reused).
    pub fn build_time(&self) -> Duration {
        self.build
    }

    /// The one tracer, over this scene and its accelerator.
    pub fn tracer(&self) -> Tracer<'_, SceneAccel> {
        Tracer::new(&self.scene, &self.accel)
    }

    /// Records pixel (`x`, `y`), sample `sample`: the trace the app steps through.
    pub fn record(&self, x: u32, y: u32, sample: u32) -> Trace {
        self.tracer().record(x, y, sample)
    }
}

impl std::fmt::Debug for PreparedScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PreparedScene")
            .field("scene", &self.scene.name)
            .field("accel_choice", &self.accel_choice)
            .field("build", &self.build)
            .finish_non_exhaustive()
    }
}

/// Whether two scenes share their geometry (same file text and objects).
fn same_geometry(a: &Scene, b: &Scene) -> bool {
    a.source_hash == b.source_hash
        && a.path == b.path
        && a.objects.len() == b.objects.len()
        && a.objects == b.objects
}
