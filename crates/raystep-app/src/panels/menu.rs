//! The menu bar: File, View, Help, Lessons and Lab. Its items, their words and their keys come
//! from the table of actions ([`crate::actions`]).

use crate::actions::{self, Action, Targets};
use crate::state::{AppState, Command, Document, SaveKind};
use crate::view::RenderView;
use egui::RichText;

/// A menu button for `action` (its label with its key, its tooltip); whether it was clicked.
fn item(ui: &mut egui::Ui, state: &AppState, action: Action, enabled: bool) -> bool {
    let r = ui.add_enabled(enabled, egui::Button::new(action.menu_label(state)));
    match action.tooltip() {
        Some(t) => r.on_hover_text(t),
        None => r,
    }
    .clicked()
}

/// The menu bar (the Lab toggle opens the lab window in `panels`).
pub(super) fn menu_bar(
    ui: &mut egui::Ui,
    state: &AppState,
    render: &mut RenderView,
    panels: &mut super::Panels,
    cmds: &mut Vec<Command>,
) {
    let ctx = ui.ctx().clone();
    let to = &mut Targets {
        state,
        ctx: &ctx,
        render,
        toggle_fullscreen: &mut panels.toggle_fullscreen,
        lab_open: &mut panels.lab.open,
        cmds,
    };
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| {
            for a in [Action::Open, Action::OpenBuiltin] {
                if item(ui, state, a, true) {
                    a.perform(to);
                }
            }
            // In a web page a file opened there lives in the page's memory, gone after a
            // reload: the list keeps those still there (and the built-in files).
            let recent: Vec<_> = (state.prefs.recent.iter())
                .filter(|p| !crate::platform::IN_BROWSER || crate::platform::files::is_file(p))
                .collect();
            if !recent.is_empty() {
                ui.menu_button("Recent", |ui| {
                    for p in recent {
                        if ui.button(p.display().to_string()).clicked() {
                            to.cmds.push(Command::Open(p.clone()));
                        }
                    }
                });
            }
            if item(ui, state, Action::Reload, true) {
                Action::Reload.perform(to);
            }
            ui.separator();
            let has_trace = state.stepping.is_some();
            for kind in [SaveKind::Trace, SaveKind::DiagramPng, SaveKind::StepsGif] {
                if item(ui, state, Action::SaveAs(kind), has_trace) {
                    Action::SaveAs(kind).perform(to);
                }
            }
            // A page is closed with its tab: there is nothing to quit in the browser.
            if !crate::platform::IN_BROWSER {
                ui.separator();
                if item(ui, state, Action::Quit, true) {
                    Action::Quit.perform(to);
                }
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
                crate::state::ThemeChoice::Light,
                crate::state::ThemeChoice::Dark,
                crate::state::ThemeChoice::HighContrast,
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
            let leave = actions::keys_text(&[Action::LeavePresentation]);
            ui.checkbox(
                &mut p.presentation,
                format!("Presentation mode ({leave} leaves)"),
            )
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
            let height = crate::layout::window_height_at_zoom_1(ui.ctx());
            let here = crate::state::Prefs {
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
            if item(ui, state, Action::FullScreen, true) {
                Action::FullScreen.perform(to);
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
            if item(ui, state, Action::ResetZoom, true) {
                Action::ResetZoom.perform(to);
            }
            let reset = item(ui, state, Action::ResetLayout, true);
            if p != state.prefs {
                to.cmds.push(Command::SetPrefs(p));
            }
            if reset {
                Action::ResetLayout.perform(to);
            }
        });
        ui.menu_button("Help", |ui| {
            ui.label("Click a pixel of the render to trace it.");
            for line in actions::help_lines() {
                ui.label(line);
            }
            ui.label("Scroll on the render to zoom, drag to pan, double-click to fit.");
            ui.label("Drop a scene (.toml), a glTF model (.gltf, .glb) or a saved trace (.json) on the window to open it.");
        });
        let mut learn = state.prefs.show_learn;
        if toggle(ui, state, &mut learn, Action::Lessons) {
            Action::Lessons.perform(to);
        }
        let mut lab = *to.lab_open;
        if toggle(ui, state, &mut lab, Action::Lab) {
            Action::Lab.perform(to);
        }
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

/// A toggle button for `action`, showing `on`; whether it was clicked.
fn toggle(ui: &mut egui::Ui, state: &AppState, on: &mut bool, action: Action) -> bool {
    let r = ui.toggle_value(on, action.label(state));
    match action.tooltip() {
        Some(t) => r.on_hover_text(t),
        None => r,
    }
    .clicked()
}
