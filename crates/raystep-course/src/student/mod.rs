//! Checking a student's own ray tracer against raystep's trace, step by step.
//!
//! The student's program prints its trace in a JSON Lines format any language can write
//! ([`format`](mod@format), documented in `lessons/starter/README.md`); raystep traces the same pixel
//! ([`expected`]), lines the two up ray by ray and test by test ([`compare`]) and says in words
//! where the student first went wrong, naming common mistakes, with the command that opens
//! raystep at the step showing the right numbers. [`grade_submission`] runs a program on a set
//! of scenes and pixels ([`run`]: a time and an output limit, never through a shell) and scores
//! one test per pixel and stage; [`gradescope_json`] writes Gradescope's `results.json`.
//!
//! ```
//! use raystep_course::student::{compare::{Stage, TracerTolerances, grade}, expected::expected, format};
//!
//! let trace = raystep_core::PreparedScene::new(raystep_core::scene::default_scene()).record(160, 120, 0);
//! let ours = expected(&trace);
//! // raystep's own trace, written in the format and read back, gets full marks.
//! let text = format::write(&ours.pixel);
//! let checks = grade(&ours, &format::parse(&text).unwrap(), Stage::Color, &TracerTolerances::default());
//! assert!(checks.iter().all(|c| c.pass));
//! ```

mod camera_mistakes;
mod closest_hit;
pub mod compare;
mod coverage;
pub mod expected;
pub mod format;
pub mod image;
pub mod instancing;
pub mod isolate;
pub mod path;
pub mod path_compare;
pub mod run;
mod sheet;
mod stage;
pub mod statistical;
mod surface;

pub use sheet::variant_text;
pub use sheet::{TracerSheet, TracerSheetScene, Vary, load_tracer_sheet, parse_tracer_sheet};

use crate::platform::{Duration, Instant};
use crate::record::number::{Style, fmt64};
use crate::trace::PreparedScene;
use compare::{Stage, TracerTolerances};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// One scene of a grading run and the pixels to check in it.
#[derive(Debug, Clone)]
pub struct Job {
    /// The scene file the student's program is given.
    pub path: PathBuf,
    /// The scene, prepared once.
    pub prepared: std::sync::Arc<PreparedScene>,
    /// The pixels.
    pub pixels: Vec<[u32; 2]>,
    /// raystep's render, made once when an image is checked.
    pub reference: std::sync::Arc<std::sync::OnceLock<Result<::image::RgbImage, String>>>,
    /// The values drawn for this student's variant of the scene, if it varies.
    pub variant: Option<String>,
    /// The scene file feedback's commands name (None: the student's variant lives in a private
    /// folder removed after grading, so there is no file to name).
    pub open_path: Option<PathBuf>,
    /// The last stage checked on this scene, when its sheet entry says (else the run's).
    pub upto: Option<Stage>,
    /// Graded statistically (`--statistical`): a path-traced scene's sample-by-sample stages
    /// are replaced by [`check_statistical`]'s test.
    pub statistical: bool,
}

impl Job {
    /// A job for `path` (absolute) and its pixels.
    pub fn new(
        path: PathBuf,
        prepared: std::sync::Arc<PreparedScene>,
        pixels: Vec<[u32; 2]>,
    ) -> Job {
        Job {
            open_path: Some(path.clone()),
            path,
            prepared,
            pixels,
            reference: Default::default(),
            variant: None,
            upto: None,
            statistical: false,
        }
    }
}

/// The whole-image check of a submission: the student's PNG of each scene, named by a pattern
/// (`{stem}` is the scene file's stem) relative to the submission's folder.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageSpec {
    /// e.g. `render-{stem}.png`.
    pub pattern: String,
    /// Levels of 255 a channel may differ by.
    pub tolerance: u8,
    /// Where to write each difference image (`{stem}` and `{student}` replaced), if anywhere.
    pub diff: Option<String>,
}

/// One scored test (one pixel and stage), as Gradescope lists it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TestResult {
    /// e.g. `three-spheres.toml (160, 120): sphere`.
    pub name: String,
    /// 0 or 1.
    pub score: f64,
    /// 1.
    pub max_score: f64,
    /// What went wrong, in words (empty when right).
    pub output: String,
    /// Gradescope's visibility.
    pub visibility: String,
}

