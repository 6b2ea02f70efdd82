//! The repository's root and its shipped scene files, for the tests that walk every scene.

use std::path::PathBuf;

/// The repository's root.
pub fn root() -> PathBuf {
    let mut p = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    while !p.join("crates").is_dir() {
        assert!(p.pop(), "no folder above the test's crate holds crates/");
    }
    p
}

/// Every `scenes/*.toml`, sorted.
pub fn shipped() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(root().join("scenes"))
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

/// The shipped scenes the GPU renders: all but those that place instances (`[[instance]]`),
/// which the GPU does not trace yet (it says so instead of rendering).
#[allow(dead_code)]
pub fn shipped_for_gpu() -> Vec<PathBuf> {
    shipped()
        .into_iter()
        .filter(|p| !std::fs::read_to_string(p).unwrap().contains("[[instance]]"))
        .collect()
}

/// The shipped scenes rendered by Whitted's tracer (no `integrator =` line): the ones the student
/// format, the grader and the camera-convention tests are about.
#[allow(dead_code)]
pub fn shipped_whitted() -> Vec<PathBuf> {
    shipped()
        .into_iter()
        .filter(|p| {
            !std::fs::read_to_string(p)
                .unwrap()
                .lines()
                .any(|l| l.trim_start().starts_with("integrator"))
        })
        .collect()
}

/// The Whitted scenes the starter kit's model tracer (lessons/starter/tracer.py) reads: all but
/// those with instances, which the kit does not trace yet (it knows no `[[instance]]`).
#[allow(dead_code)]
pub fn shipped_for_students() -> Vec<PathBuf> {
    shipped_whitted()
        .into_iter()
        .filter(|p| !std::fs::read_to_string(p).unwrap().contains("[[instance]]"))
        .collect()
}
