//! Mip-mapping and ray cones: the pyramid's levels, a trilinear read blended by hand, the level
//! of detail a ray cone picks on scenes/mipmap.toml against the pixel's own footprint (worked
//! in f64 from the scene's text, and from where the neighbouring pixels' rays land), and the
//! aliasing it removes, measured against a supersampled reference.

use crate::common::exact::{self, V};
use glam::Vec3;
use raystep_core::accel::SceneAccel;
use raystep_core::record::texturing::TexelLookup;
use raystep_core::record::{Step, Trace};
use raystep_core::render::cpu::{RenderOptions, render};
use raystep_core::scene::{Filter, Scene, Texture, TextureKind, Wrap, load_file};
use raystep_core::trace::Tracer;
use raystep_core::trace::texture::{Cone, LevelOfDetail, lookup};
use std::path::{Path, PathBuf};

fn scene_path() -> PathBuf {
    Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/mipmap.toml"
    ))
    .to_path_buf()
}

fn scene_text() -> toml::Value {
    toml::from_str(&std::fs::read_to_string(scene_path()).unwrap()).unwrap()
}

fn record(scene: &Scene, x: u32, y: u32) -> Trace {
    let (accel, _) = SceneAccel::build(scene);
    Tracer::new(scene, &accel).record(x, y, 0)
}

/// The recorded texture step of the primary ray.
fn texture_step(trace: &Trace) -> Step {
    trace
        .root
        .steps
        .iter()
        .find(|s| matches!(s.step, Step::Texture { .. }))
        .expect("a texture step")
        .step
        .clone()
}

/// A 4 × 4 image read trilinearly between levels 0 and 1 at λ = 1.25 (held, so f = 0.25):
/// level 0 at (u, v) = (0.5, 0.5) is the address (2, 2), whose four texels (1, 1), (2, 1),
/// (1, 2), (2, 2) weigh ¼ each; level 1 (2 × 2, each texel the mean of a 2 × 2 block) at (1, 1)
/// weighs its four texels ¼ each, the image's mean. Texel (i, j) has red i + 4j.
#[test]
fn trilinear_blends_two_levels_by_hand() {
    let texels: Vec<Vec3> = (0..16).map(|k| Vec3::new(k as f32, 1.0, 0.0)).collect();
    let tex = Texture {
        name: "t".into(),
        kind: TextureKind::image(
            "t.png".into(),
            4,
            4,
            texels,
            Filter::Trilinear,
            Wrap::Repeat,
        ),
    };
    assert_eq!(tex.levels().len(), 3, "4 × 4, 2 × 2, 1 × 1");
    // Level 1 by hand: (0 + 1 + 4 + 5)/4 = 2.5, (2 + 3 + 6 + 7)/4 = 4.5, 10.5, 12.5.
    let level1: Vec<f32> = (0..2)
        .flat_map(|j| (0..2).map(move |i| (i, j)))
        .map(|(i, j)| tex.texel_at(1, i, j).x)
        .collect();
    assert_eq!(level1, [2.5, 4.5, 10.5, 12.5]);
    assert_eq!(tex.texel_at(2, 0, 0).x, 7.5);
    let lod = LevelOfDetail {
        cone: Cone {
            spread: 0.0,
            distance: 0.0,
        },
        width: 0.0,
        cos: 1.0,
        texels_per_area: 16.0,
        footprint: 2.378_414_2,
        lambda: 1.25,
        levels: [0, 1],
        count: 2,
        fraction: 0.25,
        addresses: [[0.0; 2]; 2],
        colors: [Vec3::ZERO; 2],
    };
    let l = lookup(&tex, [0.5, 0.5], Some(lod));
    // Level 0: (5 + 6 + 9 + 10)/4 = 7.5; level 1: (2.5 + 4.5 + 10.5 + 12.5)/4 = 7.5.
    let lod = l.lod.unwrap();
    assert_eq!(lod.addresses, [[2.0, 2.0], [1.0, 1.0]]);
    assert_eq!(lod.colors[0].x, 7.5);
    assert_eq!(lod.colors[1].x, 7.5);
    assert_eq!(l.count, 8);
    assert!(
        l.texels[..4]
            .iter()
            .all(|t| t.level == 0 && t.weight == 0.25)
    );
    assert!(
        l.texels[4..]
            .iter()
            .all(|t| t.level == 1 && t.weight == 0.25)
    );
    let at: Vec<[u32; 2]> = l.texels[..4].iter().map(|t| t.at).collect();
    assert_eq!(at, [[1, 1], [2, 1], [1, 2], [2, 2]]);
    // Off centre, the levels differ: (u, v) = (0.25, 0.75) is level 0's (1, 1), the centre of
    // the texels (0, 0), (1, 0), (0, 1), (1, 1) → (0 + 1 + 4 + 5)/4 = 2.5; level 1's (0.5, 0.5)
    // is texel (0, 0)'s centre, 2.5 with weight 1 (its neighbours wrap, weighted 0).
    let l = lookup(&tex, [0.25, 0.75], Some(lod));
    let lod = l.lod.unwrap();
    assert_eq!(lod.colors[0].x, 2.5);
    assert_eq!(lod.colors[1].x, 2.5);
    assert_eq!(l.color.x, 2.5);
    // Red at (0.375, 0.625): level 0 at (1.5, 1.5) is texel (1, 1) alone = 5; level 1 at
    // (0.75, 0.75): f = 0.25 both ways, 0.5625·2.5 + 0.1875·4.5 + 0.1875·10.5 + 0.0625·12.5 = 5.
    // 0.75·5 + 0.25·5 = 5.
    let l = lookup(&tex, [0.375, 0.625], Some(lod));
    assert_eq!(l.lod.unwrap().colors, [Vec3::new(5.0, 1.0, 0.0); 2]);
}

