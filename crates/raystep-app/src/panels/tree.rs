//! The trace tree: every step of the selected pixel's trace, indented under the ray it belongs
//! to; a click goes to the step, and the current step is scrolled into view. The rows are built
//! once per trace ([`TreePanel`]).

use crate::explain::describe;
use crate::record::number::{num, v3};
use crate::state::{AppState, Command, StepMove};
use egui::{RichText, Vec2};

/// A row of the trace tree: a ray's heading or one of its steps.
#[derive(Debug, Clone)]
pub enum Row {
    /// A ray starts (index into [`crate::record::Trace::rays`]).
    Ray {
        /// Nesting depth.
        depth: u32,
        /// The heading.
        text: String,
    },
    /// A step (timeline index).
    Step {
        /// Timeline index.
        k: usize,
        /// Nesting depth.
        depth: u32,
        /// The description.
        text: String,
    },
}

/// What the trace tree keeps between frames (not persisted).
#[derive(Default)]
pub struct TreePanel {
    /// The rows of the current trace, with the trace generation they were built for.
    pub rows: Option<(u64, Vec<Row>)>,
    /// The row the tree last scrolled to (the current step's).
    pub scroll_row: Option<usize>,
    /// The (trace generation, step) the tree last scrolled to.
    pub scrolled: Option<(u64, usize)>,
}

/// The rows of the trace tree.
fn tree_rows(state: &AppState) -> Vec<Row> {
    let Some(s) = &state.stepping else {
        return vec![];
    };
    let rays = s.trace.rays();
    let mut rows = vec![];
    let mut last_ray = usize::MAX;
    for (k, &(ri, si)) in s.index.iter().enumerate() {
        let ray = rays[ri];
        if ri != last_ray && si == 0 {
            let hit = match &ray.hit {
                Some(h) => format!("hits \"{}\" at t = {}", h.name, num(h.t)),
                None => "hits nothing".into(),
            };
            rows.push(Row::Ray {
                depth: ray.depth,
                text: format!(
                    "{} ray from {} along {}: {hit}",
                    ray.kind.name(),
                    v3(ray.origin),
                    v3(ray.direction)
                ),
            });
        }
        last_ray = ri;
        rows.push(Row::Step {
            k,
            depth: s.ray_depth[ri],
            text: format!("{k}. {}", describe::describe(&ray.steps[si].step, ray.kind)),
        });
    }
    rows
}

/// The trace tree, or, folded, the button that unfolds it.
pub fn panel(ui: &mut egui::Ui, state: &AppState, cache: &mut TreePanel, cmds: &mut Vec<Command>) {
    if state.prefs.layout.tree_collapsed {
        let b = ui
            .button("▸")
            .on_hover_text("show the trace tree (every step of the pixel's trace)");
        if b.clicked() {
            let mut p = state.prefs.clone();
            p.layout.tree_collapsed = false;
            cmds.push(Command::SetPrefs(p));
        }
        return;
    }
    ui.horizontal(|ui| {
        if ui
            .small_button("◂")
            .on_hover_text("fold the trace tree away (View → Fold the trace tree)")
            .clicked()
        {
            let mut p = state.prefs.clone();
            p.layout.tree_collapsed = true;
            cmds.push(Command::SetPrefs(p));
        }
        ui.heading("Trace");
    });
    let Some(s) = &state.stepping else {
        ui.label("Click a pixel of the render to trace it.");
        return;
    };
    let t = &s.trace;
    ui.label(format!(
        "pixel ({}, {}) sample {} → colour {}",
        t.pixel[0],
        t.pixel[1],
        t.sample,
        v3(t.color)
    ));
    if !s.record_time.is_zero() {
        ui.label(format!(
            "{} steps, {} rays, recorded in {:.2} ms",
            s.len(),
            t.rays().len(),
            s.record_time.as_secs_f64() * 1e3
        ));
    } else if state.showing_gpu_trace {
        ui.label(format!(
            "{} steps, {} rays, traced on the GPU (its own steps, read back)",
            s.len(),
            t.rays().len()
        ));
    }
    if cache
        .rows
        .as_ref()
        .is_none_or(|(g, _)| *g != state.trace_generation)
    {
        cache.rows = Some((state.trace_generation, tree_rows(state)));
    }
    let Some((_, rows)) = cache.rows.as_ref() else {
        return;
    };
    // Every row is exactly `inner` high (a selectable button's height), so the offset of row i
    // is i · row_h and the current step can be scrolled to before it is laid out.
    let inner = (ui.text_style_height(&egui::TextStyle::Button)
        + 2.0 * ui.spacing().button_padding.y)
        .max(ui.spacing().interact_size.y);
    let row_h = inner + ui.spacing().item_spacing.y;
    let mut area = egui::ScrollArea::both()
        .id_salt("tree-scroll")
        .auto_shrink([false, false]);
    let target = (state.trace_generation, state.step);
    if cache.scrolled != Some(target) {
        cache.scrolled = Some(target);
        if let Some(i) = rows
            .iter()
            .position(|r| matches!(r, Row::Step { k, .. } if *k == state.step))
        {
            let h = ui.available_height();
            area = area.vertical_scroll_offset((i as f32 * row_h - h * 0.4).max(0.0));
            cache.scroll_row = Some(i);
        }
    }
    // show_rows takes the height without the spacing, which it adds itself.
    area.show_rows(ui, inner, rows.len(), |ui, range| {
        for row in &rows[range] {
            let size = Vec2::new(ui.available_width(), inner);
            // Deep nesting indents at most a third of the panel: the text stays readable.
            let indent_max = size.x / 3.0;
            let row_layout = egui::Layout::left_to_right(egui::Align::Center);
            ui.allocate_ui_with_layout(size, row_layout, |ui| {
                ui.set_min_size(size);
                ui.set_max_height(inner);
                match row {
                    Row::Ray { depth, text } => {
                        ui.add_space((*depth as f32 * 14.0).min(indent_max));
                        ui.add(egui::Label::new(RichText::new(text).strong()).truncate())
                            .on_hover_text(text);
                    }
                    Row::Step { k, depth, text } => {
                        ui.add_space((*depth as f32 * 14.0).min(indent_max) + 10.0);
                        let sel = *k == state.step;
                        let r = ui
                            .add(egui::Button::selectable(sel, text.as_str()).truncate())
                            .on_hover_text(text);
                        if r.clicked() {
                            cmds.push(Command::Step(StepMove::To(*k)));
                        }
                    }
                }
            });
        }
    });
}
