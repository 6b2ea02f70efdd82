//! Lining a student's trace up with raystep's and saying, in words, where it first differs.

use super::expected::Expected;
use super::format::{Pixel, Ray, Test};
use super::stage::in_scope;
pub use super::stage::{Stage, ray_name};
use crate::record::Tolerance;
use serde::{Deserialize, Serialize};

/// How close a student's numbers must be (a grading sheet's `[tolerance]` table). Numbers —
/// distances, roots, coefficients, positions, directions — follow [`Tolerance`]'s
/// [`abs_plus_rel`](Tolerance::abs_plus_rel) rule, |yours − raystep's| ≤ abs + rel·|raystep's|
/// ([`TracerTolerances::numbers`]), on values scaled to a unit-length direction. Colour channels
/// must be within `color`, spawned rays' origins within `offset` (a student's own offset off the
/// surface is allowed).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TracerTolerances {
    /// Relative.
    pub rel: f64,
    /// Absolute.
    pub abs: f64,
    /// Absolute, for colour channels.
    pub color: f64,
    /// Absolute, for the origins of shadow, reflection and refraction rays.
    pub offset: f64,
}

impl Default for TracerTolerances {
    /// Loose enough for a student's f32 arithmetic (rounding differs in the 7th digit), tight
    /// enough to catch any formula mistake.
    fn default() -> Self {
        TracerTolerances {
            rel: 1e-3,
            abs: 1e-4,
            color: 4e-3,
            offset: 2e-2,
        }
    }
}

/// The verdict of one stage for one pixel.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Check {
    /// The stage.
    pub stage: Stage,
    /// Passed?
    pub pass: bool,
    /// The first divergence in words (empty when passed), with the common mistake named when it
    /// is recognised.
    pub message: String,
    /// The timeline step of raystep's trace that shows the right numbers.
    pub step: Option<usize>,
}

pub(super) fn len(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}
pub(super) fn unit(v: [f64; 3]) -> [f64; 3] {
    let l = len(v);
    if l > 0.0 { v.map(|x| x / l) } else { v }
}
pub(super) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub(super) fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    len([a[0] - b[0], a[1] - b[1], a[2] - b[2]])
}

/// "your b is −4.1, raystep's is −8.2" and a hint naming the likely mistake.
fn yours_vs(name: &str, yours: f64, want: f64, hint: &str) -> String {
    format!(
        "your {name} is {}, raystep's is {}{hint}",
        n(yours),
        n(want)
    )
}

/// A number as feedback shows it.
pub(super) fn n(x: f64) -> String {
    crate::record::number::fmt64(x, crate::record::number::Style::Label)
}
pub(super) fn v(x: [f64; 3]) -> String {
    format!("({}, {}, {})", n(x[0]), n(x[1]), n(x[2]))
}

impl TracerTolerances {
    /// The tolerances for a ray `depth` bounces deep: rounding differences compound at every
    /// bounce (raystep computes in f32), so the relative and absolute parts grow by one unit per
    /// level (a depth-4 reflection's t may differ by 0.5 %).
    pub fn at_depth(&self, depth: u32) -> TracerTolerances {
        let k = 1.0 + depth.min(64) as f64;
        TracerTolerances {
            rel: self.rel * k,
            abs: self.abs * k,
            ..*self
        }
    }

    /// The rule for numbers: |yours − raystep's| ≤ abs + rel·|raystep's|.
    pub fn numbers(&self) -> Tolerance {
        Tolerance::abs_plus_rel(self.abs, self.rel)
    }

    pub(super) fn close(&self, yours: f64, want: f64) -> bool {
        self.numbers().allows(yours, want)
    }
    /// Vectors: |yours − want| ≤ abs + rel·|want| with the absolute part given.
    pub(super) fn close3(&self, yours: [f64; 3], want: [f64; 3], abs: f64) -> bool {
        self.numbers()
            .with_abs(abs)
            .allows_distance(dist(yours, want), len(want))
    }
}

