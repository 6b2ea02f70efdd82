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
//! use raystep::student::{compare::{Stage, Tolerance, grade}, expected::expected, format};
//!
//! let trace = raystep::PreparedScene::new(raystep::scene::default_scene()).record(160, 120, 0);
//! let ours = expected(&trace);
//! // raystep's own trace, written in the format and read back, gets full marks.
//! let text = format::write(&ours.pixel);
//! let checks = grade(&ours, &format::parse(&text).unwrap(), Stage::Color, &Tolerance::default());
//! assert!(checks.iter().all(|c| c.pass));
//! ```

pub mod compare;
pub mod expected;
pub mod format;
pub mod image;
pub mod run;

use crate::record::number::{Style, fmt64};
use crate::trace::PreparedScene;
use compare::{Stage, Tolerance};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

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
}

impl Job {
    /// A job for `path` (absolute) and its pixels.
    pub fn new(
        path: PathBuf,
        prepared: std::sync::Arc<PreparedScene>,
        pixels: Vec<[u32; 2]>,
    ) -> Job {
        Job {
            path,
            prepared,
            pixels,
            reference: Default::default(),
            variant: None,
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
        self.tests.iter().map(|t| t.score).sum()
    }
    /// The points possible.
    pub fn max_score(&self) -> f64 {
        self.tests.iter().map(|t| t.max_score).sum()
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
        for t in &self.tests {
            if t.score < t.max_score {
                s += &format!("\n✗ {}\n", t.name);
                for l in t.output.lines() {
                    s += &format!("  {l}\n");
                }
            }
        }
        if self.tests.iter().all(|t| t.score >= t.max_score) {
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
    tol: &Tolerance,
    limits: run::Limits,
) -> Report {
    let start = Instant::now();
    let mut tests = vec![];
    for job in jobs {
        let file = job
            .path
            .file_name()
            .map_or("scene".into(), |f| f.to_string_lossy().to_string());
        for &[x, y] in &job.pixels {
            let trace = job.prepared.record(x, y, 0);
            let exp = expected::expected(&trace);
            let name = |st: Stage| format!("{file} ({x}, {y}): {}", st.name());
            let stages: Vec<Stage> = Stage::ALL.iter().copied().filter(|s| *s <= upto).collect();
            let out = run::run(template, dir, &job.path, x, y, limits)
                .map_err(|e| e.to_string())
                .and_then(|text| {
                    format::parse(&text).map_err(|e| format!("your program's output, {e}"))
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
                        if !c.pass
                            && let Some(k) = c.step
                        {
                            output += &format!(
                                "\nSee raystep's numbers: raystep open {} --pixel {x},{y} --step {k}",
                                job.path.display()
                            );
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
        }
    }
    Report {
        student: student.to_string(),
        tests,
        seconds: start.elapsed().as_secs_f64(),
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

/// A grading sheet (TOML): which scenes and pixels, up to which stage, with what limits.
///
/// ```toml
/// title = "Checkpoint 2: spheres and planes"
/// upto = "closest-hit"          # camera, sphere, plane-triangle, closest-hit, shadows, secondary, color
/// timeout_s = 10                # per run
/// [[scene]]
/// file = "../scenes/three-spheres.toml"   # relative to the sheet
/// pixels = [[160, 120], [40, 200]]
/// random_pixels = 2             # plus this many drawn per student (from the student id)
/// ```
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sheet {
    /// A title for reports.
    #[serde(default)]
    pub title: String,
    /// Salts the per-student pixels (default: the sheet's file stem).
    #[serde(default)]
    pub id: Option<String>,
    /// The last stage checked.
    #[serde(default = "all_stages")]
    pub upto: Stage,
    /// Seconds per run.
    #[serde(default)]
    pub timeout_s: Option<f64>,
    /// Tolerances.
    #[serde(default)]
    pub tolerance: Option<Tolerance>,
    /// The scenes.
    pub scene: Vec<SheetScene>,
}

fn all_stages() -> Stage {
    Stage::Color
}

/// One scene of a sheet.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SheetScene {
    /// The scene file, relative to the sheet.
    pub file: PathBuf,
    /// Pixels every student gets.
    #[serde(default)]
    pub pixels: Vec<[u32; 2]>,
    /// Pixels drawn per student.
    #[serde(default)]
    pub random_pixels: u32,
    /// Scene values drawn per student (each student grades on their own variant of the scene).
    #[serde(default)]
    pub vary: Vec<Vary>,
}

/// One value of a scene drawn per student: key `key` (element `index` of a vector) of the object,
/// light or material named `object`, uniformly in `range`, rounded to `decimals` places.
///
/// ```toml
/// [[scene.vary]]
/// object = "middle"
/// key = "radius"
/// range = [0.8, 1.2]
/// ```
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Vary {
    /// The `name` of a `[[sphere]]`, `[[plane]]`, `[[triangle]]`, `[[mesh]]`, `[[light]]` or
    /// `[[material]]` of the scene file.
    pub object: String,
    /// The key to set (a number, or a vector with `index`).
    pub key: String,
    /// Which element of a vector key (0 = x).
    #[serde(default)]
    pub index: Option<usize>,
    /// The interval the value is drawn from.
    pub range: [f64; 2],
    /// Decimal places (default 2).
    #[serde(default = "two")]
    pub decimals: u32,
}

fn two() -> u32 {
    2
}

/// The scene file's text with `vary`'s values for `student` set in it (by `toml_edit`, so the
/// file keeps its comments and layout) and mesh files made absolute, so the variant can live in
/// another folder; and a line saying what was drawn.
pub(crate) fn variant_text(
    text: &str,
    scene_dir: &Path,
    vary: &[Vary],
    id: &str,
    file: &str,
    student: &str,
) -> Result<(String, String), String> {
    let mut doc: toml_edit::DocumentMut = text.parse().map_err(|e| format!("{e}"))?;
    let mut drawn = vec![];
    for v in vary {
        let [lo, hi] = v.range;
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return Err(format!(
                "vary {}.{}: range must be two finite numbers, low first",
                v.object, v.key
            ));
        }
        let what = format!(
            "{}.{}{}",
            v.object,
            v.key,
            v.index.map_or(String::new(), |i| format!("[{i}]"))
        );
        let u = crate::lesson::uniform(crate::lesson::draw(id, file, student, &what));
        let scale = 10f64.powi(v.decimals.min(9) as i32);
        let x = ((lo + u * (hi - lo)) * scale).round() / scale;
        let mut found = false;
        for kind in ["sphere", "plane", "triangle", "mesh", "light", "material"] {
            let Some(tables) = doc.get_mut(kind).and_then(|t| t.as_array_of_tables_mut()) else {
                continue;
            };
            for t in tables.iter_mut() {
                if t.get("name").and_then(|n| n.as_str()) != Some(v.object.as_str()) {
                    continue;
                }
                found = true;
                match v.index {
                    None => {
                        t[v.key.as_str()] = toml_edit::value(x);
                    }
                    Some(i) => {
                        let arr = t
                            .get_mut(v.key.as_str())
                            .and_then(|k| k.as_array_mut())
                            .filter(|a| i < a.len())
                            .ok_or_else(|| {
                                format!(
                                    "vary {what}: \"{}\" has no vector {} with an element {i}",
                                    v.object, v.key
                                )
                            })?;
                        arr.replace(i, x);
                    }
                }
            }
        }
        if !found {
            return Err(format!(
                "vary {what}: the scene has no object, light or material named \"{}\"",
                v.object
            ));
        }
        drawn.push(format!("{what} = {x}"));
    }
    // Mesh files, relative to the original scene, made absolute.
    if let Some(meshes) = doc.get_mut("mesh").and_then(|t| t.as_array_of_tables_mut()) {
        for m in meshes.iter_mut() {
            if let Some(obj) = m.get("obj").and_then(|o| o.as_str()).map(str::to_string) {
                let abs = scene_dir.join(obj);
                m["obj"] = toml_edit::value(abs.display().to_string());
            }
        }
    }
    Ok((doc.to_string(), drawn.join(", ")))
}

/// Reads a sheet; errors name the file, line and column.
pub fn load_sheet(path: &Path) -> Result<Sheet, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    parse_sheet(&text, path)
}

/// Reads a sheet's `text` and checks its values (as [`load_sheet`] does); errors name `path`,
/// the line and the column.
pub fn parse_sheet(text: &str, path: &Path) -> Result<Sheet, String> {
    let sheet: Sheet = toml::from_str(text).map_err(|e| {
        let (line, col) = e
            .span()
            .map(|s| crate::lesson::line_col(text, s.start))
            .unwrap_or((0, 0));
        format!("{}:{line}:{col}: {}", path.display(), e.message())
    })?;
    if sheet.scene.is_empty() {
        return Err(format!("{}: the sheet lists no [[scene]]", path.display()));
    }
    if sheet
        .timeout_s
        .is_some_and(|t| !(t.is_finite() && t > 0.0 && t <= 3600.0))
    {
        return Err(format!(
            "{}: timeout_s must be a number of seconds in (0, 3600]",
            path.display()
        ));
    }
    if let Some(t) = &sheet.tolerance
        && ![t.rel, t.abs, t.color, t.offset]
            .iter()
            .all(|x| x.is_finite() && *x >= 0.0)
    {
        return Err(format!(
            "{}: tolerance values must be finite and not negative",
            path.display()
        ));
    }
    Ok(sheet)
}

/// The jobs of a sheet for one student: its pixels plus the student's drawn ones, each inside
/// the scene's image (a listed pixel outside it is an error naming it).
pub fn sheet_jobs(sheet: &Sheet, sheet_path: &Path, student: &str) -> Result<Vec<Job>, String> {
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
        if !sc.vary.is_empty() {
            // The student's own variant of the scene, written where it outlives the grading
            // (the feedback's `raystep open` links point at it).
            let text = std::fs::read_to_string(&path)
                .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
            let dir = std::path::absolute(path.parent().unwrap_or(Path::new(".")))
                .map_err(|e| e.to_string())?;
            let (varied, drawn) = variant_text(
                &text,
                &dir,
                &sc.vary,
                &id,
                &sc.file.display().to_string(),
                student,
            )
            .map_err(|e| format!("{}: {}: {e}", sheet_path.display(), sc.file.display()))?;
            let safe: String = student
                .chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                        c
                    } else {
                        '_'
                    }
                })
                .collect();
            let out = std::env::temp_dir()
                .join("raystep-grade")
                .join(&id)
                .join(safe)
                .join(
                    sc.file
                        .file_name()
                        .unwrap_or(std::ffi::OsStr::new("scene.toml")),
                );
            if let Some(d) = out.parent() {
                std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
            }
            crate::io::write_atomic(&out, varied.as_bytes())?;
            path = out;
            variant = Some(drawn);
        }
        let scene = crate::scene::load_file(&path).map_err(|e| e.to_string())?;
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
        for k in 0..sc.random_pixels.min(1000) {
            let px = crate::lesson::draw(&id, &file, student, &format!("pixel {k} x"));
            let py = crate::lesson::draw(&id, &file, student, &format!("pixel {k} y"));
            pixels.push([
                crate::lesson::pick_int(px, 0, w as i64 - 1) as u32,
                crate::lesson::pick_int(py, 0, h as i64 - 1) as u32,
            ]);
        }
        let mut job = Job::new(
            std::path::absolute(&path).unwrap_or(path),
            std::sync::Arc::new(PreparedScene::new(scene)),
            pixels,
        );
        job.variant = variant;
        jobs.push(job);
    }
    Ok(jobs)
}

/// A class run: every subfolder of `class` is one student's submission (the folder's name is
/// the student); returns each report, in name order.
pub fn grade_class(
    class: &Path,
    template: &str,
    jobs_for: &dyn Fn(&str) -> Result<Vec<Job>, String>,
    upto: Stage,
    tol: &Tolerance,
    limits: run::Limits,
    image: Option<&ImageSpec>,
) -> Result<Vec<Report>, String> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(class)
        .map_err(|e| format!("{}: cannot read: {e}", class.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    let mut out = vec![];
    for d in dirs {
        let student = d
            .file_name()
            .map_or("?".into(), |f| f.to_string_lossy().to_string());
        let jobs = jobs_for(&student)?;
        let mut r = grade_submission(&student, template, &d, &jobs, upto, tol, limits);
        if let Some(spec) = image {
            check_images(&mut r, &d, &jobs, spec);
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
    head.extend(Stage::ALL.iter().map(|s| s.name().to_string()));
    head.push("notes".into());
    rows.push(head);
    for r in reports {
        let mut row = vec![
            r.student.clone(),
            fmt64(r.score(), Style::Exact),
            fmt64(r.max_score(), Style::Exact),
        ];
        for st in Stage::ALL {
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
        // The first failure's first line, as a note.
        row.push(
            r.tests
                .iter()
                .find(|t| t.score < t.max_score)
                .and_then(|t| t.output.lines().next())
                .unwrap_or("")
                .to_string(),
        );
        rows.push(row);
    }
    crate::lesson::csv::write_csv(&rows)
}

/// The time limit as a duration (seconds from a sheet or the command line).
pub fn seconds(s: f64) -> Duration {
    Duration::from_secs_f64(s.clamp(0.001, 3600.0))
}
