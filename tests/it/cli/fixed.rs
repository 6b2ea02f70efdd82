//! Bugs found in the code and fixed: each test names the command that showed it.

use super::*;

/// A saved trace must load back (DESIGN: "loading a trace needs no scene"). The first
/// closest-hit step records `previous` = ∞, which serde_json writes as `null`, and an `f32`
/// field does not deserialize from `null`:
/// `raystep trace scenes/three-spheres.toml --pixel 160,120 --save t.json`, then
/// `Trace::load("t.json")` → "not a raystep trace: invalid type: null, expected f32".
#[test]
fn saved_trace_loads_back() {
    let dir = tempfile::tempdir().unwrap();
    let saved = dir.path().join("t.json");
    ok(&Cli::with(
        "trace @ --pixel 160,120 --save @",
        &[&three_spheres(), &saved],
    ));
    raystep::record::Trace::load(&saved).unwrap_or_else(|e| panic!("{e}"));
}

/// `--offset` of the axis-aligned plane takes any f64, NaN and ∞ included, while the vector
/// arguments reject them: `raystep intersect plane --axis x --offset nan --origin 0,0,-5
/// --dir 1,0,1 --json` exits 0 with `"numerator": null`.
#[test]
fn non_finite_plane_offset_is_rejected() {
    for c in ["nan", "inf"] {
        fails(
            &Cli::new(&format!(
                "intersect plane --axis x --offset {c} --origin 0,0,-5 --dir 1,0,1"
            )),
            &["--offset"],
        );
    }
}

/// Shape parameters finite in f64 but beyond f32's range become ∞ in the default f32 precision,
/// and the calculator prints NaN intermediates with exit 0:
/// `raystep intersect sphere --center 1e300,0,0 --radius 1 --origin 0,0,-5 --dir 0,0,1 --json`
/// → `"b": null, "discriminant": null`. The ray's origin is rejected in the same situation.
#[test]
fn shape_parameters_overflowing_f32_are_rejected() {
    fails(&sphere("1e300,0,0", "1", "0,0,-5", "0,0,1"), &["--center"]);
    fails(
        &Cli::new(
            "intersect triangle --p0 1e300,0,0 --p1 0,1,0 --p2 0,0,1 --origin 0,0,-5 --dir 0,0,1",
        ),
        &["--p0"],
    );
}

/// `--accel bvh` is accepted by `trace` and recorded in the trace's settings, but the trace is
/// made by brute force (src/cli/trace_cmd.rs always passes `&BruteForce`): no BVH node steps.
#[test]
fn trace_with_bvh_records_node_visits() {
    let v = json_of(&Cli::with(
        "trace @ --pixel 160,120 --accel bvh --json",
        &[&three_spheres()],
    ));
    assert_eq!(v["settings"]["accel"], "bvh");
    let steps = v["root"]["steps"].as_array().unwrap();
    assert!(
        steps.iter().any(|s| s["type"] == "node"),
        "no BVH node steps in a BVH trace"
    );
}

// ---------------------------------------------------------------------------------------------