/// A submission's grade.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// The student (a class folder's subfolder name, or `--student`).
    pub student: String,
    /// Every test.
    pub tests: Vec<TestResult>,
    /// Seconds spent, the student's program included.
    pub seconds: f64,
}

impl Report {
    /// The points scored.
    pub fn score(&self) -> f64 {
        // Folded from +0 (an empty f64 sum is −0, which prints as "-0").
        self.tests.iter().fold(0.0, |a, t| a + t.score)
    }
    /// The points possible.
    pub fn max_score(&self) -> f64 {
        self.tests.iter().fold(0.0, |a, t| a + t.max_score)
    }
    /// The report as text: the score, then every failed test's feedback.
    pub fn text(&self) -> String {
        let mut s = format!(
            "{}: {} / {} ({} tests, {:.1} s)\n",
            self.student,
            self.score(),
            self.max_score(),
            self.tests.len(),
            self.seconds
        );
        // The statistical verdicts lead, passed or not.
        for t in self
            .tests
            .iter()
            .filter(|t| t.name.ends_with(": statistical"))
        {
            let mark = if t.score >= t.max_score { "✓" } else { "✗" };
            s += &format!("\n{mark} {} ({} / {})\n", t.name, t.score, t.max_score);
            for l in t.output.lines() {
                s += &format!("  {l}\n");
            }
        }
        for t in self.tests.iter().filter(|t| t.name.ends_with(COPIED)) {
            s += &format!("\n⚠ {}\n  {}\n", t.name, t.output);
        }
        for t in self
            .tests
            .iter()
            .filter(|t| !t.name.ends_with(": statistical"))
        {
            if t.score < t.max_score {
                s += &format!("\n✗ {}\n", t.name);
                for l in t.output.lines() {
                    s += &format!("  {l}\n");
                }
            }
        }
        if self.tests.is_empty() {
            s += "no tests were run\n";
        } else if self.tests.iter().all(|t| t.score >= t.max_score) {
            s += "every test passed\n";
        }
        s
    }
}

/// Gradescope's autograder `results.json` for a report: the score, the maximum, every test with
/// its name, score, max_score, output and visibility.
pub fn gradescope_json(r: &Report) -> String {
    let v = serde_json::json!({
        "score": r.score(),
        "max_score": r.max_score(),
        "execution_time": (r.seconds * 1000.0).round() / 1000.0,
        "output": format!("raystep grade-tracer: {} / {}", r.score(), r.max_score()),
        "visibility": "visible",
        "stdout_visibility": "hidden",
        "tests": r.tests,
    });
    serde_json::to_string_pretty(&v).unwrap_or_default() + "\n"
}

