//! The GPU's own step trace: the trace shader (`crates/raystep-gpu/src/wgsl/trace_log.wgsl`) logs every step one
//! invocation takes into a bounded buffer; this module reads that log back into raystep's trace
//! format ([`Trace`]), so `raystep diff` and the app's stepper treat a GPU trace as a CPU one.
//!
//! Every number in the steps is the GPU's, read back bit for bit. Two kinds of value are filled in
//! here instead, because the GPU never computes them:
//! - names (objects, lights, materials) and the triangle's vertices, from the scene;
//! - each ray's colour. The GPU does not nest colours as the CPU's recursion does: it adds each
//!   ray's own term (its `Color` record), times the ray's share of the pixel, to the pixel. A
//!   ray's colour in the trace is composed from the GPU's own terms, children and Schlick
//!   reflectance by the CPU's formula (`crates/raystep-core/src/trace/whitted.rs` `shade`), so it is the colour the
//!   CPU would form from those numbers; the trace's final colour is the GPU's pixel.
//!
//! Also derived here, by comparisons only: which root a sphere test chose, a sphere's `b` as
//! 2·(f·d) for the stable test, a refraction's critical angle (for the explanation).

use crate::record::samples::MAX_PIXEL_SAMPLES;
use crate::record::{
    HitRecord, NodeAction, NodeVisit, RayKind, RayRecord, Stage, Step, StepRecord, TRACE_VERSION,
    Trace, TraceObject,
};
use crate::scene::Scene;
use crate::shapes::{
    BoxMethod, BoxTest, PlaneForm, PlaneTest, RootChoice, Shape, SlabAxis, SphereCase,
    SphereMethod, SphereTest, TriangleMethod, TriangleTest,
};
use crate::trace::shading::critical_angle_deg;
use crate::trace::tracer::WEIGHT_CUTOFF;
use glam::Vec3;
use std::collections::HashMap;

mod mc;
mod surface;
use surface::{shading_normal_step, surface_step, texture_lod, texture_step};

/// Words of the log before the first record (see `trace_log.wgsl`).
pub const LOG_HEADER: usize = crate::interface::LOG_HEADER as usize;
/// Words the trace buffer holds by default: 16 MiB, about 300,000 steps.
pub const DEFAULT_LOG_WORDS: usize = 1 << 22;
/// A scratch slot the kernel did not reach.
const NOT_COMPUTED: u32 = 0x7fc0_dead;
use crate::interface::NO_OBJECT;
use crate::scene::NO_INSTANCE;

use crate::interface::{ray_kind, tag};

/// A GPU trace read back: the trace, and what the reading found.
#[derive(Debug, Clone)]
pub struct GpuTrace {
    /// The trace, in raystep's format.
    pub trace: Trace,
    /// The log ran out of room: the steps after the last one kept were not recorded (the trace
    /// ends with a `truncated` step).
    pub truncated: bool,
    /// Steps read from the log.
    pub steps: usize,
    /// Monte Carlo: the log ran out while the pixel's samples were summarised, after the traced
    /// sample's steps were all kept. A trace whose log ran out has no Monte Carlo record (a
    /// record holds every sample's summary or none).
    pub summaries_truncated: bool,
}

/// Reads a payload of f32 bits and u32s.
struct Payload<'a> {
    words: &'a [u32],
    at: usize,
}

impl Payload<'_> {
    fn u(&mut self) -> Result<u32, String> {
        let w = self
            .words
            .get(self.at)
            .copied()
            .ok_or_else(|| "a record is shorter than its kind".to_string())?;
        self.at += 1;
        Ok(w)
    }
    fn f(&mut self) -> Result<f32, String> {
        self.u().map(f32::from_bits)
    }
    fn b(&mut self) -> Result<bool, String> {
        self.u().map(|w| w != 0)
    }
    fn v(&mut self) -> Result<[f32; 3], String> {
        Ok([self.f()?, self.f()?, self.f()?])
    }
}

/// One ray while the log is read: its record (children not attached yet) and the ids of the
/// rays it spawned, by the position of their `Spawn` steps.
struct Building {
    record: RayRecord,
    spawned: Vec<u32>,
    /// The GPU's own colour term for this ray (its `Color` record).
    own: Option<[f32; 3]>,
}

