//! The student trace format: JSON Lines, one record per line, that a tracer in any language can
//! write (documented in `lessons/starter/README.md`, version [`FORMAT_VERSION`]).
//!
//! Every key but `type` may be left out; the checker compares only what is there. A line that is
//! blank or starts with `#` is skipped (so a tracer may print comments), and so is a record of a
//! type the format does not define; any other line must be one JSON object with a `type`, whose
//! known keys hold the right kinds of value, else the whole output is refused with the line
//! named. (NaN is not JSON: a tracer that prints it is refused there.)

use serde::{Deserialize, Serialize};

/// The format's version (the optional first record `{"type":"format","version":1}`).
pub const FORMAT_VERSION: u32 = 1;

/// The record types the format defines (others are skipped).
pub const KNOWN_TYPES: [&str; 11] = [
    "format", "pixel", "ray", "instance", "sphere", "plane", "triangle", "hit", "surface",
    "shadow", "color",
];

/// Between an instance's name and its prototype's primitive in a combined name, as raystep
/// names an instanced hit: `gem near → gem[9]`.
pub const INSTANCE_ARROW: &str = " → ";

/// The name of `object` as `instance` places it (`gem near → gem[9]`), or `object` itself.
pub fn placed_name(instance: Option<&str>, object: &str) -> String {
    match instance {
        Some(i) if !object.contains(INSTANCE_ARROW) => format!("{i}{INSTANCE_ARROW}{object}"),
        _ => object.to_string(),
    }
}

