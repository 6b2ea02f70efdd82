//! The Monte Carlo stiff cases S26–S29 of docs/NUMERICS.md: the sampling numerics of lights and
//! BSDFs (a sphere light's cone, GGX at near-mirror roughness, grazing directions, huge and tiny
//! emitting triangles), each quantity in a textbook and a stable formulation, in f32 and f64,
//! measured against an exact reference ([`exact`]) like the intersection kernels: relative error
//! (p99 and max), ulps, and *misclassified* — a result that is zero, negative, infinite or NaN
//! where the exact value is a positive number the precision can hold (a light the integrator
//! drops, a density that is no density, a sampled direction collapsed onto its axis).
//!
//! ```
//! use raystep_course::stability::mc::McMethod;
//! use raystep_course::stability::{Options, Precision, run};
//! let report = run(&Options { rays: 8, min_timing_s: 0.0, ..Options::quick() });
//! let pdf = report.mc_row("S26", "cone pdf", McMethod::Textbook, Precision::F32).expect("S26 ran");
//! println!("textbook cone pdf: max rel error {:.1e}, {} misclassified", pdf.max_rel, pdf.misclassified);
//! ```

pub mod exact;
pub mod kernels;

use super::exact::Dd;
use super::stats::{percentile, time_per_item, ulp};
use super::{Options, Precision};
use crate::math::Real;
use rayon::prelude::*;
use serde::Serialize;
use std::hint::black_box;

/// A formulation of a Monte Carlo quantity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum McMethod {
    /// As courses write it (and as raystep wrote it before issue 48).
    Textbook,
    /// Rewritten not to cancel (docs/NUMERICS.md derives each). In f32, raystep's own kernels
    /// where their signatures allow ([`kernels::raystep`]); in f64, the lab's code.
    Stable,
}

impl McMethod {
    /// Both, in report order.
    pub const ALL: [McMethod; 2] = [McMethod::Textbook, McMethod::Stable];
    /// "textbook" or "stable".
    pub fn name(self) -> &'static str {
        match self {
            McMethod::Textbook => "textbook",
            McMethod::Stable => "stable",
        }
    }
}

/// A GGX sample's inputs (S27): roughness α, the uniform number u for θh, the azimuth's cosine
/// and sine, and the outgoing direction ωo (local frame, z the normal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GgxInput {
    /// α = roughness².
    pub alpha: f64,
    /// The uniform number for θh.
    pub u: f64,
    /// cos φ.
    pub cphi: f64,
    /// sin φ.
    pub sphi: f64,
    /// ωo.
    pub wo: [f64; 3],
}

/// A grazing sample's inputs (S28).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GrazingInput {
    /// A unit direction nearly perpendicular to `n` (the cosine-hemisphere pdf's).
    pub w: [f64; 3],
    /// The unit normal (of the surface, and of the emitting triangle).
    pub n: [f64; 3],
    /// From the shading point to a point on the emitting triangle, nearly in its plane.
    pub d: [f64; 3],
    /// The triangle's area.
    pub area: f64,
    /// Uniform numbers for a cosine-weighted direction near the horizon.
    pub u: [f64; 2],
}

/// The inputs of a case (every number exact in f32: both precisions see the same inputs).
#[derive(Debug, Clone, PartialEq)]
pub enum McData {
    /// S26: (distance to the centre, radius, u).
    Cone(Vec<[f64; 3]>),
    /// S27.
    Ggx(Vec<GgxInput>),
    /// S28.
    Grazing(Vec<GrazingInput>),
    /// S29: the triangles' vertices.
    Area(Vec<[[f64; 3]; 3]>),
}

impl McData {
    fn len(&self) -> usize {
        match self {
            McData::Cone(v) => v.len(),
            McData::Ggx(v) => v.len(),
            McData::Grazing(v) => v.len(),
            McData::Area(v) => v.len(),
        }
    }
    /// The names of the quantities each sample yields, in order.
    pub fn quantities(&self) -> &'static [&'static str] {
        match self {
            McData::Cone(_) => &["1 − cos θmax", "cone pdf", "cos θ", "sin θ"],
            McData::Ggx(_) => &["sin θh", "D(h)", "pdf"],
            McData::Grazing(_) => &["cosine pdf", "light pdf", "sampled cos θ"],
            McData::Area(_) => &["area"],
        }
    }
}

/// One Monte Carlo stiff case.
#[derive(Debug, Clone, PartialEq)]
pub struct McCase {
    /// "S26" …
    pub id: &'static str,
    /// What it is, in a few words.
    pub title: &'static str,
    /// Whether it also runs in f64 (S29's stable form *is* the f64 computation: f32 only).
    pub f64_rows: bool,
    /// Its samples.
    pub data: McData,
}

