//! The stability lab in the app: a window that runs the quick suite of [`crate::stability`] on a
//! background thread and shows its table and its error-against-cost plots (egui_plot), and, for
//! the selected pixel, every number the tracer recorded beside its exact value and the error in
//! ulps (click a row to go to its step). For a path-traced scene it also compares the path
//! tracer's estimators (light sampling, BSDF sampling, MIS) as `raystep converge --strategy`
//! does: the same table, and the error against samples per pixel as a plot.

use super::state::{AppState, Command, StepMove};
use crate::scene::{Integrator, Scene, Strategy};
use crate::stability::converge::{
    ConvergeOptions, StrategyRun, Target, measured_words, run_strategies, strategy_name,
    strategy_table, target_words,
};
use crate::stability::pixel::{ExactValue, exact_values};
use crate::stability::{self, CostPoint, Precision, Primitive, Report};
use egui::{Color32, RichText};
use egui_plot::{Legend, Line, Plot, PlotPoints, Points};

/// A finished comparison of strategies, or why it failed.
pub type Comparison = Result<Vec<StrategyRun>, String>;

/// The strategies the lab compares, in the table's order.
const ALL_STRATEGIES: [Strategy; 3] = [Strategy::Light, Strategy::Bsdf, Strategy::Mis];
use crate::platform::Instant;
use std::sync::mpsc::Receiver;

/// The lab window's state (part of [`super::panels::Panels`]).
pub struct LabView {
    /// The window is open.
    pub open: bool,
    /// What the suite button runs (the quick suite, on one worker thread).
    pub options: stability::Options,
    /// The quick suite running in the background, and when it started.
    running: Option<(Receiver<Report>, Instant)>,
    /// The last report.
    pub report: Option<Report>,
    /// The exact values of the selected pixel's trace (for the trace generation they were made
    /// for).
    pixel: Option<(u64, Vec<ExactValue>)>,
    /// The strategy comparison running in the background, and when it started.
    comparing: Option<(Receiver<Comparison>, Instant, String)>,
    /// The last comparison (or why it failed), and the scene it was of.
    pub comparison: Option<(String, Comparison)>,
}

/// What the lab's comparison of strategies renders: the levels up to this spp, with this many
/// seeds (the command line's `--max-spp 16 --seeds 2`).
pub const COMPARE_MAX_SPP: u32 = 16;
/// Seeds per level of the lab's comparison.
pub const COMPARE_SEEDS: u32 = 2;

impl Default for LabView {
    fn default() -> Self {
        LabView {
            open: false,
            // One worker: the render and the UI keep the other core.
            options: stability::Options {
                threads: Some(1),
                ..stability::Options::quick()
            },
            running: None,
            report: None,
            pixel: None,
            comparing: None,
            comparison: None,
        }
    }
}

impl LabView {
    /// Starts the quick suite in the background (unless it is running): a case a step, on a
    /// thread of its own natively, between frames in a web page (which keeps drawing).
    pub fn start(&mut self, ctx: &egui::Context) {
        if self.running.is_some() {
            return;
        }
        let (tx, rx) = std::sync::mpsc::channel();
        let repaint = ctx.clone();
        let mut suite = stability::Suite::new(&self.options);
        crate::platform::spawn_steps(move || match suite.step() {
            None => true,
            Some(report) => {
                let _ = tx.send(report);
                repaint.request_repaint();
                false
            }
        });
        self.running = Some((rx, Instant::now()));
    }

    /// Whether the suite or a comparison is running.
    pub fn running(&self) -> bool {
        self.running.is_some() || self.comparing.is_some()
    }

    /// Starts comparing the path tracer's strategies on `scene` in the background.
    pub fn compare(&mut self, ctx: &egui::Context, scene: Scene) {
        if self.comparing.is_some() {
            return;
        }
        let (tx, rx) = std::sync::mpsc::channel();
        let repaint = ctx.clone();
        let name = scene.name.clone();
        crate::platform::spawn(move || {
            let opts = ConvergeOptions {
                max_spp: COMPARE_MAX_SPP,
                seeds: COMPARE_SEEDS,
                threads: Some(1),
                ..ConvergeOptions::default()
            };
            let runs = run_strategies(&scene, &opts, &ALL_STRATEGIES, &mut |_| {});
            let _ = tx.send(runs);
            repaint.request_repaint();
        });
        self.comparing = Some((rx, Instant::now(), name));
    }

    /// Takes a finished run.
    fn poll(&mut self) {
        if let Some((rx, _, name)) = &self.comparing
            && let Ok(r) = rx.try_recv()
        {
            self.comparison = Some((name.clone(), r));
            self.comparing = None;
        }
        if let Some((rx, _)) = &self.running
            && let Ok(r) = rx.try_recv()
        {
            self.report = Some(r);
            self.running = None;
        }
    }
}

/// The lab window (when open).
pub fn window(ctx: &egui::Context, state: &AppState, lab: &mut LabView, cmds: &mut Vec<Command>) {
    lab.poll();
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
            strategies_section(ui, state, lab);
            ui.separator();
            suite_section(ui, lab);
        });
    lab.open = open;
    if lab.running() {
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
fn strategies_section(ui: &mut egui::Ui, state: &AppState, lab: &mut LabView) {
    let scene = state.prepared.as_ref().map(|p| p.scene().clone());
    let path = scene
        .as_ref()
        .is_some_and(|s| s.settings.integrator == Integrator::Path);
    ui.horizontal_wrapped(|ui| {
        let button = ui
            .add_enabled(
                path && lab.comparing.is_none(),
                egui::Button::new("Compare light, BSDF and MIS"),
            )
            .on_hover_text(format!(
                "the path tracer's three estimators at 1 … {COMPARE_MAX_SPP} spp, {COMPARE_SEEDS} \
                 seeds each, against one reference (as `raystep converge SCENE --strategy \
                 light,bsdf,mis --max-spp {COMPARE_MAX_SPP} --seeds {COMPARE_SEEDS}`)"
            ));
        if button.clicked()
            && let Some(s) = scene.clone()
        {
            lab.compare(ui.ctx(), s);
        }
        if let Some((_, started, _)) = &lab.comparing {
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

fn suite_section(ui: &mut egui::Ui, lab: &mut LabView) {
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
            lab.start(ui.ctx());
        }
        if let Some((_, started)) = &lab.running {
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
