//! Building the tree: obvhs's build of the scene's finite primitives at the scene's quality,
//! then raystep's layout — nodes in depth-first order, the leaf-ordered objects and shapes, the
//! four-lane triangle packs, the outline the diagrams draw — and the tree's SAH cost.

use super::collapse::collapse;
use super::parallel::{PARALLEL_FROM, map_in_order};
use super::reshape::{cap_depth, split_mixed_leaves};
use super::tri4::{self, NO_PACK};
use super::{Bvh, Node};
use crate::platform::{Duration, Instant};
use crate::record::OutlineNode;
use crate::record::validate::MAX_BVH_DEPTH;
use crate::scene::{BvhQuality, Scene, Shape};
use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::bvh2::{Bvh2, reinsertion::ReinsertionOptimizer};
use obvhs::ploc::PlocBuilder;
use obvhs::{Boundable, BvhBuildParams};
use rayon::prelude::*;

/// How many levels of the tree the outline keeps (the ray tree diagram asks for at most this).
const OUTLINE_DEPTH: u32 = 6;

/// obvhs's `builder::build_bvh2` step for step (PLOC, reinsertion, leaf collapse, reinsertion),
/// with raystep's clock (obvhs times its build with `std::time::Instant`, which panics in a
/// browser: see `platform`) and raystep's own leaf collapse (the same tree, sooner: see
/// `collapse`). `core` gains the time the steps took.
pub(super) fn build_bvh2<T: Boundable>(
    primitives: &[T],
    config: BvhBuildParams,
    core: &mut Duration,
) -> Bvh2 {
    let start = Instant::now();
    let mut bvh2 = PlocBuilder::with_capacity(primitives.len()).build(
        config.ploc_search_distance,
        primitives,
        (0..primitives.len() as u32).collect::<Vec<_>>(),
        config.sort_precision,
        config.search_depth_threshold,
    );
    let mut reinsertion = ReinsertionOptimizer::default();
    reinsertion.run(&mut bvh2, config.reinsertion_batch_ratio, None);
    collapse(
        &mut bvh2,
        config.max_prims_per_leaf.clamp(1, 255),
        config.collapse_traversal_cost,
    );
    reinsertion.run(
        &mut bvh2,
        config.reinsertion_batch_ratio * config.post_collapse_reinsertion_batch_ratio_multiplier,
        None,
    );
    *core += start.elapsed();
    #[cfg(debug_assertions)]
    bvh2.validate(primitives, false, config.pre_split);
    bvh2
}

#[derive(Clone, Copy)]
pub(super) struct PrimBox(pub(super) Aabb);

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

/// Up to this many primitives, `medium` and `high` offer every node of the tree for
/// reinsertion (see [`build_params`]).
pub const FULL_REINSERTION_UP_TO: usize = 1 << 18;

/// obvhs's preset for a build quality over `primitives` boxes. `medium` and `high` then offer
/// every node for reinsertion (obvhs's `reinsertion_batch_ratio` 1, the ratio of its
/// `very_slow_build`, instead of the presets' 0.05 and 0.2) on trees of at most
/// [`FULL_REINSERTION_UP_TO`] primitives: Meister and Bittner's reinsertion moves each node to
/// where it adds the least surface area, and a pass over every node is what pulls the big
/// primitives (a room's walls) up the tree that PLOC, pairing neighbours by their centres,
/// buries deep. Measured with `raystep bench SCENE --section build` (2026-12-02): the sphereflake
/// (7,381 balls) SAH cost 21.2 → 18.7 and shadow rays 7.60 → 8.52 million a second, the
/// fractal mountain (131,072 triangles) 28.9 → 26.9 and 4.74 → 5.18, for a build of 16 instead
/// of 3 ms and 195 instead of 41 ms; the path-traced Cornell box visits 9.9 boxes a ray instead
/// of 13.5. The million-triangle tetrahedron's regular tree does not change, and its build
/// would take 2.5 times as long: above the bound the presets' ratios stand. `low` stays
/// obvhs's fast build as it is.
pub(super) fn build_params(quality: BvhQuality, primitives: usize) -> BvhBuildParams {
    let preset = match quality {
        BvhQuality::Low => return BvhBuildParams::very_fast_build(),
        BvhQuality::Medium => BvhBuildParams::medium_build(),
        BvhQuality::High => BvhBuildParams::slow_build(),
    };
    if primitives <= FULL_REINSERTION_UP_TO {
        BvhBuildParams {
            reinsertion_batch_ratio: 1.0,
            ..preset
        }
    } else {
        preset
    }
}

