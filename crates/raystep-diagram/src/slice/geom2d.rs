//! 2D vector helpers of the slice, and the 3D cuts it projects (boxes, triangles).

use super::*;

pub(super) fn sub(a: Px, b: Px) -> Px {
    [a[0] - b[0], a[1] - b[1]]
}

pub(super) fn add(a: Px, b: Px) -> Px {
    [a[0] + b[0], a[1] + b[1]]
}

pub(super) fn mul(a: Px, k: f32) -> Px {
    [a[0] * k, a[1] * k]
}

pub(super) fn len(a: Px) -> f32 {
    (a[0] * a[0] + a[1] * a[1]).sqrt()
}

pub(super) fn unit(a: Px) -> Option<Px> {
    let l = len(a);
    (l > 1e-6 && l.is_finite()).then(|| [a[0] / l, a[1] / l])
}

pub(super) fn perp(a: Px) -> Px {
    [-a[1], a[0]]
}

pub(super) fn in_rect(r: [f32; 4], p: Px) -> bool {
    p[0] >= r[0] && p[0] <= r[0] + r[2] && p[1] >= r[1] && p[1] <= r[1] + r[3]
}

pub(super) fn inset_rect(r: [f32; 4], k: f32) -> [f32; 4] {
    [
        r[0] + k,
        r[1] + k,
        (r[2] - 2.0 * k).max(1.0),
        (r[3] - 2.0 * k).max(1.0),
    ]
}

/// The part of segment a→b inside `r` = [x, y, width, height]: the canvas's one line clipper.
pub(super) fn clip_to_rect(r: [f32; 4], a: Px, b: Px) -> Option<(Px, Px)> {
    let f = |v: f32| f64::from(v);
    let rect = [f(r[0]), f(r[1]), f(r[0] + r[2]), f(r[1] + r[3])];
    let (p, q) = crate::canvas::clip_segment(rect, [f(a[0]), f(a[1])], [f(b[0]), f(b[1])])?;
    Some(([p[0] as f32, p[1] as f32], [q[0] as f32, q[1] as f32]))
}

/// Where the half-line from `from` along `dir` leaves the plot.
pub(super) fn border_point(lay: &SliceLayout, from: Px, dir: Px) -> Option<Px> {
    let u = unit(dir)?;
    let far = add(from, mul(u, 4.0 * (lay.plot[2] + lay.plot[3])));
    clip_to_rect(lay.plot, from, far).map(|(_, b)| b)
}

