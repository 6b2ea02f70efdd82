//! A bounding volume hierarchy: built by obvhs (`Bvh2`, PLOC + reinsertion), traversed by
//! raystep's own loop so that every node visit can be observed.
//!
//! The traversal follows obvhs's `ray_traverse_dynamic` (test both children of a node, visit the
//! nearer first, push the farther), with docs/NUMERICS.md's robust slab test instead of obvhs's: true
//! IEEE reciprocals (obvhs clamps tiny components, giving false misses for near-parallel rays,
//! S21), the ray's own t_min honoured (S23), and `<=` so flat boxes are hit (S22). Infinite planes
//! stay outside the tree: they are tested first and their hit tightens t_max.

use super::{
    Accelerator, Hit, PerRay, accept, any_of, closest_of, test_any_shape, test_closest_shape,
    tie_ray, triangle_step,
};
use crate::math::Ray;
use crate::record::OutlineNode;
use crate::record::{NodeAction, NodeVisit, Observer};
use crate::scene::{BvhQuality, Scene, Shape};
use crate::shapes::aabb::slab_robust;
use crate::shapes::triangle::{self, Shear, TriangleMethod};
use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::bvh2::{Bvh2, builder::build_bvh2};
use obvhs::{Boundable, BvhBuildParams};
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// How many levels of the tree the outline keeps (the ray tree diagram asks for at most this).
const OUTLINE_DEPTH: u32 = 6;

struct PrimBox(Aabb);

impl Boundable for PrimBox {
    fn aabb(&self) -> Aabb {
        self.0
    }
}

/// The box of a finite shape, rounded outwards by one float so it contains the shape's points
/// as the kernels compute them.
pub fn shape_bounds(shape: &Shape) -> Option<(Vec3, Vec3)> {
    let (lo, hi) = match *shape {
        Shape::Sphere { center, radius } => {
            (center - Vec3::splat(radius), center + Vec3::splat(radius))
        }
        Shape::Triangle { p } => (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2])),
        Shape::Plane { .. } | Shape::AxisPlane { .. } => return None,
    };
    let down = |v: Vec3| Vec3::new(v.x.next_down(), v.y.next_down(), v.z.next_down());
    let up = |v: Vec3| Vec3::new(v.x.next_up(), v.y.next_up(), v.z.next_up());
    match shape {
        Shape::Sphere { .. } => Some((down(lo), up(hi))),
        // Triangle boxes are exact: the vertices are the extremes.
        _ => Some((lo, hi)),
    }
}

/// What a leaf slot holds should an id be out of range (it never is: obvhs's indices are into
/// the boxes it was given): a sphere no ray can hit.
const EMPTY_SHAPE: Shape = Shape::Sphere {
    center: Vec3::ZERO,
    radius: 0.0,
};

/// obvhs's preset for a build quality.
fn build_params(quality: BvhQuality) -> BvhBuildParams {
    match quality {
        BvhQuality::Low => BvhBuildParams::very_fast_build(),
        BvhQuality::Medium => BvhBuildParams::medium_build(),
        BvhQuality::High => BvhBuildParams::slow_build(),
    }
}

/// The traversal's list of subtrees still to visit (first child index, and the children's depth
/// when the observer records): the first 32 indices in an array on the machine stack, any beyond
/// (a tree deeper than 32 levels on a ray that defers a subtree at every level) in a vector.
/// Written out rather than a `SmallVec` because its push and pop are the traversal's inner loop;
/// `records` (the observer's constant) keeps the depths, in a vector, only when they are recorded.
struct Todo {
    first: [u32; 32],
    len: usize,
    spill: Vec<u32>,
    depth: Vec<u32>,
}

impl Todo {
    #[inline(always)]
    fn new() -> Self {
        Todo {
            first: [0; 32],
            len: 0,
            spill: Vec::new(),
            depth: Vec::new(),
        }
    }

    #[inline(always)]
    fn push(&mut self, first: u32, depth: u32, records: bool) {
        if records {
            self.depth.push(depth);
        }
        match self.first.get_mut(self.len) {
            Some(f) => {
                *f = first;
                self.len += 1;
            }
            None => self.spill.push(first),
        }
    }

    #[inline(always)]
    fn pop(&mut self, records: bool) -> Option<(u32, u32)> {
        let first = match self.spill.pop() {
            Some(top) => top,
            None => {
                self.len = self.len.checked_sub(1)?;
                *self.first.get(self.len)?
            }
        };
        let depth = if records { self.depth.pop()? } else { 0 };
        Some((first, depth))
    }
}

mod ray_box;
mod tri4;
use ray_box::FastRay;
use tri4::{NO_PACK, Tri4};

