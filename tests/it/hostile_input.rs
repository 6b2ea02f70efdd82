//! Hostile and extreme files, given to the `raystep` binary as a user would: devices, FIFOs and
//! symbolic links as inputs and outputs, writes that fail or are killed half-way, and inputs past
//! the size limits, run under a memory cap (`prlimit --as`) that the limits must hold under.
#![cfg(unix)]

use assert_cmd::Command;
use std::os::unix::fs::FileTypeExt;
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::time::{Duration, Instant};

use crate::common::hostile;
use hostile::{bin, mkfifo, raystep, scene};

/// The names in a directory, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn temporaries(dir: &Path) -> Vec<String> {
    names(dir)
        .into_iter()
        .filter(|n| n.starts_with(".tmp"))
        .collect()
}

const PNG_MAGIC: &[u8] = b"\x89PNG\r\n\x1a\n";

// ---------------------------------------------------------------------------------------------
// Outputs: symbolic links, FIFOs, failures, kills

#[test]
fn an_output_symlink_is_written_through_and_kept() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), 8, 6);
    let real = dir.path().join("real");
    std::fs::create_dir(&real).unwrap();
    std::fs::write(real.join("out.png"), b"old").unwrap();
    let link = dir.path().join("link.png");
    std::os::unix::fs::symlink("real/out.png", &link).unwrap();
    raystep()
        .arg("render")
        .arg(&s)
        .arg("-o")
        .arg(&link)
        .timeout(Duration::from_secs(60))
        .assert()
        .success();
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink(),
        "the link was replaced by a file"
    );
    assert!(
        std::fs::read(real.join("out.png"))
            .unwrap()
            .starts_with(PNG_MAGIC)
    );
    assert_eq!(names(&real), ["out.png"]);
    assert_eq!(names(dir.path()), ["link.png", "real", "scene.toml"]);
}

#[test]
fn a_fifo_output_is_written_into_not_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), 8, 6);
    let fifo = dir.path().join("pipe.png");
    mkfifo(&fifo);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).unwrap())
    };
    raystep()
        .arg("render")
        .arg(&s)
        .arg("-o")
        .arg(&fifo)
        .timeout(Duration::from_secs(60))
        .assert()
        .success();
    // Checked before joining the reader, which would wait forever had the FIFO been replaced.
    assert!(
        std::fs::symlink_metadata(&fifo)
            .unwrap()
            .file_type()
            .is_fifo()
    );
    assert!(reader.join().unwrap().starts_with(PNG_MAGIC));
    assert_eq!(names(dir.path()), ["pipe.png", "scene.toml"]);
}

#[test]
fn a_write_that_fails_leaves_the_old_file_and_no_temporary_file() {
    // A file-size limit of 1000 bytes: the 160×120 PNG is larger, so its write fails (EFBIG).
    // Without care the kernel's SIGXFSZ would kill the process and leave the temporary file.
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), 160, 120);
    let out = dir.path().join("out.png");
    std::fs::write(&out, b"old").unwrap();
    let o = std::process::Command::new("prlimit")
        .arg("--fsize=1000")
        .arg(bin())
        .arg("render")
        .arg(&s)
        .arg("-o")
        .arg(&out)
        .output()
        .expect("prlimit runs");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.signal(), None, "killed by a signal: {stderr}");
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("out.png") && stderr.contains("cannot write"),
        "{stderr}"
    );
    assert_eq!(std::fs::read(&out).unwrap(), b"old");
    assert_eq!(names(dir.path()), ["out.png", "scene.toml"]);
}