fn kind_of(k: u32) -> Result<RayKind, String> {
    Ok(match k {
        ray_kind::PRIMARY => RayKind::Primary,
        ray_kind::SHADOW => RayKind::Shadow,
        ray_kind::REFLECTION => RayKind::Reflection,
        ray_kind::REFRACTION => RayKind::Refraction,
        ray_kind::DIFFUSE => RayKind::Diffuse,
        ray_kind::GLOSSY => RayKind::Glossy,
        _ => return Err(format!("ray kind {k} is not one raystep has")),
    })
}

fn step(step: Step) -> StepRecord {
    StepRecord {
        stage: step.stage(),
        step,
    }
}

fn slot(s: &[f32; 32], i: usize) -> Option<f32> {
    let v = s[i];
    (v.to_bits() != NOT_COMPUTED).then_some(v)
}

fn slot3(s: &[f32; 32], i: usize) -> Option<[f32; 3]> {
    Some([slot(s, i)?, slot(s, i + 1)?, slot(s, i + 2)?])
}

/// The CPU's root choice (`crates/raystep-core/src/shapes/sphere.rs` `finish`), applied to the GPU's roots.
fn choose(test: &mut SphereTest<f32>, t_min: f32, t_max: f32, t0: f32, t1: f32) {
    let (lo, hi) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    test.roots = Some([lo, hi]);
    test.computed_roots = Some([t0, t1]);
    test.case = if test.discriminant == 0.0 {
        SphereCase::Tangent
    } else {
        SphereCase::EnterExit
    };
    test.choice = if lo > t_min {
        if lo < t_max {
            RootChoice::NearRoot
        } else {
            RootChoice::BeyondTMax
        }
    } else if hi > t_min {
        if hi < t_max {
            RootChoice::FarRoot
        } else {
            RootChoice::BeyondTMax
        }
    } else {
        RootChoice::Behind
    };
}

/// A test record (`intersection` in the trace shader) as the step the CPU records.
fn test_step(scene: &Scene, p: &mut Payload) -> Result<Step, String> {
    let object = p.u()?;
    let kind = p.u()?;
    let (t_min, t_max) = (p.f()?, p.f()?);
    let (hit, t) = (p.b()?, p.f()?);
    let (u, v) = (p.f()?, p.f()?);
    let mut s = [0f32; 32];
    for x in s.iter_mut() {
        *x = p.f()?;
    }
    let shape = scene
        .objects
        .get(object as usize)
        .map(|o| o.shape)
        .ok_or_else(|| format!("object {object} is not in the scene"))?;
    let name = scene.object_name(object);
    let found = hit.then_some(t);
    let _ = (u, v);
    Ok(match (kind, shape) {
        (0, Shape::Sphere { .. }) => {
            let method = scene.settings.sphere_method;
            let stable = method == SphereMethod::Stable;
            let c = slot(&s, 5).unwrap_or(f32::NAN);
            let mut test = SphereTest {
                method,
                a: slot(&s, 3).unwrap_or(f32::NAN),
                // The stable test computes f·d; the CPU records b = 2·(f·d) (exact: a doubling).
                b: slot(&s, 4).map_or(f32::NAN, |x| if stable { 2.0 * x } else { x }),
                c,
                discriminant: slot(&s, 6).unwrap_or(f32::NAN),
                delta_prime: slot(&s, 7),
                q: slot(&s, 13),
                f: slot3(&s, 0),
                b_half: slot(&s, 8),
                l: slot3(&s, 9),
                sqrt_discriminant: slot(&s, 12),
                computed_roots: None,
                roots: None,
                case: SphereCase::Miss,
                choice: RootChoice::NoRoots,
                t: found,
                inside: c < 0.0,
            };
            if let (Some(t0), Some(t1)) = (slot(&s, 14), slot(&s, 15)) {
                choose(&mut test, t_min, t_max, t0, t1);
            }
            Step::Sphere { object, name, test }
        }
        (1 | 2, Shape::Plane { .. } | Shape::AxisPlane { .. }) => {
            let form = match shape {
                Shape::Plane { normal, offset } => PlaneForm::General {
                    normal: normal.to_array(),
                    offset,
                },
                Shape::AxisPlane { axis, offset } => PlaneForm::Axis { axis, offset },
                _ => unreachable!("matched above"),
            };
            let denominator = slot(&s, 1).unwrap_or(f32::NAN);
            Step::Plane {
                object,
                name,
                test: PlaneTest {
                    form,
                    denominator,
                    numerator: slot(&s, 0).unwrap_or(f32::NAN),
                    parallel: denominator == 0.0,
                    t_raw: slot(&s, 2),
                    t: found,
                },
            }
        }
        (3, Shape::Triangle { p: vertices }) => {
            let method = scene.settings.triangle_method;
            let stopped_at = slot(&s, 26).unwrap_or(2.0) as u8;
            let test = match method {
                TriangleMethod::Watertight => TriangleTest {
                    method,
                    det: slot(&s, 18).unwrap_or(0.0),
                    dt: slot(&s, 22),
                    du: None,
                    dv: None,
                    edges: slot3(&s, 15),
                    permutation: slot3(&s, 0).map(|k| k.map(|x| x as usize)),
                    shear: slot3(&s, 3),
                    sheared: match (slot3(&s, 6), slot3(&s, 9), slot3(&s, 12)) {
                        (Some(a), Some(b), Some(c)) => Some([a, b, c]),
                        _ => None,
                    },
                    z_scaled: slot3(&s, 19),
                    e1: None,
                    e2: None,
                    t_vec: None,
                    t_star: slot(&s, 23),
                    u: slot(&s, 24),
                    v: slot(&s, 25),
                    stopped_at,
                    t: found,
                },
                TriangleMethod::MollerTrumbore => TriangleTest {
                    method,
                    det: slot(&s, 6).unwrap_or(0.0),
                    dt: slot(&s, 10),
                    du: slot(&s, 12),
                    dv: slot(&s, 14),
                    edges: None,
                    permutation: None,
                    shear: None,
                    sheared: None,
                    z_scaled: None,
                    e1: slot3(&s, 0),
                    e2: slot3(&s, 3),
                    t_vec: slot3(&s, 7),
                    t_star: slot(&s, 11),
                    u: slot(&s, 13),
                    v: slot(&s, 15),
                    stopped_at,
                    t: found,
                },
            };
            Step::Triangle {
                object,
                name,
                vertices: vertices.map(|v| v.to_array()),
                test,
            }
        }
        _ => {
            return Err(format!(
                "a test of object {object} has kind {kind}, not its shape's"
            ));
        }
    })
}

