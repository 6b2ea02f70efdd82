//! What the students' programs may not do while they are graded: outlive the grading (every
//! descendant is stopped after each run, those that left the program's process group too) and
//! run raystep to copy its numbers (raystep's binary is hidden from them where the platform
//! allows).
//!
//! What each platform gives:
//! - **Linux**: raystep becomes the *child subreaper* of everything it starts
//!   (`prctl(PR_SET_CHILD_SUBREAPER)`), so a process a student's program leaves behind — in a
//!   new session (`setsid`) or process group, double-forked — becomes raystep's child when its
//!   parent ends, and is stopped after the run with every other child. Run as root with
//!   `CAP_SYS_ADMIN` (Gradescope's autograder is), each program also runs in a mount namespace
//!   of its own in which raystep's own binary and every `raystep` on the `PATH` are covered by
//!   an empty device (`/dev/null` bound over them): running them fails, reading them gives
//!   nothing.
//! - **Other Unix systems**: the program's process group is stopped after each run; a process
//!   that left the group (setsid) can outlive the grading, and raystep is not hidden.
//! - **Windows**: the program itself is stopped; nothing else.
//!
//! What hiding cannot prevent: a copy of raystep elsewhere (in the submission, under another
//! name, in a folder not on the `PATH`), another program that computes the same numbers, or a
//! student who ran raystep before submitting and prints its saved output. The grade report
//! therefore also names output that is raystep's own trace text verbatim (every number as
//! raystep prints it), for the teacher to look at.

use std::sync::OnceLock;
#[cfg(target_os = "linux")]
use std::sync::atomic::{AtomicBool, Ordering};

#[cfg(target_os = "linux")]
static REAPER: AtomicBool = AtomicBool::new(false);

/// The files bound over in each program's mount namespace (None: hiding is off).
static HIDDEN: OnceLock<Option<Vec<std::ffi::CString>>> = OnceLock::new();

/// Makes this process the reaper of everything its children leave behind, so that
/// [`stop_descendants`] can stop them. Call it only in a process whose children are all
/// students' programs (`raystep grade-tracer`): after each run every child is stopped.
/// Returns whether the platform gives it.
pub fn reap_descendants() -> bool {
    #[cfg(target_os = "linux")]
    {
        let ok = rustix::process::set_child_subreaper(Some(rustix::process::getpid())).is_ok();
        REAPER.store(ok, Ordering::SeqCst);
        ok
    }
    #[cfg(not(target_os = "linux"))]
    false
}

