//! Companion files: kitchens (JSON or FOON object blocks), goals (JSON or object blocks),
//! motion success rates and utensil lists.

use std::path::Path;

use rustc_hash::FxHashMap;

use crate::error::{Error, InputKind, Location, Result, Warning, WarningKind};
pub use crate::model::ObjectSpec;
use crate::model::check_rate;
use crate::parse::{
    Annotation, LineKind, Lines, annotation, classify, empty_ingredient_fault,
    second_container_fault, second_list_fault,
};

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

/// The input without a leading UTF-8 byte-order mark (accepted in every input, as in FOON
/// files; positions are counted after it).
fn strip_bom(data: &[u8]) -> &[u8] {
    data.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(data)
}

fn is_json(data: &[u8]) -> bool {
    matches!(
        strip_bom(data).iter().find(|b| !b.is_ascii_whitespace()),
        Some(b'[' | b'{')
    )
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
    if !is_json(data) {
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
    let data = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_objects(&data, Some(path), kind)
}

/// Motion success rates: `motion<TAB>rate` lines.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MotionRates {
    /// In file order, each motion once.
    pub entries: Vec<(String, f64)>,
    /// Position of each motion in `entries`.
    map: FxHashMap<String, usize>,
}

impl MotionRates {
    /// Rates from `(motion, rate)` pairs. Every rate is checked ([`check_rate`]); the same
    /// motion twice with the same rate is kept once, with two different rates it is an error.
    pub fn from_pairs(pairs: impl IntoIterator<Item = (String, f64)>) -> Result<Self> {
        let mut r = Self::default();
        for (m, v) in pairs {
            check_rate(Some(&m), v)?;
            if let Err(old) = r.insert(m, v) {
                let (m, first) = &r.entries[old];
                return Err(Error::Invalid(format!(
                    "motion '{m}' has two rates: {first} and {v}"
                )));
            }
        }
        Ok(r)
    }

    /// Adds a rate; a motion already given with another rate is left as it is and the
    /// position of its entry is returned.
    // The same number written twice is the same rate: exact equality is meant.
    #[allow(clippy::float_cmp)]
    fn insert(&mut self, m: String, v: f64) -> std::result::Result<(), usize> {
        if let Some(&i) = self.map.get(&m) {
            return if self.entries[i].1 == v {
                Ok(())
            } else {
                Err(i)
            };
        }
        self.map.insert(m.clone(), self.entries.len());
        self.entries.push((m, v));
        Ok(())
    }

    pub fn get(&self, motion: &str) -> Option<f64> {
        self.map.get(motion).map(|&i| self.entries[i].1)
    }

    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

/// Parses a motion table: `motion<TAB>rate` lines (blank lines and `#` comments skipped).
/// Motion names are trimmed and lower-cased; rates are numbers between 0 and 1. A motion
/// listed twice with the same rate is kept once; with two different rates it is an error
/// naming both lines.
pub fn parse_rates(data: &[u8], path: Option<&Path>) -> Result<MotionRates> {
    parse_rates_impl(data, path, None)
}

/// Parses a motion table, going on after bad lines: each error is collected, with whether it
/// is a motion with two rates, and its line is skipped (of two rates, the first is kept).
/// Used by the linter.
pub(crate) fn parse_rates_recovering(
    data: &[u8],
    path: Option<&Path>,
) -> (MotionRates, Vec<(Error, bool)>) {
    let mut errors = Vec::new();
    match parse_rates_impl(data, path, Some(&mut errors)) {
        Ok(r) => (r, errors),
        Err(e) => {
            errors.push((e, false));
            (MotionRates::default(), errors)
        }
    }
}

fn parse_rates_impl(
    data: &[u8],
    path: Option<&Path>,
    mut errors: Option<&mut Vec<(Error, bool)>>,
) -> Result<MotionRates> {
    let kind = InputKind::Motions;
    let mut r = MotionRates::default();
    // The line of each entry of `r`.
    let mut lines: Vec<u64> = Vec::new();
    for line in Lines::new(data, path, kind) {
        let mut two_rates = false;
        let one = || -> Result<()> {
            let line = line?;
            let t = line.text;
            if t.trim().is_empty() || t.starts_with('#') {
                return Ok(());
            }
            let err = |col: u32, reason: String| Error::parse(kind, path, line.number, col, reason);
            let Some((name, rate)) = t.split_once('\t') else {
                return Err(err(
                    line.column_of(t.len()),
                    "expected 'motion<TAB>rate'".into(),
                ));
            };
            // The rate starts right after the TAB (offset taken before trimming the name).
            let col = line.column_of(name.len() + 1);
            let name = name.trim();
            if name.is_empty() {
                return Err(err(1, "empty motion name".into()));
            }
            let v: f64 = rate.trim().parse().map_err(|_| {
                let shown: String = rate.trim().chars().take(20).collect();
                err(col, format!("rate '{shown}' is not a number"))
            })?;
            let name = name.to_lowercase();
            check_rate(Some(&name), v).map_err(|e| err(col, e.to_string()))?;
            match r.insert(name, v) {
                Ok(()) => {
                    lines.resize(r.len(), line.number);
                    Ok(())
                }
                Err(i) => {
                    two_rates = true;
                    let (m, first) = &r.entries[i];
                    Err(err(
                        col,
                        format!(
                            "motion '{m}' has two rates: {first} (line {}) and {v} (line {})",
                            lines[i], line.number
                        ),
                    ))
                }
            }
        };
        if let Err(e) = one() {
            // (After an error that stops reading, a NUL byte or invalid UTF-8, the lines end.)
            match errors.as_deref_mut() {
                Some(errs) => errs.push((e, two_rates)),
                None => return Err(e),
            }
        }
    }
    Ok(r)
}

pub fn load_rates(path: &Path) -> Result<MotionRates> {
    let data = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_rates(&data, Some(path))
}

/// Utensil names, one a line (right-stripped; blank lines and `#` comments skipped). A
/// name contains no TAB and does not start with a JSON bracket or quote (`[`, `]`, `{`, `}`,
/// `"`), so that a JSON or FOON file given as a utensil list is an error, not a list of odd
/// names.
pub fn parse_utensils(data: &[u8], path: Option<&Path>) -> Result<Vec<String>> {
    let mut out = Vec::new();
    for line in Lines::new(data, path, InputKind::Utensils) {
        let line = line?;
        let t = line.text.trim_end();
        if t.trim().is_empty() || t.starts_with('#') {
            continue;
        }
        let err = |byte: usize, reason: String| {
            Error::parse(
                InputKind::Utensils,
                path,
                line.number,
                line.column_of(byte),
                reason,
            )
        };
        if let Some(i) = t.find('\t') {
            return Err(err(
                i,
                "a utensil name must not contain a TAB (a utensil list has one name a line)".into(),
            ));
        }
        let start = t.len() - t.trim_start().len();
        if let Some(c) = t[start..].chars().next().filter(|c| "[]{}\"".contains(*c)) {
            return Err(err(
                start,
                format!(
                    "a utensil name must not start with '{c}' (this looks like JSON; a \
                     utensil list has one name a line)"
                ),
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
