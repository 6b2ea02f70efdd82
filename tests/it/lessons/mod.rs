//! The lessons in `lessons/`: every lesson's front matter parses, its scene loads, its pixel is in
//! the image, the primary ray's closest hit is what the lesson says, the steps it points at exist,
//! every relative link resolves, the lessons are numbered 01..12 and the index links them in
//! order, and together they cover the twelve topics of the course.

use raystep::accel::SceneAccel;
use raystep::lesson::{Lesson, explaining_step, load_exercise_sheet, load_lessons, parse_lesson};
use raystep::trace::Tracer;
use std::path::{Path, PathBuf};

/// The number of lessons the course has.
const LESSONS: usize = 20;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn lessons_dir() -> PathBuf {
    root().join("lessons")
}

/// Every Markdown file in `lessons/` (README.md included), sorted by name.
fn markdown_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(lessons_dir())
        .expect("lessons/ exists")
        .map(|e| e.expect("a readable directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    files.sort();
    files
}

/// The lessons proper: every `lessons/*.md` but README.md, sorted by name.
fn lesson_files() -> Vec<PathBuf> {
    markdown_files()
        .into_iter()
        .filter(|p| p.file_name().is_some_and(|n| n != "README.md"))
        .collect()
}

fn file_name(p: &Path) -> String {
    p.file_name().unwrap().to_string_lossy().into_owned()
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The lesson as the library (and the app) reads it.
fn lesson(p: &Path) -> Lesson {
    parse_lesson(&read(p), p).unwrap_or_else(|e| panic!("{e}"))
}

/// The targets of the inline Markdown links `[text](target)` in `text`, outside code spans and
/// fenced code blocks.
fn links(text: &str) -> Vec<String> {
    let mut out = vec![];
    let mut in_fence = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_fence = !in_fence;
            continue;
        }
        if in_fence {
            continue;
        }
        // Drop code spans so that `a[i](x)` in code is not read as a link.
        let mut plain = String::new();
        for (i, part) in line.split('`').enumerate() {
            if i % 2 == 0 {
                plain.push_str(part);
            }
        }
        let mut rest = plain.as_str();
        while let Some(k) = rest.find("](") {
            let after = &rest[k + 2..];
            let Some(close) = after.find(')') else { break };
            let target = after[..close].split_whitespace().next().unwrap_or("");
            out.push(target.to_string());
            rest = &after[close + 1..];
        }
    }
    out
}

/// A link that points at a file of this repository: not a URL, not a bare `#anchor`.
fn relative_path(target: &str) -> Option<&str> {
    let lower = target.to_ascii_lowercase();
    if target.is_empty()
        || target.starts_with('#')
        || lower.starts_with("http://")
        || lower.starts_with("https://")
        || lower.starts_with("mailto:")
    {
        return None;
    }
    Some(target.split('#').next().unwrap_or(target))
}

#[test]
fn lessons_are_numbered_01_to_20_without_gaps() {
    let names: Vec<String> = lesson_files().iter().map(|p| file_name(p)).collect();
    assert_eq!(
        names.len(),
        LESSONS,
        "expected {LESSONS} lessons, found {names:?}"
    );
    for (i, name) in names.iter().enumerate() {
        let prefix = format!("{:02}-", i + 1);
        assert!(
            name.starts_with(&prefix),
            "lesson {} should be named {prefix}….md, found {name} (all: {names:?})",
            i + 1
        );
        let slug = &name[prefix.len()..name.len() - 3];
        assert!(
            !slug.is_empty()
                && slug
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-'),
            "{name}: the name after the number should be a lower-case slug"
        );
    }
}

