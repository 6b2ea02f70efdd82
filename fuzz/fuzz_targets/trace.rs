//! The trace reader, `diff` and every diagram kind on a trace that loads.
#![no_main]

use libfuzzer_sys::fuzz_target;
use raystep::fuzzing;

fuzz_target!(|data: &[u8]| {
    fuzzing::trace_input(data).assert_holds();
});
