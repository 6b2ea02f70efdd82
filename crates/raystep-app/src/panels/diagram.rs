//! The diagram panel (beside the render): which diagram to show, the slice's controls, and the
//! diagram of the current step drawn to a texture ([`DiagramPanel`] keeps it until something it
//! depends on changes) — or the 3D view docked in its place.

use crate::diagram::DiagramKind;
use crate::gpu_view::GpuView;
use crate::scene3d::{self, Scene3dView};
use crate::state::{AppState, Command, DiagramChoice};
use egui::{ColorImage, TextureHandle, TextureOptions, Vec2};

/// What the diagram panel keeps between frames (not persisted).
#[derive(Default)]
pub struct DiagramPanel {
    texture: Option<(TextureHandle, DiagramKey)>,
    /// The large view's texture ([`DiagramPanel::enlarged`]).
    large_texture: Option<(TextureHandle, DiagramKey)>,
    /// Show the diagram large, over the render and this panel (for a class: the hemisphere, the
    /// light's samples).
    pub enlarged: bool,
    /// Why the last diagram could not be drawn, if it could not.
    pub error: Option<String>,
    /// Show the docked 3D view in place of the diagram.
    pub show_3d: bool,
    /// The 3D view docked here, beside the render.
    pub docked: Scene3dView,
}

/// What a cached diagram texture shows.
#[derive(Debug, Clone, PartialEq)]
struct DiagramKey {
    generation: u64,
    kind: DiagramKind,
    step: usize,
    size: [u32; 2],
    theme: crate::state::ThemeChoice,
    angle: f32,
    top_down: bool,
    scale: f32,
}

impl DiagramPanel {
    /// The diagram texture for the current step at `size` (the panel's, or the large view's
    /// when `large`), drawn when anything it depends on changed.
    pub fn diagram(
        &mut self,
        ctx: &egui::Context,
        state: &AppState,
        size: [u32; 2],
        large: bool,
    ) -> Option<TextureHandle> {
        let s = state.stepping.as_ref()?;
        let kind = state.diagram_kind()?;
        let key = DiagramKey {
            generation: state.trace_generation,
            kind,
            step: state.step,
            size,
            theme: state.prefs.effective_theme(),
            angle: state.prefs.slice_angle,
            top_down: state.prefs.top_down,
            scale: ctx.pixels_per_point(),
        };
        let slot = if large {
            &mut self.large_texture
        } else {
            &mut self.texture
        };
        if let Some((t, k)) = slot
            && *k == key
        {
            return Some(t.clone());
        }
        // Diagram text follows the UI scale (presentation mode included).
        let opts = crate::diagram::ViewOptions {
            scale: ctx.pixels_per_point(),
            ..state.view_options(size[0], size[1])
        };
        match crate::diagram::draw(&s.trace, kind, &opts) {
            Ok(c) => {
                self.error = None;
                let img = ColorImage::from_rgba_premultiplied(
                    [c.pixmap.width() as usize, c.pixmap.height() as usize],
                    c.pixmap.data(),
                );
                let t = match slot.take() {
                    Some((mut t, _)) => {
                        t.set(img, TextureOptions::LINEAR);
                        t
                    }
                    None => ctx.load_texture("diagram", img, TextureOptions::LINEAR),
                };
                *slot = Some((t.clone(), key));
                Some(t)
            }
            Err(e) => {
                self.error = Some(e);
                None
            }
        }
    }
}

