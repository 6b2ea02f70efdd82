//! The stability lab in the app: a window that runs the quick suite of [`crate::stability`] on a
//! background thread and shows its table and its error-against-cost plots (egui_plot), and, for
//! the selected pixel, every number the tracer recorded beside its exact value and the error in
//! ulps (click a row to go to its step). For a path-traced scene it also compares the path
//! tracer's estimators (light sampling, BSDF sampling, MIS) as `raystep converge --strategy`
//! does: the same table, and the error against samples per pixel as a plot. The runs themselves
//! belong to the app's state ([`super::state::lab`]); the window asks for them with commands.

use super::state::lab::{COMPARE_MAX_SPP, COMPARE_SEEDS, LabCmd};
use super::state::{AppState, Command, StepMove};
use crate::scene::Integrator;
use crate::stability::converge::{
    Target, measured_words, strategy_name, strategy_table, target_words,
};
use crate::stability::pixel::{ExactValue, exact_values};
use crate::stability::{CostPoint, Precision, Primitive};
use egui::{Color32, RichText};
use egui_plot::{Legend, Line, Plot, PlotPoints, Points};

/// What the lab window keeps between frames (part of [`super::panels::Panels`]): whether it is
/// open, and the selected pixel's exact values, made once per trace. The runs and their results
/// are [`AppState::lab`]'s.
#[derive(Default)]
pub struct LabView {
    /// The window is open.
    pub open: bool,
    /// The exact values of the selected pixel's trace (for the trace generation they were made
    /// for).
    pixel: Option<(u64, Vec<ExactValue>)>,
}

/// The lab window (when open).
pub fn window(ctx: &egui::Context, state: &AppState, lab: &mut LabView, cmds: &mut Vec<Command>) {
    if !lab.open {
        return;
    }
    let mut open = lab.open;
    egui::Window::new("Stability lab")
        .open(&mut open)
        .default_size([760.0, 620.0])
        .vscroll(true)
        .show(ctx, |ui| {
            pixel_section(ui, state, lab, cmds);
            ui.separator();
            strategies_section(ui, state, cmds);
            ui.separator();
            suite_section(ui, state, cmds);
        });
    lab.open = open;
    if state.lab.running() {
        ctx.request_repaint_after(std::time::Duration::from_millis(250));
    }
}

fn pixel_section(ui: &mut egui::Ui, state: &AppState, lab: &mut LabView, cmds: &mut Vec<Command>) {
    let Some(s) = &state.stepping else {
        ui.label("Click a pixel: its numbers are compared with their exact values here.");
        return;
    };
    let generation = state.trace_generation;
    if lab.pixel.as_ref().is_none_or(|(g, _)| *g != generation) {
        let scene = state.prepared.as_ref().map(|p| p.scene());
        lab.pixel = Some((generation, exact_values(&s.trace, scene)));
    }
    let values = &lab.pixel.as_ref().expect("made above").1;
    ui.label(
        RichText::new(format!(
            "Pixel ({}, {}): each recorded f32 number against its exact value",
            s.trace.pixel[0], s.trace.pixel[1]
        ))
        .strong(),
    );
    ui.label(
        "Exact = rational arithmetic on the very f32 inputs the test saw (square roots to 400 \
         bits); the error is in f32 ulps of the exact value. Click a row to see its step.",
    );
    if values.is_empty() {
        ui.label("This trace has no sphere, plane or triangle numbers to compare.");
        return;
    }
    egui::ScrollArea::vertical()
        .id_salt("lab-pixel")
        .max_height(220.0)
        .show(ui, |ui| {
            egui::Grid::new("lab-pixel-grid")
                .striped(true)
                .num_columns(6)
                .show(ui, |ui| {
                    for h in ["", "object", "quantity", "recorded (f32)", "exact", "error"] {
                        ui.label(RichText::new(h).strong());
                    }
                    ui.end_row();
                    for v in values {
                        if ui
                            .selectable_label(state.step == v.step, format!("step {}", v.step))
                            .clicked()
                        {
                            cmds.push(Command::Step(StepMove::To(v.step)));
                        }
                        ui.label(&v.object);
                        ui.label(v.quantity);
                        ui.monospace(crate::record::number::num(v.recorded));
                        ui.monospace(format!("{:.10e}", v.exact));
                        let color = if v.ulps <= 2.0 {
                            ui.visuals().text_color()
                        } else if v.ulps <= 64.0 {
                            Color32::from_rgb(200, 130, 0)
                        } else {
                            Color32::from_rgb(210, 40, 40)
                        };
                        ui.label(
                            RichText::new(precision_ulps(v.ulps, Precision::F32)).color(color),
                        );
                        ui.end_row();
                    }
                });
        });
}

