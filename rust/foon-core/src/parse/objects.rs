//! Lists of objects (kitchens and goals): the JSON form of an [`ObjectSpec`] and FOON object
//! blocks, read by one loader for files and for text given on a command line alike.

use std::borrow::Cow;
use std::path::Path;

use serde::Deserialize;

use super::lines::{
    Annotation, LineKind, Lines, annotation, classify, empty_ingredient_fault, normalise,
    second_container_fault, second_list_fault, strip_bom,
};
use super::read_file;
use crate::error::{Error, InputKind, Location, Result, Warning, WarningKind};
use crate::kitchen::Kitchen;
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

/// Where a parse of a list of objects puts each object it reads, in file order: a list of
/// [`ObjectSpec`]s, or a [`Kitchen`](crate::kitchen::Kitchen) built straight from the text
/// (no owned strings per item).
pub(crate) trait ObjectSink {
    /// One object, its fields as written (states and ingredients in their written order).
    fn object<'a>(
        &mut self,
        label: &'a str,
        states: impl Iterator<Item = &'a str>,
        ingredients: impl Iterator<Item = &'a str>,
        container: Option<&'a str>,
    );
}

impl ObjectSink for Vec<ObjectSpec> {
    fn object<'a>(
        &mut self,
        label: &'a str,
        states: impl Iterator<Item = &'a str>,
        ingredients: impl Iterator<Item = &'a str>,
        container: Option<&'a str>,
    ) {
        self.push(ObjectSpec {
            label: label.to_owned(),
            states: states.map(str::to_owned).collect(),
            ingredients: ingredients.map(str::to_owned).collect(),
            container: container.map(str::to_owned),
        });
    }
}

impl ObjectSink for Kitchen {
    fn object<'a>(
        &mut self,
        label: &'a str,
        states: impl Iterator<Item = &'a str>,
        ingredients: impl Iterator<Item = &'a str>,
        container: Option<&'a str>,
    ) {
        self.push(label, states, ingredients, container);
    }
}

impl Kitchen {
    /// Reads the objects of `data` (see [`parse_objects`]) into this kitchen: the grammar
    /// stays here, the kitchen gets each object as it is read.
    pub(crate) fn read_objects(
        &mut self,
        data: &[u8],
        path: Option<&Path>,
        kind: InputKind,
    ) -> Result<()> {
        parse_objects_into(data, path, kind, &mut Vec::new(), self)
    }
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
    let mut out = Vec::new();
    parse_objects_into(data, path, kind, notes, &mut out)?;
    Ok(out)
}

/// As [`parse_objects_noting`], giving each object to `sink` as it is read. On an error the
/// sink may hold the objects read before it.
pub(crate) fn parse_objects_into(
    data: &[u8],
    path: Option<&Path>,
    kind: InputKind,
    notes: &mut Vec<Warning>,
    sink: &mut impl ObjectSink,
) -> Result<()> {
    if !super::json::is_json(data) {
        return parse_object_blocks(data, path, kind, notes, sink);
    }
    let data = strip_bom(data);
    let text = std::str::from_utf8(data).map_err(|e| {
        let (line, column) = end_position(&data[..e.valid_up_to()]);
        Error::parse(kind, path, line, column, "invalid UTF-8")
    })?;
    // Deserialise the shape the first character announces (rather than trying both), so
    // that serde_json reports where and why the data goes wrong.
    let mut de = serde_json::Deserializer::from_str(text);
    if text.trim_start().starts_with('[') {
        return serde::de::DeserializeSeed::deserialize(Items(sink), &mut de)
            .and_then(|()| de.end())
            .map_err(|e| json_error(kind, path, text, &e));
    }
    let one = serde::de::DeserializeSeed::deserialize(OneObject, &mut de)
        .and_then(|o| de.end().map(|()| o))
        .map_err(|e| json_error(kind, path, text, &e))?;
    if kind != InputKind::Goal {
        return Err(Error::parse(
            kind,
            path,
            1,
            1,
            "expected a JSON list of objects",
        ));
    }
    one.give(sink);
    Ok(())
}

/// The object of object blocks being read: its fields as ranges of one text buffer, reused
/// from object to object (no allocation per object once the buffer has grown).
#[derive(Default)]
struct Pending {
    text: String,
    open: bool,
    label: (usize, usize),
    states: Vec<(usize, usize)>,
    ingredients: Vec<(usize, usize)>,
    container: Option<(usize, usize)>,
}

