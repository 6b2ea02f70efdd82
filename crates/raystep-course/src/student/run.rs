//! Running a student's program: the command template split into words (shell quoting rules, by
//! the `shlex` crate) with `{scene}`, `{x}` and `{y}` substituted inside each word, never through
//! a shell; a time limit and an output limit; stdin closed. The program runs in a process group
//! of its own, stopped whole when the run ends (on Unix: process spawning is native-only, and
//! the grader is a command-line tool).

use crate::platform::{Duration, Instant};
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use wait_timeout::ChildExt;

/// Limits on one run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Wall-clock time.
    pub timeout: Duration,
    /// Bytes of standard output kept; more stops the program.
    pub max_output: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            timeout: Duration::from_secs(10),
            max_output: 16 << 20,
        }
    }
}

/// Why a run gave no output to grade.
#[derive(Debug, Clone, PartialEq)]
pub enum RunError {
    /// The template is empty or badly quoted.
    Template(String),
    /// The program could not be started.
    Start(String),
    /// It ran past the time limit and was stopped.
    Timeout(Duration),
    /// It printed more than the output limit and was stopped.
    TooMuchOutput(usize),
    /// It exited with a failure (status, the end of its stderr).
    Failed(String, String),
    /// Its output is not UTF-8 text.
    NotText,
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RunError::Template(m) => write!(f, "the --run command cannot be used: {m}"),
            RunError::Start(m) => write!(f, "your program could not be started: {m}"),
            RunError::Timeout(d) => write!(
                f,
                "your program ran longer than {:.1} s and was stopped (an endless loop? a recursion with no depth limit?)",
                d.as_secs_f64()
            ),
            RunError::TooMuchOutput(n) => write!(
                f,
                "your program printed more than {} MB and was stopped",
                n / (1 << 20)
            ),
            RunError::Failed(status, err) => {
                // The last line first (usually the error itself), then the end of stderr.
                let last = err.lines().rev().find(|l| !l.trim().is_empty());
                write!(f, "your program failed ({status})")?;
                if let Some(l) = last {
                    write!(f, ": {}", l.trim())?;
                    write!(f, "\nThe end of what it wrote to stderr:\n{err}")?;
                }
                Ok(())
            }
            RunError::NotText => write!(f, "your program's output is not UTF-8 text"),
        }
    }
}

/// The command's words for one pixel.
pub fn words(template: &str, scene: &Path, x: u32, y: u32) -> Result<Vec<String>, RunError> {
    let parts =
        shlex::split(template).ok_or_else(|| RunError::Template("unbalanced quotes".into()))?;
    if parts.is_empty() {
        return Err(RunError::Template("it is empty".into()));
    }
    let scene = scene.display().to_string();
    Ok(parts
        .into_iter()
        .map(|w| {
            w.replace("{scene}", &scene)
                .replace("{x}", &x.to_string())
                .replace("{y}", &y.to_string())
        })
        .collect())
}

/// What a run printed: its standard output, and a note when raystep had to step in (a process
/// the program started kept the output open after the program ended).
#[derive(Debug, Clone, PartialEq)]
pub struct Output {
    /// Standard output, as UTF-8 text.
    pub stdout: String,
    /// Said to the student beside the verdicts, if anything.
    pub note: Option<String>,
}

/// Bytes of standard error kept: the end, where a traceback's summary line is.
const STDERR_TAIL: usize = 64 << 10;
/// Lines of standard error shown in a report, and characters of each.
const STDERR_LINES: usize = 8;
const STDERR_LINE_CHARS: usize = 400;
/// How long the output may stay open after the program ended (a background process holding it)
/// before the program's whole process group is stopped.
const LINGER: Duration = Duration::from_secs(1);

/// A pipe read to its end on a thread of its own, into a buffer that can be looked at any time:
/// what was read is kept even if the pipe never closes.
struct Drain {
    /// The bytes kept, and whether bytes were dropped from the front.
    kept: Arc<Mutex<(Vec<u8>, bool)>>,
    /// More than the head limit arrived.
    over: Arc<AtomicBool>,
    /// Says once when the pipe reached its end.
    eof: std::sync::mpsc::Receiver<()>,
}

/// Which bytes a [`Drain`] keeps.
#[derive(Clone, Copy)]
enum Keep {
    /// The first n; one more sets `over` and stops reading.
    Head(usize),
    /// The last n; the rest is read and dropped, so the program never blocks on a full pipe.
    Tail(usize),
}

impl Drain {
    fn start(mut pipe: impl Read + Send + 'static, keep: Keep) -> Drain {
        let kept = Arc::new(Mutex::new((Vec::new(), false)));
        let over = Arc::new(AtomicBool::new(false));
        let (tx, eof) = std::sync::mpsc::channel();
        let (k, o) = (kept.clone(), over.clone());
        std::thread::spawn(move || {
            let mut chunk = vec![0u8; 64 << 10];
            loop {
                let n = match pipe.read(&mut chunk) {
                    Ok(0) => break,
                    Ok(n) => n,
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                    Err(_) => break,
                };
                let Ok(mut g) = k.lock() else { break };
                let (buf, cut) = &mut *g;
                buf.extend_from_slice(&chunk[..n]);
                match keep {
                    Keep::Head(max) if buf.len() > max => {
                        buf.truncate(max + 1);
                        o.store(true, Ordering::SeqCst);
                        break;
                    }
                    Keep::Tail(max) if buf.len() > 2 * max => {
                        buf.drain(..buf.len() - max);
                        *cut = true;
                    }
                    _ => {}
                }
            }
            let _ = tx.send(());
        });
        Drain { kept, over, eof }
    }

