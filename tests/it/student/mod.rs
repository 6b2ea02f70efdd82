//! The student trace format and `raystep grade-tracer`: reading the format (and refusing bad
//! output with its line), raystep's own trace graded full marks, mistakes planted by hand in
//! raystep's output found at the right ray and quantity and named, programs that crash, hang,
//! print garbage, NaN or far too much graded zero with a message while the other tests run,
//! Gradescope's `results.json` checked against its documented shape, and a class run's CSV.

use assert_cmd::Command;
use raystep::student::compare::{Stage, TracerTolerances, grade};
use raystep::student::expected::{Expected, expected};
use raystep::student::format::{self, Test, parse, write};
use serde_json::Value;
use std::path::Path;

use crate::common::scenes;
use scenes::{root, shipped_whitted as shipped};

fn traced(scene: &Path, x: u32, y: u32) -> Expected {
    let s = raystep::scene::load_file(scene).unwrap();
    expected(&raystep::PreparedScene::new(s).record(x, y, 0))
}

/// Every record type read by hand: which ray each record lands on (a `color` naming depth 0
/// after a child goes back to the primary ray; a `shadow` record after a shadow ray goes to the
/// lit ray), nulls as misses, comments and unknown record types skipped.
#[test]
fn the_format_reads_every_record_where_it_belongs() {
    let text = r#"{"type":"format","version":1}
# a comment
{"type":"pixel","x":3,"y":4}
{"type":"ray","kind":"primary","depth":0,"origin":[0,0,0],"direction":[0,0,2]}
{"type":"my-own-bounding-sphere","hit":true}
{"type":"sphere","object":"ball","a":4,"b":-20,"c":21,"discriminant":64,"t":1.5}
{"type":"plane","object":"floor","denominator":0,"t":null}
{"type":"triangle","object":"tri","det":-2,"u":0.25,"v":0.5,"t":3}
{"type":"hit","object":"ball","t":1.5,"point":[0,0,3],"normal":[0,0,-1]}
{"type":"ray","kind":"shadow","depth":1,"origin":[0,0,2.9],"direction":[1,1,-1],"light":"key"}
{"type":"sphere","object":"ball","t":null}
{"type":"shadow","light":"key","blocked":false}
{"type":"surface","normal":[0,0.6,-0.8],"uv":[1.25,-0.5],"texel":[-1,7],"texture":[0.5,0.5,0.5],"depth":0}
{"type":"color","rgb":[0.5,0.25,0],"depth":0}
"#;
    let px = parse(text).unwrap();
    assert_eq!(px.len(), 1);
    let p = &px[0];
    assert_eq!(p.at, Some([3, 4]));
    assert_eq!(p.rays.len(), 2);
    let (primary, shadow) = (&p.rays[0], &p.rays[1]);
    assert_eq!(primary.tests.len(), 3);
    assert_eq!(
        primary.tests[0],
        Test::Sphere {
            object: "ball".into(),
            abcd: [Some(4.0), Some(-20.0), Some(21.0), Some(64.0)],
            t: Some(Some(1.5))
        }
    );
    assert_eq!(
        primary.tests[1],
        Test::Plane {
            object: "floor".into(),
            denominator: Some(0.0),
            t: Some(None)
        }
    );
    assert_eq!(
        primary.hit.clone().unwrap().unwrap().point,
        Some([0.0, 0.0, 3.0])
    );
    assert_eq!(primary.shadows, vec![("key".to_string(), Some(false))]);
    assert_eq!(primary.color, Some([0.5, 0.25, 0.0]));
    // The `surface` record after the shadow ray goes, by its depth, to the primary ray.
    assert_eq!(
        primary.surface,
        Some(raystep::student::format::Surface {
            normal: Some([0.0, 0.6, -0.8]),
            uv: Some([1.25, -0.5]),
            texel: Some([-1, 7]),
            texture: Some([0.5; 3]),
        })
    );
    assert_eq!(shadow.surface, None);
    // A texel is a pair of integers: 2.5 is refused, naming the record and its line.
    let e = parse("{\"type\":\"ray\"}\n{\"type\":\"surface\",\"texel\":[2.5,1]}\n").unwrap_err();
    assert_eq!(e.line, 2);
    assert!(
        e.message
            .contains("a \"surface\" record the format cannot read"),
        "{e}"
    );
    assert_eq!(shadow.parent, Some(0));
    assert_eq!(shadow.light.as_deref(), Some("key"));
    assert_eq!(shadow.tests.len(), 1);
    assert_eq!(shadow.color, None);
}

