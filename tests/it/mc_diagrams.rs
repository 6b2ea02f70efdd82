//! What a Monte Carlo trace shows: its record of the pixel's samples (checked against the render
//! and against each sample's own full trace), that record read back and refused when corrupt,
//! the hemisphere's lobe and solid angles against closed forms, the diagrams each step gets,
//! the samples plot's dots and mean, and the 3D view's shadow rays ending on the sampled points.

use glam::Vec3;
use raystep::PreparedScene;
use raystep::diagram::hemisphere::{PlaneFrame, lobe, solid_angle};
use raystep::diagram::{DiagramKind, ViewOptions, available, draw, kinds_for_step, samples};
use raystep::mc::lights::LightShape;
use raystep::record::samples::luminance;
use raystep::record::{Step, Trace};
use raystep::render::{RenderOptions, render};
use raystep::scene::{Bsdf, Integrator, Scene, load_file};
use std::f32::consts::PI;
use std::path::Path;

fn shipped(name: &str, integrator: Integrator, spp: u32) -> Scene {
    let mut s = load_file(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes")
            .join(name),
    )
    .unwrap();
    s.settings.integrator = integrator;
    s.settings.spp = spp;
    s.camera.width = 32;
    s.camera.height = 24;
    s
}

/// The mean of the recorded samples is the rendered pixel, bit for bit (the render sums its
/// samples in its own tiles, in the same order), under both integrators.
#[test]
fn the_recorded_samples_average_to_the_rendered_pixel() {
    for (file, integrator) in [
        ("cornell-area.toml", Integrator::Path),
        ("soft-shadows.toml", Integrator::Distribution),
        ("veach-mis.toml", Integrator::Path),
    ] {
        let prepared = PreparedScene::new(shipped(file, integrator, 12));
        let image = render(&prepared.tracer(), &RenderOptions::default())
            .unwrap()
            .pixels;
        for (x, y) in [(5, 20), (16, 12), (28, 3)] {
            let t = prepared.record(x, y, 4);
            let mc = t
                .monte_carlo
                .as_ref()
                .expect("a Monte Carlo trace has its record");
            assert_eq!(mc.spp, 12);
            assert_eq!(mc.samples.len(), 12);
            assert_eq!(
                mc.mean(),
                image[(y * 32 + x) as usize].to_array(),
                "{file} ({x}, {y})"
            );
            // The traced sample is one of them.
            assert_eq!(mc.samples[4].color, t.color);
        }
    }
}

/// Each summary holds what the sample's own full trace records at its first hit: the hit, the
/// light points with their pdfs and verdicts, and the direction it bounced to.
#[test]
fn each_summary_is_what_the_full_trace_of_its_sample_records() {
    let prepared = PreparedScene::new(shipped("cornell-area.toml", Integrator::Path, 8));
    let (x, y) = (10, 15);
    let mc = prepared.record(x, y, 0).monte_carlo.unwrap();
    for k in 0..8u32 {
        let t = prepared.record(x, y, k);
        let s = &mc.samples[k as usize];
        assert_eq!(s.sample, k);
        assert_eq!(s.color, t.color);
        let own: Vec<&Step> = t.root.steps.iter().map(|s| &s.step).collect();
        let hit = own.iter().find_map(|s| match s {
            Step::Surface { point, .. } => Some(*point),
            _ => None,
        });
        assert_eq!(s.hit, hit, "sample {k}");
        let lights: Vec<([f32; 3], f32, bool)> = own
            .iter()
            .filter_map(|s| match s {
                Step::LightSample {
                    point,
                    pdf,
                    blocked,
                    ..
                } => Some((*point, *pdf, *blocked)),
                _ => None,
            })
            .collect();
        let kept: Vec<([f32; 3], f32, bool)> = s
            .light_samples
            .iter()
            .map(|l| (l.point, l.pdf, l.blocked))
            .collect();
        assert_eq!(kept, lights, "sample {k}");
        let bounce = own.iter().find_map(|s| match s {
            Step::BsdfSample { direction, .. } => Some(*direction),
            _ => None,
        });
        assert_eq!(s.bounce, bounce, "sample {k}");
        // Every light they aimed at is kept, with its shape.
        for l in &s.light_samples {
            assert!(mc.light(l.light).is_some());
        }
    }
    // The red wall's BSDF is kept: diffuse.
    assert!(
        mc.bsdfs
            .iter()
            .any(|b| matches!(b.bsdf, Bsdf::Diffuse { .. }))
    );
}

