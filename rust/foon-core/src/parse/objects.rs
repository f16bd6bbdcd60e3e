//! Lists of objects (kitchens and goals): the JSON form of an [`ObjectSpec`] and FOON object
//! blocks, read by one loader for files and for text given on a command line alike.

use std::path::Path;

use serde::Deserialize;

use super::lines::{
    Annotation, LineKind, Lines, annotation, classify, empty_ingredient_fault, normalise,
    second_container_fault, second_list_fault, strip_bom,
};
use super::read_file;
use crate::error::{Error, InputKind, Location, Result, Warning, WarningKind};
use crate::model::{ObjectSpec, label_fault, states_fault};

fn json_error(kind: InputKind, path: Option<&Path>, text: &str, e: &serde_json::Error) -> Error {
    let msg = e.to_string();
    // serde_json appends " at line L column C"; the location is given separately.
    let reason = msg
        .rsplit_once(" at line ")
        .map_or(msg.as_str(), |(r, _)| r)
        .to_owned();
    let line = e.line().max(1);
    // serde_json counts the column in bytes; ours is in characters.
    let column = text.split('\n').nth(line - 1).map_or(e.column(), |l| {
        let mut b = e.column().saturating_sub(1).min(l.len());
        while !l.is_char_boundary(b) {
            b -= 1;
        }
        l[..b].chars().count() + 1
    });
    Error::parse(kind, path, line as u64, column.max(1) as u32, reason)
}

/// 1-based line and character column just after `valid` (valid UTF-8 text).
fn end_position(valid: &[u8]) -> (u64, u32) {
    let text = std::str::from_utf8(valid).unwrap_or_default();
    let line = text.bytes().filter(|&b| b == b'\n').count() as u64 + 1;
    let last = text.rfind('\n').map_or(text, |i| &text[i + 1..]);
    (line, last.chars().count() as u32 + 1)
}

/// Parses a list of objects: JSON (a list, or one object when `kind` is a goal) or FOON
/// object blocks (`O`/`S` lines; `//` lines are ignored). The one loader of objects, for
/// files and for text given on a command line alike (`path` names the source in messages).
///
/// JSON objects are `{"label", "states", "ingredients", "container"}`: the label a non-empty
/// string, the states and ingredients lists of strings, the container a string; any field
/// but the label may be absent or `null` (no states, no ingredients, no container). Wrong
/// types, unknown fields, non-finite numbers and nesting deeper than 128 levels are errors
/// with a line and column; nothing is coerced.
pub fn parse_objects(data: &[u8], path: Option<&Path>, kind: InputKind) -> Result<Vec<ObjectSpec>> {
    parse_objects_noting(data, path, kind, &mut Vec::new())
}

/// As [`parse_objects`], also collecting the annotation faults of object blocks (a second
/// container or ingredient list on one object, an empty ingredient) as warnings.
pub(crate) fn parse_objects_noting(
    data: &[u8],
    path: Option<&Path>,
    kind: InputKind,
    notes: &mut Vec<Warning>,
) -> Result<Vec<ObjectSpec>> {
    if !super::json::is_json(data) {
        return parse_object_blocks(data, path, kind, notes);
    }
    let data = strip_bom(data);
    let text = std::str::from_utf8(data).map_err(|e| {
        let (line, column) = end_position(&data[..e.valid_up_to()]);
        Error::parse(kind, path, line, column, "invalid UTF-8")
    })?;
    // Deserialise the shape the first character announces (rather than trying both), so
    // that serde_json reports where and why the data goes wrong.
    if text.trim_start().starts_with('[') {
        return serde_json::from_str::<Vec<ObjectSpec>>(text)
            .map_err(|e| json_error(kind, path, text, &e));
    }
    let one =
        serde_json::from_str::<ObjectSpec>(text).map_err(|e| json_error(kind, path, text, &e))?;
    if kind != InputKind::Goal {
        return Err(Error::parse(
            kind,
            path,
            1,
            1,
            "expected a JSON list of objects",
        ));
    }
    Ok(vec![one])
}