#[test]
fn every_lesson_traces_to_what_it_says() {
    let files = lesson_files();
    assert!(!files.is_empty(), "no lessons found");
    for p in files {
        let name = file_name(&p);
        let fm = lesson(&p);
        let body = &fm.body;
        assert!(!fm.title.trim().is_empty(), "{name}: empty title");
        assert!(
            !fm.steps.is_empty(),
            "{name}: `steps` should name at least one step worth looking at"
        );
        assert!(
            fm.steps.windows(2).all(|w| w[0] < w[1]),
            "{name}: `steps` should be increasing, got {:?}",
            fm.steps
        );
        assert!(
            !Path::new(&fm.scene).is_absolute() && !fm.scene.contains(".."),
            "{name}: the scene should be a path from the repository root, got {}",
            fm.scene
        );
        assert!(
            body.contains(&fm.scene),
            "{name}: the lesson's text should name its scene {}",
            fm.scene
        );

        let mut scene = raystep::scene::load_file(&root().join(&fm.scene))
            .unwrap_or_else(|e| panic!("{name}: scene {} does not load: {e}", fm.scene));
        fm.settings
            .apply(&mut scene)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let [x, y] = fm.pixel;
        assert!(
            x < scene.camera.width && y < scene.camera.height,
            "{name}: pixel ({x}, {y}) is outside the {}×{} image of {}",
            scene.camera.width,
            scene.camera.height,
            fm.scene
        );

        let (accel, _) = SceneAccel::build(&scene);
        let trace = Tracer::new(&scene, &accel).record(x, y, 0);
        let hit = trace
            .root
            .hit
            .as_ref()
            .map_or("nothing", |h| h.name.as_str());
        assert_eq!(
            hit, fm.hits,
            "{name}: the primary ray of pixel ({x}, {y}) in {} hits \"{hit}\", the lesson says \"{}\"",
            fm.scene, fm.hits
        );

        let n = trace.timeline().len();
        for &k in &fm.steps {
            assert!(
                k < n,
                "{name}: step {k} does not exist: pixel ({x}, {y}) has {n} steps (0–{})",
                n - 1
            );
        }
    }
}