/// The camera's pixel spread γ in f64 from the scene text: atan(2·tan(fov/2) / height).
fn spread(scene: &toml::Value) -> f64 {
    let c = &scene["camera"];
    let fov = c["fov"].as_integer().unwrap() as f64;
    let h = c["height"].as_integer().unwrap() as f64;
    (2.0 * (fov.to_radians() / 2.0).tan() / h).atan()
}

/// Where pixel (x, y)'s centre ray meets the floor y = 0, in f64.
fn floor_hit(scene: &toml::Value, x: u32, y: u32) -> (f64, V, V) {
    let (o, d) = exact::camera_ray(scene, x, y);
    let t = -o[1] / d[1];
    (t, exact::add(o, exact::mul(d, t)), d)
}

/// On the trilinear floor (right half of the image), the recorded cone and level against the
/// scene worked in f64: W = γ·t (a primary ray's unit direction), |n·d| = |d_y|, 64 × 64
/// texels per unit of floor (u, v = x, z), L = W·64/|d_y|, λ = log₂ L; the levels ⌊λ⌋ and
/// ⌊λ⌋ + 1 weighted 1 − f and f. And the cone's footprint is the pixel's: the neighbouring
/// pixels' rays land L texels away along the floor (within 1 %, for the pixel's own angle).
#[test]
fn the_ray_cone_picks_the_level_of_the_pixels_footprint() {
    let text = scene_text();
    let scene = load_file(&scene_path()).unwrap();
    let gamma = spread(&text);
    let mut lambdas = vec![];
    for (x, y) in [(240, 200), (250, 150), (200, 125), (300, 118), (170, 112)] {
        let (t, _, d) = floor_hit(&text, x, y);
        let l_want = gamma * t * 64.0 / d[1].abs();
        let lambda_want = l_want.log2();
        let trace = record(&scene, x, y);
        let Step::Texture {
            texture,
            lookup: TexelLookup::Image { lod: Some(lod), .. },
            ..
        } = texture_step(&trace)
        else {
            panic!("pixel ({x}, {y}): not a trilinear lookup");
        };
        assert_eq!(texture, "trilinear", "({x}, {y})");
        let rel = |got: f32, want: f64| (f64::from(got) - want).abs() / want.abs();
        assert!(rel(lod.spread, gamma) < 1e-6, "γ {} vs {gamma}", lod.spread);
        assert!(rel(lod.distance, t) < 1e-5, "d {} vs {t}", lod.distance);
        assert!(
            rel(lod.cos, d[1].abs()) < 1e-5,
            "cos {} vs {}",
            lod.cos,
            d[1]
        );
        assert!(
            rel(lod.texels_per_area, 4096.0) < 1e-5,
            "{}",
            lod.texels_per_area
        );
        assert!(
            rel(lod.footprint, l_want) < 1e-4,
            "L {} vs {l_want}",
            lod.footprint
        );
        assert!(
            (f64::from(lod.lambda) - lambda_want).abs() < 1e-4,
            "({x}, {y}): λ {} vs {lambda_want}",
            lod.lambda
        );
        let held = lambda_want.clamp(0.0, 6.0);
        let (l0, f) = (held.floor(), held - held.floor());
        assert_eq!(lod.levels[0].level, l0 as u32, "({x}, {y})");
        assert!((f64::from(lod.levels[0].weight) - (1.0 - f)).abs() < 1e-4);
        if f > 1e-4 && l0 < 6.0 {
            assert_eq!(lod.levels.len(), 2);
            assert_eq!(lod.levels[1].level, l0 as u32 + 1);
            assert_eq!(lod.levels[1].size, [64 >> (l0 as u32 + 1); 2]);
        }
        // The footprint against the pixel's own: the neighbouring pixels' rays (up and down)
        // land this far away along the floor, in texels, on average. The cone's γ is the angle
        // of a pixel at the image's centre; off the axis a pixel subtends less, so L is
        // compared after scaling by this pixel's own angle to its neighbour over γ.
        let (_, p, d) = floor_hit(&text, x, y);
        let (_, below, d_below) = floor_hit(&text, x, y + 1);
        let (_, above, _) = floor_hit(&text, x, y - 1);
        let dist = |a: V, b: V| exact::dot(exact::sub(a, b), exact::sub(a, b)).sqrt();
        let step_texels = (dist(p, below) + dist(p, above)) / 2.0 * 64.0;
        let angle = exact::dot(d, d_below).clamp(-1.0, 1.0).acos();
        let own = l_want * angle / gamma;
        assert!(
            (step_texels / own - 1.0).abs() < 0.01,
            "({x}, {y}): the neighbours are {step_texels} texels away, the cone says {own}"
        );
        lambdas.push(lod.lambda);
    }
    // Farther pixels pick higher levels, from the image itself near the camera to the top.
    assert!(lambdas.windows(2).all(|w| w[0] < w[1]), "{lambdas:?}");
    assert!(
        lambdas[0] < 1.0 && *lambdas.last().unwrap() > 5.0,
        "{lambdas:?}"
    );
}

