//! The dialogs over the window: File → Open (see [`crate::files`]) and the save dialogs
//! (a trace, a diagram, the steps as a GIF, the edited scene).

use crate::actions::{self, Action};
use crate::state::{AppState, Command, Dialog};
use egui::Vec2;
use std::path::PathBuf;

/// The open dialog, if any.
pub fn show(ui: &mut egui::Ui, state: &AppState, cmds: &mut Vec<Command>) {
    let Some(d) = &state.dialog else {
        return;
    };
    let ctx = ui.ctx().clone();
    match d {
        // A page has no folders to browse: the browser's own file picker opens instead.
        Dialog::Open { .. } if crate::platform::IN_BROWSER => {
            let repaint = ctx.clone();
            if let Err(e) = crate::platform::browser::pick_files(move || repaint.request_repaint())
            {
                cmds.push(Command::ShowError(e));
            }
            cmds.push(Command::CloseDialog);
        }
        Dialog::Open { path } => crate::files::open_dialog(&ctx, state, path, cmds),
        Dialog::Save { kind, path } => {
            let mut path = path.clone();
            egui::Window::new(kind.title())
                .collapsible(false)
                .anchor(egui::Align2::CENTER_CENTER, Vec2::ZERO)
                .show(&ctx, |ui| {
                    let mut go = false;
                    ui.horizontal(|ui| {
                        let l = ui.label("File");
                        let r = ui
                            .add(egui::TextEdit::singleline(&mut path).desired_width(420.0))
                            .labelled_by(l.id);
                        go |= r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                        // The name is ready to edit, and Enter saves, without a click first
                        // (asked after reading Enter: focus asked for undoes `lost_focus`).
                        if !go && ui.memory(|m| m.focused().is_none()) {
                            r.request_focus();
                        }
                    });
                    ui.horizontal(|ui| {
                        go |= ui.button("Save").clicked();
                        actions::button(ui, state, Action::CloseDialog, true, cmds);
                    });
                    if go && !path.trim().is_empty() {
                        cmds.push(Command::Save(*kind, PathBuf::from(path.trim())));
                    }
                });
            let current = d_path(d);
            if path != current && !cmds.iter().any(|c| matches!(c, Command::Save(..))) {
                cmds.push(Command::ShowDialog(Dialog::Save { kind: *kind, path }));
            }
        }
    }
}

fn d_path(d: &Dialog) -> String {
    match d {
        Dialog::Open { path } | Dialog::Save { path, .. } => path.clone(),
    }
}
