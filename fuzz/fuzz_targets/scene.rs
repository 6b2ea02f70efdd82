//! The scene loader: TOML, and the OBJ mesh it may name. The input is the scene's TOML, then
//! (optionally) a line `%%OBJ%%` and an OBJ file, written as `mesh.obj` next to the scene. A scene
//! that loads is also traced at one pixel (the loader's guarantees are what the tracer relies on).
#![no_main]

use libfuzzer_sys::fuzz_target;
use raystep::fuzzing;

fuzz_target!(|data: &[u8]| {
    fuzzing::scene_input(data).assert_holds();
});