/// Grades the program `template` (run in `dir`) on every job's pixels, up to stage `upto`.
/// Nothing the program does (crash, hang, garbage, too much output) stops the grading: that
/// pixel's tests score 0 with the reason.
pub fn grade_submission(
    student: &str,
    template: &str,
    dir: &Path,
    jobs: &[Job],
    upto: Stage,
    tol: &TracerTolerances,
    limits: run::Limits,
) -> Report {
    let start = Instant::now();
    let mut tests = vec![];
    for job in jobs {
        let file = job
            .path
            .file_name()
            .map_or("scene".into(), |f| f.to_string_lossy().to_string());
        let upto = job.upto.unwrap_or(upto);
        if path::applies(job.prepared.scene()) {
            // With --statistical, the statistical test replaces the sample-by-sample stages.
            if !job.statistical {
                grade_paths(&mut tests, &file, template, dir, job, upto, tol, limits);
            }
            continue;
        }
        for &[x, y] in &job.pixels {
            let trace = job.prepared.record(x, y, 0);
            let exp = expected::with_names(expected::expected(&trace), job.prepared.scene());
            let name = |st: Stage| format!("{file} ({x}, {y}): {}", st.name());
            let stages: Vec<Stage> = Stage::graded(upto, false)
                .into_iter()
                .filter(|st| exp.judges(*st, upto))
                .collect();
            let mut note = None;
            let mut copied = false;
            let out = run::run(template, dir, &job.path, x, y, limits)
                .map_err(|e| e.to_string())
                .and_then(|o| {
                    note = o.note;
                    copied = isolate::is_raysteps_text(&o.stdout, &format::write(&exp.pixel));
                    format::parse(&o.stdout).map_err(|e| format!("your program's output, {e}"))
                });
            match out {
                Err(why) => {
                    for st in stages {
                        tests.push(TestResult {
                            name: name(st),
                            score: 0.0,
                            max_score: 1.0,
                            output: why.clone(),
                            visibility: "visible".into(),
                        });
                    }
                }
                Ok(pixels) => {
                    for c in compare::grade(&exp, &pixels, upto, tol) {
                        let mut output = c.message.clone();
                        if !c.pass
                            && let Some(v) = &job.variant
                        {
                            output += &format!("\n(Your variant of the scene: {v}.)");
                        }
                        if !c.pass {
                            output += &see_numbers(job, x, y, c.step);
                        }
                        if let Some(n) = &note {
                            output += &format!("\n(Note: {n}.)");
                        }
                        tests.push(TestResult {
                            name: name(c.stage),
                            score: if c.pass { 1.0 } else { 0.0 },
                            max_score: 1.0,
                            output,
                            visibility: "visible".into(),
                        });
                    }
                }
            }
            if copied {
                tests.push(copied_test(&file, x, y));
            }
        }
    }
    Report {
        student: student.to_string(),
        tests,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// Grades a path-traced job's pixels sample by sample (format version 2), as
/// [`grade_submission`] does a Whitted job's.
#[allow(clippy::too_many_arguments)]
fn grade_paths(
    tests: &mut Vec<TestResult>,
    file: &str,
    template: &str,
    dir: &Path,
    job: &Job,
    upto: Stage,
    tol: &TracerTolerances,
    limits: run::Limits,
) {
    let stages = Stage::graded(upto, true);
    for &[x, y] in &job.pixels {
        let exp = path::expected(&job.prepared, x, y);
        let name = |st: Stage| format!("{file} ({x}, {y}): {}", st.name());
        let mut note = None;
        let mut copied = false;
        let out = run::run(template, dir, &job.path, x, y, limits)
            .map_err(|e| e.to_string())
            .and_then(|o| {
                note = o.note;
                copied = isolate::is_raysteps_text(&o.stdout, &path::write(&exp.pixel));
                path::parse(&o.stdout).map_err(|e| format!("your program's output, {e}"))
            });
        match out {
            Err(why) => {
                for st in &stages {
                    tests.push(TestResult {
                        name: name(*st),
                        score: 0.0,
                        max_score: 1.0,
                        output: why.clone(),
                        visibility: "visible".into(),
                    });
                }
            }
            Ok(pixels) => {
                for c in path_compare::grade(&exp, &pixels, &stages, tol) {
                    let mut output = c.check.message.clone();
                    if !c.check.pass {
                        if let Some(v) = &job.variant {
                            output += &format!("\n(Your variant of the scene: {v}.)");
                        }
                        output += &see_sample(job, x, y, c.sample.unwrap_or(0), c.check.step);
                    }
                    if let Some(n) = &note {
                        output += &format!("\n(Note: {n}.)");
                    }
                    tests.push(TestResult {
                        name: name(c.check.stage),
                        score: if c.check.pass { 1.0 } else { 0.0 },
                        max_score: 1.0,
                        output,
                        visibility: "visible".into(),
                    });
                }
            }
        }
        if copied {
            tests.push(copied_test(file, x, y));
        }
    }
}

/// The suffix of the (0-point) test that names output which is raystep's own trace text.
pub const COPIED: &str = ": raystep's own output";

/// The 0-point test that names pixel (x, y)'s output as raystep's own text, for the teacher.
fn copied_test(file: &str, x: u32, y: u32) -> TestResult {
    TestResult {
        name: format!("{file} ({x}, {y}){COPIED}"),
        score: 0.0,
        max_score: 0.0,
        output: isolate::raysteps_text_note(x, y),
        visibility: "visible".into(),
    }
}

/// The feedback's pointer to raystep's numbers for sample `k` of a path-traced pixel: `trace
/// --sample k` prints them (step `[K]`); the app opens sample 0 at its step.
fn see_sample(job: &Job, x: u32, y: u32, k: u32, step: Option<usize>) -> String {
    let Some(path) = &job.open_path else {
        return "\n(Your variant lives only while grading runs: grade again with --variants DIR to keep it and see raystep's numbers for it.)".into();
    };
    let arg = crate::assets::scene_argument(path);
    let scene = shlex::try_quote(&arg).map_or_else(|_| arg.clone(), |q| q.into_owned());
    let at = step.map_or(String::new(), |s| format!(" (step [{s}])"));
    let mut out =
        format!("\nSee raystep's numbers: raystep trace {scene} --pixel {x},{y} --sample {k}{at}");
    if k == 0
        && let Some(s) = step
    {
        out += &format!("\nor in the app: raystep open {scene} --pixel {x},{y} --step {s}");
    }
    out
}

/// The statistical check of each path-traced job (`--statistical`), which replaces its
/// sample-by-sample stages: the student's per-pixel statistics (a file named by `pattern`,
/// `{stem}` the scene file's stem, relative to `dir`) against raystep's own render with a seed of
/// the student's ([`statistical::student_reference`]) by Welch's t-test
/// ([`statistical::compare_with`]). One test per scene, worth the tests it replaces (its pixels
/// times the path stages up to `upto`), put first in the report. The file's image must be the
/// scene's (checked before anything is allocated); a file that cannot be read scores 0 with the
/// reason.
pub fn check_statistical(
    report: &mut Report,
    dir: &Path,
    jobs: &[Job],
    pattern: &str,
    upto: Stage,
) {
    let mut lead = vec![];
    for job in jobs.iter().filter(|j| path::applies(j.prepared.scene())) {
        let stem = job
            .path
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().to_string());
        let file = dir.join(pattern.replace("{stem}", &stem));
        let name = format!(
            "{}: statistical",
            job.path
                .file_name()
                .map_or("scene".into(), |f| f.to_string_lossy().to_string())
        );
        let scene = job.prepared.scene();
        let size = (scene.camera.width, scene.camera.height);
        let verdict = crate::io::read_text(&file, crate::io::limits::SCENE * 16, "statistics file")
            .map_err(|e| format!("failed: {}: cannot read: {e}", file.display()))
            .and_then(|text| {
                statistical::parse_for(&text, Some(size))
                    .map_err(|e| format!("failed: {}: {e}", file.display()))
            })
            .map(|img| {
                statistical::compare_with(
                    &img,
                    &statistical::student_reference(scene, &report.student),
                    statistical::Requirements {
                        min_samples: scene.settings.spp,
                    },
                )
            });
        let worth =
            (job.pixels.len() * Stage::graded(job.upto.unwrap_or(upto), true).len()).max(1) as f64;
        let (score, output) = match verdict {
            Err(e) => (0.0, e),
            Ok(v) => (if v.pass { worth } else { 0.0 }, v.message),
        };
        lead.push(TestResult {
            name,
            score,
            max_score: worth,
            output,
            visibility: "visible".into(),
        });
    }
    report.tests.splice(0..0, lead);
}

/// The feedback's pointer to raystep's own numbers for a failed check: the command that opens
/// the app at the pixel and step, and the one that prints the same trace in a terminal, with
/// the step's number, `[K]`, as both show it.
fn see_numbers(job: &Job, x: u32, y: u32, step: Option<usize>) -> String {
    let Some(path) = &job.open_path else {
        return "\n(Your variant lives only while grading runs: grade again with --variants DIR to keep it and see raystep's numbers for it.)".into();
    };
    let arg = crate::assets::scene_argument(path);
    let scene = shlex::try_quote(&arg).map_or_else(|_| arg.clone(), |q| q.into_owned());
    match step {
        Some(k) => format!(
            "\nSee raystep's numbers at step [{k}]: raystep open {scene} --pixel {x},{y} --step {k}\nor in a terminal: raystep trace {scene} --pixel {x},{y} (step [{k}])"
        ),
        None => format!(
            "\nSee raystep's numbers: raystep open {scene} --pixel {x},{y}\nor in a terminal: raystep trace {scene} --pixel {x},{y}"
        ),
    }
}

/// Adds the whole-image test of each job to `report`: passed when at most one pixel in a
/// thousand differs from raystep's render by more than the tolerance.
pub fn check_images(report: &mut Report, dir: &Path, jobs: &[Job], spec: &ImageSpec) {
    for job in jobs {
        let stem = job
            .path
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().to_string());
        let file = dir.join(spec.pattern.replace("{stem}", &stem));
        let reference = job
            .reference
            .get_or_init(|| image::reference(&job.prepared));
        let result = reference
            .as_ref()
            .map_err(|e| format!("raystep's render failed: {e}"))
            .and_then(|r| image::compare(&file, r, spec.tolerance));
        let (score, output) = match result {
            Err(e) => (0.0, e),
            Ok(c) => {
                let mut out = format!(
                    "{} of {} pixels differ from raystep's render by more than {}/255 (the largest difference: {}/255)",
                    c.off, c.pixels, spec.tolerance, c.max_diff
                );
                if let Some(d) = &spec.diff {
                    let path = PathBuf::from(
                        d.replace("{stem}", &stem)
                            .replace("{student}", &report.student),
                    );
                    match crate::render::image::write_png(&path, &c.diff) {
                        Ok(()) => out += &format!("; difference image: {}", path.display()),
                        Err(e) => {
                            out += &format!("; the difference image could not be written: {e}")
                        }
                    }
                }
                ((c.off * 1000 <= c.pixels) as u8 as f64, out)
            }
        };
        report.tests.push(TestResult {
            name: format!(
                "{}: image",
                job.path
                    .file_name()
                    .map_or("scene".into(), |f| f.to_string_lossy().to_string())
            ),
            score,
            max_score: 1.0,
            output,
            visibility: "visible".into(),
        });
    }
}

