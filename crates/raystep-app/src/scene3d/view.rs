//! The 3D view itself: its state ([`Scene3dView`]), the "3D view" tab with its toolbar, the
//! view docked beside the render, and the picture drawn by [`crate::view3d`] on eframe's own
//! wgpu device (drawn again only when what it shows changes).

use super::editor::editor_ui;
use super::picking::{Drag, gizmo, interact};
use crate::gpu::GpuContext;
use crate::record::Trace;
use crate::scene::Scene;
use crate::state::{AppState, Command};
use crate::view3d::camera::ViewCamera;
use crate::view3d::gpu::Renderer;
use crate::view3d::{self, Viewpoint, geometry};
use eframe::egui_wgpu::{self, wgpu};
use egui::{Color32, Pos2, Rect, RichText, Sense, Vec2};
use std::sync::Arc;
use std::time::Duration;

/// The largest side the 3D view draws at, in pixels (a software rasterizer takes ~40 ms per
/// megapixel; the picture is scaled up beyond it).
const MAX_DRAW_SIDE: f32 = 1600.0;
/// The fan of rays: an N×N grid of pixels.
pub const FAN: u32 = 8;

/// What the picture shows, to draw again only when it changes.
#[derive(Debug, Clone, PartialEq)]
struct DrawKey {
    scene: usize,
    trace: u64,
    step: usize,
    viewpoint: Viewpoint,
    size: [u32; 2],
    options: (bool, bool, bool, Option<u32>, bool),
}

/// The 3D view's state (held by [`crate::panels::Panels`]: the tab's and the docked one).
#[derive(Default)]
pub struct Scene3dView {
    /// Where the view looks from.
    pub viewpoint: Viewpoint,
    /// Show the rays of an 8×8 grid of pixels too.
    pub fan: bool,
    /// Show the BVH boxes the current ray visited so far.
    pub bvh: bool,
    /// Draw the objects translucent.
    pub see_through: bool,
    /// Show the editor beside the view.
    pub editor: bool,
    renderer: Option<Result<Renderer, String>>,
    texture: Option<egui::TextureId>,
    key: Option<DrawKey>,
    fan_cache: Option<(usize, Arc<Vec<Trace>>)>,
    pub(super) drag: Option<Drag>,
    /// The view camera of the last frame and where the picture was drawn (screen points).
    pub last_view: Option<(ViewCamera, Rect)>,
    /// How long the last draw took (submit to completion).
    pub frame_time: Option<Duration>,
    /// How many draws were made (tests watch it).
    pub draws: u64,
    /// The rays the last draw showed (tests check stepping changes them).
    pub drawn_rays: usize,
    /// The selected object's move handles on screen last frame: its centre and the x, y and z
    /// arrows' tips (points).
    pub gizmo: Option<(Pos2, [Pos2; 3])>,
}

impl Scene3dView {
    fn renderer(&mut self, rs: &egui_wgpu::RenderState) -> Result<&mut Renderer, String> {
        let r = self.renderer.get_or_insert_with(|| {
            let ctx = GpuContext::from_device(
                rs.device.clone(),
                rs.queue.clone(),
                rs.adapter.get_info(),
                rs.adapter.features(),
            );
            Renderer::new(ctx).map_err(|e| e.to_string())
        });
        r.as_mut().map_err(|e| e.clone())
    }

    /// The fan's traces for the prepared scene, recorded once per scene and settings.
    fn fan(&mut self, state: &AppState) -> Arc<Vec<Trace>> {
        let Some(p) = &state.prepared else {
            return Arc::default();
        };
        let key = Arc::as_ptr(p) as usize;
        match &self.fan_cache {
            Some((k, t)) if *k == key => Arc::clone(t),
            _ => {
                let t = Arc::new(view3d::fan_traces(p, FAN));
                self.fan_cache = Some((key, Arc::clone(&t)));
                t
            }
        }
    }
}

