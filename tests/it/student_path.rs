//! grade-tracer on path tracers (student trace format version 2): raystep's own samples,
//! written in the format and read back, get full marks; each classic mistake, planted in
//! raystep's own output, fails its stage with the mistake named; the statistical mode passes
//! raystep's own image drawn with another seed and fails one 10 % too bright.

use raystep::student::compare::{Stage, TracerTolerances};
use raystep::student::path::{self, PathExpected, PathPixel};
use raystep::student::path_compare::grade;
use raystep::student::statistical;

use crate::common::scenes;
use scenes::root;

fn prepared(scene: &str) -> raystep::PreparedScene {
    raystep::PreparedScene::new(raystep::scene::load_file(&root().join(scene)).unwrap())
}

/// Per path stage: passed, and the message — of `student` (written and read back) against `e`.
fn verdicts(e: &PathExpected, student: &PathPixel) -> Vec<(Stage, bool, String)> {
    let text = path::write(student);
    let parsed = path::parse(&text).unwrap();
    grade(e, &parsed, &Stage::PATH, &TracerTolerances::default())
        .into_iter()
        .map(|c| (c.check.stage, c.check.pass, c.check.message))
        .collect()
}

fn failed(v: &[(Stage, bool, String)]) -> Vec<(Stage, String)> {
    v.iter()
        .filter(|x| !x.1)
        .map(|x| (x.0, x.2.clone()))
        .collect()
}

/// The stage's message, asserting it failed.
fn message(v: &[(Stage, bool, String)], stage: Stage) -> String {
    let (_, pass, m) = v.iter().find(|x| x.0 == stage).unwrap();
    assert!(!pass, "{stage:?} passed: {v:?}");
    m.clone()
}

/// The first pixel of Cornell's area-light box (scanning a coarse grid) whose samples `want`.
fn find(p: &raystep::PreparedScene, want: impl Fn(&PathExpected) -> bool) -> PathExpected {
    for y in (8..256).step_by(24) {
        for x in (8..256).step_by(24) {
            let e = path::expected(p, x, y);
            if want(&e) {
                return e;
            }
        }
    }
    panic!("no pixel found");
}

#[test]
fn raysteps_own_samples_get_full_marks() {
    let p = prepared("scenes/cornell-area.toml");
    for [x, y] in [[128, 128], [60, 200], [200, 40], [128, 250]] {
        let e = path::expected(&p, x, y);
        assert_eq!(e.pixel.samples.len(), 16);
        let v = verdicts(&e, &e.pixel);
        assert_eq!(failed(&v), vec![], "({x}, {y})");
        assert_eq!(v.len(), 7);
    }
    // The format's text has every record type of version 2.
    let text = path::write(&path::expected(&p, 128, 128).pixel);
    for ty in [
        "\"format\"",
        "\"path\"",
        "\"ray\"",
        "\"hit\"",
        "\"light-sample\"",
        "\"sample\"",
        "\"bounce\"",
        "\"value\"",
        "\"color\"",
    ] {
        assert!(text.contains(&format!("\"type\":{ty}")), "{ty}");
    }
    assert!(text.starts_with("{\"type\":\"format\",\"version\":2}\n"));
}

#[test]
fn a_wrong_random_number_and_a_missing_sample_are_named() {
    let p = prepared("scenes/cornell-area.toml");
    let e = path::expected(&p, 128, 128);
    let mut s = e.pixel.clone();
    let b = s.samples[2].vertices[0].sample.as_mut().unwrap();
    let want = b.random[0];
    b.random[0].value = 0.25;
    let v = verdicts(&e, &s);
    let m = message(&v, Stage::Random);
    assert!(
        m.starts_with("sample 2, the camera ray's hit: your BSDF sample's number for dimension"),
        "{m}"
    );
    assert!(
        m.contains(&format!("dimension {} is 0.25", want.dimension)),
        "{m}"
    );
    assert!(m.contains("uniform((128, 128), 2,"), "{m}");
    assert!(m.contains("--statistical"), "{m}");
    // Only the random stage judges the numbers.
    assert_eq!(failed(&v).len(), 1, "{v:?}");

    let mut s = e.pixel.clone();
    s.samples.retain(|x| x.sample != 5);
    let v = verdicts(&e, &s);
    assert_eq!(failed(&v).len(), 7);
    assert!(message(&v, Stage::Path).starts_with("you printed no path for sample 5"));
}

