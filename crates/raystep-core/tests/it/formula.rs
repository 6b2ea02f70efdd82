//! The math panel (`raystep_core::explain::formula`): every step of real recorded traces is explained,
//! the printed numbers are the recorded ones, the substituted formulas use the very numbers their
//! values came from, and hand-computed cases come out as computed by hand.

use raystep_core::accel::SceneAccel;
use raystep_core::explain::formula::{Explanation, Formula, explain};
use raystep_core::record::number::num;
use raystep_core::record::{NodeAction, RayRecord, Step, Trace};
use raystep_core::scene::{AccelChoice, Scene, Shape, load_file, load_str};
use raystep_core::shapes::{SphereMethod, TriangleMethod};
use raystep_core::trace::Tracer;
use std::path::Path;

const SHIPPED: [&str; 5] = [
    "first-sphere.toml",
    "three-spheres.toml",
    "triangles.toml",
    "mirror-glass.toml",
    "cornell.toml",
];

fn shipped(name: &str) -> Scene {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("scenes")
        .join(name);
    load_file(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn record(scene: &Scene, x: u32, y: u32) -> Trace {
    let (accel, _) = SceneAccel::build(scene);
    Tracer::new(scene, &accel).record(x, y, 0)
}

/// Pixels on a coarse grid (every `step` pixels, centred in the cells) plus the centre pixel.
fn grid(scene: &Scene, step: u32) -> Vec<(u32, u32)> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let mut out = vec![(w / 2, h / 2)];
    for y in (step / 2..h).step_by(step as usize) {
        for x in (step / 2..w).step_by(step as usize) {
            out.push((x, y));
        }
    }
    out
}

/// Every (ray, step) of a trace with its explanation.
fn explained(trace: &Trace) -> Vec<(&RayRecord, &Step, Explanation)> {
    trace
        .timeline()
        .into_iter()
        .map(|(r, s)| (r, &s.step, explain(trace, r, &s.step)))
        .collect()
}

fn get<'a>(e: &'a Explanation, name: &str) -> &'a Formula {
    e.lines
        .iter()
        .find(|l| l.name == name)
        .unwrap_or_else(|| panic!("no line {name:?} in {e:#?}"))
}

fn has(e: &Explanation, name: &str) -> bool {
    e.lines.iter().any(|l| l.name == name)
}

/// Parses a number as `describe::num` prints it (shortest round trip, so exact).
fn parse(s: &str) -> f32 {
    match s.trim() {
        "∞" => f32::INFINITY,
        "-∞" => f32::NEG_INFINITY,
        t => t
            .trim_start_matches('(')
            .trim_end_matches(')')
            .parse()
            .unwrap_or_else(|e| panic!("{t:?}: {e}")),
    }
}

/// The ASCII numbers in a substituted formula, in order (`-` only as a sign or in an exponent;
/// the operators use `−`).
fn numbers(s: &str) -> Vec<f32> {
    let mut out = vec![];
    let mut cur = String::new();
    let flush = |cur: &mut String, out: &mut Vec<f32>| {
        if cur.chars().any(|c| c.is_ascii_digit()) {
            out.push(
                cur.parse()
                    .unwrap_or_else(|e| panic!("{cur:?} in {s:?}: {e}")),
            );
        }
        cur.clear();
    };
    for c in s.chars() {
        // Scientific notation too (`7.1525574e-7`): `e` after a digit, `-` after that `e`.
        let exponent = c == 'e' && cur.ends_with(|d: char| d.is_ascii_digit());
        let exponent_sign = c == '-' && cur.ends_with('e');
        if c.is_ascii_digit()
            || c == '.'
            || (c == '-' && cur.is_empty())
            || exponent
            || exponent_sign
        {
            cur.push(c);
        } else {
            flush(&mut cur, &mut out);
        }
    }
    flush(&mut cur, &mut out);
    out
}

/// The arguments of `max(…)` / `min(…)` as printed.
fn args(s: &str) -> Vec<f32> {
    let inner = &s[s.find('(').unwrap() + 1..s.rfind(')').unwrap()];
    inner.split(", ").map(parse).collect()
}

