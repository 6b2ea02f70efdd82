//! The triangle tests' lines: Möller–Trumbore and the watertight test by hand, their stops, and
//! the recorded values.

use super::*;

#[test]
fn moller_trumbore_by_hand() {
    // S = (0, 0.5, −2), Q = (0, 0, 1): E1 = (−1, −1, 0), E2 = (1, −1, 0), −Q = (0, 0, −1),
    // D0 = −Q·(E1 × E2) = −2; T = (0, −0.5, −2), Dt = T·(E1 × E2) = −4, t* = 2;
    // T × E2 = (−2, −2, 0.5): Du = −0.5, u* = 0.25; E1 × T = (2, −2, 0.5): Dv = −0.5, v* = 0.25.
    let trace = record(&triangle_scene([0.0, 0.5, -2.0], "moller-trumbore"), 1, 1);
    assert_eq!(trace.root.direction, [0.0, 0.0, 1.0]);
    let (_, e) = triangle_step(&trace);
    let want = [
        ("E1", "(-1, -1, 0)"),
        ("E2", "(1, -1, 0)"),
        ("D0", "-2"),
        ("T", "(0, -0.5, -2)"),
        ("Dt", "-4"),
        ("t*", "2"),
        ("Du", "-0.5"),
        ("u*", "0.25"),
        ("Dv", "-0.5"),
        ("v*", "0.25"),
        ("(b0, b1, b2)", "(0.5, 0.25, 0.25)"),
    ];
    for (n, v) in want {
        assert_eq!(get(&e, n).value, v, "{n}");
    }
    assert_eq!(get(&e, "t*").substituted, "(-4)/(-2)");
    assert_eq!(
        get(&e, "D0").substituted,
        "det((-0, -0, -1), (-1, -1, 0), (1, -1, 0))"
    );
    assert!(e.conclusion.starts_with("Hit at t = 2"), "{}", e.conclusion);

    // From the other side, looking away: t* = −2, so the test stops at step 5 with no u or v.
    let trace = record(&triangle_scene([0.0, 0.5, 2.0], "moller-trumbore"), 1, 1);
    let (_, e) = triangle_step(&trace);
    assert_eq!(get(&e, "t*").value, "-2");
    assert_eq!(e.lines.last().unwrap().name, "t in range?");
    assert_eq!(e.lines.last().unwrap().value, "no");
    assert!(!has(&e, "Du") && !has(&e, "u*"));
    assert!(e.conclusion.contains("step 5"), "{}", e.conclusion);
}

#[test]
fn watertight_by_hand() {
    // Q = (0, 0, 1): z is already the largest component, so no permutation and no shear;
    // P′ᵢ = Pᵢ − S: (0, 0.5, 2), (−1, −0.5, 2), (1, −0.5, 2).
    // e0 = x1·y2 − y1·x2 = (−1)(−0.5) − (−0.5)(1) = 1, e1 = x2·y0 − y2·x0 = 0.5, e2 = 0.5;
    // det = 2; t_scaled = Σ eᵢzᵢ = 4; t = 2, u = 0.25, v = 0.25.
    let trace = record(&triangle_scene([0.0, 0.5, -2.0], "watertight"), 1, 1);
    let (_, e) = triangle_step(&trace);
    assert_eq!(get(&e, "(kx, ky, kz)").value, "(x, y, z)");
    assert_eq!(get(&e, "P′1").value, "(-1, -0.5, 2)");
    assert_eq!(get(&e, "e0").substituted, "(-1)·(-0.5) − (-0.5)·1");
    for (n, v) in [
        ("e0", "1"),
        ("e1", "0.5"),
        ("e2", "0.5"),
        ("det", "2"),
        ("t_scaled", "4"),
        ("t", "2"),
        ("u", "0.25"),
        ("v", "0.25"),
    ] {
        assert_eq!(get(&e, n).value, v, "{n}");
    }
    assert!(e.conclusion.starts_with("Hit at t = 2"), "{}", e.conclusion);
}

