//! χ² goodness-of-fit tests of the Monte Carlo sampling routines (`raystep_core::mc::sample`), after
//! Nori's (Jakob, the Nori educational renderer's warptest): draw N samples, histogram them over
//! bins of their domain, compare with the counts the routine's density predicts — the density
//! written again here from the published formula, not taken from the code under test — with
//! bins expected to hold fewer than 5 samples pooled, and reject at significance α = 0.01.
//!
//! The inputs are the project's own random numbers (`portable::random::uniform2` over sample indices),
//! so a poor hash fails here too. Every test is seeded: it passes or fails the same way on every
//! run (a correct sampler would fail for about 1 seed in 100; these seeds pass). One test feeds a
//! wrong sampler on purpose and checks that it is rejected, so the tests can fail.

use glam::Vec3;
use raystep_core::mc::sample::{
    cosine_hemisphere, ggx_normal, sphere_cone, thin_lens, triangle_point, uniform_sphere,
    uniform_triangle,
};
use raystep_core::portable::random::uniform2;
use statrs::distribution::{ChiSquared, ContinuousCDF};
use std::f64::consts::PI;

/// The significance level: a correct sampler is rejected with this probability.
const ALPHA: f64 = 0.01;
/// Samples per test.
const N: u32 = 200_000;

fn inputs(seed: u32) -> impl Iterator<Item = [f32; 2]> {
    (0..N).map(move |i| uniform2([17, 29], i, 0, seed))
}

/// Pearson's χ² of observed against expected counts, bins expecting fewer than 5 pooled into
/// one. Returns (statistic, degrees of freedom, p-value). A sample in a bin expected to be empty
/// is an error by itself.
fn chi2(observed: &[f64], expected: &[f64]) -> (f64, usize, f64) {
    let mut stat = 0.0;
    let mut bins = 0usize;
    let (mut pool_o, mut pool_e) = (0.0, 0.0);
    for (&o, &e) in observed.iter().zip(expected) {
        assert!(e > 0.0 || o == 0.0, "{o} samples where the density is 0");
        if e < 5.0 {
            pool_o += o;
            pool_e += e;
        } else {
            stat += (o - e) * (o - e) / e;
            bins += 1;
        }
    }
    if pool_e > 0.0 {
        stat += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        bins += 1;
    }
    let dof = bins - 1;
    let p = 1.0 - ChiSquared::new(dof as f64).unwrap().cdf(stat);
    (stat, dof, p)
}

/// ∫∫ f over [a0, a1] × [b0, b1] by composite Simpson's rule, 16 intervals each way.
fn simpson2(f: &dyn Fn(f64, f64) -> f64, a: (f64, f64), b: (f64, f64)) -> f64 {
    const K: usize = 16;
    let w = |i: usize| match i {
        0 | K => 1.0,
        i if i % 2 == 1 => 4.0,
        _ => 2.0,
    };
    let (ha, hb) = ((a.1 - a.0) / K as f64, (b.1 - b.0) / K as f64);
    let mut s = 0.0;
    for i in 0..=K {
        for j in 0..=K {
            s += w(i) * w(j) * f(a.0 + i as f64 * ha, b.0 + j as f64 * hb);
        }
    }
    s * ha * hb / 9.0
}

