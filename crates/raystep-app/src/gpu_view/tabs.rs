//! The GPU view's tabs: the tab strip, the GPU render with its debug pixel and trace switch,
//! and the CPU − GPU difference.

use super::*;

/// The tab strip above the central view (only when the app has a GPU view).
pub fn tabs(ui: &mut egui::Ui, gpu: &mut GpuView) {
    ui.horizontal(|ui| {
        for (tab, label, hover) in [
            (
                CentralTab::Cpu,
                "CPU render",
                "the render on the CPU; click a pixel to trace it",
            ),
            (
                CentralTab::Gpu,
                "GPU render",
                "the same scene traced by a WGSL shader generated for it; drag to orbit",
            ),
            (
                CentralTab::Difference,
                "CPU − GPU",
                "where the two renders differ, and by how much",
            ),
            (
                CentralTab::Scene3d,
                "3D view",
                "the scene in space: the camera, its image plane and the pixel's rays; edit the scene",
            ),
        ] {
            if ui
                .selectable_label(gpu.tab == tab, label)
                .on_hover_text(hover)
                .clicked()
            {
                gpu.tab = tab;
            }
        }
    });
}

/// The path radio buttons: a change is a command.
fn path_choice(ui: &mut egui::Ui, gpu: &GpuState, cmds: &mut Vec<Command>, hover: bool) {
    let mut path = gpu.path;
    let f = ui.radio_value(&mut path, GpuPath::Fragment, "fragment");
    let c = ui.radio_value(&mut path, GpuPath::Compute, "compute");
    if hover {
        f.on_hover_text("a full-screen triangle: the rasterizer interpolates the primary rays");
        c.on_hover_text("a compute shader, one invocation per pixel");
    }
    if path != gpu.path {
        cmds.push(Command::Gpu(GpuCmd::SetPath(path)));
    }
}

