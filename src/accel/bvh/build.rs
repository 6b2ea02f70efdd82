//! Building the tree: obvhs's build of the scene's finite primitives at the scene's quality,
//! then raystep's layout — nodes in depth-first order, the leaf-ordered objects and shapes, the
//! four-lane triangle packs, the outline the diagrams draw — and the tree's SAH cost.

use super::tri4::{self, NO_PACK};
use super::{Bvh, Node};
use crate::record::OutlineNode;
use crate::scene::{BvhQuality, Scene, Shape};
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
        // Two independent halves, about as long as each other on a million triangles:
        // raystep's nodes in depth-first order (see `depth_first`) and the walks over them; the
        // leaf-ordered objects and shapes.
        let ((mut nodes, ((max_depth, outline), finite_boxes)), (leaf_objects, leaf_shapes)) =
            rayon::join(
                || {
                    let nodes = depth_first(&bvh2.nodes);
                    let walks = rayon::join(
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
                    );
                    (nodes, walks)
                },
                || {
                    let leaf_objects = match &finite {
                        None => bvh2.primitive_indices.clone(),
                        Some(f) => map_in_order(&bvh2.primitive_indices, |&i| {
                            f.get(i as usize).copied().unwrap_or(0)
                        }),
                    };
                    let leaf_shapes = map_in_order(&leaf_objects, |&id| {
                        scene
                            .objects
                            .get(id as usize)
                            .map_or(EMPTY_SHAPE, |o| o.shape)
                    });
                    (leaf_objects, leaf_shapes)
                },
            );
        #[cfg(target_arch = "x86_64")]
        let wide = crate::accel::avx2_fma();
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
}

/// From this many bytes of nodes a tree is prefetched as it is walked. Measured with `raystep
/// bench SCENE --section rays` (alternated runs): on the million-triangle tetrahedron (25 MB of
/// nodes) shadow rays 6–8 % faster, primary rays unchanged; on the mountain of 131,072 triangles
/// (2.9 MB) and the sphereflake (0.2 MB), whose trees sit in the caches, 4–8 % slower.
pub(super) const PREFETCH_FROM: usize = 16 << 20;

/// From this many items the build's per-item steps run on rayon's threads; below it, starting
/// them costs more than they save (a dozen-primitive tree took 30× longer to build in parallel).
const PARALLEL_FROM: usize = 16_384;

/// `items.iter().map(f).collect()`, in parallel for big slices (the order is kept either way).
pub(super) fn map_in_order<T: Sync, U: Send>(
    items: &[T],
    f: impl Fn(&T) -> U + Sync + Send,
) -> Vec<U> {
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
