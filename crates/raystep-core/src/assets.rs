//! The scenes, lessons and exercise sheets that ship with raystep, **built into the binary**, so a
//! `cargo install`ed raystep has them from any folder.
//!
//! Every file of `scenes/`, `lessons/`, `lessons/exercises/` and `lessons/starter/` (the student
//! tracer's starter kit) is compiled in with
//! `include_bytes!` (a test checks the list below against the folders, so a new file cannot be
//! forgotten). The tracer, the lessons and the sheets refer to one another by relative paths (a
//! lesson's scene from the repository root, a sheet's scene from the sheet, a scene's OBJ from the
//! scene), so the built-in copies are unpacked once into a cache folder named after the build's
//! content hash ([`unpacked`]) and everything is read from there: the app's *Shipped scenes* and
//! Lessons panel, `raystep render cornell` and the other commands that take a built-in scene by
//! name. The cache is rewritten from the binary whenever a file there differs, so editing it
//! changes nothing; `raystep examples --write DIR` writes a copy to edit.

// Finding built-in files by name and writing them out serve the command line, which the browser
// build leaves out.
#![cfg_attr(target_arch = "wasm32", allow(dead_code))]

use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// One built-in file: its path from the repository root and its bytes.
#[derive(Debug, Clone, Copy)]
pub struct Asset {
    /// The path from the repository root, with `/` separators (`scenes/cornell.toml`).
    pub path: &'static str,
    /// The file's contents.
    pub bytes: &'static [u8],
}

macro_rules! assets {
    ($($p:literal),* $(,)?) => {
        &[$(Asset { path: $p, bytes: include_bytes!(concat!(env!("CARGO_MANIFEST_DIR"), "/../../", $p)) }),*]
    };
}

/// Every built-in file, scenes first.
pub static ASSETS: &[Asset] = assets!(
    "scenes/acne.toml",
    "scenes/cornell-area.toml",
    "scenes/cornell.toml",
    "scenes/depth-of-field.toml",
    "scenes/far-sphere.toml",
    "scenes/first-sphere.toml",
    "scenes/gltf-table.toml",
    "scenes/gltf/table.bin",
    "scenes/gltf/table.gltf",
    "scenes/icosahedron.obj",
    "scenes/instances.toml",
    "scenes/leaky-edge.toml",
    "scenes/low-poly-sphere.obj",
    "scenes/mipmap.toml",
    "scenes/mirror-glass.toml",
    "scenes/smooth-shading.toml",
    "scenes/soft-shadows.toml",
    "scenes/teapot-stadium.toml",
    "scenes/textures.toml",
    "scenes/textures/checks-64x64.png",
    "scenes/textures/globe-64x32.png",
    "scenes/textures/tiles-8x8.png",
    "scenes/three-spheres.toml",
    "scenes/triangles.toml",
    "scenes/veach-mis.toml",
    "lessons/README.md",
    "lessons/01-rays-and-the-camera.md",
    "lessons/02-ray-sphere.md",
    "lessons/03-ray-plane.md",
    "lessons/04-ray-triangle.md",
    "lessons/05-the-naive-loop.md",
    "lessons/06-bounding-boxes-and-the-bvh.md",
    "lessons/07-shadows.md",
    "lessons/08-reflection.md",
    "lessons/09-refraction-and-tir.md",
    "lessons/10-antialiasing.md",
    "lessons/11-ray-tracing-on-the-gpu.md",
    "lessons/12-numerical-robustness.md",
    "lessons/13-monte-carlo-integration.md",
    "lessons/14-area-lights-and-soft-shadows.md",
    "lessons/15-path-tracing.md",
    "lessons/16-multiple-importance-sampling.md",
    "lessons/17-smooth-shading.md",
    "lessons/18-textures.md",
    "lessons/19-mipmap.md",
    "lessons/20-instances.md",
    "lessons/starter/README.md",
    "lessons/starter/sheet.toml",
    "lessons/starter/path-sheet.toml",
    "lessons/starter/tracer.py",
    "lessons/exercises/01-camera.toml",
    "lessons/exercises/02-sphere.toml",
    "lessons/exercises/03-plane.toml",
    "lessons/exercises/04-triangle.toml",
    "lessons/exercises/05-naive-loop.toml",
    "lessons/exercises/06-bvh.toml",
    "lessons/exercises/07-shadows.toml",
    "lessons/exercises/08-reflection.toml",
    "lessons/exercises/09-refraction.toml",
    "lessons/exercises/10-antialiasing.toml",
    "lessons/exercises/11-gpu.toml",
    "lessons/exercises/12-robustness.toml",
    "lessons/exercises/13-monte-carlo.toml",
    "lessons/exercises/14-area-lights.toml",
    "lessons/exercises/15-path-tracing.toml",
    "lessons/exercises/16-mis.toml",
    "lessons/exercises/17-smooth-shading.toml",
    "lessons/exercises/18-textures.toml",
    "lessons/exercises/19-mipmap.toml",
    "lessons/exercises/20-instances.toml",
);