/// The GPU render view (the central panel's "GPU render" tab).
pub fn gpu_tab(ui: &mut egui::Ui, state: &AppState, view: &mut GpuView, cmds: &mut Vec<Command>) {
    let gpu = &state.gpu;
    let Some(prepared) = &state.prepared else {
        ui.label("Preparing the scene…");
        return;
    };
    if gpu.needs_frame(prepared, state.pixel) {
        cmds.push(Command::Gpu(GpuCmd::Frame));
    }
    if gpu.waiting() {
        ui.ctx().request_repaint();
    }
    ui.horizontal_wrapped(|ui| {
        path_choice(ui, gpu, cmds, true);
        if ui
            .add_enabled(
                gpu.orbit != Orbit::IDENTITY,
                egui::Button::new("Reset view"),
            )
            .clicked()
        {
            cmds.push(Command::Gpu(GpuCmd::SetOrbit(Orbit::IDENTITY)));
        }
        ui.toggle_value(&mut view.show_wgsl, "WGSL");
    });
    if let Some(line) = gpu.adapter_line() {
        ui.label(RichText::new(line).small());
    }
    late_errors(ui, gpu);
    let settings = &prepared.scene().settings;
    if settings.integrator.is_monte_carlo() {
        let name = clap::ValueEnum::to_possible_value(&settings.integrator)
            .map_or_else(String::new, |v| v.get_name().to_string());
        let so_far = match gpu.samples_so_far() {
            Some((done, spp)) if done < spp => {
                format!("{done} of {spp} samples per pixel so far")
            }
            _ => format!("{} samples per pixel", settings.spp),
        };
        ui.label(
            RichText::new(format!(
                "{name} integrator on the GPU: {so_far}, the CPU's random numbers \
                 (the same image bit for bit where the arithmetic is exact)."
            ))
            .small(),
        );
    }
    if let Some(e) = gpu.error_for(prepared) {
        if e.starts_with(NO_WEBGPU) {
            return no_webgpu(ui, e);
        }
        ui.colored_label(ui.visuals().error_fg_color, format!("GPU view: {e}"));
        return;
    }
    let Some((id, size)) = view.image(ui.ctx(), gpu) else {
        ui.label(
            "Opening the GPU, measuring its arithmetic and tracing the first frame (the \
             answers come back on later frames)…",
        );
        ui.ctx().request_repaint();
        return;
    };
    if let Some((path, d)) = gpu.frame_time() {
        ui.label(format!(
            "{} path: {:.2} ms per frame ({}), {}×{}",
            path.name(),
            d.as_secs_f64() * 1e3,
            if crate::platform::IN_BROWSER {
                "the trace and display passes, submit until the browser said they were done"
            } else {
                "trace pass, submit to completion"
            },
            size[0],
            size[1]
        ));
    }
    if state.pixel.is_some() {
        pick_table(ui, state, prepared.scene(), gpu);
        trace_switch(ui, state, cmds);
    }
    if view.show_wgsl {
        if let Some(wgsl) = gpu.wgsl() {
            ui.label(format!(
                "Generated for this scene: {} lines, {} bytes (features the scene lacks are left out)",
                wgsl.lines().count(),
                wgsl.len()
            ));
            egui::ScrollArea::both()
                .id_salt("wgsl")
                .auto_shrink([false, false])
                .show(ui, |ui| {
                    ui.add(
                        egui::TextEdit::multiline(&mut wgsl.to_string())
                            .code_editor()
                            .interactive(false)
                            .desired_width(f32::INFINITY),
                    );
                });
        }
        return;
    }
    // The image, fitted, with drag to orbit and scroll to zoom.
    let avail = ui.available_size();
    let scale = (avail.x / size[0] as f32)
        .min(avail.y / size[1] as f32)
        .max(0.05);
    let shown = egui::vec2(size[0] as f32, size[1] as f32) * scale;
    let (rect, response) = ui.allocate_exact_size(shown, Sense::click_and_drag());
    view.image_rect = Some(rect);
    ui.painter().image(
        id,
        rect,
        egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
        Color32::WHITE,
    );
    let mut orbit = gpu.orbit;
    let drag = response.drag_delta();
    if drag != egui::Vec2::ZERO {
        // 0.01 radians per point; the pitch within ±1.4 radians.
        let per_point = 0.01_f32.to_degrees();
        let limit = 1.4_f32.to_degrees();
        orbit.yaw -= drag.x * per_point;
        orbit.pitch = (orbit.pitch - drag.y * per_point).clamp(-limit, limit);
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0 {
            orbit.distance = (orbit.distance * (-scroll * 0.002).exp()).clamp(0.1, 10.0);
        }
    }
    if response.double_clicked() {
        orbit = Orbit::IDENTITY;
    }
    if orbit != gpu.orbit {
        cmds.push(Command::Gpu(GpuCmd::SetOrbit(orbit)));
    }
}

