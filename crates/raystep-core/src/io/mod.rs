//! Files in and out, safely. Inputs are read only from regular files and never past a stated size
//! ([`read_input`], [`read_text`], [`limits`]); outputs are written whole or not at all
//! ([`write_atomic`]), through symbolic links, and leave no temporary file behind when the write
//! fails or the process is stopped by SIGINT, SIGTERM or SIGHUP. What the command line prints
//! goes through [`out`] (`outln!`), whose failures — a full disk, `/dev/full` — are reported by
//! [`stdout_result`] instead of panicking or passing unnoticed.

// Printing (`outln!`) and reading from the disk serve the command line and native files: the
// browser build has neither.
#![cfg_attr(target_arch = "wasm32", allow(unused_imports, unused_macros))]

use std::io::{Read, Write};
use std::path::Path;
use std::sync::Mutex;

/// The largest file of each kind raystep reads (bytes). A larger file is refused with an error
/// that states the limit; nothing past the limit is ever read (a file that grows while it is
/// read, or a device such as `/dev/zero`, cannot make raystep use more memory than this).
pub mod limits {
    const MIB: u64 = 1 << 20;
    /// A scene file (TOML).
    pub const SCENE: u64 = 16 * MIB;
    /// An OBJ mesh named by a scene.
    pub const OBJ: u64 = 128 * MIB;
    /// A material library (`mtllib`) named by an OBJ file.
    pub const MTL: u64 = 16 * MIB;
    /// A saved step trace (JSON).
    pub const TRACE: u64 = 256 * MIB;
    /// An exercise sheet (TOML).
    pub const SHEET: u64 = 4 * MIB;
    /// A student's answers file (TOML).
    pub const ANSWERS: u64 = 4 * MIB;
    /// A class's submissions (CSV).
    pub const CSV: u64 = 64 * MIB;
    /// A lesson (Markdown).
    pub const LESSON: u64 = 4 * MIB;

    /// A limit in words (`16 MiB`, `512 bytes`).
    pub fn describe(limit: u64) -> String {
        if limit >= MIB && limit.is_multiple_of(MIB) {
            format!("{} MiB", limit / MIB)
        } else {
            format!("{limit} bytes")
        }
    }
}

/// Reads the whole of `path` (`what` names the kind of file in errors, in the singular: "scene file"), but only
/// if it is a regular file (after following symbolic links) of at most `limit` bytes.
///
/// FIFOs, devices, sockets and directories are refused without being opened (opening a FIFO would
/// block until a writer appears). The file is opened non-blocking and checked again (so one
/// swapped in after the check is refused too), and read through `take(limit + 1)`, so a file that
/// grows while it is read cannot exceed the limit either. Errors are `io::Error`s whose message
/// says what is wrong (`InvalidInput` for a file of the wrong kind, `FileTooLarge` past the
/// limit), so callers format them as they would any read error.
pub fn read_input(path: &Path, limit: u64, what: &str) -> std::io::Result<Vec<u8>> {
    use std::io::{Error, ErrorKind};
    let wrong_kind = |ft: &std::fs::FileType| {
        Error::new(
            ErrorKind::InvalidInput,
            format!(
                "is {}, not a regular file: {what}s are read only from regular files",
                kind_of(ft)
            ),
        )
    };
    let too_large = |size: Option<u64>| {
        Error::new(
            ErrorKind::FileTooLarge,
            match size {
                Some(s) => format!(
                    "is {s} bytes, more than the limit of {} for {what}s",
                    limits::describe(limit)
                ),
                None => format!(
                    "is larger than the limit of {} for {what}s",
                    limits::describe(limit)
                ),
            },
        )
    };
    // In the browser, files are the page's own (`platform::files`): regular by construction.
    #[cfg(target_arch = "wasm32")]
    {
        let _ = wrong_kind;
        let len = crate::platform::files::len(path)?;
        if len > limit {
            return Err(too_large(Some(len)));
        }
        crate::platform::files::read(path)
    }
    #[cfg(not(target_arch = "wasm32"))]
    read_disk_file(path, limit, wrong_kind, too_large)
}