impl Bvh {
    /// Builds the tree over the scene's finite objects with the obvhs preset of the scene's
    /// [`BvhQuality`]. Objects whose boxes share a centre end in one leaf (see `Coincident`),
    /// and no node lies deeper than [`MAX_BVH_DEPTH`], the depth a trace may record.
    pub fn build(scene: &Scene) -> Bvh {
        Bvh::build_over(scene, 0..scene.world().len())
    }

    /// [`Bvh::build`] over the objects `range` of the scene's list only: a prototype's, for the
    /// bottom-level BVH of its instances ([`crate::accel::TwoLevel`]). Its leaves name the
    /// objects by their ids in the scene.
    pub fn build_over(scene: &Scene, range: std::ops::Range<usize>) -> Bvh {
        let start = Instant::now();
        let objects = scene.objects.get(range.clone()).unwrap_or_default();
        let base = range.start as u32;
        // Boxes, the tree's layout and the leaf-ordered shapes are computed in parallel on big
        // scenes (on a million triangles these steps took 100 ms of a 520 ms build serially);
        // the result does not depend on the thread count. A plane gets an empty box here, and
        // only a scene with planes pays for a second pass that leaves them out. (Listing the
        // planes on one thread took 10 ms on a million triangles.)
        let all = map_in_order(objects, |o| match shape_bounds(&o.shape) {
            Some((lo, hi)) => PrimBox(Aabb::new(Vec3A::from(lo), Vec3A::from(hi))),
            None => PrimBox(Aabb::INVALID),
        });
        let plane_id = |(id, o): (usize, &crate::scene::Object)| {
            matches!(o.shape, Shape::Plane { .. } | Shape::AxisPlane { .. })
                .then_some(base + id as u32)
        };
        let planes: Vec<u32> = if objects.len() >= PARALLEL_FROM {
            objects
                .par_iter()
                .enumerate()
                .filter_map(plane_id)
                .collect()
        } else {
            objects.iter().enumerate().filter_map(plane_id).collect()
        };
        // (the finite objects' ids, in the order obvhs sees them, when that is not 0, 1, 2, …)
        let (boxes, finite) = if planes.is_empty() {
            (all, None)
        } else {
            let (finite, boxes): (Vec<u32>, Vec<PrimBox>) = all
                .into_iter()
                .zip(objects)
                .enumerate()
                .filter(|(_, (_, o))| shape_bounds(&o.shape).is_some())
                .map(|(id, (b, _))| (base + id as u32, b))
                .unzip();
            (boxes, Some(finite))
        };
        let mut core = Duration::ZERO;
        // Primitives whose boxes share a centre go to obvhs as one box (see `Coincident`).
        let coincident = Coincident::find(&boxes);
        let mut bvh2 = if boxes.is_empty() {
            Bvh2::default()
        } else if let Some(c) = &coincident {
            let mut t = build_bvh2(
                &c.boxes,
                build_params(scene.settings.bvh_quality, c.boxes.len()),
                &mut core,
            );
            c.expand(&mut t);
            t
        } else {
            build_bvh2(
                &boxes,
                build_params(scene.settings.bvh_quality, boxes.len()),
                &mut core,
            )
        };
        // A leaf of triangles and balls becomes two: see `reshape::split_mixed_leaves`.
        let is_triangle = |i: u32| {
            let id = match &finite {
                None => base + i,
                Some(f) => f.get(i as usize).copied().unwrap_or(u32::MAX),
            };
            matches!(
                scene.objects.get(id as usize).map(|o| &o.shape),
                Some(Shape::Triangle { .. })
            )
        };
        let any = |kind: fn(&Shape) -> bool| objects.iter().any(|o| kind(&o.shape));
        if any(|s| matches!(s, Shape::Triangle { .. }))
            && any(|s| matches!(s, Shape::Sphere { .. }))
        {
            split_mixed_leaves(&mut bvh2, &boxes, is_triangle);
        }
        drop(boxes);
        drop(coincident);
        let bvh2 = cap_depth(bvh2, MAX_BVH_DEPTH);
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
                        None if base == 0 => bvh2.primitive_indices.clone(),
                        None => map_in_order(&bvh2.primitive_indices, |&i| base + i),
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

/// Primitives whose boxes have the same centre, gathered before obvhs builds: no split can
/// separate them, so a top-down builder stops there and makes them one leaf. obvhs's builder
/// (PLOC, bottom-up) instead pairs nodes by the area of their union, and between equal boxes
/// every pairing ties: each node then picks the farthest candidate, only one pair per pass
/// agrees, and the tree becomes a chain, built in quadratic time (20,000 spheres at one point:
/// depth 19,992 and 22 s of build; 300 made a tree of depth 292, deeper than a trace may
/// record). Each such group goes to obvhs as one box, the union of its members' boxes, and
/// comes back as one leaf holding all of them (`expand`), as a top-down builder would leave it.
/// Its members are tested one after the other, as brute force tests them (ties go to the lower
/// id whatever the order, see [`crate::accel::tie_ray`]). Only runs of at least
/// [`COINCIDENT_FROM`] are gathered: a shorter one costs obvhs nothing worth saving, and
/// ordinary meshes have them (each of the SPD tetrahedra's four faces has the tetrahedron's box),
/// whose trees, and so whose renders, stay as they were.
struct Coincident {
    /// One box per group, in the order of each group's first member (a lone primitive is a
    /// group of one).
    boxes: Vec<PrimBox>,
    /// Group `g`'s members (indices into the boxes `find` was given, ascending) are
    /// `members[starts[g]..starts[g + 1]]`.
    starts: Vec<u32>,
    members: Vec<u32>,
}

/// The fewest primitives with one centre that are gathered into one leaf (see `Coincident`):
/// twice obvhs's most primitives per leaf at every quality, so a run shorter than this makes a
/// chain of at most 15 levels, built in a few passes.
const COINCIDENT_FROM: usize = 16;

impl Coincident {
    /// The groups of `boxes` with the same centre, or None when no [`COINCIDENT_FROM`] share one
    /// (the usual case: then obvhs gets the boxes as they are). Centres are compared exactly, by
    /// their bits (with −0 taken as +0). A digest pass rules most scenes out first (see
    /// `may_have_run`); only then are all the centres sorted.
    fn find(boxes: &[PrimBox]) -> Option<Coincident> {
        if boxes.len() < COINCIDENT_FROM || !may_have_run(boxes) {
            return None;
        }
        let key = centre_key;
        let mut order: Vec<([u32; 3], u32)> = if boxes.len() >= PARALLEL_FROM {
            boxes
                .par_iter()
                .enumerate()
                .map(|(i, b)| (key(b), i as u32))
                .collect()
        } else {
            boxes
                .iter()
                .enumerate()
                .map(|(i, b)| (key(b), i as u32))
                .collect()
        };
        if order.len() >= PARALLEL_FROM {
            order.par_sort_unstable();
        } else {
            order.sort_unstable();
        }
        // Each primitive's leader: the lowest index with its centre (a run of equal centres is
        // sorted by index, so its first entry) in a run of at least COINCIDENT_FROM; itself in
        // a shorter one.
        let mut lead: Vec<u32> = (0..boxes.len() as u32).collect();
        let mut gathered = false;
        for run in order.chunk_by(|a, b| a.0 == b.0) {
            if run.len() < COINCIDENT_FROM {
                continue;
            }
            gathered = true;
            let leader = run.first().map_or(0, |r| r.1);
            for &(_, me) in run {
                lead[me as usize] = leader;
            }
        }
        drop(order);
        if !gathered {
            return None;
        }
        // Groups numbered in the order of their leaders (a leader comes first in its group);
        // then a counting sort of the members.
        let mut number = vec![u32::MAX; boxes.len()];
        let mut sizes: Vec<u32> = vec![];
        for &l in &lead {
            let n = &mut number[l as usize];
            if *n == u32::MAX {
                *n = sizes.len() as u32;
                sizes.push(0);
            }
            sizes[*n as usize] += 1;
        }
        let mut starts = Vec::with_capacity(sizes.len() + 1);
        starts.push(0u32);
        for s in &sizes {
            starts.push(starts[starts.len() - 1] + s);
        }
        let mut fill: Vec<u32> = starts[..sizes.len()].to_vec();
        let mut members = vec![0u32; boxes.len()];
        let mut unions = vec![Aabb::INVALID; sizes.len()];
        for (i, b) in boxes.iter().enumerate() {
            let g = number[lead[i] as usize] as usize;
            members[fill[g] as usize] = i as u32;
            fill[g] += 1;
            unions[g] = unions[g].union(&b.0);
        }
        Some(Coincident {
            boxes: unions.into_iter().map(PrimBox).collect(),
            starts,
            members,
        })
    }

    /// Turns a tree built over the groups' boxes into one over the primitives: each leaf's
    /// groups are replaced by their members (a leaf of one group of 20,000 holds 20,000).
    fn expand(&self, tree: &mut Bvh2) {
        let groups = std::mem::take(&mut tree.primitive_indices);
        // Where each slot of the old list starts in the new one.
        let mut at = Vec::with_capacity(groups.len() + 1);
        let mut out = Vec::with_capacity(self.members.len());
        for &g in &groups {
            at.push(out.len() as u32);
            let range = match (self.starts.get(g as usize), self.starts.get(g as usize + 1)) {
                (Some(&a), Some(&b)) => a as usize..b as usize,
                _ => 0..0,
            };
            out.extend_from_slice(self.members.get(range).unwrap_or_default());
        }
        at.push(out.len() as u32);
        for n in tree.nodes.iter_mut().filter(|n| n.is_leaf()) {
            let (a, b) = (
                n.first_index as usize,
                n.first_index as usize + n.prim_count as usize,
            );
            if let (Some(&a), Some(&b)) = (at.get(a), at.get(b)) {
                n.first_index = a;
                n.prim_count = b - a;
            }
        }
        tree.primitive_indices = out;
        tree.primitives_to_nodes.clear();
    }
}

/// Whether `boxes` may hold [`COINCIDENT_FROM`] with one centre (false: surely not). A 64-bit
/// digest of each centre (SplitMix64's finalizer mixes every bit of it in; equal centres have
/// equal digests) is counted by its top bits, in about one slot per box; only a slot counting
/// COINCIDENT_FROM can hold such a run, and only the digests in such slots are sorted to look
/// for one. Usually no slot is that full and the answer costs two passes over the boxes; a
/// mesh's short runs (the tetrahedra's faces, by four) fill a few slots. On the
/// million-triangle tetrahedron (SPD tetra 9) this pass took 13–29 ms where sorting every centre
/// took 188–421 ms (`raystep render` of it, dev profile, two cores, five alternated runs each).
fn may_have_run(boxes: &[PrimBox]) -> bool {
    let mix = |mut h: u64| {
        h = (h ^ (h >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        h = (h ^ (h >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        h ^ (h >> 31)
    };
    let digest = |b: &PrimBox| {
        let [x, y, z] = centre_key(b);
        mix(mix((u64::from(x) << 32) | u64::from(y)) ^ u64::from(z))
    };
    let digests = map_in_order(boxes, digest);
    // At least one bit, at most 32: a slot per box, rounded up to a power of two.
    let bits = boxes
        .len()
        .next_power_of_two()
        .trailing_zeros()
        .clamp(1, 32);
    let slot = |d: u64| (d >> (64 - bits)) as usize;
    let mut counts = vec![0u8; 1 << bits];
    for &d in &digests {
        if let Some(c) = counts.get_mut(slot(d)) {
            *c = c.saturating_add(1);
        }
    }
    let full = |d: u64| {
        counts
            .get(slot(d))
            .is_some_and(|&c| usize::from(c) >= COINCIDENT_FROM)
    };
    let mut suspects: Vec<u64> = digests.into_iter().filter(|&d| full(d)).collect();
    suspects.sort_unstable();
    suspects
        .chunk_by(|a, b| a == b)
        .any(|run| run.len() >= COINCIDENT_FROM)
}

/// A box's centre (its min + max, −0 taken as +0) as bits, equal for equal centres.
fn centre_key(b: &PrimBox) -> [u32; 3] {
    let c = b.0.min + b.0.max + Vec3A::ZERO;
    [c.x.to_bits(), c.y.to_bits(), c.z.to_bits()]
}

/// From this many bytes of nodes a tree is prefetched as it is walked. Measured with `raystep
/// bench SCENE --section rays` (alternated runs): on the million-triangle tetrahedron (25 MB of
/// nodes) shadow rays 6–8 % faster, primary rays unchanged; on the mountain of 131,072 triangles
/// (2.9 MB) and the sphereflake (0.2 MB), whose trees sit in the caches, 4–8 % slower.
pub(super) const PREFETCH_FROM: usize = 16 << 20;

/// obvhs's nodes as raystep's, in depth-first order with sibling pairs kept together: the
/// root, then each pair followed by the pairs below its second node, then those below its first
/// (a walk with a stack, the order of obvhs's `reorder_in_stack_traversal_order`). obvhs's
/// builder leaves a tree's levels far apart in memory, so each step down a big tree waited for
/// memory; in this order a subtree's nodes lie together (on the million-triangle tetrahedron:
/// primary rays 7 % and shadow rays 17–20 % faster, `raystep bench SCENE --section rays`).
/// Inner nodes get their children's new index; the leaves' object ranges do not move. One
/// serial pass that writes the nodes in order (a parallel gather by a permutation took three
/// times as long).
pub(super) fn depth_first(nodes: &[obvhs::bvh2::node::Bvh2Node]) -> Vec<Node> {
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
mod tests {
    use super::super::reshape::node_bits;
    use super::*;
    use obvhs::bvh2::node::Bvh2Node;

    /// raystep's copy of obvhs's build helper builds obvhs's tree, node for node.
    #[test]
    fn the_build_is_obvhs_own() {
        let boxes: Vec<PrimBox> = (0..500u32)
            .map(|i| {
                let f = i as f32;
                let c = Vec3A::new((f * 0.37).sin() * 9.0, (f * 0.11).cos() * 5.0, f * 0.02);
                PrimBox(Aabb::new(
                    c - 0.3,
                    c + 0.2 + Vec3A::splat((f * 0.7).sin().abs()),
                ))
            })
            .collect();
        for q in [BvhQuality::Low, BvhQuality::Medium, BvhQuality::High] {
            let mut a = Duration::ZERO;
            let mut b = std::time::Duration::ZERO;
            let params = build_params(q, boxes.len());
            let ours = build_bvh2(&boxes, params, &mut a);
            let theirs = obvhs::bvh2::builder::build_bvh2(&boxes, params, &mut b);
            let bits = |t: &Bvh2| -> Vec<[u32; 8]> { t.nodes.iter().map(node_bits).collect() };
            assert_eq!(bits(&ours), bits(&theirs), "{q:?}");
            assert_eq!(ours.primitive_indices, theirs.primitive_indices, "{q:?}");
        }
    }

    /// The SAH cost of an obvhs tree, from its definition (written here apart from
    /// `Bvh::sah_cost`): every inner node's surface area, plus every leaf's times its primitive
    /// count, over the root's area.
    fn sah(t: &Bvh2) -> f64 {
        let area = |n: &Bvh2Node| {
            let d = n.aabb().max - n.aabb().min;
            2.0 * f64::from(d.x * d.y + d.y * d.z + d.z * d.x)
        };
        let root = area(&t.nodes[0]);
        t.nodes
            .iter()
            .map(|n| area(n) * f64::from(n.prim_count.max(1)))
            .sum::<f64>()
            / root
    }

    /// A room (six walls, each two flat boxes the size of the wall) around a ball of 168 small
    /// boxes and a pane: the glTF table scene's world, in boxes. PLOC pairs the walls by their
    /// centres and buries them in the tree; offering every node for reinsertion (`medium` up
    /// to [`FULL_REINSERTION_UP_TO`] primitives) pulls them up, and the tree's SAH cost falls
    /// below that of obvhs's own `medium_build` (11.6 against 12.3). Above the bound `medium`
    /// is obvhs's preset exactly, and `low` always is.
    #[test]
    fn medium_offers_every_node_for_reinsertion_on_trees_of_up_to_two_to_the_eighteen() {
        let wall = |lo: [f32; 3], hi: [f32; 3]| PrimBox(Aabb::new(lo.into(), hi.into()));
        let mut boxes = Vec::new();
        for _ in 0..2 {
            boxes.push(wall([-1.0, 0.0, -1.0], [1.0, 0.0, 1.0]));
            boxes.push(wall([-1.0, 2.0, -1.0], [1.0, 2.0, 1.0]));
            boxes.push(wall([-1.0, 0.0, 1.0], [1.0, 2.0, 1.0]));
            boxes.push(wall([-1.0, 0.0, -1.0], [1.0, 2.0, -1.0]));
            boxes.push(wall([-1.0, 0.0, -1.0], [-1.0, 2.0, 1.0]));
            boxes.push(wall([1.0, 0.0, -1.0], [1.0, 2.0, 1.0]));
        }
        for i in 0..168u32 {
            let (a, b) = (i as f32 * 0.37, i as f32 * 0.61);
            let c = Vec3A::new(
                0.3 + 0.1 * a.cos(),
                0.9 + 0.1 * b.sin(),
                0.1 * (a + b).cos(),
            );
            boxes.push(PrimBox(Aabb::new(c - 0.01, c + 0.01)));
        }
        boxes.push(wall([-0.3, 0.75, -0.1], [-0.1, 1.0, 0.1]));
        boxes.push(wall([-0.3, 0.75, -0.1], [-0.1, 1.0, 0.1]));
        let (mut a, mut b) = (Duration::ZERO, Duration::ZERO);
        let full = build_bvh2(
            &boxes,
            build_params(BvhQuality::Medium, boxes.len()),
            &mut a,
        );
        let preset = build_bvh2(&boxes, BvhBuildParams::medium_build(), &mut b);
        assert!(
            sah(&full) < 0.97 * sah(&preset),
            "SAH {} against obvhs's medium {}",
            sah(&full),
            sah(&preset)
        );
        let p = build_params(BvhQuality::Medium, FULL_REINSERTION_UP_TO);
        assert_eq!(p.reinsertion_batch_ratio, 1.0);
        let p = build_params(BvhQuality::High, FULL_REINSERTION_UP_TO);
        assert_eq!(p.reinsertion_batch_ratio, 1.0);
        assert!(p.pre_split && p.search_depth_threshold == 2, "{p:?}");
        let above = FULL_REINSERTION_UP_TO + 1;
        for (q, preset) in [
            (BvhQuality::Medium, BvhBuildParams::medium_build()),
            (BvhQuality::High, BvhBuildParams::slow_build()),
        ] {
            let p = build_params(q, above);
            assert_eq!(p.reinsertion_batch_ratio, preset.reinsertion_batch_ratio);
        }
        for n in [1, above] {
            let p = build_params(BvhQuality::Low, n);
            let preset = BvhBuildParams::very_fast_build();
            assert_eq!(p.reinsertion_batch_ratio, preset.reinsertion_batch_ratio);
        }
    }

    #[test]
    fn boxes_with_one_centre_become_one_group() {
        let cube = |c: f32, r: f32| PrimBox(Aabb::new(Vec3A::splat(c - r), Vec3A::splat(c + r)));
        // Distinct centres, or fewer than 16 at one: nothing to gather.
        assert!(Coincident::find(&[cube(0.0, 1.0), cube(1.0, 1.0)]).is_none());
        assert!(Coincident::find(&vec![cube(0.0, 1.0); COINCIDENT_FROM - 1]).is_none());
        // Sixteen at 0 (one larger), one at 5 and fifteen at 7 (kept apart), the rest at 0.
        let mut boxes = vec![cube(0.0, 1.0), cube(5.0, 1.0), cube(0.0, 2.0)];
        boxes.extend(vec![cube(7.0, 1.0); 15]);
        boxes.extend(vec![cube(0.0, 1.0); 14]);
        let g = Coincident::find(&boxes).expect("sixteen share a centre");
        assert_eq!(g.boxes.len(), 1 + 1 + 15);
        let at_zero: Vec<u32> = [0, 2].into_iter().chain(18..32).collect();
        assert_eq!(&g.members[..16], &at_zero[..]);
        assert_eq!(&g.starts[..3], &[0, 16, 17]);
        let apart: Vec<u32> = [1].into_iter().chain(3..18).collect();
        assert_eq!(&g.members[16..], &apart[..]);
        assert_eq!(g.boxes[0].0, cube(0.0, 2.0).0);
        assert_eq!(g.boxes[1].0, cube(5.0, 1.0).0);
        // A tree over the groups: a leaf of group 1 (one primitive), then a leaf of group 0
        // (sixteen) and group 2 (one); expanded, the leaves hold 1 and 17 primitives.
        let mut t = Bvh2 {
            nodes: vec![
                Bvh2Node::new(cube(2.0, 6.0).0, 0, 1),
                Bvh2Node::new(g.boxes[1].0, 1, 0),
                Bvh2Node::new(g.boxes[0].0.union(&g.boxes[2].0), 2, 1),
            ],
            primitive_indices: vec![1, 0, 2],
            ..Bvh2::default()
        };
        g.expand(&mut t);
        let mut want = vec![1];
        want.extend(&at_zero);
        want.push(3);
        assert_eq!(t.primitive_indices, want);
        assert_eq!((t.nodes[1].first_index, t.nodes[1].prim_count), (0, 1));
        assert_eq!((t.nodes[2].first_index, t.nodes[2].prim_count), (1, 17));
    }
}
