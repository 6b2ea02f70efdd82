//! Exercise sheets, answers files and class CSVs. The input is a sheet's TOML, then a line
//! `%%ANSWERS%%` and an answers file, then a line `%%CSV%%` and a class CSV.
#![no_main]

use libfuzzer_sys::fuzz_target;
use raystep::fuzzing;

fuzz_target!(|data: &[u8]| {
    fuzzing::sheet_input(data).assert_holds();
});
