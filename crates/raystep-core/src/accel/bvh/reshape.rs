//! obvhs's tree reshaped before raystep lays it out: a leaf that mixes triangles and balls
//! split in two (`split_mixed_leaves`), and a tree cut at the depth a trace may record
//! (`cap_depth`). Both take and give obvhs's own `Bvh2`, so the layout that follows
//! (`super::build`) sees one tree whatever was changed.

use super::build::PrimBox;
use obvhs::aabb::Aabb;
use obvhs::bvh2::{Bvh2, node::Bvh2Node};

/// Every leaf of `tree` that holds both triangles and other shapes (balls) made an inner node
/// over two leaves: its triangles, then the rest, each part in the leaf's own order, each with
/// the box of its own primitives. obvhs's builder weighs every primitive alike, so it may leave
/// a ball in a leaf with the wall it rests against (the Cornell box's two balls each shared a
/// leaf with two wall triangles, whose box every ray in the room enters): then every ray that
/// enters the leaf tests the ball, where a leaf of its own has a box that most rays miss, and
/// the triangles alone can be tested four at a time (the AVX2 build's packs). The tree does not
/// depend on the machine (the split is made on every one), and a leaf of one kind is untouched,
/// so a scene of triangles only, or of balls only, keeps obvhs's tree node for node.
pub(super) fn split_mixed_leaves(
    tree: &mut Bvh2,
    boxes: &[PrimBox],
    is_triangle: impl Fn(u32) -> bool,
) {
    let bound = |prims: &[u32]| {
        prims.iter().fold(Aabb::INVALID, |b, &p| {
            b.union(&boxes.get(p as usize).map_or(Aabb::INVALID, |x| x.0))
        })
    };
    let mut split = false;
    for i in 0..tree.nodes.len() {
        let Some(&n) = tree.nodes.get(i) else { break };
        if !n.is_leaf() {
            continue;
        }
        let first = n.first_index as usize;
        let Some(prims) = tree
            .primitive_indices
            .get_mut(first..first + n.prim_count as usize)
        else {
            continue;
        };
        // Most leaves are of one kind: they are looked at, not copied.
        let triangles = prims.iter().filter(|&&p| is_triangle(p)).count();
        if triangles == 0 || triangles == prims.len() {
            continue;
        }
        let (mut parts, rest): (Vec<u32>, Vec<u32>) = prims.iter().partition(|&&p| is_triangle(p));
        parts.extend(rest);
        prims.copy_from_slice(&parts);
        let (a, b) = parts.split_at(triangles);
        let at = tree.nodes.len() as u32;
        tree.nodes
            .push(Bvh2Node::new(bound(a), a.len() as u32, n.first_index));
        tree.nodes.push(Bvh2Node::new(
            bound(b),
            b.len() as u32,
            n.first_index + a.len() as u32,
        ));
        if let Some(node) = tree.nodes.get_mut(i) {
            *node = Bvh2Node::new(*n.aabb(), 0, at);
        }
        split = true;
    }
    if split {
        // obvhs's optional maps no longer hold; nothing here reads them.
        tree.parents.clear();
        tree.primitives_to_nodes.clear();
        tree.children_are_ordered_after_parents = false;
    }
}