/// Lesson 20's records: the tests after an `instance` record are of its prototype, named as
/// raystep names an instanced hit (`gem near → gem[9]`), until the next `instance` record; a
/// test's own `instance` key (null: the world's) overrides that; a hit names its instance. What
/// `write` prints reads back the same.
#[test]
fn instance_records_name_their_prototypes_tests() {
    let text = r#"{"type":"ray","kind":"primary","depth":0,"origin":[0,0,0],"direction":[0,0,1]}
{"type":"plane","object":"floor","denominator":0,"t":null}
{"type":"instance","name":"gem near","origin":[1,2,3],"direction":[0,0,5]}
{"type":"triangle","object":"gem[9]","det":1,"u":0.1,"v":0.2,"t":2}
{"type":"sphere","object":"ball","instance":null,"t":null}
{"type":"instance","name":"egg","origin":[0,0,0],"direction":[0,0,1]}
{"type":"sphere","object":"ball","t":3}
{"type":"sphere","object":"ball","instance":"marble","t":null}
{"type":"hit","instance":"gem near","object":"gem[9]","t":2,"point":[0,0,2],"normal":[0,0,-1]}
"#;
    let px = parse(text).unwrap();
    let r = &px[0].rays[0];
    let names: Vec<&str> = r.tests.iter().map(Test::object).collect();
    assert_eq!(
        names,
        [
            "floor",
            "gem near → gem[9]",
            "ball",
            "egg → ball",
            "marble → ball"
        ]
    );
    assert_eq!(r.instances.len(), 2);
    assert_eq!(
        (r.instances[0].name.as_str(), r.instances[0].first_test),
        ("gem near", 1)
    );
    assert_eq!(r.instances[0].origin, Some([1.0, 2.0, 3.0]));
    assert_eq!(r.instances[0].direction, Some([0.0, 0.0, 5.0]));
    assert_eq!((r.instances[1].first_test, r.instances[1].line), (3, 6));
    assert_eq!(
        r.hit.clone().unwrap().unwrap().object.as_deref(),
        Some("gem near → gem[9]")
    );
    let mut back = parse(&write(&px[0])).unwrap().remove(0);
    for r in &mut back.rays {
        r.line = 1;
        for (i, line) in r.instances.iter_mut().zip([3, 6]) {
            i.line = line;
        }
    }
    assert_eq!(back.rays, px[0].rays);
}

/// Output the checker cannot use is refused with its line: not JSON, no type, a known record
/// with a value of the wrong kind, NaN (not JSON), an overflowing number, a child ray with no
/// parent, a format version from the future.
#[test]
fn bad_output_is_refused_with_its_line() {
    let ray = r#"{"type":"ray","kind":"primary","depth":0}"#;
    for (text, line, words) in [
        (format!("{ray}\nhello world"), 2, "not a JSON object"),
        (format!("{ray}\n{{\"t\":1}}"), 2, "needs a \"type\""),
        (
            format!("{ray}\n{{\"type\":\"sphere\",\"a\":\"one\"}}"),
            2,
            "\"sphere\" record",
        ),
        (
            format!("{ray}\n{{\"type\":\"sphere\",\"a\":NaN}}"),
            2,
            "not a JSON object",
        ),
        (format!("{ray}\n{{\"type\":\"sphere\",\"a\":1e999}}"), 2, ""),
        (
            "{\"type\":\"ray\",\"kind\":\"shadow\",\"depth\":1}".to_string(),
            1,
            "no ray of depth 0",
        ),
        (
            "{\"type\":\"format\",\"version\":7}".to_string(),
            1,
            "version 7",
        ),
        (
            format!("{ray}\n{{\"type\":\"ray\",\"kind\":\"laser\"}}"),
            2,
            "ray kind",
        ),
    ] {
        let e = parse(&text).unwrap_err();
        assert_eq!(e.line, line, "{text}: {e}");
        assert!(e.message.contains(words), "{text}: {e}");
    }
}

