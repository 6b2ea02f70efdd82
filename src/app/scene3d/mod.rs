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

pub use view::{FAN, Scene3dView, docked, tab};
