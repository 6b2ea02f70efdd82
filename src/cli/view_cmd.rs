//! `raystep view`: the app's 3D scene view drawn headless into a PNG (for slides and tests): the
//! scene, the camera with its image plane and the selected pixel's rays up to a step.

use super::{SettingsArgs, parse_pixel};
use crate::diagram::Theme;
use crate::view3d::camera::Orbit;
use crate::view3d::{self, Viewpoint, geometry};
use std::path::PathBuf;

/// Arguments of `raystep view`.
#[derive(Debug, clap::Args)]
pub struct ViewArgs {
    /// A scene file (.toml) or a built-in scene's name.
    pub scene: PathBuf,
    /// The pixel X,Y whose rays are drawn.
    #[arg(long, value_parser = parse_pixel)]
    pub pixel: Option<[u32; 2]>,
    /// Draw the rays up to step K: the `[K]` that `raystep trace` prints before the step
    /// (counted from 0, as in the app's step list); default: the whole trace.
    #[arg(long)]
    pub step: Option<usize>,
    /// Orbit YAW,PITCH in degrees around the scene (0,0 = from behind the scene's camera);
    /// default 35,25.
    #[arg(long, value_parser = parse_orbit, allow_hyphen_values = true)]
    pub orbit: Option<[f32; 2]>,
    /// Distance from the scene's centre, as a multiple of the distance that fits the whole scene
    /// (1 = fits; 0.5 = twice as close), 0.02 … 50.
    #[arg(long, default_value_t = 0.8, value_parser = parse_distance)]
    pub distance: f32,
    /// Orbit about this point X,Y,Z instead of the scene's centre.
    #[arg(long, value_parser = super::parse_vec3, allow_hyphen_values = true)]
    pub look_at: Option<[f64; 3]>,
    /// Look through the scene's camera (the view matches the render) instead of orbiting.
    #[arg(long, conflicts_with_all = ["orbit", "look_at"])]
    pub through_camera: bool,
    /// Also draw the rays of an N×N grid of pixels (the camera's fan of rays), 1 … 32.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=32))]
    pub grid: Option<u32>,
    /// Draw the BVH boxes the current ray visited so far.
    #[arg(long)]
    pub bvh: bool,
    /// Draw the objects translucent, to see the rays inside them.
    #[arg(long)]
    pub see_through: bool,
    /// Picture size WxH (64 … 8192 a side); default 1280x720, or with --through-camera the
    /// camera's proportions within 1280x720 (a picture of other proportions would be stretched).
    #[arg(long, value_parser = parse_size)]
    pub size: Option<[u32; 2]>,
    /// Colour theme.
    #[arg(long, value_enum, default_value_t = super::diagram_cmd::ThemeArg::Dark)]
    pub theme: super::diagram_cmd::ThemeArg,
    /// Output file (.png).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Setting overrides.
    #[command(flatten)]
    pub settings: SettingsArgs,
}

fn parse_orbit(s: &str) -> Result<[f32; 2], String> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| format!("expected YAW,PITCH in degrees, got \"{s}\""))?;
    let num = |t: &str, what: &str| -> Result<f32, String> {
        let v: f32 = t
            .trim()
            .parse()
            .map_err(|_| format!("--orbit: \"{t}\" is not a number ({what})"))?;
        if !v.is_finite() {
            return Err(format!("--orbit: the {what} must be finite"));
        }
        Ok(v)
    };
    let pitch = num(b, "pitch")?;
    if !(-89.0..=89.0).contains(&pitch) {
        return Err(format!(
            "--orbit: the pitch must be between -89 and 89 degrees, got {pitch}"
        ));
    }
    Ok([num(a, "yaw")?, pitch])
}

fn parse_distance(s: &str) -> Result<f32, String> {
    let v: f32 = s
        .trim()
        .parse()
        .map_err(|_| format!("\"{s}\" is not a number"))?;
    if !(0.02..=50.0).contains(&v) {
        return Err(format!("{s}: the distance must be between 0.02 and 50"));
    }
    Ok(v)
}

fn parse_size(s: &str) -> Result<[u32; 2], String> {
    super::parse_size_within(s, view3d::gpu::MAX_SIDE)
}

