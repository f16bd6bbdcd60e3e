//! FOONs in JSON: the lab's dialect, a list of functional units
//! `{"input_nodes": [...], "motion_node": "...", "output_nodes": [...]}` whose nodes are
//! `{"label", "states", "ingredients", "container"}`, with the two optional fields that
//! `foon`'s own JSON adds so that nothing of the text form is lost: `"in_motion"` (0 or 1) on
//! a node and `"motion_meta"` (the extra fields of the motion line, such as times) on a unit.
//!
//! Strings follow the text rules: labels, states and motions are lower-cased and
//! right-stripped; ingredients and containers are kept as written. What FOON text cannot
//! hold is refused (NUL, a line feed, a TAB outside motion metadata, a `,` in an
//! ingredient), so every JSON FOON can be written as text; everything text holds loads. Errors name the file, line and
//! column (of the offending value; for a missing field, of the object that lacks it).

use std::path::Path;

use serde::Deserialize;
use serde::de::IgnoredAny;

use super::ParseOptions;
use super::foon::report;
use super::lines::{empty_ingredient_fault, normalise, strip_bom};
use crate::error::{Error, InputKind, Location, Result, Warning, WarningKind};
use crate::index::{Builder, NONE, RawObject};

/// Whether an input is JSON: its first non-blank byte (after a byte-order mark) is `[` or
/// `{`. FOON text never starts so.
pub(crate) fn is_json(data: &[u8]) -> bool {
    matches!(
        strip_bom(data).iter().find(|b| !b.is_ascii_whitespace()),
        Some(b'[' | b'{')
    )
}

/// How many units are read between two calls of a cancel closure.
const CANCEL_EVERY_UNITS: usize = 256;

/// A functional unit as written in JSON.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JsonFu {
    input_nodes: Vec<JsonNode>,
    #[serde(deserialize_with = "motion")]
    motion_node: String,
    output_nodes: Vec<JsonNode>,
    #[serde(default, deserialize_with = "meta")]
    motion_meta: Option<String>,
}

/// A node: an object as written in one unit.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JsonNode {
    #[serde(deserialize_with = "label")]
    label: String,
    #[serde(default, deserialize_with = "states")]
    states: Vec<String>,
    #[serde(default, deserialize_with = "ingredients")]
    ingredients: Vec<String>,
    #[serde(default, deserialize_with = "container")]
    container: Option<String>,
    #[serde(default = "flag_not_given", deserialize_with = "in_motion")]
    in_motion: u8,
}

fn flag_not_given() -> u8 {
    2
}

type De<T, E> = std::result::Result<T, E>;

/// Why text cannot be a field of FOON text, if it cannot (`tab_ok` for motion metadata,
/// whose fields are TAB-separated and which ends its line). FOON text holds every character
/// but NUL, the line feed and (between fields) the TAB, and drops a carriage return that
/// ends a line: any other control character loads from text, so it loads from JSON too
/// (what `foon` writes as JSON always loads back).
fn text_fault(s: &str, what: &str, tab_ok: bool) -> Option<String> {
    let cr_at_end = tab_ok && s.ends_with('\r');
    s.chars()
        .find(|&c| match c {
            '\0' | '\n' => true,
            '\t' => !tab_ok,
            '\r' => cr_at_end,
            _ => false,
        })
        .map(|c| {
            format!(
                "{what} '{}' holds the control character {c:?}",
                s.escape_debug()
            )
        })
}

fn custom<E: serde::de::Error>(msg: impl std::fmt::Display) -> E {
    E::custom(msg)
}

/// A label, state or motion: lower-cased and right-stripped, not empty.
fn name<'de, D: serde::Deserializer<'de>>(d: D, what: &str) -> De<String, D::Error> {
    let s = String::deserialize(d)?;
    if let Some(f) = text_fault(&s, what, false) {
        return Err(custom(f));
    }
    let v = normalise(&s).into_owned();
    if v.is_empty() {
        return Err(custom(format!("empty {what}")));
    }
    Ok(v)
}

fn label<'de, D: serde::Deserializer<'de>>(d: D) -> De<String, D::Error> {
    name(d, "object label")
}

fn motion<'de, D: serde::Deserializer<'de>>(d: D) -> De<String, D::Error> {
    name(d, "motion")
}

fn meta<'de, D: serde::Deserializer<'de>>(d: D) -> De<Option<String>, D::Error> {
    let s = Option::<String>::deserialize(d)?;
    if let Some(f) = s
        .as_deref()
        .and_then(|s| text_fault(s, "motion_meta", true))
    {
        return Err(custom(f));
    }
    Ok(s.filter(|s| !s.trim().is_empty()))
}