/// `tree` with every inner node at depth `limit` made a leaf of all the primitives below it, so
/// that no node lies deeper than `limit` (the depth a trace may record, [`MAX_BVH_DEPTH`](crate::record::validate::MAX_BVH_DEPTH)).
/// Gathering coincident primitives (see `Coincident` in `super::build`) keeps obvhs's trees far shallower on every
/// scene seen; this is the bound should some other arrangement of boxes still chain. A tree
/// within the limit is returned as it is; a deeper one is rewritten, its nodes in depth-first
/// order (children after their parent) and its leaves' primitives side by side.
pub(super) fn cap_depth(tree: Bvh2, limit: u32) -> Bvh2 {
    let nodes = &tree.nodes;
    let child = |n: &Bvh2Node, k: u32| nodes.get((n.first_index + k) as usize);
    // The depth, without recursion.
    let mut deepest = 0u32;
    let mut stack = vec![(0usize, 0u32)];
    while let Some((i, d)) = stack.pop() {
        let Some(n) = nodes.get(i) else { continue };
        deepest = deepest.max(d);
        if deepest > limit {
            break;
        }
        if !n.is_leaf() {
            stack.push((n.first_index as usize, d + 1));
            stack.push((n.first_index as usize + 1, d + 1));
        }
    }
    if deepest <= limit {
        return tree;
    }
    let prims = &tree.primitive_indices;
    let leaf_prims = |n: &Bvh2Node| {
        prims
            .get(n.first_index as usize..n.first_index as usize + n.prim_count as usize)
            .unwrap_or_default()
    };
    let mut out_nodes: Vec<Bvh2Node> = Vec::with_capacity(nodes.len());
    let mut out_prims: Vec<u32> = Vec::with_capacity(prims.len());
    // (old index, new index, depth): the new node is already placed, its fields to be set.
    let mut todo = vec![(0usize, 0usize, 0u32)];
    out_nodes.push(nodes.first().copied().unwrap_or_default());
    while let Some((old, new, depth)) = todo.pop() {
        let Some(n) = nodes.get(old) else { continue };
        let first_prim = out_prims.len() as u32;
        if n.is_leaf() {
            out_prims.extend_from_slice(leaf_prims(n));
        } else if depth >= limit {
            // Every primitive below, in the subtree's own order.
            let mut below = vec![old];
            while let Some(j) = below.pop() {
                let Some(m) = nodes.get(j) else { continue };
                if m.is_leaf() {
                    out_prims.extend_from_slice(leaf_prims(m));
                } else {
                    below.push(m.first_index as usize + 1);
                    below.push(m.first_index as usize);
                }
            }
        } else if let (Some(_), Some(_)) = (child(n, 0), child(n, 1)) {
            let at = out_nodes.len();
            out_nodes.push(Bvh2Node::default());
            out_nodes.push(Bvh2Node::default());
            if let Some(p) = out_nodes.get_mut(new) {
                *p = Bvh2Node::new(*n.aabb(), 0, at as u32);
            }
            todo.push((n.first_index as usize + 1, at + 1, depth + 1));
            todo.push((n.first_index as usize, at, depth + 1));
            continue;
        }
        let count = out_prims.len() as u32 - first_prim;
        if let Some(p) = out_nodes.get_mut(new) {
            *p = Bvh2Node::new(*n.aabb(), count, first_prim);
        }
    }
    let mut capped = Bvh2 {
        nodes: out_nodes,
        primitive_indices: out_prims,
        ..Bvh2::default()
    };
    capped.uses_spatial_splits = tree.uses_spatial_splits;
    capped.max_depth = tree.max_depth;
    capped.children_are_ordered_after_parents = true;
    capped
}