/// One line of a student trace. Keys the format does not define are ignored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "kebab-case")]
pub enum Record {
    /// The format's version; optional, first if present.
    Format {
        /// [`FORMAT_VERSION`].
        #[serde(default, skip_serializing_if = "Option::is_none")]
        version: Option<u32>,
    },
    /// Starts a pixel.
    Pixel {
        /// x from the left.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        x: Option<u32>,
        /// y from the top.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        y: Option<u32>,
    },
    /// Starts a ray; the records after it belong to it until the next `ray` or `pixel` (a
    /// `shadow`, `hit` or `color` record may name the depth of the ray it belongs to instead).
    Ray {
        /// `primary`, `shadow`, `reflection` or `refraction`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        kind: Option<String>,
        /// Recursion depth (primary = 0; a shadow ray is one deeper than the ray it leaves).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        depth: Option<u32>,
        /// Origin S.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        origin: Option<[f64; 3]>,
        /// Direction Q (any length: the checker compares directions and scales t by |Q|).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        direction: Option<[f64; 3]>,
        /// A shadow ray's light (helps pair it with raystep's when there are several lights).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        light: Option<String>,
    },
    /// The ray carried into an instance's object space (lesson 20): S′ = M⁻¹S (a point),
    /// Q′ = M⁻¹Q (a vector, not renormalised, so t is the world ray's t). The `sphere` and
    /// `triangle` records after it, until the ray's next `instance` record, are tests of the
    /// instance's prototype with that ray (a test with `"instance": null` is the world's).
    Instance {
        /// The instance's name in the scene file.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        /// S′, the origin in object space.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        origin: Option<[f64; 3]>,
        /// Q′, the direction in object space.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        direction: Option<[f64; 3]>,
    },
    /// A ray–sphere test in the course notes' form (docs/SOURCES.md): a = Q·Q, b = 2 f·Q, c = f·f − r², f = S − G.
    Sphere {
        /// The instance whose prototype this is (default: the ray's latest `instance` record;
        /// null: a world object).
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        instance: Option<Option<String>>,
        /// The sphere's name in the scene file.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        object: Option<String>,
        /// a.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        a: Option<f64>,
        /// b.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        b: Option<f64>,
        /// c.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        c: Option<f64>,
        /// b² − 4ac.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        discriminant: Option<f64>,
        /// The chosen root, or null for a miss.
        #[serde(default, deserialize_with = "present")]
        t: Option<Option<f64>>,
    },
    /// A ray–plane test: denominator Q·n, t or null.
    Plane {
        /// The instance whose prototype this is (default: the ray's latest `instance` record;
        /// null: a world object).
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        instance: Option<Option<String>>,
        /// The plane's name.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        object: Option<String>,
        /// Q·n.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        denominator: Option<f64>,
        /// The hit distance, or null for a miss.
        #[serde(default, deserialize_with = "present")]
        t: Option<Option<f64>>,
    },
    /// A ray–triangle test (Möller–Trumbore, lesson 4): det = D0 = det(−Q, E1, E2), u and v the
    /// weights of P1 and P2, t or null.
    Triangle {
        /// The instance whose prototype this is (default: the ray's latest `instance` record;
        /// null: a world object).
        #[serde(
            default,
            deserialize_with = "present",
            skip_serializing_if = "Option::is_none"
        )]
        instance: Option<Option<String>>,
        /// The triangle's name.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        object: Option<String>,
        /// D0.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        det: Option<f64>,
        /// u.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        u: Option<f64>,
        /// v.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        v: Option<f64>,
        /// The hit distance, or null for a miss.
        #[serde(default, deserialize_with = "present")]
        t: Option<Option<f64>>,
    },
    /// The ray's closest hit (`object` null: the ray hits nothing).
    Hit {
        /// The instance the hit lies on, if any (the object is then its prototype's primitive).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        instance: Option<String>,
        /// The object hit, or null.
        #[serde(default, deserialize_with = "present")]
        object: Option<Option<String>>,
        /// The hit distance.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        t: Option<f64>,
        /// The hit point.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        point: Option<[f64; 3]>,
        /// The unit normal, facing the ray.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        normal: Option<[f64; 3]>,
        /// The depth of the ray this belongs to (default: the latest ray).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        depth: Option<u32>,
    },
    /// What the surface gives shading at the ray's closest hit (lessons 17–19): the shading
    /// normal, the texture coordinates, the texel read and the texture's colour there.
    Surface {
        /// The unit shading normal on the ray's side: a smooth triangle's vertex normals
        /// blended with the hit's barycentrics, (1 − u − v)·n₀ + u·n₁ + v·n₂, normalized.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        normal: Option<[f64; 3]>,
        /// The texture coordinates (u, v) at the hit, before the wrap mode.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        uv: Option<[f64; 2]>,
        /// The texel read: an image's column and row (row 0 at the top; a bilinear read's
        /// first texel, (⌊x − ½⌋, ⌊y − ½⌋) wrapped), or a checker's square (⌊u·s₀⌋, ⌊v·s₁⌋).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        texel: Option<[i64; 2]>,
        /// The texture's colour at (u, v), linear RGB (before the material's colour multiplies
        /// it).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        texture: Option<[f64; 3]>,
        /// The depth of the ray this belongs to (default: the latest ray).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        depth: Option<u32>,
    },
    /// Whether a light is blocked from the ray's hit point.
    Shadow {
        /// The light's name.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        light: Option<String>,
        /// Blocked?
        #[serde(default, skip_serializing_if = "Option::is_none")]
        blocked: Option<bool>,
        /// The depth of the ray this belongs to (default: the latest ray that is not a shadow ray).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        depth: Option<u32>,
    },
    /// The ray's colour, linear RGB (the primary ray's is the pixel's).
    Color {
        /// r, g, b.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        rgb: Option<[f64; 3]>,
        /// The depth of the ray this belongs to (default: the latest ray). A recursive tracer
        /// prints a ray's colour after its children's: it names the depth.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        depth: Option<u32>,
    },
}

/// A key that may be absent (None), null (Some(None)) or a value (Some(Some)).
fn present<'de, D, T>(d: D) -> Result<Option<Option<T>>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Deserialize<'de>,
{
    Option::<T>::deserialize(d).map(Some)
}

