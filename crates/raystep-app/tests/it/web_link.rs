//! The browser build's links (`#scene=cornell&pixel=160,120&step=7`): `app::web::follow` opens
//! the built-in scene at that pixel and step, and names what it cannot use. (The web page
//! calls it on start and whenever the address's `#…` changes; it is plain app code, tested here
//! natively.)

use raystep_app::RaystepApp;
use raystep_app::state::{Document, Prefs};
use raystep_app::web::follow;
use std::time::{Duration, Instant};

fn app() -> RaystepApp {
    RaystepApp::with_context(&egui::Context::default(), Prefs::default(), None)
}

/// Ticks the app's state until `done` holds (the scene loads and the pixel is traced in the
/// background), for at most a minute.
fn wait(a: &mut RaystepApp, done: impl Fn(&RaystepApp) -> bool) {
    let start = Instant::now();
    while !done(a) {
        assert!(start.elapsed() < Duration::from_secs(60), "timed out");
        a.state.tick(Instant::now());
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn a_link_opens_its_scene_at_its_pixel_and_step() {
    let mut a = app();
    follow(&mut a, "#scene=cornell&pixel=100,150&step=7");
    wait(&mut a, |a| {
        a.state.stepping.is_some() && a.state.pixel == Some([100, 150]) && a.state.step == 7
    });
    let Document::Scene { scene, .. } = &a.state.doc else {
        panic!("no scene open");
    };
    // The title of scenes/cornell.toml.
    assert_eq!(scene.name, "Cornell box");
    // The same link again changes nothing (the page calls this every frame).
    a.state.step = 2;
    follow(&mut a, "#scene=cornell&pixel=100,150&step=7");
    assert_eq!(a.state.step, 2);
}

#[test]
fn a_link_it_cannot_use_is_named_in_the_status_bar() {
    let mut a = app();
    follow(&mut a, "#scene=atlantis&step=x");
    let m = a.state.message.as_ref().expect("a message");
    assert!(m.error);
    assert!(
        m.text.contains("\"atlantis\" is not a built-in scene"),
        "{}",
        m.text
    );
    assert!(m.text.contains("\"x\" is not a whole number"), "{}", m.text);
}

/// A pixel outside the image and a huge step (a mistyped or hostile link) never panic: the app
/// renders the scene and traces no pixel, or the step is clamped.
#[test]
fn a_link_past_the_image_or_the_steps_is_harmless() {
    for link in [
        "#scene=cornell&pixel=99999,99999&step=99999",
        "#scene=cornell&pixel=4294967295,0",
        "#scene=cornell&pixel=10,10&step=18446744073709551615",
    ] {
        let mut a = app();
        follow(&mut a, link);
        wait(&mut a, |a| a.state.rendered.is_some() && !a.state.busy());
        for _ in 0..5 {
            a.state.tick(Instant::now());
        }
        if let Some(s) = &a.state.stepping {
            assert!(
                a.state.step < s.index.len(),
                "{link}: step {}",
                a.state.step
            );
        }
    }
}