/// One node of the tree in raystep's own layout (box, and either two children or a leaf range).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Node {
    /// Box minimum (16-byte aligned for the SIMD slab test).
    pub min: Vec3A,
    /// Box maximum.
    pub max: Vec3A,
    /// Leaf: index of its first object in [`Bvh::leaf_objects`]; inner: index of its first child
    /// (the second is `first + 1`).
    pub first: u32,
    /// Number of objects in a leaf; 0 for an inner node.
    pub count: u32,
    /// A leaf of triangles only: index of its first [`Tri4`] pack in [`Bvh::packs`] (the AVX2
    /// build tests four triangles at once); otherwise [`NO_PACK`]. (The node's padding: it
    /// stays 48 bytes.)
    pack: u32,
}

impl Node {
    /// Whether the node is a leaf.
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// A BVH over a scene's finite primitives, plus the list of its planes.
pub struct Bvh {
    /// The nodes; `nodes[0]` is the root.
    pub nodes: Vec<Node>,
    /// Object ids in leaf order.
    pub leaf_objects: Vec<u32>,
    /// Their shapes, in the same order: a leaf's primitives lie side by side in memory, as the
    /// traversal reads them (the scene's own list is in file order).
    leaf_shapes: Vec<Shape>,
    /// The triangles of the leaves that hold only triangles, four to a pack (see [`Node`]'s
    /// `pack`), for the four-lane watertight test of the AVX2 build.
    packs: Vec<Tri4>,
    /// Infinite primitives (planes), tested before the tree.
    pub planes: Vec<u32>,
    /// The tree's depth.
    pub max_depth: usize,
    /// Wall time of the whole build (boxes, obvhs's build, raystep's layout).
    pub build_time: Duration,
    /// Wall time of obvhs's core build alone.
    pub core_time: Duration,
    /// The top levels of the tree for diagrams (see [`Accelerator::outline`]).
    pub outline: Vec<OutlineNode>,
    /// obvhs's tree itself, in the order its builder left the nodes (kept for comparisons
    /// with its own traversal; [`Bvh::nodes`] is the same tree in depth-first order).
    pub obvhs: Bvh2,
    /// Whether every node's box is finite (then a ray with a finite origin and reciprocals takes
    /// the box test without NaN handling).
    finite_boxes: bool,
    /// Whether queries take the AVX2 + FMA build: decided once, at build time, so a query reads
    /// a field of the tree rather than process-wide flags (shared cache lines that other threads
    /// may be writing next to).
    wide: bool,
    /// Whether the AVX2 build asks the CPU to prefetch what lies below each pair it tests: only
    /// for trees too big for the caches (see [`PREFETCH_FROM`]).
    prefetch: bool,
    /// [`Bvh::sah_cost`], computed when first asked (the app shows it every frame).
    sah: std::sync::OnceLock<f64>,
}

impl Bvh {
    /// Builds the tree over the scene's finite objects with the obvhs preset of the scene's
    /// [`BvhQuality`].
    pub fn build(scene: &Scene) -> Bvh {
        let start = Instant::now();
        // Boxes, the tree's layout and the leaf-ordered shapes are computed in parallel on big
        // scenes (on a million triangles these steps took 100 ms of a 520 ms build serially);
        // the result does not depend on the thread count. A plane gets an empty box here, and
        // only a scene with planes pays for a second pass that leaves them out.
        let all = map_in_order(&scene.objects, |o| match shape_bounds(&o.shape) {
            Some((lo, hi)) => PrimBox(Aabb::new(Vec3A::from(lo), Vec3A::from(hi))),
            None => PrimBox(Aabb::INVALID),
        });
        let planes: Vec<u32> = scene
            .objects
            .iter()
            .enumerate()
            .filter(|(_, o)| shape_bounds(&o.shape).is_none())
            .map(|(id, _)| id as u32)
            .collect();
        // (the finite objects' ids, in the order obvhs sees them, when that is not 0, 1, 2, …)
        let (boxes, finite) = if planes.is_empty() {
            (all, None)
        } else {
            let (finite, boxes): (Vec<u32>, Vec<PrimBox>) = all
                .into_iter()
                .zip(&scene.objects)
                .enumerate()
                .filter(|(_, (_, o))| shape_bounds(&o.shape).is_some())
                .map(|(id, (b, _))| (id as u32, b))
                .unzip();
            (boxes, Some(finite))
        };
        let mut core = Duration::ZERO;
        let bvh2 = if boxes.is_empty() {
            Bvh2::default()
        } else {
            build_bvh2(&boxes, build_params(scene.settings.bvh_quality), &mut core)
        };
        drop(boxes);
        // raystep's nodes, in depth-first order (see `depth_first`).
        let mut nodes = depth_first(&bvh2.nodes);
        let leaf_objects = match &finite {
            None => bvh2.primitive_indices.clone(),
            Some(f) => map_in_order(&bvh2.primitive_indices, |&i| {
                f.get(i as usize).copied().unwrap_or(0)
            }),
        };
        // The leaf-ordered shapes and the walks over the tree are independent.
        let (leaf_shapes, ((max_depth, outline), finite_boxes)) = rayon::join(
            || {
                map_in_order(&leaf_objects, |&id| {
                    scene
                        .objects
                        .get(id as usize)
                        .map_or(EMPTY_SHAPE, |o| o.shape)
                })
            },
            || {
                rayon::join(
                    || {
                        rayon::join(
                            || tree_depth(&nodes),
                            || compute_outline(&nodes, OUTLINE_DEPTH),
                        )
                    },
                    || {
                        nodes
                            .par_iter()
                            .all(|n| n.min.is_finite() && n.max.is_finite())
                    },
                )
            },
        );
        #[cfg(target_arch = "x86_64")]
        let wide = super::avx2_fma();
        #[cfg(not(target_arch = "x86_64"))]
        let wide = false;
        // Only the AVX2 build reads the packs.
        let packs = if wide {
            tri4::pack_leaves(&mut nodes, &leaf_shapes)
        } else {
            vec![]
        };
        let prefetch = nodes.len() * std::mem::size_of::<Node>() >= PREFETCH_FROM;
        Bvh {
            nodes,
            leaf_objects,
            leaf_shapes,
            packs,
            planes,
            max_depth,
            build_time: start.elapsed(),
            core_time: core,
            outline,
            obvhs: bvh2,
            prefetch,
            finite_boxes,
            wide,
            sah: std::sync::OnceLock::new(),
        }
    }

