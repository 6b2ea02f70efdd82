//! Checking a student's instances (lesson 20): the ray carried into each instance's object space
//! (S′ = M⁻¹S a point, Q′ = M⁻¹Q a vector, not renormalised), and the hit carried back — the
//! point by M, the normal by the inverse transpose M⁻ᵀ. The classic mistakes are named: the
//! normal carried by M, S′ carried as a vector, Q′ as a point or renormalised, the ray carried by
//! M instead of M⁻¹, the object-space point or normal printed as the world's.
//!
//! The matrices are raystep's recorded ones (3 × 4 rows, the 4th row 0 0 0 1); the candidates
//! for a mistake are computed here in f64 from them.

use super::compare::{Divergence, TracerTolerances, dot, len, ray_name, unit, v};
use super::expected::Expected;
use super::format::{INSTANCE_ARROW, Pixel, Test};
use super::stage::{Stage, in_scope};

/// A 3 × 4 affine matrix by rows.
type Rows = [[f64; 4]; 3];

/// What raystep recorded of a hit carried back from an instance.
#[derive(Debug, Clone, PartialEq)]
pub struct InstanceHitFacts {
    /// The instance's name.
    pub name: String,
    /// M.
    pub to_world: Rows,
    /// M⁻¹.
    pub to_object: Rows,
    /// The hit point in object space.
    pub point: [f64; 3],
    /// The unit normal in object space, facing the object-space ray.
    pub normal: [f64; 3],
    /// M·normal, renormalised: the classic mistake.
    pub wrong_normal: [f64; 3],
}

/// A·p + the translation column: a point carried by A.
pub fn point(a: &Rows, p: [f64; 3]) -> [f64; 3] {
    a.map(|r| r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + r[3])
}

/// A·v without the translation: a vector carried by A.
pub fn vector(a: &Rows, p: [f64; 3]) -> [f64; 3] {
    a.map(|r| r[0] * p[0] + r[1] * p[1] + r[2] * p[2])
}

/// Aᵀ·n (A's 3 × 3 part): with A = M⁻¹, the normal n carried by M⁻ᵀ, not renormalised.
pub fn transpose_times(a: &Rows, n: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|j| a[0][j] * n[0] + a[1][j] * n[1] + a[2][j] * n[2])
}

/// The normal `n` carried by M⁻ᵀ and renormalised, from M⁻¹'s rows.
pub fn carry_normal(to_object: &Rows, n: [f64; 3]) -> [f64; 3] {
    unit(transpose_times(to_object, n))
}

/// The inverse of an affine matrix (None when singular): the candidate "carried by M" needs M
/// where only M⁻¹ was recorded with the ray.
pub fn invert(a: &Rows) -> Option<Rows> {
    let m = |i: usize, j: usize| a[i][j];
    let cof = |i: usize, j: usize| {
        let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
        let (c0, c1) = ((j + 1) % 3, (j + 2) % 3);
        m(r0, c0) * m(r1, c1) - m(r0, c1) * m(r1, c0)
    };
    let det = m(0, 0) * cof(0, 0) + m(0, 1) * cof(0, 1) + m(0, 2) * cof(0, 2);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    // The inverse's (i, j) is the cofactor (j, i) over the determinant.
    let mut inv = [[0.0; 4]; 3];
    for (i, row) in inv.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().take(3).enumerate() {
            *x = cof(j, i) / det;
        }
    }
    let t = [a[0][3], a[1][3], a[2][3]];
    let moved = vector(&inv, t);
    for (row, m) in inv.iter_mut().zip(moved) {
        row[3] = -m;
    }
    Some(inv)
}

