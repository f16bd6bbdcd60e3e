//! The FOON text parser: the four dialects of real files (course `O`, lab `O<id>` with flags
//! and CRLF, motion times), read in chunks of whole lines on the thread pool (each line read
//! into what it is, with chunk-local string ids) and fed to a [`Builder`] in input order by
//! one thread that holds the state of the unit being read, so that the index, its warnings and
//! its errors are the same for any chunking.

use std::borrow::Cow;
use std::path::Path;

use hashbrown::HashTable;
use rayon::prelude::*;

use super::ParseOptions;
use super::lines::{
    Annotation, Line, LineKind, Lines, annotation, classify, empty_ingredient_fault, normalise,
    second_container_fault, second_list_fault,
};
use crate::error::{Error, InputKind, Location, Result, Warning, WarningKind};
use crate::index::{Builder, NONE, RawObject, hash};
use crate::progress::Progress;

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
pub(super) const CANCEL_EVERY_LINES: u64 = 4096;

/// Bytes per chunk read on one thread when the caller sets none (chunks end at line ends).
pub(super) const DEFAULT_CHUNK_BYTES: usize = 256 << 10;

/// A string interner local to one chunk: a chunk's lines are read on their own thread with
/// local ids, and the index interns each distinct string of a chunk once, in reading order,
/// with the hash computed here.
#[derive(Default)]
struct Local {
    text: String,
    ends: Vec<u32>,
    /// The index hash of each string ([`hash::hash_str`]).
    hashes: Vec<u32>,
    table: HashTable<u32>,
}

/// The local table's hash of a string of index hash `h` (spread over 64 bits).
fn spread(h: u32) -> u64 {
    u64::from(h).wrapping_mul(0x9e37_79b9_7f4a_7c15)
}

impl Local {
    fn text(&self, id: u32) -> &str {
        let i = id as usize;
        let start = if i == 0 { 0 } else { self.ends[i - 1] as usize };
        &self.text[start..self.ends[i] as usize]
    }

    fn intern(&mut self, s: &str) -> u32 {
        let ih = hash::hash_str(s);
        let h = spread(ih);
        let (text, ends) = (&self.text, &self.ends);
        let at = |id: u32| {
            let i = id as usize;
            let start = if i == 0 { 0 } else { ends[i - 1] as usize };
            &text[start..ends[i] as usize]
        };
        if let Some(&id) = self.table.find(h, |&id| at(id) == s) {
            return id;
        }
        let id = self.ends.len() as u32;
        self.text.push_str(s);
        self.ends.push(self.text.len() as u32);
        self.hashes.push(ih);
        let hashes = &self.hashes;
        self.table
            .insert_unique(h, id, |&id| spread(hashes[id as usize]));
        id
    }
}

/// One item of an ingredient list, read.
#[derive(Clone, Copy)]
struct Ing {
    /// Local id of the item as written.
    id: u32,
    /// Byte offset of the item in its line.
    offset: u32,
}

/// What the third field of an `S` line says, read.
enum StateOp {
    /// A plain state (local id of the normalised second field).
    Plain(u32),
    /// A malformed third field: column and reason.
    BadAnnotation(Box<(u32, String)>),
    /// An ingredient list: byte offset of the field, byte range of the text between the
    /// braces (in the line), and the range of its items in [`Chunk::ings`].
    Ingredients {
        f2_off: u32,
        inner: (u32, u32),
        items: (u32, u32),
    },
    /// A container: byte offset of the field and local id of the text between the brackets.
    Container { f2_off: u32, inner: u32 },
}

/// What one line is, read without the index (so on any thread).
enum Op {
    /// `//`.
    End,
    /// A line that is not a FOON line (before it counts as a line of the unit).
    Bad(Box<Fault>),
    /// A fault that ends the input (invalid UTF-8, a NUL byte, a line too long).
    Stop(Box<Fault>),
    /// An `O`/`S`/`M` line whose second field is missing or empty.
    Field(Box<Fault>),
    Object {
        label: u32,
        in_motion: u8,
    },
    State(StateOp),
    Motion {
        motion: u32,
        meta: u32,
    },
}

/// A line that does something: its number within the chunk, where it starts in the chunk (for
/// the columns of rare messages), and what it is.
struct LineOp {
    number: u32,
    start: u32,
    op: Op,
}

// A chunk's lines are held until they are fed: keep each small.
const _: () = assert!(std::mem::size_of::<LineOp>() <= 32);