#[test]
fn lessons_with_exercises_point_at_sheets_that_load_and_explain_their_answers() {
    let lessons = load_lessons(&lessons_dir()).expect("the lessons load");
    assert_eq!(lessons.len(), LESSONS);
    // Every lesson is tied to an exercise sheet.
    for l in &lessons {
        assert!(
            l.exercises.is_some(),
            "{}: the lesson names no exercise sheet (add `exercises = \"exercises/….toml\"` to its front matter)",
            file_name(&l.file)
        );
    }
    for l in &lessons {
        let name = file_name(&l.file);
        let path = l.exercises_path().unwrap();
        let sheet = load_exercise_sheet(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(!sheet.questions.is_empty(), "{name}: an empty sheet");
        // Every question of the sheet, for one student: the step that explains the answer
        // exists and is of the kind the quantity is read from.
        for q in &sheet.questions {
            let v = sheet.variant(q, "s1");
            let scene = match &v.scene_toml {
                Some(t) => raystep::scene::load_str(t, "inline", path.parent()).unwrap(),
                None => match &q.scene {
                    raystep::lesson::SceneSource::File(p) => raystep::scene::load_file(p).unwrap(),
                    raystep::lesson::SceneSource::Inline(_) => unreachable!(),
                },
            };
            let (accel, _) = SceneAccel::build(&scene);
            let trace = Tracer::new(&scene, &accel).record(v.pixel[0], v.pixel[1], 0);
            let k = explaining_step(&trace, q)
                .unwrap_or_else(|| panic!("{name}: question {} has no explaining step", q.id));
            assert!(k < trace.timeline().len());
        }
    }
}

#[test]
fn every_relative_link_resolves() {
    let dir = lessons_dir();
    let mut checked = 0;
    for p in markdown_files() {
        let name = file_name(&p);
        for target in links(&read(&p)) {
            let Some(rel) = relative_path(&target) else {
                continue;
            };
            let resolved = dir.join(rel);
            assert!(
                resolved.is_file(),
                "{name}: the link ({target}) points at {}, which is not a file",
                resolved.display()
            );
            checked += 1;
        }
    }
    assert!(checked > 0, "no relative links were found to check");
}

#[test]
fn scenes_named_in_the_text_exist() {
    for p in lesson_files() {
        let name = file_name(&p);
        let text = read(&p);
        let mut rest = text.as_str();
        while let Some(k) = rest.find("scenes/") {
            let tail = &rest[k..];
            let end = tail
                .find(|c: char| !(c.is_ascii_alphanumeric() || "/-_.".contains(c)))
                .unwrap_or(tail.len());
            let path = tail[..end].trim_end_matches('.');
            if path.ends_with(".toml") {
                assert!(
                    root().join(path).is_file(),
                    "{name}: mentions {path}, which does not exist"
                );
            }
            rest = &tail[end..];
        }
    }
}

#[test]
fn the_index_links_every_lesson_in_order() {
    let readme = read(&lessons_dir().join("README.md"));
    let targets: Vec<String> = links(&readme)
        .iter()
        .filter_map(|t| relative_path(t).map(|r| r.trim_start_matches("./").to_string()))
        .collect();
    let mut last = None;
    for p in lesson_files() {
        let name = file_name(&p);
        let pos = targets
            .iter()
            .position(|t| *t == name)
            .unwrap_or_else(|| panic!("lessons/README.md does not link {name}"));
        if let Some((prev_pos, prev)) = &last {
            assert!(
                pos > *prev_pos,
                "lessons/README.md links {name} before {prev}: the index should be in order"
            );
        }
        last = Some((pos, name));
    }
}

#[test]
fn the_lessons_cover_their_topics_in_order() {
    // For each lesson, the words its topic cannot be taught without (case-insensitive).
    let topics: [&[&str]; LESSONS] = [
        &["one ray per pixel", "inverse mapping", "camera"],
        &["discriminant", "quadratic", "normal", "root"],
        &["plane", "axis-aligned", "parallel", "denominator"],
        &["Möller–Trumbore", "Cramer", "barycentric", "early exit"],
        &["naive loop", "closest hit", "massively slow"],
        &[
            "BVH",
            "bounding box",
            "bounding sphere",
            "spatial subdivision",
        ],
        &["shadow ray", "blocked"],
        &["reflection", "reflective"],
        &[
            "refraction",
            "Snell",
            "total internal reflection",
            "critical angle",
        ],
        &["antialiasing", "jitter", "samples"],
        &[
            "fragment shader",
            "ray-generation",
            "traversal",
            "intersection",
            "any-hit",
            "closest-hit",
            "miss",
        ],
        &["acne", "no offset", "watertight", "textbook", "f32"],
        &[
            "estimator",
            "expectation",
            "variance",
            "1/√n",
            "standard error",
        ],
        &[
            "penumbra",
            "area",
            "per steradian",
            "soft shadow",
            "blocked",
        ],
        &[
            "rendering equation",
            "next-event estimation",
            "cosine-weighted",
            "Russian roulette",
            "divided by q",
        ],
        &[
            "power heuristic",
            "light sampling",
            "BSDF sampling",
            "weight",
            "relMSE",
        ],
        &[
            "barycentric",
            "vertex normal",
            "shading normal",
            "shadow terminator",
            "tangent plane",
        ],
        &[
            "texture coordinates",
            "texel",
            "nearest",
            "bilinear",
            "wrap",
        ],
        &[
            "mip",
            "ray cone",
            "level of detail",
            "footprint",
            "trilinear",
            "aliasing",
        ],
        &[
            "instance",
            "object space",
            "BLAS",
            "TLAS",
            "inverse transpose",
        ],
    ];
    let files = lesson_files();
    assert_eq!(files.len(), LESSONS);
    for (p, words) in files.iter().zip(topics) {
        let name = file_name(p);
        let text = read(p).to_lowercase();
        for w in words {
            assert!(
                text.contains(&w.to_lowercase()),
                "{name} should mention \"{w}\""
            );
        }
    }
}

#[test]
fn link_extraction_sees_links_and_skips_code() {
    let text = "See [one](01-a.md) and [web](https://example.com) and [here](#top).\n\
                `[not](code.md)` but [two](02-b.md#part \"title\")\n\
                ```\n[fenced](nope.md)\n```\n";
    let found = links(text);
    assert_eq!(
        found,
        ["01-a.md", "https://example.com", "#top", "02-b.md#part"]
    );
    let rel: Vec<&str> = found.iter().filter_map(|t| relative_path(t)).collect();
    assert_eq!(rel, ["01-a.md", "02-b.md"]);
}

// ---------------------------------------------------------------------------------------------
// Every quoted number comes from the command beside it (the convention is in lessons/README.md,
// "Writing a lesson: quoted numbers").
// ---------------------------------------------------------------------------------------------

/// A number written in a lesson or printed by raystep.
#[derive(Debug, Clone, PartialEq)]
struct Number {
    /// As written (`−7.8414445e−07`).
    text: String,
    /// Its value.
    value: f64,
    /// Whether it has a decimal point or an exponent (only those are checked).
    decimal: bool,
    /// The place value of its last digit (`0.001` for `2.731`, `1e-14` for `7.8414445e-7`).
    ulp: f64,
    /// Followed by `…`: cut, not rounded (`0.5863…`).
    cut: bool,
    /// Preceded by `≈`: a rounded or hand-made approximation, not checked.
    approx: bool,
    /// Followed by a unit of time (`ms`, `s`): a timing, which differs between machines.
    timing: bool,
}

/// The numbers in `text`. A minus is `-` or `−` (U+2212) right before the digits; digits that
/// continue a word (`E1`, `D0`, `pbrt-v4`) are not numbers; `1.2.3` is not a number.
fn numbers_in(text: &str) -> Vec<Number> {
    let c: Vec<char> = text.chars().collect();
    let is_minus = |ch: char| ch == '-' || ch == '−';
    let word = |ch: char| ch.is_alphanumeric() || ch == '_';
    let digits_from = |mut i: usize| {
        while i < c.len() && c[i].is_ascii_digit() {
            i += 1;
        }
        i
    };
    let mut out = vec![];
    let mut i = 0;
    while i < c.len() {
        let starts_number = c[i].is_ascii_digit()
            || (is_minus(c[i]) && c.get(i + 1).is_some_and(|d| d.is_ascii_digit()));
        let glued = i > 0 && (word(c[i - 1]) || c[i - 1] == '.');
        if !starts_number || glued {
            i += 1;
            continue;
        }
        let start = i;
        let negative = is_minus(c[i]);
        if negative {
            i += 1;
        }
        let int_end = digits_from(i);
        let mut end = int_end;
        let mut decimals = 0;
        if end + 1 < c.len() && c[end] == '.' && c[end + 1].is_ascii_digit() {
            let frac_end = digits_from(end + 1);
            decimals = frac_end - end - 1;
            end = frac_end;
        }
        let mut exponent = 0i32;
        let mut has_exponent = false;
        if end < c.len() && (c[end] == 'e' || c[end] == 'E') {
            let mut j = end + 1;
            let exp_negative = j < c.len() && is_minus(c[j]);
            if j < c.len() && (is_minus(c[j]) || c[j] == '+') {
                j += 1;
            }
            let exp_end = digits_from(j);
            if exp_end > j && !(exp_end < c.len() && word(c[exp_end])) {
                let e: i32 = c[j..exp_end].iter().collect::<String>().parse().unwrap();
                exponent = if exp_negative { -e } else { e };
                has_exponent = true;
                end = exp_end;
            }
        }
        // `1.2.3` or `4th`: not a number.
        let version = end + 1 < c.len() && c[end] == '.' && c[end + 1].is_ascii_digit();
        if version || (end < c.len() && word(c[end]) && !has_exponent) {
            i = end;
            while i < c.len() && (word(c[i]) || c[i] == '.') {
                i += 1;
            }
            continue;
        }
        let written: String = c[start..end].iter().collect();
        let mantissa: String = c[if negative { start + 1 } else { start }..end]
            .iter()
            .take_while(|ch| **ch != 'e' && **ch != 'E')
            .collect();
        let m: f64 = mantissa.parse().unwrap();
        let value = if negative { -m } else { m } * 10f64.powi(exponent);
        let before: String = c[..start].iter().rev().take(3).collect();
        let after: String = c[end..].iter().take(4).collect();
        let unit = after.trim_start_matches(' ');
        out.push(Number {
            text: written,
            value,
            decimal: decimals > 0 || has_exponent,
            ulp: 10f64.powi(exponent - decimals as i32),
            cut: after.starts_with('…'),
            approx: before.trim_start().starts_with('≈'),
            timing: (unit.starts_with("ms")
                || unit.starts_with("s ")
                || unit == "s"
                || unit.starts_with("s,")
                || unit.starts_with("s.")
                || unit.starts_with("s)"))
                && after.starts_with(' '),
        });
        i = end;
    }
    out
}

/// Whether the printed number `p` is the quoted number `q`, at the precision `q` is written to:
/// `p` rounds to `q` (or, for `q…`, `p`'s digits start with `q`'s).
fn quotes(q: &Number, p: f64) -> bool {
    // A hair of slack for the decimal ↔ binary conversions.
    let slack = q.ulp * 1e-6 + q.value.abs() * 1e-12;
    if q.cut {
        if q.value >= 0.0 {
            p >= q.value - slack && p < q.value + q.ulp + slack
        } else {
            p <= q.value + slack && p > q.value - q.ulp - slack
        }
    } else {
        (p - q.value).abs() <= q.ulp / 2.0 + slack
    }
}

/// One command a lesson quotes, where it is quoted.
#[derive(Debug, Clone)]
struct Quoted {
    /// The command line as written (without its `# comment`).
    line: String,
}

impl Quoted {
    /// The raystep subcommand (`trace`, `open`, …).
    fn subcommand(&self) -> &str {
        self.line.split_whitespace().nth(1).unwrap_or("")
    }

    /// Whether the test can run it: not the app (`open`), not a benchmark (`bench`: minutes,
    /// and timings), not a GPU comparison (`compare`: needs an adapter).
    fn runnable(&self) -> bool {
        !matches!(self.subcommand(), "open" | "bench" | "compare")
    }
}

/// The `raystep` commands of a line of a `sh` block or of a code span: the command before a
/// pipe or a `# comment`, if the line is one.
fn command_of(code: &str) -> Option<Quoted> {
    let code = code.trim();
    if !code.starts_with("raystep ") {
        return None;
    }
    let line = code.split(" # ").next().unwrap_or(code);
    let line = line.split(" | ").next().unwrap_or(line).trim();
    Some(Quoted {
        line: line.to_string(),
    })
}

/// What a lesson quotes: a number, where, and the commands it must come from.
#[derive(Debug)]
struct Claim {
    number: Number,
    /// 1-based line of the lesson file.
    line: usize,
    /// The commands that should print it (empty: none precedes it).
    sources: Vec<Quoted>,
}

/// The lesson's checked numbers and their sources, by the convention of lessons/README.md:
///
/// - the numbers of a prose block (a paragraph, a list item, a table) come from the `raystep`
///   commands in its own code spans, else from those of the last ```` ```sh ```` block above it;
/// - the numbers in a `sh` line's `# comment` come from that line's command;
/// - only numbers with a decimal point or an exponent are checked; not those after `≈`, not
///   timings (a number followed by `ms` or `s`), not headings, not command arguments, and no
///   block that holds `<!-- not checked: … -->`.
fn claims(text: &str) -> Vec<Claim> {
    let mut out = vec![];
    let mut fence: Option<String> = None; // the open fence's language
    let mut last_sh: Vec<Quoted> = vec![];
    let mut fence_cmds: Vec<Quoted> = vec![];
    let mut block: Vec<(usize, &str)> = vec![];
    let mut front_matter = text.starts_with("+++");
    let mut seen_open = false;

    let flush = |block: &mut Vec<(usize, &str)>, last_sh: &Vec<Quoted>, out: &mut Vec<Claim>| {
        if block.is_empty() {
            return;
        }
        let joined: String = block.iter().map(|(_, l)| *l).collect::<Vec<_>>().join("\n");
        let skip = joined.contains("<!-- not checked") || joined.trim_start().starts_with('#');
        if !skip {
            // The block's own commands (in code spans), and its text outside them.
            let mut own = vec![];
            let mut found = vec![];
            for (n, l) in block.iter() {
                let mut plain = String::new();
                for (k, part) in l.split('`').enumerate() {
                    match (k % 2 == 1).then(|| command_of(part)).flatten() {
                        Some(q) => own.push(q),
                        None => plain.push_str(part),
                    }
                    plain.push(' ');
                }
                // Link targets are file names, not quoted numbers.
                let mut text = String::new();
                let mut rest = plain.as_str();
                while let Some(k) = rest.find("](") {
                    text.push_str(&rest[..k + 1]);
                    let after = &rest[k + 2..];
                    rest = after.find(')').map_or("", |c| &after[c + 1..]);
                }
                text.push_str(rest);
                found.extend(numbers_in(&text).into_iter().map(|number| (number, *n)));
            }
            let own: Vec<Quoted> = own.into_iter().filter(Quoted::runnable).collect();
            let sources = if own.is_empty() { last_sh } else { &own };
            out.extend(found.into_iter().map(|(number, line)| Claim {
                number,
                line,
                sources: sources.clone(),
            }));
        }
        block.clear();
    };

    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        if front_matter {
            if line.trim() == "+++" {
                if seen_open {
                    front_matter = false;
                }
                seen_open = true;
            }
            continue;
        }
        let t = line.trim_start();
        if let Some(lang) = t.strip_prefix("```") {
            flush(&mut block, &last_sh, &mut out);
            match fence.take() {
                Some(open) => {
                    if open == "sh" {
                        last_sh = std::mem::take(&mut fence_cmds);
                    }
                }
                None => fence = Some(lang.trim().to_string()),
            }
            continue;
        }
        if let Some(lang) = &fence {
            if lang == "sh"
                && let Some(q) = command_of(t)
            {
                // Numbers in the line's comment come from the line's command.
                if let Some((_, comment)) = t.split_once(" # ") {
                    for number in numbers_in(comment) {
                        out.push(Claim {
                            number,
                            line: n,
                            sources: if q.runnable() {
                                vec![q.clone()]
                            } else {
                                vec![]
                            },
                        });
                    }
                }
                fence_cmds.push(q);
            }
            continue;
        }
        let starts_item = t.starts_with("- ")
            || t.starts_with("* ")
            || t.split_once(". ")
                .is_some_and(|(d, _)| !d.is_empty() && d.chars().all(|ch| ch.is_ascii_digit()));
        let table_row = t.starts_with('|');
        let in_table = block
            .last()
            .is_some_and(|(_, l)| l.trim_start().starts_with('|'));
        // A comment (`<!-- not checked: … -->`) belongs to the block it follows.
        let new_block = t.is_empty()
            || t.starts_with('#')
            || (starts_item && !in_table)
            || (table_row != in_table && !block.is_empty());
        if new_block && !t.starts_with("<!--") {
            flush(&mut block, &last_sh, &mut out);
        }
        if t.is_empty() {
            continue;
        }
        block.push((n, line));
        if t.starts_with('#') {
            flush(&mut block, &last_sh, &mut out);
        }
    }
    flush(&mut block, &last_sh, &mut out);
    out.retain(|c| c.number.decimal && !c.number.approx && !c.number.timing);
    out
}

