//! `grade-tracer --sheet`: a grading sheet's TOML, read and checked, its scenes' `vary` values
//! drawn (in memory) and the sheet expanded into its scenes and pixels, `random_pixels` drawn.
#![no_main]

use libfuzzer_sys::fuzz_target;
use raystep::fuzzing;

fuzz_target!(|data: &[u8]| {
    fuzzing::grade_sheet_input(data).assert_holds();
});
