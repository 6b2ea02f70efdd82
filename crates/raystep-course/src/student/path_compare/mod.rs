//! A student's path tracer against raystep's, sample by sample (format version 2): the same
//! random numbers make the same paths, so every number of every sample can be compared, and the
//! classic mistakes named — a cosine-weighted pdf without its cosine, a light sample's pdf left
//! per unit area, MIS weights that do not sum to one, emission counted twice after next-event
//! estimation, Russian roulette that does not divide by its probability, a direction sampled
//! into the surface.

use super::compare::{Check, TracerTolerances};
use super::path::{Draw, MAX_CHECKED_DEPTH, PathExpected, PathPixel, PathSample, Vertex};
use super::stage::Stage;
use crate::trace::monte_carlo::power_heuristic;

mod estimate;
mod sampling;
use estimate::estimate;
use sampling::{bounces, bsdf_samples, light_samples};

/// The verdict of one stage for one pixel, and the sample raystep's numbers are in.
#[derive(Debug, Clone, PartialEq)]
pub struct PathCheck {
    /// The verdict; its `step` is a step of sample `sample`'s trace.
    pub check: Check,
    /// The sample whose trace shows the right numbers.
    pub sample: Option<u32>,
}

/// (message, sample, step)
type Divergence = Option<(String, u32, usize)>;

fn n(x: f64) -> String {
    crate::record::number::fmt64(x, crate::record::number::Style::Label)
}
fn v(x: [f64; 3]) -> String {
    format!("({}, {}, {})", n(x[0]), n(x[1]), n(x[2]))
}
fn len(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}
fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = len(v);
    if l > 0.0 { v.map(|x| x / l) } else { v }
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    len([a[0] - b[0], a[1] - b[1], a[2] - b[2]])
}

/// Where in the pixel a record is, in words: "sample 3, bounce 1".
fn place(k: u32, d: u32) -> String {
    if d == 0 {
        format!("sample {k}, the camera ray's hit")
    } else {
        format!("sample {k}, bounce {d}")
    }
}

/// Tolerances for a vertex `d` deep (rounding compounds along a path).
fn tol_at(t: &TracerTolerances, d: u32) -> (f64, f64) {
    let k = 1.0 + d.min(64) as f64;
    (t.abs * k, t.rel * k)
}
fn close(t: &TracerTolerances, d: u32, yours: f64, want: f64) -> bool {
    let (a, r) = tol_at(t, d);
    (yours - want).abs() <= a + r * want.abs()
}
fn close3(t: &TracerTolerances, d: u32, yours: [f64; 3], want: [f64; 3], abs: f64) -> bool {
    let (a, r) = tol_at(t, d);
    dist(yours, want) <= abs.max(a) + r * len(want)
}

/// The tolerance of numbers made from a direction (a cosine, a cosine-weighted pdf): the
/// absolute part of directions' (10 × abs).
fn direction_tol(t: &TracerTolerances) -> TracerTolerances {
    TracerTolerances {
        abs: t.abs * 10.0,
        ..*t
    }
}

/// Grades one pixel's samples, a check per stage of `stages`.
pub fn grade(
    e: &PathExpected,
    student: &[PathPixel],
    stages: &[Stage],
    tol: &TracerTolerances,
) -> Vec<PathCheck> {
    let at = e.pixel.at;
    let mine = student
        .iter()
        .find(|p| p.at.is_some() && p.at == at)
        .or_else(|| (student.len() == 1).then(|| &student[0]));
    stages
        .iter()
        .map(|&stage| {
            let found = match mine {
                None => Some((
                    format!(
                        "no records for pixel {}: print a `pixel` record, then each sample's `path`",
                        at.map_or("?".into(), |[x, y]| format!("({x}, {y})"))
                    ),
                    0,
                    0,
                )),
                Some(s) => stage_check(e, s, stage, tol),
            };
            match found {
                None => PathCheck {
                    check: Check {
                        stage,
                        pass: true,
                        message: String::new(),
                        step: None,
                    },
                    sample: None,
                },
                Some((message, k, step)) => PathCheck {
                    check: Check {
                        stage,
                        pass: false,
                        message,
                        step: Some(step),
                    },
                    sample: Some(k),
                },
            }
        })
        .collect()
}