    /// The tree's SAH cost: Σ over inner nodes of area/root area × 1 (a box test pair) plus Σ
    /// over leaves of area/root area × primitives (each test costing one) — the usual measure of
    /// tree quality, comparable between builds only on the same scene.
    pub fn sah_cost(&self) -> f64 {
        *self.sah.get_or_init(|| self.compute_sah_cost())
    }

    fn compute_sah_cost(&self) -> f64 {
        let area = |n: &Node| {
            let d = (n.max - n.min).max(Vec3A::ZERO);
            2.0 * f64::from(d.x * d.y + d.y * d.z + d.z * d.x)
        };
        let Some(root) = self.nodes.first() else {
            return 0.0;
        };
        let root_area = area(root).max(f64::MIN_POSITIVE);
        self.nodes
            .iter()
            .map(|n| area(n) / root_area * if n.is_leaf() { f64::from(n.count) } else { 1.0 })
            .sum()
    }

    /// Bytes the tree takes: its nodes, object ids and leaf-ordered shapes, and the plane list.
    pub fn memory(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>()
            + self.leaf_shapes.len() * std::mem::size_of::<Shape>()
            + self.packs.len() * std::mem::size_of::<Tri4>()
            + (self.leaf_objects.len() + self.planes.len()) * 4
    }

    /// A leaf's object ids and shapes (one bounds check each for the whole leaf).
    #[inline(always)]
    fn leaf(&self, node: &Node) -> impl Iterator<Item = (u32, &Shape)> {
        let range = node.first as usize..node.first as usize + node.count as usize;
        let ids = self.leaf_objects.get(range.clone()).unwrap_or_default();
        let shapes = self.leaf_shapes.get(range).unwrap_or_default();
        ids.iter().copied().zip(shapes)
    }

    /// Tests the primitives of a leaf the ray reaches, in leaf order; false stops the traversal.
    /// On the AVX2 build a leaf of triangles under the watertight test takes them four at a
    /// time ([`tri4`]); each lane's result is then taken in leaf order exactly as the scalar
    /// test's would be, and a recording observer gets the scalar test's record.
    #[inline(always)]
    fn test_leaf<O: Observer, const WIDE: bool>(
        &self,
        node: &Node,
        ray: &mut Ray<f32>,
        obs: &mut O,
        leaf: &mut impl LeafTest<O>,
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        if WIDE && node.pack != NO_PACK && leaf.watertight() {
            return self.test_leaf4(node, ray, obs, leaf);
        }
        for (id, shape) in self.leaf(node) {
            if !leaf.test(id, shape, ray, obs) {
                return false;
            }
        }
        true
    }

