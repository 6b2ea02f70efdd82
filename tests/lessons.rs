//! The lessons in `lessons/`: every lesson's front matter parses, its scene loads, its pixel is in
//! the image, the primary ray's closest hit is what the lesson says, the steps it points at exist,
//! every relative link resolves, the lessons are numbered 01..12 and the index links them in
//! order, and together they cover the twelve topics of the course.

use raystep::accel::SceneAccel;
use raystep::lesson::{Lesson, explaining_step, load_lessons, load_sheet, parse_lesson};
use raystep::trace::Tracer;
use std::path::{Path, PathBuf};

/// The number of lessons the course has.
const LESSONS: usize = 12;

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
fn lessons_are_numbered_01_to_12_without_gaps() {
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
        let sheet = load_sheet(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
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
fn the_lessons_cover_the_twelve_topics_in_order() {
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
