//! The quick suite: the defaults' key cases, the documented failures of the textbook methods,
//! no NaN, the failure scenes (a leaky edge, acne), and the suite run a case a step.

use super::*;

#[test]
fn defaults_have_no_misclassifications_or_leaks_on_the_key_cases() {
    let r = quick();
    for case in ["S1", "S3", "S6", "S12", "S13"] {
        for m in [Method::SphereStable, Method::Watertight] {
            let Some(row) = r.row(case, m, Precision::F32) else {
                continue;
            };
            assert!(row.rays > 0);
            assert_eq!(row.misclassified, 0, "{case} {}", m.name());
            assert_eq!(row.leaks, 0, "{case} {}", m.name());
        }
    }
    // Each of those cases was run by one of the two methods.
    for case in ["S1", "S3", "S6"] {
        assert!(r.row(case, Method::SphereStable, Precision::F32).is_some());
    }
    for case in ["S12", "S13"] {
        let row = r.row(case, Method::Watertight, Precision::F32).unwrap();
        assert_eq!(row.leak_rays, row.rays);
    }
    // The error-bound offset: no self-hits, and the surface 4e-5 beyond is reached.
    for case in ["S7", "S19"] {
        let row = r
            .row(case, Method::OffsetErrorBound, Precision::F32)
            .unwrap();
        assert_eq!((row.self_hits, row.misclassified), (0, 0), "{case}");
    }
}

#[test]
fn the_seeds_methods_show_the_documented_failures() {
    let r = quick();
    // S1: the textbook quadratic loses the radius of a far sphere in f32.
    let s1 = r.row("S1", Method::SphereTextbook, Precision::F32).unwrap();
    assert!(s1.misclassified * 20 > s1.rays, "{s1:?}");
    // S12: Möller–Trumbore leaks at shared edges in f32 (docs/NUMERICS.md: 7.4%).
    let s12 = r
        .row("S12", Method::MollerTrumbore, Precision::F32)
        .unwrap();
    assert!(s12.leaks * 50 > s12.leak_rays, "{s12:?}");
    // S19/S7: no offset self-hits; a fixed ε skips a surface 4e-5 away.
    assert!(
        r.row("S19", Method::OffsetNone, Precision::F32)
            .unwrap()
            .self_hits
            > 0
    );
    let s7 = r.row("S7", Method::OffsetFixed, Precision::F32).unwrap();
    assert_eq!(s7.misclassified, s7.rays);
    // S23: the BVH finds exactly what brute force finds, at 1e-5 and 5e-5 apart.
    let s23 = r.row("S23", Method::SlabRobust, Precision::F32).unwrap();
    assert!(s23.rays > 0 && s23.exact_hits > 0);
    assert_eq!(s23.misclassified, 0);
    // S22: the plain slab test drops zero-thickness boxes.
    let s22 = r.row("S22", Method::SlabPlain, Precision::F32).unwrap();
    assert_eq!(s22.misclassified, s22.rays);
}

#[test]
fn no_method_returns_nan_and_invalid_rays_are_rejected() {
    let r = quick();
    for row in &r.rows {
        assert_eq!(row.nonfinite, 0, "{row:?}");
        if row.case == "S25" {
            assert!(row.rays > 0);
            assert_eq!(row.misclassified, 0, "an invalid ray was accepted: {row:?}");
        }
    }
    // Every case of the catalogue ran.
    for k in 1..=25 {
        let id = format!("S{k}");
        assert!(r.rows.iter().any(|row| row.case == id), "{id} missing");
    }
    for k in 26..=29 {
        let id = format!("S{k}");
        assert!(r.mc.iter().any(|row| row.case == id), "{id} missing");
    }
}

#[test]
fn leaky_edge_scene_leaks_with_moller_trumbore_only() {
    let mut s = scene("leaky-edge.toml");
    let holes = |px: &[glam::Vec3], w: usize, h: usize| {
        // Background pixels with the fan on both sides (left/right or above/below).
        let bg = |x: usize, y: usize| px[y * w + x] == glam::Vec3::ZERO;
        (1..h - 1)
            .flat_map(|y| (1..w - 1).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                bg(x, y) && ((!bg(x - 1, y) && !bg(x + 1, y)) || (!bg(x, y - 1) && !bg(x, y + 1)))
            })
            .count()
    };
    let (w, h) = (s.camera.width as usize, s.camera.height as usize);
    let mt = holes(&render(&s), w, h);
    s.settings.triangle_method = raystep::shapes::TriangleMethod::Watertight;
    let wt = holes(&render(&s), w, h);
    assert!(mt > 0, "no crack with Möller–Trumbore");
    assert_eq!(wt, 0);
}

#[test]
fn acne_scene_shows_acne_without_offset_only() {
    let mut s = scene("acne.toml");
    let none = render(&s);
    s.settings.offset = raystep::scene::OffsetPolicy::Robust;
    let robust = render(&s);
    // Acne darkens lit pixels to ambient: count pixels darker than with the robust offset.
    let darker = none
        .iter()
        .zip(&robust)
        .filter(|(a, b)| a.element_sum() + 0.05 < b.element_sum())
        .count();
    assert!(darker * 50 > none.len(), "only {darker} acne pixels");
    // And nothing is brighter: acne only ever adds false shadow.
    assert!(
        none.iter()
            .zip(&robust)
            .all(|(a, b)| a.element_sum() <= b.element_sum() + 0.05)
    );
}

/// The suite a case a step (the app's Lab in a web page draws between steps): several steps,
/// each but the last without a report, and the report the one-call run's (the timings apart).
#[test]
fn the_suite_in_steps_gives_the_runs_report() {
    let whole = quick();
    let mut suite = raystep::stability::Suite::new(&Options::quick());
    let mut steps = 1;
    let stepped = loop {
        match suite.step() {
            Some(r) => break r,
            None => steps += 1,
        }
    };
    let cases: std::collections::BTreeSet<_> = whole.rows.iter().map(|r| r.case).collect();
    // A case a step (some cases share a name in the rows), then the report.
    assert!(
        steps > cases.len(),
        "{steps} steps for {} case names",
        cases.len()
    );
    let key = |r: &raystep::stability::Row| {
        format!(
            "{} {:?} {:?} {} {} {} {} {} {} {} {}",
            r.case,
            r.method,
            r.precision,
            r.rays,
            r.misclassified,
            r.leaks,
            r.self_hits,
            r.nonfinite,
            r.compared,
            r.t_max_ulps,
            r.t_p99_ulps
        )
    };
    assert_eq!(
        stepped.rows.iter().map(key).collect::<Vec<_>>(),
        whole.rows.iter().map(key).collect::<Vec<_>>()
    );
    assert_eq!(stepped.rays, whole.rays);
}
