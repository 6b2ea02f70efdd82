//! One-line descriptions of steps in words, for the command line's trace tree (and the app).

use crate::record::number::{num, opt, v3};
use crate::record::words;
use crate::record::{RayKind, RayRecord, Stage, Step, Trace};
use crate::shapes::{PlaneForm, RootChoice, SphereMethod, TriangleMethod};
use std::fmt::Write;

/// The stage's name as the pipeline calls it.
pub fn stage_name(s: Stage) -> &'static str {
    match s {
        Stage::RayGeneration => "ray-generation",
        Stage::Traversal => "traversal",
        Stage::Intersection => "intersection",
        Stage::AnyHit => "any-hit",
        Stage::ClosestHit => "closest-hit",
        Stage::Miss => "miss",
    }
}

/// Where a triangle test stopped, in words: on a shadow ray a t at or beyond the ray's end is
/// the light (or something behind it), not "beyond the closest hit".
fn triangle_stop(test: &crate::shapes::TriangleTest<f32>, kind: RayKind) -> &'static str {
    match (test.stopped_at, test.t_star) {
        (5, Some(t)) if kind == RayKind::Shadow && t > 0.0 => {
            "t out of range: at or beyond the shadow ray's end (just short of the light), not in the way"
        }
        _ => test.stop_reason(),
    }
}

/// What a light sample needs said when the shading point lies on the light it samples (a lamp's
/// own surface: a camera ray that hit the lamp, or a bounce that did): its density and its
/// contribution then look wrong but are not. None for any other sample. `trace` gives the
/// light's shape (its Monte Carlo record) and the shading point (the ray's surface step).
pub fn own_light_note(trace: &Trace, ray: &RayRecord, step: &Step) -> Option<String> {
    use crate::mc::lights::LightShape;
    let Step::LightSample {
        light, direction, ..
    } = step
    else {
        return None;
    };
    let shape = trace.monte_carlo.as_ref()?.light(*light)?.shape;
    let point = ray.steps.iter().find_map(|s| match s.step {
        Step::Surface { point, .. } => Some(glam::Vec3::from(point)),
        _ => None,
    })?;
    let d = glam::Vec3::from(*direction);
    match shape {
        LightShape::Triangle { p, normal, .. } => {
            // In the light's plane: the point is on the lamp (or beside it, in its plane).
            let scale = (p[1] - p[0]).length().max((p[2] - p[0]).length());
            let off = (point - p[0]).dot(normal).abs();
            let cos_l = d.dot(normal).abs();
            (off <= 1e-4 * scale.max(1e-6)).then(|| {
                format!(
                    "the shading point lies on this light's own plane (on the lamp itself): every \
                     point of the lamp is seen edge-on from here (|cos θ| at the light = {}), so \
                     its density per steradian, d² / (A · |cos θ|), means nothing here (it may be \
                     huge, or 0) and the sample adds next to nothing; the lamp's own light was \
                     counted when the ray hit it",
                    num(cos_l)
                )
            })
        }
        LightShape::Sphere { center, radius } => {
            let dc = (center - point).length();
            (dc <= radius * (1.0 + 1e-3)).then(|| {
                format!(
                    "the shading point is on (or inside) this sphere light itself (its distance \
                     to the centre, {}, is the radius {} to within rounding): the light fills \
                     the half of the sky below the tangent plane, so its cone density and its \
                     contribution mean nothing here; the lamp's own light was counted when the \
                     ray hit it",
                    num(dc),
                    num(radius)
                )
            })
        }
        LightShape::Point { .. } => None,
    }
}

