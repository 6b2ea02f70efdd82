//! `raystep intersect`: the sphere, plane, triangle and box calculators against hand-derived
//! numbers and The Ray Tracer Challenge's published vectors.

use super::*;

/// S = (0, 0, −5), Q = (0, 0, 1), unit sphere at the origin (RTC ch. 5 "A ray intersects a
/// sphere at two points"): f = S − G = (0, 0, −5), a = Q·Q = 1, b = 2 f·Q = −10,
/// c = f·f − r² = 25 − 1 = 24, Δ = b² − 4ac = 100 − 96 = 4 (stable: b′ = −f·Q = 5,
/// Δ′ = r² − ‖f + (b′/a)Q‖² = 1 − ‖(0, 0, 0)‖² = 1, 4aΔ′ = 4), roots (10 ∓ 2)/2 = 4, 6; t = 4.
/// All are small integers, exact in f32 and f64, so they are compared exactly.
#[test]
fn sphere_enter_exit_all_methods_and_precisions() {
    for m in METHODS {
        for p in PRECISIONS {
            let v = unit_sphere("0,0,-5", "0,0,1", &format!("--method {m} --precision {p}"));
            let what = format!("{m} {p}: {v}");
            assert_eq!(num(&v, "a"), 1.0, "{what}");
            assert_eq!(num(&v, "b"), -10.0, "{what}");
            assert_eq!(num(&v, "c"), 24.0, "{what}");
            assert_eq!(num(&v, "discriminant"), 4.0, "{what}");
            assert_eq!(nums(&v["roots"]), [4.0, 6.0], "{what}");
            assert_eq!(v["case"], "enter-exit", "{what}");
            assert_eq!(num(&v, "t"), 4.0, "{what}");
            assert_eq!(v["hit"], true, "{what}");
        }
    }
}

/// S = (0, 1, −5) (RTC "A ray intersects a sphere at a tangent"): f = (0, 1, −5), b = −10,
/// c = 1 + 25 − 1 = 25, Δ = 100 − 100 = 0 (stable: f + 5Q = (0, 1, 0), Δ′ = 1 − 1 = 0);
/// the double root is 10/2 = 5.
#[test]
fn sphere_tangent() {
    for m in METHODS {
        for p in PRECISIONS {
            let v = unit_sphere("0,1,-5", "0,0,1", &format!("--method {m} --precision {p}"));
            let what = format!("{m} {p}: {v}");
            assert_eq!(num(&v, "c"), 25.0, "{what}");
            assert_eq!(num(&v, "discriminant"), 0.0, "{what}");
            assert_eq!(v["case"], "tangent", "{what}");
            assert_eq!(nums(&v["roots"]), [5.0, 5.0], "{what}");
            assert_eq!(num(&v, "t"), 5.0, "{what}");
        }
    }
}

/// S = (0, 2, −5) (RTC "A ray misses a sphere"): c = 4 + 25 − 1 = 28,
/// Δ = b² − 4ac = 100 − 4·1·28 = −12 (stable: f + 5Q = (0, 2, 0), Δ′ = 1 − 4 = −3, 4aΔ′ = −12).
#[test]
fn sphere_miss() {
    for m in METHODS {
        for p in PRECISIONS {
            let v = unit_sphere("0,2,-5", "0,0,1", &format!("--method {m} --precision {p}"));
            let what = format!("{m} {p}: {v}");
            assert_eq!(num(&v, "c"), 28.0, "{what}");
            assert!(num(&v, "discriminant") < 0.0, "{what}");
            assert_eq!(num(&v, "discriminant"), -12.0, "{what}");
            assert_eq!(v["case"], "miss", "{what}");
            assert_eq!(v["roots"], json!([]), "{what}");
            assert!(v["t"].is_null(), "{what}");
            assert_eq!(v["hit"], false, "{what}");
        }
    }
}

