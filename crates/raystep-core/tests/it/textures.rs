//! Textures: texture coordinates from each shape, checker squares, nearest and bilinear image
//! reads with every wrap mode, the colour they give Phong and the Monte Carlo BSDFs, and the
//! scene's images read back. Expected values are worked by hand (in the comments) or computed
//! here in f64 from the formulas and the PNG's own bytes; never taken from the code under test.

use glam::Vec3;
use raystep_core::accel::{Hit, SceneAccel};
use raystep_core::explain::formula::explain;
use raystep_core::record::texturing::{TexelLookup, UvMapping};
use raystep_core::record::{Step, Trace};
use raystep_core::scene::{
    Bsdf, Filter, Material, Scene, Texture, TextureKind, Wrap, load_file, load_str,
};
use raystep_core::trace::Tracer;
use raystep_core::trace::interaction::interact;
use raystep_core::trace::texture::{lookup, plane_axes, tex_coords};
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes")).to_path_buf()
}

fn record(scene: &Scene, x: u32, y: u32) -> Trace {
    let (accel, _) = SceneAccel::build(scene);
    Tracer::new(scene, &accel).record(x, y, 0)
}

/// An image texture of `w` × `h` texels given row by row (row 0 at the top).
fn image(w: u32, h: u32, texels: Vec<Vec3>, filter: Filter, wrap: Wrap) -> Texture {
    assert_eq!(texels.len(), (w * h) as usize);
    Texture {
        name: "t".into(),
        kind: TextureKind::image("t.png".into(), w, h, texels, filter, wrap),
    }
}

fn close(a: Vec3, b: [f64; 3], tol: f64) -> bool {
    a.to_array()
        .iter()
        .zip(b)
        .all(|(x, y)| (f64::from(*x) - y).abs() <= tol)
}

#[test]
fn checker_squares_by_hand() {
    let (light, dark) = (Vec3::splat(0.9), Vec3::splat(0.1));
    let t = Texture {
        name: "c".into(),
        kind: TextureKind::Checker {
            squares: [2, 3],
            colors: [light, dark],
        },
    };
    // (u, v) → (⌊2u⌋, ⌊3v⌋), odd when the sum is.
    let cases = [
        ([0.74, 0.1], [1.0, 0.0], true),    // (1, 0)
        ([0.2, 0.5], [0.0, 1.0], true),     // (0, 1)
        ([0.6, 0.5], [1.0, 1.0], false),    // (1, 1)
        ([-0.2, -0.5], [-1.0, -2.0], true), // ⌊−0.4⌋ = −1, ⌊−1.5⌋ = −2
        ([-0.6, 0.0], [-2.0, 0.0], false),  // ⌊−1.2⌋ = −2
        ([1e7, 1e7], [2e7, 3e7], false),    // large: both even
    ];
    for (uv, cell, odd) in cases {
        let l = lookup(&t, uv, None);
        assert_eq!((l.cell, l.odd), (cell, odd), "{uv:?}");
        assert_eq!(l.color, if odd { dark } else { light });
        assert_eq!(l.count, 0);
    }
}

#[test]
fn nearest_reads_the_texel_the_point_falls_in() {
    // 4 × 2 texels, each texel's colour its own (column, row, 0).
    let texels = (0..2)
        .flat_map(|r| (0..4).map(move |c| Vec3::new(c as f32, r as f32, 0.0)))
        .collect();
    let t = image(4, 2, texels, Filter::Nearest, Wrap::Repeat);
    // x = u·4, y = (1 − v)·2: row 0 is the top (v near 1).
    for (uv, at) in [
        ([0.99, 0.01], [3, 1]), // x 3.96, y 1.98
        ([0.0, 1.0], [0, 0]),   // x 0, y 0
        ([0.26, 0.74], [1, 0]), // x 1.04, y 0.52
        ([1.3, -0.2], [1, 0]),  // repeat: (0.3, 0.8): x 1.2, y 0.4
    ] {
        let l = lookup(&t, uv, None);
        assert_eq!(l.count, 1);
        assert_eq!(l.texels[0].at, at, "{uv:?}");
        assert_eq!(l.texels[0].weight, 1.0);
        assert_eq!(l.color, Vec3::new(at[0] as f32, at[1] as f32, 0.0));
    }
}

