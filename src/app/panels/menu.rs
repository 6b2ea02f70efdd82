//! The menu bar: File, View, Help, Lessons and Lab.

use crate::app::state::{AppState, Command, Dialog, Document, SaveKind};
use crate::app::view::RenderView;
use egui::RichText;

/// The menu bar (the Lab toggle opens the lab window in `panels`).
pub(super) fn menu_bar(
    ui: &mut egui::Ui,
    state: &AppState,
    render: &mut RenderView,
    panels: &mut super::Panels,
    cmds: &mut Vec<Command>,
) {
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| {
            if ui.button("Open…").clicked() {
                cmds.push(Command::ShowDialog(Dialog::Open {
                    path: state
                        .path()
                        .map(|p| p.display().to_string())
                        .unwrap_or_default(),
                }));
            }
            if ui.button("Built-in scene").clicked() {
                cmds.push(Command::OpenBuiltin);
            }
            if !state.prefs.recent.is_empty() {
                ui.menu_button("Recent", |ui| {
                    for p in &state.prefs.recent {
                        if ui.button(p.display().to_string()).clicked() {
                            cmds.push(Command::Open(p.clone()));
                        }
                    }
                });
            }
            if ui.button("Reload").clicked() {
                cmds.push(Command::Reload);
            }
            ui.separator();
            let has_trace = state.stepping.is_some();
            for kind in [SaveKind::Trace, SaveKind::DiagramPng, SaveKind::StepsGif] {
                if ui
                    .add_enabled(has_trace, egui::Button::new(format!("{}…", kind.title())))
                    .clicked()
                {
                    cmds.push(Command::ShowDialog(Dialog::Save {
                        kind,
                        path: state.suggested_name(kind),
                    }));
                }
            }
            ui.separator();
            if ui.button("Quit").clicked() {
                ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
            }
        });
        ui.menu_button("View", |ui| {
            let mut p = state.prefs.clone();
            // The theme in force: presentation mode has its own.
            ui.label(if p.presentation {
                "Theme (presentation mode)"
            } else {
                "Theme"
            });
            for t in [
                crate::app::state::ThemeChoice::Light,
                crate::app::state::ThemeChoice::Dark,
                crate::app::state::ThemeChoice::HighContrast,
            ] {
                ui.radio_value(p.theme_in_force_mut(), t, t.label());
            }
            ui.separator();
            ui.horizontal(|ui| {
                let l = ui.label("Scale");
                ui.add(egui::Slider::new(&mut p.scale, 0.75..=3.0).step_by(0.05))
                    .labelled_by(l.id)
                    .on_hover_text("the size of everything outside presentation mode");
            });
            ui.checkbox(&mut p.presentation, "Presentation mode (Esc leaves)")
                .on_hover_text(
                    "for a projector: high contrast, large text, a large render, diagram and \
                     math panel, the trace tree folded; leaving puts your layout back",
                );
            ui.horizontal(|ui| {
                let l = ui.label("Presentation scale");
                ui.add(egui::Slider::new(&mut p.presentation_scale, 1.0..=3.0).step_by(0.05))
                    .labelled_by(l.id)
                    .on_hover_text(
                        "the size of everything in presentation mode, on a screen 1080 pixels \
                         high; a smaller screen gets it in proportion (never below 1), so text \
                         takes the same share of the projected picture",
                    );
            });
            let height = crate::app::layout::window_height_at_zoom_1(ui.ctx());
            let here = crate::app::state::Prefs {
                presentation: true,
                ..p.clone()
            }
            .effective_scale_for(height);
            if (here - p.presentation_scale).abs() >= 0.005 {
                ui.weak(format!(
                    "{here:.2} in this window ({} pixels high)",
                    height.round()
                ));
            }
            if ui.button("Full screen (F11)").clicked() {
                panels.toggle_fullscreen = true;
            }
            ui.separator();
            ui.checkbox(&mut p.show_learn, "Lessons and exercises");
            ui.checkbox(&mut p.show_settings, "Settings panel");
            ui.checkbox(&mut p.show_tree, "Trace tree");
            if RenderView::has_heatmap(state) {
                ui.checkbox(&mut p.heatmap, "Visits heatmap over the render");
            }
            if p.show_tree {
                ui.checkbox(&mut p.layout.tree_collapsed, "Fold the trace tree");
            }
            if ui.button("Reset zoom").clicked() {
                render.reset_zoom();
            }
            let reset = ui
                .button("Reset layout")
                .on_hover_text("the panels back to their default sizes, fitted to the window")
                .clicked();
            if p != state.prefs {
                cmds.push(Command::SetPrefs(p));
            }
            if reset {
                cmds.push(Command::ResetLayout);
            }
        });
        ui.menu_button("Help", |ui| {
            ui.label("Click a pixel of the render to trace it.");
            ui.label("← → (or ↑ ↓): previous / next step");
            ui.label("Home / End: first / last step");
            ui.label("Space: play / pause");
            ui.label("F11: full screen · Esc: leave presentation mode");
            ui.label("Scroll on the render to zoom, drag to pan, double-click to fit.");
            ui.label("Drop a scene (.toml) or a saved trace (.json) on the window to open it.");
        });
        let mut learn = state.prefs.show_learn;
        if ui
            .toggle_value(&mut learn, "Lessons")
            .on_hover_text("the lessons, and exercises whose answers the tracer checks")
            .clicked()
        {
            // The lessons take the settings panel's place (a lesson sets its own settings;
            // View → Settings panel shows both): the render keeps its width.
            let mut p = state.prefs.clone();
            p.show_learn = learn;
            p.show_settings = !learn;
            cmds.push(Command::SetPrefs(p));
        }
        ui.toggle_value(&mut panels.lab.open, "Lab")
            .on_hover_text("the stability lab: the selected pixel's numbers against exact values, and every method on the stiff cases");
        ui.separator();
        let title = match &state.doc {
            Document::Scene { scene, path } => format!(
                "{} — {}",
                scene.name,
                path.as_ref()
                    .map_or("built in".to_string(), |p| crate::assets::shown_path(p))
            ),
            Document::Trace { path } => format!("trace — {}", path.display()),
            Document::Empty => String::new(),
        };
        ui.label(RichText::new(title).strong());
    });
}
