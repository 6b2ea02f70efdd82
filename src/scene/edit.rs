//! Editing a scene file: moving objects, changing a sphere's radius, a material or a light, with
//! undo and redo, and saving the file back with the user's comments and layout kept.
//!
//! The TOML document is the source of truth. Every [`Edit`] changes the document (through
//! `toml_edit`, so only the touched values change: untouched lines keep every byte, an edited
//! value keeps the comment after it), and the edited [`Scene`] is what the loader
//! ([`load_str`]) makes of the document's text. So a saved file always loads to the scene the
//! user saw, and an edit the loader rejects (a negative radius, a reflectance above 1) is refused
//! with the loader's own message, leaving the document as it was.
//!
//! ```
//! use raystep::scene::edit::{Edit, SceneDoc};
//!
//! let text = "[[sphere]]\nname = \"ball\"\ncenter = [0, 1, 0]  # the ball\n";
//! let mut doc = SceneDoc::parse(text, "ball.toml", None).unwrap();
//! let scene = doc.apply(&Edit::Move { group: 0, by: [1.0, 0.0, 0.5] }).unwrap();
//! assert_eq!(doc.text(), "[[sphere]]\nname = \"ball\"\ncenter = [1, 1, 0.5]  # the ball\n");
//! assert_eq!(scene.groups[0].name, "ball");
//! doc.undo();
//! assert_eq!(doc.text(), text);
//! ```

use super::{Scene, SceneError, load_str};
use std::collections::{HashMap, VecDeque};
use std::path::{Path, PathBuf};
use toml_edit::{Array, ArrayOfTables, DocumentMut, InlineTable, Item, Table, TableLike, Value};

/// The kind of an object entry of a scene file (`[[sphere]]`, `[[plane]]`, `[[triangle]]`,
/// `[[mesh]]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EntryKind {
    /// `[[sphere]]`.
    Sphere,
    /// `[[plane]]`.
    Plane,
    /// `[[triangle]]`.
    Triangle,
    /// `[[mesh]]`.
    Mesh,
}

impl EntryKind {
    /// Every kind, in the order the scene format lists them.
    pub const ALL: [EntryKind; 4] = [
        EntryKind::Sphere,
        EntryKind::Plane,
        EntryKind::Triangle,
        EntryKind::Mesh,
    ];

    /// The kind's key in the file (`"sphere"`, …), which is also the first word of the name the
    /// loader gives an unnamed entry (`sphere 3`).
    pub fn key(self) -> &'static str {
        match self {
            EntryKind::Sphere => "sphere",
            EntryKind::Plane => "plane",
            EntryKind::Triangle => "triangle",
            EntryKind::Mesh => "mesh",
        }
    }
}

/// Which entry of the file a group of the loaded scene came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct EntryRef {
    /// The entry's kind.
    pub kind: EntryKind,
    /// Its index within its `[[kind]]` array (0-based, as in the loader's names `sphere 3`).
    pub index: usize,
}

/// One change a user makes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Edit {
    /// Moves object group `group` (an index into [`Scene::groups`]) by `by` (world units): a
    /// sphere's `center`, a triangle's three `vertices`, a mesh's `translate`, a plane's `point`
    /// (an `axis` plane: `offset` += `by[axis]`). Each changed coordinate is rounded to 6
    /// decimals (more if the file wrote it with more), so repeated drags write `0.3`, not
    /// `0.30000000000000004`; a component of `by` that is 0 leaves its coordinate as written.
    Move {
        /// The group.
        group: u32,
        /// The displacement.
        by: [f64; 3],
    },
    /// Sets a sphere's radius (a positive, finite number).
    SetRadius {
        /// The group (a sphere).
        group: u32,
        /// The new radius.
        radius: f64,
    },
    /// Sets one field of the material group `group` uses. A material shared by several
    /// objects changes for all of them ([`SceneDoc::material_users`] says how many); an object
    /// with no `material` key gets a `[[material]]` of its own (the defaults plus this field).
    SetMaterial {
        /// The group.
        group: u32,
        /// The field.
        field: MaterialField,
        /// Its new value ([`MaterialValue::Color`] for [`MaterialField::Color`], a number for
        /// the others).
        value: MaterialValue,
    },
    /// Moves a light or sets its colour: `light` is an index into [`Scene::lights`] (the file's
    /// `[[light]]` entries, in order).
    SetLight {
        /// The light.
        light: u32,
        /// Which field.
        field: LightField,
        /// The new position or colour.
        value: [f64; 3],
    },
}

