//! raystep's own trace in the student format: what a student's tracer is checked against.
//!
//! Sphere and plane values are the ones raystep recorded (its course-notes-form a, b, c and
//! discriminant, its denominator); a test's `t` is the nearest root past t_min *ignoring* the
//! closest hit so far, because a student's loop usually tests every object against an open
//! interval and keeps the nearest afterwards. Triangles are given in Möller–Trumbore's terms
//! (lesson 4), computed in double precision from the recorded ray and vertices, whichever
//! method raystep used.

use super::format::{Hit, InstanceRay, Pixel, Ray, Surface, Test, placed_name};
use super::instancing::{InstanceHitFacts, carry_normal, transpose_times};
use crate::record::{RayRecord, Step, Trace};

/// raystep's trace of one pixel in the student model, with where each part is in the trace's
/// timeline (for the `raystep open … --step K` links).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Expected {
    /// The pixel's rays.
    pub pixel: Pixel,
    /// Per ray: the timeline index of its first step.
    pub ray_step: Vec<usize>,
    /// Per ray, per test: the timeline index of the test.
    pub test_step: Vec<Vec<usize>>,
    /// Per ray: the timeline index of its surface (hit point and normal), if any.
    pub hit_step: Vec<Option<usize>>,
    /// Per ray: the timeline index of its surface reading (the texture's step, else the shading
    /// normal's), if it has one.
    pub surface_step: Vec<Option<usize>>,
    /// Per ray: what raystep recorded about its surface reading, for naming mistakes.
    pub surfaces: Vec<SurfaceFacts>,
    /// Per ray, per instance entered: the timeline index of its step and M⁻¹ (3 × 4 rows), for
    /// naming mistakes in the object-space ray.
    pub instance_steps: Vec<Vec<(usize, [[f64; 4]; 3])>>,
    /// Per ray: the hit carried back from an instance, for naming mistakes in its normal.
    pub instance_hits: Vec<Option<InstanceHitFacts>>,
    /// Per ray, per light: the timeline index of the light's step.
    pub light_step: Vec<Vec<usize>>,
    /// Per ray: the reflection's or refraction's recorded numbers, for spotting mistakes.
    pub bends: Vec<Bend>,
    /// The camera and the primary ray's point inside the pixel (for naming camera mistakes).
    pub camera: Option<(crate::scene::Camera, [f32; 2])>,
    /// The textures met, by name ([`ImageRead::texture`] indexes it).
    pub texture_names: Vec<String>,
    /// The name of every object of the scene (for telling a student that a name they printed
    /// is not one; empty: not checked). [`expected`] leaves it empty (a trace names only the
    /// objects it met); [`with_names`] fills it.
    pub names: Vec<String>,
}

impl Expected {
    /// Whether `stage` judges anything at this pixel up to `upto`: every stage does but
    /// `surface`, which judges only a smooth-shaded or textured hit of a ray it looks at.
    pub fn judges(&self, stage: super::stage::Stage, upto: super::stage::Stage) -> bool {
        stage != super::stage::Stage::Surface
            || self
                .pixel
                .rays
                .iter()
                .any(|r| r.surface.is_some() && super::stage::in_scope(&r.kind, upto))
    }
}

