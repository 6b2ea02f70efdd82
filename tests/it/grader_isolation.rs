//! What a student's program may not do while grade-tracer grades it: leave a process running
//! after the grading (one that calls `setsid()` included), or run raystep to copy its numbers
//! (hidden where the platform allows: Linux as root); output that is raystep's own trace text
//! is named in the report whatever the platform. Needs `python3` (which `.ci/run` installs).

use assert_cmd::Command;
use serde_json::Value;
use std::path::Path;

use crate::common::scenes;
use scenes::root;

fn raystep() -> Command {
    Command::cargo_bin("raystep").unwrap()
}

/// grade-tracer's JSON report and its stderr.
fn grade(run: &str, extra: &[&str]) -> (Value, String) {
    let out = raystep()
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
            "--run",
            run,
        ])
        .args(extra)
        .assert()
        .success()
        .get_output()
        .clone();
    (
        serde_json::from_slice(&out.stdout).unwrap(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Whether a process whose command line holds `token` is running (not a zombie).
fn running_with(token: &str) -> Vec<String> {
    let mut found = vec![];
    for e in std::fs::read_dir("/proc").unwrap().flatten() {
        let name = e.file_name().to_string_lossy().to_string();
        if name.parse::<u32>().is_err() {
            continue;
        }
        let cmd = std::fs::read(format!("/proc/{name}/cmdline")).unwrap_or_default();
        let stat = std::fs::read_to_string(format!("/proc/{name}/stat")).unwrap_or_default();
        let zombie = stat
            .rsplit_once(") ")
            .is_some_and(|(_, s)| s.starts_with('Z'));
        if !zombie && String::from_utf8_lossy(&cmd).contains(token) {
            found.push(name);
        }
    }
    found
}

/// A program that forks a child which calls `setsid()` (leaving the program's process group and
/// session) and sleeps, and one that double-forks the same way: when grade-tracer has exited,
/// neither sleeper runs (Linux: raystep reaps and stops every descendant).
#[cfg(target_os = "linux")]
#[test]
fn a_child_that_calls_setsid_does_not_outlive_the_grading() {
    let dir = tempfile::tempdir().unwrap();
    let token = format!("raystep-setsid-{}", std::process::id());
    let prog = dir.path().join("escape.py");
    std::fs::write(
        &prog,
        "import os, sys, time\n\
         if os.fork() == 0:\n\
         \x20   os.setsid()\n\
         \x20   if os.fork() == 0:\n\
         \x20       os.setsid() if False else None\n\
         \x20       time.sleep(60)\n\
         \x20       os._exit(0)\n\
         \x20   time.sleep(60)\n\
         \x20   os._exit(0)\n\
         print('{\"type\":\"pixel\",\"x\":160,\"y\":150}')\n",
    )
    .unwrap();
    let start = std::time::Instant::now();
    // The token rides in the program's arguments, which its children inherit.
    let (v, _) = grade(&format!("python3 {} {token}", prog.display()), &[]);
    assert!(start.elapsed().as_secs() < 30, "{:?}", start.elapsed());
    assert_eq!(v["score"], 0.0, "{v}");
    let left = running_with(&token);
    assert!(left.is_empty(), "still running after grading: {left:?}");
}

/// raystep run by the student's program: where raystep can hide itself (Linux as root, with
/// CAP_SYS_ADMIN) the run fails and scores nothing; elsewhere grade-tracer says on stderr that
/// it could not. With `--allow-raystep` the copy scores, and the report names the pixel's output
/// as raystep's own trace text.
#[test]
fn a_submission_that_runs_raystep_is_refused_or_named() {
    let copy = format!(
        "'{}' trace {{scene}} --pixel {{x}},{{y}} --format student",
        env!("CARGO_BIN_EXE_raystep")
    );
    let (v, err) = grade(&copy, &[]);
    if err.contains("raystep is not hidden") {
        eprintln!("raystep could not hide itself here: {err}");
    } else {
        assert_eq!(v["score"], 0.0, "{v}");
        assert!(
            v["tests"][0]["output"]
                .as_str()
                .unwrap()
                .contains("could not be started"),
            "{v}"
        );
    }
    let (v, _) = grade(&copy, &["--allow-raystep"]);
    assert_eq!(v["score"], v["max_score"], "{v}");
    let named: Vec<&Value> = v["tests"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|t| t["name"] == "three-spheres.toml (160, 150): raystep's own output")
        .collect();
    assert_eq!(named.len(), 1, "{v}");
    assert_eq!(named[0]["max_score"], 0.0);
    assert!(
        named[0]["output"]
            .as_str()
            .unwrap()
            .contains("raystep's own trace text"),
        "{v}"
    );
}

/// A tracer of its own is not named: raystep's output with every number rounded differently
/// (to 9 significant digits, as a float64 tracer's would differ) is not raystep's text.
#[test]
fn a_tracer_of_its_own_is_not_named_a_copy() {
    let s = raystep::scene::load_file(&root().join("scenes/three-spheres.toml")).unwrap();
    let e =
        raystep::student::expected::expected(&raystep::PreparedScene::new(s).record(160, 150, 0));
    let text = raystep::student::format::write(&e.pixel);
    assert!(raystep::student::isolate::is_raysteps_text(&text, &text));
    let mut own = String::new();
    for l in text.lines() {
        let mut v: Value = serde_json::from_str(l).unwrap();
        fn perturb(v: &mut Value) {
            match v {
                Value::Number(n) if n.as_f64().is_some_and(|x| x.fract() != 0.0) => {
                    let x = n.as_f64().unwrap() * (1.0 + 3e-8);
                    *v = serde_json::json!(x);
                }
                Value::Array(a) => a.iter_mut().for_each(perturb),
                Value::Object(o) => o.values_mut().for_each(perturb),
                _ => {}
            }
        }
        perturb(&mut v);
        own += &(v.to_string() + "\n");
    }
    assert!(!raystep::student::isolate::is_raysteps_text(&own, &text));
    let _ = Path::new(".");
}
