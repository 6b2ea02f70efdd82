//! The statistical check of a Monte Carlo tracer that draws its own random numbers (`raystep
//! grade-tracer --statistical`): the student's image, with each pixel's sample mean, sample
//! variance and sample count, against raystep's own, by Welch's t-test (as Nori's `warptest`
//! and its image tests do), per pixel and for the image as a whole.
//!
//! **False-failure rate.** A correct tracer fails with probability about [`ALPHA`] = 10⁻³:
//! half of it goes to the whole-image test, half is shared among the regions' tests by
//! Bonferroni's correction. Regions, not single pixels: a path tracer's pixel values are heavy
//! tailed, and a pixel's few dozen samples do not make the t-test's tails trustworthy at the
//! levels a per-pixel Bonferroni correction needs (tried: 2 false failures in 16 correct
//! images). The rate is measured by `tests/it/statistical_mode.rs`'s ignored test
//! `false_failure_rate`: 1 failure in 1000 correct 24×24 renders at 64 spp (95 % upper bound
//! 0.0047; book/grading.md gives the command).
//!
//! The student's claims are not trusted: every pixel of the scene's image is required, with at
//! least the scene's samples per pixel; the claimed variances may add up to at most
//! [`VARIANCE_RATIO`] times raystep's, and each is cut to [`VARIANCE_CAP`] times raystep's
//! (plus the image's mean pixel variance). Each student is graded against a reference of their
//! own ([`student_reference`]), so one unlucky reference never fails a class.
//!
//! The file is JSON Lines, like the trace format (`lessons/starter/README.md`):
//!
//! ```text
//! {"type":"format","version":2}
//! {"type":"image","width":32,"height":24}
//! {"type":"pixel","x":0,"y":0,"samples":64,"mean":[0.1,0.2,0.3],"variance":[0.01,0.02,0.03]}
//! ```
//!
//! with `variance` the unbiased sample variance of the pixel's sample values, per channel.

use crate::trace::PreparedScene;
use serde::Deserialize;
use statrs::distribution::{ContinuousCDF, StudentsT};

/// The grader's false-failure rate: the probability that a correct tracer's image fails.
pub const ALPHA: f64 = 1e-3;

/// One pixel's sample statistics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelStats {
    /// Sample count.
    pub n: u32,
    /// Mean, per channel.
    pub mean: [f64; 3],
    /// Unbiased sample variance, per channel.
    pub variance: [f64; 3],
}

/// An image's per-pixel sample statistics (None: a pixel the file does not give).
#[derive(Debug, Clone, PartialEq)]
pub struct StatImage {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Row-major pixels.
    pub pixels: Vec<Option<PixelStats>>,
}

impl StatImage {
    /// The pixel at (x, y).
    pub fn at(&self, x: u32, y: u32) -> Option<PixelStats> {
        self.pixels
            .get((y as usize) * (self.width as usize) + x as usize)
            .copied()
            .flatten()
    }
}

