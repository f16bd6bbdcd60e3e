//! The FOON text parser: the four dialects of real files (course `O`, lab `O<id>` with flags
//! and CRLF, motion times), streaming over the bytes line by line into a [`Builder`].

use std::path::Path;

use super::ParseOptions;
use super::lines::{
    Annotation, LineKind, Lines, annotation, classify, empty_ingredient_fault, normalise,
    second_container_fault, second_list_fault,
};
use crate::error::{Error, InputKind, Location, Result, Warning, WarningKind};
use crate::index::{Builder, NONE, RawObject};

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

/// Parses FOON text into `b` (one source): errors are collected in `errors` when it is given (the
/// unit of a bad line is dropped), else the first one is returned; `cancel` is called every
/// [`CANCEL_EVERY_LINES`] lines.
pub(super) fn parse_impl(
    b: &mut Builder,
    data: &[u8],
    path: Option<&Path>,
    opts: ParseOptions,
    mut errors: Option<&mut Vec<Error>>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<()> {
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
                    finish(b, &mut block, Some(line.number))?;
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
                                        b,
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
                                            b,
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
                                        b,
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
                            report(b, opts.strict, at, WarningKind::TwoMotions, &fault)?;
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
    finish(b, &mut block, None)?;
    Ok(())
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
