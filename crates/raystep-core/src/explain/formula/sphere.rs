//! The math panel's ray–sphere test: the quadratic (textbook or stable), its roots and the choice.

use super::*;
use crate::record::words;

impl Ctx<'_> {
    /// The sphere test: every number shown is the recorded one (f, a, b, b′, c, l, Δ′, Δ, √Δ,
    /// q, the roots as computed and in order); nothing is recomputed here. The scene gives only
    /// the inputs G and r. A value the record lacks (a trace saved before it was recorded)
    /// shows as —.
    pub(super) fn sphere(&self, object: u32, name: &str, test: &SphereTest<f32>) -> Explanation {
        let geo = self.object(object).and_then(|o| match o.shape {
            Shape::Sphere { center, radius } => Some((center, radius)),
            _ => None,
        });
        let d = self.dir();
        let mut lines = vec![];
        let fs = test.f.map(Vec3::from);
        let rs = match geo {
            Some((center, radius)) => {
                lines.push(line(
                    "f",
                    "S − G",
                    format!("{} − {}", vv(self.origin()), vv(center)),
                    fs.map_or("—".into(), vv),
                    Some(format!(
                        "from the sphere's centre G to the ray's origin (r = {})",
                        num(radius)
                    )),
                ));
                Some(radius)
            }
            None => None,
        };
        let fstr = fs.map_or("f".to_string(), vv);
        let r2 = rs.map_or("r²".to_string(), |r| format!("{}²", p(r)));
        lines.push(line(
            "a",
            "Q·Q",
            format!("{}·{}", vv(d), vv(d)),
            num(test.a),
            None,
        ));
        let textbook = test.method == SphereMethod::Textbook;
        if textbook {
            lines.push(line(
                "b",
                "2 f·Q",
                format!("2·{}·{}", fstr, vv(d)),
                num(test.b),
                None,
            ));
            lines.push(line(
                "c",
                "f·f − r²",
                format!("{fstr}·{fstr} − {r2}"),
                num(test.c),
                Some(if test.inside {
                    "< 0: the origin is inside the sphere".into()
                } else {
                    "≥ 0: the origin is outside (or on) the sphere".into()
                }),
            ));
            lines.push(line(
                "Δ",
                "b² − 4ac",
                format!("{}² − 4·{}·{}", p(test.b), num(test.a), p(test.c)),
                num(test.discriminant),
                Some(case_note(test)),
            ));
        } else {
            let b_half = test.b_half;
            lines.push(line(
                "b′",
                "−f·Q",
                format!("−{}·{}", fstr, vv(d)),
                b_half.map_or("—".into(), num),
                Some(format!("the textbook's b = 2f·Q = {}", num(test.b))),
            ));
            lines.push(line(
                "c",
                "f·f − r²",
                format!("{fstr}·{fstr} − {r2}"),
                num(test.c),
                Some(if test.inside {
                    "< 0: the origin is inside the sphere".into()
                } else {
                    "≥ 0: the origin is outside (or on) the sphere".into()
                }),
            ));
            let ls = test.l.map(Vec3::from);
            let lstr = ls.map_or("l".to_string(), vv);
            if let Some(l) = ls {
                lines.push(line(
                    "l",
                    "f + (b′/a)·Q",
                    format!(
                        "{} + ({}/{})·{}",
                        fstr,
                        b_half.map_or("b′".into(), p),
                        num(test.a),
                        vv(d)
                    ),
                    vv(l),
                    Some("from the centre to the ray's line, at right angles".into()),
                ));
            }
            if let Some(dp) = test.delta_prime {
                lines.push(line(
                    "Δ′",
                    "r² − l·l",
                    format!("{r2} − {lstr}·{lstr}"),
                    num(dp),
                    Some("a vector difference: keeps r² even when |f| ≫ r (c has lost it)".into()),
                ));
            }
            lines.push(line(
                "Δ",
                "4a·Δ′",
                format!(
                    "4·{}·{}",
                    num(test.a),
                    p(test.delta_prime.unwrap_or(f32::NAN))
                ),
                num(test.discriminant),
                Some(format!(
                    "the textbook's b² − 4ac, computed robustly; {}",
                    case_note(test)
                )),
            ));
        }
        let (rmin, rmax) = (self.ray.t_min, self.t_max());
        if let Some([lo, hi]) = test.roots {
            if textbook {
                let sq = test.sqrt_discriminant.map_or("—".into(), num);
                lines.push(line(
                    "√Δ",
                    "√Δ",
                    format!("√{}", num(test.discriminant)),
                    sq.clone(),
                    None,
                ));
                // The roots as the kernel computed them, before putting them in order (a > 0,
                // so the − root is the smaller).
                let [t0, t1] = test.computed_roots.unwrap_or([lo, hi]);
                lines.push(line(
                    "t₀",
                    "(−b − √Δ)/2a",
                    format!("({} − {})/(2·{})", num(-test.b), sq, num(test.a)),
                    num(t0),
                    Some("the near root".into()),
                ));
                lines.push(line(
                    "t₁",
                    "(−b + √Δ)/2a",
                    format!("({} + {})/(2·{})", num(-test.b), sq, num(test.a)),
                    num(t1),
                    Some("the far root".into()),
                ));
            } else if let Some(q) = test.q {
                // b′'s sign: the recorded b′, or (a trace without it) that of −b.
                let sign = if test.b_half.unwrap_or(-test.b) >= 0.0 {
                    "+"
                } else {
                    "−"
                };
                lines.push(line(
                    "q",
                    "b′ + sign(b′)·√(a·Δ′)",
                    format!(
                        "{} {sign} √({}·{})",
                        test.b_half.map_or("—".into(), num),
                        num(test.a),
                        p(test.delta_prime.unwrap_or(f32::NAN))
                    ),
                    num(q),
                    Some("adds numbers of one sign: no cancellation".into()),
                ));
                if q == 0.0 {
                    lines.push(line(
                        "t₀ = t₁",
                        "0",
                        "",
                        "0",
                        Some("q = 0 (tangent at the origin): c/q would be 0/0".into()),
                    ));
                } else {
                    // The kernel's divisions c/q and q/a, as recorded.
                    let [t0, t1] = test.computed_roots.unwrap_or([f32::NAN; 2]);
                    let shown = |x: f32| {
                        if test.computed_roots.is_some() {
                            num(x)
                        } else {
                            "—".into()
                        }
                    };
                    lines.push(line(
                        "c/q",
                        "c/q",
                        format!("{}/{}", p(test.c), p(q)),
                        shown(t0),
                        None,
                    ));
                    lines.push(line(
                        "q/a",
                        "q/a",
                        format!("{}/{}", p(q), num(test.a)),
                        shown(t1),
                        None,
                    ));
                }
                lines.push(line(
                    "t₀, t₁",
                    "the two roots, in order",
                    "",
                    format!("{}, {}", num(lo), num(hi)),
                    None,
                ));
            }
            let up = self.upper();
            let (choice, sub, val) = match test.choice {
                RootChoice::NearRoot => (
                    format!("t_min < t₀ {up} t_max"),
                    format!("{} < {} {up} {}", num(rmin), num(lo), num(rmax)),
                    num(lo),
                ),
                RootChoice::FarRoot => (
                    format!("t₀ ≤ t_min < t₁ {up} t_max"),
                    format!(
                        "{} ≤ {} < {} {up} {}",
                        num(lo),
                        num(rmin),
                        num(hi),
                        num(rmax)
                    ),
                    num(hi),
                ),
                RootChoice::Behind => (
                    "t₁ ≤ t_min".into(),
                    format!("{} ≤ {}", num(hi), num(rmin)),
                    "none".into(),
                ),
                RootChoice::BeyondTMax => {
                    let first = if lo > rmin { lo } else { hi };
                    (
                        if self.ties_kept() {
                            "first root past t_min > t_max".into()
                        } else {
                            "first root past t_min ≥ t_max".into()
                        },
                        format!(
                            "{} {} {}",
                            num(first),
                            if self.ties_kept() { ">" } else { "≥" },
                            num(rmax)
                        ),
                        "none".into(),
                    )
                }
                RootChoice::NoRoots => ("no roots".into(), String::new(), "none".into()),
            };
            lines.push(line("t", &choice, sub, val, None));
        }
        let conclusion = match (test.case, test.choice) {
            (_, RootChoice::NoRoots) if test.discriminant.is_nan() => {
                "Δ is NaN (overflow): treated as a miss.".to_string()
            }
            (SphereCase::Miss, _) | (_, RootChoice::NoRoots) => {
                words::sentence(words::sphere_case(SphereCase::Miss))
            }
            (_, RootChoice::NearRoot | RootChoice::FarRoot) => format!(
                "{} Hit at t = {}.",
                words::sentence(words::root_choice_on(test.choice, self.ray.kind)),
                test.t.map_or("?".into(), num)
            ),
            (_, choice) => words::sentence(words::root_choice_on(choice, self.ray.kind)),
        };
        Explanation {
            title: format!(
                "Ray–sphere \"{name}\" ({})",
                if textbook {
                    "textbook quadratic"
                } else {
                    "stable quadratic, Ray Tracing Gems ch. 7"
                }
            ),
            lines,
            conclusion,
        }
    }
}
