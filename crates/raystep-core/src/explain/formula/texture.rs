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
            roughness,
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
                lod,
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
                match (filter, lod) {
                    (Filter::Nearest, _) => {
                        address_lines(&mut lines, *wrapped, *address, [w, h], "");
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
                    (Filter::Trilinear, Some(lod)) => {
                        lod_lines(&mut lines, lod, [w, h]);
                        let mut rest = &texels[..];
                        for m in &lod.levels {
                            let sub = format!("{}", m.level);
                            address_lines(&mut lines, *wrapped, m.address, m.size, &sub);
                            let n = rest.len().min(4);
                            bilinear_lines(&mut lines, m.address, &rest[..n], m.color, &sub);
                            rest = &rest[n..];
                        }
                        if let [a, b] = &lod.levels[..] {
                            lines.push(line(
                                "T",
                                &format!("(1 − f)·T{} + f·T{}", sub(a.level), sub(b.level)),
                                format!(
                                    "{}·{} + {}·{}",
                                    num(a.weight),
                                    v3(a.color),
                                    num(b.weight),
                                    v3(b.color)
                                ),
                                v3(*texel),
                                Some("f = λ − ⌊λ⌋: the levels blended by where λ falls".into()),
                            ));
                        }
                    }
                    _ => {
                        address_lines(&mut lines, *wrapped, *address, [w, h], "");
                        bilinear_lines(&mut lines, *address, texels, *texel, "");
                    }
                }
                let at = match lod.as_ref().map(|l| &l.levels[..]) {
                    Some([a]) => {
                        format!(" in mip level {} ({} × {})", a.level, a.size[0], a.size[1])
                    }
                    Some([a, b]) => format!(
                        " in mip levels {} and {}, weighted {} and {}",
                        a.level,
                        b.level,
                        num(a.weight),
                        num(b.weight)
                    ),
                    _ => String::new(),
                };
                format!(
                    "(u, v) = ({}, {}) reads \"{texture}\" at texel position ({}, {}){at} \
                     ({}, {} wrap): its colour is {}.",
                    num(u),
                    num(v),
                    num(address[0]),
                    num(address[1]),
                    match filter {
                        Filter::Nearest => "nearest texel",
                        Filter::Bilinear => "bilinear",
                        Filter::Trilinear => "trilinear",
                    },
                    wrap.name(),
                    v3(*texel)
                )
            }
        };
        if let Some(r) = roughness {
            lines.push(line(
                "r",
                "roughness × T_g",
                format!("{} × {}", num(r.material), num(texel[1])),
                num(r.roughness),
                Some(
                    "a roughness texture: its green channel scales the glossy BSDF's roughness (glTF keeps roughness in green)"
                        .into(),
                ),
            ));
            let mirror = r.roughness < crate::scene::MIN_ROUGHNESS;
            lines.push(line(
                "α",
                "r²",
                format!("{}²", num(r.roughness)),
                if mirror {
                    format!("a mirror (r < {})", num(crate::scene::MIN_ROUGHNESS))
                } else {
                    num(r.roughness * r.roughness)
                },
                Some("GGX's α; below the least roughness the BSDF is a perfect mirror".into()),
            ));
            return Explanation {
                title: format!("Roughness texture \"{texture}\" from {}", mapping.name()),
                lines,
                conclusion: format!(
                    "{conclusion} The glossy BSDF's roughness here is {}.",
                    num(r.roughness)
                ),
            };
        }
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

/// A level number as a subscript (T₀, T₁₂).
fn sub(level: u32) -> String {
    level
        .to_string()
        .chars()
        .map(|c| char::from_u32(0x2080 + c.to_digit(10).unwrap_or(0)).unwrap_or(c))
        .collect()
}

/// The address lines, x = u′·w and y = (1 − v′)·h, at a level (`level` names it, or "" for the
/// image itself).
fn address_lines(
    lines: &mut Vec<Formula>,
    wrapped: [f32; 2],
    address: [f32; 2],
    [w, h]: [u32; 2],
    level: &str,
) {
    let (x, y, note) = if level.is_empty() {
        (
            "x".to_string(),
            "y".to_string(),
            format!("a {w} × {h} image; texel (i, j) has its centre at (i + ½, j + ½)"),
        )
    } else {
        let l = sub(level.parse().unwrap_or(0));
        (
            format!("x{l}"),
            format!("y{l}"),
            format!("mip level {level}, {w} × {h} texels"),
        )
    };
    lines.push(line(
        &x,
        "u′·w",
        format!("{}·{w}", p(wrapped[0])),
        num(address[0]),
        Some(note),
    ));
    lines.push(line(
        &y,
        "(1 − v′)·h",
        format!("(1 − {})·{h}", p(wrapped[1])),
        num(address[1]),
        level
            .is_empty()
            .then(|| "rows count down from the top of the image, v up from its bottom".into()),
    ));
}

/// Bilinear's lines: the corner texel, the fractions, the four weights and the sum.
fn bilinear_lines(
    lines: &mut Vec<Formula>,
    address: [f32; 2],
    texels: &[crate::record::texturing::Texel],
    color: [f32; 3],
    level: &str,
) {
    let (xs, ys) = (address[0] - 0.5, address[1] - 0.5);
    let (x0, y0) = (xs.floor(), ys.floor());
    let (fx, fy) = (xs - x0, ys - y0);
    let l = if level.is_empty() {
        String::new()
    } else {
        sub(level.parse().unwrap_or(0))
    };
    lines.push(line(
        "x₀, y₀",
        "⌊x − ½⌋, ⌊y − ½⌋",
        "",
        format!("{}, {}", num(x0), num(y0)),
        Some("the texel whose centre is up and to the left of the point".into()),
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
        &format!("T{l}"),
        "Σ w·texel",
        texels
            .iter()
            .map(|t| format!("{}·{}", num(t.weight), v3(t.color)))
            .collect::<Vec<_>>()
            .join(" + "),
        v3(color),
        None,
    ));
}

/// The ray cone's lines: its width, the texture's density, the footprint, λ and the levels.
fn lod_lines(
    lines: &mut Vec<Formula>,
    lod: &crate::record::texturing::LodRecord,
    [w, h]: [u32; 2],
) {
    lines.push(line(
        "W",
        "γ·d",
        format!("{}·{}", p(lod.spread), p(lod.distance)),
        num(lod.width),
        Some(
            "the ray cone's width: γ is the angle one pixel subtends at the eye, d the path's length from it"
                .into(),
        ),
    ));
    lines.push(line(
        "|n·d̂|",
        "|n·Q| / |Q|",
        "",
        num(lod.cos),
        Some("the geometric normal against the unit ray direction: a slanted view stretches the footprint".into()),
    ));
    lines.push(line(
        "ρ",
        "texels per unit area",
        "",
        num(lod.texels_per_area),
        Some(format!(
            "how densely the {w} × {h} image covers the surface here"
        )),
    ));
    lines.push(line(
        "L",
        "W·√ρ / |n·d̂|",
        format!(
            "{}·√{} / {}",
            p(lod.width),
            p(lod.texels_per_area),
            p(lod.cos)
        ),
        num(lod.footprint),
        Some("the footprint's side in texels of the image".into()),
    ));
    let levels = lod
        .levels
        .iter()
        .map(|m| m.level.to_string())
        .collect::<Vec<_>>()
        .join(" and ");
    lines.push(line(
        "λ",
        "log₂ L",
        format!("log₂ {}", p(lod.footprint)),
        num(lod.lambda),
        Some(format!(
            "the level of detail: level {levels} (⌊λ⌋ and the next, held to the pyramid)"
        )),
    ));
}
