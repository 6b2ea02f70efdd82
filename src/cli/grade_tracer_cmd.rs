//! `raystep grade-tracer`: run a student's own tracer and check its trace against raystep's.

use super::parse_pixel;
use crate::student::compare::Stage;
use crate::student::{self, Job, run::Limits};
use crate::trace::PreparedScene;
use std::path::{Path, PathBuf};

/// Arguments of `raystep grade-tracer`.
#[derive(Debug, clap::Args)]
pub struct GradeTracerArgs {
    /// The student's program, run once per pixel: `{scene}` (the scene file's path), `{x}` and
    /// `{y}` are replaced inside its words (split like a shell would, but never run by one).
    #[arg(long)]
    pub run: String,
    /// A grading sheet (TOML): scenes, pixels, per-student pixels, the last stage, limits.
    #[arg(long, conflicts_with_all = ["scene", "pixels"])]
    pub sheet: Option<PathBuf>,
    /// A quick check without a sheet: the scene file, or a built-in scene's name (`cornell`).
    #[arg(long, requires = "pixels")]
    pub scene: Option<PathBuf>,
    /// With --scene: the pixels, `X,Y;X,Y;…`.
    #[arg(long)]
    pub pixels: Option<String>,
    /// The student's id (draws a sheet's per-student pixels; names the report).
    #[arg(long, default_value = "student")]
    pub student: String,
    /// Grade a class: every subfolder of this folder is one submission (its name the student),
    /// the program run inside it.
    #[arg(long)]
    pub class: Option<PathBuf>,
    /// With --class: write the grades CSV here.
    #[arg(long, requires = "class")]
    pub csv: Option<PathBuf>,
    /// With --class: write each student's report (`<student>.txt`) and Gradescope
    /// `<student>.json` into this folder.
    #[arg(long, requires = "class")]
    pub out: Option<PathBuf>,
    /// The last stage checked (each includes the ones before; default: the sheet's, else color).
    #[arg(long, value_enum)]
    pub upto: Option<Stage>,
    /// Print Gradescope's `results.json` instead of the text report.
    #[arg(long, conflicts_with = "class")]
    pub json: bool,
    /// Seconds per run of the program (default: the sheet's, else 10).
    #[arg(long)]
    pub timeout: Option<f64>,
    /// Also check the student's rendered image of each scene: a PNG named by this pattern
    /// (`{stem}`: the scene file's stem), relative to the submission's folder (the current
    /// folder without --class), against raystep's render.
    #[arg(long)]
    pub image: Option<String>,
    /// With --image: levels of 255 a channel may differ by.
    #[arg(long, default_value_t = 2, requires = "image")]
    pub image_tolerance: u8,
    /// With --image: write the difference image here (`{stem}` and `{student}` replaced; with
    /// --class and --out, default `<out>/{student}-{stem}-diff.png`).
    #[arg(long, requires = "image")]
    pub diff: Option<String>,
    /// Keep each student's variant of a sheet's varied scenes in this folder (`<student>-…/<scene>`),
    /// so the feedback can name the file to open. Default: with --class and --out, `<out>/variants`;
    /// otherwise a private temporary folder, removed when grading ends.
    #[arg(long)]
    pub variants: Option<PathBuf>,
    /// Grade a path tracer that draws its own random numbers statistically, instead of sample by
    /// sample: the student's per-pixel sample statistics of each path-traced scene (a JSON Lines
    /// file named by this pattern, `{stem}` the scene file's stem, relative to the submission's
    /// folder; every pixel of the scene's image, each with the scene's spp samples or more)
    /// against raystep's render with a seed of the student's own, by Welch's t-test, per pixel
    /// and for the whole image; a correct image fails with probability about 1e-3. One test per
    /// scene, worth the sample-by-sample tests it replaces, first in the report.
    #[arg(long)]
    pub statistical: Option<String>,
    /// Let the students' programs run raystep (to try the grader with raystep's own output as a
    /// submission). By default raystep hides its own binary and any `raystep` on the PATH from
    /// them where the platform allows (Linux as root: a mount namespace per run).
    #[arg(long)]
    pub allow_raystep: bool,
    /// Megabytes of output per run; more stops the program.
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub max_output_mb: u32,
}

/// The quick check's pixels, `X,Y;X,Y`.
fn parse_pixels(s: &str) -> Result<Vec<[u32; 2]>, String> {
    s.split(';')
        .filter(|p| !p.trim().is_empty())
        .map(|p| parse_pixel(p).map_err(|e| format!("--pixels: {e}")))
        .collect::<Result<Vec<_>, _>>()
        .and_then(|v| {
            if v.is_empty() {
                Err("--pixels lists no pixel (X,Y;X,Y…)".into())
            } else {
                Ok(v)
            }
        })
}