impl Pending {
    fn add(&mut self, s: &str) -> (usize, usize) {
        let start = self.text.len();
        self.text.push_str(s);
        (start, self.text.len())
    }

    fn get(&self, (a, b): (usize, usize)) -> &str {
        &self.text[a..b]
    }

    fn label(&self) -> &str {
        self.get(self.label)
    }

    /// Gives the open object (if any) to `sink` and starts none.
    fn flush(&mut self, sink: &mut impl ObjectSink) {
        if std::mem::take(&mut self.open) {
            let t = self.text.as_str();
            let get = |(a, b): (usize, usize)| &t[a..b];
            sink.object(
                get(self.label),
                self.states.iter().map(|&r| get(r)),
                self.ingredients.iter().map(|&r| get(r)),
                self.container.map(get),
            );
        }
    }

    /// Starts a new object labelled `label`.
    fn start(&mut self, label: &str) {
        self.text.clear();
        self.states.clear();
        self.ingredients.clear();
        self.container = None;
        self.label = self.add(label);
        self.open = true;
    }
}

fn parse_object_blocks(
    data: &[u8],
    path: Option<&Path>,
    kind: InputKind,
    notes: &mut Vec<Warning>,
    sink: &mut impl ObjectSink,
) -> Result<()> {
    let mut obj = Pending::default();
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
        let value = normalise(f1);
        if lk == LineKind::Object {
            if value.is_empty() {
                return Err(err(
                    line.number,
                    line.column_of(f1_off),
                    "empty object label".into(),
                ));
            }
            obj.flush(sink);
            obj.start(&value);
            continue;
        }
        if !obj.open {
            return Err(err(line.number, 1, "state line before any object".into()));
        }
        if let Some(&(f2_off, f2)) = fields.get(2) {
            let col = line.column_of(f2_off);
            let at = |byte: usize| Location::new(path, line.number, line.column_of(byte));
            match annotation(f2).map_err(|r| err(line.number, col, r))? {
                Annotation::Ingredients(inner) => {
                    if !obj.ingredients.is_empty() {
                        let old: Vec<&str> = obj.ingredients.iter().map(|&r| obj.get(r)).collect();
                        let fault = second_list_fault(obj.label(), &old.join(","), inner);
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
                    obj.ingredients.clear();
                    for ing in inner.split(',') {
                        let r = obj.add(ing);
                        obj.ingredients.push(r);
                    }
                }
                Annotation::Container(inner) => {
                    if let Some(old) = obj.container {
                        let fault = second_container_fault(obj.label(), obj.get(old), inner);
                        notes.push(Warning::fault(
                            at(f2_off),
                            WarningKind::TwoContainers,
                            &fault,
                        ));
                    }
                    obj.container = Some(obj.add(inner));
                }
            }
        } else if value.is_empty() {
            return Err(err(
                line.number,
                line.column_of(f1_off),
                "empty state".into(),
            ));
        } else {
            let r = obj.add(&value);
            obj.states.push(r);
        }
    }
    obj.flush(sink);
    Ok(())
}

/// Reads a kitchen (JSON list or object blocks).
pub fn load_objects(path: &Path, kind: InputKind) -> Result<Vec<ObjectSpec>> {
    let data = read_file(path)?;
    parse_objects(&data, Some(path), kind)
}

/// A JSON string, borrowed from the input when it has no escapes.
struct Text<'a>(Cow<'a, str>);

impl<'de: 'a, 'a> Deserialize<'de> for Text<'a> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Text<'de>;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a string")
            }

            fn visit_borrowed_str<E>(self, v: &'de str) -> std::result::Result<Text<'de>, E> {
                Ok(Text(Cow::Borrowed(v)))
            }

            fn visit_str<E>(self, v: &str) -> std::result::Result<Text<'de>, E> {
                Ok(Text(Cow::Owned(v.to_owned())))
            }

            fn visit_string<E>(self, v: String) -> std::result::Result<Text<'de>, E> {
                Ok(Text(Cow::Owned(v)))
            }
        }
        d.deserialize_str(V)
    }
}

