//! `raystep grade-tracer` against programs and class folders that try to get more than they
//! earn or that misbehave: printing too little scores nothing for that stage, per-student scene
//! copies go to a private folder that is removed afterwards, a background process holding the
//! output loses nothing and is stopped, the end of stderr is kept, odd folder names stay apart
//! and cannot inject formulas into the grades CSV, and sheets that would grade nothing (or
//! silently less) are refused with the sheet named. Needs `python3` (which `.ci/run` installs).

use assert_cmd::Command;
use raystep::student::compare::{Stage, TracerTolerances, grade};
use raystep::student::expected::{Expected, expected};
use raystep::student::format::{parse, write};
use serde_json::Value;
use std::path::Path;

use crate::common::scenes;
use scenes::root;

fn traced(scene: &str, x: u32, y: u32) -> Expected {
    let s = raystep::scene::load_file(&root().join(scene)).unwrap();
    expected(&raystep::PreparedScene::new(s).record(x, y, 0))
}

/// Per stage: passed, and the message.
fn verdicts(e: &Expected, text: &str) -> Vec<(Stage, bool, String)> {
    grade(
        e,
        &parse(text).unwrap(),
        Stage::Color,
        &TracerTolerances::default(),
    )
    .into_iter()
    .map(|c| (c.stage, c.pass, c.message))
    .collect()
}

/// raystep's own output with `keep` deciding, per record, what stays (None drops the line).
fn rewrite(text: &str, keep: impl Fn(Value) -> Option<Value>) -> String {
    let mut out = String::new();
    for l in text.lines() {
        if let Some(v) = keep(serde_json::from_str(l).unwrap()) {
            out += &v.to_string();
            out.push('\n');
        }
    }
    out
}

/// The pixels used: a reflected, refracted, shadowed pixel of `mirror-glass` (every stage has
/// something to judge) and a lit pixel of `three-spheres`.
const PIXELS: [(&str, u32, u32); 2] = [
    ("scenes/mirror-glass.toml", 200, 150),
    ("scenes/three-spheres.toml", 160, 150),
];