/// An error in ulps named by its precision ("2.90e6 f32 ulps", "0.50 f64 ulps").
fn precision_ulps(u: f64, p: Precision) -> String {
    if u == 0.0 {
        "exact".into()
    } else if u < 100.0 {
        format!("{u:.2} {} ulps", p.name())
    } else {
        format!("{u:.2e} {} ulps", p.name())
    }
}

/// Light sampling, BSDF sampling and MIS on the scene as it is set now, each against one
/// reference: the command line's table and the error against spp.
fn strategies_section(ui: &mut egui::Ui, state: &AppState, cmds: &mut Vec<Command>) {
    let lab = &state.lab;
    let path = state
        .prepared
        .as_ref()
        .is_some_and(|p| p.scene().settings.integrator == Integrator::Path);
    ui.horizontal_wrapped(|ui| {
        let button = ui
            .add_enabled(
                path && lab.comparison_started().is_none(),
                egui::Button::new("Compare light, BSDF and MIS"),
            )
            .on_hover_text(format!(
                "the path tracer's three estimators at 1 … {COMPARE_MAX_SPP} spp, {COMPARE_SEEDS} \
                 seeds each, against one reference (as `raystep converge SCENE --strategy \
                 light,bsdf,mis --max-spp {COMPARE_MAX_SPP} --seeds {COMPARE_SEEDS}`)"
            ));
        if button.clicked() {
            cmds.push(Command::Lab(LabCmd::CompareStrategies));
        }
        if let Some(started) = lab.comparison_started() {
            ui.spinner();
            ui.label(format!(
                "rendering… {:.0} s",
                started.elapsed().as_secs_f64()
            ));
        } else if !path {
            ui.label("(for a scene rendered with the path integrator)");
        }
    });
    let Some((name, result)) = &lab.comparison else {
        return;
    };
    let runs = match result {
        Ok(r) => r,
        Err(e) => {
            ui.colored_label(ui.visuals().error_fg_color, e);
            return;
        }
    };
    let target = Target::of(runs, None);
    ui.label(format!(
        "\"{name}\": relMSE against one MIS reference, medians over {COMPARE_SEEDS} seeds \
         (the errors are the command line's, bit for bit; the times are this machine's, now)"
    ));
    ui.label(target_words(runs, target));
    if let Some(r) = runs.first() {
        ui.label(measured_words(&r.report));
    }
    let (head, rows) = strategy_table(runs, target);
    egui::Grid::new("lab-strategies")
        .striped(true)
        .show(ui, |ui| {
            for h in &head {
                ui.label(RichText::new(h).strong());
            }
            ui.end_row();
            for row in rows {
                for cell in row {
                    ui.monospace(cell);
                }
                ui.end_row();
            }
        });
    Plot::new("lab-strategies-plot")
        .height(200.0)
        .legend(Legend::default())
        .x_axis_label("log₂ samples per pixel")
        .y_axis_label("log₁₀ relMSE (median)")
        .show(ui, |plot| {
            for r in runs {
                let pts: Vec<[f64; 2]> = r
                    .report
                    .levels
                    .iter()
                    .filter(|l| l.relmse[1] > 0.0)
                    .map(|l| [(l.spp as f64).log2(), l.relmse[1].log10()])
                    .collect();
                plot.line(Line::new(strategy_name(r.strategy), PlotPoints::from(pts)));
            }
        });
}