/// A chunk of lines read on its own: every line that does something, the ingredient items,
/// the chunk's strings, and how many lines and bytes it spans.
#[derive(Default)]
struct Chunk {
    ops: Vec<LineOp>,
    ings: Vec<Ing>,
    local: Local,
    lines: u64,
    bytes: u64,
}

/// Reads the lines of `data` (a part of the input that starts at a line start and ends at a
/// line end or at the end of the input) into a [`Chunk`]: all that can be known of each line
/// without the index. Line numbers and errors are relative to the chunk.
fn read_chunk(data: &[u8], path: Option<&Path>) -> Chunk {
    let mut c = Chunk {
        bytes: data.len() as u64,
        ..Chunk::default()
    };
    let mut fields: Vec<(usize, &str)> = Vec::new();
    let base = data.as_ptr() as usize;
    let err = |line: u64, column: u32, reason: String| {
        Box::new(Fault {
            line,
            column,
            reason,
        })
    };
    let mut lines = Lines::part(data, path, InputKind::Foon);
    for line in &mut lines {
        let line = match line {
            Ok(l) => l,
            Err(e) => {
                let (line, column) = e.location().map_or((0, 1), |l| (l.line, l.column));
                let reason = match e {
                    Error::Parse { reason, .. } => reason,
                    other => other.to_string(),
                };
                c.ops.push(LineOp {
                    number: local_line(line),
                    start: 0,
                    op: Op::Stop(err(line, column, reason)),
                });
                break;
            }
        };
        let number = line.number;
        let start = (line.text.as_ptr() as usize - base) as u32;
        let push = |c: &mut Chunk, op: Op| {
            c.ops.push(LineOp {
                number: local_line(number),
                start,
                op,
            });
        };
        let kind = match classify(&line, &mut fields) {
            Ok(k) => k,
            Err((col, r)) => {
                push(&mut c, Op::Bad(err(number, col, r)));
                continue;
            }
        };
        match kind {
            LineKind::Blank | LineKind::Comment => continue,
            LineKind::End => {
                push(&mut c, Op::End);
                continue;
            }
            _ => {}
        }
        let Some(&(f1_off, f1)) = fields.get(1) else {
            let what = field_name(kind);
            let e = err(
                number,
                line.column_of(line.text.len()),
                format!("missing {what} (no TAB-separated field)"),
            );
            push(&mut c, Op::Field(e));
            continue;
        };
        let value = normalise(f1);
        if value.is_empty() && !(kind == LineKind::State && fields.len() > 2) {
            let what = field_name(kind);
            let e = err(number, line.column_of(f1_off), format!("empty {what}"));
            push(&mut c, Op::Field(e));
            continue;
        }
        let op = match kind {
            LineKind::Object => {
                let in_motion = match fields.get(2).map(|(_, f)| f.trim()) {
                    Some("0") => 0,
                    Some("1") => 1,
                    _ => 2,
                };
                Op::Object {
                    label: c.local.intern(&value),
                    in_motion,
                }
            }
            LineKind::State => Op::State(match fields.get(2) {
                None => StateOp::Plain(c.local.intern(&value)),
                Some(&(f2_off, f2)) => match annotation(f2) {
                    Err(r) => StateOp::BadAnnotation(Box::new((line.column_of(f2_off), r))),
                    Ok(Annotation::Ingredients(inner)) => {
                        let first = c.ings.len() as u32;
                        let mut offset = f2_off + 1;
                        for ing in inner.split(',') {
                            let id = c.local.intern(ing);
                            c.ings.push(Ing {
                                id,
                                offset: offset as u32,
                            });
                            offset += ing.len() + 1;
                        }
                        let from = (f2_off + 1) as u32;
                        StateOp::Ingredients {
                            f2_off: f2_off as u32,
                            inner: (from, from + inner.len() as u32),
                            items: (first, c.ings.len() as u32),
                        }
                    }
                    Ok(Annotation::Container(inner)) => StateOp::Container {
                        f2_off: f2_off as u32,
                        inner: c.local.intern(inner),
                    },
                },
            }),
            _ => {
                let motion = c.local.intern(&value);
                let meta = if fields.len() > 2 {
                    let rest: Vec<&str> = fields[2..].iter().map(|(_, f)| f.trim()).collect();
                    c.local.intern(&rest.join("\t"))
                } else {
                    NONE
                };
                Op::Motion { motion, meta }
            }
        };
        push(&mut c, op);
    }
    c.lines = lines.read_count();
    c
}