/// A student's tracer is graded against Whitted's (format version 1) or, on a path-traced
/// scene, against raystep's path tracer sample by sample (version 2); a scene set to the
/// distribution integrator is refused with a message that says how to grade it.
pub fn gradable(scene: &crate::scene::Scene, path: &Path) -> Result<(), String> {
    use crate::scene::Integrator;
    match scene.settings.integrator {
        Integrator::Whitted | Integrator::Path => Ok(()),
        other => Err(format!(
            "{}: grade-tracer grades Whitted tracers and path tracers (sample by sample), and this scene is set to the {} integrator: set `integrator = \"path\"` (or \"whitted\") in its [render] table to grade it step by step, or check a rendered image with --statistical",
            path.display(),
            clap::ValueEnum::to_possible_value(&other)
                .map_or_else(String::new, |v| v.get_name().to_string())
        )),
    }
}

/// The most pixels a sheet's scene draws per student (`random_pixels`).
pub const MAX_RANDOM_PIXELS: u32 = 1000;

/// Where each student's variant of a varied scene is written while grading.
#[derive(Debug)]
pub enum VariantDir {
    /// A private folder made fresh for this run (mode 0700 on Unix, under the system's temporary
    /// folder) and removed with this value: no other user can see or plant anything in it.
    Private(tempfile::TempDir),
    /// A folder the teacher chose (`--variants`), kept afterwards so feedback can name the files.
    Kept(PathBuf),
}

