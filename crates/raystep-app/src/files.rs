//! File → Open: a small file browser in egui — a path field, the folder it names (sub-folders,
//! `.toml` scenes and `.json` traces), the parent folder, the scenes built into raystep and the
//! recent files.
//!
//! Written here rather than taken from a crate: the pure-egui file dialog crate
//! (`egui-file-dialog`, newest release 0.15) is built for egui 0.36 and cannot be used with the
//! egui 0.37 this app uses, and a native dialog (`rfd`) needs GTK or a desktop portal, which a
//! classroom machine or a container often lacks. It only lists folders: every error (a folder that
//! cannot be read) is shown in the dialog, and nothing here can panic on what the disk holds.

use super::state::{AppState, Command, Dialog};
use std::path::{Path, PathBuf};

/// At most this many entries of one folder are listed (a folder of a million files would make
/// every frame slow); the dialog says when some were left out.
const MAX_ENTRIES: usize = 2000;

/// One entry of the listed folder.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct Entry {
    /// Folders sort first.
    pub is_dir: bool,
    /// The entry's name.
    pub name: String,
    /// Its full path.
    pub path: PathBuf,
}

/// A folder's listing: folders and the files raystep opens (`.toml`, `.json`), folders first, each
/// group sorted by name; hidden entries (a leading `.`) left out. Returns the entries and whether
/// the folder had more than 2,000 entries (`MAX_ENTRIES`).
pub fn list_folder(dir: &Path) -> Result<(Vec<Entry>, bool), String> {
    let rd = std::fs::read_dir(dir).map_err(|e| format!("{}: cannot list: {e}", dir.display()))?;
    let mut out = vec![];
    let mut more = false;
    for e in rd.flatten() {
        if out.len() >= MAX_ENTRIES {
            more = true;
            break;
        }
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') {
            continue;
        }
        let path = e.path();
        // Follows symbolic links, so a link to a folder is a folder.
        let is_dir = path.is_dir();
        let wanted = path.extension().and_then(|x| x.to_str()).is_some_and(|x| {
            ["toml", "json", "gltf", "glb"]
                .iter()
                .any(|k| x.eq_ignore_ascii_case(k))
        });
        if is_dir || wanted {
            out.push(Entry { is_dir, name, path });
        }
    }
    // Folders first (`true` sorts after `false`, hence the reversed key).
    out.sort_by(|a, b| b.is_dir.cmp(&a.is_dir).then_with(|| a.name.cmp(&b.name)));
    Ok((out, more))
}

/// The folder a typed path shows: the path itself if it is a folder, else its parent, else the
/// working directory (made absolute so the dialog always says where it is).
pub fn folder_of(typed: &str) -> PathBuf {
    let p = Path::new(typed.trim());
    let dir = if typed.trim().is_empty() {
        PathBuf::from(".")
    } else if p.is_dir() {
        p.to_path_buf()
    } else {
        match p.parent() {
            Some(d) if !d.as_os_str().is_empty() && d.is_dir() => d.to_path_buf(),
            _ => PathBuf::from("."),
        }
    };
    std::fs::canonicalize(&dir).unwrap_or(dir)
}

/// The path typed for a folder (with a trailing separator, so the field shows it is a folder).
fn typed_folder(dir: &Path) -> String {
    let mut s = dir.display().to_string();
    if !s.ends_with(std::path::MAIN_SEPARATOR) {
        s.push(std::path::MAIN_SEPARATOR);
    }
    s
}

