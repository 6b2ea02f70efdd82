//! The slice's captions: one line per focused step, and its number formats.

use super::*;
use crate::record::words;

/// One line saying what a step did (the subtitle while stepping).
pub(super) fn step_caption(ray: &RayRecord, step: &Step) -> String {
    let kind = ray.kind.name();
    let verdict =
        |t: Option<f32>| t.map_or("miss".to_string(), |t| format!("hit at t = {}", label(t)));
    match step {
        Step::Camera { .. } => "camera: the primary ray from the eye through the pixel".into(),
        Step::TlasNode(n) => format!(
            "{kind} ray: TLAS node {} (depth {}): {}",
            n.node,
            n.depth,
            words::node_action(n.action, ray.kind)
        ),
        Step::Instance {
            name, prototype, ..
        } => format!("{kind} ray: into the object space of \"{name}\" (a {prototype})"),
        Step::InstanceHit { name, .. } => {
            format!("{kind} ray: the hit on \"{name}\" carried back to the world")
        }
        Step::Node(n) if n.instance.is_some() => format!(
            "{kind} ray: BLAS node {} (depth {}): {}",
            n.node,
            n.depth,
            words::node_action(n.action, ray.kind)
        ),
        Step::Node(n) => format!(
            "{kind} ray: BVH node {} (depth {}): {}",
            n.node,
            n.depth,
            words::node_action(n.action, ray.kind)
        ),
        Step::SphereNode {
            node,
            depth,
            action,
            ..
        } => format!(
            "{kind} ray: bounding sphere {node} (depth {depth}): {}",
            words::node_action(*action, ray.kind)
        ),
        Step::Cell {
            cell, primitives, ..
        } => format!(
            "{kind} ray: grid cell ({}, {}, {}), {primitives} listed",
            cell[0], cell[1], cell[2]
        ),
        Step::MailboxSkip { name, .. } => {
            format!("{kind} ray: \"{name}\" already missed: mailbox skip")
        }
        Step::Sphere { name, test, .. } => {
            let roots = match test.roots {
                None => "no real roots".to_string(),
                Some([a, b]) if a == b => format!("touches at t = {}", label(a)),
                Some([a, b]) => format!("roots {} and {}", label(a), label(b)),
            };
            format!(
                "{kind} ray: sphere \"{name}\": {roots} → {}",
                verdict(test.t)
            )
        }
        Step::Plane { name, test, .. } => match test.t_raw {
            Some(t) => format!(
                "{kind} ray: plane \"{name}\": t = {} → {}",
                label(t),
                verdict(test.t)
            ),
            None => format!("{kind} ray: plane \"{name}\": parallel → miss"),
        },
        Step::Triangle { name, test, .. } => {
            format!("{kind} ray: triangle \"{name}\" → {}", verdict(test.t))
        }
        Step::Accept { name, t, .. } => {
            format!("{kind} ray: closest so far \"{name}\" at t = {}", label(*t))
        }
        Step::Miss { .. } => format!("{kind} ray: no hit → background"),
        Step::Surface { inside, .. } => {
            format!(
                "{kind} ray: hit point and normal{}",
                if *inside {
                    " (from inside: normal flipped)"
                } else {
                    ""
                }
            )
        }
        Step::ShadingNormal { angle_deg, .. } => format!(
            "{kind} ray: smooth shading: the vertex normals blended, {}° from the flat normal",
            label(*angle_deg)
        ),
        Step::Texture {
            texture, uv, texel, ..
        } => format!(
            "{kind} ray: texture \"{texture}\" at (u, v) = ({}, {}): colour {}",
            label(uv[0]),
            label(uv[1]),
            raystep_core::record::number::v3(*texel)
        ),
        Step::ShadowRay { name, distance, .. } => {
            format!("shadow ray towards \"{name}\" ({} away)", label(*distance))
        }
        Step::Light {
            name,
            blocked,
            blocker,
            l_dot_n,
            ..
        } => {
            if *blocked {
                format!(
                    "light \"{name}\": blocked by \"{}\" → ambient only",
                    blocker.as_deref().unwrap_or("?")
                )
            } else if *l_dot_n <= 0.0 {
                format!("light \"{name}\": behind the surface → ambient only")
            } else {
                format!("light \"{name}\": visible, l·n = {}", label(*l_dot_n))
            }
        }
        Step::Reflect { reflective, .. } => {
            format!("reflect: r = d − 2(d·n)n, weight {}", label(*reflective))
        }
        Step::Refract {
            n1,
            n2,
            total_internal_reflection,
            sin2_t,
            ..
        } => {
            if *total_internal_reflection {
                format!(
                    "refract {} → {}: sin²θt = {} > 1: total internal reflection",
                    label(*n1),
                    label(*n2),
                    label(*sin2_t)
                )
            } else {
                format!(
                    "refract {} → {}: θt = {}°",
                    label(*n1),
                    label(*n2),
                    fmt(
                        sin2_t.clamp(0.0, 1.0).sqrt().asin().to_degrees(),
                        Style::Decimals(1)
                    )
                )
            }
        }
        Step::Schlick { reflectance, .. } => {
            format!("Schlick: reflectance R = {}", label(*reflectance))
        }
        Step::DepthLimit { max_depth } => format!("recursion limit {max_depth}: no secondary ray"),
        Step::WeightCutoff { .. }
        | Step::Truncated { .. }
        | Step::HardwareTraversal { .. }
        | Step::Lens { .. }
        | Step::LightSample { .. }
        | Step::BsdfSample { .. }
        | Step::Emitted { .. }
        | Step::RussianRoulette { .. } => crate::explain::describe::describe(step, ray.kind),
        Step::Spawn { .. } => format!("{kind} ray spawns a child ray"),
        Step::Color { .. } => format!("{kind} ray: colour summed"),
    }
}