/// A field of a `[[material]]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MaterialField {
    /// `color`: linear RGB, each component ≥ 0.
    Color,
    /// `ambient` (≥ 0).
    Ambient,
    /// `diffuse` (≥ 0).
    Diffuse,
    /// `specular` (≥ 0).
    Specular,
    /// `shininess` (> 0).
    Shininess,
    /// `reflective`, in [0, 1].
    Reflective,
    /// `transparency`, in [0, 1].
    Transparency,
    /// `refractive_index` (> 0).
    RefractiveIndex,
}

impl MaterialField {
    /// The field's key in the file.
    pub fn key(self) -> &'static str {
        match self {
            MaterialField::Color => "color",
            MaterialField::Ambient => "ambient",
            MaterialField::Diffuse => "diffuse",
            MaterialField::Specular => "specular",
            MaterialField::Shininess => "shininess",
            MaterialField::Reflective => "reflective",
            MaterialField::Transparency => "transparency",
            MaterialField::RefractiveIndex => "refractive_index",
        }
    }
}

/// The new value of a material field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MaterialValue {
    /// A coefficient, exponent or index.
    Number(f64),
    /// A colour (linear RGB).
    Color([f64; 3]),
}

/// A field of a `[[light]]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LightField {
    /// `position`.
    Position,
    /// `color` (intensity, linear RGB).
    Color,
}

impl LightField {
    /// The field's key in the file.
    pub fn key(self) -> &'static str {
        match self {
            LightField::Position => "position",
            LightField::Color => "color",
        }
    }
}

/// The most bytes of text the undo history keeps; the oldest steps are dropped beyond it (the
/// last step is always kept).
const MAX_HISTORY_BYTES: usize = 256 << 20;

/// A scene's TOML document being edited, with undo and redo.
///
/// The text is the state: undo and redo restore it byte for byte. Edits keep the file's
/// line endings (LF or CRLF), a byte-order mark and a missing final newline.
#[derive(Debug, Clone)]
pub struct SceneDoc {
    /// The document, as `toml_edit` holds it.
    doc: DocumentMut,
    /// Its text now (the document rendered with `style`).
    text: String,
    /// The file name for messages.
    file: String,
    /// Where OBJ paths start from.
    base: Option<PathBuf>,
    style: Style,
    /// Texts before each undoable step, oldest first.
    undo: VecDeque<String>,
    /// Their total length.
    undo_bytes: usize,
    /// Texts undone, most recent last.
    redo: Vec<String>,
    /// The text when the gesture in progress began.
    gesture: Option<String>,
    /// The text last saved or opened.
    saved: String,
}

/// What `toml_edit` normalises away and the file had.
#[derive(Debug, Clone, Copy)]
struct Style {
    bom: bool,
    crlf: bool,
    final_newline: bool,
}

impl Style {
    fn of(text: &str) -> Style {
        let body = text.strip_prefix('\u{feff}').unwrap_or(text);
        let lf = body.matches('\n').count();
        Style {
            bom: body.len() != text.len(),
            crlf: lf > 0 && body.matches("\r\n").count() == lf,
            final_newline: body.is_empty() || body.ends_with('\n'),
        }
    }