#[test]
fn moller_trumbore_lists_no_lines_past_its_stop() {
    let mut scene = shipped("triangles.toml");
    scene.settings.triangle_method = TriangleMethod::MollerTrumbore;
    scene.settings.accel = AccelChoice::None; // every triangle for every ray: all the stops
    let mut seen = [0usize; 13];
    for (x, y) in grid(&scene, 40) {
        let trace = record(&scene, x, y);
        for (ray, step, e) in explained(&trace) {
            let Step::Triangle { test, vertices, .. } = step else {
                continue;
            };
            let stop = test.stopped_at as usize;
            seen[stop] += 1;
            // E1, E2 and T are recorded: bit-equal to the f32 differences of the step's own
            // vertices and the ray's origin, and printed as recorded.
            let diff = |a: [f32; 3], b: [f32; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
            let bits = |v: [f32; 3]| v.map(f32::to_bits);
            let xyz = |v: [f32; 3]| format!("({}, {}, {})", num(v[0]), num(v[1]), num(v[2]));
            let [p0, p1, p2] = *vertices;
            let (e1, e2) = (test.e1.unwrap(), test.e2.unwrap());
            assert_eq!(bits(e1), bits(diff(p1, p0)));
            assert_eq!(bits(e2), bits(diff(p2, p0)));
            assert_eq!(get(&e, "E1").value, xyz(e1));
            assert_eq!(get(&e, "E2").value, xyz(e2));
            assert_eq!(test.t_vec.is_some(), stop > 2);
            if let Some(tv) = test.t_vec {
                assert_eq!(bits(tv), bits(diff(ray.origin, p0)));
                assert_eq!(get(&e, "T").value, xyz(tv));
            }
            let reached = |n: &str| has(&e, n);
            assert_eq!(get(&e, "D0").value, num(test.det));
            assert_eq!(reached("Dt"), stop > 2, "{e:#?}");
            assert_eq!(reached("t*"), stop > 2);
            assert_eq!(reached("Du"), stop > 5, "{e:#?}");
            assert_eq!(reached("u*"), stop > 5);
            assert_eq!(reached("Dv"), stop > 8, "{e:#?}");
            assert_eq!(reached("v*"), stop > 8);
            assert_eq!(reached("(b0, b1, b2)"), stop == 12);
            // Each quotient's substitution is made of the printed numerator and D0, and their
            // f32 quotient is the printed value.
            let d0 = parse(&get(&e, "D0").value);
            for (q, n) in [("t*", "Dt"), ("u*", "Du"), ("v*", "Dv")] {
                if !reached(q) {
                    continue;
                }
                let num_ = parse(&get(&e, n).value);
                let sub = numbers(&get(&e, q).substituted);
                assert!(same(sub[0], num_) && same(sub[1], d0), "{q}: {sub:?}");
                assert!(same(num_ / d0, parse(&get(&e, q).value)), "{q}");
            }
            if stop == 12 {
                assert!(e.conclusion.starts_with("Hit"));
            } else {
                assert!(e.conclusion.contains(&format!("step {stop}")));
            }
        }
    }
    for stop in [5, 8, 11, 12] {
        assert!(seen[stop] > 0, "no test stopped at {stop}: {seen:?}");
    }
}

#[test]
fn watertight_values_are_the_recorded_ones() {
    let mut scene = shipped("triangles.toml");
    scene.settings.accel = AccelChoice::None;
    let mut hits = 0;
    for (x, y) in grid(&scene, 60) {
        let trace = record(&scene, x, y);
        for (_, step, e) in explained(&trace) {
            let Step::Triangle { test, .. } = step else {
                continue;
            };
            let edges = test.edges.unwrap();
            for (i, edge) in edges.iter().enumerate() {
                assert_eq!(get(&e, &format!("e{i}")).value, num(*edge));
            }
            // The shear and the sheared vertices are the recorded ones, printed and used as such.
            let [sx, sy, sz] = test.shear.expect("a watertight test records its shear");
            assert_eq!(
                get(&e, "Sx, Sy, Sz").value,
                format!("{}, {}, {}", num(sx), num(sy), num(sz))
            );
            let q = test.sheared.expect("and its sheared vertices");
            for (i, v) in q.iter().enumerate() {
                assert_eq!(
                    get(&e, &format!("P′{i}")).value,
                    format!("({}, {}, {})", num(v[0]), num(v[1]), num(v[2]))
                );
            }
            for (i, (a, b)) in [(1, 2), (2, 0), (0, 1)].into_iter().enumerate() {
                let sub = numbers(&get(&e, &format!("e{i}")).substituted);
                let want = [q[a][0], q[b][1], q[a][1], q[b][0]];
                assert!(
                    sub.iter().zip(want).all(|(&x, y)| same(x, y)),
                    "e{i}: {sub:?} vs {want:?}"
                );
                // The recorded edge is what those vertices give: x·y − y·x evaluated exactly
                // (two f32 products are exact in f64), within the kernel's rounding.
                let exact = q[a][0] as f64 * q[b][1] as f64 - q[a][1] as f64 * q[b][0] as f64;
                let ulp = (edges[i].abs().max(f32::MIN_POSITIVE) * f32::EPSILON) as f64;
                assert!(
                    (edges[i] as f64 - exact).abs() <= 2.0 * ulp,
                    "e{i} = {} recorded, {exact} from the recorded vertices",
                    edges[i]
                );
            }
            if let (Some(z), Some(dt)) = (test.z_scaled, test.dt) {
                let sub = numbers(&get(&e, "t_scaled").substituted);
                assert!(same(sub[1], z[0]) && same(sub[3], z[1]) && same(sub[5], z[2]));
                assert_eq!(
                    (edges[0] * z[0] + edges[1] * z[1] + edges[2] * z[2]).to_bits(),
                    dt.to_bits(),
                    "the recorded scaled t is Σ eᵢ·z′ᵢ of the recorded values"
                );
            }
            let outside = test.stopped_at == 8;
            assert_eq!(has(&e, "det"), !outside);
            assert_eq!(has(&e, "t"), !outside && test.stopped_at != 2);
            if has(&e, "t") {
                assert_eq!(get(&e, "t").value, num(test.t_star.unwrap()));
                assert_eq!(get(&e, "u").value, num(test.u.unwrap()));
                assert_eq!(get(&e, "v").value, num(test.v.unwrap()));
            }
            hits += usize::from(test.stopped_at == 12);
        }
    }
    assert!(hits > 0);
}
