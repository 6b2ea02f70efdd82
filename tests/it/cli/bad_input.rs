//! Bad input on the command line: a clear message and a non-zero exit, never a panic.

use super::*;

#[test]
fn bad_vectors_are_rejected() {
    fails(&sphere("0,0,0", "1", "0,0,-5", "0,0,0"), &["zero"]);
    fails(
        &sphere("0,0,0", "1", "0,0,-5", "0,0,nan"),
        &["--dir", "finite"],
    );
    fails(
        &sphere("0,0,0", "1", "0,0,-5", "0,0,inf"),
        &["--dir", "finite"],
    );
    fails(&sphere("0,0,0", "1", "0,0,-5", "0,1"), &["--dir", "three"]);
    fails(
        &sphere("0,0,0", "1", "0,0,-5", "0,1,2,3"),
        &["--dir", "three"],
    );
    fails(
        &sphere("0,0,0", "1", "a,b,c", "0,0,1"),
        &["--origin", "not a number"],
    );
    fails(&sphere("x,0,0", "1", "0,0,-5", "0,0,1"), &["--center"]);
    // The same checks guard every shape's vectors.
    fails(&Cli::new(TRI).and("--origin 0,0,-5 --dir 0,0,0"), &["zero"]);
    fails(
        &Cli::new(CUBE).and("--origin 0,0,-5 --dir nan,0,1"),
        &["--dir"],
    );
    fails(
        &Cli::new("intersect plane --axis y --offset 0 --origin 0,0,-5 --dir 0,0"),
        &["--dir"],
    );
}

#[test]
fn bad_sphere_radius_is_rejected() {
    for r in ["-1", "0", "nan", "inf", "one"] {
        fails(&sphere("0,0,0", r, "0,0,-5", "0,0,1"), &["--radius"]);
    }
}

#[test]
fn bad_plane_is_rejected() {
    let ray = "--origin 0,1,0 --dir 0,-1,0";
    fails(
        &Cli::new("intersect plane --point 0,0,0 --normal 0,0,0").and(ray),
        &["--normal"],
    );
    // --point without --normal; the two forms mixed; an unknown axis.
    fails(
        &Cli::new("intersect plane --point 0,0,0").and(ray),
        &["--normal"],
    );
    fails(
        &Cli::new("intersect plane --point 0,0,0 --normal 0,1,0 --axis y").and(ray),
        &["--axis"],
    );
    fails(&Cli::new("intersect plane --axis w").and(ray), &["--axis"]);
}

#[test]
fn bad_box_is_rejected() {
    let ray = "--origin 0,0,-5 --dir 0,0,1";
    fails(
        &Cli::new("intersect box --min 1,1,1 --max -1,-1,-1").and(ray),
        &["--min", "--max"],
    );
    // min > max on one axis only.
    fails(
        &Cli::new("intersect box --min -1,2,-1 --max 1,1,1").and(ray),
        &["--min"],
    );
}

#[test]
fn unknown_method_precision_or_command_is_rejected() {
    let ray = "--origin 0,0,-5 --dir 0,0,1";
    fails(
        &sphere("0,0,0", "1", "0,0,-5", "0,0,1").and("--method quadratic"),
        &["quadratic", "--method"],
    );
    fails(
        &Cli::new(TRI).and(ray).and("--method moller"),
        &["--method"],
    );
    fails(&Cli::new(CUBE).and(ray).and("--method fast"), &["--method"]);
    fails(
        &sphere("0,0,0", "1", "0,0,-5", "0,0,1").and("--precision f16"),
        &["--precision"],
    );
    fails(&Cli::new("intersect cone"), &["cone"]);
    fails(&Cli::new("frobnicate"), &["frobnicate"]);
}

#[test]
fn bad_trace_arguments_are_rejected() {
    let (_dir, scene) = one_sphere();
    let trace = |more: &str| Cli::with("trace @", &[&scene]).and(more);
    // The image is 101×101: x and y run 0 … 100.
    fails(&trace("--pixel 101,0"), &["--pixel", "outside"]);
    fails(&trace("--pixel 0,101"), &["--pixel", "outside"]);
    fails(&trace("--pixel 1,2,3"), &["--pixel"]);
    fails(&trace("--pixel a,b"), &["--pixel"]);
    fails(&trace(""), &["--pixel"]);
    // One sample per pixel: sample 0 only; with --spp 4, samples 0 … 3.
    fails(&trace("--pixel 50,50 --sample 1"), &["--sample"]);
    fails(&trace("--pixel 50,50 --spp 4 --sample 4"), &["--sample"]);
    fails(&trace("--pixel 50,50 --spp 0"), &["--spp"]);
    fails(&trace("--pixel 50,50 --offset sideways"), &["--offset"]);
    fails(
        &trace("--pixel 50,50 --sphere-method quadratic"),
        &["--sphere-method"],
    );
}

#[test]
fn missing_scene_file_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("no-such-scene.toml");
    fails(
        &Cli::with("trace @ --pixel 0,0", &[&missing]),
        &["no-such-scene.toml"],
    );
    fails(
        &Cli::with("scene check @", &[&missing]),
        &["no-such-scene.toml"],
    );
}

/// A syntax error: the array on line 6 is not closed, so the parser meets `radius` at line 7,
/// column 1, where it expects `,` or `]`. A semantic error: `radius = -1` is line 4, column 1.
/// An unknown field: `colour` is line 4, column 1. Each message starts with file:line:column.
#[test]
fn malformed_scene_names_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let syntax = write_scene(
        dir.path(),
        "syntax.toml",
        "[camera]\nwidth = 10\n\n[[sphere]]\nname = \"a\"\ncenter = [0, 0\nradius = 1\n",
    );
    let at = format!("{}:7:1", syntax.display());
    fails(&Cli::with("scene check @", &[&syntax]), &[&at]);
    fails(&Cli::with("trace @ --pixel 0,0", &[&syntax]), &[&at]);

    let semantic = write_scene(
        dir.path(),
        "semantic.toml",
        "[[sphere]]\nname = \"a\"\ncenter = [0, 0, 0]\nradius = -1\n",
    );
    let at = format!("{}:4:1", semantic.display());
    fails(&Cli::with("scene check @", &[&semantic]), &[&at, "radius"]);

    let unknown = write_scene(
        dir.path(),
        "unknown.toml",
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\ncolour = 3\n",
    );
    let at = format!("{}:4:1", unknown.display());
    fails(&Cli::with("scene check @", &[&unknown]), &[&at, "colour"]);
}

#[test]
fn save_into_a_missing_directory_fails_and_creates_nothing() {
    let (dir, scene) = one_sphere();
    let missing_dir = dir.path().join("not-here");
    let target = missing_dir.join("trace.json");
    fails(
        &Cli::with("trace @ --pixel 50,50 --save @", &[&scene, &target]),
        &["not-here"],
    );
    assert!(!target.exists());
    assert!(!missing_dir.exists());
    // Saving onto an existing directory fails too, and leaves it alone.
    fails(
        &Cli::with("trace @ --pixel 50,50 --save @", &[&scene, &dir.path()]),
        &["directory"],
    );
    assert!(dir.path().is_dir());
    // A failed trace (bad pixel) writes no file.
    let never = dir.path().join("never.json");
    fails(
        &Cli::with("trace @ --pixel 500,0 --save @", &[&scene, &never]),
        &["--pixel"],
    );
    assert!(!never.exists());
    assert_eq!(
        file_names(dir.path()),
        ["one.toml"],
        "nothing but the scene is left"
    );
}

// ---------------------------------------------------------------------------------------------