/// `e` with the names of every object of `scene`, and the colours an image texture read with a
/// classic mistake would give (for naming it).
pub fn with_names(mut e: Expected, scene: &crate::scene::Scene) -> Expected {
    e.names = (0..scene.objects.len() as u32)
        .map(|i| scene.object_name(i))
        .collect();
    // A prototype's primitives as each instance places them: `gem near → gem[9]`.
    for inst in &scene.instances {
        if let Some(g) = scene.groups.get(inst.group as usize) {
            e.names.extend(
                (g.first..g.first + g.count)
                    .map(|i| placed_name(Some(&inst.name), &scene.object_name(i))),
            );
        }
    }
    for f in &mut e.surfaces {
        let Some(r) = f.image else { continue };
        let Some(name) = e.texture_names.get(r.texture) else {
            continue;
        };
        let Some(tex) = scene.textures.iter().find(|t| &t.name == name) else {
            continue;
        };
        // Level 0 only: a trilinear read's mistakes show in its first level's texel.
        if r.filter == crate::scene::Filter::Trilinear {
            continue;
        }
        let [w, h] = r.size.map(f64::from);
        let [u, v] = r.wrapped;
        let reads = [
            (Misread::VFlipped, [u * w, v * h], r.filter, 0.5),
            (
                Misread::HalfTexel,
                [u * w, (1.0 - v) * h],
                crate::scene::Filter::Bilinear,
                0.0,
            ),
            (
                Misread::Nearest,
                [u * w, (1.0 - v) * h],
                crate::scene::Filter::Nearest,
                0.5,
            ),
            (
                Misread::Bilinear,
                [u * w, (1.0 - v) * h],
                crate::scene::Filter::Bilinear,
                0.5,
            ),
        ];
        f.misreads = reads
            .into_iter()
            .filter(|(m, _, filter, _)| {
                *filter != r.filter || matches!(m, Misread::VFlipped | Misread::HalfTexel)
            })
            .filter(|(m, ..)| {
                *m != Misread::HalfTexel || r.filter == crate::scene::Filter::Bilinear
            })
            .map(|(m, at, filter, half)| (m, read_image(tex, &r, at, filter, half, false)))
            .collect();
        let at = [u * w, (1.0 - v) * h];
        f.misreads.push((
            Misread::NotDecoded,
            read_image(tex, &r, at, r.filter, 0.5, true),
        ));
    }
    e
}

/// sRGB's encoding of a linear value (IEC 61966-2-1): what the file stored.
pub(super) fn to_srgb(c: f64) -> f64 {
    if c <= 0.0031308 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// An image's colour at `at` (texel units of level 0), nearest or bilinear with the texel
/// centres at `half` past the integers, in f64: an independent read, for naming mistakes.
/// `encoded`: each texel as the file stores it (sRGB, not decoded to linear).
fn read_image(
    tex: &crate::scene::Texture,
    r: &ImageRead,
    at: [f64; 2],
    filter: crate::scene::Filter,
    half: f64,
    encoded: bool,
) -> [f64; 3] {
    let [w, h] = r.size;
    let index = |i: f64, n: u32| -> u32 {
        let last = i64::from(n.max(1)) - 1;
        let i = i.floor() as i64;
        (match r.wrap {
            crate::scene::Wrap::Repeat => i.rem_euclid(last + 1),
            _ => i.clamp(0, last),
        }) as u32
    };
    let texel = |x: f64, y: f64| {
        let c = tex.texel_at(0, index(x, w), index(y, h));
        [c.x, c.y, c.z]
            .map(f64::from)
            .map(|c| if encoded { to_srgb(c) } else { c })
    };
    if filter == crate::scene::Filter::Nearest {
        return texel(at[0], at[1]);
    }
    let (xs, ys) = (at[0] - half, at[1] - half);
    let (x0, y0) = (xs.floor(), ys.floor());
    let (fx, fy) = (xs - x0, ys - y0);
    let mut out = [0.0; 3];
    for (dx, dy, wt) in [
        (0.0, 0.0, (1.0 - fx) * (1.0 - fy)),
        (1.0, 0.0, fx * (1.0 - fy)),
        (0.0, 1.0, (1.0 - fx) * fy),
        (1.0, 1.0, fx * fy),
    ] {
        let c = texel(x0 + dx, y0 + dy);
        for k in 0..3 {
            out[k] += wt * c[k];
        }
    }
    out
}

/// What raystep recorded about a hit's shading normal and texture read, beyond what the
/// student prints: what feedback needs to name a mistake.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SurfaceFacts {
    /// The geometric normal, facing the ray.
    pub geometric: Option<[f64; 3]>,
    /// A smooth triangle's vertex normals n₀, n₁, n₂.
    pub vertex_normals: Option<[[f64; 3]; 3]>,
    /// A triangle's barycentrics (u, v): the weights of its second and third vertices.
    pub barycentric: Option<[f64; 2]>,
    /// A triangle's vertex texture coordinates.
    pub vertex_uvs: Option<[[f64; 2]; 3]>,
    /// An image texture's read.
    pub image: Option<ImageRead>,
    /// A checker's squares per unit of u and of v.
    pub checker: Option<[u32; 2]>,
    /// The texture's colour as a classic mistake would read it (filled by [`with_names`], which
    /// has the image): v flipped, texel centres off by half, nearest for bilinear and the other
    /// way round.
    pub misreads: Vec<(Misread, [f64; 3])>,
}

