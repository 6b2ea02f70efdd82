//! The panels: read-only views of [`AppState`] that return [`Command`]s. Panels and settings
//! that do not apply to the open scene are left out, not greyed (no triangle method for a
//! sphere-only scene, no recursion depth without mirrors or glass, no heatmap without a BVH).
//!
//! Each panel has its own module, with what it keeps between frames: [`menu`] (the menu bar),
//! [`status`] (the status bar and the load-error banner), [`steps`] (the step controls and the
//! timeline), [`learn`] (lessons and exercises), [`settings`], [`tree`] (the trace tree),
//! [`diagram`] and [`math`] (the explain panel on the right), and [`dialogs`]. The render view
//! is [`super::view`], the GPU tabs [`super::gpu_view`], the 3D view [`super::scene3d`], the
//! lab window [`super::lab`]. [`show`] lays them out.

pub mod diagram;
pub mod dialogs;
pub mod learn;
pub mod math;
pub mod menu;
pub mod settings;
pub mod status;
pub mod steps;
pub mod tree;

use super::gpu_view::{self, CentralTab, GpuView};
use super::lab::LabView;
use super::layout::Side;
use super::scene3d::{self, Scene3dView};
use super::state::{AppState, Command, Document};
use super::view::{self, RenderView};
use egui::Sense;

