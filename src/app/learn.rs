//! Lessons and exercises in the app: the lessons of `lessons/` rendered as Markdown beside the
//! render (with buttons that open the lesson's scene at its pixel and jump to its steps), and an
//! exercise mode — a student's own variant of each question, an answer field, right or wrong at
//! once with how far off, hints one at a time, and then the step and diagram that explain the
//! answer.
//!
//! [`Learn`] is part of [`AppState`] and changes only through [`LearnCmd`]s; [`panel`] draws it.

use super::state::{AppState, Command, Message};
use super::view::Views;
use crate::lesson::{
    self, Answer, Lesson, Mark, Question, SceneSource, Sheet, lessons_dir, load_lessons, load_sheet,
};
use egui::{Color32, RichText};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, TryRecvError};

/// Which half of the panel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LearnTab {
    /// The lesson text.
    #[default]
    Lesson,
    /// The exercise sheet.
    Exercises,
}

/// One question's state for the current student.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Attempt {
    /// What is in the answer field.
    pub answer: String,
    /// The marking of the last check (of `checked`).
    pub mark: Option<Mark>,
    /// The answer that was checked.
    pub checked: String,
    /// What the tracer says (computed at the first check).
    pub expected: Option<Answer>,
    /// How many hints are shown.
    pub hints: usize,
    /// How many times the student checked.
    pub tries: u32,
}

/// The lessons and the exercise session.
#[derive(Debug, Default)]
pub struct Learn {
    /// The lessons.
    pub lessons: Vec<Lesson>,
    /// Why the lessons could not be read.
    pub lessons_error: Option<String>,
    /// The lesson shown.
    pub lesson: usize,
    /// The tab shown.
    pub tab: LearnTab,
    /// The exercise sheets found (`lessons/exercises/*.toml`).
    pub sheets: Vec<PathBuf>,
    /// The open sheet (or the error that loading it gave).
    pub sheet: Option<(PathBuf, Result<Sheet, String>)>,
    /// The student id variants are drawn for.
    pub student: String,
    /// The question shown.
    pub question: usize,
    /// One attempt per question of the open sheet.
    pub attempts: Vec<Attempt>,
    /// A check in progress: the expected answer is being computed on a background thread
    /// (loading the question's scene and preparing it never blocks the UI).
    pub checking: Option<Checking>,
    /// The question whose explaining step the app goes to when the pixel it just opened has
    /// been recorded.
    pub explain: Option<Question>,
}

/// A check waiting for its expected answer.
#[derive(Debug)]
pub struct Checking {
    /// The question checked.
    pub question: usize,
    /// The student id it was checked for.
    pub student: String,
    /// The answer as it was when the student pressed Check.
    pub answer: String,
    result: Receiver<Result<Answer, String>>,
}

/// What the learn panel can ask for.
#[derive(Debug, Clone, PartialEq)]
pub enum LearnCmd {
    /// Show a tab.
    Tab(LearnTab),
    /// Show lesson `i`.
    Lesson(usize),
    /// Open the shown lesson's scene with its settings, at its pixel and first step.
    OpenLesson,
    /// Open an exercise sheet (and show the exercises tab).
    OpenSheet(PathBuf),
    /// Change the student id (variants change with it; attempts start over).
    Student(String),
    /// Show question `i`.
    Question(usize),
    /// Edit the shown question's answer.
    Answer(String),
    /// Mark the shown question's answer.
    Check,
    /// Reveal the next hint.
    Hint,
    /// Open the shown question's scene at its pixel, on the step that explains the answer.
    Explain,
}

