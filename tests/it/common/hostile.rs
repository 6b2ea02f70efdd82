//! What the hostile-input tests (`hostile_cli.rs`, `hostile_input.rs`) share: the binary, a small
//! scene of a given size, and a FIFO.

use assert_cmd::Command;
use std::path::{Path, PathBuf};

/// The `raystep` binary, as a command to run.
pub fn raystep() -> Command {
    Command::cargo_bin("raystep").expect("the raystep binary is built")
}

/// The `raystep` binary's path.
pub fn bin() -> PathBuf {
    assert_cmd::cargo::cargo_bin("raystep")
}

/// A small scene (one sphere, one light) of the given size.
pub fn scene(dir: &Path, width: u32, height: u32) -> PathBuf {
    let p = dir.join("scene.toml");
    std::fs::write(
        &p,
        format!(
            "[camera]\nwidth = {width}\nheight = {height}\n\n[[light]]\nposition = [-10, 10, -10]\n\n\
             [[sphere]]\nname = \"ball\"\n"
        ),
    )
    .unwrap();
    p
}

/// Makes a FIFO at `p`.
pub fn mkfifo(p: &Path) {
    let c = std::ffi::CString::new(p.as_os_str().as_encoded_bytes()).unwrap();
    // SAFETY: a valid NUL-terminated path; mkfifo only creates a file.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0, "mkfifo");
}
