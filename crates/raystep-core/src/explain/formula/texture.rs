//! The `Texture` step: from the hit to (u, v), from (u, v) to texels, and the colour.

use super::*;
use crate::record::texturing::{TexelLookup, UvMapping};
use crate::scene::{Filter, Wrap};

impl Ctx<'_> {
    /// Explains a texture lookup with the recorded numbers.
    pub(super) fn texture(&self, step: &Step) -> Explanation {
        let Step::Texture {
            texture,
            mapping,
            barycentric,
            vertex_uvs,
            direction,
            axes,
            uv,
            lookup,
            texel,
            color,
        } = step
        else {
            return Explanation::default();
        };
        let mut lines = vec![];
        let [u, v] = *uv;
        match mapping {
            UvMapping::VertexUvs => {
                if let (Some([b1, b2]), Some(t)) = (barycentric, vertex_uvs) {
                    let b0 = 1.0 - b1 - b2;
                    lines.push(line(
                        "b₀",
                        "1 − b₁ − b₂",
                        format!("1 − {} − {}", p(*b1), p(*b2)),
                        p(b0),
                        Some("the hit's barycentric weights, from the triangle test".into()),
                    ));
                    for (k, name) in ["u", "v"].into_iter().enumerate() {
                        lines.push(line(
                            name,
                            &format!("b₀·t₀{name} + b₁·t₁{name} + b₂·t₂{name}"),
                            format!(
                                "{}·{} + {}·{} + {}·{}",
                                p(b0),
                                p(t[0][k]),
                                p(*b1),
                                p(t[1][k]),
                                p(*b2),
                                p(t[2][k])
                            ),
                            num(uv[k]),
                            (k == 0).then(|| {
                                format!(
                                    "the vertices' texture coordinates t₀ = ({}, {}), t₁ = ({}, {}), t₂ = ({}, {}) blended as the vertices are in P",
                                    num(t[0][0]),
                                    num(t[0][1]),
                                    num(t[1][0]),
                                    num(t[1][1]),
                                    num(t[2][0]),
                                    num(t[2][1])
                                )
                            }),
                        ));
                    }
                }
            }
            UvMapping::Barycentric => lines.push(line(
                "(u, v)",
                "(b₁, b₂)",
                "",
                format!("({}, {})", num(u), num(v)),
                Some("the triangle has no texture coordinates: the barycentrics are used".into()),
            )),
            UvMapping::Sphere => {
                if let Some(d) = direction {
                    lines.push(line(
                        "d",
                        "(P − C)/r",
                        "",
                        v3(*d),
                        Some("the outward unit normal".into()),
                    ));
                    lines.push(line(
                        "u",
                        "(atan2(−d_z, d_x) + π) / 2π",
                        format!("(atan2({}, {}) + π) / 2π", p(-d[2]), p(d[0])),
                        num(u),
                        Some("the longitude, 0 … 1 once round".into()),
                    ));
                    lines.push(line(
                        "v",
                        "atan2(√(d_x² + d_z²), −d_y) / π",
                        format!("atan2(√({}² + {}²), {}) / π", p(d[0]), p(d[2]), p(-d[1])),
                        num(v),
                        Some("the latitude: 0 at the bottom, 1 at the top".into()),
                    ));
                }
            }
            UvMapping::Plane => {
                let point = self.surface_before().map(|(pt, _)| pt);
                if let Some(a) = axes {
                    for (k, name) in ["u", "v"].into_iter().enumerate() {
                        lines.push(line(
                            name,
                            &format!("P·a{}", if k == 0 { "₁" } else { "₂" }),
                            point.map_or(String::new(), |pt| format!("{}·{}", vv(pt), v3(a[k]))),
                            num(uv[k]),
                            (k == 0).then(|| {
                                "the point's coordinates along two axes in the plane".to_string()
                            }),
                        ));
                    }
                }
            }
        }
        let conclusion = match lookup {
            TexelLookup::Checker {
                squares, cell, odd, ..
            } => {
                lines.push(line(
                    "i",
                    "⌊u·s₁⌋",
                    format!("⌊{}·{}⌋", p(u), squares[0]),
                    num(cell[0]),
                    Some(format!(
                        "{} × {} squares per unit of u and v",
                        squares[0], squares[1]
                    )),
                ));
                lines.push(line(
                    "j",
                    "⌊v·s₂⌋",
                    format!("⌊{}·{}⌋", p(v), squares[1]),
                    num(cell[1]),
                    None,
                ));
                lines.push(line(
                    "T",
                    "i + j even: colour 1; odd: colour 2",
                    format!(
                        "{} + {} is {}",
                        num(cell[0]),
                        num(cell[1]),
                        if *odd { "odd" } else { "even" }
                    ),
                    v3(*texel),
                    None,
                ));
                format!(
                    "(u, v) = ({}, {}) falls in square ({}, {}) of \"{texture}\", an {} one: \
                     its colour is {}.",
                    num(u),
                    num(v),
                    num(cell[0]),
                    num(cell[1]),
                    if *odd { "odd" } else { "even" },
                    v3(*texel)
                )
            }
            TexelLookup::Image {
                size,
                filter,
                wrap,
                wrapped,
                address,
                texels,
            } => {
                let [w, h] = *size;
                let wrap_formula = match wrap {
                    Wrap::Repeat => "t − ⌊t⌋",
                    Wrap::Clamp => "min(max(t, 0), 1)",
                    Wrap::Mirror => "m = t − 2⌊t/2⌋; m ≤ 1 ? m : 2 − m",
                };
                if *wrapped != [u, v] {
                    lines.push(line(
                        "(u′, v′)",
                        wrap_formula,
                        "",
                        format!("({}, {})", num(wrapped[0]), num(wrapped[1])),
                        Some(format!("{} wrap", wrap.name())),
                    ));
                }
                lines.push(line(
                    "x",
                    "u′·w",
                    format!("{}·{w}", p(wrapped[0])),
                    num(address[0]),
                    Some(format!(
                        "a {w} × {h} image; texel (i, j) has its centre at (i + ½, j + ½)"
                    )),
                ));
                lines.push(line(
                    "y",
                    "(1 − v′)·h",
                    format!("(1 − {})·{h}", p(wrapped[1])),
                    num(address[1]),
                    Some("rows count down from the top of the image, v up from its bottom".into()),
                ));
                match filter {
                    Filter::Nearest => {
                        if let Some(t) = texels.first() {
                            lines.push(line(
                                "(i, j)",
                                "(⌊x⌋, ⌊y⌋)",
                                "",
                                format!("({}, {})", t.at[0], t.at[1]),
                                Some("nearest: the texel the point falls in".into()),
                            ));
                        }
                        lines.push(line("T", "texel(i, j)", "", v3(*texel), None));
                    }
                    Filter::Bilinear => {
                        let (xs, ys) = (address[0] - 0.5, address[1] - 0.5);
                        let (x0, y0) = (xs.floor(), ys.floor());
                        let (fx, fy) = (xs - x0, ys - y0);
                        lines.push(line(
                            "x₀, y₀",
                            "⌊x − ½⌋, ⌊y − ½⌋",
                            "",
                            format!("{}, {}", num(x0), num(y0)),
                            Some(
                                "the texel whose centre is up and to the left of the point".into(),
                            ),
                        ));
                        lines.push(line(
                            "f_x, f_y",
                            "(x − ½) − x₀, (y − ½) − y₀",
                            "",
                            format!("{}, {}", num(fx), num(fy)),
                            Some("how far the point is towards the next texel centre".into()),
                        ));
                        let names = [
                            "(1 − f_x)(1 − f_y)",
                            "f_x(1 − f_y)",
                            "(1 − f_x)f_y",
                            "f_x·f_y",
                        ];
                        for (t, formula) in texels.iter().zip(names) {
                            lines.push(line(
                                &format!("w({}, {})", t.at[0], t.at[1]),
                                formula,
                                "",
                                num(t.weight),
                                Some(format!(
                                    "texel ({}, {}) = {}",
                                    t.at[0],
                                    t.at[1],
                                    v3(t.color)
                                )),
                            ));
                        }
                        lines.push(line(
                            "T",
                            "Σ w·texel",
                            texels
                                .iter()
                                .map(|t| format!("{}·{}", num(t.weight), v3(t.color)))
                                .collect::<Vec<_>>()
                                .join(" + "),
                            v3(*texel),
                            None,
                        ));
                    }
                }
                format!(
                    "(u, v) = ({}, {}) reads \"{texture}\" at texel position ({}, {}) \
                     ({}, {} wrap): its colour is {}.",
                    num(u),
                    num(v),
                    num(address[0]),
                    num(address[1]),
                    match filter {
                        Filter::Nearest => "nearest texel",
                        Filter::Bilinear => "bilinear",
                    },
                    wrap.name(),
                    v3(*texel)
                )
            }
        };
        let material = self
            .ray
            .hit
            .as_ref()
            .and_then(|h| self.object(h.object))
            .map(|o| o.color);
        lines.push(line(
            "C",
            "material colour × T",
            material.map_or(String::new(), |m| format!("{} × {}", v3(m), v3(*texel))),
            v3(*color),
            Some(
                "Whitted's Phong terms use C; a Monte Carlo BSDF's albedo or tint is multiplied by T"
                    .into(),
            ),
        ));
        Explanation {
            title: format!("Texture \"{texture}\" from {}", mapping.name()),
            lines,
            conclusion: format!("{conclusion} The surface colour is {}.", v3(*color)),
        }
    }
}