/// [`read_input`]'s reading from the disk, with its checks.
#[cfg(not(target_arch = "wasm32"))]
fn read_disk_file(
    path: &Path,
    limit: u64,
    wrong_kind: impl Fn(&std::fs::FileType) -> std::io::Error,
    too_large: impl Fn(Option<u64>) -> std::io::Error,
) -> std::io::Result<Vec<u8>> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(wrong_kind(&meta.file_type()));
    }
    if meta.len() > limit {
        return Err(too_large(Some(meta.len())));
    }
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        // Non-blocking, so a FIFO put in the file's place after the check above cannot hang the
        // open; it changes nothing for a regular file.
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(wrong_kind(&meta.file_type()));
    }
    let mut bytes = Vec::with_capacity(meta.len().min(limit) as usize);
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(None));
    }
    Ok(bytes)
}

/// [`read_input`] for a text file: the bytes must be UTF-8.
pub fn read_text(path: &Path, limit: u64, what: &str) -> std::io::Result<String> {
    let bytes = read_input(path, limit, what)?;
    // UTF-16 (what some editors and spreadsheets save as "Unicode"): its byte order mark, or
    // the NUL bytes of its ASCII characters, which no UTF-8 text has.
    let utf16 = if bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]) {
        Some("it starts with a UTF-16 byte order mark")
    } else if bytes.contains(&0) {
        Some("it has NUL bytes, as UTF-16 text of plain characters has")
    } else {
        None
    };
    if let Some(why) = utf16 {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "is not UTF-8 text but looks like UTF-16 ({why}): {what}s must be UTF-8 — save it as UTF-8 (in a spreadsheet: \"CSV UTF-8\")"
            ),
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "is not UTF-8 text (byte {} is not valid UTF-8): {what}s must be UTF-8",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// The first error writing to standard output (later output is dropped).
static STDOUT_FAILED: Mutex<Option<std::io::Error>> = Mutex::new(None);

/// Writes to standard output, as `print!` does, but never panics: the first failure is kept for
/// [`stdout_result`] and later output is dropped. `outln!` is its `println!`.
pub fn out(args: std::fmt::Arguments<'_>) {
    let mut failed = STDOUT_FAILED.lock().unwrap_or_else(|e| e.into_inner());
    if failed.is_some() {
        return;
    }
    if let Err(e) = std::io::stdout().lock().write_fmt(args) {
        *failed = Some(e);
    }
}

/// Flushes standard output and says whether everything written to it through [`out`] arrived:
/// `Err` with a message for a write error (`No space left on device` on a full disk or
/// `/dev/full`). A closed pipe (`raystep … | head -1`) is not an error: the reader has what it
/// wanted, and the output ends quietly as a Unix tool's does.
pub fn stdout_result() -> Result<(), String> {
    let mut failed = STDOUT_FAILED.lock().unwrap_or_else(|e| e.into_inner());
    if failed.is_none()
        && let Err(e) = std::io::stdout().lock().flush()
    {
        *failed = Some(e);
    }
    match failed.as_ref() {
        Some(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(format!("cannot write to standard output: {e}"))
        }
        _ => Ok(()),
    }
}