/// The GPU debug buffer of the selected pixel beside the CPU trace's values.
fn pick_table(ui: &mut egui::Ui, state: &AppState, scene: &Scene, gpu: &GpuState) {
    let Some(pick) = gpu.pick() else {
        if gpu.waiting() {
            ui.label("Reading the pixel's debug buffer back from the GPU…");
        }
        return;
    };
    let p = match pick {
        Ok(p) => p,
        Err(e) => {
            ui.colored_label(ui.visuals().error_fg_color, format!("debug pixel: {e}"));
            return;
        }
    };
    let cpu = state.stepping.as_ref().map(|s| &s.trace.root);
    let hit = cpu.and_then(|r| r.hit.as_ref());
    let hit_name = hit.map(|h| h.name.clone());
    // The CPU's test against the object it hit: the discriminant of a sphere, u and v of a
    // triangle.
    let (mut disc, mut u, mut v) = (None, None, None);
    if let (Some(r), Some(name)) = (cpu, &hit_name) {
        // Inside an instance the tests name the prototype's primitive (`ball`), the hit the
        // instance and the primitive (`egg → ball`).
        let mut inside: Option<&str> = None;
        for s in &r.steps {
            let within = inside;
            let placed = move |n: &str| match within {
                Some(i) => format!("{i} → {n}"),
                None => n.to_string(),
            };
            match &s.step {
                Step::Instance { name: i, .. } => inside = Some(i),
                Step::Sphere { name: n, test, .. } if placed(n) == *name => {
                    disc = Some(test.discriminant)
                }
                Step::Triangle { name: n, test, .. } if placed(n) == *name => {
                    u = test.u;
                    v = test.v;
                }
                _ => {}
            }
        }
    }
    let nodes = cpu.map(|r| {
        r.steps
            .iter()
            // The world's tree, and with instances the TLAS and each BLAS entered: every box
            // the GPU's walk tests counts in its debug buffer.
            .filter(|s| matches!(s.step, Step::Node(_) | Step::TlasNode(_)))
            .count()
    });
    let opt = |x: Option<f32>| x.map_or("—".to_string(), num);
    let gpu_name = p.object.map_or("nothing".into(), |id| {
        match p.instance.and_then(|i| scene.instances.get(i as usize)) {
            Some(inst) => format!("{} → {}", inst.name, scene.object_name(id)),
            None => scene.object_name(id),
        }
    });
    let rows: Vec<(&str, String, String)> = vec![
        (
            "hit object",
            hit_name.clone().unwrap_or_else(|| "nothing".into()),
            gpu_name,
        ),
        (
            "t",
            opt(hit.map(|h| h.t)),
            if p.object.is_some() {
                num(p.t)
            } else {
                "—".into()
            },
        ),
        ("discriminant", opt(disc), opt(p.discriminant)),
        ("u", opt(u), if u.is_some() { num(p.u) } else { "—".into() }),
        ("v", opt(v), if v.is_some() { num(p.v) } else { "—".into() }),
        (
            "BVH nodes visited",
            nodes.map_or("—".into(), |n| n.to_string()),
            p.nodes_text(),
        ),
    ];
    // Leave out what neither side computed (u and v off triangles, nodes without a BVH).
    let with_bvh = state
        .stepping
        .as_ref()
        .is_some_and(|s| s.trace.bvh.is_some());
    let rows: Vec<_> = rows
        .into_iter()
        .filter(|(name, c, g)| {
            if *name == "BVH nodes visited" {
                with_bvh || p.nodes_visited > 0 || p.hardware_traversal
            } else {
                !(c == "—" && g == "—")
            }
        })
        .collect();
    ui.label(
        RichText::new(format!(
            "Pixel ({}, {}), primary ray, traced on both:",
            p.pixel[0], p.pixel[1]
        ))
        .strong(),
    );
    egui::Grid::new("gpu-pick")
        .striped(true)
        .num_columns(3)
        .show(ui, |ui| {
            ui.label(RichText::new("quantity").strong());
            ui.label(RichText::new("CPU trace").strong());
            ui.label(RichText::new("GPU debug buffer").strong());
            ui.end_row();
            for (name, c, g) in rows {
                ui.label(name);
                ui.monospace(c);
                ui.monospace(g);
                ui.end_row();
            }
        });
}

/// CPU ⇄ GPU: which trace of the selected pixel the stepper, math panel and diagrams show. The
/// GPU's own trace is made on first use (the trace shader logs each step the chosen path takes)
/// and compared with the CPU's; the first divergence is named, marked on the step bar, and one
/// click away.
fn trace_switch(ui: &mut egui::Ui, state: &AppState, cmds: &mut Vec<Command>) {
    let Some(pixel) = state.pixel else {
        return;
    };
    if state.stepping.is_none() {
        return;
    }
    ui.horizontal_wrapped(|ui| {
        ui.label("Step through:");
        if ui
            .selectable_label(!state.showing_gpu_trace, "CPU trace")
            .on_hover_text("the CPU tracer's steps for this pixel")
            .clicked()
        {
            cmds.push(Command::ShowCpuTrace);
        }
        let gpu_button = ui
            .selectable_label(state.showing_gpu_trace, "GPU trace")
            .on_hover_text(
                "the GPU's own steps: the trace shader logs every step the chosen path (fragment \
                 or compute) takes for this pixel, read back into the same stepper, math panel \
                 and diagrams",
            );
        if gpu_button.clicked() {
            cmds.push(Command::Gpu(GpuCmd::TracePixel));
        }
    });
    match state.gpu.gpu_trace(pixel, state.sample) {
        None => {}
        Some(None) => {
            ui.label("Reading the GPU's step log back…");
        }
        Some(Some(Ok(g))) => {
            let colour = if g.divergence.is_some() {
                ui.visuals().warn_fg_color
            } else {
                ui.visuals().text_color()
            };
            ui.label(RichText::new(&g.verdict).color(colour));
            if g.truncated {
                ui.colored_label(
                    ui.visuals().warn_fg_color,
                    "The GPU's step log ran out: its trace stops early.",
                );
            }
            if let Some(k) = g.divergence
                && state.showing_gpu_trace
                && ui.button(format!("Go to step {k}")).clicked()
            {
                cmds.push(Command::Step(StepMove::To(k)));
            }
        }
        Some(Some(Err(e))) => {
            ui.colored_label(ui.visuals().error_fg_color, format!("GPU trace: {e}"));
        }
    }
}