/// The convex hull of points (gift wrapping is plenty for ≤ 12 points).
pub(super) fn convex_hull(mut pts: Vec<Px>) -> Vec<Px> {
    pts.retain(|p| p[0].is_finite() && p[1].is_finite());
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    pts.dedup_by(|a, b| len(sub(*a, *b)) < 1e-3);
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: Px, a: Px, b: Px| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut lower: Vec<Px> = vec![];
    for &p in &pts {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0.0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<Px> = vec![];
    for &p in pts.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0.0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

// ---------------------------------------------------------------------------------------------
// Colours.

pub(super) fn overlap(a: [f32; 4], b: [f32; 4]) -> bool {
    a[0] < b[0] + b[2] && b[0] < a[0] + a[2] && a[1] < b[1] + b[3] && b[1] < a[1] + a[3]
}

/// Whether the outline of the circle (`c`, `r`) passes through the rectangle `rect` = [x, y,
/// width, height].
pub(super) fn crosses_circle(rect: [f32; 4], c: Px, r: f32) -> bool {
    let [x, y, w, h] = rect;
    let near = [c[0].clamp(x, x + w), c[1].clamp(y, y + h)];
    let far = [
        if c[0] - x > x + w - c[0] { x } else { x + w },
        if c[1] - y > y + h - c[1] { y } else { y + h },
    ];
    len(sub(near, c)) <= r && len(sub(far, c)) >= r
}

pub(super) fn dot(a: Px, b: Px) -> f32 {
    a[0] * b[0] + a[1] * b[1]
}

pub(super) fn rot(a: Px, ang: f32) -> Px {
    let (s, c) = ang.sin_cos();
    [a[0] * c - a[1] * s, a[0] * s + a[1] * c]
}

pub(super) fn bisect(a: Px, b: Px) -> Px {
    unit(add(a, b)).unwrap_or(perp(a))
}

/// A box's outline in the view: its cut by the plane (a convex polygon; true) or, when the
/// plane misses it or looking from above, its projection (false).
pub(super) fn box_outline(lay: &SliceLayout, lo: Vec3, hi: Vec3) -> (Vec<Px>, bool) {
    let (pts, cut) = box_points(&lay.frame, lo, hi);
    (convex_hull(pts.iter().map(|p| lay.px(*p)).collect()), cut)
}

/// The points whose hull is a box's outline: where the cutting plane crosses its 12 edges (true),
/// or its 8 corners when the plane misses it or looking from above (false).
pub(super) fn box_points(f: &Frame, lo: Vec3, hi: Vec3) -> (Vec<Vec3>, bool) {
    let corner = |k: usize| {
        Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    };
    if !f.top_down {
        let mut pts = vec![];
        for a in 0..8 {
            for bit in [1, 2, 4] {
                let b = a | bit;
                if b == a {
                    continue;
                }
                let (pa, pb) = (corner(a), corner(b));
                let (da, db) = (f.dist(pa), f.dist(pb));
                if da == 0.0 {
                    pts.push(pa);
                }
                if (da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0) {
                    pts.push(pa + (pb - pa) * (da / (da - db)));
                }
                if db == 0.0 {
                    pts.push(pb);
                }
            }
        }
        if pts.len() >= 2 {
            return (pts, true);
        }
    }
    ((0..8).map(corner).collect(), false)
}

/// Where the cutting plane crosses a triangle: a segment, if it does.
pub(super) fn triangle_cut(f: &Frame, p: [Vec3; 3]) -> Option<[Vec3; 2]> {
    let d: Vec<f32> = p.iter().map(|v| f.dist(*v)).collect();
    let mut pts = vec![];
    for k in 0..3 {
        let (a, b) = (k, (k + 1) % 3);
        if d[a] == 0.0 {
            pts.push(p[a]);
        }
        if (d[a] < 0.0 && d[b] > 0.0) || (d[a] > 0.0 && d[b] < 0.0) {
            pts.push(p[a] + (p[b] - p[a]) * (d[a] / (d[a] - d[b])));
        }
    }
    (pts.len() >= 2).then(|| [pts[0], pts[pts.len() - 1]])
}

/// Where the grid's cell boundaries across `axis` (`cells` equal cells between `lo` and `hi`)
/// meet the cutting plane: one segment per boundary plane the plane crosses inside the grid's
/// box. Empty when the boundary planes are parallel to the cutting plane, or when, at `scale`
/// pixels per unit, neighbouring lines would fall under 4 pixels apart.
pub(super) fn grid_lines(
    f: &Frame,
    lo: Vec3,
    hi: Vec3,
    axis: usize,
    cells: u32,
    scale: f32,
) -> Vec<(Vec3, Vec3)> {
    let (Some(&l), Some(&h)) = (lo.as_ref().get(axis), hi.as_ref().get(axis)) else {
        return vec![];
    };
    let e = Vec3::AXES.get(axis).copied().unwrap_or(Vec3::X);
    // The boundary planes' normal projected into the cutting plane: moving along it changes
    // only this axis's coordinate among directions in the plane.
    let w = e - f.m * f.m.dot(e);
    let wa = w.dot(e);
    let cell = (h - l) / cells.max(1) as f32;
    // Lines are cell / |w| apart in the plane (|w|² = wa).
    let spacing = cell / wa.sqrt() * scale;
    // (A NaN spacing, from a degenerate grid, draws nothing too.)
    if wa < 1e-4 || spacing.is_nan() || spacing < 4.0 {
        return vec![];
    }
    // Along each line: the direction in the cutting plane that keeps this axis fixed.
    let Some(dir) = f.m.cross(e).try_normalize() else {
        return vec![];
    };
    let mut out = vec![];
    for k in 0..=cells {
        let x = l + cell * k as f32;
        let p0 = f.cut_o + w * ((x - f.cut_o.dot(e)) / wa);
        // Clip the line p0 + s·dir to the box on the other two axes.
        let (mut s0, mut s1) = (f32::NEG_INFINITY, f32::INFINITY);
        for b in (0..3).filter(|&b| b != axis) {
            let (o, d) = (p0[b], dir[b]);
            if d.abs() < 1e-9 {
                if o < lo[b] || o > hi[b] {
                    s0 = f32::INFINITY;
                }
                continue;
            }
            let (ta, tb) = ((lo[b] - o) / d, (hi[b] - o) / d);
            s0 = s0.max(ta.min(tb));
            s1 = s1.min(ta.max(tb));
        }
        if s0 < s1 && s0.is_finite() && s1.is_finite() {
            out.push((p0 + dir * s0, p0 + dir * s1));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cutting plane z = 0 through a 2×3×2-cell grid over [0, 2]×[0, 3]×[−1, 1]: by hand,
    /// the x boundaries meet it in the segments x = 0, 1, 2 from y = 0 to 3; the y boundaries in
    /// y = 0 … 3 from x = 0 to 2; the z boundaries are parallel to it and give nothing.
    #[test]
    fn grid_lines_by_hand() {
        let f = Frame {
            o: Vec3::ZERO,
            x: Vec3::X,
            y: Vec3::Y,
            m: Vec3::Z,
            cut_o: Vec3::new(5.0, -7.0, 0.0),
            d: Vec3::X,
            top_down: false,
        };
        let (lo, hi) = (Vec3::new(0.0, 0.0, -1.0), Vec3::new(2.0, 3.0, 1.0));
        let sorted = |mut v: Vec<(Vec3, Vec3)>| {
            for s in &mut v {
                if s.0.to_array() > s.1.to_array() {
                    *s = (s.1, s.0);
                }
            }
            v
        };
        let x = sorted(grid_lines(&f, lo, hi, 0, 2, 100.0));
        let want: Vec<(Vec3, Vec3)> = (0..=2)
            .map(|k| (Vec3::new(k as f32, 0.0, 0.0), Vec3::new(k as f32, 3.0, 0.0)))
            .collect();
        assert_eq!(x, want);
        let y = sorted(grid_lines(&f, lo, hi, 1, 3, 100.0));
        let want: Vec<(Vec3, Vec3)> = (0..=3)
            .map(|k| (Vec3::new(0.0, k as f32, 0.0), Vec3::new(2.0, k as f32, 0.0)))
            .collect();
        assert_eq!(y, want);
        assert!(grid_lines(&f, lo, hi, 2, 2, 100.0).is_empty());
        // At 3 pixels per unit the 1-unit cells are under 4 pixels apart: left out.
        assert!(grid_lines(&f, lo, hi, 0, 2, 3.0).is_empty());
        // A plane that misses the box: nothing.
        let far = Frame {
            cut_o: Vec3::new(0.0, 0.0, 5.0),
            ..f
        };
        assert!(grid_lines(&far, lo, hi, 0, 2, 100.0).is_empty());
    }
}