/// raystep's statistics of `prepared`'s image: every pixel's spp samples (finite ones; a
/// sample with NaN or infinity is left out, as the render does), their mean and variance.
pub fn reference(prepared: &PreparedScene) -> StatImage {
    let scene = prepared.scene();
    let (w, h) = (scene.camera.width, scene.camera.height);
    let spp = scene.settings.spp;
    let tracer = prepared.tracer();
    let pixel = |x: u32, y: u32| {
        let mut sum = [0.0f64; 3];
        let mut sum2 = [0.0f64; 3];
        let mut n = 0u32;
        for k in 0..spp {
            let c = tracer.trace_sample(x, y, k, &mut crate::record::observer::Silent);
            if !c.is_finite() {
                continue;
            }
            n += 1;
            for (i, v) in c.to_array().into_iter().enumerate() {
                sum[i] += v as f64;
                sum2[i] += (v as f64) * (v as f64);
            }
        }
        (n > 0).then(|| {
            let nn = n as f64;
            let mean = sum.map(|s| s / nn);
            let variance = std::array::from_fn(|i| {
                if n > 1 {
                    ((sum2[i] - nn * mean[i] * mean[i]) / (nn - 1.0)).max(0.0)
                } else {
                    0.0
                }
            });
            PixelStats { n, mean, variance }
        })
    };
    // Rows shared among the machine's cores (every pixel's numbers are its own: the same image
    // on any number of threads).
    let threads = (crate::platform::threads() as u32).clamp(1, h.max(1));
    let mut rows: Vec<(u32, Vec<Option<PixelStats>>)> = std::thread::scope(|sc| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                let pixel = &pixel;
                sc.spawn(move || {
                    (t..h)
                        .step_by(threads as usize)
                        .map(|y| (y, (0..w).map(|x| pixel(x, y)).collect()))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap_or_default())
            .collect()
    });
    rows.sort_by_key(|r| r.0);
    StatImage {
        width: w,
        height: h,
        pixels: rows.into_iter().flat_map(|r| r.1).collect(),
    }
}

/// Writes `img` in the file format above.
pub fn write(img: &StatImage) -> String {
    let mut s = format!(
        "{{\"type\":\"format\",\"version\":2}}\n{{\"type\":\"image\",\"width\":{},\"height\":{}}}\n",
        img.width, img.height
    );
    for y in 0..img.height {
        for x in 0..img.width {
            if let Some(p) = img.at(x, y) {
                let v = serde_json::json!({
                    "type": "pixel", "x": x, "y": y, "samples": p.n,
                    "mean": p.mean, "variance": p.variance,
                });
                s += &v.to_string();
                s.push('\n');
            }
        }
    }
    s
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case")]
enum Line {
    Format {
        #[serde(default)]
        version: Option<u32>,
    },
    Image {
        width: u32,
        height: u32,
    },
    Pixel {
        x: u32,
        y: u32,
        samples: u32,
        mean: [f64; 3],
        variance: [f64; 3],
    },
}

/// Reads a statistics file; errors name the line. The image's size is checked before anything
/// is allocated: an image past a million pixels must have a `pixel` record for each.
pub fn parse(text: &str) -> Result<StatImage, String> {
    parse_for(text, None)
}

/// Reads a statistics file for a scene whose image is `size` (width, height): an `image`
/// record of another size is refused at its line, before anything is allocated. A UTF-8 byte
/// order mark is skipped; a pixel given twice is refused.
pub fn parse_for(text: &str, size: Option<(u32, u32)>) -> Result<StatImage, String> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut img: Option<StatImage> = None;
    let mut given = vec![];
    let mut seen = std::collections::HashSet::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let l = raw.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let rec: Line = serde_json::from_str(l).map_err(|e| {
            let shown: String = l.chars().take(80).collect();
            let what = serde_json::from_str::<serde_json::Value>(l)
                .ok()
                .and_then(|v| v.get("type").and_then(|t| t.as_str()).map(str::to_string))
                .map_or("a record".to_string(), |t| format!("a \"{t}\" record"));
            format!(
                "line {line}: {what} the statistics format cannot read ({e}; expected {}): {shown}",
                "{\"type\":\"image\",\"width\":W,\"height\":H} or {\"type\":\"pixel\",\"x\":X,\"y\":Y,\"samples\":N,\"mean\":[r,g,b],\"variance\":[r,g,b]}"
            )
        })?;
        match rec {
            Line::Format { version } => {
                if version.is_some_and(|v| v != 2) {
                    return Err(format!(
                        "line {line}: the statistics file is format version 2"
                    ));
                }
            }
            Line::Image { width, height } => {
                if img.is_some() {
                    return Err(format!("line {line}: a second `image` record"));
                }
                if let Some((w, h)) = size
                    && (w, h) != (width, height)
                {
                    return Err(format!(
                        "line {line}: the `image` record says {width}×{height}, and the scene's image is {w}×{h}: give the statistics of the scene's image, every pixel"
                    ));
                }
                if width == 0 || height == 0 {
                    return Err(format!(
                        "line {line}: an image of {width}×{height} pixels cannot be graded"
                    ));
                }
                img = Some(StatImage {
                    width,
                    height,
                    pixels: vec![],
                });
            }
            Line::Pixel {
                x,
                y,
                samples,
                mean,
                variance,
            } => {
                let Some(im) = img.as_mut() else {
                    return Err(format!(
                        "line {line}: a pixel before the `image` record (its width and height)"
                    ));
                };
                if x >= im.width || y >= im.height {
                    return Err(format!(
                        "line {line}: pixel ({x}, {y}) is outside the {}×{} image",
                        im.width, im.height
                    ));
                }
                if samples == 0 {
                    return Err(format!("line {line}: pixel ({x}, {y}) has 0 samples"));
                }
                if !mean.iter().chain(&variance).all(|v| v.is_finite())
                    || variance.iter().any(|v| *v < 0.0)
                {
                    return Err(format!(
                        "line {line}: pixel ({x}, {y}): means must be finite and variances finite and not negative"
                    ));
                }
                if !seen.insert((x, y)) {
                    return Err(format!(
                        "line {line}: pixel ({x}, {y}) is given a second time"
                    ));
                }
                given.push((
                    [x, y],
                    PixelStats {
                        n: samples,
                        mean,
                        variance,
                    },
                ));
            }
        }
    }
    let Some(mut im) = img else {
        return Err("no `image` record: the file must give the image's width and height".into());
    };
    // Allocated only now, and only as large as the file can fill (a file that names a huge image
    // and gives a few pixels is refused without it).
    let all = im.width as u64 * im.height as u64;
    if all > (1 << 20) && all > given.len() as u64 {
        return Err(format!(
            "the file gives {} of the {} pixels of its {}×{} image: give every pixel",
            given.len(),
            all,
            im.width,
            im.height
        ));
    }
    im.pixels = vec![None; all as usize];
    for ([x, y], p) in given {
        im.pixels[y as usize * im.width as usize + x as usize] = Some(p);
    }
    Ok(im)
}

