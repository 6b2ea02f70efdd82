//! The math panel's closest-hit bookkeeping: an accepted hit, a miss, the surface at the hit and the shadow ray.

use super::*;

impl Ctx<'_> {
    pub(super) fn accept(&self, name: &str, t: f32, previous: f32) -> Explanation {
        let lines = vec![
            line(
                "t < t_max?",
                "t < t_max",
                format!("{} < {}", num(t), num(previous)),
                yes_no(t < previous),
                None,
            ),
            line(
                "t_max",
                "t",
                format!("{} → {}", num(previous), num(t)),
                num(t),
                Some("the interval shrinks: later tests only accept closer hits".into()),
            ),
        ];
        let conclusion = if self.ray.kind == RayKind::Shadow {
            format!(
                "\"{name}\" lies between the point and the light (t = {}): the light is blocked, and the shadow ray stops at this first blocker.",
                num(t)
            )
        } else {
            format!("\"{name}\" at t = {} is the closest hit so far.", num(t))
        };
        Explanation {
            title: format!("Any-hit: \"{name}\" is accepted"),
            lines,
            conclusion,
        }
    }

    pub(super) fn miss(&self, background: [f32; 3]) -> Explanation {
        let t_max = self.ray.t_max.unwrap_or(f32::INFINITY);
        Explanation {
            title: "Miss: the ray hits nothing".into(),
            lines: vec![line(
                "colour",
                "background",
                "",
                v3(background),
                Some(format!(
                    "nothing in ({}, {})",
                    num(self.ray.t_min),
                    num(t_max)
                )),
            )],
            conclusion: "No object was hit in the ray's interval: the miss shader returns the background colour.".into(),
        }
    }

    /// The surface interaction. The raw point S + t·Q is computed here exactly as the tracer's
    /// `interact` does (`origin + dir·t` in f32); the projected point, normal, error bound and
    /// offset origin are the recorded ones.
    pub(super) fn surface(
        &self,
        point: [f32; 3],
        normal: [f32; 3],
        inside: bool,
        error_bound: [f32; 3],
        over_point: [f32; 3],
    ) -> Explanation {
        let hit = self.ray.hit.as_ref();
        // On an instance the point and normal were found in object space and carried back (the
        // step before shows how): the object's own formulas do not apply to the world numbers.
        let obj = hit
            .filter(|h| h.instance.is_none())
            .and_then(|h| self.object(h.object));
        let mut lines = vec![];
        if let Some(h) = hit {
            let raw = self.origin() + self.dir() * h.t;
            lines.push(line(
                "X",
                "S + t·Q",
                format!("{} + {}·{}", vv(self.origin()), num(h.t), vv(self.dir())),
                vv(raw),
                Some("the hit point along the ray".into()),
            ));
        }
        let (psym, psub, nsym, nsub, esym) = match obj.map(|o| (o.shape, hit)) {
            Some((Shape::Sphere { center, radius }, _)) => (
                "G + r·(X − G)/|X − G|",
                format!(
                    "{} + {}·(X − {})/|X − {}|",
                    vv(center),
                    num(radius),
                    vv(center),
                    vv(center)
                ),
                "(P − G)/r",
                format!("(P − {})/{}", vv(center), num(radius)),
                "γ₅|P − G| + γ₂|P|",
            ),
            Some((Shape::Plane { normal: n, offset }, _)) => (
                "X − n(X·n − c)",
                format!("X − {}·(X·{} − {})", vv(n), vv(n), p(offset)),
                "n",
                vv(n),
                "γ₇(|P| + |n|(|P|·|n| + |c|))",
            ),
            Some((Shape::AxisPlane { axis, offset }, _)) => (
                "X with that coordinate set to c",
                format!("X{} = {}", AXES[axis.min(2)], num(offset)),
                "the axis",
                {
                    let mut n = [0.0f32; 3];
                    n[axis.min(2)] = 1.0;
                    v3(n)
                },
                "γ₃|P|, exact on the plane's axis",
            ),
            Some((Shape::Triangle { p: tp }, h)) => {
                let [u, v] = h.and_then(|h| h.uv).unwrap_or([f32::NAN; 2]);
                (
                    "(1 − u − v)·P0 + u·P1 + v·P2",
                    format!(
                        "{}·{} + {}·{} + {}·{}",
                        p(1.0 - u - v),
                        vv(tp[0]),
                        p(u),
                        vv(tp[1]),
                        p(v),
                        vv(tp[2])
                    ),
                    "normalize(E1 × E2)",
                    format!("normalize({} × {})", vv(tp[1] - tp[0]), vv(tp[2] - tp[0])),
                    "γ₇ Σ|bᵢPᵢ|",
                )
            }
            None => (
                "on the surface",
                String::new(),
                "outward normal",
                String::new(),
                "rounding-error bound",
            ),
        };
        lines.push(line(
            "P",
            psym,
            psub,
            v3(point),
            Some("recomputed from the shape itself, more accurate than S + t·Q".into()),
        ));
        lines.push(line(
            "n",
            nsym,
            nsub,
            v3(normal),
            Some(if inside {
                "flipped: the ray hit the surface from inside".into()
            } else {
                "faces the incoming ray".into()
            }),
        ));
        lines.push(line(
            "δ",
            esym,
            "",
            v3(error_bound),
            Some("how far the stored P may be from the true point, per axis".into()),
        ));
        let s = &self.trace.settings;
        let (osym, onote) = match s.offset {
            OffsetPolicy::None => (
                "P",
                "no offset: spawned rays may re-hit this surface (acne)".to_string(),
            ),
            OffsetPolicy::Fixed => ("P + ε·n", format!("ε = {}", num(s.epsilon))),
            OffsetPolicy::Robust => (
                "P + (|n|·δ)·n, then one float further out",
                "pbrt-v4's OffsetRayOrigin: past the error bound, on the side the ray leaves \
                 (a moved coordinate ends at least 2⁻¹⁰⁰ from 0, never a subnormal)"
                    .into(),
            ),
        };
        let osub = match s.offset {
            OffsetPolicy::None => String::new(),
            OffsetPolicy::Fixed => format!("{} + {}·{}", v3(point), num(s.epsilon), v3(normal)),
            OffsetPolicy::Robust => format!(
                "{} + ({}·{})·{}",
                v3(point),
                vv(Vec3::from(normal).abs()),
                v3(error_bound),
                v3(normal)
            ),
        };
        lines.push(line("over point", osym, osub, v3(over_point), Some(onote)));
        let name = hit.map_or("?".to_string(), |h| h.name.clone());
        Explanation {
            title: format!("Surface interaction on \"{name}\""),
            lines,
            conclusion: format!(
                "The closest hit is at P = {} with normal n = {}{}; rays leaving on the normal's side start at {}.",
                v3(point),
                v3(normal),
                if inside { " (hit from inside)" } else { "" },
                v3(over_point)
            ),
        }
    }

    /// Smooth shading: the vertex normals blended at the hit (the arithmetic of
    /// `trace::interaction::interpolate_normal`, redone here in the same f32 order).
    pub(super) fn shading_normal(
        &self,
        vertex_normals: &[[f32; 3]; 3],
        u: f32,
        v: f32,
        normal: [f32; 3],
        angle_deg: f32,
        lifted: Option<[f32; 3]>,
    ) -> Explanation {
        let n = vertex_normals.map(Vec3::from);
        let b0 = 1.0 - u - v;
        let blend = n[0] * b0 + n[1] * u + n[2] * v;
        let len = blend.length();
        let (geometric, point) = self
            .before()
            .iter()
            .rev()
            .find_map(|s| match s.step {
                Step::Surface { normal, point, .. } => {
                    Some((Vec3::from(normal), Vec3::from(point)))
                }
                _ => None,
            })
            .unzip();
        let turned = len.is_normal() && (blend / len).dot(Vec3::from(normal)) < 0.0;
        let mut lines = vec![
            line(
                "b₀",
                "1 − u − v",
                format!("1 − {} − {}", p(u), p(v)),
                p(b0),
                None,
            ),
            line(
                "s",
                "b₀·n₀ + u·n₁ + v·n₂",
                format!(
                    "{}·{} + {}·{} + {}·{}",
                    p(b0),
                    vv(n[0]),
                    p(u),
                    vv(n[1]),
                    p(v),
                    vv(n[2])
                ),
                vv(blend),
                Some("the vertex normals weighted as the vertices are in P".into()),
            ),
            line("|s|", "√(s·s)", "", num(len), None),
        ];
        lines.push(line(
            "n_s",
            if turned { "−s / |s|" } else { "s / |s|" },
            "",
            v3(normal),
            Some(if !len.is_normal() {
                "the vertex normals cancel here: the geometric normal shades instead".into()
            } else if turned {
                "turned round to the side the ray came from, as the geometric normal is".into()
            } else {
                "unit length again: a blend of unit vectors is shorter than 1".into()
            }),
        ));
        if let Some(g) = geometric {
            lines.push(line(
                "∠(n_s, n)",
                "atan2(|n_s × n|, n_s · n)",
                "",
                format!("{}°", num(angle_deg)),
                Some(format!("the geometric normal n = {}", vv(g))),
            ));
        }
        let mut conclusion = format!(
            "Lighting, reflection and refraction use n_s = {}, {}° from the flat triangle's \
             normal; which side the ray is on, and where spawned rays start, still use the \
             geometric normal.",
            v3(normal),
            num(angle_deg)
        );
        // Hanika's lift: the vertices' tangent planes, from the hit triangle's own vertices.
        let vertices = self
            .ray
            .hit
            .as_ref()
            .and_then(|h| self.object(h.object))
            .and_then(|o| match o.shape {
                Shape::Triangle { p } => Some(p),
                _ => None,
            });
        if let (Some(lifted), Some(point), Some(pv)) = (lifted, point, vertices) {
            let side = if turned { -1.0 } else { 1.0 };
            let d = [0, 1, 2].map(|i| (point - pv[i]).dot(n[i] * side));
            lines.push(line(
                "d₀, d₁, d₂",
                "(P − Pᵢ)·nᵢ",
                "",
                format!("{}, {}, {}", num(d[0]), num(d[1]), num(d[2])),
                Some("how far P lies above (+) or below (−) each vertex's tangent plane".into()),
            ));
            let moved = Vec3::from(lifted) - point;
            lines.push(line(
                "P′",
                "P − (min(d₀, 0)·n₀·b₀ + min(d₁, 0)·n₁·u + min(d₂, 0)·n₂·v)",
                "",
                v3(lifted),
                Some(if moved == Vec3::ZERO {
                    "not lifted: P lies on or above every vertex's tangent plane".into()
                } else {
                    format!(
                        "lifted by {} towards the smooth surface",
                        num(moved.length())
                    )
                }),
            ));
            conclusion = format!(
                "{conclusion} Hanika's terminator fix: rays leaving on this side start from \
                 P′ = {} instead of P.",
                v3(lifted)
            );
        }
        Explanation {
            title: "Smooth shading: the interpolated normal".into(),
            lines,
            conclusion,
        }
    }

    /// The child ray spawned by the next `Spawn` step after this one, if any.
    pub(super) fn next_child(&self) -> Option<&RayRecord> {
        let i = self.idx?;
        match self.ray.steps.get(i + 1).map(|s| &s.step) {
            Some(Step::Spawn { child }) => self.ray.children.get(*child as usize),
            _ => None,
        }
    }

    /// A shadow ray. L − P is computed here exactly as the tracer does (`position − point`).
    pub(super) fn shadow_ray(&self, light: u32, name: &str, distance: f32) -> Explanation {
        let mut lines = vec![];
        let lpos = self.trace.lights.get(light as usize).map(|l| l.position);
        if let (Some(l), Some((pt, _))) = (lpos, self.surface_before()) {
            let to = l - pt;
            lines.push(line(
                "L − P",
                "L − P",
                format!("{} − {}", vv(l), vv(pt)),
                vv(to),
                None,
            ));
            lines.push(line(
                "distance",
                "|L − P|",
                format!("|{}|", vv(to)),
                num(distance),
                None,
            ));
        } else {
            lines.push(line("distance", "|L − P|", "", num(distance), None));
        }
        if let Some(c) = self.next_child() {
            lines.push(line(
                "S",
                "P offset towards the light",
                "",
                v3(c.origin),
                None,
            ));
            lines.push(line(
                "Q",
                "L − S",
                lpos.map_or(String::new(), |l| format!("{} − {}", vv(l), v3(c.origin))),
                v3(c.direction),
                Some("not normalized: t = 1 is the light".into()),
            ));
            lines.push(line(
                "t_max",
                "1 − 10⁻⁴",
                "",
                c.t_max.map_or("∞".into(), num),
                Some("stops just short of the light".into()),
            ));
        }
        Explanation {
            title: format!("Shadow ray towards light \"{name}\""),
            lines,
            conclusion: "The light faces the surface, so a shadow ray checks the segment to it: any object hit with t in (0, t_max) blocks the light.".into(),
        }
    }
}