/// Runs the commands lessons quote, each once.
struct Runner {
    /// Where the commands' output files go (`-o tri.png` is written here, not into the
    /// repository).
    out_dir: tempfile::TempDir,
    /// Each command's standard output and error, by command line.
    seen: std::collections::HashMap<String, Result<String, String>>,
    /// The files written so far, as the lesson names them, and where they went: a later
    /// command that reads one reads it there (`raystep scene spd … -o /tmp/balls3.toml`, then
    /// `raystep render /tmp/balls3.toml …`).
    written: std::collections::HashMap<String, String>,
}

impl Runner {
    fn new() -> Runner {
        Runner {
            out_dir: tempfile::tempdir().expect("a temporary folder"),
            seen: Default::default(),
            written: Default::default(),
        }
    }

    /// The command's output (stdout, then stderr), or why it failed. It runs from the
    /// repository root, as the lessons say, with every file it writes sent to a temporary folder.
    fn output(&mut self, q: &Quoted) -> Result<String, String> {
        if let Some(r) = self.seen.get(&q.line) {
            return r.clone();
        }
        let r = (|| {
            let words =
                shlex::split(&q.line).ok_or_else(|| format!("cannot split `{}`", q.line))?;
            // `python3 …` (the starter kit) runs as written; `raystep …` is this build's.
            let program = match words.first().map(String::as_str) {
                Some("python3") => "python3",
                _ => env!("CARGO_BIN_EXE_raystep"),
            };
            let mut args: Vec<String> = vec![];
            let mut redirect = false;
            for w in words.into_iter().skip(1) {
                if redirect {
                    let name = Path::new(&w).file_name().unwrap_or_default();
                    let to = self.out_dir.path().join(name).display().to_string();
                    self.written.insert(w.clone(), to.clone());
                    args.push(to);
                } else {
                    args.push(self.written.get(&w).cloned().unwrap_or_else(|| w.clone()));
                }
                redirect = matches!(
                    w.as_str(),
                    "-o" | "--output" | "--save" | "--heatmap" | "--out"
                );
            }
            // `converge` writes its folder (default ./converge) even without `--out`.
            if args.first().is_some_and(|a| a == "converge") && !args.iter().any(|a| a == "--out") {
                args.push("--out".into());
                args.push(self.out_dir.path().join("converge").display().to_string());
            }
            let start = std::time::Instant::now();
            let out = std::process::Command::new(program)
                .args(&args)
                .current_dir(root())
                .output()
                .map_err(|e| format!("cannot run `{}`: {e}", q.line))?;
            // What each command costs the suite (seen with --nocapture).
            eprintln!("{:.1} s: {}", start.elapsed().as_secs_f64(), q.line);
            let text = String::from_utf8_lossy(&out.stdout).into_owned()
                + &String::from_utf8_lossy(&out.stderr);
            if out.status.success() {
                Ok(text)
            } else {
                Err(format!("`{}` failed ({}):\n{text}", q.line, out.status))
            }
        })();
        self.seen.insert(q.line.clone(), r.clone());
        r
    }
}