fn same(a: f32, b: f32) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// f64 dot product.
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn f64x3(v: [f32; 3]) -> [f64; 3] {
    v.map(f64::from)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The unit sphere at the origin seen from (0, 0, −5) through the middle pixel of a 3×3 image:
/// the primary ray is exactly S = (0, 0, −5), Q = (0, 0, 1).
fn axis_scene(method: &str) -> Scene {
    let text = format!(
        r#"
[camera]
from = [0, 0, -5]
at = [0, 0, 0]
width = 3
height = 3

[render]
sphere_method = "{method}"

[[light]]
position = [-10, 10, -10]

[[sphere]]
name = "ball"
"#
    );
    load_str(&text, "axis.toml", None).unwrap()
}

#[test]
fn unit_sphere_by_hand() {
    // By hand: f = S − G = (0, 0, −5); a = Q·Q = 1; b = 2 f·Q = −10; c = f·f − r² = 25 − 1 = 24;
    // Δ = b² − 4ac = 100 − 96 = 4; t = (10 ∓ 2)/2 = 4 and 6; the near root 4 is the hit.
    // Stable: b′ = −f·Q = 5; l = f + (b′/a)Q = (0, 0, 0); Δ′ = r² − l·l = 1; Δ = 4aΔ′ = 4;
    // q = b′ + √(aΔ′) = 6; c/q = 4, q/a = 6.
    for method in ["textbook", "stable"] {
        let trace = record(&axis_scene(method), 1, 1);
        assert_eq!(trace.root.origin, [0.0, 0.0, -5.0]);
        assert_eq!(trace.root.direction, [0.0, 0.0, 1.0]);
        let step = trace
            .root
            .steps
            .iter()
            .map(|s| &s.step)
            .find(|s| matches!(s, Step::Sphere { .. }))
            .expect("a sphere test");
        let e = explain(&trace, &trace.root, step);
        assert!(e.title.contains("\"ball\""), "{}", e.title);
        assert_eq!(get(&e, "f").value, "(0, 0, -5)");
        assert_eq!(get(&e, "a").value, "1");
        assert_eq!(get(&e, "c").value, "24");
        assert_eq!(get(&e, "Δ").value, "4");
        assert!(get(&e, "Δ").note.as_deref().unwrap().contains("> 0"));
        assert_eq!(get(&e, "t").value, "4");
        if method == "textbook" {
            assert!(e.title.contains("textbook"));
            assert_eq!(get(&e, "b").value, "-10");
            assert_eq!(get(&e, "b").substituted, "2·(0, 0, -5)·(0, 0, 1)");
            assert_eq!(get(&e, "Δ").substituted, "(-10)² − 4·1·24");
            assert_eq!(get(&e, "√Δ").value, "2");
            assert_eq!(get(&e, "t₀").substituted, "(10 − 2)/(2·1)");
            assert_eq!(get(&e, "t₀").value, "4");
            assert_eq!(get(&e, "t₁").value, "6");
        } else {
            assert!(e.title.contains("stable"));
            assert_eq!(get(&e, "b′").value, "5");
            assert_eq!(get(&e, "l").value, "(0, 0, 0)");
            assert_eq!(get(&e, "Δ′").value, "1");
            assert_eq!(get(&e, "Δ").substituted, "4·1·1");
            assert_eq!(get(&e, "q").value, "6");
            assert_eq!(get(&e, "c/q").value, "4");
            assert_eq!(get(&e, "q/a").value, "6");
            assert_eq!(get(&e, "t₀, t₁").value, "4, 6");
        }
        assert!(e.conclusion.contains("near root"), "{}", e.conclusion);
    }
}

#[test]
fn every_sphere_step_prints_its_record_and_consistent_substitutions() {
    let mut checked = [0usize; 2];
    for name in ["three-spheres.toml", "mirror-glass.toml", "cornell.toml"] {
        for method in [SphereMethod::Textbook, SphereMethod::Stable] {
            let mut scene = shipped(name);
            scene.settings.sphere_method = method;
            for (x, y) in grid(&scene, 50) {
                let trace = record(&scene, x, y);
                for (ray, step, e) in explained(&trace) {
                    let Step::Sphere { object, test, .. } = step else {
                        continue;
                    };
                    let Some(Shape::Sphere { center, radius }) = trace
                        .objects
                        .iter()
                        .find(|o| o.id == *object)
                        .map(|o| o.shape)
                    else {
                        panic!("sphere {object} not in the trace's objects");
                    };
                    let (a, c) = (parse(&get(&e, "a").value), parse(&get(&e, "c").value));
                    assert!(same(a, test.a) && same(c, test.c));
                    assert_eq!(get(&e, "Δ").value, num(test.discriminant));
                    // Independently, in f64: a = Q·Q, c = f·f − r², b = 2 f·Q, to f32 rounding.
                    let d = f64x3(ray.direction);
                    let f = sub(f64x3(ray.origin), f64x3(center.to_array()));
                    let eps = 4.0 * f32::EPSILON as f64;
                    assert!((a as f64 - dot(d, d)).abs() <= eps * dot(d, d));
                    let r2 = radius as f64 * radius as f64;
                    assert!((c as f64 - (dot(f, f) - r2)).abs() <= eps * (dot(f, f) + r2));
                    let b64 = 2.0 * dot(f, d);
                    let bound = eps * 2.0 * dot(f, f).sqrt() * dot(d, d).sqrt();
                    assert!((test.b as f64 - b64).abs() <= bound + 1e-30);
                    // The recorded f is S − G in f32 (one correctly rounded subtraction per
                    // component), and the panel prints it.
                    let rec_f = test.f.expect("f is recorded");
                    let g = center.to_array();
                    for i in 0..3 {
                        assert_eq!(rec_f[i].to_bits(), (ray.origin[i] - g[i]).to_bits());
                    }
                    let vf = format!("({}, {}, {})", num(rec_f[0]), num(rec_f[1]), num(rec_f[2]));
                    assert_eq!(get(&e, "f").value, vf);
                    match method {
                        SphereMethod::Textbook => {
                            // Δ's substitution is made of the printed b, a and c.
                            let b = parse(&get(&e, "b").value);
                            let n = numbers(&get(&e, "Δ").substituted);
                            assert_eq!(n.len(), 4, "{:?}", get(&e, "Δ"));
                            assert!(same(n[0], b) && same(n[2], a) && same(n[3], c));
                            // …and b² − 4ac of those numbers, in f32, is the printed Δ.
                            assert!(same(b * b - 4.0 * a * c, parse(&get(&e, "Δ").value)));
                            // √Δ and the two roots as computed: IEEE square root and
                            // (−b ∓ √Δ)/2a of the recorded numbers, bit for bit, as printed.
                            if let Some(sq) = test.sqrt_discriminant {
                                assert_eq!(sq.to_bits(), test.discriminant.sqrt().to_bits());
                                assert_eq!(get(&e, "√Δ").value, num(sq));
                                let [t0, t1] = test.computed_roots.expect("roots as computed");
                                assert_eq!(t0.to_bits(), ((-test.b - sq) / (2.0 * a)).to_bits());
                                assert_eq!(t1.to_bits(), ((-test.b + sq) / (2.0 * a)).to_bits());
                                assert_eq!(get(&e, "t₀").value, num(t0));
                                assert_eq!(get(&e, "t₁").value, num(t1));
                            } else {
                                assert!(test.roots.is_none());
                            }
                            checked[0] += 1;
                        }
                        SphereMethod::Stable => {
                            let dp = parse(&get(&e, "Δ′").value);
                            assert!(same(dp, test.delta_prime.unwrap()));
                            assert!(same(4.0 * a * dp, test.discriminant));
                            // b′ = −f·Q and l = f + (b′/a)·Q as recorded and printed; b′ agrees
                            // with the f64 dot product to f32 rounding.
                            let bh = test.b_half.expect("b′ is recorded");
                            assert_eq!(get(&e, "b′").value, num(bh));
                            assert!((bh as f64 + dot(f, d)).abs() <= bound / 2.0 + 1e-30);
                            let l = test.l.expect("l is recorded");
                            let vl = format!("({}, {}, {})", num(l[0]), num(l[1]), num(l[2]));
                            assert_eq!(get(&e, "l").value, vl);
                            if let (Some(q), Some([t0, t1])) = (test.q, test.computed_roots)
                                && q != 0.0
                            {
                                assert_eq!(t0.to_bits(), (test.c / q).to_bits());
                                assert_eq!(t1.to_bits(), (q / a).to_bits());
                            }
                            checked[1] += 1;
                        }
                    }
                    if let Some([lo, hi]) = test.roots {
                        if method == SphereMethod::Textbook {
                            assert_eq!(get(&e, "t₀").value, num(lo));
                            assert_eq!(get(&e, "t₁").value, num(hi));
                        } else {
                            let q = parse(&get(&e, "q").value);
                            if q != 0.0 {
                                // The printed c/q and q/a are the two recorded roots.
                                let mut r =
                                    [parse(&get(&e, "c/q").value), parse(&get(&e, "q/a").value)];
                                r.sort_by(f32::total_cmp);
                                assert!(same(r[0], lo) && same(r[1], hi), "{e:#?}");
                            }
                        }
                        if let Some(t) = test.t {
                            assert_eq!(get(&e, "t").value, num(t));
                        }
                    } else {
                        assert!(!has(&e, "t"), "{e:#?}");
                    }
                }
            }
        }
    }
    assert!(checked[0] > 50 && checked[1] > 50, "{checked:?}");
}

/// The scene of RTC ch. 15's triangle P0 (0, 1, 0), P1 (−1, 0, 0), P2 (1, 0, 0), seen along +z
/// through the middle pixel of a 3×3 image from `from`.
fn triangle_scene(from: [f32; 3], method: &str) -> Scene {
    let text = format!(
        r#"
[camera]
from = [{}, {}, {}]
at = [{}, {}, {}]
width = 3
height = 3

[render]
triangle_method = "{method}"

[[light]]
position = [-10, 10, -10]

[[triangle]]
name = "rtc"
vertices = [[0, 1, 0], [-1, 0, 0], [1, 0, 0]]
"#,
        from[0],
        from[1],
        from[2],
        from[0],
        from[1],
        from[2] + 2.0
    );
    load_str(&text, "tri.toml", None).unwrap()
}

fn triangle_step(trace: &Trace) -> (&Step, Explanation) {
    let step = trace
        .root
        .steps
        .iter()
        .map(|s| &s.step)
        .find(|s| matches!(s, Step::Triangle { .. }))
        .expect("a triangle test");
    (step, explain(trace, &trace.root, step))
}

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

#[test]
fn bvh_slab_intervals_recompute_from_the_printed_numbers() {
    // t_near = max(t_min, entries) and t_far = min(t_max, exits): recomputing them from the printed
    // arguments must give the recorded values bit for bit — which also checks that the t_max the
    // panel prints is the one the box was tested against (it shrinks as hits are accepted, and a
    // far sibling is tested with the t_max from before its near sibling's leaf).
    let mut visits = 0;
    for name in ["three-spheres.toml", "triangles.toml", "cornell.toml"] {
        let mut scene = shipped(name);
        scene.settings.accel = AccelChoice::Bvh;
        for (x, y) in grid(&scene, 40) {
            let trace = record(&scene, x, y);
            for (ray, step, e) in explained(&trace) {
                let Step::Node(n) = step else {
                    continue;
                };
                visits += 1;
                let near = get(&e, "t_near");
                let far = get(&e, "t_far");
                assert_eq!(near.value, num(n.test.t_near));
                assert_eq!(far.value, num(n.test.t_far));
                let a = args(&near.substituted);
                assert!(same(a[0], ray.t_min));
                let t_near = a.iter().fold(a[0], |m, &x| m.max(x));
                assert!(same(t_near, n.test.t_near), "{e:#?}");
                let b = args(&far.substituted);
                let t_far = b.iter().fold(b[0], |m, &x| m.min(x));
                assert!(same(t_far, n.test.t_far), "{name} ({x}, {y}): {e:#?}");
                // The slab entries are where the ray crosses the box's planes (f64, loosely).
                for (i, ax) in n.test.axes.iter().enumerate() {
                    let q = ray.direction[i] as f64;
                    if q.abs() < 1e-3 {
                        continue;
                    }
                    let planes = [n.test.min[i] as f64, n.test.max[i] as f64]
                        .map(|s| (s - ray.origin[i] as f64) / q);
                    let entry = planes[0].min(planes[1]);
                    assert!(
                        (ax.t_entry as f64 - entry).abs() <= 1e-4 * (1.0 + entry.abs()),
                        "{entry} vs {}",
                        ax.t_entry
                    );
                }
                // The recorded plane distances are (slab − S)·(1/Q) in f32 bit for bit, the entry
                // is one of them, and the panel prints them as recorded.
                for (i, ax) in n.test.axes.iter().enumerate() {
                    let [t0, t1] = ax.planes.expect("the robust test records its planes");
                    let o = ray.origin[i];
                    assert_eq!(t0.to_bits(), ((n.test.min[i] - o) * ax.inv_dir).to_bits());
                    assert_eq!(t1.to_bits(), ((n.test.max[i] - o) * ax.inv_dir).to_bits());
                    let entry = if ax.inv_dir.is_sign_negative() {
                        t1
                    } else {
                        t0
                    };
                    assert_eq!(ax.t_entry.to_bits(), entry.to_bits());
                    let a = ["x", "y", "z"][i];
                    assert_eq!(
                        get(&e, &format!("t0{a}, t1{a}")).value,
                        format!("{}, {}", num(t0), num(t1))
                    );
                }
                assert_eq!(get(&e, "overlap?").value == "yes", n.test.hit);
                if n.test.hit && n.action == NodeAction::Culled {
                    assert_eq!(get(&e, "still in reach?").value, "no");
                }
            }
        }
    }
    assert!(visits > 100, "{visits}");
}

#[test]
fn camera_plane_light_and_refraction_lines_agree_with_f64() {
    let mut kinds = [0usize; 4];
    for name in ["three-spheres.toml", "mirror-glass.toml", "cornell.toml"] {
        let scene = shipped(name);
        for (x, y) in grid(&scene, 45) {
            let trace = record(&scene, x, y);
            for (ray, step, e) in explained(&trace) {
                match step {
                    Step::Camera {
                        pixel,
                        offset,
                        screen,
                        direction,
                        ..
                    } => {
                        kinds[0] += 1;
                        assert_eq!(get(&e, "sx").value, num(screen[0]));
                        assert_eq!(get(&e, "sy").value, num(screen[1]));
                        let c = &trace.camera;
                        let sx = 2.0 * (pixel[0] as f64 + offset[0] as f64) / c.width as f64 - 1.0;
                        assert!((sx - parse(&get(&e, "sx").value) as f64).abs() < 1e-6);
                        // The direction from the camera's geometry, in f64.
                        let from = f64x3(c.from.to_array());
                        let w = sub(from, f64x3(c.at.to_array()));
                        let norm = |v: [f64; 3]| {
                            let l = dot(v, v).sqrt();
                            v.map(|x| x / l)
                        };
                        let w = norm(w);
                        let up = f64x3(c.up.to_array());
                        let u = norm([
                            up[1] * w[2] - up[2] * w[1],
                            up[2] * w[0] - up[0] * w[2],
                            up[0] * w[1] - up[1] * w[0],
                        ]);
                        let v = [
                            w[1] * u[2] - w[2] * u[1],
                            w[2] * u[0] - w[0] * u[2],
                            w[0] * u[1] - w[1] * u[0],
                        ];
                        let hh = (c.fov as f64 / 2.0).to_radians().tan();
                        let hw = hh * c.width as f64 / c.height as f64;
                        let sy = 1.0 - 2.0 * (pixel[1] as f64 + offset[1] as f64) / c.height as f64;
                        let d = norm([0, 1, 2].map(|i| sx * hw * u[i] + sy * hh * v[i] - w[i]));
                        let printed = numbers(&get(&e, "Q").value);
                        for ((got, want), rec) in printed.iter().zip(d).zip(direction) {
                            assert!((*got as f64 - want).abs() < 1e-5, "{printed:?} {d:?}");
                            assert!(same(*got, *rec));
                        }
                    }
                    Step::Plane { test, .. } if !test.parallel => {
                        kinds[1] += 1;
                        let t = get(&e, "t");
                        assert_eq!(t.value, num(test.t_raw.unwrap()));
                        let n = numbers(&t.substituted);
                        assert!(same(n[0] / n[1], parse(&t.value)));
                        assert!(same(n[0], test.numerator) && same(n[1], test.denominator));
                    }
                    Step::Light { light, l_dot_n, .. } => {
                        kinds[2] += 1;
                        assert_eq!(get(&e, "l·n").value, num(*l_dot_n));
                        // l·n in f64 from the light's position and the surface's point and normal.
                        let (p, nrm) = ray
                            .steps
                            .iter()
                            .find_map(|s| match s.step {
                                Step::Surface { point, normal, .. } => Some((point, normal)),
                                _ => None,
                            })
                            .unwrap();
                        let l = sub(
                            f64x3(trace.lights[*light as usize].position.to_array()),
                            f64x3(p),
                        );
                        let ln = dot(l, f64x3(nrm)) / dot(l, l).sqrt();
                        assert!((ln - *l_dot_n as f64).abs() < 1e-5, "{ln} vs {l_dot_n}");
                    }
                    Step::Refract {
                        n1,
                        n2,
                        cos_i,
                        sin2_t,
                        total_internal_reflection,
                        ..
                    } => {
                        kinds[3] += 1;
                        assert_eq!(get(&e, "cos θᵢ").value, num(*cos_i));
                        assert_eq!(get(&e, "sin² θₜ").value, num(*sin2_t));
                        let eta = *n1 as f64 / *n2 as f64;
                        let s2 = eta * eta * (1.0 - (*cos_i as f64).powi(2));
                        assert!((s2 - *sin2_t as f64).abs() < 1e-5);
                        assert_eq!(has(&e, "cos θₜ"), !total_internal_reflection);
                        assert_eq!(
                            e.conclusion.contains("total internal reflection"),
                            *total_internal_reflection
                        );
                    }
                    _ => {}
                }
            }
        }
    }
    assert!(kinds.iter().all(|&k| k > 0), "{kinds:?}");
}

fn variant(s: &Step) -> &'static str {
    match s {
        Step::Camera { .. } => "camera",
        Step::Node(_) => "node",
        Step::SphereNode { .. } => "sphere-node",
        Step::Cell { .. } => "cell",
        Step::MailboxSkip { .. } => "mailbox-skip",
        Step::Sphere { .. } => "sphere",
        Step::Plane { .. } => "plane",
        Step::Triangle { .. } => "triangle",
        Step::Accept { .. } => "accept",
        Step::Miss { .. } => "miss",
        Step::Surface { .. } => "surface",
        Step::ShadowRay { .. } => "shadow-ray",
        Step::Light { .. } => "light",
        Step::Reflect { .. } => "reflect",
        Step::Refract { .. } => "refract",
        Step::Schlick { .. } => "schlick",
        Step::DepthLimit { .. } => "depth-limit",
        Step::WeightCutoff { .. } => "weight-cutoff",
        Step::Truncated { .. } => "truncated",
        Step::HardwareTraversal { .. } => "hardware-traversal",
        Step::Spawn { .. } => "spawn",
        Step::Color { .. } => "color",
        Step::Lens { .. } => "lens",
        Step::LightSample { .. } => "light-sample",
        Step::BsdfSample { .. } => "bsdf-sample",
        Step::Emitted { .. } => "emitted",
        Step::RussianRoulette { .. } => "russian-roulette",
    }
}

