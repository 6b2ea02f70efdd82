//! Tracing: deterministic sampling, Phong/Snell/Schlick shading and
//! the one recursive Whitted tracer. What the tracer reports — the observer and its records —
//! lives one layer down, in [`crate::record`].

pub mod prepared;
pub mod sampling;
pub mod shading;
pub mod whitted;

pub use prepared::PreparedScene;
pub use whitted::Tracer;
