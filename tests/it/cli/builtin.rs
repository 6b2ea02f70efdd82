//! Built-in scenes and lessons, `examples`, the diagrams' frame delay, `render --profile`, a
//! closed pipe.

use super::*;

#[test]
fn examples_write_every_built_in_file_and_refuse_to_overwrite() {
    let dir = tempfile::tempdir().unwrap();
    let out = ok(&Cli::with("examples --write @", &[&dir.path()]));
    let root = std::fs::canonicalize(dir.path()).unwrap();
    // Every file of the repository's scenes/ and lessons/ folders (the starter kit too), byte
    // for byte, named with its full path.
    let repo = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut count = 0;
    for sub in [
        "scenes",
        "scenes/gltf",
        "scenes/textures",
        "lessons",
        "lessons/exercises",
        "lessons/starter",
    ] {
        for e in std::fs::read_dir(repo.join(sub)).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                continue;
            }
            let rel = p.strip_prefix(repo).unwrap();
            let written = root.join(rel);
            assert_eq!(
                std::fs::read(&written).unwrap(),
                std::fs::read(&p).unwrap(),
                "{}",
                rel.display()
            );
            assert!(
                out.contains(&format!("wrote {}\n", written.display())),
                "{out}"
            );
            count += 1;
        }
    }
    assert!(count > 30, "{count}");
    assert!(out.contains(&format!("{count} files written")), "{out}");
    // A second time: refused, nothing changed; with --force: written again.
    let lesson = root.join("lessons/02-ray-sphere.md");
    std::fs::write(&lesson, "mine").unwrap();
    fails(
        &Cli::with("examples --write @", &[&dir.path()]),
        &["already exists", "--force"],
    );
    assert_eq!(std::fs::read_to_string(&lesson).unwrap(), "mine");
    ok(&Cli::with("examples --write @ --force", &[&dir.path()]));
    assert_ne!(std::fs::read_to_string(&lesson).unwrap(), "mine");
}

#[test]
fn a_built_in_scene_by_name_from_any_folder() {
    let dir = tempfile::tempdir().unwrap();
    // The triangles scene loads its OBJ from the built-in copy, in a folder with no scenes/.
    let out = raystep()
        .current_dir(dir.path())
        .args(["scene", "check", "triangles", "--json"])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let v: Value = serde_json::from_slice(&out).unwrap();
    // Four triangles, a plane and the 20 faces of icosahedron.obj.
    assert_eq!(v["primitives"], 25, "{v}");
    assert_eq!(v["triangles"], 24, "{v}");
    // `render` writes where it is told and says so with the full path.
    let out = raystep()
        .current_dir(dir.path())
        .args(["render", "first-sphere", "-o", "s.png"])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let out = String::from_utf8(out).unwrap();
    let full = std::fs::canonicalize(dir.path().join("s.png")).unwrap();
    assert!(out.contains(&format!("wrote {}", full.display())), "{out}");
    // An unknown name lists the built-in ones.
    let err = raystep()
        .current_dir(dir.path())
        .args(["render", "cornel", "-o", "c.png"])
        .assert()
        .failure()
        .get_output()
        .stderr
        .clone();
    let err = String::from_utf8(err).unwrap();
    assert!(
        err.contains("built-in scenes:") && err.contains("cornell"),
        "{err}"
    );
}

/// `diagram --animate --delay-ms` sets the GIF's frame delay (the last frame is held for at
/// least 3 s); the default is 800 ms; a delay outside 20 … 60000 ms or not a number is refused
/// with a message naming the option's range and no file written.
#[test]
fn animated_diagram_frame_delay() {
    use image::AnimationDecoder as _;
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/first-sphere.toml");
    let delays = |gif: &Path| -> Vec<u32> {
        let file = std::io::BufReader::new(std::fs::File::open(gif).unwrap());
        image::codecs::gif::GifDecoder::new(file)
            .unwrap()
            .into_frames()
            .map(|f| {
                let (n, d) = f.unwrap().delay().numer_denom_ms();
                n / d.max(1)
            })
            .collect()
    };
    let quick = dir.path().join("quick.gif");
    ok(&Cli::with(
        "diagram @ --pixel 160,120 --size 160x120 --animate --delay-ms 250 -o @",
        &[&scene, &quick],
    ));
    let d = delays(&quick);
    assert!(d.len() > 2, "{d:?}");
    assert!(d[..d.len() - 1].iter().all(|&ms| ms == 250), "{d:?}");
    assert!(d[d.len() - 1] >= 3000, "the last frame is held: {d:?}");
    let plain = dir.path().join("plain.gif");
    ok(&Cli::with(
        "diagram @ --pixel 160,120 --size 160x120 --animate -o @",
        &[&scene, &plain],
    ));
    assert_eq!(delays(&plain)[0], 800, "the default delay");
    let bad = dir.path().join("bad.gif");
    for (arg, msg) in [
        ("5", "between 20 and 60000 ms"),
        ("fast", "not a whole number"),
    ] {
        fails(
            &Cli::with(
                &format!("diagram @ --pixel 160,120 --animate --delay-ms {arg} -o @"),
                &[&scene, &bad],
            ),
            &["--delay-ms", msg],
        );
        assert!(!bad.exists(), "no file for a refused delay");
    }
}