/// `println!` through [`out`]: never panics; see [`stdout_result`].
#[macro_export]
macro_rules! outln {
    () => {
        $crate::io::out(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::io::out(format_args!("{}\n", format_args!($($arg)*)))
    };
}
pub use crate::outln;

/// Writing files whole or not at all: native only (a page has no files; the browser build saves
/// with a download, `app::files`).
#[cfg(not(target_arch = "wasm32"))]
mod collide;
#[cfg(all(test, unix))]
use crate::platform::atomic::current_umask;
#[cfg(not(target_arch = "wasm32"))]
pub use crate::platform::atomic::write_atomic;
pub(crate) use crate::platform::files::kind_of;
#[cfg(not(target_arch = "wasm32"))]
pub use collide::{check_outputs, same_file};

/// In the browser a file the user saves is kept in the page's memory (so the app can open it
/// again) and offered as a download named after `path`'s file name.
#[cfg(target_arch = "wasm32")]
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    crate::platform::files::write(path, bytes)?;
    let name = path
        .file_name()
        .map_or_else(|| "raystep".into(), |n| n.to_string_lossy().into_owned());
    crate::platform::browser::download(&name, bytes)
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::os::unix::fs::PermissionsExt;

    #[test]
    fn a_new_file_gets_the_usual_mode_and_an_old_one_keeps_its_own() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.json");
        write_atomic(&p, b"{}").unwrap();
        let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
        assert_eq!(
            mode,
            0o666 & !current_umask(),
            "not the temporary file's 0600"
        );
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o640)).unwrap();
        write_atomic(&p, b"[]").unwrap();
        let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o640);
        assert_eq!(std::fs::read(&p).unwrap(), b"[]");
    }

    fn mkfifo(p: &Path) {
        let ok = std::process::Command::new("mkfifo")
            .arg(p)
            .status()
            .unwrap();
        assert!(ok.success(), "mkfifo");
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_symlink_is_written_through_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let sub = dir.path().join("real");
        std::fs::create_dir(&sub).unwrap();
        let target = sub.join("out.json");
        std::fs::write(&target, b"old").unwrap();
        let link = dir.path().join("link.json");
        std::os::unix::fs::symlink("real/out.json", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        // The temporary file went beside the target, and is gone.
        assert_eq!(names(&sub), ["out.json"]);
        assert_eq!(names(dir.path()), ["link.json", "real"]);
        // A dangling link (through a second link) creates its target.
        let missing = sub.join("new.json");
        std::os::unix::fs::symlink(&missing, dir.path().join("a")).unwrap();
        std::os::unix::fs::symlink("a", dir.path().join("b")).unwrap();
        write_atomic(&dir.path().join("b"), b"x").unwrap();
        assert_eq!(std::fs::read(&missing).unwrap(), b"x");
        assert!(
            std::fs::symlink_metadata(dir.path().join("b"))
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert!(
            std::fs::symlink_metadata(dir.path().join("a"))
                .unwrap()
                .file_type()
                .is_symlink()
        );
    }

    #[test]
    fn a_fifo_is_written_into_not_replaced() {
        use std::os::unix::fs::FileTypeExt;
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe.png");
        mkfifo(&fifo);
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read(fifo).unwrap())
        };
        write_atomic(&fifo, b"through the pipe").unwrap();
        // Checked before joining the reader, which would wait forever had the FIFO been replaced.
        assert!(
            std::fs::symlink_metadata(&fifo)
                .unwrap()
                .file_type()
                .is_fifo()
        );
        assert_eq!(reader.join().unwrap(), b"through the pipe");
        assert_eq!(names(dir.path()), ["pipe.png"]);
    }

    #[test]
    fn special_inputs_are_refused_without_opening_them() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("scene.toml");
        mkfifo(&fifo);
        // Opening a FIFO with no writer would block forever: this returns at once.
        let e = read_input(&fifo, 1000, "scene file").unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
        assert_eq!(
            e.to_string(),
            "is a FIFO (named pipe), not a regular file: scene files are read only from regular files"
        );
        let e = read_input(dir.path(), 1000, "scene file").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("is a directory, not a regular file"),
            "{e}"
        );
        // Through a symlink, the target's kind counts.
        std::os::unix::fs::symlink(&fifo, dir.path().join("link.toml")).unwrap();
        assert!(read_input(&dir.path().join("link.toml"), 1000, "scene file").is_err());
    }

    #[test]
    fn inputs_are_read_up_to_the_limit_and_no_further() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.obj");
        std::fs::write(&p, vec![b'v'; 100]).unwrap();
        assert_eq!(read_input(&p, 100, "OBJ file").unwrap().len(), 100);
        let e = read_input(&p, 99, "OBJ file").unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::FileTooLarge);
        assert_eq!(
            e.to_string(),
            "is 100 bytes, more than the limit of 99 bytes for OBJ files"
        );
        assert_eq!(limits::describe(16 << 20), "16 MiB");
        std::fs::write(&p, b"ok \xff").unwrap();
        let e = read_text(&p, 100, "scene file").unwrap_err();
        assert_eq!(
            e.to_string(),
            "is not UTF-8 text (byte 3 is not valid UTF-8): scene files must be UTF-8"
        );
        let e = read_input(&dir.path().join("none"), 100, "scene file").unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::NotFound);
    }
}
/// A written file's path as messages show it: absolute (symbolic links resolved), so "wrote X"
/// says where X is whatever the working directory.
pub fn full_path(p: &std::path::Path) -> String {
    std::fs::canonicalize(p)
        .or_else(|_| std::path::absolute(p))
        .unwrap_or_else(|_| p.to_path_buf())
        .display()
        .to_string()
}