fn stage_check(
    e: &PathExpected,
    s: &PathPixel,
    stage: Stage,
    tol: &TracerTolerances,
) -> Divergence {
    if stage == Stage::Mis
        && let Some(d) = mis_sums(e, s, tol)
    {
        return Some(d);
    }
    for full in &e.pixel.samples {
        let k = full.sample;
        // The vertices compared: up to MAX_CHECKED_DEPTH (the value is the whole path's).
        let cut = PathSample {
            vertices: full
                .vertices
                .iter()
                .filter(|v| v.depth <= MAX_CHECKED_DEPTH)
                .cloned()
                .collect(),
            ..full.clone()
        };
        let Some(ss) = s.samples.iter().find(|p| p.sample == k) else {
            return Some((
                format!(
                    "you printed no path for sample {k}: print {{\"type\":\"path\",\"sample\":{k}}} and its records for each of the pixel's first {} samples",
                    e.pixel.samples.len()
                ),
                k,
                0,
            ));
        };
        // Past a bounce whose ray hits another object than raystep's (a ray grazing an edge,
        // decided by rounding), the vertices are about different points: only the path stage
        // judges them (and says where the paths part).
        let parted = parted_at(&cut, ss);
        let mut cut = cut;
        if stage != Stage::Path {
            cut.vertices.retain(|v| v.depth < parted);
        }
        let es = &cut;
        // Every stage judges the records of raystep's vertices: a stage passes only on what it
        // compared, so a path the student left out (or printed without its rays) fails every
        // stage, not only the path stage (which says why in its own words).
        if stage != Stage::Path {
            for ev in &es.vertices {
                if let Err(m) = vertex(ss, ev, k) {
                    return Some(m);
                }
            }
        }
        let found = match stage {
            Stage::Random => random(e, es, ss),
            Stage::Path => path(e, es, ss, tol),
            Stage::BsdfSample => bsdf_samples(es, ss, tol),
            Stage::LightSample => light_samples(es, ss, tol),
            Stage::Bounce => bounces(es, ss, tol),
            Stage::Mis => mis(es, ss, tol),
            Stage::Estimate => estimate(e, full, es, ss, parted == u32::MAX, tol),
            _ => None,
        };
        if found.is_some() {
            return found;
        }
    }
    None
}

/// The first bounce (depth ≥ 1) whose ray hits another object in the student's path than in
/// raystep's (u32::MAX: none). The camera ray's hit is never excused.
fn parted_at(es: &PathSample, ss: &PathSample) -> u32 {
    for ev in es.vertices.iter().filter(|v| v.depth >= 1) {
        let Some(sv) = ss.vertices.get(ev.depth as usize) else {
            break;
        };
        let (Some(eh), Some(sh)) = (&ev.hit, &sv.hit) else {
            continue;
        };
        let differs = match (eh, sh) {
            (None, None) => false,
            (Some(a), Some(b)) => b.object.is_some() && a.object != b.object && !same_place(a, b),
            _ => true,
        };
        if differs {
            return ev.depth;
        }
    }
    u32::MAX
}

/// Two hits of different objects at the same point with the same normal: a ray through the
/// edge two triangles of one surface share, where rounding picks either.
fn same_place(a: &super::path::PathHit, b: &super::path::PathHit) -> bool {
    match (a.point, b.point, a.normal, b.normal) {
        (Some(p), Some(q), Some(m), Some(n)) => {
            dist(p, q) <= 1e-3 * len(p).max(1.0) && dot(unit(m), unit(n)) > 0.9999
        }
        _ => false,
    }
}

/// The student's vertex `d` of a path, or the message that it is missing.
fn vertex<'a>(ss: &'a PathSample, ev: &Vertex, k: u32) -> Result<&'a Vertex, (String, u32, usize)> {
    ss.vertices.get(ev.depth as usize).ok_or_else(|| {
        (
            format!(
                "sample {k}: your path has {} ray{}, raystep's has a ray of depth {} (print a `ray` record for the camera ray and each bounce)",
                ss.vertices.len(),
                if ss.vertices.len() == 1 { "" } else { "s" },
                ev.depth
            ),
            k,
            ev.at,
        )
    })
}

