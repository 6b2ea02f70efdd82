//! Exercise sheets (`raystep exercise`, `check`, `grade`): every shipped sheet is marked against
//! answers read straight out of a recorded trace's timeline (not through raystep's own
//! extraction), perturbed answers fail, variants differ between students and repeat for one, a
//! quantity is checked against a hand computation, a class is graded with malformed rows, and bad
//! input exits non-zero with a located message.

use assert_cmd::Command;
use raystep::lesson::{self, ExerciseSheet, Question, SceneSource};
use raystep::record::{RayKind, Step, Trace};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn sheets() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("lessons/exercises"))
        .expect("lessons/exercises exists")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

fn raystep() -> Command {
    Command::cargo_bin("raystep").expect("the raystep binary is built")
}

const STUDENTS: [&str; 4] = ["s1001", "alice@example.org", "Bob Smith", "42"];

/// Records the question's variant with the library directly.
fn record(sheet: &ExerciseSheet, q: &Question, student: &str) -> Trace {
    let v = sheet.variant(q, student);
    let scene = match &q.scene {
        SceneSource::File(p) => raystep::scene::load_file(p).unwrap(),
        SceneSource::Inline(_) => {
            raystep::scene::load_str(v.scene_toml.as_ref().unwrap(), "inline", None).unwrap()
        }
    };
    let (accel, _) = raystep::accel::SceneAccel::build(&scene);
    raystep::trace::Tracer::new(&scene, &accel).record(v.pixel[0], v.pixel[1], 0)
}

/// An answer read from the timeline, independently of raystep's extraction code.
#[derive(Debug, Clone, PartialEq)]
enum A {
    Num(f64),
    Vec([f64; 3]),
    Bool(bool),
    Name(String),
    None,
}

impl A {
    fn text(&self) -> String {
        match self {
            A::Num(x) => format!("{x}"),
            A::Vec([x, y, z]) => format!("({x}, {y}, {z})"),
            A::Bool(b) => if *b { "yes" } else { "no" }.into(),
            A::Name(n) => format!("\"{n}\""),
            A::None => "none".into(),
        }
    }

    /// An answer just beyond the tolerance (or simply different).
    fn perturbed(&self, abs: f64, rel: f64) -> String {
        let off = |x: f64| 2.0 * (abs + rel * x.abs()) + 0.01;
        match self {
            A::Num(x) => format!("{}", x + off(*x)),
            A::Vec([x, y, z]) => {
                let n = (x * x + y * y + z * z).sqrt();
                format!("{}, {y}, {z}", x + off(n))
            }
            A::Bool(b) => if *b { "no" } else { "yes" }.into(),
            A::Name(_) => "no-such-object".into(),
            A::None => "1, 2, 3".into(),
        }
    }
}