fn states<'de, D: serde::Deserializer<'de>>(d: D) -> De<Vec<String>, D::Error> {
    let v = Option::<Vec<String>>::deserialize(d)?.unwrap_or_default();
    v.iter()
        .map(|s| {
            if let Some(f) = text_fault(s, "state", false) {
                return Err(custom(f));
            }
            let n = normalise(s).into_owned();
            if n.is_empty() {
                return Err(custom("an object has an empty state"));
            }
            Ok(n)
        })
        .collect()
}

fn ingredients<'de, D: serde::Deserializer<'de>>(d: D) -> De<Vec<String>, D::Error> {
    let v = Option::<Vec<String>>::deserialize(d)?.unwrap_or_default();
    for s in &v {
        if let Some(f) = text_fault(s, "ingredient", false) {
            return Err(custom(f));
        }
        if s.contains(',') {
            return Err(custom(format!(
                "ingredient '{s}' holds a ',' (FOON text separates ingredients with it)"
            )));
        }
    }
    Ok(v)
}

fn container<'de, D: serde::Deserializer<'de>>(d: D) -> De<Option<String>, D::Error> {
    let v = Option::<String>::deserialize(d)?;
    if let Some(f) = v.as_deref().and_then(|s| text_fault(s, "container", false)) {
        return Err(custom(f));
    }
    Ok(v)
}

fn in_motion<'de, D: serde::Deserializer<'de>>(d: D) -> De<u8, D::Error> {
    match Option::<u64>::deserialize(d)? {
        None => Ok(2),
        Some(v @ (0 | 1)) => Ok(v as u8),
        Some(v) => Err(custom(format!("in_motion is 0 or 1, not {v}"))),
    }
}

/// Positions in the text: 1-based line and character column of a byte offset.
struct Text<'a> {
    src: &'a str,
    path: Option<&'a Path>,
    /// Line of `line_at` (counted incrementally for the units' start lines).
    line: u64,
    line_at: usize,
}

impl Text<'_> {
    fn position(&self, off: usize) -> (u64, u32) {
        let mut off = off.min(self.src.len());
        while !self.src.is_char_boundary(off) {
            off -= 1;
        }
        let before = &self.src[..off];
        let line = memchr::memchr_iter(b'\n', before.as_bytes()).count() as u64 + 1;
        let start = before.rfind('\n').map_or(0, |i| i + 1);
        (line, before[start..].chars().count() as u32 + 1)
    }

    fn at(&self, off: usize) -> Location {
        let (line, col) = self.position(off);
        Location::new(self.path, line, col)
    }

    fn error(&self, off: usize, reason: impl Into<String>) -> Error {
        Error::Parse {
            at: self.at(off),
            kind: InputKind::Foon,
            reason: reason.into(),
        }
    }

    /// The line of `off`, for offsets that only grow.
    fn line_of(&mut self, off: usize) -> u64 {
        let from = self.line_at.min(off);
        self.line += memchr::memchr_iter(b'\n', &self.src.as_bytes()[from..off]).count() as u64;
        self.line_at = off;
        self.line
    }

    /// The error of `serde_json` `e`, met reading the value that starts at `start`.
    fn serde_error(&self, start: usize, e: &serde_json::Error) -> Error {
        let slice = &self.src[start..];
        let line_start = if e.line() <= 1 {
            0
        } else {
            memchr::memchr_iter(b'\n', slice.as_bytes())
                .nth(e.line() - 2)
                .map_or(slice.len(), |i| i + 1)
        };
        let mut off = start + line_start + e.column().saturating_sub(1);
        let msg = e.to_string();
        // serde_json appends " at line L column C"; the location is given separately.
        let reason = msg
            .rsplit_once(" at line ")
            .map_or(msg.as_str(), |(r, _)| r);
        if reason.starts_with("missing field") {
            off = enclosing_object(self.src, start, off);
        }
        self.error(off, reason)
    }
}

fn skip_ws(text: &str, mut i: usize) -> usize {
    let b = text.as_bytes();
    while i < b.len() && matches!(b[i], b' ' | b'\t' | b'\n' | b'\r') {
        i += 1;
    }
    i
}

