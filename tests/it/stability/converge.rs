//! The command line's `stability` and `converge`: tables, plots, the fall of the error with spp,
//! strategies against one reference, the target, the noise.

use super::*;

#[test]
fn stability_quick_writes_markdown_csv_and_plots() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lab");
    Command::cargo_bin("raystep")
        .unwrap()
        .args(["stability", "--quick", "--out"])
        .arg(&out)
        .assert()
        .success();
    let csv = std::fs::read_to_string(out.join("stability.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header, raystep::stability::report::CSV_COLUMNS);
    let mut n = 0;
    for line in lines {
        let fields = csv_fields(line);
        assert_eq!(fields.len(), header.len(), "{line}");
        assert!(fields[0].starts_with('S'));
        assert!(["f32", "f64"].contains(&fields[4].as_str()));
        for (k, f) in fields.iter().enumerate().skip(5) {
            if f.is_empty() {
                assert!(header[k].starts_with("uv_"), "{}: empty", header[k]);
                continue;
            }
            let v: f64 = f.parse().unwrap_or_else(|_| panic!("{}: {f}", header[k]));
            assert!(v >= 0.0, "{}: {v}", header[k]);
        }
        n += 1;
    }
    assert!(n > 50, "only {n} rows");
    let md = std::fs::read_to_string(out.join("stability.md")).unwrap();
    assert!(md.contains("| primitive | method | precision |"));
    // The Monte Carlo cases: their own CSV (a header, then 2 methods × f32/f64 × 10 quantities
    // of S26–S28, and S29's area in f32), and a section of the Markdown.
    assert!(md.contains("## Monte Carlo sampling (S26–S29)"));
    let mc = std::fs::read_to_string(out.join("stability-mc.csv")).unwrap();
    let mut lines = mc.lines();
    assert_eq!(
        lines.next().unwrap(),
        raystep::stability::report::MC_CSV_COLUMNS.join(",")
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 2 * 2 * 10 + 2, "{mc}");
    for line in rows {
        let f = csv_fields(line);
        assert_eq!(
            f.len(),
            raystep::stability::report::MC_CSV_COLUMNS.len(),
            "{line}"
        );
        assert!(
            ["S26", "S27", "S28", "S29"].contains(&f[0].as_str()),
            "{line}"
        );
        assert!(["textbook", "stable"].contains(&f[3].as_str()));
        assert!(["f32", "f64"].contains(&f[4].as_str()));
        for x in &f[5..] {
            let v: f64 = x.parse().unwrap_or_else(|_| panic!("{line}"));
            assert!(v >= 0.0 && v.is_finite(), "{line}");
        }
    }
    for prim in ["sphere", "triangle", "plane", "box", "spawn"] {
        assert_eq!(
            png_size(&out.join(format!("stability-{prim}.png"))),
            (900, 600)
        );
    }
}

#[test]
fn converge_writes_tables_and_plots_and_mse_falls_like_one_over_spp() {
    let dir = tempfile::tempdir().unwrap();
    // A small copy of the first lesson's scene: the ball's edge is all the noise there is.
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/first-sphere.toml"),
    )
    .unwrap()
    .replace("width = 320", "width = 96")
    .replace("height = 240", "height = 72");
    let scene = dir.path().join("small.toml");
    std::fs::write(&scene, text).unwrap();
    let out = dir.path().join("conv");
    Command::cargo_bin("raystep")
        .unwrap()
        .args(["converge"])
        .arg(&scene)
        .args(["--max-spp", "16", "--seeds", "3", "--out"])
        .arg(&out)
        .assert()
        .success();
    let csv = std::fs::read_to_string(out.join("converge.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        raystep::stability::converge::CSV_COLUMNS.join(",")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 5 * 3, "spp 1, 2, 4, 8, 16 × 3 seeds");
    assert!(
        rows.iter()
            .all(|r| r.len() == 9 && r[6] == 0.0 && r[7] == 0.0)
    );
    // Median MSE per level, and the log–log slope against spp.
    let mut pts = vec![];
    for spp in [1.0, 2.0, 4.0, 8.0, 16.0] {
        let mut m: Vec<f64> = rows.iter().filter(|r| r[0] == spp).map(|r| r[3]).collect();
        m.sort_by(f64::total_cmp);
        pts.push((f64::ln(spp), m[1].ln()));
    }
    let slope = raystep::stability::converge::slope(&pts);
    println!("MSE slope {slope:.2}");
    // Independent samples give −1; raystep's jitter is stratified, which at the ball's edge
    // (the only noise here) tends to −1.5 (measured −1.39 on this scene). Accept both regimes.
    assert!((-1.7..=-0.6).contains(&slope), "slope {slope}");
    let md = std::fs::read_to_string(out.join("converge.md")).unwrap();
    assert!(md.contains("ε = 0.01") && md.contains("Equal time") && md.contains("FLIP"));
    assert_eq!(png_size(&out.join("converge-spp.png")), (900, 600));
    assert_eq!(png_size(&out.join("converge-time.png")), (900, 600));
}

/// `converge --strategy`: under a small sphere light over a diffuse plane, BSDF sampling alone
/// finds the light with probability (r/h)² = 1/16 per sample (a Bernoulli estimator of relative
/// variance 15 per sample), light sampling alone samples the cone the light subtends (its
/// estimate varies only with cos θ): light sampling and MIS must be far below BSDF sampling,
/// and each estimator, its samples independent, must fall like 1/spp.
#[test]
fn converge_compares_strategies_against_one_reference() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("lamp.toml");
    std::fs::write(
        &scene,
        "[camera]\nfrom = [0, 3, -3]\nat = [0, 0, 0]\nwidth = 32\nheight = 24\nfov = 10\n\
         [render]\nintegrator = \"path\"\nmax_depth = 1\n\
         [[material]]\nname = \"grey\"\nbsdf = \"diffuse\"\ncolor = [0.5, 0.5, 0.5]\n\
         [[material]]\nname = \"lamp\"\ncolor = [0, 0, 0]\nbsdf = \"diffuse\"\nemission = [10, 10, 10]\n\
         [[plane]]\naxis = \"y\"\nmaterial = \"grey\"\n\
         [[sphere]]\ncenter = [0, 2, 0]\nradius = 0.5\nmaterial = \"lamp\"\n",
    )
    .unwrap();
    let out = dir.path().join("conv");
    let run = Command::cargo_bin("raystep")
        .unwrap()
        .args(["converge"])
        .arg(&scene)
        .args([
            "--strategy",
            "light,bsdf,mis",
            "--max-spp",
            "16",
            "--seeds",
            "3",
            "--out",
        ])
        .arg(&out)
        .assert()
        .success()
        .get_output()
        .clone();
    let md = String::from_utf8_lossy(&run.stdout);
    assert!(md.contains("| strategy | relMSE at 16 spp"), "{md}");
    // Progress went to stderr although it is a pipe here, not a terminal: a line for each of
    // the reference's passes (issue 48: nothing came for minutes), then each level.
    let progress = String::from_utf8_lossy(&run.stderr);
    let reference_lines = progress
        .lines()
        .filter(|l| l.contains("of the MIS reference's 256 spp"))
        .count();
    assert_eq!(
        reference_lines,
        raystep::stability::converge::REFERENCE_STEPS as usize - 1,
        "{progress}"
    );
    assert!(
        progress.contains("the reference (256 spp, MIS) done"),
        "{progress}"
    );
    assert!(progress.contains("mis: level 16 spp"), "{progress}");
    let csv = std::fs::read_to_string(out.join("converge.csv")).unwrap();
    assert!(csv.starts_with("strategy,spp,seed,"));
    // The median relMSE at 16 spp, and the MSE slope, per strategy.
    let mut top = std::collections::BTreeMap::new();
    for name in ["light", "bsdf", "mis"] {
        let rows: Vec<Vec<f64>> = csv
            .lines()
            .filter_map(|l| l.strip_prefix(&format!("{name},")))
            .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows.len(), 5 * 3, "{name}");
        let median = |spp: f64, k: usize| {
            let mut m: Vec<f64> = rows.iter().filter(|r| r[0] == spp).map(|r| r[k]).collect();
            m.sort_by(f64::total_cmp);
            m[1]
        };
        let pts: Vec<(f64, f64)> = [1.0, 2.0, 4.0, 8.0, 16.0]
            .iter()
            .map(|s| (f64::ln(*s), median(*s, 3).ln()))
            .collect();
        let slope = raystep::stability::converge::slope(&pts);
        println!(
            "{name}: relMSE at 16 spp {}, MSE slope {slope:.2}",
            median(16.0, 5)
        );
        assert!((-1.5..=-0.6).contains(&slope), "{name}: slope {slope}");
        top.insert(name, median(16.0, 5));
        assert_eq!(
            png_size(&out.join(format!("converge-{name}.png"))),
            (32, 24)
        );
    }
    assert!(top["light"] * 10.0 < top["bsdf"], "{top:?}");
    assert!(top["mis"] * 10.0 < top["bsdf"], "{top:?}");
    assert_eq!(png_size(&out.join("converge-spp.png")), (900, 600));
}

