//! Bad sheets and bad input: a non-zero exit and a message with the file, line and column.

use super::*;

#[test]
fn bad_input_exits_non_zero_with_a_located_message() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let write = |name: &str, text: &str| {
        let p = d.join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let ex = |p: &Path| {
        vec![
            "exercise".as_ref(),
            p.as_os_str().to_owned().leak() as &std::ffi::OsStr,
            "--student".as_ref(),
            "s".as_ref(),
        ]
    };
    // TOML syntax.
    let p = write("syntax.toml", "[[question]]\nid = \"a\"\ntext = \"oops\n");
    fails(&ex(&p), &["syntax.toml:3:"]);
    // A missing scene file, located at the `scene` key.
    let p = write(
        "missing.toml",
        "[[question]]\nid = \"a\"\ntext = \"t\"\nscene = \"nowhere.toml\"\npixel = [0, 0]\nquantity = \"closest_t\"\n",
    );
    fails(
        &ex(&p),
        &[
            "missing.toml:4:9",
            "question \"a\" → scene",
            "does not exist",
        ],
    );
    // An unknown quantity.
    let p = write(
        "quantity.toml",
        "[[question]]\nid = \"a\"\ntext = \"t\"\nscene = \"../x\"\npixel = [0, 0]\nquantity = \"colour\"\n",
    );
    fails(
        &ex(&p),
        &["quantity.toml:6:12", "quantity", "unknown variant `colour`"],
    );
    // A scene that does not load (checked when the sheet is loaded): the sheet, the question's
    // header and the scene's error.
    let p = write(
        "scene.toml",
        "[[question]]\nid = \"a\"\ntext = \"t\"\nscene_toml = \"\"\"\n[[sphere]]\nradius = {r}\n\"\"\"\npixel = [0, 0]\nquantity = \"closest_t\"\nparams = { r = [-2, -1] }\n",
    );
    fails(
        &ex(&p),
        &["scene.toml:1:1: question \"a\" → scene_toml", "radius"],
    );
    // A pixel outside the image.
    let p = write(
        "pixel.toml",
        "[[question]]\nid = \"a\"\ntext = \"t\"\nscene_toml = \"\"\npixel = [400, 0]\nquantity = \"closest_t\"\n",
    );
    fails(&ex(&p), &["pixel 400,0 is outside the 320×240 image"]);
    // A question that needs an object.
    let p = write(
        "object.toml",
        "[[question]]\nid = \"a\"\ntext = \"t\"\nscene_toml = \"\"\npixel = [0, 0]\nquantity = \"discriminant\"\n",
    );
    fails(&ex(&p), &["object.toml:6:12", "needs `object"]);
    // A malformed class CSV names the row and column.
    let sheet = root().join("lessons/exercises/02-sphere.toml");
    let out = d.join("g.csv");
    let csv = write("bad.csv", "student,disc\nann,1\nben,\"2\n");
    fails(
        &[
            "grade".as_ref(),
            sheet.as_os_str(),
            csv.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ],
        &["bad.csv: row 3, column 2", "never closed"],
    );
    // (A column that is no question is ignored and listed: tests/it/class_path.rs.) A header with
    // no student column is an error naming the header.
    let csv = write("cols.csv", "name,disc\n");
    fails(
        &[
            "grade".as_ref(),
            sheet.as_os_str(),
            csv.as_os_str(),
            "-o".as_ref(),
            out.as_os_str(),
        ],
        &[
            "cols.csv: row 1: no column holds the student's id",
            "\"name\", \"disc\"",
        ],
    );
    assert!(!out.exists(), "no grades file on bad input");
    // An answers file with a line that isn't `id = value`.
    let ans = write("answers.txt", "disc = 1\nnear 2\n");
    fails(
        &[
            "check".as_ref(),
            sheet.as_os_str(),
            "--student".as_ref(),
            "s".as_ref(),
            "--answers".as_ref(),
            ans.as_os_str(),
        ],
        &["answers.txt:2:"],
    );
}

#[test]
fn a_sheet_naming_an_object_or_light_its_scene_lacks_is_refused_with_its_place() {
    // The object: line 13, column 10 is where "bal" starts (after `object = `).
    let text = small_sheet("", "quantity = \"discriminant\"\nobject = \"bal\"");
    let e = lesson::parse_exercise_sheet(&text, "s.toml", None, "s").unwrap_err();
    let msg = e.to_string();
    assert_eq!((e.line, e.column), (Some(13), Some(10)), "{msg}");
    assert!(
        msg.contains("object") && msg.contains("\"bal\"") && msg.contains("ball"),
        "{msg}"
    );
    // The light: the scene has one light (index 0), the question asks for light 1.
    let text = small_sheet("", "quantity = \"shadow_blocked\"\nlight = 1");
    let e = lesson::parse_exercise_sheet(&text, "s.toml", None, "s").unwrap_err();
    let msg = e.to_string();
    assert_eq!((e.line, e.column), (Some(13), Some(9)), "{msg}");
    assert!(msg.contains("1 light") && msg.contains("light 1"), "{msg}");
    // The same sheet with names the scene has loads.
    let ok = small_sheet("", "quantity = \"discriminant\"\nobject = \"ball\"");
    assert!(lesson::parse_exercise_sheet(&ok, "s.toml", None, "s").is_ok());
}

#[test]
fn error_columns_count_characters_not_bytes() {
    // Multi-byte characters (Δ, –) before the error: the column counts characters. Where the
    // error is comes from the TOML parser itself (a byte offset); the column is converted.
    let char_col = |text: &str| {
        let at = toml::from_str::<toml::Table>(text)
            .unwrap_err()
            .span()
            .expect("a located TOML error")
            .start;
        (at + 1, text[..at].chars().count() + 1)
    };
    let text = "title = \"Δ–Δ\"; x = 7\n";
    let (byte_col, want) = char_col(text);
    assert_ne!(
        byte_col, want,
        "the test needs multi-byte characters before the error"
    );
    let e = lesson::parse_exercise_sheet(text, "s.toml", None, "s").unwrap_err();
    assert_eq!((e.line, e.column), (Some(1), Some(want)), "{e}");
    // A lesson's front matter (its line 1 is the file's line 2).
    let fm = "title = \"Δ–Δ\"; scene = 3\n";
    let (_, want) = char_col(fm);
    let l = format!("+++\n{fm}+++\n");
    let e = lesson::parse_lesson(&l, Path::new("l.md")).unwrap_err();
    assert!(e.starts_with(&format!("l.md:2:{want}:")), "{e}");
}
