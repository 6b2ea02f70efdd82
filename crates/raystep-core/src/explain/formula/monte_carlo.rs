//! The math panel for the Monte Carlo steps: the estimator's formula with the recorded numbers.
//! Every value shown was recorded by the integrator (the random numbers with their dimensions,
//! the densities, the BSDF value, the MIS weights); the products are the recorded ones too.

use super::{Explanation, line, yes_no};
use crate::record::Draw;
use crate::record::number::{num, v3};

/// "u₁₆ = 0.25, u₁₇ = 0.5": the draws with their dimensions.
pub(crate) fn draws(random: &[Draw]) -> String {
    if random.is_empty() {
        return "none (deterministic)".into();
    }
    random
        .iter()
        .map(|d| format!("u[{}] = {}", d.dimension, num(d.value)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The line listing the random numbers a step drew.
fn random_line(random: &[Draw]) -> super::Formula {
    line(
        "u",
        "uniform(pixel, sample, dimension, seed)",
        "",
        draws(random),
        None,
    )
}

/// The thin lens.
pub(super) fn lens(
    random: &[Draw],
    lens_point: [f32; 3],
    focus_point: [f32; 3],
    pdf: f32,
    direction: [f32; 3],
) -> Explanation {
    Explanation {
        title: "Thin lens".into(),
        lines: vec![
            random_line(random),
            line(
                "(dx, dy)",
                "r · concentric_disk(u)",
                "",
                "",
                Some("a point uniform on the lens of radius r (the aperture)".into()),
            ),
            line("O", "eye + dx·u + dy·v", "", v3(lens_point), None),
            line(
                "F",
                "eye + d · focus_distance / (d · −w)",
                "",
                v3(focus_point),
                Some("where the pinhole ray d meets the plane in focus".into()),
            ),
            line("D", "(F − O) / |F − O|", "", v3(direction), None),
            line("pdf", "1 / (π r²)", "", num(pdf), Some("per unit area of the lens".into())),
        ],
        conclusion: "Every point of the lens aims at the same point F: what lies on the plane in focus is sharp, what lies off it spreads over a disk (depth of field).".into(),
    }
}

/// Next-event estimation: one light sample.
#[allow(clippy::too_many_arguments)]
pub(super) fn light_sample(
    name: &str,
    random: &[Draw],
    point: [f32; 3],
    distance: f32,
    select_pdf: f32,
    pdf: f32,
    radiance: [f32; 3],
    bsdf: [f32; 3],
    cos: f32,
    bsdf_pdf: f32,
    mis_weight: f32,
    blocked: bool,
    contribution: [f32; 3],
) -> Explanation {
    let delta = pdf == 0.0;
    let mut lines = vec![
        random_line(random),
        line(
            "y",
            "a point on the light",
            "",
            v3(point),
            Some(format!("\"{name}\", at distance {}", num(distance))),
        ),
        line("P(light)", "pick probability", "", num(select_pdf), None),
    ];
    if delta {
        lines.push(line(
            "L",
            "I / d²",
            "",
            v3(radiance),
            Some("a point light: a delta, no density".into()),
        ));
    } else {
        lines.push(line(
            "p_light",
            "P(light) · pdf(ω)",
            "",
            num(pdf),
            Some("per steradian".into()),
        ));
        lines.push(line("L", "emitted radiance", "", v3(radiance), None));
    }
    lines.push(line("f", "BSDF(ωo, ωi)", "", v3(bsdf), None));
    lines.push(line("cos θ", "|ωi · n|", "", num(cos), None));
    if !delta {
        lines.push(line("p_bsdf", "BSDF's pdf of ωi", "", num(bsdf_pdf), None));
        lines.push(line(
            "w",
            "p_light² / (p_light² + p_bsdf²)",
            format!("{}² / ({}² + {}²)", num(pdf), num(pdf), num(bsdf_pdf)),
            num(mis_weight),
            Some("the power heuristic (1 when MIS is off)".into()),
        ));
    }
    lines.push(line(
        "visible?",
        "shadow ray reaches y",
        "",
        yes_no(!blocked),
        None,
    ));
    let formula = if delta {
        "throughput · f · L · cos θ / P(light)"
    } else {
        "throughput · f · L · cos θ · w / p_light"
    };
    lines.push(line("contribution", formula, "", v3(contribution), None));
    Explanation {
        title: format!("Light sample: \"{name}\""),
        lines,
        conclusion: if blocked {
            "The shadow ray is blocked: this sample adds nothing (the shadow's share of the soft edge).".into()
        } else {
            "One sample of the direct light: averaged over many samples it converges to the light's true contribution.".into()
        },
    }
}

/// A BSDF sample.
#[allow(clippy::too_many_arguments)]
pub(super) fn bsdf_sample(
    bsdf: &str,
    lobe: &str,
    random: &[Draw],
    direction: [f32; 3],
    pdf: Option<f32>,
    value: [f32; 3],
    cos: f32,
    weight: [f32; 3],
    throughput: [f32; 3],
) -> Explanation {
    let mut lines = vec![
        random_line(random),
        line(
            "ωi",
            &format!("sample the {bsdf} BSDF ({lobe})"),
            "",
            v3(direction),
            None,
        ),
    ];
    match pdf {
        Some(p) => {
            lines.push(line(
                "pdf",
                "density of ωi",
                "",
                num(p),
                Some("per steradian".into()),
            ));
            lines.push(line("f", "BSDF(ωo, ωi)", "", v3(value), None));
            lines.push(line("cos θ", "|ωi · n|", "", num(cos), None));
            lines.push(line(
                "weight",
                "f · cos θ / pdf",
                format!("{} · {} / {}", v3(value), num(cos), num(p)),
                v3(weight),
                None,
            ));
        }
        None => lines.push(line(
            "weight",
            "a delta: the reflectance (glass: 1/η² through the surface)",
            "",
            v3(weight),
            None,
        )),
    }
    lines.push(line(
        "throughput",
        "product of the weights from the camera",
        "",
        v3(throughput),
        None,
    ));
    Explanation {
        title: format!("BSDF sample ({bsdf}, {lobe})"),
        lines,
        conclusion: "The next ray leaves in ωi; whatever radiance it brings back is multiplied by the weight.".into(),
    }
}

/// Emission found by a ray.
#[allow(clippy::too_many_arguments)]
pub(super) fn emitted(
    name: &str,
    radiance: [f32; 3],
    light_pdf: f32,
    bsdf_pdf: f32,
    mis_weight: f32,
    contribution: [f32; 3],
) -> Explanation {
    let mut lines = vec![line("Le", "emitted radiance", "", v3(radiance), None)];
    if bsdf_pdf > 0.0 {
        lines.push(line(
            "p_bsdf",
            "pdf of the BSDF sample that found it",
            "",
            num(bsdf_pdf),
            None,
        ));
        lines.push(line(
            "p_light",
            "pdf had light sampling chosen it",
            "",
            num(light_pdf),
            None,
        ));
        lines.push(line(
            "w",
            "p_bsdf² / (p_bsdf² + p_light²)",
            format!(
                "{}² / ({}² + {}²)",
                num(bsdf_pdf),
                num(bsdf_pdf),
                num(light_pdf)
            ),
            num(mis_weight),
            Some("the power heuristic".into()),
        ));
    } else {
        lines.push(line(
            "w",
            "1",
            "",
            num(mis_weight),
            Some("seen from the camera or a mirror: light sampling could not have found it".into()),
        ));
    }
    lines.push(line(
        "contribution",
        "throughput · w · Le",
        "",
        v3(contribution),
        None,
    ));
    Explanation {
        title: format!("Emission: \"{name}\""),
        lines,
        conclusion: "The ray landed on a light; MIS shares this light between the two strategies so it is counted once on average.".into(),
    }
}

/// Russian roulette.
pub(super) fn roulette(
    random: Draw,
    probability: f32,
    survived: bool,
    throughput: [f32; 3],
) -> Explanation {
    Explanation {
        title: "Russian roulette".into(),
        lines: vec![
            line(
                "q",
                "min(1, max channel of the throughput)",
                "",
                num(probability),
                None,
            ),
            line(
                "u",
                "uniform(pixel, sample, dimension, seed)",
                format!("u[{}]", random.dimension),
                num(random.value),
                None,
            ),
            line(
                "go on?",
                "u < q",
                format!("{} < {}", num(random.value), num(probability)),
                yes_no(survived),
                None,
            ),
            line(
                "throughput",
                if survived {
                    "throughput / q"
                } else {
                    "(the path ends)"
                },
                "",
                v3(throughput),
                None,
            ),
        ],
        conclusion: if survived {
            "The path goes on, its weight divided by q, so that on average the estimate is unchanged.".into()
        } else {
            "The path ends here: what it would have gathered is made up, on average, by the paths that survive.".into()
        },
    }
}
