//! The learn panel: the lessons rendered as Markdown beside the render, and exercise mode (a
//! student's own variant of each question, an answer field, the mark, hints, and the step that
//! explains the answer). It reads [`crate::state::learn::Learn`] and returns commands.

use crate::lesson::{self, Answer, Lesson, Mark};
use crate::state::learn::{Attempt, LearnCmd, LearnTab};
use crate::state::{AppState, Command, Dialog, SaveKind};
use egui::{Color32, RichText};
use std::path::Path;

/// What the learn panel keeps between frames (not persisted).
#[derive(Default)]
pub struct LearnPanel {
    /// The Markdown viewer's cache (the lessons' layout).
    pub markdown: egui_commonmark::CommonMarkCache,
}

/// The learn panel.
pub fn panel(ui: &mut egui::Ui, state: &AppState, cache: &mut LearnPanel, cmds: &mut Vec<Command>) {
    // Every button and label wraps: one wider than the panel would widen what follows it too
    // (a lesson's text or a question would then be cut off at the panel's edge).
    ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Wrap);
    let learn = &state.learn;
    // The tabs' names are single words: broken in the middle ("Exercise / s") they read badly,
    // so in a narrow panel the second tab moves to a row of its own instead.
    ui.horizontal_wrapped(|ui| {
        ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Extend);
        for (tab, label) in [
            (LearnTab::Lesson, "Lesson"),
            (LearnTab::Exercises, "Exercises"),
        ] {
            if ui
                .selectable_label(learn.tab == tab, RichText::new(label).strong())
                .clicked()
            {
                cmds.push(Command::Learn(LearnCmd::Tab(tab)));
            }
        }
    });
    ui.separator();
    match learn.tab {
        LearnTab::Lesson => lesson_tab(ui, state, cache, cmds),
        LearnTab::Exercises => exercise_tab(ui, state, cache, cmds),
    }
}

fn lesson_tab(
    ui: &mut egui::Ui,
    state: &AppState,
    cache: &mut LearnPanel,
    cmds: &mut Vec<Command>,
) {
    let learn = &state.learn;
    if let Some(e) = &learn.lessons_error {
        ui.colored_label(ui.visuals().error_fg_color, e);
        return;
    }
    let lessons = &learn.lessons;
    if lessons.is_empty() {
        ui.label("No lessons found in lessons/.");
        return;
    }
    let i = learn.lesson.min(lessons.len() - 1);
    let l = &lessons[i];
    ui.horizontal(|ui| {
        if ui
            .add_enabled(i > 0, egui::Button::new("◀"))
            .on_hover_text("previous lesson")
            .on_disabled_hover_text("this is the first lesson")
            .clicked()
        {
            cmds.push(Command::Learn(LearnCmd::Lesson(i - 1)));
        }
        // ▶ first, at the right edge; the chooser takes what is left (its drop-down icon comes
        // on top of the width it is given), so the row is never wider than the panel.
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            if ui
                .add_enabled(i + 1 < lessons.len(), egui::Button::new("▶"))
                .on_hover_text("next lesson")
                .on_disabled_hover_text("this is the last lesson")
                .clicked()
            {
                cmds.push(Command::Learn(LearnCmd::Lesson(i + 1)));
            }
            let sp = ui.spacing();
            let icon = sp.icon_width + sp.icon_spacing + 2.0 * sp.button_padding.x;
            egui::ComboBox::from_id_salt("lesson-choice")
                .selected_text(format!("{}. {}", i + 1, l.title))
                .width((ui.available_width() - icon - sp.item_spacing.x).max(40.0))
                .truncate()
                .show_ui(ui, |ui| {
                    for (k, other) in lessons.iter().enumerate() {
                        if ui
                            .selectable_label(k == i, format!("{}. {}", k + 1, other.title))
                            .clicked()
                        {
                            cmds.push(Command::Learn(LearnCmd::Lesson(k)));
                        }
                    }
                });
        });
    });
    let here = state.path() == Some(l.scene_path().as_path()) && state.pixel == Some(l.pixel);
    ui.horizontal_wrapped(|ui| {
        if ui
            .button(format!(
                "Open {} at pixel ({}, {})",
                l.scene, l.pixel[0], l.pixel[1]
            ))
            .on_hover_text("opens the scene with the lesson's settings and selects the pixel")
            .clicked()
        {
            cmds.push(Command::Learn(LearnCmd::OpenLesson));
        }
    });
    ui.horizontal_wrapped(|ui| {
        ui.label("Steps to look at:");
        for &k in &l.steps {
            let b = ui
                .add_enabled(
                    here,
                    egui::Button::new(k.to_string()).selected(here && state.step == k),
                )
                .on_hover_text(format!("go to step {k} (counted from 0)"))
                .on_disabled_hover_text("open the lesson's scene and pixel first");
            if b.clicked() {
                cmds.push(Command::Step(crate::state::StepMove::To(k)));
            }
        }
    });
    if !l.settings.is_empty() {
        ui.label(RichText::new(settings_line(l)).small());
    }
    if let Some(p) = l.exercises_path()
        && ui.button("Exercises for this lesson").clicked()
    {
        cmds.push(Command::Learn(LearnCmd::OpenSheet(p)));
    }
    ui.separator();
    egui::ScrollArea::vertical()
        .id_salt(("lesson-scroll", i))
        .auto_shrink([false, false])
        .show(ui, |ui| {
            egui_commonmark::CommonMarkViewer::new().show(ui, &mut cache.markdown, &l.body);
        });
    follow_links(ui, lessons, l, cmds);
}

