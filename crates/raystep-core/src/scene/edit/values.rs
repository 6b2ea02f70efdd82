//! Reading and writing the numbers of a scene's TOML document: vectors and numbers read from
//! tables, moves and new values written back rounded and in the style the file already uses,
//! keeping each value's comment.

use super::*;

/// A number a value holds (an integer or a float).
pub(super) fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Integer(i) => Some(*i.value() as f64),
        Value::Float(f) => Some(*f.value()),
        _ => None,
    }
}

/// Three numbers an array holds.
pub(super) fn vec3(a: &Array) -> Option<[f64; 3]> {
    if a.len() != 3 {
        return None;
    }
    let mut out = [0.0; 3];
    for (o, v) in out.iter_mut().zip(a.iter()) {
        *o = number(v)?;
    }
    Some(out)
}

/// The number `key` holds, or `default` when it is absent.
pub(super) fn read_number(
    t: &dyn TableLike,
    key: &str,
    default: f64,
    what: &str,
) -> Result<f64, String> {
    match t.get(key) {
        None => Ok(default),
        Some(item) => item
            .as_value()
            .and_then(number)
            .ok_or_else(|| format!("{what} → {key}: is not a number")),
    }
}

/// The three numbers `key` holds, or `default` when it is absent.
pub(super) fn read_vec3(
    t: &dyn TableLike,
    key: &str,
    default: [f64; 3],
    what: &str,
) -> Result<[f64; 3], String> {
    match t.get(key) {
        None => Ok(default),
        Some(item) => item
            .as_array()
            .and_then(vec3)
            .ok_or_else(|| format!("{what} → {key}: is not 3 numbers [x, y, z]")),
    }
}

pub(super) fn shift_vec3(
    t: &mut dyn TableLike,
    key: &str,
    default: [f64; 3],
    by: [f64; 3],
    what: &str,
) -> Result<(), String> {
    let old = read_vec3(t, key, default, what)?;
    let new = shifted(old, by);
    finite(&format!("{what} → {key}"), &new)?;
    if new != old {
        set_vec3(t, key, new);
    }
    Ok(())
}

pub(super) fn shift_triangle(
    t: &mut dyn TableLike,
    by: [f64; 3],
    what: &str,
) -> Result<(), String> {
    let bad = || format!("{what} → vertices: is not 3 points [[x, y, z], [x, y, z], [x, y, z]]");
    let arr = t
        .get_mut("vertices")
        .and_then(Item::as_array_mut)
        .filter(|a| a.len() == 3)
        .ok_or_else(bad)?;
    let mut points = [[0.0; 3]; 3];
    for (p, v) in points.iter_mut().zip(arr.iter()) {
        *p = v.as_array().and_then(vec3).ok_or_else(bad)?;
    }
    let new = points.map(|p| shifted(p, by));
    finite(&format!("{what} → vertices"), new.as_flattened())?;
    for (k, p) in new.iter().enumerate() {
        if let Some(a) = arr.get_mut(k).and_then(Value::as_array_mut) {
            write_into(a, *p);
        }
    }
    Ok(())
}

/// `old + by`, rounded; a component not moved keeps its value exactly.
pub(super) fn shifted(old: [f64; 3], by: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| {
        if by[i] == 0.0 {
            old[i]
        } else {
            moved(old[i], by[i])
        }
    })
}

/// Sets `key` to `x`, in the style of the number it replaces, keeping its comment.
pub(super) fn set_number(t: &mut dyn TableLike, key: &str, x: f64) {
    match t.get_mut(key) {
        Some(Item::Value(v)) => {
            if number(v) != Some(x) {
                let mut new = styled(Some(v), x, None);
                *new.decor_mut() = v.decor().clone();
                *v = new;
            }
        }
        Some(item) => *item = Item::Value(styled(None, x, None)),
        None => insert_key(t, key, styled(None, x, None)),
    }
}

/// Sets `key` to three numbers: the elements that change are replaced in place (each in the
/// style of the number it replaces, the array's layout and comments kept).
pub(super) fn set_vec3(t: &mut dyn TableLike, key: &str, new: [f64; 3]) {
    match t.get_mut(key) {
        Some(Item::Value(Value::Array(a))) if vec3(a).is_some() => write_into(a, new),
        Some(Item::Value(v)) => {
            let mut fresh = Value::Array(new_array(new));
            *fresh.decor_mut() = v.decor().clone();
            *v = fresh;
        }
        Some(item) => *item = Item::Value(Value::Array(new_array(new))),
        None => insert_key(t, key, Value::Array(new_array(new))),
    }
}

pub(super) fn new_array(v: [f64; 3]) -> Array {
    v.iter().map(|&x| styled(None, x, None)).collect()
}

