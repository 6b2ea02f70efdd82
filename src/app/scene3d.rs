//! The 3D view in the app (the central panel's "3D view" tab): the scene in space with the
//! camera, its image plane and the selected pixel's rays up to the current step, drawn by
//! [`crate::view3d`] on eframe's own wgpu device. Drag to orbit, right-drag to pan, scroll to
//! zoom, double-click to reset; click an object to select it and drag the coloured arrows to
//! move it; the editor beside the view changes radii, materials and lights, with undo, redo and
//! save. Every edit re-traces the pixel and restarts the render.

use super::state::editing::EditCmd;
use super::state::{AppState, Command};
use crate::accel::Accelerator;
use crate::gpu::GpuContext;
use crate::record::{Silent, Trace};
use crate::scene::edit::{Edit, LightField, MaterialField, MaterialValue};
use crate::scene::{Scene, Shape};
use crate::view3d::camera::{Orbit, ViewCamera};
use crate::view3d::gpu::Renderer;
use crate::view3d::{self, Viewpoint, geometry};
use eframe::egui_wgpu::{self, wgpu};
use egui::{Color32, Pos2, Rect, RichText, Sense, Stroke, Vec2};
use glam::Vec3;
use std::sync::Arc;
use std::time::Duration;

/// The largest side the 3D view draws at, in pixels (a software rasterizer takes ~40 ms per
/// megapixel; the picture is scaled up beyond it).
const MAX_DRAW_SIDE: f32 = 1600.0;
/// The fan of rays: an N×N grid of pixels.
pub const FAN: u32 = 8;

/// What a drag is doing.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Drag {
    Orbit,
    Pan,
    /// Moving the selected object along `axis`: the axis's direction on screen (unit, points)
    /// and the world length of one point along it.
    Axis {
        axis: usize,
        screen_dir: Vec2,
        world_per_point: f32,
    },
}

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

/// The 3D view's state (part of [`super::view::Views`]).
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
    drag: Option<Drag>,
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
        view,
        &response,
        rect,
        &cam,
        handles.as_ref(),
        cmds,
    );
}

/// The selected object's move handles: its centre and, per axis, the arrow's end on screen.
struct Handles {
    group: u32,
    center: Pos2,
    ends: [Pos2; 3],
    world_len: f32,
}

/// Where an object group is, for its handles: a sphere's centre, the mean of triangle vertices,
/// a plane's point nearest the scene's centre.
fn group_center(scene: &Scene, group: u32) -> Option<Vec3> {
    let g = scene.groups.get(group as usize)?;
    let objs = scene
        .objects
        .get(g.first as usize..(g.first + g.count) as usize)?;
    let mut sum = Vec3::ZERO;
    let mut n = 0.0;
    let b = geometry::bounds(scene);
    for o in objs {
        match o.shape {
            Shape::Sphere { center, .. } => {
                sum += center;
                n += 1.0;
            }
            Shape::Triangle { p } => {
                sum += p[0] + p[1] + p[2];
                n += 3.0;
            }
            Shape::Plane { normal, offset } => {
                sum += b.center - normal * (normal.dot(b.center) - offset);
                n += 1.0;
            }
            Shape::AxisPlane { axis, offset } => {
                let mut c = b.center;
                c[axis.min(2)] = offset;
                sum += c;
                n += 1.0;
            }
        }
    }
    (n > 0.0).then(|| sum / n).filter(|c| c.is_finite())
}

const AXIS_COLORS: [Color32; 3] = [
    Color32::from_rgb(230, 70, 60),
    Color32::from_rgb(80, 200, 90),
    Color32::from_rgb(70, 130, 240),
];

fn gizmo(
    ui: &egui::Ui,
    scene: &Scene,
    group: u32,
    cam: &ViewCamera,
    rect: Rect,
) -> Option<Handles> {
    let c = group_center(scene, group)?;
    let to_screen = |p: Vec3| {
        cam.project(p, rect.width(), rect.height())
            .map(|[x, y]| rect.min + Vec2::new(x, y))
    };
    let center = to_screen(c)?;
    let world_len = cam.world_per_pixel(c, rect.height()) * 70.0;
    let mut ends = [center; 3];
    for (i, axis) in [Vec3::X, Vec3::Y, Vec3::Z].into_iter().enumerate() {
        ends[i] = to_screen(c + axis * world_len)?;
        ui.painter()
            .arrow(center, ends[i] - center, Stroke::new(4.0, AXIS_COLORS[i]));
        ui.painter().text(
            ends[i],
            egui::Align2::LEFT_BOTTOM,
            ["x", "y", "z"][i],
            egui::FontId::proportional(14.0),
            AXIS_COLORS[i],
        );
    }
    ui.painter().circle_filled(center, 4.0, Color32::WHITE);
    Some(Handles {
        group,
        center,
        ends,
        world_len,
    })
}