impl VariantDir {
    /// A fresh private folder.
    pub fn private() -> Result<VariantDir, String> {
        let mut b = tempfile::Builder::new();
        b.prefix("raystep-grade-");
        #[cfg(unix)]
        {
            // Made with this mode (not changed afterwards): never open to anyone else.
            use std::os::unix::fs::PermissionsExt;
            b.permissions(std::fs::Permissions::from_mode(0o700));
        }
        b.tempdir()
            .map(VariantDir::Private)
            .map_err(|e| format!("cannot make a private temporary folder: {e}"))
    }

    /// The folder.
    pub fn path(&self) -> &Path {
        match self {
            VariantDir::Private(t) => t.path(),
            VariantDir::Kept(p) => p,
        }
    }

    /// Writes `student`'s variant of the scene `name` and returns its path: in a private folder
    /// as a new file (never through a link: the open fails if anything is there already), in a
    /// kept folder as any other output (atomically).
    fn write(&self, student: &str, name: &std::ffi::OsStr, text: &str) -> Result<PathBuf, String> {
        let dir = self.path().join(folder_name(student));
        let file = dir.join(name);
        let err = |e: std::io::Error| format!("{}: {e}", file.display());
        match self {
            VariantDir::Private(_) => {
                std::fs::create_dir_all(&dir).map_err(err)?;
                // Written again when a student is graded twice: the old file goes first (removing
                // a link removes the link, not what it points to).
                if std::fs::symlink_metadata(&file).is_ok() {
                    std::fs::remove_file(&file).map_err(err)?;
                }
                let mut f = std::fs::OpenOptions::new()
                    .write(true)
                    .create_new(true)
                    .open(&file)
                    .map_err(err)?;
                std::io::Write::write_all(&mut f, text.as_bytes()).map_err(err)?;
            }
            VariantDir::Kept(_) => {
                std::fs::create_dir_all(&dir).map_err(err)?;
                crate::io::write_atomic(&file, text.as_bytes())?;
            }
        }
        Ok(file)
    }
}

