//! Picking and the move arrows: a click selects the object under the pointer (found by
//! raystep's own closest-hit search), the selected object's coloured x, y and z arrows drag it
//! along an axis, and drags elsewhere orbit, pan and zoom the view.

use super::group_center;
use crate::accel::Accelerator;
use crate::record::Silent;
use crate::scene::edit::Edit;
use crate::scene::{Scene, Shape};
use crate::state::editing::EditCmd;
use crate::state::{AppState, Command};
use crate::view3d::camera::{Orbit, ViewCamera};
use crate::view3d::{Viewpoint, geometry};
use egui::{Color32, Pos2, Rect, Stroke, Vec2};
use glam::Vec3;

/// What a drag is doing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Drag {
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

/// The selected object's move handles: its centre and, per axis, the arrow's end on screen.
pub(super) struct Handles {
    group: u32,
    /// The object's centre on screen.
    pub(super) center: Pos2,
    /// The x, y and z arrows' tips on screen.
    pub(super) ends: [Pos2; 3],
    world_len: f32,
}

const AXIS_COLORS: [Color32; 3] = [
    Color32::from_rgb(230, 70, 60),
    Color32::from_rgb(80, 200, 90),
    Color32::from_rgb(70, 130, 240),
];

pub(super) fn gizmo(
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
pub(super) fn interact(
    ui: &egui::Ui,
    state: &AppState,
    scene: &Scene,
    (drag, viewpoint): (&mut Option<Drag>, &mut Viewpoint),
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
        *drag = Some(match axis {
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
    if let Some(d) = *drag
        && delta != Vec2::ZERO
    {
        match d {
            Drag::Orbit => {
                let mut o = match *viewpoint {
                    Viewpoint::Orbit(o) => o,
                    Viewpoint::Camera => Orbit::default(),
                };
                o.yaw -= delta.x * 0.4;
                o.pitch += delta.y * 0.4;
                *viewpoint = Viewpoint::Orbit(o.sanitized());
            }
            Drag::Pan => {
                if let Viewpoint::Orbit(mut o) = *viewpoint {
                    let (u, v, _) = cam.basis();
                    let k = cam.world_per_pixel(cam.target, rect.height());
                    let shift = (u * -delta.x + v * delta.y) * k;
                    o.pan = (Vec3::from(o.pan) + shift).to_array();
                    *viewpoint = Viewpoint::Orbit(o.sanitized());
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
        if matches!(*drag, Some(Drag::Axis { .. })) {
            cmds.push(Command::Edit(EditCmd::EndGesture));
        }
        *drag = None;
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0
            && let Viewpoint::Orbit(mut o) = *viewpoint
        {
            o.distance *= (-scroll * 0.002).exp();
            *viewpoint = Viewpoint::Orbit(o.sanitized());
        }
    }
    if response.double_clicked() {
        *viewpoint = Viewpoint::default();
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
