//! The render view (zoom, pan, hover readout, click to select, heatmap overlay): what it keeps
//! between frames ([`RenderView`]: the render's texture, the zoom and pan) and the function that
//! draws it. Nothing here is persisted; the other panels keep their own caches (see
//! [`super::panels::Panels`]).

use super::state::{AppState, Command};
use egui::{Color32, ColorImage, Pos2, Rect, Sense, TextureHandle, TextureOptions, Vec2};
use std::sync::atomic::Ordering;

/// Over a Monte Carlo render: how many samples per pixel the image holds so far (the render
/// comes in passes of 1, 1, 2, 4, … samples), and a button that renders it again slowly
/// enough for a class to watch the noise go.
fn converge_row(ui: &mut egui::Ui, state: &AppState, cmds: &mut Vec<Command>) {
    let spp = state.settings.spp;
    let (text, running) = match &state.job {
        Some(_) if state.prepared.is_none() => ("preparing the scene…".to_string(), true),
        Some(job) => {
            let done = job.live.samples_done.load(Ordering::Relaxed);
            let watching = if job.pace.is_some() { ", watching" } else { "" };
            (
                format!("{done} of {spp} samples per pixel so far{watching}"),
                true,
            )
        }
        None => (
            format!("{spp} sample{} per pixel", if spp == 1 { "" } else { "s" }),
            false,
        ),
    };
    ui.horizontal_wrapped(|ui| {
        let integrator = match state.settings.integrator {
            crate::scene::Integrator::Path => "Path tracing",
            _ => "Distribution ray tracing",
        };
        ui.strong(format!("{integrator} · {text}"));
        let watching = state.job.as_ref().is_some_and(|j| j.pace.is_some());
        // Greyed out while it is being watched (not hidden: the image does not jump).
        if spp > 1
            && ui
                .add_enabled(
                    !(running && watching),
                    egui::Button::new("▶ Watch it converge"),
                )
                .on_hover_text(
                    "render again from one sample per pixel, each pass (1, 2, 4, … samples) \
                     held on screen for a moment",
                )
                .clicked()
        {
            cmds.push(Command::WatchConverge);
        }
    });
}

/// The render view's textures, zoom and pan (not persisted).
#[derive(Default)]
pub struct RenderView {
    /// The render as shown (sRGB), kept on the CPU so a new render paints over the old one.
    shown: Vec<Color32>,
    shown_size: [usize; 2],
    render_tex: Option<TextureHandle>,
    /// (renders started, tiles done, finished) of what the texture holds.
    render_key: (u64, usize, bool),
    heat_tex: Option<(TextureHandle, u64)>,
    heat_max: u32,
    /// Zoom relative to "fit" (1 = the image fills the view).
    pub zoom: f32,
    /// Pan in points from the centred position.
    pub pan: Vec2,
    /// The pixel under the cursor.
    pub hovered: Option<[u32; 2]>,
    /// Where the image was drawn last frame (screen rect in points) and points per pixel.
    pub image_rect: Option<(Rect, f32)>,
    /// A click on the render waiting to become a selection: (pixel, time of the click). It
    /// waits out the double-click delay, so that a double-click (fit to view) selects nothing.
    pub pending_click: Option<([u32; 2], f64)>,
}

impl RenderView {
    /// Back to fit: zoom 1, no pan (View → Reset zoom).
    pub fn reset_zoom(&mut self) {
        self.zoom = 1.0;
        self.pan = Vec2::ZERO;
    }

    /// Brings the render texture up to date with the running or finished render.
    fn update_render(&mut self, ctx: &egui::Context, state: &AppState) {
        let Some(scene) = state.scene() else {
            return;
        };
        let size = [scene.camera.width as usize, scene.camera.height as usize];
        if self.shown_size != size {
            self.shown = vec![Color32::from_gray(40); size[0] * size[1]];
            self.shown_size = size;
            self.render_key = (u64::MAX, 0, false);
        }
        let key;
        if let Some(job) = &state.job {
            key = (
                state.renders_started,
                job.live.tiles_done.load(Ordering::Relaxed),
                false,
            );
            if key != self.render_key {
                let live = job.live.pixels.lock().unwrap_or_else(|e| e.into_inner());
                for (dst, src) in self.shown.iter_mut().zip(live.iter()) {
                    if src[3] == 255 {
                        *dst = Color32::from_rgb(src[0], src[1], src[2]);
                    }
                }
            }
        } else if let Some(r) = &state.rendered {
            key = (state.renders_started, usize::MAX, true);
            if key != self.render_key && r.output.pixels.len() == self.shown.len() {
                for (dst, p) in self.shown.iter_mut().zip(&r.output.pixels) {
                    let [r, g, b] = crate::render::image::srgb8_rgb(*p);
                    *dst = Color32::from_rgb(r, g, b);
                }
            }
        } else {
            return;
        }
        if key != self.render_key || self.render_tex.is_none() {
            self.render_key = key;
            let img = ColorImage::new(size, self.shown.clone());
            match &mut self.render_tex {
                Some(t) => t.set(img, TextureOptions::NEAREST),
                None => {
                    self.render_tex = Some(ctx.load_texture("render", img, TextureOptions::NEAREST))
                }
            }
        }
    }