/// The time to a target error, interpolated on the log–log line: levels (1 s, relMSE 0.4) and
/// (2 s, 0.1) reach 0.2 at √2 s (ln t = ln 2 · ln 2 / ln 4); a target below every level is not
/// reached; one the first level meets is its time; an early dip below it does not count.
#[test]
fn time_to_relmse_interpolates_on_the_log_log_line() {
    use raystep::stability::converge::{ConvergeReport, time_to_relmse};
    let r = ConvergeReport {
        scene: "s".into(),
        device: "CPU".into(),
        size: [1, 1],
        build_seconds: 0.0,
        reference_spp: 16,
        reference_seconds: 0.0,
        measured_pixels: 1,
        left_out_pixels: 0,
        samples: vec![],
        levels: vec![level(1, 1.0, 0.4), level(2, 2.0, 0.1)],
        mse_slope: -2.0,
        image: vec![],
    };
    let t = time_to_relmse(&r, 0.2).unwrap();
    assert!((t - 2f64.sqrt()).abs() < 1e-12, "{t}");
    assert_eq!(time_to_relmse(&r, 0.05), None);
    assert_eq!(time_to_relmse(&r, 0.5), Some(1.0));
    // Below the target at 1 spp, above at 2, below at 4: it is reached between 2 and 4 spp.
    let mut r = r;
    r.levels = vec![level(1, 1.0, 0.1), level(2, 2.0, 0.4), level(4, 4.0, 0.1)];
    let t = time_to_relmse(&r, 0.2).unwrap();
    assert!((t - 2.0 * 2f64.sqrt()).abs() < 1e-12, "{t}");
}

