//! The lessons in `lessons/`: Markdown files with a TOML front matter that ties each one to a
//! scene, a pixel, the steps worth looking at, settings to set and (optionally) an exercise sheet.
//!
//! ```text
//! +++
//! title = "Ray–sphere: the quadratic"
//! scene = "scenes/three-spheres.toml"   # from the repository root (the lessons folder's parent)
//! pixel = [150, 110]
//! hits = "middle"                       # what the pixel's primary ray hits ("nothing" for a miss)
//! steps = [3, 5, 11]                    # timeline indexes, counted from 0
//! exercises = "exercises/02-sphere.toml"   # optional, from the lessons folder
//! [settings]                            # optional: the scene format's [render] names
//! sphere_method = "textbook"
//! +++
//! # 2. Ray–sphere …
//! ```

use crate::scene::{AccelChoice, BvhQuality, OffsetPolicy, Scene};
use crate::shapes::{SphereMethod, TriangleMethod};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// One lesson.
#[derive(Debug, Clone, PartialEq)]
pub struct Lesson {
    /// The Markdown file.
    pub file: PathBuf,
    /// Its title.
    pub title: String,
    /// The scene, as written (a path from the repository root).
    pub scene: String,
    /// The pixel to click.
    pub pixel: [u32; 2],
    /// What the pixel's primary ray hits.
    pub hits: String,
    /// The steps worth looking at (timeline indexes from 0, increasing).
    pub steps: Vec<usize>,
    /// The settings to set before looking.
    pub settings: LessonSettings,
    /// The exercise sheet, as written (a path from the lessons folder).
    pub exercises: Option<String>,
    /// The Markdown after the front matter, without its HTML comments (notes for the tests).
    pub body: String,
}

/// A lesson's `[settings]`: overrides with the scene format's `[render]` names and spellings.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LessonSettings {
    /// Recursion limit (0–64).
    pub max_depth: Option<u32>,
    /// Samples per pixel (1–65536).
    pub spp: Option<u32>,
    /// Background colour (linear RGB).
    pub background: Option<[f32; 3]>,
    /// Ray–sphere method.
    pub sphere_method: Option<SphereMethod>,
    /// Ray–triangle method.
    pub triangle_method: Option<TriangleMethod>,
    /// Offset policy for spawned rays.
    pub offset: Option<OffsetPolicy>,
    /// The fixed offset's distance (positive).
    pub epsilon: Option<f32>,
    /// Acceleration structure.
    pub accel: Option<AccelChoice>,
    /// The BVH's build quality.
    pub bvh_quality: Option<BvhQuality>,
    /// Jitter seed.
    pub seed: Option<u32>,
    /// The light transport (`whitted`, `distribution`, `path`).
    pub integrator: Option<crate::scene::Integrator>,
    /// The path tracer's estimator for direct light (`mis`, `light`, `bsdf`).
    pub strategy: Option<crate::scene::Strategy>,
    /// The Monte Carlo integrators' 2D samples (`independent`, `stratified`).
    pub sampler: Option<crate::scene::SamplerKind>,
    /// Where rays leave smooth triangles (`none`, `hanika`).
    pub terminator: Option<crate::scene::Terminator>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FrontMatter {
    title: String,
    scene: String,
    pixel: [u32; 2],
    hits: String,
    steps: Vec<usize>,
    exercises: Option<String>,
    #[serde(default)]
    settings: LessonSettings,
}