/// One ray of a pixel, with what was recorded about it.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Ray {
    /// Kind as written (`primary`, …).
    pub kind: String,
    /// Depth.
    pub depth: u32,
    /// Origin.
    pub origin: Option<[f64; 3]>,
    /// Direction.
    pub direction: Option<[f64; 3]>,
    /// A shadow ray's light.
    pub light: Option<String>,
    /// The parent ray's index (None for the primary ray).
    pub parent: Option<usize>,
    /// The primitive tests, in order (an instance's named `instance → primitive`).
    pub tests: Vec<Test>,
    /// The instances the ray entered, in order, each with the ray in its object space.
    pub instances: Vec<InstanceRay>,
    /// The closest hit: None = no record; Some(None) = a miss.
    pub hit: Option<Option<Hit>>,
    /// What the surface gives shading at the closest hit (None: no `surface` record).
    pub surface: Option<Surface>,
    /// Lights: (name, blocked).
    pub shadows: Vec<(String, Option<bool>)>,
    /// Colour.
    pub color: Option<[f64; 3]>,
    /// The line it starts on (1-based; 0 for raystep's own).
    pub line: usize,
}

/// The ray carried into an instance's object space.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct InstanceRay {
    /// The instance's name.
    pub name: String,
    /// S′ = M⁻¹S.
    pub origin: Option<[f64; 3]>,
    /// Q′ = M⁻¹Q.
    pub direction: Option<[f64; 3]>,
    /// The index in the ray's `tests` of the first test after it.
    pub first_test: usize,
    /// The line it is on (1-based; 0 for raystep's own).
    pub line: usize,
}

/// A primitive test.
#[derive(Debug, Clone, PartialEq)]
pub enum Test {
    /// A sphere.
    Sphere {
        /// Name.
        object: String,
        /// a, b, c, discriminant.
        abcd: [Option<f64>; 4],
        /// t: None = not given; Some(None) = a miss.
        t: Option<Option<f64>>,
    },
    /// A plane.
    Plane {
        /// Name.
        object: String,
        /// Q·n.
        denominator: Option<f64>,
        /// t.
        t: Option<Option<f64>>,
    },
    /// A triangle.
    Triangle {
        /// Name.
        object: String,
        /// D0, u, v.
        det_u_v: [Option<f64>; 3],
        /// t.
        t: Option<Option<f64>>,
    },
}

impl Test {
    /// The object's name.
    pub fn object(&self) -> &str {
        match self {
            Test::Sphere { object, .. }
            | Test::Plane { object, .. }
            | Test::Triangle { object, .. } => object,
        }
    }
}

/// A closest hit.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Hit {
    /// The object's name, if given.
    pub object: Option<String>,
    /// t.
    pub t: Option<f64>,
    /// Point.
    pub point: Option<[f64; 3]>,
    /// Normal.
    pub normal: Option<[f64; 3]>,
}

/// A `surface` record: the shading normal and the texture's reading at a hit.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Surface {
    /// The unit shading normal.
    pub normal: Option<[f64; 3]>,
    /// The texture coordinates (u, v).
    pub uv: Option<[f64; 2]>,
    /// The texel (column, row) or checker square read.
    pub texel: Option<[i64; 2]>,
    /// The texture's colour at (u, v).
    pub texture: Option<[f64; 3]>,
}

/// One pixel's rays (the primary ray first; every other ray after its parent).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Pixel {
    /// x, y as written (None when the output has no `pixel` record).
    pub at: Option<[u32; 2]>,
    /// The rays.
    pub rays: Vec<Ray>,
}

