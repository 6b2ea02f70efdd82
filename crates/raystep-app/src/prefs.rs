//! The preferences the app remembers between runs (theme, scale, panels and their sizes, play
//! speed, recent files, student id), each checked when read back from a file.

use super::layout::Layout;
use crate::diagram::{self, DiagramKind};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// The colour scheme.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum ThemeChoice {
    /// Dark text on white (the default: best on most projectors).
    #[default]
    Light,
    /// Light text on dark grey.
    Dark,
    /// White on black with heavier lines, for a washed-out projector at the back of a hall.
    HighContrast,
}

impl ThemeChoice {
    /// The menu label.
    pub fn label(self) -> &'static str {
        match self {
            ThemeChoice::Light => "Light",
            ThemeChoice::Dark => "Dark",
            ThemeChoice::HighContrast => "High contrast",
        }
    }

    /// The diagrams' colours for this scheme.
    pub fn diagram_theme(self) -> diagram::Theme {
        match self {
            ThemeChoice::Light => diagram::Theme::LIGHT,
            ThemeChoice::Dark | ThemeChoice::HighContrast => diagram::Theme::DARK,
        }
    }
}

/// Which diagram the diagram panel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum DiagramChoice {
    /// The one that best explains the current step (changes as you step).
    #[default]
    Auto,
    /// Always this kind (when the trace has it).
    Kind(DiagramKind),
}

/// What the app remembers between runs (eframe persistence).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Prefs {
    /// Colour scheme.
    pub theme: ThemeChoice,
    /// UI scale (1 = normal).
    pub scale: f32,
    /// Presentation mode: high contrast, large text, full screen.
    pub presentation: bool,
    /// UI scale in presentation mode.
    pub presentation_scale: f32,
    /// The last scene or trace opened from a file.
    pub last_file: Option<PathBuf>,
    /// Recently opened files, newest first.
    pub recent: Vec<PathBuf>,
    /// Show the BVH heatmap over the render.
    pub heatmap: bool,
    /// Playback speed in steps per second.
    pub speed: f32,
    /// The diagram panel's choice.
    pub diagram: DiagramChoice,
    /// Slice diagram: angle of the cutting plane about the primary ray (degrees).
    pub slice_angle: f32,
    /// Slice diagram: view from above.
    pub top_down: bool,
    /// Show the trace tree panel.
    pub show_tree: bool,
    /// Show the settings panel.
    pub show_settings: bool,
    /// Show the lessons and exercises panel.
    pub show_learn: bool,
    /// The student id the exercises are drawn for.
    pub student: String,
    /// The panel sizes (fractions of the window) in force.
    pub layout: Layout,
    /// The colour scheme of presentation mode.
    pub presentation_theme: ThemeChoice,
    /// The panel sizes presentation mode uses (remembered from the last presentation).
    pub presentation_layout: Layout,
    /// The layout and panels to restore when presentation mode ends.
    pub before_presentation: Option<SavedLayout>,
    /// The answers typed into exercise sheets, kept between runs (in the browser: the page's
    /// storage): by [`answers_key`] (sheet and student), then by question id.
    pub answers: BTreeMap<String, BTreeMap<String, String>>,
}

/// The most sheet-and-student pairs whose answers are kept, and the longest answer kept.
pub const MAX_KEPT_SHEETS: usize = 64;
/// The longest answer kept (characters).
pub const MAX_KEPT_ANSWER: usize = 200;

/// Where the answers of `student` to the sheet `sheet` are kept in [`Prefs::answers`]: the
/// sheet's file name and the student id.
pub fn answers_key(sheet: &std::path::Path, student: &str) -> String {
    let name = sheet
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    format!("{name}|{student}")
}

/// The panels shown and their sizes, kept while presentation mode replaces them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(default)]
pub struct SavedLayout {
    /// The panel sizes.
    pub layout: Layout,
    /// The lessons panel was shown.
    pub show_learn: bool,
    /// The settings panel was shown.
    pub show_settings: bool,
    /// The trace tree was shown.
    pub show_tree: bool,
}

impl Default for Prefs {
    fn default() -> Self {
        Prefs {
            theme: ThemeChoice::Light,
            scale: 1.0,
            presentation: false,
            presentation_scale: 1.6,
            last_file: None,
            recent: vec![],
            heatmap: false,
            speed: 2.0,
            diagram: DiagramChoice::Auto,
            slice_angle: 0.0,
            top_down: false,
            show_tree: true,
            show_settings: true,
            show_learn: false,
            student: String::new(),
            layout: Layout::default(),
            presentation_theme: ThemeChoice::HighContrast,
            presentation_layout: Layout::presentation(),
            before_presentation: None,
            answers: BTreeMap::new(),
        }
    }
}

impl Prefs {
    /// The theme in force (presentation mode has its own, high contrast unless changed).
    pub fn effective_theme(&self) -> ThemeChoice {
        if self.presentation {
            self.presentation_theme
        } else {
            self.theme
        }
    }