/// The most bytes of a chunk before its last line: a chunk is under 4 GiB (with its last line,
/// at most [`super::MAX_LINE_BYTES`]), so its byte offsets and line numbers fit a `u32`.
const MAX_CHUNK_BYTES: usize = 1 << 30;
const _: () = assert!(MAX_CHUNK_BYTES + super::MAX_LINE_BYTES < u32::MAX as usize);

/// A line number within a chunk (which has fewer than `u32::MAX` lines, see
/// [`MAX_CHUNK_BYTES`]); the input's line numbers (`u64`) are checked where the index keeps
/// them (see [`super::line_u32`]).
fn local_line(n: u64) -> u32 {
    debug_assert!(u32::try_from(n).is_ok());
    n as u32
}

/// The error `e` of a chunk whose first line is line `base + 1` of the input.
fn rebase(f: &Fault, base: u64, path: Option<&Path>) -> Error {
    Error::parse(
        InputKind::Foon,
        path,
        f.line + base,
        f.column,
        f.reason.clone(),
    )
}

/// A parse error of a chunk, at a line numbered within the chunk.
struct Fault {
    line: u64,
    column: u32,
    reason: String,
}

/// Feeds chunks to the index in input order, with one unit's state carried across chunks, so
/// that the result (ids, warnings, notes, duplicates, errors) does not depend on where the
/// chunks end.
struct Feeder<'a, 'e> {
    path: Option<&'a Path>,
    opts: ParseOptions,
    errors: Option<&'e mut Vec<Error>>,
    cancel: &'a (dyn Fn() -> bool + Sync),
    progress: Option<&'a Progress>,
    block: Block,
    /// Lines before the current chunk.
    base: u64,
    /// Lines read since the cancel closure was last called.
    since_cancel: u64,
    /// Index ids of the current chunk's local strings ([`NONE`] until first used).
    ids: Vec<u32>,
    /// The input ended early (a fault that ends it).
    stopped: bool,
}

impl Feeder<'_, '_> {
    /// Feeds one chunk (`data` is its bytes).
    fn chunk(&mut self, b: &mut Builder, data: &[u8], c: &Chunk) -> Result<()> {
        if self.stopped {
            return Ok(());
        }
        self.ids.clear();
        self.ids.resize(c.local.ends.len(), NONE);
        if self.since_cancel >= CANCEL_EVERY_LINES {
            self.since_cancel = 0;
            if (self.cancel)() {
                return Err(Error::Cancelled);
            }
        }
        for lo in &c.ops {
            if self.since_cancel >= CANCEL_EVERY_LINES {
                self.since_cancel = 0;
                if (self.cancel)() {
                    return Err(Error::Cancelled);
                }
            }
            self.since_cancel += 1;
            let line = self.base + u64::from(lo.number);
            let mut ended = false;
            let r = self.line(b, data, c, lo, line, &mut ended);
            if let Err(e) = r {
                // A size error ends the parse, even a recovering one.
                let errs = match self.errors.as_deref_mut() {
                    Some(errs) if !matches!(e, Error::TooLarge { .. }) => errs,
                    _ => return Err(e),
                };
                errs.push(e);
                if !ended {
                    // Drop the unit the bad line belongs to (a `//` error has ended its unit).
                    self.block.has_lines = true;
                    self.block.poisoned = true;
                }
            }
            if self.stopped {
                break;
            }
        }
        self.base += c.lines;
        if let Some(p) = self.progress {
            p.add(c.bytes);
        }
        Ok(())
    }

    /// The index id of local string `id` of chunk `c`.
    fn id(&mut self, b: &mut Builder, c: &Chunk, id: u32) -> u32 {
        let slot = &mut self.ids[id as usize];
        if *slot == NONE {
            *slot = b.intern_hashed(c.local.text(id), c.local.hashes[id as usize]);
        }
        *slot
    }

