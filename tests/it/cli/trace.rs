//! `raystep trace`: JSON, the tree, --save, the step numbers, determinism.

use super::*;

/// The camera at (0, 0, −5) looking at the origin: w = normalize(from − at) = (0, 0, −1),
/// u = normalize(up × w) = (0, 1, 0) × (0, 0, −1) = (−1, 0, 0), v = w × u = (0, 1, 0).
/// Pixel (50, 50) of 101×101 at its centre: sx = 2·50.5/101 − 1 = 0 and
/// sy = 1 − 2·50.5/101 = 0 (exact in f32), so the direction is normalize(−w) = (0, 0, 1) and
/// the ray meets the unit sphere where −5 + t = −1: t = 4 (the enter-exit case above).
#[test]
fn trace_json_centre_pixel_hits_the_sphere_at_t4() {
    let (_dir, scene) = one_sphere();
    let v = json_of(&Cli::with("trace @ --pixel 50,50 --json", &[&scene]));
    assert_eq!(v["version"], 1);
    assert_eq!(v["pixel"], json!([50, 50]));
    assert_eq!(v["sample"], 0);
    let root = &v["root"];
    assert_eq!(root["kind"], "primary");
    assert_eq!(root["depth"], 0);
    assert_eq!(nums(&root["origin"]), [0.0, 0.0, -5.0]);
    assert_eq!(nums(&root["direction"]), [0.0, 0.0, 1.0]);
    let camera = &root["steps"][0];
    assert_eq!(camera["type"], "camera");
    assert_eq!(camera["stage"], "ray-generation");
    assert_eq!(camera["pixel"], json!([50, 50]));
    assert_eq!(
        nums(&camera["offset"]),
        [0.5, 0.5],
        "spp = 1: the pixel centre"
    );
    assert_eq!(nums(&camera["screen"]), [0.0, 0.0]);
    assert_eq!(nums(&camera["direction"]), [0.0, 0.0, 1.0]);

    let steps = root["steps"].as_array().unwrap();
    let test = steps
        .iter()
        .find(|s| s["type"] == "sphere")
        .expect("a sphere test step");
    assert_eq!(test["stage"], "intersection");
    assert_eq!(test["name"], "ball");
    assert_eq!(num(&test["test"], "discriminant"), 4.0);
    assert_eq!(nums(&test["test"]["roots"]), [4.0, 6.0]);

    assert_eq!(root["hit"]["name"], "ball");
    assert_eq!(num(&root["hit"], "t"), 4.0);
    // The lit sphere sends a shadow ray towards "lamp".
    let children = root["children"].as_array().unwrap();
    assert!(children.iter().any(|c| c["kind"] == "shadow"), "{root}");
}

/// Pixel (0, 0) looks about 39° off the axis (sx ≈ sy ≈ ±0.99 times tan 30° ≈ 0.57 each), while
/// the sphere subtends asin(1/5) ≈ 11.5° from the camera: the primary ray misses and returns
/// the default black background.
#[test]
fn trace_json_corner_pixel_misses() {
    let (_dir, scene) = one_sphere();
    let v = json_of(&Cli::with("trace @ --pixel 0,0 --json", &[&scene]));
    let root = &v["root"];
    assert!(root["hit"].is_null(), "{root}");
    let steps = root["steps"].as_array().unwrap();
    assert!(
        steps
            .iter()
            .any(|s| s["type"] == "miss" && s["stage"] == "miss"),
        "{root}"
    );
    assert_eq!(nums(&v["color"]), [0.0, 0.0, 0.0]);
}

#[test]
fn trace_tree_names_rays_and_stages() {
    let (_dir, scene) = one_sphere();
    let out = ok(&Cli::with("trace @ --pixel 50,50", &[&scene]));
    for want in [
        "primary ray",
        "[ray-generation]",
        "[intersection]",
        "shadow ray",
        "[closest-hit] light",
        "\"ball\"",
    ] {
        assert!(out.contains(want), "tree lacks {want:?}:\n{out}");
    }
    assert_in_order(
        &out,
        &["primary ray", "[0] [ray-generation]", "[1] [intersection]"],
    );

    let out = ok(&Cli::with("trace @ --pixel 160,120", &[&three_spheres()]));
    for want in [
        "primary ray",
        "[ray-generation]",
        "[intersection]",
        "shadow ray",
        "[closest-hit] light",
    ] {
        assert!(
            out.contains(want),
            "three-spheres tree lacks {want:?}:\n{out}"
        );
    }
}

