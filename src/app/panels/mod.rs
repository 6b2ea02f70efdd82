//! The panels: read-only views of [`AppState`] that return [`Command`]s. Panels and settings
//! that do not apply to the open scene are left out, not greyed (no triangle method for a
//! sphere-only scene, no recursion depth without mirrors or glass, no heatmap without a BVH).

pub mod learn;
pub mod menu;
pub mod settings;

use super::layout::Side;
use super::state::{AppState, Command, DiagramChoice, Dialog, Document, StepMove};
use super::view::{self, Row, Views};
use crate::diagram::DiagramKind;
use crate::explain::describe;
use crate::record::number::{num, v3};
use crate::record::{Stage, Step};
use egui::{Color32, RichText, Sense, Vec2};
use menu::menu_bar;
use settings::settings_panel;
use std::path::PathBuf;

/// Draws the whole window. The side panels take the widths [`super::layout::Layout::widths`] computes from
/// the window's width every frame (so they follow the window and can never squeeze the render
/// below its share); their edges are dragged with handles drawn here.
pub fn show(ui: &mut egui::Ui, state: &AppState, views: &mut Views, cmds: &mut Vec<Command>) {
    let window = ui.available_rect_before_wrap();
    let width = window.width();
    views.window_rect = Some(window);
    let mut rects: Vec<(&'static str, egui::Rect)> = vec![];
    egui::Panel::top("menu").show(ui, |ui| menu_bar(ui, state, views, cmds));
    if let Some(e) = &state.load_error {
        egui::Panel::top("load-error").show(ui, |ui| error_banner(ui, e, cmds));
    }
    egui::Panel::bottom("status").show(ui, |ui| status_bar(ui, state, views));
    if state.stepping.is_some() {
        egui::Panel::bottom("steps").show(ui, |ui| step_controls(ui, state, cmds));
    }
    let layout = state.prefs.layout;
    let mut shown = vec![];
    if state.prefs.show_learn {
        shown.push(Side::Learn);
    }
    if state.prefs.show_settings {
        shown.push(Side::Settings);
    }
    if state.prefs.show_tree {
        shown.push(Side::Tree);
    }
    shown.push(Side::Explain);
    let widths = layout.widths(width, &shown);
    let width_of = |side: Side| {
        shown
            .iter()
            .position(|s| *s == side)
            .and_then(|i| widths.get(i).copied())
            .unwrap_or(0.0)
    };
    let others = |side: Side| widths.iter().sum::<f32>() - width_of(side);
    let mut drag: Option<(Side, f32)> = None;
    let mut left_panel = |ui: &mut egui::Ui,
                          side: Side,
                          id: &'static str,
                          resizable: bool,
                          add: &mut dyn FnMut(&mut egui::Ui)| {
        let r = egui::Panel::left(id)
            .resizable(false)
            .exact_size(width_of(side))
            .show(ui, |ui| contained(ui, add));
        let rect = r.response.rect;
        rects.push((id, rect));
        if resizable && let Some(x) = resize_handle(ui, id, rect.right(), rect, true) {
            drag = Some((side, x - rect.left()));
        }
    };
    if state.prefs.show_learn {
        left_panel(ui, Side::Learn, "learn", true, &mut |ui| {
            learn::panel(ui, state, views, cmds)
        });
    }
    if state.prefs.show_settings {
        left_panel(ui, Side::Settings, "settings", true, &mut |ui| {
            egui::ScrollArea::vertical()
                .id_salt("settings-scroll")
                .auto_shrink([false, false])
                .show(ui, |ui| settings_panel(ui, state, views, cmds));
        });
    }
    let mut math_drag = None;
    let r = egui::Panel::right("explain")
        .resizable(false)
        .exact_size(width_of(Side::Explain))
        .show(ui, |ui| {
            contained(ui, |ui| {
                let height = ui.available_height();
                let r = egui::Panel::bottom("math")
                    .resizable(false)
                    .exact_size(layout.math_height(height))
                    .show(ui, |ui| {
                        egui::ScrollArea::vertical()
                            .id_salt("math-scroll")
                            .auto_shrink([false, false])
                            .show(ui, |ui| math_panel(ui, state));
                    });
                let rect = r.response.rect;
                if let Some(y) = resize_handle(ui, "math", rect.top(), rect, false) {
                    math_drag = Some((rect.bottom() - y, height));
                }
                egui::CentralPanel::default().show(ui, |ui| diagram_panel(ui, state, views, cmds));
            })
        });
    let rect = r.response.rect;
    rects.push(("explain", rect));
    if let Some(x) = resize_handle(ui, "explain", rect.left(), rect, true) {
        drag = Some((Side::Explain, rect.right() - x));
    }
    if state.prefs.show_tree {
        let collapsed = layout.tree_collapsed;
        let r = egui::Panel::left("tree")
            .resizable(false)
            .exact_size(width_of(Side::Tree))
            .show(ui, |ui| {
                contained(ui, |ui| {
                    if collapsed {
                        let b = ui
                            .button("▸")
                            .on_hover_text("show the trace tree (every step of the pixel's trace)");
                        if b.clicked() {
                            let mut p = state.prefs.clone();
                            p.layout.tree_collapsed = false;
                            cmds.push(Command::SetPrefs(p));
                        }
                    } else {
                        tree_panel(ui, state, views, cmds);
                    }
                })
            });
        let rect = r.response.rect;
        rects.push(("tree", rect));
        if !collapsed && let Some(x) = resize_handle(ui, "tree", rect.right(), rect, true) {
            drag = Some((Side::Tree, x - rect.left()));
        }
    }
    let mut p = state.prefs.clone();
    if let Some((side, wanted)) = drag {
        p.layout.drag(side, wanted, width, others(side));
    }
    if let Some((wanted, height)) = math_drag {
        p.layout.drag_math(wanted, height);
    }
    if p != state.prefs {
        cmds.push(Command::SetPrefs(p));
    }
    views.centre_rect = Some(ui.available_rect_before_wrap());
    views.panel_rects = rects;
    egui::CentralPanel::default().show(ui, |ui| match &state.doc {
        Document::Trace { path } => {
            ui.vertical_centered(|ui| {
                ui.add_space(40.0);
                ui.heading("Replaying a saved trace");
                ui.label(format!("{}", path.display()));
                if let Some(s) = &state.stepping {
                    ui.label(format!(
                        "scene \"{}\" (sha-256 {}…), pixel ({}, {}), sample {}, raystep {}",
                        s.trace.scene,
                        s.trace.scene_hash.get(..12).unwrap_or(&s.trace.scene_hash),
                        s.trace.pixel[0],
                        s.trace.pixel[1],
                        s.trace.sample,
                        s.trace.raystep
                    ));
                }
                ui.label("There is no render: the trace was opened without its scene.");
            });
        }
        _ => {
            use super::gpu_view::{self, CentralTab};
            if !views.gpu.available() {
                return view::render_view(ui, state, views, cmds);
            }
            gpu_view::tabs(ui, &mut views.gpu);
            match views.gpu.tab {
                CentralTab::Cpu => view::render_view(ui, state, views, cmds),
                CentralTab::Gpu => gpu_view::gpu_tab(ui, state, &mut views.gpu),
                CentralTab::Difference => gpu_view::difference_tab(ui, state, &mut views.gpu),
                CentralTab::Scene3d => super::scene3d::tab(
                    ui,
                    state,
                    &mut views.scene3d,
                    views.gpu.render_state.as_ref(),
                    cmds,
                ),
            }
        }
    });
    dialogs(ui, state, cmds);
    super::lab::window(ui.ctx(), state, &mut views.lab, cmds);
}

/// Runs `add` in a child of `ui` that cannot grow it: content wider than the panel (a row of
/// widgets that does not wrap) is clipped instead of widening the panel — the creep that a
/// panel remembering its content's width had.
fn contained(ui: &mut egui::Ui, add: impl FnOnce(&mut egui::Ui)) {
    let rect = ui.max_rect();
    let mut child = ui.new_child(
        egui::UiBuilder::new()
            .max_rect(rect)
            .layout(egui::Layout::top_down(egui::Align::Min)),
    );
    child.shrink_clip_rect(rect);
    add(&mut child);
}

/// A handle on a panel's edge at `at` (x for a vertical edge, y for a horizontal one) along
/// `rect`; returns where the pointer is while it is being dragged.
fn resize_handle(
    ui: &mut egui::Ui,
    id: &str,
    at: f32,
    rect: egui::Rect,
    vertical: bool,
) -> Option<f32> {
    let r = if vertical {
        egui::Rect::from_x_y_ranges(at - 4.0..=at + 4.0, rect.y_range())
    } else {
        egui::Rect::from_x_y_ranges(rect.x_range(), at - 4.0..=at + 4.0)
    };
    let resp = ui.interact(r, ui.scope_id().with(("panel-edge", id)), Sense::drag());
    if resp.hovered() || resp.dragged() {
        ui.ctx().set_cursor_icon(if vertical {
            egui::CursorIcon::ResizeHorizontal
        } else {
            egui::CursorIcon::ResizeVertical
        });
        let stroke = ui.visuals().widgets.active.fg_stroke;
        if vertical {
            ui.painter().vline(at, rect.y_range(), stroke);
        } else {
            ui.painter().hline(rect.x_range(), at, stroke);
        }
    }
    let pos = resp.interact_pointer_pos()?;
    resp.dragged()
        .then_some(if vertical { pos.x } else { pos.y })
}

/// The load error: one bar that never takes more than a few lines (the message scrolls), with
/// Reload and × (hide it until the next error).
fn error_banner(ui: &mut egui::Ui, e: &str, cmds: &mut Vec<Command>) {
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
                if ui.button("Reload").clicked() {
                    cmds.push(Command::Reload);
                }
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

fn status_bar(ui: &mut egui::Ui, state: &AppState, views: &Views) {
    ui.horizontal(|ui| {
        if let Some(s) = state.scene() {
            let f = &s.features;
            ui.label(format!(
                "{} primitive{} ({}), {} light{}",
                f.primitives,
                if f.primitives == 1 { "" } else { "s" },
                f.kinds().join(", "),
                f.lights,
                if f.lights == 1 { "" } else { "s" }
            ));
            ui.separator();
        }
        if let Some(job) = &state.job {
            let p = job.live.progress();
            let phase = if state.prepared.is_none() {
                "preparing (building the BVH)".to_string()
            } else {
                format!("rendering {:.0}%", p * 100.0)
            };
            ui.add(
                egui::ProgressBar::new(p)
                    .desired_width(160.0)
                    .text(phase.clone()),
            );
            ui.label(phase);
        } else if let Some(r) = &state.rendered {
            ui.label(format!(
                "rendered in {:.2} s (build {:.0} ms, trace {:.0} ms, {:.2} Mrays/s, {} threads)",
                r.wall.as_secs_f64(),
                r.build.as_secs_f64() * 1e3,
                r.output.stats.trace.as_secs_f64() * 1e3,
                r.output.stats.mrays_per_s(),
                r.output.stats.threads
            ));
        }
        if let Some(p) = views.hovered {
            ui.separator();
            let colour = view::pixel_colour(state, p).unwrap_or_default();
            ui.label(format!("pixel ({}, {}) {colour}", p[0], p[1]));
        }
        if let Some(m) = &state.message {
            ui.separator();
            let t = RichText::new(&m.text);
            ui.label(if m.error {
                t.color(Color32::from_rgb(220, 50, 50))
            } else {
                t
            });
        }
    });
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

fn tree_panel(ui: &mut egui::Ui, state: &AppState, views: &mut Views, cmds: &mut Vec<Command>) {
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
    }
    if views
        .tree
        .as_ref()
        .is_none_or(|(g, _)| *g != state.trace_generation)
    {
        views.tree = Some((state.trace_generation, tree_rows(state)));
    }
    let Some((_, rows)) = views.tree.as_ref() else {
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
    if views.tree_scrolled != Some(target) {
        views.tree_scrolled = Some(target);
        if let Some(i) = rows
            .iter()
            .position(|r| matches!(r, Row::Step { k, .. } if *k == state.step))
        {
            let h = ui.available_height();
            area = area.vertical_scroll_offset((i as f32 * row_h - h * 0.4).max(0.0));
            views.tree_scroll_row = Some(i);
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

fn step_controls(ui: &mut egui::Ui, state: &AppState, cmds: &mut Vec<Command>) {
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
        if ui.button("⇤ First").clicked() {
            cmds.push(Command::Step(StepMove::First));
        }
        if ui.button("◀ Previous").clicked() {
            cmds.push(Command::Step(StepMove::Previous));
        }
        let play = if state.playing {
            "‖ Pause"
        } else {
            "▶ Play"
        };
        if ui.button(play).clicked() {
            cmds.push(Command::TogglePlay);
        }
        if ui.button("Next ▶").clicked() {
            cmds.push(Command::Step(StepMove::Next));
        }
        if ui.button("Last ⇥").clicked() {
            cmds.push(Command::Step(StepMove::Last));
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

/// The formula of the current step with the recorded numbers substituted.
fn math_panel(ui: &mut egui::Ui, state: &AppState) {
    let Some(s) = &state.stepping else {
        return;
    };
    let Some((ray, step)) = s.at(state.step) else {
        return;
    };
    let e = crate::explain::formula::explain(&s.trace, ray, &step.step);
    // On a projector the formulas are what the room reads: larger still than the UI's scale.
    let math_size = if state.prefs.presentation { 1.3 } else { 1.1 };
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

fn diagram_panel(ui: &mut egui::Ui, state: &AppState, views: &mut Views, cmds: &mut Vec<Command>) {
    ui.set_min_width(ui.available_width());
    let Some(s) = &state.stepping else {
        ui.label("The diagrams appear when a pixel is traced.");
        return;
    };
    let mut p = state.prefs.clone();
    let slice = state.diagram_kind() == Some(DiagramKind::Slice);
    // A short panel (a small window, presentation mode's large text) keeps its height for the
    // diagram: the kinds in a drop-down and the slice's controls on the same row.
    if ui.available_height() < COMPACT_DIAGRAM_CONTROLS_BELOW {
        ui.horizontal_wrapped(|ui| {
            let l = ui.label("Diagram");
            let chosen = match p.diagram {
                DiagramChoice::Auto => "Follow the step",
                DiagramChoice::Kind(k) => diagram_label(k),
            };
            egui::ComboBox::from_id_salt("diagram-kind")
                .selected_text(chosen)
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut p.diagram, DiagramChoice::Auto, "Follow the step");
                    for k in &s.kinds {
                        ui.selectable_value(
                            &mut p.diagram,
                            DiagramChoice::Kind(*k),
                            diagram_label(*k),
                        );
                    }
                })
                .response
                .labelled_by(l.id)
                .on_hover_text("which diagram to show");
            if slice {
                let l = ui.label("angle");
                ui.add(
                    egui::DragValue::new(&mut p.slice_angle)
                        .range(-180.0..=180.0)
                        .suffix("°"),
                )
                .labelled_by(l.id)
                .on_hover_text("turn the slice about the primary ray (drag or type)");
                ui.checkbox(&mut p.top_down, "from above");
            }
        });
    } else {
        ui.horizontal_wrapped(|ui| {
            ui.selectable_value(&mut p.diagram, DiagramChoice::Auto, "Follow the step");
            for k in &s.kinds {
                ui.selectable_value(&mut p.diagram, DiagramChoice::Kind(*k), diagram_label(*k));
            }
        });
        if slice {
            ui.horizontal_wrapped(|ui| {
                let l = ui.label("Slice angle");
                ui.add(egui::Slider::new(&mut p.slice_angle, -180.0..=180.0).suffix("°"))
                    .labelled_by(l.id);
                ui.checkbox(&mut p.top_down, "from above");
            });
        }
    }
    if p != state.prefs {
        cmds.push(Command::SetPrefs(p));
    }
    if views.gpu.available() {
        ui.toggle_value(&mut views.diagram_3d, "3D view here")
            .on_hover_text("the 3D view of the scene and the pixel's rays, beside the render");
    }
    if views.diagram_3d && views.gpu.available() {
        let rs = views.gpu.render_state.clone();
        super::scene3d::docked(ui, state, &mut views.scene3d_docked, rs.as_ref(), cmds);
        return;
    }
    let avail = ui.available_size();
    let ppp = ui.ctx().pixels_per_point();
    let size = [
        ((avail.x * ppp) as u32).clamp(64, 2048),
        ((avail.y * ppp) as u32).clamp(64, 2048),
    ];
    // Round to 8 pixels so a panel being resized does not redraw on every frame.
    let size = [size[0] / 8 * 8, size[1] / 8 * 8];
    match views.diagram(ui.ctx(), state, size) {
        Some(t) => {
            ui.add(
                egui::Image::new(&t)
                    .fit_to_exact_size(Vec2::new(size[0] as f32, size[1] as f32) / ppp),
            );
        }
        None => {
            ui.label(views.diagram_error.clone().unwrap_or_default());
        }
    }
}

/// Below this height (points) the diagram panel puts its controls on one compact row.
const COMPACT_DIAGRAM_CONTROLS_BELOW: f32 = 420.0;

fn diagram_label(k: DiagramKind) -> &'static str {
    match k {
        DiagramKind::Slice => "Slice",
        DiagramKind::Quadratic => "Quadratic",
        DiagramKind::Barycentric => "Barycentric",
        DiagramKind::Bvh => "BVH",
        DiagramKind::Raytree => "Ray tree",
    }
}

fn dialogs(ui: &mut egui::Ui, state: &AppState, cmds: &mut Vec<Command>) {
    let Some(d) = &state.dialog else {
        return;
    };
    let ctx = ui.ctx().clone();
    match d {
        Dialog::Open { path } => super::files::open_dialog(&ctx, state, path, cmds),
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
                    });
                    ui.horizontal(|ui| {
                        go |= ui.button("Save").clicked();
                        if ui.button("Cancel").clicked() {
                            cmds.push(Command::CloseDialog);
                        }
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
