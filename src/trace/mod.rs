//! Tracing: the camera, deterministic sampling, shading, the observer and its records, and the
//! one recursive Whitted tracer.

pub mod camera;
pub mod describe;
pub mod diff;
pub mod formula;
pub mod observer;
pub mod record;
pub mod sampling;
pub mod shading;
pub mod validate;
pub mod whitted;

pub use observer::{Counter, Observer, Recorder, Silent};
pub use record::{
    HitRecord, NodeAction, NodeVisit, OutlineNode, RayKind, RayRecord, Stage, Step, StepRecord,
    Trace, TraceError, TraceObject,
};
pub use whitted::Tracer;