    #[allow(clippy::too_many_lines)]
    fn line(
        &mut self,
        b: &mut Builder,
        data: &[u8],
        c: &Chunk,
        lo: &LineOp,
        number: u64,
        ended: &mut bool,
    ) -> Result<()> {
        let (path, strict) = (self.path, self.opts.strict);
        let err =
            |col: u32, reason: String| Error::parse(InputKind::Foon, path, number, col, reason);
        match &lo.op {
            Op::Bad(e) => return Err(rebase(e, self.base, path)),
            Op::Stop(e) => {
                self.stopped = true;
                return Err(rebase(e, self.base, path));
            }
            Op::End => {
                *ended = true;
                return finish(b, &mut self.block, path, self.opts, Some(number));
            }
            _ => {}
        }
        let block = &mut self.block;
        if !block.has_lines {
            block.has_lines = true;
            block.start_line = number;
        }
        block.last_line = number;
        // The line's text, for the columns of rare messages.
        let text = || {
            let s = lo.start as usize;
            let rest = &data[s.min(data.len())..];
            let end = memchr::memchr(b'\n', rest).unwrap_or(rest.len());
            let raw = &rest[..end];
            let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
            let t = std::str::from_utf8(raw).unwrap_or("");
            Line { number, text: t }
        };
        match lo.op {
            Op::Field(ref e) => return Err(rebase(e, self.base, path)),
            Op::Object { label, in_motion } => {
                let label = self.id(b, c, label);
                let block = &mut self.block;
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
            Op::State(ref s) => {
                let first_of_fu = if block.motion.is_some() {
                    block.first_output
                } else {
                    0
                };
                if block.objects.len() <= first_of_fu {
                    return Err(err(
                        1,
                        "state line before any object of this functional unit".to_owned(),
                    ));
                }
                let obj = block.objects.last().copied();
                let at = |byte: u32| Location::new(path, number, text().column_of(byte as usize));
                match *s {
                    StateOp::Plain(id) => {
                        let id = self.id(b, c, id);
                        push_state(&mut self.block, id);
                    }
                    StateOp::BadAnnotation(ref bad) => {
                        return Err(err(bad.0, bad.1.clone()));
                    }
                    StateOp::Ingredients {
                        f2_off,
                        inner,
                        items,
                    } => {
                        let t = text();
                        let inner = t.text.get(inner.0 as usize..inner.1 as usize).unwrap_or("");
                        if let Some(o) = obj.filter(|o| o.ingredients.0 != o.ingredients.1) {
                            let old: Vec<&str> = block.ingredients
                                [o.ingredients.0 as usize..o.ingredients.1 as usize]
                                .iter()
                                .map(|&i| b.text(i))
                                .collect();
                            let fault = second_list_fault(b.text(o.label), &old.join(","), inner);
                            report(
                                b,
                                strict,
                                at(f2_off),
                                WarningKind::TwoIngredientLists,
                                &fault,
                            )?;
                        }
                        let start = self.block.ingredients.len();
                        for ing in &c.ings[items.0 as usize..items.1 as usize] {
                            let name = c.local.text(ing.id);
                            if name.is_empty() {
                                let fault = empty_ingredient_fault(inner);
                                report(
                                    b,
                                    strict,
                                    at(ing.offset),
                                    WarningKind::EmptyIngredient,
                                    &fault,
                                )?;
                            } else if name != name.trim() {
                                b.note(Warning {
                                    at: at(ing.offset),
                                    kind: WarningKind::SpacedIngredient,
                                    message: format!(
                                        "ingredient '{name}' has leading or trailing spaces"
                                    ),
                                });
                            }
                            let id = self.id(b, c, ing.id);
                            if self.block.ingredients[start..].contains(&id) {
                                b.note(Warning {
                                    at: at(ing.offset),
                                    kind: WarningKind::DuplicateIngredient,
                                    message: format!("ingredient '{name}' is listed twice"),
                                });
                            }
                            self.block.ingredients.push(id);
                        }
                        // A later list replaces an earlier one (course behaviour), so the
                        // object's range is the latest list.
                        let block = &mut self.block;
                        let end = block.ingredients.len() as u32;
                        if let Some(o) = block.objects.last_mut() {
                            o.ingredients = (start as u32, end);
                        }
                    }
                    StateOp::Container { f2_off, inner } => {
                        let name = c.local.text(inner);
                        if let Some(o) = obj.filter(|o| o.container != NONE) {
                            let fault =
                                second_container_fault(b.text(o.label), b.text(o.container), name);
                            report(b, strict, at(f2_off), WarningKind::TwoContainers, &fault)?;
                        }
                        if name.trim().is_empty() {
                            b.note(Warning {
                                at: at(f2_off),
                                kind: WarningKind::EmptyContainer,
                                message: format!("empty container '[{name}]'"),
                            });
                        }
                        let id = self.id(b, c, inner);
                        if let Some(o) = self.block.objects.last_mut() {
                            o.container = id;
                        }
                    }
                }
            }
            Op::Motion { motion, meta } => {
                if block.motion.is_some() {
                    if !block.two_motions {
                        block.two_motions = true;
                        let fault = format!(
                            "functional unit starting at line {} has a second motion line",
                            block.start_line
                        );
                        let at = Location::new(path, number, 1);
                        report(b, strict, at, WarningKind::TwoMotions, &fault)?;
                    }
                    return Ok(());
                }
                let motion = self.id(b, c, motion);
                let meta = if meta == NONE {
                    NONE
                } else {
                    self.id(b, c, meta)
                };
                let block = &mut self.block;
                block.motion = Some((motion, meta));
                block.first_output = block.objects.len();
            }
            Op::End | Op::Bad(_) | Op::Stop(_) => {}
        }
        Ok(())
    }
}

/// Ends the unit being read: its warning (no motion line, no closing `//`), then the unit
/// itself into the index. `end_line` is the line of its `//` (`None` at the end of the input).
fn finish(
    b: &mut Builder,
    block: &mut Block,
    path: Option<&Path>,
    opts: ParseOptions,
    end_line: Option<u64>,
) -> Result<()> {
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
        let line = match super::line_u32(block.start_line) {
            Ok(l) => l,
            Err(e) => {
                block.clear();
                return Err(e);
            }
        };
        let objs: Vec<RawObject<'_>> = block.objects.iter().map(|s| block.raw(s)).collect();
        let (inputs, outputs) = objs.split_at(block.first_output);
        let _ = b.add_fu(motion, meta, inputs, outputs, line);
    }
    block.clear();
    Ok(())
}

