//! Python tracers graded by `raystep grade-tracer`: the starter kit (`lessons/starter/tracer.py`,
//! camera rays only) gets full marks on the camera stage of every shipped scene and is told what
//! to do next; the model student (`tests/student_tracer/tracer.py`, an independent Python
//! implementation of the lessons' formulas) gets full marks on every stage of every shipped
//! scene; the same tracer with a planted bug loses marks at the right ray and quantity, with the
//! mistake named. Needs `python3` (3.11 or newer), which `.ci/run` installs.

use assert_cmd::Command;
use serde_json::Value;
use std::path::Path;

use crate::common::scenes;
use scenes::{root, shipped_whitted as shipped};

/// Grades `run` on `scene` at `pixels` up to `upto`; the Gradescope JSON.
fn grade(scene: &Path, pixels: &str, upto: &str, run: &str) -> Value {
    let out = Command::cargo_bin("raystep")
        .unwrap()
        .current_dir(root())
        .args([
            "grade-tracer",
            "--scene",
            &scene.display().to_string(),
            "--pixels",
            pixels,
            "--upto",
            upto,
            "--json",
            "--timeout",
            "60",
            "--run",
            run,
        ])
        .assert()
        .success()
        .get_output()
        .clone();
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Each scene's image size, for pixels at its corners and inside.
fn pixels(scene: &Path) -> String {
    let s = raystep::scene::load_file(scene).unwrap();
    let (w, h) = (s.camera.width, s.camera.height);
    [
        (0, 0),
        (w - 1, h - 1),
        (w / 2, h / 2),
        (w / 4, 3 * h / 4),
        (3 * w / 4, h / 3),
    ]
    .iter()
    .map(|(x, y)| format!("{x},{y}"))
    .collect::<Vec<_>>()
    .join(";")
}

fn failures(v: &Value) -> Vec<String> {
    v["tests"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|t| t["score"] != t["max_score"])
        .map(|t| format!("{}: {}", t["name"], t["output"]))
        .collect()
}

#[test]
fn the_starter_kit_passes_the_camera_stage_everywhere() {
    let run = "python3 lessons/starter/tracer.py {scene} {x} {y}";
    for scene in shipped() {
        let v = grade(&scene, &pixels(&scene), "camera", run);
        assert_eq!(failures(&v), Vec::<String>::new(), "{}", scene.display());
        assert_eq!(v["score"], 5.0);
    }
    // The next stage tells the student what is missing.
    let v = grade(
        &root().join("scenes/first-sphere.toml"),
        "160,120",
        "sphere",
        run,
    );
    let f = failures(&v);
    assert_eq!(f.len(), 1, "{f:?}");
    assert!(
        f[0].contains("you printed no sphere test for this pixel"),
        "{f:?}"
    );
}

const MODEL: &str = "python3 tests/student_tracer/tracer.py {scene} {x} {y}";

/// The model student — an independent Python tracer of the lessons' formulas, in double
/// precision — gets full marks at every stage on the shipped scenes, except where the scene is
/// built to show rounding: `acne.toml` turns raystep's offset off (raystep's own shadow rays hit
/// their surface there, a correct student's do not) and the centre row of `leaky-edge.toml` runs
/// along shared triangle edges, where which triangle is hit is rounding noise.
#[test]
fn the_model_student_gets_full_marks() {
    for scene in shipped() {
        let name = scene.file_name().unwrap().to_string_lossy().to_string();
        let px = match name.as_str() {
            "acne.toml" => continue,
            "leaky-edge.toml" => "0,0;199,199;50,150;150,60;100,20".to_string(),
            // The egg, the tall gem (non-uniform scales), the gem at the back (rotated on three
            // axes), the near gem (a `matrix`) and the marble.
            "instances.toml" => "110,104;210,72;150,88;130,136;110,136".to_string(),
            _ => pixels(&scene),
        };
        let v = grade(&scene, &px, "color", MODEL);
        assert_eq!(failures(&v), Vec::<String>::new(), "{name}");
        // Seven stages at each of the five pixels, and the surface stage at those whose hit is
        // smooth-shaded or textured.
        let surface = v["tests"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|t| t["name"].as_str().unwrap().ends_with(": surface"))
            .count();
        assert_eq!(v["score"], 35.0 + surface as f64, "{name}");
        assert_eq!(v["max_score"], v["score"], "{name}");
        if ["textures.toml", "mipmap.toml"].contains(&name.as_str()) {
            assert!(surface >= 3, "{name}: {surface} surface tests");
        }
    }
    // The smooth sphere's pixels are graded at the surface stage too (its shading normal).
    let v = grade(
        &root().join("scenes/smooth-shading.toml"),
        "215,120;200,130;230,110",
        "color",
        MODEL,
    );
    assert_eq!(failures(&v), Vec::<String>::new());
    assert_eq!(v["score"], 24.0);
}

/// The first failing test of a grading, with the stage it belongs to.
fn first_failure(v: &Value) -> (String, String) {
    let t = v["tests"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["score"] != t["max_score"])
        .unwrap_or_else(|| panic!("no failure: {v}"));
    (
        t["name"].as_str().unwrap().to_string(),
        t["output"].as_str().unwrap().to_string(),
    )
}

/// All the feedback of a grading.
fn all_output(v: &Value) -> String {
    failures(v).join("\n")
}

/// The model student with a planted bug loses marks; the first divergence is at the ray and
/// quantity the bug changes, and the feedback names the mistake.
#[test]
fn planted_bugs_are_found_at_the_right_ray_and_named() {
    let scene = |s: &str| root().join("scenes").join(s);
    let bug = |b: &str| format!("{MODEL} --bug {b}");

    // b = f·Q: the first sphere test of the primary ray.
    let v = grade(
        &scene("first-sphere.toml"),
        "160,120",
        "color",
        &bug("half-b"),
    );
    let (name, out) = first_failure(&v);
    assert_eq!(name, "first-sphere.toml (160, 120): sphere");
    assert!(
        out.starts_with("ray 0 (the primary ray, depth 0), sphere \"ball\": your b is"),
        "{out}"
    );
    assert!(
        out.contains("your b looks like f·Q: the course notes' b is 2 f·Q"),
        "{out}"
    );
    assert!(out.contains("raystep open"), "{out}");

    // The normal P − G not divided by r (the spheres of radius ≠ 1).
    let v = grade(
        &scene("three-spheres.toml"),
        "100,160;220,160",
        "closest-hit",
        &bug("unnormalized-normal"),
    );
    assert!(
        v["score"].as_f64().unwrap() < v["max_score"].as_f64().unwrap(),
        "{v}"
    );
    assert!(
        all_output(&v).contains("normalize it"),
        "{}",
        all_output(&v)
    );

    // No offset: the shadow ray hits the sphere it leaves, the light is said blocked.
    let v = grade(
        &scene("three-spheres.toml"),
        "191,119",
        "color",
        &bug("no-shadow-offset"),
    );
    let (name, out) = first_failure(&v);
    assert_eq!(name, "three-spheres.toml (191, 119): sphere");
    assert!(
        out.starts_with("ray 1 (the shadow ray towards light \"key\", depth 1), sphere \"middle\""),
        "{out}"
    );
    assert!(out.contains("hits the surface it leaves"), "{out}");
    assert!(
        all_output(&v).contains("(shadow acne)"),
        "{}",
        all_output(&v)
    );

    // r = d + 2(d·n)n: the reflection ray off the mirror.
    let v = grade(
        &scene("mirror-glass.toml"),
        "79,149",
        "color",
        &bug("reflect-sign"),
    );
    let text = all_output(&v);
    assert!(
        text.contains("(the reflection ray, depth 1): your direction"),
        "{text}"
    );
    assert!(
        text.contains("the sign is wrong: r = d − 2(d·n)n"),
        "{text}"
    );

    // η = n2/n1: the refraction ray into the glass.
    let v = grade(
        &scene("mirror-glass.toml"),
        "159,149",
        "color",
        &bug("snell-inverted"),
    );
    let text = all_output(&v);
    assert!(text.contains("(the refraction ray, depth"), "{text}");
    assert!(text.contains("Snell's ratio is inverted"), "{text}");
}

/// Lesson 20's classic mistakes, planted in the model student, are caught at the first stage
/// that sees them and named: the normal carried by M instead of M⁻ᵀ (seen only where the scale
/// is not uniform: on a uniformly scaled gem M·n′ points the same way), the origin carried into
/// object space as a vector, the direction renormalised there.
#[test]
fn planted_instance_mistakes_are_found_and_named() {
    let scene = root().join("scenes/instances.toml");
    let bug = |b: &str| format!("{MODEL} --bug {b}");
    // The egg: the unit sphere scaled by (0.6, 1, 0.6).
    let v = grade(&scene, "110,104", "color", &bug("normal-by-m"));
    let (name, out) = first_failure(&v);
    assert_eq!(name, "instances.toml (110, 104): closest-hit");
    assert!(
        out.starts_with("ray 0 (the primary ray, depth 0): your normal is"),
        "{out}"
    );
    assert!(
        out.contains("that is M·n′: a normal is carried by the inverse transpose"),
        "{out}"
    );
    // The left gem, scaled by 0.3 in every direction: the same mistake gives the right normal.
    let v = grade(&scene, "230,120", "closest-hit", &bug("normal-by-m"));
    assert_eq!(failures(&v), Vec::<String>::new());

    let v = grade(&scene, "110,104", "color", &bug("origin-as-vector"));
    let (name, out) = first_failure(&v);
    assert_eq!(name, "instances.toml (110, 104): sphere");
    assert!(
        out.starts_with(
            "ray 0 (the primary ray, depth 0), instance \"egg\": your origin S′ (in object space) is"
        ),
        "{out}"
    );
    assert!(
        out.contains("S′ is a point: M⁻¹'s translation column applies to it"),
        "{out}"
    );

    // The tall gem (a mesh: its instance ray is judged with its triangles).
    let v = grade(&scene, "210,72", "color", &bug("renormalized-q"));
    let (name, out) = first_failure(&v);
    assert_eq!(name, "instances.toml (210, 72): plane-triangle");
    assert!(
        out.starts_with(
            "ray 0 (the primary ray, depth 0), instance \"gem tall\": your direction Q′ (in object space) is"
        ),
        "{out}"
    );
    assert!(
        out.contains("Q′ is renormalised: keep M⁻¹Q as it is"),
        "{out}"
    );
}

/// Lessons 17–19's classic mistakes, planted in the model student, are caught at the surface
/// stage — the first stage that sees them — and named: the smooth normal's weights on the wrong
/// vertices, v flipped, texel centres off by half, the image's sRGB values used as linear.
#[test]
fn planted_surface_mistakes_are_found_and_named() {
    let scene = |s: &str| root().join("scenes").join(s);
    let bug = |b: &str| format!("{MODEL} --bug {b}");
    let cases = [
        (
            "smooth-shading.toml",
            "230,110",
            "normal-weights",
            "your shading normal is",
            "the weights are (1 − u − v, u, v) on (P0, P1, P2)",
        ),
        // The globe (64 × 32, bilinear): the row, then the colour.
        (
            "textures.toml",
            "100,100",
            "v-flipped",
            "your texel (column, row) is (50, 19), raystep's is (50, 11)",
            "v is flipped: row 0 is the top of the image",
        ),
        (
            "textures.toml",
            "110,90",
            "half-texel",
            "your texel (column, row) is (53, 9), raystep's is (52, 9)",
            "texel centres are at (i + ½, j + ½)",
        ),
        // Here the same first texel, but other weights: named from the colour.
        (
            "textures.toml",
            "90,110",
            "half-texel",
            "your texture colour is",
            "that is bilinear with the texel centres at integers",
        ),
        (
            "textures.toml",
            "90,110",
            "srgb-not-decoded",
            "your texture colour is",
            "that is the image's stored (sRGB) value: decode each texel to linear",
        ),
    ];
    for (file, px, b, what, hint) in cases {
        let v = grade(&scene(file), px, "color", &bug(b));
        let (name, out) = first_failure(&v);
        assert_eq!(
            name,
            format!("{file} ({}): surface", px.replace(',', ", ")),
            "{b}"
        );
        assert!(
            out.starts_with(&format!("ray 0 (the primary ray, depth 0): {what}")),
            "{b}: {out}"
        );
        assert!(out.contains(hint), "{b}: {out}");
        // The earlier stages pass: the mistake is in the surface's reading, not the hit.
        let earlier = failures(&v)
            .iter()
            .filter(|f| {
                ["camera", "sphere", "plane-triangle", "closest-hit"]
                    .iter()
                    .any(|s| f.contains(&format!("): {s}\"")))
            })
            .count();
        assert_eq!(earlier, 0, "{b}: {}", all_output(&v));
    }
    // Graded only up to the closest hit, a textured pixel has no surface test.
    let v = grade(
        &scene("textures.toml"),
        "100,100",
        "closest-hit",
        &bug("v-flipped"),
    );
    assert_eq!(failures(&v), Vec::<String>::new());
    assert_eq!(v["score"], 4.0);
}

/// The example sheets shipped with the starter kit grade the model student full marks (their
/// listed and per-student pixels: up to the closest hit; a path tracer's stages), and the
/// starter kit short of that.
#[test]
fn the_shipped_sheet_grades_the_model_student() {
    let run = |sheet: &str, tracer: &str, student: &str| -> Value {
        let out = Command::cargo_bin("raystep")
            .unwrap()
            .current_dir(root())
            .args([
                "grade-tracer",
                "--sheet",
                sheet,
                "--student",
                student,
                "--json",
                "--run",
                &format!("python3 {tracer} {{scene}} {{x}} {{y}}"),
            ])
            .assert()
            .success()
            .get_output()
            .clone();
        serde_json::from_slice(&out.stdout).unwrap()
    };
    // 3 + 2 pixels of three-spheres and 1 + 1 of first-sphere, four stages each.
    for student in ["s1001", "s1002"] {
        let v = run(
            "lessons/starter/sheet.toml",
            "tests/student_tracer/tracer.py",
            student,
        );
        assert_eq!(failures(&v), Vec::<String>::new(), "{student}");
        assert_eq!(v["max_score"], 28.0, "{v}");
    }
    let v = run(
        "lessons/starter/sheet.toml",
        "lessons/starter/tracer.py",
        "s1001",
    );
    assert!(v["score"].as_f64().unwrap() < 28.0, "{v}");
    // The path tracer's sheet: 3 + 2 pixels of the path-traced cornell-area, seven path stages
    // each; the model's path tracer and the completed kit get them all, the kit as shipped none.
    for student in ["s1001", "s1002"] {
        for tracer in [
            "tests/student_tracer/tracer.py",
            "tests/student_tracer/starter_completed.py",
        ] {
            let v = run("lessons/starter/path-sheet.toml", tracer, student);
            assert_eq!(failures(&v), Vec::<String>::new(), "{student} {tracer}");
            assert_eq!(v["max_score"], 35.0, "{v}");
        }
    }
    let v = run(
        "lessons/starter/path-sheet.toml",
        "lessons/starter/tracer.py",
        "s1001",
    );
    assert_eq!(v["score"], 0.0, "{v}");
}

/// A sheet can vary the scene per student: each student's program is given their own variant
/// file (values drawn from the student id, the same id the same values; comments kept; a mesh
/// still found), raystep grades against that variant, and the model student gets full marks on
/// it. A `vary` naming no object of the scene is refused, naming the sheet and the object.
#[test]
fn sheets_vary_the_scene_per_student() {
    let dir = tempfile::tempdir().unwrap();
    let sheet = dir.path().join("vary.toml");
    let scenes = root().join("scenes");
    std::fs::write(
        &sheet,
        format!(
            "upto = \"color\"\n\
             [[scene]]\nfile = \"{0}/three-spheres.toml\"\npixels = [[150, 110], [100, 160]]\n\
             [[scene.vary]]\nobject = \"middle\"\nkey = \"radius\"\nrange = [0.8, 1.2]\n\
             [[scene.vary]]\nobject = \"key\"\nkey = \"position\"\nindex = 1\nrange = [6, 14]\ndecimals = 1\n\
             [[scene]]\nfile = \"{0}/triangles.toml\"\npixels = [[80, 130]]\n\
             [[scene.vary]]\nobject = \"icosahedron\"\nkey = \"scale\"\nrange = [0.9, 1.1]\n",
            scenes.display()
        ),
    )
    .unwrap();
    let s = raystep::student::load_tracer_sheet(&sheet).unwrap();
    let variants = raystep::student::VariantDir::private().unwrap();
    let jobs = |who: &str| raystep::student::sheet_jobs(&s, &sheet, who, &variants).unwrap();
    let (a, a2, b) = (jobs("ada"), jobs("ada"), jobs("bob"));
    let radius = |j: &raystep::student::Job| {
        let sc = j.prepared.scene();
        let id = (0..sc.objects.len() as u32)
            .find(|&i| sc.object_name(i) == "middle")
            .unwrap();
        match sc.objects[id as usize].shape {
            raystep::scene::Shape::Sphere { radius, .. } => radius,
            other => panic!("{other:?}"),
        }
    };
    assert_eq!(radius(&a[0]), radius(&a2[0]));
    assert_ne!(
        (radius(&a[0]), a[0].variant.clone()),
        (radius(&b[0]), b[0].variant.clone())
    );
    assert!((0.8..=1.2).contains(&radius(&a[0])));
    let text = std::fs::read_to_string(&a[0].path).unwrap();
    assert!(
        text.starts_with("# Three spheres on a plane, one light"),
        "{text}"
    );
    assert!(
        a[0].variant
            .as_deref()
            .unwrap()
            .starts_with("middle.radius = "),
        "{:?}",
        a[0].variant
    );
    assert!(a[1].prepared.scene().objects.len() > 20, "the mesh loaded");
    // The model student reads the variant it is given: full marks.
    let out = Command::cargo_bin("raystep")
        .unwrap()
        .current_dir(root())
        .args([
            "grade-tracer",
            "--sheet",
            &sheet.display().to_string(),
            "--student",
            "ada",
            "--json",
            "--run",
            MODEL,
        ])
        .assert()
        .success()
        .get_output()
        .clone();
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(failures(&v), Vec::<String>::new());
    assert_eq!(v["max_score"], 21.0);
    // A vary of an object the scene lacks.
    std::fs::write(
        &sheet,
        format!(
            "[[scene]]\nfile = \"{}/three-spheres.toml\"\npixels = [[1, 1]]\n\
             [[scene.vary]]\nobject = \"nobody\"\nkey = \"radius\"\nrange = [1, 2]\n",
            scenes.display()
        ),
    )
    .unwrap();
    let s = raystep::student::load_tracer_sheet(&sheet).unwrap();
    let err = raystep::student::sheet_jobs(
        &s,
        &sheet,
        "ada",
        &raystep::student::VariantDir::private().unwrap(),
    )
    .unwrap_err();
    assert!(
        err.contains("vary.toml") && err.contains("named \"nobody\""),
        "{err}"
    );
}

/// The starter kit's `uniform` (Python, `lessons/starter/tracer.py`) draws raystep's random
/// numbers bit for bit: 200 inputs, extremes included, against `raystep::portable::random::uniform`.
#[test]
fn the_starter_kits_uniform_is_raysteps() {
    let mut inputs = vec![
        ([0u32, 0u32], 0u32, 0u32, 0u32),
        ([u32::MAX, u32::MAX], u32::MAX, u32::MAX, u32::MAX),
        ([40, 160], 0, 3094, 0),
    ];
    let mut h = 12345u32;
    for _ in 0..197 {
        let mut next = || {
            h = raystep::portable::random::pcg_hash(h);
            h
        };
        inputs.push((
            [next() % 4096, next() % 4096],
            next() % 65536,
            next() % 8192,
            next(),
        ));
    }
    let calls: Vec<String> = inputs
        .iter()
        .map(|(p, s, d, seed)| {
            format!(
                "print(repr(t.uniform(({}, {}), {s}, {d}, {seed})))",
                p[0], p[1]
            )
        })
        .collect();
    let script = format!(
        "import sys\nsys.path.insert(0, 'lessons/starter')\nimport tracer as t\n{}\n",
        calls.join("\n")
    );
    let out = std::process::Command::new("python3")
        .arg("-c")
        .arg(&script)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("python3 runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let got: Vec<f64> = text.lines().map(|l| l.parse().unwrap()).collect();
    assert_eq!(got.len(), inputs.len());
    for ((p, s, d, seed), g) in inputs.iter().zip(got) {
        let want = raystep::portable::random::uniform(*p, *s, *d, *seed);
        assert_eq!(g, f64::from(want), "uniform({p:?}, {s}, {d}, {seed})");
    }
}

/// Pixels of the path-traced Cornell box, corners and inside.
const CORNELL_PIXELS: &str = "128,128;60,200;200,40;30,30;10,250;250,10;128,5;90,180;220,130;0,0";

/// The path tracers: the model student's (tests/student_tracer/path_tracer.py, reached through
/// the model's tracer.py) and the starter kit with its TODOs filled in
/// (tests/student_tracer/starter_completed.py imports the kit unchanged) get full marks on every
/// path stage, sample by sample; the kit as shipped runs, prints format version 2 and is told
/// what is missing.
#[test]
fn the_path_tracers_get_full_marks_and_the_starter_kit_is_told_what_is_missing() {
    let scene = root().join("scenes/cornell-area.toml");
    for run in [
        MODEL,
        "python3 tests/student_tracer/starter_completed.py {scene} {x} {y}",
    ] {
        let v = grade(&scene, CORNELL_PIXELS, "estimate", run);
        assert_eq!(failures(&v), Vec::<String>::new(), "{run}");
        assert_eq!(v["score"], 70.0, "{run}");
    }
    let v = grade(
        &scene,
        "128,128",
        "estimate",
        "python3 lessons/starter/tracer.py {scene} {x} {y}",
    );
    let text = all_output(&v);
    assert_eq!(v["score"], 0.0, "{text}");
    assert!(
        text.contains("sample 0, the camera ray's hit: your ray escapes, raystep's hits"),
        "{text}"
    );
}

/// The model's path tracer with a classic mistake planted loses marks at the stage that judges
/// it, and the feedback names the mistake.
#[test]
fn planted_path_tracing_mistakes_are_named() {
    let scene = root().join("scenes/cornell-area.toml");
    for (bug, stage, words) in [
        (
            "pdf-no-cosine",
            "bsdf-sample",
            "your pdf is missing the cosine",
        ),
        ("area-pdf", "light-sample", "per unit area of the light"),
        (
            "mis-balance-emission",
            "mis",
            "MIS weights that do not sum to one",
        ),
        ("emission-twice", "mis", "emission counted twice"),
        (
            "roulette-no-divide",
            "bounce",
            "your roulette does not divide by its probability",
        ),
        ("wrong-hemisphere", "bsdf-sample", "points into the surface"),
    ] {
        let run = format!(
            "python3 tests/student_tracer/path_tracer.py {{scene}} {{x}} {{y}} --bug {bug}"
        );
        let v = grade(&scene, "128,128;60,200", "estimate", &run);
        let hit = v["tests"].as_array().unwrap().iter().any(|t| {
            t["score"] == 0.0
                && t["name"].as_str().unwrap().ends_with(&format!(": {stage}"))
                && t["output"].as_str().unwrap().contains(words)
        });
        assert!(hit, "{bug}: {}", all_output(&v));
    }
}

/// The starter kit writes the statistics file of `grade-tracer --statistical`
/// (`tracer.py SCENE --stats FILE`): completed, on a 12×12 Cornell box, it passes Welch's test
/// against raystep's render; the file has one pixel record per pixel.
#[test]
fn the_completed_kit_writes_statistics_that_pass() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(root().join("scenes/cornell-area.toml"))
        .unwrap()
        .replace("width = 256", "width = 12")
        .replace("height = 256", "height = 12")
        .replace("spp = 16", "spp = 32");
    std::fs::write(dir.path().join("tiny.toml"), text).unwrap();
    let kit = root().join("tests/student_tracer/starter_completed.py");
    let status = std::process::Command::new("python3")
        .arg(&kit)
        .args(["tiny.toml", "--stats", "stats-tiny.jsonl"])
        .current_dir(dir.path())
        .status()
        .unwrap();
    assert!(status.success());
    let stats = std::fs::read_to_string(dir.path().join("stats-tiny.jsonl")).unwrap();
    assert_eq!(stats.lines().count(), 2 + 144);
    let out = Command::cargo_bin("raystep")
        .unwrap()
        .current_dir(dir.path())
        .args([
            "grade-tracer",
            "--scene",
            "tiny.toml",
            "--pixels",
            "6,6",
            "--upto",
            "random",
            "--json",
            "--statistical",
            "stats-{stem}.jsonl",
            "--run",
            &format!("python3 {} {{scene}} {{x}} {{y}}", kit.display()),
        ])
        .assert()
        .success()
        .get_output()
        .clone();
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(failures(&v), Vec::<String>::new());
    // The statistical test replaces the sample-by-sample stages and leads the report.
    assert_eq!(v["tests"][0]["name"], "tiny.toml: statistical");
    assert_eq!(v["tests"].as_array().unwrap().len(), 1, "{v}");
    assert_eq!(v["score"], v["max_score"], "{v}");
}
