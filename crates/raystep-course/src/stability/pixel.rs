//! One traced pixel against the exact references: for every intersection test the pixel's trace
//! recorded (in f32, the renderer's numbers), the exact counterpart of each number — computed in
//! rationals from the very f32 inputs the test saw (the ray as recorded, the object as the scene
//! holds it) — and the recorded value's error in ulps. The app's lab panel shows this for the
//! selected pixel; it is how a student sees *where* a formula lost its digits.

use super::exact::{self, q};
use crate::record::{RayRecord, Step, Trace};
use crate::scene::{Scene, Shape};
use num_rational::BigRational;

/// One recorded number and its exact counterpart.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactValue {
    /// Timeline index of the step that recorded it.
    pub step: usize,
    /// The object tested.
    pub object: String,
    /// What the number is ("discriminant", "t₀", "u", …).
    pub quantity: &'static str,
    /// The value the tracer computed (f32).
    pub recorded: f32,
    /// The exact value, rounded to f64 (29 bits finer than f32: enough to count f32 ulps).
    pub exact: f64,
    /// |recorded − exact| in ulps of the exact value in f32.
    pub ulps: f64,
}

/// The size of one f32 ulp at `x` (the spacing of f32 values around |x|; subnormal spacing
/// below the normal range).
pub fn ulp_f32(x: f64) -> f64 {
    let a = x.abs();
    if a < f32::MIN_POSITIVE as f64 {
        return 2f64.powi(-149);
    }
    2f64.powi(a.log2().floor() as i32 - 23)
}

fn q3(v: [f32; 3]) -> [BigRational; 3] {
    v.map(|x| q(f64::from(x)))
}

fn dot(a: &[BigRational; 3], b: &[BigRational; 3]) -> BigRational {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

fn value(
    step: usize,
    object: &str,
    quantity: &'static str,
    recorded: f32,
    exact: f64,
) -> ExactValue {
    let ulps = if recorded as f64 == exact {
        0.0
    } else {
        (recorded as f64 - exact).abs() / ulp_f32(exact)
    };
    ExactValue {
        step,
        object: object.to_string(),
        quantity,
        recorded,
        exact,
        ulps,
    }
}

/// Every sphere, plane and triangle number of `trace` against its exact value. Spheres and
/// planes need `scene` (their geometry is not in the trace); without it (a replayed trace) only
/// the triangles, whose vertices the trace records, are compared.
pub fn exact_values(trace: &Trace, scene: Option<&Scene>) -> Vec<ExactValue> {
    let u = f32::EPSILON as f64 * 0.5;
    let mut out = vec![];
    for (k, (ray, s)) in trace.timeline().into_iter().enumerate() {
        let (o, d) = ray_inputs(ray);
        match &s.step {
            Step::Sphere { object, name, test } => {
                let Some(Shape::Sphere { center, radius }) = shape(scene, *object) else {
                    continue;
                };
                let (gq, oq, dq, r) = (
                    q3(center.to_array()),
                    q3(ray.origin),
                    q3(ray.direction),
                    q(f64::from(*radius)),
                );
                let f = [&oq[0] - &gq[0], &oq[1] - &gq[1], &oq[2] - &gq[2]];
                let a = dot(&dq, &dq);
                let b = dot(&f, &dq) * q(2.0);
                let c = dot(&f, &f) - &r * &r;
                // b² − 4ac; the stable method records 4a·Δ′, the same number.
                let disc = &b * &b - q(4.0) * &a * &c;
                out.push(value(
                    k,
                    name,
                    "discriminant",
                    test.discriminant,
                    exact::to_f64(&disc),
                ));
                if let Some([t0, t1]) = test.roots {
                    let e = exact::sphere(
                        center.to_array().map(f64::from),
                        f64::from(*radius),
                        o,
                        d,
                        u,
                    );
                    // The exact roots in increasing order.
                    let mut roots: Vec<f64> =
                        [e.t, e.other].iter().flatten().map(|x| x.hi).collect();
                    roots.sort_by(f64::total_cmp);
                    if roots.len() == 2 {
                        out.push(value(k, name, "t₀", t0, roots[0]));
                        out.push(value(k, name, "t₁", t1, roots[1]));
                    }
                }
            }
            Step::Plane { object, name, test } => {
                let (n, c) = match shape(scene, *object) {
                    Some(Shape::Plane { normal, offset }) => (normal.to_array(), *offset),
                    Some(Shape::AxisPlane { axis, offset }) => {
                        let mut n = [0.0f32; 3];
                        n[*axis] = 1.0;
                        (n, *offset)
                    }
                    _ => continue,
                };
                if let Some(t) = test.hit() {
                    let e = exact::plane(n.map(f64::from), f64::from(c), o, d, u);
                    if let Some(te) = e.t {
                        out.push(value(k, name, "t", t, te.hi));
                    }
                }
            }
            Step::Triangle {
                name,
                vertices,
                test,
                ..
            } => {
                let e = exact::triangle(vertices.map(|v| v.map(f64::from)), o, d, u);
                for (quantity, rec, ex) in
                    [("t", test.t, e.t), ("u", test.u, e.u), ("v", test.v, e.v)]
                {
                    if let (Some(r), Some(x)) = (rec, ex) {
                        out.push(value(k, name, quantity, r, x.hi));
                    }
                }
            }
            _ => {}
        }
    }
    out
}

fn ray_inputs(r: &RayRecord) -> ([f64; 3], [f64; 3]) {
    (r.origin.map(f64::from), r.direction.map(f64::from))
}

fn shape(scene: Option<&Scene>, object: u32) -> Option<&Shape> {
    scene?.objects.get(object as usize).map(|o| &o.shape)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ulps_of_simple_numbers() {
        assert_eq!(ulp_f32(1.0), 2f64.powi(-23));
        assert_eq!(ulp_f32(1.5), 2f64.powi(-23));
        assert_eq!(ulp_f32(2.0), 2f64.powi(-22));
        assert_eq!(ulp_f32(-0.75), 2f64.powi(-24));
    }
}