/// Where the text parse gets its bytes: windows of whole lines, in order.
pub(super) trait Source<'d> {
    /// The next window (whole lines, or the rest of the input), or `None` at the end.
    fn next_window(&mut self) -> Result<Option<Cow<'d, [u8]>>>;
}

/// Windows of an input held in memory.
pub(super) struct InMemory<'d> {
    pub(super) data: &'d [u8],
    pub(super) window: usize,
}

impl<'d> Source<'d> for InMemory<'d> {
    fn next_window(&mut self) -> Result<Option<Cow<'d, [u8]>>> {
        if self.data.is_empty() {
            return Ok(None);
        }
        let end = line_end_after(self.data, self.window);
        let (w, rest) = self.data.split_at(end);
        self.data = rest;
        Ok(Some(Cow::Borrowed(w)))
    }
}

/// The end of the first line that ends at or after byte `at` (the whole input if none does).
pub(super) fn line_end_after(data: &[u8], at: usize) -> usize {
    if at >= data.len() {
        return data.len();
    }
    let from = at.saturating_sub(1);
    memchr::memchr(b'\n', &data[from..]).map_or(data.len(), |i| from + i + 1)
}

/// Splits a window into chunks of about `chunk` bytes at line ends and reads them in parallel.
fn read_window(w: &[u8], chunk: usize, path: Option<&Path>) -> Vec<(usize, usize, Chunk)> {
    let mut ranges = Vec::new();
    let mut pos = 0;
    while pos < w.len() {
        let end = pos + line_end_after(&w[pos..], chunk);
        ranges.push((pos, end));
        pos = end;
    }
    let read = |(s, e): (usize, usize)| (s, e, read_chunk(&w[s..e], path));
    if ranges.len() == 1 {
        // One chunk (a small file): read here, without handing it to the thread pool.
        return ranges.into_iter().map(read).collect();
    }
    // On the worker pool; without one (its threads could not start), here.
    let on_pool = ranges.clone();
    crate::search::batch::in_pool(|| on_pool.into_par_iter().map(read).collect())
        .unwrap_or_else(|_| ranges.into_iter().map(read).collect())
}

