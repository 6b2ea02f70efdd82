//! The closest-hit stage: each ray's `hit` record against raystep's — the object (an
//! instance's primitive named `instance → primitive`), t, the point P = S + t·Q and the unit
//! normal facing the ray — with the common mistakes named (a normal not normalized or not
//! flipped, and on an instance the point or normal left in object space or the normal carried
//! by M instead of M⁻ᵀ: [`super::instancing`]).

use super::compare::{Divergence, TracerTolerances, len, n, scales, unit, v};
use super::expected::Expected;
use super::format::Pixel;
use super::stage::{Stage, in_scope, ray_name};

pub(super) fn hits(
    e: &Expected,
    s: &Pixel,
    m: &[Option<usize>],
    upto: Stage,
    tol: &TracerTolerances,
) -> Divergence {
    for (i, er) in e.pixel.rays.iter().enumerate() {
        if !in_scope(&er.kind, upto) || er.kind == "shadow" {
            continue;
        }
        let Some(sr) = m.get(i).copied().flatten().and_then(|k| s.rays.get(k)) else {
            continue;
        };
        let step = e
            .hit_step
            .get(i)
            .copied()
            .flatten()
            .or(e.ray_step.get(i).copied());
        let name = ray_name(&e.pixel, i);
        let (ls, le) = scales(er, sr);
        let tol = &tol.at_depth(er.depth);
        let Some(eh) = &er.hit else { continue };
        let instance = e.instance_hits.get(i).and_then(Option::as_ref);
        let Some(sh) = &sr.hit else {
            return Some((
                format!(
                    "{name}: no `hit` record: print the ray's closest hit (object null for none)"
                ),
                step,
            ));
        };
        match (eh, sh) {
            (None, None) => {}
            (Some(h), None) => {
                return Some((
                    format!(
                        "{name}: you found no hit, raystep's closest hit is \"{}\" at t = {}",
                        h.object.clone().unwrap_or_default(),
                        h.t.map_or("?".into(), n)
                    ),
                    step,
                ));
            }
            (None, Some(h)) => {
                return Some((
                    format!(
                        "{name}: you hit \"{}\", raystep's ray hits nothing",
                        h.object.clone().unwrap_or_default()
                    ),
                    step,
                ));
            }
            (Some(eh), Some(sh)) => {
                if let (Some(so), Some(eo)) = (&sh.object, &eh.object)
                    && so != eo
                {
                    return Some((
                        format!(
                            "{name}: your closest hit is \"{so}\"{}, raystep's is \"{eo}\" at t = {} — keep the smallest t past t_min",
                            sh.t.map_or(String::new(), |t| format!(" at t = {}", n(t))),
                            eh.t.map_or("?".into(), n)
                        ),
                        step,
                    ));
                }
                if let (Some(y), Some(w)) = (sh.t, eh.t)
                    && !tol.close(y * ls, w * le)
                {
                    return Some((
                        format!("{name}: your closest t is {}, raystep's is {}", n(y), n(w)),
                        step,
                    ));
                }
                if let (Some(y), Some(w)) = (sh.point, eh.point)
                    && !tol.close3(y, w, tol.abs * len(w).max(1.0))
                {
                    let hint = match super::instancing::point_hint(instance, y, tol) {
                        "" => " — P = S + t·Q",
                        h => h,
                    };
                    return Some((
                        format!(
                            "{name}: your hit point is {}, raystep's is {}{hint}",
                            v(y),
                            v(w)
                        ),
                        step,
                    ));
                }
                if let (Some(y), Some(w)) = (sh.normal, eh.normal)
                    && !tol.close3(y, w, tol.abs * 10.0)
                {
                    let l = len(y);
                    let hint = if (l - 1.0).abs() > 1e-3 && tol.close3(unit(y), w, tol.abs * 10.0) {
                        format!(" — your normal has length {}: normalize it", n(l))
                    } else if tol.close3(y.map(|x| -x), w, tol.abs * 10.0) {
                        " — it points away from the ray: flip it when the ray meets the surface from behind (Q·n > 0)".to_string()
                    } else {
                        super::instancing::normal_hint(instance, y, tol).to_string()
                    };
                    return Some((
                        format!(
                            "{name}: your normal is {}, raystep's is {}{hint}",
                            v(y),
                            v(w)
                        ),
                        step,
                    ));
                }
            }
        }
    }
    None
}