/// The random numbers: raystep's dimensions, and each number the hash's.
fn random(e: &PathExpected, es: &PathSample, ss: &PathSample) -> Divergence {
    let k = es.sample;
    let px = e.pixel.at.unwrap_or([0, 0]);
    let hash = |d: u32| f64::from(crate::portable::random::uniform(px, k, d, e.seed));
    let check = |what: &str, d: u32, want: &[Draw], yours: &[Draw], at: usize| -> Divergence {
        if want.is_empty() {
            return None;
        }
        if yours.is_empty() {
            return Some((
                format!(
                    "{}: your {what} prints no random numbers: give it \"random\": [{{\"dimension\": D, \"value\": u}}, …] (raystep draws dimension{} {} here)",
                    place(k, d),
                    if want.len() == 1 { "" } else { "s" },
                    want.iter()
                        .map(|w| w.dimension.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                k,
                at,
            ));
        }
        for (i, w) in want.iter().enumerate() {
            let Some(y) = yours.get(i) else {
                return Some((
                    format!(
                        "{}: your {what} draws {} number{}, raystep's {} (dimension {} is missing)",
                        place(k, d),
                        yours.len(),
                        if yours.len() == 1 { "" } else { "s" },
                        want.len(),
                        w.dimension
                    ),
                    k,
                    at,
                ));
            };
            if y.dimension != w.dimension {
                return Some((
                    format!(
                        "{}: your {what} draws dimension {}, raystep draws {} — bounce b takes the dimensions from 16 + 1024·b: slot 0 picks the light, 1 and 2 the point on it, 4 and 5 the BSDF's direction, 6 Russian roulette",
                        place(k, d),
                        y.dimension,
                        w.dimension
                    ),
                    k,
                    at,
                ));
            }
            // The hash's number, bit for bit (a stratified sampler moves it: then raystep's).
            let exact = if e.stratified {
                w.value
            } else {
                hash(w.dimension)
            };
            let ok = if e.stratified {
                (y.value - exact).abs() <= 1e-6
            } else {
                y.value == exact
            };
            if !ok {
                return Some((
                    format!(
                        "{}: your {what}'s number for dimension {} is {}, raystep's uniform(({}, {}), {k}, {}, {}) is {} — compute it with the starter kit's uniform(); if your tracer draws its own random numbers, grade it with --statistical instead",
                        place(k, d),
                        w.dimension,
                        y.value,
                        px[0],
                        px[1],
                        w.dimension,
                        e.seed,
                        exact
                    ),
                    k,
                    at,
                ));
            }
        }
        None
    };
    for ev in &es.vertices {
        let d = ev.depth;
        let sv = match vertex(ss, ev, k) {
            Ok(sv) => sv,
            Err(m) => return Some(m),
        };
        for (i, el) in ev.lights.iter().enumerate() {
            let yours = sv.lights.get(i).map_or(&[][..], |l| &l.random[..]);
            if sv.lights.get(i).is_none() {
                return Some((
                    format!(
                        "{}: you printed no light-sample record (raystep samples light \"{}\" here)",
                        place(k, d),
                        el.light.as_deref().unwrap_or("?")
                    ),
                    k,
                    el.at,
                ));
            }
            if let Some(x) = check("light sample", d, &el.random, yours, el.at) {
                return Some(x);
            }
        }
        if let Some(eb) = &ev.sample {
            let Some(sb) = &sv.sample else {
                return Some((
                    format!(
                        "{}: you printed no sample record (the BSDF's direction)",
                        place(k, d)
                    ),
                    k,
                    eb.at,
                ));
            };
            if let Some(x) = check("BSDF sample", d, &eb.random, &sb.random, eb.at) {
                return Some(x);
            }
        }
        if let Some(er) = &ev.roulette
            && let Some(w) = er.random
        {
            let Some(sr) = &sv.roulette else {
                return Some((
                    format!(
                        "{}: you printed no roulette record (raystep plays Russian roulette after this bounce)",
                        place(k, d)
                    ),
                    k,
                    er.at,
                ));
            };
            let yours: Vec<Draw> = sr.random.into_iter().collect();
            if let Some(x) = check("roulette", d, &[w], &yours, er.at) {
                return Some(x);
            }
        }
    }
    None
}

/// The camera ray, every hit, the path's length.
fn path(e: &PathExpected, es: &PathSample, ss: &PathSample, tol: &TracerTolerances) -> Divergence {
    let k = es.sample;
    for ev in &es.vertices {
        let d = ev.depth;
        let sv = match vertex(ss, ev, k) {
            Ok(sv) => sv,
            Err(mut m) => {
                // Name why, when the student's own path says it.
                if let Some(last) = ss.vertices.last() {
                    if last.roulette.and_survived() == Some(false) {
                        m.0 += " — your roulette ended the path there (see the bounce stage)";
                    } else if last.hit == Some(None) {
                        m.0 += " — your ray escaped there";
                    }
                }
                return Some(m);
            }
        };
        if d == 0 {
            if let (Some(o), Some(eo)) = (sv.origin, ev.origin)
                && !close3(tol, 0, o, eo, tol.abs * len(eo).max(1.0))
            {
                return Some((
                    format!(
                        "sample {k}: your camera ray's origin is {}, raystep's is {}",
                        v(o),
                        v(eo)
                    ),
                    k,
                    ev.at,
                ));
            }
            if let (Some(dd), Some(ed)) = (sv.direction, ev.direction)
                && !close3(tol, 0, unit(dd), unit(ed), tol.abs * 10.0)
            {
                return Some((
                    format!(
                        "sample {k}: your camera ray's direction (normalized) is {}, raystep's is {} — sample k of a pixel is jittered in its own cell of a grid of ⌈√spp⌉ columns, every cell of area 1/spp (see the starter kit's README)",
                        v(unit(dd)),
                        v(unit(ed))
                    ),
                    k,
                    ev.at,
                ));
            }
            if sv.direction.is_none() {
                return Some((
                    format!("sample {k}: your camera ray has no direction"),
                    k,
                    ev.at,
                ));
            }
        }
        let Some(eh) = &ev.hit else { continue };
        let Some(sh) = &sv.hit else {
            return Some((
                format!("{}: you printed no hit record for this ray", place(k, d)),
                k,
                ev.at,
            ));
        };
        match (eh, sh) {
            (None, None) => {}
            (None, Some(h)) => {
                return Some((
                    format!(
                        "{}: your ray hits \"{}\", raystep's escapes",
                        place(k, d),
                        h.object.as_deref().unwrap_or("?")
                    ),
                    k,
                    ev.at,
                ));
            }
            (Some(h), None) => {
                return Some((
                    format!(
                        "{}: your ray escapes, raystep's hits \"{}\"",
                        place(k, d),
                        h.object.as_deref().unwrap_or("?")
                    ),
                    k,
                    ev.at,
                ));
            }
            (Some(eh), Some(sh)) => {
                if sh.object.is_some() && sh.object != eh.object && !same_place(eh, sh) {
                    let unknown = sh
                        .object
                        .as_ref()
                        .is_some_and(|o| !e.names.is_empty() && !e.names.contains(o));
                    return Some((
                        format!(
                            "{}: your ray hits \"{}\", raystep's hits \"{}\"{}",
                            place(k, d),
                            sh.object.as_deref().unwrap_or("?"),
                            eh.object.as_deref().unwrap_or("?"),
                            if unknown {
                                " (the scene has no object of that name: print the names of the scene file)"
                            } else {
                                ""
                            }
                        ),
                        k,
                        ev.at,
                    ));
                }
                for (what, y, w) in [
                    ("point", sh.point, eh.point),
                    ("normal", sh.normal, eh.normal),
                ] {
                    let (Some(y), Some(w)) = (y, w) else {
                        if y.is_none() && w.is_some() {
                            return Some((
                                format!("{}: your hit has no {what}", place(k, d)),
                                k,
                                ev.at,
                            ));
                        }
                        continue;
                    };
                    let abs = if what == "point" {
                        tol.abs * len(w).max(1.0) * 10.0
                    } else {
                        tol.abs * 10.0
                    };
                    if !close3(tol, d, y, w, abs) {
                        let hint = if what == "normal" && close3(tol, d, y.map(|c| -c), w, abs) {
                            " — it faces away from the ray: flip it towards the ray"
                        } else {
                            ""
                        };
                        return Some((
                            format!(
                                "{}: your {what} is {}, raystep's is {}{hint}",
                                place(k, d),
                                v(y),
                                v(w)
                            ),
                            k,
                            ev.at,
                        ));
                    }
                }
            }
        }
    }
    if ss.vertices.len() > es.vertices.len()
        && es
            .vertices
            .last()
            .is_some_and(|l| l.depth < MAX_CHECKED_DEPTH)
    {
        let last = es.vertices.last();
        let why = match last {
            Some(l) if l.roulette.and_survived() == Some(false) => {
                " — raystep's roulette ends it there"
            }
            Some(l) if l.hit == Some(None) => " — raystep's ray escapes there",
            Some(l) if l.sample.is_none() => {
                " — raystep's path stops there: max_depth bounces at most"
            }
            _ => "",
        };
        return Some((
            format!(
                "sample {k}: your path has {} rays, raystep's {}{why}",
                ss.vertices.len(),
                es.vertices.len()
            ),
            k,
            last.map_or(0, |l| l.at),
        ));
    }
    None
}

trait Survived {
    fn and_survived(&self) -> Option<bool>;
}
impl Survived for Option<super::path::Roulette> {
    fn and_survived(&self) -> Option<bool> {
        self.as_ref().and_then(|r| r.survived)
    }
}

/// Which heuristic a student's light-sample weights follow, found from their own numbers.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Heuristic {
    Power,
    Balance,
    One,
}

impl Heuristic {
    fn weight(self, a: f64, b: f64) -> f64 {
        match self {
            Heuristic::Power => power_heuristic(a as f32, b as f32) as f64,
            Heuristic::Balance => {
                if a + b > 0.0 {
                    a / (a + b)
                } else {
                    0.0
                }
            }
            Heuristic::One => 1.0,
        }
    }
    fn name(self) -> &'static str {
        match self {
            Heuristic::Power => "the power heuristic",
            Heuristic::Balance => "the balance heuristic",
            Heuristic::One => "weight 1 (no MIS)",
        }
    }
}

