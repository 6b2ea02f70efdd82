//! The math panel (below the diagram): the formula of the current step with the numbers the
//! renderer used substituted.

use crate::explain::describe;
use crate::record::Step;
use crate::record::number::num;
use crate::state::AppState;
use egui::RichText;

/// The formula of the current step with the recorded numbers substituted.
pub fn panel(ui: &mut egui::Ui, state: &AppState) {
    let Some(s) = &state.stepping else {
        return;
    };
    let Some((ray, step)) = s.at(state.step) else {
        return;
    };
    let e = crate::explain::formula::explain(&s.trace, ray, &step.step);
    // On a projector the formulas are what the room reads: larger still than the UI's scale.
    let math_size = if state.prefs.presentation { 1.3 } else { 1.1 };
    if let Some(mc) = &s.trace.monte_carlo {
        // The pixel's estimate from its samples so far (0 … the traced one): what playing the
        // samples one at a time updates.
        let k = s.trace.sample as usize;
        let est = describe::running_estimate(mc, k + 1);
        ui.label(RichText::new(format!("The pixel so far: samples 0–{k}")).strong());
        let lines = [
            format!(
                "estimate = (1/n) Σ sampleᵢ = ({}, {}, {}), n = {}",
                num(est.mean[0] as f32),
                num(est.mean[1] as f32),
                num(est.mean[2] as f32),
                est.n
            ),
            if est.n < 2 {
                format!(
                    "luminance {} (one sample: no spread to measure yet)",
                    num(est.luminance as f32)
                )
            } else {
                format!(
                    "luminance {} ± {} (95 %: 1.96 · s/√n, s = {})",
                    num(est.luminance as f32),
                    num(est.half_width as f32),
                    num(est.sd as f32)
                )
            },
        ];
        for line in lines {
            ui.label(
                RichText::new(line)
                    .monospace()
                    .size(ui.text_style_height(&egui::TextStyle::Body) * math_size),
            );
        }
        ui.separator();
    }
    ui.heading(&e.title);
    ui.label(
        RichText::new(format!(
            "{} · {} ray · f32, the numbers the renderer used",
            describe::stage_name(step.stage),
            ray.kind.name()
        ))
        .weak(),
    );
    ui.add_space(4.0);
    for f in &e.lines {
        let mut line = if f.symbolic == f.name {
            f.name.clone()
        } else {
            format!("{} = {}", f.name, f.symbolic)
        };
        if !f.substituted.is_empty() {
            line += &format!(" = {}", f.substituted);
        }
        if f.value != f.symbolic {
            line += &format!(" = {}", f.value);
        }
        ui.horizontal_wrapped(|ui| {
            ui.label(
                RichText::new(line)
                    .monospace()
                    .size(ui.text_style_height(&egui::TextStyle::Body) * math_size),
            );
            if let Some(n) = &f.note {
                ui.label(RichText::new(n).italics());
            }
        });
    }
    ui.add_space(4.0);
    ui.label(RichText::new(&e.conclusion).strong());

    if let Step::Triangle { .. } | Step::Sphere { .. } = step.step {
        ui.add_space(4.0);
        ui.label(RichText::new(describe::describe(&step.step, ray.kind)).weak());
    }
}
