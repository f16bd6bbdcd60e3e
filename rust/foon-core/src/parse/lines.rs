//! The line reader and the line grammar shared by every text input (FOON files, object
//! blocks, motion tables, utensil lists): checked lines ([`Lines`]), what a FOON line is
//! ([`classify`]), and the one grammar of an `S` line's third field ([`annotation`]) with the
//! faults it reports.

use std::borrow::Cow;
use std::path::Path;

use crate::error::{Error, InputKind, Result};

/// A line longer than this is rejected (no real FOON line comes near it).
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The input without a leading UTF-8 byte-order mark (accepted in every input; positions are
/// counted after it).
pub(crate) fn strip_bom(data: &[u8]) -> &[u8] {
    data.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(data)
}

/// One line, checked and split: its number, its text, and the byte offsets of its fields.
pub(crate) struct Line<'a> {
    pub(crate) number: u64,
    pub(crate) text: &'a str,
}

impl Line<'_> {
    /// 1-based character column of byte offset `byte` in the line.
    pub(crate) fn column_of(&self, byte: usize) -> u32 {
        let byte = byte.min(self.text.len());
        self.text
            .get(..byte)
            .map_or(1, |s| s.chars().count() as u32 + 1)
    }
}

/// Iterates over the lines of `data`, checking size, NUL bytes and UTF-8; strips `\r`.
/// UTF-8 and NUL bytes are checked for the whole input at once; lines are then slices of the
/// valid text, and the first fault is reported at its own line and column.
pub(crate) struct Lines<'a> {
    /// The input up to its first fault (all of it for a good file).
    text: &'a str,
    pos: usize,
    number: u64,
    path: Option<&'a Path>,
    kind: InputKind,
    /// What the first fault is, when `text` stops before the end of the input.
    fault: Option<&'static str>,
    done: bool,
}

impl<'a> Lines<'a> {
    pub(crate) fn new(data: &'a [u8], path: Option<&'a Path>, kind: InputKind) -> Self {
        // A UTF-8 byte-order mark at the start is not part of the first line.
        Self::part(strip_bom(data), path, kind)
    }

    /// The lines of a part of an input that starts at a line boundary (no byte-order mark is
    /// looked for), numbered from 1 within the part. A part that ends at a line end gives the
    /// same lines and faults as the same bytes inside the whole input, since a line feed is
    /// never inside a UTF-8 sequence.
    pub(crate) fn part(data: &'a [u8], path: Option<&'a Path>, kind: InputKind) -> Self {
        let (valid, bad_utf8) = match std::str::from_utf8(data) {
            Ok(t) => (t, false),
            Err(e) => (
                std::str::from_utf8(&data[..e.valid_up_to()]).unwrap_or(""),
                true,
            ),
        };
        let (text, fault) = match memchr::memchr(0, valid.as_bytes()) {
            Some(i) => (&valid[..i], Some("NUL byte")),
            None => (valid, bad_utf8.then_some("invalid UTF-8")),
        };
        Self {
            text,
            pos: 0,
            number: 0,
            path,
            kind,
            fault,
            done: false,
        }
    }

    /// How many lines have been read.
    pub(crate) fn read_count(&self) -> u64 {
        self.number
    }

    fn error(&self, line: u64, column: u32, reason: impl Into<String>) -> Error {
        Error::parse(self.kind, self.path, line, column, reason)
    }

    fn line(&mut self, raw: &'a str) -> Result<Line<'a>> {
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
        if raw.len() > MAX_LINE_BYTES {
            self.done = true;
            return Err(self.error(
                self.number,
                1,
                format!(
                    "line is {} bytes long (the limit is {MAX_LINE_BYTES})",
                    raw.len()
                ),
            ));
        }
        Ok(Line {
            number: self.number,
            text: raw,
        })
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = Result<Line<'a>>;

    fn next(&mut self) -> Option<Self::Item> {
        let text = self.text;
        if self.done || (self.pos >= text.len() && self.fault.is_none()) {
            return None;
        }
        let rest = &text[self.pos..];
        self.number += 1;
        let Some(end) = memchr::memchr(b'\n', rest.as_bytes()) else {
            self.done = true;
            if let Some(what) = self.fault {
                // The fault is on this line, right after `rest`.
                let col = rest.chars().count() as u32 + 1;
                return Some(Err(self.error(self.number, col, what)));
            }
            return Some(self.line(rest));
        };
        self.pos += end + 1;
        Some(self.line(&rest[..end]))
    }
}

/// Lower-case and right-strip, as the course does with the second field of every line
/// (FOON files and object blocks alike).
pub(crate) fn normalise(s: &str) -> Cow<'_, str> {
    let t = s.trim_end();
    if t.bytes().any(|b| b.is_ascii_uppercase() || b >= 0x80) {
        Cow::Owned(t.to_lowercase())
    } else {
        Cow::Borrowed(t)
    }
}

/// What a line is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LineKind {
    Blank,
    Comment,
    End,
    Object,
    State,
    Motion,
}