/// A classic mistake in reading an image texture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Misread {
    /// The row from v·h instead of (1 − v)·h.
    VFlipped,
    /// Bilinear's four texels from (⌊x⌋, ⌊y⌋), f = x − ⌊x⌋: texel centres at integers.
    HalfTexel,
    /// The nearest texel where the texture is bilinear.
    Nearest,
    /// Bilinear where the texture is nearest.
    Bilinear,
    /// The file's 8-bit sRGB values used as linear (c/255, not decoded).
    NotDecoded,
}

/// How raystep read an image texture at a hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImageRead {
    /// The texture's index in the scene.
    pub texture: usize,
    /// Width and height of the level first read.
    pub size: [u32; 2],
    /// The filter.
    pub filter: crate::scene::Filter,
    /// The wrap mode.
    pub wrap: crate::scene::Wrap,
    /// (u, v) after the wrap mode.
    pub wrapped: [f64; 2],
    /// The point in texel units of the level first read: (u·w, (1 − v)·h).
    pub address: [f64; 2],
}

/// What raystep recorded about a ray's reflection and refraction.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Bend {
    /// n1 / n2 of a refraction.
    pub eta: Option<f64>,
}

/// An f32 as the f64 with the same shortest decimal form (1.6f32 → 1.6, not 1.600000023841858),
/// so the format reads like the trace the app shows.
fn f(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(x as f64)
}

fn v64(a: [f32; 3]) -> [f64; 3] {
    a.map(f)
}