/// Parses FOON text into `b` (one source) from the windows of `source`: errors are collected in
/// `errors` when it is given (the unit of a bad line is dropped), else the first one is
/// returned; `cancel` is called every [`CANCEL_EVERY_LINES`] lines. Chunks of `chunk_bytes`
/// are read on the thread pool while the previous ones feed the index in input order, so the
/// result is the same for every chunk size and number of threads.
#[allow(clippy::too_many_arguments)]
pub(super) fn parse_stream(
    b: &mut Builder,
    source: &mut dyn Source<'_>,
    path: Option<&Path>,
    opts: ParseOptions,
    errors: Option<&mut Vec<Error>>,
    cancel: &(dyn Fn() -> bool + Sync),
    progress: Option<&Progress>,
    chunk_bytes: usize,
) -> Result<()> {
    parse_stream_from(
        b,
        source,
        path,
        opts,
        errors,
        cancel,
        progress,
        chunk_bytes,
        0,
    )
}

/// As [`parse_stream`], the input's first line being line `base + 1` (tests of line numbers
/// past `u32`, without a file of billions of lines).
#[allow(clippy::too_many_arguments)]
fn parse_stream_from<'d>(
    b: &mut Builder,
    source: &mut dyn Source<'d>,
    path: Option<&Path>,
    opts: ParseOptions,
    errors: Option<&mut Vec<Error>>,
    cancel: &(dyn Fn() -> bool + Sync),
    progress: Option<&Progress>,
    chunk_bytes: usize,
    base: u64,
) -> Result<()> {
    let chunk = chunk_bytes.clamp(1, MAX_CHUNK_BYTES);
    let mut feeder = Feeder {
        path,
        opts,
        errors,
        cancel,
        progress,
        block: Block::default(),
        base,
        since_cancel: CANCEL_EVERY_LINES,
        ids: Vec::new(),
        stopped: false,
    };
    let read = |w: Option<Cow<'d, [u8]>>| {
        w.map(|w| {
            let chunks = read_window(&w, chunk, path);
            (w, chunks)
        })
    };
    let mut current = read(source.next_window()?);
    while let Some((w, chunks)) = current.take() {
        let next = if feeder.stopped {
            None
        } else {
            source.next_window()?
        };
        let mut feed = || -> Result<()> {
            for (s, e, c) in &chunks {
                feeder.chunk(b, &w[*s..*e], c)?;
            }
            Ok(())
        };
        // The next window is read while this one feeds the index; the last one feeds alone.
        let (fed, next) = if next.is_some() {
            crate::search::batch::in_pool(|| rayon::join(feed, || read(next)))?
        } else {
            (feed(), None)
        };
        fed?;
        current = next;
    }
    finish(b, &mut feeder.block, path, opts, None)
}

/// Reports a fault of `kind` at `at`: in strict mode an error, otherwise a warning (a load
/// warning or a lint note, per [`WarningKind::is_load_warning`]) that ends with what is done.
pub(super) fn report(
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

/// Appends a plain state to the last object of the block (its states are the last ones
/// pushed, since an object's lines are contiguous).
fn push_state(block: &mut Block, id: u32) {
    block.states.push(id);
    let end = block.states.len() as u32;
    if let Some(o) = block.objects.last_mut() {
        o.states.1 = end;
    }
}

#[cfg(test)]
mod tests {
    use super::{InMemory, parse_stream_from};
    use crate::error::Error;
    use crate::index::Builder;
    use crate::parse::ParseOptions;

    const UNIT: &[u8] = b"O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n";

    /// Parses `UNIT` (its first line being line `base + 1`): the unit's line, or the error.
    fn unit_line(base: u64, recover: bool, chunk: usize) -> Result<u32, Error> {
        let mut b = Builder::new();
        b.begin_source(None);
        let mut errors = Vec::new();
        let mut src = InMemory {
            data: UNIT,
            window: chunk,
        };
        let opts = ParseOptions::default();
        let errs = recover.then_some(&mut errors);
        parse_stream_from(
            &mut b,
            &mut src,
            None,
            opts,
            errs,
            &|| false,
            None,
            chunk,
            base,
        )?;
        assert!(errors.is_empty());
        Ok(b.finish().fu_line(0))
    }

    /// Line numbers are `u64` while read and `u32` in the index: a unit that starts past
    /// `u32::MAX` is a size error (even when recovering), never a wrapped number.
    #[test]
    fn line_numbers_past_u32_are_too_large() {
        let max = u64::from(u32::MAX);
        for recover in [false, true] {
            for chunk in [1, 8, 1 << 20] {
                assert_eq!(unit_line(max - 1, recover, chunk).unwrap(), u32::MAX);
                let e = unit_line(max, recover, chunk).unwrap_err();
                assert!(matches!(e, Error::TooLarge { what: "lines", .. }), "{e}");
            }
        }
    }
}