/// The heuristic every one of the student's light-sample weights (with both pdfs printed)
/// follows, if one does.
fn light_heuristic(s: &PathPixel) -> Option<Heuristic> {
    let ws: Vec<(f64, f64, f64)> = s
        .samples
        .iter()
        .flat_map(|p| p.vertices.iter())
        .flat_map(|v| v.lights.iter())
        .filter_map(|l| Some((l.pdf?, l.bsdf_pdf?, l.mis_weight?)))
        .filter(|(p, _, _)| *p > 0.0)
        .collect();
    if ws.is_empty() {
        return None;
    }
    // Exactly 1 everywhere is no MIS (the power heuristic comes close to 1 when the light's
    // density dwarfs the BSDF's, but not to 1 itself).
    if ws.iter().all(|(_, _, w)| (*w - 1.0).abs() <= 1e-9) {
        return Some(Heuristic::One);
    }
    [Heuristic::Power, Heuristic::Balance]
        .into_iter()
        .find(|h| {
            ws.iter()
                .all(|(a, b, w)| (h.weight(*a, *b) - w).abs() <= 2e-3)
        })
}

/// Emission found by a BSDF sample, against the student's own light-sample weights: the two
/// strategies' weights of one direction must sum to one, and emission the light samples
/// already counted must not be counted again in full.
fn mis_sums(e: &PathExpected, s: &PathPixel, tol: &TracerTolerances) -> Divergence {
    let h = light_heuristic(s);
    for es in &e.pixel.samples {
        let k = es.sample;
        let Some(ss) = s.samples.iter().find(|p| p.sample == k) else {
            continue;
        };
        let parted = parted_at(es, ss);
        for ev in es
            .vertices
            .iter()
            .filter(|v| v.depth > 0 && v.depth <= MAX_CHECKED_DEPTH && v.depth < parted)
        {
            let d = ev.depth;
            let Some(sv) = ss.vertices.get(d as usize) else {
                continue;
            };
            let Some(ee) = &ev.emission else { continue };
            let want = ee.mis_weight.unwrap_or(1.0);
            // Light sampling could have found this point (raystep weighs it below 1).
            if want >= 1.0 - 1e-6 {
                continue;
            }
            let Some(se) = &sv.emission else { continue };
            let yours = se.mis_weight.unwrap_or(1.0);
            if close(tol, d, yours, want) {
                continue;
            }
            let lp = se.light_pdf.or(ee.light_pdf).unwrap_or(0.0);
            let bp = se.bsdf_pdf.or(ee.bsdf_pdf).unwrap_or(0.0);
            if yours >= 1.0 - 1e-6 && matches!(h, None | Some(Heuristic::One)) {
                return Some((
                    format!(
                        "{}: emission counted twice — this light could be sampled by next-event estimation at the previous hit, which already counted it, and your path adds its emission again with weight 1; raystep weighs it {} by MIS. Either weigh both strategies by MIS, or with next-event estimation alone count emission only from the camera and after a mirror or glass bounce",
                        place(k, d),
                        n(want)
                    ),
                    k,
                    ee.at,
                ));
            }
            if let Some(h) = h.filter(|h| *h != Heuristic::One) {
                let other = h.weight(lp, bp);
                if (yours + other - 1.0).abs() > 1e-3 {
                    return Some((
                        format!(
                            "{}: MIS weights that do not sum to one — your weight of this emission (the BSDF sample's) is {}, and your light samples' weight for the same direction would be {} ({} of light pdf {} and BSDF pdf {}): the two must sum to 1, so use the same heuristic for both (raystep's power heuristic gives the BSDF sample {})",
                            place(k, d),
                            n(yours),
                            n(other),
                            h.name(),
                            n(lp),
                            n(bp),
                            n(want)
                        ),
                        k,
                        ee.at,
                    ));
                }
            }
        }
    }
    None
}

