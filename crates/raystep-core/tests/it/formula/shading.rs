//! The camera, plane, light, refraction and shading lines against f64 and the record.

use super::*;

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
