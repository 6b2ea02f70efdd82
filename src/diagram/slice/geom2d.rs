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
    let (p, q) =
        crate::diagram::canvas::clip_segment(rect, [f(a[0]), f(a[1])], [f(b[0]), f(b[1])])?;
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
