//! What the panels ask the app's state for: [`Command`], and the small vocabulary its commands
//! are made of (moves through the timeline, what a save writes, the open dialog).

use super::learn::LearnCmd;
use super::{Prefs, editing, gpu, lab};
use crate::platform::Duration;
use crate::record::Trace;
use crate::scene::Settings;
use std::path::PathBuf;
use std::sync::Arc;

/// A move through the timeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepMove {
    /// The first step.
    First,
    /// One back.
    Previous,
    /// One forward.
    Next,
    /// The last step.
    Last,
    /// Step number k.
    To(usize),
}

/// What a save dialog writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SaveKind {
    /// The current trace as JSON.
    Trace,
    /// The current diagram as PNG.
    DiagramPng,
    /// Every step of the current diagram as an animated GIF.
    StepsGif,
    /// The edited scene as TOML ("Save as").
    Scene,
    /// The open exercise sheet's answers, as a one-row class CSV for `raystep grade`.
    Answers,
}

impl SaveKind {
    /// The dialog's title.
    pub fn title(self) -> &'static str {
        match self {
            SaveKind::Trace => "Save trace (JSON)",
            SaveKind::DiagramPng => "Export diagram (PNG)",
            SaveKind::StepsGif => "Export all steps (animated GIF)",
            SaveKind::Scene => "Save scene as (TOML)",
            SaveKind::Answers => "Export answers (CSV for raystep grade)",
        }
    }
}

/// An open dialog.
#[derive(Debug, Clone, PartialEq)]
pub enum Dialog {
    /// Open a scene or trace file by path.
    Open {
        /// The path being typed.
        path: String,
    },
    /// Save or export to a path.
    Save {
        /// What to write.
        kind: SaveKind,
        /// The path being typed.
        path: String,
    },
}

/// How long "watch it converge" holds each pass of a Monte Carlo render on screen.
pub const CONVERGE_PACE: Duration = Duration::from_millis(800);

/// Everything a panel can ask for.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// Open a scene (.toml, .gltf, .glb) or a saved trace (.json).
    Open(PathBuf),
    /// Open the built-in scene.
    OpenBuiltin,
    /// Reload the open file.
    Reload,
    /// Change the live settings (restarts the render).
    SetSettings(Settings),
    /// Select a pixel (traces it).
    SelectPixel([u32; 2]),
    /// Choose which sample of the pixel to trace.
    SetSample(u32),
    /// Move through the steps.
    Step(StepMove),
    /// Start or stop playback.
    TogglePlay,
    /// Start or stop adding the pixel's samples one at a time (from the traced one; from the
    /// first when the last is traced).
    ToggleSamplePlay,
    /// Render again, holding each progressive pass on screen for [`CONVERGE_PACE`] ("watch it
    /// converge"; a Monte Carlo scene's render only).
    WatchConverge,
    /// Change the preferences.
    SetPrefs(Prefs),
    /// Write a file.
    Save(SaveKind, PathBuf),
    /// Show a dialog.
    ShowDialog(Dialog),
    /// Close the dialog.
    CloseDialog,
    /// Show an error in the status bar (a file the browser could not read, …).
    ShowError(String),
    /// Lessons and exercises.
    Learn(LearnCmd),
    /// Hide the load error banner (until the next error).
    DismissError,
    /// Put the panels back to their default sizes (for the mode in force).
    ResetLayout,
    /// Edit the scene, select an object, undo, redo, save.
    Edit(editing::EditCmd),
    /// Step through the GPU's own trace of the selected pixel (from the GPU tab) instead of the
    /// CPU's; the step index is kept, so the same step can be compared.
    /// With the first step where it parts from the CPU's, if it does.
    ShowGpuTrace(Arc<Trace>, Option<usize>),
    /// Back to the CPU's trace of the selected pixel (recorded again), the step index kept.
    ShowCpuTrace,
    /// Run the stability lab's suite, or compare the path tracer's strategies.
    Lab(lab::LabCmd),
    /// The GPU view: trace its frame, compare it with the CPU render, trace the pixel on the
    /// GPU, change its path or orbit.
    Gpu(gpu::GpuCmd),
}
