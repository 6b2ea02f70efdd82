//! Every question states what its scene sets differently from the defaults (the premise
//! checker, and a planted unstated field of view it must find).

use super::*;

/// A number as a sheet would write it: integers without a decimal point.
fn fmt_num(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{}", x as i64)
    } else {
        format!("{x}")
    }
}

fn toml_num(v: &toml::Value) -> Option<f64> {
    v.as_float().or_else(|| v.as_integer().map(|i| i as f64))
}

fn toml_vec(v: &toml::Value) -> Option<Vec<f64>> {
    v.as_array()?.iter().map(toml_num).collect()
}

/// The text as the checks read it: Unicode minus signs as `-`, no whitespace, lower case.
fn squash(s: &str) -> String {
    s.replace('−', "-")
        .chars()
        .filter(|c| !c.is_whitespace())
        .flat_map(char::to_lowercase)
        .collect()
}

/// Whether `text` (squashed) has the number `x` as a whole token (not part of a longer number).
fn has_number(text: &str, x: f64) -> bool {
    let n = fmt_num(x);
    let bytes = text.as_bytes();
    text.match_indices(&n).any(|(i, _)| {
        let before = i.checked_sub(1).map(|j| bytes[j]);
        let after = bytes.get(i + n.len()).copied();
        let after2 = bytes.get(i + n.len() + 1).copied();
        let digit = |c: Option<u8>| c.is_some_and(|c| c.is_ascii_digit());
        // "-5" must not match inside "-0.5" (a leading minus is part of `n` when negative), nor
        // "2" inside "2.5"; a full stop ending the sentence is fine.
        let glued_before =
            digit(before) || before == Some(b'.') || (x >= 0.0 && before == Some(b'-'));
        let glued_after = digit(after) || (after == Some(b'.') && digit(after2));
        !glued_before && !glued_after
    })
}

/// Whether `text` (squashed) writes the vector `v` as `(a,b,c)` or `[a,b,c]`.
fn has_vector(text: &str, v: &[f64]) -> bool {
    let inner: Vec<String> = v.iter().map(|x| fmt_num(*x)).collect();
    let inner = inner.join(",");
    text.contains(&format!("({inner})")) || text.contains(&format!("[{inner}]"))
}

/// The shipped scene file the text names (`three-spheres.toml`), parsed: a parameter equal to
/// that file's counts as stated (the student can read it there).
fn named_scene(text: &str) -> Option<toml::Table> {
    let dir = root().join("scenes");
    let mut names: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    names.sort();
    let p = names
        .into_iter()
        .find(|p| text.contains(&*p.file_name().unwrap().to_string_lossy()))?;
    Some(toml::from_str(&std::fs::read_to_string(p).unwrap()).unwrap())
}

/// The value of `key` in the table of `kind` (`camera`, or the `[[kind]]` named `name`) of a
/// named shipped scene.
fn in_named(
    named: Option<&toml::Table>,
    kind: &str,
    name: Option<&str>,
    key: &str,
) -> Option<toml::Value> {
    let named = named?;
    if kind == "camera" {
        return named.get("camera")?.get(key).cloned();
    }
    named
        .get(kind)?
        .as_array()?
        .iter()
        .find(|o| o.get("name").and_then(|n| n.as_str()) == name)?
        .get(key)
        .cloned()
}