#[test]
fn a_pdf_missing_the_cosine_is_named() {
    let p = prepared("scenes/cornell-area.toml");
    let e = path::expected(&p, 128, 128);
    let mut s = e.pixel.clone();
    // pdf = 1/π instead of cos θ/π at every diffuse bounce of sample 0.
    for v in &mut s.samples[0].vertices {
        if let Some(b) = v.sample.as_mut()
            && let Some(Some(pdf)) = b.pdf
        {
            let cos = v.bounce.as_ref().unwrap().cos.unwrap();
            b.pdf = Some(Some(pdf / cos));
        }
    }
    let v = verdicts(&e, &s);
    let m = message(&v, Stage::BsdfSample);
    assert!(
        m.starts_with("sample 0, the camera ray's hit: your pdf is 0.3183"),
        "{m}"
    );
    assert!(m.contains("your pdf is missing the cosine"), "{m}");
}

#[test]
fn a_direction_in_the_wrong_hemisphere_is_named() {
    let p = prepared("scenes/cornell-area.toml");
    let e = path::expected(&p, 128, 128);
    let mut s = e.pixel.clone();
    let v0 = &mut s.samples[1].vertices[0];
    let n = v0.hit.clone().flatten().unwrap().normal.unwrap();
    let b = v0.sample.as_mut().unwrap();
    let d = b.direction.unwrap();
    let k = 2.0 * (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]);
    b.direction = Some([d[0] - k * n[0], d[1] - k * n[1], d[2] - k * n[2]]);
    let v = verdicts(&e, &s);
    let m = message(&v, Stage::BsdfSample);
    assert!(
        m.starts_with("sample 1, the camera ray's hit: your sampled direction"),
        "{m}"
    );
    assert!(m.contains("points into the surface"), "{m}");
}

#[test]
fn a_light_pdf_left_in_area_measure_is_named() {
    let p = prepared("scenes/cornell-area.toml");
    let e = path::expected(&p, 128, 128);
    let mut s = e.pixel.clone();
    let l = &mut s.samples[0].vertices[0].lights[0];
    let area = e.pixel.samples[0].vertices[0].lights[0].area_pdf.unwrap();
    // Pick probability 1/2 (two equal triangles), area 0.125: 4 per unit area.
    assert!((area - 4.0).abs() < 1e-4, "{area}");
    l.pdf = Some(area);
    let v = verdicts(&e, &s);
    let m = message(&v, Stage::LightSample);
    assert!(
        m.contains("your light sample's pdf is 4.000, raystep's is"),
        "{m}"
    );
    assert!(m.contains("per unit area of the light"), "{m}");
    assert!(m.contains("pdf_ω = pdf_A · d² / |cos θ_light|"), "{m}");
}

/// A sample whose path finds the light by a BSDF sample, weighed below 1 by MIS.
fn emission_found(e: &PathExpected) -> Option<(usize, usize)> {
    e.pixel.samples.iter().enumerate().find_map(|(k, s)| {
        s.vertices.iter().enumerate().find_map(|(d, v)| {
            (d > 0
                && d as u32 <= path::MAX_CHECKED_DEPTH
                && v.emission
                    .as_ref()
                    .is_some_and(|x| x.mis_weight.is_some_and(|w| w > 1e-9 && w < 0.99)))
            .then_some((k, d))
        })
    })
}