/// S = origin (RTC "A ray originates inside a sphere"): f = 0, a = 1, b = 0, c = −1,
/// Δ = 0 + 4 = 4, roots (0 ∓ 2)/2 = −1, 1; −1 is behind the origin, so t = 1 (the far root).
/// S = (0, 0, 5) (RTC "A sphere is behind a ray"): b = 10, c = 24, roots (−10 ∓ 2)/2 = −6, −4:
/// both behind, no hit.
#[test]
fn sphere_inside_and_behind() {
    for m in METHODS {
        for p in PRECISIONS {
            let flags = format!("--method {m} --precision {p}");
            let v = unit_sphere("0,0,0", "0,0,1", &flags);
            let what = format!("{m} {p}: {v}");
            assert_eq!(num(&v, "b"), 0.0, "{what}");
            assert_eq!(num(&v, "c"), -1.0, "{what}");
            assert_eq!(nums(&v["roots"]), [-1.0, 1.0], "{what}");
            assert_eq!(num(&v, "t"), 1.0, "{what}");
            assert_eq!(v["hit"], true, "{what}");

            let v = unit_sphere("0,0,5", "0,0,1", &flags);
            let what = format!("{m} {p}: {v}");
            assert_eq!(nums(&v["roots"]), [-6.0, -4.0], "{what}");
            assert!(v["t"].is_null(), "{what}");
            assert_eq!(v["hit"], false, "{what}");
        }
    }
}

/// With --tmin 4.5 the near root 4 is ignored (hits at t ≤ tmin do not count) and the far
/// root 6 is taken.
#[test]
fn sphere_tmin_picks_the_far_root() {
    for m in METHODS {
        let v = unit_sphere("0,0,-5", "0,0,1", &format!("--method {m} --tmin 4.5"));
        assert_eq!(nums(&v["roots"]), [4.0, 6.0], "{m}: {v}");
        assert_eq!(num(&v, "t"), 6.0, "{m}: {v}");
        assert_eq!(v["hit"], true, "{m}: {v}");
    }
}

/// The far sphere (docs/NUMERICS.md S1): unit sphere at the origin, S = (0.5, 0, −4100),
/// Q = (0, 0, 1). Exactly: f = S, b = −8200, c = 0.25 + 4100² − 1 = 16 809 999.25,
/// Δ = 8200² − 4c = 67 240 000 − 67 239 997 = 3, near root (8200 − √3)/2 = 4100 − √0.75
/// ≈ 4099.13397. f64 holds all of these exactly.
/// In f32, 4100² = 16 810 000 lies in [2²⁴, 2²⁵) where the spacing is 2: f·f = 16 810 000.25
/// rounds to 16 810 000; minus 1 gives 16 809 999, a tie that rounds to the even 16 810 000 —
/// so the textbook Δ = 67 240 000 − 67 240 000 = 0 (both exact at spacing 8): the radius is
/// lost and the root is 4100, not 4099.134. The stable form gets Δ′ = r² − ‖(0.5, 0, 0)‖² = 0.75
/// from a vector difference and keeps the near root to within the f32 spacing at 4100 (2⁻¹¹).
#[test]
fn far_sphere_f32_textbook_loses_the_radius() {
    let exact = 4100.0 - 0.75f64.sqrt();
    let run = |m: &str, p: &str| {
        unit_sphere(
            "0.5,0,-4100",
            "0,0,1",
            &format!("--method {m} --precision {p}"),
        )
    };

    let tb64 = run("textbook", "f64");
    close(num(&tb64, "discriminant"), 3.0, 1e-9, "f64 textbook Δ");
    close(num(&tb64, "t"), exact, 1e-6, "f64 textbook near root");

    let tb32 = run("textbook", "f32");
    let t = tb32["t"].as_f64();
    assert!(
        t.is_none_or(|t| (t - exact).abs() > 0.1),
        "f32 textbook should not find the near root {exact}: {tb32}"
    );

    let st32 = run("stable", "f32");
    close(num(&st32, "discriminant"), 3.0, 1e-3, "f32 stable Δ");
    close(num(&st32, "t"), exact, 1e-3, "f32 stable near root");

    let st64 = run("stable", "f64");
    close(num(&st64, "t"), exact, 1e-9, "f64 stable near root");
}

