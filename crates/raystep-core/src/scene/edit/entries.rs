//! Finding an object's or a material's entry in the scene's TOML document: the `[[kind]]`
//! tables (or inline arrays) in the order the loader reads them.

use super::*;

/// The `index`-th table of the array `key` (`[[key]]` tables or an inline `key = [{…}, …]`).
pub(super) fn table<'a>(
    doc: &'a DocumentMut,
    key: &str,
    index: usize,
) -> Option<&'a dyn TableLike> {
    match doc.get(key)? {
        Item::ArrayOfTables(a) => a.get(index).map(|t| t as &dyn TableLike),
        Item::Value(Value::Array(a)) => {
            a.get(index)?.as_inline_table().map(|t| t as &dyn TableLike)
        }
        _ => None,
    }
}

/// As [`table`], mutable.
pub(super) fn table_mut<'a>(
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
pub(super) fn count(doc: &DocumentMut, key: &str) -> usize {
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
pub(super) fn entries(doc: &DocumentMut) -> Vec<EntryRef> {
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
pub(super) fn entry_of(doc: &DocumentMut, group: u32) -> Result<EntryRef, String> {
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
pub(super) fn describe(doc: &DocumentMut, e: EntryRef) -> String {
    format!("{} \"{}\"", e.kind.key(), entry_name(doc, e))
}

/// An entry's name: its `name`, else the loader's `kind index`.
pub(super) fn entry_name(doc: &DocumentMut, e: EntryRef) -> String {
    table(doc, e.kind.key(), e.index)
        .and_then(|t| t.get("name"))
        .and_then(Item::as_str)
        .map_or_else(|| format!("{} {}", e.kind.key(), e.index), str::to_string)
}

/// The name the loader knows `[[material]]` `i` by.
pub(super) fn material_name(doc: &DocumentMut, i: usize) -> String {
    table(doc, "material", i)
        .and_then(|t| t.get("name"))
        .and_then(Item::as_str)
        .map_or_else(|| format!("material {i}"), str::to_string)
}

/// The index of the material called `name`.
pub(super) fn find_material(doc: &DocumentMut, name: &str) -> Option<usize> {
    (0..count(doc, "material")).find(|&i| material_name(doc, i) == name)
}