    fn render(self, doc: &DocumentMut) -> String {
        let mut s = doc.to_string();
        if self.crlf {
            s = s.replace("\r\n", "\n").replace('\n', "\r\n");
        }
        if !self.final_newline {
            if s.ends_with("\r\n") {
                s.truncate(s.len() - 2);
            } else if s.ends_with('\n') {
                s.truncate(s.len() - 1);
            }
        }
        if self.bom {
            s.insert(0, '\u{feff}');
        }
        s
    }
}

impl SceneDoc {
    /// Parses `text` (the file's contents). `file` names it in errors, `base` is the folder OBJ
    /// paths start from (as for [`load_str`]). Only the TOML syntax is checked here;
    /// [`SceneDoc::scene`] loads the scene.
    pub fn parse(text: &str, file: &str, base: Option<&Path>) -> Result<SceneDoc, String> {
        let doc: DocumentMut = text.parse().map_err(|e| format!("{file}: {e}"))?;
        Ok(SceneDoc {
            doc,
            text: text.to_string(),
            file: file.to_string(),
            base: base.map(Path::to_path_buf),
            style: Style::of(text),
            undo: VecDeque::new(),
            undo_bytes: 0,
            redo: vec![],
            gesture: None,
            saved: text.to_string(),
        })
    }

    /// The document's text now.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The scene the document describes now ([`load_str`] on [`SceneDoc::text`]).
    pub fn scene(&self) -> Result<Scene, SceneError> {
        load_str(&self.text, &self.file, self.base.as_deref())
    }

    /// Which file entry each group of [`SceneDoc::scene`] comes from (in the order of
    /// [`Scene::groups`]: the entries' order in the file, whatever their kind, as the loader
    /// makes them).
    pub fn entries(&self) -> Vec<EntryRef> {
        entries(&self.doc)
    }

    /// How many groups an edit of group `group`'s material changes: the number of object
    /// entries naming the same `[[material]]` (this one included), or 1 for an object with no
    /// `material` key (its edit gives it a material of its own). `None` for a group the document
    /// does not have.
    pub fn material_users(&self, group: u32) -> Option<usize> {
        let doc = &self.doc;
        let entries = entries(doc);
        let e = *entries.get(group as usize)?;
        let names: HashMap<String, usize> = (0..count(doc, "material"))
            .map(|i| (material_name(doc, i), i))
            .collect();
        let material = |e: &EntryRef| {
            let t = table(doc, e.kind.key(), e.index)?;
            names.get(t.get("material")?.as_str()?).copied()
        };
        let Some(idx) = material(&e) else {
            return Some(1);
        };
        Some(entries.iter().filter(|o| material(o) == Some(idx)).count())
    }

    /// Applies an edit as one undoable step (or as part of the gesture in progress, see
    /// [`SceneDoc::begin_gesture`]) and returns the edited scene. An edit that is not possible
    /// (a group or light the scene does not have, a number that is not finite, a radius ≤ 0) or
    /// whose text the loader rejects leaves the document unchanged and returns the reason. An
    /// edit that changes no byte of the text makes no undo step.
    pub fn apply(&mut self, e: &Edit) -> Result<Scene, String> {
        let mut doc = self.doc.clone();
        edit_document(&mut doc, e)?;
        let text = self.style.render(&doc);
        if text == self.text {
            return self.scene().map_err(|e| message(&e));
        }
        let scene = load_str(&text, &self.file, self.base.as_deref()).map_err(|e| message(&e))?;
        let before = std::mem::replace(&mut self.text, text);
        if self.gesture.is_none() {
            self.push_undo(before);
            self.redo.clear();
        }
        self.doc = doc;
        Ok(scene)
    }

    /// Starts a gesture (a drag): the edits applied until [`SceneDoc::end_gesture`] make one
    /// undo step together. A gesture already in progress goes on.
    pub fn begin_gesture(&mut self) {
        if self.gesture.is_none() {
            self.gesture = Some(self.text.clone());
        }
    }