/// Every step of the Monte Carlo scenes is explained, and each Monte Carlo step is among them.
#[test]
fn every_monte_carlo_step_is_explained() {
    let mut seen = std::collections::BTreeSet::new();
    for name in [
        "cornell-area.toml",
        "depth-of-field.toml",
        "soft-shadows.toml",
        "veach-mis.toml",
    ] {
        let mut scene = shipped(name);
        scene.settings.rr_depth = 0;
        for (x, y) in grid(&scene, 40) {
            check_all_steps(&record(&scene, x, y), &mut seen);
        }
    }
    for v in [
        "lens",
        "light-sample",
        "bsdf-sample",
        "emitted",
        "russian-roulette",
    ] {
        assert!(seen.contains(v), "{v} not seen: {seen:?}");
    }
}

fn check_all_steps(trace: &Trace, seen: &mut std::collections::BTreeSet<&'static str>) {
    for (_, step, e) in explained(trace) {
        seen.insert(variant(step));
        assert!(!e.title.trim().is_empty(), "{step:?}");
        assert!(!e.conclusion.trim().is_empty(), "{step:?}");
        if !format!("{step:?}").contains("NaN") {
            let text = format!("{e:?}");
            assert!(!text.contains("NaN"), "{step:?}\n{e:#?}");
        }
        for l in &e.lines {
            assert!(!l.name.is_empty() && !l.symbolic.is_empty(), "{e:#?}");
        }
    }
}

