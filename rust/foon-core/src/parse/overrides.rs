//! Per-unit rate overrides: `unit<TAB>rate` lines into [`RateOverrides`].

use std::path::{Path, PathBuf};

use super::lines::Lines;
use super::read_file;
use crate::error::{Error, InputKind, Result};

/// Success rates of single FUs that replace their motion's rate in a profile: FU index (the
/// FOON's unit number, from 0, in file order after duplicates are dropped) to rate.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RateOverrides {
    /// Sorted by unit, each unit once.
    pub entries: Vec<(u32, f64)>,
    /// The line of each entry (0 when built in code), for range errors.
    pub lines: Vec<u64>,
    pub path: Option<PathBuf>,
}

impl RateOverrides {
    /// Overrides from `(unit, rate)` pairs, checked as the file's lines are.
    pub fn from_pairs(pairs: impl IntoIterator<Item = (u32, f64)>) -> Result<Self> {
        let mut v: Vec<(u32, f64, u64)> = Vec::new();
        for (f, r) in pairs {
            check_unit_rate(f, r).map_err(Error::Invalid)?;
            v.push((f, r, 0));
        }
        Self::build(v, None)
    }

    /// Overrides from `(unit, rate, line)` entries read from `path` earlier (the form
    /// [`RateOverrides::triples`] gives back), checked again.
    pub fn from_lines(v: Vec<(u32, f64, u64)>, path: Option<&Path>) -> Result<Self> {
        for &(f, r, line) in &v {
            check_unit_rate(f, r).map_err(|e| match path {
                Some(_) => Error::parse(InputKind::RateOverrides, path, line, 1, e),
                None => Error::Invalid(e),
            })?;
        }
        Self::build(v, path)
    }

    /// `(unit, rate, line)` of every entry.
    pub fn triples(&self) -> Vec<(u32, f64, u64)> {
        self.entries
            .iter()
            .zip(&self.lines)
            .map(|(&(f, r), &l)| (f, r, l))
            .collect()
    }

    fn build(mut v: Vec<(u32, f64, u64)>, path: Option<&Path>) -> Result<Self> {
        v.sort_by_key(|&(f, _, line)| (f, line));
        let mut o = Self {
            path: path.map(Path::to_path_buf),
            ..Self::default()
        };
        for (f, r, line) in v {
            if let Some(&(last, old)) = o.entries.last() {
                if last == f {
                    #[allow(clippy::float_cmp)]
                    if old == r {
                        continue;
                    }
                    let first = o.lines[o.lines.len() - 1];
                    let reason = format!("unit {f} has two rates: {old} (line {first}) and {r}");
                    return Err(match path {
                        Some(_) => Error::parse(InputKind::RateOverrides, path, line, 1, reason),
                        None => Error::Invalid(reason),
                    });
                }
            }
            o.entries.push((f, r));
            o.lines.push(line);
        }
        Ok(o)
    }

    /// The override of unit `f`, if any.
    pub fn get(&self, f: u32) -> Option<f64> {
        self.entries
            .binary_search_by_key(&f, |&(u, _)| u)
            .ok()
            .map(|i| self.entries[i].1)
    }

    /// Errors (with the file's line) when a unit is not one of the FOON's `fu_count` units.
    pub fn check_units(&self, fu_count: usize) -> Result<()> {
        let Some(i) = self
            .entries
            .iter()
            .position(|&(f, _)| f as usize >= fu_count)
        else {
            return Ok(());
        };
        let f = self.entries[i].0;
        let reason = format!("unit {f} is out of range: the FOON has {fu_count} units");
        Err(match &self.path {
            Some(p) => Error::parse(InputKind::RateOverrides, Some(p), self.lines[i], 1, reason),
            None => Error::Invalid(reason),
        })
    }

    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

fn check_unit_rate(f: u32, r: f64) -> std::result::Result<(), String> {
    if (0.0..=1.0).contains(&r) {
        Ok(())
    } else {
        Err(format!("the rate of unit {f} is {r}, not between 0 and 1"))
    }
}

/// Parses a rate override file: `unit<TAB>rate` lines, `unit` an FU index (a whole number
/// from 0), `rate` between 0 and 1; blank lines and `#` comments skipped. A unit given twice
/// with the same rate is kept once, with two rates it is an error naming both lines.
pub fn parse_overrides(data: &[u8], path: Option<&Path>) -> Result<RateOverrides> {
    let kind = InputKind::RateOverrides;
    let mut v = Vec::new();
    for line in Lines::new(data, path, kind) {
        let line = line?;
        let t = line.text;
        if t.trim().is_empty() || t.trim_start().starts_with('#') {
            continue;
        }
        let err = |col: u32, reason: String| Error::parse(kind, path, line.number, col, reason);
        let Some((unit, rate)) = t.split_once('\t') else {
            return Err(err(
                line.column_of(t.len()),
                "expected 'unit<TAB>rate'".into(),
            ));
        };
        let lead = unit.len() - unit.trim_start().len();
        let unit_col = line.column_of(lead);
        let f: u32 = unit.trim().parse().map_err(|_| {
            let shown: String = unit.trim().chars().take(20).collect();
            err(
                unit_col,
                format!("unit '{shown}' is not a unit index (a whole number from 0)"),
            )
        })?;
        let col = line.column_of(unit.len() + 1);
        let r: f64 = rate.trim().parse().map_err(|_| {
            let shown: String = rate.trim().chars().take(20).collect();
            err(col, format!("rate '{shown}' is not a number"))
        })?;
        check_unit_rate(f, r).map_err(|e| err(col, e))?;
        v.push((f, r, line.number));
    }
    RateOverrides::build(v, path)
}

pub fn load_overrides(path: &Path) -> Result<RateOverrides> {
    let data = read_file(path)?;
    parse_overrides(&data, Some(path))
}
