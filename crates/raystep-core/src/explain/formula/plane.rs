//! The math panel's ray–plane test: the general plane and the axis-aligned shortcut.

use super::*;

impl Ctx<'_> {
    pub(super) fn plane(&self, name: &str, test: &PlaneTest<f32>) -> Explanation {
        let (o, d) = (self.ray.origin, self.ray.direction);
        let mut lines = vec![];
        let form = match test.form {
            PlaneForm::General { normal, offset } => {
                lines.push(line(
                    "denominator",
                    "Q·n",
                    format!("{}·{}", v3(d), v3(normal)),
                    num(test.denominator),
                    None,
                ));
                lines.push(line(
                    "numerator",
                    "c − S·n",
                    format!("{} − {}·{}", num(offset), v3(o), v3(normal)),
                    num(test.numerator),
                    None,
                ));
                "general: X·n = c".to_string()
            }
            PlaneForm::Axis { axis, offset } => {
                let a = AXES[axis.min(2)];
                lines.push(line(
                    "denominator",
                    &format!("Q{a}"),
                    "",
                    num(test.denominator),
                    None,
                ));
                lines.push(line(
                    "numerator",
                    &format!("c − S{a}"),
                    format!("{} − {}", num(offset), p(o[axis.min(2)])),
                    num(test.numerator),
                    None,
                ));
                format!("axis-aligned: {a} = c")
            }
        };
        let conclusion = if test.parallel {
            lines[0].note = Some("= 0: the ray runs parallel to the plane".into());
            "The denominator is zero: the ray is parallel to the plane (or lies in it) — a miss, never a division by zero.".to_string()
        } else {
            let t_raw = test.t_raw.unwrap_or(f32::NAN);
            lines.push(line(
                "t",
                "numerator / denominator",
                format!("{}/{}", p(test.numerator), p(test.denominator)),
                num(t_raw),
                None,
            ));
            lines.push(self.range_line(t_raw));
            match test.t {
                Some(t) => format!("Hit at t = {}.", num(t)),
                None if t_raw > self.ray.t_min => {
                    "t is beyond t_max (something closer was already hit): a miss.".into()
                }
                None => "t is at or behind the origin: a miss.".into(),
            }
        };
        Explanation {
            title: format!("Ray–plane \"{name}\" ({form})"),
            lines,
            conclusion,
        }
    }
}