    /// The theme the View menu changes: the one in force.
    pub fn theme_in_force_mut(&mut self) -> &mut ThemeChoice {
        if self.presentation {
            &mut self.presentation_theme
        } else {
            &mut self.theme
        }
    }

    /// The preferences with everything a damaged or foreign preferences file could spoil made
    /// safe: scales, speed and angle finite and in range, panel fractions valid for any window,
    /// paths absolute (relative ones are dropped: they depended on the folder the app was started
    /// from), at most 8 recent files, a student id of reasonable length.
    pub fn validated(mut self) -> Prefs {
        let d = Prefs::default();
        let fin = |x: f32, lo: f32, hi: f32, default: f32| {
            if x.is_finite() {
                x.max(lo).min(hi)
            } else {
                default
            }
        };
        self.scale = fin(self.scale, 0.5, 3.0, d.scale);
        self.presentation_scale = fin(self.presentation_scale, 0.5, 3.0, d.presentation_scale);
        self.speed = fin(self.speed, 0.25, 30.0, d.speed);
        self.slice_angle = fin(self.slice_angle, -180.0, 180.0, d.slice_angle);
        self.layout = self.layout.validated();
        self.presentation_layout = self.presentation_layout.validated();
        if let Some(b) = &mut self.before_presentation {
            b.layout = b.layout.validated();
        }
        if !self.presentation {
            self.before_presentation = None;
        }
        self.last_file = self.last_file.filter(|p| p.is_absolute());
        self.recent.retain(|p| p.is_absolute());
        self.recent.truncate(8);
        if self.student.chars().count() > 64 {
            self.student = self.student.chars().take(64).collect();
        }
        while self.answers.len() > MAX_KEPT_SHEETS {
            self.answers.pop_first();
        }
        for answers in self.answers.values_mut() {
            answers.retain(|q, a| q.len() <= 100 && a.chars().count() <= MAX_KEPT_ANSWER);
        }
        self
    }

    /// These preferences with presentation mode turned to `on`: turning it on keeps the
    /// panels shown and their sizes and puts presentation's own in their place (a large render,
    /// diagram and math panel; no settings or lessons panel; the trace tree folded); turning it
    /// off puts back exactly what was there before.
    pub fn with_presentation(mut self, on: bool) -> Prefs {
        if on == self.presentation {
            return self;
        }
        if on {
            self.before_presentation = Some(SavedLayout {
                layout: self.layout,
                show_learn: self.show_learn,
                show_settings: self.show_settings,
                show_tree: self.show_tree,
            });
            self.layout = self.presentation_layout.validated();
            self.show_learn = false;
            self.show_settings = false;
            self.show_tree = true;
        } else {
            self.presentation_layout = self.layout;
            if let Some(b) = self.before_presentation.take() {
                self.layout = b.layout;
                self.show_learn = b.show_learn;
                self.show_settings = b.show_settings;
                self.show_tree = b.show_tree;
            } else {
                self.layout = Layout::default();
            }
        }
        self.presentation = on;
        self
    }

    /// The UI scale in force in a window `height` points high at zoom 1. Presentation mode's
    /// scale is chosen for a screen [`PRESENTATION_HEIGHT`] points high and applied in
    /// proportion on a smaller one, never below 1: its text then takes the same share of the
    /// projected picture on a 1024×768 projector as on a 1920×1080 one, and the render and
    /// the diagram keep their room.
    pub fn effective_scale_for(&self, height: f32) -> f32 {
        if self.presentation {
            let k = if height.is_finite() && height > 0.0 {
                (height / PRESENTATION_HEIGHT).min(1.0)
            } else {
                1.0
            };
            (self.presentation_scale * k).max(self.presentation_scale.min(1.0))
        } else {
            self.scale
        }
    }
}

/// The screen height (points at zoom 1) presentation mode's scale is chosen for.
pub const PRESENTATION_HEIGHT: f32 = 1080.0;

#[cfg(test)]
mod tests {
    use super::*;

    /// Presentation mode's scale follows the screen's height below 1080 points, never below 1;
    /// the ordinary scale does not. (Values by hand: 1.6 · 768/1080 = 1.1378.)
    #[test]
    fn presentation_scale_follows_the_screen_height() {
        let p = Prefs {
            presentation: true,
            presentation_scale: 1.6,
            scale: 1.25,
            ..Prefs::default()
        };
        assert!((p.effective_scale_for(768.0) - 1.137_778).abs() < 1e-5);
        assert_eq!(p.effective_scale_for(1080.0), 1.6);
        assert_eq!(
            p.effective_scale_for(2160.0),
            1.6,
            "never above the chosen scale"
        );
        assert_eq!(p.effective_scale_for(400.0), 1.0, "never below 1");
        assert_eq!(p.effective_scale_for(f32::NAN), 1.6);
        let small = Prefs {
            presentation_scale: 0.8,
            ..p.clone()
        };
        assert_eq!(
            small.effective_scale_for(400.0),
            0.8,
            "a scale below 1 is kept"
        );
        let normal = Prefs {
            presentation: false,
            ..p
        };
        assert_eq!(normal.effective_scale_for(400.0), 1.25);
    }
}