#[test]
fn mis_weights_that_do_not_sum_to_one_are_named() {
    let p = prepared("scenes/cornell-area.toml");
    let e = find(&p, |e| emission_found(e).is_some());
    let (k, d) = emission_found(&e).unwrap();
    let mut s = e.pixel.clone();
    // The light samples keep the power heuristic, the emission takes the balance heuristic.
    let em = s.samples[k].vertices[d].emission.as_mut().unwrap();
    let (lp, bp) = (em.light_pdf.unwrap(), em.bsdf_pdf.unwrap());
    em.mis_weight = Some(bp / (bp + lp));
    let v = verdicts(&e, &s);
    let m = message(&v, Stage::Mis);
    assert!(m.contains("MIS weights that do not sum to one"), "{m}");
    assert!(m.contains("the power heuristic"), "{m}");
    assert!(m.starts_with(&format!("sample {k}, bounce {d}:")), "{m}");
}

#[test]
fn emission_counted_twice_after_next_event_estimation_is_named() {
    let p = prepared("scenes/cornell-area.toml");
    let e = find(&p, |e| emission_found(e).is_some());
    let (k, d) = emission_found(&e).unwrap();
    // Next-event estimation without MIS (weight 1), and emission found by a BSDF sample counted
    // in full too.
    let mut s = e.pixel.clone();
    for sm in &mut s.samples {
        for v in &mut sm.vertices {
            for l in &mut v.lights {
                l.mis_weight = Some(1.0);
            }
            if let Some(em) = v.emission.as_mut() {
                em.mis_weight = Some(1.0);
            }
        }
    }
    let v = verdicts(&e, &s);
    let m = message(&v, Stage::Mis);
    assert!(
        m.starts_with(&format!("sample {k}, bounce {d}: emission counted twice")),
        "{m}"
    );
}

#[test]
fn roulette_that_does_not_divide_by_its_probability_is_named() {
    let p = prepared("scenes/cornell-area.toml");
    let survived = |e: &PathExpected| {
        e.pixel.samples.iter().enumerate().find_map(|(k, s)| {
            s.vertices.iter().enumerate().find_map(|(d, v)| {
                v.roulette
                    .as_ref()
                    .is_some_and(|r| r.survived == Some(true) && r.probability.unwrap() < 0.9)
                    .then_some((k, d))
            })
        })
    };
    let e = find(&p, |e| survived(e).is_some());
    let (k, d) = survived(&e).unwrap();
    let mut s = e.pixel.clone();
    let v = &mut s.samples[k].vertices[d];
    v.roulette.as_mut().unwrap().throughput = v.bounce.as_ref().unwrap().throughput;
    let v = verdicts(&e, &s);
    let m = message(&v, Stage::Bounce);
    assert!(
        m.contains("your roulette does not divide by its probability"),
        "{m}"
    );
}

#[test]
fn a_distribution_scene_is_refused_with_a_way_out() {
    let path = root().join("scenes/soft-shadows.toml");
    let s = raystep::scene::load_file(&path).unwrap();
    let err = raystep::student::gradable(&s, &path).unwrap_err();
    assert!(err.contains("soft-shadows.toml"), "{err}");
    assert!(err.contains("distribution integrator"), "{err}");
    assert!(err.contains("--statistical"), "{err}");
    let c = raystep::scene::load_file(&root().join("scenes/cornell-area.toml")).unwrap();
    assert!(raystep::student::gradable(&c, &path).is_ok());
}

/// A small path-traced scene for the statistical tests: Cornell's box at 24×24, 64 samples.
fn small(seed: u32) -> raystep::PreparedScene {
    let mut s = raystep::scene::load_file(&root().join("scenes/cornell-area.toml")).unwrap();
    s.camera.width = 24;
    s.camera.height = 24;
    s.settings.spp = 64;
    s.settings.seed = seed;
    raystep::PreparedScene::new(s)
}