#[test]
fn the_record_reads_back_and_a_corrupt_one_is_refused_by_field() {
    let prepared = PreparedScene::new(shipped("soft-shadows.toml", Integrator::Distribution, 4));
    let t = prepared.record(16, 20, 1);
    let json = t.to_json();
    let back = Trace::from_json(&json, "t.json").unwrap();
    assert_eq!(back, t);
    // A Whitted trace has no Monte Carlo record, and its JSON does not mention one.
    let w =
        PreparedScene::new(shipped("soft-shadows.toml", Integrator::Whitted, 4)).record(16, 20, 1);
    assert!(w.monte_carlo.is_none());
    assert!(!w.to_json().contains("monte_carlo"));

    let mut v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let samples = v["monte_carlo"]["samples"].as_array().unwrap().clone();
    let (i, k) = samples
        .iter()
        .enumerate()
        .find_map(|(i, s)| (!s["light_samples"].as_array().unwrap().is_empty()).then_some((i, 0)))
        .expect("a sample with a light point");
    v["monte_carlo"]["samples"][i]["light_samples"][k]["light"] = 9999.into();
    let e = Trace::from_json(&v.to_string(), "bad.json")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&format!(
            "monte_carlo.samples[{i}].light_samples[{k}].light"
        )),
        "{e}"
    );
    let mut v: serde_json::Value = serde_json::from_str(&json).unwrap();
    v["monte_carlo"]["samples"].as_array_mut().unwrap().pop();
    let e = Trace::from_json(&v.to_string(), "bad.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("monte_carlo.samples") && e.contains("4"), "{e}");
    let mut v: serde_json::Value = serde_json::from_str(&json).unwrap();
    v["monte_carlo"]["lights"][0]["shape"]["radius"] = (-1.0).into();
    let e = Trace::from_json(&v.to_string(), "bad.json")
        .unwrap_err()
        .to_string();
    assert!(e.contains("monte_carlo.lights[0].shape.radius"), "{e}");
}

/// The lobe the hemisphere draws: a Lambert surface's density is cos θ / π in any plane
/// through the normal; a nearly smooth GGX surface's peaks at the mirror direction.
#[test]
fn the_hemisphere_lobe_against_closed_forms() {
    let f = PlaneFrame::new(
        Vec3::ZERO,
        Vec3::Y,
        Vec3::new(0.5, -1.0, 0.0).normalize(),
        Vec3::X,
    );
    let diffuse = Bsdf::Diffuse {
        albedo: Vec3::splat(0.5),
    };
    for (theta, p) in lobe(&diffuse, &f, 180) {
        let want = (theta.cos() / PI).max(0.0);
        assert!((p - want).abs() < 1e-5, "θ = {theta}: {p} against {want}");
    }
    let glossy = Bsdf::Glossy {
        tint: Vec3::ONE,
        alpha: 0.0009,
    };
    let pts = lobe(&glossy, &f, 1800);
    let peak = pts.iter().max_by(|a, b| a.1.total_cmp(&b.1)).unwrap().0;
    // The incoming ray travels (0.5, −1, 0): ωo = (−0.447, 0.894, 0) and the mirror direction
    // (0.447, 0.894, 0), atan(0.5) from the normal on the side opposite ωo.
    let (wo_theta, _) = f.angle(f.wo);
    let want = -wo_theta;
    assert!(
        (peak - want).abs() < 0.2f32.to_radians(),
        "peak at {}°, mirror at {}°",
        peak.to_degrees(),
        want.to_degrees()
    );
    assert!((want.abs() - 0.5f32.atan()).abs() < 1e-5);
}