impl LessonSettings {
    /// Applies the overrides to `scene`'s settings; out-of-range values are an error naming the
    /// field.
    pub fn apply(&self, scene: &mut Scene) -> Result<(), String> {
        let s = &mut scene.settings;
        if let Some(v) = self.max_depth {
            if v > 64 {
                return Err(format!("settings.max_depth must be 0–64, got {v}"));
            }
            s.max_depth = v;
        }
        if let Some(v) = self.spp {
            if !(1..=65536).contains(&v) {
                return Err(format!("settings.spp must be 1–65536, got {v}"));
            }
            s.spp = v;
        }
        if let Some(v) = self.background {
            if v.iter().any(|c| !c.is_finite() || *c < 0.0) {
                return Err(format!(
                    "settings.background must be three finite non-negative numbers, got {v:?}"
                ));
            }
            s.background = glam::Vec3::from(v);
        }
        if let Some(v) = self.sphere_method {
            s.sphere_method = v;
        }
        if let Some(v) = self.triangle_method {
            s.triangle_method = v;
        }
        if let Some(v) = self.offset {
            s.offset = v;
        }
        if let Some(v) = self.epsilon {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("settings.epsilon must be positive, got {v}"));
            }
            s.epsilon = v;
        }
        if let Some(v) = self.accel {
            s.accel = v;
        }
        if let Some(v) = self.integrator {
            s.integrator = v;
        }
        if let Some(v) = self.strategy {
            if v != crate::scene::Strategy::Mis && s.integrator != crate::scene::Integrator::Path {
                return Err(format!(
                    "settings.strategy = {}: a strategy applies to the path integrator (set integrator to path too)",
                    clap::ValueEnum::to_possible_value(&v)
                        .map_or_else(String::new, |p| p.get_name().to_string())
                ));
            }
            s.strategy = v;
        }
        if let Some(v) = self.sampler {
            s.sampler = v;
        }
        if let Some(v) = self.terminator {
            s.terminator = v;
        }
        if let Some(v) = self.bvh_quality {
            s.bvh_quality = v;
        }
        if let Some(v) = self.seed {
            s.seed = v;
        }
        Ok(())
    }

    /// Whether nothing is overridden.
    pub fn is_empty(&self) -> bool {
        *self == LessonSettings::default()
    }
}

/// Parses a lesson's text; `file` names it in errors (`file:line:column: …`).
pub fn parse_lesson(text: &str, file: &Path) -> Result<Lesson, String> {
    let name = file.display();
    let text = text.replace("\r\n", "\n");
    let rest = text
        .strip_prefix("+++\n")
        .ok_or_else(|| format!("{name}:1:1: a lesson starts with a `+++` line (front matter)"))?;
    let end = rest
        .find("\n+++\n")
        .or_else(|| rest.ends_with("\n+++").then(|| rest.len() - 4))
        .ok_or_else(|| format!("{name}: the front matter has no closing `+++` line"))?;
    let (fm, body) = (&rest[..=end], rest.get(end + 5..).unwrap_or(""));
    let parsed: FrontMatter = toml::from_str(fm).map_err(|e| {
        let (line, col) = e
            .span()
            .map(|s| crate::text::line_col(fm, s.start))
            .unwrap_or((0, 0));
        // +1: the opening `+++` line.
        format!("{name}:{}:{col}: {}", line + 1, e.message())
    })?;
    if parsed.steps.windows(2).any(|w| w[0] >= w[1]) {
        return Err(format!(
            "{name}: steps should be increasing, got {:?}",
            parsed.steps
        ));
    }
    Ok(Lesson {
        file: file.to_path_buf(),
        title: parsed.title,
        scene: parsed.scene,
        pixel: parsed.pixel,
        hits: parsed.hits,
        steps: parsed.steps,
        settings: parsed.settings,
        exercises: parsed.exercises,
        body: without_comments(body),
    })
}

/// `body` without its HTML comments (`<!-- not checked: … -->`, the lessons' notes for
/// `tests/it/lessons/`), which a Markdown viewer that does not render HTML would show as text; a
/// line that held only a comment goes with it.
fn without_comments(body: &str) -> String {
    let mut out = String::with_capacity(body.len());
    let mut rest = body;
    while let Some(start) = rest.find("<!--") {
        let Some(len) = rest[start..].find("-->") else {
            break;
        };
        let end = start + len + 3;
        let before = &rest[..start];
        let line_start = before.rfind('\n').map_or(0, |k| k + 1);
        let alone = before[line_start..].trim().is_empty()
            && rest[end..]
                .split('\n')
                .next()
                .is_some_and(|l| l.trim().is_empty());
        if alone {
            // Drop the whole line, its newline included.
            out.push_str(&before[..line_start]);
            rest = rest[end..].split_once('\n').map_or("", |(_, after)| after);
        } else {
            out.push_str(before.trim_end_matches(' '));
            rest = &rest[end..];
        }
    }
    out.push_str(rest);
    out
}

