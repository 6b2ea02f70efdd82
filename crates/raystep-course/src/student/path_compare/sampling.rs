//! The stages that compare a sample's draws at each vertex: the BSDF's sampled direction and
//! its pdf, the light samples (point, pdf, blocked or not), and the bounce (BSDF value, cosine,
//! throughput, Russian roulette).

use super::*;

/// The BSDF's samples: the hemisphere, the direction, the pdf.
pub(super) fn bsdf_samples(es: &PathSample, ss: &PathSample, tol: &TracerTolerances) -> Divergence {
    let k = es.sample;
    for ev in &es.vertices {
        let d = ev.depth;
        let Some(eb) = &ev.sample else { continue };
        let sv = match vertex(ss, ev, k) {
            Ok(sv) => sv,
            Err(m) => return Some(m),
        };
        let Some(sb) = &sv.sample else {
            return Some((
                format!(
                    "{}: you printed no sample record (the BSDF's direction and pdf)",
                    place(k, d)
                ),
                k,
                eb.at,
            ));
        };
        let normal = ev.hit.clone().flatten().and_then(|h| h.normal);
        let (Some(want), Some(yours)) = (eb.direction, sb.direction) else {
            return Some((
                format!("{}: your sample has no direction", place(k, d)),
                k,
                eb.at,
            ));
        };
        let (want, yours) = (unit(want), unit(yours));
        if let Some(nn) = normal
            && dot(want, nn) > 1e-3
            && dot(yours, nn) < -1e-3
        {
            return Some((
                format!(
                    "{}: your sampled direction {} points into the surface (its cosine with the normal {} is {}): a reflected direction leaves on the side the ray came from — build the local frame around the normal that faces the ray, with the sampled z along it",
                    place(k, d),
                    v(yours),
                    v(nn),
                    n(dot(yours, nn))
                ),
                k,
                eb.at,
            ));
        }
        // A sampled direction carries the rounding of the hit point and normal it starts from.
        if !close3(tol, d, yours, want, tol.abs * 20.0) {
            return Some((
                format!(
                    "{}: your sampled direction (normalized) is {}, raystep's is {} — the cosine-weighted direction: the concentric disk map of (u0, u1), lifted to the hemisphere (z = √(1 − x² − y²)), in the frame around the normal (see the starter kit)",
                    place(k, d),
                    v(yours),
                    v(want)
                ),
                k,
                eb.at,
            ));
        }
        let Some(ep) = eb.pdf else { continue };
        let Some(sp) = sb.pdf else {
            return Some((format!("{}: your sample has no pdf", place(k, d)), k, eb.at));
        };
        match (ep, sp) {
            (None, None) => {}
            (None, Some(p)) => {
                return Some((
                    format!(
                        "{}: your pdf is {}, but a mirror's (or glass's) direction is a delta, not a density: print \"pdf\": null",
                        place(k, d),
                        n(p)
                    ),
                    k,
                    eb.at,
                ));
            }
            (Some(p), None) => {
                return Some((
                    format!(
                        "{}: your pdf is null, raystep's is {}: only a mirror's or glass's direction is a delta",
                        place(k, d),
                        n(p)
                    ),
                    k,
                    eb.at,
                ));
            }
            // cos θ / π: as close as the directions are.
            (Some(want), Some(yours)) if !close(&direction_tol(tol), d, yours, want) => {
                let cos = ev.bounce.as_ref().and_then(|b| b.cos).unwrap_or(0.0);
                let hint = if cos > 1e-3 && cos < 0.999 && close(tol, d, yours, want / cos) {
                    format!(
                        " — your pdf is missing the cosine: cosine-weighted sampling's density is cos θ / π (here {} / π), not 1/π",
                        n(cos)
                    )
                } else {
                    String::new()
                };
                return Some((
                    format!(
                        "{}: your pdf is {}, raystep's is {}{hint}",
                        place(k, d),
                        n(yours),
                        n(want)
                    ),
                    k,
                    eb.at,
                ));
            }
            _ => {}
        }
    }
    None
}

