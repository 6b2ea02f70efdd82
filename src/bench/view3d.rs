//! The 3D view and live editing (`--section view3d`).

use super::*;

/// The 3D view and live editing: per scene, drawing the view at 1280×720 (the geometry built,
/// drawn and waited for, on the headless adapter; with the 8×8 fan of rays too) and the time from an edit to
/// the updated trace (the edit through the TOML document and the loader, preparing the scene —
/// the accelerator's build — and recording the centre pixel), as the app does it.
/// `inputs`: (name, the scene file's text, the folder its OBJ paths start from).
pub fn view3d(
    inputs: &[(String, String, Option<std::path::PathBuf>)],
    reps: usize,
) -> Result<(), String> {
    use crate::scene::edit::{Edit, SceneDoc};
    use crate::view3d::{self, Viewpoint, geometry};
    let ctx = crate::gpu::GpuContext::headless().map_err(|e| e.to_string())?;
    crate::io::outln!("## 3D view at 1280×720 and edit → updated trace (ms, medians of {reps})");
    crate::io::outln!("adapter: {}\n", ctx.adapter_name());
    crate::io::outln!(
        "| scene | objects | frame | frame with 8×8 fan | edit + load | prepare | record pixel | edit → trace |"
    );
    crate::io::outln!("|---|---|---|---|---|---|---|---|");
    let mut renderer = view3d::gpu::Renderer::new(ctx).map_err(|e| e.to_string())?;
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    for (name, text, base) in inputs {
        let mut doc = SceneDoc::parse(text, name, base.as_deref())?;
        let scene = doc.scene().map_err(|e| e.to_string())?;
        let prepared = PreparedScene::new(scene.clone());
        let [x, y] = [scene.camera.width / 2, scene.camera.height / 2];
        let trace = prepared.record(x, y, 0);
        let fan = view3d::fan_traces(&prepared, 8);
        let options = geometry::Options::default();
        // The app's frame: the geometry built and drawn, submit to completion (the readback
        // `render_image` adds for a PNG is left out).
        let frame = |renderer: &mut view3d::gpu::Renderer,
                     fan: &[crate::record::Trace]|
         -> Result<Duration, String> {
            let mut times = vec![];
            for _ in 0..reps.max(1) {
                let t0 = Instant::now();
                let g = geometry::build(prepared.scene(), Some(&trace), fan, &options);
                let build = t0.elapsed();
                let cam = Viewpoint::default().camera(
                    &prepared.scene().camera,
                    &g.bounds,
                    1280.0 / 720.0,
                );
                renderer
                    .draw(&g, &cam, [1280, 720], [0.0, 0.0, 0.0, 1.0])
                    .map_err(|e| e.to_string())?;
                times.push(build + renderer.last_frame);
            }
            times.sort();
            Ok(times[times.len() / 2])
        };
        let draw = frame(&mut renderer, &[])?;
        let draw_fan = frame(&mut renderer, &fan)?;
        // Edits move the first object up and down by a small step (the scene stays valid).
        let mut sign = 1.0;
        let mut edit = Duration::ZERO;
        let mut prep = Duration::ZERO;
        let mut record = Duration::ZERO;
        let mut totals = vec![];
        for _ in 0..reps.max(1) {
            let t0 = Instant::now();
            let edited = doc.apply(&Edit::Move {
                group: 0,
                by: [0.0, 0.01 * sign, 0.0],
            })?;
            sign = -sign;
            let t1 = Instant::now();
            let p = PreparedScene::with_settings(
                &std::sync::Arc::new(edited),
                &prepared.scene().settings,
                None,
            );
            let t2 = Instant::now();
            std::hint::black_box(p.record(x, y, 0));
            let t3 = Instant::now();
            edit += t1 - t0;
            prep += t2 - t1;
            record += t3 - t2;
            totals.push(t3 - t0);
        }
        totals.sort();
        let n = reps.max(1) as u32;
        crate::io::outln!(
            "| {name} | {} | {:.1} | {:.1} | {:.1} | {:.1} | {:.2} | {:.1} |",
            scene.objects.len(),
            ms(draw),
            ms(draw_fan),
            ms(edit / n),
            ms(prep / n),
            ms(record / n),
            ms(totals[totals.len() / 2]),
        );
    }
    Ok(())
}