fn suite_section(ui: &mut egui::Ui, state: &AppState, cmds: &mut Vec<Command>) {
    let lab = &state.lab;
    ui.horizontal(|ui| {
        let label = if lab.report.is_some() {
            "Run the quick suite again"
        } else {
            "Run the quick suite"
        };
        if ui
            .add_enabled(!lab.running(), egui::Button::new(label))
            .on_hover_text("every method in f32 and f64 on the stiff cases S1–S25 (as `raystep stability --quick`)")
            .clicked()
        {
            cmds.push(Command::Lab(LabCmd::RunSuite));
        }
        if let Some(started) = lab.suite_started() {
            ui.spinner();
            ui.label(format!("running… {:.0} s", started.elapsed().as_secs_f64()));
        }
    });
    let Some(report) = &lab.report else {
        ui.label(
            "The suite measures, for every method and precision, how often it is wrong outside \
             the rounding band, how far off t is in ulps, leaks at shared edges, self-hits of \
             spawned rays and NaNs — and what each test costs.",
        );
        return;
    };
    ui.label(format!(
        "{} rays, {} rows, {:.1} s{}",
        report.rays,
        report.rows.len(),
        report.seconds,
        if report.quick { " (quick suite)" } else { "" }
    ));
    for prim in [
        Primitive::Sphere,
        Primitive::Triangle,
        Primitive::Plane,
        Primitive::Box,
        Primitive::Spawn,
    ] {
        let points: Vec<&CostPoint> = report
            .points
            .iter()
            .filter(|p| p.primitive == prim)
            .collect();
        if points.is_empty() {
            continue;
        }
        egui::CollapsingHeader::new(RichText::new(prim.name()).strong())
            .id_salt(("lab-prim", prim.name()))
            .default_open(prim == Primitive::Sphere || prim == Primitive::Triangle)
            .show(ui, |ui| {
                summary_grid(ui, prim, &points);
                error_plot(ui, prim, &points);
            });
    }
}

fn summary_grid(ui: &mut egui::Ui, prim: Primitive, points: &[&CostPoint]) {
    egui::Grid::new(("lab-summary", prim.name()))
        .striped(true)
        .show(ui, |ui| {
            for h in [
                "method",
                "ns/test",
                "t p99",
                "t max",
                "misclassified",
                "leaks",
                "self-hits",
                "NaN/∞",
            ] {
                ui.label(RichText::new(h).strong());
            }
            ui.end_row();
            for p in points {
                ui.label(p.label());
                ui.monospace(format!("{:.1}", p.ns_per_test));
                // Each row's ulps are of its own precision: an f64 ulp is 2²⁹ times smaller.
                ui.monospace(precision_ulps(p.p99_ulps, p.precision));
                ui.monospace(precision_ulps(p.max_ulps, p.precision));
                for n in [p.misclassified, p.leaks, p.self_hits, p.nonfinite] {
                    let text = RichText::new(n.to_string()).monospace();
                    ui.label(if n > 0 {
                        text.color(Color32::from_rgb(210, 40, 40))
                    } else {
                        text
                    });
                }
                ui.end_row();
            }
        });
}

/// Error against cost: x = ns per test, y = log₁₀ of the p99 t error in ulps of the point's own
/// precision (0.01 ulps for an exact method, so it stays on the plot). One point per method ×
/// precision.
fn error_plot(ui: &mut egui::Ui, prim: Primitive, points: &[&CostPoint]) {
    Plot::new(("lab-plot", prim.name()))
        .height(180.0)
        .legend(Legend::default())
        .x_axis_label("ns per test")
        .y_axis_label("log₁₀ p99 error (ulps of its precision: f32 ●, f64 ■)")
        .show(ui, |plot| {
            for p in points {
                let y = p.p99_ulps.max(0.01).log10();
                let shape = match p.precision {
                    Precision::F32 => egui_plot::MarkerShape::Circle,
                    Precision::F64 => egui_plot::MarkerShape::Square,
                };
                plot.points(
                    Points::new(p.label(), PlotPoints::from(vec![[p.ns_per_test, y]]))
                        .shape(shape)
                        .radius(6.0),
                );
            }
        });
}