/// A node record as the CPU's node visit: a BVH's ([`Step::Node`], marked with the instance
/// whose BLAS it belongs to) or the TLAS's ([`Step::TlasNode`]).
fn node_step(p: &mut Payload, tlas: bool) -> Result<Step, String> {
    let node = p.u()?;
    let depth = p.u()?;
    let (min, max, inv) = (p.v()?, p.v()?, p.v()?);
    let (t0, t1, entry, exit) = (p.v()?, p.v()?, p.v()?, p.v()?);
    let (t_near, t_far) = (p.f()?, p.f()?);
    let leaf = p.b()?;
    let first = p.u()?;
    let action = match p.u()? {
        0 => NodeAction::Culled,
        1 => NodeAction::Descend,
        2 => NodeAction::Pushed,
        3 => NodeAction::TestPrimitives,
        a => return Err(format!("node action {a} is not one raystep has")),
    };
    let instance = p.u()?;
    let axes = [0, 1, 2].map(|i| SlabAxis {
        inv_dir: inv[i],
        planes: Some([t0[i], t1[i]]),
        t_entry: entry[i],
        t_exit: exit[i],
    });
    let visit = NodeVisit {
        node,
        depth,
        test: BoxTest {
            method: BoxMethod::Robust,
            min,
            max,
            axes,
            t_near,
            t_far,
            hit: t_near <= t_far,
        },
        leaf,
        children: (!leaf).then_some([first, first.wrapping_add(1)]),
        action,
        instance: (instance != NO_INSTANCE).then_some(instance),
    };
    Ok(if tlas {
        Step::TlasNode(visit)
    } else {
        Step::Node(visit)
    })
}