#[test]
fn every_step_of_every_shipped_scene_is_explained() {
    let mut seen = std::collections::BTreeSet::new();
    for name in SHIPPED {
        let scene = shipped(name);
        let (w, h) = (scene.camera.width, scene.camera.height);
        check_all_steps(&record(&scene, w / 2, h / 2), &mut seen);
        // A coarse grid, with the BVH, and with a low recursion limit (depth-limit steps).
        for (x, y) in grid(&scene, 80) {
            check_all_steps(&record(&scene, x, y), &mut seen);
        }
        for accel in [AccelChoice::Bvh, AccelChoice::Spheres, AccelChoice::Grid] {
            let mut with = scene.clone();
            with.settings.accel = accel;
            for (x, y) in grid(&scene, 80) {
                check_all_steps(&record(&with, x, y), &mut seen);
            }
        }
        let mut shallow = scene.clone();
        shallow.settings.max_depth = 1;
        shallow.settings.sphere_method = SphereMethod::Textbook;
        shallow.settings.triangle_method = TriangleMethod::MollerTrumbore;
        for (x, y) in grid(&scene, 80) {
            check_all_steps(&record(&shallow, x, y), &mut seen);
        }
    }
    let all = [
        "camera",
        "node",
        "sphere-node",
        "cell",
        "mailbox-skip",
        "sphere",
        "plane",
        "triangle",
        "accept",
        "miss",
        "surface",
        "shadow-ray",
        "light",
        "reflect",
        "refract",
        "schlick",
        "depth-limit",
        "spawn",
        "color",
    ];
    for v in all {
        assert!(seen.contains(v), "no {v} step seen: {seen:?}");
    }
}