/// The picture's size. Looking through the camera draws the camera's view at the camera's
/// proportions (the view keeps them, so another shape would stretch the picture): by default the
/// largest such picture within 1280×720, and a --size of other proportions is refused.
fn picture_size(
    size: Option<[u32; 2]>,
    through_camera: bool,
    c: &crate::scene::Camera,
) -> Result<[u32; 2], String> {
    let (cw, ch) = (f64::from(c.width.max(1)), f64::from(c.height.max(1)));
    match (size, through_camera) {
        (Some([w, h]), true) if (f64::from(w) * ch / cw - f64::from(h)).abs() > 1.0 => {
            Err(format!(
                "--size {w}x{h}: --through-camera draws the camera's view, which is {}×{}: give \
             --size the same proportions (e.g. {}x{}), or leave it out",
                c.width,
                c.height,
                w,
                (f64::from(w) * ch / cw).round()
            ))
        }
        (Some(s), _) => Ok(s),
        (None, false) => Ok([1280, 720]),
        (None, true) => {
            let k = (1280.0 / cw).min(720.0 / ch);
            let side = |v: f64| ((v * k).round() as u32).clamp(64, view3d::gpu::MAX_SIDE);
            Ok([side(cw), side(ch)])
        }
    }
}

/// Runs `raystep view`.
pub fn run(args: &ViewArgs) -> Result<(), String> {
    super::check_png_path(&args.output)?;
    let scene = super::load_scene(Some(&args.scene), &args.settings)?;
    let prepared = crate::PreparedScene::new(scene);
    let c = &prepared.scene().camera;
    let trace = match args.pixel {
        Some([x, y]) => {
            if x >= c.width || y >= c.height {
                return Err(format!(
                    "--pixel {x},{y} is outside the {}×{} image",
                    c.width, c.height
                ));
            }
            Some(prepared.record(x, y, 0))
        }
        None if args.step.is_some() => return Err("--step needs --pixel X,Y".into()),
        None => None,
    };
    if let (Some(t), Some(k)) = (&trace, args.step) {
        let steps = t.timeline().len();
        if k >= steps {
            return Err(format!(
                "--step {k} does not exist: this trace has {steps} steps (0 … {})",
                steps - 1
            ));
        }
    }
    let size = picture_size(args.size, args.through_camera, c)?;
    let fan = args
        .grid
        .map(|n| view3d::fan_traces(&prepared, n))
        .unwrap_or_default();
    let options = geometry::Options {
        step: args.step,
        bvh: args.bvh,
        see_through: args.see_through,
        selected: None,
        eye: None,
        camera: true,
        theme: if args.theme == super::diagram_cmd::ThemeArg::Dark {
            Theme::DARK
        } else {
            Theme::LIGHT
        },
    };
    let viewpoint = if args.through_camera {
        Viewpoint::Camera
    } else {
        let [yaw, pitch] = args.orbit.unwrap_or([35.0, 25.0]);
        let center = geometry::bounds(prepared.scene()).center;
        let pan = args.look_at.map_or([0.0; 3], |p| {
            (glam::Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32) - center).to_array()
        });
        Viewpoint::Orbit(Orbit {
            yaw,
            pitch,
            distance: args.distance,
            pan,
        })
    };
    let ctx = crate::gpu::GpuContext::headless().map_err(|e| e.to_string())?;
    let adapter = ctx.adapter_name();
    let mut renderer = view3d::gpu::Renderer::new(ctx).map_err(|e| e.to_string())?;
    let img = view3d::render_image(
        &mut renderer,
        &prepared,
        trace.as_ref(),
        &fan,
        &options,
        viewpoint,
        size,
    )
    .map_err(|e| e.to_string())?;
    let drawn = renderer.last_frame;
    // The GPU's pictures and buffers go before the PNG is encoded.
    drop(renderer);
    crate::render::image::write_png(&args.output, &img)?;
    super::emit(&format!(
        "wrote {} ({}×{}, drawn in {:.1} ms on {adapter})\n",
        args.output.display(),
        size[0],
        size[1],
        drawn.as_secs_f64() * 1e3
    ))
}