/// What the panels keep between frames, each panel's in its own struct (nothing here is
/// persisted; the render view's is [`RenderView`]).
#[derive(Default)]
pub struct Panels {
    /// The trace tree's rows and scroll position.
    pub tree: tree::TreePanel,
    /// The diagram's texture and the docked 3D view.
    pub diagram: diagram::DiagramPanel,
    /// The lesson viewer's Markdown cache.
    pub learn: learn::LearnPanel,
    /// The GPU view (and which tab the central panel shows).
    pub gpu: GpuView,
    /// The "3D view" tab.
    pub scene3d: Scene3dView,
    /// The stability lab window.
    pub lab: LabView,
    /// F11 or the menu asked to toggle full screen (the app does it after the frame).
    pub toggle_fullscreen: bool,
    /// The whole window last frame, in points.
    pub window_rect: Option<egui::Rect>,
    /// The space the central view (the render) had last frame, in points.
    pub centre_rect: Option<egui::Rect>,
    /// The side panels' rects last frame (name, rect), in points.
    pub panel_rects: Vec<(&'static str, egui::Rect)>,
}

/// Draws the whole window: the menu, the banner and the bars along the edges, the side panels,
/// the central view, then the dialogs and the lab window over them.
pub fn show(
    ui: &mut egui::Ui,
    state: &AppState,
    render: &mut RenderView,
    panels: &mut Panels,
    cmds: &mut Vec<Command>,
) {
    let window = ui.available_rect_before_wrap();
    panels.window_rect = Some(window);
    if let Some(full) = &state.embed {
        return embedded(ui, state, render, panels, full, cmds);
    }
    egui::Panel::top("menu").show(ui, |ui| menu::menu_bar(ui, state, render, panels, cmds));
    if let Some(e) = &state.load_error {
        egui::Panel::top("load-error").show(ui, |ui| status::error_banner(ui, state, e, cmds));
    }
    if let Some(scene) = state.scene()
        && !scene.warnings.is_empty()
    {
        egui::Panel::top("load-warnings").show(ui, |ui| load_warnings(ui, &scene.warnings));
    }
    egui::Panel::bottom("status").show(ui, |ui| status::status_bar(ui, state, render));
    if state.stepping.is_some() {
        egui::Panel::bottom("steps").show(ui, |ui| steps::controls(ui, state, cmds));
    }
    side_panels(ui, window.width(), state, render, panels, cmds);
    panels.centre_rect = Some(ui.available_rect_before_wrap());
    egui::CentralPanel::default().show(ui, |ui| central(ui, state, render, panels, cmds));
    // The diagram large, over the render and the explain panel.
    if let Some(centre) = panels.centre_rect {
        let explain = panels
            .panel_rects
            .iter()
            .find(|(n, _)| *n == "explain")
            .map(|(_, r)| *r);
        let area = explain.map_or(centre, |e| centre.union(e));
        diagram::enlarged_view(ui.ctx(), state, &mut panels.diagram, area);
    }
    dialogs::show(ui, state, cmds);
    super::lab::window(ui.ctx(), state, &mut panels.lab, cmds);
}

/// The compact window a page embeds (the book's live figures, `#embed&…`): a line naming the
/// moment with a link to the full app there, the render, the step controls, and the diagram
/// beside the render (below it in a narrow frame). No menu, settings or trace tree.
fn embedded(
    ui: &mut egui::Ui,
    state: &AppState,
    render: &mut RenderView,
    panels: &mut Panels,
    full: &str,
    cmds: &mut Vec<Command>,
) {
    let window = ui.available_rect_before_wrap();
    egui::Panel::top("embed-title").show(ui, |ui| {
        ui.horizontal_wrapped(|ui| {
            let scene = state.scene().map_or(String::new(), |s| s.name.clone());
            let at = state
                .pixel
                .map_or(String::new(), |[x, y]| format!(" · pixel ({x}, {y})"));
            ui.label(egui::RichText::new(format!("raystep · {scene}{at}")).strong());
            ui.add(
                egui::Hyperlink::from_label_and_url("Open in the full app ↗", full)
                    .open_in_new_tab(true),
            );
        });
    });
    if let Some(e) = &state.load_error {
        egui::Panel::top("load-error").show(ui, |ui| status::error_banner(ui, state, e, cmds));
    }
    if state.stepping.is_some() {
        egui::Panel::bottom("steps").show(ui, |ui| steps::controls(ui, state, cmds));
    }
    let wide = window.width() >= 560.0;
    let diagram = |ui: &mut egui::Ui, panels: &mut Panels, cmds: &mut Vec<Command>| {
        contained(ui, |ui| {
            diagram::panel(ui, state, &mut panels.diagram, &panels.gpu, cmds)
        })
    };
    if wide {
        egui::Panel::right("embed-diagram")
            .resizable(false)
            .exact_size(window.width() * 0.45)
            .show(ui, |ui| diagram(ui, panels, cmds));
    } else {
        egui::Panel::bottom("embed-diagram")
            .resizable(false)
            .exact_size(window.height() * 0.35)
            .show(ui, |ui| diagram(ui, panels, cmds));
    }
    panels.centre_rect = Some(ui.available_rect_before_wrap());
    egui::CentralPanel::default().show(ui, |ui| view::render_view(ui, state, render, cmds));
}

/// What loading the scene left out or added (a glTF file's unread features, a framed view, a
/// headlight), folded under one line.
fn load_warnings(ui: &mut egui::Ui, warnings: &[String]) {
    let n = warnings.len();
    egui::CollapsingHeader::new(format!(
        "⚠ {n} note{} on loading this scene",
        if n == 1 { "" } else { "s" }
    ))
    .id_salt("load-warnings")
    .show(ui, |ui| {
        for w in warnings {
            ui.label(w);
        }
    });
}

/// The side panels: the lessons, the settings and the trace tree on the left, the explain panel
/// (the diagram over the math) on the right. They take the widths
/// [`super::layout::Layout::widths`] computes from the window's width every frame (so they
/// follow the window and can never squeeze the render below its share); their edges are
/// dragged with handles drawn here. `width` is the window's.
fn side_panels(
    ui: &mut egui::Ui,
    width: f32,
    state: &AppState,
    render: &RenderView,
    panels: &mut Panels,
    cmds: &mut Vec<Command>,
) {
    let mut rects: Vec<(&'static str, egui::Rect)> = vec![];
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
            learn::panel(ui, state, &mut panels.learn, cmds)
        });
    }
    if state.prefs.show_settings {
        left_panel(ui, Side::Settings, "settings", true, &mut |ui| {
            egui::ScrollArea::vertical()
                .id_salt("settings-scroll")
                .auto_shrink([false, false])
                .show(ui, |ui| settings::settings_panel(ui, state, render, cmds));
        });
    }
    let mut math_drag = None;
    // A Monte Carlo pixel's diagrams get their own share of the height.
    let sampling = state
        .stepping
        .as_ref()
        .is_some_and(|s| s.trace.monte_carlo.is_some());
    let r = egui::Panel::right("explain")
        .resizable(false)
        .exact_size(width_of(Side::Explain))
        .show(ui, |ui| {
            contained(ui, |ui| {
                let height = ui.available_height();
                let r = egui::Panel::bottom("math")
                    .resizable(false)
                    .exact_size(layout.math_height(height, sampling))
                    .show(ui, |ui| {
                        egui::ScrollArea::vertical()
                            .id_salt("math-scroll")
                            .auto_shrink([false, false])
                            .show(ui, |ui| math::panel(ui, state));
                    });
                let rect = r.response.rect;
                if let Some(y) = resize_handle(ui, "math", rect.top(), rect, false) {
                    math_drag = Some((rect.bottom() - y, height));
                }
                egui::CentralPanel::default().show(ui, |ui| {
                    diagram::panel(ui, state, &mut panels.diagram, &panels.gpu, cmds)
                });
            })
        });
    let rect = r.response.rect;
    rects.push(("explain", rect));
    if let Some(x) = resize_handle(ui, "explain", rect.left(), rect, true) {
        drag = Some((Side::Explain, rect.right() - x));
    }
    if state.prefs.show_tree {
        let r = egui::Panel::left("tree")
            .resizable(false)
            .exact_size(width_of(Side::Tree))
            .show(ui, |ui| {
                contained(ui, |ui| tree::panel(ui, state, &mut panels.tree, cmds))
            });
        let rect = r.response.rect;
        rects.push(("tree", rect));
        if !layout.tree_collapsed
            && let Some(x) = resize_handle(ui, "tree", rect.right(), rect, true)
        {
            drag = Some((Side::Tree, x - rect.left()));
        }
    }
    let mut p = state.prefs.clone();
    if let Some((side, wanted)) = drag {
        p.layout.drag(side, wanted, width, others(side));
    }
    if let Some((wanted, height)) = math_drag {
        p.layout.drag_math(wanted, height, sampling);
    }
    if p != state.prefs {
        cmds.push(Command::SetPrefs(p));
    }
    panels.panel_rects = rects;
}

/// The central view: the render (or, with the wgpu renderer, the tabs over it: the GPU render,
/// the difference, the 3D view); a saved trace opened without its scene says so instead.
fn central(
    ui: &mut egui::Ui,
    state: &AppState,
    render: &mut RenderView,
    panels: &mut Panels,
    cmds: &mut Vec<Command>,
) {
    if let Document::Trace { path } = &state.doc {
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
        return;
    }
    if !panels.gpu.available() {
        return view::render_view(ui, state, render, cmds);
    }
    gpu_view::tabs(ui, &mut panels.gpu);
    match panels.gpu.tab {
        CentralTab::Cpu => view::render_view(ui, state, render, cmds),
        CentralTab::Gpu => gpu_view::gpu_tab(ui, state, &mut panels.gpu, cmds),
        CentralTab::Difference => gpu_view::difference_tab(ui, state, &mut panels.gpu, cmds),
        CentralTab::Scene3d => scene3d::tab(
            ui,
            state,
            &mut panels.scene3d,
            panels.gpu.render_state.as_ref(),
            cmds,
        ),
    }
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
