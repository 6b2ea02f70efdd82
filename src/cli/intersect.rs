//! `raystep intersect …`: one ray against one primitive, every intermediate explained in the
//! order the seeds compute it, in f32 or f64.

use super::parse_vec3;
use crate::math::{Ray, Real, Vector, vec_from_f64};
use crate::shapes::{
    BoxMethod, PlaneForm, RootChoice, SphereCase, SphereMethod, TriangleMethod, aabb, plane,
    sphere, triangle,
};
use clap::{Args, Subcommand, ValueEnum};
use serde_json::{Map, Value, json};
use std::fmt::Write;

/// The ray, shared by every shape.
#[derive(Debug, Clone, Args)]
pub struct RayArgs {
    /// Ray origin S as X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub origin: [f64; 3],
    /// Ray direction Q as X,Y,Z (not necessarily unit length; not zero).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub dir: [f64; 3],
    /// Hits at t ≤ tmin are ignored.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub tmin: f64,
    /// Arithmetic precision.
    #[arg(long, value_enum, default_value_t = Precision::F32)]
    pub precision: Precision,
    /// Print one JSON object instead of the explanation.
    #[arg(long)]
    pub json: bool,
}

/// Floating-point precision.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Precision {
    /// Single precision (the renderer's).
    F32,
    /// Double precision.
    F64,
}

/// The primitive to test.
#[derive(Debug, Subcommand)]
pub enum Shape {
    /// A sphere: the quadratic at² + bt + c = 0.
    Sphere {
        /// Centre G as X,Y,Z.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        center: [f64; 3],
        /// Radius r > 0.
        #[arg(long, allow_hyphen_values = true)]
        radius: f64,
        /// Method.
        #[arg(long, value_enum, default_value_t = SphereMethod::Stable)]
        method: SphereMethod,
        /// The ray.
        #[command(flatten)]
        ray: RayArgs,
    },
    /// A plane: --point and --normal (X·n = c), or --axis and --offset (the shortcut).
    Plane {
        /// A point on the plane.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, requires = "normal", conflicts_with_all = ["axis", "offset"])]
        point: Option<[f64; 3]>,
        /// The plane's normal (need not be unit length).
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, requires = "point")]
        normal: Option<[f64; 3]>,
        /// Axis of an axis-aligned plane.
        #[arg(long, value_enum, required_unless_present = "point")]
        axis: Option<Axis>,
        /// The axis-aligned plane's coordinate c.
        #[arg(long, allow_hyphen_values = true, requires = "axis")]
        offset: Option<f64>,
        /// The ray.
        #[command(flatten)]
        ray: RayArgs,
    },
    /// A triangle P0, P1, P2.
    Triangle {
        /// Vertex P0.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        p0: [f64; 3],
        /// Vertex P1.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        p1: [f64; 3],
        /// Vertex P2.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        p2: [f64; 3],
        /// Method.
        #[arg(long, value_enum, default_value_t = TriangleMethod::MollerTrumbore)]
        method: TriangleMethod,
        /// The ray.
        #[command(flatten)]
        ray: RayArgs,
    },
    /// An axis-aligned box: the slab test.
    Box {
        /// Minimum corner.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        min: [f64; 3],
        /// Maximum corner.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        max: [f64; 3],
        /// Method.
        #[arg(long, value_enum, default_value_t = BoxMethod::Robust)]
        method: BoxMethod,
        /// The ray.
        #[command(flatten)]
        ray: RayArgs,
    },
}

/// An axis name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Axis {
    /// x.
    X,
    /// y.
    Y,
    /// z.
    Z,
}

/// Runs `raystep intersect`.
pub fn run(shape: &Shape) -> Result<(), String> {
    let ray = match shape {
        Shape::Sphere { ray, .. }
        | Shape::Plane { ray, .. }
        | Shape::Triangle { ray, .. }
        | Shape::Box { ray, .. } => ray,
    };
    let (text, value) = match ray.precision {
        Precision::F32 => compute::<f32>(shape, ray)?,
        Precision::F64 => compute::<f64>(shape, ray)?,
    };
    if ray.json {
        super::emit(&(serde_json::to_string_pretty(&value).expect("json") + "\n"))
    } else {
        super::emit(&text)
    }
}