/// The names of the built-in scenes (`cornell`, `three-spheres`, …), sorted.
pub fn scene_names() -> Vec<&'static str> {
    ASSETS
        .iter()
        .filter_map(|a| a.path.strip_prefix("scenes/")?.strip_suffix(".toml"))
        .collect()
}

/// The built-in scene called `name` (`cornell`, `cornell.toml` or `scenes/cornell.toml`).
pub fn builtin_scene(name: &str) -> Option<&'static Asset> {
    let stem = name.strip_prefix("scenes/").unwrap_or(name);
    let stem = stem.strip_suffix(".toml").unwrap_or(stem);
    ASSETS.iter().find(|a| {
        a.path
            .strip_prefix("scenes/")
            .and_then(|p| p.strip_suffix(".toml"))
            == Some(stem)
    })
}

/// The names of the built-in exercise sheets (`01-camera`, `02-sphere`, …), sorted.
pub fn sheet_names() -> Vec<&'static str> {
    ASSETS
        .iter()
        .filter_map(|a| {
            a.path
                .strip_prefix("lessons/exercises/")?
                .strip_suffix(".toml")
        })
        .collect()
}

/// The built-in exercise sheet called `name`: `02-sphere`, `02-sphere.toml`,
/// `exercises/02-sphere.toml` or `lessons/exercises/02-sphere.toml`.
pub fn builtin_sheet(name: &str) -> Option<&'static Asset> {
    let stem = name.strip_prefix("lessons/").unwrap_or(name);
    let stem = stem.strip_prefix("exercises/").unwrap_or(stem);
    let stem = stem.strip_suffix(".toml").unwrap_or(stem);
    ASSETS.iter().find(|a| {
        a.path
            .strip_prefix("lessons/exercises/")
            .and_then(|p| p.strip_suffix(".toml"))
            == Some(stem)
    })
}

/// A short hash of every built-in file (names the cache folder, so two builds never share one).
fn content_hash() -> String {
    let mut h = Sha256::new();
    for a in ASSETS {
        h.update(a.path.as_bytes());
        h.update([0]);
        h.update((a.bytes.len() as u64).to_le_bytes());
        h.update(a.bytes);
    }
    h.finalize()
        .iter()
        .take(6)
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Writes every built-in file under `root` (keeping its relative path), skipping files whose
/// contents are already right.
fn unpack_into(root: &Path) -> Result<(), String> {
    for a in ASSETS {
        let path = root.join(a.path);
        if crate::platform::files::read(&path).is_ok_and(|b| b == a.bytes) {
            continue;
        }
        crate::platform::files::write(&path, a.bytes)?;
    }
    Ok(())
}

/// The folder holding the built-in files (`scenes/`, `lessons/`, `lessons/exercises/`), unpacked
/// on first use into the user's cache folder (else the temporary folder). The folder's name holds
/// the version and a hash of the contents.
pub fn unpacked() -> Result<&'static Path, String> {
    static ROOT: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    ROOT.get_or_init(|| {
        let name = format!("builtin-{}-{}", env!("CARGO_PKG_VERSION"), content_hash());
        let first = crate::platform::files::cache_base().join(&name);
        match unpack_into(&first) {
            Ok(()) => Ok(first),
            Err(e1) => {
                let second = std::env::temp_dir().join("raystep").join(&name);
                unpack_into(&second).map(|()| second).map_err(|e2| {
                    format!("cannot unpack the built-in scenes and lessons: {e1}; {e2}")
                })
            }
        }
    })
    .as_ref()
    .map(PathBuf::as_path)
    .map_err(Clone::clone)
}

/// The unpacked copy of the built-in scene `name`, if there is one.
pub fn builtin_scene_path(name: &str) -> Result<Option<PathBuf>, String> {
    match builtin_scene(name) {
        Some(a) => Ok(Some(unpacked()?.join(a.path))),
        None => Ok(None),
    }
}

/// A path as the app shows it: a built-in file as `scenes/cornell.toml (built in)` (its unpacked
/// copy's folder names the user's cache and the build, which say nothing), any other in full.
pub fn shown_path(p: &Path) -> String {
    let builtin = unpacked()
        .ok()
        .and_then(|root| p.strip_prefix(root).ok())
        .map(|rel| format!("{} (built in)", rel.display()));
    builtin.unwrap_or_else(|| p.display().to_string())
}

