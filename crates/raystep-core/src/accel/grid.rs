//! The uniform grid: spatial subdivision, the "Raytracing" slides' third way (docs/SOURCES.md) of
//! avoiding tests.
//!
//! The box around the scene's finite primitives is cut into equal cells; each cell lists every
//! primitive whose bounding box overlaps it. A ray walks the cells it crosses, nearest first, by
//! 3D-DDA (Amanatides & Woo, "A fast voxel traversal algorithm", Eurographics 1987), and tests
//! only the primitives the cells list:
//!
//! - the entry cell is the cell of the point where the ray enters the grid (or of its origin,
//!   inside the grid), its indices clamped into the grid, since rounding may put that point a
//!   hair outside;
//! - per axis, `t_next` is where the ray crosses the next cell boundary and `t_delta` how far
//!   apart the crossings are; the walk steps along the axis with the smallest `t_next` (the lowest
//!   axis on a tie);
//! - a hit is accepted only if it lies inside the current cell (t ≤ the cell's exit): a primitive
//!   that spans several cells may be hit beyond this one, where a nearer primitive listed only in
//!   a later cell could still be in front of it (in the walk's last cell any hit is accepted: no
//!   cell follows);
//! - the mailbox: a primitive already tested in an earlier cell *and missed* is not tested again
//!   (a miss stays a miss: the ray's t interval only shrinks). One hit beyond its cell is tested
//!   again where it is reached, so its hit is accepted in the right cell.
//!
//! Infinite planes stay outside the grid, as with the BVH: they are tested first and their hit
//! tightens t_max. So do finite primitives that span most of the grid when the rest fit a far
//! smaller box (a sphere of radius 10⁹ around a scene): listed, they would make the grid as big
//! as themselves and crowd every other primitive into a few cells.
//!
//! Resolution: Cleary & Wyvill's heuristic, cells per axis ∝ the box's extent so that the grid
//! holds about λ·N cells for N primitives, i.e. λ^(1/3)·N^(1/3) per axis on a cube. λ =
//! [`GRID_LAMBDA`] = 4, measured with `raystep bench --section grid-lambda` (λ from 0.5 to 32 on
//! the shipped and SPD scenes): on every scene of over 100 primitives λ = 4 is within 7 % of the
//! fastest λ (λ = 8 is up to 7 % faster on the SPD tetrahedra, λ = 2 equal on the balls);
//! coarser grids test up to 3× more primitives per ray, finer ones walk up to 2× more cells. On
//! scenes of a handful of primitives every λ is within noise. No λ rescues the teapot in a
//! stadium: its teapot stays in a few cells whatever the resolution (a two-level grid or an
//! octree would refine there; neither is built, see book/tracer.md).

use super::bvh::shape_bounds;
use super::{Accelerator, Hit, accept, any_of, closest_of, test_any, test_object, tie_ray};
use crate::math::Ray;
use crate::record::{Observer, Step};
use crate::scene::Scene;
use crate::shapes::aabb::slab_robust;
use glam::Vec3;
use smallvec::SmallVec;
use std::collections::HashSet;

/// Cells per primitive (λ): the grid holds about λ·N cells for N finite primitives.
pub const GRID_LAMBDA: f32 = 4.0;

/// The most cells along one axis (keeps a grid of a million triangles within memory).
pub const MAX_CELLS_PER_AXIS: u32 = crate::record::validate::MAX_GRID_CELLS_PER_AXIS;

/// The most primitive references the cells may hold together (a primitive spanning k cells
/// counts k times): 32 M, 128 MiB of lists. A finer grid that would exceed it is coarsened.
pub const MAX_REFERENCES: u64 = 32 << 20;

/// A uniform grid over the scene's finite primitives.
#[derive(Debug, Clone)]
pub struct Grid {
    /// The grid's box.
    pub min: Vec3,
    /// The grid's box.
    pub max: Vec3,
    /// Cells along x, y, z.
    pub dims: [u32; 3],
    cell_size: Vec3,
    /// `starts[c]..starts[c + 1]` indexes `lists` for cell `c` (x fastest, then y, then z).
    starts: Vec<u32>,
    /// The primitives of every cell, ascending object ids within a cell.
    lists: Vec<u32>,
    /// Infinite planes and the primitives that span the grid (see `keep_out_spanning`), tested
    /// first, in object order.
    outside: Vec<u32>,
}