/// The lesson's `[settings]` in words.
fn settings_line(l: &Lesson) -> String {
    // The spellings of the scene format (and of the lesson's front matter).
    fn spelled<T: serde::Serialize>(v: T) -> String {
        serde_json::to_value(v)
            .ok()
            .and_then(|v| v.as_str().map(String::from))
            .unwrap_or_default()
    }
    let s = &l.settings;
    let mut parts = vec![];
    if let Some(v) = s.sphere_method {
        parts.push(format!("sphere method {}", spelled(v)));
    }
    if let Some(v) = s.triangle_method {
        parts.push(format!("triangle method {}", spelled(v)));
    }
    if let Some(v) = s.offset {
        parts.push(format!("offset {}", spelled(v)));
    }
    if let Some(v) = s.accel {
        parts.push(format!("accel {}", spelled(v)));
    }
    if let Some(v) = s.bvh_quality {
        parts.push(format!("BVH quality {}", spelled(v)));
    }
    if let Some(v) = s.spp {
        parts.push(format!("{v} samples per pixel"));
    }
    if let Some(v) = s.max_depth {
        parts.push(format!("depth {v}"));
    }
    if let Some(v) = s.epsilon {
        parts.push(format!("ε = {v}"));
    }
    if let Some(v) = s.seed {
        parts.push(format!("seed {v}"));
    }
    format!("The lesson sets: {}.", parts.join(", "))
}

/// Links between lessons and to scenes open in the app instead of a browser; web links are
/// left for the platform to open.
fn follow_links(ui: &egui::Ui, lessons: &[Lesson], current: &Lesson, cmds: &mut Vec<Command>) {
    ui.ctx().output_mut(|o| {
        o.commands.retain(|c| {
            let egui::OutputCommand::OpenUrl(open) = c else {
                return true;
            };
            let url = open.url.as_str();
            if url.contains("://") || url.starts_with("mailto:") || url.starts_with('#') {
                return true;
            }
            let file = url.split('#').next().unwrap_or(url);
            let target = current.dir().join(file);
            if let Some(k) = lessons.iter().position(|l| {
                l.file.file_name() == target.file_name() && l.file.parent() == target.parent()
            }) {
                cmds.push(Command::Learn(LearnCmd::Lesson(k)));
            } else if file.ends_with(".toml") || file.ends_with(".json") {
                cmds.push(Command::Open(target));
            }
            // Anything else relative (the README, an OBJ) has no view here: drop it.
            false
        })
    });
}

