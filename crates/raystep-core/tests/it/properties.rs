//! Property tests for the intersection kernels (docs/NUMERICS.md): for finite inputs in reasonable
//! ranges no kernel reports NaN, and the textbook and robust formulations — and f32 and f64 —
//! agree wherever the answer is well conditioned.
//!
//! Every input is drawn in f64 and rounded to f32 first, so the f32 and f64 runs see the very
//! same numbers and the f64 reference (computed here, independently of the kernels) describes
//! exactly the case the f32 kernel was given.

use glam::DVec3;
use proptest::prelude::*;
use raystep_core::math::{Ray, Real, vec_from_f64};
use raystep_core::shapes::{
    BoxMethod, SphereMethod, TriangleMethod, aabb, plane, sphere, triangle,
};

/// Enough cases to cover the space, few enough that the file runs in a few seconds.
const CASES: u32 = 512;

type P3 = [f64; 3];

// ---------------------------------------------------------------------------------------------
// Strategies.

/// Rounds to the nearest f32 (and back), so both precisions get identical inputs.
fn f32r(x: f64) -> f64 {
    x as f32 as f64
}

fn f32r3(p: P3) -> P3 {
    p.map(f32r)
}

fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> + Clone {
    (lo.ln()..hi.ln()).prop_map(|x| f32r(x.exp()))
}

/// A coordinate in ±1e3.
fn coord() -> impl Strategy<Value = f64> + Clone {
    (-1e3..1e3f64).prop_map(f32r)
}

fn point() -> impl Strategy<Value = P3> + Clone {
    [coord(), coord(), coord()]
}

/// A non-zero direction of length 1e-2 … 1e2 (kernels must not assume unit directions), with
/// exactly-zero components now and then (axis-parallel rays: ±∞ reciprocals, parallel planes).
fn direction() -> impl Strategy<Value = P3> + Clone {
    direction_with_zeros(1)
}

/// A direction whose components are exactly zero with weight `zero_weight` in 6 + `zero_weight`.
fn direction_with_zeros(zero_weight: u32) -> impl Strategy<Value = P3> + Clone {
    let component = prop_oneof![zero_weight => Just(0.0), 6 => -1.0..1.0f64];
    (
        [component.clone(), component.clone(), component],
        log_uniform(1e-2, 1e2),
    )
        .prop_filter("non-zero direction", |(d, _)| {
            DVec3::from(*d).length() > 1e-2
        })
        .prop_map(|(d, s)| f32r3((DVec3::from(d).normalize() * s).to_array()))
}

/// The far end of the ray's interval: usually ∞, sometimes finite.
fn t_max() -> impl Strategy<Value = f64> + Clone {
    prop_oneof![3 => Just(f64::INFINITY), 1 => log_uniform(1e-1, 1e4)]
}

fn radius() -> impl Strategy<Value = f64> + Clone {
    log_uniform(1e-2, 1e2)
}

fn ray<T: Real>(o: P3, d: P3, t_max: f64) -> Ray<T> {
    Ray::new(
        vec_from_f64::<T>(o),
        vec_from_f64::<T>(d),
        T::lit(0.0),
        T::from_f64(t_max),
    )
    .unwrap_or_else(|e| panic!("the strategies make valid rays: {e}"))
}