/// Runs `raystep grade-tracer`.
pub fn run(args: &GradeTracerArgs) -> Result<(), String> {
    // Nothing a student's program starts outlives its run; raystep out of its reach.
    student::isolate::reap_descendants();
    if !args.allow_raystep
        && let Err(why) = student::isolate::hide_raystep()
    {
        eprintln!(
            "note: raystep is not hidden from the students' programs here: {why} (output that is raystep's own trace text is still named in the reports)"
        );
    }
    if let Some(csv) = &args.csv {
        let mut inputs = vec![];
        if let Some(p) = &args.sheet {
            inputs.push(("the grading sheet", p.as_path()));
        }
        if let Some(p) = &args.scene {
            inputs.push(("the scene", p.as_path()));
        }
        crate::io::check_outputs(&inputs, &[("--csv", csv)])?;
    }
    let sheet = match &args.sheet {
        Some(p) => Some(student::load_tracer_sheet(p)?),
        None => None,
    };
    let quick: Option<Job> = match (&args.scene, &args.pixels) {
        (Some(arg), Some(px)) => {
            let pixels = parse_pixels(px)?;
            // A file, or a built-in scene by name (its unpacked copy is what the student's
            // program is given).
            let path = &crate::assets::resolve_scene(arg)?;
            let scene = crate::scene::load_file(path).map_err(|e| e.to_string())?;
            student::gradable(&scene, path)?;
            let (w, h) = (scene.camera.width, scene.camera.height);
            if let Some([x, y]) = pixels.iter().find(|[x, y]| *x >= w || *y >= h) {
                return Err(format!(
                    "--pixels: ({x}, {y}) is outside the {w}×{h} image of {}",
                    path.display()
                ));
            }
            let abs = std::path::absolute(path).unwrap_or(path.clone());
            Some(Job::new(
                abs,
                std::sync::Arc::new(PreparedScene::new(scene)),
                pixels,
            ))
        }
        _ if sheet.is_none() => {
            return Err("give a --sheet, or --scene and --pixels".into());
        }
        _ => None,
    };
    let upto = args
        .upto
        .or(sheet.as_ref().map(|s| s.upto))
        .unwrap_or(Stage::Color);
    let tol = sheet.as_ref().and_then(|s| s.tolerance).unwrap_or_default();
    let timeout = args
        .timeout
        .or(sheet.as_ref().and_then(|s| s.timeout_s))
        .unwrap_or(10.0);
    if !(timeout.is_finite() && timeout > 0.0 && timeout <= 3600.0) {
        return Err(format!(
            "--timeout {timeout}: give a number of seconds in (0, 3600]"
        ));
    }
    let limits = Limits {
        timeout: student::seconds(timeout),
        max_output: args.max_output_mb as usize * (1 << 20),
    };
    // Where the students' variants of varied scenes go (removed at the end when private).
    let variants = match args.variants.clone().or_else(|| {
        args.class
            .is_some()
            .then(|| args.out.as_ref().map(|o| o.join("variants")))
            .flatten()
    }) {
        Some(dir) => student::VariantDir::Kept(dir),
        None => student::VariantDir::private()?,
    };
    let jobs_for = |who: &str| -> Result<Vec<Job>, String> {
        match (&sheet, &args.sheet, &quick) {
            (Some(s), Some(p), _) => student::sheet_jobs(s, p, who, &variants),
            (_, _, Some(job)) => Ok(vec![job.clone()]),
            _ => Err("no scenes to grade".into()),
        }
    };
    let image = args.image.as_ref().map(|pattern| student::ImageSpec {
        pattern: pattern.clone(),
        tolerance: args.image_tolerance,
        diff: args.diff.clone().or_else(|| {
            (args.class.is_some())
                .then_some(args.out.as_ref())
                .flatten()
                .map(|o| o.join("{student}-{stem}-diff.png").display().to_string())
        }),
    });
    if let Some(class) = &args.class {
        let reports = student::grade_tracer_class(
            class,
            &args.run,
            &jobs_for,
            upto,
            &tol,
            limits,
            image.as_ref(),
            args.statistical.as_deref(),
        )?;
        if reports.is_empty() {
            return Err(format!("{}: no submission folders in it", class.display()));
        }
        if let Some(dir) = &args.out {
            std::fs::create_dir_all(dir)
                .map_err(|e| format!("{}: cannot create: {e}", dir.display()))?;
            for r in &reports {
                crate::io::write_atomic(
                    &dir.join(format!("{}.txt", r.student)),
                    r.text().as_bytes(),
                )?;
                crate::io::write_atomic(
                    &dir.join(format!("{}.json", r.student)),
                    student::gradescope_json(r).as_bytes(),
                )?;
            }
        }
        let csv = student::grades_csv(&reports);
        if let Some(p) = &args.csv {
            crate::io::write_atomic(p, csv.as_bytes())?;
        }
        let mut text = String::new();
        for r in &reports {
            text += &format!(
                "{}: {} / {} ({:.1} s)\n",
                r.student,
                r.score(),
                r.max_score(),
                r.seconds
            );
        }
        if let Some(p) = &args.csv {
            text += &format!("wrote {}\n", super::full_path(p));
        }
        return super::emit(&text);
    }
    let mut jobs = jobs_for(&args.student)?;
    for j in &mut jobs {
        j.statistical = args.statistical.is_some();
    }
    let mut report = student::grade_submission(
        &args.student,
        &args.run,
        Path::new("."),
        &jobs,
        upto,
        &tol,
        limits,
    );
    if let Some(spec) = &image {
        student::check_images(&mut report, Path::new("."), &jobs, spec);
    }
    if let Some(pattern) = &args.statistical {
        student::check_statistical(&mut report, Path::new("."), &jobs, pattern, upto);
    }
    if args.json {
        super::emit(&student::gradescope_json(&report))
    } else {
        super::emit(&report.text())
    }
}
