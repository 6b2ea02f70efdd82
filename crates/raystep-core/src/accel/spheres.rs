//! A hierarchy of bounding spheres: the "Raytracing" slides' second way (docs/SOURCES.md) of
//! avoiding tests.
//!
//! The tree is the BVH's own tree (obvhs's build, see [`super::Bvh`]) with every box replaced by
//! a sphere, built bottom-up: a leaf's sphere encloses its primitives' bounding spheres (a
//! sphere's own; a triangle's centred on its box's centre through its farthest vertex), an inner
//! node's encloses its two children's. Reusing the BVH's topology makes the comparison a fair one:
//! the two hierarchies group the same primitives the same way and differ only in the bounding
//! shape — which is exactly the lesson (a sphere is cheaper to test than a box and rotates
//! freely, but bounds long thin things far more loosely).
//!
//! Each node visit is lesson 2's ray–sphere test (the scene's sphere method): the ray is inside
//! the sphere between the two roots, so the node is culled when there are no real roots or
//! [t₀, t₁] does not meet (t_min, t_max). Children are visited nearer first (by t₀), except that
//! a shadow ray, which any blocker stops, takes the farther first, as in the BVH (see the BVH's
//! `AnyHit`); infinite planes stay outside the tree and are tested first.

use super::bvh::shape_bounds;
use super::{Accelerator, Bvh, Hit, any_of, closest_of, test_any, test_closest};
use crate::math::Ray;
use crate::record::{NodeAction, Observer, Step};
use crate::scene::{Scene, Shape};
use crate::shapes::{SphereMethod, SphereTest, sphere};
use glam::Vec3;
use smallvec::SmallVec;

/// A node: its bounding sphere and, as in the BVH, its leaf range or first child.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereNode {
    /// The centre.
    pub center: Vec3,
    /// The radius.
    pub radius: f32,
    /// Leaf: index of its first object in [`SphereTree::leaf_objects`]; inner: its first child
    /// (the second is `first + 1`).
    pub first: u32,
    /// Number of objects in a leaf; 0 for an inner node.
    pub count: u32,
}

impl SphereNode {
    /// Whether the node is a leaf.
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// The bounding-sphere hierarchy.
#[derive(Debug, Clone)]
pub struct SphereTree {
    /// The nodes; `nodes[0]` is the root.
    pub nodes: Vec<SphereNode>,
    /// Object ids in leaf order.
    pub leaf_objects: Vec<u32>,
    /// Infinite primitives (planes), tested before the tree.
    pub planes: Vec<u32>,
}

/// The smallest sphere enclosing two spheres.
fn merge((c1, r1): (Vec3, f32), (c2, r2): (Vec3, f32)) -> (Vec3, f32) {
    let d = c1.distance(c2);
    if d + r2 <= r1 {
        (c1, r1)
    } else if d + r1 <= r2 {
        (c2, r2)
    } else {
        let r = (d + r1 + r2) * 0.5;
        (c1 + (c2 - c1) * ((r - r1) / d), r)
    }
}

/// A bounding sphere of one finite primitive.
fn primitive_sphere(shape: &Shape) -> Option<(Vec3, f32)> {
    match *shape {
        Shape::Sphere { center, radius } => Some((center, radius)),
        Shape::Triangle { p } => {
            let (lo, hi) = shape_bounds(shape)?;
            let c = (lo + hi) * 0.5;
            let r = p.iter().map(|v| v.distance(c)).fold(0.0, f32::max);
            Some((c, r))
        }
        Shape::Plane { .. } | Shape::AxisPlane { .. } => None,
    }
}

/// Grows a radius so that f32 rounding in the merges cannot leave a point outside.
fn pad((c, r): (Vec3, f32)) -> (Vec3, f32) {
    (c, r * (1.0 + 1e-5) + c.abs().max_element() * 1e-6 + 1e-6)
}

impl SphereTree {
    /// Builds the sphere tree over `bvh`'s topology for `scene`.
    pub fn from_bvh(scene: &Scene, bvh: &Bvh) -> SphereTree {
        let mut nodes: Vec<SphereNode> = bvh
            .nodes
            .iter()
            .map(|n| SphereNode {
                center: Vec3::ZERO,
                radius: 0.0,
                first: n.first,
                count: n.count,
            })
            .collect();
        // Children before their parents: the reverse of a pre-order walk from the root.
        let mut order = Vec::with_capacity(nodes.len());
        let mut todo = vec![0usize];
        while let Some(i) = todo.pop() {
            let Some(n) = nodes.get(i) else { continue };
            order.push(i);
            if !n.is_leaf() {
                todo.push(n.first as usize);
                todo.push(n.first as usize + 1);
            }
        }
        for &i in order.iter().rev() {
            let n = nodes[i];
            let s = if n.is_leaf() {
                let ids = bvh
                    .leaf_objects
                    .get(n.first as usize..(n.first + n.count) as usize)
                    .unwrap_or(&[]);
                ids.iter()
                    .filter_map(|&id| primitive_sphere(&scene.objects[id as usize].shape))
                    .map(pad)
                    .reduce(merge)
            } else {
                let (a, b) = (n.first as usize, n.first as usize + 1);
                match (nodes.get(a), nodes.get(b)) {
                    (Some(a), Some(b)) => Some(merge((a.center, a.radius), (b.center, b.radius))),
                    _ => None,
                }
            };
            let (c, r) = pad(s.unwrap_or((Vec3::ZERO, 0.0)));
            nodes[i].center = c;
            nodes[i].radius = r;
        }
        SphereTree {
            nodes,
            leaf_objects: bvh.leaf_objects.clone(),
            planes: bvh.planes.clone(),
        }
    }

