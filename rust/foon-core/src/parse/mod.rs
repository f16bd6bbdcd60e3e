//! Parsing: every text input into the model or the index. FOON text or JSON ([`parse_foon`]), lists
//! of objects (kitchens and goals, [`parse_objects`]), motion tables ([`parse_rates`]) and
//! utensil lists ([`parse_utensils`]), each with a `load_*` form that reads a file. They share
//! one line reader and one line grammar (`lines`).

mod foon;
mod json;
mod lines;
mod objects;
mod overrides;
mod rates;
mod utensils;

use std::borrow::Cow;
use std::io::Read;
use std::path::Path;

use crate::error::{Error, Result};
use crate::index::{Builder, Foon};
use crate::progress::Progress;

pub use lines::MAX_LINE_BYTES;
pub(crate) use objects::parse_objects_noting;
pub use objects::{load_objects, parse_objects};
pub use overrides::{RateOverrides, load_overrides, parse_overrides};
pub(crate) use rates::parse_rates_recovering;
pub use rates::{load_rates, parse_rates};
pub use utensils::{load_utensils, parse_utensils};

/// Options for loading.
#[derive(Debug, Clone, Copy, Default)]
pub struct ParseOptions {
    /// Turn every warning into an error.
    pub strict: bool,
}

/// How a parse is run, beyond what it means ([`ParseOptions`]): where it reports its
/// progress. The default reports nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct ParseControl<'a> {
    /// Updated with the bytes read out of the bytes of the input (phase `"parse"`).
    pub progress: Option<&'a Progress>,
    /// Bytes of text read as one chunk on one thread (0: the default). Any value gives the
    /// same result; tests use tiny chunks.
    #[doc(hidden)]
    pub chunk_bytes: usize,
}

impl ParseControl<'_> {
    fn chunk(&self) -> usize {
        if self.chunk_bytes == 0 {
            foon::DEFAULT_CHUNK_BYTES
        } else {
            self.chunk_bytes
        }
    }

    /// Bytes read ahead while the index is fed: one chunk per thread (two windows are held
    /// at once, the one feeding the index and the one being read, so a larger window only
    /// adds memory: a window's lines take several times its bytes until they are fed).
    fn window(&self) -> usize {
        self.chunk()
            .saturating_mul(crate::search::batch::max_threads())
    }
}

/// Line `n` as the `u32` the index keeps, or [`Error::TooLarge`] past it.
pub(crate) fn line_u32(n: u64) -> Result<u32> {
    u32::try_from(n).map_err(|_| Error::TooLarge {
        what: "lines",
        limit: u64::from(u32::MAX),
    })
}

/// Checks that `path` is a file that can be read to its end: regular files and pipes are (a
/// FIFO or a process substitution such as `<(zcat foon.txt.gz)` waits for its writer, as `cat`
/// does); devices and sockets are refused, so that `/dev/zero` is an error rather than a read
/// without end. Returns the size the file has now (0 for a pipe).
fn check_readable(path: &Path) -> Result<u64> {
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
    Ok(meta.len())
}

/// Reads a whole file; the error names the file (see [`check_readable`] for what is read).
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>> {
    check_readable(path)?;
    std::fs::read(path).map_err(|e| Error::io(path, e))
}

/// Reads from `file` into `buf` until it holds at least `want` bytes or the file ends;
/// returns whether it ended.
fn read_up_to(
    file: &mut std::fs::File,
    path: &Path,
    buf: &mut Vec<u8>,
    want: usize,
) -> Result<bool> {
    while buf.len() < want {
        let len = buf.len();
        buf.resize(want.min(len + (8 << 20)), 0);
        match file.read(&mut buf[len..]) {
            Ok(0) => {
                buf.truncate(len);
                return Ok(true);
            }
            Ok(n) => buf.truncate(len + n),
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => buf.truncate(len),
            Err(e) => return Err(Error::io(path, e)),
        }
    }
    Ok(false)
}

/// Windows of whole lines read from a file, so that the text is never held whole.
struct FileWindows<'p> {
    file: std::fs::File,
    path: &'p Path,
    /// Bytes read past the last line end of the previous window.
    carry: Vec<u8>,
    window: usize,
    ended: bool,
}

impl foon::Source<'static> for FileWindows<'_> {
    fn next_window(&mut self) -> Result<Option<Cow<'static, [u8]>>> {
        let mut w = std::mem::take(&mut self.carry);
        let mut want = self.window;
        // The carried bytes hold no line end: only what is read after them is searched.
        let mut searched = w.len();
        loop {
            if !self.ended {
                self.ended = read_up_to(&mut self.file, self.path, &mut w, want)?;
            }
            if self.ended {
                return Ok((!w.is_empty()).then_some(Cow::Owned(w)));
            }
            if let Some(i) = memchr::memrchr(b'\n', &w[searched..]) {
                let i = searched + i;
                self.carry = w[i + 1..].to_vec();
                w.truncate(i + 1);
                return Ok(Some(Cow::Owned(w)));
            }
            searched = w.len();
            // One line longer than a window: read on to its end.
            want = w.len().saturating_add(self.window);
        }
    }
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
    let mut b = Builder::for_bytes(data.len());
    parse_into(&mut b, data, path, opts, errors, cancel)?;
    b.try_finish()
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
    parse_into_with(b, data, path, opts, errors, cancel, ParseControl::default())
}

