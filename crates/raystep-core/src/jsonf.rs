//! Floats in JSON, infinities included. JSON has no ∞ or NaN (serde_json writes `null`), yet a
//! step trace legitimately holds them: the closest hit "so far" starts at ∞, a slab's reciprocal
//! of a zero direction component is ±∞, and a ray lying in a slab's face gives 0·∞ = NaN.
//! Fields marked `#[serde(with = "crate::jsonf")]` write finite values as numbers and the others
//! as the strings `"inf"`, `"-inf"` and `"nan"`, and read both forms back exactly.

use serde::de::{self, Deserializer, Visitor};
use serde::ser::{SerializeSeq, Serializer};
use std::fmt;

/// A float, an option of one, or an array of them, (de)serialized with non-finite values as strings.
pub trait JsonFloat: Sized {
    /// Serializes the value.
    fn ser<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error>;
    /// Deserializes the value.
    fn de<'de, D: Deserializer<'de>>(d: D) -> Result<Self, D::Error>;
}

struct FloatVisitor;

impl Visitor<'_> for FloatVisitor {
    type Value = f64;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a number or one of \"inf\", \"-inf\", \"nan\"")
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<f64, E> {
        Ok(v)
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<f64, E> {
        Ok(v as f64)
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<f64, E> {
        Ok(v as f64)
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<f64, E> {
        match v {
            "inf" => Ok(f64::INFINITY),
            "-inf" => Ok(f64::NEG_INFINITY),
            "nan" => Ok(f64::NAN),
            other => Err(E::invalid_value(de::Unexpected::Str(other), &self)),
        }
    }
}

fn ser_f64<S: Serializer>(x: f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_nan() {
        s.serialize_str("nan")
    } else if x == f64::INFINITY {
        s.serialize_str("inf")
    } else if x == f64::NEG_INFINITY {
        s.serialize_str("-inf")
    } else {
        s.serialize_f64(x)
    }
}

impl JsonFloat for f32 {
    fn ser<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        if self.is_finite() {
            s.serialize_f32(*self)
        } else {
            ser_f64(*self as f64, s)
        }
    }
    fn de<'de, D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        // Finite values were written in f32's shortest form, so parsing them as f64 and rounding
        // to f32 gives back the same bits.
        d.deserialize_any(FloatVisitor).map(|v| v as f32)
    }
}

impl JsonFloat for f64 {
    fn ser<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        ser_f64(*self, s)
    }
    fn de<'de, D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(FloatVisitor)
    }
}

/// Adapts a [`JsonFloat`] to serde's traits (for options and sequences).
struct W<T>(T);

impl<T: JsonFloat> serde::Serialize for W<&T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.ser(s)
    }
}

impl<'de, T: JsonFloat> serde::Deserialize<'de> for W<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        T::de(d).map(W)
    }
}

impl<T: JsonFloat> JsonFloat for Option<T> {
    fn ser<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Some(v) => s.serialize_some(&W(v)),
            None => s.serialize_none(),
        }
    }
    fn de<'de, D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        <Option<W<T>> as serde::Deserialize>::deserialize(d).map(|o| o.map(|w| w.0))
    }
}

impl<T: JsonFloat, const N: usize> JsonFloat for [T; N] {
    fn ser<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut seq = s.serialize_seq(Some(N))?;
        for v in self {
            seq.serialize_element(&W(v))?;
        }
        seq.end()
    }
    fn de<'de, D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = <Vec<W<T>> as serde::Deserialize>::deserialize(d)?;
        let n = v.len();
        let items: Vec<T> = v.into_iter().map(|w| w.0).collect();
        items
            .try_into()
            .map_err(|_| de::Error::invalid_length(n, &format!("{N} numbers").as_str()))
    }
}

/// For `#[serde(with = "crate::jsonf")]`.
pub fn serialize<T: JsonFloat, S: Serializer>(v: &T, s: S) -> Result<S::Ok, S::Error> {
    v.ser(s)
}

/// For `#[serde(with = "crate::jsonf")]`.
pub fn deserialize<'de, T: JsonFloat, D: Deserializer<'de>>(d: D) -> Result<T, D::Error> {
    T::de(d)
}

#[cfg(test)]
mod tests {
    #[derive(serde::Serialize, serde::Deserialize, PartialEq, Debug)]
    struct S {
        #[serde(with = "super")]
        a: f32,
        #[serde(with = "super")]
        b: [f32; 3],
        #[serde(with = "super")]
        c: Option<f32>,
        #[serde(with = "super")]
        d: Option<[f32; 2]>,
    }

    #[test]
    fn non_finite_round_trip() {
        let s = S {
            a: f32::INFINITY,
            b: [f32::NEG_INFINITY, 0.1, -0.0],
            c: Some(f32::INFINITY),
            d: None,
        };
        let j = serde_json::to_string(&s).unwrap();
        assert_eq!(j, r#"{"a":"inf","b":["-inf",0.1,-0.0],"c":"inf","d":null}"#);
        let back: S = serde_json::from_str(&j).unwrap();
        assert_eq!(back, s);
        assert!(back.b[2].is_sign_negative());
        let nan: S =
            serde_json::from_str(r#"{"a":"nan","b":[1,2,3],"c":null,"d":[1,"inf"]}"#).unwrap();
        assert!(nan.a.is_nan());
        assert!(
            serde_json::from_str::<S>(r#"{"a":"lots","b":[1,2,3],"c":null,"d":null}"#).is_err()
        );
    }
}
