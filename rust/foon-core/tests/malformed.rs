//! The malformed-input corpus (`tests/malformed/` at the repository root), checked against the
//! core directly: every case must fail with a parse error at the listed line and column whose
//! reason contains the listed text. A case with a `warning` (a load warning) or a `note` (a
//! `foon check` finding) is an error in strict mode only. `tests/test_malformed.py` checks
//! the same cases through the Python API and the CLI.

use std::path::{Path, PathBuf};

use foon_core::parse::{load_objects, load_rates, load_utensils};
use foon_core::{Error, InputKind, ParseOptions, WarningKind, load_foon};
use serde::Deserialize;

#[derive(Deserialize)]
struct Case {
    file: String,
    kind: String,
    line: u64,
    column: u32,
    reason_contains: String,
    #[allow(dead_code)]
    dialect: String,
    #[serde(default)]
    strict: bool,
    #[serde(default)]
    warning: Option<String>,
    /// A strict-only error that is a `foon check` finding (a lint note of the index, not a
    /// load warning) without strict mode.
    #[serde(default)]
    note: Option<String>,
}

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/malformed")
}

fn load(kind: &str, path: &Path, strict: bool) -> Result<(), Error> {
    match kind {
        "foon" => load_foon(path, ParseOptions { strict }).map(|_| ()),
        "kitchen" => load_objects(path, InputKind::Kitchen).map(|_| ()),
        "goal" => load_objects(path, InputKind::Goal).map(|_| ()),
        "motions" => load_rates(path).map(|_| ()),
        "utensils" => load_utensils(path).map(|_| ()),
        other => panic!("unknown kind {other}"),
    }
}

#[test]
fn every_case_fails_where_listed() {
    let cases: Vec<Case> =
        serde_json::from_str(&std::fs::read_to_string(dir().join("cases.json")).unwrap()).unwrap();
    assert!(cases.len() >= 40);
    let mut wrong = Vec::new();
    for c in &cases {
        let path = dir().join(&c.file);
        match load(&c.kind, &path, c.strict) {
            Err(Error::Parse { at, reason, .. }) => {
                if at.line != c.line
                    || at.column != c.column
                    || !reason.contains(&c.reason_contains)
                    || at.path.as_deref() != Some(path.as_path())
                {
                    wrong.push(format!(
                        "{}: got {}:{} {reason:?}, expected {}:{} ~{:?}",
                        c.file, at.line, at.column, c.line, c.column, c.reason_contains
                    ));
                }
            }
            other => wrong.push(format!("{}: expected a parse error, got {other:?}", c.file)),
        }
        // A strict-only error is a warning (and the file loads) without strict mode.
        if let Some(w) = &c.warning {
            let foon = load_foon(&path, ParseOptions::default()).unwrap();
            let kinds: Vec<WarningKind> = foon.warnings().iter().map(|w| w.kind).collect();
            assert!(
                kinds.iter().any(|k| k.as_str() == w),
                "{}: warnings {kinds:?}, expected {w}",
                c.file
            );
            assert!(foon.warnings().iter().all(|w| w.at.line == c.line));
        }
        if let Some(n) = &c.note {
            let foon = load_foon(&path, ParseOptions::default()).unwrap();
            assert!(foon.warnings().is_empty(), "{}", c.file);
            assert!(
                foon.notes()
                    .iter()
                    .any(|w| w.kind.as_str() == n && (w.at.line, w.at.column) == (c.line, c.column)),
                "{}: notes {:?}, expected {n} at {}:{}",
                c.file,
                foon.notes(),
                c.line,
                c.column
            );
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}
