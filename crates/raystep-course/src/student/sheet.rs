//! Tracer grading sheets (`raystep grade-tracer --sheet`, TOML): the scenes, pixels, stages
//! and limits a class's tracers are checked on, read with every error located.

use super::*;

/// A tracer grading sheet (`raystep grade-tracer --sheet`, TOML): which scenes and pixels a
/// student's own tracer is checked on, up to which stage, with what limits. Not to be confused
/// with [`crate::lesson::ExerciseSheet`], questions whose answers a student types.
///
/// ```toml
/// title = "Checkpoint 2: spheres and planes"
/// upto = "closest-hit"          # camera, sphere, plane-triangle, closest-hit, surface, shadows, secondary, color
/// timeout_s = 10                # per run
/// [[scene]]
/// file = "../scenes/three-spheres.toml"   # relative to the sheet
/// pixels = [[160, 120], [40, 200]]
/// random_pixels = 2             # plus this many drawn per student (from the student id)
/// ```
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TracerSheet {
    /// A title for reports.
    #[serde(default)]
    pub title: String,
    /// Salts the per-student pixels (default: the sheet's file stem).
    #[serde(default)]
    pub id: Option<String>,
    /// The last stage checked.
    #[serde(default = "all_stages")]
    pub upto: Stage,
    /// Seconds per run.
    #[serde(default)]
    pub timeout_s: Option<f64>,
    /// Tolerances.
    #[serde(default)]
    pub tolerance: Option<TracerTolerances>,
    /// The scenes.
    pub scene: Vec<TracerSheetScene>,
}

fn all_stages() -> Stage {
    Stage::Color
}

/// One scene of a [`TracerSheet`].
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TracerSheetScene {
    /// The scene file, relative to the sheet.
    pub file: PathBuf,
    /// Pixels every student gets.
    #[serde(default)]
    pub pixels: Vec<[u32; 2]>,
    /// Pixels drawn per student.
    #[serde(default)]
    pub random_pixels: u32,
    /// Scene values drawn per student (each student grades on their own variant of the scene).
    #[serde(default)]
    pub vary: Vec<Vary>,
    /// The last stage checked on this scene (default: the sheet's `upto`); a path-traced
    /// scene's stages are `random` … `estimate`.
    #[serde(default)]
    pub upto: Option<Stage>,
}

/// One value of a scene drawn per student: key `key` (element `index` of a vector) of the object,
/// light or material named `object`, uniformly in `range`, rounded to `decimals` places.
///
/// ```toml
/// [[scene.vary]]
/// object = "middle"
/// key = "radius"
/// range = [0.8, 1.2]
/// ```
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Vary {
    /// The `name` of a `[[sphere]]`, `[[plane]]`, `[[triangle]]`, `[[mesh]]`, `[[light]]` or
    /// `[[material]]` of the scene file.
    pub object: String,
    /// The key to set (a number, or a vector with `index`).
    pub key: String,
    /// Which element of a vector key (0 = x).
    #[serde(default)]
    pub index: Option<usize>,
    /// The interval the value is drawn from.
    pub range: [f64; 2],
    /// Decimal places (default 2).
    #[serde(default = "two")]
    pub decimals: u32,
}

fn two() -> u32 {
    2
}