/// Every lesson in `dir` (each `*.md` but README.md), sorted by file name.
pub fn load_lessons(dir: &Path) -> Result<Vec<Lesson>, String> {
    let entries = crate::platform::files::list(dir)
        .map_err(|e| format!("{}: cannot list: {e}", dir.display()))?;
    let mut files: Vec<PathBuf> = entries
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .filter(|p| p.file_name().is_some_and(|n| n != "README.md"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| {
            let text = crate::io::read_text(p, crate::io::limits::LESSON, "lesson")
                .map_err(|e| format!("{}: cannot read: {e}", p.display()))?;
            parse_lesson(&text, p)
        })
        .collect()
}

/// The lessons folder: the lessons built into raystep (unpacked into a folder on first use),
/// so the app has them from any working directory.
pub fn lessons_dir() -> Result<PathBuf, String> {
    crate::assets::unpacked().map(|root| root.join("lessons"))
}

impl Lesson {
    /// The lessons folder this lesson is in.
    pub fn dir(&self) -> &Path {
        self.file.parent().unwrap_or(Path::new("."))
    }

    /// The scene file (the lessons folder's parent is the repository root).
    pub fn scene_path(&self) -> PathBuf {
        let dir = self.dir();
        dir.parent().unwrap_or(dir).join(&self.scene)
    }

    /// The exercise sheet's file, if the lesson has one.
    pub fn exercises_path(&self) -> Option<PathBuf> {
        self.exercises.as_ref().map(|e| self.dir().join(e))
    }

    /// Loads the lesson's scene with its settings applied.
    pub fn load_scene(&self) -> Result<Scene, String> {
        let path = self.scene_path();
        let mut scene = crate::scene::load_file(&path).map_err(|e| e.to_string())?;
        self.settings
            .apply(&mut scene)
            .map_err(|e| format!("{}: {e}", self.file.display()))?;
        Ok(scene)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_front_matter_error_names_the_line() {
        let text = "+++\ntitle = \"x\"\nscene = 3\n+++\nbody";
        let e = parse_lesson(text, Path::new("l.md")).unwrap_err();
        assert!(e.starts_with("l.md:3:"), "{e}");
        assert!(e.contains("scene") || e.contains("string"), "{e}");
    }

    #[test]
    fn the_body_follows_the_front_matter() {
        let text = "+++\ntitle = \"T\"\nscene = \"scenes/a.toml\"\npixel = [1, 2]\nhits = \"ball\"\nsteps = [0, 4]\nexercises = \"exercises/a.toml\"\n[settings]\nspp = 4\n+++\n# Body\n";
        let l = parse_lesson(text, Path::new("/r/lessons/01-a.md")).unwrap();
        assert_eq!(l.body, "# Body\n");
        assert_eq!(l.pixel, [1, 2]);
        assert_eq!(l.settings.spp, Some(4));
        assert_eq!(l.scene_path(), Path::new("/r/scenes/a.toml"));
        assert_eq!(
            l.exercises_path().unwrap(),
            Path::new("/r/lessons/exercises/a.toml")
        );
    }

    #[test]
    fn the_body_leaves_out_html_comments() {
        let text = "+++\ntitle = \"T\"\nscene = \"scenes/a.toml\"\npixel = [1, 2]\nhits = \"ball\"\nsteps = [0]\n+++\nA 0.5 by hand. <!-- not checked: by hand -->\nB\n<!-- a note\non two lines -->\nC\n";
        let l = parse_lesson(text, Path::new("l.md")).unwrap();
        assert_eq!(l.body, "A 0.5 by hand.\nB\nC\n");
        // An unclosed comment is left as it is.
        assert_eq!(without_comments("a <!-- b"), "a <!-- b");
    }

    #[test]
    fn settings_out_of_range_are_refused() {
        let mut scene = crate::scene::default_scene();
        let s = LessonSettings {
            spp: Some(0),
            ..Default::default()
        };
        assert!(s.apply(&mut scene).unwrap_err().contains("spp"));
    }
}