#[test]
fn a_loaded_trace_explains_the_same_without_the_scene() {
    let scene = shipped("mirror-glass.toml");
    let trace = record(&scene, 260, 150);
    let loaded = Trace::from_json(&trace.to_json(), "t.json").unwrap();
    let a: Vec<Explanation> = explained(&trace).into_iter().map(|(_, _, e)| e).collect();
    let b: Vec<Explanation> = explained(&loaded).into_iter().map(|(_, _, e)| e).collect();
    assert_eq!(a, b);
    // A step handed in from a copy (not an element of the ray) is still found by value.
    let (ray, s) = trace.timeline()[3];
    let copy = s.step.clone();
    assert_eq!(explain(&trace, ray, &copy), explain(&trace, ray, &s.step));
}

#[test]
fn accept_shrinks_t_max_for_later_tests() {
    // In three-spheres the floor is tested first; a sphere hit in front of it is then tested
    // against the floor's t, which the panel prints as t_max.
    let scene = shipped("three-spheres.toml");
    let mut found = false;
    for (x, y) in grid(&scene, 20) {
        let trace = record(&scene, x, y);
        let r = &trace.root;
        let Some(first) = r
            .steps
            .iter()
            .position(|s| matches!(s.step, Step::Accept { .. }))
        else {
            continue;
        };
        let Step::Accept { t, .. } = r.steps[first].step else {
            unreachable!()
        };
        for s in &r.steps[first + 1..] {
            if let Step::Sphere { test, .. } = &s.step
                && test.t.is_some()
            {
                let e = explain(&trace, r, &s.step);
                let sub = &get(&e, "t").substituted;
                assert!(sub.ends_with(&format!("< {}", num(t))), "{sub}");
                found = true;
                break;
            }
        }
        if found {
            break;
        }
    }
    assert!(found, "no sphere hit after the floor's");
}

