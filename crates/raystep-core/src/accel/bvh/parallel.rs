//! When the BVH build's per-item steps run on rayon's threads, and the one helper that decides:
//! the builder (`build.rs`) and the four-lane triangle packing (`tri4.rs`) both map over their
//! items through it.

use rayon::prelude::*;

/// From this many items the build's per-item steps run on rayon's threads; below it, starting
/// them costs more than they save (a dozen-primitive tree took 30× longer to build in parallel).
pub(super) const PARALLEL_FROM: usize = 16_384;

/// `items.iter().map(f).collect()`, in parallel for big slices (the order is kept either way).
pub(super) fn map_in_order<T: Sync, U: Send>(
    items: &[T],
    f: impl Fn(&T) -> U + Sync + Send,
) -> Vec<U> {
    if items.len() >= PARALLEL_FROM {
        items.par_iter().map(f).collect()
    } else {
        items.iter().map(f).collect()
    }
}
