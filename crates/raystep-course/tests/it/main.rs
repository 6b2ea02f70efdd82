//! raystep-course's integration tests, one test binary: a pixel traced exactly (the stability
//! lab), the path-tracer grader against outputs that try to game it, and the tolerance rules of
//! the sheets and the grader.

// The repository's root and its shipped scenes, shared with the workspace's other tests.
#[path = "../../../../tests/it/common/scenes.rs"]
mod scenes;
mod common {
    pub(crate) use super::scenes;
}

mod exact_pixel;
mod path_gaming;
mod tolerance_rules;
