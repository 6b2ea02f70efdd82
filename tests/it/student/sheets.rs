//! Grading sheets, `raystep trace --format student`, the whole-image check and the argument checks.

use super::*;

/// A sheet draws each student's extra pixels from the student id (the same id, the same pixels;
/// another id, others), inside the image; a sheet with a pixel outside the image, an unknown key
/// or no scene is refused naming the file (and line for TOML errors).
#[test]
fn sheets_give_each_student_their_own_pixels() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/three-spheres.toml");
    let sheet = dir.path().join("cp1.toml");
    std::fs::write(
        &sheet,
        format!(
            "title = \"Checkpoint 1\"\nupto = \"sphere\"\n[[scene]]\nfile = \"{}\"\npixels = [[160, 120]]\nrandom_pixels = 3\n",
            scene.display()
        ),
    )
    .unwrap();
    let s = raystep::student::load_tracer_sheet(&sheet).unwrap();
    let pix = |who: &str| {
        raystep::student::sheet_jobs(
            &s,
            &sheet,
            who,
            &raystep::student::VariantDir::private().unwrap(),
        )
        .unwrap()[0]
            .pixels
            .clone()
    };
    let (a, a2, b) = (pix("ada"), pix("ada"), pix("bob"));
    assert_eq!(a, a2);
    assert_ne!(a, b);
    assert_eq!(a.len(), 4);
    assert_eq!(a[0], [160, 120]);
    assert!(a.iter().all(|[x, y]| *x < 320 && *y < 240), "{a:?}");
    for (body, words) in [
        (
            format!(
                "[[scene]]\nfile = \"{}\"\npixels = [[999, 0]]\n",
                scene.display()
            ),
            "outside its 320×240 image".to_string(),
        ),
        (
            "colour = 1\n[[scene]]\nfile = \"x.toml\"\n".to_string(),
            "cp1.toml:1:1".to_string(),
        ),
        (
            "title = \"none\"\nscene = []\n".to_string(),
            "lists no [[scene]]".to_string(),
        ),
    ] {
        std::fs::write(&sheet, &body).unwrap();
        let err = raystep::student::load_tracer_sheet(&sheet)
            .and_then(|s| {
                raystep::student::sheet_jobs(
                    &s,
                    &sheet,
                    "ada",
                    &raystep::student::VariantDir::private().unwrap(),
                )
                .map(|_| ())
            })
            .unwrap_err();
        assert!(err.contains(&words), "{body}: {err}");
    }
}

/// `raystep trace --format student` prints raystep's trace in the format (what a student
/// compares their own output with), which reads back as that pixel.
#[test]
fn trace_prints_the_student_format() {
    let scene = root().join("scenes/triangles.toml");
    let out = raystep()
        .args([
            "trace",
            &scene.display().to_string(),
            "--pixel",
            "80,130",
            "--format",
            "student",
        ])
        .assert()
        .success()
        .get_output()
        .clone();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with(
        "{\"type\":\"format\",\"version\":1}\n{\"type\":\"pixel\",\"x\":80,\"y\":130}\n"
    ));
    let px = format::parse(&text).unwrap();
    assert_eq!(px[0].at, Some([80, 130]));
    assert!(
        px[0].rays[0]
            .tests
            .iter()
            .any(|t| matches!(t, Test::Triangle { .. }))
    );
}

mod never_panics {
    use super::*;
    use proptest::prelude::*;

    /// raystep's own output for one pixel, cut into lines.
    fn lines() -> Vec<String> {
        let e = traced(&root().join("scenes/mirror-glass.toml"), 200, 150);
        write(&e.pixel).lines().map(str::to_string).collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// Any text, and raystep's output with lines dropped, repeated, swapped or with a
        /// number replaced, parses or is refused (never a panic), and whatever parses is graded
        /// without a panic.
        #[test]
        fn reading_and_grading_never_panic(
            junk in ".{0,200}",
            ops in proptest::collection::vec((0usize..64, 0usize..64, 0u8..4, -1e30f64..1e30), 0..12),
        ) {
            let _ = parse(&junk);
            let base = lines();
            let mut l = base.clone();
            for (a, b, op, x) in ops {
                let n = l.len().max(1);
                let (a, b) = (a % n, b % n);
                match op {
                    0 if !l.is_empty() => { l.remove(a); }
                    1 if !l.is_empty() => { let s = l[a].clone(); l.insert(b.min(l.len()), s); }
                    2 if !l.is_empty() => { let last = l.len() - 1; l.swap(a, b.min(last)); }
                    3 if !l.is_empty() => {
                        if let Ok(mut v) = serde_json::from_str::<Value>(&l[a]) {
                            if let Some(o) = v.as_object_mut() {
                                let keys: Vec<String> = o.keys().cloned().collect();
                                let k = &keys[b % keys.len()];
                                if k != "type" { o.insert(k.clone(), Value::from(x)); }
                            }
                            l[a] = v.to_string();
                        }
                    }
                    _ => {}
                }
            }
            let text = l.join("\n");
            if let Ok(px) = parse(&text) {
                let e = traced(&root().join("scenes/mirror-glass.toml"), 200, 150);
                let _ = grade(&e, &px, Stage::Color, &TracerTolerances::default());
            }
        }
    }
}