fn read_quantity(trace: &Trace, q: &Question) -> A {
    let kind = match format!("{:?}", q.ray).as_str() {
        "Primary" => RayKind::Primary,
        "Shadow" => RayKind::Shadow,
        "Reflection" => RayKind::Reflection,
        "Refraction" => RayKind::Refraction,
        "Diffuse" => RayKind::Diffuse,
        "Glossy" => RayKind::Glossy,
        other => panic!("ray {other}"),
    };
    let timeline = trace.timeline();
    // The first ray of that kind in the order steps happened.
    let Some(first) = timeline
        .iter()
        .find(|(r, _)| r.kind == kind)
        .map(|(r, _)| *r)
    else {
        return A::None;
    };
    let steps: Vec<&Step> = timeline
        .iter()
        .filter(|(r, _)| std::ptr::eq(*r, first))
        .map(|(_, s)| &s.step)
        .collect();
    let obj = q.object.as_deref();
    let accepted = steps.iter().rev().find_map(|s| match s {
        Step::Accept { name, t, .. } => Some((name.clone(), *t)),
        _ => None,
    });
    let sphere = steps.iter().find_map(|s| match s {
        Step::Sphere { name, test, .. } if Some(name.as_str()) == obj => Some(*test),
        _ => None,
    });
    let num = |x: Option<f32>| x.map_or(A::None, |x| A::Num(x as f64));
    let vec = |v: [f32; 3]| A::Vec(v.map(|c| c as f64));
    let triangle = || {
        let target = obj
            .map(String::from)
            .or_else(|| accepted.as_ref().map(|a| a.0.clone()))?;
        steps.iter().find_map(|s| match s {
            Step::Triangle { name, test, .. } if *name == target => Some(*test),
            _ => None,
        })
    };
    match q.quantity.name() {
        "discriminant" => num(sphere.map(|t| t.discriminant)),
        "near_root" => num(sphere.and_then(|t| t.roots).map(|r| r[0])),
        "far_root" => num(sphere.and_then(|t| t.roots).map(|r| r[1])),
        "closest_t" => num(accepted.map(|a| a.1)),
        "hit_object" => accepted.map_or(A::None, |a| A::Name(a.0)),
        "triangle_u" => num(triangle().and_then(|t| t.u)),
        "triangle_v" => num(triangle().and_then(|t| t.v)),
        "bvh_nodes_visited" => {
            A::Num(steps.iter().filter(|s| matches!(s, Step::Node(_))).count() as f64)
        }
        "shadow_blocked" => steps
            .iter()
            .find_map(|s| match s {
                Step::Light { light, blocked, .. } if *light == q.light => Some(A::Bool(*blocked)),
                _ => None,
            })
            .unwrap_or(A::None),
        "reflected_direction" => steps
            .iter()
            .find_map(|s| match s {
                Step::Reflect { direction, .. } => Some(vec(*direction)),
                _ => None,
            })
            .unwrap_or(A::None),
        "texture_u" | "texture_v" | "texel_column" | "texel_row" | "texture_color" => steps
            .iter()
            .find_map(|s| match s {
                Step::Texture {
                    uv, lookup, texel, ..
                } => Some(match q.quantity.name() {
                    "texture_u" => A::Num(uv[0] as f64),
                    "texture_v" => A::Num(uv[1] as f64),
                    "texture_color" => vec(*texel),
                    column_or_row => {
                        let k = usize::from(column_or_row == "texel_row");
                        match lookup {
                            raystep::record::texturing::TexelLookup::Checker { cell, .. } => {
                                A::Num(cell[k] as f64)
                            }
                            raystep::record::texturing::TexelLookup::Image { texels, .. } => {
                                A::Num(texels[0].at[k] as f64)
                            }
                        }
                    }
                }),
                _ => None,
            })
            .unwrap_or(A::None),
        "shading_normal" => steps
            .iter()
            .find_map(|s| match s {
                Step::ShadingNormal { normal, .. } => Some(vec(*normal)),
                _ => None,
            })
            .unwrap_or(A::None),
        "cone_width" | "mip_lambda" | "mip_level" => steps
            .iter()
            .find_map(|s| match s {
                Step::Texture {
                    lookup: raystep::record::texturing::TexelLookup::Image { lod: Some(l), .. },
                    ..
                } => Some(match q.quantity.name() {
                    "cone_width" => A::Num(l.width as f64),
                    "mip_lambda" => A::Num(l.lambda as f64),
                    _ => A::Num(l.levels[0].level as f64),
                }),
                _ => None,
            })
            .unwrap_or(A::None),
        "hit_point" | "normal" => steps
            .iter()
            .find_map(|s| match s {
                Step::Surface { point, normal, .. } => {
                    Some(vec(if q.quantity.name() == "normal" {
                        *normal
                    } else {
                        *point
                    }))
                }
                _ => None,
            })
            .unwrap_or(A::None),
        "refracted_direction" => steps
            .iter()
            .find_map(|s| match s {
                Step::Refract { direction, .. } => Some(direction.map_or(A::None, vec)),
                _ => None,
            })
            .unwrap_or(A::None),
        "total_internal_reflection" => steps
            .iter()
            .find_map(|s| match s {
                Step::Refract {
                    total_internal_reflection,
                    ..
                } => Some(A::Bool(*total_internal_reflection)),
                _ => None,
            })
            .unwrap_or(A::None),
        "color" => steps
            .iter()
            .rev()
            .find_map(|s| match s {
                Step::Color { color } => Some(vec(*color)),
                _ => None,
            })
            .unwrap_or(A::None),
        "light_pdf" | "mis_weight" => steps
            .iter()
            .find_map(|s| match s {
                Step::LightSample {
                    pdf, mis_weight, ..
                } => Some(A::Num(if q.quantity.name() == "light_pdf" {
                    *pdf as f64
                } else {
                    *mis_weight as f64
                })),
                _ => None,
            })
            .unwrap_or(A::None),
        "light_contribution" => steps
            .iter()
            .find_map(|s| match s {
                Step::LightSample { contribution, .. } => Some(vec(*contribution)),
                _ => None,
            })
            .unwrap_or(A::None),
        "bsdf_pdf" | "throughput" | "sample_direction" => steps
            .iter()
            .find_map(|s| match s {
                Step::BsdfSample {
                    pdf,
                    throughput,
                    direction,
                    ..
                } => Some(match q.quantity.name() {
                    "bsdf_pdf" => num(*pdf),
                    "throughput" => vec(*throughput),
                    _ => vec(*direction),
                }),
                _ => None,
            })
            .unwrap_or(A::None),
        "roulette_probability" => steps
            .iter()
            .find_map(|s| match s {
                Step::RussianRoulette { probability, .. } => Some(A::Num(*probability as f64)),
                _ => None,
            })
            .unwrap_or(A::None),
        // The ray carried into the object space of the instance it hit: the `Instance` step
        // whose BLAS walk accepted the closest hit (the last one before the last `Accept`).
        "object_origin" | "object_direction" => {
            let last_accept = steps
                .iter()
                .rposition(|s| matches!(s, Step::Accept { .. }))
                .unwrap_or(0);
            steps[..last_accept]
                .iter()
                .rev()
                .find_map(|s| match s {
                    Step::Instance {
                        origin, direction, ..
                    } => Some(if q.quantity.name() == "object_origin" {
                        vec(*origin)
                    } else {
                        vec(*direction)
                    }),
                    _ => None,
                })
                .unwrap_or(A::None)
        }
        other => panic!("the test reads no {other}: add it"),
    }
}