/// A scene path as a command to type should name it: a built-in scene's unpacked copy by the
/// scene's name (`three-spheres`, which every command that takes a scene accepts), so the
/// command works on any machine; any other absolute path without its `..`s.
pub fn scene_argument(p: &Path) -> String {
    // A sheet names its scene relative to itself (`lessons/exercises/../../scenes/…`): resolve
    // the `..` by the names alone (the unpacked folder has no links).
    let mut lexical = PathBuf::new();
    for c in p.components() {
        match c {
            std::path::Component::ParentDir => {
                lexical.pop();
            }
            std::path::Component::CurDir => {}
            c => lexical.push(c),
        }
    }
    let name = unpacked()
        .ok()
        .and_then(|root| lexical.strip_prefix(root).ok())
        .and_then(|rel| rel.strip_prefix("scenes").ok())
        .and_then(|f| f.to_str()?.strip_suffix(".toml"))
        .filter(|n| builtin_scene(n).is_some());
    match name {
        Some(n) => n.to_string(),
        // An absolute path without its `..` (a sheet's scene) when that is the same file (a
        // link before a `..` would make it another); a relative one as given.
        None if p.is_absolute()
            && std::fs::canonicalize(&lexical).ok() == std::fs::canonicalize(p).ok() =>
        {
            lexical.display().to_string()
        }
        None => p.display().to_string(),
    }
}

/// The built-in scenes' files (unpacked), sorted by name.
pub fn builtin_scene_paths() -> Result<Vec<PathBuf>, String> {
    let root = unpacked()?;
    Ok(scene_names()
        .into_iter()
        .map(|n| root.join("scenes").join(format!("{n}.toml")))
        .collect())
}

/// What a command-line scene argument names: the file if it exists, else the built-in scene of
/// that name (`cornell`), else the file (whose loading then reports that it does not exist).
pub fn resolve_scene(arg: &Path) -> Result<PathBuf, String> {
    if arg.exists() {
        return Ok(arg.to_path_buf());
    }
    match arg.to_str().map(builtin_scene_path) {
        Some(Ok(Some(p))) => Ok(p),
        Some(Err(e)) => Err(e),
        _ => Ok(arg.to_path_buf()),
    }
}

/// What a command-line exercise sheet argument names: the file if it exists, else the built-in
/// sheet of that name (`02-sphere`), else the file (whose loading then reports that it does not
/// exist) — as [`resolve_scene`] does for scenes.
pub fn resolve_sheet(arg: &Path) -> Result<PathBuf, String> {
    if arg.exists() {
        return Ok(arg.to_path_buf());
    }
    match arg.to_str().and_then(builtin_sheet) {
        Some(a) => Ok(unpacked()?.join(a.path)),
        None => Ok(arg.to_path_buf()),
    }
}

/// Loads a scene named on the command line: a file, or a built-in scene by name (see
/// [`resolve_scene`]). A missing file's error lists the built-in names.
pub fn load_scene(arg: &Path) -> Result<crate::scene::Scene, String> {
    let path = resolve_scene(arg)?;
    let scene = crate::scene::load_file(&path).map_err(|e| {
        if path.exists() {
            e.to_string()
        } else {
            format!("{e} (built-in scenes: {})", scene_names().join(", "))
        }
    })?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    Ok(scene)
}

/// Writes every built-in file under `dir` (`dir/scenes/…`, `dir/lessons/…`), each atomically.
/// Refuses, before writing anything, when a file would be replaced and `force` is off. Returns the
/// absolute paths written.
pub fn write_examples(dir: &Path, force: bool) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("{}: cannot create the folder: {e}", dir.display()))?;
    let dir = std::fs::canonicalize(dir)
        .map_err(|e| format!("{}: cannot open the folder: {e}", dir.display()))?;
    let targets: Vec<(PathBuf, &Asset)> = ASSETS.iter().map(|a| (dir.join(a.path), a)).collect();
    // Every target is checked before anything is written: a FIFO would make the write wait for
    // a reader forever, and a device or a folder cannot hold the file, --force or not.
    let wrong: Vec<String> = targets
        .iter()
        .filter_map(|(p, _)| not_writable_here(&dir, p))
        .collect();
    if let Some(first) = wrong.first() {
        return Err(format!(
            "{first}{}; nothing was written — remove {}, or write to another folder",
            if wrong.len() > 1 {
                format!(
                    " ({} of the {} files are not regular files)",
                    wrong.len(),
                    targets.len()
                )
            } else {
                String::new()
            },
            if wrong.len() > 1 { "them" } else { "it" },
        ));
    }
    if !force {
        let existing: Vec<String> = targets
            .iter()
            .filter(|(p, _)| p.exists())
            .map(|(p, _)| p.display().to_string())
            .collect();
        if let Some(first) = existing.first() {
            return Err(format!(
                "{first}: already exists ({} of the {} files do); nothing was written — pass \
                 --force to replace them",
                existing.len(),
                targets.len()
            ));
        }
    }
    let mut written = vec![];
    for (path, a) in targets {
        if let Some(d) = path.parent() {
            std::fs::create_dir_all(d)
                .map_err(|e| format!("{}: cannot create the folder: {e}", d.display()))?;
        }
        crate::io::write_atomic(&path, a.bytes)?;
        written.push(path);
    }
    Ok(written)
}