/// Directions binned by cos θ (edges `z`) and φ (`nphi` equal bins); the expected counts integrate
/// `pdf(cos θ, φ)` per steradian (dω = d cos θ dφ). Returns the p-value.
fn test_directions(
    name: &str,
    samples: impl Iterator<Item = Vec3>,
    z: &[f64],
    nphi: usize,
    pdf: &dyn Fn(f64, f64) -> f64,
) -> f64 {
    let nz = z.len() - 1;
    let mut observed = vec![0.0; nz * nphi];
    let mut n = 0.0;
    for v in samples {
        n += 1.0;
        assert!(
            (v.length() - 1.0).abs() < 1e-4,
            "{name}: {v} is not unit length"
        );
        let c = f64::from(v.z);
        let zi = z
            .windows(2)
            .position(|e| c >= e[0] && c <= e[1])
            .unwrap_or_else(|| panic!("{name}: cos θ = {c} outside the domain"));
        let phi = f64::from(v.y).atan2(f64::from(v.x)).rem_euclid(2.0 * PI);
        let pi = ((phi / (2.0 * PI) * nphi as f64) as usize).min(nphi - 1);
        observed[zi * nphi + pi] += 1.0;
    }
    let dphi = 2.0 * PI / nphi as f64;
    let mut expected = vec![0.0; nz * nphi];
    for zi in 0..nz {
        for pi in 0..nphi {
            let phi = (pi as f64 * dphi, (pi + 1) as f64 * dphi);
            expected[zi * nphi + pi] = n * simpson2(pdf, (z[zi], z[zi + 1]), phi);
        }
    }
    let total: f64 = expected.iter().sum::<f64>() / n;
    assert!(
        (total - 1.0).abs() < 1e-3,
        "{name}: the density integrates to {total}"
    );
    let (stat, dof, p) = chi2(&observed, &expected);
    eprintln!("{name}: χ² = {stat:.1}, {dof} degrees of freedom, p = {p:.4}");
    p
}

fn edges(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..=n)
        .map(|i| lo + (hi - lo) * i as f64 / n as f64)
        .collect()
}

#[test]
fn cosine_hemisphere_matches_cos_theta_over_pi() {
    let p = test_directions(
        "cosine hemisphere",
        inputs(1).map(|u| cosine_hemisphere(u).value),
        &edges(0.0, 1.0, 10),
        20,
        &|z, _| z.max(0.0) / PI,
    );
    assert!(p > ALPHA, "rejected: p = {p}");
    // The pdf it reports is its density: cos θ / π at the direction it made.
    for u in inputs(2).take(1000) {
        let s = cosine_hemisphere(u);
        assert!((f64::from(s.pdf) - f64::from(s.value.z) / PI).abs() < 1e-6);
    }
}

#[test]
fn uniform_sphere_matches_one_over_four_pi() {
    let p = test_directions(
        "uniform sphere",
        inputs(3).map(|u| uniform_sphere(u).value),
        &edges(-1.0, 1.0, 10),
        20,
        &|_, _| 1.0 / (4.0 * PI),
    );
    assert!(p > ALPHA, "rejected: p = {p}");
}

#[test]
fn ggx_normals_match_walters_distribution() {
    for (k, alpha) in [0.1f64, 0.5, 1.0].into_iter().enumerate() {
        // Walter et al. 2007, eq. 33, in its own (tan θ) form: D(h) = α² / (π cos⁴θ (α² + tan²θ)²),
        // sampled with density D(h) cos θ.
        let d = move |c: f64| {
            if c <= 0.0 {
                return 0.0;
            }
            let tan2 = (1.0 - c * c) / (c * c);
            alpha * alpha / (PI * c.powi(4) * (alpha * alpha + tan2).powi(2))
        };
        // Bins equal in θ (the lobe of a small α is narrow in cos θ).
        let z: Vec<f64> = (0..=20)
            .rev()
            .map(|i| (std::f64::consts::FRAC_PI_2 * i as f64 / 20.0).cos())
            .collect();
        let mut z = z;
        z[0] = 0.0;
        let p = test_directions(
            &format!("GGX α = {alpha}"),
            inputs(10 + k as u32).map(|u| ggx_normal(alpha as f32, u).value),
            &z,
            12,
            &|c, _| d(c) * c,
        );
        assert!(p > ALPHA, "α = {alpha}: rejected, p = {p}");
        for u in inputs(20 + k as u32).take(1000) {
            let s = ggx_normal(alpha as f32, u);
            let want = d(f64::from(s.value.z)) * f64::from(s.value.z);
            assert!(
                (f64::from(s.pdf) - want).abs() <= 1e-3 * want.max(1.0),
                "α = {alpha}: pdf {} vs {want}",
                s.pdf
            );
        }
    }
}

