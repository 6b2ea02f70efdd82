//! `raystep intersect …`: one ray against one primitive, every intermediate explained in the order
//! the course notes (docs/SOURCES.md) compute it, in f32 or f64.

use super::parse_vec3;
use crate::explain::intersect as explain;
use crate::math::{Ray, Real, Vector, vec_from_f64};
use crate::shapes::{BoxMethod, SphereMethod, TriangleMethod, aabb, plane, sphere, triangle};
use clap::{Args, Subcommand, ValueEnum};
use serde_json::Value;

/// The ray, shared by every shape.
#[derive(Debug, Clone, Args)]
pub struct RayArgs {
    /// Ray origin S as X,Y,Z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub origin: [f64; 3],
    /// Ray direction Q as X,Y,Z (not necessarily unit length; not zero).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub dir: [f64; 3],
    /// Hits at t ≤ tmin are ignored.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub tmin: f64,
    /// Arithmetic precision.
    #[arg(long, value_enum, default_value_t = Precision::F32)]
    pub precision: Precision,
    /// Print one JSON object instead of the explanation.
    #[arg(long)]
    pub json: bool,
}

/// Floating-point precision.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Precision {
    /// Single precision (the renderer's).
    F32,
    /// Double precision.
    F64,
}

/// The primitive to test.
#[derive(Debug, Subcommand)]
pub enum Shape {
    /// A sphere: the quadratic at² + bt + c = 0.
    Sphere {
        /// Centre G as X,Y,Z.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        center: [f64; 3],
        /// Radius r > 0.
        #[arg(long, allow_hyphen_values = true)]
        radius: f64,
        /// Method.
        #[arg(long, value_enum, default_value_t = SphereMethod::Stable)]
        method: SphereMethod,
        /// The ray.
        #[command(flatten)]
        ray: RayArgs,
    },
    /// A plane: --point and --normal (X·n = c), or --axis and --offset (the shortcut).
    Plane {
        /// A point on the plane.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, requires = "normal", conflicts_with_all = ["axis", "offset"])]
        point: Option<[f64; 3]>,
        /// The plane's normal (need not be unit length).
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, requires = "point")]
        normal: Option<[f64; 3]>,
        /// Axis of an axis-aligned plane.
        #[arg(long, value_enum, required_unless_present = "point")]
        axis: Option<Axis>,
        /// The axis-aligned plane's coordinate c.
        #[arg(long, allow_hyphen_values = true, requires = "axis")]
        offset: Option<f64>,
        /// The ray.
        #[command(flatten)]
        ray: RayArgs,
    },
    /// A triangle P0, P1, P2.
    Triangle {
        /// Vertex P0.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        p0: [f64; 3],
        /// Vertex P1.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        p1: [f64; 3],
        /// Vertex P2.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        p2: [f64; 3],
        /// Method.
        #[arg(long, value_enum, default_value_t = TriangleMethod::MollerTrumbore)]
        method: TriangleMethod,
        /// The ray.
        #[command(flatten)]
        ray: RayArgs,
    },
    /// An axis-aligned box: the slab test.
    Box {
        /// Minimum corner.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        min: [f64; 3],
        /// Maximum corner.
        #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
        max: [f64; 3],
        /// Method.
        #[arg(long, value_enum, default_value_t = BoxMethod::Robust)]
        method: BoxMethod,
        /// The ray.
        #[command(flatten)]
        ray: RayArgs,
    },
}

/// An axis name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Axis {
    /// x.
    X,
    /// y.
    Y,
    /// z.
    Z,
}

/// Runs `raystep intersect`.
pub fn run(shape: &Shape) -> Result<(), String> {
    let ray = match shape {
        Shape::Sphere { ray, .. }
        | Shape::Plane { ray, .. }
        | Shape::Triangle { ray, .. }
        | Shape::Box { ray, .. } => ray,
    };
    let (text, value) = match ray.precision {
        Precision::F32 => compute::<f32>(shape, ray)?,
        Precision::F64 => compute::<f64>(shape, ray)?,
    };
    if ray.json {
        super::emit(&(serde_json::to_string_pretty(&value).expect("json") + "\n"))
    } else {
        super::emit(&text)
    }
}

fn compute<T: Real>(shape: &Shape, args: &RayArgs) -> Result<(String, Value), String> {
    let tmin = scalar::<T>("--tmin", args.tmin)?;
    if tmin < T::zero() {
        return Err(format!("--tmin must not be negative, got {}", args.tmin));
    }
    let ray = Ray::<T>::new(
        vector::<T>("--origin", args.origin)?,
        vector::<T>("--dir", args.dir)?,
        tmin,
        T::infinity(),
    )
    .map_err(|e| format!("--origin/--dir: {e}"))?;
    let mut s = String::new();
    let value = match shape {
        Shape::Sphere {
            center,
            radius,
            method,
            ..
        } => {
            let r = scalar::<T>("--radius", *radius)?;
            if r <= T::zero() {
                return Err(format!("--radius must be positive, got {radius}"));
            }
            let g = vector::<T>("--center", *center)?;
            let t = sphere::intersect(&ray, g, r, *method);
            explain::sphere(&mut s, &ray, g, r, &t)
        }
        Shape::Plane {
            point,
            normal,
            axis,
            offset,
            ..
        } => {
            let t = if let Some(ax) = axis {
                let axis = *ax as usize;
                let c = scalar::<T>("--offset", offset.unwrap_or(0.0))?;
                plane::axis(&ray, axis, c)
            } else {
                let n = normal.expect("clap requires --normal with --point");
                let unit =
                    crate::math::unit_f64(n).ok_or("--normal must not be the zero vector")?;
                let nn = vec_from_f64::<T>(unit);
                let p = vector::<T>("--point", point.expect("clap requires --point"))?;
                let c = p.dot(nn);
                plane::general(&ray, nn, c)
            };
            explain::plane(&mut s, &ray, &t)
        }
        Shape::Triangle {
            p0, p1, p2, method, ..
        } => {
            let p = [
                vector::<T>("--p0", *p0)?,
                vector::<T>("--p1", *p1)?,
                vector::<T>("--p2", *p2)?,
            ];
            let t = triangle::intersect(&ray, p, *method);
            explain::triangle(&mut s, &ray, p, &t)
        }
        Shape::Box {
            min, max, method, ..
        } => {
            let lo = vector::<T>("--min", *min)?;
            let hi = vector::<T>("--max", *max)?;
            if (0..3).any(|i| lo.at(i) > hi.at(i)) {
                return Err(format!(
                    "--min {min:?} must not exceed --max {max:?} on any axis"
                ));
            }
            let t = aabb::intersect(&ray, lo, hi, *method);
            explain::aabb(&mut s, &ray, lo, hi, &t)
        }
    };
    Ok((s, value))
}

/// A command-line number in precision `T`, rejected if it is not finite there.
fn scalar<T: Real>(flag: &str, x: f64) -> Result<T, String> {
    let v = T::from_f64(x);
    if !x.is_finite() {
        return Err(format!("{flag} must be a finite number, got {x}"));
    }
    if !v.is_finite() {
        return Err(format!(
            "{flag} {x:e} is too large for {} (at most {:e})",
            T::NAME,
            T::max_value().to_f64()
        ));
    }
    Ok(v)
}

/// A command-line vector in precision `T`, rejected if a component is not finite there.
fn vector<T: Real>(flag: &str, a: [f64; 3]) -> Result<T::V, String> {
    for c in a {
        scalar::<T>(flag, c)?;
    }
    Ok(vec_from_f64::<T>(a))
}