/// An `INSTANCE` record: the instance and the ray in its object space (its name, prototype and
/// M⁻¹ from the scene).
fn instance_step(scene: &Scene, p: &mut Payload) -> Result<Step, String> {
    let instance = p.u()?;
    let (origin, direction) = (p.v()?, p.v()?);
    let inst = scene
        .instances
        .get(instance as usize)
        .ok_or_else(|| format!("instance {instance} is not one of the scene's"))?;
    Ok(Step::Instance {
        instance,
        name: inst.name.clone(),
        prototype: scene
            .groups
            .get(inst.group as usize)
            .map_or_else(String::new, |g| g.name.clone()),
        to_object: inst.to_object.0,
        origin,
        direction,
    })
}

/// An `INSTANCE_HIT` record: the hit carried back from the instance's object space.
fn instance_hit_step(scene: &Scene, p: &mut Payload) -> Result<Step, String> {
    let instance = p.u()?;
    let (point, normal, world_point, world_normal, wrong_normal) =
        (p.v()?, p.v()?, p.v()?, p.v()?, p.v()?);
    let inst = scene
        .instances
        .get(instance as usize)
        .ok_or_else(|| format!("instance {instance} is not one of the scene's"))?;
    Ok(Step::InstanceHit {
        instance,
        name: inst.name.clone(),
        to_world: inst.to_world.0,
        to_object: inst.to_object.0,
        point,
        normal,
        world_point,
        world_normal,
        wrong_normal,
    })
}