impl Grid {
    /// Builds the grid for `scene` (the heuristic of the module documentation).
    pub fn build(scene: &Scene) -> Grid {
        Grid::build_with_lambda(scene, GRID_LAMBDA)
    }

    /// Builds the grid with about `lambda` cells per primitive instead of [`GRID_LAMBDA`] (the
    /// `grid-lambda` bench sweeps it). A `lambda` that is not a positive number gives one cell.
    pub fn build_with_lambda(scene: &Scene, lambda: f32) -> Grid {
        let mut outside = vec![];
        let mut boxes = vec![];
        for (id, o) in scene.world().iter().enumerate() {
            match shape_bounds(&o.shape) {
                Some(b) => boxes.push((id as u32, b)),
                None => outside.push(id as u32),
            }
        }
        outside.extend(keep_out_spanning(&mut boxes));
        // Tested first in object order.
        outside.sort_unstable();
        let (min, max) = bounds(&boxes);
        let (mut min, mut max) = (min, max);
        if boxes.is_empty() {
            return Grid {
                min: Vec3::ZERO,
                max: Vec3::ZERO,
                dims: [0; 3],
                cell_size: Vec3::ONE,
                starts: vec![0],
                lists: vec![],
                outside,
            };
        }
        // A flat scene (all primitives in one plane) still gets a grid one cell thick; the box
        // grows by a ten-thousandth on every side so that primitives on its faces (a room's
        // walls) lie inside it, not on a boundary a rounding error may put them beyond.
        let extent =
            (max - min).max(Vec3::splat((max - min).max_element() * 1e-3).max(Vec3::splat(1e-6)));
        min -= extent * 1e-4;
        let extent = extent * (1.0 + 2e-4);
        max = min + extent;
        let n = boxes.len() as f32;
        let volume = extent.x * extent.y * extent.z;
        let per_unit = (lambda.max(0.0) * n / volume).cbrt();
        let dims = extent.to_array().map(|e| {
            let d = (e * per_unit).round();
            if d.is_finite() {
                (d as u32).clamp(1, MAX_CELLS_PER_AXIS)
            } else {
                1
            }
        });
        // The cells each primitive's box overlaps, and their total. Each box grows by a
        // thousandth of a cell first, so a primitive lying on a cell boundary (a flat scene on a
        // grid plane) is listed on both sides: a hit computed a rounding error past the boundary
        // is still in a cell that lists it.
        type Range = (u32, [u32; 3], [u32; 3]);
        let plan = |dims: [u32; 3]| -> (Vec3, Vec<Range>, u64) {
            let cell_size = extent / Vec3::new(dims[0] as f32, dims[1] as f32, dims[2] as f32);
            let grid_cell = |p: Vec3| -> [u32; 3] {
                let c = (p - min) / cell_size;
                [0, 1, 2].map(|a| {
                    let f = c[a].floor();
                    if f.is_nan() || f < 0.0 {
                        0
                    } else {
                        (f as u32).min(dims[a] - 1)
                    }
                })
            };
            let margin = cell_size * 1e-3;
            let mut total = 0u64;
            let ranges = boxes
                .iter()
                .map(|(id, (lo, hi))| {
                    let (a, b) = (grid_cell(*lo - margin), grid_cell(*hi + margin));
                    total += (0..3).map(|k| u64::from(b[k] - a[k] + 1)).product::<u64>();
                    (*id, a, b)
                })
                .collect();
            (cell_size, ranges, total)
        };
        // Many large primitives could list themselves in millions of cells each: coarsen the
        // grid until the lists fit (a grid of one cell lists every primitive once).
        let mut dims = dims;
        let (mut cell_size, mut ranges, mut total) = plan(dims);
        while total > MAX_REFERENCES && dims.iter().any(|&d| d > 1) {
            dims = dims.map(|d| d.div_ceil(2));
            (cell_size, ranges, total) = plan(dims);
        }
        let cells = (dims[0] * dims[1] * dims[2]) as usize;
        let mut counts = vec![0u32; cells + 1];
        for &(_, a, b) in &ranges {
            for z in a[2]..=b[2] {
                for y in a[1]..=b[1] {
                    for x in a[0]..=b[0] {
                        counts[((z * dims[1] + y) * dims[0] + x) as usize] += 1;
                    }
                }
            }
        }
        let mut starts = vec![0u32; cells + 1];
        for c in 0..cells {
            starts[c + 1] = starts[c] + counts[c];
        }
        let mut fill = starts.clone();
        let mut lists = vec![0u32; starts[cells] as usize];
        // Ascending ids within a cell: `ranges` is in object order.
        for (id, a, b) in ranges {
            for z in a[2]..=b[2] {
                for y in a[1]..=b[1] {
                    for x in a[0]..=b[0] {
                        let c = ((z * dims[1] + y) * dims[0] + x) as usize;
                        lists[fill[c] as usize] = id;
                        fill[c] += 1;
                    }
                }
            }
        }
        Grid {
            min,
            max,
            dims,
            cell_size,
            starts,
            lists,
            outside,
        }
    }