fn distance_to_segment(p: Pos2, a: Pos2, b: Pos2) -> f32 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_sq().max(1e-6)).clamp(0.0, 1.0);
    (a + ab * t - p).length()
}

#[allow(clippy::too_many_arguments)]
fn interact(
    ui: &egui::Ui,
    state: &AppState,
    scene: &Scene,
    view: &mut Scene3dView,
    response: &egui::Response,
    rect: Rect,
    cam: &ViewCamera,
    handles: Option<&Handles>,
    cmds: &mut Vec<Command>,
) {
    if response.drag_started() {
        let pointer = response.interact_pointer_pos();
        let secondary = ui.input(|i| {
            i.pointer.button_down(egui::PointerButton::Secondary)
                || i.pointer.button_down(egui::PointerButton::Middle)
        });
        let axis = handles.zip(pointer).and_then(|(h, p)| {
            (0..3)
                .map(|i| (i, distance_to_segment(p, h.center, h.ends[i])))
                .filter(|(_, d)| *d < 10.0)
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(i, _)| (i, h))
        });
        view.drag = Some(match axis {
            Some((i, h)) => {
                let screen = h.ends[i] - h.center;
                let len = screen.length().max(1.0);
                cmds.push(Command::Edit(EditCmd::BeginGesture));
                Drag::Axis {
                    axis: i,
                    screen_dir: screen / len,
                    world_per_point: h.world_len / len,
                }
            }
            None if secondary => Drag::Pan,
            None => Drag::Orbit,
        });
    }
    let delta = response.drag_delta();
    if let Some(d) = view.drag
        && delta != Vec2::ZERO
    {
        match d {
            Drag::Orbit => {
                let mut o = match view.viewpoint {
                    Viewpoint::Orbit(o) => o,
                    Viewpoint::Camera => Orbit::default(),
                };
                o.yaw -= delta.x * 0.4;
                o.pitch += delta.y * 0.4;
                view.viewpoint = Viewpoint::Orbit(o.sanitized());
            }
            Drag::Pan => {
                if let Viewpoint::Orbit(mut o) = view.viewpoint {
                    let (u, v, _) = cam.basis();
                    let k = cam.world_per_pixel(cam.target, rect.height());
                    let shift = (u * -delta.x + v * delta.y) * k;
                    o.pan = (Vec3::from(o.pan) + shift).to_array();
                    view.viewpoint = Viewpoint::Orbit(o.sanitized());
                }
            }
            Drag::Axis {
                axis,
                screen_dir,
                world_per_point,
            } => {
                let amount = delta.dot(screen_dir) * world_per_point;
                if let Some(g) = state.selected
                    && amount.is_finite()
                    && amount != 0.0
                {
                    let mut by = [0.0; 3];
                    by[axis] = f64::from(amount);
                    cmds.push(Command::Edit(EditCmd::Apply(Edit::Move { group: g, by })));
                }
            }
        }
    }
    if response.drag_stopped() {
        if matches!(view.drag, Some(Drag::Axis { .. })) {
            cmds.push(Command::Edit(EditCmd::EndGesture));
        }
        view.drag = None;
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0
            && let Viewpoint::Orbit(mut o) = view.viewpoint
        {
            o.distance *= (-scroll * 0.002).exp();
            view.viewpoint = Viewpoint::Orbit(o.sanitized());
        }
    }
    if response.double_clicked() {
        view.viewpoint = Viewpoint::default();
    } else if response.clicked()
        && let Some(p) = response.interact_pointer_pos()
    {
        let at = p - rect.min;
        let picked = pick(state, scene, cam, [at.x, at.y], rect);
        if picked != state.selected {
            cmds.push(Command::Edit(EditCmd::Select(picked)));
        }
    }
    let _ = handles.map(|h| h.group);
}

