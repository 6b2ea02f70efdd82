//! The settings panel: the scene in a few words and the settings a teacher flips live, each
//! shown only when the scene has something it affects.

use crate::record::number::num;
use crate::scene::{
    AccelChoice, BvhQuality, Integrator, OffsetPolicy, SamplerKind, Settings, Strategy, Terminator,
};
use crate::shapes::{SphereMethod, TriangleMethod};
use crate::state::{AppState, Command};
use crate::view::RenderView;
use egui::RichText;

/// The settings a teacher flips live, each shown only when the scene has something it affects.
pub(super) fn settings_panel(
    ui: &mut egui::Ui,
    state: &AppState,
    render: &RenderView,
    cmds: &mut Vec<Command>,
) {
    ui.set_min_width(ui.available_width());
    let Some(scene) = state.scene() else {
        if let Some(s) = &state.stepping {
            ui.heading("Trace settings");
            settings_summary(ui, &s.trace.settings);
        }
        return;
    };
    let f = scene.features;
    ui.heading("Scene");
    ui.label(format!(
        "{} × {} pixels, field of view {}°",
        scene.camera.width, scene.camera.height, scene.camera.fov
    ));
    let mut effects = vec![];
    if f.reflective {
        effects.push("mirrors");
    }
    if f.transparent {
        effects.push("glass");
    }
    if !effects.is_empty() {
        ui.label(format!("materials: {}", effects.join(", ")));
    }
    ui.separator();
    ui.heading("Render settings");
    let mut s: Settings = state.settings.clone();
    ui.horizontal(|ui| {
        let l = ui.label("Samples per pixel");
        ui.add(egui::DragValue::new(&mut s.spp).range(1..=256))
            .labelled_by(l.id)
            .on_hover_text("rays traced per pixel, averaged (jittered inside the pixel)");
    });
    ui.label(RichText::new("Integrator").strong());
    ui.horizontal_wrapped(|ui| {
        ui.radio_value(&mut s.integrator, Integrator::Whitted, "Whitted")
            .on_hover_text("point lights with Phong, perfect mirror and refraction rays");
        ui.radio_value(&mut s.integrator, Integrator::Distribution, "distribution")
            .on_hover_text(
                "Cook 1984: area lights sampled (soft shadows), glossy rays, the thin lens",
            );
        ui.radio_value(&mut s.integrator, Integrator::Path, "path")
            .on_hover_text(
                "Kajiya 1986: light and BSDF sampling combined by MIS, Russian roulette",
            );
    });
    if s.integrator.is_monte_carlo() {
        ui.horizontal_wrapped(|ui| {
            ui.label("2D samples");
            ui.radio_value(&mut s.sampler, SamplerKind::Independent, "independent")
                .on_hover_text("every light point, BSDF direction and lens point drawn alone");
            ui.radio_value(&mut s.sampler, SamplerKind::Stratified, "stratified")
                .on_hover_text(
                    "the pixel's samples share a grid: one per cell, jittered inside it",
                );
        });
    }
    if s.integrator == Integrator::Path {
        ui.horizontal_wrapped(|ui| {
            ui.label("Direct light");
            ui.radio_value(&mut s.strategy, Strategy::Mis, "MIS")
                .on_hover_text("light and BSDF sampling, combined by the power heuristic");
            ui.radio_value(&mut s.strategy, Strategy::Light, "light")
                .on_hover_text("light sampling alone (next-event estimation)");
            ui.radio_value(&mut s.strategy, Strategy::Bsdf, "BSDF")
                .on_hover_text("BSDF sampling alone: emitters count where paths find them");
        });
    }
    if f.reflective || f.transparent || s.integrator.is_monte_carlo() {
        ui.horizontal(|ui| {
            let l = ui.label("Recursion depth");
            ui.add(egui::DragValue::new(&mut s.max_depth).range(0..=16))
                .labelled_by(l.id)
                .on_hover_text("how many mirror or glass bounces a ray may make");
        });
    }
    // In the browser, where the render runs and why: on the page's Web Workers, or on its own
    // thread where it has none (and the reason, which a teacher can act on).
    if crate::platform::IN_BROWSER {
        let threads = match crate::platform::workers() {
            0 => format!(
                "Render threads: 1, the page's own{}",
                crate::platform::one_thread_why().map_or(String::new(), |w| format!(": {w}"))
            ),
            1 => "Render threads: 1 Web Worker".to_string(),
            n => format!("Render threads: {n} Web Workers"),
        };
        ui.label(threads).on_hover_text(
            "the page renders on every core where it is cross-origin isolated (its service \
             worker, coi.js, sees to that over HTTPS or from localhost)",
        );
    }
    ui.label(RichText::new("Acceleration").strong());
    ui.horizontal_wrapped(|ui| {
        ui.radio_value(&mut s.accel, AccelChoice::Auto, "auto")
            .on_hover_text("a BVH when the scene is large enough to gain from one");
        ui.radio_value(&mut s.accel, AccelChoice::None, "naive loop")
            .on_hover_text("test every primitive for every ray");
        ui.radio_value(&mut s.accel, AccelChoice::Bvh, "BVH")
            .on_hover_text("a bounding volume hierarchy: skip what a ray's boxes miss");
        ui.radio_value(&mut s.accel, AccelChoice::Spheres, "spheres")
            .on_hover_text("a hierarchy of bounding spheres: skip what a ray's spheres miss");
        ui.radio_value(&mut s.accel, AccelChoice::Grid, "grid")
            .on_hover_text("a uniform grid: walk the cells the ray crosses, nearest first");
    });
    if let Some(p) = &state.prepared {
        let choice = p.accel_choice();
        ui.label(match choice {
            AccelChoice::Bvh => "using a BVH",
            AccelChoice::Spheres => "using bounding spheres",
            AccelChoice::Grid => "using a uniform grid",
            _ => "testing every primitive for every ray",
        });
        let instances = p.scene().instances.len();
        if instances > 0 {
            // The world's objects take the choice above; the instances their own two levels.
            let prototypes = p.scene().prototypes.len();
            ui.label(format!(
                "{instances} instance{}: a TLAS over them, {prototypes} BLAS (one per prototype)",
                if instances == 1 { "" } else { "s" },
            ))
            .on_hover_text(
                "the two-level BVH: the ray walks a tree over the instances' boxes in the world, then each prototype's own tree in its object space",
            );
        }
        if matches!(choice, AccelChoice::Bvh | AccelChoice::Spheres) {
            ui.horizontal_wrapped(|ui| {
                ui.label("Tree quality");
                ui.radio_value(&mut s.bvh_quality, BvhQuality::Low, "low")
                    .on_hover_text("builds fastest; rays may visit more boxes");
                ui.radio_value(&mut s.bvh_quality, BvhQuality::Medium, "medium")
                    .on_hover_text("the default");
                ui.radio_value(&mut s.bvh_quality, BvhQuality::High, "high")
                    .on_hover_text("builds slowest; rays may visit fewer boxes");
            });
            if let Some(b) = p.bvh() {
                // The build time (which varies from run to run) only on hover.
                ui.label(format!(
                    "{} nodes, depth {}, SAH cost {:.1}",
                    b.nodes.len(),
                    b.max_depth,
                    b.sah_cost(),
                ))
                .on_hover_text(format!(
                    "SAH cost: the expected cost of a random ray, in box-pair tests and \
                     primitive tests (lower is better).\nBuilt in {:.1} ms.",
                    b.build_time.as_secs_f64() * 1e3
                ));
            }
        }
    }
    if f.spheres > 0 {
        ui.label(RichText::new("Ray–sphere").strong());
        ui.horizontal_wrapped(|ui| {
            ui.radio_value(&mut s.sphere_method, SphereMethod::Textbook, "textbook")
                .on_hover_text(
                    "t = (−b ± √Δ) / 2a as written: loses a far sphere's radius to cancellation",
                );
            ui.radio_value(&mut s.sphere_method, SphereMethod::Stable, "stable")
                .on_hover_text(
                    "Ray Tracing Gems ch. 7: neither root subtracts nearly equal numbers",
                );
        });
    }
    if f.triangles > 0 {
        ui.label(RichText::new("Ray–triangle").strong());
        ui.horizontal_wrapped(|ui| {
            ui.radio_value(
                &mut s.triangle_method,
                TriangleMethod::MollerTrumbore,
                "Möller–Trumbore",
            )
            .on_hover_text("the classic test: rays through a shared edge can slip between");
            ui.radio_value(
                &mut s.triangle_method,
                TriangleMethod::Watertight,
                "watertight",
            )
            .on_hover_text("Woop, Benthin and Wald's test: no ray slips through a shared edge");
        });
    }
    if f.lights > 0 || f.reflective || f.transparent {
        ui.label(RichText::new("Ray-origin offset").strong());
        ui.horizontal_wrapped(|ui| {
            ui.radio_value(&mut s.offset, OffsetPolicy::None, "no offset")
                .on_hover_text("secondary rays start exactly on the surface: shadow acne");
            ui.radio_value(&mut s.offset, OffsetPolicy::Fixed, "fixed ε")
                .on_hover_text("secondary rays start ε along the normal");
            ui.radio_value(&mut s.offset, OffsetPolicy::Robust, "robust")
                .on_hover_text(
                    "pbrt's offset: the hit point's rounding-error bound along the normal",
                );
        });
        if s.offset == OffsetPolicy::Fixed {
            ui.horizontal(|ui| {
                let l = ui.label("ε");
                ui.add(
                    egui::DragValue::new(&mut s.epsilon)
                        .range(1e-7..=1.0)
                        .speed(1e-5),
                )
                .labelled_by(l.id)
                .on_hover_text("the fixed offset, in scene units");
            });
        }
    }
    if f.smooth > 0 {
        ui.label(RichText::new("Shadow terminator").strong());
        ui.horizontal_wrapped(|ui| {
            ui.radio_value(&mut s.terminator, Terminator::None, "flat triangle")
                .on_hover_text(
                    "rays leave from the hit point on the flat triangle: where the smooth normal \
                     still faces the light, neighbouring facets block the shadow ray (a jagged \
                     terminator)",
                );
            ui.radio_value(&mut s.terminator, Terminator::Hanika, "Hanika's lift")
                .on_hover_text(
                    "rays leave from the point lifted onto the vertices' tangent planes \
                     (Ray Tracing Gems II, ch. 4): the terminator follows the smooth surface",
                );
        });
    }
    if s.spp > 1 {
        ui.horizontal(|ui| {
            let l = ui.label("Jitter seed");
            ui.add(egui::DragValue::new(&mut s.seed))
                .labelled_by(l.id)
                .on_hover_text(
                    "the seed of the jitter inside each pixel and of every Monte Carlo number",
                );
        });
    }
    if scene.settings != s && ui.button("Back to the file's settings").clicked() {
        s = scene.settings.clone();
    }
    if s != state.settings {
        cmds.push(Command::SetSettings(s));
    }
    if state.settings.spp > 1 {
        let mut sample = state.sample;
        ui.horizontal(|ui| {
            let l = ui.label("Traced sample");
            ui.add(egui::DragValue::new(&mut sample).range(0..=state.settings.spp - 1))
                .labelled_by(l.id)
                .on_hover_text("which of the pixel's samples the trace shows");
        });
        if state.settings.integrator.is_monte_carlo() && state.pixel.is_some() {
            let label = if state.sample_playing {
                "‖ Pause the samples"
            } else {
                "▶ One sample at a time"
            };
            if ui
                .button(label)
                .on_hover_text(
                    "add the pixel's samples one at a time, at the play speed: the math \
                     panel's estimate and its 95 % interval update with each",
                )
                .clicked()
            {
                cmds.push(Command::ToggleSamplePlay);
            }
        }

        if sample != state.sample {
            cmds.push(Command::SetSample(sample));
        }
    }
    if RenderView::has_heatmap(state) {
        ui.separator();
        let mut p = state.prefs.clone();
        // Named after what it counts: BVH nodes, bounding spheres or grid cells.
        let (label, hover) = match state.prepared.as_ref().map(|p| p.accel_choice()) {
            Some(AccelChoice::Spheres) => (
                "Spheres heatmap",
                "how many bounding spheres each pixel's rays tested",
            ),
            Some(AccelChoice::Grid) => (
                "Grid heatmap",
                "how many grid cells each pixel's rays walked",
            ),
            _ => (
                "BVH heatmap",
                "how many BVH nodes each pixel's rays visited",
            ),
        };
        ui.checkbox(&mut p.heatmap, label).on_hover_text(hover);
        if p.heatmap {
            ui.label(format!(
                "accelerator visits per pixel (nodes or cells), dark purple = 0 … yellow ≥ {}",
                render.heat_max()
            ));
        }
        if p != state.prefs {
            cmds.push(Command::SetPrefs(p));
        }
    }
}