/// The scene parameters a question's text must state (those that differ from the scene format's
/// documented defaults, for the camera and the objects the question relies on), each checked in
/// the variant's text — or in the shipped scene file the text names, when the value is that
/// file's. Returns what is missing.
fn unstated(q: &Question, text: &str, scene_toml: &str) -> Vec<String> {
    let t = squash(text);
    let named = named_scene(text);
    let named = named.as_ref();
    let same = |kind: &str, name: Option<&str>, key: &str, v: &toml::Value| {
        in_named(named, kind, name, key).is_some_and(|n| {
            n == *v
                || (toml_vec(&n).is_some() && toml_vec(&n) == toml_vec(v))
                || (toml_num(&n).is_some() && toml_num(&n) == toml_num(v))
        })
    };
    let mut missing = vec![];
    let scene: toml::Table = toml::from_str(scene_toml).expect("the variant's scene is TOML");
    // The camera (defaults from book/scenes.md, "The scene format").
    let cam = scene.get("camera").and_then(|c| c.as_table());
    let get = |k: &str| cam.and_then(|c| c.get(k));
    for (k, default) in [
        ("from", [0.0, 0.0, -5.0]),
        ("at", [0.0, 0.0, 0.0]),
        ("up", [0.0, 1.0, 0.0]),
    ] {
        if let Some(raw) = get(k)
            && let Some(v) = toml_vec(raw)
            && v != default
            && !has_vector(&t, &v)
            && !same("camera", None, k, raw)
        {
            missing.push(format!("camera.{k} = {v:?}"));
        }
    }
    if let Some(fov) = get("fov").and_then(toml_num)
        && fov != 60.0
        && !same("camera", None, "fov", get("fov").unwrap())
    {
        let n = fmt_num(fov);
        let said = [
            format!("{n}°"),
            format!("fov{n}"),
            format!("fov={n}"),
            format!("fovof{n}"),
            format!("fieldofview{n}"),
            format!("fieldofviewof{n}"),
            format!("fieldofviewis{n}"),
        ];
        if !said.iter().any(|s| t.contains(s)) {
            missing.push(format!("camera.fov = {n}"));
        }
    }
    let w = get("width").and_then(toml_num).unwrap_or(320.0);
    let h = get("height").and_then(toml_num).unwrap_or(240.0);
    let named_size = get("width").is_none_or(|v| same("camera", None, "width", v))
        && get("height").is_none_or(|v| same("camera", None, "height", v))
        && named.is_some();
    if (w, h) != (320.0, 240.0) && !named_size {
        let (w, h) = (fmt_num(w), fmt_num(h));
        if ![format!("{w}×{h}"), format!("{w}x{h}")]
            .iter()
            .any(|s| t.contains(s))
        {
            missing.push(format!("camera width × height = {w} × {h}"));
        }
    }
    // The objects: the one named by `object`, else every object (which one is hit, where, and
    // what blocks a shadow ray depend on all of them).
    let relied = |name: Option<&str>| match (&q.object, name) {
        (Some(o), Some(n)) => o == n,
        (Some(_), None) => false,
        (None, _) => true,
    };
    let tables = |key: &str| -> Vec<toml::Table> {
        scene
            .get(key)
            .and_then(|v| v.as_array())
            .map(|a| a.iter().filter_map(|t| t.as_table().cloned()).collect())
            .unwrap_or_default()
    };
    for s in tables("sphere") {
        let name = s.get("name").and_then(|n| n.as_str());
        if !relied(name) {
            continue;
        }
        let label = name.unwrap_or("sphere");
        if let Some(c) = s.get("center").and_then(toml_vec)
            && c != [0.0, 0.0, 0.0]
            && !has_vector(&t, &c)
            && !same("sphere", name, "center", &s["center"])
        {
            missing.push(format!("{label}.center = {c:?}"));
        }
        if let Some(r) = s.get("radius").and_then(toml_num)
            && r != 1.0
            && !has_number(&t, r)
            && !same("sphere", name, "radius", &s["radius"])
        {
            missing.push(format!("{label}.radius = {r}"));
        }
    }
    for p in tables("plane") {
        let name = p.get("name").and_then(|n| n.as_str());
        if !relied(name) {
            continue;
        }
        let label = name.unwrap_or("plane");
        if let Some(axis) = p.get("axis").and_then(|a| a.as_str()) {
            let off = p.get("offset").and_then(toml_num).unwrap_or(0.0);
            let stated = p
                .get("offset")
                .is_some_and(|o| same("plane", name, "offset", o));
            if !t.contains(&format!("{axis}={}", fmt_num(off))) && !stated {
                missing.push(format!("{label}: the plane {axis} = {}", fmt_num(off)));
            }
        } else {
            for (k, default) in [("point", [0.0, 0.0, 0.0]), ("normal", [0.0, 1.0, 0.0])] {
                if let Some(v) = p.get(k).and_then(toml_vec)
                    && v != default
                    && !has_vector(&t, &v)
                {
                    missing.push(format!("{label}.{k} = {v:?}"));
                }
            }
        }
    }
    for tri in tables("triangle") {
        let name = tri.get("name").and_then(|n| n.as_str());
        if !relied(name) {
            continue;
        }
        let label = name.unwrap_or("triangle");
        if let Some(vs) = tri.get("vertices").and_then(|v| v.as_array()) {
            for v in vs.iter().filter_map(toml_vec) {
                if !has_vector(&t, &v) {
                    missing.push(format!("{label}: vertex {v:?}"));
                }
            }
        }
    }
    if q.quantity == lesson::Quantity::ShadowBlocked {
        let lights = tables("light");
        if let Some(l) = lights.get(q.light as usize)
            && let Some(p) = l.get("position").and_then(toml_vec)
            && !has_vector(&t, &p)
            && !named
                .and_then(|n| {
                    n.get("light")?
                        .as_array()?
                        .get(q.light as usize)?
                        .get("position")
                })
                .is_some_and(|np| toml_vec(np).as_deref() == Some(&p[..]))
        {
            missing.push(format!("light {}: position {p:?}", q.light));
        }
    }
    if matches!(
        q.quantity,
        lesson::Quantity::RefractedDirection | lesson::Quantity::TotalInternalReflection
    ) {
        for m in tables("material") {
            if let Some(n) = m.get("refractive_index").and_then(toml_num)
                && n != 1.0
                && !has_number(&t, n)
            {
                missing.push(format!("refractive_index = {n}"));
            }
        }
    }
    missing
}

