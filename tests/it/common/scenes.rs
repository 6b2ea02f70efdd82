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
