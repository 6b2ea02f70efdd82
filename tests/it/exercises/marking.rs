//! Marking: every shipped sheet against answers read from the trace, variants, hints, a hand
//! computation, the sheet's feedback, solutions, built-in sheets by name.

use super::*;

#[test]
fn at_least_three_sheets_ship_and_load() {
    let s = sheets();
    assert!(s.len() >= 3, "{s:?}");
    for p in &s {
        let sheet = lesson::load_exercise_sheet(p).unwrap_or_else(|e| panic!("{e}"));
        assert!(!sheet.questions.is_empty());
        for q in &sheet.questions {
            assert!(
                !q.hints.is_empty(),
                "{}: {} has no hints",
                p.display(),
                q.id
            );
        }
    }
}

#[test]
fn every_shipped_sheet_marks_answers_read_from_the_trace() {
    for path in sheets() {
        let sheet = lesson::load_exercise_sheet(&path).unwrap();
        for student in STUDENTS {
            let mut right = String::new();
            let mut wrong = String::new();
            for q in &sheet.questions {
                let a = read_quantity(&record(&sheet, q, student), q);
                right += &format!("{} = {}\n", q.id, a.text());
                wrong += &format!(
                    "{} = {}\n",
                    q.id,
                    a.perturbed(q.tolerance.abs, q.tolerance.rel)
                );
            }
            let marks = check(&path, student, &right);
            for m in marks["questions"].as_array().unwrap() {
                assert_eq!(
                    m["right"],
                    true,
                    "{} / {student}: {m}\nanswers:\n{right}",
                    path.display()
                );
            }
            assert_eq!(marks["score"], marks["out_of"]);
            let marks = check(&path, student, &wrong);
            for m in marks["questions"].as_array().unwrap() {
                assert_eq!(
                    m["right"],
                    false,
                    "{} / {student}: {m}\nanswers:\n{wrong}",
                    path.display()
                );
            }
            assert_eq!(marks["score"], 0.0);
        }
    }
}

#[test]
fn variants_differ_between_students_and_repeat_for_one() {
    for path in sheets() {
        let sheet = lesson::load_exercise_sheet(&path).unwrap();
        for q in &sheet.questions {
            let varied = !q.params.is_empty()
                || q.pixel
                    .iter()
                    .any(|c| matches!(c, lesson::Coord::Range(..)));
            let vs: Vec<_> = STUDENTS.iter().map(|s| sheet.variant(q, s)).collect();
            for (s, v) in STUDENTS.iter().zip(&vs) {
                assert_eq!(&sheet.variant(q, s), v, "{}: {}", path.display(), q.id);
            }
            if varied {
                assert!(
                    vs.iter().any(|v| v != &vs[0]),
                    "{}: {} is the same for every student",
                    path.display(),
                    q.id
                );
            }
        }
        // The command prints the same questions for the same id, different ones for another.
        let run = |s: &str| {
            raystep()
                .arg("exercise")
                .arg(&path)
                .args(["--student", s, "--json"])
                .assert()
                .success()
                .get_output()
                .stdout
                .clone()
        };
        assert_eq!(run("s1001"), run("s1001"));
        assert_ne!(run("s1001"), run("s1002"));
    }
}

#[test]
fn hints_are_revealed_one_at_a_time() {
    let path = root().join("lessons/exercises/02-sphere.toml");
    let json = |n: &str| -> Value {
        let out = raystep()
            .arg("exercise")
            .arg(&path)
            .args(["--student", "x", "--json", "--hints", n])
            .assert()
            .success()
            .get_output()
            .stdout
            .clone();
        serde_json::from_slice(&out).unwrap()
    };
    let sheet = lesson::load_exercise_sheet(&path).unwrap();
    for n in 0..3 {
        let doc = json(&n.to_string());
        for (q, j) in sheet
            .questions
            .iter()
            .zip(doc["questions"].as_array().unwrap())
        {
            let shown: Vec<&str> = j["hints"]
                .as_array()
                .unwrap()
                .iter()
                .map(|h| h.as_str().unwrap())
                .collect();
            let want: Vec<&str> = q.hints.iter().take(n).map(String::as_str).collect();
            assert_eq!(shown, want);
        }
    }
}

