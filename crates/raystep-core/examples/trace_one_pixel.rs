//! raystep-core as a course's library: load a scene, trace one pixel with every step recorded,
//! print the steps, and test a sphere with the same kernel the renderer uses.
//!
//! `cargo run -p raystep-core --example trace_one_pixel [SCENE.toml X Y]` (`cargo test` builds
//! it, so it keeps compiling).

use raystep_core::PreparedScene;
use raystep_core::explain::describe;
use raystep_core::math::Ray;
use raystep_core::record::Step;
use raystep_core::shapes::{SphereMethod, sphere};

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scene = match args.first() {
        Some(path) => {
            raystep_core::scene::load_file(std::path::Path::new(path)).map_err(|e| e.to_string())?
        }
        None => raystep_core::scene::default_scene(),
    };
    let pixel = |i: usize, default: u32| -> Result<u32, String> {
        args.get(i)
            .map_or(Ok(default), |a| a.parse().map_err(|e| format!("{a}: {e}")))
    };
    let (x, y) = (
        pixel(1, scene.camera.width / 2)?,
        pixel(2, scene.camera.height / 2)?,
    );
    if x >= scene.camera.width || y >= scene.camera.height {
        return Err(format!("pixel ({x}, {y}) is outside the image"));
    }

    // Every step the tracer took for the pixel, as the app and `raystep trace` show it.
    let prepared = PreparedScene::new(scene);
    let trace = prepared.record(x, y, 0);
    print!("{}", describe::tree(&trace));
    let sphere_tests = trace
        .timeline()
        .iter()
        .filter(|(_, s)| matches!(s.step, Step::Sphere { .. }))
        .count();
    println!("{sphere_tests} sphere tests; colour {:?}", trace.color);

    // A kernel on its own: a ray at a unit sphere, with every intermediate it computed.
    let ray = Ray::new(
        [0.0f32, 0.0, -5.0].into(),
        [0.0, 0.0, 1.0].into(),
        0.0,
        f32::INFINITY,
    )
    .map_err(|e| format!("{e:?}"))?;
    let rec = sphere::intersect(&ray, [0.0, 0.0, 0.0].into(), 1.0, SphereMethod::Stable);
    println!("unit sphere from z = -5: {rec:?}");
    Ok(())
}
