//! FOON text parser: the four dialects of real files (course `O`, lab `O<id>` with flags and
//! CRLF, motion times), streaming over the bytes line by line.

use std::borrow::Cow;
use std::path::Path;

use crate::error::{Error, InputKind, Location, Result, Warning, WarningKind};
use crate::index::{Builder, Foon, NONE, RawObject};

/// A line longer than this is rejected (no real FOON line comes near it).
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// Options for loading.
#[derive(Debug, Clone, Copy, Default)]
pub struct ParseOptions {
    /// Turn every warning into an error.
    pub strict: bool,
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
        let data = data.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(data);
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

/// Lower-case and right-strip, as the course does with the second field of every line.
fn normalise(s: &str) -> Cow<'_, str> {
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

/// What the second field of a line of this kind is, for messages.
fn field_name(kind: LineKind) -> &'static str {
    match kind {
        LineKind::Object => "object label",
        LineKind::State => "state",
        _ => "motion",
    }
}

/// Scratch storage for the objects of the FU being read (flat, reused across FUs).
#[derive(Default)]
struct Block {
    /// Per object: label, container, in-motion flag, and ranges into `states`/`ingredients`.
    objects: Vec<ObjSpan>,
    states: Vec<u32>,
    ingredients: Vec<u32>,
    motion: Option<(u32, u32)>,
    /// Index in `objects` of the first output.
    first_output: usize,
    start_line: u64,
    last_line: u64,
    two_motions: bool,
    has_lines: bool,
    /// A line of this unit was malformed (recovering parse): the unit is dropped.
    poisoned: bool,
}

#[derive(Clone, Copy)]
struct ObjSpan {
    label: u32,
    container: u32,
    in_motion: u8,
    states: (u32, u32),
    ingredients: (u32, u32),
}

impl Block {
    fn clear(&mut self) {
        self.objects.clear();
        self.states.clear();
        self.ingredients.clear();
        self.motion = None;
        self.first_output = 0;
        self.two_motions = false;
        self.has_lines = false;
        self.poisoned = false;
    }

    fn raw(&self, span: &ObjSpan) -> RawObject<'_> {
        RawObject {
            label: span.label,
            states: &self.states[span.states.0 as usize..span.states.1 as usize],
            ingredients: &self.ingredients
                [span.ingredients.0 as usize..span.ingredients.1 as usize],
            container: span.container,
            in_motion: span.in_motion,
        }
    }
}

/// How many lines are read between two calls of a cancel closure.
const CANCEL_EVERY_LINES: u64 = 4096;

/// Parses FOON text into an index.
pub fn parse_foon(data: &[u8], path: Option<&Path>, opts: ParseOptions) -> Result<Foon> {
    parse_foon_cancellable(data, path, opts, &|| false)
}