/// Which student ray answers each of raystep's (None: the student has no such ray). The
/// primary ray is the student's first primary ray; a child is the student's ray of the same kind
/// under the matched parent (for shadow rays, towards the same light if named), nearest in
/// direction.
pub fn match_rays(e: &Pixel, s: &Pixel) -> Vec<Option<usize>> {
    let mut m: Vec<Option<usize>> = vec![None; e.rays.len()];
    let mut used = vec![false; s.rays.len()];
    if let Some(first) = s.rays.iter().position(|r| r.kind == "primary")
        && !m.is_empty()
    {
        m[0] = Some(first);
        used[first] = true;
    }
    for i in 1..e.rays.len() {
        let er = &e.rays[i];
        let Some(sp) = er.parent.and_then(|p| m.get(p).copied().flatten()) else {
            continue;
        };
        let cands: Vec<usize> = (0..s.rays.len())
            .filter(|&k| !used[k] && s.rays[k].parent == Some(sp) && s.rays[k].kind == er.kind)
            .collect();
        let named: Vec<usize> = cands
            .iter()
            .copied()
            .filter(|&k| er.light.is_some() && s.rays[k].light == er.light)
            .collect();
        let pool = if named.is_empty() { cands } else { named };
        let ed = er.direction.map(unit);
        let best = pool.into_iter().min_by(|&a, &b| {
            let score = |k: usize| match (ed, s.rays[k].direction) {
                (Some(e), Some(d)) => -dot(e, unit(d)),
                _ => 0.0,
            };
            score(a).total_cmp(&score(b))
        });
        if let Some(k) = best {
            m[i] = Some(k);
            used[k] = true;
        }
    }
    m
}

/// Grades one pixel: a check per stage up to `upto`.
pub fn grade_pixel(e: &Expected, s: &Pixel, upto: Stage, tol: &TracerTolerances) -> Vec<Check> {
    let m = match_rays(&e.pixel, s);
    Stage::ALL
        .iter()
        .copied()
        .filter(|st| *st <= upto && e.judges(*st, upto))
        .map(|stage| {
            // A stage the program printed nothing for scores 0 (see `coverage`).
            let found = super::coverage::missing(e, s, &m, stage, upto).or_else(|| match stage {
                Stage::Camera => camera(e, s, &m, tol),
                Stage::Sphere | Stage::PlaneTriangle => {
                    super::instancing::instance_rays(e, s, &m, stage, upto, tol)
                        .or_else(|| tests(e, s, &m, stage, upto, tol))
                }
                Stage::ClosestHit => super::closest_hit::hits(e, s, &m, upto, tol),
                Stage::Surface => super::surface::surface(e, s, &m, upto, tol),
                Stage::Shadows => shadows(e, s, &m, tol),
                Stage::Secondary => secondary(e, s, &m, tol),
                Stage::Color => color(e, s, &m, tol),
                // A path tracer's stages are `path_compare`'s.
                _ => None,
            });
            match found {
                None => Check {
                    stage,
                    pass: true,
                    message: String::new(),
                    step: None,
                },
                Some((message, step)) => Check {
                    stage,
                    pass: false,
                    message,
                    step,
                },
            }
        })
        .collect()
}

pub(super) type Divergence = Option<(String, Option<usize>)>;

