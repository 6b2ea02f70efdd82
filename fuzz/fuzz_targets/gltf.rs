//! The glTF reader: the input is a whole `.gltf` (JSON) or `.glb` file, opened as a scene. A
//! file that loads is also traced at one pixel.
#![no_main]

use libfuzzer_sys::fuzz_target;
use raystep::fuzzing;

fuzz_target!(|data: &[u8]| {
    fuzzing::gltf_input(data).assert_holds();
});