/// Fails the case if any reported value is NaN.
fn no_nan<T: Real>(
    kernel: &str,
    fields: &[(&str, Option<T>)],
    record: &dyn std::fmt::Debug,
) -> Result<(), TestCaseError> {
    for (name, v) in fields {
        if let Some(v) = v {
            prop_assert!(
                !Real::to_f64(*v).is_nan(),
                "{kernel} ({}): `{name}` is NaN in {record:?}",
                T::NAME
            );
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Kernels run in precision T, checked for NaN; they return the hit distance as f64.

fn run_sphere<T: Real>(
    o: P3,
    d: P3,
    tm: f64,
    c: P3,
    r: f64,
    m: SphereMethod,
) -> Result<Option<f64>, TestCaseError> {
    let ray = ray::<T>(o, d, tm);
    let s = sphere::intersect(&ray, vec_from_f64::<T>(c), T::from_f64(r), m);
    let roots = s.roots.map_or([None, None], |[a, b]| [Some(a), Some(b)]);
    let fields = [
        ("a", Some(s.a)),
        ("b", Some(s.b)),
        ("c", Some(s.c)),
        ("discriminant", Some(s.discriminant)),
        ("delta_prime", s.delta_prime),
        ("q", s.q),
        ("roots[0]", roots[0]),
        ("roots[1]", roots[1]),
        ("t", s.t),
    ];
    no_nan(&format!("sphere {m:?}"), &fields, &s)?;
    if let Some(t) = s.t {
        prop_assert!(ray.accepts(t), "t = {t} outside the ray's interval: {s:?}");
        prop_assert!(roots.contains(&Some(t)), "t is not one of the roots: {s:?}");
    }
    Ok(s.t.map(|t| t.to_f64()))
}

/// `axis` = None: the general plane X·n = offset; Some(k): the plane X_k = offset.
fn run_plane<T: Real>(
    o: P3,
    d: P3,
    tm: f64,
    axis: Option<usize>,
    n: P3,
    offset: f64,
) -> Result<Option<f64>, TestCaseError> {
    let ray = ray::<T>(o, d, tm);
    let p = match axis {
        None => plane::general(&ray, vec_from_f64::<T>(n), T::from_f64(offset)),
        Some(k) => plane::axis(&ray, k, T::from_f64(offset)),
    };
    let fields = [
        ("denominator", Some(p.denominator)),
        ("numerator", Some(p.numerator)),
        ("t_raw", p.t_raw),
        ("t", p.t),
    ];
    no_nan(&format!("plane {axis:?}"), &fields, &p)?;
    prop_assert_eq!(p.parallel, p.denominator.to_f64() == 0.0, "{:?}", p);
    prop_assert!(p.t.is_none_or(|t| ray.accepts(t)), "{:?}", p);
    Ok(p.t.map(|t| t.to_f64()))
}

/// Returns the hit as (t, u, v).
fn run_triangle<T: Real>(
    o: P3,
    d: P3,
    tm: f64,
    v: [P3; 3],
    m: TriangleMethod,
) -> Result<Option<(f64, f64, f64)>, TestCaseError> {
    let ray = ray::<T>(o, d, tm);
    let tri = triangle::intersect(&ray, v.map(vec_from_f64::<T>), m);
    let e = tri.edges.map_or([None; 3], |e| e.map(Some));
    let fields = [
        ("det", Some(tri.det)),
        ("dt", tri.dt),
        ("du", tri.du),
        ("dv", tri.dv),
        ("edges[0]", e[0]),
        ("edges[1]", e[1]),
        ("edges[2]", e[2]),
        ("t_star", tri.t_star),
        ("u", tri.u),
        ("v", tri.v),
        ("t", tri.t),
    ];
    no_nan(&format!("triangle {m:?}"), &fields, &tri)?;
    prop_assert_eq!(tri.t.is_some(), tri.stopped_at == 12, "{:?}", tri);
    Ok(match (tri.t, tri.u, tri.v) {
        (Some(t), Some(u), Some(v)) => {
            prop_assert!(ray.accepts(t), "{:?}", tri);
            Some((t.to_f64(), u.to_f64(), v.to_f64()))
        }
        (Some(_), ..) => {
            return Err(TestCaseError::fail(format!(
                "a hit without barycentrics: {tri:?}"
            )));
        }
        _ => None,
    })
}

/// Returns whether the box is hit, with the f64 (t_near, t_far).
fn run_box<T: Real>(
    o: P3,
    d: P3,
    tm: f64,
    lo: P3,
    hi: P3,
    m: BoxMethod,
) -> Result<(bool, f64, f64), TestCaseError> {
    let ray = ray::<T>(o, d, tm);
    let b = aabb::intersect(&ray, vec_from_f64::<T>(lo), vec_from_f64::<T>(hi), m);
    let mut fields = vec![("t_near", Some(b.t_near)), ("t_far", Some(b.t_far))];
    for (i, a) in b.axes.iter().enumerate() {
        fields.push(("inv_dir", Some(a.inv_dir)));
        // docs/NUMERICS.md S20: a ray lying in a face plane with a zero direction component has slab
        // distances 0·∞ = NaN by policy (the slab then imposes no limit); anywhere else, never NaN.
        let in_face = d[i] == 0.0 && (o[i] == lo[i] || o[i] == hi[i]);
        if !in_face {
            fields.push(("t_entry", Some(a.t_entry)));
            fields.push(("t_exit", Some(a.t_exit)));
        }
    }
    no_nan(&format!("box {m:?}"), &fields, &b)?;
    Ok((b.hit, b.t_near.to_f64(), b.t_far.to_f64()))
}

// ---------------------------------------------------------------------------------------------
// Independent f64 references (on the f32-rounded inputs).

/// The squared distance from `c` to the ray's line, ‖f − (f·d/d·d)·d‖² with f = o − c.
fn line_distance(o: P3, d: P3, c: P3) -> f64 {
    let (f, d) = (DVec3::from(o) - DVec3::from(c), DVec3::from(d));
    (f - d * (f.dot(d) / d.dot(d))).length()
}

/// Möller–Trumbore by Cramer's rule in f64, without any early exit: (t, u, v) of the ray's line
/// and the triangle's plane, or None when they are parallel.
fn triangle_reference(o: P3, d: P3, v: [P3; 3]) -> Option<(f64, f64, f64)> {
    let [p0, p1, p2] = v.map(DVec3::from);
    let (e1, e2, s, nd) = (p1 - p0, p2 - p0, DVec3::from(o) - p0, -DVec3::from(d));
    let det = nd.dot(e1.cross(e2));
    (det != 0.0).then(|| {
        (
            s.dot(e1.cross(e2)) / det,
            nd.dot(s.cross(e2)) / det,
            nd.dot(e1.cross(s)) / det,
        )
    })
}

// ---------------------------------------------------------------------------------------------
// Shaped cases for the agreement tests: rays aimed near the primitive, so hits and misses both
// occur often.

/// A sphere, and a ray from `dist` away (in radii) aimed at a point within 1.5 r of the centre —
/// or, one time in four, pointing the opposite way (the sphere behind the ray).
fn aimed_sphere() -> impl Strategy<Value = (P3, P3, P3, f64)> {
    let aim = (
        direction(),
        0.0..1.5f64,
        log_uniform(1e-2, 1e2),
        prop::bool::weighted(0.25),
    );
    (point(), radius(), direction(), log_uniform(5e-2, 1e2), aim).prop_map(
        |(c, r, from, dist, (aim, aim_r, speed, away))| {
            let (cv, from, aim) = (
                DVec3::from(c),
                DVec3::from(from).normalize(),
                DVec3::from(aim).normalize(),
            );
            let o = f32r3((cv + from * (dist * r)).to_array());
            let target = cv + aim * (aim_r * r);
            let speed = if away { -speed } else { speed };
            let d = f32r3(((target - DVec3::from(o)).normalize() * speed).to_array());
            (o, d, c, r)
        },
    )
}

/// A triangle (size 1e-1 … 1e2 around a centre in ±1e3) and a ray aimed at the point with
/// barycentrics (1 − b1 − b2, b1, b2), b1, b2 ∈ [−0.5, 1.5], from up to 1e3 away — or, one time
/// in four, pointing the opposite way (the triangle behind the ray).
fn aimed_triangle() -> impl Strategy<Value = (P3, P3, [P3; 3])> {
    let offset = || [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64];
    (
        point(),
        log_uniform(1e-1, 1e2),
        [offset(), offset(), offset()],
        (-0.5..1.5f64, -0.5..1.5f64),
        direction(),
        log_uniform(1e-1, 1e3),
        (log_uniform(1e-2, 1e2), prop::bool::weighted(0.25)),
    )
        .prop_map(|(c, size, offs, (b1, b2), from, dist, (speed, away))| {
            let speed = if away { -speed } else { speed };
            let cv = DVec3::from(c);
            let v = offs.map(|o| f32r3((cv + DVec3::from(o) * size).to_array()));
            let [p0, p1, p2] = v.map(DVec3::from);
            let target = p0 * (1.0 - b1 - b2) + p1 * b1 + p2 * b2;
            let o = f32r3((target + DVec3::from(from).normalize() * dist).to_array());
            let d = f32r3(((target - DVec3::from(o)).normalize() * speed).to_array());
            (o, d, v)
        })
}

/// Relative agreement of two distances.
fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs())
}

// ---------------------------------------------------------------------------------------------
// No NaN, ever, for finite inputs.

fn sphere_no_nan(o: P3, d: P3, tm: f64, c: P3, r: f64) -> Result<(), TestCaseError> {
    for m in [SphereMethod::Textbook, SphereMethod::Stable] {
        run_sphere::<f32>(o, d, tm, c, r, m)?;
        run_sphere::<f64>(o, d, tm, c, r, m)?;
    }
    Ok(())
}

fn plane_no_nan(o: P3, d: P3, tm: f64, n: P3, offset: f64, k: usize) -> Result<(), TestCaseError> {
    // The scene loader stores general planes with a unit normal.
    let n = f32r3(DVec3::from(n).normalize().to_array());
    for axis in [None, Some(k)] {
        run_plane::<f32>(o, d, tm, axis, n, offset)?;
        run_plane::<f64>(o, d, tm, axis, n, offset)?;
    }
    Ok(())
}

fn triangle_no_nan(o: P3, d: P3, tm: f64, v: [P3; 3]) -> Result<(), TestCaseError> {
    for m in [TriangleMethod::MollerTrumbore, TriangleMethod::Watertight] {
        run_triangle::<f32>(o, d, tm, v, m)?;
        run_triangle::<f64>(o, d, tm, v, m)?;
    }
    Ok(())
}

/// `flat` < 3 makes the box zero-thick along that axis (an axis-aligned quad, docs/NUMERICS.md S22).
fn box_no_nan(o: P3, d: P3, tm: f64, c: P3, half: P3, flat: usize) -> Result<(), TestCaseError> {
    let half: P3 = std::array::from_fn(|i| if i == flat { 0.0 } else { half[i] });
    let lo = std::array::from_fn(|i| f32r(c[i] - half[i]));
    let hi = std::array::from_fn(|i| f32r(c[i] + half[i]));
    for m in [BoxMethod::Plain, BoxMethod::Robust] {
        run_box::<f32>(o, d, tm, lo, hi, m)?;
        run_box::<f64>(o, d, tm, lo, hi, m)?;
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Exact invariance.

/// Scaling the direction by a power of two k changes no rounding anywhere: every product,
/// quotient and square root of the kernels scales exactly (barring overflow and underflow,
/// out of reach for these ranges with |k| ≤ 2²⁰). So every kernel must give the same hit or miss,
/// with t divided by k exactly and the very same barycentrics — no conditioning needed, this
/// holds bit for bit near edges, at grazing angles, everywhere.
fn scale_invariance(
    (o, d, c, r): (P3, P3, P3, f64),
    (to, td, tv): (P3, P3, [P3; 3]),
    n: P3,
    offset: f64,
    half: P3,
    j: i32,
) -> Result<(), TestCaseError> {
    let k = 2f64.powi(j);
    let dk = d.map(|x| x * k);
    let tdk = td.map(|x| x * k);
    let inf = f64::INFINITY;
    let scaled = |t: Option<f64>| t.map(|t| t / k);
    for m in [SphereMethod::Textbook, SphereMethod::Stable] {
        let a = run_sphere::<f32>(o, d, inf, c, r, m)?;
        let b = run_sphere::<f32>(o, dk, inf, c, r, m)?;
        prop_assert_eq!(scaled(a), b, "sphere {:?}, k = 2^{}", m, j);
    }
    let n = f32r3(DVec3::from(n).normalize().to_array());
    for axis in [None, Some(0)] {
        let a = run_plane::<f32>(o, d, inf, axis, n, offset)?;
        let b = run_plane::<f32>(o, dk, inf, axis, n, offset)?;
        prop_assert_eq!(scaled(a), b, "plane {:?}, k = 2^{}", axis, j);
    }
    for m in [TriangleMethod::MollerTrumbore, TriangleMethod::Watertight] {
        let a = run_triangle::<f32>(to, td, inf, tv, m)?;
        let b = run_triangle::<f32>(to, tdk, inf, tv, m)?;
        prop_assert_eq!(
            a.map(|(t, u, v)| (t / k, u, v)),
            b,
            "triangle {:?}, k = 2^{}: ray {:?} + t·{:?}, vertices {:?}",
            m,
            j,
            to,
            td,
            tv
        );
    }
    let lo: P3 = std::array::from_fn(|i| f32r(c[i] - half[i]));
    let hi: P3 = std::array::from_fn(|i| f32r(c[i] + half[i]));
    for m in [BoxMethod::Plain, BoxMethod::Robust] {
        let a = run_box::<f32>(o, d, inf, lo, hi, m)?;
        let b = run_box::<f32>(o, dk, inf, lo, hi, m)?;
        prop_assert_eq!(a.0, b.0, "box {:?}, k = 2^{}", m, j);
    }
    Ok(())
}

/// The smallest case `direction_scale_invariance` keeps finding, written out: a 0.1-unit
/// triangle 500 units below the origin, hit head-on. Möller–Trumbore hits it at t = 500/|d| for
/// any |d|; the watertight test must too, whatever the length of the direction.
#[test]
fn watertight_hit_does_not_depend_on_direction_length() {
    use glam::Vec3;
    let tri = [
        Vec3::ZERO,
        Vec3::new(0.0, -0.1, 0.0),
        Vec3::new(0.1, 0.0, 0.0),
    ];
    for len in [1.0f32, 0.1, 0.01, 0.001] {
        let ray = Ray::<f32>::infinite(Vec3::new(0.02, -0.02, 500.0), Vec3::new(0.0, 0.0, -len));
        let ray = ray.unwrap();
        let mt = triangle::moller_trumbore(&ray, tri);
        let wt = triangle::watertight(&ray, tri);
        let expect = 500.0 / len;
        assert!(
            mt.t.is_some_and(|t| (t - expect).abs() <= expect * 1e-6),
            "MT, |d| = {len}: {mt:?}"
        );
        assert!(
            wt.t.is_some_and(|t| (t - expect).abs() <= expect * 1e-6),
            "watertight misses a head-on hit at t = {expect} with |d| = {len}: {wt:?}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Agreement where the answer is well conditioned.

/// Textbook and stable sphere agree (hit/miss, and t to 1e-3 relative in f32) when the ray's
/// line passes the centre at less than 0.9 r or more than 1.1 r and the sphere is nearer than
/// 100 r (so the textbook c = f·f − r² keeps r) — and, beyond those two conditions, the origin
/// is not within 1% of the surface (where a root near t = 0 makes hit/miss a matter of
/// rounding). f32 and f64 agree on hit/miss in the same cases, and all match the exact answer.
fn sphere_agreement((o, d, c, r): (P3, P3, P3, f64)) -> Result<(), TestCaseError> {
    let rho = line_distance(o, d, c);
    let dist = (DVec3::from(o) - DVec3::from(c)).length();
    prop_assume!(rho < 0.9 * r || rho > 1.1 * r);
    prop_assume!(dist < 100.0 * r && (dist - r).abs() > 0.01 * r);
    let inf = f64::INFINITY;
    let tb = run_sphere::<f32>(o, d, inf, c, r, SphereMethod::Textbook)?;
    let st = run_sphere::<f32>(o, d, inf, c, r, SphereMethod::Stable)?;
    prop_assert_eq!(
        tb.is_some(),
        st.is_some(),
        "textbook {:?} vs stable {:?} (ρ/r = {})",
        tb,
        st,
        rho / r
    );
    if let (Some(a), Some(b)) = (tb, st) {
        prop_assert!(close(a, b, 1e-3), "textbook t = {a}, stable t = {b}");
    }
    for m in [SphereMethod::Textbook, SphereMethod::Stable] {
        let t32 = run_sphere::<f32>(o, d, inf, c, r, m)?;
        let t64 = run_sphere::<f64>(o, d, inf, c, r, m)?;
        prop_assert_eq!(
            t32.is_some(),
            t64.is_some(),
            "{:?}: f32 {:?} vs f64 {:?}",
            m,
            t32,
            t64
        );
        if let (Some(a), Some(b)) = (t32, t64) {
            prop_assert!(close(a, b, 1e-3), "{m:?}: f32 t = {a}, f64 t = {b}");
        }
    }
    // The exact answer: the line meets the sphere iff ρ < r, and a hit needs the far root
    // ahead of the origin (always, from inside; from outside, iff the ray heads for the centre).
    let f = DVec3::from(o) - DVec3::from(c);
    let ahead = f.dot(DVec3::from(d)) < 0.0 || dist < r;
    prop_assert_eq!(st.is_some(), rho < r && ahead);
    Ok(())
}

/// u = 2⁻²⁴, f32's unit roundoff.
const U32: f64 = f32::EPSILON as f64 / 2.0;

/// Möller–Trumbore and watertight agree on hit/miss and on t, u, v when the ray meets the
/// triangle's plane well inside (all barycentrics > 1e-3) or well outside (one < −1e-3) the
/// triangle; f32 and f64 agree on hit/miss there, and all match the exact answer.
///
/// "Well" must also beat the f32 rounding of the inputs themselves: both tests work on
/// coordinates of magnitude `extent`, while the triangle seen along the ray is only h·|cos θ|
/// wide (h its smallest altitude), so the barycentrics carry an error of a few
/// u·extent/(h·|cos θ|). A grazing ray from 400 units away at a 0.7-unit triangle
/// (|cos θ| = 0.03) has barycentrics uncertain by ~1e-3 in f32: neither answer is wrong there.
fn triangle_agreement((o, d, v): (P3, P3, [P3; 3])) -> Result<(), TestCaseError> {
    let Some((t_ref, u_ref, v_ref)) = triangle_reference(o, d, v) else {
        return Err(TestCaseError::reject("parallel"));
    };
    let b = [1.0 - u_ref - v_ref, u_ref, v_ref];
    let min_b = b.iter().copied().fold(f64::INFINITY, f64::min);
    let [p0, p1, p2] = v.map(DVec3::from);
    let n = (p1 - p0).cross(p2 - p0);
    let max_edge = (p1 - p0)
        .length()
        .max((p2 - p1).length())
        .max((p0 - p2).length());
    let h = n.length() / max_edge;
    let dv = DVec3::from(d);
    let cos = n.normalize().dot(dv.normalize()).abs();
    let extent = [o, v[0], v[1], v[2]]
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let rounding = 32.0 * U32 * extent / (h * cos);
    prop_assume!(min_b.abs() > rounding.max(1e-3));
    // The origin is clearly off the triangle's plane, so `t > t_min` is not a matter of
    // rounding either. The watertight test refuses hits within its conservative error bound of
    // t = 0 (pbrt-v4), which as a distance from the plane is about γ₅·E³/A (E the largest vertex
    // distance from the origin, A the area): keep well clear of 1e-5·E³/A.
    let perp = t_ref.abs() * dv.length() * cos;
    let reach = v
        .iter()
        .map(|p| (DVec3::from(*p) - DVec3::from(o)).length())
        .fold(0.0, f64::max);
    prop_assume!(perp > (1e-5 * reach.powi(3) / (0.5 * n.length())).max(1e-2));
    let inside = min_b > 1e-3 && t_ref > 0.0;
    let inf = f64::INFINITY;
    let mt = run_triangle::<f32>(o, d, inf, v, TriangleMethod::MollerTrumbore)?;
    let wt = run_triangle::<f32>(o, d, inf, v, TriangleMethod::Watertight)?;
    let why = format!("reference b = {b:?}, t = {t_ref}; ray {o:?} + t·{d:?}, vertices {v:?}");
    prop_assert_eq!(mt.is_some(), inside, "Möller–Trumbore {:?}, {}", mt, why);
    prop_assert_eq!(wt.is_some(), inside, "watertight {:?}, {}", wt, why);
    if let (Some(a), Some(w)) = (mt, wt) {
        // t inherits the inputs' rounding too: u·extent across the plane is u·extent/|cos θ|
        // along the ray, relative to the distance travelled, |t·d|.
        let tol_t = (32.0 * U32 * extent / (t_ref.abs() * dv.length() * cos)).max(1e-3);
        prop_assert!(
            close(a.0, w.0, tol_t),
            "t: MT {} vs WT {} (±{tol_t:e})",
            a.0,
            w.0
        );
        // The same rounding bound limits how closely the barycentrics can agree.
        let tol = rounding.max(1e-3);
        let (du, dv) = ((a.1 - w.1).abs(), (a.2 - w.2).abs());
        prop_assert!(
            du < tol && dv < tol,
            "u, v: MT {a:?} vs WT {w:?} (±{tol:e})"
        );
    }
    for m in [TriangleMethod::MollerTrumbore, TriangleMethod::Watertight] {
        let hit64 = run_triangle::<f64>(o, d, inf, v, m)?;
        prop_assert_eq!(
            hit64.is_some(),
            inside,
            "{:?} in f64: {:?}, {}",
            m,
            hit64,
            why
        );
    }
    Ok(())
}

/// f32 and f64 agree with the exact answer on plane hits unless the ray is nearly parallel
/// (|d̂·n| < 1e-3) or starts within 1e-2 of the plane.
fn plane_agreement(o: P3, d: P3, n: P3, offset: f64, k: usize) -> Result<(), TestCaseError> {
    let n = f32r3(DVec3::from(n).normalize().to_array());
    for (axis, nv) in [(None, DVec3::from(n)), (Some(k), DVec3::AXES[k])] {
        let den = DVec3::from(d).dot(nv);
        let num = offset - DVec3::from(o).dot(nv);
        if den.abs() < 1e-3 * DVec3::from(d).length() || num.abs() < 1e-2 {
            continue;
        }
        let exact = num / den > 0.0;
        let inf = f64::INFINITY;
        let (h32, h64) = (
            run_plane::<f32>(o, d, inf, axis, n, offset)?,
            run_plane::<f64>(o, d, inf, axis, n, offset)?,
        );
        prop_assert_eq!(h32.is_some(), exact, "{:?} f32: {:?}", axis, h32);
        prop_assert_eq!(h64.is_some(), exact, "{:?} f64: {:?}", axis, h64);
    }
    Ok(())
}

/// Plain and robust slab tests, in f32 and f64, agree with the exact answer when the overlap of
/// the ray's interval with the box is clearly non-empty or clearly empty.
fn box_agreement(o: P3, d: P3, c: P3, half: P3) -> Result<(), TestCaseError> {
    let lo: P3 = std::array::from_fn(|i| f32r(c[i] - half[i]));
    let hi: P3 = std::array::from_fn(|i| f32r(c[i] + half[i]));
    // The exact slab interval (the strategy gives no zero components here, so no ∞·0).
    let (mut near, mut far) = (0.0f64, f64::INFINITY);
    for i in 0..3 {
        let (a, b) = ((lo[i] - o[i]) / d[i], (hi[i] - o[i]) / d[i]);
        near = near.max(a.min(b));
        far = far.min(a.max(b));
    }
    let scale = near.abs().max(far.abs()).max(1.0 / DVec3::from(d).length());
    prop_assume!((far - near).abs() > 1e-3 * scale);
    let exact = near < far;
    let inf = f64::INFINITY;
    for m in [BoxMethod::Plain, BoxMethod::Robust] {
        prop_assert_eq!(
            run_box::<f32>(o, d, inf, lo, hi, m)?.0,
            exact,
            "{:?} f32",
            m
        );
        prop_assert_eq!(
            run_box::<f64>(o, d, inf, lo, hi, m)?.0,
            exact,
            "{:?} f64",
            m
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(CASES))]

    #[test]
    fn sphere_never_nan(
        o in point(), d in direction(), tm in t_max(), c in point(), r in radius(),
    ) {
        sphere_no_nan(o, d, tm, c, r)?;
    }

    #[test]
    fn aimed_sphere_never_nan((o, d, c, r) in aimed_sphere(), tm in t_max()) {
        sphere_no_nan(o, d, tm, c, r)?;
    }

    #[test]
    fn plane_never_nan(
        o in point(), d in direction(), tm in t_max(), n in direction(), offset in coord(),
        k in 0..3usize,
    ) {
        plane_no_nan(o, d, tm, n, offset, k)?;
    }

    /// Now and then a degenerate triangle (docs/NUMERICS.md S15): two equal vertices, or all three.
    #[test]
    fn triangle_never_nan(
        o in point(), d in direction(), tm in t_max(), v in [point(), point(), point()],
        degenerate in 0..4u8,
    ) {
        let v = match degenerate {
            0 => [v[0], v[1], v[1]],
            1 => [v[0], v[0], v[0]],
            _ => v,
        };
        triangle_no_nan(o, d, tm, v)?;
    }

    #[test]
    fn aimed_triangle_never_nan((o, d, v) in aimed_triangle(), tm in t_max()) {
        triangle_no_nan(o, d, tm, v)?;
    }

    #[test]
    fn box_never_nan(
        o in point(), d in direction(), tm in t_max(), c in point(),
        half in [radius(), radius(), radius()], flat in 0..4usize,
    ) {
        box_no_nan(o, d, tm, c, half, flat)?;
    }

    #[test]
    fn direction_scale_invariance(
        sphere in aimed_sphere(), tri in aimed_triangle(), n in direction(), offset in coord(),
        half in [radius(), radius(), radius()], j in -20..=20i32,
    ) {
        scale_invariance(sphere, tri, n, offset, half, j)?;
    }

    #[test]
    fn sphere_methods_and_precisions_agree(case in aimed_sphere()) {
        sphere_agreement(case)?;
    }

    #[test]
    fn triangle_methods_and_precisions_agree(case in aimed_triangle()) {
        triangle_agreement(case)?;
    }

    #[test]
    fn plane_precisions_agree(
        o in point(), d in direction(), n in direction(), offset in coord(), k in 0..3usize,
    ) {
        plane_agreement(o, d, n, offset, k)?;
    }

    #[test]
    fn box_methods_and_precisions_agree(
        o in point(), d in direction_with_zeros(0), c in point(),
        half in [radius(), radius(), radius()],
    ) {
        box_agreement(o, d, c, half)?;
    }
}