/// On an instance the cone's width is still a world length, so the texel density must be per
/// unit of world area. The right floor's two triangles made prototypes squeezed by (¼, ½, 2)
/// and placed back by instances scaled by (4, 2, 0.5): the world's floor is the same, each
/// prototype packs its texels into half the area (det M = 4, |M⁻ᵀn| = ½ for the floor's normal
/// (0, 1, 0), so M stretches the area by 2), and the cone must still find 4096 texels per unit
/// area and the λ worked in f64 from the scene's text. (Reading the prototype's density
/// unscaled gave 8192 and λ half a level too high.)
#[test]
fn the_ray_cone_reads_a_scaled_instance_in_world_area() {
    let text = scene_text();
    let mut src = std::fs::read_to_string(scene_path()).unwrap();
    for (world, object) in [
        (
            "vertices = [[-40, 0, -4], [0, 0, 200], [0, 0, -4]]",
            "vertices = [[-10, 0, -8], [0, 0, 400], [0, 0, -8]]",
        ),
        (
            "vertices = [[-40, 0, -4], [-40, 0, 200], [0, 0, 200]]",
            "vertices = [[-10, 0, -8], [-10, 0, 400], [0, 0, 400]]",
        ),
    ] {
        assert!(src.contains(world));
        src = src.replace(world, object);
    }
    for name in ["right near", "right far"] {
        src += &format!(
            "\n[[instance]]\nname = \"{name} placed\"\nof = \"{name}\"\nscale = [4, 2, 0.5]\n"
        );
    }
    let dir = scene_path().parent().unwrap().to_path_buf();
    let scene = raystep_core::scene::load_str(&src, "mipmap-instanced.toml", Some(&dir)).unwrap();
    assert_eq!(scene.instances.len(), 2);
    let gamma = spread(&text);
    for (x, y) in [(240, 200), (250, 150), (200, 125), (300, 118)] {
        let (t, _, d) = floor_hit(&text, x, y);
        let lambda_want = (gamma * t * 64.0 / d[1].abs()).log2();
        let trace = record(&scene, x, y);
        assert!(
            trace
                .root
                .hit
                .as_ref()
                .unwrap()
                .name
                .ends_with("placed → right near")
                || trace
                    .root
                    .hit
                    .as_ref()
                    .unwrap()
                    .name
                    .ends_with("placed → right far"),
            "({x}, {y})"
        );
        let Step::Texture {
            lookup: TexelLookup::Image { lod: Some(lod), .. },
            ..
        } = texture_step(&trace)
        else {
            panic!("pixel ({x}, {y}): not a trilinear lookup");
        };
        let rel = (f64::from(lod.texels_per_area) - 4096.0).abs() / 4096.0;
        assert!(rel < 1e-5, "({x}, {y}): ρ = {}", lod.texels_per_area);
        assert!(
            (f64::from(lod.lambda) - lambda_want).abs() < 1e-4,
            "({x}, {y}): λ {} vs {lambda_want}",
            lod.lambda
        );
    }
}