/// Writes three numbers into an array of three numbers, touching only those that change (in
/// the style of the number each replaces, or of its padded neighbours).
pub(super) fn write_into(a: &mut Array, new: [f64; 3]) {
    let pad = a.iter().filter_map(padding).max();
    for (i, &x) in new.iter().enumerate() {
        if let Some(v) = a.get_mut(i)
            && number(v) != Some(x)
        {
            let mut fresh = styled(Some(v), x, pad);
            *fresh.decor_mut() = v.decor().clone();
            *v = fresh;
        }
    }
}

/// Adds `key = v` at the end of a table, indented as the table's first key is.
pub(super) fn insert_key(t: &mut dyn TableLike, key: &str, v: Value) {
    let indent = t
        .iter()
        .next()
        .and_then(|(k, _)| t.key(k))
        .and_then(|k| k.leaf_decor().prefix())
        .and_then(|p| p.as_str())
        .map(|p| p.rsplit('\n').next().unwrap_or("").to_string())
        .filter(|p| !p.is_empty() && p.chars().all(|c| c == ' ' || c == '\t'));
    t.insert(key, Item::Value(v));
    if let (Some(indent), Some(mut k)) = (indent, t.key_mut(key)) {
        k.leaf_decor_mut().set_prefix(indent);
    }
}

// ---------------------------------------------------------------------------------------------
// Numbers.

/// Digits after the point in `x`'s shortest decimal form.
pub(super) fn decimals(x: f64) -> usize {
    let s = format!("{}", x.abs());
    s.split_once('.').map_or(0, |(_, f)| f.len())
}

/// `x` rounded to `d` decimals (the nearest double to the rounded decimal).
pub(super) fn round_to(x: f64, d: usize) -> f64 {
    format!("{x:.d$}").parse::<f64>().unwrap_or(x)
}

/// A coordinate moved: `old + by` rounded to 6 decimals, or to as many as `old` has.
pub(super) fn moved(old: f64, by: f64) -> f64 {
    round_to(old + by, decimals(old).clamp(6, 30))
}

/// A value set by the user (a radius, a coefficient, a colour, a light's position): rounded to 6
/// decimals or 6 significant digits, whichever keeps more, which strips the binary noise of a
/// value computed in f64 or f32 (`0.8_f32` is 0.800000011920929) but keeps a tiny radius.
pub(super) fn tidy(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let d = 5 - x.abs().log10().floor() as i64;
    if d > 40 {
        return x;
    }
    round_to(x, d.max(6) as usize)
}

/// `x` as an integer literal, when it is one (and small enough to be read back exactly).
pub(super) fn int_repr(x: f64) -> Option<String> {
    (x.fract() == 0.0 && x.abs() < 1e15).then(|| format!("{}", x as i64))
}

/// `x` as a float literal: shortest decimals, exponent notation for very large or small.
pub(super) fn float_repr(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && !(1e-5..1e16).contains(&a) {
        return format!("{x:e}");
    }
    let s = format!("{x}");
    if s.contains('.') { s } else { s + ".0" }
}

/// Digits after the point of a plain float literal (`0.1600` → 4), `None` for other forms
/// (exponents, `inf`, integers).
pub(super) fn fixed_decimals(repr: &str) -> Option<usize> {
    let body = repr.trim_start_matches(['+', '-']);
    let (int, frac) = body.split_once('.')?;
    let digits = |s: &str| !s.is_empty() && s.chars().all(|c| c.is_ascii_digit() || c == '_');
    (digits(int) && digits(frac)).then(|| frac.chars().filter(char::is_ascii_digit).count())
}

/// The decimals a float is padded to with trailing zeros (`0.1600` → 4, `-200.0` → 1), `None`
/// for a float written without them (`0.5`) and for other values.
pub(super) fn padding(v: &Value) -> Option<usize> {
    let Value::Float(f) = v else { return None };
    fixed_decimals(&f.display_repr()).filter(|&k| k > decimals(*f.value()))
}

/// The number `x` written as a TOML value in the style of `old`, the value it replaces: a float
/// padded with zeros stays padded to as many decimals (`0.1600` → `0.2500`, `-200.0` →
/// `-199.0`); otherwise, as for a new value, a whole number is an integer (so `0` moved to
/// `0.5` and back is `0` again) and others are short floats. `pad` is the padding of the
/// value's neighbours in an array, used when `old` itself shows none.
pub(super) fn styled(old: Option<&Value>, x: f64, pad: Option<usize>) -> Value {
    let x = x + 0.0; // no negative zero
    let pad = match old {
        Some(v @ Value::Float(_)) => padding(v).or(pad),
        _ => None,
    };
    let repr = match pad {
        Some(k) if x.abs() < 1e16 => format!("{x:.*}", k.max(decimals(x))),
        _ => int_repr(x).unwrap_or_else(|| float_repr(x)),
    };
    repr.parse::<Value>().unwrap_or_else(|_| Value::from(x))
}
