//! Motion tables: `motion<TAB>rate` lines into [`MotionRates`].

use std::path::Path;

use super::lines::Lines;
use super::read_file;
use crate::error::{Error, InputKind, Result};
use crate::model::{MotionRates, check_rate};

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
            let name = MotionRates::motion_name(name);
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
    let data = read_file(path)?;
    parse_rates(&data, Some(path))
}
