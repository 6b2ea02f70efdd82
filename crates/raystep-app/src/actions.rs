//! The app's actions in one table: what each menu item, button and key does. Every [`Action`]
//! names its label, its tooltip, its keyboard shortcuts and the [`Effect`] it has (most issue
//! a [`Command`]); the menu bar, the step controls, the editor's buttons, the Help menu and the
//! keyboard handler all read them here, so a shortcut and the text that tells of it cannot
//! drift apart.
//!
//! Keys with Ctrl (⌘ on a Mac) are consumed as shortcuts and shown in the button's tooltip;
//! plain keys count every press (auto-repeat included) and are listed in the Help menu.

use super::state::editing::EditCmd;
use super::state::{AppState, Command, Dialog, SaveKind, StepMove};
use super::view::RenderView;
use egui::{Key, KeyboardShortcut, Modifiers};
use std::borrow::Cow;

/// Something the user can ask for from a menu, a button or the keyboard.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// File → Open….
    Open,
    /// File → Built-in scene.
    OpenBuiltin,
    /// File → Reload (and the load-error banner's button).
    Reload,
    /// A save dialog: File → Save trace, Export diagram, Export all steps; the editor's Save as.
    SaveAs(SaveKind),
    /// File → Quit.
    Quit,
    /// View → Full screen.
    FullScreen,
    /// View → Reset zoom (the render back to fit).
    ResetZoom,
    /// View → Reset layout.
    ResetLayout,
    /// The Lessons toggle in the menu bar.
    Lessons,
    /// The Lab toggle in the menu bar.
    Lab,
    /// The first step.
    FirstStep,
    /// The previous step.
    PreviousStep,
    /// Play or pause the steps.
    PlayPause,
    /// The next step.
    NextStep,
    /// The last step.
    LastStep,
    /// The editor's redo.
    Redo,
    /// The editor's undo.
    Undo,
    /// The editor's save (the scene file written back).
    SaveScene,
    /// Close the open dialog.
    CloseDialog,
    /// Leave presentation mode (the layout from before it comes back).
    LeavePresentation,
}

/// What an action does.
// One is made per click or key press and applied at once: its size does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq)]
pub enum Effect {
    /// Changes the state: applied by [`AppState::apply`] after the frame.
    Command(Command),
    /// Full screen on or off (the window's, done after the frame).
    ToggleFullscreen,
    /// The render view back to fit.
    ResetZoom,
    /// The lab window open or closed.
    ToggleLab,
    /// Closes the window.
    Quit,
}

/// A key, with or without Ctrl (⌘ on a Mac) and Shift.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shortcut {
    /// With Ctrl (⌘ on a Mac): consumed as a shortcut. Without: every press of the key counts,
    /// with Shift or not, but not with Ctrl, ⌘ or Alt.
    pub command: bool,
    /// With Shift too (only with `command`).
    pub shift: bool,
    /// The key.
    pub key: Key,
}

const fn plain(key: Key) -> Shortcut {
    Shortcut {
        command: false,
        shift: false,
        key,
    }
}

const fn ctrl(key: Key) -> Shortcut {
    Shortcut {
        command: true,
        shift: false,
        key,
    }
}

const fn ctrl_shift(key: Key) -> Shortcut {
    Shortcut {
        command: true,
        shift: true,
        key,
    }
}

impl Shortcut {
    /// The shortcut as the Help menu and tooltips write it: "←", "Home", "Ctrl+Shift+Z".
    pub fn text(self) -> String {
        let key = match self.key {
            Key::ArrowLeft => "←",
            Key::ArrowRight => "→",
            Key::ArrowUp => "↑",
            Key::ArrowDown => "↓",
            Key::Escape => "Esc",
            k => k.name(),
        };
        let ctrl = if self.command { "Ctrl+" } else { "" };
        let shift = if self.shift { "Shift+" } else { "" };
        format!("{ctrl}{shift}{key}")
    }

    /// egui's form of a shortcut with Ctrl (None for a plain key).
    fn keyboard_shortcut(self) -> Option<KeyboardShortcut> {
        let modifiers = match (self.command, self.shift) {
            (false, _) => return None,
            (true, false) => Modifiers::COMMAND,
            (true, true) => Modifiers::COMMAND | Modifiers::SHIFT,
        };
        Some(KeyboardShortcut::new(modifiers, self.key))
    }
}

