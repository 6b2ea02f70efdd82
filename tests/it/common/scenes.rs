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

/// The shipped scenes the GPU renders: every one (instances included: the compute path walks the
/// TLAS and each BLAS, ray queries build the hardware's own).
#[allow(dead_code)]
pub fn shipped_for_gpu() -> Vec<PathBuf> {
    shipped()
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

/// The shipped Cornell box (`scenes/cornell-area.toml`) with instances: a textured gem placed
/// three times (a uniform scale, a non-uniform one, a `matrix`), and the box's ball made a
/// prototype (its material `ball`) placed twice (once as it was, once as an egg). Read it with
/// `scenes/` as its folder (the gem is `icosahedron.obj`).
#[allow(dead_code)]
pub fn instanced_cornell(ball: &str) -> String {
    let mut text = std::fs::read_to_string(root().join("scenes/cornell-area.toml")).unwrap();
    text = text.replace(
        "name = \"mirror ball\"\ncenter = [0.45, 0.3, -0.25]\nradius = 0.3\nmaterial = \"mirror\"",
        &format!("name = \"mirror ball\"\ncenter = [0, 0, 0]\nradius = 0.3\nmaterial = \"{ball}\""),
    );
    text += r#"
[[texture]]
name = "check"
checker = [4, 4]
colors = [[0.9, 0.8, 0.3], [0.2, 0.3, 0.6]]

[[material]]
name = "gem"
bsdf = "diffuse"
color = [1, 1, 1]
texture = "check"

[[mesh]]
name = "gem"
obj = "icosahedron.obj"
material = "gem"

[[instance]]
name = "gem a"
of = "gem"
scale = 0.15
rotate = [0, 30, 0]
translate = [0.55, 0.29, 0.6]

[[instance]]
name = "gem b"
of = "gem"
scale = [0.12, 0.3, 0.12]
rotate = [15, 0, 20]
translate = [-0.02, 0.62, 0.75]

[[instance]]
name = "gem c"
of = "gem"
matrix = [[0.1, 0, 0.05, -0.3], [0, 0.12, 0, 1.3], [-0.05, 0, 0.1, 0.3]]

[[instance]]
name = "ball"
of = "mirror ball"
translate = [0.45, 0.3, -0.25]

[[instance]]
name = "egg"
of = "mirror ball"
scale = [1.4, 0.6, 1]
translate = [-0.35, 0.19, -0.55]
"#;
    text
}
