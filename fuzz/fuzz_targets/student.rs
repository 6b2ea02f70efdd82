//! `grade-tracer`'s input: a student program's output in the student trace format (JSON Lines).
//! Output that parses is written back and read again, and graded against raystep's trace of
//! fixed pixels of shipped scenes at every stage: the grader must never panic on what it reads.
#![no_main]

use libfuzzer_sys::fuzz_target;
use raystep::fuzzing;

fuzz_target!(|data: &[u8]| {
    fuzzing::student_input(data).assert_holds();
});
