//! The sphere test's lines: a unit sphere by hand, and every sphere step of real traces.

use super::*;

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
