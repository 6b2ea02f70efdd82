//! The math panel: for one step of a recorded trace, the formulas the tracer evaluated, with the
//! numbers substituted, in the precision the renderer used.
//!
//! Every [`Formula`] reads `name = symbolic = substituted = value`. The policy for numbers:
//!
//! - Where the kernel **recorded** a value (a sphere's a, b, c and Δ, a triangle's determinants, a
//!   slab's entry and exit, l·n, the refracted direction, …), the line prints the recorded f32,
//!   formatted by [`describe::num`](super::describe::num) and
//!   [`describe::v3`](super::describe::v3) (shortest round-trip form), and `substituted` is
//!   built from the recorded inputs of that very computation.
//! - Where an input was **not recorded** (f = S − G, E1 = P1 − P0, the camera basis, the light
//!   vector l, the watertight test's sheared vertices, …), it is computed here in f32 with the same
//!   operations in the same order as the kernel (the same glam calls on the same recorded inputs),
//!   so it is the value the renderer had. The doc comment of each such helper says so.
//! - What neither the trace nor the kernel's inputs determine (the Phong coefficients k_a, k_d,
//!   k_s and the shininess, which a trace does not store) stays a symbol.
//!
//! Nothing here needs the scene: a loaded trace file is enough.

use super::camera::CameraRays;
use super::describe::{num, v3};
use super::record::{NodeAction, RayKind, RayRecord, Step, Trace, TraceObject};
use crate::math::gamma;
use crate::scene::{OffsetPolicy, Shape};
use crate::shapes::{
    BoxMethod, BoxTest, PlaneForm, PlaneTest, RootChoice, SphereCase, SphereMethod, SphereTest,
    TriangleMethod, TriangleTest,
};
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// One line of the math panel: `name = symbolic = substituted = value`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Formula {
    /// The quantity computed, e.g. `Δ` or `a`.
    pub name: String,
    /// The formula in symbols, e.g. `b² − 4ac`.
    pub symbolic: String,
    /// The formula with the numbers the renderer used, e.g. `(-10)² − 4·1·24`; empty when it
    /// would add nothing to `symbolic`.
    pub substituted: String,
    /// The result, e.g. `4` (the recorded value where the kernel recorded one).
    pub value: String,
    /// What the value means, e.g. `> 0: two roots`.
    pub note: Option<String>,
}

/// The math panel's content for one step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Explanation {
    /// What is being evaluated, e.g. `Ray–sphere "middle" (textbook quadratic)`.
    pub title: String,
    /// The formulas in the order the tracer evaluated them (a test that stopped early lists only
    /// the lines up to its stop).
    pub lines: Vec<Formula>,
    /// The decision, in words.
    pub conclusion: String,
}

/// Explains `step`, one of `ray`'s steps in `trace`, as formulas with the recorded numbers.
///
/// `step` should be an element of `ray.steps` (as [`Trace::timeline`] hands them out): its
/// position there tells which t_max the kernel tested against (t_max shrinks at every `Accept`)
/// and which `Surface` a shading step belongs to. A step not found in `ray` is still explained,
/// against the ray's initial interval.
pub fn explain(trace: &Trace, ray: &RayRecord, step: &Step) -> Explanation {
    let idx = ray
        .steps
        .iter()
        .position(|s| std::ptr::eq(&s.step, step))
        .or_else(|| ray.steps.iter().position(|s| &s.step == step));
    let cx = Ctx { trace, ray, idx };
    match step {
        Step::Camera {
            pixel,
            sample,
            offset,
            screen,
            direction,
        } => cx.camera(*pixel, *sample, *offset, *screen, *direction),
        Step::Node(n) => cx.node(n),
        Step::Sphere { object, name, test } => cx.sphere(*object, name, test),
        Step::Plane { name, test, .. } => cx.plane(name, test),
        Step::Triangle {
            name,
            vertices,
            test,
            ..
        } => match test.method {
            TriangleMethod::MollerTrumbore => cx.moller_trumbore(name, vertices, test),
            TriangleMethod::Watertight => cx.watertight(name, vertices, test),
        },
        Step::Accept {
            name, t, previous, ..
        } => cx.accept(name, *t, *previous),
        Step::Miss { background } => cx.miss(*background),
        Step::Surface {
            point,
            normal,
            inside,
            error_bound,
            over_point,
        } => cx.surface(*point, *normal, *inside, *error_bound, *over_point),
        Step::ShadowRay {
            light,
            name,
            distance,
        } => cx.shadow_ray(*light, name, *distance),
        Step::Light {
            light,
            name,
            blocked,
            blocker,
            l_dot_n,
            r_dot_e,
            ambient,
            diffuse,
            specular,
        } => cx.light(
            *light,
            name,
            *blocked,
            blocker.as_deref(),
            *l_dot_n,
            *r_dot_e,
            [*ambient, *diffuse, *specular],
        ),
        Step::Reflect {
            reflective,
            direction,
        } => cx.reflect(*reflective, *direction),
        Step::Refract {
            n1,
            n2,
            cos_i,
            sin2_t,
            critical_angle_deg,
            total_internal_reflection,
            direction,
        } => cx.refract(
            *n1,
            *n2,
            *cos_i,
            *sin2_t,
            *critical_angle_deg,
            *total_internal_reflection,
            *direction,
        ),
        Step::Schlick { reflectance } => cx.schlick(*reflectance),
        Step::DepthLimit { max_depth } => cx.depth_limit(*max_depth),
        Step::WeightCutoff {
            kind,
            contribution,
            cutoff,
        } => cx.weight_cutoff(*kind, *contribution, *cutoff),
        Step::Truncated { max_steps } => Explanation {
            title: "The trace stops here".into(),
            lines: vec![],
            conclusion: format!(
                "The trace reached its limit of {max_steps} recorded steps. The tracer went on and every colour is exact, but the rest of its work was not kept."
            ),
        },
        Step::Spawn { child } => cx.spawn(*child),
        Step::Color { color } => cx.color(*color),
    }
}

