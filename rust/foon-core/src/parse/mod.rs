//! Parsing: every text input into the model or the index. FOON text or JSON ([`parse_foon`]), lists
//! of objects (kitchens and goals, [`parse_objects`]), motion tables ([`parse_rates`]) and
//! utensil lists ([`parse_utensils`]), each with a `load_*` form that reads a file. They share
//! one line reader and one line grammar (`lines`).

mod foon;
mod json;
mod lines;
mod objects;
mod rates;
mod utensils;

use std::path::Path;

use crate::error::{Error, Result};
use crate::index::{Builder, Foon};

pub use lines::MAX_LINE_BYTES;
pub(crate) use objects::parse_objects_noting;
pub use objects::{load_objects, parse_objects};
pub(crate) use rates::parse_rates_recovering;
pub use rates::{load_rates, parse_rates};
pub use utensils::{load_utensils, parse_utensils};

/// Options for loading.
#[derive(Debug, Clone, Copy, Default)]
pub struct ParseOptions {
    /// Turn every warning into an error.
    pub strict: bool,
}

/// Reads a whole file; the error names the file. Regular files and pipes are read (a FIFO
/// or a process substitution such as `<(zcat foon.txt.gz)` waits for its writer, as `cat`
/// does); devices and sockets are refused, so that `/dev/zero` is an error rather than a read
/// without end.
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if !readable_kind(meta.file_type()) {
        return Err(Error::io(
            path,
            std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "not a regular file (a device or a socket)",
            ),
        ));
    }
    std::fs::read(path).map_err(|e| Error::io(path, e))
}

#[cfg(unix)]
fn readable_kind(t: std::fs::FileType) -> bool {
    use std::os::unix::fs::FileTypeExt;
    !(t.is_char_device() || t.is_block_device() || t.is_socket())
}

#[cfg(not(unix))]
fn readable_kind(_: std::fs::FileType) -> bool {
    true
}

/// Parses a FOON into an index: FOON text, or JSON (the lab's dialect, see `json`) when its
/// first non-blank byte is `[` or `{`.
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
    parse_any(data, path, opts, None, cancel)
}

/// The parser the content calls for: JSON (the first non-blank byte is `[` or `{`) or text.
fn parse_any(
    data: &[u8],
    path: Option<&Path>,
    opts: ParseOptions,
    errors: Option<&mut Vec<Error>>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Foon> {
    let mut b = Builder::new();
    parse_into(&mut b, data, path, opts, errors, cancel)?;
    Ok(b.finish())
}

/// Parses one source (FOON text, or the lab's JSON when its first non-blank byte is `[` or
/// `{`) into `b`, which may already hold other sources: many files build one index, an FU
/// found again (in this source or an earlier one) is recorded as a further origin of the
/// first copy. Errors are collected in `errors` when it is given (the unit of a bad line is
/// dropped), else the first one is returned; `cancel` is called every few thousand lines.
pub fn parse_into(
    b: &mut Builder,
    data: &[u8],
    path: Option<&Path>,
    opts: ParseOptions,
    errors: Option<&mut Vec<Error>>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<()> {
    b.begin_source(path);
    if json::is_json(data) {
        json::parse_impl(b, data, path, opts, errors, cancel)
    } else {
        foon::parse_impl(b, data, path, opts, errors, cancel)
    }
}

/// Parses FOON text, going on after malformed lines: each error is collected and the unit it
/// belongs to is dropped. Used by the linter, which reports every problem at once.
pub fn parse_foon_recovering(
    data: &[u8],
    path: Option<&Path>,
    opts: ParseOptions,
) -> (Foon, Vec<Error>) {
    match parse_foon_recovering_cancellable(data, path, opts, &|| false) {
        Ok(r) => r,
        Err(e) => (empty_of(path), vec![e]),
    }
}

/// As [`parse_foon_recovering`], calling `cancel` every few thousand lines: when it answers
/// true, the parse stops with [`Error::Cancelled`] (the only error it returns).
pub fn parse_foon_recovering_cancellable(
    data: &[u8],
    path: Option<&Path>,
    opts: ParseOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<(Foon, Vec<Error>)> {
    let mut errors = Vec::new();
    match parse_any(data, path, opts, Some(&mut errors), cancel) {
        Ok(f) => Ok((f, errors)),
        Err(Error::Cancelled) => Err(Error::Cancelled),
        Err(e) => {
            errors.push(e);
            Ok((empty_of(path), errors))
        }
    }
}

/// The empty FOON of a source that could not be read.
fn empty_of(path: Option<&Path>) -> Foon {
    let mut b = Builder::new();
    b.begin_source(path);
    b.finish()
}

/// Reads a file and parses it as FOON text.
pub fn load_foon(path: &Path, opts: ParseOptions) -> Result<Foon> {
    load_foon_cancellable(path, opts, &|| false)
}

/// As [`load_foon`], calling `cancel` every few thousand lines (see
/// [`parse_foon_cancellable`]). A file that starts with the index magic is opened as a
/// `.foonidx` index ([`Foon::open_index`]: memory-mapped, whatever its name); text and JSON
/// are parsed into a builder sized from the file's length.
pub fn load_foon_cancellable(
    path: &Path,
    opts: ParseOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Foon> {
    if cancel() {
        return Err(Error::Cancelled);
    }
    // A regular file is probed for the magic; a pipe is read once and its bytes tell.
    let regular = std::fs::metadata(path).is_ok_and(|m| m.is_file());
    if regular && crate::index::file::is_index_file(path) {
        return Foon::open_index(path);
    }
    let data = read_file(path)?;
    if crate::index::file::is_index(&data) {
        return Foon::from_index_bytes(&data, path);
    }
    let mut b = Builder::for_bytes(data.len());
    parse_into(&mut b, &data, Some(path), opts, None, cancel)?;
    drop(data);
    b.try_finish()
}
