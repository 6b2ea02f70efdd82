//! `raystep grade-tracer`'s two inputs as the `student` and `grade_sheet` fuzz targets see them
//! (`raystep::fuzzing::{student_input, grade_sheet_input}`), in short: raystep's own student
//! output and the shipped grading sheets are accepted, and mutated copies of them return (no
//! panic, no hang). The inputs the fuzzers found, and the ones found while writing the targets,
//! are regular tests here. The fuzzers run far longer (book/testing.md → Fuzzing).

use proptest::prelude::*;
use raystep::fuzzing::{self, STUDENT_PIXELS, grade_sheet_path};
use raystep::student::format;
use std::time::{Duration, Instant};

use crate::common::scenes;
use scenes::{root, shipped};

/// raystep's own output in the student format (`raystep trace --format student`): the pixels
/// the target grades against, and the middle pixel of every shipped scene.
fn student_seeds() -> Vec<String> {
    let pixel = |path: &std::path::Path, x: u32, y: u32| {
        let mut scene = raystep::scene::load_file(path).unwrap();
        // The student format is Whitted's (the Monte Carlo scenes are recorded under it).
        scene.settings.integrator = raystep::scene::Integrator::Whitted;
        let trace = raystep::PreparedScene::new(scene).record(x, y, 0);
        format::write(&raystep::student::expected::expected(&trace).pixel)
    };
    let mut v: Vec<String> = STUDENT_PIXELS
        .iter()
        .map(|(name, x, y)| pixel(&root().join(format!("scenes/{name}.toml")), *x, *y))
        .collect();
    for p in shipped() {
        let s = raystep::scene::load_file(&p).unwrap();
        v.push(pixel(&p, s.camera.width / 2, s.camera.height / 2));
    }
    v
}

/// The starter kit's grading sheet, and one that varies its scenes per student.
fn sheet_seeds() -> Vec<String> {
    vec![
        std::fs::read_to_string(grade_sheet_path()).unwrap(),
        "title = \"Variants\"\nid = \"checkpoint-3\"\nupto = \"shadows\"\ntimeout_s = 2.5\n\
         tolerance = { rel = 1e-3, abs = 1e-4, color = 4e-3, offset = 2e-2 }\n\
         [[scene]]\nfile = \"../../scenes/three-spheres.toml\"\npixels = [[150, 110], [100, 160]]\n\
         random_pixels = 2\n\
         [[scene.vary]]\nobject = \"middle\"\nkey = \"radius\"\nrange = [0.8, 1.2]\n\
         [[scene.vary]]\nobject = \"key\"\nkey = \"position\"\nindex = 1\nrange = [6, 14]\n\
         decimals = 1\n\
         [[scene]]\nfile = \"../../scenes/triangles.toml\"\npixels = [[80, 130]]\n\
         [[scene.vary]]\nobject = \"icosahedron\"\nkey = \"scale\"\nrange = [0.9, 1.1]\n"
            .to_string(),
    ]
}

#[test]
fn the_seeds_are_accepted_unmutated() {
    for s in student_seeds() {
        let r = fuzzing::student_input(s.as_bytes());
        assert!(r.accepted && r.violations.is_empty(), "{r:?}");
    }
    for s in sheet_seeds() {
        let r = fuzzing::grade_sheet_input(s.as_bytes());
        assert!(r.accepted && r.violations.is_empty(), "{r:?}");
    }
}