fn camera(e: &Expected, s: &Pixel, m: &[Option<usize>], tol: &TracerTolerances) -> Divergence {
    let step = e.ray_step.first().copied();
    let er = e.pixel.rays.first()?;
    let Some(sr) = m.first().copied().flatten().and_then(|k| s.rays.get(k)) else {
        return Some((
            "no primary ray: print a `ray` record of kind \"primary\"".into(),
            step,
        ));
    };
    if let (Some(o), Some(eo)) = (sr.origin, er.origin)
        && !tol.close3(o, eo, tol.abs * len(eo).max(1.0))
    {
        return Some((
            format!(
                "{}: your origin is {}, raystep's is {} (the camera's position, `from`)",
                ray_name(&e.pixel, 0),
                v(o),
                v(eo)
            ),
            step,
        ));
    }
    if let (Some(d), Some(ed)) = (sr.direction, er.direction)
        && !tol.close3(unit(d), unit(ed), tol.abs * 10.0)
    {
        let (ud, ue) = (unit(d), unit(ed));
        // Mistakes are recognised in the camera's own frame (see `camera_mistakes`).
        let named = e
            .camera
            .as_ref()
            .zip(e.pixel.at)
            .and_then(|((cam, offset), at)| {
                super::camera_mistakes::camera_hint(cam, at, *offset, ud)
            });
        let hint = if dot(ud, ue) < -0.99 {
            " — it points backwards: the direction is the pixel's point on the image plane minus the eye"
        } else {
            named.unwrap_or(
                " — check the pixel's centre (x + 0.5, y + 0.5), the field of view and the aspect ratio (lesson 1)",
            )
        };
        return Some((
            format!(
                "{}: your direction (normalized) is {}, raystep's is {}{hint}",
                ray_name(&e.pixel, 0),
                v(ud),
                v(ue)
            ),
            step,
        ));
    }
    None
}

/// The scale of a student's ray against raystep's: (student |Q|, raystep |Q|).
pub(super) fn scales(er: &Ray, sr: &Ray) -> (f64, f64) {
    let le = er.direction.map_or(1.0, len).max(f64::MIN_POSITIVE);
    let ls = sr.direction.map_or(le, len).max(f64::MIN_POSITIVE);
    (ls, le)
}

