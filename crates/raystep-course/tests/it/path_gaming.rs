//! grade-tracer's path stages (format version 2) against outputs that print less: every stage
//! passes only on records it compared, so removing any record kind, or any field of one, from
//! an output — right or with planted mistakes — never raises a stage's verdict; a tracer that
//! draws its own random numbers and prints values three times too large passes no stage.

use raystep_course::student::compare::{Stage, TracerTolerances};
use raystep_course::student::path::{self, PathExpected, PathPixel};
use raystep_course::student::path_compare::grade;
use serde_json::Value;

use crate::common::scenes;
use scenes::root;

fn prepared(scene: &str, seed: Option<u32>) -> raystep_core::PreparedScene {
    let mut s = raystep_core::scene::load_file(&root().join(scene)).unwrap();
    if let Some(seed) = seed {
        s.settings.seed = seed;
    }
    raystep_core::PreparedScene::new(s)
}

/// Per path stage, whether `text` passes it (an output that cannot be read passes none).
fn passes(e: &PathExpected, text: &str) -> Vec<bool> {
    match path::parse(text) {
        Ok(px) => grade(e, &px, &Stage::PATH, &TracerTolerances::default())
            .into_iter()
            .map(|c| c.check.pass)
            .collect(),
        Err(_) => vec![false; Stage::PATH.len()],
    }
}

/// `text` with each line passed through `edit` (None drops it).
fn rewrite(text: &str, edit: impl Fn(Value) -> Option<Value>) -> String {
    text.lines()
        .filter_map(|l| edit(serde_json::from_str(l).unwrap()))
        .map(|v| v.to_string() + "\n")
        .collect()
}

fn scaled(p: &PathPixel, by: f64) -> PathPixel {
    let mut p = p.clone();
    for s in &mut p.samples {
        s.value = s.value.map(|v| v.map(|c| c * by));
    }
    p
}