    /// Builds the BVH and the sphere tree over it.
    pub fn build(scene: &Scene) -> SphereTree {
        SphereTree::from_bvh(scene, &Bvh::build(scene))
    }

    /// Bytes the tree takes.
    pub fn memory(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<SphereNode>()
            + (self.leaf_objects.len() + self.planes.len()) * 4
    }

    fn leaf(&self, n: &SphereNode) -> &[u32] {
        self.leaf_objects
            .get(n.first as usize..(n.first + n.count) as usize)
            .unwrap_or(&[])
    }

    /// Lesson 2's test against node `i`'s sphere, with the ray's current interval. Returns the
    /// test and where the ray enters the sphere's span within (t_min, t_max), or None if culled.
    #[inline(always)]
    fn test(
        &self,
        scene: &Scene,
        ray: &Ray<f32>,
        n: &SphereNode,
    ) -> (SphereTest<f32>, Option<f32>) {
        let test = match scene.settings.sphere_method {
            SphereMethod::Textbook => sphere::textbook(ray, n.center, n.radius),
            SphereMethod::Stable => sphere::stable(ray, n.center, n.radius),
        };
        let enter = match test.roots {
            Some([t0, t1]) if t1 >= ray.t_min && t0 <= ray.t_max => Some(t0.max(ray.t_min)),
            _ => None,
        };
        (test, enter)
    }

