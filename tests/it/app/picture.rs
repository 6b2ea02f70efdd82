//! The README's picture (`docs/app.png`) is the app as it is today: the Cornell box at pixel
//! (150, 200), step 5, drawn by the app itself headless on the software adapter, compared with
//! the committed file as the diagrams' goldens are (at most 0.5 % of the pixels differing by more
//! than 16 in a channel), leaving out the timings, which change every run. After an intended
//! change to the window: `UPDATE_GOLDEN=1 cargo test --test it app::picture::`, and look at it.

use super::{rendered, settle_layout, timing_rects, wait_for};
use crate::common::app_harness::wgpu_harness;
use raystep::app::state::{Command, StepMove};
use std::path::Path;

#[test]
fn the_readmes_picture_is_current() {
    let path = Path::new("scenes").join("cornell.toml");
    let Some(mut h) = wgpu_harness("the_readmes_picture_is_current", Some(path), false) else {
        return;
    };
    wait_for(&mut h, "the render", rendered);
    h.state_mut().state.apply(Command::SelectPixel([150, 200]));
    h.state_mut().state.apply(Command::Step(StepMove::To(5)));
    settle_layout(&mut h);
    // The timings' places, in pixels.
    let scale = h.ctx.pixels_per_point();
    let timings: Vec<egui::Rect> = timing_rects(&h)
        .into_iter()
        .map(|r| r.expand(2.0) * scale)
        .collect();
    assert_eq!(timings.len(), 2, "the timing labels are in the window");
    let got = h.render().expect("the window renders");
    let file = crate::common::scenes::root().join("docs/app.png");
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        got.save(&file).unwrap();
        return;
    }
    let want = image::open(&file).unwrap().to_rgba8();
    let keep = || {
        let out = std::env::temp_dir().join("raystep-app-picture-actual.png");
        got.save(&out).unwrap();
        out.display().to_string()
    };
    assert_eq!(
        want.dimensions(),
        got.dimensions(),
        "docs/app.png is not the window's size (this run's picture: {})",
        keep()
    );
    let (differing, compared) = crate::common::golden::differing(&got, &want, |x, y| {
        let p = egui::pos2(x as f32 + 0.5, y as f32 + 0.5);
        timings.iter().any(|r| r.contains(p))
    });
    assert!(
        differing * 200 <= compared,
        "docs/app.png: {differing} of {compared} pixels differ from the window drawn now (this run's picture: {}; UPDATE_GOLDEN=1 redraws it)",
        keep()
    );
}