#[test]
fn every_question_states_what_differs_from_the_defaults() {
    let mut problems = vec![];
    for path in sheets() {
        let sheet = lesson::load_exercise_sheet(&path).unwrap();
        for q in &sheet.questions {
            for student in STUDENTS {
                let v = sheet.variant(q, student);
                let missing = match (&q.scene, &v.scene_toml) {
                    (SceneSource::Inline(_), Some(scene)) => unstated(q, &v.text, scene),
                    // A shipped scene file: the text must name it (the file states the rest).
                    (SceneSource::File(p), _) => {
                        let name = p.file_name().unwrap().to_string_lossy().into_owned();
                        if v.text.contains(&name) {
                            vec![]
                        } else {
                            vec![format!("the scene file's name {name}")]
                        }
                    }
                    (SceneSource::Inline(_), None) => unreachable!("inline scenes are filled"),
                };
                if !missing.is_empty() {
                    problems.push(format!(
                        "{} question \"{}\" (student {student}): the text does not state {}",
                        path.file_name().unwrap().to_string_lossy(),
                        q.id,
                        missing.join("; ")
                    ));
                    break;
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_checker_finds_an_unstated_field_of_view() {
    // The check itself, on the case that was wrong: fov 45 not in the text.
    let sheet = lesson::parse_exercise_sheet(
        "[[question]]\nid = \"q\"\ntext = \"Camera at (0, 0, -5), 64 × 48 pixels, ball of radius 2.\"\n\
         scene_toml = \"\"\"\n[camera]\nfov = 45\nwidth = 64\nheight = 48\n[[sphere]]\nname = \"ball\"\nradius = 2\n\"\"\"\n\
         pixel = [1, 1]\nquantity = \"discriminant\"\nobject = \"ball\"\n",
        "t.toml",
        None,
        "t",
    )
    .unwrap();
    let q = &sheet.questions[0];
    let v = sheet.variant(q, "s");
    let missing = unstated(q, &v.text, v.scene_toml.as_ref().unwrap());
    assert_eq!(missing, ["camera.fov = 45"]);
    let fixed = v.text.replace("Camera", "Camera (field of view 45°)");
    assert!(unstated(q, &fixed, v.scene_toml.as_ref().unwrap()).is_empty());
}