    /// [`Bvh::test_leaf`] for a leaf of triangles, four lanes at a time.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    #[allow(unsafe_code)] // the four-lane test, reached only from the AVX2 build
    fn test_leaf4<O: Observer>(
        &self,
        node: &Node,
        ray: &mut Ray<f32>,
        obs: &mut O,
        leaf: &mut impl LeafTest<O>,
    ) -> bool {
        let (first, count) = (node.first as usize, node.count as usize);
        let pack = node.pack as usize;
        let packs = self
            .packs
            .get(pack..pack + count.div_ceil(4))
            .unwrap_or_default();
        let shear = leaf.shear(ray);
        // SAFETY: `WIDE` is true only inside `closest_avx2`/`any_avx2`, which run only after
        // `avx2_fma()` found AVX2 and FMA on this CPU.
        let r4 = unsafe { tri4::Ray4::new(ray, &shear) };
        for (k, pack) in packs.iter().enumerate() {
            // SAFETY: as above.
            let lanes = unsafe { tri4::test4(&r4, pack) };
            let range = first + 4 * k..first + count.min(4 * k + 4);
            let ids = self.leaf_objects.get(range.clone()).unwrap_or_default();
            let shapes = self.leaf_shapes.get(range).unwrap_or_default();
            if lanes.pass | lanes.exact == 0 {
                // All four missed, whatever t_max: recorded (or counted) as four misses.
                debug_assert!(shapes.iter().all(|s| match s {
                    Shape::Triangle { p } =>
                        triangle::watertight_sheared(ray, &shear, *p).t.is_none(),
                    _ => false,
                }));
                leaf.misses(ids, shapes, ray, obs);
                continue;
            }
            for (j, (&id, shape)) in ids.iter().zip(shapes).enumerate() {
                let go_on = if lanes.exact & (1 << j) != 0 {
                    leaf.test(id, shape, ray, obs)
                } else {
                    let found = LaneHit {
                        t: lanes.t.get(j).copied().unwrap_or(f32::NAN),
                        u: lanes.u.get(j).copied().unwrap_or(0.0),
                        v: lanes.v.get(j).copied().unwrap_or(0.0),
                        pass: lanes.pass & (1 << j) != 0,
                    };
                    leaf.lane(id, shape, found, ray, obs)
                };
                if !go_on {
                    return false;
                }
            }
        }
        true
    }

