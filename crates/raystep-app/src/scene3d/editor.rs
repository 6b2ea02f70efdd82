//! The scene editor beside the 3D view: undo, redo and save; the selected object's place, size
//! and material; the lights. Every change is an [`EditCmd`] the state applies (and can undo).

use super::group_center;
use crate::actions::{self, Action};
use crate::scene::edit::{Edit, LightField, MaterialField, MaterialValue};
use crate::scene::{Scene, Shape};
use crate::state::editing::EditCmd;
use crate::state::{AppState, Command, SaveKind};
use egui::RichText;
use glam::Vec3;

/// The editor beside the view: undo, redo, save; the selected object's place, size and
/// material; the lights.
pub(super) fn editor_ui(
    ui: &mut egui::Ui,
    state: &AppState,
    scene: &Scene,
    cmds: &mut Vec<Command>,
) {
    let Some(editor) = &state.editor else {
        ui.label("This scene cannot be edited: it was not opened from a scene file.");
        return;
    };
    ui.horizontal_wrapped(|ui| {
        actions::button(ui, state, Action::Undo, editor.can_undo(), cmds);
        actions::button(ui, state, Action::Redo, editor.can_redo(), cmds);
        actions::button(ui, state, Action::SaveScene, true, cmds);
        actions::button(ui, state, Action::SaveAs(SaveKind::Scene), true, cmds);
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
    // A prototype is drawn only where its instances place it: its own place and size are in
    // its object space, under every instance's matrix.
    let placing: Vec<&str> = scene
        .instances
        .iter()
        .filter(|i| i.group == group)
        .map(|i| i.name.as_str())
        .collect();
    if !placing.is_empty() {
        let shown = placing
            .iter()
            .take(4)
            .copied()
            .collect::<Vec<_>>()
            .join(", ");
        let more = if placing.len() > 4 { ", …" } else { "" };
        ui.label(
            RichText::new(format!(
                "the prototype of {} instance{} ({shown}{more}): its position and size are in its own object space, so a change moves and resizes every copy within its instance; each copy's place is its [[instance]] table's matrix in the scene file",
                placing.len(),
                if placing.len() == 1 { "" } else { "s" }
            ))
            .small(),
        );
    }
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