#[test]
fn sphere_cone_is_uniform_in_the_subtended_cone() {
    let (distance, radius) = (3.0f32, 1.0f32);
    let cos_max = (1.0 - (f64::from(radius) / f64::from(distance)).powi(2)).sqrt();
    let solid_angle = 2.0 * PI * (1.0 - cos_max);
    let p = test_directions(
        "sphere cone",
        inputs(4).map(|u| sphere_cone(distance, radius, u).unwrap().value),
        &edges(cos_max, 1.0, 10),
        20,
        &|_, _| 1.0 / solid_angle,
    );
    assert!(p > ALPHA, "rejected: p = {p}");
    let s = sphere_cone(distance, radius, [0.3, 0.7]).unwrap();
    assert!((f64::from(s.pdf) - 1.0 / solid_angle).abs() < 1e-5);
    // Every direction of the cone hits the sphere: its line passes within the radius.
    for u in inputs(5).take(2000) {
        let v = sphere_cone(distance, radius, u).unwrap().value;
        let centre = Vec3::new(0.0, 0.0, distance);
        let closest = centre - v * centre.dot(v);
        assert!(closest.length() <= radius * (1.0 + 1e-4), "{v} misses");
    }
}

#[test]
fn thin_lens_points_are_uniform_on_the_disk() {
    let radius = 0.5f32;
    // Bins over (r², φ): dA = ½ d(r²) dφ, the density 1/(πR²).
    let (nr, nphi) = (10, 20);
    let r2max = f64::from(radius) * f64::from(radius);
    let mut observed = vec![0.0; nr * nphi];
    for u in inputs(6) {
        let s = thin_lens(radius, u).unwrap();
        let [x, y] = s.value.map(f64::from);
        let r2 = x * x + y * y;
        assert!(r2 <= r2max * (1.0 + 1e-5), "({x}, {y}) is off the lens");
        let ri = ((r2 / r2max * nr as f64) as usize).min(nr - 1);
        let phi = y.atan2(x).rem_euclid(2.0 * PI);
        let pi = ((phi / (2.0 * PI) * nphi as f64) as usize).min(nphi - 1);
        observed[ri * nphi + pi] += 1.0;
        assert!((f64::from(s.pdf) - 1.0 / (PI * r2max)).abs() < 1e-4);
    }
    let dphi = 2.0 * PI / nphi as f64;
    let expected: Vec<f64> = (0..nr * nphi)
        .map(|b| {
            let (ri, pi) = ((b / nphi) as f64, (b % nphi) as f64);
            let density = |_: f64, _: f64| 0.5 / (PI * r2max);
            let r2 = (ri * r2max / nr as f64, (ri + 1.0) * r2max / nr as f64);
            f64::from(N) * simpson2(&density, r2, (pi * dphi, (pi + 1.0) * dphi))
        })
        .collect();
    let (stat, dof, p) = chi2(&observed, &expected);
    eprintln!("thin lens: χ² = {stat:.1}, {dof} degrees of freedom, p = {p:.4}");
    assert!(p > ALPHA, "rejected: p = {p}");
}

/// The area of the cell [x0, x1] × [y0, y1] below the line x + y = 1, exactly: the integral over x
/// of clamp(1 − x − y0, 0, y1 − y0), piecewise linear.
fn below_diagonal(x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
    let h = y1 - y0;
    let f = |x: f64| (1.0 - x - y0).clamp(0.0, h);
    // Break at the kinks x = 1 − y1 and x = 1 − y0; between them f is linear: trapezoids.
    let mut xs = vec![x0, x1, 1.0 - y1, 1.0 - y0];
    xs.retain(|&x| x >= x0 && x <= x1);
    xs.sort_by(f64::total_cmp);
    xs.windows(2)
        .map(|w| (w[1] - w[0]) * (f(w[0]) + f(w[1])) / 2.0)
        .sum()
}

