//! The two-level acceleration structure of Vulkan's and DirectX's ray-tracing APIs: a
//! bottom-level BVH (BLAS) per prototype, built once in its object space however many instances
//! place it, and a top-level BVH (TLAS) over the instances' world boxes.
//!
//! A query first asks the world's own accelerator (the scene's objects that are not
//! prototypes), then walks the TLAS with the world ray: a node's box is tested, an inner node's
//! two children are pushed (the one whose centre lies nearer along the ray on top), a leaf's
//! instances are entered. Entering an instance carries the ray into its object space by M⁻¹
//! (`Step::Instance`) and walks the prototype's BLAS with it (its node visits name the
//! instance); a hit there becomes the closest so far and shortens the world ray, which the
//! next TLAS boxes are tested against.

use super::{Accelerator, Bvh, Hit, SceneAccel, bvh::FastRay, bvh::Tlas, bvh::Todo};
use crate::math::Ray;
use crate::platform::{Duration, Instant};
use crate::record::{HitRecord, NodeAction, NodeVisit, Observer, RayKind, Step};
use crate::scene::Scene;
use crate::shapes::aabb::slab_robust;
use glam::{Vec3, Vec3A};

/// The world's accelerator, the TLAS and one BLAS per prototype.
pub struct TwoLevel {
    /// The accelerator of the world's own objects (the scene's `accel` choice).
    pub world: SceneAccel,
    /// The tree over the instances.
    pub tlas: Tlas,
    /// One tree per prototype ([`Scene::prototypes`]), in object space.
    pub blas: Vec<Bvh>,
    /// Time to build the TLAS.
    pub tlas_time: Duration,
    /// Time to build every BLAS.
    pub blas_time: Duration,
}

impl TwoLevel {
    /// Builds the BLAS of each prototype (once each) and the TLAS over the instances, around an
    /// already built world accelerator.
    pub fn build(scene: &Scene, world: SceneAccel) -> TwoLevel {
        let start = Instant::now();
        let blas = scene
            .prototypes
            .iter()
            .map(|p| {
                let g = &scene.groups[p.group as usize];
                Bvh::build_over(scene, g.first as usize..(g.first + g.count) as usize)
            })
            .collect();
        let blas_time = start.elapsed();
        let start = Instant::now();
        let tlas = Tlas::build(&scene.instances, scene.settings.bvh_quality);
        TwoLevel {
            world,
            tlas,
            blas,
            tlas_time: start.elapsed(),
            blas_time,
        }
    }

    /// Bytes the structures take: the world's, the TLAS and every BLAS (the instances' matrices
    /// are the scene's).
    pub fn memory(&self) -> usize {
        self.world.memory() + self.tlas.memory() + self.blas.iter().map(Bvh::memory).sum::<usize>()
    }

    /// The TLAS walk alone, for the benchmark that times the two levels apart: the instances
    /// whose boxes `ray` reaches (its whole interval, no hit shortening it), none entered.
    pub fn instances_reached(&self, ray: &Ray<f32>) -> u32 {
        let inv = Vec3::ONE / ray.dir;
        let mut stack = Todo::new();
        stack.push(0, 0, false);
        let mut reached = 0;
        while let Some((n, _)) = stack.pop(false) {
            let Some(node) = self.tlas.nodes.get(n as usize) else {
                continue;
            };
            if !slab_robust(ray, inv, Vec3::from(node.min), Vec3::from(node.max)).hit {
                continue;
            }
            if node.is_leaf() {
                reached += node.count;
            } else {
                stack.push(node.first + 1, 0, false);
                stack.push(node.first, 0, false);
            }
        }
        reached
    }

    /// Walks the TLAS for `r`, entering the instances whose boxes it reaches. `closest`: keep
    /// the nearest hit (shortening `r`); otherwise stop at the first.
    #[inline(always)]
    fn walk<O: Observer>(
        &self,
        scene: &Scene,
        r: &mut Ray<f32>,
        closest: bool,
        best: &mut Option<Hit>,
        obs: &mut O,
    ) {
        if self.tlas.nodes.is_empty() {
            return;
        }
        let inv = Vec3::ONE / r.dir;
        // The ray prepared for the BVH's 128-bit slab test: lane for lane the robust test's
        // operations (NaN handled as it does), so each decision is the recorded test's, which
        // only an observer that records builds.
        let fast = FastRay::new(r, inv);
        // (node, depth): the BVH's own list of subtrees to visit, on the machine stack (no
        // allocation per ray); the depths are kept only when the observer records them.
        let mut stack = Todo::new();
        stack.push(0, 0, O::RECORDS);
        while let Some((n, depth)) = stack.pop(O::RECORDS) {
            let Some(node) = self.tlas.nodes.get(n as usize) else {
                continue;
            };
            // t_max as it is now (an instance's hit shortens it); origin, direction and t_min
            // never change.
            let (t_near, t_far) = fast.interval::<false>(node, Vec3A::splat(r.t_max));
            let action = match (t_near <= t_far, node.is_leaf()) {
                (false, _) => NodeAction::Culled,
                (true, true) => NodeAction::TestPrimitives,
                (true, false) => NodeAction::Descend,
            };
            obs.accel_visit(|| {
                Step::TlasNode(NodeVisit {
                    node: n,
                    depth,
                    test: slab_robust(r, inv, Vec3::from(node.min), Vec3::from(node.max)),
                    leaf: node.is_leaf(),
                    children: (!node.is_leaf()).then_some([node.first, node.first + 1]),
                    action,
                    instance: None,
                })
            });
            match action {
                NodeAction::Culled | NodeAction::Pushed => {}
                NodeAction::Descend => {
                    let (a, b) = (node.first, node.first + 1);
                    let along = |c: u32| {
                        self.tlas.nodes.get(c as usize).map_or(f32::INFINITY, |m| {
                            ((Vec3::from(m.min) + Vec3::from(m.max)) * 0.5 - r.origin).dot(r.dir)
                        })
                    };
                    // The nearer on top, so it is taken next; ties: `a` first.
                    if along(a) <= along(b) {
                        stack.push(b, depth + 1, O::RECORDS);
                        stack.push(a, depth + 1, O::RECORDS);
                    } else {
                        stack.push(a, depth + 1, O::RECORDS);
                        stack.push(b, depth + 1, O::RECORDS);
                    }
                }
                NodeAction::TestPrimitives => {
                    for &i in self.tlas.leaf(node) {
                        if self.enter(scene, i, r, closest, best, obs) && !closest {
                            return;
                        }
                    }
                }
            }
        }
    }