impl Action {
    /// Every action, in the order the keyboard handler tries them: Redo before Undo (Ctrl+Z
    /// would also match Ctrl+Shift+Z, as it ignores Shift), and for Esc, closing a dialog
    /// before leaving presentation mode.
    pub const ALL: [Action; 23] = [
        Action::Open,
        Action::OpenBuiltin,
        Action::Reload,
        Action::SaveAs(SaveKind::Trace),
        Action::SaveAs(SaveKind::DiagramPng),
        Action::SaveAs(SaveKind::StepsGif),
        Action::Quit,
        Action::FullScreen,
        Action::ResetZoom,
        Action::ResetLayout,
        Action::Lessons,
        Action::Lab,
        Action::FirstStep,
        Action::PreviousStep,
        Action::PlayPause,
        Action::NextStep,
        Action::LastStep,
        Action::Redo,
        Action::Undo,
        Action::SaveScene,
        Action::SaveAs(SaveKind::Scene),
        Action::CloseDialog,
        Action::LeavePresentation,
    ];

    /// The words on its menu item or button (Play becomes Pause while playing).
    pub fn label(self, state: &AppState) -> Cow<'static, str> {
        Cow::Borrowed(match self {
            Action::Open => "Open…",
            Action::OpenBuiltin => "Built-in scene",
            Action::Reload => "Reload",
            Action::SaveAs(SaveKind::Scene) => "Save as…",
            Action::SaveAs(kind) => return Cow::Owned(format!("{}…", kind.title())),
            Action::Quit => "Quit",
            Action::FullScreen => "Full screen",
            Action::ResetZoom => "Reset zoom",
            Action::ResetLayout => "Reset layout",
            Action::Lessons => "Lessons",
            Action::Lab => "Lab",
            Action::FirstStep => "⇤ First",
            Action::PreviousStep => "◀ Previous",
            Action::PlayPause if state.playing => "‖ Pause",
            Action::PlayPause => "▶ Play",
            Action::NextStep => "Next ▶",
            Action::LastStep => "Last ⇥",
            Action::Redo => "⟳ Redo",
            Action::Undo => "⟲ Undo",
            Action::SaveScene => "Save",
            Action::CloseDialog => "Cancel",
            Action::LeavePresentation => "Leave presentation mode",
        })
    }

    /// The label of its menu item: with its first plain key, if it has one ("Full screen (F11)").
    pub fn menu_label(self, state: &AppState) -> String {
        let label = self.label(state);
        match self.shortcuts().first() {
            Some(s) if !s.command => format!("{label} ({})", s.text()),
            _ => label.into_owned(),
        }
    }

    /// What it explains when hovered, without the shortcut.
    fn hint(self) -> Option<&'static str> {
        match self {
            Action::ResetLayout => {
                Some("the panels back to their default sizes, fitted to the window")
            }
            Action::Lessons => Some("the lessons, and exercises whose answers the tracer checks"),
            Action::Lab => Some(
                "the stability lab: the selected pixel's numbers against exact values, and every method on the stiff cases",
            ),
            Action::SaveScene => Some("write the scene file back, comments kept"),
            _ => None,
        }
    }

    /// Its tooltip: the hint, led by the first shortcut with Ctrl if it has one
    /// ("Ctrl+S: write the scene file back, comments kept").
    pub fn tooltip(self) -> Option<String> {
        let keys = self
            .shortcuts()
            .iter()
            .find(|s| s.command)
            .map(|s| s.text());
        match (keys, self.hint()) {
            (Some(k), Some(h)) => Some(format!("{k}: {h}")),
            (Some(k), None) => Some(k),
            (None, h) => h.map(str::to_string),
        }
    }

    /// Its keys, the main one first.
    pub fn shortcuts(self) -> &'static [Shortcut] {
        match self {
            Action::FullScreen => const { &[plain(Key::F11)] },
            Action::FirstStep => const { &[plain(Key::Home)] },
            Action::PreviousStep => const { &[plain(Key::ArrowLeft), plain(Key::ArrowUp)] },
            Action::PlayPause => const { &[plain(Key::Space)] },
            Action::NextStep => const { &[plain(Key::ArrowRight), plain(Key::ArrowDown)] },
            Action::LastStep => const { &[plain(Key::End)] },
            Action::Redo => const { &[ctrl_shift(Key::Z), ctrl(Key::Y)] },
            Action::Undo => const { &[ctrl(Key::Z)] },
            Action::SaveScene => const { &[ctrl(Key::S)] },
            Action::CloseDialog | Action::LeavePresentation => const { &[plain(Key::Escape)] },
            _ => &[],
        }
    }

    /// Whether its keys do anything now: the editor's need an editable scene, Esc a dialog to
    /// close or presentation mode to leave.
    pub fn keys_apply(self, state: &AppState) -> bool {
        match self {
            Action::Redo | Action::Undo | Action::SaveScene => state.editor.is_some(),
            Action::CloseDialog => state.dialog.is_some(),
            Action::LeavePresentation => state.prefs.presentation,
            _ => true,
        }
    }

    /// What it does in `state`.
    pub fn effect(self, state: &AppState) -> Effect {
        let step = |m| Effect::Command(Command::Step(m));
        match self {
            Action::Open => Effect::Command(Command::ShowDialog(Dialog::Open {
                path: state
                    .path()
                    .map(|p| p.display().to_string())
                    .unwrap_or_default(),
            })),
            Action::OpenBuiltin => Effect::Command(Command::OpenBuiltin),
            Action::Reload => Effect::Command(Command::Reload),
            Action::SaveAs(kind) => Effect::Command(Command::ShowDialog(Dialog::Save {
                kind,
                path: state.suggested_name(kind),
            })),
            Action::Quit => Effect::Quit,
            Action::FullScreen => Effect::ToggleFullscreen,
            Action::ResetZoom => Effect::ResetZoom,
            Action::ResetLayout => Effect::Command(Command::ResetLayout),
            Action::Lessons => {
                // The lessons take the settings panel's place (a lesson sets its own
                // settings; View → Settings panel shows both): the render keeps its width.
                let mut p = state.prefs.clone();
                p.show_learn = !state.prefs.show_learn;
                p.show_settings = !p.show_learn;
                Effect::Command(Command::SetPrefs(p))
            }
            Action::Lab => Effect::ToggleLab,
            Action::FirstStep => step(StepMove::First),
            Action::PreviousStep => step(StepMove::Previous),
            Action::PlayPause => Effect::Command(Command::TogglePlay),
            Action::NextStep => step(StepMove::Next),
            Action::LastStep => step(StepMove::Last),
            Action::Redo => Effect::Command(Command::Edit(EditCmd::Redo)),
            Action::Undo => Effect::Command(Command::Edit(EditCmd::Undo)),
            Action::SaveScene => Effect::Command(Command::Edit(EditCmd::Save(None))),
            Action::CloseDialog => Effect::Command(Command::CloseDialog),
            Action::LeavePresentation => {
                // The state puts the layout from before presentation back.
                let mut p = state.prefs.clone();
                p.presentation = false;
                Effect::Command(Command::SetPrefs(p))
            }
        }
    }

    /// Does what it does in `state`: see [`perform`].
    pub fn perform(self, to: &mut Targets<'_>) {
        let effect = self.effect(to.state);
        perform(effect, to);
    }
}

