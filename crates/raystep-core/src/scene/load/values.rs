//! One field's value checked where the file gives it: `Loc` knows the object's place in the
//! text and turns a bad number, colour or choice into an error naming its line, column and field.

use super::*;

/// Where an object sits in the file, for locating its fields.
pub(super) struct Loc<'a> {
    pub(super) what: String,
    pub(super) span: Option<Range<usize>>,
    pub(super) ctx: &'a Ctx<'a>,
}

impl Loc<'_> {
    pub(super) fn err(&self, field: &str, message: impl Into<String>) -> SceneError {
        let (line, column) = match &self.span {
            Some(span) => {
                let pos = self
                    .ctx
                    .find_field(span.clone(), field)
                    .unwrap_or(span.start);
                let (l, c) = self.ctx.line_col(pos);
                (Some(l), Some(c))
            }
            None => (None, None),
        };
        SceneError {
            file: self.ctx.file.into(),
            line,
            column,
            field: Some(if field.is_empty() {
                self.what.clone()
            } else {
                format!("{} → {field}", self.what)
            }),
            message: message.into(),
        }
    }

    pub(super) fn num(&self, field: &str, x: f64) -> Result<f32, SceneError> {
        if !x.is_finite() {
            return Err(self.err(field, format!("must be a finite number, got {x}")));
        }
        if x.abs() > MAX_MAGNITUDE {
            return Err(self.err(
                field,
                format!("{x:e} is too large: scene numbers lie within ±{MAX_MAGNITUDE:e}, where single-precision (f32) tracing stays finite"),
            ));
        }
        Ok(x as f32)
    }

    pub(super) fn nonneg(&self, field: &str, x: f64) -> Result<f32, SceneError> {
        let v = self.num(field, x)?;
        if v < 0.0 {
            return Err(self.err(field, format!("must not be negative, got {x}")));
        }
        Ok(v)
    }

    pub(super) fn unit(&self, field: &str, x: f64) -> Result<f32, SceneError> {
        let v = self.nonneg(field, x)?;
        if v > 1.0 {
            return Err(self.err(field, format!("must lie in [0, 1], got {x}")));
        }
        Ok(v)
    }

    pub(super) fn vec3(&self, field: &str, a: [f64; 3]) -> Result<Vec3, SceneError> {
        if a.iter().any(|c| !c.is_finite()) {
            return Err(self.err(field, format!("must be three finite numbers, got {a:?}")));
        }
        if a.iter().any(|c| c.abs() > MAX_MAGNITUDE) {
            return Err(self.err(
                field,
                format!("{a:?} has a component too large: scene numbers lie within ±{MAX_MAGNITUDE:e}, where single-precision (f32) tracing stays finite"),
            ));
        }
        Ok(Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32))
    }

    /// A triangle's vertex: within ±[`MAX_VERTEX`].
    pub(super) fn vertex(&self, field: &str, a: [f64; 3]) -> Result<Vec3, SceneError> {
        let v = self.vec3(field, a)?;
        if a.iter().any(|c| c.abs() > MAX_VERTEX) {
            return Err(self.err(field, vertex_too_large(&format!("{a:?}"))));
        }
        Ok(v)
    }

    /// A position or length of a sphere, plane, light or camera: within ±[`MAX_COORD`].
    pub(super) fn coord(&self, field: &str, x: f64) -> Result<f32, SceneError> {
        if x.is_finite() && x.abs() > MAX_COORD {
            return Err(self.err(
                field,
                format!("{x:e} is too large: positions and radii lie within ±{MAX_COORD:e}, where their squares stay finite in single precision (f32)"),
            ));
        }
        if x.is_finite() {
            return Ok(x as f32);
        }
        self.num(field, x)
    }

    /// A point of a sphere, plane, light or camera: within ±[`MAX_COORD`].
    pub(super) fn coord3(&self, field: &str, a: [f64; 3]) -> Result<Vec3, SceneError> {
        if a.iter().all(|c| c.is_finite()) {
            if a.iter().any(|c| c.abs() > MAX_COORD) {
                return Err(self.err(
                    field,
                    format!("{a:?} has a component too large: positions lie within ±{MAX_COORD:e}, where their squares stay finite in single precision (f32)"),
                ));
            }
            return Ok(Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32));
        }
        self.vec3(field, a)
    }

    pub(super) fn color(&self, field: &str, a: [f64; 3]) -> Result<Vec3, SceneError> {
        let v = self.vec3(field, a)?;
        if v.min_element() < 0.0 {
            return Err(self.err(
                field,
                format!("colour components must not be negative, got {a:?}"),
            ));
        }
        Ok(v)
    }

    /// A colour that is a reflectance: each component in [0, 1].
    pub(super) fn unit_color(&self, field: &str, a: [f64; 3]) -> Result<Vec3, SceneError> {
        let v = self.color(field, a)?;
        if v.max_element() > 1.0 {
            return Err(self.err(
                field,
                format!(
                    "a texture's colours are reflectances: each component lies in [0, 1], got {a:?}"
                ),
            ));
        }
        Ok(v)
    }

    pub(super) fn choice<T: clap::ValueEnum>(&self, field: &str, s: &str) -> Result<T, SceneError> {
        T::from_str(s, true).map_err(|_| {
            let names: Vec<String> = T::value_variants()
                .iter()
                .filter_map(|v| {
                    v.to_possible_value()
                        .map(|p| format!("\"{}\"", p.get_name()))
                })
                .collect();
            self.err(
                field,
                format!(
                    "unknown value \"{s}\"; expected one of {}",
                    names.join(", ")
                ),
            )
        })
    }
}