/// Next-event estimation: the light, the point, the pdf per steradian, blocked or not.
pub(super) fn light_samples(
    es: &PathSample,
    ss: &PathSample,
    tol: &TracerTolerances,
) -> Divergence {
    let k = es.sample;
    for ev in &es.vertices {
        let d = ev.depth;
        if ev.lights.is_empty() {
            continue;
        }
        let sv = match vertex(ss, ev, k) {
            Ok(sv) => sv,
            Err(m) => return Some(m),
        };
        for (i, el) in ev.lights.iter().enumerate() {
            let Some(sl) = sv.lights.get(i) else {
                return Some((
                    format!(
                        "{}: you printed no light-sample record (raystep samples light \"{}\" here)",
                        place(k, d),
                        el.light.as_deref().unwrap_or("?")
                    ),
                    k,
                    el.at,
                ));
            };
            if sl.light.is_none() {
                return Some((
                    format!(
                        "{}: your light sample names no light (\"light\": the light's name; raystep samples \"{}\" here)",
                        place(k, d),
                        el.light.as_deref().unwrap_or("?")
                    ),
                    k,
                    el.at,
                ));
            }
            if sl.light != el.light {
                return Some((
                    format!(
                        "{}: you sampled light \"{}\", raystep \"{}\" — the light is picked with probability proportional to its power (mean of Le × π × area) from the first number",
                        place(k, d),
                        sl.light.as_deref().unwrap_or("?"),
                        el.light.as_deref().unwrap_or("?")
                    ),
                    k,
                    el.at,
                ));
            }
            if let (Some(w), Some(y)) = (el.point, sl.point)
                && !close3(tol, d, y, w, tol.abs * len(w).max(1.0) * 10.0)
            {
                return Some((
                    format!(
                        "{}: your point on light \"{}\" is {}, raystep's is {}",
                        place(k, d),
                        el.light.as_deref().unwrap_or("?"),
                        v(y),
                        v(w)
                    ),
                    k,
                    el.at,
                ));
            }
            if sl.point.is_none() {
                return Some((
                    format!("{}: your light sample has no point", place(k, d)),
                    k,
                    el.at,
                ));
            }
            if let Some(want) = el.pdf.filter(|_| !el.grazing) {
                let Some(yours) = sl.pdf else {
                    return Some((
                        format!("{}: your light sample has no pdf", place(k, d)),
                        k,
                        el.at,
                    ));
                };
                // The density grows as 1 / cos θ_light: float32 rounding shows more in it.
                let loose = TracerTolerances {
                    rel: tol.rel * 5.0,
                    ..*tol
                };
                if !close(&loose, d, yours, want) {
                    let hint = match el.area_pdf {
                        Some(a) if close(tol, d, yours, a) => format!(
                            " — your pdf is per unit area of the light ({} = pick / area); the estimate integrates over directions, so convert it to solid angle: pdf_ω = pdf_A · d² / |cos θ_light| (d the distance, θ_light the angle at the light)",
                            n(a)
                        ),
                        _ => String::new(),
                    };
                    return Some((
                        format!(
                            "{}: your light sample's pdf is {}, raystep's is {}{hint}",
                            place(k, d),
                            n(yours),
                            n(want)
                        ),
                        k,
                        el.at,
                    ));
                }
            }
            if let Some(want) = el.blocked
                && sl.blocked != Some(want)
            {
                return Some((
                    format!(
                        "{}: your shadow ray to the light is {}, raystep's is {}{}",
                        place(k, d),
                        match sl.blocked {
                            Some(true) => "blocked",
                            Some(false) => "not blocked",
                            None => "not printed (\"blocked\")",
                        },
                        if want { "blocked" } else { "not blocked" },
                        if sl.blocked == Some(true) {
                            " — stop the shadow ray just short of the light's point (t < 1 − ε on the segment) and start it off the surface"
                        } else {
                            ""
                        }
                    ),
                    k,
                    el.at,
                ));
            }
        }
    }
    None
}