/// Describes one step of a ray of kind `kind` in a line of words and numbers (the kind decides
/// the words for a node pushed for later: see [`words::node_action`]).
pub fn describe(step: &Step, kind: RayKind) -> String {
    match step {
        Step::Camera {
            pixel,
            sample,
            offset,
            screen,
            direction,
        } => {
            let at = format!(
                "camera: pixel ({}, {}) sample {sample}, at ({}, {}) in the pixel",
                pixel[0],
                pixel[1],
                num(offset[0]),
                num(offset[1])
            );
            if screen.iter().all(|s| s.is_nan()) {
                // A GPU trace of the fragment path: no screen position was computed.
                format!(
                    "{at} → direction {} (interpolated by the rasterizer)",
                    v3(*direction)
                )
            } else {
                format!(
                    "{at} → screen ({}, {}) → direction {}",
                    num(screen[0]),
                    num(screen[1]),
                    v3(*direction)
                )
            }
        }
        Step::TlasNode(n) => format!(
            "TLAS node {} (depth {}{}): slabs give t_near = {}, t_far = {} → {}",
            n.node,
            n.depth,
            if n.leaf { ", leaf of instances" } else { "" },
            num(n.test.t_near),
            num(n.test.t_far),
            match n.action {
                crate::record::NodeAction::TestPrimitives => "hit: enter its instances",
                a => words::node_action(a, kind),
            }
        ),
        Step::Instance {
            name,
            prototype,
            origin,
            direction,
            ..
        } => format!(
            "into the object space of instance \"{name}\" ({prototype}): S′ = M⁻¹·S = {}, Q′ = M⁻¹·Q = {} → walk {prototype}'s BLAS",
            v3(*origin),
            v3(*direction)
        ),
        Step::InstanceHit {
            name,
            point,
            normal,
            world_point,
            world_normal,
            wrong_normal,
            ..
        } => format!(
            "hit carried back from instance \"{name}\": P = M·P′ = M·{} = {}; n = M⁻ᵀ·n′ = M⁻ᵀ·{} → {} (M·n′ would give {})",
            v3(*point),
            v3(*world_point),
            v3(*normal),
            v3(*world_normal),
            v3(*wrong_normal)
        ),
        // A BLAS's nodes (an instance's prototype tree) read as the world tree's.
        Step::Node(n) => format!(
            "{} node {} (depth {}{}): slabs give t_near = {}, t_far = {} → {}",
            if n.instance.is_some() { "BLAS" } else { "BVH" },
            n.node,
            n.depth,
            if n.leaf { ", leaf" } else { "" },
            num(n.test.t_near),
            num(n.test.t_far),
            words::node_action(n.action, kind)
        ),
        Step::SphereNode {
            node,
            depth,
            center,
            radius,
            test,
            leaf,
            action,
            ..
        } => format!(
            "bounding sphere {node} (depth {depth}{}): centre {}, r = {}: {} → {}",
            if *leaf { ", leaf" } else { "" },
            v3(*center),
            num(*radius),
            match test.roots {
                Some([t0, t1]) =>
                    format!("the ray is inside it for t in [{}, {}]", num(t0), num(t1)),
                None => "Δ < 0, the ray's line passes it by".into(),
            },
            words::node_action(*action, kind)
        ),
        Step::Cell {
            cell,
            t_entry,
            t_exit,
            axis,
            primitives,
            ..
        } => format!(
            "grid cell ({}, {}, {}){}: t from {} to {}, {primitives} primitive{} listed",
            cell[0],
            cell[1],
            cell[2],
            axis.map_or(" (the entry cell)".to_string(), |a| format!(
                " (stepped along {})",
                words::axis(a)
            )),
            num(*t_entry),
            num(*t_exit),
            if *primitives == 1 { "" } else { "s" }
        ),
        Step::MailboxSkip { name, .. } => {
            format!("\"{name}\" was tested in an earlier cell and missed: the mailbox skips it")
        }
        Step::Sphere { name, test, .. } => {
            let mut s = format!(
                "sphere \"{name}\" ({}): a = {}, b = {}, c = {}, Δ = b² − 4ac = {}",
                match test.method {
                    SphereMethod::Textbook => "textbook",
                    SphereMethod::Stable => "stable",
                },
                num(test.a),
                num(test.b),
                num(test.c),
                num(test.discriminant)
            );
            let _ = write!(s, " → {}", words::sphere_case(test.case));
            if let Some([t0, t1]) = test.roots {
                let _ = write!(s, ", roots {} and {}", num(t0), num(t1));
            }
            if test.choice != RootChoice::NoRoots {
                let _ = write!(s, " → {}", words::root_choice_on(test.choice, kind));
            }
            s
        }
        Step::Plane { name, test, .. } => {
            let form = match test.form {
                PlaneForm::General { .. } => "X·n = c",
                PlaneForm::Axis { axis, .. } => match axis {
                    0 => "x = c",
                    1 => "y = c",
                    2 => "z = c",
                    _ => "axis = c",
                },
            };
            if test.parallel {
                format!(
                    "plane \"{name}\" ({form}): denominator = {} → parallel: miss",
                    num(test.denominator)
                )
            } else {
                format!(
                    "plane \"{name}\" ({form}): t = {} / {} = {}{}",
                    num(test.numerator),
                    num(test.denominator),
                    opt(test.t_raw),
                    match (test.t, test.t_raw) {
                        (Some(_), _) => " → hit",
                        (None, Some(t)) if t > 0.0 && kind == RayKind::Shadow => {
                            " → at or beyond the shadow ray's end (the light): not in the way"
                        }
                        (None, Some(t)) if t > 0.0 => " → beyond the closest hit so far: miss",
                        _ => " → behind the origin: miss",
                    }
                )
            }
        }
        Step::Triangle { name, test, .. } => match test.method {
            TriangleMethod::MollerTrumbore => format!(
                "triangle \"{name}\" (Möller–Trumbore): D0 = {}, Dt = {}, Du = {}, Dv = {}, t* = {}, u* = {}, v* = {} → stopped at step {}: {}",
                num(test.det),
                opt(test.dt),
                opt(test.du),
                opt(test.dv),
                opt(test.t_star),
                opt(test.u),
                opt(test.v),
                test.stopped_at,
                triangle_stop(test, kind)
            ),
            TriangleMethod::Watertight => format!(
                "triangle \"{name}\" (watertight): edges {}, det = {}, t = {}, u = {}, v = {} → {}",
                test.edges.map_or("—".into(), v3),
                // "det = 0" would read as a parallel ray: a test that stopped at the edges'
                // signs never computed it.
                opt(test.det_computed()),
                opt(test.t_star),
                opt(test.u),
                opt(test.v),
                triangle_stop(test, kind)
            ),
        },
        Step::Accept {
            name, t, previous, ..
        } => {
            format!(
                "closest so far: \"{name}\" at t = {} (was {}); t_max shrinks",
                num(*t),
                num(*previous)
            )
        }
        Step::Miss { background } => format!("no hit: background {}", v3(*background)),
        Step::Surface {
            point,
            normal,
            inside,
            over_point,
            ..
        } => format!(
            "surface at {} with normal {}{}; spawned rays start at {}",
            v3(*point),
            v3(*normal),
            if *inside {
                " (hit from inside: normal flipped)"
            } else {
                ""
            },
            v3(*over_point)
        ),
        Step::ShadingNormal {
            normal,
            angle_deg,
            lifted,
            ..
        } => format!(
            "smooth shading: the vertex normals blended at (u, v) give the shading normal {} \
             ({}° from the flat normal){}",
            v3(*normal),
            num(*angle_deg),
            lifted.map_or(String::new(), |p| format!(
                "; Hanika's lift: rays on its side leave from P′ = {}",
                v3(p)
            ))
        ),
        Step::Texture {
            texture,
            mapping,
            uv,
            lookup,
            texel,
            roughness,
            ..
        } => format!(
            "{}texture \"{texture}\": (u, v) = ({}, {}) from {}, {}: colour {}{}",
            roughness.map_or(String::new(), |_| "roughness ".into()),
            num(uv[0]),
            num(uv[1]),
            mapping.name(),
            match lookup {
                crate::record::texturing::TexelLookup::Checker { cell, odd, .. } => format!(
                    "square ({}, {}), {}",
                    num(cell[0]),
                    num(cell[1]),
                    if *odd { "odd" } else { "even" }
                ),
                crate::record::texturing::TexelLookup::Image {
                    texels,
                    address,
                    lod,
                    ..
                } => format!(
                    "{}texel position ({}, {}): {}",
                    lod.as_ref().map_or(String::new(), |l| format!(
                        "ray cone γ·d = {}·{} = {} wide, |n·d̂| = {}, footprint {} texels, \
                         λ = {}: mip level {}; ",
                        num(l.spread),
                        num(l.distance),
                        num(l.width),
                        num(l.cos),
                        num(l.footprint),
                        num(l.lambda),
                        l.levels
                            .iter()
                            .map(|m| format!("{} (weight {})", m.level, num(m.weight)))
                            .collect::<Vec<_>>()
                            .join(" and ")
                    )),
                    num(address[0]),
                    num(address[1]),
                    match texels.as_slice() {
                        [t] => format!("texel ({}, {})", t.at[0], t.at[1]),
                        ts => format!(
                            "texels {} weighted {}",
                            ts.iter()
                                .map(|t| if lod.is_some() {
                                    format!("({}, {}) of level {}", t.at[0], t.at[1], t.level)
                                } else {
                                    format!("({}, {})", t.at[0], t.at[1])
                                })
                                .collect::<Vec<_>>()
                                .join(", "),
                            ts.iter()
                                .map(|t| num(t.weight))
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    }
                ),
            },
            v3(*texel),
            roughness.map_or(String::new(), |r| format!(
                "; roughness {} × green {} = {}",
                num(r.material),
                num(texel[1]),
                num(r.roughness)
            ))
        ),
        Step::ShadowRay { name, distance, .. } => {
            format!(
                "shadow ray towards light \"{name}\" ({} away)",
                num(*distance)
            )
        }
        Step::Light {
            name,
            blocked,
            blocker,
            l_dot_n,
            r_dot_e,
            ambient,
            diffuse,
            specular,
            ..
        } => {
            let vis = if *blocked {
                format!(
                    "blocked by \"{}\": ambient only",
                    blocker.as_deref().unwrap_or("?")
                )
            } else if *l_dot_n <= 0.0 {
                "behind the surface: ambient only".into()
            } else {
                "visible".into()
            };
            format!(
                "light \"{name}\": {vis}; l·n = {}, r·e = {}; ambient {} + diffuse {} + specular {}",
                num(*l_dot_n),
                num(*r_dot_e),
                v3(*ambient),
                v3(*diffuse),
                v3(*specular)
            )
        }
        Step::Reflect {
            reflective,
            direction,
            ..
        } => {
            format!(
                "reflect (reflective = {}): r = d − 2(d·n)n = {}",
                num(*reflective),
                v3(*direction)
            )
        }
        Step::Refract {
            n1,
            n2,
            cos_i,
            sin2_t,
            critical_angle_deg,
            total_internal_reflection,
            direction,
            ..
        } => {
            let mut s = format!(
                "refract n1 = {} → n2 = {}: cos θi = {}, sin² θt = {}",
                num(*n1),
                num(*n2),
                num(*cos_i),
                num(*sin2_t)
            );
            if let Some(c) = critical_angle_deg {
                let _ = write!(s, " (critical angle {}°)", num(*c));
            }
            if *total_internal_reflection {
                s += " > 1 → total internal reflection: no refracted ray";
            } else if let Some(d) = direction {
                let _ = write!(s, " → refracted direction {}", v3(*d));
            }
            s
        }
        Step::Schlick { reflectance, .. } => format!(
            "Schlick: reflectance R = {}, so reflection × R + refraction × (1 − R)",
            num(*reflectance)
        ),
        Step::DepthLimit { max_depth } => {
            format!("recursion limit {max_depth} reached: no secondary ray")
        }
        Step::WeightCutoff {
            kind,
            contribution,
            cutoff,
        } => format!(
            "{} ray not spawned: its share of the pixel, {}, is below the cut-off {}",
            kind.name(),
            num(*contribution),
            num(*cutoff)
        ),
        Step::Lens {
            random,
            lens_point,
            focus_point,
            ..
        } => format!(
            "thin lens: {} → lens point {}, aimed at {} on the plane in focus",
            crate::explain::formula::monte_carlo::draws(random),
            v3(*lens_point),
            v3(*focus_point)
        ),
        Step::LightSample {
            name,
            random,
            pdf,
            select_pdf,
            mis_weight,
            blocked,
            contribution,
            ..
        } => format!(
            "light sample on \"{name}\": {} · P(pick) = {}, pdf = {}, MIS w = {} → {}",
            crate::explain::formula::monte_carlo::draws(random),
            num(*select_pdf),
            num(*pdf),
            num(*mis_weight),
            if *blocked {
                "blocked, adds nothing".to_string()
            } else {
                format!("adds {}", v3(*contribution))
            }
        ),
        Step::BsdfSample {
            bsdf,
            lobe,
            random,
            direction,
            pdf,
            weight,
            ..
        } => format!(
            "{bsdf} BSDF sample ({lobe}): {} → direction {}, pdf {}, weight f·cos/pdf = {}",
            crate::explain::formula::monte_carlo::draws(random),
            v3(*direction),
            pdf.map_or("δ".to_string(), num),
            v3(*weight)
        ),
        Step::Emitted {
            name,
            radiance,
            mis_weight,
            contribution,
            ..
        } => format!(
            "\"{name}\" emits {} · MIS w = {} → adds {}",
            v3(*radiance),
            num(*mis_weight),
            v3(*contribution)
        ),
        Step::RussianRoulette {
            random,
            probability,
            survived,
            ..
        } => format!(
            "Russian roulette: u[{}] = {} {} q = {} → {}",
            random.dimension,
            num(random.value),
            if *survived { "<" } else { "≥" },
            num(*probability),
            if *survived {
                "the path goes on, weight ÷ q"
            } else {
                "the path ends"
            }
        ),
        Step::Truncated { max_steps } => format!(
            "the trace stops here: it reached its limit of {max_steps} steps (the tracing went on; the colours are exact)"
        ),
        Step::HardwareTraversal { primitives } => format!(
            "hardware traversal of {primitives} primitive boxes: the boxes it tested are not revealed"
        ),
        Step::Spawn { child } => format!("→ child ray {child}"),
        Step::Color { color } => format!("colour {}", v3(*color)),
    }
}

/// The whole trace as an indented tree of rays and steps, children where they were spawned.
///
/// Every step line starts with its number in brackets, `[K]`: its index in
/// [`Trace::timeline`], counted from 0 over every step in the order it happened, the spawn steps
/// included (`[9] [closest-hit] → child ray 0`, the child ray's steps below it). That is the
/// number the app's step list and step bar show and what `--step K` takes (`raystep diagram`,
/// `raystep view`, `raystep open`).
pub fn tree(trace: &Trace) -> String {
    fn ray(trace: &Trace, r: &RayRecord, indent: usize, k: &mut usize, out: &mut String) {
        let pad = "  ".repeat(indent);
        let _ = writeln!(
            out,
            "{pad}{} ray (depth {}): S = {}, Q = {}, t in ({}, {}){}",
            r.kind.name(),
            r.depth,
            v3(r.origin),
            v3(r.direction),
            num(r.t_min),
            r.t_max.map_or("∞".into(), num),
            if r.weight != 1.0 && r.weight != 0.0 {
                format!(", weight {}", num(r.weight))
            } else {
                String::new()
            }
        );
        for s in &r.steps {
            let _ = writeln!(
                out,
                "{pad}  [{k}] [{}] {}{}",
                stage_name(s.stage),
                describe(&s.step, r.kind),
                own_light_note(trace, r, &s.step).map_or(String::new(), |n| format!(" ({n})"))
            );
            *k += 1;
            // The child's steps follow its spawn step, as in the timeline.
            if let Step::Spawn { child } = s.step
                && let Some(c) = r.children.get(child as usize)
            {
                ray(trace, c, indent + 1, k, out);
            }
        }
        match (&r.hit, r.kind) {
            (Some(h), RayKind::Shadow) => {
                let _ = writeln!(
                    out,
                    "{pad}  ⇒ blocked by \"{}\" at t = {}",
                    h.name,
                    num(h.t)
                );
            }
            (None, RayKind::Shadow) => {
                let _ = writeln!(out, "{pad}  ⇒ nothing in the way");
            }
            (Some(h), _) => {
                let _ = writeln!(out, "{pad}  ⇒ hit \"{}\" at t = {}", h.name, num(h.t));
            }
            (None, _) => {}
        }
    }
    let mut out = format!(
        "scene \"{}\", pixel ({}, {}), sample {}: colour {}\n",
        trace.scene,
        trace.pixel[0],
        trace.pixel[1],
        trace.sample,
        v3(trace.color)
    );
    if let Some(mc) = &trace.monte_carlo {
        out.push_str(&pixel_summary(mc));
    }
    ray(trace, &trace.root, 0, &mut 0, &mut out);
    out
}

/// The estimate of a Monte Carlo pixel from its first `n` samples: what the app's math panel
/// shows while the samples are added one at a time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunningEstimate {
    /// Finite samples among the first `n` (a sample that is not finite is left out).
    pub n: usize,
    /// Their mean, linear RGB.
    pub mean: [f64; 3],
    /// The mean of their luminance (Rec. 709).
    pub luminance: f64,
    /// The sample standard deviation of their luminance (0 below 2 samples).
    pub sd: f64,
    /// The half-width of the 95 % confidence interval of the luminance mean, 1.96 · sd / √n
    /// (the normal approximation: with few samples, or a heavy tail, it is optimistic).
    pub half_width: f64,
}