/// Solid angles: the triangle (1,0,0), (0,1,0), (0,0,1) seen from the origin covers one octant
/// of the sphere, 4π/8; a sphere of radius r at distance d covers 2π(1 − √(1 − r²/d²)).
#[test]
fn solid_angles_against_closed_forms() {
    let octant = LightShape::Triangle {
        p: [Vec3::X, Vec3::Y, Vec3::Z],
        normal: Vec3::ONE.normalize(),
        area: 3f32.sqrt() / 2.0,
    };
    assert!((solid_angle(&octant, Vec3::ZERO) - PI / 2.0).abs() < 1e-6);
    let s = LightShape::Sphere {
        center: Vec3::new(0.0, 0.0, 5.0),
        radius: 3.0,
    };
    // r/d = 3/5: cos θmax = 4/5, Ω = 2π/5.
    assert!((solid_angle(&s, Vec3::ZERO) - 2.0 * PI / 5.0).abs() < 1e-5);
}

#[test]
fn each_monte_carlo_step_gets_its_diagram() {
    let prepared = PreparedScene::new(shipped("cornell-area.toml", Integrator::Path, 4));
    let t = prepared.record(10, 15, 0);
    let have = available(&t);
    for k in [
        DiagramKind::Hemisphere,
        DiagramKind::AreaLight,
        DiagramKind::Samples,
    ] {
        assert!(have.contains(&k), "{have:?}");
    }
    let tl = t.timeline();
    let light = tl
        .iter()
        .position(|(_, s)| matches!(s.step, Step::LightSample { .. }))
        .unwrap();
    assert_eq!(kinds_for_step(&t, light)[0], DiagramKind::AreaLight);
    let bounce = tl
        .iter()
        .position(|(_, s)| matches!(s.step, Step::BsdfSample { .. }))
        .unwrap();
    assert_eq!(kinds_for_step(&t, bounce)[0], DiagramKind::Hemisphere);
    // Every diagram draws at every step, at a small and a large size.
    for k in &have {
        for (w, h) in [(240, 180), (1200, 900)] {
            for step in [None, Some(light), Some(bounce)] {
                let opts = ViewOptions {
                    width: w,
                    height: h,
                    focus: step,
                    ..ViewOptions::default()
                };
                draw(&t, *k, &opts).unwrap();
            }
        }
    }
    // A Whitted trace has none of them.
    let w =
        PreparedScene::new(shipped("cornell-area.toml", Integrator::Whitted, 4)).record(10, 15, 0);
    let have = available(&w);
    assert!(!have.contains(&DiagramKind::Hemisphere) && !have.contains(&DiagramKind::Samples));
    // A light sample on a point light (the distribution tracer in a Whitted scene) has a
    // hemisphere but no area-light diagram.
    let p = PreparedScene::new(shipped("three-spheres.toml", Integrator::Distribution, 2));
    let t = p.record(16, 12, 0);
    if let Some(k) = t
        .timeline()
        .iter()
        .position(|(_, s)| matches!(s.step, Step::LightSample { .. }))
    {
        let kinds = kinds_for_step(&t, k);
        assert!(!kinds.contains(&DiagramKind::AreaLight), "{kinds:?}");
        assert_eq!(kinds[0], DiagramKind::Hemisphere);
    }
}