/// The first instance whose object-space ray a student printed differently from raystep's, at
/// the stage of its prototype's tests (a sphere's at `sphere`, a mesh's at `plane-triangle`).
/// An instance the student did not enter is theirs to cull, unless the ray hits it.
pub(super) fn instance_rays(
    e: &Expected,
    s: &Pixel,
    m: &[Option<usize>],
    stage: Stage,
    upto: Stage,
    tol: &TracerTolerances,
) -> Divergence {
    for (i, er) in e.pixel.rays.iter().enumerate() {
        if !in_scope(&er.kind, upto) || er.instances.is_empty() {
            continue;
        }
        let Some(sr) = m.get(i).copied().flatten().and_then(|k| s.rays.get(k)) else {
            continue;
        };
        let tol = &tol.at_depth(er.depth);
        let (Some(world_o), Some(world_d)) = (er.origin, er.direction) else {
            continue;
        };
        let le = len(world_d).max(f64::MIN_POSITIVE);
        let ls = sr.direction.map_or(le, len).max(f64::MIN_POSITIVE);
        for (j, ei) in er.instances.iter().enumerate() {
            let end = er
                .instances
                .get(j + 1)
                .map_or(er.tests.len(), |n| n.first_test);
            let at_stage = er.tests.get(ei.first_test..end).is_some_and(|ts| {
                ts.iter().any(|t| match t {
                    Test::Sphere { .. } => stage == Stage::Sphere,
                    _ => stage == Stage::PlaneTriangle,
                })
            });
            if !at_stage {
                continue;
            }
            let step = e
                .instance_steps
                .get(i)
                .and_then(|v| v.get(j))
                .map(|(k, _)| *k);
            let at = |what: String| {
                format!(
                    "{}, instance \"{}\": {what}",
                    ray_name(&e.pixel, i),
                    ei.name
                )
            };
            let Some(si) = sr.instances.iter().find(|x| x.name == ei.name) else {
                let hits_it = er
                    .hit
                    .clone()
                    .flatten()
                    .and_then(|h| h.object)
                    .is_some_and(|o| o.starts_with(&format!("{}{INSTANCE_ARROW}", ei.name)));
                if hits_it && sr.instances.is_empty() {
                    return Some((
                        at("you printed no `instance` record, and the ray hits this instance: before testing its prototype, print the ray carried into its object space, {\"type\":\"instance\",\"name\":…,\"origin\": S′ = M⁻¹S,\"direction\": Q′ = M⁻¹Q}".into()),
                        step,
                    ));
                }
                continue;
            };
            if si.origin.is_none() || si.direction.is_none() {
                return Some((
                    at("your `instance` record has no `origin` or no `direction`: print the ray carried into object space, S′ = M⁻¹S and Q′ = M⁻¹Q".into()),
                    step,
                ));
            }
            let to_object = e.instance_steps.get(i).and_then(|v| v.get(j)).map(|x| x.1);
            let to_world = to_object.as_ref().and_then(invert);
            if let (Some(y), Some(w)) = (si.origin, ei.origin)
                && !tol.close3(y, w, tol.abs * len(w).max(1.0))
            {
                let like = |c: [f64; 3]| tol.close3(y, c, tol.abs * len(c).max(1.0));
                let hint = if to_object.is_some_and(|a| like(vector(&a, world_o))) {
                    " — S′ is a point: M⁻¹'s translation column applies to it (w = 1)"
                } else if to_world.is_some_and(|a| like(point(&a, world_o))) {
                    " — that is M·S: into object space is the inverse, M⁻¹ (M carries object space to the world)"
                } else if like(world_o) {
                    " — that is the world origin S: carry it into object space, S′ = M⁻¹S"
                } else {
                    ""
                };
                return Some((
                    at(format!(
                        "your origin S′ (in object space) is {}, raystep's is {}{hint}",
                        v(y),
                        v(w)
                    )),
                    step,
                ));
            }
            if let (Some(y), Some(w)) = (si.direction, ei.direction) {
                // Scaled as the world rays are: a student's |Q| may differ from raystep's.
                let (ys, ws) = (y.map(|x| x / ls), w.map(|x| x / le));
                if !tol.close3(ys, ws, tol.abs * len(ws).max(1.0)) {
                    let like = |c: [f64; 3]| {
                        let c = c.map(|x| x / le);
                        tol.close3(ys, c, tol.abs * len(c).max(1.0))
                    };
                    let renormalised =
                        dot(unit(y), unit(w)) > 1.0 - 1e-6 && (len(y) - 1.0).abs() < 1e-6;
                    let hint = if renormalised {
                        " — Q′ is renormalised: keep M⁻¹Q as it is, so that t means the same point in both spaces (the hits of different instances then compare by t)"
                    } else if to_object.is_some_and(|a| like(point(&a, world_d))) {
                        " — Q′ is a vector: M⁻¹'s translation column does not apply to it (w = 0)"
                    } else if to_world.is_some_and(|a| like(vector(&a, world_d))) {
                        " — that is M·Q: into object space is the inverse, M⁻¹"
                    } else if like(world_d) {
                        " — that is the world direction Q: carry it into object space, Q′ = M⁻¹Q"
                    } else {
                        ""
                    };
                    return Some((
                        at(format!(
                            "your direction Q′ (in object space) is {}, raystep's is {}{hint}",
                            v(y),
                            v(w)
                        )),
                        step,
                    ));
                }
            }
        }
    }
    None
}

