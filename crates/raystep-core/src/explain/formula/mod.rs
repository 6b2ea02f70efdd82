//! The math panel: for one step of a recorded trace, the formulas the tracer evaluated, with the
//! numbers substituted, in the precision the renderer used.
//!
//! Every [`Formula`] reads `name = symbolic = substituted = value`. The policy for numbers:
//!
//! - Where the kernel **recorded** a value, the line prints the recorded f32, formatted by
//!   [`crate::record::number::num`] and [`crate::record::number::v3`]
//!   (shortest round-trip form), and `substituted` is built from the recorded inputs of that very
//!   computation. The intersection tests record every intermediate shown: the sphere's f = S − G,
//!   a, b, b′, c, l, Δ′, Δ, √Δ, q and its roots as computed; Möller–Trumbore's E1, E2, T and
//!   determinants; the watertight test's permutation, shear, sheared vertices, edge functions
//!   and scaled z; a slab's plane distances, entry and exit. A trace saved before a value was
//!   recorded shows — in its place.
//! - Where an input was **not recorded** (the camera basis, the shading's light, eye and
//!   reflected vectors, Snell's η and cos θₜ), it is computed here in f32 with the same
//!   operations in the same order as the kernel (the same glam calls on the same recorded
//!   inputs), so it is the value the renderer had. The doc comment of each such helper says so.
//! - What neither the trace nor the kernel's inputs determine (the Phong coefficients k_a, k_d,
//!   k_s and the shininess, which a trace does not store) stays a symbol.
//!
//! Nothing here needs the scene: a loaded trace file is enough.

use crate::math::gamma;
use crate::record::number::{num, v3};
use crate::record::words;
use crate::record::{NodeAction, RayKind, RayRecord, Step, Trace, TraceObject};
use crate::scene::camera::CameraRays;
use crate::scene::{OffsetPolicy, Shape};
use crate::shapes::{
    BoxMethod, BoxTest, PlaneForm, PlaneTest, RootChoice, SphereCase, SphereMethod, SphereTest,
    TriangleMethod, TriangleTest,
};
use glam::Vec3;
use serde::{Deserialize, Serialize};

mod hit;
mod instance;
pub(crate) mod monte_carlo;
mod plane;
mod shading;
mod sphere;
mod texture;
mod traversal;
mod triangle;

/// One line of the math panel: `name = symbolic = substituted = value`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Formula {
    /// The quantity computed, e.g. `Δ` or `a`.
    pub name: String,
    /// The formula in symbols, e.g. `b² − 4ac`.
    pub symbolic: String,
    /// The formula with the numbers the renderer used, e.g. `(-10)² − 4·1·24`; empty when it
    /// would add nothing to `symbolic`.
    pub substituted: String,
    /// The result, e.g. `4` (the recorded value where the kernel recorded one).
    pub value: String,
    /// What the value means, e.g. `> 0: two roots`.
    pub note: Option<String>,
}

/// The math panel's content for one step.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Explanation {
    /// What is being evaluated, e.g. `Ray–sphere "middle" (textbook quadratic)`.
    pub title: String,
    /// The formulas in the order the tracer evaluated them (a test that stopped early lists only
    /// the lines up to its stop).
    pub lines: Vec<Formula>,
    /// The decision, in words.
    pub conclusion: String,
}

impl Explanation {
    /// The explanation with `note` (a sentence without its full stop) added to its conclusion.
    fn with_note(mut self, note: Option<String>) -> Explanation {
        if let Some(n) = note {
            self.conclusion = format!("{} {}", words::sentence(&n), self.conclusion);
        }
        self
    }
}