    /// Walks the tree, calling `leaf(object, ray)` for the primitives of every leaf the ray
    /// reaches, nearer subtrees first (`farther_first`: farther first); `leaf` returns false to
    /// stop.
    #[inline(always)]
    fn traverse<O: Observer>(
        &self,
        scene: &Scene,
        ray: &mut Ray<f32>,
        obs: &mut O,
        farther_first: bool,
        mut leaf: impl FnMut(u32, &mut Ray<f32>, &mut O) -> bool,
    ) {
        let Some(root) = self.nodes.first() else {
            return;
        };
        // (node index, depth, action decided by the parent) — the root decides for itself.
        let mut stack: SmallVec<[(u32, u32); 64]> = SmallVec::new();
        let (test, enter) = self.test(scene, ray, root);
        let action = match (enter, root.is_leaf()) {
            (None, _) => NodeAction::Culled,
            (Some(_), true) => NodeAction::TestPrimitives,
            (Some(_), false) => NodeAction::Descend,
        };
        self.report(obs, 0, 0, root, test, action);
        match action {
            NodeAction::Culled => return,
            NodeAction::TestPrimitives => {
                for &id in self.leaf(root) {
                    if !leaf(id, ray, obs) {
                        return;
                    }
                }
                return;
            }
            _ => stack.push((root.first, 1)),
        }
        while let Some((first, depth)) = stack.pop() {
            let (Some(a), Some(b)) = (
                self.nodes.get(first as usize),
                self.nodes.get(first as usize + 1),
            ) else {
                continue;
            };
            let (ta, ea) = self.test(scene, ray, a);
            let (tb, eb) = self.test(scene, ray, b);
            // Nearer first: the child the ray enters first (or the other, `farther_first`).
            let a_first = match (ea, eb) {
                (Some(x), Some(y)) => (x <= y) != farther_first,
                (Some(_), None) => true,
                (None, _) => false,
            };
            let order = if a_first {
                [(first, a, ta, ea), (first + 1, b, tb, eb)]
            } else {
                [(first + 1, b, tb, eb), (first, a, ta, ea)]
            };
            // The second inner child is pushed first, so the first one is popped next.
            let mut descend: SmallVec<[u32; 2]> = SmallVec::new();
            for (k, (id, node, test, enter)) in order.into_iter().enumerate() {
                // The far sphere is re-checked against t_max, which the near leaf may have shrunk.
                let reach = enter.is_some_and(|e| e <= ray.t_max);
                let action = match (reach, node.is_leaf()) {
                    (false, _) => NodeAction::Culled,
                    (true, true) => NodeAction::TestPrimitives,
                    (true, false) if k == 0 => NodeAction::Descend,
                    (true, false) => NodeAction::Pushed,
                };
                self.report(obs, id, depth, node, test, action);
                match action {
                    NodeAction::TestPrimitives => {
                        for &o in self.leaf(node) {
                            if !leaf(o, ray, obs) {
                                return;
                            }
                        }
                    }
                    NodeAction::Descend | NodeAction::Pushed => descend.push(node.first),
                    NodeAction::Culled => {}
                }
            }
            // Push the second first so the first is walked first.
            for &f in descend.iter().rev() {
                stack.push((f, depth + 1));
            }
        }
    }

    #[inline(always)]
    fn report<O: Observer>(
        &self,
        obs: &mut O,
        id: u32,
        depth: u32,
        node: &SphereNode,
        test: SphereTest<f32>,
        action: NodeAction,
    ) {
        obs.accel_visit(|| Step::SphereNode {
            node: id,
            depth,
            center: node.center.to_array(),
            radius: node.radius,
            test,
            leaf: node.is_leaf(),
            children: (!node.is_leaf()).then_some([node.first, node.first + 1]),
            action,
        });
    }
}

impl SphereTree {
    #[inline(always)]
    fn closest_in<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        let mut r = *ray;
        let mut best = None;
        closest_of(scene, &self.planes, &mut r, &mut best, obs);
        self.traverse(scene, &mut r, obs, false, |id, r, obs| {
            test_closest(scene, id, r, &mut best, obs);
            true
        });
        best
    }

    #[inline(always)]
    fn any_in<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        if let Some(h) = any_of(scene, &self.planes, ray, obs) {
            return Some(h);
        }
        let mut found = None;
        let mut r = *ray;
        self.traverse(scene, &mut r, obs, true, |id, r, obs| {
            test_any(scene, id, r, &mut found, obs)
        });
        found
    }
}

two_builds!(SphereTree);

impl Accelerator for SphereTree {
    #[inline]
    fn closest<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        self.closest_fastest(scene, ray, obs)
    }

    #[inline]
    fn any<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        self.any_fastest(scene, ray, obs)
    }

    fn name(&self) -> &'static str {
        "bounding spheres"
    }
}