/// Draws the open dialog for the typed `path` and pushes what the user asks for.
pub fn open_dialog(ctx: &egui::Context, state: &AppState, typed: &str, cmds: &mut Vec<Command>) {
    let mut path = typed.to_string();
    egui::Window::new("Open a scene or a saved trace")
        .collapsible(false)
        .anchor(egui::Align2::CENTER_CENTER, egui::Vec2::ZERO)
        .show(ctx, |ui| {
            // A fixed width and a fixed-height listing: the dialog keeps its size (and its
            // buttons their places) whatever folder it shows.
            ui.set_width(600.0);
            let mut go = false;
            ui.horizontal(|ui| {
                let l = ui.label("Path");
                let r = ui
                    .add(egui::TextEdit::singleline(&mut path).desired_width(420.0))
                    .labelled_by(l.id)
                    .on_hover_text("a .toml scene or a .json trace; a folder lists it below");
                go |= r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            });
            ui.horizontal(|ui| {
                go |= ui.button("Open").clicked();
                if ui.button("Cancel").clicked() {
                    cmds.push(Command::CloseDialog);
                }
            });
            if go && !path.trim().is_empty() {
                let p = PathBuf::from(path.trim());
                if p.is_dir() {
                    path = typed_folder(&p);
                } else {
                    cmds.push(Command::Open(p));
                }
            }
            ui.separator();
            let dir = folder_of(&path);
            ui.horizontal(|ui| {
                let up = dir.parent().map(Path::to_path_buf);
                let r = ui
                    .add_enabled(up.is_some(), egui::Button::new("↑ Parent folder"))
                    .on_disabled_hover_text("this is the top folder");
                if r.clicked()
                    && let Some(u) = up
                {
                    path = typed_folder(&u);
                }
                ui.label(dir.display().to_string());
            });
            egui::ScrollArea::vertical()
                .id_salt("files-folder")
                .max_height(260.0)
                .min_scrolled_height(260.0)
                .auto_shrink([false, false])
                .show(ui, |ui| match list_folder(&dir) {
                    Ok((entries, more)) => {
                        if entries.is_empty() {
                            ui.weak("(no folders, .toml or .json files here)");
                        }
                        for e in entries {
                            if e.is_dir {
                                if ui
                                    .add(egui::Button::new(format!("{}/", e.name)).truncate())
                                    .clicked()
                                {
                                    path = typed_folder(&e.path);
                                }
                            } else if ui
                                .add(egui::Button::new(e.name.as_str()).truncate())
                                .clicked()
                            {
                                cmds.push(Command::Open(e.path));
                            }
                        }
                        if more {
                            ui.weak(format!(
                                "(only the first {MAX_ENTRIES} entries are listed: type a path)"
                            ));
                        }
                    }
                    Err(e) => {
                        ui.colored_label(ui.visuals().error_fg_color, e);
                    }
                });
            ui.separator();
            ui.label("Scenes built into raystep:");
            match crate::assets::builtin_scene_paths() {
                Ok(paths) => {
                    ui.horizontal_wrapped(|ui| {
                        for p in paths {
                            let name = p
                                .file_stem()
                                .map(|s| s.to_string_lossy().into_owned())
                                .unwrap_or_default();
                            if ui
                                .button(name)
                                .on_hover_text(p.display().to_string())
                                .clicked()
                            {
                                cmds.push(Command::Open(p));
                            }
                        }
                    });
                }
                Err(e) => {
                    ui.colored_label(ui.visuals().error_fg_color, e);
                }
            }
            if ui.button("the default scene (three spheres)").clicked() {
                cmds.push(Command::OpenBuiltin);
                cmds.push(Command::CloseDialog);
            }
            if !state.prefs.recent.is_empty() {
                ui.separator();
                ui.label("Recent files:");
                for p in &state.prefs.recent {
                    let r = ui.add_enabled(p.is_file(), egui::Button::new(p.display().to_string()));
                    if r.on_disabled_hover_text("this file is no longer there")
                        .clicked()
                    {
                        cmds.push(Command::Open(p.clone()));
                    }
                }
            }
        });
    let opening = cmds.iter().any(|c| {
        matches!(
            c,
            Command::Open(_) | Command::OpenBuiltin | Command::CloseDialog
        )
    });
    if path != typed && !opening {
        cmds.push(Command::ShowDialog(Dialog::Open { path }));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_lists_folders_first_then_scenes_and_traces_only() {
        let d = tempfile::tempdir().unwrap();
        for f in ["b.toml", "a.json", "notes.txt", ".hidden.toml", "C.TOML"] {
            std::fs::write(d.path().join(f), "").unwrap();
        }
        std::fs::create_dir(d.path().join("zsub")).unwrap();
        let (entries, more) = list_folder(d.path()).unwrap();
        let names: Vec<&str> = entries.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names, ["zsub", "C.TOML", "a.json", "b.toml"]);
        assert!(!more);
        assert!(list_folder(&d.path().join("missing")).is_err());
    }

    #[test]
    fn a_typed_file_shows_its_folder() {
        let d = tempfile::tempdir().unwrap();
        let f = d.path().join("x.toml");
        std::fs::write(&f, "").unwrap();
        let canon = std::fs::canonicalize(d.path()).unwrap();
        assert_eq!(folder_of(&f.display().to_string()), canon);
        assert_eq!(folder_of(&d.path().display().to_string()), canon);
        assert_eq!(
            folder_of(&d.path().join("not-yet.toml").display().to_string()),
            canon
        );
    }
}