    /// The objects tested before the walk, in object order: the infinite planes and the
    /// primitives kept out of the grid because they span most of it (see [`Grid::build`]).
    pub fn outside(&self) -> &[u32] {
        &self.outside
    }

    /// Cells in the grid.
    pub fn cells(&self) -> usize {
        self.starts.len() - 1
    }

    /// Primitive references over all cells (a primitive spanning k cells counts k times).
    pub fn references(&self) -> usize {
        self.lists.len()
    }

    /// Bytes the grid takes (cell starts and lists).
    pub fn memory(&self) -> usize {
        (self.starts.len() + self.lists.len() + self.outside.len()) * 4
    }

    /// The primitives cell (x, y, z) lists.
    pub fn cell(&self, c: [u32; 3]) -> &[u32] {
        let i = ((c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]) as usize;
        match (self.starts.get(i), self.starts.get(i + 1)) {
            (Some(&a), Some(&b)) => self.lists.get(a as usize..b as usize).unwrap_or(&[]),
            _ => &[],
        }
    }

    /// The box of cell (x, y, z).
    pub fn cell_box(&self, c: [u32; 3]) -> (Vec3, Vec3) {
        let lo = self.min + self.cell_size * Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
        (lo, lo + self.cell_size)
    }

    /// The recorded step of entering cell `cell`.
    fn cell_step(&self, cell: [u32; 3], t_entry: f32, t_exit: f32, axis: Option<u8>) -> Step {
        let (min, max) = self.cell_box(cell);
        Step::Cell {
            cell,
            t_entry,
            t_exit,
            axis,
            primitives: self.cell(cell).len() as u32,
            min: min.to_array(),
            max: max.to_array(),
        }
    }

    /// Walks the cells `ray` crosses, nearest first, calling `visit(cell, t_entry, t_exit,
    /// axis stepped)` for each; `visit` returns false to stop. The walk also stops past the
    /// ray's t_max (which `visit` may shrink through `ray`).
    #[inline(always)]
    pub fn walk(
        &self,
        ray: &mut Ray<f32>,
        mut visit: impl FnMut(&Grid, [u32; 3], f32, f32, Option<u8>, bool, &mut Ray<f32>) -> bool,
    ) {
        if self.dims[0] == 0 {
            return;
        }
        let inv = Vec3::ONE / ray.dir;
        let slab = slab_robust(ray, inv, self.min, self.max);
        if !slab.hit {
            return;
        }
        let t_start = slab.t_near.max(ray.t_min);
        let t_end = slab.t_far;
        let p = ray.origin + ray.dir * t_start;
        let c = (p - self.min) / self.cell_size;
        let mut cell = [0, 1, 2].map(|a| {
            let f = c[a].floor();
            if f.is_nan() || f < 0.0 {
                0
            } else {
                (f as u32).min(self.dims[a] - 1)
            }
        });
        let mut step = [0i32; 3];
        let mut t_next = [f32::INFINITY; 3];
        let mut t_delta = [f32::INFINITY; 3];
        for a in 0..3 {
            let d = ray.dir[a];
            if d > 0.0 {
                step[a] = 1;
                let boundary = self.min[a] + self.cell_size[a] * (cell[a] + 1) as f32;
                t_next[a] = (boundary - ray.origin[a]) * inv[a];
                t_delta[a] = self.cell_size[a] * inv[a];
            } else if d < 0.0 {
                step[a] = -1;
                let boundary = self.min[a] + self.cell_size[a] * cell[a] as f32;
                t_next[a] = (boundary - ray.origin[a]) * inv[a];
                t_delta[a] = -self.cell_size[a] * inv[a];
            }
        }
        let mut t_entry = t_start;
        let mut axis = None;
        loop {
            // Nothing in this cell or beyond can be nearer than a hit already found.
            if t_entry > ray.t_max {
                return;
            }
            // The axis with the nearest boundary (the lowest axis on a tie).
            let mut a = 0;
            if t_next[1] < t_next[a] {
                a = 1;
            }
            if t_next[2] < t_next[a] {
                a = 2;
            }
            let t_exit = t_next[a].min(t_end);
            let next = cell[a] as i64 + step[a] as i64;
            // The last cell of the walk: no cell follows, so any hit found here is the nearest.
            let last = t_exit >= t_end
                || t_next[a].is_infinite()
                || next < 0
                || next >= self.dims[a] as i64;
            if !visit(self, cell, t_entry, t_exit, axis, last, ray) || last {
                return;
            }
            if t_exit > ray.t_max {
                return;
            }
            cell[a] = next as u32;
            t_entry = t_exit;
            t_next[a] += t_delta[a];
            axis = Some(a as u8);
        }
    }
}

