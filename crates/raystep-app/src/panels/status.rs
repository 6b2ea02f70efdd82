//! The status bar along the bottom (the scene in a few words, the render's progress or time,
//! the pixel under the cursor, the last message) and the load-error banner along the top.

use crate::actions::{self, Action};
use crate::state::{AppState, Command};
use crate::view::{self, RenderView};
use egui::{Color32, RichText};
use std::sync::atomic::Ordering;

/// The load error: one bar that never takes more than a few lines (the message scrolls), with
/// Reload and × (hide it until the next error).
pub fn error_banner(ui: &mut egui::Ui, state: &AppState, e: &str, cmds: &mut Vec<Command>) {
    egui::Frame::new()
        .fill(Color32::from_rgb(120, 20, 20))
        .inner_margin(6.0)
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.label(
                    RichText::new("The file did not load")
                        .strong()
                        .color(Color32::WHITE),
                )
                .on_hover_text(
                    "What was open before stays shown; fix the file and it reloads by itself.",
                );
                actions::button(ui, state, Action::Reload, true, cmds);
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    if ui.button("×").on_hover_text("hide this message").clicked() {
                        cmds.push(Command::DismissError);
                    }
                });
            });
            let line = ui.text_style_height(&egui::TextStyle::Monospace);
            egui::ScrollArea::vertical()
                .id_salt("load-error-scroll")
                .max_height(line * 4.0)
                .show(ui, |ui| {
                    ui.label(RichText::new(e).monospace().color(Color32::WHITE));
                });
        });
}

/// The status bar: the scene in a few words, the render's progress (or how long it took), the
/// pixel under the cursor with its colour, and the last message. One line, whatever the window:
/// what does not fit is cut short with "…" (the whole text on hover) rather than run off the
/// window's edge (in presentation mode at 1024×768 about half of it fits) or wrap onto a second
/// line, which would move the render above it whenever the pointer's pixel comes and goes.
pub fn status_bar(ui: &mut egui::Ui, state: &AppState, render: &RenderView) {
    // A label that ends in "…" where the line runs out.
    let label = |ui: &mut egui::Ui, text: egui::WidgetText| {
        ui.add(egui::Label::new(text).truncate());
    };
    ui.horizontal(|ui| {
        if let Some(s) = state.scene() {
            let f = &s.features;
            // Objects whose material emits are area lights (the Monte Carlo integrators').
            let area = f.emitters;
            let area = if area > 0 {
                format!(
                    ", {area} emitting primitive{}",
                    if area == 1 { "" } else { "s" }
                )
            } else {
                String::new()
            };
            let placed = if f.instances > 0 {
                format!(
                    ", {} instance{}",
                    f.instances,
                    if f.instances == 1 { "" } else { "s" }
                )
            } else {
                String::new()
            };
            label(ui, format!(
                "{} primitive{} ({}){placed}, {} point light{}{area}",
                f.primitives,
                if f.primitives == 1 { "" } else { "s" },
                f.kinds().join(", "),
                f.lights,
                if f.lights == 1 { "" } else { "s" }
            ).into());
            ui.separator();
        }
        if let Some(job) = &state.job {
            let p = job.live.progress();
            let phase = if state.prepared.is_none() {
                "preparing (building the BVH)".to_string()
            } else {
                let total = job.live.samples_total.load(Ordering::Relaxed);
                if total > 0 {
                    // A progressive render: the samples every pixel has so far, and the time.
                    format!(
                        "rendering {:.0}%: {} of {total} samples per pixel, {:.1} s",
                        p * 100.0,
                        job.live.samples_done.load(Ordering::Relaxed),
                        job.started.elapsed().as_secs_f64()
                    )
                } else {
                    format!("rendering {:.0}%", p * 100.0)
                }
            };
            ui.add(
                egui::ProgressBar::new(p)
                    .desired_width(160.0)
                    .text(phase.clone()),
            );
            label(ui, phase.into());
        } else if let Some(r) = &state.rendered {
            let spp = state.settings.spp;
            label(ui, format!(
                "rendered{} in {:.2} s (build {:.0} ms, trace {:.0} ms, {:.2} Mrays/s, {} thread{})",
                if spp > 1 {
                    format!(" {spp} samples per pixel")
                } else {
                    String::new()
                },
                r.wall.as_secs_f64(),
                r.build.as_secs_f64() * 1e3,
                r.output.stats.trace.as_secs_f64() * 1e3,
                r.output.stats.mrays_per_s(),
                r.output.stats.threads,
                if r.output.stats.threads == 1 { "" } else { "s" }
            ).into());
        }
        if let Some(p) = render.hovered {
            ui.separator();
            let colour = view::pixel_colour(state, p).unwrap_or_default();
            label(ui, format!("pixel ({}, {}) {colour}", p[0], p[1]).into());
        }
        if let Some(m) = &state.message {
            ui.separator();
            let t = RichText::new(&m.text);
            label(
                ui,
                if m.error {
                    t.color(Color32::from_rgb(220, 50, 50))
                } else {
                    t
                }
                .into(),
            );
        }
    });
}