fn parse_object_blocks(
    data: &[u8],
    path: Option<&Path>,
    kind: InputKind,
    notes: &mut Vec<Warning>,
) -> Result<Vec<ObjectSpec>> {
    let mut out: Vec<ObjectSpec> = Vec::new();
    let mut fields = Vec::new();
    let err = |line: u64, col: u32, reason: String| Error::parse(kind, path, line, col, reason);
    for line in Lines::new(data, path, kind) {
        let line = line?;
        let lk = classify(&line, &mut fields).map_err(|(c, r)| err(line.number, c, r))?;
        match lk {
            LineKind::Blank | LineKind::Comment | LineKind::End => continue,
            LineKind::Motion => {
                return Err(err(
                    line.number,
                    1,
                    "a motion line is not allowed in a list of objects".into(),
                ));
            }
            LineKind::Object | LineKind::State => {}
        }
        let Some(&(f1_off, f1)) = fields.get(1) else {
            return Err(err(
                line.number,
                line.column_of(line.text.len()),
                "missing field (no TAB-separated field)".into(),
            ));
        };
        let value = normalise(f1).into_owned();
        if lk == LineKind::Object {
            if value.is_empty() {
                return Err(err(
                    line.number,
                    line.column_of(f1_off),
                    "empty object label".into(),
                ));
            }
            out.push(ObjectSpec {
                label: value,
                ..ObjectSpec::default()
            });
            continue;
        }
        let Some(obj) = out.last_mut() else {
            return Err(err(line.number, 1, "state line before any object".into()));
        };
        if let Some(&(f2_off, f2)) = fields.get(2) {
            let col = line.column_of(f2_off);
            let at = |byte: usize| Location::new(path, line.number, line.column_of(byte));
            match annotation(f2).map_err(|r| err(line.number, col, r))? {
                Annotation::Ingredients(inner) => {
                    if !obj.ingredients.is_empty() {
                        let old = obj.ingredients.join(",");
                        let fault = second_list_fault(&obj.label, &old, inner);
                        notes.push(Warning::fault(
                            at(f2_off),
                            WarningKind::TwoIngredientLists,
                            &fault,
                        ));
                    }
                    let mut offset = f2_off + 1;
                    for ing in inner.split(',') {
                        if ing.is_empty() {
                            let fault = empty_ingredient_fault(inner);
                            notes.push(Warning::fault(
                                at(offset),
                                WarningKind::EmptyIngredient,
                                &fault,
                            ));
                        }
                        offset += ing.len() + 1;
                    }
                    // A later list replaces an earlier one (course behaviour).
                    obj.ingredients = inner.split(',').map(str::to_owned).collect();
                }
                Annotation::Container(inner) => {
                    if let Some(old) = &obj.container {
                        let fault = second_container_fault(&obj.label, old, inner);
                        notes.push(Warning::fault(
                            at(f2_off),
                            WarningKind::TwoContainers,
                            &fault,
                        ));
                    }
                    obj.container = Some(inner.to_owned());
                }
            }
        } else if value.is_empty() {
            return Err(err(
                line.number,
                line.column_of(f1_off),
                "empty state".into(),
            ));
        } else {
            obj.states.push(value);
        }
    }
    Ok(out)
}

/// Reads a kitchen (JSON list or object blocks).
pub fn load_objects(path: &Path, kind: InputKind) -> Result<Vec<ObjectSpec>> {
    let data = read_file(path)?;
    parse_objects(&data, Some(path), kind)
}

/// The JSON form of an object: `{"label", "states", "ingredients", "container"}`. Every
/// field but the label is optional, and `null` is the same as an absent field (no states, no
/// ingredients, no container). Types are never coerced.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JsonObject {
    #[serde(deserialize_with = "checked_label")]
    label: String,
    #[serde(default, deserialize_with = "checked_states")]
    states: Option<Vec<String>>,
    #[serde(default)]
    ingredients: Option<Vec<String>>,
    #[serde(default)]
    container: Option<String>,
}

// The field checks run where each field is read, so that an error has the JSON parser's
// location; they are the checks of `ObjectSpec::new`.
fn checked_label<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<String, D::Error> {
    let s = String::deserialize(d)?;
    match label_fault(&s) {
        Some(f) => Err(serde::de::Error::custom(f)),
        None => Ok(s),
    }
}

fn checked_states<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<Vec<String>>, D::Error> {
    let v = Option::<Vec<String>>::deserialize(d)?;
    match v.as_deref().and_then(states_fault) {
        Some(f) => Err(serde::de::Error::custom(f)),
        None => Ok(v),
    }
}

/// Reads a [`JsonObject`] from a JSON object only (serde's derived form would also take a
/// list of the field values, `["ice", ["crushed"]]`, which is not a kitchen item).
struct ObjectOnly;

impl<'de> serde::de::Visitor<'de> for ObjectOnly {
    type Value = JsonObject;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("struct ObjectSpec")
    }

    fn visit_map<A: serde::de::MapAccess<'de>>(
        self,
        map: A,
    ) -> std::result::Result<JsonObject, A::Error> {
        JsonObject::deserialize(serde::de::value::MapAccessDeserializer::new(map))
    }
}

impl<'de> Deserialize<'de> for ObjectSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let j = d.deserialize_map(ObjectOnly)?;
        ObjectSpec::new(
            j.label,
            j.states.unwrap_or_default(),
            j.ingredients.unwrap_or_default(),
            j.container,
        )
        .map_err(serde::de::Error::custom)
    }
}