fn exercise_tab(
    ui: &mut egui::Ui,
    state: &AppState,
    cache: &mut LearnPanel,
    cmds: &mut Vec<Command>,
) {
    let learn = &state.learn;
    let current = learn.sheet.as_ref().map(|(p, _)| p.as_path());
    let name = |p: &Path| {
        p.file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into())
    };
    ui.horizontal(|ui| {
        ui.label("Sheet:");
        egui::ComboBox::from_id_salt("sheet-choice")
            .selected_text(current.map_or("choose a sheet".into(), name))
            .show_ui(ui, |ui| {
                for p in &learn.sheets {
                    if ui
                        .selectable_label(current == Some(p.as_path()), name(p))
                        .clicked()
                    {
                        cmds.push(Command::Learn(LearnCmd::OpenSheet(p.clone())));
                    }
                }
            });
    });
    let mut student = learn.student.clone();
    ui.horizontal(|ui| {
        let label = ui.label("Student id:");
        let r = ui.add(
            egui::TextEdit::singleline(&mut student)
                .hint_text("e.g. your login")
                .desired_width(160.0),
        );
        r.labelled_by(label.id);
    });
    if student != learn.student {
        cmds.push(Command::Learn(LearnCmd::Student(student)));
    }
    let Some((path, sheet)) = &learn.sheet else {
        ui.label(
            "Choose a sheet: each question asks for a number the tracer computes for a pixel.",
        );
        return;
    };
    let sheet = match sheet {
        Ok(s) => s,
        Err(e) => {
            ui.colored_label(ui.visuals().error_fg_color, e);
            if ui.button("Reload the sheet").clicked() {
                cmds.push(Command::Learn(LearnCmd::OpenSheet(path.clone())));
            }
            return;
        }
    };
    ui.label(RichText::new(&sheet.title).strong());
    let right = learn
        .attempts
        .iter()
        .filter(|a| a.mark.as_ref().is_some_and(|m| m.right))
        .count();
    ui.horizontal_wrapped(|ui| {
        for (k, (q, a)) in sheet.questions.iter().zip(&learn.attempts).enumerate() {
            let sign = match &a.mark {
                Some(m) if m.right => " ✔",
                Some(_) => " ✘",
                None => "",
            };
            if ui
                .selectable_label(k == learn.question, format!("{}{sign}", k + 1))
                .on_hover_text(&q.id)
                .clicked()
            {
                cmds.push(Command::Learn(LearnCmd::Question(k)));
            }
        }
        ui.label(format!("{right} of {} right", sheet.questions.len()));
        if ui
            .button("Export answers")
            .on_hover_text(
                "Your answers as a CSV file (student, question ids) that your teacher's \
                 `raystep grade` marks",
            )
            .clicked()
        {
            cmds.push(Command::ShowDialog(Dialog::Save {
                kind: SaveKind::Answers,
                path: state.suggested_name(SaveKind::Answers),
            }));
        }
    });
    ui.separator();
    let Some((q, a)) = learn.current_question() else {
        return;
    };
    if learn.student.trim().is_empty() {
        ui.label("Type your student id: the numbers in the questions are your own.");
        return;
    }
    let v = sheet.variant(q, learn.student.trim());
    egui::ScrollArea::vertical()
        .id_salt("question-scroll")
        .auto_shrink([false, false])
        .show(ui, |ui| {
            ui.label(
                RichText::new(format!(
                    "Question {} of {} ({} point{})",
                    learn.question + 1,
                    sheet.questions.len(),
                    crate::lesson::short(q.points),
                    if q.points == 1.0 { "" } else { "s" }
                ))
                .strong(),
            );
            // Question texts and hints are Markdown (`code`, *emphasis*; line breaks reflow).
            egui_commonmark::CommonMarkViewer::new().show(ui, &mut cache.markdown, v.text.trim());
            ui.add_space(6.0);
            let mut answer = a.answer.clone();
            let mut submit = false;
            ui.horizontal_wrapped(|ui| {
                let label = ui.label("Answer:");
                let r = ui.add(
                    egui::TextEdit::singleline(&mut answer)
                        .hint_text(q.quantity.kind().describe())
                        .desired_width(ui.available_width().min(200.0)),
                );
                submit = r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                r.labelled_by(label.id);
                let checking = learn.checking.is_some();
                if ui
                    .add_enabled(!checking, egui::Button::new("Check"))
                    .on_disabled_hover_text("computing the expected answer for your variant…")
                    .clicked()
                {
                    submit = true;
                }
            });
            if answer != a.answer {
                cmds.push(Command::Learn(LearnCmd::Answer(answer)));
            }
            if submit && learn.checking.is_none() {
                cmds.push(Command::Learn(LearnCmd::Check));
            }
            if let Some(m) = &a.mark {
                mark_line(ui, m, a, sheet.feedback);
            }
            ui.add_space(6.0);
            ui.horizontal_wrapped(|ui| {
                let more = a.hints < q.hints.len();
                if ui
                    .add_enabled(
                        more,
                        egui::Button::new(format!("Hint ({} of {})", a.hints, q.hints.len())),
                    )
                    .on_hover_text("shows the next hint")
                    .on_disabled_hover_text(if q.hints.is_empty() {
                        "this question has no hints"
                    } else {
                        "every hint is shown"
                    })
                    .clicked()
                {
                    cmds.push(Command::Learn(LearnCmd::Hint));
                }
                if ui
                    .add_enabled(a.tries > 0, egui::Button::new("Show me in the tracer"))
                    .on_disabled_hover_text(
                        "check an answer first: the tracer shows the answer after your first try",
                    )
                    .on_hover_text(
                        "opens this question's scene and pixel on the step with the answer",
                    )
                    .clicked()
                {
                    cmds.push(Command::Learn(LearnCmd::Explain));
                }
            });
            for (k, h) in q.hints.iter().take(a.hints).enumerate() {
                egui_commonmark::CommonMarkViewer::new().show(
                    ui,
                    &mut cache.markdown,
                    &format!("**Hint {}:** {h}", k + 1),
                );
            }
            if a.mark.as_ref().is_some_and(|m| m.right)
                && let Some(e) = &a.expected
            {
                ui.add_space(4.0);
                ui.label(format!("The tracer computed: {}", show_answer(e)));
            }
        });
}

/// An expected answer: the tracer's numbers are f32, so they print as f32 (no f64 noise).
fn show_answer(a: &Answer) -> String {
    lesson::show(a)
}

/// Right or wrong, and what the sheet's feedback policy tells about it.
fn mark_line(ui: &mut egui::Ui, m: &Mark, a: &Attempt, feedback: lesson::Feedback) {
    let told = a
        .expected
        .as_ref()
        .map(|e| feedback.explain(m, e, a.tries))
        .unwrap_or_default();
    let stale = if a.checked != a.answer {
        " (for the answer checked before your edit)"
    } else {
        ""
    };
    let (color, text) = if m.right {
        let close = if told.is_empty() {
            String::new()
        } else {
            format!(" — {told}")
        };
        (
            Color32::from_rgb(0, 150, 60),
            format!("✔ Right{close}{stale}"),
        )
    } else {
        let why = if told.is_empty() {
            "that is not what the tracer found".to_string()
        } else {
            told
        };
        (
            Color32::from_rgb(210, 40, 40),
            format!("✘ Not right: {why}{stale}. Try again, or take a hint."),
        )
    };
    ui.label(RichText::new(text).color(color).strong());
}