/// Why `path` (a target under `dir`) cannot be written as a regular file, if it cannot: it is
/// something other than a regular file (after following symbolic links), or a folder on the
/// way to it is not a folder.
fn not_writable_here(dir: &Path, path: &Path) -> Option<String> {
    let on_the_way = path
        .ancestors()
        .skip(1)
        .take_while(|a| a.starts_with(dir) && *a != dir);
    for a in on_the_way {
        if let Ok(m) = std::fs::metadata(a)
            && !m.is_dir()
        {
            return Some(format!(
                "{}: is {}, not a folder: raystep examples cannot write {} there",
                a.display(),
                if m.is_file() {
                    "a file"
                } else {
                    crate::io::kind_of(&m.file_type())
                },
                path.display()
            ));
        }
    }
    match std::fs::metadata(path) {
        Ok(m) if !m.is_file() => Some(format!(
            "{}: is {}, not a regular file: raystep examples writes only regular files",
            path.display(),
            crate::io::kind_of(&m.file_type())
        )),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_file_of_the_shipped_folders_is_built_in() {
        let root = &Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let mut on_disk = vec![];
        for sub in [
            "scenes",
            "scenes/gltf",
            "scenes/textures",
            "lessons",
            "lessons/exercises",
            "lessons/starter",
        ] {
            for e in std::fs::read_dir(root.join(sub)).unwrap() {
                let p = e.unwrap().path();
                if p.is_file() {
                    on_disk.push(format!(
                        "{sub}/{}",
                        p.file_name().unwrap().to_string_lossy()
                    ));
                }
            }
        }
        on_disk.sort();
        let mut built_in: Vec<String> = ASSETS.iter().map(|a| a.path.to_string()).collect();
        built_in.sort();
        assert_eq!(built_in, on_disk);
    }

    #[test]
    fn the_unpacked_copy_is_the_built_in_bytes() {
        let root = unpacked().unwrap();
        for a in ASSETS {
            assert_eq!(
                std::fs::read(root.join(a.path)).unwrap(),
                a.bytes,
                "{}",
                a.path
            );
        }
        // A built-in scene with an OBJ loads from there (the OBJ beside it).
        let scene = load_scene(Path::new("triangles")).unwrap();
        assert_eq!(scene.objects.len(), 25);
    }

    #[test]
    fn names_resolve_with_or_without_the_folder_and_extension() {
        for n in ["cornell", "cornell.toml", "scenes/cornell.toml"] {
            assert_eq!(
                builtin_scene(n).map(|a| a.path),
                Some("scenes/cornell.toml")
            );
        }
        assert!(builtin_scene("icosahedron").is_none());
        assert!(builtin_scene("nope").is_none());
        assert!(scene_names().contains(&"three-spheres"));
        assert!(!scene_names().contains(&"icosahedron"));
    }

    #[test]
    fn sheet_names_resolve_like_scene_names() {
        for n in [
            "02-sphere",
            "02-sphere.toml",
            "exercises/02-sphere.toml",
            "lessons/exercises/02-sphere.toml",
        ] {
            assert_eq!(
                builtin_sheet(n).map(|a| a.path),
                Some("lessons/exercises/02-sphere.toml"),
                "{n}"
            );
        }
        // A scene is not a sheet, nor is the starter kit's grading sheet.
        assert!(builtin_sheet("cornell").is_none());
        assert!(builtin_sheet("sheet").is_none());
        assert_eq!(sheet_names().len(), 20);
        assert_eq!(sheet_names()[0], "01-camera");
        // An existing file of that name wins over the built-in sheet.
        let dir = std::env::temp_dir().join(format!("raystep-sheet-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let own = dir.join("02-sphere");
        std::fs::write(&own, "").unwrap();
        assert_eq!(resolve_sheet(&own).unwrap(), own);
        std::fs::remove_dir_all(&dir).unwrap();
        let p = resolve_sheet(Path::new("02-sphere")).unwrap();
        assert_eq!(
            std::fs::read(&p).unwrap(),
            builtin_sheet("02-sphere").unwrap().bytes
        );
    }
}