/// The samples plot: one dot per sample, filled with that sample's colour, at the height of its
/// luminance; the pixel's line at the luminance of the rendered pixel; the samples after the
/// traced one faded.
#[test]
fn the_samples_plot_puts_each_sample_and_the_pixel_where_their_values_say() {
    let prepared = PreparedScene::new(shipped("soft-shadows.toml", Integrator::Distribution, 16));
    let image = render(&prepared.tracer(), &RenderOptions::default())
        .unwrap()
        .pixels;
    let (x, y) = (16, 20);
    // The last sample traced: every dot is drawn in full (later samples would be faded).
    let t = prepared.record(x, y, 15);
    let opts = ViewOptions {
        width: 900,
        height: 600,
        ..ViewOptions::default()
    };
    let l = samples::layout(&t, &opts).unwrap();
    let [_, top, _, bottom] = l.area;
    let at = |v: f32| bottom - v / l.top_value * (bottom - top);
    let pixel = image[(y * 32 + x) as usize].to_array();
    assert!((l.mean_y - at(luminance(pixel))).abs() < 1e-3);
    let mc = t.monte_carlo.as_ref().unwrap();
    assert_eq!(l.dots.len(), 16);
    let c = draw(&t, DiagramKind::Samples, &opts).unwrap();
    for (s, d) in mc.samples.iter().zip(&l.dots) {
        let d = d.unwrap();
        assert!((d[1] - at(luminance(s.color))).abs() < 1e-3);
        let px = c.pixel(d[0].round() as u32, d[1].round() as u32).unwrap();
        let want = s.color.map(raystep::render::image::srgb8);
        for ch in 0..3 {
            assert!(
                (px[ch] as i32 - want[ch] as i32).abs() <= 2,
                "sample {}: {px:?} against {want:?}",
                s.sample
            );
        }
    }
    // Traced at sample 3, the dots of samples 4… are faded towards the background (white).
    let early = prepared.record(x, y, 3);
    let c = draw(&early, DiagramKind::Samples, &opts).unwrap();
    let mc = early.monte_carlo.as_ref().unwrap();
    let l = samples::layout(&early, &opts).unwrap();
    let mut checked = 0;
    for ((s, d), run) in mc.samples.iter().zip(&l.dots).zip(&l.running).skip(4) {
        let d = d.unwrap();
        // The running mean's line shows through a faded dot: look only at dots clear of it.
        if (run[1] - d[1]).abs() < 12.0 || (l.mean_y - d[1]).abs() < 12.0 {
            continue;
        }
        checked += 1;
        let px = c.pixel(d[0].round() as u32, d[1].round() as u32).unwrap();
        let full = s.color.map(raystep::render::image::srgb8);
        assert!(
            (0..3).all(|ch| px[ch] > full[ch]),
            "sample {}: {px:?} should be paler than {full:?}",
            s.sample
        );
    }
    assert!(checked > 0);
}

/// The 3D view draws a sample's path and its shadow rays: every light sample that reached its
/// light is a shadow ray drawn from the hit to the sampled point on the light.
#[test]
fn the_3d_view_draws_the_shadow_rays_to_the_sampled_points() {
    let s = shipped("cornell-area.toml", Integrator::Path, 4);
    let prepared = PreparedScene::new(s.clone());
    let t = prepared.record(10, 15, 2);
    let g = raystep::view3d::geometry::build(&s, Some(&t), &[], &Default::default());
    let mut checked = 0;
    for (_, st) in t.timeline() {
        // A light point below the surface or on the light's back is not worth a shadow ray.
        if let Step::LightSample {
            point,
            blocked: false,
            cos,
            radiance,
            ..
        } = st.step
            && cos > 0.0
            && radiance.iter().any(|c| *c > 0.0)
        {
            let p = Vec3::from(point);
            assert!(
                g.rays
                    .iter()
                    .any(|r| r.kind == raystep::record::RayKind::Shadow
                        && (r.origin + r.dir * r.length - p).length() < 1e-3 * (1.0 + p.length())),
                "no shadow ray ends at {p}: {:?}",
                g.rays
                    .iter()
                    .filter(|r| r.kind == raystep::record::RayKind::Shadow)
                    .map(|r| (r.origin + r.dir * r.length, r.end))
                    .collect::<Vec<_>>()
            );
            checked += 1;
        }
    }
    assert!(checked > 0);
    let bounces = t
        .rays()
        .iter()
        .filter(|r| r.kind == raystep::record::RayKind::Diffuse)
        .count();
    let drawn = g
        .rays
        .iter()
        .filter(|r| r.kind == raystep::record::RayKind::Diffuse)
        .count();
    assert_eq!(bounces, drawn);
    assert!(bounces > 0);
}