/// The explanation names the intermediates in the order they are computed.
#[test]
fn sphere_plain_output_names_the_intermediates_in_order() {
    for m in METHODS {
        let out = ok(&Cli::new(&format!(
            "intersect sphere --center 0,0,0 --radius 1 --origin 0,0,-5 --dir 0,0,1 --method {m}"
        )));
        assert_in_order(&out, &["a = ", "b = ", "c = ", "Δ = b² − 4ac"]);
    }
}

// ---------------------------------------------------------------------------------------------
// intersect plane
// ---------------------------------------------------------------------------------------------

/// RTC ch. 9 "Intersecting a plane from above": the plane y = 0 (point (0, 0, 0), normal
/// (0, 1, 0)), S = (0, 1, 0), Q = (0, −1, 0): denominator Q·n = −1, numerator
/// c − S·n = 0 − 1 = −1, t = 1. "From below": S = (0, −1, 0), Q = (0, 1, 0): numerator
/// 0 − (−1) = 1, denominator 1, t = 1.
#[test]
fn plane_general_rtc_vectors() {
    for p in PRECISIONS {
        let base = format!("intersect plane --point 0,0,0 --normal 0,1,0 --json --precision {p}");
        let v = json_of(&Cli::new(&base).and("--origin 0,1,0 --dir 0,-1,0"));
        assert_eq!(num(&v, "denominator"), -1.0, "{v}");
        assert_eq!(num(&v, "numerator"), -1.0, "{v}");
        assert_eq!(v["parallel"], false, "{v}");
        assert_eq!(num(&v, "t"), 1.0, "{v}");
        assert_eq!(v["hit"], true, "{v}");

        let v = json_of(&Cli::new(&base).and("--origin 0,-1,0 --dir 0,1,0"));
        assert_eq!(num(&v, "denominator"), 1.0, "{v}");
        assert_eq!(num(&v, "numerator"), 1.0, "{v}");
        assert_eq!(num(&v, "t"), 1.0, "{v}");
    }
}

/// The plane x + y + z = 6 given as point (1, 2, 3) and normal (1, 1, 1) (not unit length);
/// the ray S = (−1, 0, 0), Q = (1, 1, 1): −1 + t + t + t = 6, so t = 7/3. With the unit normal
/// n = (1, 1, 1)/√3: denominator Q·n = 3/√3 = √3, numerator c − S·n = 6/√3 + 1/√3 = 7/√3.
/// A negative vector component (--origin -1,0,0) is accepted as a value.
#[test]
fn plane_general_oblique_by_hand() {
    let run = |p: &str| {
        json_of(&Cli::new(&format!(
            "intersect plane --point 1,2,3 --normal 1,1,1 --origin -1,0,0 --dir 1,1,1 --precision {p} --json"
        )))
    };
    let v = run("f64");
    close(num(&v, "t"), 7.0 / 3.0, 1e-12, "f64 t");
    close(
        num(&v, "denominator"),
        3f64.sqrt(),
        1e-12,
        "f64 denominator",
    );
    close(
        num(&v, "numerator"),
        7.0 / 3f64.sqrt(),
        1e-12,
        "f64 numerator",
    );
    let v = run("f32");
    close(num(&v, "t"), 7.0 / 3.0, 1e-5, "f32 t");
    assert_eq!(v["hit"], true);
}

/// The axis-aligned shortcut y = −1 (`--offset -1`, a negative value), S = (−1, 3, 0),
/// Q = (0, −2, 0): denominator Q_y = −2, numerator c − S_y = −1 − 3 = −4, t = −4/−2 = 2.
#[test]
fn plane_axis_form_with_negative_offset() {
    let line = "intersect plane --axis y --offset -1 --origin -1,3,0 --dir 0,-2,0";
    let v = json_of(&Cli::new(line).and("--json"));
    assert_eq!(num(&v, "denominator"), -2.0, "{v}");
    assert_eq!(num(&v, "numerator"), -4.0, "{v}");
    assert_eq!(v["parallel"], false, "{v}");
    assert_eq!(num(&v, "t"), 2.0, "{v}");
    assert_eq!(v["hit"], true, "{v}");

    let out = ok(&Cli::new(line));
    assert!(
        out.contains("y = -1"),
        "the plane is named with its offset:\n{out}"
    );
    // The hit point S + 2Q = (−1, −1, 0).
    assert!(out.contains("(-1, -1, 0)"), "{out}");
}