/// A program that prints too little scores 0 on each stage it printed nothing for, with "you
/// printed no …": the pixel record alone, names without numbers, an empty primary ray. Printing
/// the right numbers for one stage more never scores less.
#[test]
fn printing_too_little_scores_nothing() {
    for (scene, x, y) in PIXELS {
        let e = traced(scene, x, y);
        let full = write(&e.pixel);
        // Sanity: every stage has something to judge here, and the full output passes.
        assert!(
            verdicts(&e, &full).iter().all(|(_, pass, _)| *pass),
            "{scene}"
        );
        let pixel_only = format!("{{\"type\":\"pixel\",\"x\":{x},\"y\":{y}}}\n");
        let names_only = rewrite(&full, |mut v| {
            let o = v.as_object_mut().unwrap();
            o.retain(|k, _| {
                ["type", "kind", "depth", "object", "light", "x", "y"].contains(&k.as_str())
            });
            Some(v)
        });
        let empty_primary = format!(
            "{{\"type\":\"pixel\",\"x\":{x},\"y\":{y}}}\n{{\"type\":\"ray\",\"kind\":\"primary\"}}\n"
        );
        for (what, text) in [
            ("the pixel record alone", &pixel_only),
            ("names without numbers", &names_only),
            ("an empty primary ray", &empty_primary),
        ] {
            for (stage, pass, msg) in verdicts(&e, text) {
                assert!(!pass, "{scene}, {what}: {stage:?} passed");
                assert!(
                    msg.contains("you printed no") || msg.contains(" has no `"),
                    "{scene}, {what}: {stage:?}: {msg}"
                );
            }
        }
        // One kind of record left out at a time: its stage scores 0, saying what is missing.
        for (ty, stage, words) in [
            ("sphere", Stage::Sphere, "you printed no sphere test"),
            ("hit", Stage::ClosestHit, "you printed no `hit` record"),
            ("shadow", Stage::Shadows, "you printed no shadow record"),
            ("color", Stage::Color, "you printed no colour"),
        ] {
            let text = rewrite(&full, |v| (v["type"] != ty).then_some(v));
            let v = verdicts(&e, &text);
            let (_, pass, msg) = v.iter().find(|(s, ..)| *s == stage).unwrap();
            assert!(!pass && msg.contains(words), "{scene}, no {ty}: {msg}");
            // The camera is still judged on its numbers, and passes.
            assert!(v[0].1, "{scene}, no {ty}: {:?}", v[0]);
        }
        // One key left out of every record that has it.
        for (ty, key, stage, words) in [
            (
                "ray",
                "direction",
                Stage::Camera,
                "you printed no direction",
            ),
            ("sphere", "b", Stage::Sphere, "has no `b`"),
            ("sphere", "t", Stage::Sphere, "has no `t`"),
            ("hit", "normal", Stage::ClosestHit, "has no `normal`"),
            ("hit", "t", Stage::ClosestHit, "has no `t`"),
            ("shadow", "blocked", Stage::Shadows, "no shadow `blocked`"),
        ] {
            let text = rewrite(&full, |mut v| {
                if v["type"] == ty {
                    v.as_object_mut().unwrap().remove(key);
                }
                Some(v)
            });
            let v = verdicts(&e, &text);
            let (_, pass, msg) = v.iter().find(|(s, ..)| *s == stage).unwrap();
            assert!(
                !pass && msg.contains(words),
                "{scene}, {ty} without {key}: {msg}"
            );
        }
    }
    // The secondary rays: a reflection ray without its direction, at the first pixel of
    // three-spheres (on a 10-pixel grid) whose primary ray is reflected.
    let e = (0..24)
        .flat_map(|j| (0..32).map(move |i| (10 * i, 10 * j)))
        .map(|(x, y)| traced("scenes/three-spheres.toml", x, y))
        .find(|e| e.pixel.rays.iter().any(|r| r.kind == "reflection"))
        .expect("three-spheres has a mirror");
    let full = write(&e.pixel);
    let text = rewrite(&full, |mut v| {
        if v["type"] == "ray" && v["kind"] == "reflection" {
            v.as_object_mut().unwrap().remove("direction");
        }
        Some(v)
    });
    let v = verdicts(&e, &text);
    let (_, pass, msg) = v.iter().find(|(s, ..)| *s == Stage::Secondary).unwrap();
    assert!(!pass && msg.contains("you printed no direction"), "{msg}");
}

fn raystep() -> Command {
    Command::cargo_bin("raystep").unwrap()
}

fn script(dir: &Path, name: &str, body: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, body).unwrap();
    format!("python3 {}", p.display())
}

/// The Gradescope JSON of `run` on `three-spheres` at (160, 150).
fn gradescope(run: &str, extra: &[&str], env: &[(&str, &Path)]) -> Value {
    let mut cmd = raystep();
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd
        .args([
            "grade-tracer",
            "--scene",
            &root()
                .join("scenes/three-spheres.toml")
                .display()
                .to_string(),
            "--pixels",
            "160,150",
            "--json",
            // Some tests run raystep itself as the student's program.
            "--allow-raystep",
            "--run",
            run,
        ])
        .args(extra)
        .assert()
        .success()
        .get_output()
        .clone();
    serde_json::from_slice(&out.stdout).unwrap()
}

/// End to end, a program that prints only the pixel record scores 0 of 7 (it scored 6).
#[test]
fn the_pixel_record_alone_scores_zero_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    let run = script(
        dir.path(),
        "lazy.py",
        "import sys\nprint('{\"type\":\"pixel\",\"x\":%s,\"y\":%s}' % (sys.argv[2], sys.argv[3]))\n",
    );
    let v = gradescope(&format!("{run} {{scene}} {{x}} {{y}}"), &[], &[]);
    assert_eq!(v["score"], 0.0, "{v}");
    assert_eq!(v["max_score"], 7.0, "{v}");
}

