//! Utensil lists: one name a line.

use std::path::Path;

use super::lines::Lines;
use super::read_file;
use crate::error::{Error, InputKind, Result};

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
    let data = read_file(path)?;
    parse_utensils(&data, Some(path))
}