/// Why a student's output could not be read.
#[derive(Debug, Clone, PartialEq)]
pub struct FormatError {
    /// The line (1-based).
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

impl std::fmt::Display for FormatError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

fn finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Reads a student's output: every pixel in it, in order. NaN cannot be written in JSON; a
/// number that overflows to infinity is refused with its line.
pub fn parse(text: &str) -> Result<Vec<Pixel>, FormatError> {
    let mut pixels: Vec<Pixel> = vec![];
    // The last pixel's latest ray that is not a shadow ray, overall and per depth: where a
    // record without a depth, and a ray or record naming one, belongs (looked up, not searched
    // for, so a flood of rays is read in linear time).
    let mut latest_lit: Option<usize> = None;
    let mut lit_at_depth: std::collections::HashMap<u32, usize> = Default::default();
    // The latest ray's latest `instance` record: whose prototype the tests after it test.
    let mut inside: Option<String> = None;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let l = raw.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let err = |message: String| FormatError { line, message };
        let shown: String = l.chars().take(80).collect();
        let value: serde_json::Value = serde_json::from_str(l)
            .map_err(|e| {
                // Text that is not JSON at all is usually a debugging print.
                let hint = if l.starts_with(['{', '[']) {
                    ""
                } else {
                    " — print debugging output to standard error (Python: print(..., file=sys.stderr)); standard output is for the trace's records"
                };
                err(format!("not a JSON object ({e}): {shown}{hint}"))
            })?;
        let Some(ty) = value
            .get("type")
            .and_then(|t| t.as_str())
            .map(str::to_string)
        else {
            return Err(err(format!("a record needs a \"type\": {shown}")));
        };
        // A record of a type the format does not define (a student's own bounding volumes,
        // timings…) is not an error: it is skipped.
        if !KNOWN_TYPES.contains(&ty.as_str()) {
            continue;
        }
        let rec: Record = serde_json::from_value(value).map_err(|e| {
            err(format!(
                "a \"{ty}\" record the format cannot read ({e}): {shown}"
            ))
        })?;
        let nums: Vec<f64> = numbers(&rec);
        if !finite(&nums) {
            return Err(err("a number is not finite".into()));
        }
        match rec {
            Record::Format { version } => {
                if let Some(v) = version
                    && v != FORMAT_VERSION
                {
                    return Err(err(format!(
                        "format version {v}: this raystep reads version {FORMAT_VERSION}"
                    )));
                }
            }
            Record::Pixel { x, y } => {
                pixels.push(Pixel {
                    at: x.zip(y).map(|(x, y)| [x, y]),
                    rays: vec![],
                });
                latest_lit = None;
                lit_at_depth.clear();
                inside = None;
            }
            Record::Ray {
                kind,
                depth,
                origin,
                direction,
                light,
            } => {
                if pixels.is_empty() {
                    pixels.push(Pixel::default());
                }
                let px = pixels.last_mut().expect("pushed above");
                let kind = kind.unwrap_or_else(|| "primary".into());
                if !["primary", "shadow", "reflection", "refraction"].contains(&kind.as_str()) {
                    return Err(err(format!(
                        "ray kind \"{kind}\": expected primary, shadow, reflection or refraction"
                    )));
                }
                let depth = depth.unwrap_or(0);
                // The parent: the latest non-shadow ray one level up.
                let parent = depth
                    .checked_sub(1)
                    .and_then(|d| lit_at_depth.get(&d).copied());
                if kind != "primary" && parent.is_none() {
                    return Err(err(format!(
                        "a {kind} ray of depth {depth} with no ray of depth {} before it",
                        depth.saturating_sub(1)
                    )));
                }
                inside = None;
                if kind != "shadow" {
                    latest_lit = Some(px.rays.len());
                    lit_at_depth.insert(depth, px.rays.len());
                }
                px.rays.push(Ray {
                    kind,
                    depth,
                    origin,
                    direction,
                    light,
                    parent,
                    line,
                    ..Default::default()
                });
            }
            rec => {
                let Some(px) = pixels.last_mut() else {
                    return Err(err("a record before any ray".into()));
                };
                let depth_of = match &rec {
                    Record::Hit { depth, .. }
                    | Record::Surface { depth, .. }
                    | Record::Shadow { depth, .. }
                    | Record::Color { depth, .. } => *depth,
                    _ => None,
                };
                let owner = match depth_of {
                    Some(d) => lit_at_depth.get(&d).copied(),
                    None if matches!(rec, Record::Shadow { .. }) => latest_lit,
                    None => px.rays.len().checked_sub(1),
                };
                let Some(ray) = owner.and_then(|k| px.rays.get_mut(k)) else {
                    return Err(err("a record before any ray (of that depth)".into()));
                };
                let current = inside.clone();
                let placed = |instance: Option<Option<String>>, object: Option<String>| {
                    let instance = instance.unwrap_or_else(|| current.clone());
                    placed_name(instance.as_deref(), &object.unwrap_or_default())
                };
                match rec {
                    Record::Instance {
                        name,
                        origin,
                        direction,
                    } => {
                        let name = name.unwrap_or_default();
                        ray.instances.push(InstanceRay {
                            name: name.clone(),
                            origin,
                            direction,
                            first_test: ray.tests.len(),
                            line,
                        });
                        inside = Some(name);
                    }
                    Record::Sphere {
                        instance,
                        object,
                        a,
                        b,
                        c,
                        discriminant,
                        t,
                    } => ray.tests.push(Test::Sphere {
                        object: placed(instance, object),
                        abcd: [a, b, c, discriminant],
                        t,
                    }),
                    Record::Plane {
                        instance,
                        object,
                        denominator,
                        t,
                    } => ray.tests.push(Test::Plane {
                        object: placed(instance, object),
                        denominator,
                        t,
                    }),
                    Record::Triangle {
                        instance,
                        object,
                        det,
                        u,
                        v,
                        t,
                    } => ray.tests.push(Test::Triangle {
                        object: placed(instance, object),
                        det_u_v: [det, u, v],
                        t,
                    }),
                    Record::Hit {
                        instance,
                        object,
                        t,
                        point,
                        normal,
                        ..
                    } => {
                        ray.hit = Some(match object {
                            Some(None) => None,
                            object => Some(Hit {
                                object: object
                                    .flatten()
                                    .map(|o| placed_name(instance.as_deref(), &o)),
                                t,
                                point,
                                normal,
                            }),
                        })
                    }
                    Record::Surface {
                        normal,
                        uv,
                        texel,
                        texture,
                        ..
                    } => {
                        ray.surface = Some(Surface {
                            normal,
                            uv,
                            texel,
                            texture,
                        })
                    }
                    Record::Shadow { light, blocked, .. } => {
                        ray.shadows.push((light.unwrap_or_default(), blocked))
                    }
                    Record::Color { rgb, .. } => ray.color = rgb,
                    Record::Format { .. } | Record::Pixel { .. } | Record::Ray { .. } => {}
                }
            }
        }
    }
    Ok(pixels)
}