/// The raystep binary as a student's program that prints raystep's own trace.
fn raystep_trace_cmd() -> String {
    format!(
        "'{}' trace {{scene}} --pixel {{x}},{{y}} --format student",
        env!("CARGO_BIN_EXE_raystep")
    )
}

/// A program that leaves a background process holding its output: what it printed is graded
/// (full marks), the report says a process held the pipe, the grading does not wait for the
/// process, and the process is stopped (not left running under PID 1).
#[test]
fn a_background_child_holding_stdout_loses_nothing_and_is_stopped() {
    let dir = tempfile::tempdir().unwrap();
    let pid_file = dir.path().join("pid");
    let run = script(
        dir.path(),
        "bg.py",
        &format!(
            "import subprocess, sys\n\
             subprocess.run(sys.argv[1:])\n\
             sys.stdout.flush()\n\
             p = subprocess.Popen(['sleep', '300'])\n\
             open({:?}, 'w').write(str(p.pid))\n",
            pid_file.display().to_string()
        ),
    );
    let start = std::time::Instant::now();
    let v = gradescope(&format!("{run} {}", raystep_trace_cmd()), &[], &[]);
    assert!(start.elapsed().as_secs() < 60, "{:?}", start.elapsed());
    assert_eq!(v["score"], v["max_score"], "{v}");
    assert!(
        v["tests"][0]["output"]
            .as_str()
            .unwrap()
            .contains("kept its output open"),
        "{v}"
    );
    let pid = std::fs::read_to_string(&pid_file).unwrap();
    // The process group was killed: the sleeper is gone (give the kernel a moment to reap it).
    let alive = || {
        Path::new(&format!("/proc/{}", pid.trim())).exists() && {
            let stat =
                std::fs::read_to_string(format!("/proc/{}/stat", pid.trim())).unwrap_or_default();
            // A zombie (state Z) has ended; it waits only for its parent to read its status.
            !stat.split(") ").nth(1).is_some_and(|s| s.starts_with('Z'))
        }
    };
    for _ in 0..50 {
        if !alive() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    assert!(!alive(), "the background process {pid} still runs");
}

/// A program that writes 100,000 debug lines to stderr, then fails with a traceback: the report
/// shows the traceback's last line whole (it showed the first 64 KiB).
#[test]
fn the_end_of_stderr_is_kept() {
    let dir = tempfile::tempdir().unwrap();
    let run = script(
        dir.path(),
        "noisy.py",
        "import sys\nfor i in range(100000):\n    print('debug line', i, file=sys.stderr)\n\
         raise ValueError('the discriminant went negative at the very end')\n",
    );
    let v = gradescope(&run, &[], &[]);
    let out = v["tests"][0]["output"].as_str().unwrap();
    assert!(
        out.contains("ValueError: the discriminant went negative at the very end"),
        "{out}"
    );
    assert!(out.contains("debug line 99999"), "{out}");
    assert!(!out.contains("debug line 0\n"), "{out}");
}

/// The end of stderr as shown: the last lines, a partial first line dropped when the front was
/// cut, a very long line kept by its end.
#[test]
fn stderr_tail_keeps_whole_last_lines() {
    use raystep::student::run::stderr_tail;
    let text = "half a li\nne one\nline two\nline three\n";
    assert_eq!(
        stderr_tail(text.as_bytes(), false),
        "half a li\nne one\nline two\nline three"
    );
    assert_eq!(
        stderr_tail(text.as_bytes(), true),
        "ne one\nline two\nline three"
    );
    let many: String = (0..20).map(|i| format!("l{i}\n")).collect();
    assert_eq!(
        stderr_tail(many.as_bytes(), false),
        "l12\nl13\nl14\nl15\nl16\nl17\nl18\nl19"
    );
    let long = format!("{}END", "x".repeat(10_000));
    let shown = stderr_tail(long.as_bytes(), false);
    assert!(shown.starts_with('…') && shown.ends_with("xEND"), "{shown}");
    assert!(shown.chars().count() <= 401, "{}", shown.len());
}

/// A sheet that varies a scene: the copies go to a fresh private folder under TMPDIR (mode 0700)
/// and are removed afterwards; a link planted at the old fixed path is never written through;
/// two runs never share a folder.
#[test]
fn variants_go_to_a_private_folder_removed_afterwards() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let scene = root().join("scenes/three-spheres.toml");
    let sheet = dir.path().join("cp2.toml");
    std::fs::write(
        &sheet,
        format!(
            "[[scene]]\nfile = \"{}\"\npixels = [[160, 150]]\n\
             [[scene.vary]]\nobject = \"middle\"\nkey = \"radius\"\nrange = [0.8, 1.2]\n",
            scene.display()
        ),
    )
    .unwrap();
    // Another user's file, and a link to it where the old grader wrote ada's copy.
    let victim = dir.path().join("victim.txt");
    std::fs::write(&victim, "precious").unwrap();
    let old = tmp.join("raystep-grade/cp2/ada");
    std::fs::create_dir_all(&old).unwrap();
    std::os::unix::fs::symlink(&victim, old.join("three-spheres.toml")).unwrap();
    // The student's program reports the mode of its scene's folder's parent, then prints
    // raystep's trace of the scene it was given.
    let modes = dir.path().join("modes.txt");
    let run = script(
        dir.path(),
        "peek.py",
        &format!(
            "import os, stat, subprocess, sys\n\
             d = os.path.dirname(os.path.dirname(os.path.abspath(sys.argv[1])))\n\
             open({:?}, 'a').write(d + ' ' + oct(stat.S_IMODE(os.stat(d).st_mode)) + '\\n')\n\
             subprocess.run([{:?}, 'trace', sys.argv[1], '--pixel', sys.argv[2] + ',' + sys.argv[3], '--format', 'student'])\n",
            modes.display().to_string(),
            env!("CARGO_BIN_EXE_raystep")
        ),
    );
    for _ in 0..2 {
        let out = raystep()
            .env("TMPDIR", &tmp)
            .args([
                "grade-tracer",
                "--sheet",
                &sheet.display().to_string(),
                "--student",
                "ada",
                "--json",
                "--allow-raystep",
                "--run",
                &format!("{run} {{scene}} {{x}} {{y}}"),
            ])
            .assert()
            .success()
            .get_output()
            .clone();
        let v: Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["score"], v["max_score"], "{v}");
        // Failed feedback would name no removed file: the variant is gone.
        assert!(!v.to_string().contains("raystep open"), "{v}");
    }
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    let seen = std::fs::read_to_string(&modes).unwrap();
    let lines: Vec<&str> = seen.lines().collect();
    assert_eq!(lines.len(), 2, "{seen}");
    let (a, b) = (
        lines[0].split(' ').collect::<Vec<_>>(),
        lines[1].split(' ').collect::<Vec<_>>(),
    );
    assert_eq!((a[1], b[1]), ("0o700", "0o700"), "{seen}");
    assert_ne!(a[0], b[0], "two runs shared a folder: {seen}");
    for l in &lines {
        let folder = l.split(' ').next().unwrap();
        assert!(folder.starts_with(&tmp.display().to_string()), "{folder}");
        assert!(!Path::new(folder).exists(), "{folder} was left behind");
    }
    // Only the planted old folder remains in TMPDIR.
    let left: Vec<_> = std::fs::read_dir(&tmp)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, vec![std::ffi::OsString::from("raystep-grade")]);
}