/// Welch's two-sided t-test of two means with their (unbiased) variances and counts: the
/// p-value. Both standard errors 0: 1 when the means agree (to 1e-9 relative), else 0.
pub fn welch_p(m1: f64, v1: f64, n1: f64, m2: f64, v2: f64, n2: f64) -> f64 {
    let (s1, s2) = (v1 / n1, v2 / n2);
    let se2 = s1 + s2;
    if se2 <= 0.0 || !se2.is_finite() {
        let same = (m1 - m2).abs() <= 1e-9 * (1.0 + m1.abs().max(m2.abs()));
        return if same { 1.0 } else { 0.0 };
    }
    let t = (m1 - m2) / se2.sqrt();
    // Welch–Satterthwaite degrees of freedom (a side with one sample adds none).
    let mut den = 0.0;
    if n1 > 1.0 {
        den += s1 * s1 / (n1 - 1.0);
    }
    if n2 > 1.0 {
        den += s2 * s2 / (n2 - 1.0);
    }
    let dof = if den > 0.0 {
        (se2 * se2 / den).max(1.0)
    } else {
        1.0
    };
    match StudentsT::new(0.0, 1.0, dof) {
        Ok(d) => (2.0 * d.sf(t.abs())).min(1.0),
        Err(_) => 0.0,
    }
}

/// The verdict of a statistical check.
#[derive(Debug, Clone, PartialEq)]
pub struct Verdict {
    /// Passed both tests?
    pub pass: bool,
    /// In words: the verdict first, then the pixels and regions rejected, the whole image's
    /// p-value, the false-failure rate.
    pub message: String,
}