fn tests(
    e: &Expected,
    s: &Pixel,
    m: &[Option<usize>],
    stage: Stage,
    upto: Stage,
    tol: &TracerTolerances,
) -> Divergence {
    for (i, er) in e.pixel.rays.iter().enumerate() {
        if !in_scope(&er.kind, upto) {
            continue;
        }
        let Some(sr) = m.get(i).copied().flatten().and_then(|k| s.rays.get(k)) else {
            continue;
        };
        let (ls, le) = scales(er, sr);
        let tol = &tol.at_depth(er.depth);
        for (j, et) in er.tests.iter().enumerate() {
            let step = e.test_step.get(i).and_then(|t| t.get(j)).copied();
            let st = sr.tests.iter().find(|t| {
                t.object() == et.object()
                    && std::mem::discriminant(*t) == std::mem::discriminant(et)
            });
            let this_stage = matches!(
                (stage, et),
                (Stage::Sphere, Test::Sphere { .. })
                    | (
                        Stage::PlaneTriangle,
                        Test::Plane { .. } | Test::Triangle { .. }
                    )
            );
            let Some(st) = st else {
                // Skipped tests are fine (a student's own culling), but not the test of the
                // object the ray hits: every correct tracer makes that one.
                let hit_object = er
                    .hit
                    .clone()
                    .flatten()
                    .and_then(|h| h.object)
                    .is_some_and(|o| o == et.object());
                if this_stage && hit_object {
                    return Some((
                        format!(
                            "{}: you printed no test of \"{}\", the object this ray hits: print a `{}` record for each test{}",
                            ray_name(&e.pixel, i),
                            et.object(),
                            match et {
                                Test::Sphere { .. } => "sphere",
                                Test::Plane { .. } => "plane",
                                Test::Triangle { .. } => "triangle",
                            },
                            match et.object().split_once(super::format::INSTANCE_ARROW) {
                                Some((i, _)) => format!(
                                    " (an instance's: after an `instance` record named \"{i}\", which the tests after it belong to)"
                                ),
                                None => String::new(),
                            }
                        ),
                        step,
                    ));
                }
                continue;
            };
            let at = |what: &str| {
                format!(
                    "{}, {} \"{}\": {what}",
                    ray_name(&e.pixel, i),
                    match et {
                        Test::Sphere { .. } => "sphere",
                        Test::Plane { .. } => "plane",
                        Test::Triangle { .. } => "triangle",
                    },
                    et.object()
                )
            };
            let t_check = |yours: Option<Option<f64>>,
                           want: Option<Option<f64>>|
             -> Option<String> {
                match (yours, want) {
                    (Some(Some(y)), Some(Some(w))) if !tol.close(y * ls, w * le) => Some(format!(
                        "your t is {}, raystep's is {} (as distances along a unit direction: {} and {})",
                        n(y),
                        n(w),
                        n(y * ls),
                        n(w * le)
                    )),
                    (Some(Some(y)), Some(None)) => Some(format!(
                        "you hit it at t = {}, raystep's ray misses it (no root in front of the origin)",
                        n(y)
                    )),
                    (Some(None), Some(Some(w))) => Some(format!(
                        "you miss it, raystep's ray hits it at t = {}",
                        n(w)
                    )),
                    _ => None,
                }
            };
            // The test of the surface a spawned ray leaves depends on the offset off it (the
            // student's own): its b, c and discriminant are not compared, and a root at t ≈ 0
            // where raystep's ray has none is the ray hitting its own surface (acne).
            let leaving = er
                .parent
                .and_then(|p| e.pixel.rays.get(p))
                .and_then(|p| p.hit.clone().flatten())
                .and_then(|h| h.object)
                .is_some_and(|o| o == et.object());
            if leaving && this_stage {
                let (yours, want) = match (et, st) {
                    (Test::Sphere { t: w, .. }, Test::Sphere { t: y, .. })
                    | (Test::Plane { t: w, .. }, Test::Plane { t: y, .. })
                    | (Test::Triangle { t: w, .. }, Test::Triangle { t: y, .. }) => (*y, *w),
                    _ => (None, None),
                };
                let scale = er.origin.map_or(1.0, len).max(1.0);
                if let (Some(Some(y)), Some(None)) = (yours, want)
                    && (y * ls).abs() <= 1e-3 * scale
                {
                    return Some((
                        at(&format!(
                            "your {} ray hits the surface it leaves, at t = {} (raystep's does not): start it off the surface, moved along the normal (shadow acne, lessons 7 and 12)",
                            er.kind,
                            n(y)
                        )),
                        step,
                    ));
                }
                continue;
            }
            match (stage, et, st) {
                (
                    Stage::Sphere,
                    Test::Sphere {
                        abcd: ea, t: etv, ..
                    },
                    Test::Sphere {
                        abcd: sa, t: stv, ..
                    },
                ) => {
                    // a scales with |Q|², b with |Q|, c not at all, the discriminant with |Q|².
                    let names = ["a", "b", "c", "discriminant"];
                    let sc = [(ls * ls, le * le), (ls, le), (1.0, 1.0), (ls * ls, le * le)];
                    for k in 0..4 {
                        let (Some(y), Some(w)) = (sa[k], ea[k]) else {
                            continue;
                        };
                        let (ys, ws) = (y / sc[k].0, w / sc[k].1);
                        // The discriminant cancels: judge it against the size of its terms.
                        let ok = if k == 3 {
                            let size = ea[1].map_or(0.0, |b| (b / le).powi(2))
                                + ea[0]
                                    .zip(ea[2])
                                    .map_or(0.0, |(a, c)| (4.0 * a * c / (le * le)).abs());
                            tol.numbers()
                                .allows_distance((ys - ws).abs(), size.max(ws.abs()))
                        } else {
                            tol.close(ys, ws)
                        };
                        if ok {
                            continue;
                        }
                        let hint = if k == 1 && tol.close(ys * 2.0, ws) {
                            " — your b looks like f·Q: the course notes' b is 2 f·Q"
                        } else if k == 1 && tol.close(-ys, ws) {
                            " — the sign is wrong: f = S − G (from the centre to the origin)"
                        } else if k == 2 {
                            " — check c = f·f − r²"
                        } else if k == 3 {
                            " — check the discriminant b² − 4ac"
                        } else {
                            ""
                        };
                        return Some((at(&yours_vs(names[k], y, w, hint)), step));
                    }
                    if let Some(msg) = t_check(*stv, *etv) {
                        return Some((at(&msg), step));
                    }
                }
                (
                    Stage::PlaneTriangle,
                    Test::Plane {
                        denominator: ed,
                        t: etv,
                        ..
                    },
                    Test::Plane {
                        denominator: sd,
                        t: stv,
                        ..
                    },
                ) => {
                    if let (Some(y), Some(w)) = (sd, ed)
                        && !tol.close(y / ls, w / le)
                    {
                        let hint = if tol.close(-y / ls, w / le) {
                            " — the sign is wrong: the denominator is Q·n with the plane's own normal"
                        } else {
                            ""
                        };
                        return Some((at(&yours_vs("denominator Q·n", *y, *w, hint)), step));
                    }
                    if let Some(msg) = t_check(*stv, *etv) {
                        return Some((at(&msg), step));
                    }
                }
                (
                    Stage::PlaneTriangle,
                    Test::Triangle {
                        det_u_v: ev,
                        t: etv,
                        ..
                    },
                    Test::Triangle {
                        det_u_v: sv,
                        t: stv,
                        ..
                    },
                ) => {
                    let names = ["det D0", "u", "v"];
                    let sc = [(ls, le), (1.0, 1.0), (1.0, 1.0)];
                    for k in 0..3 {
                        let (Some(y), Some(w)) = (sv[k], ev[k]) else {
                            continue;
                        };
                        if !tol.close(y / sc[k].0, w / sc[k].1) {
                            let hint = if k == 0 && tol.close(-y / ls, w / le) {
                                " — the sign is wrong: D0 = det(−Q, E1, E2)"
                            } else if k > 0 && sv[3 - k].is_some_and(|o| tol.close(o, w)) {
                                " — u and v are swapped: u weighs P1, v weighs P2"
                            } else {
                                ""
                            };
                            return Some((at(&yours_vs(names[k], y, w, hint)), step));
                        }
                    }
                    if let Some(msg) = t_check(*stv, *etv) {
                        return Some((at(&msg), step));
                    }
                }
                _ => {}
            }
        }
    }
    None
}

