//! If the app panics after all, the user loses nothing and learns where to look: a panic hook
//! (installed when the window opens) saves the user's place — preferences with the student id,
//! the open file, the selected pixel and step — and writes a short crash report, both in the
//! app's state folder ([`state_dir`]). The next start takes the saved place back, validated like
//! any remembered preferences, and renames the file so that a place that crashes again cannot
//! start a crash loop.

use super::state::{AppState, Prefs};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The user's place, as the panic hook saves it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(default)]
pub struct Place {
    /// The preferences (student id included).
    pub prefs: Prefs,
    /// The open file (absolute), if a file was open.
    pub file: Option<PathBuf>,
    /// The selected pixel.
    pub pixel: Option<[u32; 2]>,
    /// The step shown.
    pub step: usize,
}

impl Place {
    /// The place `state` shows.
    pub fn of(state: &AppState) -> Place {
        Place {
            prefs: state.prefs.clone(),
            file: state
                .path()
                .map(|p| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf())),
            pixel: state.pixel,
            step: state.step,
        }
    }
}

/// The place the hook saves: updated by the app every frame.
static LATEST: Mutex<Option<Place>> = Mutex::new(None);

/// The file the place is saved to.
pub const STATE_FILE: &str = "crash-state.json";
/// The crash report.
pub const REPORT_FILE: &str = "crash-report.txt";
/// What [`recover`] renames the saved place to once it has been taken back.
pub const RECOVERED_FILE: &str = "crash-state.recovered.json";

/// Where raystep keeps its crash state and report: `$RAYSTEP_STATE_DIR`, else
/// `$XDG_STATE_HOME/raystep`, else `~/.local/state/raystep`, else eframe's storage folder.
pub fn state_dir() -> Option<PathBuf> {
    let abs = |v: std::ffi::OsString| Some(PathBuf::from(v)).filter(|p| p.is_absolute());
    if let Some(d) = std::env::var_os("RAYSTEP_STATE_DIR").and_then(abs) {
        return Some(d);
    }
    if let Some(d) = std::env::var_os("XDG_STATE_HOME").and_then(abs) {
        return Some(d.join("raystep"));
    }
    if let Some(h) = std::env::home_dir().filter(|h| h.is_absolute()) {
        return Some(h.join(".local").join("state").join("raystep"));
    }
    #[cfg(not(target_arch = "wasm32"))]
    return eframe::storage_dir("raystep");
    #[cfg(target_arch = "wasm32")]
    None
}

/// Remembers the place to save if the app panics (called once per frame).
pub fn remember(state: &AppState) {
    let place = Place::of(state);
    if let Ok(mut l) = LATEST.try_lock()
        && l.as_ref() != Some(&place)
    {
        *l = Some(place);
    }
}

/// Installs the panic hook: the previous hook still prints the panic; then, for a panic on the
/// UI thread, the place is saved and the report written into `dir`.
pub fn install(dir: PathBuf) {
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        previous(info);
        let thread = std::thread::current();
        let thread_name = thread.name().unwrap_or("unnamed").to_string();
        let message = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "(no message)".into());
        let location = info
            .location()
            .map(|l| format!("{}:{}:{}", l.file(), l.line(), l.column()))
            .unwrap_or_default();
        // try_lock: a panic while the app held the lock must not deadlock the hook.
        let place = if thread_name == "main" {
            LATEST.try_lock().ok().and_then(|l| l.clone())
        } else {
            None
        };
        match write_crash(&dir, &thread_name, &message, &location, place.as_ref()) {
            Ok(report) => eprintln!(
                "raystep stopped on an error{}. The report is in {}",
                if place.is_some() {
                    "; your place (preferences, student id, file, pixel, step) was saved and \
                     the next start takes it back"
                } else {
                    ""
                },
                report.display(),
            ),
            Err(e) => eprintln!("raystep could not write its crash report: {e}"),
        }
    }));
}

/// Writes the crash report (and the place, if any) into `dir`; returns the report's path.
pub fn write_crash(
    dir: &Path,
    thread: &str,
    message: &str,
    location: &str,
    place: Option<&Place>,
) -> Result<PathBuf, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    if let Some(p) = place {
        let json = serde_json::to_string_pretty(p).map_err(|e| e.to_string())?;
        crate::io::write_atomic(&dir.join(STATE_FILE), json.as_bytes())?;
    }
    let when = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let place_line = match place {
        Some(p) => format!(
            "open file: {}\npixel: {:?}\nstep: {}\nsaved place: {}\n",
            p.file
                .as_ref()
                .map_or("(built-in scene)".into(), |f| f.display().to_string()),
            p.pixel,
            p.step,
            dir.join(STATE_FILE).display()
        ),
        None => String::new(),
    };
    let report = format!(
        "raystep {} stopped on an error\ntime: {when} (seconds since 1970)\nthread: {thread}\n\
         where: {location}\nmessage: {message}\n{place_line}",
        env!("CARGO_PKG_VERSION"),
    );
    let path = dir.join(REPORT_FILE);
    crate::io::write_atomic(&path, report.as_bytes())?;
    Ok(path)
}

/// Takes back the place a crash saved in `dir` (validated), renaming the file so that it is
/// taken back once only. A file that does not parse is renamed too and ignored.
pub fn recover(dir: &Path) -> Option<Place> {
    let path = dir.join(STATE_FILE);
    let text = std::fs::read_to_string(&path).ok()?;
    let _ = std::fs::rename(&path, dir.join(RECOVERED_FILE));
    let mut place: Place = serde_json::from_str(&text).ok()?;
    place.prefs = place.prefs.validated();
    place.file = place.file.filter(|f| f.is_absolute() && f.is_file());
    Some(place)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_saved_place_is_taken_back_once_and_validated() {
        let dir = tempfile::tempdir().unwrap();
        let scene = std::path::absolute(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../scenes/cornell.toml"
        ))
        .unwrap();
        let mut prefs = Prefs {
            student: "ada".into(),
            scale: 99.0,
            ..Prefs::default()
        };
        prefs.layout.tree = 7.0;
        let place = Place {
            prefs,
            file: Some(scene.clone()),
            pixel: Some([3, 4]),
            step: 12,
        };
        let report = write_crash(dir.path(), "main", "boom", "x.rs:1:2", Some(&place)).unwrap();
        let text = std::fs::read_to_string(&report).unwrap();
        assert!(text.contains("message: boom") && text.contains("where: x.rs:1:2"));
        assert!(text.contains("step: 12"));
        let back = recover(dir.path()).expect("the place comes back");
        assert_eq!(back.prefs.student, "ada");
        assert_eq!(back.prefs.scale, 3.0, "a scale out of range is clamped");
        assert_eq!(back.prefs.layout.tree, Prefs::default().layout.tree);
        assert_eq!(back.file, Some(scene));
        assert_eq!((back.pixel, back.step), (Some([3, 4]), 12));
        assert!(recover(dir.path()).is_none(), "only once: no crash loop");
        assert!(dir.path().join(RECOVERED_FILE).is_file());
    }

    #[test]
    fn a_damaged_saved_place_is_ignored() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join(STATE_FILE), "{ not json").unwrap();
        assert!(recover(dir.path()).is_none());
        assert!(!dir.path().join(STATE_FILE).exists());
    }
}
