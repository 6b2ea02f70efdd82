//! obvhs's leaf collapse (`bvh2::leaf_collapser::collapse`), computed in one walk: the same
//! tree, node for node and primitive for primitive, in half to three quarters of the time on big trees.
//!
//! Why raystep has its own: PLOC builds bottom up, one primitive a leaf, and the collapse then
//! merges two leaves into one wherever the SAH says a leaf of both costs less than the node
//! above them. obvhs decides this bottom up in parallel, each thread climbing from a leaf by
//! parent links with an atomic counter at every node; then, for every merged node, walks its
//! subtree again to gather its primitives; then computes every parent link again. On the
//! million-triangle tetrahedron (SPD tetra 9, two million nodes before the collapse) that took
//! 144–203 ms on two cores after `medium`'s first reinsertion and 101–137 ms after `low`'s.
//! Here one post-order walk with a stack decides every node (a node after its two children)
//! and lays out the leaves' primitives in the walk's order as it goes, so that a merged node's
//! primitives are already one run; one pass in index order then writes the kept nodes, their
//! primitives and the parent links: 76–118 and 70–111 ms on one core (eight alternated runs of
//! each on the same trees). The test below compares the two on random trees.

use obvhs::bvh2::{Bvh2, leaf_collapser, node::Bvh2Node};

/// What obvhs's `leaf_collapser::collapse(bvh, max_prims, traversal_cost)` does to `bvh`,
/// the same result. The cases this module does not handle itself, none of which obvhs's builds
/// make (the whole tree collapsing into its root, nodes the root does not reach, a tree that
/// keeps a primitive-to-node map), go to obvhs's own.
pub(super) fn collapse(bvh: &mut Bvh2, max_prims: u32, traversal_cost: f32) {
    let n = bvh.nodes.len();
    // obvhs's own early returns, in its order.
    if max_prims <= 1 || n as u64 <= u64::from(max_prims) * 2 + 1 {
        return;
    }
    if !bvh.primitive_indices.is_empty() && bvh.primitive_indices.len() as u64 <= max_prims.into() {
        return;
    }
    if bvh.nodes[0].is_leaf() {
        return;
    }
    if !bvh.primitives_to_nodes.is_empty() {
        leaf_collapser::collapse(bvh, max_prims, traversal_cost);
        return;
    }
    let Some(plan) = Plan::decide(bvh, max_prims, traversal_cost) else {
        leaf_collapser::collapse(bvh, max_prims, traversal_cost);
        return;
    };
    plan.apply(bvh);
}

/// The collapse's decisions for every node of a tree, and its leaves' primitives in walk order.
struct Plan {
    /// Primitives of the leaf each node becomes (0: it stays an inner node, or it is merged
    /// into its parent).
    prims: Vec<u32>,
    /// Whether the node stays in the tree (false: its parent or an ancestor became a leaf).
    kept: Vec<bool>,
    /// Where each node's primitives start in `walk_prims`.
    before: Vec<u32>,
    /// Every leaf's primitives, the leaves in the walk's order (first child first).
    walk_prims: Vec<u32>,
}

impl Plan {
    /// Decides every node bottom up, as obvhs does: a node whose two children are (or have
    /// become) leaves becomes one leaf of both when that leaf holds at most `max_prims`
    /// primitives and its cost, area × (primitives − `traversal_cost`), is at most the children's,
    /// Σ area × primitives — or when both children are the one primitive (a split's halves).
    /// None when the root itself would become a leaf, or when the links from the root do not
    /// reach every node exactly once.
    fn decide(bvh: &Bvh2, max_prims: u32, traversal_cost: f32) -> Option<Plan> {
        let nodes = &bvh.nodes;
        let n = nodes.len();
        let source = &bvh.primitive_indices;
        let mut plan = Plan {
            prims: vec![0; n],
            kept: vec![true; n],
            before: vec![0; n],
            walk_prims: Vec::with_capacity(source.len()),
        };
        // A node's index with this bit set: its children are decided, decide it.
        const CHILDREN_DONE: u32 = 1 << 31;
        if n as u64 >= u64::from(CHILDREN_DONE) {
            return None;
        }
        let mut stack = vec![0u32];
        let mut visits = 0usize;
        while let Some(top) = stack.pop() {
            let i = (top & !CHILDREN_DONE) as usize;
            let node = nodes.get(i)?;
            if top & CHILDREN_DONE == 0 {
                // A tree visits each node once; more visits means the links are not a tree.
                visits += 1;
                if visits > n {
                    return None;
                }
                plan.before[i] = plan.walk_prims.len() as u32;
                if node.is_leaf() {
                    let first = node.first_index as usize;
                    plan.walk_prims
                        .extend_from_slice(source.get(first..first + node.prim_count as usize)?);
                    plan.prims[i] = node.prim_count;
                } else {
                    stack.push(i as u32 | CHILDREN_DONE);
                    stack.push(node.first_index.checked_add(1)?);
                    stack.push(node.first_index);
                }
                continue;
            }
            let c = node.first_index as usize;
            let (left, right) = (nodes.get(c)?, nodes.get(c + 1)?);
            let (l, r) = (plan.prims[c], plan.prims[c + 1]);
            let total = l + r;
            if l > 0 && r > 0 && total <= max_prims {
                let merged = node.aabb().half_area() * (total as f32 - traversal_cost);
                let apart =
                    left.aabb().half_area() * l as f32 + right.aabb().half_area() * r as f32;
                let one_primitive = left.first_index == right.first_index && total == 2;
                if merged <= apart || one_primitive {
                    plan.prims[i] = total;
                    plan.prims[c] = 0;
                    plan.prims[c + 1] = 0;
                    plan.kept[c] = false;
                    plan.kept[c + 1] = false;
                }
            }
        }
        // A node the walk did not reach (obvhs's builds leave none) would be decided by obvhs
        // as its own leaf; leave such an array to obvhs.
        (visits == n && plan.prims[0] == 0).then_some(plan)
    }