#[test]
fn statistical_mode_passes_another_seed_and_fails_a_ten_percent_bias() {
    let reference = statistical::reference(&small(0));
    let other = statistical::reference(&small(1));
    assert_ne!(reference, other);
    // Written and read back, as a student's file is.
    let other = statistical::parse(&statistical::write(&other)).unwrap();
    let v = statistical::compare(&other, &reference);
    assert!(v.pass, "{}", v.message);
    assert!(v.message.contains("about 0.001"), "{}", v.message);
    // 10 % too bright: every sample × 1.1 (the mean × 1.1, the variance × 1.21).
    let mut biased = other.clone();
    for p in biased.pixels.iter_mut().flatten() {
        p.mean = p.mean.map(|m| m * 1.1);
        p.variance = p.variance.map(|v| v * 1.21);
    }
    let v = statistical::compare(&biased, &reference);
    assert!(!v.pass, "{}", v.message);
    assert!(
        v.message.contains("the image as a whole differs"),
        "{}",
        v.message
    );
    assert!(v.message.contains("10 % brighter"), "{}", v.message);
    // A wrong size is said.
    let mut wrong = other.clone();
    wrong.width = 23;
    assert!(
        statistical::compare(&wrong, &reference)
            .message
            .contains("your image is 23×24")
    );
}

#[test]
fn a_statistics_file_with_errors_names_the_line() {
    let err = statistical::parse("{\"type\":\"image\",\"width\":2,\"height\":2}\n{\"type\":\"pixel\",\"x\":5,\"y\":0,\"samples\":4,\"mean\":[0,0,0],\"variance\":[0,0,0]}\n").unwrap_err();
    assert!(err.starts_with("line 2: pixel (5, 0) is outside"), "{err}");
    let err = statistical::parse("{\"type\":\"pixel\",\"x\":0,\"y\":0,\"samples\":4,\"mean\":[0,0,0],\"variance\":[0,0,0]}\n").unwrap_err();
    assert!(err.contains("before the `image` record"), "{err}");
    let err = statistical::parse("{\"type\":\"image\",\"width\":2,\"height\":2}\n{\"type\":\"pixel\",\"x\":0,\"y\":0,\"samples\":4,\"mean\":[0,0,0],\"variance\":[-1,0,0]}\n").unwrap_err();
    assert!(err.contains("not negative"), "{err}");
}

/// `raystep trace --format student` on a path-traced scene prints raystep's samples in version
/// 2, the very model the grader compares with.
#[test]
fn trace_prints_version_2_on_a_path_traced_scene() {
    let out = assert_cmd::Command::cargo_bin("raystep")
        .unwrap()
        .current_dir(root())
        .args([
            "trace",
            "scenes/cornell-area.toml",
            "--pixel",
            "128,128",
            "--format",
            "student",
        ])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let text = String::from_utf8(out).unwrap();
    let e = path::expected(&prepared("scenes/cornell-area.toml"), 128, 128);
    assert_eq!(text, path::write(&e.pixel));
    let back = path::parse(&text).unwrap();
    assert_eq!(back.len(), 1);
    assert_eq!(back[0].samples.len(), 16);
    for (b, w) in back[0].samples.iter().zip(&e.pixel.samples) {
        assert_eq!(b.vertices.len(), w.vertices.len());
        assert_eq!(b.value, w.value);
    }
}