    /// Waits up to `d` for the pipe's end; true if it came.
    fn ended_within(&self, d: Duration) -> bool {
        match self.eof.recv_timeout(d) {
            Ok(()) => true,
            Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => true,
            Err(std::sync::mpsc::RecvTimeoutError::Timeout) => false,
        }
    }

    /// The bytes kept so far, and whether the front was dropped.
    fn take(&self) -> (Vec<u8>, bool) {
        self.kept
            .lock()
            .map(|mut g| std::mem::take(&mut *g))
            .unwrap_or_default()
    }
}

/// The end of what a program wrote to stderr, as a report shows it: its last lines (a partial
/// first line, when the front was dropped, left out), each cut to a readable length from the
/// front, so the summary line of a traceback is always whole.
pub fn stderr_tail(bytes: &[u8], cut: bool) -> String {
    let text = String::from_utf8_lossy(bytes);
    let mut lines: Vec<&str> = text.lines().collect();
    if cut && lines.len() > 1 {
        lines.remove(0);
    }
    let start = lines.len().saturating_sub(STDERR_LINES);
    lines[start..]
        .iter()
        .map(|l| {
            let n = l.chars().count();
            if n > STDERR_LINE_CHARS {
                let tail: String = l.chars().skip(n - STDERR_LINE_CHARS).collect();
                format!("…{tail}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The program and every process it started (its process group, which the program leads).
struct Group {
    child: std::process::Child,
}

impl Group {
    /// Stops the whole group (on Unix; elsewhere the program itself).
    fn kill(&mut self) {
        #[cfg(unix)]
        {
            // The group's id is the program's pid (it was started as the group's leader). An
            // error (ESRCH: every process of the group has ended) needs nothing done.
            use rustix::process::{Pid, Signal, kill_process_group};
            if let Some(pid) = i32::try_from(self.child.id()).ok().and_then(Pid::from_raw) {
                let _ = kill_process_group(pid, Signal::KILL);
            }
        }
        let _ = self.child.kill();
        // Those that left the group (a new session or group): where raystep reaps them.
        super::isolate::stop_descendants(self.child.id());
    }
}

/// Runs the student's program for one pixel in `dir` and returns what it printed.
///
/// The program leads a process group of its own; whatever happens, the whole group is stopped
/// when the run ends, so nothing it started outlives the grading. A process it left running
/// that keeps its standard output open does not lose what the program printed: raystep waits
/// `LINGER` (1 s) for the output to end, then stops the group and grades what was read, saying so.
pub fn run(
    template: &str,
    dir: &Path,
    scene: &Path,
    x: u32,
    y: u32,
    limits: Limits,
) -> Result<Output, RunError> {
    let w = words(template, scene, x, y)?;
    let mut cmd = Command::new(&w[0]);
    cmd.args(&w[1..])
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    #[cfg(unix)]
    {
        use std::os::unix::process::CommandExt;
        cmd.process_group(0);
    }
    super::isolate::apply(&mut cmd);
    let child = cmd
        .spawn()
        .map_err(|e| RunError::Start(format!("{}: {e}", w[0])))?;
    let mut group = Group { child };
    let out = group
        .child
        .stdout
        .take()
        .map(|p| Drain::start(p, Keep::Head(limits.max_output)));
    let err = group
        .child
        .stderr
        .take()
        .map(|p| Drain::start(p, Keep::Tail(STDERR_TAIL)));
    let over = || out.as_ref().is_some_and(|d| d.over.load(Ordering::SeqCst));
    let start = Instant::now();
    let status = loop {
        match group.child.wait_timeout(Duration::from_millis(20)) {
            Ok(Some(st)) => break Ok(st),
            Ok(None) => {}
            Err(e) => break Err(RunError::Start(e.to_string())),
        }
        if over() {
            group.kill();
            let _ = group.child.wait();
            return Err(RunError::TooMuchOutput(limits.max_output));
        }
        if start.elapsed() > limits.timeout {
            group.kill();
            let _ = group.child.wait();
            return Err(RunError::Timeout(limits.timeout));
        }
    };
    let status = match status {
        Ok(s) => s,
        Err(e) => {
            group.kill();
            return Err(e);
        }
    };
    // The output ends when every process holding it has ended; one the program left running
    // may hold it open: give it a moment, then stop the group and keep what was read.
    let held = out.as_ref().is_some_and(|d| !d.ended_within(LINGER));
    group.kill();
    if held && let Some(d) = &out {
        d.ended_within(Duration::from_millis(200));
    }
    if over() {
        return Err(RunError::TooMuchOutput(limits.max_output));
    }
    let (stdout, _) = out.map(|d| d.take()).unwrap_or_default();
    if !status.success() {
        let (bytes, cut) = err
            .map(|d| {
                d.ended_within(Duration::from_millis(200));
                d.take()
            })
            .unwrap_or_default();
        return Err(RunError::Failed(
            status.to_string(),
            stderr_tail(&bytes, cut),
        ));
    }
    let stdout = String::from_utf8(stdout).map_err(|_| RunError::NotText)?;
    let note = held.then(|| {
        format!(
            "a process your program started kept its output open after your program ended; raystep stopped it after {:.0} s and graded what your program had printed",
            LINGER.as_secs_f64()
        )
    });
    Ok(Output { stdout, note })
}