/// Each bounce's f, cos and throughput, and the roulette.
pub(super) fn bounces(es: &PathSample, ss: &PathSample, tol: &TracerTolerances) -> Divergence {
    let k = es.sample;
    // Roulette is judged on the student's own numbers at every depth (it starts after rr_depth
    // bounces, often deeper than the vertices compared with raystep's).
    for sv in &ss.vertices {
        let (Some(r), Some(b)) = (&sv.roulette, &sv.bounce) else {
            continue;
        };
        let (Some(q), Some(after), Some(before)) = (r.probability, r.throughput, b.throughput)
        else {
            continue;
        };
        let step = es
            .vertices
            .get(sv.depth as usize)
            .and_then(|v| v.roulette.as_ref().map(|r| r.at))
            .unwrap_or(0);
        let max = before.iter().copied().fold(f64::MIN, f64::max);
        if (q - max.min(1.0)).abs() > 1e-3 * (1.0 + q) {
            return Some((
                format!(
                    "{}: your roulette's probability of going on is {}, and your throughput's largest channel is {}: q = min(1, the throughput's largest channel)",
                    place(k, sv.depth),
                    n(q),
                    n(max)
                ),
                k,
                step,
            ));
        }
        if r.survived == Some(true)
            && q < 0.999
            && q > 0.0
            && dist(after, before) <= 1e-6 * (1.0 + len(before))
        {
            return Some((
                format!(
                    "{}: your roulette does not divide by its probability: the path goes on with probability q = {} and its throughput stays {}; it must become throughput / q = {}, or the paths roulette ends are missing from the average (the image comes out too dark)",
                    place(k, sv.depth),
                    n(q),
                    v(before),
                    v(before.map(|c| c / q))
                ),
                k,
                step,
            ));
        }
    }
    for ev in &es.vertices {
        let d = ev.depth;
        let Some(eb) = &ev.bounce else { continue };
        let sv = match vertex(ss, ev, k) {
            Ok(sv) => sv,
            Err(m) => return Some(m),
        };
        let Some(sb) = &sv.bounce else {
            return Some((
                format!(
                    "{}: you printed no bounce record (the BSDF's value, the cosine, the throughput)",
                    place(k, d)
                ),
                k,
                eb.at,
            ));
        };
        if let Some(w) = eb.bsdf {
            match sb.bsdf {
                None => {
                    return Some((
                        format!("{}: your bounce has no bsdf value", place(k, d)),
                        k,
                        eb.at,
                    ));
                }
                Some(y) if !close3(tol, d, y, w, tol.abs) => {
                    let hint = if close3(tol, d, y.map(|c| c / std::f64::consts::PI), w, tol.abs) {
                        " — a diffuse BSDF is albedo / π"
                    } else {
                        ""
                    };
                    return Some((
                        format!(
                            "{}: your BSDF value f is {}, raystep's is {}{hint}",
                            place(k, d),
                            v(y),
                            v(w)
                        ),
                        k,
                        eb.at,
                    ));
                }
                _ => {}
            }
        }
        if let Some(w) = eb.cos {
            match sb.cos {
                None => {
                    return Some((format!("{}: your bounce has no cos", place(k, d)), k, eb.at));
                }
                // A dot product of unit vectors: as close as the directions are.
                Some(y) if !close(&direction_tol(tol), d, y, w) => {
                    return Some((
                        format!(
                            "{}: your cosine is {}, raystep's is {} (|cos θ| of the new direction with the normal)",
                            place(k, d),
                            n(y),
                            n(w)
                        ),
                        k,
                        eb.at,
                    ));
                }
                _ => {}
            }
        }
        if let Some(w) = eb.throughput {
            match sb.throughput {
                None => {
                    return Some((
                        format!("{}: your bounce has no throughput", place(k, d)),
                        k,
                        eb.at,
                    ));
                }
                Some(y) if !close3(tol, d, y, w, tol.abs) => {
                    return Some((
                        format!(
                            "{}: your throughput after the bounce is {}, raystep's is {} (the throughput before it × f · cos / pdf)",
                            place(k, d),
                            v(y),
                            v(w)
                        ),
                        k,
                        eb.at,
                    ));
                }
                _ => {}
            }
        }
        let Some(er) = &ev.roulette else { continue };
        let Some(sr) = &sv.roulette else {
            return Some((
                format!(
                    "{}: you printed no roulette record (raystep plays Russian roulette after bounce {})",
                    place(k, d),
                    d
                ),
                k,
                er.at,
            ));
        };
        for (what, missing) in [
            (
                "probability",
                er.probability.is_some() && sr.probability.is_none(),
            ),
            ("survived", er.survived.is_some() && sr.survived.is_none()),
            (
                "throughput",
                er.throughput.is_some() && sr.throughput.is_none(),
            ),
        ] {
            if missing {
                return Some((
                    format!("{}: your roulette has no {what}", place(k, d)),
                    k,
                    er.at,
                ));
            }
        }
        if let (Some(w), Some(y)) = (er.probability, sr.probability)
            && !close(tol, d, y, w)
        {
            return Some((
                format!(
                    "{}: your roulette's probability of going on is {}, raystep's is {} (q = min(1, the throughput's largest channel))",
                    place(k, d),
                    n(y),
                    n(w)
                ),
                k,
                er.at,
            ));
        }
        if let Some(w) = er.survived
            && sr.survived != Some(w)
        {
            return Some((
                format!(
                    "{}: your path {} the roulette, raystep's {} (it goes on when u < q)",
                    place(k, d),
                    if sr.survived == Some(true) {
                        "survives"
                    } else {
                        "does not survive"
                    },
                    if w { "survives" } else { "does not" }
                ),
                k,
                er.at,
            ));
        }
        if let (Some(w), Some(y)) = (er.throughput, sr.throughput)
            && !close3(tol, d, y, w, tol.abs)
        {
            let before = eb.throughput.unwrap_or(w);
            let hint = if er.survived == Some(true)
                && er.probability.is_some_and(|q| q < 0.999)
                && close3(tol, d, y, before, tol.abs)
            {
                " — your roulette does not divide by its probability: a path that goes on with probability q must carry throughput / q, or the paths it ends are missing from the average (the image comes out too dark)"
            } else {
                ""
            };
            return Some((
                format!(
                    "{}: your throughput after the roulette is {}, raystep's is {}{hint}",
                    place(k, d),
                    v(y),
                    v(w)
                ),
                k,
                er.at,
            ));
        }
    }
    None
}