#[test]
fn the_discriminant_and_t_match_a_hand_computation() {
    // The eye at (0, 0, −5) looks at a unit sphere at the origin through the centre of a 1 × 1
    // image, so d = (0, 0, 1): a = d·d = 1, f = (0, 0, −5), b = 2 f·d = −10, c = f·f − 1 = 24,
    // Δ = b² − 4ac = 100 − 96 = 4, and the near root t = (10 − √4)/2 = 4.
    let dir = tempfile::tempdir().unwrap();
    let sheet_path = dir.path().join("hand.toml");
    std::fs::write(&sheet_path, HAND_SHEET).unwrap();
    let sheet = lesson::load_exercise_sheet(&sheet_path).unwrap();
    let expected: Vec<lesson::Answer> = sheet
        .questions
        .iter()
        .map(|q| sheet.expected(q, &sheet.variant(q, "anyone")).unwrap())
        .collect();
    assert_eq!(
        expected,
        vec![lesson::Answer::Number(4.0), lesson::Answer::Number(4.0)]
    );
    let marks = check(&sheet_path, "anyone", "disc = 4\nt = 4.0\n");
    assert_eq!(marks["score"], 2.0, "{marks}");
    let marks = check(&sheet_path, "anyone", "disc = 4.01\nt = 3.99\n");
    assert_eq!(marks["score"], 0.0, "{marks}");
    let q = &marks["questions"][0];
    assert!(
        (q["abs_error"].as_f64().unwrap() - 0.01).abs() < 1e-9,
        "{q}"
    );
    assert!(
        (q["rel_error"].as_f64().unwrap() - 0.0025).abs() < 1e-9,
        "{q}"
    );
}

#[test]
fn feedback_is_the_sheets_choice_and_defaults_to_right_or_wrong() {
    let parse = |head: &str| {
        lesson::parse_exercise_sheet(
            &small_sheet(head, "quantity = \"closest_t\""),
            "s.toml",
            None,
            "s",
        )
    };
    assert_eq!(parse("").unwrap().feedback, lesson::Feedback::RightWrong);
    assert_eq!(
        parse("feedback = \"direction\"\n").unwrap().feedback,
        lesson::Feedback::Direction
    );
    assert_eq!(
        parse("feedback = \"distance\"\n").unwrap().feedback,
        lesson::Feedback::Distance
    );
    assert_eq!(
        parse("feedback = { show_after = 3 }\n").unwrap().feedback,
        lesson::Feedback::ShowAfter(3)
    );
    let e = parse("feedback = \"loud\"\n").unwrap_err();
    assert_eq!((e.line, e.column), (Some(1), Some(12)), "{e}");
    assert!(parse("feedback = { show_after = 0 }\n").is_err());
    // Every shipped sheet keeps the default or says which policy it uses.
    for path in sheets() {
        lesson::load_exercise_sheet(&path).unwrap();
    }
}

#[test]
fn check_uses_the_sheets_feedback_and_a_byte_order_mark_is_fine() {
    let dir = tempfile::tempdir().unwrap();
    let sheet_path = dir.path().join("hand.toml");
    // The hand sheet with the default feedback: right or wrong and why, no distance.
    std::fs::write(
        &sheet_path,
        HAND_SHEET.replace("feedback = \"distance\"\n", ""),
    )
    .unwrap();
    let answers = dir.path().join("a.txt");
    std::fs::write(&answers, "\u{feff}disc = 5\nt = none\n").unwrap();
    let out = raystep()
        .args(["check".as_ref(), sheet_path.as_os_str()])
        .args(["--student", "x", "--answers"])
        .arg(&answers)
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let out = String::from_utf8(out).unwrap();
    // Δ = 4, the answer 5: wrong, not within the tolerance — and nothing that gives 4 away.
    let disc = out.lines().find(|l| l.starts_with("disc")).unwrap();
    assert!(
        disc.contains("wrong") && disc.contains("tolerance"),
        "{out}"
    );
    assert!(!disc.contains("off by"), "{out}");
    let t = out.lines().find(|l| l.starts_with("t ")).unwrap();
    assert!(t.contains("wrong") && t.contains("not none"), "{out}");
}