impl Learn {
    /// Reads the lessons and lists the sheets (`lessons/` as [`lessons_dir`] finds it).
    pub fn load(student: &str) -> Learn {
        let dir = lessons_dir();
        let lessons = match &dir {
            Ok(d) => load_lessons(d),
            Err(e) => Err(e.clone()),
        };
        let (lessons, lessons_error) = match lessons {
            Ok(l) => (l, None),
            Err(e) => (vec![], Some(e)),
        };
        let mut sheets: Vec<PathBuf> = dir
            .ok()
            .map(|d| d.join("exercises"))
            .and_then(|d| std::fs::read_dir(d).ok())
            .map(|entries| {
                entries
                    .filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| p.extension().is_some_and(|e| e == "toml"))
                    .collect()
            })
            .unwrap_or_default();
        sheets.sort();
        Learn {
            lessons,
            lessons_error,
            sheets,
            student: student.to_string(),
            ..Default::default()
        }
    }

    /// The lesson shown.
    pub fn current_lesson(&self) -> Option<&Lesson> {
        self.lessons.get(self.lesson)
    }

    /// The open sheet, if it loaded.
    pub fn current_sheet(&self) -> Option<&Sheet> {
        self.sheet.as_ref()?.1.as_ref().ok()
    }

    /// The question shown and its attempt.
    pub fn current_question(&self) -> Option<(&Question, &Attempt)> {
        let q = self.current_sheet()?.questions.get(self.question)?;
        Some((q, self.attempts.get(self.question)?))
    }

    fn reset_attempts(&mut self) {
        let n = self.current_sheet().map_or(0, |s| s.questions.len());
        self.attempts = vec![Attempt::default(); n];
        self.checking = None;
        self.question = self.question.min(n.saturating_sub(1));
    }
}

impl AppState {
    /// Applies a [`LearnCmd`].
    pub(super) fn apply_learn(&mut self, cmd: LearnCmd) {
        match cmd {
            LearnCmd::Tab(t) => self.learn.tab = t,
            LearnCmd::Lesson(i) => {
                let n = self.learn.lessons.len();
                self.learn.lesson = i.min(n.saturating_sub(1));
                self.learn.tab = LearnTab::Lesson;
            }
            LearnCmd::OpenLesson => {
                let Some(l) = self.learn.current_lesson().cloned() else {
                    return;
                };
                let step = l.steps.first().copied().unwrap_or(0);
                self.open_prepared(
                    &l.scene_path(),
                    Some(l.settings.clone()),
                    Some(l.pixel),
                    step,
                );
            }
            LearnCmd::OpenSheet(path) => {
                let sheet = load_sheet(&path).map_err(|e| e.to_string());
                self.learn.sheet = Some((path, sheet));
                self.learn.question = 0;
                self.learn.tab = LearnTab::Exercises;
                self.learn.reset_attempts();
            }
            LearnCmd::Student(id) => {
                if id != self.learn.student {
                    self.learn.student = id.clone();
                    self.prefs.student = id;
                    self.learn.reset_attempts();
                }
            }
            LearnCmd::Question(i) => {
                let n = self.learn.attempts.len();
                self.learn.question = i.min(n.saturating_sub(1));
            }
            LearnCmd::Answer(text) => {
                let i = self.learn.question;
                if let Some(a) = self.learn.attempts.get_mut(i) {
                    a.answer = text;
                }
            }
            LearnCmd::Hint => {
                let i = self.learn.question;
                let hints = self
                    .learn
                    .current_question()
                    .map_or(0, |(q, _)| q.hints.len());
                if let Some(a) = self.learn.attempts.get_mut(i) {
                    a.hints = (a.hints + 1).min(hints);
                }
            }
            LearnCmd::Check => self.check_answer(),
            LearnCmd::Explain => self.explain_answer(),
        }
    }

    /// Marks the shown answer against what the tracer computes for this student's variant.
    fn check_answer(&mut self) {
        let student = self.learn.student.trim().to_string();
        let i = self.learn.question;
        let Some(sheet) = self.learn.current_sheet() else {
            return;
        };
        let Some(q) = sheet.questions.get(i) else {
            return;
        };
        if student.is_empty() {
            self.message = Some(Message {
                text: "type your student id first: each student gets their own numbers".into(),
                error: true,
            });
            return;
        }
        let answer = self.learn.attempts[i].answer.clone();
        if let Some(e) = &self.learn.attempts[i].expected {
            let e = Ok(e.clone());
            self.finish_check(i, &answer, e);
            return;
        }
        // The expected answer: the question's scene loaded, prepared and traced off the UI
        // thread (a sheet may name a scene of a million triangles).
        let (sheet, q) = (sheet.clone(), q.clone());
        let (tx, rx) = std::sync::mpsc::channel();
        let repaint = self.repaint_handle();
        std::thread::spawn(move || {
            let expected = sheet.expected(&q, &sheet.variant(&q, &student));
            // A closed channel means the check was abandoned (another sheet or student).
            if tx.send(expected).is_ok() {
                repaint();
            }
        });
        self.learn.checking = Some(Checking {
            question: i,
            student: self.learn.student.trim().to_string(),
            answer,
            result: rx,
        });
    }

