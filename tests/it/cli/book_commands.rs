//! The command lines the book shows are the program's: every `raystep …` line of a shell block in
//! the README, the book's chapters (`book/*.md`), `docs/` and the lessons names commands and
//! flags that exist, checked against the `Cli` the binary parses (clap's own definition). A line
//! without optional parts (`[…]`), placeholders or elisions must parse as a whole, values
//! included.
//!
//! The lessons' commands that print the numbers they quote, and the walkthroughs' commands, are
//! run with their output compared (`tests/it/lessons/`, `tests/it/walkthrough.rs`); the
//! chapters' blocks are run here or marked (the second test below).

use clap::{CommandFactory, Parser};
use std::path::Path;

/// The `raystep` lines of every ```sh block of `text`, with their line numbers.
fn raystep_lines(text: &str) -> Vec<(usize, String)> {
    let mut out = vec![];
    let mut in_sh = false;
    let mut pending = String::new();
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if t.starts_with("```") {
            in_sh = !in_sh && (t == "```sh" || t == "```bash");
            continue;
        }
        if !in_sh {
            continue;
        }
        // A line ending in `\` goes on.
        let piece = t.strip_suffix('\\').unwrap_or(t);
        pending.push_str(piece);
        pending.push(' ');
        if t.ends_with('\\') {
            continue;
        }
        let whole = std::mem::take(&mut pending);
        let whole = whole.trim().trim_start_matches("$ ").to_string();
        if whole.starts_with("raystep ") {
            out.push((i + 1, whole));
        }
    }
    out
}

/// `line` without its trailing comment (` # …` outside quotes) and what it pipes into.
fn command_part(line: &str) -> String {
    let mut out = String::new();
    let mut quote = None;
    let chars: Vec<char> = line.chars().collect();
    for (k, &c) in chars.iter().enumerate() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if c == '"' || c == '\'' => quote = Some(c),
            None if (c == '#' || c == '|' || c == '>')
                && k > 0
                && chars[k - 1] == ' '
                && chars.get(k + 1).is_none_or(|n| *n == ' ') =>
            {
                break;
            }
            None => {}
        }
        out.push(c);
    }
    out.trim().to_string()
}

/// `s` without its bracketed optional parts (nested brackets included).
fn without_options(s: &str) -> String {
    let mut depth = 0;
    let mut out = String::new();
    for c in s.chars() {
        match c {
            '[' => depth += 1,
            ']' if depth > 0 => depth -= 1,
            _ if depth == 0 => out.push(c),
            _ => {}
        }
    }
    out
}