    /// Writes the collapsed tree into `bvh`: the kept nodes in their index order, each new
    /// leaf's primitives after the previous one's, and (if `bvh` had them) the parent links.
    fn apply(self, bvh: &mut Bvh2) {
        let nodes = &bvh.nodes;
        // Each node's index in the collapsed tree: the kept nodes before it.
        let mut new_index = Vec::with_capacity(nodes.len());
        let mut kept_count = 0u32;
        for &k in &self.kept {
            new_index.push(kept_count);
            kept_count += u32::from(k);
        }
        let mut out: Vec<Bvh2Node> = Vec::with_capacity(kept_count as usize);
        let mut prims: Vec<u32> = Vec::with_capacity(self.walk_prims.len());
        for (i, node) in nodes.iter().enumerate() {
            if !self.kept[i] {
                continue;
            }
            let mut node = *node;
            let count = self.prims[i];
            if count > 0 {
                let start = self.before[i] as usize;
                node.prim_count = count;
                node.first_index = prims.len() as u32;
                prims.extend_from_slice(&self.walk_prims[start..start + count as usize]);
            } else if !node.is_leaf() {
                node.first_index = new_index[node.first_index as usize];
            }
            out.push(node);
        }
        // obvhs recomputes the parent links when the tree had them, and drops them otherwise.
        let parents = if bvh.parents.is_empty() {
            vec![]
        } else {
            let mut parents = vec![0u32; out.len()];
            for (i, node) in out.iter().enumerate() {
                if !node.is_leaf() {
                    let c = node.first_index as usize;
                    parents[c] = i as u32;
                    parents[c + 1] = i as u32;
                }
            }
            parents
        };
        bvh.nodes = out;
        bvh.primitive_indices = prims;
        bvh.parents = parents;
    }
}

#[cfg(test)]
mod tests {
    use super::super::reshape::node_bits;
    use super::*;
    use glam::Vec3A;
    use obvhs::aabb::Aabb;
    use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
    use obvhs::ploc::{PlocBuilder, PlocSearchDistance, SortPrecision};

    /// A small deterministic generator (SplitMix64), so that the trees are the same every run.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f32 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    /// Boxes scattered in clusters of varied sizes (some flat, some repeated), so that PLOC's
    /// trees have leaves that merge and leaves that do not.
    fn boxes(count: usize, seed: u64) -> Vec<Aabb> {
        let mut rng = Rng(seed);
        let mut out = Vec::with_capacity(count);
        while out.len() < count {
            let c = Vec3A::new(rng.next(), rng.next(), rng.next()) * 100.0;
            for _ in 0..1 + (rng.next() * 12.0) as usize {
                let p = c + Vec3A::new(rng.next(), rng.next(), rng.next()) * 4.0;
                let mut size = Vec3A::new(rng.next(), rng.next(), rng.next()) * rng.next() * 3.0;
                if rng.next() < 0.2 {
                    size.y = 0.0;
                }
                let b = Aabb::new(p, p + size);
                out.push(b);
                if rng.next() < 0.05 {
                    out.push(b);
                }
            }
        }
        out.truncate(count);
        out
    }

    fn bits(t: &Bvh2) -> Vec<[u32; 8]> {
        t.nodes.iter().map(node_bits).collect()
    }

    /// On PLOC trees of 1 to 5,000 primitives, with and without reinsertion before (so with and
    /// without parent links, and with nodes out of PLOC's order), for several leaf sizes and
    /// traversal costs: the same nodes bit for bit, the same primitives, the same parent links
    /// as obvhs's `collapse`.
    #[test]
    fn the_collapse_is_obvhs_own() {
        let mut compared = 0;
        for (k, count) in [1usize, 2, 9, 17, 18, 40, 300, 1000, 5000]
            .into_iter()
            .enumerate()
        {
            let boxes = boxes(count, k as u64 + 1);
            for reinsert in [0.0, 0.05, 1.0] {
                let mut tree = PlocBuilder::with_capacity(count).build(
                    PlocSearchDistance::Minimum,
                    &boxes,
                    (0..count as u32).collect(),
                    SortPrecision::U64,
                    0,
                );
                ReinsertionOptimizer::default().run(&mut tree, reinsert, None);
                for (max_prims, cost) in [(8, 3.0), (4, 1.0), (2, 0.5), (1, 3.0), (255, 8.0)] {
                    let mut ours = tree.clone();
                    let mut theirs = tree.clone();
                    collapse(&mut ours, max_prims, cost);
                    leaf_collapser::collapse(&mut theirs, max_prims, cost);
                    let what =
                        format!("{count} boxes, reinsertion {reinsert}, {max_prims}, {cost}");
                    assert_eq!(bits(&ours), bits(&theirs), "{what}");
                    assert_eq!(ours.primitive_indices, theirs.primitive_indices, "{what}");
                    assert_eq!(ours.parents, theirs.parents, "{what}");
                    compared += usize::from(theirs.nodes.len() < tree.nodes.len());
                }
            }
        }
        // Most of the cases collapsed something (not only the early returns).
        assert!(compared >= 30, "{compared}");
    }
}