#[test]
fn bilinear_weights_by_hand_with_every_wrap_mode() {
    // 2 × 2: A B on the top row, C D below.
    let [a, b, c, d] = [
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(1.0, 1.0, 1.0),
    ];
    let mk = |wrap| image(2, 2, vec![a, b, c, d], Filter::Bilinear, wrap);
    // The centre: x = y = 1, x − ½ = 0.5: x₀ = y₀ = 0, f = ½: each weight ¼.
    let l = lookup(&mk(Wrap::Repeat), [0.5, 0.5], None);
    assert_eq!(l.address, [1.0, 1.0]);
    assert_eq!(l.count, 4);
    assert!(close(l.color, [0.5, 0.5, 0.5], 1e-7), "{:?}", l.color);
    // uv (0.3, 0.8): x = 0.6, y = 0.2·2 = 0.4; x − ½ = 0.1 → x₀ = 0, f_x = 0.1;
    // y − ½ = −0.1 → y₀ = −1, f_y = 0.9. Rows −1 and 0: repeat reads rows 1 and 0, clamp and
    // mirror row 0 twice. Weights (1 − f_x)(1 − f_y) = 0.09, f_x(1 − f_y) = 0.01,
    // (1 − f_x)f_y = 0.81, f_x·f_y = 0.09 on (x₀, y₀), (x₀+1, y₀), (x₀, y₀+1), (x₀+1, y₀+1).
    let w = [0.09, 0.01, 0.81, 0.09];
    for (wrap, rows, want) in [
        // repeat: 0.09·C + 0.01·D + 0.81·A + 0.09·B
        (
            Wrap::Repeat,
            [1, 0],
            [0.09 * 0.0 + 0.01 + 0.81, 0.01 + 0.09, 0.09 + 0.01],
        ),
        // clamp and mirror: 0.09·A + 0.01·B + 0.81·A + 0.09·B
        (Wrap::Clamp, [0, 0], [0.9, 0.1, 0.0]),
        (Wrap::Mirror, [0, 0], [0.9, 0.1, 0.0]),
    ] {
        let l = lookup(&mk(wrap), [0.3, 0.8], None);
        let at: Vec<[u32; 2]> = l.texels[..l.count].iter().map(|t| t.at).collect();
        assert_eq!(
            at,
            vec![[0, rows[0]], [1, rows[0]], [0, rows[1]], [1, rows[1]]],
            "{wrap:?}"
        );
        for (t, w) in l.texels.iter().zip(w) {
            assert!(
                (f64::from(t.weight) - w).abs() < 1e-6,
                "{wrap:?} {:?}",
                l.texels
            );
        }
        assert!(
            close(l.color, want, 1e-6),
            "{wrap:?} {:?} vs {want:?}",
            l.color
        );
    }
    // The wrap modes themselves: repeat keeps the fraction, clamp holds to [0, 1], mirror folds.
    for (wrap, u, want) in [
        (Wrap::Repeat, 1.25, 0.25),
        (Wrap::Repeat, -0.25, 0.75),
        (Wrap::Clamp, 1.25, 1.0),
        (Wrap::Clamp, -0.25, 0.0),
        (Wrap::Mirror, 1.25, 0.75),
        (Wrap::Mirror, -0.25, 0.25),
        (Wrap::Mirror, 2.25, 0.25),
    ] {
        assert_eq!(
            lookup(&mk(wrap), [u, 0.5], None).wrapped[0],
            want,
            "{wrap:?} {u}"
        );
    }
}

/// A unit sphere at the origin, textured, seen from −z.
const SPHERE: &str = r#"
[camera]
from = [0, 0, -5]
width = 64
height = 64
[[texture]]
name = "c"
checker = [8, 4]
[[material]]
name = "m"
texture = "c"
[[sphere]]
name = "s"
radius = 1
material = "m"
"#;