/// The point of it: the far floor's aliasing. Rendered with one ray per pixel, the trilinear
/// half of scenes/mipmap.toml is within 0.06 (RMS luminance, on a floor whose squares differ by
/// about 0.7) of a 64-ray supersampled reference of the same half; the bilinear half (the same
/// image, one level) is more than five times farther off (measured: 0.044 and 0.310).
/// Compared over the far floor (rows 105 … 130, where one pixel spans several of the image's
/// squares) as the root-mean-square difference of the linear luminance.
#[test]
fn trilinear_removes_the_far_floors_aliasing() {
    let mut scene = load_file(&scene_path()).unwrap();
    let (accel, _) = SceneAccel::build(&scene);
    let one = render(&Tracer::new(&scene, &accel), &RenderOptions::default())
        .unwrap()
        .pixels;
    scene.settings.spp = 64;
    // The reference: every pixel's 64 rays through the bilinear image (no mip-mapping at all).
    let mut reference = scene.clone();
    for t in &mut reference.textures {
        if let TextureKind::Image { filter, .. } = &mut t.kind {
            *filter = Filter::Bilinear;
        }
    }
    let (accel, _) = SceneAccel::build(&reference);
    let truth = render(&Tracer::new(&reference, &accel), &RenderOptions::default())
        .unwrap()
        .pixels;
    let lum = |c: Vec3| f64::from(0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z);
    let rms = |cols: std::ops::Range<usize>| {
        let (mut sum, mut n) = (0.0, 0);
        for y in 105..130 {
            for x in cols.clone() {
                let k = y * 320 + x;
                sum += (lum(one[k]) - lum(truth[k])).powi(2);
                n += 1;
            }
        }
        (sum / n as f64).sqrt()
    };
    // +x is on the left: the bilinear floor fills columns 0 … 159, the trilinear 160 … 319.
    let (bilinear, trilinear) = (rms(10..150), rms(170..310));
    println!("far floor RMS against 64 spp: bilinear {bilinear:.4}, trilinear {trilinear:.4}");
    assert!(trilinear < 0.06, "trilinear {trilinear}");
    assert!(
        bilinear > 5.0 * trilinear,
        "bilinear {bilinear}, trilinear {trilinear}"
    );
}