    /// Ends the gesture in progress: one undo step back to the text it began with, or none if
    /// the text is the same again. Does nothing outside a gesture.
    pub fn end_gesture(&mut self) {
        if let Some(start) = self.gesture.take()
            && start != self.text
        {
            self.push_undo(start);
            self.redo.clear();
        }
    }

    /// Whether a gesture is in progress.
    pub fn in_gesture(&self) -> bool {
        self.gesture.is_some()
    }

    /// Undoes the last step (ending a gesture in progress first): `None` if there is nothing to
    /// undo, else the scene the restored text describes, or the loader's message if it no longer
    /// loads (an OBJ file it names has changed on disk). The text is restored either way.
    pub fn undo(&mut self) -> Option<Result<Scene, String>> {
        self.end_gesture();
        let before = self.undo.pop_back()?;
        self.undo_bytes -= before.len();
        let now = match self.restore(before) {
            Ok(now) => now,
            Err((before, e)) => {
                self.undo_bytes += before.len();
                self.undo.push_back(before);
                return Some(Err(e));
            }
        };
        self.redo.push(now);
        Some(self.scene().map_err(|e| message(&e)))
    }

    /// Redoes the last undone step; as [`SceneDoc::undo`].
    pub fn redo(&mut self) -> Option<Result<Scene, String>> {
        self.end_gesture();
        let after = self.redo.pop()?;
        let now = match self.restore(after) {
            Ok(now) => now,
            Err((after, e)) => {
                self.redo.push(after);
                return Some(Err(e));
            }
        };
        self.push_undo(now);
        Some(self.scene().map_err(|e| message(&e)))
    }

    /// Whether there is a step to undo (a gesture in progress that changed the text counts).
    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty() || self.gesture.as_ref().is_some_and(|g| *g != self.text)
    }

    /// Whether there is a step to redo.
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Whether the text differs from what was last saved (or opened).
    pub fn dirty(&self) -> bool {
        self.text != self.saved
    }

    /// Writes the text to `path` atomically ([`crate::io::write_atomic`]: whole or not at all)
    /// and marks it saved. The message of an error names the path.
    ///
    /// The text is written as it is: OBJ paths in it are relative to the folder the scene was
    /// opened from, so a copy saved into another folder finds its meshes only if they are there
    /// too.
    pub fn save(&mut self, path: &Path) -> Result<(), String> {
        crate::io::write_atomic(path, self.text.as_bytes())?;
        self.saved = self.text.clone();
        Ok(())
    }

    fn push_undo(&mut self, text: String) {
        self.undo_bytes += text.len();
        self.undo.push_back(text);
        while self.undo.len() > 1 && self.undo_bytes > MAX_HISTORY_BYTES {
            if let Some(old) = self.undo.pop_front() {
                self.undo_bytes -= old.len();
            }
        }
    }

    /// Makes `text` (from the history) the document's, returning the text it replaces; on an
    /// error (impossible: every text in the history was parsed or rendered by toml_edit), gives
    /// `text` back and changes nothing.
    fn restore(&mut self, text: String) -> Result<String, (String, String)> {
        match text.parse::<DocumentMut>() {
            Ok(doc) => {
                self.doc = doc;
                Ok(std::mem::replace(&mut self.text, text))
            }
            Err(e) => {
                let e = format!("{}: {e}", self.file);
                Err((text, e))
            }
        }
    }
}

/// A loader error, without the file position (which points into an unsaved text).
fn message(e: &SceneError) -> String {
    match &e.field {
        Some(f) => format!("{f}: {}", e.message),
        None => e.message.clone(),
    }
}

// ---------------------------------------------------------------------------------------------
// Finding entries.