/// The object group under a point of the picture, found by raystep's own closest-hit search.
/// A plane between the eye and the scene is drawn as an outline only, so the pick passes
/// through it.
fn pick(
    state: &AppState,
    scene: &Scene,
    cam: &ViewCamera,
    at: [f32; 2],
    rect: Rect,
) -> Option<u32> {
    let p = state.prepared.as_ref()?;
    let (origin, dir) = cam.ray_through(at, rect.width(), rect.height());
    let (lo, hi) = geometry::scene_box(scene);
    let mid = (lo + hi) * 0.5;
    let mut t_min = 0.0f32;
    for _ in 0..16 {
        let ray = crate::math::Ray::new(origin, dir, t_min, f32::INFINITY).ok()?;
        let hit = p.accel().closest(p.scene(), &ray, &mut Silent)?;
        let o = scene.objects.get(hit.object as usize)?;
        let hides = match o.shape {
            Shape::Plane { normal, offset } => {
                (normal.dot(cam.eye) - offset) * (normal.dot(mid) - offset) < 0.0
            }
            Shape::AxisPlane { axis, offset } => {
                let a = axis.min(2);
                (cam.eye[a] - offset) * (mid[a] - offset) < 0.0
            }
            _ => false,
        };
        if !hides {
            return Some(o.group);
        }
        t_min = hit.t * (1.0 + 1e-4) + 1e-6;
    }
    None
}

/// The editor beside the view: undo, redo, save; the selected object's place, size and
/// material; the lights.
fn editor_ui(ui: &mut egui::Ui, state: &AppState, scene: &Scene, cmds: &mut Vec<Command>) {
    let Some(editor) = &state.editor else {
        ui.label("This scene cannot be edited: it was not opened from a scene file.");
        return;
    };
    ui.horizontal_wrapped(|ui| {
        if ui
            .add_enabled(editor.can_undo(), egui::Button::new("⟲ Undo"))
            .on_hover_text("Ctrl+Z")
            .clicked()
        {
            cmds.push(Command::Edit(EditCmd::Undo));
        }
        if ui
            .add_enabled(editor.can_redo(), egui::Button::new("⟳ Redo"))
            .on_hover_text("Ctrl+Shift+Z")
            .clicked()
        {
            cmds.push(Command::Edit(EditCmd::Redo));
        }
        if ui
            .button("Save")
            .on_hover_text("Ctrl+S: write the scene file back, comments kept")
            .clicked()
        {
            cmds.push(Command::Edit(EditCmd::Save(None)));
        }
        if ui.button("Save as…").clicked() {
            cmds.push(Command::ShowDialog(super::state::Dialog::Save {
                kind: super::state::SaveKind::Scene,
                path: state.suggested_name(super::state::SaveKind::Scene),
            }));
        }
    });
    if editor.dirty() {
        ui.colored_label(ui.visuals().warn_fg_color, "● unsaved changes");
    }
    ui.separator();
    let name = |g: u32| {
        scene
            .groups
            .get(g as usize)
            .map_or("?".into(), |g| g.name.clone())
    };
    let label = ui.label("Object");
    egui::ComboBox::from_id_salt("selected object")
        .selected_text(state.selected.map_or("(none — click one)".into(), name))
        .width(ui.available_width().min(240.0))
        .show_ui(ui, |ui| {
            for g in 0..scene.groups.len().min(2000) as u32 {
                if ui
                    .selectable_label(state.selected == Some(g), name(g))
                    .clicked()
                {
                    cmds.push(Command::Edit(EditCmd::Select(Some(g))));
                }
            }
        })
        .response
        .labelled_by(label.id);
    if let Some(g) = state.selected {
        object_ui(ui, state, scene, g, cmds);
    }
    ui.separator();
    ui.label(RichText::new("Lights").strong());
    for (i, l) in scene.lights.iter().enumerate() {
        ui.label(&l.name);
        let i = i as u32;
        let mut pos = l.position.to_array();
        if let Some(p) = vec3_ui(ui, &format!("light {i} position"), &mut pos, cmds) {
            cmds.push(Command::Edit(EditCmd::Apply(Edit::SetLight {
                light: i,
                field: LightField::Position,
                value: p.map(f64::from),
            })));
        }
        let mut c = l.color.to_array();
        ui.horizontal(|ui| {
            ui.label("colour");
            if ui.color_edit_button_rgb(&mut c).changed() {
                cmds.push(Command::Edit(EditCmd::Apply(Edit::SetLight {
                    light: i,
                    field: LightField::Color,
                    value: c.map(f64::from),
                })));
            }
        });
    }
}