/// Starts a render of a large image, waits until its temporary output file appears, freezes it
/// there (SIGSTOP), checks it is mid-write, then sends `signal` and lets it go on.
fn kill_mid_write(signal: i32) {
    // The write lasts a few milliseconds: a busy machine can miss it, so try a few times.
    for size in [(1600, 1200), (2400, 1800)].repeat(5) {
        let dir = tempfile::tempdir().unwrap();
        let s = scene(dir.path(), size.0, size.1);
        let out = dir.path().join("out.png");
        let mut child = std::process::Command::new(bin())
            .arg("render")
            .arg(&s)
            .arg("-o")
            .arg(&out)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let pid = child.id() as i32;
        let start = Instant::now();
        let caught = loop {
            if !temporaries(dir.path()).is_empty() {
                // SAFETY: signals our own child, which has not been waited for (pid is valid).
                unsafe { libc::kill(pid, libc::SIGSTOP) };
                break true;
            }
            if child.try_wait().unwrap().is_some() || start.elapsed() > Duration::from_secs(300) {
                break false;
            }
        };
        if !caught {
            let _ = child.kill();
            let _ = child.wait();
            continue; // the write was too quick to catch: a larger image
        }
        // Stopped: if the temporary file is still there, the write is not finished.
        if temporaries(dir.path()).is_empty() {
            unsafe { libc::kill(pid, libc::SIGCONT) };
            let _ = child.wait();
            continue;
        }
        unsafe {
            libc::kill(pid, signal);
            libc::kill(pid, libc::SIGCONT);
        }
        let status = child.wait().unwrap();
        if status.success() {
            // The write finished (and was renamed into place) before the signal was handled:
            // the output must then be whole.
            let png = std::fs::read(&out).unwrap();
            assert!(png.starts_with(PNG_MAGIC) && png.ends_with(b"IEND\xae\x42\x60\x82"));
            assert_eq!(names(dir.path()), ["out.png", "scene.toml"]);
        } else {
            assert_eq!(status.signal(), Some(signal), "{status:?}");
            // The signal is handled on its own thread while the writer goes on: the rename may
            // win the race, and the process then dies by the signal with its output complete.
            // Either way no temporary file is left, and an output that exists is whole.
            assert!(
                temporaries(dir.path()).is_empty(),
                "a temporary file is left after signal {signal}: {:?}",
                names(dir.path())
            );
            if out.exists() {
                let png = std::fs::read(&out).unwrap();
                assert!(
                    png.starts_with(PNG_MAGIC) && png.ends_with(b"IEND\xae\x42\x60\x82"),
                    "a half-written output is left after signal {signal}"
                );
            }
        }
        return;
    }
    panic!("never caught the render mid-write");
}

#[test]
fn sigterm_mid_write_leaves_no_temporary_file() {
    kill_mid_write(libc::SIGTERM);
}

#[test]
fn sigint_mid_write_leaves_no_temporary_file() {
    kill_mid_write(libc::SIGINT);
}

// ---------------------------------------------------------------------------------------------
// Inputs: devices, FIFOs, size limits, under a memory cap

/// The address-space cap the refusals must hold under. The debug binary maps about 200 MB
/// before it reads anything; reading /dev/zero to its end took 2–4 GB.
const CAP: &str = "--as=1073741824";

/// Runs raystep with `args` under the memory cap and a time limit; it must fail with its error
/// exit code (2 for `diff`, whose 1 means "the traces differ"; 1 otherwise) — not a crash, not a
/// signal — and say every one of `says`.
fn refused(args: &[&dyn AsRef<std::ffi::OsStr>], says: &[&str]) {
    let code = if args[0].as_ref() == "diff" { 2 } else { 1 };
    let mut cmd = Command::new("prlimit");
    cmd.arg(CAP).arg(bin());
    let mut line = String::from("raystep");
    for a in args {
        cmd.arg(a);
        line = line + " " + &a.as_ref().to_string_lossy();
    }
    let o = cmd.timeout(Duration::from_secs(60)).output().unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(
        o.status.code(),
        Some(code),
        "{line}: {:?} {stderr}",
        o.status
    );
    for s in says {
        assert!(stderr.contains(s), "{line}: stderr lacks {s:?}: {stderr}");
    }
}

