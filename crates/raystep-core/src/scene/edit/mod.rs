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
//! use raystep_core::scene::edit::{Edit, SceneDoc};
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

mod entries;
mod values;

use entries::*;
use values::*;

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
    ///
    /// A scene that includes a glTF file is refused: its `[[gltf]]` table brings many objects,
    /// and the editor edits one table per object.
    pub fn parse(text: &str, file: &str, base: Option<&Path>) -> Result<SceneDoc, String> {
        let doc: DocumentMut = text.parse().map_err(|e| format!("{file}: {e}"))?;
        if doc.contains_key("gltf") {
            return Err(format!(
                "{file}: a scene that includes a glTF file ([[gltf]]) is edited in its text, not in the app"
            ));
        }
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
