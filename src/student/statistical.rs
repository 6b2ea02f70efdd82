//! The statistical check of a Monte Carlo tracer that draws its own random numbers (`raystep
//! grade-tracer --statistical`): the student's image, with each pixel's sample mean, sample
//! variance and sample count, against raystep's own, by Welch's t-test (as Nori's `warptest`
//! and its image tests do), per pixel and for the image as a whole.
//!
//! **False-failure rate.** A correct tracer fails with probability at most [`ALPHA`] = 10⁻³:
//! half of it goes to the whole-image test, half is shared among the per-pixel tests by
//! Bonferroni's correction (each of the N channel tests at level α / (2N)), so the chance that
//! any of them rejects a correct image is at most α/2 + α/2. The test treats each pixel's mean
//! as normally distributed (the t-test's assumption, good for the dozens of samples per pixel a
//! grading run takes; with a handful of samples of a heavy-tailed pixel the true rate can
//! differ).
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
    let mut pixels = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
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
            pixels.push((n > 0).then(|| {
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
            }));
        }
    }
    StatImage {
        width: w,
        height: h,
        pixels,
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

/// Reads a statistics file; errors name the line.
pub fn parse(text: &str) -> Result<StatImage, String> {
    let mut img: Option<StatImage> = None;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let l = raw.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let rec: Line = serde_json::from_str(l).map_err(|e| {
            let shown: String = l.chars().take(80).collect();
            format!("line {line}: a record the statistics format cannot read ({e}): {shown}")
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
                if width == 0 || height == 0 || (width as u64) * (height as u64) > 1 << 26 {
                    return Err(format!(
                        "line {line}: an image of {width}×{height} pixels cannot be graded"
                    ));
                }
                img = Some(StatImage {
                    width,
                    height,
                    pixels: vec![None; (width * height) as usize],
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
                im.pixels[(y * im.width + x) as usize] = Some(PixelStats {
                    n: samples,
                    mean,
                    variance,
                });
            }
        }
    }
    img.ok_or_else(|| "no `image` record: the file must give the image's width and height".into())
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
    /// In words: the pixels rejected, the whole image's p-value, the false-failure rate.
    pub message: String,
}

/// Compares the student's statistics with raystep's: each channel of each pixel the student
/// gives by Welch's t-test at level α / (2N) (N: the channel tests), and the mean of those
/// pixels per channel at level α / 6, so that a correct image fails with probability at most
/// [`ALPHA`].
pub fn compare(student: &StatImage, reference: &StatImage) -> Verdict {
    if (student.width, student.height) != (reference.width, reference.height) {
        return Verdict {
            pass: false,
            message: format!(
                "your image is {}×{}, the scene's is {}×{}",
                student.width, student.height, reference.width, reference.height
            ),
        };
    }
    let mut pairs = vec![];
    for y in 0..reference.height {
        for x in 0..reference.width {
            if let (Some(s), Some(r)) = (student.at(x, y), reference.at(x, y)) {
                pairs.push(([x, y], s, r));
            }
        }
    }
    if pairs.is_empty() {
        return Verdict {
            pass: false,
            message: "your statistics give no pixel".into(),
        };
    }
    let tests = (pairs.len() * 3) as f64;
    let per_test = ALPHA / 2.0 / tests;
    let mut rejected = vec![];
    for (at, s, r) in &pairs {
        for c in 0..3 {
            let p = welch_p(
                s.mean[c],
                s.variance[c],
                s.n as f64,
                r.mean[c],
                r.variance[c],
                r.n as f64,
            );
            if p < per_test {
                rejected.push((*at, c, s.mean[c], r.mean[c], p));
            }
        }
    }
    // The whole image: the mean over the pixels, per channel; the variance of that mean is the
    // sum of the pixels' over P², and its degrees of freedom Welch–Satterthwaite's.
    let p_count = pairs.len() as f64;
    let mut whole = vec![];
    for c in 0..3 {
        let (mut ms, mut mr, mut vs, mut vr, mut ds, mut dr) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for (_, s, r) in &pairs {
            ms += s.mean[c];
            mr += r.mean[c];
            let (a, b) = (s.variance[c] / s.n as f64, r.variance[c] / r.n as f64);
            vs += a;
            vr += b;
            if s.n > 1 {
                ds += a * a / (s.n as f64 - 1.0);
            }
            if r.n > 1 {
                dr += b * b / (r.n as f64 - 1.0);
            }
        }
        let (ms, mr) = (ms / p_count, mr / p_count);
        let se2 = (vs + vr) / (p_count * p_count);
        let p = if se2 > 0.0 {
            let t = (ms - mr) / se2.sqrt();
            let dof = ((vs + vr) * (vs + vr) / (ds + dr).max(f64::MIN_POSITIVE)).max(1.0);
            StudentsT::new(0.0, 1.0, dof).map_or(0.0, |d| (2.0 * d.sf(t.abs())).min(1.0))
        } else {
            welch_p(ms, 0.0, 1.0, mr, 0.0, 1.0)
        };
        whole.push((ms, mr, p));
    }
    let whole_level = ALPHA / 2.0 / 3.0;
    let whole_bad = whole.iter().any(|(_, _, p)| *p < whole_level);
    let channel = ["red", "green", "blue"];
    let mut message = format!(
        "{} pixels compared with raystep's by Welch's t-test; the image's mean: yours {}, raystep's {} (p = {}, {}, {}); ",
        pairs.len(),
        fmt3(whole.iter().map(|w| w.0)),
        fmt3(whole.iter().map(|w| w.1)),
        sci(whole[0].2),
        sci(whole[1].2),
        sci(whole[2].2),
    );
    if whole_bad {
        let (c, w) = whole
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.2.total_cmp(&b.1.2))
            .expect("three channels");
        message += &format!(
            "the image as a whole differs from raystep's ({} channel {} % {}, p = {} < {}): a bias, not noise; ",
            channel[c],
            ((w.0 / w.1 - 1.0) * 100.0).abs().round(),
            if w.0 > w.1 { "brighter" } else { "darker" },
            sci(w.2),
            sci(whole_level)
        );
    }
    if rejected.is_empty() {
        message += "no pixel differs significantly";
    } else {
        rejected.sort_by(|a, b| a.4.total_cmp(&b.4));
        let shown: Vec<String> = rejected
            .iter()
            .take(5)
            .map(|([x, y], c, s, r, p)| {
                format!(
                    "({x}, {y}) {}: yours {}, raystep's {} (p = {})",
                    channel[*c],
                    crate::record::number::fmt64(*s, crate::record::number::Style::Label),
                    crate::record::number::fmt64(*r, crate::record::number::Style::Label),
                    sci(*p)
                )
            })
            .collect();
        message += &format!(
            "{} pixel channel{} differ{} significantly (p < {} each): {}",
            rejected.len(),
            if rejected.len() == 1 { "" } else { "s" },
            if rejected.len() == 1 { "s" } else { "" },
            sci(per_test),
            shown.join("; ")
        );
    }
    message += &format!(
        " (a correct tracer fails this check with probability at most {})",
        sci(ALPHA)
    );
    Verdict {
        pass: !whole_bad && rejected.is_empty(),
        message,
    }
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