/// As [`parse_into`], run as `ctl` says (progress in bytes of `data`). FOON text is read in
/// chunks on the thread pool and fed to `b` in order: the result does not depend on the
/// number of threads.
pub fn parse_into_with(
    b: &mut Builder,
    data: &[u8],
    path: Option<&Path>,
    opts: ParseOptions,
    errors: Option<&mut Vec<Error>>,
    cancel: &(dyn Fn() -> bool + Sync),
    ctl: ParseControl<'_>,
) -> Result<()> {
    if json::is_json(data) {
        b.begin_source(path);
        if let Some(p) = ctl.progress {
            p.begin("parse", data.len() as u64);
        }
        let r = json::parse_impl(b, data, path, opts, errors, cancel);
        if let (Some(p), true) = (ctl.progress, r.is_ok()) {
            p.finish();
        }
        return r;
    }
    let text = lines::strip_bom(data);
    let mut windows = foon::InMemory {
        data: text,
        window: ctl.window(),
    };
    let bom = data.len() - text.len();
    text_into(
        b,
        &mut windows,
        path,
        opts,
        errors,
        cancel,
        ctl,
        (data.len() as u64, bom),
    )
}

/// Parses FOON text from the windows of `source` into `b` as one new source, counting
/// progress in bytes: `size` is (bytes in all, 0 when unknown; bytes of a byte-order mark
/// already dropped).
#[allow(clippy::too_many_arguments)]
fn text_into(
    b: &mut Builder,
    source: &mut dyn foon::Source<'_>,
    path: Option<&Path>,
    opts: ParseOptions,
    errors: Option<&mut Vec<Error>>,
    cancel: &(dyn Fn() -> bool + Sync),
    ctl: ParseControl<'_>,
    (total, bom): (u64, usize),
) -> Result<()> {
    b.begin_source(path);
    if let Some(p) = ctl.progress {
        p.begin("parse", total);
        p.add(bom as u64);
    }
    let r = foon::parse_stream(
        b,
        source,
        path,
        opts,
        errors,
        cancel,
        ctl.progress,
        ctl.chunk(),
    );
    if let (Some(p), true) = (ctl.progress, r.is_ok()) {
        p.finish();
    }
    r
}

/// As [`parse_into`] for the file at `path`, read as it is parsed: FOON text is read in
/// windows of whole lines (so the file is never held whole next to the index; the lab's JSON
/// is read whole). Progress is in bytes of the file (of unknown total for a pipe).
pub fn load_into(
    b: &mut Builder,
    path: &Path,
    opts: ParseOptions,
    errors: Option<&mut Vec<Error>>,
    cancel: &(dyn Fn() -> bool + Sync),
    ctl: ParseControl<'_>,
) -> Result<()> {
    if cancel() {
        return Err(Error::Cancelled);
    }
    let size = check_readable(path)?;
    let mut file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    // Enough of the start to tell JSON from text (its first byte that is not blank).
    let mut head = Vec::new();
    let mut ended = false;
    let step = 64 << 10;
    while !ended {
        let want = head.len() + step;
        ended = read_up_to(&mut file, path, &mut head, want)?;
        if head.len() >= 3
            && lines::strip_bom(&head)
                .iter()
                .any(|c| !c.is_ascii_whitespace())
        {
            break;
        }
    }
    if json::is_json(&head) {
        if !ended {
            file.read_to_end(&mut head)
                .map_err(|e| Error::io(path, e))?;
        }
        return parse_into_with(b, &head, Some(path), opts, errors, cancel, ctl);
    }
    let bom = head.len() - lines::strip_bom(&head).len();
    head.drain(..bom);
    let mut windows = FileWindows {
        file,
        path,
        carry: head,
        window: ctl.window(),
        ended,
    };
    text_into(
        b,
        &mut windows,
        Some(path),
        opts,
        errors,
        cancel,
        ctl,
        (size, bom),
    )
}

/// Reads a FOON file: an index file (told by its magic, or by its name: a `.foonidx` file
/// that is not a whole index is an error) is mapped; text or JSON is parsed (see
/// [`load_into`]: a regular file is read as it is parsed), progress as `ctl` says.
pub fn load_foon_with(
    path: &Path,
    opts: ParseOptions,
    cancel: &(dyn Fn() -> bool + Sync),
    ctl: ParseControl<'_>,
) -> Result<Foon> {
    if cancel() {
        return Err(Error::Cancelled);
    }
    // A regular file is probed for the index magic, then read as it is parsed; a pipe is read
    // once and its bytes tell.
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    let named = crate::index::file::is_index_name(path);
    if meta.is_file() {
        if crate::index::file::is_index_file(path) {
            return Foon::open_index(path);
        }
        let mut b = Builder::for_bytes(usize::try_from(meta.len()).unwrap_or(usize::MAX));
        load_into(&mut b, path, opts, None, cancel, ctl)?;
        return b.try_finish();
    }
    let data = read_file(path)?;
    if named || crate::index::file::is_index(&data) {
        return Foon::from_index_bytes(&data, path);
    }
    let mut b = Builder::for_bytes(data.len());
    parse_into_with(&mut b, &data, Some(path), opts, None, cancel, ctl)?;
    drop(data);
    b.try_finish()
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
/// [`parse_foon_cancellable`]). A file that starts with the index magic, or is named
/// `.foonidx`, is opened as an index ([`Foon::open_index`]: memory-mapped); text and JSON
/// are parsed into a builder sized from the file's length.
pub fn load_foon_cancellable(
    path: &Path,
    opts: ParseOptions,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Foon> {
    load_foon_with(path, opts, cancel, ParseControl::default())
}