/// A folder name for a student: letters, digits, `-` and `_` kept, anything else `_`, and a short
/// hash of the whole name so two names that differ only in such characters stay apart.
fn folder_name(student: &str) -> String {
    use sha2::Digest;
    let safe: String = student
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .take(64)
        .collect();
    let hash = sha2::Sha256::digest(student.as_bytes());
    format!(
        "{safe}-{:02x}{:02x}{:02x}{:02x}",
        hash[0], hash[1], hash[2], hash[3]
    )
}

/// A student's name from a class folder's name: the name itself when it is UTF-8, else its UTF-8
/// parts with every other byte written `\xNN`, so two folders that differ only in such bytes
/// keep different, readable names.
pub fn student_name(folder: &std::ffi::OsStr) -> String {
    let bytes = folder.as_encoded_bytes();
    if let Ok(s) = std::str::from_utf8(bytes) {
        return s.to_string();
    }
    let mut out = String::new();
    for chunk in bytes.utf8_chunks() {
        out += chunk.valid();
        for b in chunk.invalid() {
            out += &format!("\\x{b:02X}");
        }
    }
    out
}

/// The jobs of a sheet for one student: its pixels plus the student's drawn ones, each inside
/// the scene's image (a listed pixel outside it is an error naming it).
///
/// A scene with `vary` is written, with the student's values, into `variants`; its errors (a
/// drawn value the scene refuses) name the sheet, the scene and the student.
pub fn sheet_jobs(
    sheet: &TracerSheet,
    sheet_path: &Path,
    student: &str,
    variants: &VariantDir,
) -> Result<Vec<Job>, String> {
    let base = sheet_path.parent().unwrap_or(Path::new("."));
    let id = sheet.id.clone().unwrap_or_else(|| {
        sheet_path
            .file_stem()
            .map_or("sheet".into(), |s| s.to_string_lossy().to_string())
    });
    let mut jobs = vec![];
    for sc in &sheet.scene {
        let mut path = base.join(&sc.file);
        let mut variant = None;
        let mut open_path = None;
        let scene = if sc.vary.is_empty() {
            crate::scene::load_file(&path).map_err(|e| e.to_string())?
        } else {
            // The student's own variant of the scene: its text, loaded from memory (so errors
            // name the sheet), then written where the student's program can read it.
            let text = crate::io::read_text(&path, crate::io::limits::SCENE, "scene file")
                .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
            let dir = std::path::absolute(path.parent().unwrap_or(Path::new(".")))
                .map_err(|e| e.to_string())?;
            let at = format!(
                "{}: scene {} (the variant of student \"{student}\")",
                sheet_path.display(),
                sc.file.display()
            );
            let (varied, drawn) = variant_text(
                &text,
                &dir,
                &sc.vary,
                &id,
                &sc.file.display().to_string(),
                student,
            )
            .map_err(|e| format!("{at}: {e}"))?;
            let scene = crate::scene::load_str(&varied, &at, Some(&dir))
                .map_err(|e| format!("{e}\n(The values drawn: {drawn}.)"))?;
            let name = sc
                .file
                .file_name()
                .unwrap_or(std::ffi::OsStr::new("scene.toml"));
            path = variants.write(student, name, &varied)?;
            if let VariantDir::Kept(_) = variants {
                open_path = Some(std::path::absolute(&path).unwrap_or(path.clone()));
            }
            variant = Some(drawn);
            scene
        };
        gradable(&scene, &path)?;
        let (w, h) = (scene.camera.width, scene.camera.height);
        let mut pixels = vec![];
        for &[x, y] in &sc.pixels {
            if x >= w || y >= h {
                return Err(format!(
                    "{}: pixel ({x}, {y}) of {} is outside its {w}×{h} image",
                    sheet_path.display(),
                    sc.file.display()
                ));
            }
            pixels.push([x, y]);
        }
        let file = sc.file.display().to_string();
        for k in 0..sc.random_pixels.min(MAX_RANDOM_PIXELS) {
            let px = crate::variant::draw(&id, &file, student, &format!("pixel {k} x"));
            let py = crate::variant::draw(&id, &file, student, &format!("pixel {k} y"));
            pixels.push([
                crate::variant::pick_int(px, 0, w as i64 - 1) as u32,
                crate::variant::pick_int(py, 0, h as i64 - 1) as u32,
            ]);
        }
        let mut job = Job::new(
            std::path::absolute(&path).unwrap_or(path),
            std::sync::Arc::new(PreparedScene::new(scene)),
            pixels,
        );
        if variant.is_some() {
            job.variant = variant;
            job.open_path = open_path;
        }
        job.upto = sc.upto;
        jobs.push(job);
    }
    Ok(jobs)
}