/// The box around `boxes` (an empty box, +∞ to −∞, when there are none).
fn bounds(boxes: &[(u32, (Vec3, Vec3))]) -> (Vec3, Vec3) {
    let (mut min, mut max) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for (_, (lo, hi)) in boxes {
        min = min.min(*lo);
        max = max.max(*hi);
    }
    (min, max)
}

/// With this many primitives or fewer, primitives that all span the whole scene stay in the grid
/// (its walk is then still there to see); beyond it they are all tested first, as brute force
/// would, since no cell could leave any of them out (the BVH's [`super::AUTO_BVH_THRESHOLD`]:
/// below it testing every primitive costs no more).
pub const KEEP_SPANNING_UP_TO: usize = super::AUTO_BVH_THRESHOLD;

/// Takes out of `boxes` the primitives whose box spans at least half of the grid's box along
/// every axis, when the rest then fit a box at most half as wide along every axis: it is they
/// that made the grid big, and listed in it they would crowd the rest into a few cells (one
/// sphere of radius 10⁹ among 20,000 small ones put them all in one cell: every ray tested all
/// of them, and 12 pixels took 45 s to trace where brute force took 5 ms). They are tested before the walk, as the infinite planes are, which
/// gives the same hits (ties go to the lower id whatever the order). Repeated while the smaller
/// box shows another such primitive (at most 8 rounds). When every primitive spans the box (all
/// at one point), none is kept unless there are at most [`KEEP_SPANNING_UP_TO`]. Returns their
/// ids.
fn keep_out_spanning(boxes: &mut Vec<(u32, (Vec3, Vec3))>) -> Vec<u32> {
    let mut out = vec![];
    for _ in 0..8 {
        let (min, max) = bounds(boxes);
        let extent = max - min;
        let spans = |(lo, hi): &(Vec3, Vec3)| (*hi - *lo).cmpge(extent * 0.5).all();
        let rest: Vec<(u32, (Vec3, Vec3))> =
            boxes.iter().filter(|(_, b)| !spans(b)).copied().collect();
        if rest.len() == boxes.len() {
            break;
        }
        if rest.is_empty() {
            if boxes.len() > KEEP_SPANNING_UP_TO {
                out.extend(boxes.drain(..).map(|(id, _)| id));
            }
            break;
        }
        let (rmin, rmax) = bounds(&rest);
        if !(rmax - rmin).cmple(extent * 0.5).all() {
            break;
        }
        out.extend(boxes.iter().filter(|(_, b)| spans(b)).map(|(id, _)| *id));
        *boxes = rest;
    }
    out
}

/// The grid's mailbox: the primitives a ray has already tested (and missed) in earlier cells.
/// A short list searched in turn while it holds at most [`MAILBOX_LIST`] (the usual case, on the
/// machine stack); beyond that a hash set, so that thousands of primitives listed in the same
/// cells (a cluster of coincident ones) cost a lookup each rather than a pass over all the
/// others.
#[derive(Default)]
struct Mailbox {
    few: SmallVec<[u32; MAILBOX_LIST]>,
    many: Option<HashSet<u32>>,
}

