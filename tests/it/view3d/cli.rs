//! `raystep view`: the pictures it writes, its refusals, and a snapshot.

use super::*;

/// Two steps of one pixel give different pictures; each shows the scene (many colours, mostly
/// not the background).
#[test]
fn view_pngs_of_two_steps_differ_and_show_the_scene() {
    if !have_adapter("view_pngs_of_two_steps_differ_and_show_the_scene") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cornell = scene_file("cornell.toml");
    let [x, y] = CORNELL_MIRROR_PIXEL;
    let last = prepared(&cornell).record(x, y, 0).timeline().len() - 1;
    let a = view(
        &cornell,
        &format!("--pixel {x},{y} --step 0 --size 320x180"),
        &dir.path().join("a.png"),
    );
    let b = view(
        &cornell,
        &format!("--pixel {x},{y} --step {last} --size 320x180"),
        &dir.path().join("b.png"),
    );
    let bg = raystep::diagram::Theme::DARK.background;
    for (which, img) in [("step 0", &a), ("the last step", &b)] {
        assert_eq!(img.dimensions(), (320, 180), "{which}");
        let mut colours: Vec<[u8; 3]> = img.pixels().map(|p| [p[0], p[1], p[2]]).collect();
        let background = colours
            .iter()
            .filter(|c| c.iter().zip(bg).all(|(a, b)| a.abs_diff(b) <= 2))
            .count();
        colours.sort();
        colours.dedup();
        assert!(colours.len() >= 100, "{which}: {} colours", colours.len());
        // The orbit fits the whole scene, camera included, in view: the room fills a good part
        // of the picture, not all of it.
        let share = background as f64 / f64::from(320 * 180);
        assert!(
            (0.2..0.9).contains(&share),
            "{which}: {:.0}% background",
            share * 100.0
        );
    }
    let differ = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
    assert!(differ >= 50, "the two steps differ in only {differ} pixels");
    // The reflection ray (the theme's reflection colour) is drawn at the last step only.
    let reflect = raystep::diagram::Theme::DARK.reflect;
    let blue = |img: &image::RgbaImage| {
        img.pixels()
            .filter(|p| (0..3).all(|i| p[i].abs_diff(reflect[i]) <= 12))
            .count()
    };
    eprintln!(
        "reflection-coloured pixels: step 0 {}, last step {}",
        blue(&a),
        blue(&b)
    );
    assert!(
        blue(&a) == 0 && blue(&b) >= 30,
        "reflection-coloured pixels: {} then {}",
        blue(&a),
        blue(&b)
    );
}

/// Looking through the camera without --size: a picture of the camera's proportions (cornell's
/// 320×320 camera: 720×720, the largest within 1280×720), with the primary ray's hit marker (the
/// theme's hit colour) where the pixel traced lands: (x + ½, y + ½)·720/320.
#[test]
fn view_through_the_camera_keeps_its_proportions_and_marks_the_hit_on_the_pixel() {
    if !have_adapter("view_through_the_camera_keeps_its_proportions_and_marks_the_hit_on_the_pixel")
    {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let [x, y] = CORNELL_MIRROR_PIXEL;
    let img = view(
        &scene_file("cornell.toml"),
        &format!("--pixel {x},{y} --through-camera"),
        &dir.path().join("through.png"),
    );
    assert_eq!(img.dimensions(), (720, 720));
    let k = 720.0 / 320.0;
    let want = [(x as f32 + 0.5) * k, (y as f32 + 0.5) * k];
    let hit = raystep::diagram::Theme::DARK.hit;
    let nearest = img
        .enumerate_pixels()
        .filter(|(_, _, p)| (0..3).all(|i| p[i].abs_diff(hit[i]) <= 40))
        .map(|(px, py, _)| (px as f32 + 0.5 - want[0]).hypot(py as f32 + 0.5 - want[1]))
        .fold(f32::INFINITY, f32::min);
    assert!(
        nearest <= 3.0,
        "the nearest hit-coloured pixel is {nearest} px from {want:?}"
    );
}

/// Bad arguments: a non-zero exit, a message that names the problem, and no file written.
#[test]
fn view_rejects_bad_arguments_without_writing_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let cornell = scene_file("cornell.toml");
    let missing = dir.path().join("no-such-scene.toml");
    let cases: [(&Path, &str, &str, &str); 8] = [
        (
            &cornell,
            "--pixel 320,5",
            "out.png",
            "outside the 320×320 image",
        ),
        (
            &cornell,
            "--pixel 5,320",
            "out.png",
            "outside the 320×320 image",
        ),
        (
            &cornell,
            "--pixel 5,5 --step 1000000",
            "out.png",
            "--step 1000000 does not exist",
        ),
        (&cornell, "--step 3", "out.png", "--step needs --pixel"),
        (&cornell, "--pixel 5,5 --size 10x10", "out.png", "from 64"),
        (
            &cornell,
            "--pixel 5,5 --orbit 0,95",
            "out.png",
            "between -89 and 89",
        ),
        (&cornell, "--pixel 5,5", "out.jpg", "must be a .png"),
        // cornell's camera is 320×320: a 16:9 picture of it would be stretched.
        (
            &cornell,
            "--pixel 5,5 --through-camera --size 1280x720",
            "out.png",
            "--through-camera draws the camera's view, which is 320×320",
        ),
    ];
    let missing_case = (missing.as_path(), "--pixel 5,5", "out.png", "no-such-scene");
    for (scene, args, out, says) in cases.into_iter().chain([missing_case]) {
        let out = dir.path().join(out);
        let run = raystep()
            .arg("view")
            .arg(scene)
            .args(args.split_whitespace())
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(
            !run.status.success(),
            "{args} -o {}: succeeded",
            out.display()
        );
        assert!(
            stderr.contains(says),
            "{args}: the message {stderr:?} lacks {says:?}"
        );
        assert!(!stderr.contains("panicked"), "{args}: {stderr}");
        assert!(!out.exists(), "{args}: {} was written", out.display());
    }
}

// ---------------------------------------------------------------------------------------------
// 7. A snapshot
// ---------------------------------------------------------------------------------------------

/// `raystep view` of the Cornell box with a mirror-ball pixel's rays (a reflection among them),
/// from a fixed orbit at 640×360, against tests/snapshots/view3d-cornell-mirror.png (rendered on
/// lavapipe; `UPDATE_SNAPSHOTS=1 cargo test --test it view3d::` rewrites it after an intended
/// change). The thresholds are the app snapshots': they tolerate driver noise in antialiased
/// edges, not a moved ray or a missing object.
#[test]
fn snapshot_of_the_cornell_box_with_a_reflection() {
    let cornell = scene_file("cornell.toml");
    let [x, y] = CORNELL_MIRROR_PIXEL;
    let t = prepared(&cornell).record(x, y, 0);
    assert!(
        t.rays()
            .iter()
            .any(|r| r.kind == RayKind::Reflection && r.hit.is_some()),
        "pixel {x},{y} of cornell.toml has a reflection that hits something"
    );
    if !have_adapter("snapshot_of_the_cornell_box_with_a_reflection") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let img = view(
        &cornell,
        &format!("--pixel {x},{y} --orbit 30,20 --size 640x360"),
        &dir.path().join("view.png"),
    );
    assert_eq!(img.dimensions(), (640, 360));
    egui_kittest::try_image_snapshot_options(
        &img,
        "view3d-cornell-mirror",
        &egui_kittest::SnapshotOptions::new()
            .threshold(2.0)
            .max_failed_pixels(200),
    )
    .unwrap_or_else(|e| panic!("{e}"));
}