/// Stops every child of this process but `keep` (the program, which its `Child` waits for), and
/// the children they leave behind, until none is left — when [`reap_descendants`] took effect.
pub(crate) fn stop_descendants(keep: u32) {
    #[cfg(target_os = "linux")]
    {
        use rustix::process::{Pid, Signal, WaitOptions, kill_process, waitpid};
        if !REAPER.load(Ordering::SeqCst) {
            return;
        }
        // A killed process's children are handed to this one before it can be waited for, so
        // each round finds the next generation; a fork bomb still ends: each round kills all.
        for _ in 0..1000 {
            let kids: Vec<i32> = children(std::process::id())
                .into_iter()
                .filter(|p| *p as u32 != keep)
                .collect();
            if kids.is_empty() {
                return;
            }
            for k in kids {
                if let Some(pid) = Pid::from_raw(k) {
                    let _ = kill_process(pid, Signal::KILL);
                    let _ = waitpid(Some(pid), WaitOptions::empty());
                }
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    let _ = keep;
}

/// The processes whose parent is `parent` (from /proc).
#[cfg(target_os = "linux")]
fn children(parent: u32) -> Vec<i32> {
    let Ok(dir) = std::fs::read_dir("/proc") else {
        return vec![];
    };
    dir.filter_map(|e| e.ok()?.file_name().to_str()?.parse::<i32>().ok())
        .filter(|pid| {
            std::fs::read_to_string(format!("/proc/{pid}/stat")).is_ok_and(|stat| {
                // "pid (comm) state ppid …": the name may hold spaces and parentheses.
                stat.rsplit_once(") ")
                    .and_then(|(_, rest)| rest.split_whitespace().nth(1)?.parse::<u32>().ok())
                    == Some(parent)
            })
        })
        .collect()
}

/// Hides raystep from the students' programs where the platform allows (Linux, as root with
/// `CAP_SYS_ADMIN`): its own binary and every `raystep` on the `PATH`. Tried once on raystep's
/// own binary; returns what was hidden, or why nothing could be.
pub fn hide_raystep() -> Result<Vec<std::path::PathBuf>, String> {
    #[cfg(target_os = "linux")]
    {
        let mut paths = vec![];
        if let Ok(me) = std::env::current_exe().and_then(std::fs::canonicalize) {
            paths.push(me);
        }
        if let Some(path) = std::env::var_os("PATH") {
            for dir in std::env::split_paths(&path) {
                if let Ok(p) = std::fs::canonicalize(dir.join("raystep"))
                    && p.is_file()
                    && !paths.contains(&p)
                {
                    paths.push(p);
                }
            }
        }
        let targets: Vec<std::ffi::CString> = paths
            .iter()
            .filter_map(|p| {
                std::ffi::CString::new(std::os::unix::ffi::OsStrExt::as_bytes(p.as_os_str())).ok()
            })
            .collect();
        // Tried on raystep itself: hidden, it cannot be run (EACCES).
        let Some(me) = paths.first() else {
            let _ = HIDDEN.set(None);
            return Err("raystep cannot find its own binary".into());
        };
        let mut probe = std::process::Command::new(me);
        probe
            .arg("--version")
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null());
        hide_in(&mut probe, targets.clone());
        let why = match probe.spawn() {
            Err(e) if e.raw_os_error() == Some(libc::EACCES) => None,
            Err(e) => Some(format!(
                "a mount namespace of its own cannot be made here ({e}; it needs root with CAP_SYS_ADMIN)"
            )),
            Ok(mut c) => {
                let _ = c.wait();
                Some("raystep's binary stayed reachable in the program's mount namespace".into())
            }
        };
        match why {
            None => {
                let _ = HIDDEN.set(Some(targets));
                Ok(paths)
            }
            Some(w) => {
                let _ = HIDDEN.set(None);
                Err(w)
            }
        }
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = HIDDEN.set(None);
        Err("hiding raystep from the students' programs needs Linux (a mount namespace)".into())
    }
}

/// Sets `cmd` up to run with raystep hidden, when [`hide_raystep`] succeeded.
pub(crate) fn apply(cmd: &mut std::process::Command) {
    #[cfg(target_os = "linux")]
    if let Some(Some(t)) = HIDDEN.get() {
        hide_in(cmd, t.clone());
    }
    #[cfg(not(target_os = "linux"))]
    let _ = cmd;
}

/// In the child, before the program starts: a mount namespace of its own, its mounts private
/// (nothing propagates back), and `/dev/null` bound over each of `targets`. Only system calls
/// between fork and exec (no allocation: the paths are made beforehand).
#[cfg(target_os = "linux")]
#[allow(unsafe_code)] // `pre_exec`: the only way to act between fork and exec
fn hide_in(cmd: &mut std::process::Command, targets: Vec<std::ffi::CString>) {
    use std::os::unix::process::CommandExt;
    let null = c"/dev/null";
    let root = c"/";
    // SAFETY: the closure makes only async-signal-safe system calls on memory made before the
    // fork (the CStrings and literals), as `pre_exec` requires.
    unsafe {
        cmd.pre_exec(move || {
            if libc::unshare(libc::CLONE_NEWNS) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            if libc::mount(
                std::ptr::null(),
                root.as_ptr(),
                std::ptr::null(),
                libc::MS_REC | libc::MS_PRIVATE,
                std::ptr::null(),
            ) != 0
            {
                return Err(std::io::Error::last_os_error());
            }
            for t in &targets {
                if libc::mount(
                    null.as_ptr(),
                    t.as_ptr(),
                    std::ptr::null(),
                    libc::MS_BIND,
                    std::ptr::null(),
                ) != 0
                {
                    return Err(std::io::Error::last_os_error());
                }
            }
            Ok(())
        });
    }
}

/// Whether a program's output is raystep's own trace text: the same text, or (of 20 or more
/// lines with a decimal number) nine in ten such lines exactly as raystep prints them. A tracer
/// of its own prints its own roundings (raystep prints float32 numbers in their shortest form), so
/// this names copies, not agreement.
pub fn is_raysteps_text(output: &str, raysteps: &str) -> bool {
    if output.trim() == raysteps.trim() && !raysteps.trim().is_empty() {
        return true;
    }
    let decimal = |l: &&str| {
        let b = l.as_bytes();
        b.windows(3)
            .any(|w| w[0].is_ascii_digit() && w[1] == b'.' && w[2].is_ascii_digit())
    };
    let theirs: std::collections::HashSet<&str> =
        raysteps.lines().map(str::trim).filter(decimal).collect();
    let mine: Vec<&str> = output.lines().map(str::trim).filter(decimal).collect();
    if mine.len() < 20 {
        return false;
    }
    let same = mine.iter().filter(|l| theirs.contains(*l)).count();
    same * 10 >= mine.len() * 9
}

/// The report's words for output that is raystep's own text.
pub fn raysteps_text_note(x: u32, y: u32) -> String {
    format!(
        "the output for pixel ({x}, {y}) is raystep's own trace text (`raystep trace --format student`), every number exactly as raystep prints it: a tracer of its own prints its own roundings — the teacher should look at this submission"
    )
}