/// `intersect sphere` prints the recorded intermediates: for S = (0, 0, −5), Q = (0, 0, 1) and
/// the unit sphere at the origin, by hand: f = S − G = (0, 0, −5), b = 2 f·Q = −10,
/// c = 25 − 1 = 24, Δ = 100 − 96 = 4, √Δ = 2, t = (10 ∓ 2)/2 = 4, 6; stable: b′ = −f·Q = 5,
/// l = f + (b′/a)Q = (0, 0, 0), Δ′ = r² − l·l = 1.
#[test]
fn intersect_sphere_prints_the_recorded_intermediates() {
    let line = "intersect sphere --center 0,0,0 --radius 1 --origin 0,0,-5 --dir 0,0,1 --method";
    let textbook = ok(&Cli::new(&format!("{line} textbook")));
    for want in [
        "f = S − G              = (0, 0, -5)",
        "b = 2 f·Q              = -10",
        "c = f·f − r²           = 24",
        "Δ = b² − 4ac           = 4",
        "√Δ                     = 2",
        "t = (−b ± √Δ) / 2a     = 4, 6",
    ] {
        assert!(textbook.contains(want), "{want:?} in\n{textbook}");
    }
    let stable = ok(&Cli::new(&format!("{line} stable")));
    for want in [
        "f = S − G              = (0, 0, -5)",
        "b′ = −f·Q              = 5",
        "l = f + (b′/a)Q        = (0, 0, 0)",
        "= 1   (distance² margin",
    ] {
        assert!(stable.contains(want), "{want:?} in\n{stable}");
    }
}

/// `render --profile` adds the stages line: four shares (each 0 … 100 %) naming camera rays,
/// traversal, primitive tests, and shading and spawning (their values are timings, so only their
/// form is checked; the figures are in `bench --section stages`). `render` says what the accelerator visited per ray in its own words.
#[test]
fn render_profile_prints_where_the_time_goes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/triangles.toml");
    let run = |accel: &str, profile: bool| {
        let mut args = vec![
            "render".to_string(),
            scene.display().to_string(),
            "-o".into(),
            dir.path().join("t.png").display().to_string(),
            "--accel".into(),
            accel.into(),
        ];
        if profile {
            args.push("--profile".into());
        }
        let out = raystep()
            .args(&args)
            .assert()
            .success()
            .get_output()
            .clone();
        String::from_utf8(out.stdout).unwrap()
    };
    let out = run("none", true);
    let line = out
        .lines()
        .find(|l| l.trim_start().starts_with("profile"))
        .unwrap_or_else(|| panic!("{out}"));
    let mut shares = vec![];
    for name in [
        "camera rays ",
        "traversal ",
        "primitive tests ",
        "shading and spawning ",
    ] {
        let at = line.find(name).unwrap_or_else(|| panic!("{name}: {line}"));
        let rest = &line[at + name.len()..];
        let pct: f64 = rest[..rest.find(" %").unwrap()].parse().unwrap();
        assert!((0.0..=100.0).contains(&pct), "{line}");
        shares.push(pct);
    }
    assert_eq!(shares.len(), 4);
    assert!(!run("bvh", false).contains("profile"));
    for (accel, words) in [
        ("bvh", "box tests per ray"),
        ("spheres", "bounding-sphere tests per ray"),
        ("grid", "cells walked per ray"),
    ] {
        let out = run(accel, false);
        assert!(out.contains(words), "{accel}: {out}");
    }
}

/// `render --no-counts` writes the counted render's image byte for byte (the Cornell box,
/// path-traced at 32×32, 4 samples per pixel, as an OpenEXR file of the render's own floats),
/// and its summary says that nothing was counted instead of printing zeros; with `--heatmap`,
/// which needs the counts, it is refused before anything is rendered.
#[test]
fn render_no_counts_renders_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-area.toml"),
    )
    .unwrap();
    assert_eq!(text.matches("width = 256\nheight = 256").count(), 1);
    let scene = dir.path().join("box.toml");
    std::fs::write(
        &scene,
        text.replace("width = 256\nheight = 256", "width = 32\nheight = 32"),
    )
    .unwrap();
    let run = |out: &str, more: &str| {
        let image = dir.path().join(out);
        ok(&Cli::with("render @ -o @ --spp 4 --threads 2", &[&scene, &image]).and(more))
    };
    let counted = run("counted.exr", "");
    let silent = run("silent.exr", "--no-counts");
    assert!(
        counted.contains(" shadow, ") && counted.contains("Mrays/s"),
        "{counted}"
    );
    assert!(silent.contains("not counted (--no-counts)"), "{silent}");
    assert!(
        !silent.contains("Mrays/s") && !silent.contains(" shadow, "),
        "{silent}"
    );
    let read = |f: &str| std::fs::read(dir.path().join(f)).unwrap();
    assert!(
        read("counted.exr") == read("silent.exr"),
        "the two images differ"
    );
    let (heat, image) = (dir.path().join("h.png"), dir.path().join("x.png"));
    fails(
        &Cli::with(
            "render @ --no-counts --heatmap @ -o @",
            &[&scene, &heat, &image],
        ),
        &["--heatmap", "--no-counts"],
    );
    assert!(!image.exists() && !heat.exists());
}

/// A reader that closes the pipe early (`raystep render … | head -1`) ends the command quietly,
/// as it ends `cat`: no panic message (Rust's `println!` panics on a closed pipe unless the
/// default SIGPIPE action is restored). The pipe is closed before the command writes a line,
/// so its first line already meets it.
#[cfg(unix)]
#[test]
fn a_closed_pipe_ends_a_command_without_a_panic() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("first.png");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_raystep"))
        .arg("render")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/first-sphere.toml"))
        .arg("-o")
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let done = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&done.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    // Ended by SIGPIPE (13), as `cat` is, or finished before writing anything that failed.
    assert!(
        done.status.success() || done.status.signal() == Some(13),
        "{:?}: {stderr}",
        done.status
    );
}
