//! What a student must have printed for a stage to be judged at all.
//!
//! The format lets a tracer leave any key out, and the comparison ([`super::compare`]) judges
//! the numbers that are there. Left alone, that would let a program that prints almost nothing
//! pass: a stage with nothing to compare has nothing wrong. So before any number is compared,
//! each stage checks that the student printed what it judges, wherever raystep's trace has it:
//!
//! | stage | needs, for every ray it looks at that raystep's trace has |
//! |---|---|
//! | every stage | the pixel's primary ray |
//! | camera | the primary ray's `origin` and `direction` |
//! | sphere, plane-triangle | at least one test of that kind for the pixel; on each test printed, the numbers raystep compares (`a`, `b`, `c`, `discriminant`, `t`; `denominator`, `t`; `det`, `u`, `v`, `t`); on each `instance` record printed, its `origin` and `direction` (judged in `instancing`) |
//! | closest-hit | a `hit` record, and for a hit its `object`, `t`, `point` and `normal` |
//! | surface | (where raystep's hit is smooth-shaded or textured) what closest-hit needs, and a `surface` record with the keys raystep has there: `normal` (smooth), `uv`, `texel` and `texture` (textured) |
//! | shadows | what closest-hit needs (shadow rays start at the hit), a `shadow` record with `blocked` for each light; a shadow ray printed has its `origin` and `direction` |
//! | secondary | what closest-hit needs (bounces start at the hit), each reflection and refraction ray, with its `origin` and `direction` |
//! | color | the primary ray's `color` |
//!
//! Tests of other objects may still be left out (a student's own culling). A stage that has
//! nothing more to judge at a pixel (the shadows of a ray that hits nothing, the bounces off a
//! surface that is not a mirror) passes once what it starts from is printed.

use super::expected::Expected;
use super::format::{Pixel, Test};
use super::stage::{Stage, in_scope, ray_name};

/// A stage's first missing record: the message and raystep's timeline step that has it.
pub(super) type Missing = Option<(String, Option<usize>)>;

/// How feedback names a ray the student printed no record of: "this pixel's primary ray" reads
/// better than the ray's index for the ray every student prints first.
fn whose(e: &Expected, i: usize) -> String {
    if i == 0 {
        "the primary ray of this pixel".into()
    } else {
        ray_name(&e.pixel, i)
    }
}

/// The keys of a test kind the comparison judges, with the record type's name.
fn test_keys(t: &Test) -> (&'static str, Vec<(&'static str, bool)>) {
    match t {
        Test::Sphere { abcd, t, .. } => (
            "sphere",
            vec![
                ("a", abcd[0].is_some()),
                ("b", abcd[1].is_some()),
                ("c", abcd[2].is_some()),
                ("discriminant", abcd[3].is_some()),
                ("t", t.is_some()),
            ],
        ),
        Test::Plane { denominator, t, .. } => (
            "plane",
            vec![("denominator", denominator.is_some()), ("t", t.is_some())],
        ),
        Test::Triangle { det_u_v, t, .. } => (
            "triangle",
            vec![
                ("det", det_u_v[0].is_some()),
                ("u", det_u_v[1].is_some()),
                ("v", det_u_v[2].is_some()),
                ("t", t.is_some()),
            ],
        ),
    }
}

/// The keys of raystep's `surface` record at a hit: `normal` where it is smooth-shaded, `uv`,
/// `texel` and `texture` where it is textured.
pub(super) fn surface_keys(s: &super::format::Surface) -> Vec<&'static str> {
    [
        ("normal", s.normal.is_some()),
        ("uv", s.uv.is_some()),
        ("texel", s.texel.is_some()),
        ("texture", s.texture.is_some()),
    ]
    .into_iter()
    .filter_map(|(k, has)| has.then_some(k))
    .collect()
}

/// Does test `t` belong to `stage`?
fn of_stage(t: &Test, stage: Stage) -> bool {
    match t {
        Test::Sphere { .. } => stage == Stage::Sphere,
        Test::Plane { .. } | Test::Triangle { .. } => stage == Stage::PlaneTriangle,
    }
}