/// The JSON form of an object: `{"label", "states", "ingredients", "container"}`. Every
/// field but the label is optional, and `null` is the same as an absent field (no states, no
/// ingredients, no container). Types are never coerced.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JsonObject<'a> {
    #[serde(borrow, deserialize_with = "checked_label")]
    label: Text<'a>,
    #[serde(default, borrow, deserialize_with = "checked_states")]
    states: Option<Vec<Text<'a>>>,
    #[serde(default, borrow)]
    ingredients: Option<Vec<Text<'a>>>,
    #[serde(default, borrow)]
    container: Option<Text<'a>>,
}

impl JsonObject<'_> {
    fn give(&self, sink: &mut impl ObjectSink) {
        fn strs<'b>(v: Option<&'b Vec<Text<'_>>>) -> impl Iterator<Item = &'b str> {
            v.map_or(&[][..], Vec::as_slice).iter().map(|t| &*t.0)
        }
        sink.object(
            &self.label.0,
            strs(self.states.as_ref()),
            strs(self.ingredients.as_ref()),
            self.container.as_ref().map(|c| &*c.0),
        );
    }
}

// The field checks run where each field is read, so that an error has the JSON parser's
// location; they are the checks of `ObjectSpec::new`.
fn checked_label<'de: 'a, 'a, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Text<'a>, D::Error> {
    let s = Text::deserialize(d)?;
    match label_fault(&s.0) {
        Some(f) => Err(serde::de::Error::custom(f)),
        None => Ok(s),
    }
}

fn checked_states<'de: 'a, 'a, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<Vec<Text<'a>>>, D::Error> {
    let v = Option::<Vec<Text<'a>>>::deserialize(d)?;
    // A state is checked as `ObjectSpec::new` checks a list of states (the text is copied
    // only for a state that fails: a blank one).
    let fault = v.as_deref().unwrap_or_default().iter().find_map(|s| {
        s.0.trim()
            .is_empty()
            .then(|| states_fault(&[s.0.clone().into_owned()]))
            .flatten()
    });
    match fault {
        Some(f) => Err(serde::de::Error::custom(f)),
        None => Ok(v),
    }
}

/// Reads a [`JsonObject`] from a JSON object only (serde's derived form would also take a
/// list of the field values, `["ice", ["crushed"]]`, which is not a kitchen item).
struct ObjectOnly;

impl<'de> serde::de::Visitor<'de> for ObjectOnly {
    type Value = JsonObject<'de>;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("struct ObjectSpec")
    }

    fn visit_map<A: serde::de::MapAccess<'de>>(
        self,
        map: A,
    ) -> std::result::Result<JsonObject<'de>, A::Error> {
        JsonObject::deserialize(serde::de::value::MapAccessDeserializer::new(map))
    }
}

/// One JSON object (a goal given alone).
struct OneObject;

impl<'de> serde::de::DeserializeSeed<'de> for OneObject {
    type Value = JsonObject<'de>;

    fn deserialize<D: serde::Deserializer<'de>>(
        self,
        d: D,
    ) -> std::result::Result<JsonObject<'de>, D::Error> {
        d.deserialize_map(ObjectOnly)
    }
}

/// A JSON list of objects, each given to the sink as soon as it is read.
struct Items<'s, K>(&'s mut K);

impl<'de, K: ObjectSink> serde::de::DeserializeSeed<'de> for Items<'_, K> {
    type Value = ();

    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> std::result::Result<(), D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de, K: ObjectSink> serde::de::Visitor<'de> for Items<'_, K> {
    type Value = ();

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a sequence")
    }

    fn visit_seq<A: serde::de::SeqAccess<'de>>(
        self,
        mut seq: A,
    ) -> std::result::Result<(), A::Error> {
        while let Some(o) = seq.next_element_seed(OneObject)? {
            o.give(self.0);
        }
        Ok(())
    }
}

impl<'de> Deserialize<'de> for ObjectSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let j = d.deserialize_map(ObjectOnly)?;
        let text = |t: Text<'_>| t.0.into_owned();
        let list = |v: Option<Vec<Text<'_>>>| v.unwrap_or_default().into_iter().map(text).collect();
        ObjectSpec::new(
            text(j.label),
            list(j.states),
            list(j.ingredients),
            j.container.map(text),
        )
        .map_err(serde::de::Error::custom)
    }
}
