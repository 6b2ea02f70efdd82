//! The top-level BVH: obvhs's build over the instances' world boxes, in raystep's node layout.

use super::build::{PrimBox, build_bvh2, build_params, depth_first};
use super::reshape::cap_depth;
use super::{Node, parallel::map_in_order};
use crate::platform::Duration;
use crate::record::validate::MAX_BVH_DEPTH;
use crate::scene::{BvhQuality, Instance};
use glam::Vec3A;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;

/// A BVH over instances: its leaves hold instance ids.
#[derive(Debug, Clone, Default)]
pub struct Tlas {
    /// The nodes, depth first; `nodes[0]` is the root (none: no instances).
    pub nodes: Vec<Node>,
    /// Instance ids in leaf order (a leaf holds `leaf_instances[first..first + count]`).
    pub leaf_instances: Vec<u32>,
}

impl Tlas {
    /// Builds the tree over the instances' world boxes.
    pub fn build(instances: &[Instance], quality: BvhQuality) -> Tlas {
        if instances.is_empty() {
            return Tlas::default();
        }
        let boxes = map_in_order(instances, |i| {
            PrimBox(Aabb::new(Vec3A::from(i.min), Vec3A::from(i.max)))
        });
        let mut core = Duration::ZERO;
        let bvh2: Bvh2 = build_bvh2(&boxes, build_params(quality, boxes.len()), &mut core);
        let bvh2 = cap_depth(bvh2, MAX_BVH_DEPTH);
        Tlas {
            nodes: depth_first(&bvh2.nodes),
            leaf_instances: bvh2.primitive_indices.clone(),
        }
    }

    /// The instance ids of a leaf.
    #[inline(always)]
    pub fn leaf(&self, node: &Node) -> &[u32] {
        self.leaf_instances
            .get(node.first as usize..node.first as usize + node.count as usize)
            .unwrap_or_default()
    }

    /// Bytes the tree takes.
    pub fn memory(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>() + self.leaf_instances.len() * 4
    }
}