/// `--variants DIR` keeps each student's variant, and a failed check's feedback names it with
/// the command that opens it and the one that traces it in a terminal.
#[test]
fn kept_variants_are_named_in_feedback() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/three-spheres.toml");
    let sheet = dir.path().join("cp2.toml");
    std::fs::write(
        &sheet,
        format!(
            "upto = \"camera\"\n[[scene]]\nfile = \"{}\"\npixels = [[160, 150]]\n\
             [[scene.vary]]\nobject = \"middle\"\nkey = \"radius\"\nrange = [0.8, 1.2]\n",
            scene.display()
        ),
    )
    .unwrap();
    let lazy = script(dir.path(), "lazy.py", "print('{\"type\":\"pixel\"}')\n");
    let kept = dir.path().join("kept");
    let out = raystep()
        .args([
            "grade-tracer",
            "--sheet",
            &sheet.display().to_string(),
            "--student",
            "ada",
            "--variants",
            &kept.display().to_string(),
            "--run",
            &lazy,
        ])
        .assert()
        .success()
        .get_output()
        .clone();
    let text = String::from_utf8(out.stdout).unwrap();
    let files: Vec<_> = walk(&kept);
    assert_eq!(files.len(), 1, "{files:?}");
    assert!(files[0].ends_with("three-spheres.toml"), "{files:?}");
    let shown = files[0].display().to_string();
    assert!(
        text.contains(&format!("raystep open {shown} --pixel 160,150")),
        "{text}"
    );
    assert!(
        text.contains(&format!("raystep trace {shown} --pixel 160,150")),
        "{text}"
    );
    assert!(text.contains("middle.radius = "), "{text}");
}

