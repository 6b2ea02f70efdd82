//! The book's walkthroughs (book/walkthroughs.md) (a student with the starter kit, a teacher with a fresh sheet and a
//! class CSV) are run as written: every `$ command` of their `console` blocks runs in a fresh
//! folder, in order, and every line the book shows below a command must be among the lines it
//! printed (stdout and stderr together), in the same order. `…` stands for lines left out. A
//! command that exits non-zero must say so in the book with a line `(exit status N)`.
//!
//! Files a walkthrough writes by hand (a sheet, a platform's CSV export) are code blocks after an
//! HTML comment `<!-- file: NAME -->`: the test writes them into the folder before the next
//! command. A block after `<!-- not run: why -->` (a command that opens a window) is skipped.
//!
//! So the walkthroughs cannot go stale: a changed message, a renamed flag or a new score fails
//! this test.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// One step of a walkthrough, in the book's order.
#[derive(Debug, PartialEq)]
enum Step {
    /// Write this file (relative to the walkthrough's folder) with this content.
    File { name: String, content: String },
    /// Run this shell command; these lines must be among what it prints, in order.
    Run {
        command: String,
        expect: Vec<String>,
    },
}

/// The text of the section headed `heading` (`## Title`), up to the next heading of its
/// level or above.
fn section<'a>(readme: &'a str, heading: &str) -> &'a str {
    let start = readme
        .find(&format!("\n{heading}\n"))
        .unwrap_or_else(|| panic!("book/walkthroughs.md has no section {heading:?}"));
    let rest = &readme[start + 1..];
    let level = heading.chars().take_while(|&c| c == '#').count();
    let mut end = rest.len();
    let mut fenced = false;
    let mut at = 0;
    for line in rest.split_inclusive('\n') {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        }
        let hashes = line.chars().take_while(|&c| c == '#').count();
        if at > 0 && !fenced && (1..=level).contains(&hashes) && line[hashes..].starts_with(' ') {
            end = at;
            break;
        }
        at += line.len();
    }
    &rest[..end]
}

/// The steps of a walkthrough's Markdown, in order.
fn steps(text: &str) -> Vec<Step> {
    let mut steps = Vec::new();
    let mut lines = text.lines().peekable();
    let mut file: Option<String> = None;
    let mut skip = false;
    while let Some(line) = lines.next() {
        let t = line.trim();
        if let Some(name) = t
            .strip_prefix("<!-- file:")
            .and_then(|r| r.strip_suffix("-->"))
        {
            file = Some(name.trim().to_string());
            continue;
        }
        if t.starts_with("<!-- not run:") {
            skip = true;
            continue;
        }
        let Some(lang) = t.strip_prefix("```") else {
            continue;
        };
        let mut block = Vec::new();
        for l in lines.by_ref() {
            if l.trim_start().starts_with("```") {
                break;
            }
            block.push(l.to_string());
        }
        if let Some(name) = file.take() {
            steps.push(Step::File {
                name,
                content: block.join("\n") + "\n",
            });
        } else if lang == "console" && !std::mem::take(&mut skip) {
            steps.extend(console(&block));
        } else {
            skip = false;
        }
    }
    steps
}

/// The commands of a `console` block and the lines shown below each.
fn console(block: &[String]) -> Vec<Step> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < block.len() {
        let Some(first) = block[i].strip_prefix("$ ") else {
            panic!("console block: output before any command: {:?}", block[i]);
        };
        let mut command = first.to_string();
        i += 1;
        while command.ends_with('\\') && i < block.len() {
            command.pop();
            command.push_str(block[i].trim_start_matches('>').trim_start());
            i += 1;
        }
        let mut expect = Vec::new();
        while i < block.len() && !block[i].starts_with("$ ") {
            expect.push(block[i].trim_end().to_string());
            i += 1;
        }
        out.push(Step::Run { command, expect });
    }
    out
}

/// Whether `line` is what `pattern` shows, where a `…` inside the pattern stands for any text
/// (a time, a folder that differs between machines).
fn matches(pattern: &str, line: &str) -> bool {
    let mut parts = pattern.split('…');
    let first = parts.next().unwrap_or("");
    let Some(mut rest) = line.strip_prefix(first) else {
        return false;
    };
    let parts: Vec<&str> = parts.collect();
    let Some((last, middle)) = parts.split_last() else {
        return rest.is_empty();
    };
    for m in middle {
        match rest.find(m) {
            Some(k) => rest = &rest[k + m.len()..],
            None => return false,
        }
    }
    rest.len() >= last.len() && rest.ends_with(last)
}

/// Whether every line of `expect` (but `…` and blank lines) is a line of `got`, in order.
/// Returns the first line not found.
fn missing<'a>(expect: &'a [String], got: &str) -> Option<&'a str> {
    let got: Vec<&str> = got.lines().map(str::trim_end).collect();
    let mut at = 0;
    for e in expect {
        if e == "…" || e.is_empty() {
            continue;
        }
        match got[at..].iter().position(|g| matches(e, g)) {
            Some(k) => at += k + 1,
            None => return Some(e),
        }
    }
    None
}

