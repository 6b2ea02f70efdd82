//! The text of `raystep intersect`: one kernel's record explained line by line, in the order the
//! course notes (docs/SOURCES.md) compute it, in f32 or f64. Every number printed is a field of the
//! record the kernel returned (or its input); nothing here repeats the kernel's arithmetic.
//!
//! Each function appends its lines to a string and returns the record as JSON.

use crate::math::{Ray, Real, Vector};
use crate::record::number::{Style, fmt, fmt64};
use crate::record::words;
use crate::shapes::aabb::BoxTest;
use crate::shapes::plane::PlaneTest;
use crate::shapes::sphere::SphereTest;
use crate::shapes::triangle::TriangleTest;
use crate::shapes::{BoxMethod, PlaneForm, RootChoice, SphereMethod, TriangleMethod, sphere};
use serde_json::{Map, Value, json};
use std::fmt::Write;

/// Ray–sphere: the record of [`crate::shapes::sphere::intersect`] for the sphere (`g`, `r`).
pub fn sphere<T: Real>(s: &mut String, ray: &Ray<T>, g: T::V, r: T, t: &SphereTest<T>) -> Value {
    let method = t.method;
    let name = match method {
        SphereMethod::Textbook => "textbook",
        SphereMethod::Stable => "stable, Ray Tracing Gems ch. 7",
    };
    head(s, ray, &format!("Ray–sphere intersection ({name})"));
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
    let _ = writeln!(s, "  case: {}", words::sphere_case(t.case));
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
        if t.choice == RootChoice::NoRoots {
            "none"
        } else {
            words::root_choice(t.choice)
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

/// Ray–plane: the record of [`crate::shapes::plane::axis`] or [`crate::shapes::plane::general`].
pub fn plane<T: Real>(s: &mut String, ray: &Ray<T>, t: &PlaneTest<T>) -> Value {
    match t.form {
        PlaneForm::Axis { axis, offset: c } => {
            let n = ["x", "y", "z"].get(axis).copied().unwrap_or("?");
            head(s, ray, "Ray–plane intersection (axis-aligned shortcut)");
            let _ = writeln!(s, "  plane      {n} = {c}");
            let _ = writeln!(s, "  denominator Q_{n}       = {}", t.denominator);
            let _ = writeln!(s, "  numerator c − S_{n}     = {}", t.numerator);
        }
        PlaneForm::General { normal, offset: c } => {
            head(s, ray, "Ray–plane intersection (general plane X·n = c)");
            let nn = T::V::new(normal[0], normal[1], normal[2]);
            let _ = writeln!(s, "  plane      n = {} (unit), c = P·n = {c}", v::<T>(nn));
            let _ = writeln!(s, "  denominator Q·n        = {}", t.denominator);
            let _ = writeln!(s, "  numerator c − S·n      = {}", t.numerator);
        }
    }
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

/// Ray–triangle: the record of [`crate::shapes::triangle::intersect`] for the vertices `p`.
pub fn triangle<T: Real>(s: &mut String, ray: &Ray<T>, p: [T::V; 3], t: &TriangleTest<T>) -> Value {
    let method = t.method;
    match method {
        TriangleMethod::MollerTrumbore => {
            head(
                s,
                ray,
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
                stop(t, 2, "zero: parallel to the plane")
            );
            if let Some(dt) = t.dt {
                let _ = writeln!(s, "   3. T = S − P0 = {}", xyz(t.t_vec));
                let _ = writeln!(s, "   4. Dt = det(T, E1, E2) = {dt}");
                let _ = writeln!(
                    s,
                    "   5. t* = Dt/D0 = {}{}",
                    t.t_star.expect("t*"),
                    stop(t, 5, "not in (t_min, t_max): behind the origin")
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
                s,
                ray,
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
                        t,
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
                            t,
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

/// Ray–box: the record of [`crate::shapes::aabb::intersect`] for the box `lo` … `hi`.
pub fn aabb<T: Real>(s: &mut String, ray: &Ray<T>, lo: T::V, hi: T::V, t: &BoxTest<T>) -> Value {
    let method = t.method;
    head(
        s,
        ray,
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
            real(a.inv_dir),
            real(a.t_entry),
            real(a.t_exit)
        );
    }
    let _ = writeln!(s, "  t_near = max(t_min, entries) = {}", real(t.t_near));
    let _ = writeln!(
        s,
        "  t_far  = min(t_max, exits){} = {}",
        if method == BoxMethod::Robust {
            " × (1 + 2γ₃)"
        } else {
            ""
        },
        real(t.t_far)
    );
    let _ = writeln!(
        s,
        "  {}",
        if t.hit {
            format!(
                "t_near {} t_far: the ray passes through the box",
                if method == BoxMethod::Robust {
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
    Value::Object(m)
}

/// The title and the ray.
fn head<T: Real>(s: &mut String, ray: &Ray<T>, what: &str) {
    let _ = writeln!(s, "{what} ({})", T::NAME);
    let _ = writeln!(
        s,
        "  ray        S = {}, Q = {}, t in ({}, ∞)",
        v::<T>(ray.origin),
        v::<T>(ray.dir),
        ray.t_min
    );
}

fn v<T: Real>(x: T::V) -> String {
    format!("({}, {}, {})", x.at(0), x.at(1), x.at(2))
}

/// A number in the one formatter's exact style, in its own precision.
fn real<T: Real>(x: T) -> String {
    if T::NAME == "f32" {
        // f32 → f64 → f32 is exact: this is the f32 the kernel computed.
        fmt(x.to_f64() as f32, Style::Exact)
    } else {
        fmt64(x.to_f64(), Style::Exact)
    }
}

fn stop<T: Real>(t: &TriangleTest<T>, step: u8, why: &str) -> String {
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