#[test]
fn triangle_points_are_uniform_by_area() {
    // Over the barycentric square: uniform on the half below the diagonal, density 2.
    let n = 20;
    let mut observed = vec![0.0; n * n];
    for u in inputs(7) {
        let [b1, b2] = uniform_triangle(u).map(f64::from);
        assert!(
            b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 + 1e-6,
            "({b1}, {b2})"
        );
        let i = ((b1 * n as f64) as usize).min(n - 1);
        let j = ((b2 * n as f64) as usize).min(n - 1);
        observed[i * n + j] += 1.0;
    }
    let h = 1.0 / n as f64;
    let expected: Vec<f64> = (0..n * n)
        .map(|b| {
            let (i, j) = ((b / n) as f64, (b % n) as f64);
            f64::from(N) * 2.0 * below_diagonal(i * h, (i + 1.0) * h, j * h, (j + 1.0) * h)
        })
        .collect();
    let (stat, dof, p) = chi2(&observed, &expected);
    eprintln!("triangle: χ² = {stat:.1}, {dof} degrees of freedom, p = {p:.4}");
    assert!(p > ALPHA, "rejected: p = {p}");
    // The point's density per unit area is 1/area: a right triangle with legs 2 and 3 has area 3.
    let tri = [
        Vec3::ZERO,
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(0.0, 3.0, 0.0),
    ];
    let s = triangle_point(tri, [0.25, 0.5]).unwrap();
    assert!((s.pdf - 1.0 / 3.0).abs() < 1e-6);
    // √0.25 = 0.5: weights (0.5, 0.25, 0.25) → 0.25·(2, 0, 0) + 0.25·(0, 3, 0).
    assert!((s.value - Vec3::new(0.5, 0.75, 0.0)).length() < 1e-6);
}

#[test]
fn a_wrong_sampler_is_rejected() {
    // Directions uniform in cos θ (a uniform hemisphere) checked against the cosine density: the
    // test must say no, or it could not catch a broken sampler.
    let uniform_hemisphere = |u: [f32; 2]| {
        let z = u[0];
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * std::f32::consts::PI * u[1];
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    };
    let p = test_directions(
        "uniform hemisphere against the cosine density",
        inputs(8).map(uniform_hemisphere),
        &edges(0.0, 1.0, 10),
        20,
        &|z, _| z.max(0.0) / PI,
    );
    assert!(p < 1e-12, "a wrong sampler passed: p = {p}");
}

/// The glossy BSDF's sampled directions (`mc::bsdf::sample`: a GGX normal, the view direction
/// reflected about it) against their density written here from Walter et al. 2007 (eq. 14, 38):
/// p(ωi) = D(h) cos θ_h / (4 |ωo · h|), h = (ωo + ωi)/|ωo + ωi|. A direction reflected below the
/// horizon is no sample (the path ends): the density's missing mass is its own bin. Also the
/// density the sampler returns, and `bsdf::pdf` (MIS needs both), against the formula.
#[test]
fn glossy_bsdf_directions_match_their_density() {
    use raystep_core::mc::bsdf;
    use raystep_core::scene::Bsdf;
    for (k, alpha) in [0.09f64, 0.3].into_iter().enumerate() {
        let wo = Vec3::new(0.5, 0.0, 0.75f32.sqrt());
        let b = Bsdf::Glossy {
            tint: Vec3::ONE,
            alpha: alpha as f32,
        };
        let wo64 = wo.as_dvec3();
        let density = move |c: f64, phi: f64| {
            let s = (1.0 - c * c).max(0.0).sqrt();
            let wi = glam::DVec3::new(s * phi.cos(), s * phi.sin(), c);
            let h = (wo64 + wi).normalize();
            let ch = h.z;
            if ch <= 0.0 {
                return 0.0;
            }
            let tan2 = (1.0 - ch * ch) / (ch * ch);
            let d = alpha * alpha / (PI * ch.powi(4) * (alpha * alpha + tan2).powi(2));
            d * ch / (4.0 * wo64.dot(h).abs())
        };
        // Bins equal in θ over the hemisphere, 24 in φ.
        let mut z: Vec<f64> = (0..=24)
            .rev()
            .map(|i| (std::f64::consts::FRAC_PI_2 * i as f64 / 24.0).cos())
            .collect();
        z[0] = 0.0;
        let (nz, nphi) = (z.len() - 1, 24);
        let mut observed = vec![0.0; nz * nphi + 1];
        for u in inputs(40 + k as u32) {
            let Some(s) = bsdf::sample(&b, wo, Vec3::Z, false, 0.0, u) else {
                observed[nz * nphi] += 1.0;
                continue;
            };
            let c = f64::from(s.wi.z);
            let zi = z.windows(2).position(|e| c >= e[0] && c <= e[1]).unwrap();
            let phi = f64::from(s.wi.y)
                .atan2(f64::from(s.wi.x))
                .rem_euclid(2.0 * PI);
            let pi = ((phi / (2.0 * PI) * nphi as f64) as usize).min(nphi - 1);
            observed[zi * nphi + pi] += 1.0;
            let want = density(c, phi);
            let got = f64::from(s.pdf.unwrap());
            assert!(
                (got - want).abs() <= 2e-3 * want.max(1.0),
                "pdf {got} vs {want}"
            );
            let again = f64::from(bsdf::pdf(&b, wo, s.wi, Vec3::Z));
            assert!(
                (again - want).abs() <= 2e-3 * want.max(1.0),
                "bsdf::pdf {again} vs {want}"
            );
        }
        let n = f64::from(N);
        let dphi = 2.0 * PI / nphi as f64;
        let mut expected = vec![0.0; nz * nphi + 1];
        for zi in 0..nz {
            for pi in 0..nphi {
                let phi = (pi as f64 * dphi, (pi + 1) as f64 * dphi);
                expected[zi * nphi + pi] = n * simpson2(&density, (z[zi], z[zi + 1]), phi);
            }
        }
        let inside: f64 = expected.iter().sum();
        expected[nz * nphi] = (n - inside).max(0.0);
        let (stat, dof, p) = chi2(&observed, &expected);
        eprintln!("glossy α = {alpha}: χ² = {stat:.1}, {dof} degrees of freedom, p = {p:.4}");
        assert!(p > ALPHA, "glossy α = {alpha}: rejected, p = {p}");
    }
}