/// Removes the keys `keys` from every object in `v`; returns how many were removed.
fn strip(v: &mut serde_json::Value, keys: &[&str]) -> usize {
    match v {
        serde_json::Value::Object(m) => {
            let here = keys.iter().filter(|k| m.remove(**k).is_some()).count();
            here + m.values_mut().map(|x| strip(x, keys)).sum::<usize>()
        }
        serde_json::Value::Array(a) => a.iter_mut().map(|x| strip(x, keys)).sum(),
        _ => 0,
    }
}

/// A trace saved before the watertight test recorded its shear still loads, and its explanation
/// shows — where those numbers would be (never NaN, never a recomputed value).
#[test]
fn an_older_trace_without_the_shear_shows_dashes() {
    let trace = record(&triangle_scene([0.2, 0.3, -2.0], "watertight"), 1, 1);
    let mut json: serde_json::Value = serde_json::from_str(&trace.to_json()).unwrap();
    let removed = strip(&mut json, &["shear", "sheared", "z_scaled"]);
    assert!(
        removed >= 3 && removed.is_multiple_of(3),
        "three fields a watertight test: {removed}"
    );
    let old = Trace::from_json(&json.to_string(), "old.json").expect("an older trace loads");
    let (_, e) = triangle_step(&old);
    assert_eq!(get(&e, "Sx, Sy, Sz").value, "—, —, —");
    assert_eq!(get(&e, "P′0").value, "(—, —, —)");
    assert!(get(&e, "e0").substituted.starts_with("—·—"), "{e:#?}");
    assert!(!format!("{e:?}").contains("NaN"), "{e:#?}");
    // What the record has is shown as before.
    let (_, now) = triangle_step(&trace);
    assert_eq!(get(&e, "e0").value, get(&now, "e0").value);
    assert_eq!(get(&e, "t").value, get(&now, "t").value);
}

/// Likewise a sphere test saved before f, b′, l, √Δ and the roots as computed were recorded.
#[test]
fn an_older_trace_without_the_sphere_intermediates_shows_dashes() {
    for method in [SphereMethod::Textbook, SphereMethod::Stable] {
        let mut scene = shipped("first-sphere.toml");
        scene.settings.sphere_method = method;
        let trace = record(&scene, 160, 120);
        let mut json: serde_json::Value = serde_json::from_str(&trace.to_json()).unwrap();
        let keys = ["f", "b_half", "l", "sqrt_discriminant", "computed_roots"];
        assert!(strip(&mut json, &keys) >= 2, "{method:?}");
        let old = Trace::from_json(&json.to_string(), "old.json").expect("an older trace loads");
        let (ray, step) = old
            .timeline()
            .into_iter()
            .find(|(_, s)| matches!(s.step, Step::Sphere { .. }))
            .expect("a sphere test");
        let e = explain(&old, ray, &step.step);
        assert_eq!(get(&e, "f").value, "—", "{method:?}");
        assert!(!format!("{e:?}").contains("NaN"), "{e:#?}");
        match method {
            SphereMethod::Textbook => assert_eq!(get(&e, "√Δ").value, "—"),
            _ => {
                assert_eq!(get(&e, "b′").value, "—");
                assert_eq!(get(&e, "c/q").value, "—");
                assert!(!has(&e, "l"), "no l line without l");
            }
        }
    }
}