fn shadows(e: &Expected, s: &Pixel, m: &[Option<usize>], tol: &TracerTolerances) -> Divergence {
    for (i, er) in e.pixel.rays.iter().enumerate() {
        if er.kind == "shadow" || er.shadows.is_empty() {
            continue;
        }
        let Some(sk) = m.get(i).copied().flatten() else {
            continue;
        };
        let Some(sr) = s.rays.get(sk) else { continue };
        for (j, (light, blocked)) in er.shadows.iter().enumerate() {
            let step = e.light_step.get(i).and_then(|l| l.get(j)).copied();
            let name = ray_name(&e.pixel, i);
            let Some((_, yours)) = sr.shadows.iter().find(|(l, _)| l == light) else {
                return Some((
                    format!(
                        "{name}: no `shadow` record for light \"{light}\": print whether it is blocked"
                    ),
                    step,
                ));
            };
            let (Some(y), Some(w)) = (yours, blocked) else {
                continue;
            };
            if y == w {
                continue;
            }
            // Acne: the student's shadow ray towards this light starts on the surface.
            let hit_point = er.hit.clone().flatten().and_then(|h| h.point);
            let shadow_ray = s.rays.iter().find(|r| {
                r.parent == Some(sk)
                    && r.kind == "shadow"
                    && r.light.as_deref().is_none_or(|l| l == light)
            });
            // The student's own hit point if printed (exactly equal: no offset), else raystep's
            // (within rounding: the two tracers round differently).
            let own = sr.hit.clone().flatten().and_then(|h| h.point);
            let on_surface = match (shadow_ray.and_then(|r| r.origin), own, hit_point) {
                (Some(o), Some(p), _) => dist(o, p) <= 1e-12 * len(p).max(1.0),
                (Some(o), None, Some(p)) => dist(o, p) <= 1e-6 * len(p).max(1.0),
                _ => false,
            };
            let hint = if *y && on_surface {
                " — your shadow ray starts exactly on the surface and hits it again (shadow acne): move its origin off the surface along the normal (lesson 7)"
            } else if *y {
                " — check that only hits between the point and the light block it (0 < t < the light's distance)"
            } else {
                " — test every object, up to the light's distance"
            };
            return Some((
                format!(
                    "{name}: light \"{light}\": you say {}, raystep says {}{hint}",
                    if *y { "blocked" } else { "not blocked" },
                    if *w { "blocked" } else { "not blocked" }
                ),
                step,
            ));
        }
    }
    // The shadow rays themselves, where the student printed them.
    for (i, er) in e.pixel.rays.iter().enumerate() {
        if er.kind != "shadow" {
            continue;
        }
        let Some(sr) = m.get(i).copied().flatten().and_then(|k| s.rays.get(k)) else {
            continue;
        };
        if let Some(d) = direction_divergence(e, i, er, sr, tol) {
            return Some(d);
        }
    }
    None
}

