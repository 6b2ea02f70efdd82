//! Reading a student's version 2 output ([`parse`], every line checked, the line named in
//! each error) and writing a model in the format ([`write`]).

use super::*;

/// Why a version 2 output could not be read.
pub type FormatError = crate::student::format::FormatError;

/// Reads a student's version 2 output: every pixel, in order.
pub fn parse(text: &str) -> Result<Vec<PathPixel>, FormatError> {
    let mut pixels: Vec<PathPixel> = vec![];
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let l = raw.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        let err = |message: String| FormatError { line, message };
        let shown: String = l.chars().take(80).collect();
        let value: serde_json::Value = serde_json::from_str(l).map_err(|e| {
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
        if !KNOWN_TYPES.contains(&ty.as_str()) || ty == "shadow" {
            continue;
        }
        let rec: Record = serde_json::from_value(value.clone()).map_err(|e| {
            err(match bad_field(&value, &ty) {
                Some(key) => format!(
                    "the \"{ty}\" record's \"{key}\" cannot be read ({e}): it must be {}: {shown}",
                    expected_of(&ty, &key)
                ),
                None => format!("a \"{ty}\" record the format cannot read ({e}): {shown}"),
            })
        })?;
        if !finite(&rec) {
            return Err(err("a number is not finite".into()));
        }
        if let Record::Format { version } = rec {
            if let Some(v) = version
                && v != PATH_VERSION
            {
                return Err(err(format!(
                    "format version {v}: a path-traced scene is graded in version {PATH_VERSION} (path records, see lessons/starter/README.md)"
                )));
            }
            continue;
        }
        if let Record::Pixel { x, y } = rec {
            pixels.push(PathPixel {
                at: x.zip(y).map(|(x, y)| [x, y]),
                ..Default::default()
            });
            continue;
        }
        if pixels.is_empty() {
            pixels.push(PathPixel::default());
        }
        let px = pixels.last_mut().expect("pushed above");
        match rec {
            Record::Path { sample } => {
                px.samples.push(PathSample {
                    sample: sample.unwrap_or(px.samples.len() as u32),
                    at: line,
                    ..Default::default()
                });
                continue;
            }
            Record::Color { rgb } => {
                px.color = rgb;
                continue;
            }
            _ => {}
        }
        let Some(path) = px.samples.last_mut() else {
            return Err(err(format!(
                "a \"{ty}\" record before any `path` record: start each sample with {{\"type\":\"path\",\"sample\":K}}"
            )));
        };
        if let Record::Value { rgb } = rec {
            path.value = rgb;
            continue;
        }
        if let Record::Ray {
            depth,
            origin,
            direction,
        } = rec
        {
            let want = path.vertices.len() as u32;
            if let Some(d) = depth
                && d != want
            {
                return Err(err(format!(
                    "a ray of depth {d} where the path's next ray is of depth {want} (the camera ray is 0, each bounce one more)"
                )));
            }
            path.vertices.push(Vertex {
                depth: want,
                origin,
                direction,
                at: line,
                ..Default::default()
            });
            continue;
        }
        let Some(v) = path.vertices.last_mut() else {
            return Err(err(format!(
                "a \"{ty}\" record before the path's first `ray` (the camera ray)"
            )));
        };
        match rec {
            Record::Hit {
                object,
                point,
                normal,
            } => {
                v.hit = Some(match object {
                    Some(None) => None,
                    o => Some(PathHit {
                        object: o.flatten(),
                        point,
                        normal,
                    }),
                })
            }
            Record::Emission {
                radiance,
                mis_weight,
                light_pdf,
                bsdf_pdf,
            } => {
                v.emission = Some(Emission {
                    radiance,
                    mis_weight,
                    light_pdf,
                    bsdf_pdf,
                    at: line,
                })
            }
            Record::LightSample {
                light,
                random,
                point,
                pdf,
                bsdf_pdf,
                mis_weight,
                blocked,
                contribution,
            } => v.lights.push(LightSample {
                light,
                random: random.unwrap_or_default(),
                point,
                pdf,
                bsdf_pdf,
                mis_weight,
                blocked,
                contribution,
                area_pdf: None,
                grazing: false,
                at: line,
            }),
            Record::Sample {
                random,
                direction,
                pdf,
            } => {
                v.sample = Some(BsdfSample {
                    random: random.unwrap_or_default(),
                    direction,
                    pdf,
                    at: line,
                })
            }
            Record::Bounce {
                bsdf,
                cos,
                throughput,
            } => {
                v.bounce = Some(Bounce {
                    bsdf,
                    cos,
                    throughput,
                    at: line,
                })
            }
            Record::Roulette {
                random,
                probability,
                survived,
                throughput,
            } => {
                v.roulette = Some(Roulette {
                    random,
                    probability,
                    survived,
                    throughput,
                    at: line,
                })
            }
            _ => {}
        }
    }
    Ok(pixels)
}

/// Whether every number of a record is finite (JSON cannot say NaN; a huge literal overflows
/// to infinity).
fn finite(r: &Record) -> bool {
    let mut v: Vec<f64> = vec![];
    let add3 = |a: &Option<[f64; 3]>, v: &mut Vec<f64>| v.extend(a.iter().flatten());
    let addd =
        |d: &Option<Vec<Draw>>, v: &mut Vec<f64>| v.extend(d.iter().flatten().map(|d| d.value));
    match r {
        Record::Ray {
            origin, direction, ..
        } => {
            add3(origin, &mut v);
            add3(direction, &mut v);
        }
        Record::Hit { point, normal, .. } => {
            add3(point, &mut v);
            add3(normal, &mut v);
        }
        Record::Emission {
            radiance,
            mis_weight,
            light_pdf,
            bsdf_pdf,
        } => {
            add3(radiance, &mut v);
            v.extend([mis_weight, light_pdf, bsdf_pdf].into_iter().flatten());
        }
        Record::LightSample {
            random,
            point,
            pdf,
            bsdf_pdf,
            mis_weight,
            contribution,
            ..
        } => {
            addd(random, &mut v);
            add3(point, &mut v);
            add3(contribution, &mut v);
            v.extend([pdf, bsdf_pdf, mis_weight].into_iter().flatten());
        }
        Record::Sample {
            random,
            direction,
            pdf,
        } => {
            addd(random, &mut v);
            add3(direction, &mut v);
            v.extend(pdf.iter().flatten());
        }
        Record::Bounce {
            bsdf,
            cos,
            throughput,
        } => {
            add3(bsdf, &mut v);
            add3(throughput, &mut v);
            v.extend(cos.iter());
        }
        Record::Roulette {
            random,
            probability,
            throughput,
            ..
        } => {
            v.extend(random.iter().map(|d| d.value));
            v.extend(probability.iter());
            add3(throughput, &mut v);
        }
        Record::Value { rgb } | Record::Color { rgb } => add3(rgb, &mut v),
        _ => {}
    }
    v.iter().all(|x| x.is_finite())
}

/// Writes a pixel's samples in version 2 (`raystep trace --format student` on a path-traced
/// scene).
pub fn write(px: &PathPixel) -> String {
    let mut out = vec![Record::Format {
        version: Some(PATH_VERSION),
    }];
    if let Some([x, y]) = px.at {
        out.push(Record::Pixel {
            x: Some(x),
            y: Some(y),
        });
    }
    let some = |v: &Vec<Draw>| (!v.is_empty()).then(|| v.clone());
    for s in &px.samples {
        out.push(Record::Path {
            sample: Some(s.sample),
        });
        for v in &s.vertices {
            out.push(Record::Ray {
                depth: Some(v.depth),
                origin: v.origin,
                direction: v.direction,
            });
            if let Some(h) = &v.hit {
                out.push(match h {
                    None => Record::Hit {
                        object: Some(None),
                        point: None,
                        normal: None,
                    },
                    Some(h) => Record::Hit {
                        object: Some(h.object.clone()),
                        point: h.point,
                        normal: h.normal,
                    },
                });
            }
            if let Some(e) = &v.emission {
                out.push(Record::Emission {
                    radiance: e.radiance,
                    mis_weight: e.mis_weight,
                    light_pdf: e.light_pdf,
                    bsdf_pdf: e.bsdf_pdf,
                });
            }
            for l in &v.lights {
                out.push(Record::LightSample {
                    light: l.light.clone(),
                    random: some(&l.random),
                    point: l.point,
                    pdf: l.pdf,
                    bsdf_pdf: l.bsdf_pdf,
                    mis_weight: l.mis_weight,
                    blocked: l.blocked,
                    contribution: l.contribution,
                });
            }
            if let Some(b) = &v.sample {
                out.push(Record::Sample {
                    random: some(&b.random),
                    direction: b.direction,
                    pdf: b.pdf,
                });
            }
            if let Some(b) = &v.bounce {
                out.push(Record::Bounce {
                    bsdf: b.bsdf,
                    cos: b.cos,
                    throughput: b.throughput,
                });
            }
            if let Some(r) = &v.roulette {
                out.push(Record::Roulette {
                    random: r.random,
                    probability: r.probability,
                    survived: r.survived,
                    throughput: r.throughput,
                });
            }
        }
        out.push(Record::Value { rgb: s.value });
    }
    if px.color.is_some() {
        out.push(Record::Color { rgb: px.color });
    }
    let mut s = String::new();
    for r in out {
        if let Ok(l) = serde_json::to_string(&r) {
            s += &l;
            s.push('\n');
        }
    }
    s
}

/// The first field of a record that cannot be read on its own (the record with that field
/// alone fails).
fn bad_field(value: &serde_json::Value, ty: &str) -> Option<String> {
    let obj = value.as_object()?;
    obj.iter()
        .filter(|(k, _)| *k != "type")
        .find(|(k, v)| {
            let one = serde_json::json!({ "type": ty, k.as_str(): v });
            serde_json::from_value::<Record>(one).is_err()
        })
        .map(|(k, _)| k.clone())
}

/// What a record's field must be, in words (lessons/starter/README.md's table).
fn expected_of(ty: &str, key: &str) -> &'static str {
    match (ty, key) {
        ("roulette", "random") => {
            "one {\"dimension\": D, \"value\": u} object (a roulette draws one number: not a list)"
        }
        (_, "random") => "a list of {\"dimension\": D, \"value\": u} objects",
        (_, "version" | "x" | "y" | "sample" | "depth") => "a whole number, 0 or more",
        ("hit", "object") => "the object's name (a string), or null when the ray escapes",
        (_, "light" | "object") => "a name from the scene file (a string)",
        (
            _,
            "origin" | "direction" | "point" | "normal" | "radiance" | "contribution" | "bsdf"
            | "throughput" | "rgb",
        ) => "[x, y, z]: a list of three numbers",
        ("sample", "pdf") => "a number, or null for a mirror's (delta) direction",
        (_, "blocked" | "survived") => "true or false",
        _ => "a number",
    }
}