/// Why a student's hit point on an instance may be off: the object-space point printed.
pub(super) fn point_hint(
    f: Option<&InstanceHitFacts>,
    y: [f64; 3],
    tol: &TracerTolerances,
) -> &'static str {
    match f {
        Some(f) if tol.close3(y, f.point, tol.abs * len(f.point).max(1.0)) => {
            " — that is the point in the instance's object space: carry it back to the world, P = M·P′"
        }
        _ => "",
    }
}

/// Why a student's normal at a hit on an instance may be off: carried by M (the classic
/// mistake), or the object-space normal printed.
pub(super) fn normal_hint(
    f: Option<&InstanceHitFacts>,
    y: [f64; 3],
    tol: &TracerTolerances,
) -> &'static str {
    let Some(f) = f else { return "" };
    let abs = tol.abs * 10.0;
    let either = |c: [f64; 3]| tol.close3(y, c, abs) || tol.close3(y.map(|x| -x), c, abs);
    if either(f.wrong_normal) || either(unit(vector(&f.to_world, f.normal))) {
        " — that is M·n′: a normal is carried by the inverse transpose, n = M⁻ᵀ·n′ renormalised; M would tilt it off the surface under a non-uniform scale (lesson 20)"
    } else if either(f.normal) {
        " — that is the normal in the instance's object space: carry it back to the world by the inverse transpose, n = M⁻ᵀ·n′ renormalised"
    } else {
        ""
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invert_undoes_an_affine_matrix() {
        // M: scale (2, 3, 4), a quarter turn about z, then a move by (1, 2, 3). Worked by hand:
        // M = [[0, −3, 0, 1], [2, 0, 0, 2], [0, 0, 4, 3]], so M⁻¹ carries (1, 2, 3) to the
        // origin and x → y/2, y → −x/3, z → z/4.
        let m = [
            [0.0, -3.0, 0.0, 1.0],
            [2.0, 0.0, 0.0, 2.0],
            [0.0, 0.0, 4.0, 3.0],
        ];
        let inv = invert(&m).unwrap();
        let want = [
            [0.0, 0.5, 0.0, -1.0],
            [-1.0 / 3.0, 0.0, 0.0, 1.0 / 3.0],
            [0.0, 0.0, 0.25, -0.75],
        ];
        for (r, w) in inv.iter().zip(want) {
            for (a, b) in r.iter().zip(w) {
                assert!((a - b).abs() < 1e-15, "{inv:?}");
            }
        }
        assert_eq!(point(&inv, [1.0, 2.0, 3.0]), [0.0, 0.0, 0.0]);
        assert!(
            invert(&[
                [1.0, 0.0, 0.0, 0.0],
                [2.0, 0.0, 0.0, 0.0],
                [0.0, 0.0, 1.0, 0.0]
            ])
            .is_none()
        );
    }

    #[test]
    fn a_normal_carried_by_the_inverse_transpose_stays_perpendicular() {
        // The unit sphere squashed to (1, 0.25, 1): at P′ = (1, 1, 0)/√2 the normal n′ = P′.
        // The surface's tangent t′ = (−1, 1, 0) goes to M·t′ = (−1, 0.25, 0); M⁻ᵀn′ ∝ (1, 4, 0)
        // is perpendicular to it, M·n′ ∝ (1, 0.25, 0) is not.
        let to_object = [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 4.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ];
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let n = carry_normal(&to_object, [h, h, 0.0]);
        assert!(dot(n, [-1.0, 0.25, 0.0]).abs() < 1e-15);
        let want = unit([1.0, 4.0, 0.0]);
        assert!(
            n.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-15),
            "{n:?}"
        );
    }
}