/// The weights themselves, against raystep's.
fn mis(es: &PathSample, ss: &PathSample, tol: &TracerTolerances) -> Divergence {
    let k = es.sample;
    for ev in &es.vertices {
        let d = ev.depth;
        let Some(sv) = ss.vertices.get(d as usize) else {
            return vertex(ss, ev, k).err();
        };
        for (i, el) in ev.lights.iter().enumerate() {
            let Some(want) = el.mis_weight.filter(|_| !el.grazing) else {
                continue;
            };
            let Some(sl) = sv.lights.get(i) else {
                return Some((
                    format!("{}: you printed no light-sample record", place(k, d)),
                    k,
                    el.at,
                ));
            };
            let Some(yours) = sl.mis_weight else {
                return Some((
                    format!("{}: your light sample has no mis_weight", place(k, d)),
                    k,
                    el.at,
                ));
            };
            if !close(tol, d, yours, want) {
                return Some((
                    format!(
                        "{}: your light sample's MIS weight is {}, raystep's is {} — the power heuristic: w = p_light² / (p_light² + p_bsdf²), both densities per steradian (here {} and {})",
                        place(k, d),
                        n(yours),
                        n(want),
                        n(el.pdf.unwrap_or(0.0)),
                        n(el.bsdf_pdf.unwrap_or(0.0))
                    ),
                    k,
                    el.at,
                ));
            }
        }
        match (&ev.emission, &sv.emission) {
            (None, None) => {}
            (Some(ee), None) => {
                if ee.mis_weight.unwrap_or(1.0) > 0.0 {
                    return Some((
                        format!(
                            "{}: you printed no emission record, and raystep counts \"{}\"'s emission here with weight {}",
                            place(k, d),
                            ev.hit
                                .clone()
                                .flatten()
                                .and_then(|h| h.object)
                                .unwrap_or_default(),
                            n(ee.mis_weight.unwrap_or(1.0))
                        ),
                        k,
                        ee.at,
                    ));
                }
            }
            (None, Some(se)) => {
                return Some((
                    format!(
                        "{}: you count emission here, and the surface raystep's ray hits does not emit",
                        place(k, d)
                    ),
                    k,
                    se.at.min(ev.at),
                ));
            }
            (Some(ee), Some(se)) => {
                let want = ee.mis_weight.unwrap_or(1.0);
                let yours = se.mis_weight.unwrap_or(1.0);
                if !close(tol, d, yours, want) {
                    let hint = if want == 0.0 && yours > 0.0 {
                        " — emission counted twice: next-event estimation alone already counted this light at the previous hit, so a BSDF-sampled ray that finds it adds nothing"
                    } else if want < 1.0 && yours >= 1.0 - 1e-6 && d > 0 {
                        " — emission counted twice: the light samples at the previous hit already counted this light"
                    } else {
                        ""
                    };
                    return Some((
                        format!(
                            "{}: your emission's weight is {}, raystep's is {}{hint}",
                            place(k, d),
                            n(yours),
                            n(want)
                        ),
                        k,
                        ee.at,
                    ));
                }
            }
        }
    }
    None
}
