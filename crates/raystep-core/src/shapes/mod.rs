//! The shapes ([`Shape`]) and their intersection kernels, one file per primitive.
//!
//! Every kernel is a pure function that returns a *test record*: every intermediate the course
//! notes (docs/SOURCES.md) compute, in order, plus the outcome. The renderer calls the very same
//! function and reads only the outcome; because the kernels are `#[inline]` and the record is plain
//! data, the unused intermediates are dead code on the render path. This is how raystep keeps one
//! copy of each kernel: there is no separate "teaching" version.

pub mod aabb;
pub mod plane;
pub mod shape;
pub mod sphere;
pub mod triangle;

pub use aabb::{BoxMethod, BoxTest, SlabAxis};
pub use plane::{PlaneForm, PlaneTest};
pub use shape::Shape;
pub use sphere::{RootChoice, SphereCase, SphereMethod, SphereTest};
pub use triangle::{TriangleMethod, TriangleTest};
