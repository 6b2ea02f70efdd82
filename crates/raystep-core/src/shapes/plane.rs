//! Ray–plane intersection: the general plane X·n = c, and the axis-aligned shortcut.

use crate::math::{Ray, Real, Vector};
use serde::{Deserialize, Serialize};

/// How the plane is given.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "form")]
#[serde(bound(
    serialize = "T: crate::jsonf::JsonFloat",
    deserialize = "T: crate::jsonf::JsonFloat"
))]
pub enum PlaneForm<T> {
    /// X·n = c with unit normal n.
    General {
        /// The unit normal n.
        #[serde(with = "crate::jsonf")]
        normal: [T; 3],
        /// c = P·n for a point P on the plane.
        #[serde(with = "crate::jsonf")]
        offset: T,
    },
    /// X_axis = c: the lecture notes' shortcut t = (c − S_axis)/Q_axis.
    Axis {
        /// 0 = x, 1 = y, 2 = z.
        axis: usize,
        /// The plane's coordinate c on that axis.
        #[serde(with = "crate::jsonf")]
        offset: T,
    },
}

/// Every intermediate of one ray–plane test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(bound(
    serialize = "T: crate::jsonf::JsonFloat",
    deserialize = "T: crate::jsonf::JsonFloat"
))]
pub struct PlaneTest<T> {
    /// Which form was tested.
    pub form: PlaneForm<T>,
    /// The denominator Q·n (general) or Q_axis (axis-aligned). Zero (of either sign): parallel.
    #[serde(with = "crate::jsonf")]
    pub denominator: T,
    /// The numerator c − S·n (general) or c − S_axis (axis-aligned).
    #[serde(with = "crate::jsonf")]
    pub numerator: T,
    /// Whether the ray is parallel to the plane (denominator = ±0): always a miss, never NaN.
    pub parallel: bool,
    /// numerator / denominator, when not parallel (may be negative, or ±∞ on overflow).
    #[serde(with = "crate::jsonf")]
    pub t_raw: Option<T>,
    /// The hit distance, when t_raw lies in (t_min, t_max).
    #[serde(with = "crate::jsonf")]
    pub t: Option<T>,
}

impl<T: Real> PlaneTest<T> {
    /// The hit distance, if any.
    #[inline(always)]
    pub fn hit(&self) -> Option<T> {
        self.t
    }
}

/// Intersects `ray` with the general plane X·n = c.
#[inline(always)]
pub fn general<T: Real>(ray: &Ray<T>, normal: T::V, offset: T) -> PlaneTest<T> {
    let denominator = ray.dir.dot(normal);
    let numerator = offset - ray.origin.dot(normal);
    finish(
        ray,
        PlaneForm::General {
            normal: [normal.at(0), normal.at(1), normal.at(2)],
            offset,
        },
        numerator,
        denominator,
    )
}

/// Intersects `ray` with the axis-aligned plane X_axis = c.
#[inline(always)]
pub fn axis<T: Real>(ray: &Ray<T>, axis: usize, offset: T) -> PlaneTest<T> {
    let denominator = ray.dir.at(axis);
    let numerator = offset - ray.origin.at(axis);
    finish(
        ray,
        PlaneForm::Axis { axis, offset },
        numerator,
        denominator,
    )
}

#[inline(always)]
fn finish<T: Real>(ray: &Ray<T>, form: PlaneForm<T>, numerator: T, denominator: T) -> PlaneTest<T> {
    // −0 == +0 in IEEE comparison, so both signs of zero are "parallel" (docs/NUMERICS.md S9).
    if denominator == T::zero() {
        return PlaneTest {
            form,
            denominator,
            numerator,
            parallel: true,
            t_raw: None,
            t: None,
        };
    }
    let t_raw = numerator / denominator;
    // An overflowing t (grazing slope, S10) is ±∞ and fails `< t_max` or `> t_min`: a clean miss.
    let t = if ray.accepts(t_raw) {
        Some(t_raw)
    } else {
        None
    };
    PlaneTest {
        form,
        denominator,
        numerator,
        parallel: false,
        t_raw: Some(t_raw),
        t,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn ray(o: [f32; 3], d: [f32; 3]) -> Ray<f32> {
        Ray::infinite(Vec3::from(o), Vec3::from(d)).unwrap()
    }

    // The Ray Tracer Challenge, ch. 9 ("Planes"): the xz plane y = 0.
    #[test]
    fn rtc_plane_vectors() {
        for test in [
            |r: &Ray<f32>| general(r, Vec3::Y, 0.0),
            |r: &Ray<f32>| axis(r, 1, 0.0),
        ] {
            let parallel = test(&ray([0., 10., 0.], [0., 0., 1.]));
            assert!(parallel.parallel && parallel.t.is_none());
            let coplanar = test(&ray([0., 0., 0.], [0., 0., 1.]));
            assert!(coplanar.parallel && coplanar.t.is_none());
            assert_eq!(test(&ray([0., 1., 0.], [0., -1., 0.])).t, Some(1.0));
            assert_eq!(test(&ray([0., -1., 0.], [0., 1., 0.])).t, Some(1.0));
        }
    }

    #[test]
    fn signed_zero_denominators_miss() {
        // S9: d·n = +0 and −0, origin on and off the plane: miss in all four, never NaN.
        for d in [[0., 0., 1.], [0., -0., 1.]] {
            for o in [[0., 0., 0.], [0., 1., 0.]] {
                let t = axis(&ray(o, d), 1, 0.0);
                assert!(t.parallel && t.t.is_none());
            }
        }
    }

    #[test]
    fn grazing_overflow_is_clean_miss() {
        // S10: slope 1e-40 (subnormal in f32): numerator 1 / 1e-40 overflows to +∞ → miss.
        let t = axis(&ray([0., 1., 0.], [1., -1e-40, 0.]), 1, 0.0);
        assert!(!t.parallel);
        assert!(t.t.is_none());
        assert!(!t.t_raw.unwrap().is_nan());
    }
}