impl McCase {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.data.len()
    }
    /// Whether it has none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// One case × quantity × method × precision.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct McRow {
    /// "S26" …
    pub case: &'static str,
    /// The case in a few words.
    pub title: &'static str,
    /// The quantity ("cone pdf", "sin θh", …).
    pub quantity: &'static str,
    /// The formulation.
    pub method: McMethod,
    /// The precision.
    pub precision: Precision,
    /// Samples whose exact value is a positive number the precision can hold.
    pub samples: usize,
    /// Of those, results that are zero, negative, ∞ or NaN.
    pub misclassified: usize,
    /// Results that are ∞ or NaN (of any sample).
    pub nonfinite: usize,
    /// Results compared with the exact value (samples − misclassified).
    pub compared: usize,
    /// Largest |y − exact| / exact.
    pub max_rel: f64,
    /// 99th percentile of the same.
    pub p99_rel: f64,
    /// Largest |y − exact| in ulps of the exact value (in this row's precision).
    pub max_ulps: f64,
    /// 99th percentile of the same.
    pub p99_ulps: f64,
    /// Cost: nanoseconds per sample (the case's whole kernel: all its quantities).
    pub ns_per_sample: f64,
}

/// A grazing sample in precision T: (w, n, d, area, u).
type Grazing<T> = ([T; 3], [T; 3], [T; 3], T, [T; 2]);

/// A case's inputs in precision T.
enum Prepared<T: Real> {
    Cone(Vec<[T; 3]>),
    Ggx(Vec<(T, T, T, T, [T; 3])>),
    Grazing(Vec<Grazing<T>>),
    Area(Vec<[[T; 3]; 3]>),
}

fn t<T: Real>(x: f64) -> T {
    T::from_f64(x)
}
fn t3<T: Real>(v: [f64; 3]) -> [T; 3] {
    v.map(t::<T>)
}

fn prepare<T: Real>(data: &McData) -> Prepared<T> {
    match data {
        McData::Cone(v) => Prepared::Cone(v.iter().map(|x| t3(*x)).collect()),
        McData::Ggx(v) => Prepared::Ggx(
            v.iter()
                .map(|g| (t(g.alpha), t(g.u), t(g.cphi), t(g.sphi), t3(g.wo)))
                .collect(),
        ),
        McData::Grazing(v) => Prepared::Grazing(
            v.iter()
                .map(|g| (t3(g.w), t3(g.n), t3(g.d), t(g.area), g.u.map(t::<T>)))
                .collect(),
        ),
        McData::Area(v) => Prepared::Area(v.iter().map(|p| p.map(t3)).collect()),
    }
}

/// Sample `i` of a prepared case by `m`, widened to f64 (unused slots NaN).
#[inline(always)]
fn eval<T: Real>(p: &Prepared<T>, i: usize, m: McMethod) -> [f64; 4] {
    let w = |x: T| x.to_f64();
    match p {
        Prepared::Cone(v) => kernels::cone(m, v[i][0], v[i][1], v[i][2]).map(w),
        Prepared::Ggx(v) => {
            let (a, u, c, s, wo) = v[i];
            let [x, y, z] = kernels::ggx(m, a, u, c, s, wo).map(w);
            [x, y, z, f64::NAN]
        }
        Prepared::Grazing(v) => {
            let (wi, n, d, a, u) = v[i];
            let [x, y, z] = kernels::grazing(m, wi, n, d, a, u).map(w);
            [x, y, z, f64::NAN]
        }
        Prepared::Area(v) => [w(kernels::area(m, v[i])), f64::NAN, f64::NAN, f64::NAN],
    }
}

/// Sample `i` by the stable formulation in f32 through raystep's own kernels
/// ([`kernels::raystep`]), widened to f64.
#[inline(always)]
fn eval_raystep(p: &Prepared<f32>, i: usize) -> [f64; 4] {
    let w = |x: f32| x as f64;
    match p {
        Prepared::Cone(v) => kernels::raystep::cone(v[i][0], v[i][1], v[i][2]).map(w),
        Prepared::Ggx(v) => {
            let (a, u, c, s, wo) = v[i];
            let [x, y, z] = kernels::raystep::ggx(a, u, c, s, wo).map(w);
            [x, y, z, f64::NAN]
        }
        Prepared::Grazing(v) => {
            let (wi, n, d, a, u) = v[i];
            let [x, y, _] = kernels::grazing(McMethod::Stable, wi, n, d, a, u).map(w);
            [x, y, w(kernels::raystep::cosine_z(u)), f64::NAN]
        }
        Prepared::Area(v) => [
            w(kernels::raystep::area(v[i])),
            f64::NAN,
            f64::NAN,
            f64::NAN,
        ],
    }
}

