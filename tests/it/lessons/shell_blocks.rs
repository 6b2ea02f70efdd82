//! Every shell block of the lessons and of the starter kit's README runs, or says why not.
//!
//! A block runs when each of its commands can run here: `raystep` (not the app, a benchmark or
//! the GPU) or `python3`; it runs through the lessons' [`Runner`], so a command the quoted
//! numbers already ran is not run again, and its files go to the runner's temporary folder. A
//! block that cannot run says so with `<!-- not run: reason -->` on the line before it, as the
//! book's chapters do (`tests/it/cli/book_commands.rs`).

use super::*;

/// What a block's commands need that a test does not have, if anything.
fn cannot_run(line: &str) -> Option<&'static str> {
    let words: Vec<&str> = line.split_whitespace().collect();
    match (words.first().copied(), words.get(1).copied()) {
        (Some("raystep"), Some("open")) => Some("it opens the app's window"),
        (Some("raystep"), Some("bench")) => Some("a benchmark: minutes of timings"),
        (Some("raystep"), Some("compare")) => Some("it renders on a GPU"),
        (Some("raystep"), _) if words.contains(&"--gpu") => Some("it renders on a GPU"),
        (Some("raystep" | "python3"), _) => None,
        _ => Some("not a raystep or python3 command"),
    }
}

/// The commands of the shell block in `lines` (its lines between the fences): continuation
/// lines (`\` at the end) joined, blank lines and `#` comments left out, each without its
/// trailing `# comment` or the pipe after it, with the 1-based line of the file it starts on.
fn block_commands(lines: &[&str], first_line: usize) -> Vec<(usize, String)> {
    let mut out: Vec<(usize, String)> = vec![];
    let mut open: Option<(usize, String)> = None;
    for (k, raw) in lines.iter().enumerate() {
        let l = raw.trim();
        let (n, mut text) = match open.take() {
            Some((n, head)) => (n, head + " " + l),
            None if l.is_empty() || l.starts_with('#') => continue,
            None => (first_line + k, l.to_string()),
        };
        if let Some(head) = text.strip_suffix('\\') {
            open = Some((n, head.trim_end().to_string()));
            continue;
        }
        text = text.split(" # ").next().unwrap_or(&text).to_string();
        text = text.split(" | ").next().unwrap_or(&text).trim().to_string();
        out.push((n, text));
    }
    out.extend(open);
    out
}

/// Runs every shell block of `text` (the file `name`) that is not marked `<!-- not run: … -->`,
/// and returns what failed or cannot run, with the numbers of blocks run and marked.
pub(super) fn unrun_blocks(
    text: &str,
    name: &str,
    runner: &mut Runner,
) -> (Vec<String>, usize, usize) {
    let blocks = crate::common::shell_blocks::shell_blocks(text, name);
    let mut problems = vec![];
    for (first, body) in &blocks.to_run {
        for (n, line) in block_commands(body, *first) {
            if let Some(why) = cannot_run(&line) {
                problems.push(format!(
                    "{name}:{n}: `{line}` cannot run in a test ({why}): put it in a \
                     block of its own marked `<!-- not run: why -->`"
                ));
            } else if let Err(e) = runner.output(&Quoted { line }) {
                problems.push(format!("{name}:{n}: {e}"));
            }
        }
    }
    // The marks without a usable reason, after what the blocks that ran found.
    problems.extend(blocks.problems);
    (problems, blocks.to_run.len(), blocks.marked)
}

#[test]
fn a_block_is_read_as_a_shell_reads_it() {
    let block = [
        "# a comment",
        "raystep trace a.toml --pixel 1,2   # what it prints",
        "",
        "raystep grade-tracer --scene a.toml \\",
        "    --run \"python3 t.py {scene}\"",
        "for s in 1 2; do raystep x; done | tail -1",
    ];
    assert_eq!(
        block_commands(&block, 10),
        vec![
            (11, "raystep trace a.toml --pixel 1,2".to_string()),
            (
                13,
                "raystep grade-tracer --scene a.toml --run \"python3 t.py {scene}\"".to_string()
            ),
            (15, "for s in 1 2; do raystep x; done".to_string()),
        ]
    );
    assert_eq!(cannot_run("raystep trace a.toml"), None);
    assert_eq!(cannot_run("python3 lessons/starter/tracer.py a 1 2"), None);
    assert!(cannot_run("raystep render a.toml --gpu -o a.png").is_some());
    assert!(cannot_run("raystep bench --section mc").is_some());
    assert!(cannot_run("for s in 1 2; do raystep x; done").is_some());
}

#[test]
fn a_failing_or_unmarked_block_is_reported_and_a_marked_one_is_not() {
    let text = "Text.\n\n```sh\nraystep trace scenes/nope.toml --pixel 1,1\nraystep bench\n```\n\n\
                <!-- not run: it opens the app -->\n```sh\nraystep open scenes/cornell.toml\n```\n\n\
                <!-- not run: why -->\n```sh\nraystep open x\n```\n";
    let (problems, ran, marked) = unrun_blocks(text, "t.md", &mut Runner::new());
    assert_eq!((ran, marked), (1, 1), "{problems:?}");
    assert_eq!(problems.len(), 3, "{problems:?}");
    assert!(problems[0].starts_with("t.md:4: `raystep trace scenes/nope.toml"));
    assert!(problems[1].starts_with("t.md:5: `raystep bench` cannot run"));
    assert!(problems[2].starts_with("t.md:14: `not run: why` gives no reason"));
}