/// One edit of a JSON Lines output or a TOML sheet, line by line.
#[derive(Debug, Clone)]
enum Edit {
    /// Repeat line `i` `n` times.
    Repeat(usize, usize),
    /// Delete line `i`.
    Delete(usize),
    /// Move line `i` before line `j`.
    Move(usize, usize),
    /// Replace the `k`-th number on line `i` with a hostile one.
    Number(usize, usize, &'static str),
    /// Cut line `i` at byte `k` (on a character boundary).
    Cut(usize, usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    let hostile = prop::sample::select(vec![
        "0",
        "-0",
        "-1",
        "1e308",
        "-1e308",
        "1e-320",
        "4294967295",
        "4294967296",
        "18446744073709551615",
        "1e999",
        "null",
        "[]",
        "\"x\"",
        "true",
    ]);
    prop_oneof![
        (any::<usize>(), 1usize..50).prop_map(|(i, n)| Edit::Repeat(i, n)),
        any::<usize>().prop_map(Edit::Delete),
        (any::<usize>(), any::<usize>()).prop_map(|(i, j)| Edit::Move(i, j)),
        (any::<usize>(), any::<usize>(), hostile).prop_map(|(i, k, x)| Edit::Number(i, k, x)),
        (any::<usize>(), any::<usize>()).prop_map(|(i, k)| Edit::Cut(i, k)),
    ]
}

fn apply(seed: &str, edits: &[Edit]) -> String {
    let mut lines: Vec<String> = seed.lines().map(str::to_string).collect();
    for e in edits {
        if lines.is_empty() {
            break;
        }
        let n = lines.len();
        match e {
            Edit::Repeat(i, k) => {
                let l = lines[i % n].clone();
                lines.splice(i % n..i % n, std::iter::repeat_n(l, *k));
            }
            Edit::Delete(i) => {
                lines.remove(i % n);
            }
            Edit::Move(i, j) => {
                let l = lines.remove(i % n);
                lines.insert(j % n, l);
            }
            Edit::Number(i, k, x) => {
                let l = &lines[i % n];
                // The numbers' byte ranges on the line.
                let mut spans = vec![];
                let b = l.as_bytes();
                let mut p = 0;
                while p < b.len() {
                    if b[p].is_ascii_digit()
                        || (b[p] == b'-' && b.get(p + 1).is_some_and(u8::is_ascii_digit))
                    {
                        let start = p;
                        p += 1;
                        while p < b.len() && (b[p].is_ascii_digit() || b".eE-+".contains(&b[p])) {
                            p += 1;
                        }
                        spans.push(start..p);
                    } else {
                        p += 1;
                    }
                }
                if !spans.is_empty() {
                    let r = spans[k % spans.len()].clone();
                    lines[i % n].replace_range(r, x);
                }
            }
            Edit::Cut(i, k) => {
                let l = &mut lines[i % n];
                let mut at = k % (l.len() + 1);
                while !l.is_char_boundary(at) {
                    at -= 1;
                }
                l.truncate(at);
            }
        }
    }
    lines.join("\n") + "\n"
}

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

proptest! {
    #![proptest_config(config(200))]

    #[test]
    fn edited_student_outputs_grade_or_fail_cleanly(
        k in any::<prop::sample::Index>(),
        edits in prop::collection::vec(edit(), 1..8),
    ) {
        let seeds = student_seeds();
        let r = fuzzing::student_input(apply(&seeds[k.index(seeds.len())], &edits).as_bytes());
        prop_assert!(r.violations.is_empty(), "{:?}", r.violations);
    }
}

proptest! {
    #![proptest_config(config(40))]

    #[test]
    fn edited_grading_sheets_expand_or_fail_cleanly(
        k in any::<prop::sample::Index>(),
        edits in prop::collection::vec(edit(), 1..6),
    ) {
        let seeds = sheet_seeds();
        let r = fuzzing::grade_sheet_input(apply(&seeds[k.index(seeds.len())], &edits).as_bytes());
        prop_assert!(r.violations.is_empty(), "{:?}", r.violations);
    }
}

/// The time `parse` takes on `text`, and whether it read it.
fn timed_parse(text: &str) -> (Duration, bool) {
    let t = Instant::now();
    let ok = format::parse(text).is_ok();
    (t.elapsed(), ok)
}

/// A program may print up to 16 MB (the default output limit): its output is read in time
/// linear in its records, whatever they are. Found while writing the `student` target: each ray
/// looked back through every ray before it for its parent, and each `shadow`, `hit` and `color`
/// record for its owner, so a primary ray followed by 16 MB of shadow rays took minutes.
#[test]
fn a_flood_of_shadow_rays_or_records_is_read_in_linear_time() {
    let head = "{\"type\":\"pixel\",\"x\":1,\"y\":2}\n{\"type\":\"ray\",\"kind\":\"primary\"}\n";
    let floods = [
        "{\"type\":\"ray\",\"kind\":\"shadow\",\"depth\":1}\n",
        "{\"type\":\"ray\",\"kind\":\"shadow\",\"depth\":1}\n{\"type\":\"shadow\",\"light\":\"k\"}\n",
        "{\"type\":\"ray\",\"kind\":\"shadow\",\"depth\":1}\n{\"type\":\"hit\",\"depth\":0}\n",
    ];
    for flood in floods {
        let text = format!("{head}{}", flood.repeat((16 << 20) / flood.len()));
        let (took, ok) = timed_parse(&text);
        assert!(ok, "{flood}");
        assert!(
            took < Duration::from_secs(20),
            "16 MB of {flood:?} took {took:?}"
        );
    }
}

/// A ray of the largest depth a `u32` holds, then a ray one level down looking for its parent:
/// the parent search added one to every earlier ray's depth and overflowed (a panic in debug
/// builds, the fuzzers' and the tests'). Found while writing the `student` target.
#[test]
fn a_ray_of_the_largest_depth_does_not_overflow_the_parent_search() {
    let text = "{\"type\":\"ray\",\"kind\":\"primary\",\"depth\":4294967295}\n\
                {\"type\":\"ray\",\"kind\":\"reflection\",\"depth\":1}\n";
    let err = format::parse(text).unwrap_err();
    assert_eq!(err.line, 2, "{err}");
    assert!(err.message.contains("no ray of depth 0 before it"), "{err}");
    let ok = "{\"type\":\"ray\",\"kind\":\"primary\",\"depth\":4294967294}\n\
              {\"type\":\"ray\",\"kind\":\"reflection\",\"depth\":4294967295}\n\
              {\"type\":\"color\",\"rgb\":[0,0,0],\"depth\":4294967294}\n";
    let px = format::parse(ok).unwrap();
    assert_eq!(px[0].rays[1].parent, Some(0));
    assert_eq!(px[0].rays[0].color, Some([0.0; 3]));
    let r = fuzzing::student_input(ok.as_bytes());
    assert!(r.accepted && r.violations.is_empty(), "{r:?}");
}

/// A `color` record without a depth belongs to the latest ray, a shadow ray included; written
/// back, its depth named the latest ray of that depth that is not a shadow ray, which a shadow
/// ray's parent level has none of, so the output did not read. Found by the `student` fuzzer
/// (minimized by hand from its crash).
#[test]
fn a_shadow_ray_with_a_colour_is_written_back_readably() {
    let text = "{\"type\":\"ray\",\"kind\":\"primary\"}\n\
                {\"type\":\"ray\",\"kind\":\"shadow\",\"depth\":1}\n\
                {\"type\":\"color\",\"rgb\":[0.5,0.25,0]}\n";
    let px = format::parse(text).unwrap();
    assert_eq!(px[0].rays[1].color, Some([0.5, 0.25, 0.0]));
    let back = format::parse(&format::write(&px[0])).unwrap();
    let shape = |rays: &[format::Ray]| {
        rays.iter()
            .map(|r| (r.kind.clone(), r.depth, r.parent, r.color))
            .collect::<Vec<_>>()
    };
    assert_eq!(shape(&back[0].rays), shape(&px[0].rays));
    let r = fuzzing::student_input(text.as_bytes());
    assert!(r.accepted && r.violations.is_empty(), "{r:?}");
}