/// raystep's own trace written in the format reads back as the same pixel, and is graded full
/// marks at every stage, on every shipped scene at a grid of pixels.
#[test]
fn raystep_graded_against_itself_gets_full_marks() {
    for scene in shipped() {
        let s = raystep::scene::load_file(&scene).unwrap();
        let (w, h) = (s.camera.width, s.camera.height);
        let prepared = raystep::PreparedScene::new(s);
        // On `instances.toml`, also the egg (a non-uniformly scaled sphere) and the tall gem.
        let mut pixels = vec![(0, 0), (w / 2, h / 2), (w - 1, h - 1), (w / 3, 2 * h / 3)];
        if scene.ends_with("instances.toml") {
            pixels.extend([(110, 104), (210, 72)]);
        }
        for (x, y) in pixels {
            let ours = expected(&prepared.record(x, y, 0));
            let back = parse(&write(&ours.pixel)).unwrap();
            let mut again = back[0].clone();
            for r in &mut again.rays {
                r.line = 0;
                for i in &mut r.instances {
                    i.line = 0;
                }
            }
            assert_eq!(again, ours.pixel, "{} ({x}, {y})", scene.display());
            for c in grade(&ours, &back, Stage::Color, &TracerTolerances::default()) {
                assert!(c.pass, "{} ({x}, {y}): {c:?}", scene.display());
            }
        }
    }
}

/// The first failing check of a grading, as (stage, message).
fn first_failure(e: &Expected, text: &str) -> Option<(Stage, String)> {
    grade(
        e,
        &parse(text).unwrap(),
        Stage::Color,
        &TracerTolerances::default(),
    )
    .into_iter()
    .find(|c| !c.pass)
    .map(|c| (c.stage, c.message))
}

/// Edits the JSON record of `ty` number `k` (0-based) in raystep's output.
fn edit(text: &str, ty: &str, k: usize, f: impl Fn(&mut Value)) -> String {
    let mut seen = 0;
    let mut out = String::new();
    for l in text.lines() {
        let mut v: Value = serde_json::from_str(l).unwrap();
        if v["type"] == ty {
            if seen == k {
                f(&mut v);
            }
            seen += 1;
        }
        out += &v.to_string();
        out.push('\n');
    }
    out
}

/// Mistakes planted by hand in raystep's own output are found at the right stage and quantity,
/// and the common ones are named: b without its 2, a normal not normalized or not flipped, a
/// light said blocked, a wrong colour, a missing hit; skipped tests, shuffled tests and a
/// student's own extra records are not errors.
/// Multiplies a `hit` record's normal by `k`.
fn scale_normal(v: &mut Value, k: f64) {
    let n: Vec<f64> = v["normal"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| k * x.as_f64().unwrap())
        .collect();
    v["normal"] = Value::from(n);
}