/// The scene file's text with `vary`'s values for `student` set in it (by `toml_edit`, so the
/// file keeps its comments and layout) and mesh files made absolute, so the variant can live in
/// another folder; and a line saying what was drawn.
pub fn variant_text(
    text: &str,
    scene_dir: &Path,
    vary: &[Vary],
    id: &str,
    file: &str,
    student: &str,
) -> Result<(String, String), String> {
    let mut doc: toml_edit::DocumentMut = text.parse().map_err(|e| format!("{e}"))?;
    let mut drawn = vec![];
    for v in vary {
        let [lo, hi] = v.range;
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return Err(format!(
                "vary {}.{}: range must be two finite numbers, low first",
                v.object, v.key
            ));
        }
        let what = format!(
            "{}.{}{}",
            v.object,
            v.key,
            v.index.map_or(String::new(), |i| format!("[{i}]"))
        );
        let u = crate::variant::uniform(crate::variant::draw(id, file, student, &what));
        let scale = 10f64.powi(v.decimals.min(9) as i32);
        let x = ((lo + u * (hi - lo)) * scale).round() / scale;
        if v.key == "name" {
            return Err(format!(
                "vary {what}: `name` names the object and cannot vary: give a number's key (radius, center, color, …)"
            ));
        }
        let mut found = false;
        for kind in ["sphere", "plane", "triangle", "mesh", "light", "material"] {
            let Some(tables) = doc.get_mut(kind).and_then(|t| t.as_array_of_tables_mut()) else {
                continue;
            };
            for t in tables.iter_mut() {
                if t.get("name").and_then(|n| n.as_str()) != Some(v.object.as_str()) {
                    continue;
                }
                found = true;
                let current = t.get(v.key.as_str());
                let numeric =
                    |i: &toml_edit::Item| i.as_integer().is_some() || i.as_float().is_some();
                match v.index {
                    None => {
                        // A key the scene leaves out takes its default: setting a number is fine;
                        // a key that holds text or a vector is not a number to vary.
                        if current.is_some_and(|c| !numeric(c)) {
                            return Err(format!(
                                "vary {what}: \"{}\" has {} = {}, not a number (a vector's element needs `index`)",
                                v.object,
                                v.key,
                                current.map_or(String::new(), |c| c.to_string().trim().to_string())
                            ));
                        }
                        t[v.key.as_str()] = toml_edit::value(x);
                    }
                    Some(i) => {
                        let arr = t
                            .get_mut(v.key.as_str())
                            .and_then(|k| k.as_array_mut())
                            .filter(|a| {
                                a.get(i)
                                    .is_some_and(|e| e.as_integer().is_some() || e.as_float().is_some())
                            })
                            .ok_or_else(|| {
                                format!(
                                    "vary {what}: \"{}\" has no vector {} with a number at element {i}",
                                    v.object, v.key
                                )
                            })?;
                        arr.replace(i, x);
                    }
                }
            }
        }
        if !found {
            return Err(format!(
                "vary {what}: the scene has no object, light or material named \"{}\"",
                v.object
            ));
        }
        drawn.push(format!("{what} = {x}"));
    }
    // Mesh files, relative to the original scene, made absolute.
    if let Some(meshes) = doc.get_mut("mesh").and_then(|t| t.as_array_of_tables_mut()) {
        for m in meshes.iter_mut() {
            if let Some(obj) = m.get("obj").and_then(|o| o.as_str()).map(str::to_string) {
                let abs = scene_dir.join(obj);
                m["obj"] = toml_edit::value(abs.display().to_string());
            }
        }
    }
    Ok((doc.to_string(), drawn.join(", ")))
}

/// Reads a [`TracerSheet`]; errors name the file, line and column.
pub fn load_tracer_sheet(path: &Path) -> Result<TracerSheet, String> {
    let text = crate::io::read_text(path, crate::io::limits::SHEET, "grading sheet")
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    // A byte-order mark (some editors write one) is not part of the TOML.
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    parse_tracer_sheet(text, path)
}

/// Reads a sheet's `text` and checks its values (as [`load_tracer_sheet`] does); errors name `path`,
/// the line and the column.
pub fn parse_tracer_sheet(text: &str, path: &Path) -> Result<TracerSheet, String> {
    let sheet: TracerSheet = toml::from_str(text).map_err(|e| {
        let (line, col) = e
            .span()
            .map(|s| crate::text::line_col(text, s.start))
            .unwrap_or((0, 0));
        format!("{}:{line}:{col}: {}", path.display(), e.message())
    })?;
    if sheet.scene.is_empty() {
        return Err(format!("{}: the sheet lists no [[scene]]", path.display()));
    }
    for (k, sc) in sheet.scene.iter().enumerate() {
        let at = format!(
            "{}: scene {} ({})",
            path.display(),
            k + 1,
            sc.file.display()
        );
        if sc.random_pixels > MAX_RANDOM_PIXELS {
            return Err(format!(
                "{at}: random_pixels = {}: at most {MAX_RANDOM_PIXELS} pixels are drawn per student",
                sc.random_pixels
            ));
        }
        if sc.pixels.is_empty() && sc.random_pixels == 0 {
            return Err(format!(
                "{at}: no pixels to grade: give `pixels = [[x, y], …]` or `random_pixels = N`"
            ));
        }
    }
    if sheet
        .timeout_s
        .is_some_and(|t| !(t.is_finite() && t > 0.0 && t <= 3600.0))
    {
        return Err(format!(
            "{}: timeout_s must be a number of seconds in (0, 3600]",
            path.display()
        ));
    }
    if let Some(t) = &sheet.tolerance
        && ![t.rel, t.abs, t.color, t.offset]
            .iter()
            .all(|x| x.is_finite() && *x >= 0.0)
    {
        return Err(format!(
            "{}: tolerance values must be finite and not negative",
            path.display()
        ));
    }
    Ok(sheet)
}