/// `raystep exercise 02-sphere` takes a built-in sheet by name, from any folder, as scenes are
/// taken by name; `check` and `grade` too. A name that is no sheet lists the names.
#[test]
fn a_built_in_sheet_is_taken_by_name_from_any_folder() {
    let dir = tempfile::tempdir().unwrap();
    let json = |sheet: &str, cwd: &Path| -> Value {
        let out = raystep()
            .current_dir(cwd)
            .args(["exercise", sheet, "--student", "s1001", "--json"])
            .assert()
            .success()
            .get_output()
            .stdout
            .clone();
        serde_json::from_slice(&out).unwrap()
    };
    let by_file = json("lessons/exercises/02-sphere.toml", &root());
    for name in ["02-sphere", "02-sphere.toml", "exercises/02-sphere.toml"] {
        let by_name = json(name, dir.path());
        assert_eq!(by_name["title"], by_file["title"], "{name}");
        let texts = |v: &Value| -> Vec<Value> {
            v["questions"]
                .as_array()
                .unwrap()
                .iter()
                .map(|q| q["text"].clone())
                .collect()
        };
        assert_eq!(texts(&by_name), texts(&by_file), "{name}");
    }
    let answers = dir.path().join("answers.txt");
    std::fs::write(&answers, "disc = 1\n").unwrap();
    raystep()
        .current_dir(dir.path())
        .args(["check", "02-sphere", "--student", "s1001", "--answers"])
        .arg(&answers)
        .assert()
        .success();
    let class = dir.path().join("class.csv");
    std::fs::write(&class, "student,disc\ns1001,1\n").unwrap();
    raystep()
        .current_dir(dir.path())
        .args(["grade", "02-sphere"])
        .arg(&class)
        .args(["-o", "grades.csv"])
        .assert()
        .success();
    assert!(dir.path().join("grades.csv").is_file());
    fails(
        &[
            "exercise".as_ref(),
            "02-spheres".as_ref(),
            "--student".as_ref(),
            "s".as_ref(),
        ],
        &["02-spheres", "built-in sheets: 01-camera, 02-sphere"],
    );
}

/// `--solutions` writes each number with the digits `raystep trace` prints for it (5.573929,
/// not the f64 widening 5.5739288330078125): each numeric solution appears, as written, in the
/// trace of its question's pixel.
#[test]
fn solutions_are_written_as_the_trace_writes_them() {
    let dir = tempfile::tempdir().unwrap();
    let scenes = dir.path().join("scenes");
    std::fs::create_dir(&scenes).unwrap();
    let mut numbers = 0;
    for sheet in ["02-sphere", "04-triangle", "09-refraction"] {
        let path = format!("lessons/exercises/{sheet}.toml");
        let out = raystep()
            .args([
                "exercise",
                &path,
                "--student",
                "s1001",
                "--solutions",
                "--json",
            ])
            .arg("--scenes")
            .arg(&scenes)
            .assert()
            .success()
            .get_output()
            .stdout
            .clone();
        let v: Value = serde_json::from_slice(&out).unwrap();
        for q in v["questions"].as_array().unwrap() {
            let solution = q["solution"].as_str().unwrap();
            let parts: Vec<&str> = solution.split(", ").collect();
            if !parts.iter().all(|p| p.parse::<f64>().is_ok()) {
                continue; // a name, yes/no or none
            }
            let scene = q["scene"].as_str().expect("a scene to trace");
            let pixel = format!("{},{}", q["pixel"][0], q["pixel"][1]);
            let trace = raystep()
                .args(["trace", scene, "--pixel", &pixel])
                .assert()
                .success()
                .get_output()
                .stdout
                .clone();
            let trace = String::from_utf8(trace).unwrap();
            for p in parts {
                // Not a prefix of a longer number: "4.5" must not match "4.55".
                let found = trace.match_indices(p).any(|(k, _)| {
                    let next = trace[k + p.len()..].chars().next();
                    let prev = trace[..k].chars().last();
                    !next.is_some_and(|c| c.is_ascii_digit() || c == '.' || c == 'e')
                        && !prev.is_some_and(|c| c.is_ascii_digit() || c == '.')
                });
                assert!(
                    found,
                    "{sheet} {}: the solution's {p} is not in the trace of {scene} {pixel}:\n{trace}",
                    q["id"]
                );
                numbers += 1;
            }
        }
    }
    assert!(
        numbers >= 10,
        "only {numbers} numeric solutions were compared"
    );
}
