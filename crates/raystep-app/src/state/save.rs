//! Saving from the app: the trace, the diagram, the render, and the animated GIF of every step
//! (written in the background), each atomically, with the name suggested from the scene and
//! pixel.

use super::*;

impl AppState {
    /// A file name for saving, from the scene and pixel, e.g. `three-spheres-160-120.json`.
    pub fn suggested_name(&self, kind: SaveKind) -> String {
        let stem = match (&self.doc, &self.stepping) {
            (Document::Scene { scene, path }, _) => path
                .as_ref()
                .and_then(|p| p.file_stem())
                .map_or_else(|| slug(&scene.name), |s| s.to_string_lossy().into_owned()),
            (_, Some(s)) => slug(&s.trace.scene),
            _ => "raystep".into(),
        };
        let [x, y] = self.pixel.unwrap_or([0, 0]);
        let kind_name = self.diagram_kind().map_or("diagram", DiagramKind::name);
        match kind {
            SaveKind::Trace => format!("{stem}-{x}-{y}.json"),
            SaveKind::DiagramPng => format!("{stem}-{x}-{y}-{kind_name}-step{}.png", self.step),
            SaveKind::StepsGif => format!("{stem}-{x}-{y}-steps.gif"),
            SaveKind::Scene => format!("{stem}-edited.toml"),
            SaveKind::Answers => {
                let sheet = self
                    .learn
                    .sheet
                    .as_ref()
                    .and_then(|(p, _)| p.file_stem())
                    .map_or_else(|| "answers".into(), |s| s.to_string_lossy().into_owned());
                let student = slug(self.learn.student.trim());
                format!("{sheet}-{student}.csv")
            }
        }
    }

    pub(super) fn save(&mut self, kind: SaveKind, path: &Path) {
        self.dialog = None;
        if kind == SaveKind::Scene {
            self.apply_edit(editing::EditCmd::Save(Some(path.to_path_buf())));
            return;
        }
        if kind == SaveKind::StepsGif {
            self.export_gif(path);
            return;
        }
        let result = self.write(kind, path);
        self.message = Some(match result {
            Ok(what) => Message {
                text: saved(path, &what),
                error: false,
            },
            Err(e) => Message {
                text: format!("{}: {e}", path.display()),
                error: true,
            },
        });
    }

    fn write(&self, kind: SaveKind, path: &Path) -> Result<String, String> {
        if kind == SaveKind::Answers {
            if !path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
            {
                return Err("the file name must end in .csv".into());
            }
            let csv = self.answers_csv()?;
            crate::io::write_atomic(path, csv.as_bytes())?;
            let n = self
                .learn
                .attempts
                .iter()
                .filter(|a| !a.answer.trim().is_empty());
            return Ok(format!(
                "{} answers for {}: `raystep grade SHEET FILE` marks them",
                n.count(),
                self.learn.student.trim()
            ));
        }
        let s = self
            .stepping
            .as_ref()
            .ok_or("there is no trace yet: click a pixel first")?;
        let want = match kind {
            SaveKind::Trace => "json",
            SaveKind::DiagramPng => "png",
            SaveKind::StepsGif => "gif",
            SaveKind::Scene => "toml",
            SaveKind::Answers => "csv",
        };
        if !path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case(want))
        {
            return Err(format!("the file name must end in .{want}"));
        }
        let opts = self.view_options(1024, 768);
        match kind {
            SaveKind::Trace => {
                crate::io::write_atomic(path, s.trace.to_json().as_bytes())?;
                Ok(format!("{} steps", s.len()))
            }
            SaveKind::DiagramPng => {
                let kind = self.diagram_kind().ok_or("no diagram to export")?;
                let c = diagram::draw(&s.trace, kind, &opts)?;
                crate::io::write_atomic(path, &c.png())?;
                Ok(format!("{} diagram, step {}", kind.name(), self.step))
            }
            SaveKind::StepsGif => Err("GIFs are written in the background".into()),
            SaveKind::Scene => Err("scenes are saved by the editor".into()),
            SaveKind::Answers => Err("answers are written above".into()),
        }
    }

    /// Draws every step and encodes the GIF on a background thread (a long trace takes
    /// seconds); the status line reports when it is written.
    fn export_gif(&mut self, path: &Path) {
        let Some(s) = &self.stepping else {
            self.message = Some(Message {
                text: "there is no trace yet: click a pixel first".into(),
                error: true,
            });
            return;
        };
        if !path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("gif"))
        {
            self.message = Some(Message {
                text: format!("{}: the file name must end in .gif", path.display()),
                error: true,
            });
            return;
        }
        let fixed = match self.prefs.diagram {
            DiagramChoice::Kind(k) if s.kinds.contains(&k) => Some(k),
            _ => None,
        };
        let trace = Arc::clone(&s.trace);
        let opts = self.view_options(800, 600);
        // The GIF plays at the app's play speed.
        let delay_ms = (1000.0 / self.prefs.speed.clamp(0.1, 60.0)).round() as u32;
        let path = path.to_path_buf();
        let (tx, rx) = std::sync::mpsc::channel();
        let repaint = Arc::clone(&self.repaint);
        crate::platform::spawn(move || {
            let result = diagram::animate(&trace, fixed, &opts, Some(delay_ms), |_, _| Ok(()))
                .and_then(|(gif, n)| {
                    crate::io::write_atomic(&path, &gif)?;
                    Ok(n)
                });
            let _ = tx.send(match result {
                Ok(n) => Message {
                    text: saved(&path, &format!("{n} frames")),
                    error: false,
                },
                Err(e) => Message {
                    text: format!("{}: {e}", path.display()),
                    error: true,
                },
            });
            repaint();
        });
        self.exports.push(rx);
        self.message = Some(Message {
            text: "writing the GIF in the background…".into(),
            error: false,
        });
    }

    /// Whether a background export is still running.
    pub fn exporting(&self) -> bool {
        !self.exports.is_empty()
    }
}

/// A file-name-safe version of a title.
fn slug(s: &str) -> String {
    let out: String = s
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    let out = out.trim_matches('-').to_string();
    if out.is_empty() { "scene".into() } else { out }
}

/// What the status line says when `path` was written: where natively, that it was offered as a
/// download in the browser.
fn saved(path: &Path, what: &str) -> String {
    if crate::platform::IN_BROWSER {
        format!("saved {} ({what}) as a download", path.display())
    } else {
        format!("wrote {} ({what})", crate::io::full_path(path))
    }
}