/// raystep's reference samples per pixel, per sample the scene asks for: a reference four times
/// as long as the student's render, so that its own noise adds a quarter of the student's.
pub const REFERENCE_FACTOR: u32 = 4;

/// How far a pixel's claimed variance is believed: at most this many times raystep's own
/// variance of that pixel plus the image's mean pixel variance (per channel). A claim above it is
/// cut to it, so a tracer cannot widen its own test by claiming noise it does not have.
pub const VARIANCE_CAP: f64 = 16.0;

/// The most the claimed variances may add up to, per channel, as a multiple of raystep's (a
/// correct path tracer as the starter kit describes is as noisy as raystep's).
pub const VARIANCE_RATIO: f64 = 4.0;

/// The reference a student is graded against: raystep's render of `scene` with a seed of the
/// student's own (drawn from their name and the scene's seed, so two students' references are
/// independent and grading again gives the same verdict) and [`REFERENCE_FACTOR`] times the
/// scene's samples per pixel.
pub fn student_reference(scene: &crate::scene::Scene, student: &str) -> StatImage {
    use sha2::Digest;
    let mut s = scene.clone();
    let mut h = sha2::Sha256::new();
    h.update(b"raystep statistical reference\0");
    h.update(student.as_bytes());
    h.update(scene.settings.seed.to_le_bytes());
    let d = h.finalize();
    s.settings.seed = u32::from_le_bytes([d[0], d[1], d[2], d[3]]);
    s.settings.spp = scene.settings.spp.saturating_mul(REFERENCE_FACTOR).max(1);
    reference(&PreparedScene::new(s))
}

/// What [`compare_with`] requires besides the statistics themselves.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Requirements {
    /// The fewest samples a pixel may have (the scene's samples per pixel).
    pub min_samples: u32,
}

/// Compares the student's statistics with raystep's ([`compare_with`], no least sample count).
pub fn compare(student: &StatImage, reference: &StatImage) -> Verdict {
    compare_with(student, reference, Requirements::default())
}

/// One Welch test of a group of pixels' mean (per channel): the student's against raystep's, the
/// student's variances as used (cut to [`VARIANCE_CAP`]).
struct Pair {
    at: [u32; 2],
    s: PixelStats,
    r: PixelStats,
}

/// The two-sided p-value of the mean of `pairs`' channel `c` (Welch–Satterthwaite).
fn group_p(pairs: &[&Pair], c: usize) -> (f64, f64, f64) {
    let count = pairs.len() as f64;
    let (mut ms, mut mr, mut vs, mut vr, mut ds, mut dr) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for p in pairs {
        ms += p.s.mean[c];
        mr += p.r.mean[c];
        let (a, b) = (
            p.s.variance[c] / p.s.n as f64,
            p.r.variance[c] / p.r.n as f64,
        );
        vs += a;
        vr += b;
        if p.s.n > 1 {
            ds += a * a / (p.s.n as f64 - 1.0);
        }
        if p.r.n > 1 {
            dr += b * b / (p.r.n as f64 - 1.0);
        }
    }
    let (ms, mr) = (ms / count, mr / count);
    let se2 = (vs + vr) / (count * count);
    let p = if se2 > 0.0 && se2.is_finite() {
        let t = (ms - mr) / se2.sqrt();
        let dof = ((vs + vr) * (vs + vr) / (ds + dr).max(f64::MIN_POSITIVE)).max(1.0);
        StudentsT::new(0.0, 1.0, dof).map_or(0.0, |d| (2.0 * d.sf(t.abs())).min(1.0))
    } else {
        welch_p(ms, 0.0, 1.0, mr, 0.0, 1.0)
    };
    (ms, mr, p)
}

const CHANNEL: [&str; 3] = ["red", "green", "blue"];