/// The whole-image check: raystep's own render (written by `raystep render`) passes with no
/// pixel off; the same image with a 20×20 block painted over has exactly 400 pixels off, fails,
/// and its difference image is red exactly there; an image of the wrong size or a missing file
/// fails with a message saying so.
#[test]
fn the_image_check_counts_the_pixels_off() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/first-sphere.toml");
    let png = dir.path().join("first-sphere.png");
    raystep()
        .args([
            "render",
            &scene.display().to_string(),
            "-o",
            &png.display().to_string(),
        ])
        .assert()
        .success();
    let check = |pattern: &str| -> Value {
        let out = raystep()
            .current_dir(dir.path())
            .args([
                "grade-tracer",
                "--scene",
                &scene.display().to_string(),
                "--pixels",
                "160,120",
                "--upto",
                "camera",
                "--json",
                "--run",
                &raystep_as_student(),
                "--image",
                pattern,
                "--diff",
                "diff-{stem}.png",
            ])
            .assert()
            .success()
            .get_output()
            .clone();
        let v: Value = serde_json::from_slice(&out.stdout).unwrap();
        v["tests"]
            .as_array()
            .unwrap()
            .iter()
            .find(|t| t["name"] == "first-sphere.toml: image")
            .cloned()
            .unwrap()
    };
    let t = check("{stem}.png");
    assert_eq!(t["score"], 1.0, "{t}");
    assert!(
        t["output"]
            .as_str()
            .unwrap()
            .starts_with("0 of 76800 pixels"),
        "{t}"
    );

    let mut img = image::open(&png).unwrap().to_rgb8();
    for y in 100..120 {
        for x in 10..30 {
            let p = img.get_pixel(x, y).0;
            img.put_pixel(x, y, image::Rgb([p[0] ^ 0x80, p[1], p[2]]));
        }
    }
    img.save(dir.path().join("painted.png")).unwrap();
    let t = check("painted.png");
    assert_eq!(t["score"], 0.0, "{t}");
    assert!(
        t["output"]
            .as_str()
            .unwrap()
            .starts_with("400 of 76800 pixels"),
        "{t}"
    );
    let diff = image::open(dir.path().join("diff-first-sphere.png"))
        .unwrap()
        .to_rgb8();
    for (x, y, p) in diff.enumerate_pixels() {
        let inside = (10..30).contains(&x) && (100..120).contains(&y);
        assert_eq!(p.0[0] >= 128 && p.0[1] == 0, inside, "({x}, {y}) {p:?}");
    }

    image::RgbImage::new(10, 10)
        .save(dir.path().join("small.png"))
        .unwrap();
    let t = check("small.png");
    assert!(
        t["output"]
            .as_str()
            .unwrap()
            .contains("your image is 10×10, the scene's is 320×240"),
        "{t}"
    );
    let t = check("missing.png");
    assert!(
        t["output"]
            .as_str()
            .unwrap()
            .contains("cannot read your image"),
        "{t}"
    );
}

/// Feedback on a built-in scene names it by its name in the commands it suggests, which work on
/// any machine — not by its unpacked copy's path (a cache folder named after the build).
#[test]
fn feedback_on_a_builtin_scene_names_it() {
    let kit = root().join("lessons/starter/tracer.py");
    let out = raystep()
        .args([
            "grade-tracer",
            "--scene",
            "three-spheres",
            "--pixels",
            "160,120",
        ])
        .args(["--upto", "sphere", "--run"])
        .arg(format!("python3 {} {{scene}} {{x}} {{y}}", kit.display()))
        .assert()
        .success()
        .get_output()
        .clone();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("raystep open three-spheres --pixel 160,120 --step 3\n")
            && text.contains("raystep trace three-spheres --pixel 160,120 (step [3])"),
        "{text}"
    );
    assert!(!text.contains("builtin-"), "{text}");
}

/// `--scene` takes a built-in scene's name too (the student's program gets its unpacked file);
/// bad arguments are refused with a message and a non-zero exit before anything runs.
#[test]
fn grade_tracer_arguments() {
    let out = raystep()
        .args([
            "grade-tracer",
            "--scene",
            "first-sphere",
            "--pixels",
            "160,120",
            "--allow-raystep",
            "--run",
            &raystep_as_student(),
        ])
        .assert()
        .success()
        .get_output()
        .clone();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("student: 7 / 7"), "{text}");
    // raystep's own output is named for the teacher (a 0-point line, not a failure).
    assert!(
        text.contains("⚠ first-sphere.toml (160, 120): raystep's own output"),
        "{text}"
    );
    let scene = root()
        .join("scenes/first-sphere.toml")
        .display()
        .to_string();
    for (args, words) in [
        (vec!["--scene", &scene, "--pixels", "a,b"], "--pixels"),
        (
            vec!["--scene", &scene, "--pixels", "999,0"],
            "outside the 320×240 image",
        ),
        (vec!["--scene", &scene, "--pixels", ";"], "lists no pixel"),
        (
            vec!["--scene", &scene, "--pixels", "1,1", "--timeout", "0"],
            "--timeout 0",
        ),
        (
            vec!["--scene", "no-such.toml", "--pixels", "1,1"],
            "no-such.toml",
        ),
        (vec!["--run-twice"], "unexpected argument"),
    ] {
        let mut all = vec!["grade-tracer", "--run", "python3 x.py"];
        all.extend(args.iter().copied());
        let out = raystep().args(&all).assert().failure().get_output().clone();
        let err = String::from_utf8(out.stderr).unwrap();
        assert!(err.contains(words), "{all:?}: {err}");
    }
    let out = raystep()
        .args(["grade-tracer", "--run", "python3 x.py"])
        .assert()
        .failure()
        .get_output()
        .clone();
    assert!(
        String::from_utf8(out.stderr)
            .unwrap()
            .contains("give a --sheet, or --scene and --pixels")
    );
}