/// The ray tree labels a bounce with the colour it multiplies by (issue 48: the red wall's
/// bounce read "× 0.248", the mean of its albedo's channels): a cosine-sampled diffuse bounce's
/// weight f · cos θ / pdf is the albedo, here the red wall's (0.63, 0.065, 0.05) from the
/// scene file.
#[test]
fn the_ray_tree_weighs_a_red_bounce_with_red() {
    use raystep::diagram::ray_tree::rgb_weight;
    let prepared = PreparedScene::new(shipped("cornell-area.toml", Integrator::Path, 4));
    // The first pixel of the 32 × 24 copy's middle row whose primary ray hits the red wall.
    let t = (0..32)
        .map(|x| prepared.record(x, 12, 0))
        .find(|t| {
            t.root
                .hit
                .as_ref()
                .is_some_and(|h| h.name.starts_with("red wall"))
        })
        .expect("the red wall is in the middle row");
    let bounce = t
        .root
        .children
        .iter()
        .find(|c| c.kind == raystep::record::RayKind::Diffuse)
        .expect("the path goes on from the wall");
    let w = rgb_weight(&t.root, bounce).expect("the bounce's weight is in the steps");
    for (got, want) in w.iter().zip([0.63f32, 0.065, 0.05]) {
        assert!((got - want).abs() <= 1e-6, "{w:?}");
    }
    // The recorded scalar is their mean, what the label used to show.
    assert!((bounce.weight - (0.63 + 0.065 + 0.05) / 3.0).abs() < 1e-6);
    let text = raystep::diagram::ray_tree::weight_label(Some(&t.root), bounce);
    assert_eq!(text, "× (0.63, 0.065, 0.05)");
}

/// A scene whose camera sees a floor under a sphere lamp, traced by the distribution integrator.
fn lamp_over_floor() -> Scene {
    raystep::scene::load_str(
        "[camera]\nfrom = [0, 1, -4]\nat = [0, 0, 0]\nwidth = 16\nheight = 12\n\
         [render]\nintegrator = \"distribution\"\nspp = 1\n\
         [[material]]\nname = \"grey\"\nbsdf = \"diffuse\"\ncolor = [0.5, 0.5, 0.5]\n\
         [[material]]\nname = \"lamp\"\nbsdf = \"diffuse\"\ncolor = [0, 0, 0]\nemission = [10, 10, 10]\n\
         [[plane]]\nname = \"floor\"\naxis = \"y\"\nmaterial = \"grey\"\n\
         [[sphere]]\nname = \"lamp\"\ncenter = [0, 2, 0]\nradius = 0.5\nmaterial = \"lamp\"\n",
        "lamp.toml",
        None,
    )
    .unwrap()
}

/// A shadow ray ends just short of the point it aims at on the lamp: the lamp's own sphere test
/// finds its root there, at or beyond t_max, and the trace says so — not "something nearer was
/// already hit" (issue 48), since nothing was.
#[test]
fn a_shadow_ray_reaching_its_lamp_is_not_told_something_nearer_was_hit() {
    use raystep::record::RayKind;
    use raystep::shapes::RootChoice;
    let prepared = PreparedScene::new(lamp_over_floor());
    let t = prepared.record(8, 9, 0);
    assert_eq!(t.root.hit.as_ref().unwrap().name, "floor");
    let shadow = t
        .root
        .children
        .iter()
        .find(|c| c.kind == RayKind::Shadow)
        .expect("a shadow ray to the lamp");
    assert!(shadow.hit.is_none(), "nothing is in the way");
    let beyond = shadow
        .steps
        .iter()
        .find(|s| {
            matches!(&s.step, Step::Sphere { name, test, .. }
                if name == "lamp" && test.choice == RootChoice::BeyondTMax)
        })
        .expect("the lamp's own test finds its root at the ray's end");
    let line = raystep::explain::describe::describe(&beyond.step, RayKind::Shadow);
    assert!(!line.contains("something nearer"), "{line}");
    assert!(
        line.contains("shadow ray's end") && line.contains("not in the way"),
        "{line}"
    );
    let tree = raystep::explain::describe::tree(&t);
    assert!(!tree.contains("something nearer was already hit"), "{tree}");
    // The math panel says it too.
    let e = raystep::explain::formula::explain(&t, shadow, &beyond.step);
    assert!(
        e.conclusion.contains("shadow ray's end"),
        "{}",
        e.conclusion
    );
}

