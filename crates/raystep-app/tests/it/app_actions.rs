//! The table of actions (`raystep_app::actions`) drives the menus, the buttons' tooltips, the
//! Help menu and the keyboard. The words checked here are the ones the app showed when each of
//! them was written by hand, copied from that version: the table must say the same.

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable as _;
use raystep_app::RaystepApp;
use raystep_app::actions::Action;
use raystep_app::state::Prefs;

fn harness() -> Harness<'static, RaystepApp> {
    Harness::builder()
        .with_size(egui::vec2(1400.0, 900.0))
        .build_eframe(|cc| RaystepApp::with_context(&cc.egui_ctx, Prefs::default(), None))
}

/// Opens the menu `menu` and checks it shows each of `lines`.
fn menu_shows(menu: &str, lines: &[&str]) {
    let mut h = harness();
    h.step();
    h.get_by_label(menu).click();
    h.step();
    h.step();
    for line in lines {
        assert!(
            h.query_by_label(line).is_some(),
            "the {menu} menu shows {line:?}"
        );
    }
}

#[test]
fn the_help_menu_lists_the_keys_as_before() {
    menu_shows(
        "Help",
        &[
            "← → (or ↑ ↓): previous / next step",
            "Home / End: first / last step",
            "Space: play / pause",
            "F11: full screen · Esc: leave presentation mode",
        ],
    );
}

#[test]
fn the_view_menu_names_the_keys_as_before() {
    menu_shows(
        "View",
        &[
            "Full screen (F11)",
            "Presentation mode (Esc leaves)",
            "Reset zoom",
            "Reset layout",
        ],
    );
}

#[test]
fn tooltips_name_the_ctrl_keys_as_before() {
    assert_eq!(Action::Undo.tooltip().as_deref(), Some("Ctrl+Z"));
    assert_eq!(Action::Redo.tooltip().as_deref(), Some("Ctrl+Shift+Z"));
    assert_eq!(
        Action::SaveScene.tooltip().as_deref(),
        Some("Ctrl+S: write the scene file back, comments kept")
    );
    assert_eq!(
        Action::ResetLayout.tooltip().as_deref(),
        Some("the panels back to their default sizes, fitted to the window")
    );
    // Plain keys are in the Help menu, not in tooltips: the step buttons never had any.
    assert_eq!(Action::NextStep.tooltip(), None);
    assert_eq!(Action::FullScreen.tooltip(), None);
}

#[test]
fn no_two_actions_share_a_key_but_esc() {
    // Esc closes a dialog, else leaves presentation mode: the only key two actions share, and
    // the table tries them in that order.
    for (i, a) in Action::ALL.iter().enumerate() {
        for b in &Action::ALL[i + 1..] {
            let shared = a.shortcuts().iter().any(|s| b.shortcuts().contains(s));
            let esc = [*a, *b] == [Action::CloseDialog, Action::LeavePresentation];
            assert!(!shared || esc, "{a:?} and {b:?} share a key");
        }
    }
    assert!(Action::ALL.contains(&Action::CloseDialog));
}
