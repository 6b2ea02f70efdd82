//! The stability lab: the exact references against hand-computed answers, the renderer's default
//! methods free of failures on the stiff cases that justify them, the course notes' methods visibly
//! failing (so a regression either way is caught), no NaN anywhere, the shipped failure scenes
//! showing their failure, and `raystep stability --quick` / `raystep converge` writing well-formed
//! outputs.

use assert_cmd::Command;
use num_rational::BigRational;
use raystep::stability::exact::{self, Dd};
use raystep::stability::{Method, Options, Precision, Report, run};
use std::path::Path;
use std::sync::OnceLock;

/// The quick suite, run once for all the tests that read it.
fn quick() -> &'static Report {
    static REPORT: OnceLock<Report> = OnceLock::new();
    REPORT.get_or_init(|| {
        let r = run(&Options::quick());
        // Timing is only printed, never asserted.
        for p in &r.points {
            println!(
                "{:9} {:19} {} {:8.1} ns/test",
                p.primitive.name(),
                p.method.name(),
                p.precision.name(),
                p.ns_per_test
            );
        }
        r
    })
}

fn rat(n: i64, d: i64) -> BigRational {
    BigRational::new(n.into(), d.into())
}

fn scene(name: &str) -> raystep::scene::Scene {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name);
    raystep::scene::load_file(&p).unwrap()
}

fn render(s: &raystep::scene::Scene) -> Vec<glam::Vec3> {
    let (accel, _) = raystep::accel::SceneAccel::build(s);
    let tracer = raystep::trace::Tracer::new(s, &accel);
    raystep::render::render(&tracer, &Default::default())
        .unwrap()
        .pixels
}

fn png_size(path: &Path) -> (u32, u32) {
    let img = image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    (img.width(), img.height())
}

/// A CSV line's fields, respecting quotes (titles may contain commas).
fn csv_fields(line: &str) -> Vec<String> {
    let mut fields = vec![];
    let (mut cur, mut quoted) = (String::new(), false);
    for ch in line.chars() {
        match ch {
            '"' => quoted = !quoted,
            ',' if !quoted => fields.push(std::mem::take(&mut cur)),
            c => cur.push(c),
        }
    }
    fields.push(cur);
    fields
}

use raystep::stability::mc::{self, McMethod, kernels};

/// |got − want| / want, want given as decimal digits (from 60-digit decimal arithmetic in
/// Python's `fractions` and `decimal`, on the same float inputs: an independent computation).
fn rel(got: f64, want: f64) -> f64 {
    ((got - want) / want).abs()
}

mod converge;
mod monte_carlo;
mod references;
mod suite;