/// The `index`-th table of the array `key` (`[[key]]` tables or an inline `key = [{…}, …]`).
fn table<'a>(doc: &'a DocumentMut, key: &str, index: usize) -> Option<&'a dyn TableLike> {
    match doc.get(key)? {
        Item::ArrayOfTables(a) => a.get(index).map(|t| t as &dyn TableLike),
        Item::Value(Value::Array(a)) => {
            a.get(index)?.as_inline_table().map(|t| t as &dyn TableLike)
        }
        _ => None,
    }
}

/// As [`table`], mutable.
fn table_mut<'a>(
    doc: &'a mut DocumentMut,
    key: &str,
    index: usize,
) -> Option<&'a mut dyn TableLike> {
    match doc.get_mut(key)? {
        Item::ArrayOfTables(a) => a.get_mut(index).map(|t| t as &mut dyn TableLike),
        Item::Value(Value::Array(a)) => a
            .get_mut(index)?
            .as_inline_table_mut()
            .map(|t| t as &mut dyn TableLike),
        _ => None,
    }
}

/// How many entries the array `key` has.
fn count(doc: &DocumentMut, key: &str) -> usize {
    match doc.get(key) {
        Some(Item::ArrayOfTables(a)) => a.len(),
        Some(Item::Value(Value::Array(a))) => a.len(),
        _ => 0,
    }
}

/// The object entries in file order. Inline arrays (`sphere = [{…}]`) sit in the root table,
/// before every header, in the order of their keys; `[[kind]]` tables follow in the order of
/// their headers (`Table::position`). This is the loader's order (it sorts by where each
/// entry starts in the text).
fn entries(doc: &DocumentMut) -> Vec<EntryRef> {
    let mut keyed: Vec<((u8, isize, usize), EntryRef)> = vec![];
    let root_order = |key: &str| -> isize {
        doc.as_table()
            .iter()
            .position(|(k, _)| k == key)
            .unwrap_or(0) as isize
    };
    for kind in EntryKind::ALL {
        match doc.get(kind.key()) {
            Some(Item::ArrayOfTables(a)) => {
                for (index, t) in a.iter().enumerate() {
                    let pos = t.position().unwrap_or(isize::MAX);
                    keyed.push(((1, pos, 0), EntryRef { kind, index }));
                }
            }
            Some(Item::Value(Value::Array(a))) => {
                let order = root_order(kind.key());
                for index in 0..a.len() {
                    keyed.push(((0, order, index), EntryRef { kind, index }));
                }
            }
            _ => {}
        }
    }
    keyed.sort_by_key(|(k, _)| *k);
    keyed.into_iter().map(|(_, e)| e).collect()
}

/// The entry of group `group`.
fn entry_of(doc: &DocumentMut, group: u32) -> Result<EntryRef, String> {
    let entries = entries(doc);
    entries.get(group as usize).copied().ok_or_else(|| {
        format!(
            "there is no object {group}: the scene has {} (numbered from 0)",
            entries.len()
        )
    })
}

/// The name of an entry in messages: `sphere "ball"`, or `sphere "sphere 3"` as the loader
/// names an unnamed one.
fn describe(doc: &DocumentMut, e: EntryRef) -> String {
    format!("{} \"{}\"", e.kind.key(), entry_name(doc, e))
}

/// An entry's name: its `name`, else the loader's `kind index`.
fn entry_name(doc: &DocumentMut, e: EntryRef) -> String {
    table(doc, e.kind.key(), e.index)
        .and_then(|t| t.get("name"))
        .and_then(Item::as_str)
        .map_or_else(|| format!("{} {}", e.kind.key(), e.index), str::to_string)
}

/// The name the loader knows `[[material]]` `i` by.
fn material_name(doc: &DocumentMut, i: usize) -> String {
    table(doc, "material", i)
        .and_then(|t| t.get("name"))
        .and_then(Item::as_str)
        .map_or_else(|| format!("material {i}"), str::to_string)
}

/// The index of the material called `name`.
fn find_material(doc: &DocumentMut, name: &str) -> Option<usize> {
    (0..count(doc, "material")).find(|&i| material_name(doc, i) == name)
}