fn v<T: Real>(x: T::V) -> String {
    format!("({}, {}, {})", x.at(0), x.at(1), x.at(2))
}

fn compute<T: Real>(shape: &Shape, args: &RayArgs) -> Result<(String, Value), String> {
    let tmin = scalar::<T>("--tmin", args.tmin)?;
    if tmin < T::zero() {
        return Err(format!("--tmin must not be negative, got {}", args.tmin));
    }
    let ray = Ray::<T>::new(
        vector::<T>("--origin", args.origin)?,
        vector::<T>("--dir", args.dir)?,
        tmin,
        T::infinity(),
    )
    .map_err(|e| format!("--origin/--dir: {e}"))?;
    let mut s = String::new();
    let head = |s: &mut String, what: &str| {
        let _ = writeln!(s, "{what} ({})", T::NAME);
        let _ = writeln!(
            s,
            "  ray        S = {}, Q = {}, t in ({}, ∞)",
            v::<T>(ray.origin),
            v::<T>(ray.dir),
            ray.t_min
        );
    };
    let value = match shape {
        Shape::Sphere {
            center,
            radius,
            method,
            ..
        } => {
            let r = scalar::<T>("--radius", *radius)?;
            if r <= T::zero() {
                return Err(format!("--radius must be positive, got {radius}"));
            }
            let g = vector::<T>("--center", *center)?;
            let t = sphere::intersect(&ray, g, r, *method);
            let name = match method {
                SphereMethod::Textbook => "textbook",
                SphereMethod::Stable => "stable, Ray Tracing Gems ch. 7",
            };
            head(&mut s, &format!("Ray–sphere intersection ({name})"));
            let xyz = |p: Option<[T; 3]>| {
                p.map_or("—".to_string(), |p| {
                    format!("({}, {}, {})", p[0], p[1], p[2])
                })
            };
            let _ = writeln!(s, "  sphere     G = {}, r = {r}", v::<T>(g));
            let _ = writeln!(s, "  f = S − G              = {}", xyz(t.f));
            let _ = writeln!(s, "  a = Q·Q                = {}", t.a);
            let _ = writeln!(s, "  b = 2 f·Q              = {}", t.b);
            let _ = writeln!(s, "  c = f·f − r²           = {}", t.c);
            if let (Some(dp), SphereMethod::Stable) = (t.delta_prime, method) {
                let b_half = t.b_half.map_or("—".to_string(), |b| b.to_string());
                let _ = writeln!(s, "  b′ = −f·Q              = {b_half}");
                let _ = writeln!(s, "  l = f + (b′/a)Q        = {}", xyz(t.l));
                let _ = writeln!(
                    s,
                    "  Δ′ = r² − ‖f + (b′/a)Q‖² = {dp}   (distance² margin of the ray's line)"
                );
                let _ = writeln!(s, "  Δ = b² − 4ac = 4aΔ′    = {}", t.discriminant);
            } else {
                let _ = writeln!(s, "  Δ = b² − 4ac           = {}", t.discriminant);
            }
            let _ = writeln!(
                s,
                "  case: {}",
                match t.case {
                    SphereCase::Miss => "Δ < 0 — no real roots: the ray's line misses the sphere",
                    SphereCase::Tangent => "Δ = 0 — one double root: the line touches the sphere",
                    SphereCase::EnterExit =>
                        "Δ > 0 — two roots: the line enters and leaves the sphere",
                }
            );
            if let Some([t0, t1]) = t.roots {
                if let Some(q) = t.q {
                    let _ = writeln!(s, "  q = b′ + sign(b′)√(aΔ′) = {q}");
                    let _ = writeln!(s, "  roots c/q and q/a      = {t0}, {t1}");
                } else {
                    if let Some(sq) = t.sqrt_discriminant {
                        let _ = writeln!(s, "  √Δ                     = {sq}");
                    }
                    let _ = writeln!(s, "  t = (−b ± √Δ) / 2a     = {t0}, {t1}");
                }
            }
            let _ = writeln!(
                s,
                "  choice: {}",
                match t.choice {
                    RootChoice::NoRoots => "none",
                    RootChoice::NearRoot =>
                        "the smaller root lies in (t_min, ∞): the near side of the sphere",
                    RootChoice::FarRoot =>
                        "the smaller root is behind the origin (the origin is inside): the larger root",
                    RootChoice::Behind =>
                        "both roots are behind the origin: the sphere is behind the ray",
                    RootChoice::BeyondTMax => "the usable root is beyond t_max",
                }
            );
            if let Some(th) = t.t {
                let x = ray.at(th);
                let _ = writeln!(s, "  hit        t = {th}, X = S + tQ = {}", v::<T>(x));
                let _ = writeln!(
                    s,
                    "  normal     (X − G)/r = {}",
                    v::<T>(sphere::normal::<T>(x, g, r))
                );
            } else {
                let _ = writeln!(s, "  no hit");
            }
            let mut m = Map::new();
            m.insert("a".into(), json!(t.a));
            m.insert("b".into(), json!(t.b));
            m.insert("c".into(), json!(t.c));
            m.insert("discriminant".into(), json!(t.discriminant));
            m.insert(
                "roots".into(),
                json!(t.roots.map_or(vec![], |r| r.to_vec())),
            );
            m.insert("case".into(), json!(t.case));
            m.insert("choice".into(), json!(t.choice));
            if let Some(dp) = t.delta_prime {
                m.insert("delta_prime".into(), json!(dp));
            }
            finish(m, t.t)
        }
        Shape::Plane {
            point,
            normal,
            axis,
            offset,
            ..
        } => {
            let t = if let Some(ax) = axis {
                let axis = *ax as usize;
                let c = scalar::<T>("--offset", offset.unwrap_or(0.0))?;
                let t = plane::axis(&ray, axis, c);
                let n = ["x", "y", "z"][axis];
                head(&mut s, "Ray–plane intersection (axis-aligned shortcut)");
                let _ = writeln!(s, "  plane      {n} = {c}");
                let _ = writeln!(s, "  denominator Q_{n}       = {}", t.denominator);
                let _ = writeln!(s, "  numerator c − S_{n}     = {}", t.numerator);
                t
            } else {
                let n = normal.expect("clap requires --normal with --point");
                let unit =
                    crate::math::unit_f64(n).ok_or("--normal must not be the zero vector")?;
                let nn = vec_from_f64::<T>(unit);
                let p = vector::<T>("--point", point.expect("clap requires --point"))?;
                let c = p.dot(nn);
                let t = plane::general(&ray, nn, c);
                head(&mut s, "Ray–plane intersection (general plane X·n = c)");
                let _ = writeln!(s, "  plane      n = {} (unit), c = P·n = {c}", v::<T>(nn));
                let _ = writeln!(s, "  denominator Q·n        = {}", t.denominator);
                let _ = writeln!(s, "  numerator c − S·n      = {}", t.numerator);
                t
            };
            if t.parallel {
                let _ = writeln!(
                    s,
                    "  the denominator is zero: the ray is parallel to the plane — no hit"
                );
            } else {
                let raw = t.t_raw.expect("not parallel");
                let _ = writeln!(s, "  t = numerator / denominator = {raw}");
                match t.t {
                    Some(th) => {
                        let mut x = ray.at(th);
                        if let PlaneForm::Axis { axis, offset } = t.form {
                            // The shortcut puts the hit exactly on the plane.
                            let mut a = [x.at(0), x.at(1), x.at(2)];
                            a[axis] = offset;
                            x = T::V::new(a[0], a[1], a[2]);
                        }
                        let _ = writeln!(s, "  hit        t = {th}, X = S + tQ = {}", v::<T>(x));
                    }
                    None => {
                        let _ = writeln!(s, "  t is not in (t_min, ∞): behind the origin — no hit");
                    }
                }
            }
            let mut m = Map::new();
            m.insert("denominator".into(), json!(t.denominator));
            m.insert("numerator".into(), json!(t.numerator));
            m.insert("parallel".into(), json!(t.parallel));
            finish(m, t.t)
        }
        Shape::Triangle {
            p0, p1, p2, method, ..
        } => {
            let p = [
                vector::<T>("--p0", *p0)?,
                vector::<T>("--p1", *p1)?,
                vector::<T>("--p2", *p2)?,
            ];
            let t = triangle::intersect(&ray, p, *method);
            match method {
                TriangleMethod::MollerTrumbore => {
                    head(
                        &mut s,
                        "Ray–triangle intersection (Möller–Trumbore, Cramer's rule)",
                    );
                    let _ = writeln!(
                        s,
                        "  triangle   P0 = {}, P1 = {}, P2 = {}",
                        v::<T>(p[0]),
                        v::<T>(p[1]),
                        v::<T>(p[2])
                    );
                    let _ = writeln!(
                        s,
                        "  solve S + tQ = P0 + u(P1 − P0) + v(P2 − P0), i.e. [−Q, E1, E2]·(t, u, v) = T"
                    );
                    let xyz = |p: Option<[T; 3]>| {
                        p.map_or("—".to_string(), |p| {
                            format!("({}, {}, {})", p[0], p[1], p[2])
                        })
                    };
                    let _ = writeln!(
                        s,
                        "   1. E1 = P1 − P0 = {}, E2 = P2 − P0 = {}",
                        xyz(t.e1),
                        xyz(t.e2)
                    );
                    let _ = writeln!(
                        s,
                        "   2. D0 = det(−Q, E1, E2) = {}{}",
                        t.det,
                        stop(&t, 2, "zero: parallel to the plane")
                    );
                    if let Some(dt) = t.dt {
                        let _ = writeln!(s, "   3. T = S − P0 = {}", xyz(t.t_vec));
                        let _ = writeln!(s, "   4. Dt = det(T, E1, E2) = {dt}");
                        let _ = writeln!(
                            s,
                            "   5. t* = Dt/D0 = {}{}",
                            t.t_star.expect("t*"),
                            stop(&t, 5, "not in (t_min, t_max): behind the origin")
                        );
                    }
                    if let Some(du) = t.du {
                        let _ = writeln!(s, "   6. Du = det(−Q, T, E2) = {du}");
                        let _ = writeln!(s, "   7. u* = Du/D0 = {}", t.u.expect("u"));
                        let _ = writeln!(
                            s,
                            "   8. 0 ≤ u* ≤ 1?{}",
                            if t.stopped_at == 8 {
                                " no — stop: outside the triangle"
                            } else {
                                " yes"
                            }
                        );
                    }
                    if let Some(dv) = t.dv {
                        let _ = writeln!(s, "   9. Dv = det(−Q, E1, T) = {dv}");
                        let _ = writeln!(s, "  10. v* = Dv/D0 = {}", t.v.expect("v"));
                        let _ = writeln!(
                            s,
                            "  11. v* ≥ 0 and u* + v* ≤ 1?{}",
                            if t.stopped_at == 11 {
                                " no — stop: outside the triangle"
                            } else {
                                " yes"
                            }
                        );
                    }
                    if t.stopped_at == 12 {
                        let _ = writeln!(
                            s,
                            "  12. hit at t = {}, barycentrics (1 − u − v, u, v)",
                            t.t.expect("t")
                        );
                    }
                }
                TriangleMethod::Watertight => {
                    head(
                        &mut s,
                        "Ray–triangle intersection (watertight, Woop–Benthin–Wald 2013)",
                    );
                    let _ = writeln!(
                        s,
                        "  triangle   P0 = {}, P1 = {}, P2 = {}",
                        v::<T>(p[0]),
                        v::<T>(p[1]),
                        v::<T>(p[2])
                    );
                    if let Some([kx, ky, kz]) = t.permutation {
                        let _ = writeln!(
                            s,
                            "  translate the vertices by −S; permute axes ({kx}, {ky}, {kz}) so z is Q's largest component; shear so Q = (0, 0, 1)"
                        );
                    }
                    if let Some([sx, sy, sz]) = t.shear {
                        let _ = writeln!(
                            s,
                            "  shear Sx, Sy, Sz = −Qx/Qz, −Qy/Qz, 1/Qz = {sx}, {sy}, {sz}"
                        );
                    }
                    if let Some(q) = t.sheared {
                        for (i, v) in q.iter().enumerate() {
                            let _ = writeln!(
                                s,
                                "  P′{i} = (x + Sx·z, y + Sy·z, z) of permute(P{i} − S) = ({}, {}, {})",
                                v[0], v[1], v[2]
                            );
                        }
                    }
                    if let Some([e0, e1, e2]) = t.edges {
                        let _ = writeln!(s, "  2D edge functions e0, e1, e2 = {e0}, {e1}, {e2}");
                    }
                    if t.stopped_at == 8 {
                        let _ = writeln!(
                            s,
                            "  the edge functions differ in sign: the ray passes outside — no hit"
                        );
                    } else {
                        let _ = writeln!(
                            s,
                            "  det = e0 + e1 + e2 = {}{}",
                            t.det,
                            stop(
                                &t,
                                2,
                                "zero: the ray is parallel (or the triangle degenerate)"
                            )
                        );
                        if let Some([z0, z1, z2]) = t.z_scaled {
                            let _ = writeln!(s, "  z′ = z·Sz = {z0}, {z1}, {z2}");
                        }
                        if let Some(ts) = t.t_star {
                            let _ = writeln!(
                                s,
                                "  t = Σ eᵢ z′ᵢ / det = {ts}{}",
                                stop(
                                    &t,
                                    5,
                                    "not in (t_min, t_max) (or within its own error bound)"
                                )
                            );
                            let _ = writeln!(
                                s,
                                "  u = e1/det = {}, v = e2/det = {}",
                                t.u.expect("u"),
                                t.v.expect("v")
                            );
                        }
                    }
                    if t.stopped_at == 12 {
                        let _ = writeln!(s, "  hit at t = {}", t.t.expect("t"));
                    }
                }
            }
            if t.t.is_none() {
                let _ = writeln!(
                    s,
                    "  no hit (stopped at step {}: {})",
                    t.stopped_at,
                    t.stop_reason()
                );
            }
            let mut m = Map::new();
            m.insert("det".into(), json!(t.det));
            m.insert("u".into(), json!(t.u));
            m.insert("v".into(), json!(t.v));
            m.insert("stopped_at".into(), json!(t.stopped_at));
            if t.method == TriangleMethod::MollerTrumbore {
                m.insert("dt".into(), json!(t.dt));
                m.insert("du".into(), json!(t.du));
                m.insert("dv".into(), json!(t.dv));
            } else {
                m.insert("permutation".into(), json!(t.permutation));
                m.insert("shear".into(), json!(t.shear));
                m.insert("sheared".into(), json!(t.sheared));
                m.insert("edges".into(), json!(t.edges));
                m.insert("z_scaled".into(), json!(t.z_scaled));
                m.insert("t_scaled".into(), json!(t.dt));
            }
            finish(m, t.t)
        }
        Shape::Box {
            min, max, method, ..
        } => {
            let lo = vector::<T>("--min", *min)?;
            let hi = vector::<T>("--max", *max)?;
            if (0..3).any(|i| lo.at(i) > hi.at(i)) {
                return Err(format!(
                    "--min {min:?} must not exceed --max {max:?} on any axis"
                ));
            }
            let t = aabb::intersect(&ray, lo, hi, *method);
            head(
                &mut s,
                match method {
                    BoxMethod::Plain => "Ray–box intersection (plain slab test)",
                    BoxMethod::Robust => "Ray–box intersection (robust slab test)",
                },
            );
            let _ = writeln!(s, "  box        min = {}, max = {}", v::<T>(lo), v::<T>(hi));
            for (i, a) in t.axes.iter().enumerate() {
                let n = ["x", "y", "z"][i];
                let _ = writeln!(
                    s,
                    "  {n} slab     1/Q_{n} = {}, enters at t = {}, leaves at t = {}",
                    inf(a.inv_dir),
                    inf(a.t_entry),
                    inf(a.t_exit)
                );
            }
            let _ = writeln!(s, "  t_near = max(t_min, entries) = {}", inf(t.t_near));
            let _ = writeln!(
                s,
                "  t_far  = min(t_max, exits){} = {}",
                if *method == BoxMethod::Robust {
                    " × (1 + 2γ₃)"
                } else {
                    ""
                },
                inf(t.t_far)
            );
            let _ = writeln!(
                s,
                "  {}",
                if t.hit {
                    format!(
                        "t_near {} t_far: the ray passes through the box",
                        if *method == BoxMethod::Robust {
                            "≤"
                        } else {
                            "<"
                        }
                    )
                } else {
                    "t_near > t_far: the slabs do not overlap — the ray misses the box".into()
                }
            );
            let mut m = Map::new();
            m.insert("t_near".into(), jv(t.t_near));
            m.insert("t_far".into(), jv(t.t_far));
            m.insert("hit".into(), json!(t.hit));
            // The first surface met after t_min: the entry, or the exit when the origin is inside.
            let first = if t.t_near > ray.t_min {
                t.t_near
            } else {
                t.t_far
            };
            m.insert("t".into(), if t.hit { jv(first) } else { Value::Null });
            return Ok((s, Value::Object(m)));
        }
    };
    Ok((s, value))
}