/// The target of a comparison of strategies: by default one every strategy crosses between two
/// of its levels (the geometric mean of the largest last-level relMSE and the smallest
/// first-level one); none when their ranges do not overlap; and each strategy's reach of a
/// given target says how it was found.
#[test]
fn the_default_target_is_crossed_by_every_strategy() {
    use raystep::scene::Strategy;
    use raystep::stability::converge::{
        ConvergeReport, Reach, StrategyRun, Target, default_target, reach, strategy_table,
    };
    let run = |strategy, rel: &[f64]| StrategyRun {
        strategy,
        report: ConvergeReport {
            scene: "s".into(),
            device: "CPU".into(),
            size: [1, 1],
            build_seconds: 0.0,
            reference_spp: 64,
            reference_seconds: 0.0,
            measured_pixels: 1,
            left_out_pixels: 0,
            samples: vec![],
            levels: rel
                .iter()
                .enumerate()
                .map(|(k, &e)| level(1 << k, f64::from(1u32 << k), e))
                .collect(),
            mse_slope: -1.0,
            image: vec![],
        },
    };
    // light 8 → 2, mis 4 → 1: every error in (2, 4) is crossed by both; the default is √8.
    let runs = vec![
        run(Strategy::Light, &[8.0, 4.0, 2.0]),
        run(Strategy::Mis, &[4.0, 2.0, 1.0]),
    ];
    let t = default_target(&runs).unwrap();
    assert!((t - 8f64.sqrt()).abs() < 1e-12, "{t}");
    // Each crosses it between two of its levels: light between 2 and 4 spp, mis between 1 and 2.
    assert!(matches!(
        reach(&runs[0].report, t),
        Reach::Crossed { spp: [2, 4], .. }
    ));
    assert!(matches!(
        reach(&runs[1].report, t),
        Reach::Crossed { spp: [1, 2], .. }
    ));
    let (head, rows) = strategy_table(&runs, Target::of(&runs, None));
    assert!(head[5].ends_with("(default)"), "{head:?}");
    assert!(
        rows.iter().all(|r| r[5].contains(" s (between ")),
        "{rows:?}"
    );
    // bsdf still at 10 after light's and mis's first levels: no common error, no default.
    let runs = vec![
        run(Strategy::Light, &[8.0, 4.0, 2.0]),
        run(Strategy::Bsdf, &[0.5, 3.0, 10.0]),
        run(Strategy::Mis, &[0.06, 0.04, 0.02]),
    ];
    assert_eq!(default_target(&runs), None);
    assert_eq!(Target::of(&runs, None), Target::Missing);
    let (head, rows) = strategy_table(&runs, Target::Missing);
    assert_eq!(head[5], "time to a common relMSE");
    assert!(rows.iter().all(|r| r[5] == "none: see below"), "{rows:?}");
    // A given target 3: light crosses it, bsdf never gets back below it, mis is there at once.
    let given = Target::of(&runs, Some(3.0));
    assert_eq!(given, Target::Given(3.0));
    assert!(matches!(
        reach(&runs[0].report, 3.0),
        Reach::Crossed { spp: [2, 4], .. }
    ));
    assert_eq!(reach(&runs[1].report, 3.0), Reach::NotReached { spp: 4 });
    assert_eq!(
        reach(&runs[2].report, 3.0),
        Reach::AtFirst {
            seconds: 1.0,
            spp: 1
        }
    );
    let (head, rows) = strategy_table(&runs, given);
    assert_eq!(head[5], "time to relMSE 3 (given)");
    assert_eq!(rows[1][5], "not reached by 4 spp");
    assert_eq!(rows[2][5], "≤ 1 s (already at 1 spp)");
}