/// Explains `step`, one of `ray`'s steps in `trace`, as formulas with the recorded numbers.
///
/// `step` should be an element of `ray.steps` (as [`Trace::timeline`] hands them out): its
/// position there tells which t_max the kernel tested against (t_max shrinks at every `Accept`)
/// and which `Surface` a shading step belongs to. A step not found in `ray` is still explained,
/// against the ray's initial interval.
pub fn explain(trace: &Trace, ray: &RayRecord, step: &Step) -> Explanation {
    let idx = ray
        .steps
        .iter()
        .position(|s| std::ptr::eq(&s.step, step))
        .or_else(|| ray.steps.iter().position(|s| &s.step == step));
    let cx = Ctx { trace, ray, idx };
    match step {
        Step::Camera {
            pixel,
            sample,
            offset,
            screen,
            direction,
        } => cx.camera(*pixel, *sample, *offset, *screen, *direction),
        Step::Node(n) => cx.node(n, if n.instance.is_some() { "BLAS" } else { "BVH" }),
        Step::TlasNode(n) => cx.node(n, "TLAS"),
        Step::Instance {
            name,
            prototype,
            to_object,
            origin,
            direction,
            ..
        } => cx.instance(name, prototype, to_object, *origin, *direction),
        Step::InstanceHit {
            name,
            to_world,
            to_object,
            point,
            normal,
            world_point,
            world_normal,
            wrong_normal,
            ..
        } => cx.instance_hit(
            name,
            to_world,
            to_object,
            *point,
            *normal,
            *world_point,
            *world_normal,
            *wrong_normal,
        ),
        Step::SphereNode { .. } | Step::Cell { .. } | Step::MailboxSkip { .. } => {
            cx.accel_step(step)
        }
        Step::Sphere { object, name, test } => cx.sphere(*object, name, test),
        Step::Plane { name, test, .. } => cx.plane(name, test),
        Step::Triangle {
            name,
            vertices,
            test,
            ..
        } => match test.method {
            TriangleMethod::MollerTrumbore => cx.moller_trumbore(name, vertices, test),
            TriangleMethod::Watertight => cx.watertight(name, vertices, test),
        },
        Step::Accept {
            name, t, previous, ..
        } => cx.accept(name, *t, *previous),
        Step::Miss { background } => cx.miss(*background),
        Step::Surface {
            point,
            normal,
            inside,
            error_bound,
            over_point,
        } => cx.surface(*point, *normal, *inside, *error_bound, *over_point),
        Step::ShadingNormal {
            vertex_normals,
            u,
            v,
            normal,
            angle_deg,
            lifted,
        } => cx.shading_normal(vertex_normals, *u, *v, *normal, *angle_deg, *lifted),
        Step::Texture { .. } => cx.texture(step),
        Step::ShadowRay {
            light,
            name,
            distance,
        } => cx.shadow_ray(*light, name, *distance),
        Step::Light { .. } => cx.light(step),
        Step::Reflect {
            reflective,
            direction,
            d_dot_n,
        } => cx.reflect(*reflective, *direction, *d_dot_n),
        Step::Refract { .. } => cx.refract(step),
        Step::Schlick {
            reflectance,
            r0,
            cos,
        } => cx.schlick(*reflectance, *r0, *cos),
        Step::DepthLimit { max_depth } => cx.depth_limit(*max_depth),
        Step::WeightCutoff {
            kind,
            contribution,
            cutoff,
        } => cx.weight_cutoff(*kind, *contribution, *cutoff),
        Step::Lens {
            random,
            lens_point,
            focus_point,
            pdf,
            direction,
        } => monte_carlo::lens(random, *lens_point, *focus_point, *pdf, *direction),
        Step::LightSample {
            name,
            random,
            point,
            distance,
            select_pdf,
            pdf,
            radiance,
            bsdf,
            cos,
            bsdf_pdf,
            mis_weight,
            blocked,
            contribution,
            ..
        } => monte_carlo::light_sample(
            name,
            random,
            *point,
            *distance,
            *select_pdf,
            *pdf,
            *radiance,
            *bsdf,
            *cos,
            *bsdf_pdf,
            *mis_weight,
            *blocked,
            *contribution,
        )
        .with_note(crate::explain::describe::own_light_note(
            cx.trace, cx.ray, step,
        )),
        Step::BsdfSample {
            bsdf,
            lobe,
            random,
            direction,
            pdf,
            value,
            cos,
            weight,
            throughput,
        } => monte_carlo::bsdf_sample(
            bsdf,
            lobe,
            random,
            *direction,
            *pdf,
            *value,
            *cos,
            *weight,
            *throughput,
        ),
        Step::Emitted {
            name,
            radiance,
            light_pdf,
            bsdf_pdf,
            mis_weight,
            contribution,
            ..
        } => monte_carlo::emitted(
            name,
            *radiance,
            *light_pdf,
            *bsdf_pdf,
            *mis_weight,
            *contribution,
        ),
        Step::RussianRoulette {
            random,
            probability,
            survived,
            throughput,
        } => monte_carlo::roulette(*random, *probability, *survived, *throughput),
        Step::Truncated { max_steps } => Explanation {
            title: "The trace stops here".into(),
            lines: vec![],
            conclusion: format!(
                "The trace reached its limit of {max_steps} recorded steps. The tracer went on and every colour is exact, but the rest of its work was not kept."
            ),
        },
        Step::HardwareTraversal { primitives } => Explanation {
            title: "The hardware walks its own tree".into(),
            lines: vec![],
            conclusion: format!(
                "Ray queries: the GPU walks its own acceleration structure over {primitives} primitive boxes. Which boxes it tested is not revealed to the shader; the tests below are the primitives whose boxes the ray entered."
            ),
        },
        Step::Spawn { child } => cx.spawn(*child),
        Step::Color { color } => cx.color(*color),
    }
}