/// Walks the JSON text from `from` to `to` and calls `f(offset, byte, depth)` for each
/// bracket outside strings (the depth outside it: counted before an opening one, after a
/// closing one); stops early when `f` answers true.
fn walk(text: &str, from: usize, to: usize, mut f: impl FnMut(usize, u8, usize) -> bool) {
    let b = text.as_bytes();
    let mut depth = 0usize;
    let mut i = from;
    while i < to.min(b.len()) {
        match b[i] {
            b'"' => {
                i += 1;
                while i < b.len() && b[i] != b'"' {
                    i += if b[i] == b'\\' { 2 } else { 1 };
                }
            }
            c @ (b'{' | b'[') => {
                if f(i, c, depth) {
                    return;
                }
                depth += 1;
            }
            c @ (b'}' | b']') => {
                depth = depth.saturating_sub(1);
                if f(i, c, depth) {
                    return;
                }
            }
            _ => {}
        }
        i += 1;
    }
}

/// The start of the innermost object open at `at` (an error inside it), scanning from
/// `from`; `from` itself when there is none.
fn enclosing_object(text: &str, from: usize, at: usize) -> usize {
    let mut stack: Vec<(usize, u8)> = Vec::new();
    // The closing brace at `at` belongs to the object that lacks the field.
    walk(text, from, at, |i, c, _| {
        match c {
            b'{' | b'[' => stack.push((i, c)),
            _ => {
                stack.pop();
            }
        }
        false
    });
    stack
        .iter()
        .rev()
        .find(|(_, c)| *c == b'{')
        .map_or(from, |&(i, _)| i)
}

/// The start of node `k` of a unit (inputs then outputs, counted together) whose JSON text
/// starts at `from`: the `k`-th object two levels inside the unit.
fn node_start(text: &str, from: usize, k: usize) -> usize {
    let mut seen = 0;
    let mut found = from;
    walk(text, from, text.len(), |i, c, depth| {
        if c == b'}' && depth == 0 {
            return true; // the end of the unit
        }
        if c == b'{' && depth == 2 {
            if seen == k {
                found = i;
                return true;
            }
            seen += 1;
        }
        false
    });
    found
}

