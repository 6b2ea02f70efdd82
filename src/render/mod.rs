//! Rendering the whole image: the parallel CPU renderer, and image output (sRGB PNG, heatmaps).

pub mod cpu;
pub mod image;

pub use cpu::{CANCELLED, LiveRender, RenderOptions, RenderOutput, RenderStats, render};
