//! Running a student's program: the command template split into words (shell quoting rules, by
//! the `shlex` crate) with `{scene}`, `{x}` and `{y}` substituted inside each word, never through
//! a shell; a time limit and an output limit; stdin closed.

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
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

/// Runs the student's program for one pixel in `dir` and returns its standard output.
pub fn run(
    template: &str,
    dir: &Path,
    scene: &Path,
    x: u32,
    y: u32,
    limits: Limits,
) -> Result<String, RunError> {
    let w = words(template, scene, x, y)?;
    let mut child = Command::new(&w[0])
        .args(&w[1..])
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| RunError::Start(format!("{}: {e}", w[0])))?;
    let over = Arc::new(AtomicBool::new(false));
    let (tx, rx) = std::sync::mpsc::channel();
    if let Some(out) = child.stdout.take() {
        let over = over.clone();
        let max = limits.max_output;
        std::thread::spawn(move || {
            let mut buf = vec![];
            let _ = out.take(max as u64 + 1).read_to_end(&mut buf);
            if buf.len() > max {
                over.store(true, Ordering::SeqCst);
            }
            let _ = tx.send(buf);
        });
    }
    let (etx, erx) = std::sync::mpsc::channel();
    if let Some(mut err) = child.stderr.take() {
        std::thread::spawn(move || {
            let mut buf = vec![];
            let _ = (&mut err).take(1 << 16).read_to_end(&mut buf);
            let _ = etx.send(buf);
            // The rest is read and dropped, so the program never blocks on a full pipe.
            let _ = std::io::copy(&mut err, &mut std::io::sink());
        });
    }
    let start = Instant::now();
    let status = loop {
        match child.wait_timeout(Duration::from_millis(20)) {
            Ok(Some(st)) => break Ok(st),
            Ok(None) => {}
            Err(e) => break Err(RunError::Start(e.to_string())),
        }
        if over.load(Ordering::SeqCst) {
            let _ = child.kill();
            let _ = child.wait();
            return Err(RunError::TooMuchOutput(limits.max_output));
        }
        if start.elapsed() > limits.timeout {
            let _ = child.kill();
            let _ = child.wait();
            return Err(RunError::Timeout(limits.timeout));
        }
    }?;
    // The readers end once the pipes close (a grandchild still holding one: give up after 1 s).
    let out = rx.recv_timeout(Duration::from_secs(1)).unwrap_or_default();
    if over.load(Ordering::SeqCst) {
        return Err(RunError::TooMuchOutput(limits.max_output));
    }
    if !status.success() {
        let err = erx
            .recv_timeout(Duration::from_millis(200))
            .unwrap_or_default();
        let err = String::from_utf8_lossy(&err);
        let tail: Vec<&str> = err.lines().rev().take(8).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        return Err(RunError::Failed(status.to_string(), tail.join("\n")));
    }
    String::from_utf8(out).map_err(|_| RunError::NotText)
}