/// Grades a class's tracers (`raystep grade-tracer --class`): every subfolder of `class` is one
/// student's submission (the folder's name is the student), run and checked as
/// [`grade_submission`] does; returns each report, in name order. (A class's typed answers are
/// [`crate::lesson::grade_answers_csv`]'s.)
#[allow(clippy::too_many_arguments)]
pub fn grade_tracer_class(
    class: &Path,
    template: &str,
    jobs_for: &dyn Fn(&str) -> Result<Vec<Job>, String>,
    upto: Stage,
    tol: &TracerTolerances,
    limits: run::Limits,
    image: Option<&ImageSpec>,
    statistical: Option<&str>,
) -> Result<Vec<Report>, String> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(class)
        .map_err(|e| format!("{}: cannot read: {e}", class.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    let mut out = vec![];
    let mut taken = std::collections::HashSet::new();
    for d in dirs {
        let mut student = d.file_name().map_or("?".into(), student_name);
        // Folder names are unique, their readable forms almost always: a literal "\xFF" and
        // the byte 0xFF read alike, so a second such name gets a number.
        let base = student.clone();
        let mut k = 1;
        while !taken.insert(student.clone()) {
            k += 1;
            student = format!("{base} ({k})");
        }
        let mut jobs = jobs_for(&student)?;
        for j in &mut jobs {
            j.statistical = statistical.is_some();
        }
        let mut r = grade_submission(&student, template, &d, &jobs, upto, tol, limits);
        if let Some(spec) = image {
            check_images(&mut r, &d, &jobs, spec);
        }
        if let Some(pattern) = statistical {
            check_statistical(&mut r, &d, &jobs, pattern, upto);
        }
        out.push(r);
    }
    Ok(out)
}

/// The grades CSV of a class run: `student,score,max_score,<one column per stage>,notes`
/// (a stage's column: its tests passed out of its tests).
pub fn grades_csv(reports: &[Report]) -> String {
    let mut rows = vec![];
    let mut head: Vec<String> = vec!["student".into(), "score".into(), "max_score".into()];
    // Whitted's stages always; a path tracer's when a report has them.
    let path_graded = |st: &Stage| {
        let suffix = format!(": {}", st.name());
        reports
            .iter()
            .any(|r| r.tests.iter().any(|t| t.name.ends_with(&suffix)))
    };
    let columns: Vec<Stage> = Stage::ALL
        .iter()
        .copied()
        .chain(Stage::PATH.iter().copied().filter(path_graded))
        .collect();
    head.extend(columns.iter().map(|s| s.name().to_string()));
    head.push("notes".into());
    rows.push(head);
    for r in reports {
        let mut row = vec![
            crate::text::csv::text_cell(&r.student),
            fmt64(r.score(), Style::Exact),
            fmt64(r.max_score(), Style::Exact),
        ];
        for &st in &columns {
            let suffix = format!(": {}", st.name());
            let of: Vec<&TestResult> = r
                .tests
                .iter()
                .filter(|t| t.name.ends_with(&suffix))
                .collect();
            row.push(if of.is_empty() {
                String::new()
            } else {
                format!(
                    "{}/{}",
                    of.iter().filter(|t| t.score >= t.max_score).count(),
                    of.len()
                )
            });
        }
        // Output that is raystep's own text, else the first failure's first line, as a note.
        row.push(crate::text::csv::text_cell(
            r.tests
                .iter()
                .find(|t| t.name.ends_with(COPIED))
                .or_else(|| r.tests.iter().find(|t| t.score < t.max_score))
                .and_then(|t| t.output.lines().next())
                .unwrap_or(""),
        ));
        rows.push(row);
    }
    crate::text::csv::write_csv(&rows)
}

/// The time limit as a duration (seconds from a sheet or the command line).
pub fn seconds(s: f64) -> Duration {
    Duration::from_secs_f64(s.clamp(0.001, 3600.0))
}