/// The difference tab: CPU − GPU as an image, with RMSE, max error and the count of differing
/// pixels.
pub fn difference_tab(
    ui: &mut egui::Ui,
    state: &AppState,
    view: &mut GpuView,
    cmds: &mut Vec<Command>,
) {
    let gpu = &state.gpu;
    let Some(prepared) = &state.prepared else {
        ui.label("Preparing the scene…");
        return;
    };
    if state.job.is_some() || state.rendered.is_none() {
        ui.label("Waiting for the CPU render to finish…");
        return;
    }
    if gpu.waiting() {
        ui.ctx().request_repaint();
    }
    ui.horizontal(|ui| path_choice(ui, gpu, cmds, false));
    if let Some(e) = gpu.error_for(prepared) {
        return if e.starts_with(NO_WEBGPU) {
            no_webgpu(ui, e)
        } else {
            ui.colored_label(ui.visuals().error_fg_color, format!("GPU view: {e}"));
        };
    }
    if gpu.needs_compare(prepared, state.renders_started) {
        cmds.push(Command::Gpu(GpuCmd::Compare));
    }
    late_errors(ui, gpu);
    if !gpu.ready_for(prepared) {
        ui.label("Measuring the GPU's arithmetic…");
        ui.ctx().request_repaint();
        return;
    }
    if gpu.comparing() {
        ui.label("Tracing on the GPU and reading the image back…");
        return;
    }
    match (gpu.difference(), gpu.difference_path()) {
        (Some(Ok((d, generation))), Some(path)) => {
            ui.label(RichText::new(format!("{} path: {}", path.name(), d.summary())).strong());
            ui.label(
                "Equal pixels are dim grey; differing ones run from dark red (one 8-bit step) to \
                 yellow (16 or more). Both sides compute in f32; the GPU's pow, FMA contraction \
                 and the rasterizer's interpolated rays round differently in the last bits.",
            );
            let tex = view.difference_texture(ui.ctx(), d, generation);
            let avail = ui.available_size();
            let size = tex.size_vec2();
            let scale = (avail.x / size.x).min(avail.y / size.y).max(0.05);
            ui.image((tex.id(), size * scale));
        }
        (Some(Err(e)), _) => {
            ui.colored_label(ui.visuals().error_fg_color, e);
        }
        _ => {}
    }
}

/// The GPU tabs in a browser without WebGPU: what they need.
fn no_webgpu(ui: &mut egui::Ui, why: &str) {
    ui.vertical_centered(|ui| {
        ui.add_space(40.0);
        ui.heading("The GPU tracer needs WebGPU");
        ui.add_space(8.0);
        ui.label(why);
        ui.add_space(8.0);
        ui.label(
            "The CPU render, the stepper, the diagrams, the 3D view, the lessons and the \
             exercises all work here.",
        );
    });
}

/// Errors the browser reported after the call that caused them (a web page cannot wait for
/// them).
fn late_errors(ui: &mut egui::Ui, gpu: &GpuState) {
    for e in &gpu.late_errors {
        ui.colored_label(ui.visuals().error_fg_color, format!("GPU: {e}"));
    }
}
