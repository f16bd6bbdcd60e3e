//! Companion files: kitchens (JSON or FOON object blocks), goals (JSON or object blocks),
//! motion success rates and utensil lists.

use std::path::Path;

use rustc_hash::FxHashMap;
use serde::Deserialize;

use crate::error::{Error, InputKind, Result};
use crate::index::{Foon, NONE};
use crate::parse::{LineKind, Lines, classify};

/// An object given by its text fields (a kitchen item or a goal).
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectSpec {
    #[serde(deserialize_with = "non_empty_label")]
    pub label: String,
    #[serde(default)]
    pub states: Vec<String>,
    #[serde(default)]
    pub ingredients: Vec<String>,
    #[serde(default)]
    pub container: Option<String>,
}

impl ObjectSpec {
    /// The object of `foon` with this identity.
    pub fn find_in(&self, foon: &Foon) -> Option<u32> {
        let s: Vec<&str> = self.states.iter().map(String::as_str).collect();
        let i: Vec<&str> = self.ingredients.iter().map(String::as_str).collect();
        foon.find_object(&self.label, &s, &i, self.container.as_deref())
    }

    /// A one-line description: `label [states] {ingredients} in [container]`.
    pub fn describe(&self) -> String {
        use std::fmt::Write as _;
        let mut s = self.label.clone();
        if !self.states.is_empty() {
            let _ = write!(s, " ({})", self.states.join(", "));
        }
        if !self.ingredients.is_empty() {
            let _ = write!(s, " {{{}}}", self.ingredients.join(","));
        }
        if let Some(c) = &self.container {
            let _ = write!(s, " in [{c}]");
        }
        s
    }

    /// The object `obj` of `foon` as a spec, in its first written form.
    pub fn of_object(foon: &Foon, obj: u32) -> Self {
        let v = foon.first_variant(obj);
        let c = foon.container(obj);
        Self {
            label: foon.label_text(obj).to_owned(),
            states: foon
                .variant_states(v)
                .iter()
                .map(|&s| foon.text(s).to_owned())
                .collect(),
            ingredients: foon
                .variant_ingredients(v)
                .iter()
                .map(|&s| foon.text(s).to_owned())
                .collect(),
            container: (c != NONE).then(|| foon.text(c).to_owned()),
        }
    }
}