/// Every sample's outputs by `f`, and its cost in ns per sample.
fn outputs(n: usize, opts: &Options, f: impl Fn(usize) -> [f64; 4]) -> (Vec<[f64; 4]>, f64) {
    let outs = (0..n).map(&f).collect();
    let ns = time_per_item(n, opts.min_timing_s, || {
        for i in 0..n {
            black_box(f(black_box(i)));
        }
    });
    (outs, ns)
}

/// The exact values of one sample (unused slots None).
fn reference(data: &McData, i: usize) -> [Option<Dd>; 4] {
    match data {
        McData::Cone(v) => exact::cone(v[i][0], v[i][1], v[i][2]),
        McData::Ggx(v) => {
            let g = v[i];
            let [a, b, c] = exact::ggx(g.alpha, g.u, g.cphi, g.sphi, g.wo);
            [a, b, c, None]
        }
        McData::Grazing(v) => {
            let g = v[i];
            let [a, b, c] = exact::grazing(g.w, g.n, g.d, g.area, g.u);
            [a, b, c, None]
        }
        McData::Area(v) => [exact::area(v[i]), None, None, None],
    }
}

/// Runs a case: its exact references, then every method × precision, one row per quantity (in
/// the report per quantity and precision, the textbook row above the stable one).
pub(super) fn run_case(case: &McCase, opts: &Options) -> Vec<McRow> {
    let refs: Vec<[Option<Dd>; 4]> = (0..case.len())
        .into_par_iter()
        .map(|i| reference(&case.data, i))
        .collect();
    let mut rows = vec![];
    for m in McMethod::ALL {
        rows.extend(rows_in::<f32>(case, &refs, m, Precision::F32, opts));
        if case.f64_rows {
            rows.extend(rows_in::<f64>(case, &refs, m, Precision::F64, opts));
        }
    }
    // Side by side: per quantity, per precision, textbook then stable.
    let quantities = case.data.quantities();
    rows.sort_by_key(|r| {
        let k = quantities.iter().position(|q| *q == r.quantity);
        (k, r.precision, r.method)
    });
    rows
}

fn rows_in<T: Real>(
    case: &McCase,
    refs: &[[Option<Dd>; 4]],
    m: McMethod,
    p: Precision,
    opts: &Options,
) -> Vec<McRow> {
    let n = case.len();
    // The stable rows in f32 are raystep's own kernels, where their signatures allow.
    let (outs, ns) = if p == Precision::F32 && m == McMethod::Stable {
        let prep = prepare::<f32>(&case.data);
        outputs(n, opts, |i| eval_raystep(&prep, i))
    } else {
        let prep = prepare::<T>(&case.data);
        outputs(n, opts, |i| eval(&prep, i, m))
    };
    let limit = T::max_value().to_f64();
    let sort = |v: &mut Vec<f64>| v.sort_by(|a, b| a.total_cmp(b));
    let mut rows = vec![];
    for (k, quantity) in case.data.quantities().iter().enumerate() {
        let mut row = McRow {
            case: case.id,
            title: case.title,
            quantity,
            method: m,
            precision: p,
            samples: 0,
            misclassified: 0,
            nonfinite: 0,
            compared: 0,
            max_rel: 0.0,
            p99_rel: 0.0,
            max_ulps: 0.0,
            p99_ulps: 0.0,
            ns_per_sample: ns,
        };
        let (mut rels, mut ulps) = (vec![], vec![]);
        for (out, r) in outs.iter().zip(refs) {
            let y = out[k];
            if !y.is_finite() {
                row.nonfinite += 1;
            }
            // Only exact values the precision can hold are judged.
            let Some(e) = r[k].filter(|e| e.hi > 0.0 && e.hi <= limit) else {
                continue;
            };
            row.samples += 1;
            if !(y.is_finite() && y > 0.0) {
                row.misclassified += 1;
                continue;
            }
            let err = e.abs_error(y);
            rels.push(err / e.hi);
            ulps.push(err / ulp(e.hi, p));
        }
        row.compared = rels.len();
        sort(&mut rels);
        sort(&mut ulps);
        row.max_rel = rels.last().copied().unwrap_or(0.0);
        row.p99_rel = percentile(&rels, 0.99);
        row.max_ulps = ulps.last().copied().unwrap_or(0.0);
        row.p99_ulps = percentile(&ulps, 0.99);
        rows.push(row);
    }
    rows
}
