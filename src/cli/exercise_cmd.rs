//! `raystep exercise`, `raystep check` and `raystep grade`: exercise sheets with answers checked
//! against the tracer (see [`crate::lesson`] for the sheet format).

use crate::lesson::{self, ExerciseSheet};
use serde_json::json;
use std::path::PathBuf;

/// Arguments of `raystep exercise`.
#[derive(Debug, clap::Args)]
pub struct ExerciseArgs {
    /// The exercise sheet (TOML), or a built-in sheet's name (`02-sphere`).
    pub sheet: PathBuf,
    /// The student's id: each id gets its own variant of every question.
    #[arg(long)]
    pub student: String,
    /// Print the questions as JSON.
    #[arg(long)]
    pub json: bool,
    /// Reveal the first N hints of each question.
    #[arg(long, default_value_t = 0)]
    pub hints: usize,
    /// Also print the answers raystep's tracer gives (the teacher's key for this student).
    #[arg(long)]
    pub solutions: bool,
    /// Write each inline scene of this student's variant to `DIR/<question id>.toml`.
    #[arg(long, value_name = "DIR")]
    pub scenes: Option<PathBuf>,
}

/// Arguments of `raystep check`.
#[derive(Debug, clap::Args)]
pub struct CheckArgs {
    /// The exercise sheet (TOML), or a built-in sheet's name (`02-sphere`).
    pub sheet: PathBuf,
    /// The student's id.
    #[arg(long)]
    pub student: String,
    /// The answers: one `question-id = answer` per line (`#` comments).
    #[arg(long)]
    pub answers: PathBuf,
    /// Print the marks as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `raystep grade`.
#[derive(Debug, clap::Args)]
pub struct GradeArgs {
    /// The exercise sheet (TOML), or a built-in sheet's name (`02-sphere`).
    pub sheet: PathBuf,
    /// The class's answers: CSV with header `student,<question ids…>`.
    pub submissions: PathBuf,
    /// The grades file to write (CSV, written atomically).
    #[arg(short, long)]
    pub output: PathBuf,
}

/// Loads a sheet named on the command line: a file, or a built-in sheet by name (`02-sphere`),
/// as scenes are. A missing file's error lists the built-in names.
fn load(arg: &std::path::Path) -> Result<ExerciseSheet, String> {
    let path = crate::assets::resolve_sheet(arg)?;
    lesson::load_exercise_sheet(&path).map_err(|e| {
        if path.exists() {
            e.to_string()
        } else {
            format!(
                "{e} (built-in sheets: {})",
                crate::assets::sheet_names().join(", ")
            )
        }
    })
}

fn student_id(s: &str) -> Result<&str, String> {
    let s = s.trim();
    if s.is_empty() {
        return Err("--student: the student id is empty".into());
    }
    Ok(s)
}

/// Runs `raystep exercise`.
pub fn run_exercise(args: &ExerciseArgs) -> Result<(), String> {
    let sheet = load(&args.sheet)?;
    let student = student_id(&args.student)?;
    if let Some(dir) = &args.scenes
        && !dir.is_dir()
    {
        return Err(format!("--scenes: {} is not a directory", dir.display()));
    }
    let mut text = format!("{} — student {student}\n", sheet.title);
    let mut items = vec![];
    for (i, q) in sheet.questions.iter().enumerate() {
        let v = sheet.variant(q, student);
        // Make sure the question can be answered (the scene loads, the pixel is inside).
        let expected = sheet.expected(q, &v)?;
        let [x, y] = v.pixel;
        let mut scene_path = match &q.scene {
            lesson::SceneSource::File(p) => Some(crate::assets::scene_argument(p)),
            lesson::SceneSource::Inline(_) => None,
        };
        if let (Some(dir), Some(toml)) = (&args.scenes, &v.scene_toml) {
            let p = dir.join(format!("{}.toml", q.id));
            crate::io::write_atomic(&p, toml.as_bytes())?;
            scene_path = Some(super::full_path(&p));
        }
        let shown: Vec<&String> = q.hints.iter().take(args.hints).collect();
        text += &format!(
            "\n{}. [{}] ({} point{}; answer with {})\n   {}\n",
            i + 1,
            q.id,
            q.points,
            if q.points == 1.0 { "" } else { "s" },
            q.quantity.kind().describe(),
            v.text.trim().replace('\n', "\n   ")
        );
        match &scene_path {
            Some(p) if sheet.trace_command => {
                text += &format!("   trace it: raystep trace {p} --pixel {x},{y}\n")
            }
            // A graded quiz: where, but not the command that prints the answer.
            Some(p) => text += &format!("   scene {p}, pixel {x},{y}\n"),
            None => {
                text += &format!(
                    "   pixel {x},{y} of the question's own scene (write it with --scenes DIR)\n"
                )
            }
        }
        for (k, h) in shown.iter().enumerate() {
            text += &format!("   hint {}: {h}\n", k + 1);
        }
        if q.hints.len() > shown.len() {
            text += &format!(
                "   ({} more hint{}: --hints {})\n",
                q.hints.len() - shown.len(),
                if q.hints.len() - shown.len() == 1 {
                    ""
                } else {
                    "s"
                },
                shown.len() + 1
            );
        }
        if args.solutions {
            text += &format!("   answer: {expected}\n");
        }
        items.push(json!({
            "id": q.id,
            "solution": args.solutions.then(|| expected.to_string()),
            "text": v.text,
            "answer": q.quantity.kind().describe(),
            "points": q.points,
            "pixel": v.pixel,
            "scene": scene_path,
            "scene_toml": v.scene_toml,
            "params": v.values.iter().map(|(n, p)| (n.clone(), json!(p.to_string()))).collect::<serde_json::Map<_, _>>(),
            "hints": shown,
            "hints_available": q.hints.len(),
        }));
    }
    if args.json {
        let doc = json!({
            "sheet": sheet.id,
            "title": sheet.title,
            "student": student,
            "questions": items,
        });
        super::emit(&(serde_json::to_string_pretty(&doc).expect("JSON") + "\n"))
    } else {
        super::emit(&text)
    }
}

/// Runs `raystep check`.
pub fn run_check(args: &CheckArgs) -> Result<(), String> {
    let sheet = load(&args.sheet)?;
    let student = student_id(&args.student)?;
    let file = args.answers.display().to_string();
    let text = crate::io::read_text(&args.answers, crate::io::limits::ANSWERS, "answers file")
        .map_err(|e| format!("{file}: cannot read the answers: {e}"))?;
    let ids: Vec<&str> = sheet.questions.iter().map(|q| q.id.as_str()).collect();
    let answers = lesson::parse_answers(&text, &file, &ids)?;
    let mut out = format!("{} — student {student}\n\n", sheet.title);
    let mut score = 0.0;
    let mut out_of = 0.0;
    let mut items = vec![];
    let width = ids.iter().map(|s| s.chars().count()).max().unwrap_or(0);
    for q in &sheet.questions {
        let v = sheet.variant(q, student);
        let (expected, found) = sheet.expected_and_mistakes(q, &v)?;
        let given = answers.get(&q.id).map(String::as_str);
        let mut m = lesson::mark(&expected, q.quantity.kind(), given, q.tolerance);
        lesson::mistakes::annotate(&mut m, q, given, &found);
        out_of += q.points;
        if m.right {
            score += q.points;
        }
        // What the sheet's feedback policy lets a student see (one check: tries = 1).
        let how = sheet.feedback.explain(&m, &expected, 1);
        let distance = sheet.feedback == lesson::Feedback::Distance;
        out += &format!(
            "{:width$}  {:5}  {how}\n",
            q.id,
            if m.right { "right" } else { "wrong" }
        );
        items.push(json!({
            "id": q.id,
            "right": m.right,
            "answer": given,
            "abs_error": if distance { m.abs_error } else { None },
            "rel_error": if distance { m.rel_error } else { None },
            "note": m.note,
            "mistake": m.mistake.map(|k| k.id()),
            "feedback": how,
            "points": if m.right { q.points } else { 0.0 },
        }));
    }
    out += &format!("\nscore {score} / {out_of}\n");
    if args.json {
        let doc = json!({
            "sheet": sheet.id,
            "student": student,
            "questions": items,
            "score": score,
            "out_of": out_of,
        });
        super::emit(&(serde_json::to_string_pretty(&doc).expect("JSON") + "\n"))
    } else {
        super::emit(&out)
    }
}

/// Runs `raystep grade`.
pub fn run_grade(args: &GradeArgs) -> Result<(), String> {
    crate::io::check_outputs(
        &[
            ("the class's answers", &args.submissions),
            ("the exercise sheet", &args.sheet),
        ],
        &[("-o", &args.output)],
    )?;
    let sheet = load(&args.sheet)?;
    let file = args.submissions.display().to_string();
    let text = crate::io::read_text(
        &args.submissions,
        crate::io::limits::CSV,
        "submissions file",
    )
    .map_err(|e| format!("{file}: cannot read the submissions: {e}"))?;
    // Old Mac line endings (CR alone): rows end there, as with LF or CRLF.
    let text = if !text.contains('\n') && text.contains('\r') {
        text.replace('\r', "\n")
    } else {
        text
    };
    let report = lesson::grade_answers_csv(&sheet, &text, &file)?;
    crate::io::write_atomic(&args.output, report.csv.as_bytes())?;
    for w in &report.warnings {
        eprintln!("warning: {w}");
    }
    super::emit(&format!(
        "graded {} student{} → {} (mean {:.2} / {})\n",
        report.students,
        if report.students == 1 { "" } else { "s" },
        super::full_path(&args.output),
        report.mean,
        report.out_of
    ))
}