    /// Asks the CPU to start loading what the traversal reads if it enters `n`: its children's
    /// pair, or its triangle packs — while the pair holding `n` is still being tested.
    #[inline(always)]
    #[allow(unsafe_code)] // a prefetch hint
    fn prefetch_below(&self, n: &Node) {
        #[cfg(target_arch = "x86_64")]
        {
            use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
            let p = if n.is_leaf() {
                self.packs
                    .as_ptr()
                    .wrapping_add(n.pack as usize)
                    .cast::<i8>()
            } else {
                self.nodes
                    .as_ptr()
                    .wrapping_add(n.first as usize)
                    .cast::<i8>()
            };
            // SAFETY: a prefetch is a hint: it never faults, whatever the address.
            unsafe {
                _mm_prefetch::<_MM_HINT_T0>(p);
                _mm_prefetch::<_MM_HINT_T0>(p.wrapping_add(64));
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = n;
    }

    /// Walks the tree for `ray`, calling `leaf.test(object, ray)` for each primitive in the leaves the
    /// ray reaches, nearer subtrees first. `leaf` returns false to stop (any-hit). t_max shrinks
    /// as `leaf` finds closer hits (it updates `ray.t_max`).
    #[inline(always)]
    fn traverse<O: Observer, const WIDE: bool>(
        &self,
        ray: &mut Ray<f32>,
        obs: &mut O,
        leaf: &mut impl LeafTest<O>,
    ) {
        // True IEEE reciprocals: ±∞ for zero components, the sign of zero kept.
        let inv = Vec3::ONE / ray.dir;
        // A finite direction has a non-zero reciprocal, so with finite boxes and origin no slab
        // distance can be 0·∞ or ∞·0.
        if self.finite_boxes && inv.is_finite() && ray.dir.is_finite() && ray.origin.is_finite() {
            self.walk::<O, true, WIDE>(ray, inv, obs, leaf)
        } else {
            self.walk::<O, false, WIDE>(ray, inv, obs, leaf)
        }
    }

    /// [`Bvh::traverse`] with the box test `ORDERED` or not (see [`FastRay::interval`]).
    #[inline(always)]
    fn walk<O: Observer, const ORDERED: bool, const WIDE: bool>(
        &self,
        ray: &mut Ray<f32>,
        inv: Vec3,
        obs: &mut O,
        leaf: &mut impl LeafTest<O>,
    ) {
        let fast = FastRay::new(ray, inv);
        let Some(root) = self.nodes.first() else {
            return;
        };
        let (t_near, t_far) = fast.interval::<ORDERED>(root, Vec3A::splat(ray.t_max));
        let root_action = match (t_near <= t_far, root.is_leaf()) {
            (false, _) => NodeAction::Culled,
            (true, true) => NodeAction::TestPrimitives,
            (true, false) => NodeAction::Descend,
        };
        obs.node_visit(|| NodeVisit {
            node: 0,
            depth: 0,
            test: slab_robust(ray, inv, Vec3::from(root.min), Vec3::from(root.max)),
            leaf: root.is_leaf(),
            children: (!root.is_leaf()).then_some([root.first, root.first + 1]),
            action: root_action,
        });
        match root_action {
            NodeAction::Culled => return,
            NodeAction::TestPrimitives => {
                self.test_leaf::<O, WIDE>(root, ray, obs, leaf);
                return;
            }
            _ => {}
        }
        let mut todo = Todo::new();
        // (first child index, depth of the children); the depth is only kept when recorded.
        let mut current = (root.first, 1u32);
        loop {
            let (first, depth) = current;
            // t_max as the boxes were tested, so a record shows the values the decision used
            // even after a leaf shrinks it (origin, direction and t_min never change).
            let t_max_tested = ray.t_max;
            // Siblings are adjacent: one bounds check for the pair.
            let (a, b) = match self.nodes.get(first as usize..first as usize + 2) {
                Some([a, b]) => (a, b),
                _ => return,
            };
            if WIDE && self.prefetch {
                self.prefetch_below(a);
                self.prefetch_below(b);
            }
            let t_max = Vec3A::splat(t_max_tested);
            let (ia, ib) = if WIDE && ORDERED {
                fast.interval_pair(a, b, t_max)
            } else {
                (
                    fast.interval::<ORDERED>(a, t_max),
                    fast.interval::<ORDERED>(b, t_max),
                )
            };
            // Nearer first.
            let a_first = ia.0 <= ib.0;
            let (near, near_id, near_t) = if a_first {
                (a, first, ia)
            } else {
                (b, first + 1, ib)
            };
            let (far, far_id, far_t) = if a_first {
                (b, first + 1, ib)
            } else {
                (a, first, ia)
            };
            let child_depth = if O::RECORDS { depth + 1 } else { 0 };
            let mut next: Option<(u32, u32)> = None;
            // Visits one child: decide, report, then test its primitives or schedule it.
            macro_rules! visit {
                ($node:expr, $id:expr, $t:expr, $is_near:expr) => {{
                    let node: &Node = $node;
                    let (t_near, t_far) = $t;
                    // The far box is re-checked against t_max, which the near leaf may have shrunk.
                    let hit = t_near <= t_far && ($is_near || t_near <= ray.t_max);
                    let descend = $is_near || next.is_none();
                    obs.node_visit(|| {
                        let tested = Ray::<f32> {
                            origin: ray.origin,
                            dir: ray.dir,
                            t_min: ray.t_min,
                            t_max: t_max_tested,
                        };
                        NodeVisit {
                            node: $id,
                            depth,
                            test: slab_robust(
                                &tested,
                                inv,
                                Vec3::from(node.min),
                                Vec3::from(node.max),
                            ),
                            leaf: node.is_leaf(),
                            children: (!node.is_leaf()).then_some([node.first, node.first + 1]),
                            action: match (hit, node.is_leaf()) {
                                (false, _) => NodeAction::Culled,
                                (true, true) => NodeAction::TestPrimitives,
                                (true, false) if descend => NodeAction::Descend,
                                (true, false) => NodeAction::Pushed,
                            },
                        }
                    });
                    if hit {
                        if node.is_leaf() {
                            if !self.test_leaf::<O, WIDE>(node, ray, obs, leaf) {
                                return;
                            }
                        } else if descend {
                            next = Some((node.first, child_depth));
                        } else {
                            todo.push(node.first, child_depth, O::RECORDS);
                        }
                    }
                }};
            }
            visit!(near, near_id, near_t, true);
            visit!(far, far_id, far_t, false);
            current = match next.or_else(|| todo.pop(O::RECORDS)) {
                Some(n) => n,
                None => return,
            };
        }
    }
}

/// What the traversal does with each primitive of a leaf it reaches. A trait with always-inlined
/// methods rather than a closure, so that the whole query — traversal, leaf tests and kernels —
/// is one function, compiled once more for AVX2 and FMA (see [`Bvh::closest`]).
trait LeafTest<O: Observer> {
    /// Tests object `id` (whose shape is `shape`) against `ray` (shrinking its t_max on a closer hit); false stops the
    /// traversal.
    fn test(&mut self, id: u32, shape: &Shape, ray: &mut Ray<f32>, obs: &mut O) -> bool;
    /// Takes a triangle that the four-lane test has tested (see [`LaneHit`]) as [`Self::test`]
    /// would have taken its scalar test; false stops the traversal.
    fn lane(
        &mut self,
        id: u32,
        shape: &Shape,
        found: LaneHit,
        ray: &mut Ray<f32>,
        obs: &mut O,
    ) -> bool;
    /// Reports triangles that the four-lane test found all missed, whatever t_max (recorded
    /// with the scalar test's records, as [`Self::test`] would have).
    fn misses(&mut self, ids: &[u32], shapes: &[Shape], ray: &Ray<f32>, obs: &mut O);
    /// The scene being traced.
    fn scene(&self) -> &Scene;
    /// What the query computes once per ray.
    fn per(&mut self) -> &mut PerRay;
    /// Whether triangles take the watertight test (the one the four-lane test computes).
    #[inline(always)]
    fn watertight(&self) -> bool {
        self.scene().settings.triangle_method == TriangleMethod::Watertight
    }
    /// The ray's shear for the watertight test (computed once per query).
    #[inline(always)]
    fn shear(&mut self, ray: &Ray<f32>) -> Shear<f32> {
        self.per().shear(ray)
    }
}

/// One lane of the four-lane watertight test: the scalar test's t, u and v, and whether the
/// triangle passed every check but t < t_max (which the taker checks against its t_max).
#[derive(Debug, Clone, Copy)]
struct LaneHit {
    t: f32,
    u: f32,
    v: f32,
    pass: bool,
}

impl LaneHit {
    /// The hit on object `id` if the lane passed and t is below `ray`'s t_max — what the scalar
    /// test gives for that ray. The recorded step is the scalar test's own record, and debug
    /// builds check that the two agree bit for bit.
    #[inline(always)]
    fn take<O: Observer>(
        self,
        scene: &Scene,
        id: u32,
        shape: &Shape,
        ray: &Ray<f32>,
        shear: &Shear<f32>,
        obs: &mut O,
    ) -> Option<Hit> {
        if !self.pass {
            // The common case, kept short: a miss whatever t_max.
            if let Shape::Triangle { p } = *shape {
                let scalar = || triangle::watertight_sheared(ray, shear, p);
                debug_assert_eq!(scalar().t, None, "four-lane test missed object {id}");
                obs.prim_test(|| triangle_step(scene, id, p, scalar()));
            }
            return None;
        }
        let hit = (self.t < ray.t_max).then_some(Hit {
            object: id,
            t: self.t,
            u: self.u,
            v: self.v,
        });
        if let Shape::Triangle { p } = *shape {
            let scalar = || triangle::watertight_sheared(ray, shear, p);
            debug_assert_eq!(
                scalar().t.map(f32::to_bits),
                hit.map(|h| h.t.to_bits()),
                "four-lane and scalar watertight tests disagree on object {id}"
            );
            debug_assert!(
                hit.is_none_or(|h| scalar().u.map(f32::to_bits) == Some(h.u.to_bits())
                    && scalar().v.map(f32::to_bits) == Some(h.v.to_bits()))
            );
            obs.prim_test(|| triangle_step(scene, id, p, scalar()));
        }
        hit
    }
}

/// The record of a triangle the four-lane test found missed: the scalar test's own record
/// (debug builds check that it is a miss too).
#[inline(always)]
fn missed_step(
    scene: &Scene,
    id: u32,
    shape: Option<&Shape>,
    ray: &Ray<f32>,
    shear: &Shear<f32>,
) -> crate::record::Step {
    let p = match shape {
        Some(Shape::Triangle { p }) => *p,
        _ => [Vec3::ZERO; 3],
    };
    let test = triangle::watertight_sheared(ray, shear, p);
    debug_assert_eq!(test.t, None, "four-lane test missed object {id}");
    triangle_step(scene, id, p, test)
}

/// The closest hit so far.
struct ClosestHit<'a> {
    scene: &'a Scene,
    best: Option<Hit>,
    per: PerRay,
}

impl<O: Observer> LeafTest<O> for ClosestHit<'_> {
    #[inline(always)]
    fn test(&mut self, id: u32, shape: &Shape, ray: &mut Ray<f32>, obs: &mut O) -> bool {
        test_closest_shape(
            self.scene,
            id,
            shape,
            ray,
            &mut self.best,
            &mut self.per,
            obs,
        );
        true
    }

