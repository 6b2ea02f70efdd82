//! A bounding volume hierarchy: built by obvhs (`Bvh2`, PLOC + reinsertion), traversed by
//! raystep's own loop so that every node visit can be observed.
//!
//! The traversal follows obvhs's `ray_traverse_dynamic` (test both children of a node, visit the
//! nearer first, push the farther), with docs/NUMERICS.md's robust slab test instead of obvhs's: true
//! IEEE reciprocals (obvhs clamps tiny components, giving false misses for near-parallel rays,
//! S21), the ray's own t_min honoured (S23), and `<=` so flat boxes are hit (S22). Infinite planes
//! stay outside the tree: they are tested first and their hit tightens t_max.

// The four-lane triangle test runs on x86-64's AVX2 + FMA only: elsewhere (an ARM Mac, the
// browser's wasm32) its parts are not called.
#![cfg_attr(not(target_arch = "x86_64"), allow(dead_code, unused_imports))]

use super::{Accelerator, Hit, PerRay, any_of, closest_of};
use crate::math::Ray;
use crate::record::OutlineNode;
use crate::record::{NodeAction, NodeVisit, Observer};
use crate::scene::{Scene, Shape};
use crate::shapes::aabb::slab_robust;
use crate::shapes::triangle;
use glam::{Vec3, Vec3A};
use obvhs::bvh2::Bvh2;
use std::time::Duration;

/// The traversal's list of subtrees still to visit (first child index, and the children's depth
/// when the observer records): the first 32 indices in an array on the machine stack, any beyond
/// (a tree deeper than 32 levels on a ray that defers a subtree at every level) in a vector.
/// Written out rather than a `SmallVec` because its push and pop are the traversal's inner loop;
/// `records` (the observer's constant) keeps the depths, in a vector, only when they are recorded.
pub(crate) struct Todo {
    first: [u32; 32],
    len: usize,
    spill: Vec<u32>,
    depth: Vec<u32>,
}

impl Todo {
    #[inline(always)]
    pub(crate) fn new() -> Self {
        Todo {
            first: [0; 32],
            len: 0,
            spill: Vec::new(),
            depth: Vec::new(),
        }
    }

    #[inline(always)]
    pub(crate) fn push(&mut self, first: u32, depth: u32, records: bool) {
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
    pub(crate) fn pop(&mut self, records: bool) -> Option<(u32, u32)> {
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

mod build;
mod collapse;
mod leaf;
mod parallel;
mod ray_box;
mod reshape;
mod tlas;
mod tri4;
pub use build::shape_bounds;
use leaf::{AnyHit, ClosestHit, LaneHit, LeafTest};
pub(crate) use ray_box::FastRay;
pub use tlas::Tlas;
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
    /// Wall time of the whole build (boxes, the tree's build, raystep's layout).
    pub build_time: Duration,
    /// Wall time of the tree's build alone: obvhs's PLOC and reinsertion, raystep's leaf
    /// collapse (see `build::build_bvh2`).
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
    /// for trees too big for the caches (see [`build::PREFETCH_FROM`]).
    prefetch: bool,
    /// [`Bvh::sah_cost`], computed when first asked (the app shows it every frame).
    sah: std::sync::OnceLock<f64>,
}

impl Bvh {
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
            instance: None,
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
            // Nearer first; farther first for a shadow ray (see `AnyHit`). Ties: `a` first,
            // farther first `b`.
            let a_first = (ia.0 <= ib.0) != leaf.farther_first();
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
                            instance: None,
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
/// operation is the same IEEE operation in either encoding. `crates/raystep-diagram/tests/it/accelerators.rs` renders with
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

#[cfg(test)]
mod tests;