#[test]
fn sphere_coordinates_are_longitude_and_latitude() {
    let scene = load_str(SPHERE, "s.toml", None).unwrap();
    // The ray from 5·d towards the centre meets the sphere at d. By hand:
    // u = (atan2(−d_z, d_x) + π)/2π, v = atan2(√(d_x² + d_z²), −d_y)/π.
    for (d, uv) in [
        ([1.0, 0.0, 0.0], [0.5, 0.5]),
        ([0.0, 0.0, 1.0], [0.25, 0.5]),  // atan2(−1, 0) = −π/2
        ([0.0, 0.0, -1.0], [0.75, 0.5]), // atan2(1, 0) = π/2
        ([-1.0, 0.0, 0.0], [1.0, 0.5]),  // atan2(0, −1) = π
        ([0.0, 1.0, 0.0], [0.5, 1.0]),   // the north pole
        ([0.0, -1.0, 0.0], [0.5, 0.0]),  // the south pole
    ] {
        let d = Vec3::from(d);
        let ray = raystep_core::math::Ray::new(d * 5.0, -d, 0.0, f32::INFINITY).unwrap();
        let hit = Hit {
            object: 0,
            t: 4.0,
            u: 0.0,
            v: 0.0,
            instance: raystep_core::scene::NO_INSTANCE,
        };
        let it = interact(&scene, &hit, &ray);
        let c = tex_coords(&scene, &hit, &it);
        assert_eq!(c.mapping, UvMapping::Sphere);
        for k in 0..2 {
            assert!((c.uv[k] - uv[k]).abs() < 1e-6, "{d}: {:?} vs {uv:?}", c.uv);
        }
    }
    // Every pixel that hits: the recorded (u, v) against f64's atan2 of the recorded direction.
    let mut checked = 0;
    for y in 0..64 {
        for x in 0..64 {
            let trace = record(&scene, x, y);
            let Some(Step::Texture {
                direction: Some(d),
                uv,
                lookup: TexelLookup::Checker { cell, .. },
                ..
            }) = trace
                .root
                .steps
                .iter()
                .map(|s| s.step.clone())
                .find(|s| matches!(s, Step::Texture { .. }))
            else {
                continue;
            };
            let d = d.map(f64::from);
            let want_u = ((-d[2]).atan2(d[0]) + std::f64::consts::PI) / std::f64::consts::TAU;
            let want_v = (d[0] * d[0] + d[2] * d[2]).sqrt().atan2(-d[1]) / std::f64::consts::PI;
            assert!(
                (f64::from(uv[0]) - want_u).abs() < 4e-7,
                "{uv:?} vs {want_u}"
            );
            assert!(
                (f64::from(uv[1]) - want_v).abs() < 4e-7,
                "{uv:?} vs {want_v}"
            );
            assert_eq!(cell, [(uv[0] * 8.0).floor(), (uv[1] * 4.0).floor()]);
            checked += 1;
        }
    }
    assert!(checked > 300, "{checked}");
}

#[test]
fn plane_axes_are_an_orthonormal_basis_of_the_plane() {
    // The floor's by hand: s = 1, a = −1, b = 0: a₁ = (1, 0, 0), a₂ = (0, 0, −1).
    assert_eq!(plane_axes(Vec3::Y), [Vec3::X, Vec3::NEG_Z]);
    let mut rng = crate::common::rng::Rng(7);
    for _ in 0..10_000 {
        let n = loop {
            let v = rng.vec(-1.0, 1.0);
            if v.length() > 0.1 {
                break v.normalize();
            }
        };
        let [a1, a2] = plane_axes(n);
        for (x, want) in [
            (a1.dot(n), 0.0),
            (a2.dot(n), 0.0),
            (a1.dot(a2), 0.0),
            (a1.length(), 1.0),
            (a2.length(), 1.0),
        ] {
            assert!((x - want).abs() < 1e-5, "{n}: {a1} {a2}");
        }
        assert!((a1.cross(a2) - n).length() < 1e-5, "{n}");
    }
}