/// A camera ray that hits the Cornell box's ceiling lamp samples that lamp (or its other
/// half, in the same plane) from its own surface: every point of it is edge-on, so the
/// density per steradian is huge or 0 and the sample adds nothing. The trace and the math panel
/// say why; a light sample from the floor gets no such note.
#[test]
fn a_lamp_sampling_itself_is_explained() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-area.toml");
    let prepared = PreparedScene::new(load_file(&file).unwrap());
    let note_of = |x: u32, y: u32| {
        let t = prepared.record(x, y, 0);
        let sample = t
            .root
            .steps
            .iter()
            .find(|s| matches!(s.step, Step::LightSample { .. }))
            .expect("a light sample at the first hit")
            .step
            .clone();
        let note = raystep::explain::describe::own_light_note(&t, &t.root, &sample);
        let tree = raystep::explain::describe::tree(&t);
        let e = raystep::explain::formula::explain(&t, &t.root, &sample);
        (
            t.root.hit.as_ref().unwrap().name.clone(),
            note,
            tree,
            e.conclusion,
        )
    };
    let (hit, note, tree, conclusion) = note_of(128, 22);
    assert!(hit.starts_with("light "), "{hit}");
    let note = note.expect("the shading point is on the lamp");
    assert!(note.contains("on this light's own plane"), "{note}");
    assert!(tree.contains(&note), "{tree}");
    assert!(conclusion.contains("edge-on"), "{conclusion}");
    let (hit, note, _, _) = note_of(128, 230);
    assert!(hit.starts_with("floor"), "{hit}");
    assert_eq!(note, None);
}

/// The hemisphere's labels (ωo, the sampled direction, the lobe's peak density) never cover
/// one another and stay on the canvas, from a small panel to a large one (issue 48: at the app's
/// default panel size "p(ωi) up to …" lay over "ωo (to the eye)"); its panel of numbers is
/// wrapped, not cut, at the right edge.
#[test]
fn the_hemispheres_labels_do_not_overlap_at_any_size() {
    use raystep::diagram::hemisphere::draw_labelled;
    let cases = [
        // A diffuse wall's light sample, ωo near the normal: the lobe's label and ωo's met.
        (
            shipped("cornell-area.toml", Integrator::Path, 4),
            (10u32, 10u32),
        ),
        (shipped("veach-mis.toml", Integrator::Path, 4), (16, 20)),
    ];
    let mut drawn = 0;
    for (scene, (x, y)) in cases {
        let t = PreparedScene::new(scene).record(x, y, 0);
        for k in 0..t.timeline().len() {
            if !raystep::diagram::hemisphere::is_sample_step(&t.timeline()[k].1.step) {
                continue;
            }
            for (w, h) in [(320, 240), (400, 520), (800, 600)] {
                let opts = ViewOptions {
                    width: w,
                    height: h,
                    focus: Some(k),
                    ..Default::default()
                };
                let (c, labels) = draw_labelled(&t, &opts);
                assert!(labels.len() >= 2, "{labels:?}");
                for (i, a) in labels.iter().enumerate() {
                    let r = a.rect;
                    assert!(
                        r[0] >= 0.0 && r[1] >= 0.0 && r[2] <= c.width() && r[3] <= c.height(),
                        "{w}×{h}, step {k}: {a:?} leaves the canvas"
                    );
                    for b in &labels[i + 1..] {
                        let s = b.rect;
                        let apart = r[2] <= s[0] || s[2] <= r[0] || r[3] <= s[1] || s[3] <= r[1];
                        assert!(apart, "{w}×{h}, step {k}: {a:?} covers {b:?}");
                    }
                }
                drawn += 1;
            }
        }
    }
    assert!(drawn >= 6, "{drawn} hemispheres drawn");
}
