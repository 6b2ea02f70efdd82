//! Invalid rays and the spawned rays' self-hits.

use super::*;

pub(super) fn invalid_rays() -> Vec<Case> {
    let bad: Vec<([f64; 3], [f64; 3])> = vec![
        ([f64::NAN, 0.0, -5.0], [0.0, 0.0, 1.0]),
        ([0.0, f64::INFINITY, -5.0], [0.0, 0.0, 1.0]),
        ([0.0, 0.0, -5.0], [f64::NAN, 0.0, 1.0]),
        ([0.0, 0.0, -5.0], [0.0, f64::NEG_INFINITY, 1.0]),
        ([0.0, 0.0, -5.0], [0.0, 0.0, 0.0]),
        ([0.0, 0.0, -5.0], [-0.0, 0.0, -0.0]),
        // d·d underflows to zero in both precisions.
        ([0.0, 0.0, -5.0], [0.0, 0.0, 1e-200]),
        // d·d overflows in both precisions.
        ([0.0, 0.0, -5.0], [0.0, 0.0, 1e200]),
    ];
    let geos = [
        (
            Primitive::Sphere,
            Geometry::Sphere {
                center: [0.0; 3],
                radius: 1.0,
            },
        ),
        (
            Primitive::Triangle,
            Geometry::Triangles(vec![[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]]]),
        ),
        (
            Primitive::Plane,
            Geometry::Plane {
                normal: [0.0, 0.0, 1.0],
                offset: 0.0,
                axis: Some(2),
            },
        ),
        (
            Primitive::Box,
            Geometry::Aabb {
                lo: [-1.0; 3],
                hi: [1.0; 3],
            },
        ),
    ];
    geos.into_iter()
        .map(|(p, g)| {
            let q = bad
                .iter()
                .map(|&(o, d)| Query {
                    geometry: g.clone(),
                    origin: o,
                    dir: d,
                    f32_exact: false,
                })
                .collect();
            rays(
                "S25",
                "NaN, ±∞, zero, under/overflowing rays",
                p,
                Kind::Reject,
                q,
            )
        })
        .collect()
}

pub(super) fn vec3(v: [f64; 3]) -> Vec3 {
    Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)
}

pub(super) fn spawn_s7(rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for _ in 0..n {
        // Concentric spheres r = 1 and 1 + 4e-5; a ray from inside the inner one leaves it and
        // must hit the outer one 4e-5 further on (a fixed ε = 1e-4 jumps over it).
        let c = vec3(scale(rng.unit(), rng.range(0.0, 2.0)));
        let o = c + vec3(scale(rng.unit(), rng.range(0.0, 0.5)));
        q.push(SpawnQuery {
            shape: Shape::Sphere {
                center: c,
                radius: 1.0,
            },
            second: Some(Shape::Sphere {
                center: c,
                radius: 1.0 + 4e-5,
            }),
            origin: o,
            dir: vec3(rng.unit()),
            mode: SpawnMode::Continue,
        });
    }
    Case {
        id: "S7",
        title: "concentric spheres 4e-5 apart, ray leaving the inner",
        primitive: Primitive::Spawn,
        data: CaseData::Spawn(q),
    }
}

pub(super) fn spawn_s19(opts: &Options, rng: &mut Rng, n: usize) -> Case {
    let mut q = vec![];
    for s in pick(opts, &[1e-3, 1.0, 1e3, 1e6]) {
        for k in 0..n {
            // A primary ray meets a sphere, plane or triangle at scale s at 1°…89° to the
            // surface; the reflected ray must not hit the surface again.
            let theta = rng.range(1.0, 89.0).to_radians();
            let nrm = rng.unit();
            let (t1, t2) = basis(nrm);
            let incoming = add(scale(nrm, -theta.sin()), scale(t1, theta.cos()));
            let p = scale(rng.unit(), s * rng.range(0.0, 3.0));
            let shape = match k % 3 {
                0 => Shape::Sphere {
                    center: vec3(sub(p, scale(nrm, s))),
                    radius: s as f32,
                },
                1 => {
                    let n32 = vec3(nrm).normalize();
                    Shape::Plane {
                        normal: n32,
                        offset: n32.dot(vec3(p)),
                    }
                }
                _ => Shape::Triangle {
                    p: [
                        vec3(add(p, scale(add(t1, t2), -s))),
                        vec3(add(p, scale(t1, 2.0 * s))),
                        vec3(add(p, scale(t2, 2.0 * s))),
                    ],
                },
            };
            let origin = vec3(sub(p, scale(incoming, 3.0 * s)));
            q.push(SpawnQuery {
                shape,
                second: None,
                origin,
                dir: vec3(incoming),
                mode: SpawnMode::Reflect,
            });
        }
    }
    Case {
        id: "S19",
        title: "reflected rays from spheres, planes, triangles at 1e-3…1e6, 1°…89°",
        primitive: Primitive::Spawn,
        data: CaseData::Spawn(q),
    }
}

pub(super) fn toml_vec(v: Vec3) -> String {
    format!("[{:e}, {:e}, {:e}]", v.x, v.y, v.z)
}

pub(super) fn bvh_scenes(rng: &mut Rng, n: usize) -> Case {
    use crate::math::Ray;
    let mut out = vec![];
    // A random scene of spheres and triangles scaled by 1e-5: no fixed t_min may creep into
    // the traversal.
    let s = 1e-5f32;
    let mut t = format!("[[plane]]\naxis = \"y\"\noffset = {:e}\n", -12.0 * s);
    for _ in 0..40 {
        t += &format!(
            "[[sphere]]\ncenter = {}\nradius = {:e}\n",
            toml_vec(rvec(rng) * 10.0 * s),
            rng.range(0.1, 1.5) as f32 * s
        );
        let c = rvec(rng) * 10.0;
        let p: Vec<Vec3> = (0..3).map(|_| (c + rvec(rng) * 2.0) * s).collect();
        t += &format!(
            "[[triangle]]\nvertices = [{}, {}, {}]\n",
            toml_vec(p[0]),
            toml_vec(p[1]),
            toml_vec(p[2])
        );
    }
    if let Ok(scene) = crate::scene::load_str(&t, "s23-tiny.toml", None) {
        let rays = (0..n)
            .filter_map(|_| {
                let o = rvec(rng) * 20.0 * s;
                let target = rvec(rng) * 10.0 * s;
                Ray::infinite(o, target - o).ok()
            })
            .collect();
        out.push((scene, rays));
    }
    // Two spheres whose surfaces are 5e-5 apart; rays from just inside the inner one outwards.
    let t = "[[sphere]]\nradius = 1\n[[sphere]]\nradius = 1.00005\n[[sphere]]\ncenter = [5, 0, 0]\n\
             [[sphere]]\ncenter = [-5, 0, 0]\n";
    if let Ok(scene) = crate::scene::load_str(t, "s23-close.toml", None) {
        let rays = (0..n)
            .filter_map(|_| {
                let d = rvec(rng);
                let o = d.normalize_or_zero() * 0.999;
                Ray::new(o, d, 0.0, f32::INFINITY).ok()
            })
            .collect();
        out.push((scene, rays));
    }
    Case {
        id: "S23",
        title: "BVH against brute force: scene scaled by 1e-5; surfaces 5e-5 apart",
        primitive: Primitive::Box,
        data: CaseData::Scenes(out),
    }
}