impl Effect {
    /// The command, if it is one.
    pub fn command(self) -> Option<Command> {
        match self {
            Effect::Command(c) => Some(c),
            _ => None,
        }
    }
}

/// A button for `action` (its label and tooltip) in a panel that only issues commands; a click
/// pushes the action's command onto `cmds`. Returns whether it was clicked.
pub fn button(
    ui: &mut egui::Ui,
    state: &AppState,
    action: Action,
    enabled: bool,
    cmds: &mut Vec<Command>,
) -> bool {
    let r = ui.add_enabled(enabled, egui::Button::new(action.label(state)));
    let clicked = match action.tooltip() {
        Some(t) => r.on_hover_text(t),
        None => r,
    }
    .clicked();
    if clicked && let Some(c) = action.effect(state).command() {
        cmds.push(c);
    }
    clicked
}

/// What an action acts on.
pub struct Targets<'a> {
    /// The state it reads (commands change it only after the frame).
    pub state: &'a AppState,
    /// The window (for Quit).
    pub ctx: &'a egui::Context,
    /// The render view (for Reset zoom).
    pub render: &'a mut RenderView,
    /// The request to toggle full screen (the app does it after the frame).
    pub toggle_fullscreen: &'a mut bool,
    /// Whether the lab window is open.
    pub lab_open: &'a mut bool,
    /// Where commands go.
    pub cmds: &'a mut Vec<Command>,
}