/// The diagram panel: the choice of diagram, its controls and the diagram (or the docked 3D
/// view, with the wgpu renderer).
pub fn panel(
    ui: &mut egui::Ui,
    state: &AppState,
    cache: &mut DiagramPanel,
    gpu: &GpuView,
    cmds: &mut Vec<Command>,
) {
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
            large_toggle(ui, &mut cache.enlarged);
        });
    } else {
        ui.horizontal_wrapped(|ui| {
            ui.selectable_value(&mut p.diagram, DiagramChoice::Auto, "Follow the step");
            for k in &s.kinds {
                ui.selectable_value(&mut p.diagram, DiagramChoice::Kind(*k), diagram_label(*k));
            }
            ui.separator();
            large_toggle(ui, &mut cache.enlarged);
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
    if gpu.available() {
        ui.toggle_value(&mut cache.show_3d, "3D view here")
            .on_hover_text("the 3D view of the scene and the pixel's rays, beside the render");
    }
    if cache.show_3d && gpu.available() {
        scene3d::docked(
            ui,
            state,
            &mut cache.docked,
            gpu.render_state.as_ref(),
            cmds,
        );
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
    match cache.diagram(ui.ctx(), state, size, false) {
        Some(t) => {
            ui.add(
                egui::Image::new(&t)
                    .fit_to_exact_size(Vec2::new(size[0] as f32, size[1] as f32) / ppp),
            );
        }
        None => {
            ui.label(cache.error.clone().unwrap_or_default());
        }
    }
}

/// The toggle that shows the diagram large ([`enlarged_view`]).
fn large_toggle(ui: &mut egui::Ui, enlarged: &mut bool) {
    ui.toggle_value(enlarged, "Large view").on_hover_text(
        "show this diagram large, over the render (click again, or ✕ on it, to put it back); \
         it follows the step",
    );
}

/// The diagram large ([`DiagramPanel::enlarged`]), in `area` (the render's and this panel's
/// space): a frame with the diagram drawn at that size, its text at the UI's scale, and a button
/// that puts it back.
pub fn enlarged_view(
    ctx: &egui::Context,
    state: &AppState,
    cache: &mut DiagramPanel,
    area: egui::Rect,
) {
    if !cache.enlarged || state.stepping.is_none() {
        return;
    }
    let mut keep = true;
    egui::Area::new(egui::Id::unique("diagram-large"))
        .fixed_pos(area.min)
        .order(egui::Order::Middle)
        .show(ctx, |ui| {
            egui::Frame::window(ui.style()).show(ui, |ui| {
                // Never negative, however small the window (a tiny window left less than the
                // frame's margins).
                let inner = (area.size() - Vec2::splat(24.0)).max(Vec2::ZERO);
                ui.set_min_size(inner);
                ui.set_max_size(inner);
                ui.horizontal(|ui| {
                    let kind = state.diagram_kind().map_or("Diagram", diagram_label);
                    ui.strong(format!("{kind}, large"));
                    if ui
                        .button("✕ Back to the panel")
                        .on_hover_text("put the diagram back in its panel")
                        .clicked()
                    {
                        keep = false;
                    }
                });
                let size = large_size(ui.available_size(), ctx);
                let ppp = ctx.pixels_per_point();
                match cache.diagram(ctx, state, size, true) {
                    Some(t) => {
                        ui.add(
                            egui::Image::new(&t)
                                .fit_to_exact_size(Vec2::new(size[0] as f32, size[1] as f32) / ppp),
                        );
                    }
                    None => {
                        ui.label(cache.error.clone().unwrap_or_default());
                    }
                }
            });
        });
    cache.enlarged = keep;
}

/// The large view's texture size (pixels) for `avail` points: the space at the UI's scale, made
/// smaller as a whole (never stretched) where a side would pass what the GPU's textures allow
/// (2048 on some devices, against 3000 and more of a 4K window), rounded to 8 pixels.
pub fn large_size(avail: Vec2, ctx: &egui::Context) -> [u32; 2] {
    let ppp = ctx.pixels_per_point();
    let max_side = ctx.input(|i| i.max_texture_side).clamp(64, 8192) as f32;
    let raw = [
        (avail.x * ppp).clamp(64.0, 1.0e5),
        (avail.y * ppp).clamp(64.0, 1.0e5),
    ];
    let k = (max_side / raw[0].max(raw[1])).min(1.0);
    raw.map(|v| ((v * k).round() as u32).clamp(64, max_side as u32) / 8 * 8)
}

/// Below this height (points) the diagram panel puts its controls on one compact row.
const COMPACT_DIAGRAM_CONTROLS_BELOW: f32 = 420.0;

fn diagram_label(k: DiagramKind) -> &'static str {
    match k {
        DiagramKind::Slice => "Slice",
        DiagramKind::Quadratic => "Quadratic",
        DiagramKind::Barycentric => "Barycentric",
        DiagramKind::Bvh => "BVH",
        DiagramKind::Tlas => "TLAS/BLAS",
        DiagramKind::Raytree => "Ray tree",
        DiagramKind::Hemisphere => "Hemisphere",
        DiagramKind::AreaLight => "Area light",
        DiagramKind::Samples => "Samples",
        DiagramKind::Texture => "Texture",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_large_view_fits_the_gpus_textures_without_stretching() {
        // A fresh context allows 2048-pixel textures at 1 pixel per point.
        let ctx = egui::Context::default();
        assert_eq!(ctx.input(|i| i.max_texture_side), 2048);
        assert_eq!(large_size(Vec2::new(800.0, 600.0), &ctx), [800, 600]);
        // 3424 × 2720 (the monkey's 4K window): scaled by 2048/3424 as a whole, 2720 → 1626.9
        // → 1624 after rounding down to 8.
        assert_eq!(large_size(Vec2::new(3424.0, 2720.0), &ctx), [2048, 1624]);
        assert_eq!(large_size(Vec2::new(3064.0, 80.0), &ctx), [2048, 64]);
        assert_eq!(large_size(Vec2::new(f32::NAN, 0.0), &ctx), [64, 64]);
    }
}