/// "45 % brighter" (or darker) of a mean against raystep's.
fn brighter(yours: f64, theirs: f64) -> String {
    if theirs.abs() < 1e-12 {
        return if yours > theirs { "brighter" } else { "darker" }.into();
    }
    format!(
        "{} % {}",
        ((yours / theirs - 1.0) * 100.0).abs().round(),
        if yours > theirs { "brighter" } else { "darker" }
    )
}

/// Compares the student's statistics with raystep's: the file must give every pixel of the
/// scene's image, each with at least `req.min_samples` samples, and variances that add up to at
/// most [`VARIANCE_RATIO`] times raystep's; then, with each pixel's claimed variance believed up
/// to [`VARIANCE_CAP`], the mean of each region of the image (at most 8 × 8 regions) per channel
/// by Welch's t-test at level α / (2R) (R: the region tests), and the mean of the whole image per
/// channel at level α / 6, so that a correct image fails with probability about [`ALPHA`]
/// (measured: see book/grading.md). A failure names the regions where the image differs
/// significantly (or, for a bias spread thinly, those that differ most) and the pixels that
/// differ most.
pub fn compare_with(student: &StatImage, reference: &StatImage, req: Requirements) -> Verdict {
    let fail = |m: String| Verdict {
        pass: false,
        message: format!("failed: {m}"),
    };
    if (student.width, student.height) != (reference.width, reference.height) {
        return fail(format!(
            "your image is {}×{}, the scene's is {}×{}",
            student.width, student.height, reference.width, reference.height
        ));
    }
    let (w, h) = (reference.width, reference.height);
    let mut missing = vec![];
    let mut few = None;
    let mut pairs = vec![];
    for y in 0..h {
        for x in 0..w {
            match (student.at(x, y), reference.at(x, y)) {
                (None, _) => missing.push([x, y]),
                (Some(s), Some(r)) => {
                    if s.n < req.min_samples && few.is_none() {
                        few = Some(([x, y], s.n));
                    }
                    pairs.push(Pair { at: [x, y], s, r });
                }
                // raystep has no finite sample there (never with a sane scene): not compared.
                (Some(_), None) => {}
            }
        }
    }
    if !missing.is_empty() {
        let shown: Vec<String> = missing
            .iter()
            .take(5)
            .map(|[x, y]| format!("({x}, {y})"))
            .collect();
        return fail(format!(
            "your statistics give {} of the {} pixels of the {w}×{h} image: every pixel is required (missing: {}{})",
            (w as usize * h as usize) - missing.len(),
            w as usize * h as usize,
            shown.join(", "),
            if missing.len() > 5 { ", …" } else { "" }
        ));
    }
    if let Some(([x, y], n)) = few {
        return fail(format!(
            "pixel ({x}, {y}) has {n} sample{}, and the scene asks for {} per pixel: render with the scene's spp",
            if n == 1 { "" } else { "s" },
            req.min_samples
        ));
    }
    if pairs.is_empty() {
        return fail("raystep's render has no pixel to compare".into());
    }
    // Claimed variances: the image's total against raystep's, then each pixel's cut to the cap.
    let mut mean_var = [0.0; 3];
    for c in 0..3 {
        let sum_s: f64 = pairs.iter().map(|p| p.s.variance[c]).sum();
        let sum_r: f64 = pairs.iter().map(|p| p.r.variance[c]).sum();
        mean_var[c] = sum_r / pairs.len() as f64;
        if sum_s > VARIANCE_RATIO * sum_r + 1e-12 {
            return fail(format!(
                "your pixels' {} variances add up to {} times raystep's ({} against {}): a path tracer as the starter kit describes is about as noisy as raystep's, and more than {VARIANCE_RATIO} times is not believed — compute each pixel's variance as the unbiased sample variance of its samples' values",
                CHANNEL[c],
                if sum_r > 0.0 {
                    crate::record::number::fmt64(sum_s / sum_r, crate::record::number::Style::Label)
                } else {
                    "infinitely many".into()
                },
                crate::record::number::fmt64(sum_s, crate::record::number::Style::Label),
                crate::record::number::fmt64(sum_r, crate::record::number::Style::Label),
            ));
        }
    }
    let mut capped = 0usize;
    for p in &mut pairs {
        for (c, mv) in mean_var.iter().enumerate() {
            let cap = VARIANCE_CAP * (p.r.variance[c] + mv);
            if p.s.variance[c] > cap {
                p.s.variance[c] = cap;
                capped += 1;
            }
        }
    }
    // The regions: the image cut into at most 8 × 8 of them (each at least 2 pixels wide), each
    // region's mean tested per channel at level α / 2 shared among them (Bonferroni). A region's
    // mean is over hundreds of samples, where the t-test's normal approximation holds even for a
    // path tracer's heavy-tailed pixels; a single pixel's 16 or 64 samples are not enough for the
    // tails a per-pixel Bonferroni level needs (measured: 2 false failures in 16 correct images).
    let tile = w.max(h).div_ceil(8).max(2);
    let (cols, rows) = (w.div_ceil(tile), h.div_ceil(tile));
    let mut groups: Vec<Vec<&Pair>> = (0..cols * rows).map(|_| vec![]).collect();
    for p in &pairs {
        groups[((p.at[1] / tile) * cols + p.at[0] / tile) as usize].push(p);
    }
    let tested = groups.iter().filter(|g| !g.is_empty()).count().max(1);
    let per_region = ALPHA / 2.0 / (tested * 3) as f64;
    let mut regions = vec![];
    for (i, g) in groups.iter().enumerate() {
        if g.is_empty() {
            continue;
        }
        for c in 0..3 {
            let (ms, mr, p) = group_p(g, c);
            regions.push((i as u32, c, ms, mr, p));
        }
    }
    regions.sort_by(|a, b| a.4.total_cmp(&b.4));
    let rejected: Vec<_> = regions.iter().filter(|r| r.4 < per_region).collect();
    let all: Vec<&Pair> = pairs.iter().collect();
    let whole: Vec<(f64, f64, f64)> = (0..3).map(|c| group_p(&all, c)).collect();
    let whole_level = ALPHA / 2.0 / 3.0;
    let whole_bad = whole.iter().any(|(_, _, p)| *p < whole_level);
    let pass = !whole_bad && rejected.is_empty();
    let mut message = if pass {
        "passed: your image agrees with raystep's within its noise; ".to_string()
    } else {
        "failed: your image differs from raystep's by more than its noise; ".to_string()
    };
    if whole_bad {
        let (c, w) = whole
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.2.total_cmp(&b.1.2))
            .expect("three channels");
        message += &format!(
            "the image as a whole differs from raystep's ({} channel {}, p = {} < {}): a bias, not noise; ",
            CHANNEL[c],
            brighter(w.0, w.1),
            sci(w.2),
            sci(whole_level)
        );
    }
    let region_name = |i: u32| {
        let (x0, y0) = ((i % cols) * tile, (i / cols) * tile);
        format!(
            "x {x0}–{}, y {y0}–{}",
            (x0 + tile).min(w) - 1,
            (y0 + tile).min(h) - 1
        )
    };
    let describe = |list: &[&(u32, usize, f64, f64, f64)]| -> String {
        list.iter()
            .take(6)
            .map(|(i, c, ms, mr, p)| {
                format!(
                    "{} {} {} (p = {})",
                    region_name(*i),
                    CHANNEL[*c],
                    brighter(*ms, *mr),
                    sci(*p)
                )
            })
            .collect::<Vec<_>>()
            .join("; ")
            + if list.len() > 6 { "; …" } else { "" }
    };
    if !rejected.is_empty() {
        let mut named: Vec<u32> = rejected.iter().map(|r| r.0).collect();
        named.sort_unstable();
        named.dedup();
        message += &format!(
            "it differs significantly (p < {} each) in {} of the {tested} regions of {tile}×{tile} pixels: {}; ",
            sci(per_region),
            named.len(),
            describe(&rejected)
        );
    } else if whole_bad {
        let top: Vec<_> = regions.iter().take(3).collect();
        message += &format!(
            "no region of {tile}×{tile} pixels differs significantly on its own (the difference is spread over the image); the regions that differ most: {}; ",
            describe(&top)
        );
    }
    if !pass {
        // The pixels that differ most, by Welch's t-test of each pixel (not a verdict: a pixel's
        // few samples make its own p-value rough).
        let mut px: Vec<([u32; 2], usize, f64, f64, f64)> = pairs
            .iter()
            .flat_map(|p| {
                (0..3).map(move |c| {
                    (
                        p.at,
                        c,
                        p.s.mean[c],
                        p.r.mean[c],
                        welch_p(
                            p.s.mean[c],
                            p.s.variance[c],
                            p.s.n as f64,
                            p.r.mean[c],
                            p.r.variance[c],
                            p.r.n as f64,
                        ),
                    )
                })
            })
            .collect();
        px.sort_by(|a, b| a.4.total_cmp(&b.4));
        let shown: Vec<String> = px
            .iter()
            .take(5)
            .map(|([x, y], c, s, r, p)| {
                format!(
                    "({x}, {y}) {}: yours {}, raystep's {} (p = {})",
                    CHANNEL[*c],
                    crate::record::number::fmt64(*s, crate::record::number::Style::Label),
                    crate::record::number::fmt64(*r, crate::record::number::Style::Label),
                    sci(*p)
                )
            })
            .collect();
        message += &format!("the pixels that differ most: {}; ", shown.join("; "));
    }
    message += &format!(
        "{} pixels compared with raystep's by Welch's t-test; the image's mean: yours {}, raystep's {} (p = {}, {}, {})",
        pairs.len(),
        fmt3(whole.iter().map(|w| w.0)),
        fmt3(whole.iter().map(|w| w.1)),
        sci(whole[0].2),
        sci(whole[1].2),
        sci(whole[2].2),
    );
    if capped > 0 {
        message += &format!(
            "; {capped} pixel channel variance{} claimed above {VARIANCE_CAP} times raystep's {} cut to it",
            if capped == 1 { "" } else { "s" },
            if capped == 1 { "was" } else { "were" }
        );
    }
    message += &format!(
        " (a correct tracer fails this check with probability about {})",
        sci(ALPHA)
    );
    Verdict { pass, message }
}