#[test]
fn printing_less_never_scores_more() {
    let p = prepared("scenes/cornell-area.toml", None);
    let theirs = prepared("scenes/cornell-area.toml", Some(7));
    for [x, y] in [[128, 128], [60, 200], [200, 40]] {
        let e = path::expected(&p, x, y);
        // A right output; values three times too large; a tracer with its own random numbers
        // (raystep's with another seed), right and three times too bright; every BSDF number
        // wrong.
        let own = path::expected(&theirs, x, y).pixel;
        let mut wrong_random = e.pixel.clone();
        for s in &mut wrong_random.samples {
            for v in &mut s.vertices {
                if let Some(b) = v.sample.as_mut() {
                    for r in &mut b.random {
                        r.value = 0.5;
                    }
                }
            }
        }
        let bases = [
            ("right", e.pixel.clone()),
            ("values × 3", scaled(&e.pixel, 3.0)),
            ("own random numbers", own.clone()),
            ("own random numbers, values × 3", scaled(&own, 3.0)),
            ("wrong random numbers", wrong_random),
        ];
        for (name, base) in bases {
            let text = path::write(&base);
            let before = passes(&e, &text);
            // Every record kind dropped, and every field of every kind.
            let mut kinds: Vec<(String, Vec<String>)> = vec![];
            for l in text.lines() {
                let v: Value = serde_json::from_str(l).unwrap();
                let ty = v["type"].as_str().unwrap().to_string();
                let keys: Vec<String> = v
                    .as_object()
                    .unwrap()
                    .keys()
                    .filter(|k| *k != "type")
                    .cloned()
                    .collect();
                match kinds.iter_mut().find(|k| k.0 == ty) {
                    Some(k) => {
                        for key in keys {
                            if !k.1.contains(&key) {
                                k.1.push(key);
                            }
                        }
                    }
                    None => kinds.push((ty, keys)),
                }
            }
            assert!(kinds.len() >= 9, "{kinds:?}");
            for (ty, keys) in &kinds {
                let mut variants = vec![(
                    format!("no {ty} records"),
                    rewrite(&text, |v| (v["type"] != ty.as_str()).then_some(v)),
                )];
                for key in keys {
                    variants.push((
                        format!("{ty} without {key}"),
                        rewrite(&text, |mut v| {
                            if v["type"] == ty.as_str() {
                                v.as_object_mut().unwrap().remove(key);
                            }
                            Some(v)
                        }),
                    ));
                }
                for (what, t) in variants {
                    let after = passes(&e, &t);
                    for (i, st) in Stage::PATH.iter().enumerate() {
                        assert!(
                            !after[i] || before[i],
                            "({x}, {y}), {name}, {what}: the {} stage passes, and failed with the record",
                            st.name()
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn outputs_that_print_almost_nothing_score_nothing() {
    let p = prepared("scenes/cornell-area.toml", None);
    let e = path::expected(&p, 128, 128);
    let text = path::write(&e.pixel);
    // Only `path` and `value` records (raystep's own values), and sixteen bare `path` lines.
    let path_value = rewrite(&text, |v| {
        matches!(
            v["type"].as_str(),
            Some("format" | "pixel" | "path" | "value")
        )
        .then_some(v)
    });
    let bare: String = (0..16)
        .map(|k| format!("{{\"type\":\"path\",\"sample\":{k}}}\n"))
        .collect();
    for (what, t) in [("path and value", path_value), ("bare paths", bare)] {
        assert_eq!(
            passes(&e, &t),
            vec![false; Stage::PATH.len()],
            "{what}: a stage passes"
        );
    }
}

#[test]
fn own_random_numbers_with_wrong_values_pass_no_estimate() {
    // Where the own tracer's paths part from raystep's after the camera ray, nothing of the
    // estimate is comparable sample by sample: the stage fails (and the statistical mode is the
    // way to grade such a tracer).
    let p = prepared("scenes/cornell-area.toml", None);
    let theirs = prepared("scenes/cornell-area.toml", Some(7));
    for y in (8..256).step_by(48) {
        for x in (8..256).step_by(48) {
            let e = path::expected(&p, x, y);
            let own = scaled(&path::expected(&theirs, x, y).pixel, 3.0);
            let v = passes(&e, &path::write(&own));
            let at = Stage::PATH
                .iter()
                .position(|s| *s == Stage::Estimate)
                .unwrap();
            assert!(!v[at], "({x}, {y}): estimate passes");
        }
    }
}

#[test]
fn raysteps_own_samples_pass_every_stage_across_the_image() {
    // The estimate's sum of contributions holds for raystep's own paths, deep ones included,
    // in both path-traced scenes.
    for scene in ["scenes/cornell-area.toml", "scenes/veach-mis.toml"] {
        let p = prepared(scene, None);
        let (w, h) = (p.scene().camera.width, p.scene().camera.height);
        for y in (3..h).step_by((h / 5).max(1) as usize) {
            for x in (5..w).step_by((w / 5).max(1) as usize) {
                let e = path::expected(&p, x, y);
                let v = passes(&e, &path::write(&e.pixel));
                assert_eq!(v, vec![true; Stage::PATH.len()], "{scene} ({x}, {y})");
            }
        }
    }
}

#[test]
fn a_record_that_cannot_be_read_names_its_field_and_what_it_must_be() {
    // Roulette's `random` as a list (it is one draw object): the error names the record, the
    // field and what it must be (it said "invalid type: map, expected u32").
    let text = "{\"type\":\"format\",\"version\":2}\n{\"type\":\"pixel\",\"x\":1,\"y\":1}\n{\"type\":\"path\",\"sample\":0}\n{\"type\":\"ray\",\"depth\":0}\n{\"type\":\"roulette\",\"random\":[{\"dimension\":22,\"value\":0.5}],\"probability\":1}\n";
    let err = path::parse(text).unwrap_err().to_string();
    assert!(
        err.contains("the \"roulette\" record's \"random\" cannot be read"),
        "{err}"
    );
    assert!(
        err.contains("one {\"dimension\": D, \"value\": u} object"),
        "{err}"
    );
    let text = "{\"type\":\"format\",\"version\":2}\n{\"type\":\"path\",\"sample\":0}\n{\"type\":\"ray\",\"depth\":0,\"origin\":[1,2]}\n";
    let err = path::parse(text).unwrap_err().to_string();
    assert!(err.contains("line 3"), "{err}");
    assert!(
        err.contains("the \"ray\" record's \"origin\" cannot be read") && err.contains("[x, y, z]"),
        "{err}"
    );
}