/// Writes an answers file and runs `raystep check --json`; returns the parsed marks.
fn check(sheet: &Path, student: &str, answers: &str) -> Value {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("answers.txt");
    std::fs::write(&f, answers).unwrap();
    let out = raystep()
        .arg("check")
        .arg(sheet)
        .args(["--student", student, "--json", "--answers"])
        .arg(&f)
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    serde_json::from_slice(&out).expect("check --json prints JSON")
}

const HAND_SHEET: &str = r#"
title = "By hand"
feedback = "distance"
[[question]]
id = "disc"
text = "Δ?"
scene_toml = """
[camera]
from = [0, 0, -5]
at = [0, 0, 0]
width = 1
height = 1
[render]
sphere_method = "textbook"
[[sphere]]
name = "ball"
"""
pixel = [0, 0]
quantity = "discriminant"
object = "ball"
tolerance = { abs = 1e-6, rel = 0 }

hints = ["b² − 4ac"]

[[question]]
id = "t"
text = "t?"
scene_toml = """
[camera]
from = [0, 0, -5]
at = [0, 0, 0]
width = 1
height = 1
[render]
sphere_method = "textbook"
[[sphere]]
name = "ball"
"""
pixel = [0, 0]
quantity = "closest_t"
tolerance = { abs = 1e-6, rel = 0 }

hints = ["(−b − √Δ)/2a"]
"#;

/// Runs raystep, expects failure without a panic and every string of `expect` on stderr.
fn fails(args: &[&std::ffi::OsStr], expect: &[&str]) {
    let out = raystep().args(args).assert().failure().get_output().clone();
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(!err.contains("panicked"), "{err}");
    for e in expect {
        assert!(err.contains(e), "expected {e:?} in:\n{err}");
    }
}

/// A one-question sheet over a small inline scene with `extra` lines in the question.
fn small_sheet(head: &str, extra: &str) -> String {
    format!(
        "{head}[[question]]\nid = \"q\"\ntext = \"Camera at (0, 0, -5).\"\n\
         scene_toml = \"\"\"\n[[light]]\nname = \"key\"\nposition = [0, 5, -5]\n\
         [[sphere]]\nname = \"ball\"\n\"\"\"\npixel = [160, 120]\n{extra}\n"
    )
}

mod grading;
mod marking;
mod premises;
mod sheet_errors;