fn sci(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if x >= 1e-3 {
        format!("{}", (x * 1e4).round() / 1e4)
    } else {
        format!("{x:.1e}")
    }
}

fn fmt3(it: impl Iterator<Item = f64>) -> String {
    let v: Vec<String> = it
        .map(|x| crate::record::number::fmt64(x, crate::record::number::Style::Label))
        .collect();
    format!("({})", v.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn welch_against_a_worked_example() {
        // Two samples with equal means: p = 1; far apart with small spread: p ≈ 0.
        assert!((welch_p(1.0, 0.5, 10.0, 1.0, 0.5, 10.0) - 1.0).abs() < 1e-12);
        assert!(welch_p(0.0, 0.01, 50.0, 1.0, 0.01, 50.0) < 1e-12);
        // t = 2 with 20 degrees of freedom each side: v/n = 0.125 each, se = 0.5, t = 1/0.5 = 2,
        // dof = (0.25)² / (2 · 0.125² / 19) = 38; two-sided p of t = 2 at 38 dof is 0.0527
        // (R: 2 * pt(-2, 38) = 0.05270).
        let p = welch_p(1.0, 2.5, 20.0, 0.0, 2.5, 20.0);
        assert!((p - 0.05270).abs() < 1e-4, "{p}");
    }
}
