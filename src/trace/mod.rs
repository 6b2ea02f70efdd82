//! Tracing: deterministic sampling, where a ray meets a surface and where its children start
//! (`interaction`), the media a ray is inside (`media`), Phong/Snell/Schlick shading and the one
//! recursive Whitted tracer. What the tracer reports — the observer and its records —
//! lives one layer down, in [`crate::record`].

pub mod interaction;
pub mod media;
pub mod prepared;
pub mod sampling;
pub mod shading;
pub mod whitted;

pub use prepared::PreparedScene;
pub use whitted::Tracer;
