//! Explaining records in words and formulas: everything here only *reads* a [`crate::record`]
//! trace; nothing repeats a kernel's arithmetic.
//!
//! - [`describe`]: one line per step, for the command line's trace tree and the app's tree;
//! - [`formula`]: the math panel — each step's formula with the recorded numbers substituted;
//! - [`diff`]: comparing two traces step by step, with tolerances, in words;
//! - [`intersect`]: the text of `raystep intersect`, one kernel's record explained line by line.
//!
//! The 2D pictures of the same records are in [`crate::diagram`].

pub mod describe;
pub mod diff;
pub mod formula;
pub mod intersect;