#[test]
fn planted_mistakes_are_found_and_named() {
    let scene = root().join("scenes/mirror-glass.toml");
    let e = traced(&scene, 200, 150);
    let ours = write(&e.pixel);
    assert_eq!(first_failure(&e, &ours), None);

    // The hit sphere is "red ball": its record is the 4th sphere test of the primary ray.
    let halved = edit(&ours, "sphere", 3, |v| {
        let b = v["b"].as_f64().unwrap();
        v["b"] = Value::from(b / 2.0);
    });
    let (st, msg) = first_failure(&e, &halved).unwrap();
    assert_eq!(st, Stage::Sphere);
    assert!(
        msg.contains("sphere \"red ball\"") && msg.contains("your b is"),
        "{msg}"
    );
    assert!(msg.contains("looks like f·Q"), "{msg}");
    assert!(msg.starts_with("ray 0 (the primary ray"), "{msg}");

    let flipped = edit(&ours, "hit", 0, |v| scale_normal(v, -1.0));
    let (st, msg) = first_failure(&e, &flipped).unwrap();
    assert_eq!(st, Stage::ClosestHit);
    assert!(msg.contains("points away from the ray"), "{msg}");

    let long = edit(&ours, "hit", 0, |v| scale_normal(v, 2.0));
    let (_, msg) = first_failure(&e, &long).unwrap();
    assert!(msg.contains("has length 2.000: normalize it"), "{msg}");

    let blocked = edit(&ours, "shadow", 0, |v| v["blocked"] = Value::from(true));
    let (st, msg) = first_failure(&e, &blocked).unwrap();
    assert_eq!(st, Stage::Shadows);
    assert!(
        msg.contains("light \"key\": you say blocked, raystep says not blocked"),
        "{msg}"
    );

    let dark = edit(&ours, "color", 0, |v| {
        v["rgb"] = Value::from(vec![0.0, 0.0, 0.0])
    });
    let (st, msg) = first_failure(&e, &dark).unwrap();
    assert_eq!(st, Stage::Color);
    assert!(msg.contains("the pixel's colour is (0, 0, 0)"), "{msg}");

    let no_hit: String = ours
        .lines()
        .filter(|l| !l.contains("\"type\":\"hit\""))
        .map(|l| format!("{l}\n"))
        .collect();
    let (st, msg) = first_failure(&e, &no_hit).unwrap();
    assert_eq!(st, Stage::ClosestHit);
    assert!(msg.contains("no `hit` record"), "{msg}");

    // Skipped tests (no plane records past the primary ray's), reversed test order and extra
    // records: still right. (Skipping every plane test of the pixel is printing nothing for
    // the plane-triangle stage: tests/it/grader_hardening.rs.)
    let mut lenient = vec![];
    let mut tests = vec![];
    let mut rays = 0;
    for l in ours.lines() {
        rays += l.contains("\"type\":\"ray\"") as usize;
        if l.contains("\"type\":\"plane\"") && rays > 1 {
            continue;
        }
        if l.contains("\"type\":\"sphere\"") {
            tests.push(l.to_string());
            continue;
        }
        if !tests.is_empty() {
            lenient.extend(tests.drain(..).rev());
            lenient.push("{\"type\":\"bounding-sphere\",\"object\":\"all\",\"hit\":true}".into());
        }
        lenient.push(l.to_string());
    }
    let lenient = lenient.join("\n");
    assert_eq!(first_failure(&e, &lenient), None, "{lenient}");
}

/// A student's direction of another length gives the same verdicts: t, a, b and the
/// discriminant are compared as if the direction were unit length.
#[test]
fn a_longer_direction_scales_t_and_the_coefficients() {
    let e = traced(&root().join("scenes/three-spheres.toml"), 160, 120);
    let k = 3.0;
    let mut text = String::new();
    let mut depth_scale = vec![];
    for l in write(&e.pixel).lines() {
        let mut v: Value = serde_json::from_str(l).unwrap();
        let mul = |v: &mut Value, key: &str, f: f64| {
            if let Some(x) = v[key].as_f64() {
                v[key] = Value::from(x * f);
            }
        };
        match v["type"].as_str().unwrap() {
            "ray" => {
                let d: Vec<f64> = v["direction"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|x| k * x.as_f64().unwrap())
                    .collect();
                v["direction"] = Value::from(d);
                depth_scale.push(());
            }
            "sphere" => {
                mul(&mut v, "a", k * k);
                mul(&mut v, "b", k);
                mul(&mut v, "discriminant", k * k);
                mul(&mut v, "t", 1.0 / k);
            }
            "plane" => {
                mul(&mut v, "denominator", k);
                mul(&mut v, "t", 1.0 / k);
            }
            "triangle" => {
                mul(&mut v, "det", k);
                mul(&mut v, "t", 1.0 / k);
            }
            "hit" => mul(&mut v, "t", 1.0 / k),
            _ => {}
        }
        text += &v.to_string();
        text.push('\n');
    }
    assert!(!depth_scale.is_empty());
    assert_eq!(first_failure(&e, &text), None);
}

fn raystep() -> Command {
    Command::cargo_bin("raystep").unwrap()
}

/// A Python program for the run tests.
fn script(dir: &Path, name: &str, body: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, body).unwrap();
    format!("python3 {}", p.display())
}

/// `raystep` itself as the student's program: its `trace --format student`.
fn raystep_as_student() -> String {
    format!(
        "'{}' trace {{scene}} --pixel {{x}},{{y}} --format student",
        env!("CARGO_BIN_EXE_raystep")
    )
}