/// The "3D view" tab.
pub fn tab(
    ui: &mut egui::Ui,
    state: &AppState,
    view: &mut Scene3dView,
    render_state: Option<&egui_wgpu::RenderState>,
    cmds: &mut Vec<Command>,
) {
    let Some(rs) = render_state else {
        ui.label("The 3D view needs the wgpu renderer.");
        return;
    };
    let Some(scene) = state.scene().cloned() else {
        ui.label("Open a scene to see it in 3D.");
        return;
    };
    toolbar(ui, state, view);
    let avail = ui.available_rect_before_wrap();
    let editor_w = if view.editor {
        (avail.width() * 0.34).clamp(200.0, 320.0)
    } else {
        0.0
    };
    let picture = Rect::from_min_max(
        avail.min,
        Pos2::new((avail.max.x - editor_w).max(avail.min.x + 1.0), avail.max.y),
    );
    picture_ui(ui, state, &scene, view, rs, picture, cmds);
    if view.editor && editor_w > 0.0 {
        let r = Rect::from_min_max(Pos2::new(picture.max.x + 6.0, avail.min.y), avail.max);
        let mut child = ui.new_child(
            egui::UiBuilder::new()
                .max_rect(r)
                .layout(egui::Layout::top_down(egui::Align::Min)),
        );
        egui::ScrollArea::vertical()
            .id_salt("scene editor")
            .auto_shrink([false, false])
            .show(&mut child, |ui| editor_ui(ui, state, &scene, cmds));
    }
    ui.allocate_rect(avail, Sense::hover());
}

/// The 3D view docked in the diagram panel, beside the render: the picture with a short row of
/// switches (the editor stays in the tab; the move arrows work here too).
pub fn docked(
    ui: &mut egui::Ui,
    state: &AppState,
    view: &mut Scene3dView,
    render_state: Option<&egui_wgpu::RenderState>,
    cmds: &mut Vec<Command>,
) {
    let (Some(rs), Some(scene)) = (render_state, state.scene().cloned()) else {
        ui.label("Open a scene to see it in 3D.");
        return;
    };
    ui.horizontal_wrapped(|ui| {
        let mut through = view.viewpoint == Viewpoint::Camera;
        if ui
            .toggle_value(&mut through, "Through the camera")
            .changed()
        {
            view.viewpoint = if through {
                Viewpoint::Camera
            } else {
                Viewpoint::default()
            };
        }
        ui.toggle_value(&mut view.fan, "8×8 rays");
        ui.checkbox(&mut view.see_through, "See-through");
    });
    let rect = ui.available_rect_before_wrap();
    picture_ui(ui, state, &scene, view, rs, rect, cmds);
    ui.allocate_rect(rect, Sense::hover());
}

fn toolbar(ui: &mut egui::Ui, state: &AppState, view: &mut Scene3dView) {
    ui.horizontal_wrapped(|ui| {
        let mut through = view.viewpoint == Viewpoint::Camera;
        if ui
            .toggle_value(&mut through, "Look through the camera")
            .on_hover_text("the view matches the render: the pixel's ray lands on the pixel")
            .changed()
        {
            view.viewpoint = if through {
                Viewpoint::Camera
            } else {
                Viewpoint::default()
            };
        }
        ui.toggle_value(&mut view.fan, "Rays of 8×8 pixels")
            .on_hover_text(
                "the camera's fan: the primary rays of a grid of pixels and their trees",
            );
        let has_bvh = state
            .stepping
            .as_ref()
            .is_some_and(|s| s.trace.bvh.is_some());
        ui.add_enabled(has_bvh, egui::Checkbox::new(&mut view.bvh, "BVH boxes"))
            .on_hover_text("the boxes the current ray has visited so far (culled ones faint)");
        ui.checkbox(&mut view.see_through, "See-through")
            .on_hover_text("draw the objects translucent, to see the rays inside them");
        ui.toggle_value(&mut view.editor, "Edit")
            .on_hover_text("move objects, change radii, materials and lights; undo, redo, save");
        if ui
            .add_enabled(
                view.viewpoint != Viewpoint::default(),
                egui::Button::new("Reset view"),
            )
            .clicked()
        {
            view.viewpoint = Viewpoint::default();
        }
    });
    if let Some(d) = view.frame_time {
        ui.label(
            RichText::new(format!(
                "drawn in {:.1} ms · drag: orbit · right-drag: pan · scroll: zoom · click: select · drag an arrow: move",
                d.as_secs_f64() * 1e3
            ))
            .small(),
        );
    }
}