/// Every number a record holds (to refuse infinities).
fn numbers(rec: &Record) -> Vec<f64> {
    let mut v = vec![];
    let add3 = |a: &Option<[f64; 3]>, v: &mut Vec<f64>| v.extend(a.iter().flatten());
    match rec {
        Record::Ray {
            origin, direction, ..
        }
        | Record::Instance {
            origin, direction, ..
        } => {
            add3(origin, &mut v);
            add3(direction, &mut v);
        }
        Record::Sphere {
            a,
            b,
            c,
            discriminant,
            t,
            ..
        } => v.extend(
            [*a, *b, *c, *discriminant, t.flatten()]
                .into_iter()
                .flatten(),
        ),
        Record::Plane { denominator, t, .. } => {
            v.extend([*denominator, t.flatten()].into_iter().flatten())
        }
        Record::Triangle {
            det, u, v: vv, t, ..
        } => v.extend([*det, *u, *vv, t.flatten()].into_iter().flatten()),
        Record::Hit {
            t, point, normal, ..
        } => {
            v.extend(t.iter());
            add3(point, &mut v);
            add3(normal, &mut v);
        }
        Record::Surface {
            normal,
            uv,
            texture,
            ..
        } => {
            add3(normal, &mut v);
            v.extend(uv.iter().flatten());
            add3(texture, &mut v);
        }
        Record::Color { rgb, .. } => add3(rgb, &mut v),
        _ => {}
    }
    v
}