fn walk(d: &Path) -> Vec<std::path::PathBuf> {
    let mut out = vec![];
    for e in std::fs::read_dir(d).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}

/// Class folders whose names differ only in bytes that are not UTF-8 get separate, readable
/// reports and CSV rows; a folder named like a formula is written as text in the CSV.
#[test]
fn odd_folder_names_stay_apart_and_cannot_inject_formulas() {
    use std::os::unix::ffi::OsStrExt;
    let dir = tempfile::tempdir().unwrap();
    let class = dir.path().join("class");
    for name in [&b"a\xff"[..], b"a\xfe", b"=HYPERLINK(\"x\")"] {
        std::fs::create_dir_all(class.join(std::ffi::OsStr::from_bytes(name))).unwrap();
    }
    let out_dir = dir.path().join("out");
    let csv = dir.path().join("grades.csv");
    let lazy = script(dir.path(), "lazy.py", "print('{\"type\":\"pixel\"}')\n");
    raystep()
        .args([
            "grade-tracer",
            "--scene",
            &root()
                .join("scenes/three-spheres.toml")
                .display()
                .to_string(),
            "--pixels",
            "160,150",
            "--upto",
            "camera",
            "--class",
            &class.display().to_string(),
            "--out",
            &out_dir.display().to_string(),
            "--csv",
            &csv.display().to_string(),
            "--run",
            &lazy,
        ])
        .assert()
        .success();
    let mut reports: Vec<String> = std::fs::read_dir(&out_dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .filter(|n| n.ends_with(".txt"))
        .collect();
    reports.sort();
    assert_eq!(
        reports,
        ["=HYPERLINK(\"x\").txt", "a\\xFE.txt", "a\\xFF.txt"]
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.contains("\n\"'=HYPERLINK(\"\"x\"\")\",0,1,"), "{text}");
    assert!(text.contains("\na\\xFE,0,1,"), "{text}");
    assert!(text.contains("\na\\xFF,0,1,"), "{text}");
}

/// Sheets that would grade nothing, or less than they say, are refused naming the sheet: no
/// pixels at all, more than 1000 drawn pixels, a `vary` of an object's name or of text; a drawn
/// value the scene refuses names the sheet (not a temporary copy). A byte-order mark is fine.
#[test]
fn sheets_that_grade_nothing_or_less_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/three-spheres.toml");
    let sheet = dir.path().join("quiz.toml");
    let file = format!("[[scene]]\nfile = \"{}\"\n", scene.display());
    let lazy = script(dir.path(), "lazy.py", "print('{\"type\":\"pixel\"}')\n");
    for (body, words) in [
        (file.clone(), "no pixels to grade"),
        (
            format!("{file}random_pixels = 5000\n"),
            "at most 1000 pixels",
        ),
        (
            format!(
                "{file}pixels = [[1, 1]]\n[[scene.vary]]\nobject = \"middle\"\nkey = \"name\"\nrange = [1, 2]\n"
            ),
            "`name` names the object and cannot vary",
        ),
        (
            format!(
                "{file}pixels = [[1, 1]]\n[[scene.vary]]\nobject = \"middle\"\nkey = \"material\"\nrange = [1, 2]\n"
            ),
            "not a number",
        ),
        (
            format!(
                "{file}pixels = [[1, 1]]\n[[scene.vary]]\nobject = \"middle\"\nkey = \"radius\"\nrange = [-2, -1]\n"
            ),
            "radius",
        ),
    ] {
        std::fs::write(&sheet, &body).unwrap();
        let out = raystep()
            .env("TMPDIR", dir.path())
            .args([
                "grade-tracer",
                "--sheet",
                &sheet.display().to_string(),
                "--run",
                &lazy,
            ])
            .assert()
            .failure()
            .get_output()
            .clone();
        let err = String::from_utf8(out.stderr).unwrap();
        assert!(err.contains(words), "{body}: {err}");
        assert!(err.contains("quiz.toml"), "{body}: {err}");
        assert!(!err.contains("raystep-grade"), "{body}: {err}");
    }
    // A byte-order mark before the sheet.
    std::fs::write(
        &sheet,
        format!("\u{feff}upto = \"camera\"\n{file}pixels = [[160, 150]]\n"),
    )
    .unwrap();
    raystep()
        .args([
            "grade-tracer",
            "--sheet",
            &sheet.display().to_string(),
            "--run",
            &lazy,
        ])
        .assert()
        .success();
}

