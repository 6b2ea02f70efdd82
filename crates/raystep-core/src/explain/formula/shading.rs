//! The math panel's shading steps: Phong lighting, reflection, refraction (Snell), Schlick, the depth limit, the weight cut-off, spawned rays and the colour.

use super::*;

impl Ctx<'_> {
    /// Phong lighting: l, r, e, l·n, r·e, the three terms and their sum are the recorded ones
    /// (an older trace without the vectors shows "—" for them). The material's Phong
    /// coefficients are not in a trace, so they stay symbols.
    pub(super) fn light(&self, step: &Step) -> Explanation {
        let Step::Light {
            light,
            name,
            blocked,
            blocker,
            l_dot_n,
            r_dot_e,
            ambient,
            diffuse,
            specular,
            light_dir,
            reflected,
            eye,
            total,
        } = step
        else {
            return Explanation::default();
        };
        let (light, blocked, blocker) = (*light, *blocked, blocker.as_deref());
        let (l_dot_n, r_dot_e) = (*l_dot_n, *r_dot_e);
        let (ambient, diffuse, specular) = (*ambient, *diffuse, *specular);
        let lt = self.trace.lights.get(light as usize);
        let lcol = lt.map_or("I".to_string(), |l| vv(l.color));
        let col = self.surface_color().map_or("c".to_string(), v3);
        let mut lines = vec![];
        let surf = self.surface_before();
        let vec_or = |v: &Option<[f32; 3]>, symbol: &str| v.map_or(symbol.to_string(), v3);
        let (ls, rs, es) = (
            vec_or(light_dir, "l"),
            vec_or(reflected, "r"),
            vec_or(eye, "e"),
        );
        let ns = surf.map_or("n".to_string(), |(_, n)| vv(n));
        if let Some(l) = light_dir {
            lines.push(line(
                "l",
                "(L − P)/|L − P|",
                match (lt, surf) {
                    (Some(lt), Some((pt, _))) => format!("({} − {})/|…|", vv(lt.position), vv(pt)),
                    _ => String::new(),
                },
                v3(*l),
                Some("unit vector towards the light".into()),
            ));
        }
        lines.push(line(
            "l·n",
            "l·n",
            format!("{ls}·{ns}"),
            num(l_dot_n),
            Some(if l_dot_n < 0.0 {
                "< 0: the light is behind the surface".into()
            } else {
                "cosine of the angle of incidence".into()
            }),
        ));
        if reflected.is_some() {
            lines.push(line(
                "r",
                "−l − 2(−l·n)n",
                "",
                rs.clone(),
                Some("the light reflected about n".into()),
            ));
        }
        if eye.is_some() {
            lines.push(line(
                "e",
                "−Q/|Q|",
                "",
                es.clone(),
                Some("unit vector towards the eye".into()),
            ));
        }
        lines.push(line(
            "r·e",
            "r·e",
            format!("{rs}·{es}"),
            num(r_dot_e),
            Some(if r_dot_e > 0.0 {
                "> 0: a highlight is possible".into()
            } else {
                "≤ 0: no highlight".into()
            }),
        ));
        lines.push(line(
            "ambient",
            "c ⊙ I · k_a",
            format!("{col} ⊙ {lcol} · k_a"),
            v3(ambient),
            Some("present even in shadow (k_a: the material's, not stored in a trace)".into()),
        ));
        let lit = !blocked && l_dot_n >= 0.0;
        lines.push(line(
            "diffuse",
            "c ⊙ I · k_d · (l·n)",
            if lit {
                format!("{col} ⊙ {lcol} · k_d · {}", num(l_dot_n))
            } else {
                "0".into()
            },
            v3(diffuse),
            (!lit).then(|| {
                if blocked {
                    "0: in shadow".into()
                } else {
                    "0: l·n < 0".into()
                }
            }),
        ));
        lines.push(line(
            "specular",
            "I · k_s · (r·e)^shininess",
            if lit && r_dot_e > 0.0 {
                format!("{lcol} · k_s · {}^shininess", num(r_dot_e))
            } else {
                "0".into()
            },
            v3(specular),
            (!(lit && r_dot_e > 0.0)).then(|| {
                if !lit {
                    "0: no direct light".into()
                } else {
                    "0: r·e ≤ 0".into()
                }
            }),
        ));
        lines.push(line(
            "total",
            "ambient + diffuse + specular",
            format!("{} + {} + {}", v3(ambient), v3(diffuse), v3(specular)),
            total.map_or("—".into(), v3),
            None,
        ));
        let conclusion = if blocked {
            format!(
                "The light is blocked by \"{}\": ambient only.",
                blocker.unwrap_or("?")
            )
        } else if l_dot_n < 0.0 {
            "The light is behind the surface: ambient only.".into()
        } else {
            format!(
                "The light reaches the surface: ambient + diffuse{}.",
                if r_dot_e > 0.0 { " + specular" } else { "" }
            )
        };
        Explanation {
            title: format!("Phong lighting from light \"{name}\""),
            lines,
            conclusion,
        }
    }

    /// A reflection ray: d·n and r are the recorded ones.
    pub(super) fn reflect(
        &self,
        reflective: f32,
        direction: [f32; 3],
        d_dot_n: Option<f32>,
    ) -> Explanation {
        let d = self.dir();
        let mut lines = vec![];
        match (self.surface_before(), d_dot_n) {
            (Some((_, n)), Some(dn)) => {
                lines.push(line(
                    "d·n",
                    "Q·n",
                    format!("{}·{}", vv(d), vv(n)),
                    num(dn),
                    None,
                ));
                lines.push(line(
                    "r",
                    "Q − 2(Q·n)n",
                    format!("{} − 2·{}·{}", vv(d), p(dn), vv(n)),
                    v3(direction),
                    None,
                ));
            }
            _ => lines.push(line("r", "Q − 2(Q·n)n", "", v3(direction), None)),
        }
        lines.push(line(
            "weight",
            "k_r",
            "",
            num(reflective),
            Some("the reflected colour is multiplied by the material's reflectivity".into()),
        ));
        Explanation {
            title: "Mirror reflection".into(),
            lines,
            conclusion: format!(
                "A reflection ray leaves along r = {}; its colour counts × {}.",
                v3(direction),
                num(reflective)
            ),
        }
    }

    /// Snell's law: η, e, cos θᵢ, sin² θₜ, the critical angle, cos θₜ and the direction are
    /// the recorded ones (an older trace without η, e and cos θₜ shows "—" for them).
    pub(super) fn refract(&self, step: &Step) -> Explanation {
        let Step::Refract {
            n1,
            n2,
            cos_i,
            sin2_t,
            critical_angle_deg: critical,
            total_internal_reflection: tir,
            direction,
            eta,
            eye,
            cos_t,
        } = step
        else {
            return Explanation::default();
        };
        let (n1, n2, cos_i, sin2_t, tir) = (*n1, *n2, *cos_i, *sin2_t, *tir);
        let opt_num = |x: Option<f32>| x.map_or("—".to_string(), num);
        let ratio = opt_num(*eta);
        let es = eye.map_or("e".to_string(), v3);
        let surf = self.surface_before();
        let mut lines = vec![line(
            "η",
            "n1/n2",
            format!("{}/{}", num(n1), num(n2)),
            ratio.clone(),
            None,
        )];
        lines.push(line(
            "cos θᵢ",
            "e·n",
            surf.map_or(String::new(), |(_, n)| format!("{es}·{}", vv(n))),
            num(cos_i),
            Some(format!(
                "θᵢ = {}°",
                num(cos_i.clamp(-1.0, 1.0).acos().to_degrees())
            )),
        ));
        lines.push(line(
            "sin² θₜ",
            "η²(1 − cos² θᵢ)",
            format!("{ratio}²·(1 − {}²)", p(cos_i)),
            num(sin2_t),
            Some(if tir {
                "> 1: no real θₜ — total internal reflection".into()
            } else {
                "≤ 1: the ray gets through".into()
            }),
        ));
        if let Some(c) = *critical {
            lines.push(line(
                "θc",
                "asin(n2/n1)",
                format!("asin({}/{})", num(n2), num(n1)),
                format!("{}°", num(c)),
                Some("beyond this angle of incidence, nothing gets out".into()),
            ));
        }
        if !tir {
            let cos_t = opt_num(*cos_t);
            lines.push(line(
                "cos θₜ",
                "√(1 − sin² θₜ)",
                format!("√(1 − {})", num(sin2_t)),
                cos_t.clone(),
                None,
            ));
            lines.push(line(
                "t",
                "(η cos θᵢ − cos θₜ)·n − η·e",
                surf.map_or(String::new(), |(_, n)| {
                    format!("({ratio}·{} − {cos_t})·{} − {ratio}·{es}", p(cos_i), vv(n),)
                }),
                direction.map_or("—".into(), v3),
                Some("the refracted direction".into()),
            ));
        }
        Explanation {
            title: "Refraction (Snell's law)".into(),
            lines,
            conclusion: if tir {
                format!(
                    "sin² θₜ = {} > 1: total internal reflection — no refracted ray; the light is all reflected.",
                    num(sin2_t)
                )
            } else {
                format!(
                    "Going from n = {} into n = {}, the ray bends to {}.",
                    num(n1),
                    num(n2),
                    direction.map_or("—".into(), v3)
                )
            },
        }
    }

    /// Schlick's approximation: R0, the cosine used and R are the recorded ones; n1, n2 and
    /// sin² θₜ are those of this ray's `Refract` step (an older trace without R0 and the cosine
    /// shows "—" for them).
    pub(super) fn schlick(
        &self,
        reflectance: f32,
        r0: Option<f32>,
        cos: Option<f32>,
    ) -> Explanation {
        let refr = self.before().iter().rev().find_map(|s| match s.step {
            Step::Refract {
                n1,
                n2,
                cos_i,
                sin2_t,
                ..
            } => Some((n1, n2, cos_i, sin2_t)),
            _ => None,
        });
        let mut lines = vec![];
        let mut tir = false;
        let r0s = r0.map_or("—".to_string(), num);
        match refr {
            Some((n1, n2, cos_i, sin2_t)) => {
                lines.push(line(
                    "R0",
                    "((n1 − n2)/(n1 + n2))²",
                    format!("(({} − {})/({} + {}))²", num(n1), num(n2), num(n1), num(n2)),
                    r0s.clone(),
                    Some("the reflectance head-on".into()),
                ));
                let cos = if n1 > n2 {
                    if sin2_t > 1.0 {
                        tir = true;
                        None
                    } else {
                        lines.push(line(
                            "cos θ",
                            "cos θₜ = √(1 − sin² θₜ)",
                            format!("√(1 − {})", num(sin2_t)),
                            cos.map_or("—".to_string(), num),
                            Some("n1 > n2: Schlick uses the transmitted angle".into()),
                        ));
                        Some(cos)
                    }
                } else {
                    lines.push(line(
                        "cos θ",
                        "cos θᵢ",
                        "",
                        cos.map_or("—".to_string(), num),
                        None,
                    ));
                    Some(cos.or(Some(cos_i)))
                };
                match cos {
                    Some(c) => lines.push(line(
                        "R(θ)",
                        "R0 + (1 − R0)(1 − cos θ)⁵",
                        format!(
                            "{r0s} + (1 − {r0s})·(1 − {})⁵",
                            c.map_or("cos θ".to_string(), p)
                        ),
                        num(reflectance),
                        None,
                    )),
                    None => lines.push(line(
                        "R(θ)",
                        "1 (total internal reflection)",
                        "",
                        num(reflectance),
                        Some(format!("sin² θₜ = {} > 1", num(sin2_t))),
                    )),
                }
            }
            None => lines.push(line(
                "R(θ)",
                "R0 + (1 − R0)(1 − cos θ)⁵",
                "",
                num(reflectance),
                Some("no Refract step in this ray (recursion limit): n1, n2 not recorded".into()),
            )),
        }
        Explanation {
            title: "Fresnel reflectance (Schlick's approximation)".into(),
            lines,
            conclusion: if tir {
                "Total internal reflection: everything is reflected (R = 1).".into()
            } else {
                format!(
                    "R = {}: the colour is surface + {}·reflected + {}·refracted.",
                    num(reflectance),
                    num(reflectance),
                    num(1.0 - reflectance)
                )
            },
        }
    }

    pub(super) fn depth_limit(&self, max_depth: u32) -> Explanation {
        let d = self.ray.depth;
        Explanation {
            title: "Recursion limit".into(),
            lines: vec![line(
                "recurse?",
                "depth < max_depth",
                format!("{d} < {max_depth}"),
                yes_no(d < max_depth),
                None,
            )],
            conclusion: format!(
                "This ray is at depth {d}, the limit is {max_depth}: no secondary ray is traced (it contributes black)."
            ),
        }
    }

    pub(super) fn weight_cutoff(
        &self,
        kind: RayKind,
        contribution: f32,
        cutoff: f32,
    ) -> Explanation {
        let kind = kind.name();
        Explanation {
            title: "Weight cut-off".into(),
            lines: vec![line(
                "spawn?",
                "share of the pixel ≥ 1/512",
                format!("{} ≥ {}", num(contribution), num(cutoff)),
                yes_no(contribution >= cutoff),
                Some(
                    "the share is the product of the weights from the camera down to this ray"
                        .into(),
                ),
            )],
            conclusion: format!(
                "The {kind} ray would add at most {} of its colour to the pixel, too little to see: it is not traced (it contributes black).",
                num(contribution)
            ),
        }
    }

    pub(super) fn spawn(&self, child: u32) -> Explanation {
        let Some(c) = self.ray.children.get(child as usize) else {
            return Explanation {
                title: format!("Child ray {child}"),
                lines: vec![],
                conclusion: "The child ray is missing from the trace.".into(),
            };
        };
        let kind = c.kind.name();
        let lines = vec![
            line("S", "origin", "", v3(c.origin), None),
            line("Q", "direction", "", v3(c.direction), None),
            line(
                "t",
                "(t_min, t_max)",
                "",
                format!("({}, {})", num(c.t_min), c.t_max.map_or("∞".into(), num)),
                None,
            ),
            line(
                "weight",
                "what the parent multiplies its colour by",
                "",
                num(c.weight),
                None,
            ),
        ];
        let conclusion = if c.kind == RayKind::Shadow {
            match &c.hit {
                Some(h) => format!(
                    "A shadow ray is traced: blocked by \"{}\" at t = {}.",
                    h.name,
                    num(h.t)
                ),
                None => "A shadow ray is traced: nothing in the way.".into(),
            }
        } else {
            format!(
                "A {kind} ray is traced at depth {}; it returns {} (× {}).",
                c.depth,
                v3(c.color),
                num(c.weight)
            )
        };
        Explanation {
            title: format!("Child ray {child}: {kind}"),
            lines,
            conclusion,
        }
    }

    /// The ray's colour. Each light's ambient + diffuse + specular and the weighted child colours
    /// are summed here in the tracer's order; the value is the recorded colour.
    pub(super) fn color(&self, color: [f32; 3]) -> Explanation {
        let before = self.before();
        if before.iter().any(|s| matches!(s.step, Step::Miss { .. })) {
            return Explanation {
                title: "The ray's colour".into(),
                lines: vec![line("colour", "background", "", v3(color), None)],
                conclusion: format!(
                    "The ray missed: its colour is the background {}.",
                    v3(color)
                ),
            };
        }
        let mut lines = vec![];
        let mut surface = Vec3::ZERO;
        let mut terms = vec![];
        for s in before {
            if let Step::Light {
                ambient,
                diffuse,
                specular,
                ..
            } = s.step
            {
                let t = Vec3::from(ambient) + Vec3::from(diffuse) + Vec3::from(specular);
                terms.push(vv(t));
                surface += t;
            }
        }
        if terms.is_empty() {
            let col = self.surface_color().map_or("c".to_string(), v3);
            lines.push(line(
                "surface",
                "c · k_a",
                format!("{col} · k_a"),
                "—",
                Some("no lights: the ambient colour (k_a is not stored in a trace)".into()),
            ));
        } else {
            lines.push(line(
                "surface",
                "Σ over lights (ambient + diffuse + specular)",
                terms.join(" + "),
                vv(surface),
                None,
            ));
        }
        let child = |k: RayKind| self.ray.children.iter().find(|c| c.kind == k);
        let schlick = before.iter().find_map(|s| match s.step {
            Step::Schlick { reflectance, .. } => Some(reflectance),
            _ => None,
        });
        let mut parts = vec!["surface".to_string()];
        let mut subst = vec![if terms.is_empty() {
            "surface".to_string()
        } else {
            vv(surface)
        }];
        for (k, nm) in [
            (RayKind::Reflection, "reflected"),
            (RayKind::Refraction, "refracted"),
        ] {
            if let Some(c) = child(k) {
                let weighted = Vec3::from(c.color) * c.weight;
                lines.push(line(
                    nm,
                    if k == RayKind::Reflection {
                        "k_r · colour of the reflection ray"
                    } else {
                        "k_t · colour of the refraction ray"
                    },
                    format!("{}·{}", num(c.weight), v3(c.color)),
                    vv(weighted),
                    None,
                ));
                match schlick {
                    Some(r) => {
                        let f = if k == RayKind::Reflection { r } else { 1.0 - r };
                        parts.push(format!(
                            "{}·{nm}",
                            if k == RayKind::Reflection {
                                "R"
                            } else {
                                "(1 − R)"
                            }
                        ));
                        subst.push(format!("{}·{}", num(f), vv(weighted)));
                    }
                    None => {
                        parts.push(nm.to_string());
                        subst.push(vv(weighted));
                    }
                }
            }
        }
        lines.push(line(
            "colour",
            &parts.join(" + "),
            subst.join(" + "),
            v3(color),
            None,
        ));
        Explanation {
            title: "The ray's colour".into(),
            lines,
            conclusion: format!(
                "The {} ray returns {}{}.",
                self.ray.kind.name(),
                v3(color),
                if self.ray.weight != 1.0 {
                    format!(", which its parent weights by {}", num(self.ray.weight))
                } else {
                    String::new()
                }
            ),
        }
    }
}