/// Programs that crash, hang, print garbage, print NaN or print 10⁸ lines: each pixel's tests
/// score zero with a message saying what happened; the grading itself succeeds (exit 0) and the
/// good pixels of a program that fails on only one are still graded.
#[test]
fn misbehaving_programs_score_zero_with_a_message() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/first-sphere.toml");
    let grade_with = |run: &str, extra: &[&str]| -> Value {
        let mut args = vec![
            "grade-tracer".to_string(),
            "--scene".into(),
            scene.display().to_string(),
            "--pixels".into(),
            "160,120;10,10".into(),
            "--upto".into(),
            "camera".into(),
            "--json".into(),
            "--allow-raystep".into(),
            "--run".into(),
            run.into(),
        ];
        args.extend(extra.iter().map(|s| s.to_string()));
        let out = raystep()
            .args(&args)
            .assert()
            .success()
            .get_output()
            .clone();
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let cases = [
        (
            script(
                dir.path(),
                "crash.py",
                "raise SystemExit('segfault, sort of')\n",
            ),
            vec![],
            "your program failed",
        ),
        (
            script(dir.path(), "hang.py", "import time\ntime.sleep(60)\n"),
            vec!["--timeout", "1"],
            "ran longer than 1.0 s",
        ),
        (
            script(dir.path(), "garbage.py", "print('hello, grader')\n"),
            vec![],
            "line 1: not a JSON object",
        ),
        (
            script(
                dir.path(),
                "nan.py",
                "print('{\"type\":\"ray\",\"kind\":\"primary\",\"origin\":[NaN,0,0]}')\n",
            ),
            vec![],
            "line 1: not a JSON object",
        ),
        (
            script(
                dir.path(),
                "flood.py",
                "import sys\nfor i in range(10**8):\n    sys.stdout.write('{\"type\":\"pixel\"}\\n')\n",
            ),
            vec!["--max-output-mb", "1"],
            "printed more than 1 MB",
        ),
    ];
    for (run, extra, words) in cases {
        let v = grade_with(&run, &extra);
        assert_eq!(v["score"], 0.0, "{run}: {v}");
        let tests = v["tests"].as_array().unwrap();
        assert_eq!(tests.len(), 2, "{v}");
        for t in tests {
            assert!(t["output"].as_str().unwrap().contains(words), "{run}: {t}");
        }
    }
    // Right at one pixel, crashing at the other: that pixel alone scores zero.
    let half = script(
        dir.path(),
        "half.py",
        &format!(
            "import subprocess, sys\nif sys.argv[2] == '10': sys.exit(2)\nsubprocess.run(['{}', 'trace', sys.argv[1], '--pixel', sys.argv[2] + ',' + sys.argv[3], '--format', 'student'])\n",
            env!("CARGO_BIN_EXE_raystep")
        ),
    );
    let v = grade_with(&format!("{half} {{scene}} {{x}} {{y}}"), &[]);
    assert_eq!(v["score"], 1.0, "{v}");
    assert_eq!(v["max_score"], 2.0, "{v}");
}

