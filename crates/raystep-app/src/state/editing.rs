//! Live editing of the open scene: the edits (through [`crate::scene::edit::SceneDoc`], the
//! scene's TOML document with undo and redo), the selection, and saving the file back with its
//! comments kept. An edit replaces the open scene and restarts the render; the selected pixel
//! is traced again (keeping the step) as soon as the scene is prepared.

use super::*;
use crate::scene::edit::{Edit, SceneDoc};

/// An editing command (part of [`Command`]).
#[derive(Debug, Clone, PartialEq)]
pub enum EditCmd {
    /// Apply one edit.
    Apply(Edit),
    /// A drag begins: the edits until [`EditCmd::EndGesture`] are one undo step.
    BeginGesture,
    /// The drag ends.
    EndGesture,
    /// Undo the last edit.
    Undo,
    /// Redo the last undone edit.
    Redo,
    /// Select an object group (None: nothing).
    Select(Option<u32>),
    /// Save the scene to its file (None) or to another file ("Save as").
    Save(Option<PathBuf>),
}

impl AppState {
    /// The document being edited, made from `text` (the scene file's contents).
    pub(super) fn make_editor(text: &str, path: Option<&Path>) -> Option<SceneDoc> {
        let file = path.map_or_else(
            || crate::scene::DEFAULT_SCENE_NAME.to_string(),
            |p| p.display().to_string(),
        );
        SceneDoc::parse(text, &file, path.and_then(Path::parent)).ok()
    }

    /// Keeps the editor (and its history) when the file just loaded is the text it holds (the
    /// reload after the app's own save); otherwise starts a new one from the file.
    pub(super) fn refresh_editor(&mut self, path: Option<&Path>) {
        let Some(p) = path else {
            self.editor = None;
            return;
        };
        let Ok(text) = crate::io::read_text(p, crate::io::limits::SCENE, "scene file") else {
            self.editor = None;
            return;
        };
        if self
            .editor
            .as_ref()
            .is_some_and(|e| e.text() == text && self.editor_path.as_deref() == Some(p))
        {
            return;
        }
        self.editor = Self::make_editor(&text, Some(p));
        self.editor_path = Some(p.to_path_buf());
        self.selected = None;
    }

    pub(super) fn apply_edit(&mut self, cmd: EditCmd) {
        match cmd {
            EditCmd::Select(g) => {
                self.selected =
                    g.filter(|g| self.scene().is_some_and(|s| (*g as usize) < s.groups.len()));
            }
            EditCmd::BeginGesture => {
                if let Some(e) = &mut self.editor {
                    e.begin_gesture();
                }
            }
            EditCmd::EndGesture => {
                if let Some(e) = &mut self.editor {
                    e.end_gesture();
                }
            }
            EditCmd::Apply(edit) => {
                let Some(e) = &mut self.editor else {
                    self.message = Some(Message {
                        text: "this scene cannot be edited (it was not opened from a file)".into(),
                        error: true,
                    });
                    return;
                };
                match e.apply(&edit) {
                    Ok(scene) => self.edited(scene),
                    Err(m) => {
                        self.message = Some(Message {
                            text: format!("edit refused: {m}"),
                            error: true,
                        })
                    }
                }
            }
            EditCmd::Undo | EditCmd::Redo => {
                let Some(e) = &mut self.editor else {
                    return;
                };
                let result = if cmd == EditCmd::Undo {
                    e.undo()
                } else {
                    e.redo()
                };
                match result {
                    Some(Ok(scene)) => self.edited(scene),
                    Some(Err(m)) => {
                        self.message = Some(Message {
                            text: format!("the restored scene does not load: {m}"),
                            error: true,
                        })
                    }
                    None => {}
                }
            }
            EditCmd::Save(to) => self.save_scene(to),
        }
    }

    /// Shows the edited scene: same file, same pixel and step, the live settings kept; the
    /// render restarts and the pixel is traced again once the scene is prepared.
    fn edited(&mut self, scene: Scene) {
        let path = self.path().map(Path::to_path_buf);
        let mut scene = scene;
        scene.path = path.clone();
        self.doc = Document::Scene {
            scene: Arc::new(scene),
            path,
        };
        if let Some(g) = self.selected
            && self.scene().is_none_or(|s| g as usize >= s.groups.len())
        {
            self.selected = None;
        }
        self.edits += 1;
        self.restart_render();
    }

    fn save_scene(&mut self, to: Option<PathBuf>) {
        self.dialog = None;
        let target = to.or_else(|| self.editor_path.clone());
        let Some(target) = target else {
            // No file yet (the built-in scene): ask where.
            self.dialog = Some(Dialog::Save {
                kind: SaveKind::Scene,
                path: self.suggested_name(SaveKind::Scene),
            });
            return;
        };
        if !target
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
        {
            self.message = Some(Message {
                text: format!("{}: a scene file name must end in .toml", target.display()),
                error: true,
            });
            return;
        }
        let Some(e) = &mut self.editor else {
            self.message = Some(Message {
                text: "this scene cannot be saved (it was not opened from a file)".into(),
                error: true,
            });
            return;
        };
        match e.save(&target) {
            Ok(()) => {
                let moved = self.editor_path.as_deref() != Some(target.as_path());
                self.editor_path = Some(target.clone());
                if moved {
                    // "Save as": the window now shows (and watches) the new file.
                    if let Document::Scene { path, .. } = &mut self.doc {
                        *path = Some(target.clone());
                    }
                    self.watch = Some(Watch::start(&target, Arc::clone(&self.repaint)));
                    let abs = std::path::absolute(&target).unwrap_or_else(|_| target.clone());
                    self.prefs.last_file = Some(abs.clone());
                    self.prefs.recent.retain(|p| *p != abs);
                    self.prefs.recent.insert(0, abs);
                    self.prefs.recent.truncate(8);
                }
                self.message = Some(Message {
                    text: format!("saved {}", crate::io::full_path(&target)),
                    error: false,
                });
            }
            Err(m) => {
                self.message = Some(Message {
                    text: m,
                    error: true,
                })
            }
        }
    }

    /// Whether the open scene has edits not saved yet.
    pub fn unsaved(&self) -> bool {
        self.editor.as_ref().is_some_and(SceneDoc::dirty)
    }
}
