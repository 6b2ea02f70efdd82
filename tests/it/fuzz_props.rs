//! The fuzzers' inputs in short: the shipped scenes, traces of shipped scenes and the shipped
//! exercise sheets (with an answers file and a class CSV), mutated, through the same entry points
//! the cargo-fuzz targets in fuzz/ call (`raystep::fuzzing`). Every input must return (no panic,
//! no hang) with every property its entry point checks holding: a refusal names the file, a
//! recorded trace reads back the same, a trace equals itself and not its copy with a step
//! removed, every available diagram draws, the answer key's own answers are marked right. A few
//! hundred cases; the fuzzers run far longer (book/testing.md → Fuzzing).

use proptest::prelude::*;
use raystep::accel::SceneAccel;
use raystep::fuzzing::{self, ANSWERS_MARKER, CSV_MARKER, OBJ_MARKER, Report};
use raystep::scene;
use raystep::trace::Tracer;
use serde_json::Value;
use std::path::Path;
use std::sync::OnceLock;

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn files(dir: &str, ext: &str) -> Vec<std::path::PathBuf> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    v.sort();
    v
}

/// A scene's image textures made checkers (`image` → `checker = [8, 8]`, its `filter` and `wrap`
/// dropped): a fuzz input carries one OBJ file but no images, and the texture coordinates,
/// materials and lookups stay in the seed.
fn images_as_checkers(text: &str) -> String {
    text.lines()
        .filter(|l| !(l.starts_with("filter =") || l.starts_with("wrap =")))
        .map(|l| {
            if l.starts_with("image =") {
                "checker = [8, 8]"
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

/// The shipped scenes, each with the OBJ it names appended (renamed `mesh.obj`) and its images
/// made checkers ([`images_as_checkers`]). A scene that includes a glTF file is left out (an
/// input carries no glTF file; [`gltf_seeds`] feed the glTF reader).
fn scene_seeds() -> &'static [String] {
    static S: OnceLock<Vec<String>> = OnceLock::new();
    S.get_or_init(|| {
        files("scenes", "toml")
            .iter()
            .filter(|p| !read(p).contains("[[gltf]]"))
            .map(|p| {
                let text = images_as_checkers(&read(p));
                let obj = text.lines().find_map(|l| {
                    let l = l.trim();
                    l.strip_prefix("obj")
                        .and_then(|r| r.trim().strip_prefix('='))
                        .map(|r| r.trim().trim_matches('"').to_string())
                });
                match obj {
                    Some(o) => {
                        let mesh = read(&p.parent().unwrap().join(&o));
                        format!(
                            "{}{OBJ_MARKER}{mesh}",
                            text.replace(&format!("\"{o}\""), "\"mesh.obj\"")
                        )
                    }
                    None => text,
                }
            })
            .collect()
    })
}

/// Traces of shipped scenes at a small depth (as `raystep trace --save` writes them).
fn trace_seeds() -> &'static [String] {
    static S: OnceLock<Vec<String>> = OnceLock::new();
    S.get_or_init(|| {
        ["three-spheres", "triangles", "mirror-glass", "first-sphere"]
            .iter()
            .map(|n| {
                let mut s = scene::load_file(Path::new(&format!("scenes/{n}.toml"))).unwrap();
                s.settings.max_depth = 2;
                let (accel, _) = SceneAccel::build(&s);
                Tracer::new(&s, &accel)
                    .record(s.camera.width / 2, s.camera.height / 2, 0)
                    .to_json()
            })
            .collect()
    })
}

/// The shipped sheets, each followed by an answers file and a class CSV naming its questions.
fn sheet_seeds() -> &'static [String] {
    static S: OnceLock<Vec<String>> = OnceLock::new();
    S.get_or_init(|| {
        files("lessons/exercises", "toml")
            .iter()
            .map(|p| {
                let text = read(p);
                let sheet = raystep::lesson::load_exercise_sheet(p).expect("a shipped sheet loads");
                let ids: Vec<&str> = sheet.questions.iter().map(|q| q.id.as_str()).collect();
                let answers: String = ids.iter().map(|id| format!("{id} = 1\n")).collect();
                let csv = format!(
                    "student,{}\nann,{}\n",
                    ids.join(","),
                    vec!["1"; ids.len()].join(",")
                );
                format!("{text}{ANSWERS_MARKER}{answers}{CSV_MARKER}{csv}")
            })
            .collect()
    })
}

/// One byte-level mutation, as libFuzzer's simplest ones.
#[derive(Debug, Clone)]
enum Mutation {
    /// Overwrite a byte.
    Set(usize, u8),
    /// Delete a range.
    Delete(usize, usize),
    /// Insert bytes.
    Insert(usize, Vec<u8>),
    /// Copy a range elsewhere.
    Copy(usize, usize, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let interesting = prop::sample::select(vec![
        b"0".to_vec(),
        b"-1".to_vec(),
        b"7".to_vec(),
        b"1e39".to_vec(),
        b"4294967296".to_vec(),
        b"nan".to_vec(),
        b"\"".to_vec(),
        b"[".to_vec(),
        b"\n".to_vec(),
        b"=".to_vec(),
        b",".to_vec(),
    ]);
    prop_oneof![
        (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Set(i, b)),
        (any::<usize>(), 1usize..64).prop_map(|(i, n)| Mutation::Delete(i, n)),
        (any::<usize>(), interesting).prop_map(|(i, b)| Mutation::Insert(i, b)),
        (any::<usize>(), 1usize..64, any::<usize>()).prop_map(|(a, n, b)| Mutation::Copy(a, n, b)),
    ]
}

fn apply(seed: &str, muts: &[Mutation]) -> Vec<u8> {
    apply_bytes(seed.as_bytes(), muts)
}

fn apply_bytes(seed: &[u8], muts: &[Mutation]) -> Vec<u8> {
    let mut d = seed.to_vec();
    for m in muts {
        let len = d.len().max(1);
        match m {
            Mutation::Set(i, b) => {
                if !d.is_empty() {
                    d[i % len] = *b;
                }
            }
            Mutation::Delete(i, n) => {
                let a = i % len;
                let b = (a + n).min(d.len());
                if a < b {
                    d.drain(a..b);
                }
            }
            Mutation::Insert(i, bytes) => {
                let at = (i % len).min(d.len());
                d.splice(at..at, bytes.iter().copied());
            }
            Mutation::Copy(a, n, b) => {
                let from = a % len;
                let to = (from + n).min(d.len());
                let chunk: Vec<u8> = d.get(from..to).unwrap_or(&[]).to_vec();
                let at = (b % len).min(d.len());
                d.splice(at..at, chunk);
            }
        }
    }
    d
}

/// Replaces the `k`-th number of a JSON document with `x` (a mutation that keeps it JSON, so it
/// reaches the trace's validation rather than the parser).
fn replace_number(v: &mut Value, k: &mut usize, x: &Value) -> bool {
    match v {
        Value::Number(_) => {
            if *k == 0 {
                *v = x.clone();
                return true;
            }
            *k -= 1;
            false
        }
        Value::Array(a) => a.iter_mut().any(|e| replace_number(e, k, x)),
        Value::Object(o) => o.values_mut().any(|e| replace_number(e, k, x)),
        _ => false,
    }
}

/// The glTF test models: a GLB with its buffer and image inside, a glTF with its buffer a
/// data: URI.
fn gltf_seeds() -> Vec<Vec<u8>> {
    ["tests/gltf/table.glb", "tests/gltf/lamp.gltf"]
        .iter()
        .map(|p| std::fs::read(p).unwrap_or_else(|e| panic!("{p}: {e}")))
        .collect()
}

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

#[test]
fn the_seeds_are_accepted_unmutated() {
    let accepted = |r: Report| r.accepted && r.violations.is_empty();
    for s in scene_seeds() {
        let r = fuzzing::scene_input(s.as_bytes());
        assert!(accepted(r.clone()), "{r:?}\n{}", &s[..80.min(s.len())]);
    }
    for s in trace_seeds() {
        let r = fuzzing::trace_input(s.as_bytes());
        assert!(accepted(r.clone()), "{r:?}");
    }
    for s in sheet_seeds() {
        let r = fuzzing::sheet_input(s.as_bytes());
        assert!(accepted(r.clone()), "{r:?}\n{}", &s[..80.min(s.len())]);
    }
}

/// Every shipped sheet's key, for twelve students, typed back as it prints is right at a
/// tolerance of 0: each number the tracer computed in f32 reads back as that f32 (the `sheet`
/// fuzzer once found a sheet with `tolerance = { abs = 0, rel = 0 }` marking its key's own
/// `0.51621705` wrong).
#[test]
fn every_key_is_right_at_a_zero_tolerance() {
    use raystep::lesson;
    let exact = raystep::record::Tolerance::within_either(0.0, 0.0);
    let mut marked = 0;
    for p in files("lessons/exercises", "toml") {
        let sheet = lesson::load_exercise_sheet(&p).expect("a shipped sheet loads");
        for q in &sheet.questions {
            for k in 0..12 {
                let v = sheet.variant(q, &format!("student-{k}"));
                let Ok(expected) = sheet.expected(q, &v) else {
                    continue;
                };
                let key = expected.to_string();
                let m = lesson::mark(&expected, q.quantity.kind(), Some(&key), exact);
                assert!(
                    m.right,
                    "{}: {} for student-{k}: {key}: {m:?}",
                    p.display(),
                    q.id
                );
                marked += 1;
            }
        }
    }
    assert!(marked > 500, "{marked}");
}

#[test]
fn the_gltf_seeds_are_accepted_unmutated() {
    for s in gltf_seeds() {
        let r = fuzzing::gltf_input(&s);
        assert!(r.accepted && r.violations.is_empty(), "{r:?}");
    }
}

proptest! {
    #![proptest_config(config(150))]

    #[test]
    fn mutated_gltf_files_load_or_fail_cleanly(
        k in any::<prop::sample::Index>(),
        muts in prop::collection::vec(mutation(), 1..6),
    ) {
        let seeds = gltf_seeds();
        let seed = &seeds[k.index(seeds.len())];
        let r = fuzzing::gltf_input(&apply_bytes(seed, &muts));
        prop_assert!(r.violations.is_empty(), "{:?}", r.violations);
    }
}

proptest! {
    #![proptest_config(config(150))]

    #[test]
    fn mutated_scenes_load_or_fail_cleanly(
        k in any::<prop::sample::Index>(),
        muts in prop::collection::vec(mutation(), 1..6),
    ) {
        let seeds = scene_seeds();
        let r = fuzzing::scene_input(&apply(&seeds[k.index(seeds.len())], &muts));
        prop_assert!(r.violations.is_empty(), "{:?}", r.violations);
    }
}

proptest! {
    #![proptest_config(config(100))]

    #[test]
    fn mutated_traces_load_or_fail_cleanly(
        k in any::<prop::sample::Index>(),
        muts in prop::collection::vec(mutation(), 1..4),
    ) {
        let seeds = trace_seeds();
        let r = fuzzing::trace_input(&apply(&seeds[k.index(seeds.len())], &muts));
        prop_assert!(r.violations.is_empty(), "{:?}", r.violations);
    }

    #[test]
    fn traces_with_a_number_replaced_load_or_fail_cleanly(
        k in any::<prop::sample::Index>(),
        at in any::<prop::sample::Index>(),
        x in prop::sample::select(vec![
            Value::from(0), Value::from(1), Value::from(2), Value::from(3), Value::from(7),
            Value::from(-1), Value::from(1e30), Value::from(4294967295u64), Value::from(0.5),
        ]),
    ) {
        let seeds = trace_seeds();
        let mut v: Value = serde_json::from_str(&seeds[k.index(seeds.len())]).unwrap();
        let mut n = 0usize;
        count_numbers(&v, &mut n);
        let mut i = at.index(n.max(1));
        replace_number(&mut v, &mut i, &x);
        let r = fuzzing::trace_input(serde_json::to_string(&v).unwrap().as_bytes());
        prop_assert!(r.violations.is_empty(), "{:?}", r.violations);
    }
}

fn count_numbers(v: &Value, n: &mut usize) {
    match v {
        Value::Number(_) => *n += 1,
        Value::Array(a) => a.iter().for_each(|e| count_numbers(e, n)),
        Value::Object(o) => o.values().for_each(|e| count_numbers(e, n)),
        _ => {}
    }
}

proptest! {
    #![proptest_config(config(60))]

    #[test]
    fn mutated_sheets_answers_and_csvs_parse_or_fail_cleanly(
        k in any::<prop::sample::Index>(),
        muts in prop::collection::vec(mutation(), 1..6),
    ) {
        let seeds = sheet_seeds();
        let r = fuzzing::sheet_input(&apply(&seeds[k.index(seeds.len())], &muts));
        prop_assert!(r.violations.is_empty(), "{:?}", r.violations);
    }
}