fn settings_summary(ui: &mut egui::Ui, s: &Settings) {
    let sphere = match s.sphere_method {
        SphereMethod::Textbook => "textbook",
        SphereMethod::Stable => "stable",
    };
    let triangle = match s.triangle_method {
        TriangleMethod::MollerTrumbore => "Möller–Trumbore",
        TriangleMethod::Watertight => "watertight",
    };
    let offset = match s.offset {
        OffsetPolicy::None => "none".to_string(),
        OffsetPolicy::Fixed => format!("fixed ε = {}", num(s.epsilon)),
        OffsetPolicy::Robust => "robust".to_string(),
    };
    let accel = match s.accel {
        AccelChoice::Auto => "automatic",
        AccelChoice::None => "naive loop",
        AccelChoice::Bvh => "BVH",
        AccelChoice::Spheres => "bounding spheres",
        AccelChoice::Grid => "uniform grid",
    };
    for line in [
        format!("samples per pixel: {}", s.spp),
        format!("recursion depth: {}", s.max_depth),
        format!("ray–sphere test: {sphere}"),
        format!("ray–triangle test: {triangle}"),
        format!("ray-origin offset: {offset}"),
        format!("acceleration: {accel}"),
    ] {
        ui.label(line);
    }
    if s.terminator == Terminator::Hanika {
        ui.label("shadow terminator: Hanika's lift");
    }
}
