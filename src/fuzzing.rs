//! The entry points the fuzzers (`fuzz/`, cargo-fuzz) and the property tests
//! (`tests/it/fuzz_props.rs`) drive with hostile input: the same code paths the command line takes
//! for a scene, a saved trace, and an exercise sheet with answers and a class CSV. Each returns
//! normally on every input, with a [`Report`]: whether the input was accepted, and every property
//! it checked that did not hold (a rejection's message names the file; what is written reads
//! back the same; a right answer is marked right; …). The property tests assert the report; the
//! fuzz targets panic on a violated property ([`Report::assert_holds`]). A panic, an abort or a
//! hang inside is a finding too.
//!
//! Inputs that carry several files separate them with marker lines: a scene's OBJ follows a line
//! [`OBJ_MARKER`]; a sheet's answers follow [`ANSWERS_MARKER`], its class CSV [`CSV_MARKER`].
//!
//! `raystep grade-tracer`'s two inputs have theirs too: a student program's output (the student
//! trace format), graded against raystep's trace of [`STUDENT_PIXELS`] at every stage
//! ([`student_input`]), and a grading sheet, read and expanded into its scenes and pixels
//! ([`grade_sheet_input`]).

use crate::diagram::{self, Theme, ViewOptions};
use crate::explain::describe;
use crate::explain::diff::compare;
use crate::lesson;
use crate::record::Tolerance;
use crate::record::Trace;
use crate::student::compare::{self as grading, Stage, grade};
use crate::student::expected::{Expected, expected, with_names};
use crate::student::{self, format};
use crate::trace::PreparedScene;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// What an entry point made of one input.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
#[must_use = "a report's violations are the finding: assert them"]
pub struct Report {
    /// The input was accepted (a scene or trace loaded, a sheet or an output parsed).
    pub accepted: bool,
    /// Every checked property that did not hold, in words (empty: all held).
    pub violations: Vec<String>,
}

impl Report {
    fn rejected() -> Report {
        Report::default()
    }

    fn accepted() -> Report {
        Report {
            accepted: true,
            violations: vec![],
        }
    }

    fn check(&mut self, holds: bool, property: impl FnOnce() -> String) {
        if !holds {
            self.violations.push(property());
        }
    }

    /// A rejection whose message must name the input's file (`file`), as every located error
    /// does.
    fn rejected_naming(message: &str, file: &str) -> Report {
        let mut r = Report::rejected();
        r.check(message.contains(file), || {
            format!("a rejection does not name the file {file}: {message}")
        });
        r
    }

    /// Panics with every violated property (the fuzz targets' check).
    pub fn assert_holds(&self) {
        assert!(
            self.violations.is_empty(),
            "violated:\n{}",
            self.violations.join("\n")
        );
    }
}

/// The line that separates a scene's TOML from its OBJ file (written as `mesh.obj`).
pub const OBJ_MARKER: &str = "\n%%OBJ%%\n";
/// The line that separates a sheet's TOML from its answers file.
pub const ANSWERS_MARKER: &str = "\n%%ANSWERS%%\n";
/// The line that separates the answers file from the class CSV.
pub const CSV_MARKER: &str = "\n%%CSV%%\n";

/// Splits `text` at the first `marker`: (before, after), or (text, "") when there is none.
pub fn split_at_marker<'a>(text: &'a str, marker: &str) -> (&'a str, &'a str) {
    text.split_once(marker).unwrap_or((text, ""))
}

/// Loads a scene (TOML, then optionally [`OBJ_MARKER`] and an OBJ written as `mesh.obj` next to
/// it); when it loads, builds its accelerator, records the trace of the middle pixel and reads
/// the trace back from its JSON, which must read back the same; a scene that does not load must
/// be refused with a message naming its file.
pub fn scene_input(data: &[u8]) -> Report {
    let text = String::from_utf8_lossy(data);
    let (toml, obj) = split_at_marker(&text, OBJ_MARKER);
    let dir = match tempfile::tempdir() {
        Ok(d) => d,
        Err(_) => return Report::rejected(),
    };
    if std::fs::write(dir.path().join("mesh.obj"), obj).is_err() {
        return Report::rejected();
    }
    let scene = match crate::scene::load_str(toml, "fuzz.toml", Some(dir.path())) {
        Ok(s) => s,
        Err(e) => return Report::rejected_naming(&e.to_string(), "fuzz.toml"),
    };
    traced_middle_pixel(scene)
}