    /// The heatmap texture of the finished render (None without BVH visits).
    fn heatmap(&mut self, ctx: &egui::Context, state: &AppState) -> Option<TextureHandle> {
        let r = state.rendered.as_ref()?;
        let visits = r.output.node_visits.as_ref()?;
        if visits.iter().all(|&v| v == 0) {
            return None;
        }
        if let Some((t, k)) = &self.heat_tex
            && *k == state.renders_started
        {
            return Some(t.clone());
        }
        let scale = crate::render::image::HeatScale::of(visits);
        self.heat_max = scale.top;
        let pixels = visits
            .iter()
            .map(|&v| {
                let [r, g, b] = scale.color(v);
                Color32::from_rgba_unmultiplied(r, g, b, 230)
            })
            .collect();
        let img = ColorImage::new([r.output.width as usize, r.output.height as usize], pixels);
        let t = ctx.load_texture("heatmap", img, TextureOptions::NEAREST);
        self.heat_tex = Some((t.clone(), state.renders_started));
        Some(t)
    }

    /// The top of the heatmap's colour scale (the 99th percentile of node visits).
    pub fn heat_max(&self) -> u32 {
        self.heat_max
    }

    /// Whether the finished render has BVH visits to show as a heatmap.
    pub fn has_heatmap(state: &AppState) -> bool {
        state
            .rendered
            .as_ref()
            .and_then(|r| r.output.node_visits.as_ref())
            .is_some_and(|v| v.iter().any(|&x| x > 0))
    }
}

/// The render view: the image fitted to the space, zoomed with the scroll wheel about the
/// cursor, panned by dragging, reset by double-clicking; a click selects the pixel.
pub fn render_view(
    ui: &mut egui::Ui,
    state: &AppState,
    view: &mut RenderView,
    cmds: &mut Vec<Command>,
) {
    let ctx = ui.ctx().clone();
    view.update_render(&ctx, state);
    let Some(scene) = state.scene() else {
        return;
    };
    let (w, h) = (scene.camera.width as f32, scene.camera.height as f32);
    if state.settings.integrator.is_monte_carlo() {
        converge_row(ui, state, cmds);
    }
    let (rect, resp) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
    if view.zoom <= 0.0 {
        view.zoom = 1.0;
    }
    let fit = (rect.width() / w).min(rect.height() / h).max(1e-3);
    if resp.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0
            && let Some(p) = resp.hover_pos()
        {
            let old = view.zoom;
            view.zoom = (old * (scroll * 0.003).exp()).clamp(0.25, 64.0);
            // Keep the point under the cursor where it is.
            let c = rect.center() + view.pan;
            view.pan += (p - c) * (1.0 - view.zoom / old);
        }
    }
    if resp.dragged() {
        view.pan += resp.drag_delta();
    }
    let now = ui.input(|i| i.time);
    if resp.double_clicked() {
        view.zoom = 1.0;
        view.pan = Vec2::ZERO;
        view.pending_click = None;
    }
    let scale = fit * view.zoom;
    let img_rect = Rect::from_center_size(rect.center() + view.pan, Vec2::new(w, h) * scale);
    view.image_rect = Some((img_rect, scale));
    let to_pixel = |p: Pos2| -> Option<[u32; 2]> {
        let q = (p - img_rect.min) / scale;
        (q.x >= 0.0 && q.y >= 0.0 && q.x < w && q.y < h).then_some([q.x as u32, q.y as u32])
    };
    let painter = ui.painter_at(rect);
    let uv = Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0));
    if let Some(t) = &view.render_tex {
        painter.image(t.id(), img_rect, uv, Color32::WHITE);
    }
    if state.prefs.heatmap
        && let Some(t) = view.heatmap(&ctx, state)
    {
        painter.image(t.id(), img_rect, uv, Color32::WHITE);
    }
    let px_rect = |p: [u32; 2]| {
        Rect::from_min_size(
            img_rect.min + Vec2::new(p[0] as f32, p[1] as f32) * scale,
            Vec2::splat(scale),
        )
    };
    view.hovered = resp.hover_pos().and_then(to_pixel);
    if let Some(p) = view.hovered {
        painter.rect_stroke(
            px_rect(p).expand(1.0),
            0.0,
            egui::Stroke::new(1.0, Color32::from_white_alpha(160)),
            egui::StrokeKind::Outside,
        );
    }
    if let Some(p) = state.pixel {
        let r = px_rect(p).expand(2.0);
        painter.rect_stroke(
            r,
            0.0,
            egui::Stroke::new(3.0, Color32::BLACK),
            egui::StrokeKind::Outside,
        );
        painter.rect_stroke(
            r,
            0.0,
            egui::Stroke::new(2.0, Color32::from_rgb(255, 210, 0)),
            egui::StrokeKind::Outside,
        );
    }
    if resp.clicked() && !resp.double_clicked() {
        view.pending_click = resp
            .interact_pointer_pos()
            .and_then(to_pixel)
            .map(|p| (p, now));
    }
    if let Some((p, at)) = view.pending_click {
        let delay = ctx.options(|o| o.input_options.max_double_click_delay);
        let waited = now - at;
        if !(0.0..delay).contains(&waited) {
            view.pending_click = None;
            cmds.push(Command::SelectPixel(p));
        } else {
            ctx.request_repaint_after(std::time::Duration::from_secs_f64(
                (delay - waited).max(0.01),
            ));
        }
    }
}

/// The colour of pixel `p` in words: linear RGB from the finished render, and its sRGB hex.
pub fn pixel_colour(state: &AppState, p: [u32; 2]) -> Option<String> {
    let r = state.rendered.as_ref()?;
    let c = r
        .output
        .pixels
        .get((p[1] * r.output.width + p[0]) as usize)?;
    let s = |v: f32| crate::render::image::srgb8(v);
    Some(format!(
        "linear ({:.3}, {:.3}, {:.3}) = sRGB #{:02x}{:02x}{:02x}",
        c.x,
        c.y,
        c.z,
        s(c.x),
        s(c.y),
        s(c.z)
    ))
}