// ---------------------------------------------------------------------------------------------
// Editing.

fn finite(what: &str, v: &[f64]) -> Result<(), String> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(format!("{what} must be finite, got {v:?}"))
    }
}

fn edit_document(doc: &mut DocumentMut, e: &Edit) -> Result<(), String> {
    match *e {
        Edit::Move { group, by } => {
            finite("a move", &by)?;
            let entry = entry_of(doc, group)?;
            let what = describe(doc, entry);
            let t = table_mut(doc, entry.kind.key(), entry.index)
                .ok_or_else(|| format!("{what} is not a table"))?;
            match entry.kind {
                EntryKind::Sphere => shift_vec3(t, "center", [0.0; 3], by, &what),
                EntryKind::Mesh => shift_vec3(t, "translate", [0.0; 3], by, &what),
                EntryKind::Triangle => shift_triangle(t, by, &what),
                EntryKind::Plane => match t.get("axis") {
                    Some(axis) => {
                        let a = match axis.as_str() {
                            Some("x") => 0,
                            Some("y") => 1,
                            Some("z") => 2,
                            _ => return Err(format!("{what}: axis must be \"x\", \"y\" or \"z\"")),
                        };
                        if by[a] == 0.0 {
                            return Ok(());
                        }
                        let old = read_number(t, "offset", 0.0, &what)?;
                        let new = moved(old, by[a]);
                        finite(&format!("{what} → offset"), &[new])?;
                        set_number(t, "offset", new);
                        Ok(())
                    }
                    None => shift_vec3(t, "point", [0.0; 3], by, &what),
                },
            }
        }
        Edit::SetRadius { group, radius } => {
            let entry = entry_of(doc, group)?;
            let what = describe(doc, entry);
            if entry.kind != EntryKind::Sphere {
                return Err(format!(
                    "{what} is not a sphere: only a sphere has a radius"
                ));
            }
            if !(radius.is_finite() && radius > 0.0) {
                return Err(format!(
                    "{what} → radius: must be a positive finite number, got {radius}"
                ));
            }
            let t = table_mut(doc, entry.kind.key(), entry.index)
                .ok_or_else(|| format!("{what} is not a table"))?;
            read_number(t, "radius", 1.0, &what)?;
            set_number(t, "radius", tidy(radius));
            Ok(())
        }
        Edit::SetMaterial {
            group,
            field,
            value,
        } => {
            let key = field.key();
            match (field, value) {
                (MaterialField::Color, MaterialValue::Color(c)) => {
                    finite(&format!("material {key}"), &c)?
                }
                (MaterialField::Color, MaterialValue::Number(_)) => {
                    return Err("a material's color is three numbers, not one".into());
                }
                (_, MaterialValue::Number(x)) => finite(&format!("material {key}"), &[x])?,
                (_, MaterialValue::Color(_)) => {
                    return Err(format!("a material's {key} is one number, not three"));
                }
            }
            let entry = entry_of(doc, group)?;
            let what = describe(doc, entry);
            let index = {
                let t = table(doc, entry.kind.key(), entry.index)
                    .ok_or_else(|| format!("{what} is not a table"))?;
                match t.get("material") {
                    None => None,
                    Some(item) => {
                        let name = item
                            .as_str()
                            .ok_or_else(|| format!("{what} → material: is not a name"))?;
                        Some(find_material(doc, name).ok_or_else(|| {
                            format!("{what} → material: unknown material \"{name}\"")
                        })?)
                    }
                }
            };
            let index = match index {
                Some(i) => i,
                None => new_material(doc, entry)?,
            };
            let mat = format!("material \"{}\"", material_name(doc, index));
            let t =
                table_mut(doc, "material", index).ok_or_else(|| format!("{mat} is not a table"))?;
            match value {
                MaterialValue::Color(c) => {
                    read_vec3(t, key, [1.0; 3], &mat)?;
                    set_vec3(t, key, c.map(tidy));
                }
                MaterialValue::Number(x) => {
                    read_number(t, key, f64::NAN, &mat)?;
                    set_number(t, key, tidy(x));
                }
            }
            Ok(())
        }
        Edit::SetLight {
            light,
            field,
            value,
        } => {
            let key = field.key();
            finite(&format!("a light's {key}"), &value)?;
            let n = count(doc, "light");
            let name = table(doc, "light", light as usize)
                .and_then(|t| t.get("name"))
                .and_then(Item::as_str)
                .map_or_else(|| format!("light {light}"), str::to_string);
            let what = format!("light \"{name}\"");
            let t = table_mut(doc, "light", light as usize).ok_or_else(|| {
                format!("there is no light {light}: the scene has {n} (numbered from 0)")
            })?;
            let default = match field {
                LightField::Position => [-10.0, 10.0, -10.0],
                LightField::Color => [1.0; 3],
            };
            read_vec3(t, key, default, &what)?;
            set_vec3(t, key, value.map(tidy));
            Ok(())
        }
    }
}