/// Parallel rays: Q·n = 0 (RTC "Intersect with a ray parallel to the plane": S = (0, 10, 0),
/// Q = (0, 0, 1); "Intersect with a coplanar ray": S = (0, 0, 0)), and the axis form with
/// Q_y = 0. Never NaN: parallel true, hit false, t null.
#[test]
fn plane_parallel_rays_miss() {
    for origin in ["0,10,0", "0,0,0"] {
        let v = json_of(&Cli::new(&format!(
            "intersect plane --point 0,0,0 --normal 0,1,0 --origin {origin} --dir 0,0,1 --json"
        )));
        assert_eq!(num(&v, "denominator"), 0.0, "{origin}: {v}");
        assert_eq!(v["parallel"], true, "{origin}: {v}");
        assert_eq!(v["hit"], false, "{origin}: {v}");
        assert!(v["t"].is_null(), "{origin}: {v}");
    }
    let line = "intersect plane --axis y --offset -1 --origin -1,3,0 --dir 1,0,0";
    let v = json_of(&Cli::new(line).and("--json"));
    assert_eq!(num(&v, "denominator"), 0.0, "{v}");
    assert_eq!(v["parallel"], true, "{v}");
    assert_eq!(v["hit"], false, "{v}");
    assert!(v["t"].is_null(), "{v}");
    let out = ok(&Cli::new(line));
    assert!(out.contains("parallel"), "{out}");
}

/// S = (0, 1, 0) moving up, away from y = 0: t = (0 − 1)/1 = −1, behind the origin: no hit,
/// and not parallel either.
#[test]
fn plane_behind_the_origin() {
    let v = json_of(&Cli::new(
        "intersect plane --point 0,0,0 --normal 0,1,0 --origin 0,1,0 --dir 0,1,0 --json",
    ));
    assert_eq!(num(&v, "denominator"), 1.0, "{v}");
    assert_eq!(num(&v, "numerator"), -1.0, "{v}");
    assert_eq!(v["parallel"], false, "{v}");
    assert_eq!(v["hit"], false, "{v}");
    assert!(v["t"].is_null(), "{v}");
}

// ---------------------------------------------------------------------------------------------
// intersect triangle
// ---------------------------------------------------------------------------------------------

fn triangle(origin: &str, dir: &str, flags: &str) -> Value {
    json_of(&Cli::new(TRI).and(&format!("--origin {origin} --dir {dir} --json {flags}")))
}