/// A number, parenthesized when negative so that it can follow an operator: `(-10)`.
fn p(x: f32) -> String {
    let s = num(x);
    if s.starts_with('-') {
        format!("({s})")
    } else {
        s
    }
}

/// A vector as [`v3`] prints it.
fn vv(v: Vec3) -> String {
    v3(v.to_array())
}

/// Shorthand for a line.
fn line(
    name: &str,
    symbolic: &str,
    substituted: impl Into<String>,
    value: impl Into<String>,
    note: Option<String>,
) -> Formula {
    Formula {
        name: name.into(),
        symbolic: symbolic.into(),
        substituted: substituted.into(),
        value: value.into(),
        note,
    }
}

fn yes_no(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// The step being explained, with the ray it belongs to and its position there.
struct Ctx<'a> {
    trace: &'a Trace,
    ray: &'a RayRecord,
    idx: Option<usize>,
}

impl Ctx<'_> {
    /// The ray's origin as this step's kernel saw it: in an instance's object space for the
    /// steps of a BLAS walk ([`Ctx::local`]), else the ray's own.
    fn origin(&self) -> Vec3 {
        Vec3::from(self.local().map_or(self.ray.origin, |l| l.0))
    }
    /// The ray's direction as this step's kernel saw it (see [`Ctx::origin`]).
    fn dir(&self) -> Vec3 {
        Vec3::from(self.local().map_or(self.ray.direction, |l| l.1))
    }

    /// The object-space ray (S′, Q′) of the instance whose BLAS walk this step belongs to: the
    /// nearest `Instance` step before it with only that walk's steps (its nodes, primitive
    /// tests and accepted hits) between. `None` for a step of the world.
    fn local(&self) -> Option<([f32; 3], [f32; 3])> {
        let idx = self.idx?;
        let in_walk = |s: &Step| match s {
            Step::Node(n) => n.instance.is_some(),
            Step::Sphere { .. } | Step::Triangle { .. } | Step::Accept { .. } => true,
            _ => false,
        };
        if !in_walk(&self.ray.steps.get(idx)?.step) {
            return None;
        }
        for s in self.ray.steps[..idx].iter().rev() {
            match &s.step {
                Step::Instance {
                    origin, direction, ..
                } => return Some((*origin, *direction)),
                other if in_walk(other) => {}
                _ => return None,
            }
        }
        None
    }

    /// The steps before this one (all of them when the step is not in the ray).
    fn before(&self) -> &[crate::record::StepRecord] {
        &self.ray.steps[..self.idx.unwrap_or(self.ray.steps.len())]
    }

    /// The ray's t_max when step `idx` ran: the initial t_max, shrunk by every `Accept` before it
    /// (the accelerators set t_max to the accepted t, and only `Accept` changes it).
    fn t_max_at(&self, idx: Option<usize>) -> f32 {
        let end = idx.unwrap_or(0).min(self.ray.steps.len());
        let mut t = self.ray.t_max.unwrap_or(f32::INFINITY);
        for s in &self.ray.steps[..end] {
            if let Step::Accept { t: a, .. } = s.step {
                t = a;
            }
        }
        t
    }

    /// Whether this step's kernel kept a hit at exactly t_max: a test of an object with a lower
    /// id than the closest so far, so that a tie at equal t goes to the lower id whatever order
    /// the accelerator tests in ([`crate::accel::tie_ray`]).
    fn ties_kept(&self) -> bool {
        let end = self.idx.unwrap_or(0).min(self.ray.steps.len());
        let closest = self.ray.steps[..end]
            .iter()
            .rev()
            .find_map(|s| match s.step {
                Step::Accept { object, .. } => Some(object),
                _ => None,
            });
        let tested = self
            .idx
            .and_then(|i| self.ray.steps.get(i))
            .and_then(|s| match s.step {
                Step::Sphere { object, .. }
                | Step::Plane { object, .. }
                | Step::Triangle { object, .. } => Some(object),
                _ => None,
            });
        matches!((tested, closest), (Some(id), Some(c)) if id < c)
    }

    /// Whether t lies in the interval this step's kernel tested against: t_min < t < t_max, or
    /// t_min < t ≤ t_max when [`Self::ties_kept`].
    fn in_range(&self, t: f32) -> bool {
        let hi = self.t_max();
        t > self.ray.t_min && (t < hi || (self.ties_kept() && t == hi))
    }

    /// The upper comparison this step's kernel made: "<", or "≤" when ties are kept.
    fn upper(&self) -> &'static str {
        if self.ties_kept() { "≤" } else { "<" }
    }

    /// The t_max this step's kernel tested against.
    fn t_max(&self) -> f32 {
        self.t_max_at(self.idx)
    }

    /// `t_min < t < t_max` (or `≤ t_max`, see [`Self::ties_kept`]), with the numbers.
    fn range_line(&self, t: f32) -> Formula {
        let (lo, hi) = (self.ray.t_min, self.t_max());
        let ok = self.in_range(t);
        let up = self.upper();
        line(
            "t in range?",
            &format!("t_min < t {up} t_max"),
            format!("{} < {} {up} {}", num(lo), num(t), num(hi)),
            yes_no(ok),
            Some(if ok && self.ties_kept() && t == hi {
                "a tie with the closest hit so far: the lower object id keeps it".into()
            } else if ok {
                "inside the ray's interval".into()
            } else if t <= lo {
                "at or behind the origin (t ≤ t_min)".into()
            } else if self.t_max() < self.ray.t_max.unwrap_or(f32::INFINITY) {
                "at or beyond the closest hit so far (t ≥ t_max)".into()
            } else {
                "at or beyond the ray's end (t ≥ t_max)".into()
            }),
        )
    }

    fn object(&self, id: u32) -> Option<&TraceObject> {
        self.trace.objects.iter().find(|o| o.id == id)
    }

    /// The colour that shades the hit: a `Texture` step's (the material's colour × the
    /// texture's) where one came before this step, else the hit object's material colour.
    fn surface_color(&self) -> Option<[f32; 3]> {
        self.before()
            .iter()
            .rev()
            .find_map(|s| match s.step {
                Step::Texture {
                    color,
                    roughness: None,
                    ..
                } => Some(color),
                _ => None,
            })
            .or_else(|| {
                let h = self.ray.hit.as_ref()?;
                self.object(h.object).map(|o| o.color)
            })
    }

    /// The latest `Surface` step before this one: (point, the normal that shades it: the
    /// `ShadingNormal` step's where the surface is smooth, else the surface's own).
    fn surface_before(&self) -> Option<(Vec3, Vec3)> {
        let mut shading = None;
        for s in self.before().iter().rev() {
            match s.step {
                Step::ShadingNormal { normal, .. } => {
                    shading.get_or_insert(Vec3::from(normal));
                }
                Step::Surface { point, normal, .. } => {
                    return Some((Vec3::from(point), shading.unwrap_or(Vec3::from(normal))));
                }
                _ => {}
            }
        }
        None
    }

    fn camera(
        &self,
        pixel: [u32; 2],
        sample: u32,
        offset: [f32; 2],
        screen: [f32; 2],
        direction: [f32; 3],
    ) -> Explanation {
        let cam = &self.trace.camera;
        if screen.iter().all(|s| s.is_nan()) {
            // A GPU trace of the fragment path: the rasterizer interpolated the direction.
            return Explanation {
                title: format!(
                    "Ray generation: pixel ({}, {}), sample {sample}",
                    pixel[0], pixel[1]
                ),
                lines: vec![line(
                    "offset",
                    "the sample's place in the pixel",
                    "",
                    format!("({}, {})", num(offset[0]), num(offset[1])),
                    None,
                )],
                conclusion: format!(
                    "The rasterizer interpolated this ray's direction across a full-screen triangle \
                     (the GPU's fragment path): sx and sy were never computed. The primary ray starts \
                     at the eye S = {} and runs along Q = {}.",
                    vv(cam.from),
                    v3(direction)
                ),
            };
        }
        // The renderer's own basis code on the trace's camera: the same f32 values it used.
        let basis = CameraRays::new(cam);
        let (w, h) = (cam.width, cam.height);
        let lines = vec![
            line(
                "offset",
                if self.trace.settings.spp <= 1 {
                    "(0.5, 0.5): the pixel centre (1 sample per pixel)"
                } else {
                    "jittered cell of a stratified grid (hash of pixel, sample, seed)"
                },
                "",
                format!("({}, {})", num(offset[0]), num(offset[1])),
                None,
            ),
            line(
                "sx",
                "2(x + oₓ)/W − 1",
                format!("2·({} + {})/{} − 1", pixel[0], num(offset[0]), w),
                num(screen[0]),
                None,
            ),
            line(
                "sy",
                "1 − 2(y + o_y)/H",
                format!("1 − 2·({} + {})/{}", pixel[1], num(offset[1]), h),
                num(screen[1]),
                Some("y counts from the top of the image".into()),
            ),
            line(
                "w",
                "normalize(from − at)",
                format!("normalize({} − {})", vv(cam.from), vv(cam.at)),
                vv(basis.w),
                Some("points backwards, out of the screen".into()),
            ),
            line(
                "u",
                "normalize(up × w)",
                format!("normalize({} × {})", vv(cam.up), vv(basis.w)),
                vv(basis.u),
                Some("right in the image".into()),
            ),
            line(
                "v",
                "w × u",
                format!("{} × {}", vv(basis.w), vv(basis.u)),
                vv(basis.v),
                Some("up in the image".into()),
            ),
            line(
                "h",
                "tan(fov/2)",
                format!("tan({}°/2)", num(cam.fov)),
                num(basis.half_height),
                None,
            ),
            line(
                "h·W/H",
                "half width",
                format!("{}·{}/{}", num(basis.half_height), w, h),
                num(basis.half_width),
                None,
            ),
            line(
                "Q",
                "normalize(sx·(h·W/H)·u + sy·h·v − w)",
                format!(
                    "normalize({}·{}·{} + {}·{}·{} − {})",
                    p(screen[0]),
                    num(basis.half_width),
                    vv(basis.u),
                    p(screen[1]),
                    num(basis.half_height),
                    vv(basis.v),
                    vv(basis.w)
                ),
                v3(direction),
                None,
            ),
        ];
        Explanation {
            title: format!(
                "Ray generation: pixel ({}, {}), sample {sample}",
                pixel[0], pixel[1]
            ),
            lines,
            conclusion: format!(
                "The primary ray starts at the eye S = {} and runs along Q = {}.",
                vv(cam.from),
                v3(direction)
            ),
        }
    }

    /// The t_max a node's box was tested against. Siblings are tested as a pair before either is
    /// recorded, so the second sibling (the farther; for a shadow ray the nearer) shows the t_max
    /// of the first one's record, even if the first one's leaf has since shrunk it.
    fn node_t_max(&self, node: u32) -> f32 {
        let Some(i) = self.idx else {
            return self.t_max();
        };
        let before = &self.ray.steps[..i];
        let parent = before.iter().rposition(
            |s| matches!(&s.step, Step::Node(n) if n.children.is_some_and(|c| c.contains(&node))),
        );
        let Some(pi) = parent else {
            return self.t_max();
        };
        let Step::Node(pn) = &before[pi].step else {
            return self.t_max();
        };
        let sibling = pn.children.map(|c| if c[0] == node { c[1] } else { c[0] });
        let sib = before[pi + 1..]
            .iter()
            .position(|s| matches!(&s.step, Step::Node(n) if Some(n.node) == sibling));
        match sib {
            Some(k) => self.t_max_at(Some(pi + 1 + k)),
            None => self.t_max(),
        }
    }
}

/// b′ = −f·Q as the stable kernel computes it (from f when the sphere is known, else −b/2).
fn case_note(test: &SphereTest<f32>) -> String {
    if test.discriminant.is_nan() {
        "NaN (overflow): a miss".into()
    } else {
        crate::record::words::sphere_case(test.case).into()
    }
}

fn upper_first(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_uppercase().collect::<String>() + c.as_str(),
        None => String::new(),
    }
}
