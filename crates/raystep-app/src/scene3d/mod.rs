//! The 3D view in the app (the central panel's "3D view" tab): the scene in space with the
//! camera, its image plane and the selected pixel's rays up to the current step, drawn by
//! [`crate::view3d`] on eframe's own wgpu device. Drag to orbit, right-drag to pan, scroll to
//! zoom, double-click to reset; click an object to select it and drag the coloured arrows to
//! move it; the editor beside the view changes radii, materials and lights, with undo, redo and
//! save. Every edit re-traces the pixel and restarts the render.
//!
//! [`view`] draws the picture and the tab around it, [`picking`] turns clicks and drags into
//! selections and moves (the coloured arrows), [`editor`] is the panel of values beside it.

mod editor;
mod picking;
mod view;

use crate::scene::{Scene, Shape};
use crate::view3d::geometry;
use glam::Vec3;

pub use view::{FAN, Scene3dView, docked, tab};

/// Where an object group is, for its handles: a sphere's centre, the mean of triangle vertices,
/// a plane's point nearest the scene's centre.
pub(super) fn group_center(scene: &Scene, group: u32) -> Option<Vec3> {
    let g = scene.groups.get(group as usize)?;
    let objs = scene
        .objects
        .get(g.first as usize..(g.first + g.count) as usize)?;
    let mut sum = Vec3::ZERO;
    let mut n = 0.0;
    let b = geometry::bounds(scene);
    for o in objs {
        match o.shape {
            Shape::Sphere { center, .. } => {
                sum += center;
                n += 1.0;
            }
            Shape::Triangle { p } => {
                sum += p[0] + p[1] + p[2];
                n += 3.0;
            }
            Shape::Plane { normal, offset } => {
                sum += b.center - normal * (normal.dot(b.center) - offset);
                n += 1.0;
            }
            Shape::AxisPlane { axis, offset } => {
                let mut c = b.center;
                c[axis.min(2)] = offset;
                sum += c;
                n += 1.0;
            }
        }
    }
    (n > 0.0).then(|| sum / n).filter(|c| c.is_finite())
}
