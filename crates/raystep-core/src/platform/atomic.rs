//! Writing a file whole or not at all ([`write_atomic`]), cleaning up after a signal.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

/// Temporary files being written now: removed by the signal thread if the process is stopped.
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Keeps a temporary file's name in [`PENDING`] while it lives.
struct Pending(PathBuf);

impl Pending {
    fn new(path: &Path) -> Self {
        lock_pending().push(path.to_path_buf());
        Pending(path.to_path_buf())
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        let mut p = lock_pending();
        if let Some(i) = p.iter().position(|x| *x == self.0) {
            p.swap_remove(i);
        }
    }
}

fn lock_pending() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    // A panic while the list was held leaves it valid: it is only pushed to and removed from.
    PENDING.lock().unwrap_or_else(|e| e.into_inner())
}

/// Starts (once) the thread that, on SIGINT, SIGTERM or SIGHUP, removes the temporary files being
/// written and then ends the process as the signal's default action would (so the exit status
/// still says "killed by SIGTERM"). SIGXFSZ (a file-size limit reached) is caught so the write
/// fails with an error, which removes the temporary file, instead of killing the process.
/// SIGKILL cannot be caught: a process killed by it may leave a `.tmpXXXXXX` file beside the
/// output (never a half-written output).
fn install_cleanup() {
    static INSTALLED: OnceLock<()> = OnceLock::new();
    INSTALLED.get_or_init(|| {
        #[cfg(unix)]
        {
            use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM, SIGXFSZ};
            // If the handlers cannot be installed, writes still work; only the clean-up on a
            // signal is lost.
            if let Ok(mut signals) =
                signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP, SIGXFSZ])
            {
                let _ = std::thread::Builder::new()
                    .name("raystep-signals".into())
                    .spawn(move || {
                        for sig in signals.forever() {
                            if sig == SIGXFSZ {
                                continue;
                            }
                            for p in lock_pending().drain(..) {
                                let _ = std::fs::remove_file(p);
                            }
                            let _ = signal_hook::low_level::emulate_default_handler(sig);
                            // Not reached unless the default action could not be restored.
                            std::process::exit(128 + sig);
                        }
                    });
            }
        }
    });
}

/// Writes `bytes` to `path`, whole or not at all.
///
/// - A regular file (or a new name) is written atomically: into a temporary file beside it, then
///   renamed over it, so a reader never sees a half-written file and a failure leaves any old file
///   untouched. A symbolic link is followed: its final target is replaced and the link is kept.
/// - A character device or a FIFO (`/dev/null`, a terminal, a named pipe another program reads)
///   is written to directly, as the shell's `>` would: replacing it by a regular file would
///   destroy it, and writing into it is what a user means by naming one.
/// - Anything else (a directory, a block device, a socket) is refused.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let shown = path.display();
    match std::fs::metadata(path) {
        Ok(m) if m.is_dir() => Err(format!("{shown}: is a directory, not a file name")),
        Ok(m) if m.is_file() => {
            let target = std::fs::canonicalize(path)
                .map_err(|e| format!("{shown}: cannot resolve the path: {e}"))?;
            replace_file(path, &target, bytes)
        }
        Ok(m) => write_special(path, &m.file_type(), bytes),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            let target = final_target(path)?;
            replace_file(path, &target, bytes)
        }
        Err(e) => Err(format!("{shown}: cannot write: {e}")),
    }
}

/// The name a new file at `path` gets: `path` itself, or the (missing) target its chain of
/// symbolic links ends at.
fn final_target(path: &Path) -> Result<PathBuf, String> {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&p) {
            Ok(m) if m.file_type().is_symlink() => {
                let t = std::fs::read_link(&p)
                    .map_err(|e| format!("{}: cannot read the link: {e}", path.display()))?;
                p = if t.is_absolute() {
                    t
                } else {
                    p.parent().unwrap_or(Path::new(".")).join(t)
                };
            }
            _ => return Ok(p),
        }
    }
    Err(format!(
        "{}: too many levels of symbolic links",
        path.display()
    ))
}

/// Writes a character device or FIFO in place; refuses other special files.
fn write_special(path: &Path, ft: &std::fs::FileType, bytes: &[u8]) -> Result<(), String> {
    let shown = path.display();
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if ft.is_char_device() || ft.is_fifo() {
            let mut f = std::fs::OpenOptions::new()
                .write(true)
                .open(path)
                .map_err(|e| format!("{shown}: cannot open for writing: {e}"))?;
            f.write_all(bytes)
                .and_then(|()| f.flush())
                .map_err(|e| format!("{shown}: cannot write: {e}"))?;
            return Ok(());
        }
    }
    Err(format!(
        "{shown}: is {}: raystep writes only regular files, character devices and FIFOs",
        super::files::kind_of(ft)
    ))
}

/// The atomic write of a regular file: `target` is `path` with its symbolic links resolved.
fn replace_file(path: &Path, target: &Path, bytes: &[u8]) -> Result<(), String> {
    let shown = path.display();
    let dir = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        return Err(format!(
            "{shown}: the directory {} does not exist",
            dir.display()
        ));
    }
    // The file the user asked for gets the usual mode: an existing file's own, else 0666 less
    // the umask, as `File::create` would give it (not the 0600 of a private temporary file).
    #[cfg(unix)]
    let mode = {
        use std::os::unix::fs::PermissionsExt;
        std::fs::metadata(target)
            .map(|m| m.permissions().mode() & 0o7777)
            .unwrap_or_else(|_| 0o666 & !current_umask())
    };
    install_cleanup();
    // The temporary name is registered for removal before the file is created, so a signal
    // arriving at any moment finds it listed; `tmp` (dropped on every error path below) removes
    // the file when the write fails.
    let mut pending = None;
    let mut tmp = tempfile::Builder::new()
        .make_in(dir, |p| {
            pending = Some(Pending::new(p));
            let f = std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(p)?;
            #[cfg(unix)]
            {
                use std::os::unix::fs::PermissionsExt;
                f.set_permissions(std::fs::Permissions::from_mode(mode))?;
            }
            Ok(f)
        })
        .map_err(|e| format!("{shown}: cannot create a file in {}: {e}", dir.display()))?;
    tmp.as_file_mut()
        .write_all(bytes)
        .map_err(|e| format!("{shown}: cannot write: {e}"))?;
    tmp.as_file()
        .sync_all()
        .map_err(|e| format!("{shown}: cannot write: {e}"))?;
    tmp.persist(target)
        .map_err(|e| format!("{shown}: cannot write: {}", e.error))?;
    // Renamed: nothing is left to remove.
    drop(pending);
    Ok(())
}

/// The process's file-creation mask, read without changing it (from /proc where it is shown;
/// the common 022 otherwise).
#[cfg(unix)]
pub(crate) fn current_umask() -> u32 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("Umask:"))
                .and_then(|v| u32::from_str_radix(v.trim(), 8).ok())
        })
        .unwrap_or(0o022)
}
