//! Lessons and exercises in the app: the lessons of `lessons/` rendered as Markdown beside the
//! render (with buttons that open the lesson's scene at its pixel and jump to its steps), and an
//! exercise mode — a student's own variant of each question, an answer field, right or wrong at
//! once with how far off, hints one at a time, and then the step and diagram that explain the
//! answer.
//!
//! [`Learn`] is part of [`AppState`] and changes only through [`LearnCmd`]s;
//! [`crate::panels::learn`] draws it.

use super::{AppState, Message};
use crate::lesson::{
    self, Answer, ExerciseSheet, Lesson, Mark, Question, SceneSource, lessons_dir,
    load_exercise_sheet, load_lessons,
};
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
    /// The classic mistakes' answers for this pixel (computed with `expected`): a wrong answer
    /// that matches one is told which.
    pub mistakes: Vec<(lesson::Mistake, Answer)>,
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
    pub sheet: Option<(PathBuf, Result<ExerciseSheet, String>)>,
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
    result: Receiver<Result<lesson::mistakes::Key, String>>,
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
            .and_then(|d| crate::platform::files::list(&d).ok())
            .map(|entries| {
                entries
                    .into_iter()
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
    pub fn current_sheet(&self) -> Option<&ExerciseSheet> {
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
    /// The key the open sheet's answers are kept under for this student, and its questions' ids.
    fn answers_key(&self) -> Option<(String, Vec<String>)> {
        let (path, sheet) = self.learn.sheet.as_ref()?;
        let sheet = sheet.as_ref().ok()?;
        let student = self.learn.student.trim();
        (!student.is_empty()).then(|| {
            (
                crate::prefs::answers_key(path, student),
                sheet.questions.iter().map(|q| q.id.to_string()).collect(),
            )
        })
    }

    /// Puts back the answers this student typed into the open sheet last time (the marks come
    /// again with the next Check).
    fn restore_answers(&mut self) {
        let Some((key, ids)) = self.answers_key() else {
            return;
        };
        let Some(kept) = self.prefs.answers.get(&key) else {
            return;
        };
        for (a, id) in self.learn.attempts.iter_mut().zip(&ids) {
            if let Some(answer) = kept.get(id) {
                a.answer = answer.clone();
            }
        }
    }

    /// Keeps question `i`'s answer `text` in the preferences (saved between runs).
    fn keep_answer(&mut self, i: usize, text: String) {
        let Some((key, ids)) = self.answers_key() else {
            return;
        };
        let Some(id) = ids.get(i) else {
            return;
        };
        let kept = self.prefs.answers.entry(key).or_default();
        if text.trim().is_empty() {
            kept.remove(id);
        } else if text.chars().count() <= crate::prefs::MAX_KEPT_ANSWER {
            kept.insert(id.clone(), text);
        }
        self.prefs.answers.retain(|_, a| !a.is_empty());
        while self.prefs.answers.len() > crate::prefs::MAX_KEPT_SHEETS {
            self.prefs.answers.pop_first();
        }
    }

    /// The open sheet's answers as a class CSV of one row, as `raystep grade` reads it
    /// (`student,<question ids…>`).
    pub fn answers_csv(&self) -> Result<String, String> {
        let (_, sheet) = self
            .learn
            .sheet
            .as_ref()
            .ok_or("no exercise sheet is open")?;
        let sheet = sheet.as_ref().map_err(Clone::clone)?;
        let student = self.learn.student.trim();
        if student.is_empty() {
            return Err("type your student id first: the answers are for your variant".into());
        }
        let mut header = vec!["student".to_string()];
        let mut row = vec![student.to_string()];
        for (q, a) in sheet.questions.iter().zip(&self.learn.attempts) {
            header.push(q.id.to_string());
            row.push(a.answer.trim().to_string());
        }
        Ok(crate::text::csv::write_csv(&[header, row]))
    }

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
                let sheet = load_exercise_sheet(&path).map_err(|e| e.to_string());
                self.learn.sheet = Some((path, sheet));
                self.learn.question = 0;
                self.learn.tab = LearnTab::Exercises;
                self.learn.reset_attempts();
                self.restore_answers();
            }
            LearnCmd::Student(id) => {
                if id != self.learn.student {
                    self.learn.student = id.clone();
                    self.prefs.student = id;
                    self.learn.reset_attempts();
                    self.restore_answers();
                }
            }
            LearnCmd::Question(i) => {
                let n = self.learn.attempts.len();
                self.learn.question = i.min(n.saturating_sub(1));
            }
            LearnCmd::Answer(text) => {
                let i = self.learn.question;
                if let Some(a) = self.learn.attempts.get_mut(i) {
                    a.answer = text.clone();
                }
                self.keep_answer(i, text);
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
            let e = Ok((e.clone(), self.learn.attempts[i].mistakes.clone()));
            self.finish_check(i, &answer, e);
            return;
        }
        // The expected answer: the question's scene loaded, prepared and traced off the UI
        // thread (a sheet may name a scene of a million triangles).
        let (sheet, q) = (sheet.clone(), q.clone());
        let (tx, rx) = std::sync::mpsc::channel();
        let repaint = self.repaint_handle();
        crate::platform::spawn(move || {
            let expected = sheet.expected_and_mistakes(&q, &sheet.variant(&q, &student));
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
    fn finish_check(
        &mut self,
        i: usize,
        answer: &str,
        expected: Result<lesson::mistakes::Key, String>,
    ) {
        let (expected, found) = match expected {
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
        let mut m = lesson::mark(&expected, q.quantity.kind(), Some(answer), q.tolerance);
        lesson::mistakes::annotate(&mut m, q, Some(answer), &found);
        let Some(a) = self.learn.attempts.get_mut(i) else {
            return;
        };
        a.expected = Some(expected);
        a.mistakes = found;
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