/// Three drag values; returns the new vector when one changed (a drag is one undo step).
fn vec3_ui(
    ui: &mut egui::Ui,
    id: &str,
    v: &mut [f32; 3],
    cmds: &mut Vec<Command>,
) -> Option<[f32; 3]> {
    let mut changed = false;
    ui.push_id(id, |ui| {
        ui.horizontal(|ui| {
            for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                let r = ui.add(
                    egui::DragValue::new(&mut v[k])
                        .speed(0.01)
                        .prefix(format!("{axis} "))
                        .max_decimals(4),
                );
                gesture(&r, cmds);
                changed |= r.changed();
            }
        });
    });
    changed.then_some(*v)
}

/// A drag on a value is one undo step.
fn gesture(r: &egui::Response, cmds: &mut Vec<Command>) {
    if r.drag_started() {
        cmds.push(Command::Edit(EditCmd::BeginGesture));
    }
    if r.drag_stopped() {
        cmds.push(Command::Edit(EditCmd::EndGesture));
    }
}

fn object_ui(
    ui: &mut egui::Ui,
    state: &AppState,
    scene: &Scene,
    group: u32,
    cmds: &mut Vec<Command>,
) {
    let Some(g) = scene.groups.get(group as usize) else {
        return;
    };
    let Some(first) = scene.objects.get(g.first as usize) else {
        return;
    };
    let kind = if g.count > 1 {
        "mesh"
    } else {
        first.shape.kind()
    };
    ui.label(format!("{kind} \"{}\"", g.name));
    if let Some(c) = group_center(scene, group) {
        let mut v = c.to_array();
        ui.label("position");
        if let Some(n) = vec3_ui(ui, "position", &mut v, cmds) {
            let by = (Vec3::from(n) - c).to_array().map(f64::from);
            cmds.push(Command::Edit(EditCmd::Apply(Edit::Move { group, by })));
        }
    }
    if let Shape::Sphere { radius, .. } = first.shape {
        let mut r = radius;
        ui.horizontal(|ui| {
            ui.label("radius");
            let resp = ui.add(
                egui::DragValue::new(&mut r)
                    .speed(0.01)
                    .range(1e-3..=1e6)
                    .max_decimals(4),
            );
            gesture(&resp, cmds);
            if resp.changed() && r > 0.0 {
                cmds.push(Command::Edit(EditCmd::Apply(Edit::SetRadius {
                    group,
                    radius: f64::from(r),
                })));
            }
        });
    }
    let Some(m) = scene.materials.get(first.material as usize) else {
        return;
    };
    ui.separator();
    let users = state
        .editor
        .as_ref()
        .and_then(|e| e.material_users(group))
        .unwrap_or(1);
    ui.label(RichText::new(format!("Material \"{}\"", m.name)).strong());
    if users > 1 {
        ui.label(
            RichText::new(format!(
                "shared by {users} objects: a change shows on all of them"
            ))
            .small(),
        );
    }
    let set = |field: MaterialField, value: MaterialValue| {
        Command::Edit(EditCmd::Apply(Edit::SetMaterial {
            group,
            field,
            value,
        }))
    };
    let mut c = m.color.to_array();
    ui.horizontal(|ui| {
        ui.label("colour");
        if ui.color_edit_button_rgb(&mut c).changed() {
            cmds.push(set(
                MaterialField::Color,
                MaterialValue::Color(c.map(f64::from)),
            ));
        }
    });
    for (field, label, value, range) in [
        (MaterialField::Ambient, "ambient", m.ambient, 0.0..=1.0),
        (MaterialField::Diffuse, "diffuse", m.diffuse, 0.0..=1.0),
        (MaterialField::Specular, "specular", m.specular, 0.0..=1.0),
        (
            MaterialField::Shininess,
            "shininess",
            m.shininess,
            1.0..=1000.0,
        ),
        (
            MaterialField::Reflective,
            "reflective",
            m.reflective,
            0.0..=1.0,
        ),
        (
            MaterialField::Transparency,
            "transparency",
            m.transparency,
            0.0..=1.0,
        ),
        (
            MaterialField::RefractiveIndex,
            "refractive index",
            m.refractive_index,
            1.0..=3.0,
        ),
    ] {
        let mut v = value;
        ui.spacing_mut().slider_width = (ui.available_width() - 150.0).max(40.0);
        let r = ui.add(egui::Slider::new(&mut v, range).text(label));
        gesture(&r, cmds);
        if r.changed() {
            cmds.push(set(field, MaterialValue::Number(f64::from(v))));
        }
    }
}