/// A node's box, primitive count and first index as bits, to compare trees exactly.
#[cfg(test)]
pub(super) fn node_bits(n: &Bvh2Node) -> [u32; 8] {
    let (lo, hi) = (n.aabb().min, n.aabb().max);
    [
        lo.x.to_bits(),
        lo.y.to_bits(),
        lo.z.to_bits(),
        hi.x.to_bits(),
        hi.y.to_bits(),
        hi.z.to_bits(),
        n.prim_count,
        n.first_index,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3A;

    /// A chain of `n` leaves, each inner node's second child the next inner node: depth n − 1,
    /// leaf k holding primitive k.
    fn chain(n: u32) -> Bvh2 {
        let b = |k: u32| Aabb::new(Vec3A::splat(k as f32), Vec3A::splat(n as f32));
        let mut nodes = vec![Bvh2Node::new(b(0), 0, 1)];
        for k in 0..n - 1 {
            let first = nodes.len() as u32;
            // Children at first (a leaf: primitive k) and first + 1 (the rest of the chain).
            nodes.push(Bvh2Node::new(b(k), 1, k));
            if k + 2 == n {
                nodes.push(Bvh2Node::new(b(k + 1), 1, k + 1));
            } else {
                nodes.push(Bvh2Node::new(b(k + 1), 0, first + 2));
            }
        }
        Bvh2 {
            nodes,
            primitive_indices: (0..n).rev().collect(),
            ..Bvh2::default()
        }
    }

    /// Every node's depth and every primitive reached, walking from the root.
    fn walk(t: &Bvh2) -> (u32, Vec<u32>) {
        let (mut deepest, mut prims) = (0, vec![]);
        let mut stack = vec![(0usize, 0u32)];
        while let Some((i, d)) = stack.pop() {
            let n = t.nodes[i];
            deepest = deepest.max(d);
            if n.is_leaf() {
                let r = n.first_index as usize..(n.first_index + n.prim_count) as usize;
                prims.extend_from_slice(&t.primitive_indices[r]);
            } else {
                stack.push((n.first_index as usize, d + 1));
                stack.push((n.first_index as usize + 1, d + 1));
            }
        }
        prims.sort_unstable();
        (deepest, prims)
    }

    /// A leaf of triangles and a ball becomes an inner node over a leaf of the triangles and
    /// a leaf of the ball, each with its own primitives' box (worked out by hand); a leaf of
    /// triangles only is left as it was.
    #[test]
    fn a_leaf_of_triangles_and_a_ball_becomes_two_leaves() {
        // Primitive p's box: the cube of half-side 0.5 about (p, 0, 0); primitive 1 is the ball.
        let cube = |p: f32| {
            Aabb::new(
                Vec3A::new(p - 0.5, -0.5, -0.5),
                Vec3A::new(p + 0.5, 0.5, 0.5),
            )
        };
        let boxes: Vec<PrimBox> = (0..6).map(|p| PrimBox(cube(p as f32))).collect();
        let all = Aabb::new(Vec3A::new(-0.5, -0.5, -0.5), Vec3A::new(5.5, 0.5, 0.5));
        let left = Aabb::new(Vec3A::new(-0.5, -0.5, -0.5), Vec3A::new(2.5, 0.5, 0.5));
        let right = Aabb::new(Vec3A::new(2.5, -0.5, -0.5), Vec3A::new(5.5, 0.5, 0.5));
        let mut t = Bvh2 {
            nodes: vec![
                Bvh2Node::new(all, 0, 1),
                Bvh2Node::new(left, 3, 0),
                Bvh2Node::new(right, 2, 3),
            ],
            primitive_indices: vec![2, 1, 0, 3, 5],
            ..Bvh2::default()
        };
        split_mixed_leaves(&mut t, &boxes, |p| p != 1);
        assert_eq!(t.nodes.len(), 5);
        // The mixed leaf is now an inner node (same box) over nodes 3 and 4.
        assert_eq!(
            node_bits(&t.nodes[1]),
            node_bits(&Bvh2Node::new(left, 0, 3))
        );
        // Its triangles 2 and 0 (in that order) from (−0.5, −0.5, −0.5) to (2.5, 0.5, 0.5), then
        // the ball alone in its own cube.
        assert_eq!(t.primitive_indices, vec![2, 0, 1, 3, 5]);
        assert_eq!(
            node_bits(&t.nodes[3]),
            node_bits(&Bvh2Node::new(left, 2, 0))
        );
        let ball = Aabb::new(Vec3A::new(0.5, -0.5, -0.5), Vec3A::new(1.5, 0.5, 0.5));
        assert_eq!(
            node_bits(&t.nodes[4]),
            node_bits(&Bvh2Node::new(ball, 1, 2))
        );
        // Untouched: the root and the leaf of triangles 3 and 5.
        assert_eq!(node_bits(&t.nodes[0]), node_bits(&Bvh2Node::new(all, 0, 1)));
        assert_eq!(
            node_bits(&t.nodes[2]),
            node_bits(&Bvh2Node::new(right, 2, 3))
        );
        // A tree with no mixed leaf is left node for node.
        let before: Vec<[u32; 8]> = t.nodes.iter().map(node_bits).collect();
        split_mixed_leaves(&mut t, &boxes, |p| p != 1);
        assert_eq!(t.nodes.iter().map(node_bits).collect::<Vec<_>>(), before);
        assert_eq!(t.primitive_indices, vec![2, 0, 1, 3, 5]);
    }

    #[test]
    fn a_tree_deeper_than_the_limit_is_cut_there_and_keeps_every_primitive() {
        let t = chain(300);
        assert_eq!(walk(&t).0, 299);
        let capped = cap_depth(t.clone(), 256);
        let (depth, prims) = walk(&capped);
        assert_eq!(depth, 256);
        assert_eq!(prims, (0..300).collect::<Vec<u32>>());
        // The inner node at the cut holds the 300 − 256 primitives below it, in one leaf.
        let leaves: Vec<u32> = capped
            .nodes
            .iter()
            .filter(|n| n.is_leaf())
            .map(|n| n.prim_count)
            .collect();
        assert_eq!(leaves.iter().max(), Some(&44));
        // Within the limit: unchanged.
        let short = chain(200);
        let same = cap_depth(short.clone(), 256);
        assert_eq!(same.nodes.len(), short.nodes.len());
        assert_eq!(same.primitive_indices, short.primitive_indices);
    }
}