/// A small copy of lesson 13's scene (soft shadows under two sphere lights, both in the
/// picture): the pixels that see a lamp are left out of the errors, and over the rest the MSE
/// is Monte Carlo noise: with independent samples it falls like 1/spp, and stratified samples
/// have less of it at 16 spp (issue 48: with the lamps' edge pixels in, both samplers had the
/// same MSE at every level and it rose from 1 to 2 spp).
#[test]
fn converge_measures_the_noise_and_stratified_samples_have_less() {
    use raystep::scene::SamplerKind;
    use raystep::stability::converge::{ConvergeOptions, direct_emitters, run};
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/soft-shadows.toml"),
    )
    .unwrap()
    .replace("width = 320", "width = 96")
    .replace("height = 240", "height = 72");
    let scene = raystep::scene::load_str(&text, "small.toml", None).unwrap();
    // Every pixel brighter than anything lit can be (it sees a lamp of radiance 400 or more
    // directly) is left out, and most of the picture is measured.
    let mut bright = scene.clone();
    bright.settings.spp = 64;
    let prepared = raystep::trace::PreparedScene::new(bright);
    let image = raystep::render::render(&prepared.tracer(), &Default::default())
        .unwrap()
        .pixels;
    let left_out = direct_emitters(&raystep::trace::PreparedScene::new(scene.clone()));
    let lamps = image.iter().filter(|p| p.max_element() > 5.0).count();
    assert!(
        lamps >= 3,
        "the small picture shows the lamps: {lamps} pixels"
    );
    for (i, p) in image.iter().enumerate() {
        assert!(
            p.max_element() <= 5.0 || left_out[i],
            "pixel {i} sees a lamp: {p}"
        );
    }
    let out = left_out.iter().filter(|o| **o).count();
    assert!(out < image.len() / 10, "{out} of {} left out", image.len());

    let opts = ConvergeOptions {
        max_spp: 16,
        seeds: 2,
        ..Default::default()
    };
    let mut top = vec![];
    for sampler in [SamplerKind::Independent, SamplerKind::Stratified] {
        let mut s = scene.clone();
        s.settings.sampler = sampler;
        let r = run(&s, &opts).unwrap();
        assert_eq!(r.left_out_pixels, out);
        assert_eq!(r.measured_pixels + out, image.len());
        let mse: Vec<f64> = r.levels.iter().map(|l| l.mse[1]).collect();
        println!("{sampler:?}: MSE {mse:?}, slope {:.2}", r.mse_slope);
        // The error falls at every level.
        assert!(mse.windows(2).all(|w| w[1] < w[0]), "{sampler:?}: {mse:?}");
        if sampler == SamplerKind::Independent {
            assert!(
                (-1.25..=-0.8).contains(&r.mse_slope),
                "slope {}",
                r.mse_slope
            );
        }
        top.push(mse[4]);
    }
    assert!(
        top[1] < 0.75 * top[0],
        "stratified {} against independent {}",
        top[1],
        top[0]
    );
}

/// A convergence level at `spp` after `seconds` whose every error (MSE, RMSE, relMSE, in each
/// channel) is `e`, with no NaN or infinite pixel.
fn level(spp: u32, seconds: f64, e: f64) -> raystep::stability::converge::Level {
    raystep::stability::converge::Level {
        spp,
        seconds,
        mse: [e; 3],
        rmse: [e; 3],
        relmse: [e; 3],
        mse_all: [e; 3],
        nan: 0,
        inf: 0,
    }
}