#[test]
fn dev_zero_is_refused_as_every_kind_of_input() {
    let z = Path::new("/dev/zero");
    let sheet = Path::new(env!("CARGO_MANIFEST_DIR")).join("lessons/exercises/01-camera.toml");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("grades.csv");
    let device = "is a character device, not a regular file";
    refused(&[&"scene", &"check", &z], &[device, "scene files"]);
    refused(
        &[&"render", &z, &"-o", &out.with_extension("png")],
        &[device],
    );
    refused(&[&"diff", &z, &z], &[device, "trace files"]);
    refused(
        &[&"check", &z, &"--student", &"s1", &"--answers", &z],
        &[device, "exercise sheets"],
    );
    refused(
        &[&"check", &sheet, &"--student", &"s1", &"--answers", &z],
        &[device, "answers files"],
    );
    refused(
        &[&"grade", &sheet, &z, &"-o", &out],
        &[device, "submissions files"],
    );
    assert_eq!(names(dir.path()), Vec::<String>::new());
}

#[test]
fn meshes_naming_devices_and_fifos_are_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo");
    mkfifo(&fifo);
    let write = |name: &str, obj: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, format!("[[mesh]]\nname = \"m\"\nobj = \"{obj}\"\n")).unwrap();
        p
    };
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    std::fs::write(
        dir.path().join("zero-mtl.obj"),
        format!("mtllib /dev/zero\n{tri}"),
    )
    .unwrap();
    std::fs::write(
        dir.path().join("fifo-mtl.obj"),
        format!("mtllib fifo\n{tri}"),
    )
    .unwrap();
    let loc = |name: &str| format!("{name}:3:1: mesh \"m\" → obj");
    // Each would have read until memory ran out, or waited for a writer forever.
    refused(
        &[&"scene", &"check", &write("a.toml", "/dev/zero")],
        &[&loc("a.toml"), "/dev/zero", "character device"],
    );
    refused(
        &[&"scene", &"check", &write("b.toml", "fifo")],
        &[&loc("b.toml"), "FIFO"],
    );
    refused(
        &[&"scene", &"check", &write("c.toml", "zero-mtl.obj")],
        &[
            &loc("c.toml"),
            "zero-mtl.obj:1: material library /dev/zero",
            "character device",
        ],
    );
    refused(
        &[&"scene", &"check", &write("d.toml", "fifo-mtl.obj")],
        &[
            &loc("d.toml"),
            "fifo-mtl.obj:1: material library fifo",
            "FIFO",
        ],
    );
    refused(&[&"scene", &"check", &fifo], &["FIFO", "scene files"]);
}

#[test]
fn inputs_past_their_limit_are_refused_under_the_cap() {
    let dir = tempfile::tempdir().unwrap();
    // Sparse files: the sizes cost no disk.
    let sized = |name: &str, len: u64| {
        let p = dir.path().join(name);
        std::fs::File::create(&p).unwrap().set_len(len).unwrap();
        p
    };
    let mib = 1u64 << 20;
    refused(
        &[&"scene", &"check", &sized("big.toml", 16 * mib + 1)],
        &["more than the limit of 16 MiB for scene files"],
    );
    let obj = sized("big.obj", 128 * mib + 1);
    let s = dir.path().join("mesh.toml");
    std::fs::write(&s, format!("[[mesh]]\nobj = \"{}\"\n", obj.display())).unwrap();
    refused(
        &[&"scene", &"check", &s],
        &[
            "mesh.toml:2:1",
            "more than the limit of 128 MiB for OBJ files",
        ],
    );
    refused(
        &[&"diff", &sized("big.json", 256 * mib + 1), &"x.json"],
        &["more than the limit of 256 MiB for trace files"],
    );
}

