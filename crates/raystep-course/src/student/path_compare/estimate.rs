//! The estimate stage: each sample's value. A value is compared with raystep's where the paths
//! agree to its end; everywhere the light samples' contributions and the emission counted at the
//! vertices compared are raystep's; and every sample's value must be the sum of the student's own
//! contributions along the path — so a value is never taken on trust where raystep's path went
//! elsewhere.

use super::*;

fn missing_value(k: u32) -> (String, u32, usize) {
    (
        format!(
            "sample {k}: you printed no value: end each path with {{\"type\":\"value\",\"rgb\":[r, g, b]}}"
        ),
        k,
        0,
    )
}

fn add(a: &mut [f64; 3], b: [f64; 3]) {
    for i in 0..3 {
        a[i] += b[i];
    }
}

/// Sample `full`'s value (raystep's whole path), against the student's `ss`: `es` is raystep's
/// path cut to the vertices compared; `unparted`: the student's path hits what raystep's does
/// all the way.
pub(super) fn estimate(
    e: &PathExpected,
    full: &PathSample,
    es: &PathSample,
    ss: &PathSample,
    unparted: bool,
    tol: &TracerTolerances,
) -> Divergence {
    let k = full.sample;
    let Some(y) = ss.value else {
        return Some(missing_value(k));
    };
    // What the vertices compared add: each light sample's contribution and the emission.
    for ev in &es.vertices {
        let d = ev.depth;
        let sv = match vertex(ss, ev, k) {
            Ok(sv) => sv,
            Err(m) => return Some(m),
        };
        for (i, el) in ev.lights.iter().enumerate() {
            let Some(want) = el.contribution.filter(|_| !el.grazing) else {
                continue;
            };
            let Some(sl) = sv.lights.get(i) else {
                return Some((
                    format!("{}: you printed no light-sample record", place(k, d)),
                    k,
                    el.at,
                ));
            };
            let Some(yours) = sl.contribution else {
                return Some((
                    format!(
                        "{}: your light sample has no contribution (what it adds to the sample: throughput · f · Le · cos · w / pdf)",
                        place(k, d)
                    ),
                    k,
                    el.at,
                ));
            };
            if !close3(tol, d, yours, want, tol.color) {
                return Some((
                    format!(
                        "{}: your light sample's contribution is {}, raystep's is {} (throughput · f · Le · cos · w / pdf)",
                        place(k, d),
                        v(yours),
                        v(want)
                    ),
                    k,
                    el.at,
                ));
            }
        }
        if let Some(ee) = &ev.emission {
            let w = ee.mis_weight.unwrap_or(1.0);
            let want = ee.radiance.unwrap_or([0.0; 3]).map(|c| c * w);
            let yours = sv
                .emission
                .as_ref()
                .and_then(|se| Some(se.radiance?.map(|c| c * se.mis_weight.unwrap_or(1.0))));
            match yours {
                None if want.iter().any(|c| *c != 0.0) => {
                    return Some((
                        format!(
                            "{}: you count no emission here (an `emission` record with its radiance), and raystep counts {} (Le × its weight)",
                            place(k, d),
                            v(want)
                        ),
                        k,
                        ee.at,
                    ));
                }
                Some(yours) if !close3(tol, d, yours, want, tol.color) => {
                    return Some((
                        format!(
                            "{}: the emission you count here (Le × its weight) is {}, raystep's is {}",
                            place(k, d),
                            v(yours),
                            v(want)
                        ),
                        k,
                        ee.at,
                    ));
                }
                _ => {}
            }
        }
    }
    // The value itself, where the two paths agree to their ends (a path deeper than one past the
    // vertices compared carries the rounding of its deep bounces: there the sum below judges it).
    let depth = full.vertices.len().saturating_sub(1) as u32;
    if unparted
        && depth <= MAX_CHECKED_DEPTH + 1
        && let Some(want) = full.value
        && !close3(tol, depth, y, want, tol.color)
    {
        return Some((
            format!(
                "sample {k}: your value is {}, raystep's is {} (the sum of the emission and light samples along the path, each times its throughput and weight)",
                v(y),
                v(want)
            ),
            k,
            0,
        ));
    }
    // The value is the sum of the student's own path: its emission (times the throughput that
    // reaches it and its weight), its light samples' contributions, the background an escaped ray
    // brings back.
    let mut sum = [0.0; 3];
    let mut t = [1.0; 3];
    let n = ss.vertices.len();
    for (i, sv) in ss.vertices.iter().enumerate() {
        let d = sv.depth;
        if let Some(se) = &sv.emission {
            let Some(r) = se.radiance else {
                return Some((
                    format!("{}: your emission has no radiance", place(k, d)),
                    k,
                    ev_at(full, d),
                ));
            };
            let w = se.mis_weight.unwrap_or(1.0);
            add(&mut sum, std::array::from_fn(|c| t[c] * r[c] * w));
        }
        if sv.hit == Some(None) {
            add(&mut sum, std::array::from_fn(|c| t[c] * e.background[c]));
        }
        for l in &sv.lights {
            let Some(c) = l.contribution else {
                return Some((
                    format!(
                        "{}: your light sample has no contribution (what it adds to the sample: throughput · f · Le · cos · w / pdf)",
                        place(k, d)
                    ),
                    k,
                    ev_at(full, d),
                ));
            };
            add(&mut sum, c);
        }
        if i + 1 < n {
            let next = sv
                .roulette
                .as_ref()
                .and_then(|r| r.throughput)
                .or_else(|| sv.bounce.as_ref().and_then(|b| b.throughput));
            let Some(next) = next else {
                return Some((
                    format!(
                        "{}: your path goes on without a throughput (a `bounce` record's \"throughput\"): its value cannot be followed",
                        place(k, d)
                    ),
                    k,
                    ev_at(full, d),
                ));
            };
            t = next;
        }
    }
    if !close3(tol, n as u32, y, sum, tol.color) {
        return Some((
            format!(
                "sample {k}: your value is {}, and your path's own records add up to {} (each emission times the throughput that reaches it and its weight, plus each light sample's contribution): a sample's value is that sum",
                v(y),
                v(sum)
            ),
            k,
            0,
        ));
    }
    None
}

/// raystep's timeline step of vertex `d` of a sample (0 past its path).
fn ev_at(full: &PathSample, d: u32) -> usize {
    full.vertices.get(d as usize).map_or(0, |v| v.at)
}