/// Light sampling on a triangle (`mc::lights::Lights::sample`): the density per steradian it
/// returns is d² / (A |cos θ_light|) written here in f64, `Lights::pdf` gives the same, and the
/// mean of 1/pdf over the samples estimates the solid angle the triangle subtends — computed
/// independently by Van Oosterom and Strackee's formula (1983) — within a Hoeffding bound at
/// δ = 10⁻⁹ (1/pdf lies in [0, A / d_min²]).
#[test]
fn triangle_light_samples_have_the_solid_angle_density() {
    let text = "[[material]]\nname = \"lamp\"\nemission = [1, 1, 1]\n[[triangle]]\nvertices = [[-1, 2, -0.5], [1.5, 2.5, 0], [0, 2, 1.2]]\nmaterial = \"lamp\"\n";
    let scene = raystep_core::scene::load_str(text, "t.toml", None).unwrap();
    let lights = raystep_core::mc::lights::Lights::new(&scene);
    let p = Vec3::new(0.2, 0.0, 0.1);
    let v = [
        glam::DVec3::new(-1.0, 2.0, -0.5),
        glam::DVec3::new(1.5, 2.5, 0.0),
        glam::DVec3::new(0.0, 2.0, 1.2),
    ];
    let area = 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).length();
    let normal = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
    let [a, b, c] = v.map(|q| q - p.as_dvec3());
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let omega = 2.0
        * (a.dot(b.cross(c)).abs())
            .atan2(la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
    let d_min = v
        .iter()
        .map(|q| (*q - p.as_dvec3()).dot(normal).abs())
        .fold(f64::INFINITY, f64::min);
    let m = area / (d_min * d_min);
    let mut sum = 0.0;
    for u in inputs(50) {
        let s = lights.sample(0, p, u).unwrap();
        let q = s.point.as_dvec3();
        let d = q - p.as_dvec3();
        let want = d.length_squared() / (area * d.normalize().dot(normal).abs());
        assert!(
            (f64::from(s.pdf) - want).abs() < 1e-4 * want,
            "{} vs {want}",
            s.pdf
        );
        let again = f64::from(lights.pdf(0, p, s.point));
        assert!((again - want).abs() < 1e-4 * want);
        sum += 1.0 / f64::from(s.pdf);
    }
    let n = f64::from(N);
    let t = m * ((2.0f64 / 1e-9).ln() / (2.0 * n)).sqrt();
    let mean = sum / n;
    eprintln!("triangle light: mean 1/pdf {mean}, solid angle {omega} ± {t}");
    assert!((mean - omega).abs() < t, "{mean} vs {omega} ± {t}");
}