/// Likewise a Möller–Trumbore test saved before E1, E2 and T were recorded.
#[test]
fn an_older_trace_without_the_moller_trumbore_vectors_shows_dashes() {
    let trace = record(&triangle_scene([0.2, 0.3, -2.0], "moller-trumbore"), 1, 1);
    let mut json: serde_json::Value = serde_json::from_str(&trace.to_json()).unwrap();
    assert!(strip(&mut json, &["e1", "e2", "t_vec"]) >= 3);
    let old = Trace::from_json(&json.to_string(), "old.json").expect("an older trace loads");
    let (_, e) = triangle_step(&old);
    assert_eq!(get(&e, "E1").value, "—");
    assert_eq!(get(&e, "T").value, "—");
    assert!(!format!("{e:?}").contains("NaN"), "{e:#?}");
    let (_, now) = triangle_step(&trace);
    assert_eq!(get(&e, "D0").value, get(&now, "D0").value);
}

/// Likewise a BVH node visit saved before the slab's plane distances were recorded.
#[test]
fn an_older_trace_without_the_slab_planes_shows_dashes() {
    let mut scene = shipped("three-spheres.toml");
    scene.settings.accel = AccelChoice::Bvh;
    let trace = record(&scene, 150, 110);
    let mut json: serde_json::Value = serde_json::from_str(&trace.to_json()).unwrap();
    assert!(strip(&mut json, &["planes"]) >= 3);
    let old = Trace::from_json(&json.to_string(), "old.json").expect("an older trace loads");
    let (ray, step) = old
        .timeline()
        .into_iter()
        .find(|(_, s)| matches!(s.step, Step::Node(_)))
        .expect("a node visit");
    let e = explain(&old, ray, &step.step);
    assert_eq!(get(&e, "t0x, t1x").value, "—, —");
    assert!(!format!("{e:?}").contains("NaN"), "{e:#?}");
}

/// The shading lines (Phong, reflection, Snell, Schlick) print the recorded intermediates bit
/// for bit, over every step of a grid of pixels of every shipped scene: nothing in the math
/// panel recomputes l, r, e, d·n, η, cos θₜ, R0 or Schlick's cosine.
#[test]
fn every_shading_line_prints_its_record() {
    let v3s = |v: [f32; 3]| format!("({}, {}, {})", num(v[0]), num(v[1]), num(v[2]));
    let mut seen = std::collections::BTreeSet::new();
    for name in SHIPPED {
        let scene = shipped(name);
        for (x, y) in grid(&scene, 40) {
            let trace = record(&scene, x, y);
            for (_, step, e) in explained(&trace) {
                match step {
                    Step::Light {
                        l_dot_n,
                        r_dot_e,
                        light_dir,
                        reflected,
                        eye,
                        total,
                        ..
                    } => {
                        seen.insert("light");
                        assert_eq!(get(&e, "l·n").value, num(*l_dot_n));
                        assert_eq!(get(&e, "r·e").value, num(*r_dot_e));
                        assert_eq!(get(&e, "l").value, v3s(light_dir.unwrap()));
                        assert_eq!(get(&e, "r").value, v3s(reflected.unwrap()));
                        assert_eq!(get(&e, "e").value, v3s(eye.unwrap()));
                        assert_eq!(get(&e, "total").value, v3s(total.unwrap()));
                    }
                    Step::Reflect {
                        direction, d_dot_n, ..
                    } => {
                        seen.insert("reflect");
                        assert_eq!(get(&e, "d·n").value, num(d_dot_n.unwrap()));
                        assert_eq!(get(&e, "r").value, v3s(*direction));
                    }
                    Step::Refract {
                        cos_i,
                        sin2_t,
                        total_internal_reflection,
                        direction,
                        eta,
                        cos_t,
                        ..
                    } => {
                        seen.insert("refract");
                        assert_eq!(get(&e, "η").value, num(eta.unwrap()));
                        assert_eq!(get(&e, "cos θᵢ").value, num(*cos_i));
                        assert_eq!(get(&e, "sin² θₜ").value, num(*sin2_t));
                        if *total_internal_reflection {
                            seen.insert("tir");
                            assert!(cos_t.is_none() && !has(&e, "cos θₜ"));
                        } else {
                            assert_eq!(get(&e, "cos θₜ").value, num(cos_t.unwrap()));
                            assert_eq!(get(&e, "t").value, v3s(direction.unwrap()));
                        }
                    }
                    Step::Schlick {
                        reflectance,
                        r0,
                        cos,
                    } => {
                        seen.insert("schlick");
                        assert_eq!(get(&e, "R(θ)").value, num(*reflectance));
                        if let Some(r0) = r0 {
                            assert_eq!(get(&e, "R0").value, num(*r0));
                            assert_eq!(get(&e, "cos θ").value, num(cos.unwrap()));
                        }
                    }
                    _ => {}
                }
            }
        }
    }
    for kind in ["light", "reflect", "refract", "schlick"] {
        assert!(
            seen.contains(kind),
            "no {kind} step in the shipped scenes: {seen:?}"
        );
    }
}