/// Does `effect`: a command joins `cmds` (the state applies it after the frame); the others
/// act on the views at once, or ask the app to (full screen).
pub fn perform(effect: Effect, to: &mut Targets<'_>) {
    match effect {
        Effect::Command(c) => to.cmds.push(c),
        Effect::ToggleFullscreen => *to.toggle_fullscreen = true,
        Effect::ResetZoom => to.render.reset_zoom(),
        Effect::ToggleLab => *to.lab_open = !*to.lab_open,
        Effect::Quit => to.ctx.send_viewport_cmd(egui::ViewportCommand::Close),
    }
}

/// The actions whose keys were pressed this frame, in order (unless a text field has the
/// keyboard). Shortcuts with Ctrl are consumed first, in [`Action::ALL`]'s order; then every
/// press of a plain key counts, auto-repeat included — two quick presses that land in one frame
/// are two steps, applied in order (the state clamps the step, so a long burst at the end stays
/// on the last step) — for the first action it applies to.
pub fn pressed(ctx: &egui::Context, state: &AppState) -> Vec<Action> {
    if ctx.egui_wants_keyboard_input() {
        return vec![];
    }
    let mut out = vec![];
    for a in Action::ALL {
        let hit = ctx.input_mut(|i| {
            a.shortcuts()
                .iter()
                .filter_map(|s| s.keyboard_shortcut())
                .any(|s| i.consume_shortcut(&s))
        });
        if hit && a.keys_apply(state) {
            out.push(a);
        }
    }
    let keys: Vec<Key> = ctx.input(|i| {
        i.events
            .iter()
            .filter_map(|e| match e {
                egui::Event::Key {
                    key,
                    pressed: true,
                    modifiers,
                    ..
                } if !modifiers.ctrl && !modifiers.command && !modifiers.alt => Some(*key),
                _ => None,
            })
            .collect()
    });
    for k in keys {
        let plain_key = |a: &Action| a.shortcuts().iter().any(|s| !s.command && s.key == k);
        if let Some(a) = Action::ALL
            .into_iter()
            .find(|a| plain_key(a) && a.keys_apply(state))
        {
            out.push(a);
        }
    }
    out
}

/// The Help menu's lines about keys: each a list of (actions, what their keys do), written
/// with the actions' own keys ("← → (or ↑ ↓): previous / next step").
const HELP: [&[(&[Action], &str)]; 4] = [
    &[(
        &[Action::PreviousStep, Action::NextStep],
        "previous / next step",
    )],
    &[(&[Action::FirstStep, Action::LastStep], "first / last step")],
    &[(&[Action::PlayPause], "play / pause")],
    &[
        (&[Action::FullScreen], "full screen"),
        (&[Action::LeavePresentation], "leave presentation mode"),
    ],
];

/// The Help menu's lines about keys.
pub fn help_lines() -> Vec<String> {
    HELP.iter()
        .map(|line| {
            line.iter()
                .map(|(actions, what)| format!("{}: {what}", keys_text(actions)))
                .collect::<Vec<_>>()
                .join(" · ")
        })
        .collect()
}

/// The keys of `actions` side by side, the main ones first and the others after "or": arrows
/// side by side ("← → (or ↑ ↓)"), named keys with a slash ("Home / End").
pub fn keys_text(actions: &[Action]) -> String {
    let most = actions
        .iter()
        .map(|a| a.shortcuts().len())
        .max()
        .unwrap_or(0);
    let mut text = String::new();
    for i in 0..most {
        let names: Vec<String> = actions
            .iter()
            .filter_map(|a| a.shortcuts().get(i))
            .map(|s| s.text())
            .collect();
        let sep = if names.iter().all(|n| n.chars().count() == 1) {
            " "
        } else {
            " / "
        };
        let keys = names.join(sep);
        if i == 0 {
            text = keys;
        } else {
            text += &format!(" (or {keys})");
        }
    }
    text
}