/// A loaded scene's middle pixel traced: what the tracer writes, the reader must accept and read
/// back unchanged.
fn traced_middle_pixel(scene: crate::scene::Scene) -> Report {
    let mut report = Report::accepted();
    let (x, y) = (scene.camera.width / 2, scene.camera.height / 2);
    let trace = PreparedScene::new(scene).record(x, y, 0);
    match Trace::from_json(&trace.to_json(), "fuzz.json") {
        Ok(back) => report.check(compare(&trace, &back, Tolerance::EXACT).is_equal(), || {
            "a recorded trace reads back different".into()
        }),
        Err(e) => report.check(false, || {
            format!("a recorded trace does not read back: {e}")
        }),
    }
    report
}

/// Opens a glTF file (the input written as `fuzz.glb`: the reader tells GLB from JSON by its
/// first bytes, whatever the name) as a scene; when it loads, records the trace of the middle
/// pixel, which must read back the same; a file that does not load must be refused with a
/// message naming it.
pub fn gltf_input(data: &[u8]) -> Report {
    let dir = match tempfile::tempdir() {
        Ok(d) => d,
        Err(_) => return Report::rejected(),
    };
    let path = dir.path().join("fuzz.glb");
    if std::fs::write(&path, data).is_err() {
        return Report::rejected();
    }
    let scene = match crate::scene::load_file(&path) {
        Ok(s) => s,
        Err(e) => return Report::rejected_naming(&e.to_string(), "fuzz.glb"),
    };
    traced_middle_pixel(scene)
}

/// Reads a trace from JSON; when it loads, prints its tree, compares it with itself and with a
/// copy missing its last root step (`diff`), and draws every available diagram kind, unfocused
/// and focused on its middle step, at a small size. A loaded trace must equal itself and differ
/// from the copy when a step was removed; a trace that does not load must be refused with a
/// message naming its file.
pub fn trace_input(data: &[u8]) -> Report {
    let Ok(text) = std::str::from_utf8(data) else {
        return Report::rejected();
    };
    let trace = match Trace::from_json(text, "fuzz.json") {
        Ok(t) => t,
        Err(e) => return Report::rejected_naming(&e.to_string(), "fuzz.json"),
    };
    let mut report = Report::accepted();
    report.check(!describe::tree(&trace).is_empty(), || {
        "a loaded trace describes as no text".into()
    });
    let names = ["a.json", "b.json"];
    let same = compare(&trace, &trace, Tolerance::EXACT);
    report.check(same.is_equal(), || "a trace differs from itself".into());
    let _ = same.to_text(&trace, &trace, names);
    let mut shorter = trace.clone();
    let removed = shorter.root.steps.pop().is_some();
    for tol in [0.0, 1e-3] {
        let cmp = compare(&trace, &shorter, Tolerance::relative_to_larger(tol, tol));
        report.check(!removed || !cmp.is_equal(), || {
            format!("a trace equals its copy with a step removed (tolerance {tol})")
        });
        let _ = cmp.to_text(&trace, &shorter, names);
        let _ = cmp.to_json(&trace, &shorter, names);
    }
    let steps = trace.timeline().len();
    let middle = (steps > 0).then_some(steps / 2);
    for kind in diagram::available(&trace) {
        for focus in [None, middle] {
            let opts = ViewOptions {
                width: 96,
                height: 72,
                theme: Theme::LIGHT,
                focus,
                slice_angle: 0.0,
                top_down: false,
                ..ViewOptions::default()
            };
            let drawn = diagram::draw(&trace, kind, &opts);
            report.check(drawn.is_ok(), || {
                format!(
                    "the available diagram {kind:?} does not draw: {}",
                    drawn.err().unwrap_or_default()
                )
            });
        }
    }
    if let Some(k) = middle {
        let _ = diagram::kinds_for_step(&trace, k);
    }
    report
}

