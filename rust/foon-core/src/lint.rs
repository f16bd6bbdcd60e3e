//! `foon check`: every problem of a FOON file at once, with file and line: parse errors,
//! annotation faults, duplicate units, suspicious ingredient lists, and FOON-level findings
//! (objects nobody produces, motions without rates, objects only reachable through cycles).

use std::path::Path;

use crate::error::{Error, InputKind, Location, Warning, WarningKind};
use crate::index::Foon;
use crate::model::{MotionRates, ObjectSpec};
use crate::parse::{
    ParseOptions, parse_foon_recovering_cancellable, parse_objects_noting, parse_rates_recovering,
    read_file,
};
use crate::prepare::Prepared;

/// How serious a finding is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Severity {
    Error,
    Warning,
    Note,
}

impl Severity {
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Error => "error",
            Self::Warning => "warning",
            Self::Note => "note",
        }
    }
}

/// One finding.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Finding {
    pub at: Location,
    pub severity: Severity,
    pub code: &'static str,
    pub message: String,
}

/// What the cross-checks use (all optional).
#[derive(Debug, Clone, Copy, Default)]
pub struct LintOptions<'a> {
    pub kitchen: Option<&'a [ObjectSpec]>,
    pub rates: Option<&'a MotionRates>,
    pub utensils: &'a [String],
}

/// True when `data` looks like a list of objects (object lines, no motion and no `//`).
fn is_object_list(data: &[u8]) -> bool {
    let mut objects = false;
    for line in data.split(|&b| b == b'\n') {
        match line.first() {
            Some(b'M') => return false,
            Some(b'/') if line.starts_with(b"//") => return false,
            Some(b'O') => objects = true,
            _ => {}
        }
    }
    objects
}

/// A finding from an error. An error about the file as a whole (a corrupt index, an I/O
/// error) has no line: its location is line 0, column 0, which is shown as `FILE: message`.
fn from_error(e: Error, path: Option<&Path>) -> Finding {
    match e {
        Error::Parse { at, reason, .. } => Finding {
            at,
            severity: Severity::Error,
            code: "syntax",
            message: reason,
        },
        // The file is the location: the message is the reason alone.
        Error::BadIndex { path: bad, reason } => Finding {
            at: Location::new(Some(path.unwrap_or(&bad)), 0, 0),
            severity: Severity::Error,
            code: "bad-index",
            message: reason,
        },
        other => Finding {
            at: Location::new(path, 0, 0),
            severity: Severity::Error,
            code: "error",
            message: other.to_string(),
        },
    }
}

/// The severity of a warning found while parsing: a fault that strict mode rejects is a
/// warning, the other kinds (spaced or repeated ingredients, `[]`) are notes.
fn severity_of(kind: WarningKind) -> Severity {
    if kind.consequence().is_some() {
        Severity::Warning
    } else {
        Severity::Note
    }
}

fn from_warning(w: &Warning) -> Finding {
    Finding {
        at: w.at.clone(),
        severity: severity_of(w.kind),
        code: w.kind.as_str(),
        message: w.message.clone(),
    }
}

/// Checks one input (FOON text, or a list of objects in FOON block form).
pub fn lint(data: &[u8], path: Option<&Path>, opts: &LintOptions<'_>) -> Vec<Finding> {
    match lint_cancellable(data, path, opts, &|| false) {
        Ok(found) => found,
        Err(e) => vec![from_error(e, path)],
    }
}

/// As [`lint`], calling `cancel` every few thousand lines of the parse: when it answers true,
/// the check stops with [`crate::Error::Cancelled`].
pub fn lint_cancellable(
    data: &[u8],
    path: Option<&Path>,
    opts: &LintOptions<'_>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> crate::Result<Vec<Finding>> {
    if is_object_list(data) {
        let mut notes = Vec::new();
        return Ok(
            match parse_objects_noting(data, path, InputKind::Kitchen, &mut notes) {
                Ok(_) => notes.iter().map(from_warning).collect(),
                Err(e) => vec![from_error(e, path)],
            },
        );
    }
    let (foon, errors) =
        parse_foon_recovering_cancellable(data, path, ParseOptions::default(), cancel)?;
    let mut out: Vec<Finding> = errors.into_iter().map(|e| from_error(e, path)).collect();
    out.extend(foon.warnings().iter().map(from_warning));
    out.extend(foon.notes().iter().map(from_warning));
    for d in foon.duplicates() {
        out.push(Finding {
            at: Location::new(path, u64::from(d.line), 1),
            severity: Severity::Warning,
            code: "duplicate-fu",
            message: format!(
                "this functional unit repeats the one at line {}; it is dropped",
                foon.fu_line(d.of)
            ),
        });
    }
    out.extend(graph_findings(&foon, path, opts));
    out.sort_by(|a, b| {
        (a.at.line, a.at.column, a.severity).cmp(&(b.at.line, b.at.column, b.severity))
    });
    Ok(out)
}

