//! Tracing: the [`Tracer`] and its three integrators, each in its own file beside it, and what
//! they stand on — deterministic sampling (`sampling`), where a ray meets a surface and where its
//! children start (`interaction`), the media a ray is inside (`media`), Phong/Snell/Schlick
//! shading (`shading`), textures (`texture`) — and [`PreparedScene`]. What the tracer reports (the observer and its
//! records) lives one layer down, in [`crate::record`]; the samplers, BSDFs and lights the Monte
//! Carlo integrators draw from, in [`crate::mc`].
//!
//! - `tracer.rs`: [`Tracer`] and [`Tracer::trace_sample`], which hands a sample to the scene's
//!   integrator ([`crate::scene::Integrator`]), and what all three share.
//! - `whitted.rs`: Whitted (1980).
//! - `distribution.rs`: distribution ray tracing (Cook, Porter and Carpenter 1984).
//! - `path.rs`: path tracing (Kajiya 1986).
//! - `monte_carlo.rs`: what the two Monte Carlo integrators share; `pixel_samples.rs`: a Monte
//!   Carlo trace's summary of its pixel's samples.
//!
//! # Where Whitted and Monte Carlo differ, and why
//!
//! A scene's material is one Phong material whichever integrator renders it; the two halves of
//! the course read it differently, each the way its own course notes do:
//!
//! - **Reflection.** Whitted reflects the *incoming* direction, r = d − 2(d·n)n, with d pointing
//!   at the surface, as the Whitted-era notes (and The Ray Tracer Challenge) write it. The Monte
//!   Carlo BSDFs work in the local frame of pbrt and Mitsuba, with both directions pointing
//!   *away* from the surface: ωo = −d and the mirror direction ωi = 2(ωo·n)n − ωo
//!   (`mc::bsdf::mirror`) — the same vector, computed in another order, so its last bits may
//!   differ. The numbers a student sees in a trace follow the convention of the half they are in.
//! - **Fresnel.** Whitted blends reflection and refraction with Schlick's approximation
//!   (`shading::schlick_recorded`), as its notes do; the Monte Carlo dielectric uses the exact
//!   Fresnel equations (`mc::bsdf`), as pbrt and Mitsuba do, so that path-traced glass agrees
//!   with Mitsuba 3 (the convergence tests compare them).
//! - **Material to BSDF.** A Monte Carlo object's BSDF is its `bsdf` table when it has one, else
//!   it is read from the Phong material by [`crate::scene::Material::bsdf`]: transparency > 0
//!   makes a smooth dielectric, reflective ≥ 0.5 a mirror of reflectance `reflective`, anything
//!   else Lambert with albedo colour × diffuse. Phong's ambient, specular and shininess have no
//!   Monte Carlo meaning and are ignored (a Monte Carlo render is lit by emitting objects and
//!   point lights alone); a Whitted render ignores `bsdf`, `roughness` and emission. Mapping
//!   rather than refusing keeps every Whitted scene renderable by the path tracer, which is how
//!   the course moves from one half to the other.
//!
//! Either way one sample's numbers are the same whether it is rendered, recorded or traced on
//! the GPU (docs/ARCHITECTURE.md, invariants).

mod distribution;
pub mod interaction;
pub mod media;
pub mod monte_carlo;
mod path;
pub mod pixel_samples;
pub mod prepared;
pub mod sampling;
pub mod shading;
pub mod texture;
pub mod tracer;
mod whitted;

pub use prepared::PreparedScene;
pub use tracer::Tracer;