/// A number, parenthesized when negative so that it can follow an operator: `(-10)`.
fn p(x: f32) -> String {
    let s = num(x);
    if s.starts_with('-') {
        format!("({s})")
    } else {
        s
    }
}

/// A vector as [`v3`] prints it.
fn vv(v: Vec3) -> String {
    v3(v.to_array())
}

/// Shorthand for a line.
fn line(
    name: &str,
    symbolic: &str,
    substituted: impl Into<String>,
    value: impl Into<String>,
    note: Option<String>,
) -> Formula {
    Formula {
        name: name.into(),
        symbolic: symbolic.into(),
        substituted: substituted.into(),
        value: value.into(),
        note,
    }
}

fn yes_no(b: bool) -> &'static str {
    if b { "yes" } else { "no" }
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// The step being explained, with the ray it belongs to and its position there.
struct Ctx<'a> {
    trace: &'a Trace,
    ray: &'a RayRecord,
    idx: Option<usize>,
}

impl Ctx<'_> {
    fn origin(&self) -> Vec3 {
        Vec3::from(self.ray.origin)
    }
    fn dir(&self) -> Vec3 {
        Vec3::from(self.ray.direction)
    }

    /// The steps before this one (all of them when the step is not in the ray).
    fn before(&self) -> &[super::record::StepRecord] {
        &self.ray.steps[..self.idx.unwrap_or(self.ray.steps.len())]
    }

    /// The ray's t_max when step `idx` ran: the initial t_max, shrunk by every `Accept` before it
    /// (the accelerators set t_max to the accepted t, and only `Accept` changes it).
    fn t_max_at(&self, idx: Option<usize>) -> f32 {
        let end = idx.unwrap_or(0);
        let mut t = self.ray.t_max.unwrap_or(f32::INFINITY);
        for s in &self.ray.steps[..end] {
            if let Step::Accept { t: a, .. } = s.step {
                t = a;
            }
        }
        t
    }

    /// The t_max this step's kernel tested against.
    fn t_max(&self) -> f32 {
        self.t_max_at(self.idx)
    }

    /// `t_min < t < t_max`, with the numbers.
    fn range_line(&self, t: f32) -> Formula {
        let (lo, hi) = (self.ray.t_min, self.t_max());
        let ok = t > lo && t < hi;
        line(
            "t in range?",
            "t_min < t < t_max",
            format!("{} < {} < {}", num(lo), num(t), num(hi)),
            yes_no(ok),
            Some(if ok {
                "inside the ray's interval".into()
            } else if t <= lo {
                "at or behind the origin (t ≤ t_min)".into()
            } else if self.t_max() < self.ray.t_max.unwrap_or(f32::INFINITY) {
                "at or beyond the closest hit so far (t ≥ t_max)".into()
            } else {
                "at or beyond the ray's end (t ≥ t_max)".into()
            }),
        )
    }

    fn object(&self, id: u32) -> Option<&TraceObject> {
        self.trace.objects.iter().find(|o| o.id == id)
    }

    /// The latest `Surface` step before this one: (point, normal).
    fn surface_before(&self) -> Option<(Vec3, Vec3)> {
        self.before().iter().rev().find_map(|s| match s.step {
            Step::Surface { point, normal, .. } => Some((Vec3::from(point), Vec3::from(normal))),
            _ => None,
        })
    }

    /// The eye vector e = −Q/|Q|, computed in f32 exactly as the tracer's `interact` does.
    fn eye(&self) -> Vec3 {
        let d = self.dir();
        -d / d.length()
    }

    fn camera(
        &self,
        pixel: [u32; 2],
        sample: u32,
        offset: [f32; 2],
        screen: [f32; 2],
        direction: [f32; 3],
    ) -> Explanation {
        let cam = &self.trace.camera;
        // The renderer's own basis code on the trace's camera: the same f32 values it used.
        let basis = CameraRays::new(cam);
        let (w, h) = (cam.width, cam.height);
        let lines = vec![
            line(
                "offset",
                if self.trace.settings.spp <= 1 {
                    "(0.5, 0.5): the pixel centre (1 sample per pixel)"
                } else {
                    "jittered cell of a stratified grid (hash of pixel, sample, seed)"
                },
                "",
                format!("({}, {})", num(offset[0]), num(offset[1])),
                None,
            ),
            line(
                "sx",
                "2(x + oₓ)/W − 1",
                format!("2·({} + {})/{} − 1", pixel[0], num(offset[0]), w),
                num(screen[0]),
                None,
            ),
            line(
                "sy",
                "1 − 2(y + o_y)/H",
                format!("1 − 2·({} + {})/{}", pixel[1], num(offset[1]), h),
                num(screen[1]),
                Some("y counts from the top of the image".into()),
            ),
            line(
                "w",
                "normalize(from − at)",
                format!("normalize({} − {})", vv(cam.from), vv(cam.at)),
                vv(basis.w),
                Some("points backwards, out of the screen".into()),
            ),
            line(
                "u",
                "normalize(up × w)",
                format!("normalize({} × {})", vv(cam.up), vv(basis.w)),
                vv(basis.u),
                Some("right in the image".into()),
            ),
            line(
                "v",
                "w × u",
                format!("{} × {}", vv(basis.w), vv(basis.u)),
                vv(basis.v),
                Some("up in the image".into()),
            ),
            line(
                "h",
                "tan(fov/2)",
                format!("tan({}°/2)", num(cam.fov)),
                num(basis.half_height),
                None,
            ),
            line(
                "h·W/H",
                "half width",
                format!("{}·{}/{}", num(basis.half_height), w, h),
                num(basis.half_width),
                None,
            ),
            line(
                "Q",
                "normalize(sx·(h·W/H)·u + sy·h·v − w)",
                format!(
                    "normalize({}·{}·{} + {}·{}·{} − {})",
                    p(screen[0]),
                    num(basis.half_width),
                    vv(basis.u),
                    p(screen[1]),
                    num(basis.half_height),
                    vv(basis.v),
                    vv(basis.w)
                ),
                v3(direction),
                None,
            ),
        ];
        Explanation {
            title: format!(
                "Ray generation: pixel ({}, {}), sample {sample}",
                pixel[0], pixel[1]
            ),
            lines,
            conclusion: format!(
                "The primary ray starts at the eye S = {} and runs along Q = {}.",
                vv(cam.from),
                v3(direction)
            ),
        }
    }

    /// The t_max a node's box was tested against. Siblings are tested as a pair before either is
    /// recorded, so the second (farther) sibling shows the t_max of the first one's record, even
    /// if the first one's leaf has since shrunk it.
    fn node_t_max(&self, node: u32) -> f32 {
        let Some(i) = self.idx else {
            return self.t_max();
        };
        let before = &self.ray.steps[..i];
        let parent = before.iter().rposition(
            |s| matches!(&s.step, Step::Node(n) if n.children.is_some_and(|c| c.contains(&node))),
        );
        let Some(pi) = parent else {
            return self.t_max();
        };
        let Step::Node(pn) = &before[pi].step else {
            return self.t_max();
        };
        let sibling = pn.children.map(|c| if c[0] == node { c[1] } else { c[0] });
        let sib = before[pi + 1..]
            .iter()
            .position(|s| matches!(&s.step, Step::Node(n) if Some(n.node) == sibling));
        match sib {
            Some(k) => self.t_max_at(Some(pi + 1 + k)),
            None => self.t_max(),
        }
    }

    fn node(&self, n: &super::record::NodeVisit) -> Explanation {
        let test: &BoxTest<f32> = &n.test;
        let o = self.ray.origin;
        let t_max_tested = self.node_t_max(n.node);
        let t_max_now = self.t_max();
        let mut lines = vec![];
        let robust = test.method == BoxMethod::Robust;
        // The kernel's factor 1 + 2γ₃, computed as `slab_axis` does.
        let enlarge = 1.0 + 2.0 * gamma::<f32>(3);
        for (i, ax) in test.axes.iter().enumerate() {
            let a = AXES[i];
            if robust {
                // Computed exactly as `slab_robust` does: (slab − S)·(1/Q).
                let t0 = (test.min[i] - o[i]) * ax.inv_dir;
                let t1 = (test.max[i] - o[i]) * ax.inv_dir;
                lines.push(line(
                    &format!("1/Q{a}"),
                    &format!("1/Q{a}"),
                    format!("1/{}", p(self.ray.direction[i])),
                    num(ax.inv_dir),
                    None,
                ));
                lines.push(line(
                    &format!("t0{a}, t1{a}"),
                    &format!("(min{a} − S{a})·(1/Q{a}), (max{a} − S{a})·(1/Q{a})"),
                    format!(
                        "({} − {})·{}, ({} − {})·{}",
                        num(test.min[i]),
                        p(o[i]),
                        p(ax.inv_dir),
                        num(test.max[i]),
                        p(o[i]),
                        p(ax.inv_dir)
                    ),
                    format!("{}, {}", num(t0), num(t1)),
                    None,
                ));
                lines.push(line(
                    &format!("{a} slab"),
                    "entry, exit × (1 + 2γ₃)",
                    if ax.inv_dir.is_sign_negative() {
                        format!("{}, {}·{}", num(t1), p(t0), num(enlarge))
                    } else {
                        format!("{}, {}·{}", num(t0), p(t1), num(enlarge))
                    },
                    format!("[{}, {}]", num(ax.t_entry), num(ax.t_exit)),
                    Some(
                        if ax.t_entry.is_nan() || ax.t_exit.is_nan() {
                            "NaN (0·∞: the ray lies in a face plane): this slab sets no limit"
                        } else if ax.inv_dir.is_sign_negative() {
                            "Q is negative on this axis: the max plane is entered first"
                        } else {
                            "the exit is enlarged by 1 + 2γ₃ so rounding cannot lose a hit"
                        }
                        .into(),
                    ),
                ));
            } else {
                lines.push(line(
                    &format!("{a} slab"),
                    &format!("sort((min{a} − S{a})/Q{a}, (max{a} − S{a})/Q{a})"),
                    format!(
                        "sort(({} − {})/{}, ({} − {})/{})",
                        num(test.min[i]),
                        p(o[i]),
                        p(self.ray.direction[i]),
                        num(test.max[i]),
                        p(o[i]),
                        p(self.ray.direction[i])
                    ),
                    format!("[{}, {}]", num(ax.t_entry), num(ax.t_exit)),
                    None,
                ));
            }
        }
        lines.push(line(
            "t_near",
            "max(t_min, entry_x, entry_y, entry_z)",
            format!(
                "max({}, {}, {}, {})",
                num(self.ray.t_min),
                num(test.axes[0].t_entry),
                num(test.axes[1].t_entry),
                num(test.axes[2].t_entry)
            ),
            num(test.t_near),
            None,
        ));
        lines.push(line(
            "t_far",
            "min(t_max, exit_x, exit_y, exit_z)",
            format!(
                "min({}, {}, {}, {})",
                num(t_max_tested),
                num(test.axes[0].t_exit),
                num(test.axes[1].t_exit),
                num(test.axes[2].t_exit)
            ),
            num(test.t_far),
            None,
        ));
        let op = if robust { "≤" } else { "<" };
        lines.push(line(
            "overlap?",
            &format!("t_near {op} t_far"),
            format!("{} {op} {}", num(test.t_near), num(test.t_far)),
            yes_no(test.hit),
            Some(if test.hit {
                "the ray's interval meets the box".into()
            } else {
                "the ray misses the box (or reaches it only beyond t_max)".into()
            }),
        ));
        // The far sibling is re-checked against t_max, which the near one's leaf may have shrunk.
        let rechecked = test.hit && n.action == NodeAction::Culled;
        if rechecked || (t_max_now < t_max_tested && test.hit) {
            lines.push(line(
                "still in reach?",
                "t_near ≤ t_max (now)",
                format!("{} ≤ {}", num(test.t_near), num(t_max_now)),
                yes_no(!rechecked),
                Some("the nearer sibling's hit shrank t_max".into()),
            ));
        }
        let kind = if n.leaf { "leaf" } else { "inner" };
        let conclusion = match n.action {
            NodeAction::Culled if rechecked => {
                "Culled: a closer hit, found in the nearer sibling, lies before this box.".into()
            }
            NodeAction::Culled => {
                "Culled: the ray misses the box, so nothing inside is tested.".to_string()
            }
            NodeAction::Descend => match n.children {
                Some([a, b]) => format!("Hit: descend into children {a} and {b}."),
                None => "Hit: descend into its children.".into(),
            },
            NodeAction::Pushed => {
                "Hit, but farther than its sibling: pushed on the stack for later.".into()
            }
            NodeAction::TestPrimitives => "Hit: test the leaf's primitives (next steps).".into(),
        };
        Explanation {
            title: format!(
                "BVH node {} (depth {}, {kind}): {} slab test",
                n.node,
                n.depth,
                if robust { "robust" } else { "plain" }
            ),
            lines,
            conclusion,
        }
    }

    /// The sphere test. f = S − G is computed here exactly as the kernel does (`origin − center`
    /// in f32); for `stable`, f·d and l = f + d·(b′/a) too, from the recorded a.
    fn sphere(&self, object: u32, name: &str, test: &SphereTest<f32>) -> Explanation {
        let geo = self.object(object).and_then(|o| match o.shape {
            Shape::Sphere { center, radius } => Some((center, radius)),
            _ => None,
        });
        let d = self.dir();
        let mut lines = vec![];
        let (fs, rs) = match geo {
            Some((center, radius)) => {
                let f = self.origin() - center;
                lines.push(line(
                    "f",
                    "S − G",
                    format!("{} − {}", vv(self.origin()), vv(center)),
                    vv(f),
                    Some(format!(
                        "from the sphere's centre G to the ray's origin (r = {})",
                        num(radius)
                    )),
                ));
                (Some(f), Some(radius))
            }
            None => (None, None),
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
            let fd = fs.map(|f| f.dot(d));
            let b_half = fd.map(|x| -x);
            lines.push(line(
                "b′",
                "−f·Q",
                format!("−{}·{}", fstr, vv(d)),
                b_half.map_or(String::new(), num),
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
            if let (Some(f), Some(bh)) = (fs, b_half) {
                // As the kernel: l = f + d·(b′/a).
                let l = f + d * (bh / test.a);
                lines.push(line(
                    "l",
                    "f + (b′/a)·Q",
                    format!("{} + ({}/{})·{}", fstr, p(bh), num(test.a), vv(d)),
                    vv(l),
                    Some("from the centre to the ray's line, at right angles".into()),
                ));
                if let Some(dp) = test.delta_prime {
                    lines.push(line(
                        "Δ′",
                        "r² − l·l",
                        format!("{r2} − {}·{}", vv(l), vv(l)),
                        num(dp),
                        Some(
                            "a vector difference: keeps r² even when |f| ≫ r (c has lost it)"
                                .into(),
                        ),
                    ));
                }
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
                let sq = test.discriminant.sqrt();
                lines.push(line(
                    "√Δ",
                    "√Δ",
                    format!("√{}", num(test.discriminant)),
                    num(sq),
                    None,
                ));
                lines.push(line(
                    "t₀",
                    "(−b − √Δ)/2a",
                    format!("({} − {})/(2·{})", num(-test.b), num(sq), num(test.a)),
                    num(lo),
                    Some("the near root".into()),
                ));
                lines.push(line(
                    "t₁",
                    "(−b + √Δ)/2a",
                    format!("({} + {})/(2·{})", num(-test.b), num(sq), num(test.a)),
                    num(hi),
                    Some("the far root".into()),
                ));
            } else if let Some(q) = test.q {
                let bh = b_half_of(fs, d, test);
                let sign = if bh >= 0.0 { "+" } else { "−" };
                lines.push(line(
                    "q",
                    "b′ + sign(b′)·√(a·Δ′)",
                    format!(
                        "{} {sign} √({}·{})",
                        num(bh),
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
                    // The kernel's own divisions on the recorded c, q and a.
                    let (t0, t1) = (test.c / q, q / test.a);
                    lines.push(line(
                        "c/q",
                        "c/q",
                        format!("{}/{}", p(test.c), p(q)),
                        num(t0),
                        None,
                    ));
                    lines.push(line(
                        "q/a",
                        "q/a",
                        format!("{}/{}", p(q), num(test.a)),
                        num(t1),
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
            let (choice, sub, val) = match test.choice {
                RootChoice::NearRoot => (
                    "t_min < t₀ < t_max",
                    format!("{} < {} < {}", num(rmin), num(lo), num(rmax)),
                    num(lo),
                ),
                RootChoice::FarRoot => (
                    "t₀ ≤ t_min < t₁ < t_max",
                    format!("{} ≤ {} < {} < {}", num(lo), num(rmin), num(hi), num(rmax)),
                    num(hi),
                ),
                RootChoice::Behind => (
                    "t₁ ≤ t_min",
                    format!("{} ≤ {}", num(hi), num(rmin)),
                    "none".into(),
                ),
                RootChoice::BeyondTMax => {
                    let first = if lo > rmin { lo } else { hi };
                    (
                        "first root past t_min ≥ t_max",
                        format!("{} ≥ {}", num(first), num(rmax)),
                        "none".into(),
                    )
                }
                RootChoice::NoRoots => ("no roots", String::new(), "none".into()),
            };
            lines.push(line("t", choice, sub, val, None));
        }
        let conclusion = match (test.case, test.choice) {
            (_, RootChoice::NoRoots) if test.discriminant.is_nan() => {
                "Δ is NaN (overflow): treated as a miss.".to_string()
            }
            (SphereCase::Miss, _) | (_, RootChoice::NoRoots) => {
                "Δ < 0: the ray's line passes the sphere by — no real roots, a miss.".into()
            }
            (_, RootChoice::NearRoot) => format!(
                "Hit at the near root t = {}: the ray enters the sphere there.",
                test.t.map_or("?".into(), num)
            ),
            (_, RootChoice::FarRoot) => format!(
                "The origin is inside the sphere (the near root is not ahead): hit at the far root t = {}.",
                test.t.map_or("?".into(), num)
            ),
            (_, RootChoice::Behind) => {
                "Both roots are at or behind the origin: the sphere is behind the ray, a miss."
                    .into()
            }
            (_, RootChoice::BeyondTMax) => {
                "The usable root lies beyond t_max (something closer was already hit): a miss."
                    .into()
            }
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

    fn plane(&self, name: &str, test: &PlaneTest<f32>) -> Explanation {
        let (o, d) = (self.ray.origin, self.ray.direction);
        let mut lines = vec![];
        let form = match test.form {
            PlaneForm::General { normal, offset } => {
                lines.push(line(
                    "denominator",
                    "Q·n",
                    format!("{}·{}", v3(d), v3(normal)),
                    num(test.denominator),
                    None,
                ));
                lines.push(line(
                    "numerator",
                    "c − S·n",
                    format!("{} − {}·{}", num(offset), v3(o), v3(normal)),
                    num(test.numerator),
                    None,
                ));
                "general: X·n = c".to_string()
            }
            PlaneForm::Axis { axis, offset } => {
                let a = AXES[axis.min(2)];
                lines.push(line(
                    "denominator",
                    &format!("Q{a}"),
                    "",
                    num(test.denominator),
                    None,
                ));
                lines.push(line(
                    "numerator",
                    &format!("c − S{a}"),
                    format!("{} − {}", num(offset), p(o[axis.min(2)])),
                    num(test.numerator),
                    None,
                ));
                format!("axis-aligned: {a} = c")
            }
        };
        let conclusion = if test.parallel {
            lines[0].note = Some("= 0: the ray runs parallel to the plane".into());
            "The denominator is zero: the ray is parallel to the plane (or lies in it) — a miss, never a division by zero.".to_string()
        } else {
            let t_raw = test.t_raw.unwrap_or(f32::NAN);
            lines.push(line(
                "t",
                "numerator / denominator",
                format!("{}/{}", p(test.numerator), p(test.denominator)),
                num(t_raw),
                None,
            ));
            lines.push(self.range_line(t_raw));
            match test.t {
                Some(t) => format!("Hit at t = {}.", num(t)),
                None if t_raw > self.ray.t_min => {
                    "t is beyond t_max (something closer was already hit): a miss.".into()
                }
                None => "t is at or behind the origin: a miss.".into(),
            }
        };
        Explanation {
            title: format!("Ray–plane \"{name}\" ({form})"),
            lines,
            conclusion,
        }
    }

    /// Möller–Trumbore. E1, E2, −Q and T = S − P0 are computed here exactly as the kernel does
    /// (glam f32 subtraction and negation); the determinants and quotients are the recorded ones.
    fn moller_trumbore(
        &self,
        name: &str,
        vertices: &[[f32; 3]; 3],
        test: &TriangleTest<f32>,
    ) -> Explanation {
        let pv = vertices.map(Vec3::from);
        let e1 = pv[1] - pv[0];
        let e2 = pv[2] - pv[0];
        let nq = -self.dir();
        let tv = self.origin() - pv[0];
        let stop = test.stopped_at;
        let mut lines = vec![
            line(
                "E1",
                "P1 − P0",
                format!("{} − {}", vv(pv[1]), vv(pv[0])),
                vv(e1),
                Some("step 1".into()),
            ),
            line(
                "E2",
                "P2 − P0",
                format!("{} − {}", vv(pv[2]), vv(pv[0])),
                vv(e2),
                Some("step 1".into()),
            ),
            line(
                "D0",
                "det(−Q, E1, E2)",
                format!("det({}, {}, {})", vv(nq), vv(e1), vv(e2)),
                num(test.det),
                Some(if stop == 2 {
                    "step 2: zero (or not finite): the ray is parallel to the plane — stop".into()
                } else {
                    "step 2: non-zero, so the system has one solution".into()
                }),
            ),
        ];
        let q = |x: Option<f32>| x.map_or("—".to_string(), num);
        if stop > 2 {
            lines.push(line(
                "T",
                "S − P0",
                format!("{} − {}", vv(self.origin()), vv(pv[0])),
                vv(tv),
                Some("step 3".into()),
            ));
            lines.push(line(
                "Dt",
                "det(T, E1, E2)",
                format!("det({}, {}, {})", vv(tv), vv(e1), vv(e2)),
                q(test.dt),
                Some("step 4".into()),
            ));
            let t = test.t_star.unwrap_or(f32::NAN);
            lines.push(line(
                "t*",
                "Dt/D0",
                format!("{}/{}", p(test.dt.unwrap_or(f32::NAN)), p(test.det)),
                num(t),
                Some("step 5".into()),
            ));
            let mut range = self.range_line(t);
            if stop == 5 {
                range.note = range.note.map(|n| format!("{n} — stop"));
            }
            lines.push(range);
        }
        if stop > 5 {
            lines.push(line(
                "Du",
                "det(−Q, T, E2)",
                format!("det({}, {}, {})", vv(nq), vv(tv), vv(e2)),
                q(test.du),
                Some("step 6".into()),
            ));
            let u = test.u.unwrap_or(f32::NAN);
            lines.push(line(
                "u*",
                "Du/D0",
                format!("{}/{}", p(test.du.unwrap_or(f32::NAN)), p(test.det)),
                num(u),
                Some("step 7: the weight of P1".into()),
            ));
            // The kernel's verdict (it stops when u* < 0 or u* > 1).
            let ok = stop > 8;
            lines.push(line(
                "u in [0, 1]?",
                "0 ≤ u* ≤ 1",
                format!("0 ≤ {} ≤ 1", num(u)),
                yes_no(ok),
                Some(if ok {
                    "step 8".into()
                } else {
                    "step 8: outside the triangle — stop".into()
                }),
            ));
        }
        if stop > 8 {
            lines.push(line(
                "Dv",
                "det(−Q, E1, T)",
                format!("det({}, {}, {})", vv(nq), vv(e1), vv(tv)),
                q(test.dv),
                Some("step 9".into()),
            ));
            let (u, v) = (test.u.unwrap_or(f32::NAN), test.v.unwrap_or(f32::NAN));
            lines.push(line(
                "v*",
                "Dv/D0",
                format!("{}/{}", p(test.dv.unwrap_or(f32::NAN)), p(test.det)),
                num(v),
                Some("step 10: the weight of P2".into()),
            ));
            // The kernel's own sum of the recorded u* and v*.
            let uv = u + v;
            // The kernel's verdict (it stops when v* < 0 or u* + v* > 1).
            let ok = stop > 11;
            lines.push(line(
                "v ≥ 0, u + v ≤ 1?",
                "v* ≥ 0 and u* + v* ≤ 1",
                format!(
                    "{} ≥ 0 and {} + {} = {} ≤ 1",
                    num(v),
                    num(u),
                    num(v),
                    num(uv)
                ),
                yes_no(ok),
                Some(if ok {
                    "step 11".into()
                } else {
                    "step 11: outside the triangle — stop".into()
                }),
            ));
        }
        if stop == 12 {
            let (u, v) = (test.u.unwrap_or(f32::NAN), test.v.unwrap_or(f32::NAN));
            lines.push(line(
                "(b0, b1, b2)",
                "(1 − u* − v*, u*, v*)",
                format!("(1 − {} − {}, {}, {})", num(u), num(v), num(u), num(v)),
                format!("({}, {}, {})", num(1.0 - u - v), num(u), num(v)),
                Some("step 12: the barycentric weights of P0, P1, P2".into()),
            ));
        }
        let conclusion = if stop == 12 {
            format!(
                "Hit at t = {} (step 12), with u = {}, v = {}.",
                q(test.t),
                q(test.u),
                q(test.v)
            )
        } else {
            format!("Stopped at step {stop}: {}. A miss.", test.stop_reason())
        };
        Explanation {
            title: format!("Ray–triangle \"{name}\" (Möller–Trumbore, Cramer's rule)"),
            lines,
            conclusion,
        }
    }

    /// The watertight test. The permutation is the recorded one; the translated, permuted and
    /// sheared vertices are computed here exactly as the kernel does (same f32 operations on the
    /// same inputs); the edge functions, det, scaled t, t, u and v are the recorded ones.
    fn watertight(
        &self,
        name: &str,
        vertices: &[[f32; 3]; 3],
        test: &TriangleTest<f32>,
    ) -> Explanation {
        let pv = vertices.map(Vec3::from);
        let d = self.dir();
        let o = self.origin();
        let [kx, ky, kz] = test.permutation.unwrap_or([0, 1, 2]).map(|k| k.min(2));
        let perm = |v: Vec3| [v[kx], v[ky], v[kz]];
        let mut q = [perm(pv[0] - o), perm(pv[1] - o), perm(pv[2] - o)];
        let dp = perm(d);
        let sx = -dp[0] / dp[2];
        let sy = -dp[1] / dp[2];
        let sz = 1.0 / dp[2];
        for v in q.iter_mut() {
            v[0] += sx * v[2];
            v[1] += sy * v[2];
        }
        let stop = test.stopped_at;
        let name_of = |k: usize| AXES[k];
        let mut lines = vec![
            line(
                "(kx, ky, kz)",
                "z = the axis of the largest |Q| component",
                format!("|Q| = {}", vv(d.abs())),
                format!("({}, {}, {})", name_of(kx), name_of(ky), name_of(kz)),
                Some("the ray is turned into +z".into()),
            ),
            line(
                "Sx, Sy, Sz",
                "−Qx/Qz, −Qy/Qz, 1/Qz (permuted)",
                format!(
                    "−{}/{}, −{}/{}, 1/{}",
                    p(dp[0]),
                    p(dp[2]),
                    p(dp[1]),
                    p(dp[2]),
                    p(dp[2])
                ),
                format!("{}, {}, {}", num(sx), num(sy), num(sz)),
                Some("the shear that makes the ray run along +z".into()),
            ),
        ];
        for (i, v) in q.iter().enumerate() {
            lines.push(line(
                &format!("P′{i}"),
                &format!("shear(permute(P{i} − S)): (x + Sx·z, y + Sy·z, z)"),
                format!("permute({} − {})", vv(pv[i]), vv(o)),
                format!("({}, {}, {})", num(v[0]), num(v[1]), num(v[2])),
                None,
            ));
        }
        let edges = test.edges.unwrap_or([f32::NAN; 3]);
        let pairs = [(1, 2), (2, 0), (0, 1)];
        for (i, (a, b)) in pairs.into_iter().enumerate() {
            lines.push(line(
                &format!("e{i}"),
                &format!("x′{a}·y′{b} − y′{a}·x′{b}"),
                format!(
                    "{}·{} − {}·{}",
                    p(q[a][0]),
                    p(q[b][1]),
                    p(q[a][1]),
                    p(q[b][0])
                ),
                num(edges[i]),
                (i == 0).then(|| {
                    "2D edge functions: which side of each edge the ray passes (one rounding, by FMA; an exact 0 is redone in f64)".into()
                }),
            ));
        }
        let mixed = edges.iter().any(|&e| e < 0.0) && edges.iter().any(|&e| e > 0.0);
        lines.push(line(
            "same signs?",
            "e0, e1, e2 all ≥ 0 or all ≤ 0",
            format!("{}, {}, {}", num(edges[0]), num(edges[1]), num(edges[2])),
            yes_no(!mixed),
            Some(if stop == 8 {
                "mixed signs: the ray passes outside an edge — stop".into()
            } else {
                "the ray passes inside (or on) all three edges".into()
            }),
        ));
        if stop != 8 {
            lines.push(line(
                "det",
                "e0 + e1 + e2",
                format!("{} + {} + {}", num(edges[0]), p(edges[1]), p(edges[2])),
                num(test.det),
                Some(if stop == 2 {
                    "zero (or not finite): the ray is parallel to the triangle — stop".into()
                } else {
                    "non-zero".into()
                }),
            ));
        }
        if stop > 2 && stop != 8 {
            let z = [q[0][2] * sz, q[1][2] * sz, q[2][2] * sz];
            lines.push(line(
                "t_scaled",
                "e0·z′0 + e1·z′1 + e2·z′2, z′ = z·Sz",
                format!(
                    "{}·{} + {}·{} + {}·{}",
                    p(edges[0]),
                    p(z[0]),
                    p(edges[1]),
                    p(z[1]),
                    p(edges[2]),
                    p(z[2])
                ),
                test.dt.map_or("—".into(), num),
                None,
            ));
            let t = test.t_star.unwrap_or(f32::NAN);
            lines.push(line(
                "t",
                "t_scaled/det",
                format!("{}/{}", p(test.dt.unwrap_or(f32::NAN)), p(test.det)),
                num(t),
                None,
            ));
            lines.push(line(
                "u",
                "e1/det",
                format!("{}/{}", p(edges[1]), p(test.det)),
                test.u.map_or("—".into(), num),
                Some("the weight of P1".into()),
            ));
            lines.push(line(
                "v",
                "e2/det",
                format!("{}/{}", p(edges[2]), p(test.det)),
                test.v.map_or("—".into(), num),
                Some("the weight of P2".into()),
            ));
            lines.push(self.range_line(t));
        }
        let in_range = test
            .t_star
            .is_some_and(|t| t > self.ray.t_min && t < self.t_max());
        let conclusion = match stop {
            12 => format!(
                "Hit at t = {}, with u = {}, v = {}.",
                test.t.map_or("?".into(), num),
                test.u.map_or("?".into(), num),
                test.v.map_or("?".into(), num)
            ),
            5 if in_range => "t is no larger than its own rounding-error bound (pbrt-v4): too close to the origin to trust — a miss.".into(),
            _ => format!("{} — a miss.", upper_first(test.stop_reason())),
        };
        Explanation {
            title: format!("Ray–triangle \"{name}\" (watertight, Woop–Benthin–Wald)"),
            lines,
            conclusion,
        }
    }

    fn accept(&self, name: &str, t: f32, previous: f32) -> Explanation {
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

    fn miss(&self, background: [f32; 3]) -> Explanation {
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
    fn surface(
        &self,
        point: [f32; 3],
        normal: [f32; 3],
        inside: bool,
        error_bound: [f32; 3],
        over_point: [f32; 3],
    ) -> Explanation {
        let hit = self.ray.hit.as_ref();
        let obj = hit.and_then(|h| self.object(h.object));
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
                "pbrt-v4's OffsetRayOrigin: past the error bound, on the side the ray leaves"
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

    /// The child ray spawned by the next `Spawn` step after this one, if any.
    fn next_child(&self) -> Option<&RayRecord> {
        let i = self.idx?;
        match self.ray.steps.get(i + 1).map(|s| &s.step) {
            Some(Step::Spawn { child }) => self.ray.children.get(*child as usize),
            _ => None,
        }
    }

    /// A shadow ray. L − P is computed here exactly as the tracer does (`position − point`).
    fn shadow_ray(&self, light: u32, name: &str, distance: f32) -> Explanation {
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

    /// Phong lighting. The light vector l = (L − P)/|L − P|, the reflected light vector
    /// r = reflect(−l, n) and the eye vector e are computed here exactly as `phong` and `interact`
    /// do; l·n, r·e and the three terms are the recorded ones. The material's Phong coefficients
    /// are not in a trace, so they stay symbols.
    #[allow(clippy::too_many_arguments)]
    fn light(
        &self,
        light: u32,
        name: &str,
        blocked: bool,
        blocker: Option<&str>,
        l_dot_n: f32,
        r_dot_e: f32,
        terms: [[f32; 3]; 3],
    ) -> Explanation {
        let [ambient, diffuse, specular] = terms;
        let lt = self.trace.lights.get(light as usize);
        let lcol = lt.map_or("I".to_string(), |l| vv(l.color));
        let col = self
            .ray
            .hit
            .as_ref()
            .and_then(|h| self.object(h.object))
            .map_or("c".to_string(), |o| v3(o.color));
        let mut lines = vec![];
        let surf = self.surface_before();
        let (ls, rs, es, ns) = match (lt, surf) {
            (Some(lt), Some((pt, n))) => {
                let to = lt.position - pt;
                let l = to / to.length();
                lines.push(line(
                    "l",
                    "(L − P)/|L − P|",
                    format!("({} − {})/|…|", vv(lt.position), vv(pt)),
                    vv(l),
                    Some("unit vector towards the light".into()),
                ));
                let r = super::shading::reflect(-l, n);
                let e = self.eye();
                (vv(l), vv(r), vv(e), vv(n))
            }
            _ => ("l".into(), "r".into(), "e".into(), "n".into()),
        };
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
        if surf.is_some() && lt.is_some() {
            lines.push(line(
                "r",
                "−l − 2(−l·n)n",
                "",
                rs.clone(),
                Some("the light reflected about n".into()),
            ));
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
        // The tracer's own sum, in its order.
        let sum = Vec3::from(ambient) + Vec3::from(diffuse) + Vec3::from(specular);
        lines.push(line(
            "total",
            "ambient + diffuse + specular",
            format!("{} + {} + {}", v3(ambient), v3(diffuse), v3(specular)),
            vv(sum),
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

    /// A reflection ray. d·n is computed here exactly as `reflect` does (`d.dot(n)` in f32 on the
    /// ray's direction and the recorded normal); r is the recorded direction.
    fn reflect(&self, reflective: f32, direction: [f32; 3]) -> Explanation {
        let d = self.dir();
        let mut lines = vec![];
        match self.surface_before() {
            Some((_, n)) => {
                let dn = d.dot(n);
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
            None => lines.push(line("r", "Q − 2(Q·n)n", "", v3(direction), None)),
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

    /// Snell's law. η = n1/n2, the eye vector and cos θₜ are computed here exactly as `refract`
    /// does; cos θᵢ, sin² θₜ, the critical angle and the direction are the recorded ones.
    #[allow(clippy::too_many_arguments)]
    fn refract(
        &self,
        n1: f32,
        n2: f32,
        cos_i: f32,
        sin2_t: f32,
        critical: Option<f32>,
        tir: bool,
        direction: Option<[f32; 3]>,
    ) -> Explanation {
        let ratio = n1 / n2;
        let surf = self.surface_before();
        let e = self.eye();
        let mut lines = vec![line(
            "η",
            "n1/n2",
            format!("{}/{}", num(n1), num(n2)),
            num(ratio),
            None,
        )];
        lines.push(line(
            "cos θᵢ",
            "e·n",
            surf.map_or(String::new(), |(_, n)| format!("{}·{}", vv(e), vv(n))),
            num(cos_i),
            Some(format!(
                "θᵢ = {}°",
                num(cos_i.clamp(-1.0, 1.0).acos().to_degrees())
            )),
        ));
        lines.push(line(
            "sin² θₜ",
            "η²(1 − cos² θᵢ)",
            format!("{}²·(1 − {}²)", num(ratio), p(cos_i)),
            num(sin2_t),
            Some(if tir {
                "> 1: no real θₜ — total internal reflection".into()
            } else {
                "≤ 1: the ray gets through".into()
            }),
        ));
        if let Some(c) = critical {
            lines.push(line(
                "θc",
                "asin(n2/n1)",
                format!("asin({}/{})", num(n2), num(n1)),
                format!("{}°", num(c)),
                Some("beyond this angle of incidence, nothing gets out".into()),
            ));
        }
        if !tir {
            let cos_t = (1.0 - sin2_t).sqrt();
            lines.push(line(
                "cos θₜ",
                "√(1 − sin² θₜ)",
                format!("√(1 − {})", num(sin2_t)),
                num(cos_t),
                None,
            ));
            lines.push(line(
                "t",
                "(η cos θᵢ − cos θₜ)·n − η·e",
                surf.map_or(String::new(), |(_, n)| {
                    format!(
                        "({}·{} − {})·{} − {}·{}",
                        num(ratio),
                        p(cos_i),
                        num(cos_t),
                        vv(n),
                        num(ratio),
                        vv(e)
                    )
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

    /// Schlick's approximation. n1, n2 and cos θᵢ come from this ray's `Refract` step; R0 and
    /// cos θₜ are computed here exactly as `schlick` does. R is the recorded reflectance.
    fn schlick(&self, reflectance: f32) -> Explanation {
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
        match refr {
            Some((n1, n2, cos_i, sin2_t)) => {
                let r0 = ((n1 - n2) / (n1 + n2)).powi(2);
                lines.push(line(
                    "R0",
                    "((n1 − n2)/(n1 + n2))²",
                    format!("(({} − {})/({} + {}))²", num(n1), num(n2), num(n1), num(n2)),
                    num(r0),
                    Some("the reflectance head-on".into()),
                ));
                let cos = if n1 > n2 {
                    if sin2_t > 1.0 {
                        tir = true;
                        None
                    } else {
                        let c = (1.0 - sin2_t).sqrt();
                        lines.push(line(
                            "cos θ",
                            "cos θₜ = √(1 − sin² θₜ)",
                            format!("√(1 − {})", num(sin2_t)),
                            num(c),
                            Some("n1 > n2: Schlick uses the transmitted angle".into()),
                        ));
                        Some(c)
                    }
                } else {
                    lines.push(line("cos θ", "cos θᵢ", "", num(cos_i), None));
                    Some(cos_i)
                };
                match cos {
                    Some(c) => lines.push(line(
                        "R(θ)",
                        "R0 + (1 − R0)(1 − cos θ)⁵",
                        format!("{} + (1 − {})·(1 − {})⁵", num(r0), num(r0), p(c)),
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

    fn depth_limit(&self, max_depth: u32) -> Explanation {
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

    fn weight_cutoff(&self, kind: RayKind, contribution: f32, cutoff: f32) -> Explanation {
        let kind = match kind {
            RayKind::Refraction => "refraction",
            RayKind::Shadow => "shadow",
            RayKind::Primary => "primary",
            RayKind::Reflection => "reflection",
        };
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

    fn spawn(&self, child: u32) -> Explanation {
        let Some(c) = self.ray.children.get(child as usize) else {
            return Explanation {
                title: format!("Child ray {child}"),
                lines: vec![],
                conclusion: "The child ray is missing from the trace.".into(),
            };
        };
        let kind = match c.kind {
            RayKind::Primary => "primary",
            RayKind::Shadow => "shadow",
            RayKind::Reflection => "reflection",
            RayKind::Refraction => "refraction",
        };
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
    fn color(&self, color: [f32; 3]) -> Explanation {
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
            let col = self
                .ray
                .hit
                .as_ref()
                .and_then(|h| self.object(h.object))
                .map_or("c".to_string(), |o| v3(o.color));
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
            Step::Schlick { reflectance } => Some(reflectance),
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
                match self.ray.kind {
                    RayKind::Primary => "primary",
                    RayKind::Shadow => "shadow",
                    RayKind::Reflection => "reflection",
                    RayKind::Refraction => "refraction",
                },
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

/// b′ = −f·Q as the stable kernel computes it (from f when the sphere is known, else −b/2).
fn b_half_of(f: Option<Vec3>, d: Vec3, test: &SphereTest<f32>) -> f32 {
    f.map_or(-test.b / 2.0, |f| -f.dot(d))
}

fn case_note(test: &SphereTest<f32>) -> String {
    if test.discriminant.is_nan() {
        "NaN (overflow): a miss".into()
    } else {
        match test.case {
            SphereCase::Miss => "< 0: no real roots".into(),
            SphereCase::Tangent => "= 0: one root (tangent)".into(),
            SphereCase::EnterExit => "> 0: two roots".into(),
        }
    }
}

fn upper_first(s: &str) -> String {
    let mut c = s.chars();
    match c.next() {
        Some(f) => f.to_uppercase().collect::<String>() + c.as_str(),
        None => String::new(),
    }
}