/// Reads the log `words` of the trace shader that traced sample `sample` of `pixel` of `scene`.
/// `bvh`: the BVH's outline when the GPU walked raystep's BVH (for the tree diagram).
pub fn decode(
    words: &[u32],
    scene: &Scene,
    pixel: [u32; 2],
    sample: u32,
    bvh: Option<Vec<crate::record::OutlineNode>>,
) -> Result<GpuTrace, String> {
    let used = (words.first().copied().unwrap_or(0) as usize).min(words.len());
    let ran_out = words.get(1).copied().unwrap_or(0) != 0;
    let mut rays: HashMap<u32, Building> = HashMap::new();
    let mut open: Vec<u32> = vec![];
    let mut pending_lod = None;
    // A roughness texture's roughness, for the `TEXTURE` record after it.
    let mut pending_roughness = None;
    let mut pixel_color = None;
    let mut at = LOG_HEADER.min(used);
    let mut steps = 0usize;
    let monte_carlo = scene.settings.integrator.is_monte_carlo();
    let mc_scene = monte_carlo.then(|| mc::McScene::new(scene));
    let mut summarising = false;
    let mut summaries = mc::Summaries::default();
    while at < used {
        let head = words[at];
        let (t, len) = (head >> 16, (head & 0xffff) as usize);
        let body = words
            .get(at + 1..at + 1 + len)
            .ok_or("the log ends inside a record")?;
        at += 1 + len;
        let mut p = Payload { words: body, at: 0 };
        steps += 1;
        if summarising {
            match t {
                tag::SURFACE => summaries.step(surface_step(&mut p)?),
                tag::LIGHT_SAMPLE => {
                    let m = mc_scene
                        .as_ref()
                        .ok_or("a light sample in a Whitted trace")?;
                    summaries.step(mc::light_sample(m, scene, &mut p)?)
                }
                tag::BSDF_SAMPLE => summaries.step(mc::bsdf_sample(&mut p)?),
                tag::SAMPLE => summaries.finish(&mut p)?,
                other => return Err(format!("record kind {other} in a sample's summary")),
            }
            continue;
        }
        let current = open.last().copied();
        let push = |rays: &mut HashMap<u32, Building>, s: Step| -> Result<(), String> {
            let id = current.ok_or("a step outside any ray")?;
            let r = rays.get_mut(&id).ok_or("a step of a ray never begun")?;
            r.record.steps.push(step(s));
            Ok(())
        };
        match t {
            tag::RAY => {
                let id = p.u()?;
                let _parent = p.u()?;
                let kind = kind_of(p.u()?)?;
                let depth = p.u()?;
                let (origin, direction) = (p.v()?, p.v()?);
                let (t_min, t_max, weight) = (p.f()?, p.f()?, p.f()?);
                let record = RayRecord {
                    kind,
                    depth,
                    origin,
                    direction,
                    t_min,
                    t_max: t_max.is_finite().then_some(t_max),
                    steps: vec![],
                    hit: None,
                    children: vec![],
                    weight,
                    color: [0.0; 3],
                };
                if rays
                    .insert(
                        id,
                        Building {
                            record,
                            spawned: vec![],
                            own: None,
                        },
                    )
                    .is_some()
                {
                    return Err(format!("ray {id} begins twice"));
                }
                open.push(id);
            }
            tag::CAMERA => {
                let px = [p.u()?, p.u()?];
                let sample = p.u()?;
                let offset = [p.f()?, p.f()?];
                let screen = [p.f()?, p.f()?].map(|x| {
                    if x.to_bits() == NOT_COMPUTED {
                        f32::NAN
                    } else {
                        x
                    }
                });
                let direction = p.v()?;
                push(
                    &mut rays,
                    Step::Camera {
                        pixel: px,
                        sample,
                        offset,
                        screen,
                        direction,
                    },
                )?;
            }
            tag::NODE => push(&mut rays, node_step(&mut p, false)?)?,
            tag::TLAS_NODE => push(&mut rays, node_step(&mut p, true)?)?,
            tag::INSTANCE => push(&mut rays, instance_step(scene, &mut p)?)?,
            tag::INSTANCE_HIT => push(&mut rays, instance_hit_step(scene, &mut p)?)?,
            tag::TEST => push(&mut rays, test_step(scene, &mut p)?)?,
            tag::ACCEPT => {
                let object = p.u()?;
                let (t, previous) = (p.f()?, p.f()?);
                push(
                    &mut rays,
                    Step::Accept {
                        object,
                        name: scene.object_name(object),
                        t,
                        previous,
                    },
                )?;
            }
            tag::MISS => push(&mut rays, Step::Miss { background: p.v()? })?,
            tag::SURFACE => push(&mut rays, surface_step(&mut p)?)?,
            tag::SHADING_NORMAL => push(&mut rays, shading_normal_step(scene, &mut p)?)?,
            tag::TEXTURE_LOD => pending_lod = Some(texture_lod(&mut p)?),
            tag::ROUGHNESS => pending_roughness = Some(p.f()?),
            tag::TEXTURE => push(
                &mut rays,
                texture_step(scene, &mut p, pending_lod.take(), pending_roughness.take())?,
            )?,
            tag::LENS => push(&mut rays, mc::lens(&mut p)?)?,
            tag::EMITTED => push(&mut rays, mc::emitted(scene, &mut p)?)?,
            tag::LIGHT_SAMPLE => {
                let m = mc_scene
                    .as_ref()
                    .ok_or("a light sample in a Whitted trace")?;
                push(&mut rays, mc::light_sample(m, scene, &mut p)?)?
            }
            tag::BSDF_SAMPLE => push(&mut rays, mc::bsdf_sample(&mut p)?)?,
            tag::ROULETTE => push(&mut rays, mc::roulette(&mut p)?)?,
            tag::SHADOW_RAY => {
                let light = p.u()?;
                push(
                    &mut rays,
                    Step::ShadowRay {
                        light,
                        name: light_name(scene, light),
                        distance: p.f()?,
                    },
                )?;
            }
            tag::LIGHT => {
                let light = p.u()?;
                let blocked = p.b()?;
                let by = p.u()?;
                let (l_dot_n, r_dot_e) = (p.f()?, p.f()?);
                let (ambient, diffuse, specular) = (p.v()?, p.v()?, p.v()?);
                let (light_dir, reflected, eye, total) = (p.v()?, p.v()?, p.v()?, p.v()?);
                push(
                    &mut rays,
                    Step::Light {
                        light,
                        name: light_name(scene, light),
                        blocked,
                        blocker: (by != NO_OBJECT).then(|| scene.object_name(by)),
                        l_dot_n,
                        r_dot_e,
                        ambient,
                        diffuse,
                        specular,
                        light_dir: Some(light_dir),
                        reflected: Some(reflected),
                        eye: Some(eye),
                        total: Some(total),
                    },
                )?;
            }
            tag::REFLECT => {
                let reflective = p.f()?;
                let direction = p.v()?;
                let d_dot_n = p.f()?;
                push(
                    &mut rays,
                    Step::Reflect {
                        reflective,
                        direction,
                        d_dot_n: Some(d_dot_n),
                    },
                )?;
            }
            tag::REFRACT => {
                let (n1, n2, cos_i, sin2_t) = (p.f()?, p.f()?, p.f()?, p.f()?);
                let tir = p.b()?;
                let direction = p.v()?;
                let eta = p.f()?;
                let eye = p.v()?;
                let cos_t = p.f()?;
                push(
                    &mut rays,
                    Step::Refract {
                        n1,
                        n2,
                        cos_i,
                        sin2_t,
                        critical_angle_deg: critical_angle_deg(n1, n2),
                        total_internal_reflection: tir,
                        direction: (!tir).then_some(direction),
                        eta: Some(eta),
                        eye: Some(eye),
                        cos_t: (!tir).then_some(cos_t),
                    },
                )?;
            }
            tag::SCHLICK => {
                let [reflectance, r0, cos] = p.v()?;
                let has = p.f()? != 0.0;
                push(
                    &mut rays,
                    Step::Schlick {
                        reflectance,
                        r0: has.then_some(r0),
                        cos: has.then_some(cos),
                    },
                )?;
            }
            tag::DEPTH_LIMIT => push(&mut rays, Step::DepthLimit { max_depth: p.u()? })?,
            tag::CUTOFF => {
                let kind = kind_of(p.u()?)?;
                push(
                    &mut rays,
                    Step::WeightCutoff {
                        kind,
                        contribution: p.f()?,
                        cutoff: WEIGHT_CUTOFF,
                    },
                )?;
            }
            tag::SPAWN => {
                let child = p.u()?;
                let id = current.ok_or("a spawn outside any ray")?;
                let r = rays.get_mut(&id).ok_or("a spawn in a ray never begun")?;
                // The index into `children` is set once the tree is put together.
                r.record.steps.push(step(Step::Spawn { child }));
                r.spawned.push(child);
            }
            tag::COLOR => {
                let c = p.v()?;
                let id = current.ok_or("a colour outside any ray")?;
                let r = rays.get_mut(&id).ok_or("a colour of a ray never begun")?;
                r.own = Some(c);
                r.record.steps.push(step(Step::Color { color: c }));
            }
            tag::END => {
                let object = p.u()?;
                let (t, u, v) = (p.f()?, p.f()?, p.f()?);
                let instance = p.u()?;
                if instance != NO_INSTANCE && scene.instances.get(instance as usize).is_none() {
                    return Err(format!("instance {instance} is not one of the scene's"));
                }
                let id = open.pop().ok_or("a ray ends that never began")?;
                let r = rays.get_mut(&id).ok_or("a ray ends that never began")?;
                r.record.hit = (object != NO_OBJECT).then(|| HitRecord {
                    object,
                    name: scene.hit_name(&crate::accel::Hit {
                        object,
                        t,
                        u,
                        v,
                        instance,
                    }),
                    t,
                    uv: matches!(
                        scene.objects.get(object as usize).map(|o| o.shape),
                        Some(Shape::Triangle { .. })
                    )
                    .then_some([u, v]),
                    instance: (instance != NO_INSTANCE).then_some(instance),
                });
            }
            tag::PIXEL => {
                pixel_color = Some(p.v()?);
                // Then the summaries of the pixel's samples (Monte Carlo).
                summarising = mc_scene.is_some();
            }
            tag::HARDWARE => {
                // The world's boxes (the shader's count), and each instance's prototype's
                // boxes, which the hardware may test through that instance's transform.
                let placed: u64 = scene
                    .instances
                    .iter()
                    .filter_map(|i| scene.groups.get(i.group as usize))
                    .map(|g| u64::from(g.count))
                    .sum();
                let primitives = u32::try_from(u64::from(p.u()?) + placed).unwrap_or(u32::MAX);
                push(&mut rays, Step::HardwareTraversal { primitives })?
            }
            other => return Err(format!("record kind {other} is not one raystep writes")),
        }
    }
    let summaries_truncated = ran_out && pixel_color.is_some();
    if ran_out && !summaries_truncated {
        // The steps stop here: mark it in the ray the GPU was in.
        let last = open.last().copied().or_else(|| rays.keys().max().copied());
        if let Some(r) = last.and_then(|id| rays.get_mut(&id)) {
            r.record.steps.push(step(Step::Truncated {
                max_steps: u32::try_from(steps).unwrap_or(u32::MAX),
            }));
        }
    }
    let root = assemble(scene, &mut rays, 0, monte_carlo)?.ok_or("the log holds no primary ray")?;
    let color = pixel_color.unwrap_or(root.color);
    let objects = referenced_objects(scene, &root);
    let kept = scene.settings.spp.min(MAX_PIXEL_SAMPLES as u32) as usize;
    if monte_carlo && !ran_out && summaries.len() != kept {
        return Err(format!(
            "the log summarises {} of the pixel's {kept} samples",
            summaries.len()
        ));
    }
    // A trace's record holds every sample's summary or none (the loader's rule): a log that ran
    // out keeps none.
    let monte_carlo = mc_scene
        .filter(|_| !ran_out)
        .map(|m| mc::record(&m, scene, &root, &objects, summaries));
    Ok(GpuTrace {
        trace: Trace {
            version: TRACE_VERSION,
            raystep: env!("CARGO_PKG_VERSION").into(),
            scene: scene.name.clone(),
            scene_hash: scene.source_hash.clone(),
            pixel,
            sample,
            settings: scene.settings.clone(),
            root,
            camera: scene.camera.clone(),
            lights: scene.lights.clone(),
            objects,
            bvh,
            grid: None,
            monte_carlo,
            color,
        },
        truncated: ran_out,
        steps,
        summaries_truncated,
    })
}