#[test]
fn the_command_lines_the_book_shows_are_the_programs() {
    let root = crate::common::scenes::root();
    let mut files: Vec<_> = ["README.md", "CONTRIBUTING.md", "lessons/starter/README.md"]
        .iter()
        .map(|f| root.join(f))
        .collect();
    for dir in ["book", "docs", "lessons"] {
        let mut more: Vec<_> = std::fs::read_dir(root.join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "md"))
            .collect();
        more.sort();
        files.extend(more);
    }
    let cli = raystep::cli::Cli::command();
    let mut failures = vec![];
    let (mut lines, mut parsed) = (0, 0);
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let name = file
            .strip_prefix(&root)
            .unwrap_or(Path::new("?"))
            .display()
            .to_string();
        for (at, line) in raystep_lines(&text) {
            lines += 1;
            let command = command_part(&line);
            let words = shlex::split(&without_options(&command)).unwrap_or_default();
            // The (sub)command the line names: follow the words while they name one.
            let mut cmd = &cli;
            let mut path = vec!["raystep".to_string()];
            for w in words.iter().skip(1) {
                match cmd.find_subcommand(w) {
                    Some(sub) => {
                        cmd = sub;
                        path.push(w.clone());
                    }
                    None => break,
                }
            }
            if path.len() == 1 && words.len() > 1 && !words[1].starts_with('-') {
                failures.push(format!(
                    "{name}:{at}: `{}` is not a raystep command",
                    words[1]
                ));
                continue;
            }
            // Every flag it shows, optional ones included, is one the command has.
            let flags: Vec<String> = command
                .split(|c: char| c.is_whitespace() || c == '[' || c == ']' || c == '|')
                .filter(|w| w.starts_with("--") && w.len() > 2)
                .map(|w| w.split('=').next().unwrap_or(w).to_string())
                .collect();
            for f in flags {
                let long = &f[2..];
                let known = long == "help"
                    || long == "version"
                    || cmd.get_arguments().any(|a| a.get_long() == Some(long));
                if !known {
                    failures.push(format!("{name}:{at}: `{}` has no flag {f}", path.join(" ")));
                }
            }
            // A line with nothing left out parses, values and all.
            let complete = !command.contains('[')
                && !command.contains('…')
                && !command.contains("...")
                && !words
                    .iter()
                    .any(|w| w == "SCENE" || w == "SCENES" || w == "DIR");
            if complete {
                parsed += 1;
                if let Err(e) = raystep::cli::Cli::try_parse_from(&words) {
                    failures.push(format!(
                        "{name}:{at}: `{command}` does not parse: {}",
                        e.to_string().lines().next().unwrap_or("")
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(
        lines >= 40 && parsed >= 20,
        "{lines} command lines, {parsed} parsed whole"
    );
}

/// Every shell block of the README, CONTRIBUTING.md, the book's chapters and `docs/` runs here,
/// or says why not with `<!-- not run: reason -->` just before it. A block that runs holds only
/// `raystep` commands; each must succeed, run from the repository's root.
#[test]
fn every_shell_block_of_the_book_runs_or_says_why_not() {
    let root = crate::common::scenes::root();
    let mut files: Vec<_> = ["README.md", "CONTRIBUTING.md"]
        .iter()
        .map(|f| root.join(f))
        .collect();
    for dir in ["book", "docs"] {
        for e in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|e| e == "md") {
                files.push(p);
            }
        }
    }
    files.sort();
    let (mut ran, mut marked, mut failures) = (0, 0, vec![]);
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let name = file.strip_prefix(&root).unwrap().display().to_string();
        let blocks = crate::common::shell_blocks::shell_blocks(&text, &name);
        failures.extend(blocks.problems);
        marked += blocks.marked;
        ran += blocks.to_run.len();
        for (first, body) in blocks.to_run {
            for (k, line) in body.iter().enumerate() {
                let l = line.trim();
                if l.is_empty() || l.starts_with('#') {
                    continue;
                }
                let words = shlex::split(&command_part(l)).unwrap_or_default();
                if words.first().map(String::as_str) != Some("raystep") {
                    failures.push(format!(
                        "{name}:{}: not a raystep command: mark the block `<!-- not run: why -->`",
                        first + k
                    ));
                    continue;
                }
                let out = assert_cmd::Command::cargo_bin("raystep")
                    .unwrap()
                    .current_dir(&root)
                    .args(&words[1..])
                    .output()
                    .unwrap();
                if !out.status.success() {
                    failures.push(format!(
                        "{name}:{}: `{l}` failed: {}",
                        first + k,
                        String::from_utf8_lossy(&out.stderr)
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(
        ran >= 1 && marked >= 10,
        "{ran} blocks ran, {marked} marked"
    );
}

/// The book's chapter on the trace format (`book/trace-format.md`) names every step type a trace
/// holds: the types of the steps recorded on every shipped scene (Whitted, distribution and path
/// tracing, instances, textures) at its centre and a corner, read from the traces' JSON, each
/// have an entry there (a line `` - `type` — what it is ``).
#[test]
fn the_trace_format_chapter_names_every_step_type() {
    let root = crate::common::scenes::root();
    let chapter = std::fs::read_to_string(root.join("book/trace-format.md")).unwrap();
    let mut seen = std::collections::BTreeSet::new();
    for scene in crate::common::scenes::shipped() {
        let s = raystep::scene::load_file(&scene).unwrap();
        let (w, h) = (s.camera.width, s.camera.height);
        let prepared = raystep::PreparedScene::new(s);
        for (x, y) in [(w / 2, h / 2), (w / 3, 2 * h / 3)] {
            let json: serde_json::Value =
                serde_json::from_str(&prepared.record(x, y, 0).to_json()).unwrap();
            fn walk(r: &serde_json::Value, seen: &mut std::collections::BTreeSet<String>) {
                for s in r["steps"].as_array().into_iter().flatten() {
                    if let Some(t) = s["type"].as_str() {
                        seen.insert(t.to_string());
                    }
                }
                for c in r["children"].as_array().into_iter().flatten() {
                    walk(c, seen);
                }
            }
            walk(&json["root"], &mut seen);
        }
    }
    // The types the chapter describes: the `names` before the dash of each "- `type` — …" entry.
    let described: std::collections::BTreeSet<String> = chapter
        .lines()
        .filter_map(|l| l.strip_prefix("- `"))
        .filter_map(|l| l.split(" — ").next())
        .flat_map(|names| {
            format!("`{names}")
                .split('`')
                .skip(1)
                .step_by(2)
                .map(str::to_string)
                .collect::<Vec<_>>()
        })
        .collect();
    let missing: Vec<_> = seen.difference(&described).collect();
    assert!(
        missing.is_empty(),
        "book/trace-format.md names no {missing:?}"
    );
    assert!(seen.len() >= 20, "{seen:?}");
}