/// `--json` prints Gradescope's `results.json` as its documentation describes it: a numeric
/// `score`, `execution_time`, `output`, `visibility` and `stdout_visibility` from the documented
/// values, and `tests`, each with a string `name`, numeric `score` ≤ `max_score`, string
/// `output` and `visibility`; no other keys than the documented ones (plus `max_score`, which
/// the issue asks for at the top level).
#[test]
fn results_json_has_gradescopes_documented_shape() {
    let scene = root().join("scenes/three-spheres.toml");
    let out = raystep()
        .args([
            "grade-tracer",
            "--scene",
            &scene.display().to_string(),
            "--pixels",
            "160,120;20,20",
            "--json",
            "--allow-raystep",
            "--run",
            &raystep_as_student(),
        ])
        .assert()
        .success()
        .get_output()
        .clone();
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let documented = [
        "score",
        "max_score",
        "execution_time",
        "output",
        "output_format",
        "test_output_format",
        "test_name_format",
        "visibility",
        "stdout_visibility",
        "extra_data",
        "tests",
        "leaderboard",
    ];
    let visibilities = ["hidden", "after_due_date", "after_published", "visible"];
    let obj = v.as_object().unwrap();
    for k in obj.keys() {
        assert!(documented.contains(&k.as_str()), "undocumented key {k}");
    }
    assert!(v["score"].is_number() && v["execution_time"].is_number());
    assert!(visibilities.contains(&v["visibility"].as_str().unwrap()));
    assert!(visibilities.contains(&v["stdout_visibility"].as_str().unwrap()));
    let tests = v["tests"].as_array().unwrap();
    // Two pixels × seven stages, and raystep's own output named at each pixel (0 points).
    assert_eq!(
        tests.len(),
        2 * 7 + 2,
        "two pixels × seven stages, two named copies"
    );
    assert_eq!(
        tests.iter().filter(|t| t["max_score"] == 0.0).count(),
        2,
        "{v}"
    );
    let test_keys = [
        "score",
        "max_score",
        "status",
        "name",
        "name_format",
        "number",
        "output",
        "output_format",
        "tags",
        "visibility",
        "extra_data",
    ];
    for t in tests {
        for k in t.as_object().unwrap().keys() {
            assert!(test_keys.contains(&k.as_str()), "undocumented test key {k}");
        }
        assert!(t["name"].is_string() && t["output"].is_string());
        assert!(t["score"].as_f64().unwrap() <= t["max_score"].as_f64().unwrap());
        assert!(visibilities.contains(&t["visibility"].as_str().unwrap()));
    }
    assert_eq!(v["score"], 14.0, "raystep itself: full marks: {v}");
}

/// A class run over a folder of submissions (a good one, one that crashes, one that hangs)
/// writes the grades CSV (one row each, a column per stage) and each student's text and JSON
/// report; the hanging one is stopped at the time limit.
#[test]
fn a_class_run_writes_the_grades_csv() {
    let class = tempfile::tempdir().unwrap();
    let out = tempfile::tempdir().unwrap();
    for who in ["ada", "bob", "cy"] {
        std::fs::create_dir(class.path().join(who)).unwrap();
    }
    // Each submission is its folder's tracer.py; ada's runs raystep itself.
    std::fs::write(
        class.path().join("ada/tracer.py"),
        format!(
            "import subprocess, sys\nsubprocess.run(['{}', 'trace', sys.argv[1], '--pixel', sys.argv[2] + ',' + sys.argv[3], '--format', 'student'])\n",
            env!("CARGO_BIN_EXE_raystep")
        ),
    )
    .unwrap();
    std::fs::write(class.path().join("bob/tracer.py"), "1/0\n").unwrap();
    std::fs::write(
        class.path().join("cy/tracer.py"),
        "import time\ntime.sleep(30)\n",
    )
    .unwrap();
    let scene = root().join("scenes/first-sphere.toml");
    let csv = out.path().join("grades.csv");
    raystep()
        .args([
            "grade-tracer",
            "--class",
            &class.path().display().to_string(),
            "--scene",
            &scene.display().to_string(),
            "--pixels",
            "160,120",
            "--upto",
            "closest-hit",
            "--timeout",
            "2",
            "--csv",
            &csv.display().to_string(),
            "--out",
            &out.path().display().to_string(),
            "--allow-raystep",
            "--run",
            "python3 tracer.py {scene} {x} {y}",
        ])
        .assert()
        .success();
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(
        rows[0],
        "student,score,max_score,camera,sphere,plane-triangle,closest-hit,surface,shadows,secondary,color,notes"
    );
    assert!(
        rows[1].starts_with("ada,4,4,1/1,1/1,1/1,1/1,,,,,"),
        "{text}"
    );
    assert!(rows[2].starts_with("bob,0,4,0/1,"), "{text}");
    assert!(rows[2].contains("ZeroDivisionError"), "{text}");
    assert!(rows[3].starts_with("cy,0,4,"), "{text}");
    assert!(rows[3].contains("longer than 2.0 s"), "{text}");
    for who in ["ada", "bob", "cy"] {
        let j: Value = serde_json::from_str(
            &std::fs::read_to_string(out.path().join(format!("{who}.json"))).unwrap(),
        )
        .unwrap();
        assert!(j["tests"].is_array());
        assert!(out.path().join(format!("{who}.txt")).exists());
    }
}

mod sheets;
