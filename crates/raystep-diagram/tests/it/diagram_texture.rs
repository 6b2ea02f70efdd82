//! The texture diagram drawn from a recorded `Texture` step: the point where the recorded
//! texel position puts it, each texel read drawn in its recorded colour (sRGB-encoded here by
//! the standard's formula) in the cell its recorded position says, a checker's squares in their
//! two colours with v pointing up.

use raystep_core::accel::SceneAccel;
use raystep_core::record::texturing::TexelLookup;
use raystep_core::record::{Step, Trace};
use raystep_core::scene::load_file;
use raystep_core::trace::Tracer;
use raystep_diagram::texture::layout;
use raystep_diagram::{DiagramKind, ViewOptions, available, draw, kinds_for_step};
use std::path::Path;

fn trace(x: u32, y: u32) -> Trace {
    let path = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/textures.toml"
    ));
    let scene = load_file(path).unwrap();
    let (accel, _) = SceneAccel::build(&scene);
    Tracer::new(&scene, &accel).record(x, y, 0)
}

/// sRGB encoding of a linear value (IEC 61966-2-1), to 8 bits.
fn srgb8(c: f32) -> u8 {
    let c = f64::from(c.clamp(0.0, 1.0));
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

fn texture_step(t: &Trace) -> (usize, &Step) {
    t.timeline()
        .into_iter()
        .enumerate()
        .find(|(_, (_, s))| matches!(s.step, Step::Texture { .. }))
        .map(|(k, (_, s))| (k, &s.step))
        .expect("a texture step")
}

fn close(a: [u8; 4], b: [u8; 3]) -> bool {
    (0..3).all(|k| a[k].abs_diff(b[k]) <= 1)
}

#[test]
fn bilinear_texels_sit_around_the_point_in_their_colours() {
    // (95, 100) is on the globe: a bilinear read of four texels.
    let t = trace(95, 100);
    let (k, step) = texture_step(&t);
    assert!(available(&t).contains(&DiagramKind::Texture));
    assert_eq!(kinds_for_step(&t, k)[0], DiagramKind::Texture);
    let Step::Texture {
        lookup: TexelLookup::Image {
            address, texels, ..
        },
        ..
    } = step
    else {
        panic!("{step:?}")
    };
    let o = ViewOptions::default();
    let l = layout(&t, &o).unwrap();
    assert_eq!(l.step, k);
    let want = l.at(f64::from(address[0]), f64::from(address[1]));
    assert_eq!(l.point_px, want);
    let c = draw(&t, DiagramKind::Texture, &o).unwrap();
    // The four texels: the first is the one whose centre is up and to the left of the point.
    let (x0, y0) = ((address[0] - 0.5).floor(), (address[1] - 0.5).floor());
    assert_eq!(texels.len(), 4);
    for (k, tx) in texels.iter().enumerate() {
        let cell = [x0 as f64 + (k & 1) as f64, y0 as f64 + (k >> 1) as f64];
        // A quarter in from the cell's corner nearest the point: inside the texel, clear of its
        // labels and of the point.
        let inner = [
            cell[0] + if k & 1 == 0 { 0.75 } else { 0.25 },
            cell[1] + if k >> 1 == 0 { 0.65 } else { 0.35 },
        ];
        let [px, py] = l.at(inner[0], inner[1]);
        let got = c.pixel(px as u32, py as u32).unwrap();
        let want = tx.color.map(srgb8);
        // The dashed square of the centres may cross it: look a few pixels around.
        let ok = (-3..=3).any(|d| {
            c.pixel((px + d as f32 * 2.0) as u32, py as u32)
                .is_some_and(|p| close(p, want))
        });
        assert!(ok, "texel {k} {:?}: {got:?} vs {want:?}", tx.at);
    }
}

#[test]
fn a_checkers_square_is_drawn_in_its_colour_with_v_up() {
    // (160, 200) is on the floor: square (−1, −2), odd.
    let t = trace(160, 200);
    let (_, step) = texture_step(&t);
    let Step::Texture {
        uv,
        lookup:
            TexelLookup::Checker {
                cell,
                colors,
                squares,
                ..
            },
        ..
    } = step
    else {
        panic!("{step:?}")
    };
    let o = ViewOptions::default();
    let l = layout(&t, &o).unwrap();
    let c = draw(&t, DiagramKind::Texture, &o).unwrap();
    // Window x = u·s₁ and y = −v·s₂: square (i, j) is the cell from (i, −j − 1) to (i + 1, −j).
    let p = l.at(
        f64::from(uv[0]) * f64::from(squares[0]),
        -(f64::from(uv[1]) * f64::from(squares[1])),
    );
    assert_eq!(l.point_px, p);
    for (di, dj) in [(0, 0), (1, 0), (0, 1), (-1, -1)] {
        let (i, j) = (cell[0] as i64 + di, cell[1] as i64 + dj);
        // A point a fifth of the way into the square (clear of its labels).
        let q = l.at(i as f64 + 0.2, (-j - 1) as f64 + 0.8);
        let got = c.pixel(q[0] as u32, q[1] as u32).unwrap();
        let want = colors[(i + j).rem_euclid(2) as usize].map(srgb8);
        assert!(close(got, want), "square ({i}, {j}): {got:?} vs {want:?}");
    }
}

#[test]
fn every_size_and_a_trace_without_a_texture() {
    let t = trace(95, 100);
    for (w, h, scale) in [
        (64, 64, 1.0),
        (300, 900, 1.0),
        (1920, 1080, 1.6),
        (4000, 200, 0.5),
    ] {
        let o = ViewOptions {
            width: w,
            height: h,
            scale,
            ..ViewOptions::default()
        };
        let c = draw(&t, DiagramKind::Texture, &o).unwrap();
        assert_eq!((c.width() as u32, c.height() as u32), (w, h));
    }
    // The sky (top-left corner) has no texture: no texture diagram is offered.
    let sky = trace(2, 2);
    assert!(!available(&sky).contains(&DiagramKind::Texture));
    assert!(draw(&sky, DiagramKind::Texture, &ViewOptions::default()).is_err());
}

/// A loaded trace may hold any numbers: a texture step whose point is 1e30 texels or squares
/// away, or not a number, still draws (the window is held to ±1e15).
#[test]
fn a_texture_step_with_absurd_numbers_still_draws() {
    for (x, y) in [(95, 100), (160, 200)] {
        for far in [1e30f32, -1e30, f32::NAN, f32::INFINITY] {
            let mut t = trace(x, y);
            for s in &mut t.root.steps {
                if let Step::Texture { uv, lookup, .. } = &mut s.step {
                    *uv = [far, far];
                    if let TexelLookup::Image { address, .. } = lookup {
                        *address = [far, far];
                    }
                }
            }
            let c = draw(&t, DiagramKind::Texture, &ViewOptions::default()).unwrap();
            assert_eq!(c.width(), 800.0);
        }
    }
}

/// A trilinear read (scenes/mipmap.toml's right-hand floor): the diagram shows the first level
/// read, its four texels around the point at that level's texel position, and dashes the ray
/// cone's footprint, L / 2^level texels across (between 1 and 2 where λ is inside the pyramid),
/// centred on the point, in the hit colour.
#[test]
fn a_trilinear_read_dashes_the_cones_footprint_at_its_level() {
    let path = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/mipmap.toml"
    ));
    let scene = load_file(path).unwrap();
    let (accel, _) = SceneAccel::build(&scene);
    let t = Tracer::new(&scene, &accel).record(250, 150, 0);
    let (_, step) = texture_step(&t);
    let Step::Texture {
        lookup:
            lookup @ TexelLookup::Image {
                address,
                lod: Some(lod),
                texels,
                ..
            },
        ..
    } = step
    else {
        panic!("{step:?}")
    };
    let level = lod.levels[0].level;
    assert!(level >= 1, "{lod:?}");
    assert_eq!(*address, lod.levels[0].address);
    let side = raystep_diagram::texture::footprint_side(lookup).unwrap();
    let want = f64::from(lod.footprint) / f64::from(1u32 << level);
    assert!(
        (side - want).abs() < 1e-9 && (1.0..2.0).contains(&side),
        "{side}"
    );
    assert!(texels[..4].iter().all(|t| t.level == level));
    let o = ViewOptions::default();
    let l = layout(&t, &o).unwrap();
    assert_eq!(
        l.point_px,
        l.at(f64::from(address[0]), f64::from(address[1]))
    );
    let c = draw(&t, DiagramKind::Texture, &o).unwrap();
    // The footprint's left edge: the hit colour on some of its pixels (it is dashed).
    let (x, y) = (f64::from(address[0]), f64::from(address[1]));
    let top = l.at(x - side / 2.0, y - side / 2.0);
    let bottom = l.at(x - side / 2.0, y + side / 2.0);
    let hit = c.theme.hit;
    let on_edge = (top[1] as u32..bottom[1] as u32)
        .filter(|&py| {
            (-1..=1).any(|dx| {
                c.pixel((top[0] as i32 + dx) as u32, py)
                    .is_some_and(|p| (0..3).all(|k| p[k].abs_diff(hit[k]) <= 8))
            })
        })
        .count();
    let len = (bottom[1] - top[1]) as usize;
    assert!(
        on_edge * 3 > len,
        "{on_edge} of {len} edge pixels in the hit colour"
    );
}