/// Converts `trace` (one sample of one pixel) to the student model.
pub fn expected(trace: &Trace) -> Expected {
    let tl = trace.timeline();
    let index_of = |s: &crate::record::StepRecord| tl.iter().position(|(_, t)| std::ptr::eq(*t, s));
    let mut out = Expected {
        pixel: Pixel {
            at: Some(trace.pixel),
            rays: vec![],
        },
        ..Default::default()
    };
    #[allow(clippy::too_many_lines)]
    fn walk(
        r: &RayRecord,
        parent: Option<usize>,
        light: Option<String>,
        out: &mut Expected,
        index_of: &dyn Fn(&crate::record::StepRecord) -> Option<usize>,
    ) {
        let me = out.pixel.rays.len();
        let mut ray = Ray {
            kind: r.kind.name().to_string(),
            depth: r.depth,
            origin: Some(v64(r.origin)),
            direction: Some(v64(r.direction)),
            light,
            parent,
            ..Default::default()
        };
        let mut tests = vec![];
        let mut hit_step = None;
        let mut lights = vec![];
        let mut shadow_lights = vec![];
        let mut bend = Bend::default();
        let (mut o, mut d) = (v64(r.origin), v64(r.direction));
        // Inside an instance: its name and the ray in its object space (the tests after it are
        // of its prototype, with that ray).
        let mut inside: Option<String> = None;
        let mut instance_steps = vec![];
        let mut instance_hit = None;
        let mut point_normal = None;
        let mut surface: Option<Surface> = None;
        let mut facts = SurfaceFacts::default();
        let mut surface_step = None;
        let mut texture_index = |name: &String| {
            out.texture_names
                .iter()
                .position(|t| t == name)
                .unwrap_or_else(|| {
                    out.texture_names.push(name.clone());
                    out.texture_names.len() - 1
                })
        };
        for s in &r.steps {
            let k = index_of(s).unwrap_or(0);
            match &s.step {
                Step::Instance {
                    name,
                    to_object,
                    origin,
                    direction,
                    ..
                } => {
                    (o, d) = (v64(*origin), v64(*direction));
                    ray.instances.push(InstanceRay {
                        name: name.clone(),
                        origin: Some(o),
                        direction: Some(d),
                        first_test: ray.tests.len(),
                        line: 0,
                    });
                    instance_steps.push((k, to_object.map(|row| row.map(f))));
                    inside = Some(name.clone());
                }
                Step::InstanceHit {
                    name,
                    to_world,
                    to_object,
                    point,
                    normal,
                    wrong_normal,
                    ..
                } => {
                    instance_hit = Some(InstanceHitFacts {
                        name: name.clone(),
                        to_world: to_world.map(|row| row.map(f)),
                        to_object: to_object.map(|row| row.map(f)),
                        point: v64(*point),
                        normal: v64(*normal),
                        wrong_normal: v64(*wrong_normal),
                    });
                }
                Step::Sphere { name, test, .. } => {
                    let t = test
                        .roots
                        .and_then(|[lo, hi]| [lo, hi].into_iter().find(|t| *t > r.t_min))
                        .map(f);
                    ray.tests.push(Test::Sphere {
                        object: placed_name(inside.as_deref(), name),
                        abcd: [test.a, test.b, test.c, test.discriminant].map(|x| Some(f(x))),
                        t: Some(t),
                    });
                    tests.push(k);
                }
                Step::Plane { name, test, .. } => {
                    let t = test
                        .t_raw
                        .filter(|t| t.is_finite() && *t > r.t_min && !test.parallel)
                        .map(f);
                    ray.tests.push(Test::Plane {
                        object: placed_name(inside.as_deref(), name),
                        denominator: Some(f(test.denominator)),
                        t: Some(t),
                    });
                    tests.push(k);
                }
                Step::Triangle { name, vertices, .. } => {
                    let (det, uvt) = moller_trumbore(o, d, vertices.map(v64), r.t_min as f64);
                    ray.tests.push(Test::Triangle {
                        object: placed_name(inside.as_deref(), name),
                        det_u_v: [Some(det), uvt.map(|x| x.0), uvt.map(|x| x.1)],
                        t: Some(uvt.map(|x| x.2)),
                    });
                    tests.push(k);
                }
                Step::Surface { point, normal, .. } => {
                    point_normal = Some((v64(*point), v64(*normal)));
                    facts.geometric = Some(v64(*normal));
                    hit_step = Some(k);
                }
                Step::ShadingNormal {
                    vertex_normals,
                    u,
                    v,
                    normal,
                    ..
                } => {
                    // On an instance the blend is in object space: carried out by M⁻ᵀ, as
                    // a tracer in world space prints it.
                    let shading = match &instance_hit {
                        Some(h) => carry_normal(&h.to_object, v64(*normal)),
                        None => v64(*normal),
                    };
                    surface.get_or_insert_default().normal = Some(shading);
                    // (Each carried without renormalising: the blend's direction is kept.)
                    facts.vertex_normals = Some(vertex_normals.map(|n| match &instance_hit {
                        Some(h) => transpose_times(&h.to_object, v64(n)),
                        None => v64(n),
                    }));
                    facts.barycentric = Some([f(*u), f(*v)]);
                    surface_step = surface_step.or(Some(k));
                }
                Step::Texture {
                    texture: texture_name,
                    uv,
                    lookup,
                    texel,
                    barycentric,
                    vertex_uvs,
                    roughness: None,
                    ..
                } => {
                    use crate::record::texturing::TexelLookup;
                    let sf = surface.get_or_insert_default();
                    sf.uv = Some(uv.map(f));
                    sf.texture = Some(v64(*texel));
                    sf.texel = match lookup {
                        TexelLookup::Checker { cell, .. } => Some(cell.map(|c| c as i64)),
                        TexelLookup::Image { texels, .. } => {
                            texels.first().map(|t| t.at.map(i64::from))
                        }
                    };
                    if let TexelLookup::Image {
                        size,
                        filter,
                        wrap,
                        wrapped,
                        address,
                        ..
                    } = lookup
                    {
                        facts.image = Some(ImageRead {
                            texture: texture_index(texture_name),
                            size: *size,
                            filter: *filter,
                            wrap: *wrap,
                            wrapped: wrapped.map(f),
                            address: address.map(f),
                        });
                    }
                    if let TexelLookup::Checker { squares, .. } = lookup {
                        facts.checker = Some(*squares);
                    }
                    if let Some(b) = barycentric {
                        facts.barycentric = Some(b.map(f));
                    }
                    facts.vertex_uvs = vertex_uvs.map(|t| t.map(|p| p.map(f)));
                    surface_step = Some(k);
                }
                Step::Light { name, blocked, .. } => {
                    ray.shadows.push((name.clone(), Some(*blocked)));
                    lights.push(k);
                }
                Step::ShadowRay { name, .. } => shadow_lights.push(name.clone()),
                Step::Refract { eta, n1, n2, .. } => {
                    bend.eta = Some(eta.map_or(f(*n1) / f(*n2), f));
                }
                _ => {}
            }
        }
        ray.surface = surface;
        ray.hit = Some(r.hit.as_ref().map(|h| Hit {
            object: Some(h.name.clone()),
            t: Some(f(h.t)),
            point: point_normal.map(|p| p.0),
            normal: point_normal.map(|p| p.1),
        }));
        // A shadow ray's hit is "blocked or not", shown by the light's record instead; it
        // returns no colour.
        if r.kind == crate::record::RayKind::Shadow {
            ray.hit = None;
        } else {
            ray.color = Some(v64(r.color));
        }
        out.pixel.rays.push(ray);
        out.ray_step
            .push(r.steps.first().and_then(index_of).unwrap_or(0));
        out.test_step.push(tests);
        out.hit_step.push(hit_step);
        out.surface_step.push(surface_step);
        out.surfaces.push(facts);
        out.light_step.push(lights);
        out.instance_steps.push(instance_steps);
        out.instance_hits.push(instance_hit);
        out.bends.push(bend);
        let mut shadow_names = shadow_lights.into_iter();
        for c in &r.children {
            let light = (c.kind == crate::record::RayKind::Shadow)
                .then(|| shadow_names.next())
                .flatten();
            walk(c, Some(me), light, out, index_of);
        }
    }
    walk(&trace.root, None, None, &mut out, &index_of);
    let offset = trace.root.steps.iter().find_map(|s| match &s.step {
        Step::Camera { offset, .. } => Some(*offset),
        _ => None,
    });
    out.camera = Some((trace.camera.clone(), offset.unwrap_or([0.5, 0.5])));
    out
}

/// Möller–Trumbore in double precision (lesson 4): D0 = det(−Q, E1, E2), and (u, v, t) when the
/// ray hits the triangle past `t_min`.
pub fn moller_trumbore(
    s: [f64; 3],
    q: [f64; 3],
    p: [[f64; 3]; 3],
    t_min: f64,
) -> (f64, Option<(f64, f64, f64)>) {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (e1, e2) = (sub(p[1], p[0]), sub(p[2], p[0]));
    let nq = [-q[0], -q[1], -q[2]];
    // det(a, b, c) = a · (b × c)
    let det = |a, b, c| dot(a, cross(b, c));
    let d0 = det(nq, e1, e2);
    if d0 == 0.0 {
        return (d0, None);
    }
    let t_vec = sub(s, p[0]);
    let t = det(t_vec, e1, e2) / d0;
    let u = det(nq, t_vec, e2) / d0;
    let v = det(nq, e1, t_vec) / d0;
    let hit = t > t_min && u >= 0.0 && v >= 0.0 && u + v <= 1.0;
    (d0, hit.then_some((u, v, t)))
}