/// `raystep trace` numbers every step `[K]` as the app's step list does: from 0, over the whole
/// timeline in the order it happened, the spawn steps included and a child ray's steps right
/// after its spawn step. The numbers are read against the JSON trace walked here, and against
/// what the app's step list shows for this pixel (its snapshot, tests/snapshots/
/// app-three-spheres-quadratic.png: "9. → child ray 0", then the shadow ray from 10 to 13);
/// the last K is one `diagram --step` takes, K + 1 is not.
#[test]
fn trace_numbers_every_step_as_the_app_and_step_arguments_do() {
    let scene = three_spheres();
    let text = ok(&Cli::with("trace @ --pixel 150,110", &[&scene]));
    let json = json_of(&Cli::with("trace @ --pixel 150,110 --json", &[&scene]));

    // The timeline from the JSON: (stage, type) of every step, children where spawned.
    fn walk(ray: &Value, out: &mut Vec<(String, String)>) {
        for s in ray["steps"].as_array().unwrap() {
            out.push((
                s["stage"].as_str().unwrap().to_string(),
                s["type"].as_str().unwrap().to_string(),
            ));
            if s["type"] == "spawn" {
                walk(&ray["children"][s["child"].as_u64().unwrap() as usize], out);
            }
        }
    }
    let mut timeline = vec![];
    walk(&json["root"], &mut timeline);

    // The step lines: "[K] [stage] …", indented under their ray.
    let steps: Vec<(usize, &str, &str)> = text
        .lines()
        .filter_map(|l| {
            let rest = l.trim_start().strip_prefix('[')?;
            let (k, rest) = rest.split_once("] [")?;
            let (stage, words) = rest.split_once("] ")?;
            Some((k.parse().ok()?, stage, words))
        })
        .collect();
    assert_eq!(
        steps.len(),
        timeline.len(),
        "one numbered line per step:\n{text}"
    );
    for (i, ((k, stage, words), (json_stage, kind))) in steps.iter().zip(&timeline).enumerate() {
        assert_eq!(*k, i, "the steps are numbered 0, 1, 2, … in order:\n{text}");
        assert_eq!(stage, json_stage, "step {k}");
        assert_eq!(
            kind == "spawn",
            words.starts_with("→ child ray"),
            "step {k}: {words}"
        );
    }
    assert_eq!(
        timeline.len(),
        16,
        "the app's list shows steps 0–15 for this pixel"
    );
    assert!(steps[9].2.starts_with("→ child ray 0"), "{text}");
    assert!(steps[11].2.starts_with("sphere \"middle\""), "{text}");
    // The child ray's header comes right after its spawn step, its first step right after it.
    let spawn = line_index(&text, "[9] [closest-hit]").expect("the spawn step's line");
    assert_eq!(line_index(&text, "shadow ray ("), Some(spawn + 1), "{text}");
    assert_eq!(
        line_index(&text, "[10] [intersection]"),
        Some(spawn + 2),
        "{text}"
    );

    // The printed numbers are the ones --step takes.
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("last.png");
    let last = timeline.len() - 1;
    ok(&Cli::with(
        &format!("diagram @ --pixel 150,110 --step {last} -o @"),
        &[&scene, &png],
    ));
    assert!(png.is_file());
    fails(
        &Cli::with(
            &format!("diagram @ --pixel 150,110 --step {} -o @", last + 1),
            &[&scene, &png],
        ),
        &["--step 16 does not exist", "16 steps (0 … 15)"],
    );
}