/// The shipped exercise sheets' folder: where a fuzzed sheet's scene paths start from.
pub fn exercises_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("lessons/exercises")
}

/// Parses a sheet (TOML, then [`ANSWERS_MARKER`] and an answers file, then [`CSV_MARKER`] and a
/// class CSV); when it parses, works out every question's expected answer for one student, marks
/// the answers file against them and grades the CSV. Each expected answer, typed as the key
/// prints it, must be marked right; a sheet that does not parse must be refused with a message
/// naming its file.
pub fn sheet_input(data: &[u8]) -> Report {
    let text = String::from_utf8_lossy(data);
    let (sheet_text, rest) = split_at_marker(&text, ANSWERS_MARKER);
    let (answers, csv) = split_at_marker(rest, CSV_MARKER);
    // CSV parsing stands on its own too (a CSV that no sheet accepts is still parsed).
    let _ = crate::text::csv::parse_csv(csv, "class.csv");
    let base = exercises_dir();
    let sheet = match lesson::parse_exercise_sheet(sheet_text, "sheet.toml", Some(&base), "sheet") {
        Ok(s) => s,
        Err(e) => return Report::rejected_naming(&e.to_string(), "sheet.toml"),
    };
    let mut report = Report::accepted();
    let ids: Vec<&str> = sheet.questions.iter().map(|q| q.id.as_str()).collect();
    let given = lesson::parse_answers(answers, "answers.txt", &ids).unwrap_or_default();
    for q in &sheet.questions {
        let v = sheet.variant(q, "fuzz");
        if let Ok(expected) = sheet.expected(q, &v) {
            let key = expected.to_string();
            let own = lesson::mark(&expected, q.quantity.kind(), Some(&key), q.tolerance);
            report.check(own.right, || {
                format!(
                    "question {}: the key's own answer {key} is marked wrong",
                    q.id
                )
            });
            let _ = lesson::mark(
                &expected,
                q.quantity.kind(),
                given.get(&q.id).map(String::as_str),
                q.tolerance,
            );
        }
    }
    let _ = lesson::grade_answers_csv(&sheet, csv, "class.csv");
    report
}

/// The pixels a fuzzed student output is graded against: (shipped scene, x, y). Between them
/// they have every stage's records: sphere and plane tests, a glass sphere hit with its
/// reflection and refraction rays, shadow rays, triangle tests, a triangle hit and two lights.
pub const STUDENT_PIXELS: [(&str, u32, u32); 4] = [
    ("mirror-glass", 240, 160),
    ("triangles", 100, 150),
    ("textures", 90, 110),
    ("smooth-shading", 230, 110),
];

/// raystep's trace of each of [`STUDENT_PIXELS`] in the student model, made once.
pub fn student_expected() -> &'static [Expected] {
    static E: OnceLock<Vec<Expected>> = OnceLock::new();
    E.get_or_init(|| {
        STUDENT_PIXELS
            .iter()
            .map(|(name, x, y)| {
                let path =
                    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenes/{name}.toml"));
                let scene = crate::scene::load_file(&path)
                    .unwrap_or_else(|e| panic!("a shipped scene loads: {e}"));
                let trace = PreparedScene::new(scene.clone()).record(*x, *y, 0);
                with_names(expected(&trace), &scene)
            })
            .collect()
    })
}

