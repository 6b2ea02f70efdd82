//! The two-level walk's own steps: the ray carried into an instance's object space, and a hit
//! carried back. Each product is recomputed here in f32 from the recorded matrix and the ray's
//! recorded origin and direction, with [`Affine`]'s operations in its order: the values the
//! tracer had.

use super::{Ctx, Explanation, line};
use crate::record::number::{num, v3};
use crate::scene::Affine;
use glam::Vec3;

const AXES: [&str; 3] = ["x", "y", "z"];

/// One row of M·p: the symbolic and substituted forms, with the translation when `point`.
fn row(m: &[f32; 4], p: [f32; 3], point: bool) -> String {
    let mut s = format!(
        "{}·{} + {}·{} + {}·{}",
        num(m[0]),
        num(p[0]),
        num(m[1]),
        num(p[1]),
        num(m[2]),
        num(p[2])
    );
    if point {
        s += &format!(" + {}", num(m[3]));
    }
    s
}

impl Ctx<'_> {
    pub(super) fn instance(
        &self,
        name: &str,
        prototype: &str,
        to_object: &[[f32; 4]; 3],
        origin: [f32; 3],
        direction: [f32; 3],
    ) -> Explanation {
        let m = Affine(*to_object);
        let s = self.ray.origin;
        let q = self.ray.direction;
        let mut lines = vec![];
        for (k, axis) in AXES.iter().enumerate() {
            let value = m.point(Vec3::from(s))[k];
            lines.push(line(
                &format!("S′{axis}"),
                &format!("(M⁻¹·S){axis} = m{k}0·Sx + m{k}1·Sy + m{k}2·Sz + m{k}3"),
                row(&to_object[k], s, true),
                num(value),
                (value.to_bits() != origin[k].to_bits())
                    .then(|| format!("recorded {}", num(origin[k]))),
            ));
        }
        for (k, axis) in AXES.iter().enumerate() {
            let value = m.vector(Vec3::from(q))[k];
            lines.push(line(
                &format!("Q′{axis}"),
                &format!("(M⁻¹·Q){axis} = m{k}0·Qx + m{k}1·Qy + m{k}2·Qz"),
                row(&to_object[k], q, false),
                num(value),
                Some(if k == 2 {
                    "a direction takes no translation; it is not renormalised, so t is the same in both spaces".into()
                } else {
                    "a direction takes no translation".into()
                }),
            ));
        }
        Explanation {
            title: format!("Into the object space of instance \"{name}\""),
            lines,
            conclusion: format!(
                "The ray S′ + t·Q′ = {} + t·{} meets \"{prototype}\" where the world ray meets this instance, at the same t: the prototype's BLAS is walked once per instance, with no copy of its triangles.",
                v3(origin),
                v3(direction)
            ),
        }
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn instance_hit(
        &self,
        name: &str,
        to_world: &[[f32; 4]; 3],
        to_object: &[[f32; 4]; 3],
        point: [f32; 3],
        normal: [f32; 3],
        world_point: [f32; 3],
        world_normal: [f32; 3],
        wrong_normal: [f32; 3],
    ) -> Explanation {
        let m = Affine(*to_world);
        let inv = Affine(*to_object);
        let mut lines = vec![];
        let p = m.point(Vec3::from(point));
        for (k, axis) in AXES.iter().enumerate() {
            lines.push(line(
                &format!("P{axis}"),
                &format!("(M·P′){axis}"),
                row(&to_world[k], point, true),
                num(p[k]),
                None,
            ));
        }
        let n = inv.transpose_vector(Vec3::from(normal));
        for (k, axis) in AXES.iter().enumerate() {
            let col = [to_object[0][k], to_object[1][k], to_object[2][k], 0.0];
            lines.push(line(
                &format!("n″{axis}"),
                &format!("(M⁻ᵀ·n′){axis} = m0{k}·n′x + m1{k}·n′y + m2{k}·n′z (column {k} of M⁻¹)"),
                row(&col, normal, false),
                num(n[k]),
                None,
            ));
        }
        lines.push(line(
            "n",
            "n″ / |n″|",
            format!("{} / {}", v3(n.to_array()), num(n.length())),
            v3(world_normal),
            Some("the world normal".into()),
        ));
        lines.push(line(
            "M·n′",
            "the matrix itself, renormalised",
            "",
            v3(wrong_normal),
            Some("the classic mistake: right only for rotations and uniform scales".into()),
        ));
        Explanation {
            title: format!("The hit on instance \"{name}\", carried back to the world"),
            lines,
            conclusion: format!(
                "The point moves with the object, by M: {}. A normal is not a point or a direction along the surface: tangents t move by M, and n must stay perpendicular to them, (M⁻ᵀn)·(Mt) = n·t = 0; so n moves by M⁻ᵀ: {}.",
                v3(world_point),
                v3(world_normal)
            ),
        }
    }
}