/// E1 = P1 − P0 = (−1, −1, 0), E2 = P2 − P0 = (1, −1, 0),
/// E1 × E2 = (0, 0, (−1)(−1) − (−1)(1)) = (0, 0, 2). Ray S = (−0.2, 0.3, −2), Q = (0, 0, 1),
/// so −Q = (0, 0, −1): D0 = det(−Q, E1, E2) = −Q·(E1 × E2) = −2.
/// T = S − P0 = (−0.2, −0.7, −2); Dt = det(T, E1, E2) = T·(E1 × E2) = −4; t = −4/−2 = 2.
/// T × E2 = ((−0.7)(0) − (−2)(−1), (−2)(1) − (−0.2)(0), (−0.2)(−1) − (−0.7)(1)) = (−2, −2, 0.9):
/// Du = det(−Q, T, E2) = −Q·(T × E2) = −0.9, u = 0.45.
/// E1 × T = ((−1)(−2) − 0, 0 − (−1)(−2), (−1)(−0.7) − (−1)(−0.2)) = (2, −2, 0.5):
/// Dv = det(−Q, E1, T) = −0.5, v = 0.25. (0.2, 0.3 are inexact in binary: hence 1e-6.)
#[test]
fn triangle_hit_moller_trumbore_and_watertight() {
    for p in PRECISIONS {
        let v = triangle(
            "-0.2,0.3,-2",
            "0,0,1",
            &format!("--method moller-trumbore --precision {p}"),
        );
        let what = format!("{p}: {v}");
        assert_eq!(num(&v, "det"), -2.0, "{what}");
        close(num(&v, "dt"), -4.0, 1e-6, &what);
        close(num(&v, "du"), -0.9, 1e-6, &what);
        close(num(&v, "dv"), -0.5, 1e-6, &what);
        close(num(&v, "t"), 2.0, 1e-6, &what);
        close(num(&v, "u"), 0.45, 1e-6, &what);
        close(num(&v, "v"), 0.25, 1e-6, &what);
        assert_eq!(v["stopped_at"], 12, "{what}");
        assert_eq!(v["hit"], true, "{what}");

        let w = triangle(
            "-0.2,0.3,-2",
            "0,0,1",
            &format!("--method watertight --precision {p}"),
        );
        let what = format!("watertight {p}: {w}");
        // Q = (0, 0, 1): z is already the largest component (no permutation) and the shear is
        // Sx = Sy = −0/1 = 0, Sz = 1; the sheared vertices are Pᵢ − S = (0.2, 0.7, 2),
        // (−0.8, −0.3, 2), (1.2, −0.3, 2), and z′ = z·Sz = 2 for each.
        assert_eq!(w["permutation"], json!([0, 1, 2]), "{what}");
        assert_eq!(nums(&w["shear"]), [0.0, 0.0, 1.0], "{what}");
        let want = [[0.2, 0.7, 2.0], [-0.8, -0.3, 2.0], [1.2, -0.3, 2.0]];
        for (i, row) in want.iter().enumerate() {
            for (got, want) in nums(&w["sheared"][i]).iter().zip(row) {
                close(*got, *want, 1e-6, &what);
            }
        }
        assert_eq!(nums(&w["z_scaled"]), [2.0, 2.0, 2.0], "{what}");
        close(num(&w, "t"), 2.0, 1e-6, &what);
        close(num(&w, "u"), 0.45, 1e-6, &what);
        close(num(&w, "v"), 0.25, 1e-6, &what);
        assert_eq!(w["stopped_at"], 12, "{what}");
        assert_eq!(w["hit"], true, "{what}");
    }
}

/// A miss at each of the stop steps of Bailey's notes, with the intermediates after the stop null:
/// * step 2, parallel: Q = (0, 1, 0) lies in the triangle's plane z = 0: D0 = −Q·(0, 0, 2) = 0.
/// * step 5, behind: S = (0, 0.5, 2): T = (0, −0.5, 2), Dt = 2·2 = 4, t = 4/−2 = −2 ≤ 0.
/// * step 8, u out (RTC "A ray misses the p1-p3 edge"): S = (1, 1, −2): T = (1, 0, −2),
///   T × E2 = (−2, −2, −1), Du = 1, u = −0.5 < 0.
/// * step 11, v < 0 (RTC "misses the p1-p2 edge"): S = (−1, 1, −2): T = (−1, 0, −2),
///   T × E2 = (−2, −2, 1), Du = −1, u = 0.5; E1 × T = (2, −2, −1), Dv = 1, v = −0.5.
/// * step 11, u + v > 1 (RTC "misses the p2-p3 edge"): S = (0, −1, −2): T = (0, −2, −2),
///   T × E2 = (−2, −2, 2), Du = −2, u = 1; E1 × T = (2, −2, 2), Dv = −2, v = 1; u + v = 2.
///
/// In every case Dt = T·(0, 0, 2) = 2·T_z = −4 except where noted.
#[test]
fn triangle_misses_at_each_stop_step() {
    // (origin, dir, stopped_at, det, [dt, du, dv, u, v]); None = must be JSON null.
    type Case<'a> = (&'a str, &'a str, u64, f64, [Option<f64>; 5]);
    let cases: [Case; 5] = [
        ("0,-1,-2", "0,1,0", 2, 0.0, [None, None, None, None, None]),
        (
            "0,0.5,2",
            "0,0,1",
            5,
            -2.0,
            [Some(4.0), None, None, None, None],
        ),
        (
            "1,1,-2",
            "0,0,1",
            8,
            -2.0,
            [Some(-4.0), Some(1.0), None, Some(-0.5), None],
        ),
        (
            "-1,1,-2",
            "0,0,1",
            11,
            -2.0,
            [Some(-4.0), Some(-1.0), Some(1.0), Some(0.5), Some(-0.5)],
        ),
        (
            "0,-1,-2",
            "0,0,1",
            11,
            -2.0,
            [Some(-4.0), Some(-2.0), Some(-2.0), Some(1.0), Some(1.0)],
        ),
    ];
    for (origin, dir, step, det, values) in cases {
        let j = triangle(origin, dir, "--method moller-trumbore");
        let what = format!("S = {origin}, Q = {dir}: {j}");
        assert_eq!(j["stopped_at"], step, "{what}");
        assert_eq!(j["hit"], false, "{what}");
        assert!(j["t"].is_null(), "{what}");
        assert_eq!(num(&j, "det"), det, "{what}");
        for (key, want) in ["dt", "du", "dv", "u", "v"].into_iter().zip(values) {
            assert!(j.get(key).is_some(), "{what}: key {key} missing");
            match want {
                None => assert!(j[key].is_null(), "{what}: {key} should be null"),
                Some(w) => close(num(&j, key), w, 1e-6, &format!("{what}: {key}")),
            }
        }
        // The watertight test misses these rays too.
        let w = triangle(origin, dir, "--method watertight");
        assert_eq!(w["hit"], false, "watertight S = {origin}, Q = {dir}: {w}");
        assert!(w["t"].is_null(), "watertight S = {origin}, Q = {dir}: {w}");
    }
}