/// Reads a student program's output (UTF-8, as `grade-tracer` requires); when it parses, checks
/// that each pixel read, written back in the format, reads again, and grades the output against
/// raystep's trace of every one of [`STUDENT_PIXELS`], up to every stage, with the default and
/// with zero tolerances: one check per stage, and no panic.
pub fn student_input(data: &[u8]) -> Report {
    let Ok(text) = std::str::from_utf8(data) else {
        return Report::rejected();
    };
    let Ok(pixels) = format::parse(text) else {
        return Report::rejected();
    };
    let mut report = Report::accepted();
    for px in &pixels {
        let written = format::write(px);
        if let Err(e) = format::parse(&written) {
            report.check(false, || {
                format!("a pixel read from the format, written back, does not read: {e}\n{written}")
            });
        }
    }
    let zero = grading::TracerTolerances {
        rel: 0.0,
        abs: 0.0,
        color: 0.0,
        offset: 0.0,
    };
    for exp in student_expected() {
        for upto in Stage::ALL {
            for tol in [grading::TracerTolerances::default(), zero] {
                let checks = grade(exp, &pixels, upto, &tol);
                let stages: Vec<Stage> = checks.iter().map(|c| c.stage).collect();
                let want: Vec<Stage> = Stage::ALL
                    .iter()
                    .copied()
                    .filter(|s| *s <= upto && exp.judges(*s, upto))
                    .collect();
                report.check(stages == want, || {
                    format!("not one check per stage up to {upto:?}: {stages:?}")
                });
            }
        }
    }
    report
}

/// Where a fuzzed grading sheet stands: the starter kit's sheet, so `../../scenes/…` names the
/// shipped scenes.
pub fn grade_sheet_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("lessons/starter/sheet.toml")
}

/// Reads a grading sheet (`grade-tracer --sheet`) as [`grade_sheet_path`]; when it parses and
/// every scene it names is a shipped scene (a fuzzed path could name any file, a device
/// included), draws each scene's `vary` values for a student and loads the variant (in memory:
/// nothing is written), then expands the sheet into its jobs — the scenes loaded and prepared,
/// the listed pixels checked and the `random_pixels` drawn — with the `vary` lists left out,
/// and checks that every pixel lies inside its scene's image.
pub fn grade_sheet_input(data: &[u8]) -> Report {
    let text = String::from_utf8_lossy(data);
    let path = grade_sheet_path();
    let Ok(sheet) = student::parse_tracer_sheet(&text, &path) else {
        return Report::rejected();
    };
    let mut report = Report::accepted();
    let base = path.parent().unwrap_or(Path::new("."));
    let Ok(scenes) = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .canonicalize()
    else {
        return report;
    };
    let shipped = |file: &Path| {
        base.join(file)
            .canonicalize()
            .is_ok_and(|p| p.starts_with(&scenes) && p.extension().is_some_and(|e| e == "toml"))
    };
    if !sheet.scene.iter().all(|sc| shipped(&sc.file)) {
        return report;
    }
    let who = "s1001";
    let id = sheet.id.clone().unwrap_or_else(|| "sheet".into());
    for sc in sheet.scene.iter().filter(|sc| !sc.vary.is_empty()) {
        let Ok(scene_text) = std::fs::read_to_string(base.join(&sc.file)) else {
            continue;
        };
        let file = sc.file.display().to_string();
        if let Ok((varied, _drawn)) =
            student::variant_text(&scene_text, &scenes, &sc.vary, &id, &file, who)
        {
            let _ = crate::scene::load_str(&varied, "variant.toml", Some(&scenes));
        }
    }
    let mut plain = sheet.clone();
    for sc in &mut plain.scene {
        sc.vary.clear();
    }
    // Without `vary` nothing is written, so the folder for variants is never used.
    let variants = student::VariantDir::Kept(std::env::temp_dir());
    if let Ok(jobs) = student::sheet_jobs(&plain, &path, who, &variants) {
        for job in &jobs {
            let cam = &job.prepared.scene().camera;
            for &[x, y] in &job.pixels {
                report.check(x < cam.width && y < cam.height, || {
                    format!(
                        "pixel ({x}, {y}) outside the {}×{} image of {}",
                        cam.width,
                        cam.height,
                        job.path.display()
                    )
                });
            }
        }
    }
    report
}