#[allow(clippy::too_many_arguments)]
fn picture_ui(
    ui: &mut egui::Ui,
    state: &AppState,
    scene: &Arc<Scene>,
    view: &mut Scene3dView,
    rs: &egui_wgpu::RenderState,
    rect: Rect,
    cmds: &mut Vec<Command>,
) {
    if rect.width() < 8.0 || rect.height() < 8.0 {
        return;
    }
    let ppp = ui.ctx().pixels_per_point();
    let scale = (MAX_DRAW_SIDE / (rect.width().max(rect.height()) * ppp)).min(1.0);
    let size = [
        ((rect.width() * ppp * scale).round() as u32).clamp(1, view3d::gpu::MAX_SIDE),
        ((rect.height() * ppp * scale).round() as u32).clamp(1, view3d::gpu::MAX_SIDE),
    ];
    let bounds = geometry::bounds(scene);
    let aspect = rect.width() / rect.height();
    let cam = view.viewpoint.camera(&scene.camera, &bounds, aspect);
    // Looking through the camera draws the picture at the image's proportions, as the render.
    let rect = if view.viewpoint == Viewpoint::Camera {
        let ia = scene.camera.width as f32 / scene.camera.height.max(1) as f32;
        let (w, h) = if aspect > ia {
            (rect.height() * ia, rect.height())
        } else {
            (rect.width(), rect.width() / ia)
        };
        Rect::from_center_size(rect.center(), Vec2::new(w, h))
    } else {
        rect
    };
    let size = if view.viewpoint == Viewpoint::Camera {
        let s = (rect.width() * ppp * scale).max(1.0) / size[0].max(1) as f32;
        [
            ((size[0] as f32 * s).round() as u32).clamp(1, view3d::gpu::MAX_SIDE),
            ((rect.height() * ppp * scale).round() as u32).clamp(1, view3d::gpu::MAX_SIDE),
        ]
    } else {
        size
    };
    let response = ui.allocate_rect(rect, Sense::click_and_drag());
    view.last_view = Some((cam, rect));
    let trace = state.stepping.as_ref().map(|s| Arc::clone(&s.trace));
    let key = DrawKey {
        scene: Arc::as_ptr(scene) as usize,
        trace: state.trace_generation,
        step: state.step,
        viewpoint: view.viewpoint,
        size,
        options: (
            view.fan,
            view.bvh,
            view.see_through,
            state.selected,
            ui.visuals().dark_mode,
        ),
    };
    if view.key.as_ref() != Some(&key) || view.texture.is_none() {
        let fan = if view.fan {
            view.fan(state)
        } else {
            Arc::default()
        };
        let options = geometry::Options {
            step: trace.as_ref().map(|_| state.step),
            bvh: view.bvh,
            see_through: view.see_through,
            selected: state.selected,
            theme: state.prefs.effective_theme().diagram_theme(),
            eye: Some(cam.eye.to_array()),
            camera: view.viewpoint != Viewpoint::Camera,
        };
        let g = geometry::build(scene, trace.as_deref(), &fan, &options);
        let bg = options.theme.background.map(|v| f32::from(v) / 255.0);
        let drawn = view.renderer(rs).and_then(|r| {
            r.draw(&g, &cam, size, bg)
                .map_err(|e| e.to_string())
                .map(|n| (n, r.last_frame))
        });
        match drawn {
            Ok((_, t)) => {
                view.frame_time = Some(t);
                view.draws += 1;
                view.drawn_rays = g.rays.len();
                if let Some(Ok(r)) = &view.renderer
                    && let Some(tv) = r.view()
                {
                    let mut renderer = rs.renderer.write();
                    match view.texture {
                        Some(id) => renderer.update_egui_texture_from_wgpu_texture(
                            &rs.device,
                            tv,
                            wgpu::FilterMode::Linear,
                            id,
                        ),
                        None => {
                            view.texture = Some(renderer.register_native_texture(
                                &rs.device,
                                tv,
                                wgpu::FilterMode::Linear,
                            ))
                        }
                    }
                }
                view.key = Some(key);
            }
            Err(e) => {
                ui.painter().text(
                    rect.center(),
                    egui::Align2::CENTER_CENTER,
                    format!("3D view: {e}"),
                    egui::FontId::proportional(14.0),
                    ui.visuals().error_fg_color,
                );
                return;
            }
        }
    }
    if let Some(id) = view.texture {
        ui.painter().image(
            id,
            rect,
            Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)),
            Color32::WHITE,
        );
    }
    let handles = state
        .selected
        .filter(|_| state.editor.is_some())
        .and_then(|g| gizmo(ui, scene, g, &cam, rect));
    view.gizmo = handles.as_ref().map(|h| (h.center, h.ends));
    interact(
        ui,
        state,
        scene,
        (&mut view.drag, &mut view.viewpoint),
        &response,
        rect,
        &cam,
        handles.as_ref(),
        cmds,
    );
}