/// The numbered steps: all twelve for a hit, in order; after a stop, nothing further.
#[test]
fn triangle_plain_output_lists_steps_and_stops() {
    let run = |origin: &str, dir: &str| {
        ok(&Cli::new(TRI).and(&format!(
            "--origin {origin} --dir {dir} --method moller-trumbore"
        )))
    };
    let hit = run("-0.2,0.3,-2", "0,0,1");
    let steps: Vec<String> = (1..=12).map(|i| format!("{i}. ")).collect();
    let steps: Vec<&str> = steps.iter().map(String::as_str).collect();
    assert_in_order(&hit, &steps);

    let parallel = run("0,-1,-2", "0,1,0");
    assert!(line_index(&parallel, "2. ").is_some(), "{parallel}");
    for later in ["3. ", "4. ", "5. ", "12. "] {
        assert!(
            line_index(&parallel, later).is_none(),
            "step {later} after a stop at 2:\n{parallel}"
        );
    }
    assert!(parallel.contains("parallel"), "{parallel}");

    for (origin, last, next) in [
        ("0,0.5,2", "5. ", "6. "),
        ("1,1,-2", "8. ", "9. "),
        ("-1,1,-2", "11. ", "12. "),
    ] {
        let out = run(origin, "0,0,1");
        assert!(line_index(&out, last).is_some(), "{out}");
        assert!(
            line_index(&out, next).is_none(),
            "step {next} after a stop at {last}:\n{out}"
        );
        assert!(out.contains("no hit"), "{out}");
    }
}

// ---------------------------------------------------------------------------------------------
// intersect box
// ---------------------------------------------------------------------------------------------

fn cube(origin: &str, dir: &str, method: &str, precision: &str) -> Value {
    json_of(&Cli::new(CUBE).and(&format!(
        "--origin {origin} --dir {dir} --method {method} --precision {precision} --json"
    )))
}