/// Gives entry `e` (which has no `material` key) a new `[[material]]` of its own, named after
/// it, and returns the material's index. The new material has only a name: the loader's
/// defaults for `[[material]]` are those of the default material objects without one get, so
/// the scene is unchanged until a field is set.
fn new_material(doc: &mut DocumentMut, e: EntryRef) -> Result<usize, String> {
    let what = describe(doc, e);
    let base = format!("{} material", entry_name(doc, e));
    let n = count(doc, "material");
    let taken: Vec<String> = (0..n).map(|i| material_name(doc, i)).collect();
    let name = std::iter::once(base.clone())
        .chain((2..).map(|k| format!("{base} {k}")))
        .find(|c| !taken.contains(c))
        .unwrap_or(base);
    // Where a new `[[material]]` goes: after the last one, or (with none) just before the
    // first object entry. toml_edit writes a table without a position after the table visited
    // before it (the last material); a new array, visited last, is given the position of the
    // header before the first object, and sorts after it.
    let first_object = EntryKind::ALL
        .iter()
        .filter_map(|k| match doc.get(k.key()) {
            Some(Item::ArrayOfTables(a)) => a.iter().filter_map(Table::position).min(),
            _ => None,
        })
        .min();
    match doc.get_mut("material") {
        Some(Item::ArrayOfTables(a)) => {
            let mut t = Table::new();
            t.insert("name", toml_edit::value(name.clone()));
            a.push(t);
        }
        Some(Item::Value(Value::Array(a))) => {
            let mut t = InlineTable::new();
            t.insert("name", Value::from(name.clone()));
            a.push(t);
        }
        Some(_) => {
            return Err("the scene's `material` is not a list of [[material]] tables".into());
        }
        None => {
            let mut t = Table::new();
            t.insert("name", toml_edit::value(name.clone()));
            t.set_position(first_object.map(|p| p.saturating_sub(1)));
            let mut a = ArrayOfTables::new();
            a.push(t);
            doc.insert("material", Item::ArrayOfTables(a));
        }
    }
    let t =
        table_mut(doc, e.kind.key(), e.index).ok_or_else(|| format!("{what} is not a table"))?;
    insert_key(t, "material", Value::from(name));
    Ok(n)
}

/// A number a value holds (an integer or a float).
fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Integer(i) => Some(*i.value() as f64),
        Value::Float(f) => Some(*f.value()),
        _ => None,
    }
}