/// `grade-tracer --statistical` end to end: a class-sized image (Cornell's box at 24×24, 64
/// samples) written by "the student" as raystep's own render with another seed passes; the
/// same file 10 % brighter fails; the test is one per scene in Gradescope's JSON.
#[test]
fn grade_tracer_statistical_end_to_end() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(root().join("scenes/cornell-area.toml"))
        .unwrap()
        .replace("width = 256", "width = 24")
        .replace("height = 256", "height = 24")
        .replace("spp = 16", "spp = 64");
    let scene = dir.path().join("small-box.toml");
    std::fs::write(&scene, &text).unwrap();
    let mut theirs = raystep::scene::load_file(&scene).unwrap();
    theirs.settings.seed = 7;
    let stats = statistical::reference(&raystep::PreparedScene::new(theirs));
    let grade = |stats: &statistical::StatImage| -> serde_json::Value {
        std::fs::write(
            dir.path().join("stats-small-box.jsonl"),
            statistical::write(stats),
        )
        .unwrap();
        let out = assert_cmd::Command::cargo_bin("raystep")
            .unwrap()
            .current_dir(dir.path())
            .args([
                "grade-tracer",
                "--scene",
                &scene.display().to_string(),
                "--pixels",
                "12,12",
                "--upto",
                "random",
                "--json",
                "--statistical",
                "stats-{stem}.jsonl",
                "--run",
                "python3 -c pass",
            ])
            .assert()
            .success()
            .get_output()
            .stdout
            .clone();
        serde_json::from_slice(&out).unwrap()
    };
    let v = grade(&stats);
    let t = v["tests"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["name"] == "small-box.toml: statistical")
        .unwrap()
        .clone();
    assert_eq!(t["score"], 1.0, "{t}");
    let mut biased = stats.clone();
    for p in biased.pixels.iter_mut().flatten() {
        p.mean = p.mean.map(|m| m * 1.1);
        p.variance = p.variance.map(|v| v * 1.21);
    }
    let v = grade(&biased);
    let t = v["tests"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["name"] == "small-box.toml: statistical")
        .unwrap()
        .clone();
    assert_eq!(t["score"], 0.0, "{t}");
    assert!(
        t["output"]
            .as_str()
            .unwrap()
            .contains("the image as a whole differs"),
        "{t}"
    );
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(96))]
    /// Hostile version 2 output — raystep's own, with lines dropped, repeated, cut short or
    /// with numbers replaced by extremes — never panics: it is refused with its line, or
    /// graded with one check per stage.
    #[test]
    fn hostile_version_2_output_never_panics(
        edits in proptest::collection::vec((0usize..400, 0u8..5, proptest::prelude::any::<f64>()), 1..12)
    ) {
        use std::sync::OnceLock;
        static E: OnceLock<PathExpected> = OnceLock::new();
        let e = E.get_or_init(|| path::expected(&prepared("scenes/cornell-area.toml"), 128, 128));
        let mut lines: Vec<String> = path::write(&e.pixel).lines().map(str::to_string).collect();
        for (at, what, x) in edits {
            if lines.is_empty() {
                break;
            }
            let i = at % lines.len();
            match what {
                0 => { lines.remove(i); }
                1 => { let l = lines[i].clone(); lines.insert(i, l); }
                2 => {
                    let l = lines[i].clone();
                    let cut = (0..=l.len() / 2).rev().find(|c| l.is_char_boundary(*c)).unwrap_or(0);
                    lines[i] = l[..cut].to_string();
                }
                3 => {
                    // Every number of the line replaced by x (JSON cannot say NaN or ∞: 1e308).
                    let x = if x.is_finite() { x } else { 1e308 };
                    let re: String = lines[i]
                        .split(',')
                        .map(|part| match part.rsplit_once(':') {
                            Some((k, v)) if v.trim_end_matches(['}', ']']).parse::<f64>().is_ok() => {
                                let tail: String = v.chars().filter(|c| *c == '}' || *c == ']').collect();
                                format!("{k}:{x:e}{tail}")
                            }
                            _ => part.to_string(),
                        })
                        .collect::<Vec<_>>()
                        .join(",");
                    lines[i] = re;
                }
                _ => {
                    let j = (i + 1) % lines.len();
                    lines.swap(i, j)
                }
            }
        }
        let text = lines.join("\n");
        if let Ok(px) = path::parse(&text) {
            for tol in [TracerTolerances::default(), TracerTolerances { rel: 0.0, abs: 0.0, color: 0.0, offset: 0.0 }] {
                let checks = grade(e, &px, &Stage::PATH, &tol);
                proptest::prop_assert_eq!(checks.len(), 7);
            }
        }
    }
}
