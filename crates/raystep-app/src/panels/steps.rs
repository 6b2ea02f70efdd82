//! The step controls along the bottom: first, previous, play, next, last, the speed, the
//! current step in words, and the timeline (one cell per step, coloured by pipeline stage).

use crate::actions::{self, Action};
use crate::explain::describe;
use crate::record::Stage;
use crate::state::{AppState, Command, StepMove};
use egui::{Color32, RichText, Sense, Vec2};

/// The colour of a pipeline stage on the timeline.
pub fn stage_colour(s: Stage) -> Color32 {
    match s {
        Stage::RayGeneration => Color32::from_rgb(86, 180, 233),
        Stage::Traversal => Color32::from_rgb(150, 150, 150),
        Stage::Intersection => Color32::from_rgb(230, 159, 0),
        Stage::AnyHit => Color32::from_rgb(204, 121, 167),
        Stage::ClosestHit => Color32::from_rgb(0, 158, 115),
        Stage::Miss => Color32::from_rgb(213, 94, 0),
    }
}

/// The step controls and the timeline (shown while a pixel's trace is open).
pub fn controls(ui: &mut egui::Ui, state: &AppState, cmds: &mut Vec<Command>) {
    let Some(s) = &state.stepping else {
        return;
    };
    let n = s.len();
    if n == 0 {
        // Only a hand-made trace file can have no steps.
        ui.label("This trace has no steps.");
        return;
    }
    // Wrapped: in presentation mode at 1024×768 the step's description does not fit beside the
    // buttons and the speed; on one row it ran past the window's edge and widened the panel,
    // and the timeline below (as wide as the panel) with it.
    ui.horizontal_wrapped(|ui| {
        for a in [
            Action::FirstStep,
            Action::PreviousStep,
            Action::PlayPause,
            Action::NextStep,
            Action::LastStep,
        ] {
            actions::button(ui, state, a, true, cmds);
        }
        ui.separator();
        let mut p = state.prefs.clone();
        let l = ui.label("Speed");
        ui.add(
            egui::Slider::new(&mut p.speed, 0.25..=30.0)
                .logarithmic(true)
                .suffix(" steps/s"),
        )
        .labelled_by(l.id);
        if p != state.prefs {
            cmds.push(Command::SetPrefs(p));
        }
        ui.separator();
        if let Some((ray, step)) = s.at(state.step) {
            if state.showing_gpu_trace {
                ui.label(
                    RichText::new("GPU trace")
                        .strong()
                        .color(ui.visuals().warn_fg_color),
                )
                .on_hover_text(
                    "the GPU's own steps (GPU tab); switch back with \"CPU trace\" there",
                );
            }
            ui.label(
                RichText::new(format!(
                    "step {} of 0–{} · {} · {} ray (depth {})",
                    state.step,
                    n - 1,
                    describe::stage_name(step.stage),
                    ray.kind.name(),
                    ray.depth
                ))
                .strong(),
            );
        }
    });
    // The timeline: one cell per step, coloured by pipeline stage; click or drag to jump.
    let (rect, resp) = ui.allocate_exact_size(
        Vec2::new(ui.available_width(), 18.0),
        Sense::click_and_drag(),
    );
    let painter = ui.painter_at(rect);
    let cell = rect.width() / n.max(1) as f32;
    let stages: Vec<Stage> = (0..n)
        .filter_map(|k| s.at(k).map(|(_, st)| st.stage))
        .collect();
    if cell >= 1.0 {
        for (k, st) in stages.iter().enumerate() {
            let x0 = rect.left() + k as f32 * cell;
            let r = egui::Rect::from_min_max(
                egui::pos2(x0, rect.top()),
                egui::pos2(x0 + cell.max(1.0), rect.bottom()),
            );
            painter.rect_filled(
                r.shrink2(Vec2::new((cell * 0.08).min(1.0), 0.0)),
                1.0,
                stage_colour(*st),
            );
        }
    } else {
        // More steps than pixels: each pixel column shows the first step it covers.
        let cols = rect.width() as usize;
        for c in 0..cols {
            let k = c * n / cols.max(1);
            let x0 = rect.left() + c as f32;
            if let Some(st) = stages.get(k) {
                painter.rect_filled(
                    egui::Rect::from_min_max(
                        egui::pos2(x0, rect.top()),
                        egui::pos2(x0 + 1.0, rect.bottom()),
                    ),
                    0.0,
                    stage_colour(*st),
                );
            }
        }
    }
    // The first step where the GPU's trace parts from the CPU's: a red mark above the cell.
    if let Some(d) = state.divergence.filter(|_| state.showing_gpu_trace) {
        let xd = rect.left() + (d as f32 + 0.5) * rect.width() / n.max(1) as f32;
        painter.line_segment(
            [egui::pos2(xd, rect.top()), egui::pos2(xd, rect.bottom())],
            egui::Stroke::new(2.0, ui.visuals().error_fg_color),
        );
    }
    let xk = rect.left() + (state.step as f32 + 0.5) * rect.width() / n.max(1) as f32;
    painter.line_segment(
        [
            egui::pos2(xk, rect.top() - 2.0),
            egui::pos2(xk, rect.bottom() + 2.0),
        ],
        egui::Stroke::new(3.0, ui.visuals().strong_text_color()),
    );
    let cell_at = |x: f32| {
        let k = (((x - rect.left()) / rect.width().max(1.0)) * n as f32).floor();
        (k.max(0.0) as usize).min(n - 1)
    };
    if let Some(p) = resp.hover_pos() {
        let k = cell_at(p.x);
        if let Some((ray, step)) = s.at(k) {
            resp.clone().on_hover_text_at_pointer(format!(
                "step {k}: {} · {} ray\n{}",
                describe::stage_name(step.stage),
                ray.kind.name(),
                describe::describe(&step.step, ray.kind)
            ));
        }
    }
    if (resp.clicked() || resp.dragged())
        && let Some(p) = resp.interact_pointer_pos()
    {
        let k = cell_at(p.x);
        if k != state.step {
            cmds.push(Command::Step(StepMove::To(k)));
        }
    }
    ui.horizontal_wrapped(|ui| {
        for st in [
            Stage::RayGeneration,
            Stage::Traversal,
            Stage::Intersection,
            Stage::AnyHit,
            Stage::ClosestHit,
            Stage::Miss,
        ] {
            if stages.contains(&st) {
                ui.label(RichText::new("■").color(stage_colour(st)));
                ui.label(describe::stage_name(st));
            }
        }
    });
}