/// The fields of an `O`/`S`/`M` line: `(byte offset, text)` for each, trailing empty fields
/// dropped. `fields[0]` is the kind with its id digits.
pub(crate) fn classify<'a>(
    line: &Line<'a>,
    fields: &mut Vec<(usize, &'a str)>,
) -> std::result::Result<LineKind, (u32, String)> {
    let t = line.text;
    if t.trim().is_empty() {
        return Ok(LineKind::Blank);
    }
    if t.starts_with('#') {
        return Ok(LineKind::Comment);
    }
    if t.starts_with("//") {
        return Ok(LineKind::End);
    }
    fields.clear();
    let mut start = 0;
    for (i, b) in t.bytes().enumerate() {
        if b == b'\t' {
            fields.push((start, &t[start..i]));
            start = i + 1;
        }
    }
    fields.push((start, &t[start..]));
    // Trailing empty fields are ignored, but the second field always stays so that an empty
    // one is reported where it is.
    while fields.len() > 2 && fields.last().is_some_and(|(_, f)| f.trim().is_empty()) {
        fields.pop();
    }
    let head = fields[0].1;
    let kind = match head.as_bytes().first() {
        Some(b'O') => LineKind::Object,
        Some(b'S') => LineKind::State,
        Some(b'M') => LineKind::Motion,
        _ => LineKind::Blank,
    };
    if kind == LineKind::Blank || !head[1..].bytes().all(|b| b.is_ascii_digit()) {
        let shown: String = head.chars().take(20).collect();
        return Err((
            1,
            format!("unknown line kind '{shown}' (expected O, S, M, // or #, then a TAB)"),
        ));
    }
    Ok(kind)
}

/// The third field of an `S` line: an ingredient list `{a,b}` or a container `[c]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Annotation<'a> {
    /// The text between the braces; its items are split on `,` and nothing is stripped.
    Ingredients(&'a str),
    /// The text between the brackets.
    Container(&'a str),
}

/// Reads the third field of an `S` line (right-stripped), the one grammar of FOON files and
/// of object lists. The error is a reason; its column is the field's.
pub(crate) fn annotation(field: &str) -> std::result::Result<Annotation<'_>, String> {
    let v = field.trim_end();
    if let Some(inner) = v.strip_prefix('{') {
        inner
            .strip_suffix('}')
            .map(Annotation::Ingredients)
            .ok_or_else(|| "ingredient list has no closing '}'".to_owned())
    } else if let Some(inner) = v.strip_prefix('[') {
        inner
            .strip_suffix(']')
            .map(Annotation::Container)
            .ok_or_else(|| "container has no closing ']'".to_owned())
    } else {
        let shown: String = v.chars().take(30).collect();
        Err(format!(
            "expected '{{ingredients}}' or '[container]' in the third field, found '{shown}'"
        ))
    }
}

/// The fault of a second container line on one object (the last one wins).
pub(crate) fn second_container_fault(label: &str, old: &str, new: &str) -> String {
    format!("object '{label}' has a second container: [{new}] after [{old}]")
}

/// The fault of a second ingredient list on one object (the last one wins).
pub(crate) fn second_list_fault(label: &str, old: &str, new: &str) -> String {
    format!("object '{label}' has a second ingredient list: {{{new}}} after {{{old}}}")
}

/// The fault of an empty item in an ingredient list (kept, as the course does).
pub(crate) fn empty_ingredient_fault(list: &str) -> String {
    format!("empty ingredient name in '{{{list}}}'")
}