    /// As [`test_closest_shape`]: tested against the tie-adjusted ray, a hit recorded as
    /// accepted and made the closest so far.
    #[inline(always)]
    fn lane(
        &mut self,
        id: u32,
        shape: &Shape,
        found: LaneHit,
        ray: &mut Ray<f32>,
        obs: &mut O,
    ) -> bool {
        let shear = self.per.shear(ray);
        let tested = tie_ray(ray, id, &self.best);
        if let Some(h) = found.take(self.scene, id, shape, &tested, &shear, obs) {
            accept(self.scene, &h, ray.t_max, obs);
            ray.t_max = h.t;
            self.best = Some(h);
        }
        true
    }

    #[inline(always)]
    fn misses(&mut self, ids: &[u32], shapes: &[Shape], ray: &Ray<f32>, obs: &mut O) {
        let shear = self.per.shear(ray);
        let best = self.best;
        obs.prim_tests(ids.len(), |j| {
            let id = ids.get(j).copied().unwrap_or(0);
            missed_step(
                self.scene,
                id,
                shapes.get(j),
                &tie_ray(ray, id, &best),
                &shear,
            )
        });
    }

    #[inline(always)]
    fn scene(&self) -> &Scene {
        self.scene
    }

    #[inline(always)]
    fn per(&mut self) -> &mut PerRay {
        &mut self.per
    }
}

/// The first hit found (shadow rays).
struct AnyHit<'a> {
    scene: &'a Scene,
    found: Option<Hit>,
    per: PerRay,
}