/// --save writes the very JSON that --json prints, complete, and nothing else beside it (the
/// write goes through a temporary file renamed over the target).
#[test]
fn trace_save_writes_the_same_json() {
    let (_dir, scene) = one_sphere();
    let out_dir = tempfile::tempdir().unwrap();
    let saved = out_dir.path().join("trace.json");
    let printed = json_of(&Cli::with(
        "trace @ --pixel 50,50 --json --save @",
        &[&scene, &saved],
    ));
    let text = std::fs::read_to_string(&saved).expect("the trace file exists");
    let from_file: Value = serde_json::from_str(&text).expect("the saved trace is complete JSON");
    assert_eq!(from_file, printed);
    assert_eq!(
        file_names(out_dir.path()),
        ["trace.json"],
        "no temporary file is left"
    );

    // Without --json the tree goes to stdout and the file still gets the JSON; overwriting works.
    let tree = ok(&Cli::with(
        "trace @ --pixel 50,50 --save @",
        &[&scene, &saved],
    ));
    assert!(tree.contains("primary ray"), "{tree}");
    let again: Value = serde_json::from_str(&std::fs::read_to_string(&saved).unwrap()).unwrap();
    assert_eq!(again, printed);
    assert_eq!(file_names(out_dir.path()), ["trace.json"]);
}

/// Deterministic (DESIGN principle 5): the same pixel and sample give the same trace, jittered
/// samples too; the sample's position inside the pixel lies in [0, 1)².
#[test]
fn trace_is_deterministic_and_samples_stay_in_the_pixel() {
    let (_dir, scene) = one_sphere();
    for sample in [0, 3] {
        let cli = Cli::with(
            &format!("trace @ --pixel 50,50 --spp 4 --sample {sample} --json"),
            &[&scene],
        );
        let a = ok(&cli);
        assert_eq!(a, ok(&cli), "sample {sample}");
        let v: Value = serde_json::from_str(&a).unwrap();
        assert_eq!(v["sample"], sample);
        assert_eq!(v["settings"]["spp"], 4);
        for o in nums(&v["root"]["steps"][0]["offset"]) {
            assert!((0.0..1.0).contains(&o), "sample {sample}: offset {o}");
        }
    }
}

/// Every offset policy, and other setting overrides, still give a trace that parses, with the
/// chosen settings recorded in it and a finite colour.
#[test]
fn trace_with_each_offset_policy_parses() {
    for offset in ["none", "fixed", "robust"] {
        let v = json_of(&Cli::with(
            &format!("trace @ --pixel 160,120 --offset {offset} --json"),
            &[&three_spheres()],
        ));
        assert_eq!(v["version"], 1, "{offset}");
        assert_eq!(v["settings"]["offset"], offset);
        assert_eq!(v["root"]["kind"], "primary");
        assert!(
            nums(&v["color"]).iter().all(|c| c.is_finite()),
            "{offset}: {}",
            v["color"]
        );
    }
    let v = json_of(&Cli::with(
        "trace @ --pixel 160,120 --sphere-method textbook --max-depth 0 --json",
        &[&three_spheres()],
    ));
    assert_eq!(v["settings"]["sphere_method"], "textbook");
    assert_eq!(v["settings"]["max_depth"], 0);
}

// ---------------------------------------------------------------------------------------------

/// `--camera NAME` looks through a camera of the scene's glTF file: gltf-table.toml places
/// gltf/table.gltf turned 180° about y, so its camera "front" at (0, 1.3, 2.6) stands at
/// (0, 1.3, −2.6); the image keeps the scene's 256 × 256. An unknown name lists the known ones.
#[test]
fn camera_picks_a_gltf_camera_by_name() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/gltf-table.toml");
    let v = json_of(&Cli::with(
        "trace @ --pixel 128,128 --camera front --integrator whitted --json",
        &[&scene],
    ));
    let from = nums(&v["camera"]["from"]);
    close(from[0], 0.0, 1e-6, "x");
    close(from[1], 1.3, 1e-6, "y");
    close(from[2], -2.6, 1e-6, "z");
    assert_eq!(
        (
            v["camera"]["width"].as_u64(),
            v["camera"]["height"].as_u64()
        ),
        (Some(256), Some(256))
    );
    fails(
        &Cli::with("trace @ --pixel 1,1 --camera side", &[&scene]),
        &["no camera named \"side\"", "known: \"front\""],
    );
}