/// As [`parse_foon`], calling `cancel` every few thousand lines: when it answers true, the
/// parse stops with [`Error::Cancelled`].
pub fn parse_foon_cancellable(
    data: &[u8],
    path: Option<&Path>,
    opts: ParseOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Foon> {
    parse_impl(data, path, opts, None, cancel)
}

/// Parses FOON text, going on after malformed lines: each error is collected and the unit it
/// belongs to is dropped. Used by the linter, which reports every problem at once.
pub fn parse_foon_recovering(
    data: &[u8],
    path: Option<&Path>,
    opts: ParseOptions,
) -> (Foon, Vec<Error>) {
    let mut errors = Vec::new();
    match parse_impl(data, path, opts, Some(&mut errors), &|| false) {
        Ok(f) => (f, errors),
        Err(e) => {
            errors.push(e);
            (Builder::new().finish(path.map(Path::to_path_buf)), errors)
        }
    }
}

fn parse_impl(
    data: &[u8],
    path: Option<&Path>,
    opts: ParseOptions,
    mut errors: Option<&mut Vec<Error>>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Foon> {
    let mut b = Builder::new();
    let mut block = Block::default();
    let mut fields: Vec<(usize, &str)> = Vec::new();
    let err = |line: u64, col: u32, reason: String| {
        Error::parse(InputKind::Foon, path, line, col, reason)
    };

    let finish = |b: &mut Builder, block: &mut Block, end_line: Option<u64>| -> Result<()> {
        if !block.has_lines || block.poisoned {
            block.clear();
            return Ok(());
        }
        let warn_line = end_line.unwrap_or(block.last_line);
        let warning = if block.two_motions {
            None // already reported at the second motion line
        } else if block.motion.is_none() {
            Some((
                WarningKind::NoMotion,
                format!(
                    "functional unit starting at line {} has no motion line",
                    block.start_line
                ),
            ))
        } else if end_line.is_none() {
            Some((
                WarningKind::Unterminated,
                "the last functional unit has no closing '//'".to_owned(),
            ))
        } else {
            None
        };
        if let Some((kind, fault)) = warning {
            let at = Location::new(path, warn_line, 1);
            if let Err(e) = report(b, opts.strict, at, kind, &fault) {
                block.clear();
                return Err(e);
            }
        }
        if let (Some((motion, meta)), false) = (block.motion, block.two_motions) {
            let raws: Vec<RawObject<'_>> = block.objects.iter().map(|s| block.raw(s)).collect();
            let (inputs, outputs) = raws.split_at(block.first_output);
            let _ = b.add_fu(motion, meta, inputs, outputs, block.start_line as u32);
        }
        block.clear();
        Ok(())
    };

    for (n, line) in Lines::new(data, path, InputKind::Foon).enumerate() {
        if n as u64 % CANCEL_EVERY_LINES == 0 && cancel() {
            return Err(Error::Cancelled);
        }
        let ended = std::cell::Cell::new(false);
        let one_line = || -> Result<()> {
            let line = line?;
            let kind = classify(&line, &mut fields).map_err(|(c, r)| err(line.number, c, r))?;
            match kind {
                LineKind::Blank | LineKind::Comment => return Ok(()),
                LineKind::End => {
                    ended.set(true);
                    finish(&mut b, &mut block, Some(line.number))?;
                    return Ok(());
                }
                _ => {}
            }
            if !block.has_lines {
                block.has_lines = true;
                block.start_line = line.number;
            }
            block.last_line = line.number;
            let Some(&(f1_off, f1)) = fields.get(1) else {
                let what = field_name(kind);
                return Err(err(
                    line.number,
                    line.column_of(line.text.len()),
                    format!("missing {what} (no TAB-separated field)"),
                ));
            };
            let value = normalise(f1);
            if value.is_empty() && !(kind == LineKind::State && fields.len() > 2) {
                let what = field_name(kind);
                return Err(err(
                    line.number,
                    line.column_of(f1_off),
                    format!("empty {what}"),
                ));
            }
            match kind {
                LineKind::Object => {
                    let label = b.intern(&value);
                    let in_motion = match fields.get(2).map(|(_, f)| f.trim()) {
                        Some("0") => 0,
                        Some("1") => 1,
                        _ => 2,
                    };
                    let n_states = block.states.len() as u32;
                    let n_ingr = block.ingredients.len() as u32;
                    block.objects.push(ObjSpan {
                        label,
                        container: NONE,
                        in_motion,
                        states: (n_states, n_states),
                        ingredients: (n_ingr, n_ingr),
                    });
                }
                LineKind::State => {
                    let first_of_fu = if block.motion.is_some() {
                        block.first_output
                    } else {
                        0
                    };
                    if block.objects.len() <= first_of_fu {
                        return Err(err(
                            line.number,
                            1,
                            "state line before any object of this functional unit".to_owned(),
                        ));
                    }
                    if let Some(&(f2_off, f2)) = fields.get(2) {
                        let col = line.column_of(f2_off);
                        let at =
                            |byte: usize| Location::new(path, line.number, line.column_of(byte));
                        let obj = block.objects.last().copied();
                        match annotation(f2).map_err(|r| err(line.number, col, r))? {
                            Annotation::Ingredients(inner) => {
                                if let Some(o) = obj.filter(|o| o.ingredients.0 != o.ingredients.1)
                                {
                                    let old: Vec<&str> = block.ingredients
                                        [o.ingredients.0 as usize..o.ingredients.1 as usize]
                                        .iter()
                                        .map(|&i| b.text(i))
                                        .collect();
                                    let fault =
                                        second_list_fault(b.text(o.label), &old.join(","), inner);
                                    report(
                                        &mut b,
                                        opts.strict,
                                        at(f2_off),
                                        WarningKind::TwoIngredientLists,
                                        &fault,
                                    )?;
                                }
                                let start = block.ingredients.len() as u32;
                                let mut offset = f2_off + 1;
                                for ing in inner.split(',') {
                                    if ing.is_empty() {
                                        let fault = empty_ingredient_fault(inner);
                                        report(
                                            &mut b,
                                            opts.strict,
                                            at(offset),
                                            WarningKind::EmptyIngredient,
                                            &fault,
                                        )?;
                                    } else if ing != ing.trim() {
                                        b.note(Warning {
                                            at: at(offset),
                                            kind: WarningKind::SpacedIngredient,
                                            message: format!(
                                                "ingredient '{ing}' has leading or trailing spaces"
                                            ),
                                        });
                                    }
                                    let id = b.intern(ing);
                                    if block.ingredients[start as usize..].contains(&id) {
                                        b.note(Warning {
                                            at: at(offset),
                                            kind: WarningKind::DuplicateIngredient,
                                            message: format!("ingredient '{ing}' is listed twice"),
                                        });
                                    }
                                    block.ingredients.push(id);
                                    offset += ing.len() + 1;
                                }
                                // A later list replaces an earlier one (course behaviour), so the
                                // object's range is the latest list.
                                let end = block.ingredients.len() as u32;
                                if let Some(o) = block.objects.last_mut() {
                                    o.ingredients = (start, end);
                                }
                            }
                            Annotation::Container(inner) => {
                                if let Some(o) = obj.filter(|o| o.container != NONE) {
                                    let fault = second_container_fault(
                                        b.text(o.label),
                                        b.text(o.container),
                                        inner,
                                    );
                                    report(
                                        &mut b,
                                        opts.strict,
                                        at(f2_off),
                                        WarningKind::TwoContainers,
                                        &fault,
                                    )?;
                                }
                                if inner.trim().is_empty() {
                                    b.note(Warning {
                                        at: at(f2_off),
                                        kind: WarningKind::EmptyContainer,
                                        message: format!("empty container '[{inner}]'"),
                                    });
                                }
                                let id = b.intern(inner);
                                if let Some(o) = block.objects.last_mut() {
                                    o.container = id;
                                }
                            }
                        }
                    } else {
                        let id = b.intern(&value);
                        push_state(&mut block, id);
                    }
                }
                LineKind::Motion => {
                    if block.motion.is_some() {
                        if !block.two_motions {
                            block.two_motions = true;
                            let fault = format!(
                                "functional unit starting at line {} has a second motion line",
                                block.start_line
                            );
                            let at = Location::new(path, line.number, 1);
                            report(&mut b, opts.strict, at, WarningKind::TwoMotions, &fault)?;
                        }
                        return Ok(());
                    }
                    let motion = b.intern(&value);
                    let meta = if fields.len() > 2 {
                        let rest: Vec<&str> = fields[2..].iter().map(|(_, f)| f.trim()).collect();
                        b.intern(&rest.join("\t"))
                    } else {
                        NONE
                    };
                    block.motion = Some((motion, meta));
                    block.first_output = block.objects.len();
                }
                _ => {}
            }

            Ok(())
        };
        if let Err(e) = one_line() {
            let Some(errs) = errors.as_deref_mut() else {
                return Err(e);
            };
            errs.push(e);
            if !ended.get() {
                // Drop the unit the bad line belongs to (a `//` error has ended its unit).
                block.has_lines = true;
                block.poisoned = true;
            }
        }
    }
    finish(&mut b, &mut block, None)?;
    Ok(b.finish(path.map(Path::to_path_buf)))
}

/// Reports a fault of `kind` at `at`: in strict mode an error, otherwise a warning (a load
/// warning or a lint note, per [`WarningKind::is_load_warning`]) that ends with what is done.
fn report(
    b: &mut Builder,
    strict: bool,
    at: Location,
    kind: WarningKind,
    fault: &str,
) -> Result<()> {
    if strict {
        return Err(Error::Parse {
            at,
            kind: InputKind::Foon,
            reason: format!("{fault} (strict mode)"),
        });
    }
    let w = Warning::fault(at, kind, fault);
    if kind.is_load_warning() {
        b.warn(w);
    } else {
        b.note(w);
    }
    Ok(())
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

/// Appends a plain state to the last object of the block (its states are the last ones
/// pushed, since an object's lines are contiguous).
fn push_state(block: &mut Block, id: u32) {
    block.states.push(id);
    let end = block.states.len() as u32;
    if let Some(o) = block.objects.last_mut() {
        o.states.1 = end;
    }
}

/// Reads a file and parses it as FOON text.
pub fn load_foon(path: &Path, opts: ParseOptions) -> Result<Foon> {
    load_foon_cancellable(path, opts, &|| false)
}

/// As [`load_foon`], calling `cancel` every few thousand lines (see
/// [`parse_foon_cancellable`]).
pub fn load_foon_cancellable(
    path: &Path,
    opts: ParseOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Foon> {
    if cancel() {
        return Err(Error::Cancelled);
    }
    let data = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_foon_cancellable(&data, Some(path), opts, cancel)
}