fn light_name(scene: &Scene, light: u32) -> String {
    scene
        .lights
        .get(light as usize)
        .map_or_else(|| format!("light {light}"), |l| l.name.clone())
}

/// Puts ray `id` together with its children (in the order it spawned them) and its colour.
/// `monte_carlo`: the GPU logged each ray's colour itself (Whitted's are composed here).
fn assemble(
    scene: &Scene,
    rays: &mut HashMap<u32, Building>,
    id: u32,
    monte_carlo: bool,
) -> Result<Option<RayRecord>, String> {
    let Some(b) = rays.remove(&id) else {
        return Ok(None);
    };
    let Building {
        mut record,
        spawned,
        own,
    } = b;
    let mut index = HashMap::new();
    for child in spawned {
        if let Some(c) = assemble(scene, rays, child, monte_carlo)? {
            index.insert(child, record.children.len() as u32);
            record.children.push(c);
        }
    }
    // Spawn steps name the child's position in `children`; a child the log lost is dropped.
    record.steps.retain_mut(|s| match &mut s.step {
        Step::Spawn { child } => match index.get(child) {
            Some(&k) => {
                *child = k;
                true
            }
            None => false,
        },
        _ => true,
    });
    if let Some(own) = own {
        let color = if monte_carlo {
            own
        } else {
            compose(scene, &record, Vec3::from(own)).to_array()
        };
        record.color = color;
        for s in record.steps.iter_mut().rev() {
            if let Step::Color { color: c } = &mut s.step {
                *c = color;
                break;
            }
        }
        // The colour of a ray that hit nothing is the miss shader's.
        let missed = record.hit.is_none();
        if let Some(last) = record.steps.last_mut()
            && missed
            && matches!(last.step, Step::Color { .. })
        {
            last.stage = Stage::Miss;
        }
    }
    Ok(Some(record))
}

/// A ray's colour from its own term and its children's colours, by the CPU's formula.
fn compose(scene: &Scene, r: &RayRecord, own: Vec3) -> Vec3 {
    let Some(hit) = &r.hit else {
        return own;
    };
    let m = scene.material_of(hit.object);
    let child = |kind: RayKind| {
        r.children
            .iter()
            .find(|c| c.kind == kind)
            .map(|c| Vec3::from(c.color))
    };
    let reflected = child(RayKind::Reflection).map_or(Vec3::ZERO, |c| c * m.reflective);
    if m.transparency > 0.0 {
        let refracted = child(RayKind::Refraction).map_or(Vec3::ZERO, |c| c * m.transparency);
        let schlick = r.steps.iter().find_map(|s| match s.step {
            Step::Schlick { reflectance, .. } => Some(reflectance),
            _ => None,
        });
        if let Some(reflectance) = schlick {
            return own + reflected * reflectance + refracted * (1.0 - reflectance);
        }
        return own + reflected + refracted;
    }
    own + reflected
}

/// The objects a trace's steps mention, as the CPU's trace lists them.
fn referenced_objects(scene: &Scene, root: &RayRecord) -> Vec<TraceObject> {
    crate::trace::tracer::referenced_objects(scene, root)
}