#[test]
fn the_image_size_limit_holds_under_the_cap() {
    let dir = tempfile::tempdir().unwrap();
    let s = scene(dir.path(), 16384, 16384);
    refused(
        &[&"render", &s, &"-o", &dir.path().join("out.png")],
        &[
            "scene.toml:2:1: camera → width",
            "more than the limit of 40000000",
        ],
    );
    // The largest accepted size loads (it is checked, not rendered, here).
    let s = scene(dir.path(), 16384, 2441);
    let o = std::process::Command::new("prlimit")
        .arg(CAP)
        .arg(bin())
        .args(["scene", "check"])
        .arg(&s)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn the_object_limit_holds_under_the_cap() {
    let dir = tempfile::tempdir().unwrap();
    let limit = raystep::scene::MAX_OBJECTS;
    let mut obj = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    obj.push_str(&"f 1 2 3\n".repeat(limit + 1));
    std::fs::write(dir.path().join("many.obj"), obj).unwrap();
    let s = dir.path().join("many.toml");
    std::fs::write(&s, "[[mesh]]\nname = \"many\"\nobj = \"many.obj\"\n").unwrap();
    refused(
        &[&"scene", &"check", &s],
        &[
            "many.toml:3:1: mesh \"many\" → obj",
            &format!(
                "{} triangles, more than the limit of {limit} objects",
                limit + 1
            ),
        ],
    );
}

// ---------------------------------------------------------------------------------------------
// NaN rays are counted

#[test]
fn render_statistics_count_nan_rays() {
    let mut scene = raystep::scene::load_str(
        "[camera]\nwidth = 4\nheight = 3\n\n[[sphere]]\n",
        "s.toml",
        None,
    )
    .unwrap();
    let render = |scene: &raystep::scene::Scene| {
        let (accel, _) = raystep::accel::SceneAccel::build(scene);
        let tracer = raystep::trace::Tracer::new(scene, &accel);
        let opts = raystep::render::RenderOptions {
            threads: Some(1),
            count: true,
            ..Default::default()
        };
        raystep::render::render(&tracer, &opts).unwrap().stats
    };
    let s = render(&scene);
    assert_eq!((s.nan_rays, s.nan_pixels), (0, 0));
    // A camera the loader refuses (from = at): w = 0/0, so all 12 primary rays are NaN. They hit
    // nothing and show the background, so no pixel is NaN: only the ray count tells.
    scene.camera.at = scene.camera.from;
    let s = render(&scene);
    assert_eq!(s.counts.primary, 12);
    assert_eq!((s.nan_rays, s.nan_pixels), (12, 0));
}

/// The deepest recursion the scene format accepts (max_depth = 64) on the shipped scene with the
/// most recursion (mirrors facing glass): the weight cut-off and the step cap keep a traced pixel
/// and a whole render small and quick under the memory cap. Before them, depth 24 aborted with a
/// trace of more than 8 GB and a 32×24 render at depth 64 never ended.
#[test]
fn the_deepest_recursion_holds_under_the_cap() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/mirror-glass.toml");
    let dir = tempfile::tempdir().unwrap();
    let trace = dir.path().join("t.json");
    let image = dir.path().join("r.png");
    for args in [
        vec![
            "trace".into(),
            scene.clone().into_os_string(),
            "--pixel".into(),
            "300,180".into(),
            "--max-depth".into(),
            "64".into(),
            "--save".into(),
            trace.clone().into_os_string(),
        ],
        vec![
            "render".into(),
            scene.clone().into_os_string(),
            "--max-depth".into(),
            "64".into(),
            "-o".into(),
            image.clone().into_os_string(),
        ],
    ] {
        let o = Command::new("prlimit")
            .arg(CAP)
            .arg(bin())
            .args(&args)
            .timeout(Duration::from_secs(300))
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{args:?}: {:?} {}",
            o.status,
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let size = std::fs::metadata(&trace).unwrap().len();
    assert!(size < 8 << 20, "the depth-64 trace is {size} bytes");
    assert!(std::fs::read(&image).unwrap().starts_with(PNG_MAGIC));
}