fn json_error(kind: InputKind, path: Option<&Path>, text: &str, e: &serde_json::Error) -> Error {
    let msg = e.to_string();
    // serde_json appends " at line L column C"; the location is given separately.
    let reason = msg
        .rsplit_once(" at line ")
        .map_or(msg.as_str(), |(r, _)| r)
        .to_owned();
    let reason = if reason.starts_with("data did not match any variant") {
        "expected an object {\"label\", \"states\", \"ingredients\", \"container\"} \
         or a list of them"
            .to_owned()
    } else {
        reason
    };
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

/// Rejects an empty label where it is read (so the error has the JSON parser's location).
fn non_empty_label<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<String, D::Error> {
    let s = String::deserialize(d)?;
    if s.is_empty() {
        return Err(serde::de::Error::custom("an object has an empty label"));
    }
    Ok(s)
}

/// 1-based line and character column just after `valid` (valid UTF-8 text).
fn end_position(valid: &[u8]) -> (u64, u32) {
    let text = std::str::from_utf8(valid).unwrap_or_default();
    let line = text.bytes().filter(|&b| b == b'\n').count() as u64 + 1;
    let last = text.rfind('\n').map_or(text, |i| &text[i + 1..]);
    (line, last.chars().count() as u32 + 1)
}

fn is_json(data: &[u8]) -> bool {
    let t = data.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(data);
    matches!(
        t.iter().find(|b| !b.is_ascii_whitespace()),
        Some(b'[' | b'{')
    )
}

/// Parses a list of objects: JSON (a list, or one object when `kind` is a goal) or FOON
/// object blocks (`O`/`S` lines; `//` lines are ignored).
pub fn parse_objects(data: &[u8], path: Option<&Path>, kind: InputKind) -> Result<Vec<ObjectSpec>> {
    if is_json(data) {
        let text = std::str::from_utf8(data).map_err(|e| {
            let (line, column) = end_position(&data[..e.valid_up_to()]);
            Error::parse(kind, path, line, column, "invalid UTF-8")
        })?;
        // Deserialise the shape the first character announces (rather than trying both),
        // so that serde_json reports where and why the data goes wrong.
        let list = if text.trim_start().starts_with('[') {
            serde_json::from_str::<Vec<ObjectSpec>>(text)
                .map_err(|e| json_error(kind, path, text, &e))?
        } else {
            let one = serde_json::from_str::<ObjectSpec>(text)
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
            vec![one]
        };
        if let Some(o) = list.iter().find(|o| o.label.is_empty()) {
            let _ = o;
            return Err(Error::parse(
                kind,
                path,
                1,
                1,
                "an object has an empty label",
            ));
        }
        return Ok(list);
    }
    parse_object_blocks(data, path, kind)
}

fn parse_object_blocks(
    data: &[u8],
    path: Option<&Path>,
    kind: InputKind,
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
        let value = f1.trim_end().to_lowercase();
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
            let v = f2.trim_end();
            let col = line.column_of(f2_off);
            if let Some(inner) = v.strip_prefix('{') {
                let inner = inner.strip_suffix('}').ok_or_else(|| {
                    err(
                        line.number,
                        col,
                        "ingredient list has no closing '}'".into(),
                    )
                })?;
                obj.ingredients = inner.split(',').map(str::to_owned).collect();
            } else if let Some(inner) = v.strip_prefix('[') {
                let inner = inner
                    .strip_suffix(']')
                    .ok_or_else(|| err(line.number, col, "container has no closing ']'".into()))?;
                obj.container = Some(inner.to_owned());
            } else {
                return Err(err(
                    line.number,
                    col,
                    "expected '{ingredients}' or '[container]' in the third field".into(),
                ));
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
    let data = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_objects(&data, Some(path), kind)
}

/// Motion success rates: `motion<TAB>rate` lines.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MotionRates {
    /// In file order; a repeated motion keeps its last rate.
    pub entries: Vec<(String, f64)>,
    map: FxHashMap<String, f64>,
}

impl MotionRates {
    pub fn from_pairs(pairs: impl IntoIterator<Item = (String, f64)>) -> Result<Self> {
        let mut r = Self::default();
        for (m, v) in pairs {
            if !(0.0..=1.0).contains(&v) {
                return Err(Error::Invalid(format!(
                    "rate of '{m}' must be between 0 and 1, not {v}"
                )));
            }
            r.insert(m, v);
        }
        Ok(r)
    }

    fn insert(&mut self, m: String, v: f64) {
        if let Some(e) = self.entries.iter_mut().find(|(k, _)| *k == m) {
            e.1 = v;
        } else {
            self.entries.push((m.clone(), v));
        }
        self.map.insert(m, v);
    }

    pub fn get(&self, motion: &str) -> Option<f64> {
        self.map.get(motion).copied()
    }

    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

pub fn parse_rates(data: &[u8], path: Option<&Path>) -> Result<MotionRates> {
    let kind = InputKind::Motions;
    let mut r = MotionRates::default();
    for line in Lines::new(data, path, kind) {
        let line = line?;
        let t = line.text;
        if t.trim().is_empty() || t.starts_with('#') {
            continue;
        }
        let Some((name, rate)) = t.split_once('\t') else {
            return Err(Error::parse(
                kind,
                path,
                line.number,
                line.column_of(t.len()),
                "expected 'motion<TAB>rate'",
            ));
        };
        // The rate starts right after the TAB (offset taken before trimming the name).
        let rate_off = name.len() + 1;
        let name = name.trim();
        if name.is_empty() {
            return Err(Error::parse(
                kind,
                path,
                line.number,
                1,
                "empty motion name",
            ));
        }
        let col = line.column_of(rate_off);
        let v: f64 = rate.trim().parse().map_err(|_| {
            let shown: String = rate.trim().chars().take(20).collect();
            Error::parse(
                kind,
                path,
                line.number,
                col,
                format!("rate '{shown}' is not a number"),
            )
        })?;
        if !(0.0..=1.0).contains(&v) {
            return Err(Error::parse(
                kind,
                path,
                line.number,
                col,
                format!("rate {v} is not between 0 and 1"),
            ));
        }
        r.insert(name.to_lowercase(), v);
    }
    Ok(r)
}

pub fn load_rates(path: &Path) -> Result<MotionRates> {
    let data = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_rates(&data, Some(path))
}

/// Utensil names, one a line (right-stripped; blank lines and `#` comments skipped).
pub fn parse_utensils(data: &[u8], path: Option<&Path>) -> Result<Vec<String>> {
    let mut out = Vec::new();
    for line in Lines::new(data, path, InputKind::Utensils) {
        let line = line?;
        let t = line.text.trim_end();
        if t.trim().is_empty() || t.starts_with('#') {
            continue;
        }
        if let Some(i) = t.find('\t') {
            return Err(Error::parse(
                InputKind::Utensils,
                path,
                line.number,
                line.column_of(i),
                "a utensil name must not contain a TAB",
            ));
        }
        out.push(t.to_owned());
    }
    Ok(out)
}

pub fn load_utensils(path: &Path) -> Result<Vec<String>> {
    let data = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_utensils(&data, Some(path))
}
