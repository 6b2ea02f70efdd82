//! Placeholder: being written.

use super::{Canvas, ViewOptions, title};
use crate::trace::Trace;

/// Draws the diagram.
pub fn draw(_trace: &Trace, opts: &ViewOptions) -> Canvas {
    let mut c = Canvas::new(opts.width, opts.height, opts.theme);
    title(&mut c, "quadratic (not drawn yet)");
    c
}