/// The first record `stage` needs that the student did not print, for raystep's trace `e` and
/// the student's pixel `s` whose rays `m` pairs with raystep's.
pub(super) fn missing(
    e: &Expected,
    s: &Pixel,
    m: &[Option<usize>],
    stage: Stage,
    upto: Stage,
) -> Missing {
    let ray_step = |i: usize| e.ray_step.get(i).copied();
    let student = |i: usize| m.get(i).copied().flatten().and_then(|k| s.rays.get(k));
    if e.pixel.rays.is_empty() {
        return None;
    }
    let Some(primary) = student(0) else {
        return Some((
            "you printed no primary ray for this pixel: print a `ray` record of kind \"primary\", then its tests, hit, shadows and colour".into(),
            ray_step(0),
        ));
    };
    // A printed ray's origin and direction.
    let ends = |i: usize| -> Missing {
        let sr = student(i)?;
        let gap = |what: &str| {
            Some((
                format!(
                    "you printed no {what} for {}: give its `ray` record an `{what}`",
                    whose(e, i)
                ),
                ray_step(i),
            ))
        };
        if sr.origin.is_none() && e.pixel.rays[i].origin.is_some() {
            return gap("origin");
        }
        if sr.direction.is_none() && e.pixel.rays[i].direction.is_some() {
            return gap("direction");
        }
        None
    };
    // A test or hit naming an object the scene does not have: the name is wrong, not the test
    // missing (judged at the stage of that kind of record).
    if !e.names.is_empty() {
        for sr in &s.rays {
            if !in_scope(&sr.kind, upto) {
                continue;
            }
            let tests = sr
                .tests
                .iter()
                .filter(|t| of_stage(t, stage))
                .map(|t| (test_keys(t).0, t.object().to_string()));
            let hit = (stage == Stage::ClosestHit)
                .then(|| sr.hit.clone().flatten().and_then(|h| h.object))
                .flatten()
                .map(|o| ("hit", o));
            for (kind, name) in tests.chain(hit) {
                if !e.names.contains(&name) {
                    let similar: Vec<&str> = e
                        .names
                        .iter()
                        .filter(|n| {
                            n.to_lowercase().contains(&name.to_lowercase())
                                || name.to_lowercase().contains(&n.to_lowercase())
                        })
                        .map(String::as_str)
                        .take(3)
                        .collect();
                    let like = if similar.is_empty() {
                        String::new()
                    } else {
                        format!(
                            " (did you mean {}?)",
                            similar
                                .iter()
                                .map(|n| format!("\"{n}\""))
                                .collect::<Vec<_>>()
                                .join(", ")
                        )
                    };
                    return Some((
                        format!(
                            "your `{kind}` record of the ray on line {} names \"{name}\", which is not an object of this scene{like}: use the `name` from the scene file (an unnamed object is \"sphere 0\", \"plane 1\", …; a mesh's triangles \"name[k]\")",
                            sr.line
                        ),
                        ray_step(0),
                    ));
                }
            }
        }
    }
    match stage {
        Stage::Camera => ends(0),
        Stage::Sphere | Stage::PlaneTriangle => {
            // At least one test of the stage's kind printed for the pixel, where raystep's rays
            // (those the student printed) make some: skipping some is culling, skipping all
            // is printing nothing.
            let wanted = e.pixel.rays.iter().enumerate().find_map(|(i, er)| {
                let first = er.tests.iter().position(|t| of_stage(t, stage))?;
                (in_scope(&er.kind, upto) && student(i).is_some()).then_some((i, first))
            });
            let printed = (0..e.pixel.rays.len())
                .filter(|&i| in_scope(&e.pixel.rays[i].kind, upto))
                .filter_map(student)
                .any(|sr| sr.tests.iter().any(|t| of_stage(t, stage)));
            if let (Some((i, j)), false) = (wanted, printed) {
                let kinds = if stage == Stage::Sphere {
                    "sphere test"
                } else {
                    "plane or triangle test"
                };
                return Some((
                    format!(
                        "you printed no {kinds} for this pixel: print a `{}` record for each test a ray makes (raystep's {} makes one)",
                        test_keys(&e.pixel.rays[i].tests[j]).0,
                        ray_name(&e.pixel, i)
                    ),
                    e.test_step.get(i).and_then(|t| t.get(j)).copied(),
                ));
            }
            for (i, er) in e.pixel.rays.iter().enumerate() {
                if !in_scope(&er.kind, upto) {
                    continue;
                }
                let Some(sr) = student(i) else { continue };
                // Each printed test that pairs with one of raystep's carries its numbers.
                for (j, et) in er.tests.iter().enumerate() {
                    if !of_stage(et, stage) {
                        continue;
                    }
                    let Some(st) = sr.tests.iter().find(|t| {
                        t.object() == et.object()
                            && std::mem::discriminant(*t) == std::mem::discriminant(et)
                    }) else {
                        continue;
                    };
                    let (kind, want) = test_keys(et);
                    let (_, have) = test_keys(st);
                    // The test of the surface a spawned ray leaves is judged by its t only.
                    let leaving = er
                        .parent
                        .and_then(|p| e.pixel.rays.get(p))
                        .and_then(|p| p.hit.clone().flatten())
                        .and_then(|h| h.object)
                        .is_some_and(|o| o == et.object());
                    let gap = want
                        .iter()
                        .zip(&have)
                        .find(|((key, w), (_, h))| *w && !*h && (!leaving || *key == "t"));
                    if let Some(((key, _), _)) = gap {
                        let keys: Vec<&str> = want.iter().map(|(k, _)| *k).collect();
                        return Some((
                            format!(
                                "your {kind} test of \"{}\" on {} has no `{key}`: print {}",
                                et.object(),
                                whose(e, i),
                                keys.join(", ")
                            ),
                            e.test_step.get(i).and_then(|t| t.get(j)).copied(),
                        ));
                    }
                }
            }
            None
        }
        Stage::ClosestHit => {
            for (i, er) in e.pixel.rays.iter().enumerate() {
                if !in_scope(&er.kind, upto) || er.kind == "shadow" {
                    continue;
                }
                let Some(sr) = student(i) else { continue };
                let step = e.hit_step.get(i).copied().flatten().or(ray_step(i));
                let Some(eh) = &er.hit else { continue };
                let Some(sh) = &sr.hit else {
                    return Some((
                        format!(
                            "you printed no `hit` record for {}: print the ray's closest hit (object null for none)",
                            whose(e, i)
                        ),
                        step,
                    ));
                };
                let (Some(eh), Some(sh)) = (eh, sh) else {
                    continue;
                };
                let gaps = [
                    ("object", eh.object.is_some(), sh.object.is_some()),
                    ("t", eh.t.is_some(), sh.t.is_some()),
                    ("point", eh.point.is_some(), sh.point.is_some()),
                    ("normal", eh.normal.is_some(), sh.normal.is_some()),
                ];
                if let Some((key, ..)) = gaps.iter().find(|(_, want, have)| *want && !*have) {
                    return Some((
                        format!(
                            "your closest hit of {} has no `{key}`: print object, t, point and normal",
                            whose(e, i)
                        ),
                        step,
                    ));
                }
            }
            None
        }
        // Shadow rays and reflections start at a ray's closest hit, and a surface's reading is
        // made there: these stages need that hit printed in full, also where raystep's ray has
        // no light, bounce or texture to judge there.
        Stage::Surface | Stage::Shadows | Stage::Secondary
            if let Some(gap) = missing(e, s, m, Stage::ClosestHit, upto) =>
        {
            Some(gap)
        }
        Stage::Surface => {
            for (i, er) in e.pixel.rays.iter().enumerate() {
                let Some(es) = &er.surface else { continue };
                if !in_scope(&er.kind, upto) {
                    continue;
                }
                let Some(sr) = student(i) else { continue };
                let step = e.surface_step.get(i).copied().flatten().or(ray_step(i));
                let Some(ss) = &sr.surface else {
                    return Some((
                        format!(
                            "you printed no `surface` record for {}: print what the surface gives shading at its hit ({})",
                            whose(e, i),
                            surface_keys(es).join(", ")
                        ),
                        step,
                    ));
                };
                let gaps = [
                    ("normal", es.normal.is_some(), ss.normal.is_some()),
                    ("uv", es.uv.is_some(), ss.uv.is_some()),
                    ("texel", es.texel.is_some(), ss.texel.is_some()),
                    ("texture", es.texture.is_some(), ss.texture.is_some()),
                ];
                if let Some((key, ..)) = gaps.iter().find(|(_, want, have)| *want && !*have) {
                    return Some((
                        format!(
                            "your `surface` record of {} has no `{key}`: print {}",
                            whose(e, i),
                            surface_keys(es).join(", ")
                        ),
                        step,
                    ));
                }
            }
            None
        }
        Stage::Shadows => {
            for (i, er) in e.pixel.rays.iter().enumerate() {
                if er.kind == "shadow" {
                    if let Some(gap) = ends(i) {
                        return Some(gap);
                    }
                    continue;
                }
                let Some(sr) = student(i) else { continue };
                for (j, (light, _)) in er.shadows.iter().enumerate() {
                    let step = e.light_step.get(i).and_then(|l| l.get(j)).copied();
                    let printed = sr.shadows.iter().find(|(l, _)| l == light);
                    let gap = match printed {
                        None => "record",
                        Some((_, None)) => "`blocked` in the `shadow` record",
                        Some(_) => continue,
                    };
                    return Some((
                        format!(
                            "you printed no shadow {gap} for light \"{light}\" at the hit of {}: print whether it is blocked",
                            whose(e, i)
                        ),
                        step,
                    ));
                }
            }
            None
        }
        Stage::Secondary => (0..e.pixel.rays.len())
            .filter(|&i| matches!(e.pixel.rays[i].kind.as_str(), "reflection" | "refraction"))
            .find_map(ends),
        Stage::Color => match (e.pixel.rays[0].color, primary.color) {
            (Some(_), None) => Some((
                "you printed no colour for this pixel: print a `color` record for the primary ray (its linear RGB)".into(),
                ray_step(0),
            )),
            _ => None,
        },
        // A path tracer's stages are `path_compare`'s.
        _ => None,
    }
}