/// What is wrong with the numbers `text` (a lesson named `name`) quotes: one line per number
/// that its commands do not print, at the precision quoted. A number's commands run in the
/// order the lesson writes them, until one prints it.
fn stale_numbers(text: &str, name: &str, runner: &mut Runner) -> Vec<String> {
    let mut problems = vec![];
    for c in claims(text) {
        let at = format!("{name}:{}: {}", c.line, c.number.text);
        if c.sources.is_empty() {
            problems.push(format!(
                "{at}: no command it could come from (put the command that prints it in a ```sh \
                 block above it, or in a code span of its paragraph; or mark the paragraph \
                 `<!-- not checked: why -->`)"
            ));
            continue;
        }
        let mut printed = false;
        let mut errors = vec![];
        for q in &c.sources {
            match runner.output(q) {
                Ok(out) => {
                    if numbers_in(&out).iter().any(|p| quotes(&c.number, p.value)) {
                        printed = true;
                        break;
                    }
                }
                Err(e) => errors.push(e),
            }
        }
        if !printed {
            let cmds: Vec<&str> = c.sources.iter().map(|q| q.line.as_str()).collect();
            problems.push(format!(
                "{at}: not printed by {}{}",
                cmds.join(" or "),
                if errors.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", errors.join("; "))
                }
            ));
        }
    }
    problems
}

mod quoted_numbers;
mod shell_blocks;
