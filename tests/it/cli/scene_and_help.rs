//! `raystep scene check`, help and the bare command.

use super::*;

/// Every shipped scene validates, and the primitive count printed agrees with --json.
#[test]
fn scene_check_accepts_every_shipped_scene() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        n += 1;
        let out = ok(&Cli::with("scene check @", &[&path]));
        let v = json_of(&Cli::with("scene check @ --json", &[&path]));
        let prims = v["primitives"]
            .as_u64()
            .unwrap_or_else(|| panic!("{}: {v}", path.display()));
        assert!(
            out.contains(&format!("primitives {prims}")),
            "{}:\n{out}",
            path.display()
        );
    }
    assert!(n >= 1, "no scenes in {}", dir.display());
}

/// scenes/three-spheres.toml, counted from the file itself (read here as plain TOML, not by
/// raystep): at the time of writing 3 `[[sphere]]`, 1 `[[plane]]`, no `[[triangle]]` or
/// `[[mesh]]`, 1 `[[light]]`: 4 primitives; the sphere with material "mirror"
/// (reflective = 0.5) makes the scene reflective, and no material has transparency.
#[test]
fn scene_check_json_counts_three_spheres() {
    let text = std::fs::read_to_string(three_spheres()).unwrap();
    let file: toml::Table = toml::from_str(&text).unwrap();
    let tables = |k: &str| {
        file.get(k)
            .and_then(|v| v.as_array())
            .cloned()
            .unwrap_or_default()
    };
    assert!(
        tables("mesh").is_empty(),
        "this test counts triangles without reading OBJ files"
    );
    let materials = tables("material");
    let property = |name: &str, key: &str| {
        materials
            .iter()
            .find(|m| m.get("name").and_then(|n| n.as_str()) == Some(name))
            .and_then(|m| m.get(key))
            .and_then(|x| x.as_float().or_else(|| x.as_integer().map(|i| i as f64)))
            .unwrap_or(0.0)
    };
    let objects: Vec<toml::Value> = ["sphere", "plane", "triangle"]
        .iter()
        .flat_map(|k| tables(k))
        .collect();
    let used: Vec<&str> = objects
        .iter()
        .filter_map(|o| o.get("material").and_then(|m| m.as_str()))
        .collect();
    let reflective = used.iter().any(|m| property(m, "reflective") > 0.0);
    let transparent = used.iter().any(|m| property(m, "transparency") > 0.0);
    let (spheres, planes, triangles) = (
        tables("sphere").len(),
        tables("plane").len(),
        tables("triangle").len(),
    );
    // Sanity check of the counting against the file as written today.
    assert!(spheres >= 3 && planes >= 1 && reflective, "{text}");

    let v = json_of(&Cli::with("scene check @ --json", &[&three_spheres()]));
    assert_eq!(v["spheres"], spheres, "{v}");
    assert_eq!(v["planes"], planes, "{v}");
    assert_eq!(v["triangles"], triangles, "{v}");
    assert_eq!(v["meshes"], 0, "{v}");
    assert_eq!(v["lights"], tables("light").len(), "{v}");
    assert_eq!(v["primitives"], objects.len(), "{v}");
    assert_eq!(v["reflective"], reflective, "{v}");
    assert_eq!(v["transparent"], transparent, "{v}");

    let out = ok(&Cli::with("scene check @", &[&three_spheres()]));
    assert!(out.contains("ok"), "{out}");
    assert!(
        out.contains(&format!("primitives {}", objects.len())),
        "{out}"
    );
}

/// The one-sphere scene: 1 sphere, 1 light, nothing else; the default material neither
/// reflects nor transmits.
#[test]
fn scene_check_of_a_written_scene() {
    let (_dir, scene) = one_sphere();
    let v = json_of(&Cli::with("scene check @ --json", &[&scene]));
    assert_eq!(
        v,
        json!({
            "spheres": 1, "planes": 0, "triangles": 0, "smooth": 0, "textured": 0, "meshes": 0, "lights": 1,
            "reflective": false, "transparent": false, "primitives": 1, "emitters": 0,
            "instances": 0
        })
    );
    let out = ok(&Cli::with("scene check @", &[&scene]));
    assert!(out.contains("primitives 1"), "{out}");
}

// ---------------------------------------------------------------------------------------------
// Help and the bare command
// ---------------------------------------------------------------------------------------------

#[test]
fn help_and_no_arguments_succeed() {
    let out = ok(&Cli::new("--help"));
    for cmd in ["intersect", "trace", "scene"] {
        assert!(out.contains(cmd), "--help lacks {cmd}:\n{out}");
    }
    let out = ok(&Cli::new("intersect sphere --help"));
    for flag in [
        "--center",
        "--radius",
        "--origin",
        "--dir",
        "--method",
        "--precision",
        "--tmin",
        "--json",
    ] {
        assert!(
            out.contains(flag),
            "intersect sphere --help lacks {flag}:\n{out}"
        );
    }
    ok(&Cli::new("trace --help"));
    ok(&Cli::new("scene check --help"));
    // With no command raystep opens the app; without a display it says so and fails cleanly.
    raystep()
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .assert()
        .failure()
        .stderr(predicate::str::contains("cannot open the app window"))
        .stderr(predicate::str::contains("panicked").not());
    raystep()
        .args(["open", "no-such-scene.toml"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("no-such-scene.toml: no such file"));
}

// ---------------------------------------------------------------------------------------------

/// `docs/CLI.md`, the command-line reference, is clap's own help for every command, written out
/// as Markdown by `clap-markdown` from the very `Cli` the binary parses, so it cannot drift from
/// the program: a changed flag, default or help text fails here until the file is regenerated
/// (`UPDATE_GOLDEN=1 cargo test --test it cli::scene_and_help::the_cli_reference`).
#[test]
fn the_cli_reference_is_claps_own_help() {
    let options = clap_markdown::MarkdownOptions::new()
        .title("The raystep command line".into())
        .show_footer(false);
    let want = format!(
        "<!-- Generated from clap's own help by clap-markdown (tests/it/cli/scene_and_help.rs, \
         `the_cli_reference_is_claps_own_help`): do not edit; regenerate with UPDATE_GOLDEN=1. -->\n\n{}",
        clap_markdown::help_markdown_custom::<raystep::cli::Cli>(&options)
    );
    let path = crate::common::scenes::root().join("docs/CLI.md");
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::write(&path, &want).unwrap();
    }
    let got = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        got == want,
        "docs/CLI.md is not clap's help of this build: regenerate it with UPDATE_GOLDEN=1 cargo test --test it cli::scene_and_help::the_cli_reference"
    );
    // Every command is in it, with its flags.
    for heading in [
        "## `raystep trace`",
        "## `raystep grade-tracer`",
        "## `raystep scene check`",
    ] {
        assert!(got.contains(heading), "{heading}");
    }
}