    /// Enters instance `i`: the ray into its object space, its BLAS walked. Returns whether it
    /// found a hit (the closest so far, for a closest-hit query).
    #[inline(always)]
    fn enter<O: Observer>(
        &self,
        scene: &Scene,
        i: u32,
        r: &mut Ray<f32>,
        closest: bool,
        best: &mut Option<Hit>,
        obs: &mut O,
    ) -> bool {
        let Some(inst) = scene.instances.get(i as usize) else {
            return false;
        };
        let Some(blas) = self.blas.get(inst.prototype as usize) else {
            return false;
        };
        let local = inst.to_object.ray(r);
        obs.step(|| Step::Instance {
            instance: i,
            name: inst.name.clone(),
            prototype: scene.groups[inst.group as usize].name.clone(),
            to_object: inst.to_object.0,
            origin: local.origin.to_array(),
            direction: local.dir.to_array(),
        });
        let mut inner = InBlas { obs, instance: i };
        let found = if closest {
            blas.closest(scene, &local, &mut inner)
        } else {
            blas.any(scene, &local, &mut inner)
        };
        match found {
            Some(mut h) => {
                h.instance = i;
                r.t_max = h.t;
                *best = Some(h);
                true
            }
            None => false,
        }
    }
}

impl Accelerator for TwoLevel {
    #[inline]
    fn closest<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        let mut best = self.world.closest(scene, ray, obs);
        let mut r = *ray;
        if let Some(h) = &best {
            r.t_max = h.t;
        }
        self.walk(scene, &mut r, true, &mut best, obs);
        best
    }

    #[inline]
    fn any<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        if let Some(h) = self.world.any(scene, ray, obs) {
            return Some(h);
        }
        let mut best = None;
        let mut r = *ray;
        self.walk(scene, &mut r, false, &mut best, obs);
        best
    }

    fn name(&self) -> &'static str {
        "TLAS/BLAS"
    }

    fn outline(&self, depth: u32) -> Option<Vec<crate::record::OutlineNode>> {
        self.world.outline(depth)
    }
}

/// The observer inside an instance's BLAS: everything passes through, the node visits marked
/// with the instance (they are nodes of the prototype's tree, not of the world's).
struct InBlas<'a, O> {
    obs: &'a mut O,
    instance: u32,
}

impl<O: Observer> Observer for InBlas<'_, O> {
    const RECORDS: bool = O::RECORDS;
    #[inline(always)]
    fn begin_ray(&mut self, kind: RayKind, depth: u32, ray: &Ray<f32>, weight: f32) {
        self.obs.begin_ray(kind, depth, ray, weight);
    }
    #[inline(always)]
    fn prim_test(&mut self, step: impl FnOnce() -> Step) {
        self.obs.prim_test(step);
    }
    #[inline(always)]
    fn prim_tests(&mut self, n: usize, step: impl FnMut(usize) -> Step) {
        self.obs.prim_tests(n, step);
    }
    #[inline(always)]
    fn node_visit(&mut self, visit: impl FnOnce() -> NodeVisit) {
        let i = self.instance;
        self.obs.node_visit(|| NodeVisit {
            instance: Some(i),
            ..visit()
        });
    }
    #[inline(always)]
    fn accel_visit(&mut self, step: impl FnOnce() -> Step) {
        self.obs.accel_visit(step);
    }
    #[inline(always)]
    fn step(&mut self, step: impl FnOnce() -> Step) {
        self.obs.step(step);
    }
    #[inline(always)]
    fn end_ray(&mut self, hit: impl FnOnce() -> Option<HitRecord>, color: Vec3) {
        self.obs.end_ray(hit, color);
    }
}