/// The most primitives the mailbox keeps as a list (see `Mailbox`).
const MAILBOX_LIST: usize = 32;

impl Mailbox {
    #[inline(always)]
    fn contains(&self, id: u32) -> bool {
        match &self.many {
            None => self.few.contains(&id),
            Some(s) => s.contains(&id),
        }
    }

    #[inline(always)]
    fn insert(&mut self, id: u32) {
        if let Some(s) = &mut self.many {
            s.insert(id);
        } else if self.few.len() < MAILBOX_LIST {
            self.few.push(id);
        } else {
            let mut s: HashSet<u32> = self.few.drain(..).collect();
            s.insert(id);
            self.many = Some(s);
        }
    }
}

impl Accelerator for Grid {
    #[inline]
    fn closest<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        let mut r = *ray;
        let mut best: Option<Hit> = None;
        closest_of(scene, &self.outside, &mut r, &mut best, obs);
        // Primitives already tested and missed (the mailbox).
        let mut missed = Mailbox::default();
        self.walk(&mut r, |grid, cell, t_entry, t_exit, axis, last, r| {
            let list = grid.cell(cell);
            obs.accel_visit(|| grid.cell_step(cell, t_entry, t_exit, axis));
            for &id in list {
                if missed.contains(id) {
                    obs.step(|| Step::MailboxSkip {
                        object: id,
                        name: scene.object_name(id),
                    });
                    continue;
                }
                match test_object(scene, id, &tie_ray(r, id, &best), obs) {
                    // Inside this cell (or in the last cell): the nearest so far.
                    Some(h) if h.t <= t_exit || last => {
                        accept(scene, &h, r.t_max, obs);
                        r.t_max = h.t;
                        best = Some(h);
                    }
                    // Beyond this cell: tested again where the ray reaches it.
                    Some(_) => {}
                    None => missed.insert(id),
                }
            }
            // Done once the nearest hit lies in this cell.
            best.is_none_or(|b| b.t > t_exit)
        });
        best
    }

    #[inline]
    fn any<O: Observer>(&self, scene: &Scene, ray: &Ray<f32>, obs: &mut O) -> Option<Hit> {
        if let Some(h) = any_of(scene, &self.outside, ray, obs) {
            return Some(h);
        }
        let mut found = None;
        let mut tested = Mailbox::default();
        let mut r = *ray;
        self.walk(&mut r, |grid, cell, t_entry, t_exit, axis, _, r| {
            let list = grid.cell(cell);
            obs.accel_visit(|| grid.cell_step(cell, t_entry, t_exit, axis));
            for &id in list {
                if tested.contains(id) {
                    obs.step(|| Step::MailboxSkip {
                        object: id,
                        name: scene.object_name(id),
                    });
                    continue;
                }
                // Any hit in (t_min, t_max) blocks the shadow ray, wherever it lies.
                if !test_any(scene, id, r, &mut found, obs) {
                    return false;
                }
                tested.insert(id);
            }
            true
        });
        found
    }

    fn name(&self) -> &'static str {
        "uniform grid"
    }

    /// None for a grid of no cells (every primitive tested first: planes only, or primitives
    /// that all span the scene), whose walk records no cell: a trace records (and the loader
    /// accepts) a grid of 1 to 256 cells per axis.
    fn grid_outline(&self) -> Option<crate::record::GridOutline> {
        if self.dims.contains(&0) {
            return None;
        }
        Some(crate::record::GridOutline {
            min: self.min.to_array(),
            max: self.max.to_array(),
            cells: self.dims,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mailbox_turns_into_a_hash_set_past_its_list_and_forgets_nothing() {
        let mut m = Mailbox::default();
        // Odd ids in, up to 999: the list fills at 32, then the set holds them all.
        for (k, id) in (1..1000).step_by(2).enumerate() {
            m.insert(id);
            assert_eq!(
                m.many.is_some(),
                k + 1 > MAILBOX_LIST,
                "after {} ids",
                k + 1
            );
        }
        assert!((1..1000).step_by(2).all(|id| m.contains(id)));
        assert!(!(0..1000).step_by(2).any(|id| m.contains(id)));
        assert!(!m.contains(1001));
    }
}