/// RTC ch. 12 "A ray intersects a cube": from each face, the slab along the ray's axis gives
/// 4 and 6 (e.g. S_x = 5, Q_x = −1: (1 − 5)/−1 = 4, (−1 − 5)/−1 = 6); the other two slabs are
/// (−∞, ∞) because S lies inside them and Q is 0 there. The plain test reports t_far = 6
/// exactly; the robust test enlarges t_far by (1 + 2γ₃), γ₃ = 3u/(1 − 3u), about 3.6e-7
/// relative in f32 (u = 2⁻²⁴), so t_far ∈ [6, 6·(1 + 1e-6)].
/// Inside (RTC's S = (0, 0.5, 0), Q = +z): the z slab is (−1, 1), so
/// t_near = max(t_min = 0, −1) = 0 and t_far ≈ 1.
#[test]
fn box_rtc_cube_hits() {
    let hits = [
        ("5,0.5,0", "-1,0,0"),
        ("-5,0.5,0", "1,0,0"),
        ("0.5,5,0", "0,-1,0"),
        ("0.5,-5,0", "0,1,0"),
        ("0.5,0,5", "0,0,-1"),
        ("0.5,0,-5", "0,0,1"),
    ];
    for m in ["plain", "robust"] {
        for p in PRECISIONS {
            for (o, d) in hits {
                let v = cube(o, d, m, p);
                let what = format!("{m} {p} S = {o}, Q = {d}: {v}");
                assert_eq!(v["hit"], true, "{what}");
                assert_eq!(num(&v, "t_near"), 4.0, "{what}");
                assert_eq!(num(&v, "t"), 4.0, "{what}");
                let far = num(&v, "t_far");
                if m == "plain" {
                    assert_eq!(far, 6.0, "{what}");
                } else {
                    assert!((6.0..=6.0 * (1.0 + 1e-6)).contains(&far), "{what}");
                }
            }
            let v = cube("0,0.5,0", "0,0,1", m, p);
            let what = format!("{m} {p} inside: {v}");
            assert_eq!(v["hit"], true, "{what}");
            assert_eq!(num(&v, "t_near"), 0.0, "{what}");
            close(num(&v, "t_far"), 1.0, 1e-6, &what);
        }
    }
}

/// RTC ch. 12 "A ray misses a cube": the slabs do not overlap (e.g. S = (2, 0, 2), Q = −z: a ray
/// at x = 2 with Q_x = 0 is never inside the x slab). Both methods miss; t is null.
#[test]
fn box_rtc_cube_misses() {
    let misses = [
        ("-2,0,0", "0.2673,0.5345,0.8018"),
        ("0,-2,0", "0.8018,0.2673,0.5345"),
        ("0,0,-2", "0.5345,0.8018,0.2673"),
        ("2,0,2", "0,0,-1"),
        ("0,2,2", "0,-1,0"),
        ("2,2,0", "-1,0,0"),
    ];
    for m in ["plain", "robust"] {
        for (o, d) in misses {
            let v = cube(o, d, m, "f32");
            assert_eq!(v["hit"], false, "{m} S = {o}, Q = {d}: {v}");
            assert!(v["t"].is_null(), "{m} S = {o}, Q = {d}: {v}");
        }
    }
}

/// A zero-thickness box (the quad z = 0, x, y ∈ [0, 1]) and the oblique ray S = (0.2, 0.3, −1),
/// Q = (0.3, 0.2, 1): the z slab gives t = (0 − (−1))/1 = 1 at both planes; x gives
/// (−0.2/0.3, 0.8/0.3) and y (−0.3/0.2, 0.7/0.2), both containing 1. So t_near = t_far = 1 and
/// the robust test (≤, t_far enlarged) hits at t = 1: the point (0.5, 0.5, 0), inside the quad.
#[test]
fn box_zero_thickness_hit_by_robust() {
    let v = json_of(&Cli::new(
        "intersect box --min 0,0,0 --max 1,1,0 --origin 0.2,0.3,-1 --dir 0.3,0.2,1 --method robust --json",
    ));
    assert_eq!(v["hit"], true, "{v}");
    close(num(&v, "t"), 1.0, 1e-6, "zero-thickness t");
}

#[test]
fn box_plain_output_names_the_slabs_in_order() {
    let out = ok(&Cli::new(CUBE).and("--origin 5,0.5,0 --dir -1,0,0"));
    assert_in_order(&out, &["x slab", "y slab", "z slab", "t_near", "t_far"]);
}