/// Writes one pixel in the format (the `raystep trace --format student` output).
pub fn write(px: &Pixel) -> String {
    let mut out = vec![Record::Format {
        version: Some(FORMAT_VERSION),
    }];
    if let Some([x, y]) = px.at {
        out.push(Record::Pixel {
            x: Some(x),
            y: Some(y),
        });
    }
    // Depth-first, each ray's colour after its children (with its depth named).
    fn walk(px: &Pixel, i: usize, out: &mut Vec<Record>) {
        let Some(r) = px.rays.get(i) else { return };
        out.push(Record::Ray {
            kind: Some(r.kind.clone()),
            depth: Some(r.depth),
            origin: r.origin,
            direction: r.direction,
            light: r.light.clone(),
        });
        // Each instance's record before its tests; a test names its object as the latest
        // instance record places it (a world object after one says `"instance": null`).
        let mut inside: Option<&str> = None;
        let mut entered = r.instances.iter().peekable();
        for (k, t) in r.tests.iter().enumerate() {
            while let Some(e) = entered.next_if(|e| e.first_test <= k) {
                out.push(instance_record(e));
                inside = Some(&e.name);
            }
            let (instance, object) = match inside.and_then(|i| {
                t.object()
                    .strip_prefix(i)
                    .and_then(|o| o.strip_prefix(INSTANCE_ARROW))
            }) {
                Some(o) => (None, o.to_string()),
                None if inside.is_some() => (Some(None), t.object().to_string()),
                None => (None, t.object().to_string()),
            };
            out.push(match t {
                Test::Sphere { abcd, t, .. } => Record::Sphere {
                    instance,
                    object: Some(object),
                    a: abcd[0],
                    b: abcd[1],
                    c: abcd[2],
                    discriminant: abcd[3],
                    t: *t,
                },
                Test::Plane { denominator, t, .. } => Record::Plane {
                    instance,
                    object: Some(object),
                    denominator: *denominator,
                    t: *t,
                },
                Test::Triangle { det_u_v, t, .. } => Record::Triangle {
                    instance,
                    object: Some(object),
                    det: det_u_v[0],
                    u: det_u_v[1],
                    v: det_u_v[2],
                    t: *t,
                },
            });
        }
        out.extend(entered.map(instance_record));
        if let Some(h) = &r.hit {
            out.push(match h {
                None => Record::Hit {
                    instance: None,
                    object: Some(None),
                    t: None,
                    point: None,
                    normal: None,
                    depth: None,
                },
                Some(h) => {
                    let split = h
                        .object
                        .as_deref()
                        .and_then(|o| o.split_once(INSTANCE_ARROW));
                    Record::Hit {
                        instance: split.map(|(i, _)| i.to_string()),
                        object: Some(split.map_or(h.object.clone(), |(_, o)| Some(o.to_string()))),
                        t: h.t,
                        point: h.point,
                        normal: h.normal,
                        depth: None,
                    }
                }
            });
        }
        if let Some(sf) = &r.surface {
            out.push(Record::Surface {
                normal: sf.normal,
                uv: sf.uv,
                texel: sf.texel,
                texture: sf.texture,
                depth: None,
            });
        }
        for (light, blocked) in &r.shadows {
            out.push(Record::Shadow {
                light: Some(light.clone()),
                blocked: *blocked,
                depth: Some(r.depth),
            });
        }
        for (k, c) in px.rays.iter().enumerate() {
            if c.parent == Some(i) {
                walk(px, k, out);
            }
        }
        if r.color.is_some() {
            // A depth names the latest ray of that depth that is not a shadow ray: a shadow
            // ray's colour (it has no children) follows its own records, without one.
            out.push(Record::Color {
                rgb: r.color,
                depth: (r.kind != "shadow").then_some(r.depth),
            });
        }
    }
    if !px.rays.is_empty() {
        walk(px, 0, &mut out);
    }
    let mut s = String::new();
    for r in out {
        // Serializing these plain records cannot fail; a failure would print nothing for it.
        if let Ok(l) = serde_json::to_string(&r) {
            s += &l;
            s.push('\n');
        }
    }
    s
}

fn instance_record(e: &InstanceRay) -> Record {
    Record::Instance {
        name: Some(e.name.clone()),
        origin: e.origin,
        direction: e.direction,
    }
}