fn graph_findings(foon: &Foon, path: Option<&Path>, opts: &LintOptions<'_>) -> Vec<Finding> {
    let mut out = Vec::new();
    // A unit is named by the file and line it was read from (for an index file: its source).
    let at_fu = |f: u32| {
        let source = foon.source_name(foon.fu_source(f));
        let from = if source.is_empty() {
            path
        } else {
            Some(Path::new(source))
        };
        Location::new(from, u64::from(foon.fu_line(f)), 1)
    };
    let describe = |o: u32| crate::write::object_line(foon, o);
    let kitchen = opts.kitchen.unwrap_or(&[]);
    let Ok(prep) = Prepared::new(foon, kitchen, opts.utensils, None, None) else {
        return out;
    };
    let n = foon.object_count() as u32;
    if opts.kitchen.is_some() {
        // Objects a unit needs that nobody produces and the kitchen lacks.
        let mut first_use = vec![u32::MAX; n as usize];
        for f in 0..foon.fu_count() as u32 {
            for &x in prep.needed(f) {
                if first_use[x as usize] == u32::MAX {
                    first_use[x as usize] = f;
                }
            }
        }
        for o in 0..n {
            let f = first_use[o as usize];
            if f != u32::MAX && foon.producers(o).is_empty() && !prep.in_kitchen(o) {
                out.push(Finding {
                    at: at_fu(f),
                    severity: Severity::Warning,
                    code: "never-produced",
                    message: format!(
                        "'{}' is used but never produced and not in the kitchen",
                        describe(o)
                    ),
                });
            }
        }
    }
    if let Some(rates) = opts.rates {
        for &m in foon.motion_ids() {
            let text = foon.text(m);
            if rates.get(text).is_none() {
                if let Some(f) = (0..foon.fu_count() as u32).find(|&f| foon.motion(f) == m) {
                    out.push(Finding {
                        at: at_fu(f),
                        severity: Severity::Warning,
                        code: "missing-rate",
                        message: format!("motion '{text}' has no success rate in the motion table"),
                    });
                }
            }
        }
    }
    if opts.kitchen.is_none() {
        return out;
    }
    // Objects that are produced, yet cannot be made from the kitchen even if every raw object
    // (one no unit produces) were at hand: every way to them goes through a cycle. Without a
    // kitchen this is not decidable (a starting item such as an empty bowl that some unit
    // also produces would look circular), so it needs one.
    let raw: Vec<bool> = (0..n).map(|o| foon.producers(o).is_empty()).collect();
    let r = prep.ranks_with(foon, &raw);
    for o in 0..n {
        if !raw[o as usize] && !prep.in_kitchen(o) && !r.is_derivable(o) {
            out.push(Finding {
                at: at_fu(foon.producers(o)[0]),
                severity: Severity::Note,
                code: "cycle-only",
                message: format!(
                    "'{}' can only be made through a cycle (no way to it from the kitchen avoids one)",
                    describe(o)
                ),
            });
        }
    }
    out
}

/// Reads and checks a file.
pub fn lint_file(path: &Path, opts: &LintOptions<'_>) -> crate::Result<Vec<Finding>> {
    lint_file_cancellable(path, opts, &|| false)
}

/// As [`lint_file`], stopping with [`crate::Error::Cancelled`] once `cancel` answers true.
pub fn lint_file_cancellable(
    path: &Path,
    opts: &LintOptions<'_>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> crate::Result<Vec<Finding>> {
    if cancel() {
        return Err(crate::Error::Cancelled);
    }
    if crate::index::file::is_index_file(path) {
        return Ok(lint_index(path, opts));
    }
    let data = read_file(path)?;
    lint_cancellable(&data, Some(path), opts, cancel)
}

/// Checks an index file: it opens (header, bounds and structure), its checksum holds, and the
/// graph checks of [`lint`] on its units (named by their source files and lines).
fn lint_index(path: &Path, opts: &LintOptions<'_>) -> Vec<Finding> {
    let foon = match Foon::open_index(path).and_then(|f| f.verify_checksum().map(|()| f)) {
        Ok(f) => f,
        Err(e) => return vec![from_error(e, Some(path))],
    };
    graph_findings(&foon, Some(path), opts)
}

/// Checks a motion table: every bad line is an error finding (code `syntax`; a motion with
/// two different rates is one too, code `two-rates`), and the rates of the good lines are
/// returned for the cross-checks of [`lint`] (of a motion with two rates, the first).
pub fn lint_rates_data(data: &[u8], path: Option<&Path>) -> (MotionRates, Vec<Finding>) {
    let (rates, errors) = parse_rates_recovering(data, path);
    let findings = errors
        .into_iter()
        .map(|(e, two_rates)| {
            let mut f = from_error(e, path);
            if two_rates {
                f.code = "two-rates";
            }
            f
        })
        .collect();
    (rates, findings)
}

/// Reads and checks a motion table (see [`lint_rates_data`]).
pub fn lint_rates(path: &Path) -> crate::Result<(MotionRates, Vec<Finding>)> {
    let data = read_file(path)?;
    Ok(lint_rates_data(&data, Some(path)))
}