impl<O: Observer> LeafTest<O> for AnyHit<'_> {
    #[inline(always)]
    fn test(&mut self, id: u32, shape: &Shape, ray: &mut Ray<f32>, obs: &mut O) -> bool {
        test_any_shape(
            self.scene,
            id,
            shape,
            ray,
            &mut self.found,
            &mut self.per,
            obs,
        )
    }

    /// As [`test_any_shape`]: a hit is recorded as accepted and ends the search.
    #[inline(always)]
    fn lane(
        &mut self,
        id: u32,
        shape: &Shape,
        found: LaneHit,
        ray: &mut Ray<f32>,
        obs: &mut O,
    ) -> bool {
        let shear = self.per.shear(ray);
        match found.take(self.scene, id, shape, ray, &shear, obs) {
            Some(h) => {
                accept(self.scene, &h, ray.t_max, obs);
                self.found = Some(h);
                false
            }
            None => true,
        }
    }

    #[inline(always)]
    fn misses(&mut self, ids: &[u32], shapes: &[Shape], ray: &Ray<f32>, obs: &mut O) {
        let shear = self.per.shear(ray);
        obs.prim_tests(ids.len(), |j| {
            let id = ids.get(j).copied().unwrap_or(0);
            missed_step(self.scene, id, shapes.get(j), ray, &shear)
        });
    }

    #[inline(always)]
    fn scene(&self) -> &Scene {
        self.scene
    }

    #[inline(always)]
    fn per(&mut self) -> &mut PerRay {
        &mut self.per
    }
}

impl Bvh {
    #[inline(always)]
    fn closest_in<O: Observer, const WIDE: bool>(
        &self,
        scene: &Scene,
        ray: &Ray<f32>,
        obs: &mut O,
    ) -> Option<Hit> {
        let mut r = *ray;
        let mut leaf = ClosestHit {
            scene,
            best: None,
            per: PerRay::default(),
        };
        closest_of(scene, &self.planes, &mut r, &mut leaf.best, obs);
        self.traverse::<O, WIDE>(&mut r, obs, &mut leaf);
        leaf.best
    }

    #[inline(always)]
    fn any_in<O: Observer, const WIDE: bool>(
        &self,
        scene: &Scene,
        ray: &Ray<f32>,
        obs: &mut O,
    ) -> Option<Hit> {
        if let Some(h) = any_of(scene, &self.planes, ray, obs) {
            return Some(h);
        }
        let mut leaf = AnyHit {
            scene,
            found: None,
            per: PerRay::default(),
        };
        let mut r = *ray;
        self.traverse::<O, WIDE>(&mut r, obs, &mut leaf);
        leaf.found
    }

    /// [`Bvh::closest_in`] compiled for AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn closest_avx2<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        self.closest_in::<O, true>(scene, ray, obs)
    }

    /// [`Bvh::any_in`] compiled for AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    fn any_avx2<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        self.any_in::<O, true>(scene, ray, obs)
    }
}

/// Both queries run the same code twice compiled: for the baseline x86-64 the binary targets and,
/// when the CPU has them, for AVX2 and FMA. The answers are the same bit for bit: Rust never
/// fuses a multiply and an add on its own, so the only FMAs are the kernels' explicit
/// `mul_add`s, which are correctly rounded whether the FMA instruction or the C library computes
/// them (the baseline build calls `fmaf`, six calls per watertight triangle test); every other
/// operation is the same IEEE operation in either encoding. `tests/accelerators.rs` renders with
/// both and compares.
impl Accelerator for Bvh {
    #[inline]
    #[allow(unsafe_code)] // calling a #[target_feature] function, after checking the CPU has it
    fn closest<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        #[cfg(target_arch = "x86_64")]
        if self.wide {
            // SAFETY: the CPU has AVX2 and FMA (just checked).
            return unsafe { self.closest_avx2(scene, ray, obs) };
        }
        self.closest_in::<O, false>(scene, ray, obs)
    }

    #[inline]
    #[allow(unsafe_code)] // calling a #[target_feature] function, after checking the CPU has it
    fn any<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        #[cfg(target_arch = "x86_64")]
        if self.wide {
            // SAFETY: the CPU has AVX2 and FMA (just checked).
            return unsafe { self.any_avx2(scene, ray, obs) };
        }
        self.any_in::<O, false>(scene, ray, obs)
    }

    fn name(&self) -> &'static str {
        "BVH"
    }

    fn outline(&self, depth: u32) -> Option<Vec<OutlineNode>> {
        Some(
            self.outline
                .iter()
                .filter(|n| n.depth <= depth)
                .cloned()
                .collect(),
        )
    }
}

/// From this many bytes of nodes a tree is prefetched as it is walked. Measured with `raystep
/// bench SCENE --section rays` (alternated runs): on the million-triangle tetrahedron (25 MB of
/// nodes) shadow rays 6–8 % faster, primary rays unchanged; on the mountain of 131,072 triangles
/// (2.9 MB) and the sphereflake (0.2 MB), whose trees sit in the caches, 4–8 % slower.
const PREFETCH_FROM: usize = 16 << 20;