/// The estimate from the first `n` kept samples of `mc`.
pub fn running_estimate(mc: &crate::record::samples::McRecord, n: usize) -> RunningEstimate {
    use crate::record::samples::luminance;
    let kept: Vec<&crate::record::samples::PixelSample> = mc
        .samples
        .iter()
        .take(n)
        .filter(|s| s.color.iter().all(|c| c.is_finite()))
        .collect();
    let k = kept.len();
    let mut mean = [0.0f64; 3];
    for s in &kept {
        for (m, c) in mean.iter_mut().zip(s.color) {
            *m += f64::from(c);
        }
    }
    let d = k.max(1) as f64;
    let mean = mean.map(|m| m / d);
    let lum: Vec<f64> = kept.iter().map(|s| f64::from(luminance(s.color))).collect();
    let lmean = lum.iter().sum::<f64>() / d;
    let var = if k > 1 {
        lum.iter().map(|v| (v - lmean).powi(2)).sum::<f64>() / (k - 1) as f64
    } else {
        0.0
    };
    let sd = var.sqrt();
    RunningEstimate {
        n: k,
        mean,
        luminance: lmean,
        sd,
        half_width: 1.96 * sd / d.sqrt(),
    }
}

/// A Monte Carlo pixel's samples in numbers: their mean (the pixel), and the spread of their
/// luminance — the sample standard deviation s and the standard error s/√n of the mean, which
/// falls as 1/√n.
pub fn pixel_summary(mc: &crate::record::samples::McRecord) -> String {
    let e = running_estimate(mc, mc.samples.len());
    let (n, mean, sd) = (e.n, e.luminance, e.sd);
    let dark = mc
        .samples
        .iter()
        .filter(|s| s.color.iter().all(|c| *c == 0.0))
        .count();
    let kept = if mc.samples.len() < mc.spp as usize {
        format!("the first {} of its {} samples", mc.samples.len(), mc.spp)
    } else {
        format!(
            "{} sample{}",
            mc.samples.len(),
            if mc.samples.len() == 1 { "" } else { "s" }
        )
    };
    // The light samples at the first hits, per light: how many, how many blocked.
    let mut per_light: Vec<(String, usize, usize)> = vec![];
    for s in &mc.samples {
        for lp in &s.light_samples {
            let name = mc.light(lp.light).map_or("?", |l| l.name.as_str());
            match per_light.iter_mut().find(|(n, _, _)| n == name) {
                Some(e) => {
                    e.1 += 1;
                    e.2 += usize::from(lp.blocked);
                }
                None => per_light.push((name.to_string(), 1, usize::from(lp.blocked))),
            }
        }
    }
    let lights = if per_light.is_empty() {
        String::new()
    } else {
        let parts: Vec<String> = per_light
            .iter()
            .map(|(n, k, b)| format!("\"{n}\" {k}, {b} blocked"))
            .collect();
        format!("  light samples at the first hit: {}\n", parts.join("; "))
    };
    format!(
        "the pixel: {kept}, mean {}; luminance mean {}, sample standard deviation s = {}, standard error s/√n = {}; {dark} sample{} added nothing\n{lights}",
        v3(mc.mean()),
        num(mean as f32),
        num(sd as f32),
        num((sd / (n.max(1) as f64).sqrt()) as f32),
        if dark == 1 { "" } else { "s" }
    )
}