/// A spawned ray's origin (within the offset tolerance) and direction against raystep's.
fn direction_divergence(
    e: &Expected,
    i: usize,
    er: &Ray,
    sr: &Ray,
    tol: &TracerTolerances,
) -> Divergence {
    let tol = &tol.at_depth(er.depth);
    let step = e.ray_step.get(i).copied();
    let name = ray_name(&e.pixel, i);
    if let (Some(o), Some(eo)) = (sr.origin, er.origin)
        && dist(o, eo) > tol.offset * len(eo).max(1.0)
    {
        return Some((
            format!(
                "{name}: your origin is {}, raystep's is {} — it starts at the hit point (moved off the surface)",
                v(o),
                v(eo)
            ),
            step,
        ));
    }
    if let (Some(d), Some(ed)) = (sr.direction, er.direction)
        && !tol.close3(unit(d), unit(ed), tol.abs * 10.0)
    {
        let hint = bend_hint(e, i, unit(d)).unwrap_or_default();
        return Some((
            format!(
                "{name}: your direction (normalized) is {}, raystep's is {}{hint}",
                v(unit(d)),
                v(unit(ed))
            ),
            step,
        ));
    }
    None
}

/// Names a wrong reflection sign or an inverted Snell ratio, when the student's direction is
/// what that mistake gives.
fn bend_hint(e: &Expected, i: usize, yours: [f64; 3]) -> Option<String> {
    let r = e.pixel.rays.get(i)?;
    let p = e.pixel.rays.get(r.parent?)?;
    let d = unit(p.direction?);
    let nrm = unit(p.hit.clone().flatten()?.normal?);
    let dn = dot(d, nrm);
    let close = |a: [f64; 3]| dist(unit(a), yours) < 1e-3;
    match r.kind.as_str() {
        "reflection" => {
            let wrong = [0, 1, 2].map(|k| d[k] + 2.0 * dn * nrm[k]);
            close(wrong).then(|| " — the sign is wrong: r = d − 2(d·n)n".to_string())
        }
        "refraction" => {
            let eta = e.bends.get(r.parent?)?.eta?;
            let inv = refract(d, nrm, 1.0 / eta)?;
            close(inv).then(|| {
                format!(
                    " — Snell's ratio is inverted: η = n1/n2 = {} (from the side the ray comes from), not {}",
                    n(eta),
                    n(1.0 / eta)
                )
            })
        }
        _ => None,
    }
}

/// Refraction of unit `d` at unit normal `nrm` (facing d) with η = n1/n2; None on total
/// internal reflection.
fn refract(d: [f64; 3], nrm: [f64; 3], eta: f64) -> Option<[f64; 3]> {
    let cos_i = -dot(d, nrm);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t > 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some([0, 1, 2].map(|k| eta * d[k] + (eta * cos_i - cos_t) * nrm[k]))
}

