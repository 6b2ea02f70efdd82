//! The shell blocks of a Markdown file as the documentation's tests read them: fences opened by
//! ```` ```sh ```` or ```` ```bash ````, each run by the test or marked `<!-- not run: reason -->`
//! on the line before it (the last non-blank one), with a reason of three words or more.

/// A Markdown file's shell blocks, sorted.
#[derive(Debug, Default)]
pub struct ShellBlocks<'a> {
    /// The blocks to run: the 1-based line of the file that the block's first line is on, and
    /// the lines between the fences.
    pub to_run: Vec<(usize, Vec<&'a str>)>,
    /// How many blocks are marked not run, with a reason.
    pub marked: usize,
    /// Marks whose reason a reader cannot use, as messages naming `name` and the line.
    pub problems: Vec<String>,
}

/// Reads the shell blocks of `text`, the file `name`.
pub fn shell_blocks<'a>(text: &'a str, name: &str) -> ShellBlocks<'a> {
    let mut out = ShellBlocks::default();
    let lines: Vec<&str> = text.lines().collect();
    let mut i = 0;
    while i < lines.len() {
        let t = lines[i].trim();
        if !t.starts_with("```") {
            i += 1;
            continue;
        }
        let end = (i + 1..lines.len())
            .find(|&j| lines[j].trim().starts_with("```"))
            .unwrap_or(lines.len());
        if t == "```sh" || t == "```bash" {
            let before = lines[..i].iter().rev().find(|l| !l.trim().is_empty());
            let reason = before
                .and_then(|l| l.trim().strip_prefix("<!-- not run:"))
                .and_then(|r| r.strip_suffix("-->"))
                .map(str::trim);
            match reason {
                Some(r) if r.split_whitespace().count() >= 3 => out.marked += 1,
                Some(r) => out.problems.push(format!(
                    "{name}:{}: `not run: {r}` gives no reason a reader can use",
                    i + 1
                )),
                None => out.to_run.push((i + 2, lines[i + 1..end].to_vec())),
            }
        }
        i = end + 1;
    }
    out
}

#[test]
fn blocks_are_found_marked_or_to_run_and_other_fences_skipped() {
    let text = "text\n```sh\nraystep a\n```\n\n<!-- not run: it opens a window -->\n\n```bash\nraystep open\n```\n<!-- not run: why -->\n```sh\nx\n```\n```toml\n[a]\n```\n```sh\nraystep b\nraystep c\n```\n";
    let b = shell_blocks(text, "f.md");
    // By hand: the first block's body is line 3; the last block's body lines 19 and 20.
    assert_eq!(
        b.to_run,
        vec![(3, vec!["raystep a"]), (19, vec!["raystep b", "raystep c"])]
    );
    assert_eq!(b.marked, 1);
    assert_eq!(
        b.problems,
        vec!["f.md:12: `not run: why` gives no reason a reader can use".to_string()]
    );
}