/// From this many items the build's per-item steps run on rayon's threads; below it, starting
/// them costs more than they save (a dozen-primitive tree took 30× longer to build in parallel).
const PARALLEL_FROM: usize = 16_384;

/// `items.iter().map(f).collect()`, in parallel for big slices (the order is kept either way).
fn map_in_order<T: Sync, U: Send>(items: &[T], f: impl Fn(&T) -> U + Sync + Send) -> Vec<U> {
    if items.len() >= PARALLEL_FROM {
        items.par_iter().map(f).collect()
    } else {
        items.iter().map(f).collect()
    }
}

/// obvhs's nodes as raystep's, in depth-first order with sibling pairs kept together: the
/// root, then each pair followed by the pairs below its second node, then those below its first
/// (a walk with a stack, the order of obvhs's `reorder_in_stack_traversal_order`). obvhs's
/// builder leaves a tree's levels far apart in memory, so each step down a big tree waited for
/// memory; in this order a subtree's nodes lie together (on the million-triangle tetrahedron:
/// primary rays 7 % and shadow rays 17–20 % faster, `raystep bench SCENE --section rays`).
/// Inner nodes get their children's new index; the leaves' object ranges do not move. One
/// serial pass that writes the nodes in order (a parallel gather by a permutation took three
/// times as long).
fn depth_first(nodes: &[obvhs::bvh2::node::Bvh2Node]) -> Vec<Node> {
    let convert = |n: &obvhs::bvh2::node::Bvh2Node| {
        let b = n.aabb();
        Node {
            min: b.min,
            max: b.max,
            first: n.first_index,
            count: n.prim_count,
            pack: NO_PACK,
        }
    };
    let mut out = Vec::with_capacity(nodes.len());
    let Some(root) = nodes.first() else {
        return out;
    };
    out.push(convert(root));
    // (obvhs's index of a pair's first node, raystep's index of their parent)
    let mut stack = vec![];
    if !root.is_leaf() {
        stack.push((root.first_index, 0usize));
    }
    // Each node is placed once, so the walk ends after `nodes.len()` of them even were the
    // children to form a cycle (obvhs's trees do not).
    while let Some((first, parent)) = stack.pop() {
        if out.len() >= nodes.len() {
            break;
        }
        let here = out.len() as u32;
        if let Some(p) = out.get_mut(parent) {
            p.first = here;
        }
        for old in [first, first.saturating_add(1)] {
            let Some(n) = nodes.get(old as usize) else {
                continue;
            };
            if !n.is_leaf() {
                stack.push((n.first_index, out.len()));
            }
            out.push(convert(n));
        }
    }
    out
}

/// The number of levels below the root (0 for a single leaf or an empty tree).
fn tree_depth(nodes: &[Node]) -> usize {
    let mut deepest = 0;
    let mut stack = vec![(0usize, 0usize)];
    while let Some((i, d)) = stack.pop() {
        let Some(n) = nodes.get(i) else { continue };
        deepest = deepest.max(d);
        if !n.is_leaf() {
            stack.push((n.first as usize, d + 1));
            stack.push((n.first as usize + 1, d + 1));
        }
    }
    deepest
}

/// The top `depth` levels of the tree with each node's primitive count (computed once, at build:
/// the counts need a walk of the whole tree, 17 ms for a million triangles).
fn compute_outline(nodes: &[Node], depth: u32) -> Vec<OutlineNode> {
    let mut out = vec![];
    // Primitive counts bottom-up, by an explicit post-order walk (no assumption about
    // obvhs's node order).
    let mut counts = vec![0u32; nodes.len()];
    let mut todo = vec![(0usize, false)];
    while let Some((i, children_done)) = todo.pop() {
        let Some(n) = nodes.get(i) else { continue };
        if n.is_leaf() {
            counts[i] = n.count;
        } else if children_done {
            counts[i] = counts[n.first as usize] + counts[n.first as usize + 1];
        } else {
            todo.push((i, true));
            todo.push((n.first as usize, false));
            todo.push((n.first as usize + 1, false));
        }
    }
    let mut stack = vec![(0u32, 0u32)];
    while let Some((i, d)) = stack.pop() {
        let Some(n) = nodes.get(i as usize) else {
            continue;
        };
        let children = (!n.is_leaf()).then_some([n.first, n.first + 1]);
        out.push(OutlineNode {
            node: i,
            depth: d,
            children,
            primitives: counts[i as usize],
            min: n.min.to_array(),
            max: n.max.to_array(),
        });
        if let Some([a, b]) = children
            && d < depth
        {
            stack.push((b, d + 1));
            stack.push((a, d + 1));
        }
    }
    out.sort_by_key(|n| n.node);
    out
}

#[cfg(test)]
mod tests;