fn secondary(e: &Expected, s: &Pixel, m: &[Option<usize>], tol: &TracerTolerances) -> Divergence {
    for (i, er) in e.pixel.rays.iter().enumerate() {
        if er.kind != "reflection" && er.kind != "refraction" {
            continue;
        }
        // Only where the student reached the parent.
        let parent_matched = er
            .parent
            .and_then(|p| m.get(p).copied().flatten())
            .is_some();
        if !parent_matched {
            continue;
        }
        let Some(sr) = m.get(i).copied().flatten().and_then(|k| s.rays.get(k)) else {
            return Some((
                format!(
                    "{}: you cast no {} ray here (depth {})",
                    ray_name(&e.pixel, i),
                    er.kind,
                    er.depth
                ),
                e.ray_step.get(i).copied(),
            ));
        };
        if let Some(d) = direction_divergence(e, i, er, sr, tol) {
            return Some(d);
        }
    }
    None
}

fn color(e: &Expected, s: &Pixel, m: &[Option<usize>], tol: &TracerTolerances) -> Divergence {
    let er = e.pixel.rays.first()?;
    let step = e.ray_step.first().copied();
    let sr = m.first().copied().flatten().and_then(|k| s.rays.get(k));
    let (Some(want), Some(sr)) = (er.color, sr) else {
        return None;
    };
    let Some(yours) = sr.color else {
        return Some((
            "the primary ray has no `color` record: print the pixel's linear colour".into(),
            step,
        ));
    };
    if (0..3).all(|k| (yours[k] - want[k]).abs() <= tol.color) {
        return None;
    }
    Some((
        format!(
            "the pixel's colour is {}, raystep's is {} (linear RGB, before gamma)",
            v(yours),
            v(want)
        ),
        step,
    ))
}

/// Grades `student`'s output for one pixel against raystep's trace.
pub fn grade(
    expected: &Expected,
    student: &[Pixel],
    upto: Stage,
    tol: &TracerTolerances,
) -> Vec<Check> {
    let at = expected.pixel.at;
    // The pixel's own records, else the only pixel printed.
    let mine = student
        .iter()
        .find(|p| p.at.is_some() && p.at == at)
        .or_else(|| (student.len() == 1).then(|| &student[0]));
    match mine {
        Some(p) => grade_pixel(expected, p, upto, tol),
        None => Stage::ALL
            .iter()
            .copied()
            .filter(|s| *s <= upto && expected.judges(*s, upto))
            .map(|stage| Check {
                stage,
                pass: false,
                message: format!(
                    "no records for pixel {}: print a `pixel` record, then its rays",
                    at.map_or("?".into(), |[x, y]| format!("({x}, {y})"))
                ),
                step: None,
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn any() -> impl Strategy<Value = f64> {
        prop_oneof![
            proptest::num::f64::ANY,
            -10.0..10.0f64,
            Just(0.0),
            Just(f64::NAN)
        ]
    }

    proptest! {
        /// `close` and `close3`, now [`Tolerance::abs_plus_rel`], keep the formulas they had:
        /// |yours − want| ≤ abs + rel·|want| and |yours − want| ≤ abs' + rel·|want| (vectors).
        #[test]
        fn close_and_close3_keep_their_formulas(
            abs in 0.0..0.1f64,
            rel in 0.0..0.1f64,
            extra in 0.0..1.0f64,
            y in [any(), any(), any()],
            w in [any(), any(), any()],
            d in -1e-2..1e-2f64,
        ) {
            let t = TracerTolerances { abs, rel, ..TracerTolerances::default() };
            prop_assert_eq!(t.close(y[0], w[0]), (y[0] - w[0]).abs() <= abs + rel * w[0].abs());
            let near = w[1] + d;
            prop_assert_eq!(t.close(near, w[1]), (near - w[1]).abs() <= abs + rel * w[1].abs());
            let by_hand = |a: [f64; 3], b: [f64; 3]| {
                let e = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
                (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt()
                    <= extra + rel * (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt()
            };
            prop_assert_eq!(t.close3(y, w, extra), by_hand(y, w));
            let near3 = w.map(|c| c + d);
            prop_assert_eq!(t.close3(near3, w, extra), by_hand(near3, w));
        }
    }
}