/// Parses a JSON FOON (see the module documentation) into `b` (one source): errors are collected
/// in `errors` when it is given (a unit with a bad value is dropped and reading goes on; a
/// syntax error ends the reading), else the first one is returned.
pub(super) fn parse_impl(
    b: &mut Builder,
    data: &[u8],
    path: Option<&Path>,
    opts: ParseOptions,
    mut errors: Option<&mut Vec<Error>>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<()> {
    let data = strip_bom(data);
    let text = match std::str::from_utf8(data) {
        Ok(t) => t,
        Err(e) => {
            let valid = std::str::from_utf8(&data[..e.valid_up_to()]).unwrap_or_default();
            let t = Text {
                src: valid,
                path,
                line: 1,
                line_at: 0,
            };
            return Err(t.error(valid.len(), "invalid UTF-8"));
        }
    };
    let mut t = Text {
        src: text,
        path,
        line: 1,
        line_at: 0,
    };
    match read_units(&mut t, b, opts, errors.as_deref_mut(), cancel) {
        Ok(()) => {}
        Err(Error::Cancelled) => return Err(Error::Cancelled),
        Err(e) => match errors {
            Some(errs) => errs.push(e),
            None => return Err(e),
        },
    }
    Ok(())
}

fn read_units(
    t: &mut Text<'_>,
    b: &mut Builder,
    opts: ParseOptions,
    mut errors: Option<&mut Vec<Error>>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<()> {
    let text = t.src;
    let bytes = text.as_bytes();
    let mut i = skip_ws(text, 0);
    match bytes.get(i) {
        Some(b'[') => i += 1,
        Some(b'{') => {
            return Err(t.error(
                i,
                "a JSON FOON is a list of functional units ([{\"input_nodes\", \
                 \"motion_node\", \"output_nodes\"}, ...]), not one object",
            ));
        }
        _ => return Err(t.error(i, "expected '[' (a JSON list of functional units)")),
    }
    let mut n = 0usize;
    loop {
        i = skip_ws(text, i);
        match bytes.get(i) {
            None => {
                return Err(t.error(i, "the list of functional units has no closing ']'"));
            }
            Some(b']') => {
                i += 1;
                break;
            }
            Some(_) if n == 0 => {}
            Some(b',') => {
                i = skip_ws(text, i + 1);
                if bytes.get(i) == Some(&b']') {
                    return Err(t.error(i, "trailing comma"));
                }
            }
            Some(_) => {
                return Err(t.error(i, "expected ',' or ']' after a functional unit"));
            }
        }
        if n % CANCEL_EVERY_UNITS == 0 && cancel() {
            return Err(Error::Cancelled);
        }
        let start = i;
        if bytes.get(start) != Some(&b'{') && bytes.get(start).is_some() {
            // serde_json would take a list of the field values as a unit.
            let e = t.error(
                start,
                "expected a functional unit (a JSON object with \"input_nodes\", \
                 \"motion_node\" and \"output_nodes\")",
            );
            i = skip_value(t, start, e, errors.as_deref_mut())?;
            n += 1;
            continue;
        }
        let mut stream = serde_json::Deserializer::from_str(&text[start..]).into_iter::<JsonFu>();
        match stream.next() {
            Some(Ok(fu)) => {
                i = start + stream.byte_offset();
                let line = t.line_of(start);
                add_unit(t, b, opts, &fu, start, line)?;
            }
            Some(Err(e)) if e.is_data() => {
                let err = t.serde_error(start, &e);
                i = skip_value(t, start, err, errors.as_deref_mut())?;
            }
            Some(Err(e)) => return Err(t.serde_error(start, &e)),
            None => return Err(t.error(i, "the list of functional units has no closing ']'")),
        }
        n += 1;
    }
    let end = skip_ws(text, i);
    if end < text.len() {
        return Err(t.error(end, "unexpected text after the list of functional units"));
    }
    Ok(())
}

/// After a bad unit at `start`: records `err` and returns the end of the unit when errors
/// are collected (and the unit is well-formed JSON), else fails with `err`.
fn skip_value(
    t: &Text<'_>,
    start: usize,
    err: Error,
    errors: Option<&mut Vec<Error>>,
) -> Result<usize> {
    let Some(errs) = errors else {
        return Err(err);
    };
    let mut stream = serde_json::Deserializer::from_str(&t.src[start..]).into_iter::<IgnoredAny>();
    match stream.next() {
        Some(Ok(_)) => {
            errs.push(err);
            Ok(start + stream.byte_offset())
        }
        Some(Err(e)) => {
            errs.push(err);
            Err(t.serde_error(start, &e))
        }
        None => Err(err),
    }
}

/// Adds one unit to the builder, with the notes and warnings of its ingredient lists and
/// containers (at the node they concern).
fn add_unit(
    t: &Text<'_>,
    b: &mut Builder,
    opts: ParseOptions,
    fu: &JsonFu,
    start: usize,
    line: u64,
) -> Result<()> {
    let nodes = || fu.input_nodes.iter().chain(&fu.output_nodes);
    let mut ids: Vec<u32> = Vec::new();
    let mut spans: Vec<(u32, u32, u8, usize, usize, usize)> = Vec::new();
    for (k, node) in nodes().enumerate() {
        let at = || t.at(node_start(t.src, start, k));
        let label = b.intern(&node.label);
        let s0 = ids.len();
        for s in &node.states {
            ids.push(b.intern(s));
        }
        let i0 = ids.len();
        for (j, ing) in node.ingredients.iter().enumerate() {
            if ing.is_empty() {
                let fault = empty_ingredient_fault(&node.ingredients.join(","));
                report(b, opts.strict, at(), WarningKind::EmptyIngredient, &fault)?;
            } else if ing != ing.trim() {
                b.note(Warning {
                    at: at(),
                    kind: WarningKind::SpacedIngredient,
                    message: format!("ingredient '{ing}' has leading or trailing spaces"),
                });
            }
            if node.ingredients[..j].contains(ing) {
                b.note(Warning {
                    at: at(),
                    kind: WarningKind::DuplicateIngredient,
                    message: format!("ingredient '{ing}' is listed twice"),
                });
            }
            ids.push(b.intern(ing));
        }
        let container = match &node.container {
            Some(c) => {
                if c.trim().is_empty() {
                    b.note(Warning {
                        at: at(),
                        kind: WarningKind::EmptyContainer,
                        message: format!("empty container '[{c}]'"),
                    });
                }
                b.intern(c)
            }
            None => NONE,
        };
        spans.push((label, container, node.in_motion, s0, i0, ids.len()));
    }
    let raws: Vec<RawObject<'_>> = spans
        .iter()
        .map(|&(label, container, in_motion, s0, i0, end)| RawObject {
            label,
            states: &ids[s0..i0],
            ingredients: &ids[i0..end],
            container,
            in_motion,
        })
        .collect();
    let (inputs, outputs) = raws.split_at(fu.input_nodes.len());
    let motion = b.intern(&fu.motion_node);
    let meta = fu.motion_meta.as_deref().map_or(NONE, |m| b.intern(m));
    let line = super::line_u32(line)?;
    let _ = b.add_fu(motion, meta, inputs, outputs, line);
    Ok(())
}