#[cfg(test)]
mod running_tests {
    use super::*;
    use crate::record::samples::{McRecord, PixelSample};

    fn sample(k: u32, c: f32) -> PixelSample {
        PixelSample {
            sample: k,
            color: [c; 3],
            hit: None,
            normal: None,
            object: None,
            light_samples: vec![],
            bounce: None,
        }
    }

    /// Grey samples 1, 0, 0.5 (luminance = the grey: Rec. 709's weights sum to 1): mean 0.5,
    /// s² = (0.25 + 0.25 + 0) / 2, so s = 0.5, and the 95 % half-width 1.96 · 0.5 / √3; a NaN
    /// sample is left out.
    #[test]
    fn running_estimate_by_hand() {
        let mc = McRecord {
            spp: 4,
            lights: vec![],
            bsdfs: vec![],
            samples: vec![
                sample(0, 1.0),
                sample(1, 0.0),
                sample(2, 0.5),
                sample(3, f32::NAN),
            ],
        };
        let e = running_estimate(&mc, 4);
        assert_eq!(e.n, 3);
        assert!((e.luminance - 0.5).abs() < 1e-7);
        assert!((e.sd - 0.5).abs() < 1e-7);
        assert!((e.half_width - 1.96 * 0.5 / 3f64.sqrt()).abs() < 1e-7);
        let one = running_estimate(&mc, 1);
        assert_eq!((one.n, one.sd, one.half_width), (1, 0.0, 0.0));
    }
}