/// Three numbers an array holds.
fn vec3(a: &Array) -> Option<[f64; 3]> {
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
fn read_number(t: &dyn TableLike, key: &str, default: f64, what: &str) -> Result<f64, String> {
    match t.get(key) {
        None => Ok(default),
        Some(item) => item
            .as_value()
            .and_then(number)
            .ok_or_else(|| format!("{what} → {key}: is not a number")),
    }
}

/// The three numbers `key` holds, or `default` when it is absent.
fn read_vec3(
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

fn shift_vec3(
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

fn shift_triangle(t: &mut dyn TableLike, by: [f64; 3], what: &str) -> Result<(), String> {
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
fn shifted(old: [f64; 3], by: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| {
        if by[i] == 0.0 {
            old[i]
        } else {
            moved(old[i], by[i])
        }
    })
}

/// Sets `key` to `x`, in the style of the number it replaces, keeping its comment.
fn set_number(t: &mut dyn TableLike, key: &str, x: f64) {
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
fn set_vec3(t: &mut dyn TableLike, key: &str, new: [f64; 3]) {
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

fn new_array(v: [f64; 3]) -> Array {
    v.iter().map(|&x| styled(None, x, None)).collect()
}

/// Writes three numbers into an array of three numbers, touching only those that change (in
/// the style of the number each replaces, or of its padded neighbours).
fn write_into(a: &mut Array, new: [f64; 3]) {
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
fn insert_key(t: &mut dyn TableLike, key: &str, v: Value) {
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
fn decimals(x: f64) -> usize {
    let s = format!("{}", x.abs());
    s.split_once('.').map_or(0, |(_, f)| f.len())
}

/// `x` rounded to `d` decimals (the nearest double to the rounded decimal).
fn round_to(x: f64, d: usize) -> f64 {
    format!("{x:.d$}").parse::<f64>().unwrap_or(x)
}

/// A coordinate moved: `old + by` rounded to 6 decimals, or to as many as `old` has.
fn moved(old: f64, by: f64) -> f64 {
    round_to(old + by, decimals(old).clamp(6, 30))
}

/// A value set by the user (a radius, a coefficient, a colour, a light's position): rounded to 6
/// decimals or 6 significant digits, whichever keeps more, which strips the binary noise of a
/// value computed in f64 or f32 (`0.8_f32` is 0.800000011920929) but keeps a tiny radius.
fn tidy(x: f64) -> f64 {
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
fn int_repr(x: f64) -> Option<String> {
    (x.fract() == 0.0 && x.abs() < 1e15).then(|| format!("{}", x as i64))
}

/// `x` as a float literal: shortest decimals, exponent notation for very large or small.
fn float_repr(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && !(1e-5..1e16).contains(&a) {
        return format!("{x:e}");
    }
    let s = format!("{x}");
    if s.contains('.') { s } else { s + ".0" }
}

/// Digits after the point of a plain float literal (`0.1600` → 4), `None` for other forms
/// (exponents, `inf`, integers).
fn fixed_decimals(repr: &str) -> Option<usize> {
    let body = repr.trim_start_matches(['+', '-']);
    let (int, frac) = body.split_once('.')?;
    let digits = |s: &str| !s.is_empty() && s.chars().all(|c| c.is_ascii_digit() || c == '_');
    (digits(int) && digits(frac)).then(|| frac.chars().filter(char::is_ascii_digit).count())
}

/// The decimals a float is padded to with trailing zeros (`0.1600` → 4, `-200.0` → 1), `None`
/// for a float written without them (`0.5`) and for other values.
fn padding(v: &Value) -> Option<usize> {
    let Value::Float(f) = v else { return None };
    fixed_decimals(&f.display_repr()).filter(|&k| k > decimals(*f.value()))
}

/// The number `x` written as a TOML value in the style of `old`, the value it replaces: a float
/// padded with zeros stays padded to as many decimals (`0.1600` → `0.2500`, `-200.0` →
/// `-199.0`); otherwise, as for a new value, a whole number is an integer (so `0` moved to
/// `0.5` and back is `0` again) and others are short floats. `pad` is the padding of the
/// value's neighbours in an array, used when `old` itself shows none.
fn styled(old: Option<&Value>, x: f64, pad: Option<usize>) -> Value {
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