/// The shading intermediates, checked against the definitions in f64 by hand on the first
/// sphere's centre pixel: l and e are unit vectors, r = −l − 2(−l·n)n, l·n and r·e are their
/// dot products (within f32 rounding of the f64 value).
#[test]
fn recorded_phong_vectors_agree_with_f64() {
    let scene = shipped("first-sphere.toml");
    let trace = record(&scene, 160, 120);
    let normal = trace
        .root
        .steps
        .iter()
        .find_map(|s| match s.step {
            Step::Surface { normal, .. } => Some(normal),
            _ => None,
        })
        .expect("a surface");
    let (l, r, e, ln, re) = trace
        .root
        .steps
        .iter()
        .find_map(|s| match &s.step {
            Step::Light {
                light_dir,
                reflected,
                eye,
                l_dot_n,
                r_dot_e,
                ..
            } => Some((
                f64x3(light_dir.unwrap()),
                f64x3(reflected.unwrap()),
                f64x3(eye.unwrap()),
                *l_dot_n as f64,
                *r_dot_e as f64,
            )),
            _ => None,
        })
        .expect("a light step");
    let n = f64x3(normal);
    assert!((dot(l, l) - 1.0).abs() < 1e-6 && (dot(e, e) - 1.0).abs() < 1e-6);
    let k = 2.0 * dot([-l[0], -l[1], -l[2]], n);
    for i in 0..3 {
        assert!((r[i] - (-l[i] - k * n[i])).abs() < 1e-6, "r = {r:?}");
    }
    assert!((dot(l, n) - ln).abs() < 1e-6);
    assert!((dot(r, e) - re).abs() < 1e-6);
}

/// A trace saved before the shading intermediates were recorded still loads and explains, with
/// — where they would be.
#[test]
fn an_older_trace_without_the_shading_intermediates_shows_dashes() {
    let scene = shipped("mirror-glass.toml");
    let (x, y) = (scene.camera.width / 2, scene.camera.height / 2);
    let trace = record(&scene, x, y);
    let mut json: serde_json::Value = serde_json::from_str(&trace.to_json()).unwrap();
    let keys = [
        "light_dir",
        "reflected",
        "eye",
        "total",
        "d_dot_n",
        "eta",
        "cos_t",
        "r0",
        "cos",
    ];
    assert!(strip(&mut json, &keys) >= 4);
    let old = Trace::from_json(&json.to_string(), "old.json").expect("an older trace loads");
    for (_, step, e) in explained(&old) {
        assert!(!format!("{e:?}").contains("NaN"), "{e:#?}");
        match step {
            Step::Light { .. } => assert_eq!(get(&e, "total").value, "—"),
            Step::Refract {
                total_internal_reflection: false,
                ..
            } => {
                assert_eq!(get(&e, "η").value, "—");
                assert_eq!(get(&e, "cos θₜ").value, "—");
            }
            _ => {}
        }
    }
}

/// The teapot's pixel (160, 150) under the BVH: its primary and shadow rays both leave nodes for
/// later.
fn teapot_under_the_bvh() -> Trace {
    let mut scene = shipped("teapot-stadium.toml");
    scene.settings.accel = AccelChoice::Bvh;
    record(&scene, 160, 150)
}

/// A node left for later says why: a closest-hit ray goes to the nearer sibling first, a shadow
/// ray to the farther (the teapot's pixel (160, 150) under the BVH has both kinds).
#[test]
fn a_pushed_node_says_which_sibling_went_first_and_why() {
    use raystep_core::record::RayKind;
    let trace = teapot_under_the_bvh();
    let mut seen = [false; 2];
    for (ray, step, e) in explained(&trace) {
        let Step::Node(n) = step else { continue };
        if n.action != NodeAction::Pushed {
            continue;
        }
        if ray.kind == RayKind::Shadow {
            assert!(
                e.conclusion.starts_with("Hit, but nearer than its sibling")
                    && e.conclusion.contains("farther box first"),
                "{}",
                e.conclusion
            );
            seen[1] = true;
        } else {
            assert_eq!(
                e.conclusion,
                "Hit, but farther than its sibling: pushed on the stack for later."
            );
            seen[0] = true;
        }
    }
    assert_eq!(seen, [true, true], "pushed nodes of both kinds of ray");
}

/// The one-line words (the command line's trace tree, the app's step list and captions) say
/// the same as the math panel, and say what the recorded numbers show: a pushed node's t_near
/// is at least its sibling's on a closest-hit ray, at most on a shadow ray.
#[test]
fn the_trace_line_of_a_pushed_node_says_which_sibling_and_the_numbers_agree() {
    use raystep_core::explain::describe::describe;
    use raystep_core::record::RayKind;
    let trace = teapot_under_the_bvh();
    let mut seen = [false; 2];
    for (ray, s) in trace.timeline() {
        let Step::Node(n) = &s.step else { continue };
        if n.action != NodeAction::Pushed {
            continue;
        }
        // Siblings are numbered (1, 2), (3, 4), …: the other of the pair, visited by the same ray
        // just before or after.
        let sibling = if n.node % 2 == 1 {
            n.node + 1
        } else {
            n.node - 1
        };
        let other = ray
            .steps
            .iter()
            .find_map(|x| match &x.step {
                Step::Node(m) if m.node == sibling => Some(m.test.t_near),
                _ => None,
            })
            .expect("the sibling's visit is recorded");
        let line = describe(&s.step, ray.kind);
        if ray.kind == RayKind::Shadow {
            assert!(n.test.t_near <= other, "{} > {other}", n.test.t_near);
            assert!(
                line.ends_with(
                    "hit, but nearer than its sibling, and a shadow ray looks in the farther first: pushed for later"
                ),
                "{line}"
            );
            seen[1] = true;
        } else {
            assert!(n.test.t_near >= other, "{} < {other}", n.test.t_near);
            assert!(
                line.ends_with("hit, but farther than its sibling: pushed for later"),
                "{line}"
            );
            seen[0] = true;
        }
    }
    assert_eq!(seen, [true, true], "pushed nodes of both kinds of ray");
}