/// A command-line number in precision `T`, rejected if it is not finite there.
fn scalar<T: Real>(flag: &str, x: f64) -> Result<T, String> {
    let v = T::from_f64(x);
    if !x.is_finite() {
        return Err(format!("{flag} must be a finite number, got {x}"));
    }
    if !v.is_finite() {
        return Err(format!(
            "{flag} {x:e} is too large for {} (at most {:e})",
            T::NAME,
            T::max_value().to_f64()
        ));
    }
    Ok(v)
}

/// A command-line vector in precision `T`, rejected if a component is not finite there.
fn vector<T: Real>(flag: &str, a: [f64; 3]) -> Result<T::V, String> {
    for c in a {
        scalar::<T>(flag, c)?;
    }
    Ok(vec_from_f64::<T>(a))
}

/// A number, with infinities written as ∞.
fn inf<T: Real>(x: T) -> String {
    if x.is_infinite() {
        if x > T::zero() {
            "∞".into()
        } else {
            "-∞".into()
        }
    } else {
        format!("{x}")
    }
}

fn stop<T: Real>(t: &triangle::TriangleTest<T>, step: u8, why: &str) -> String {
    if t.stopped_at == step {
        format!(" — {why}: stop")
    } else {
        String::new()
    }
}

/// A number as JSON; infinities and NaN as the strings "inf", "-inf", "nan" (as in traces).
fn jv<T: Real>(x: T) -> Value {
    serde_json::to_value(WithJsonF(x)).unwrap_or(Value::Null)
}

struct WithJsonF<T>(T);

impl<T: Real> serde::Serialize for WithJsonF<T> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        crate::jsonf::serialize(&self.0, s)
    }
}

fn finish<T: Real>(mut m: Map<String, Value>, t: Option<T>) -> Value {
    m.insert("t".into(), json!(t));
    m.insert("hit".into(), json!(t.is_some()));
    Value::Object(m)
}