    /// Takes a finished check's expected answer and marks it (between frames).
    pub(super) fn take_check(&mut self) {
        let Some(c) = &self.learn.checking else {
            return;
        };
        let result = match c.result.try_recv() {
            Ok(r) => r,
            Err(TryRecvError::Empty) => return,
            Err(TryRecvError::Disconnected) => Err("the check stopped unexpectedly".into()),
        };
        let Some(c) = self.learn.checking.take() else {
            return;
        };
        if c.student == self.learn.student.trim() && c.question < self.learn.attempts.len() {
            self.finish_check(c.question, &c.answer, result);
        }
    }

    /// Marks `answer` to question `i` against the expected answer (or reports the sheet's
    /// error).
    fn finish_check(&mut self, i: usize, answer: &str, expected: Result<Answer, String>) {
        let expected = match expected {
            Ok(e) => e,
            Err(e) => {
                // The sheet (not the student) is wrong: say so, mark nothing.
                self.message = Some(Message {
                    text: e,
                    error: true,
                });
                return;
            }
        };
        let Some(q) = self.learn.current_sheet().and_then(|s| s.questions.get(i)) else {
            return;
        };
        let (kind, tolerance) = (q.quantity.kind(), q.tolerance);
        let Some(a) = self.learn.attempts.get_mut(i) else {
            return;
        };
        let m = lesson::mark(&expected, kind, Some(answer), tolerance);
        a.expected = Some(expected);
        a.checked = answer.to_string();
        a.tries += 1;
        a.mark = Some(m);
    }

    /// Opens the shown question's scene (this student's variant) at its pixel, on the step that
    /// shows the answer.
    fn explain_answer(&mut self) {
        let student = self.learn.student.trim().to_string();
        let Some(sheet) = self.learn.current_sheet() else {
            return;
        };
        let Some(q) = sheet.questions.get(self.learn.question) else {
            return;
        };
        let v = sheet.variant(q, &student);
        let loaded = match (&q.scene, &v.scene_toml) {
            (SceneSource::File(p), _) => crate::scene::load_file(p).map_err(|e| e.to_string()),
            (SceneSource::Inline(_), Some(text)) => {
                let name = format!("{} — question {}", sheet.title, q.id);
                crate::scene::load_str(text, &name, Path::new(&sheet.file).parent())
                    .map_err(|e| e.to_string())
            }
            (SceneSource::Inline(t), None) => {
                crate::scene::load_str(t, &q.id, None).map_err(|e| e.to_string())
            }
        };
        let scene = match loaded {
            Ok(s) => s,
            Err(e) => {
                self.message = Some(Message {
                    text: e,
                    error: true,
                });
                return;
            }
        };
        let [x, y] = v.pixel;
        if x >= scene.camera.width || y >= scene.camera.height {
            return;
        }
        // The step is found on the trace the app records once the scene is prepared (in the
        // background, like every scene the app opens).
        let q = q.clone();
        self.show_scene(scene, [x, y], 0);
        self.learn.explain = Some(q);
    }
}

/// The learn panel.
pub fn panel(ui: &mut egui::Ui, state: &AppState, views: &mut Views, cmds: &mut Vec<Command>) {
    // Every button and label wraps: one wider than the panel would widen what follows it too
    // (a lesson's text or a question would then be cut off at the panel's edge).
    ui.style_mut().wrap_mode = Some(egui::TextWrapMode::Wrap);
    let learn = &state.learn;
    ui.horizontal(|ui| {
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
        LearnTab::Lesson => lesson_tab(ui, state, views, cmds),
        LearnTab::Exercises => exercise_tab(ui, state, views, cmds),
    }
}

fn lesson_tab(ui: &mut egui::Ui, state: &AppState, views: &mut Views, cmds: &mut Vec<Command>) {
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
                cmds.push(Command::Step(super::state::StepMove::To(k)));
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
            egui_commonmark::CommonMarkViewer::new().show(ui, &mut views.markdown, &l.body);
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

fn exercise_tab(ui: &mut egui::Ui, state: &AppState, views: &mut Views, cmds: &mut Vec<Command>) {
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
            egui_commonmark::CommonMarkViewer::new().show(ui, &mut views.markdown, v.text.trim());
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
                    &mut views.markdown,
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
