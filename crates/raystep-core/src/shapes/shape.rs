//! A primitive's geometry — the one home of the shapes raystep traces, beside their kernels
//! (`sphere.rs`, `plane.rs`, `triangle.rs`). A scene's objects hold a `Shape`; the accelerators
//! dispatch on it to the kernels (`crate::accel::test_shape`).

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// A primitive's geometry.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Shape {
    /// A sphere.
    Sphere {
        /// Centre G.
        center: Vec3,
        /// Radius r > 0.
        radius: f32,
    },
    /// The general plane X·n = offset.
    Plane {
        /// Unit normal.
        normal: Vec3,
        /// offset = P·n for a point P on the plane.
        offset: f32,
    },
    /// The axis-aligned plane X_axis = offset.
    AxisPlane {
        /// 0 = x, 1 = y, 2 = z.
        axis: usize,
        /// The plane's coordinate.
        offset: f32,
    },
    /// A triangle P0, P1, P2.
    Triangle {
        /// The vertices.
        p: [Vec3; 3],
    },
}

impl Shape {
    /// The kind's name, as the scene file spells it.
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Sphere { .. } => "sphere",
            Shape::Plane { .. } | Shape::AxisPlane { .. } => "plane",
            Shape::Triangle { .. } => "triangle",
        }
    }
    /// Whether the shape is unbounded (planes: kept out of the BVH).
    pub fn is_infinite(&self) -> bool {
        matches!(self, Shape::Plane { .. } | Shape::AxisPlane { .. })
    }
}