/// sRGB's curve in f64 (IEC 61966-2-1), for the expected texels.
fn srgb(c: u8) -> f64 {
    let c = f64::from(c) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[test]
fn the_textures_scene_reads_its_images_texels_and_lights_with_them() {
    let scene = load_file(&scenes_dir().join("textures.toml")).unwrap();
    assert_eq!(scene.features.textured, 4);
    let tiles = image::open(scenes_dir().join("textures/tiles-8x8.png"))
        .unwrap()
        .to_rgb8();
    let globe = image::open(scenes_dir().join("textures/globe-64x32.png"))
        .unwrap()
        .to_rgb8();
    let texel = |img: &image::RgbImage, at: [u32; 2]| img.get_pixel(at[0], at[1]).0.map(srgb);
    let (mut on, mut lit) = ([0; 3], 0);
    for y in (2..240).step_by(6) {
        for x in (2..320).step_by(6) {
            let trace = record(&scene, x, y);
            let steps: Vec<&Step> = trace.root.steps.iter().map(|s| &s.step).collect();
            let Some(Step::Texture {
                texture,
                uv,
                lookup,
                texel: t,
                color,
                ..
            }) = steps.iter().find(|s| matches!(s, Step::Texture { .. }))
            else {
                continue;
            };
            let t = Vec3::from(*t);
            match (texture.as_str(), lookup) {
                ("tiles", TexelLookup::Image { texels, .. }) => {
                    on[0] += 1;
                    // Nearest: ⌊8u⌋, ⌊8(1 − v)⌋, and that texel of the PNG decoded here.
                    let at = [
                        (uv[0] * 8.0).floor() as u32,
                        ((1.0 - uv[1]) * 8.0).floor() as u32,
                    ];
                    assert_eq!(texels[0].at, at.map(|c| c.min(7)));
                    assert!(close(t, texel(&tiles, texels[0].at), 1e-7));
                }
                ("globe", TexelLookup::Image { texels, .. }) => {
                    on[1] += 1;
                    let want = texels.iter().fold([0.0; 3], |acc, tx| {
                        let c = texel(&globe, tx.at);
                        [0, 1, 2].map(|k| acc[k] + f64::from(tx.weight) * c[k])
                    });
                    let sum: f64 = texels.iter().map(|tx| f64::from(tx.weight)).sum();
                    assert!((sum - 1.0).abs() < 1e-6);
                    assert!(close(t, want, 1e-6), "{t} vs {want:?}");
                }
                ("checker", TexelLookup::Checker { cell, odd, .. }) => {
                    on[2] += 1;
                    assert_eq!(*odd, (cell[0] + cell[1]).rem_euclid(2.0) == 1.0);
                    assert_eq!(t, Vec3::splat(if *odd { 0.15 } else { 0.9 }));
                }
                other => panic!("{other:?}"),
            }
            // Phong's diffuse term is k_d·(l·n)·light × the textured colour (the light is white).
            if let Some(Step::Light {
                diffuse,
                l_dot_n,
                blocked: false,
                ..
            }) = steps.iter().find(|s| matches!(s, Step::Light { .. }))
                && *l_dot_n > 0.1
            {
                let kd = scene
                    .material_of(trace.root.hit.as_ref().unwrap().object)
                    .diffuse;
                let want = Vec3::from(*color) * (kd * l_dot_n);
                assert!((Vec3::from(*diffuse) - want).abs().max_element() < 1e-6);
                lit += 1;
            }
        }
    }
    assert!(on.iter().all(|n| *n > 20) && lit > 100, "{on:?} {lit}");
}

#[test]
fn obj_texture_coordinates_are_read_and_blended() {
    let dir = tempfile::TempDir::new().unwrap();
    // A unit square in z = 0 as two triangles, with vt at the corners.
    std::fs::write(
        dir.path().join("quad.obj"),
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 2 0\nvt 2 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n",
    )
    .unwrap();
    let scene_path = dir.path().join("s.toml");
    std::fs::write(
        &scene_path,
        "[camera]\nfrom = [0.5, 0.5, -1.2]\nat = [0.5, 0.5, 0]\nwidth = 16\nheight = 16\n\
         [[texture]]\nname = \"c\"\nchecker = [1, 1]\n\
         [[material]]\nname = \"m\"\ntexture = \"c\"\n\
         [[mesh]]\nname = \"quad\"\nobj = \"quad.obj\"\nmaterial = \"m\"\n",
    )
    .unwrap();
    let scene = load_file(&scene_path).unwrap();
    assert_eq!(
        scene.vertex_uvs_of(0),
        Some(&[[0.0, 0.0], [2.0, 0.0], [2.0, 1.0]])
    );
    assert_eq!(
        scene.vertex_uvs_of(1),
        Some(&[[0.0, 0.0], [2.0, 1.0], [0.0, 1.0]])
    );
    // Each hit's u is 2x and v is y: the vt stretch the square twice along u.
    let mut checked = 0;
    for y in 0..16 {
        for x in 0..16 {
            let trace = record(&scene, x, y);
            let Some(Step::Texture { uv, mapping, .. }) = trace
                .root
                .steps
                .iter()
                .map(|s| &s.step)
                .find(|s| matches!(s, Step::Texture { .. }))
            else {
                continue;
            };
            let p = trace
                .root
                .steps
                .iter()
                .find_map(|s| match s.step {
                    Step::Surface { point, .. } => Some(point),
                    _ => None,
                })
                .unwrap();
            assert_eq!(*mapping, UvMapping::VertexUvs);
            assert!((uv[0] - 2.0 * p[0]).abs() < 1e-5 && (uv[1] - p[1]).abs() < 1e-5);
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked}");
}

#[test]
fn a_texture_multiplies_the_monte_carlo_bsdfs_albedo_and_tint_but_not_glass() {
    let t = Vec3::new(0.5, 0.25, 1.0);
    let m = Material {
        color: Vec3::new(0.8, 0.6, 0.4),
        diffuse: 0.5,
        ..Material::default()
    };
    // Lambert from the Phong fields: albedo = colour × diffuse = (0.4, 0.3, 0.2), then × t.
    let Bsdf::Diffuse { albedo } = m.bsdf_textured(Some(t), None) else {
        panic!()
    };
    assert!(close(albedo, [0.2, 0.075, 0.2], 1e-7), "{albedo}");
    assert_eq!(m.bsdf_textured(None, None), m.bsdf());
    let mirror = Material {
        reflective: 0.8,
        ..m.clone()
    };
    let Bsdf::Mirror { tint } = mirror.bsdf_textured(Some(t), None) else {
        panic!()
    };
    assert!(close(tint, [0.4, 0.2, 0.8], 1e-7));
    let glass = Material {
        transparency: 1.0,
        refractive_index: 1.5,
        ..m
    };
    assert_eq!(glass.bsdf_textured(Some(t), None), glass.bsdf());
}

#[test]
fn a_texture_step_reads_back_from_json_and_is_explained_with_its_numbers() {
    let scene = load_file(&scenes_dir().join("textures.toml")).unwrap();
    // (225, 110) is on the tiles; (95, 100) on the globe; (160, 200) on the floor.
    for (x, y, title, names) in [
        (
            225,
            110,
            "Texture \"tiles\"",
            vec!["b₀", "u", "v", "x", "y", "(i, j)", "T", "C"],
        ),
        (
            95,
            100,
            "Texture \"globe\"",
            vec!["d", "u", "v", "x", "y", "x₀, y₀", "f_x, f_y", "T", "C"],
        ),
        (
            160,
            200,
            "Texture \"checker\"",
            vec!["u", "v", "i", "j", "T", "C"],
        ),
    ] {
        let trace = record(&scene, x, y);
        let again = Trace::from_json(&trace.to_json(), "t.json").unwrap();
        assert_eq!(again.root, trace.root);
        let s = trace
            .root
            .steps
            .iter()
            .find(|s| matches!(s.step, Step::Texture { .. }))
            .unwrap();
        let e = explain(&trace, &trace.root, &s.step);
        assert!(e.title.starts_with(title), "{}", e.title);
        let got: Vec<&str> = e.lines.iter().map(|l| l.name.as_str()).collect();
        for n in &names {
            assert!(got.contains(n), "{title}: no line {n} in {got:?}");
        }
        let Step::Texture { color, .. } = &s.step else {
            unreachable!()
        };
        assert!(
            e.conclusion
                .contains(&raystep_core::record::number::v3(*color))
        );
    }
}