/// A trilinear texture step reads back from JSON unchanged, and the math panel shows the cone,
/// the footprint, λ and each level's numbers, with the recorded values substituted: λ's line
/// holds log₂ L with L's value, and T's blend the two levels' weights.
#[test]
fn a_trilinear_step_reads_back_and_is_explained_level_by_level() {
    let scene = load_file(&scene_path()).unwrap();
    let trace = record(&scene, 250, 150);
    let again = Trace::from_json(&trace.to_json(), "t.json").unwrap();
    assert_eq!(again.root, trace.root);
    let step = texture_step(&trace);
    let Step::Texture {
        lookup: TexelLookup::Image { lod: Some(lod), .. },
        ..
    } = &step
    else {
        panic!("{step:?}")
    };
    assert_eq!(lod.levels.len(), 2);
    let e = raystep_core::explain::formula::explain(&trace, &trace.root, &step);
    let names: Vec<&str> = e.lines.iter().map(|l| l.name.as_str()).collect();
    for n in [
        "W", "|n·d̂|", "ρ", "L", "λ", "x₂", "y₂", "T₂", "x₃", "y₃", "T₃", "T", "C",
    ] {
        assert!(names.contains(&n), "no line {n} in {names:?}");
    }
    let line = |n: &str| e.lines.iter().find(|l| l.name == n).unwrap();
    let num = raystep_core::record::number::num;
    assert_eq!(line("λ").value, num(lod.lambda));
    assert!(line("λ").substituted.contains(&num(lod.footprint)));
    assert_eq!(line("W").value, num(lod.width));
    let t = line("T").substituted.clone();
    assert!(
        t.contains(&num(lod.levels[0].weight)) && t.contains(&num(lod.levels[1].weight)),
        "{t}"
    );
    assert!(
        e.conclusion.contains("mip levels 2 and 3"),
        "{}",
        e.conclusion
    );
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(256))]

    /// Any trilinear read of any small image, at any (u, v) and level of detail: every level read
    /// is in the pyramid, each level's weights sum to 1 and the two levels' to 1, and the colour
    /// lies within the image's own range of texel values (every level's texels are means of
    /// them, and a read is a weighted mean of those).
    #[test]
    fn a_trilinear_read_is_a_weighted_mean_of_the_images_texels(
        w in 1u32..10,
        h in 1u32..10,
        values in proptest::collection::vec(0.0f32..1.0, 100),
        u in -3.0f32..3.0,
        v in -3.0f32..3.0,
        lambda in -2.0f32..12.0,
        wrap in proptest::sample::select(vec![Wrap::Repeat, Wrap::Clamp, Wrap::Mirror]),
    ) {
        let texels: Vec<Vec3> = (0..(w * h) as usize)
            .map(|k| Vec3::new(values[k], 1.0 - values[k], 0.5))
            .collect();
        let (lo, hi) = texels.iter().fold((f32::MAX, f32::MIN), |(a, b), t| (a.min(t.x), b.max(t.x)));
        let tex = Texture {
            name: "t".into(),
            kind: TextureKind::image("t.png".into(), w, h, texels, Filter::Trilinear, wrap),
        };
        let n = tex.levels().len() as u32;
        let last = (n - 1) as f32;
        let held = if lambda > 0.0 { lambda.min(last) } else { 0.0 };
        let l0 = held.floor();
        let fraction = held - l0;
        let lod = LevelOfDetail {
            cone: Cone { spread: 0.0, distance: 0.0 },
            width: 0.0,
            cos: 1.0,
            texels_per_area: 1.0,
            footprint: lambda.exp2(),
            lambda,
            levels: [l0 as u32, (l0 as u32 + 1).min(n - 1)],
            count: if fraction > 0.0 { 2 } else { 1 },
            fraction,
            addresses: [[0.0; 2]; 2],
            colors: [Vec3::ZERO; 2],
        };
        let l = lookup(&tex, [u, v], Some(lod));
        proptest::prop_assert_eq!(l.count, 4 * lod.count);
        for k in 0..lod.count {
            let level = &l.texels[4 * k..4 * k + 4];
            proptest::prop_assert!(level.iter().all(|t| t.level < n && t.level == lod.levels[k]));
            let size = tex.levels()[lod.levels[k] as usize];
            proptest::prop_assert!(level.iter().all(|t| t.at[0] < size.width && t.at[1] < size.height));
            let sum: f32 = level.iter().map(|t| t.weight).sum();
            proptest::prop_assert!((sum - 1.0).abs() < 1e-5, "weights sum to {}", sum);
        }
        let eps = 1e-5;
        proptest::prop_assert!(l.color.x >= lo - eps && l.color.x <= hi + eps, "{} not in [{}, {}]", l.color.x, lo, hi);
        proptest::prop_assert!((l.color.x + l.color.y - 1.0).abs() < 1e-5, "{:?}", l.color);
        proptest::prop_assert!((l.color.z - 0.5).abs() < 1e-6, "{:?}", l.color);
    }
}