/// A report with no tests says so, with a score of 0 / 0 (it printed "-0 / -0 … every test
/// passed").
#[test]
fn an_empty_report_says_no_tests_ran() {
    let r = raystep::student::Report {
        student: "ada".into(),
        tests: vec![],
        seconds: 0.0,
    };
    assert!(r.score().is_sign_positive() && r.max_score().is_sign_positive());
    let t = r.text();
    assert!(t.starts_with("ada: 0 / 0 (0 tests"), "{t}");
    assert!(
        t.contains("no tests were run") && !t.contains("every test passed"),
        "{t}"
    );
}

/// A scene set to the distribution integrator is refused, by name, with what to change (a path
/// tracer's scene is graded sample by sample, format version 2); a student's program that prints
/// version 1 for a path-traced scene is told which version to print.
#[test]
fn a_distribution_scene_is_refused_with_what_to_change() {
    let out = raystep()
        .args([
            "grade-tracer",
            "--scene",
            &root()
                .join("scenes/soft-shadows.toml")
                .display()
                .to_string(),
            "--pixels",
            "10,10",
            "--run",
            "python3 -c pass",
        ])
        .assert()
        .failure()
        .get_output()
        .clone();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("soft-shadows.toml")
            && err.contains("distribution integrator")
            && err.contains("integrator = \"path\"")
            && err.contains("--statistical"),
        "{err}"
    );
    let out = raystep()
        .args([
            "grade-tracer",
            "--scene",
            &root()
                .join("scenes/cornell-area.toml")
                .display()
                .to_string(),
            "--pixels",
            "10,10",
            "--json",
            "--run",
            "python3 -c \"print('{\\\"type\\\":\\\"format\\\",\\\"version\\\":1}')\"",
        ])
        .assert()
        .success()
        .get_output()
        .clone();
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let tests = v["tests"].as_array().unwrap();
    assert_eq!(tests.len(), 7, "{v}");
    assert_eq!(v["score"], 0.0);
    let first = tests[0]["output"].as_str().unwrap();
    assert!(
        first.contains("format version 1: a path-traced scene is graded in version 2"),
        "{first}"
    );
}