/// A folder where the walkthrough runs: the repository's scenes, lessons and tests are there
/// (links), and `raystep` is on the PATH.
fn folder() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for name in ["scenes", "lessons", "tests"] {
        std::os::unix::fs::symlink(root().join(name), dir.path().join(name)).unwrap();
    }
    dir
}

fn run(dir: &Path, command: &str) -> String {
    let bin = Path::new(env!("CARGO_BIN_EXE_raystep")).parent().unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let out = Command::new("bash")
        .arg("-c")
        .arg(format!("{command} 2>&1"))
        .current_dir(dir)
        .env("PATH", path)
        .env("NO_COLOR", "1")
        .env("COLUMNS", "100")
        .output()
        .unwrap();
    let mut text = String::from_utf8_lossy(&out.stdout).into_owned();
    if !out.status.success() {
        let code = out
            .status
            .code()
            .map_or("a signal".into(), |c| c.to_string());
        text.push_str(&format!("(exit status {code})\n"));
    }
    text
}

fn walk(heading: &str, least_commands: usize) {
    let readme = std::fs::read_to_string(root().join("book/walkthroughs.md")).unwrap();
    let steps = steps(section(&readme, heading));
    let commands = steps
        .iter()
        .filter(|s| matches!(s, Step::Run { .. }))
        .count();
    assert!(
        commands >= least_commands,
        "{heading}: {commands} commands, expected at least {least_commands}"
    );
    let dir = folder();
    let mut failures = Vec::new();
    for step in &steps {
        match step {
            Step::File { name, content } => std::fs::write(dir.path().join(name), content).unwrap(),
            Step::Run { command, expect } => {
                let got = run(dir.path(), command);
                let exited_badly = got.lines().any(|l| l.starts_with("(exit status "));
                let said = expect.iter().any(|l| l.starts_with("(exit status "));
                if let Some(line) = missing(expect, &got) {
                    failures.push(format!(
                        "$ {command}\n  the book shows: {line:?}\n  printed:\n{got}"
                    ));
                } else if exited_badly && !said {
                    failures.push(format!(
                        "$ {command}\n  failed, the book does not say so:\n{got}"
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{heading}:\n{}", failures.join("\n"));
}

#[test]
fn the_student_walkthrough_prints_what_the_readme_shows() {
    walk("## A student, with the starter kit", 6);
}

#[test]
fn the_teacher_walkthrough_prints_what_the_readme_shows() {
    walk("## A teacher, with a fresh sheet and a class CSV", 5);
}

#[test]
fn walkthrough_blocks_are_read_as_written() {
    let md = "text\n<!-- file: a.csv -->\n```csv\nx;y\n1;2\n```\n```console\n$ raystep a \\\n    --b\nline one\n…\nline two\n$ echo hi\nhi\n```\n<!-- not run: a window -->\n```console\n$ raystep open x\n```\n```sh\n$ not a walkthrough\n```\n";
    assert_eq!(
        steps(md),
        vec![
            Step::File {
                name: "a.csv".into(),
                content: "x;y\n1;2\n".into()
            },
            Step::Run {
                command: "raystep a --b".into(),
                expect: vec!["line one".into(), "…".into(), "line two".into()]
            },
            Step::Run {
                command: "echo hi".into(),
                expect: vec!["hi".into()]
            },
        ]
    );
}

#[test]
fn a_section_ends_at_the_next_heading_of_its_level() {
    let md = "intro\n## A\n### B\nb\n```sh\n# not a heading\n```\n#### C\nc\n### D\nd\n## E\n";
    assert_eq!(
        section(md, "### B"),
        "### B\nb\n```sh\n# not a heading\n```\n#### C\nc\n"
    );
    assert_eq!(
        section(md, "## A"),
        "## A\n### B\nb\n```sh\n# not a heading\n```\n#### C\nc\n### D\nd\n"
    );
}

#[test]
fn a_changed_line_or_a_wrong_order_is_caught() {
    let expect: Vec<String> = ["a", "…", "c"].iter().map(|s| s.to_string()).collect();
    assert_eq!(missing(&expect, "a\nb\nc\n"), None);
    assert_eq!(missing(&expect, "c\na\n"), Some("c"));
    assert_eq!(missing(&expect, "a\nb\nc changed\n"), Some("c"));
    assert!(matches(
        "student: 2 / 4 (4 tests, … s)",
        "student: 2 / 4 (4 tests, 0.3 s)"
    ));
    assert!(matches("wrote …/a/b.py", "wrote /tmp/x/a/b.py"));
    assert!(!matches("wrote …/a/b.py", "wrote /tmp/x/a/c.py"));
    assert!(!matches("a…b…c", "a c b"));
    assert!(matches("a…b…c", "a1b2c"));
    assert!(!matches("ab…ba", "aba"));
    let dir = folder();
    assert_eq!(run(dir.path(), "echo x; exit 3"), "x\n(exit status 3)\n");
}
