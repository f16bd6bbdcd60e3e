//! [`KitchenSet`]: named kitchens, read from one JSON object of id → items, a folder of
//! kitchen files, or one base kitchen with per-id additions and removals (the formats are in
//! `docs/BATCH.md`, "Formats").

use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

use rustc_hash::FxHashMap;
use serde::Deserializer as _;
use serde::de::{MapAccess, Visitor};
use serde_json::value::RawValue;

use crate::error::{Error, InputKind, Result};
use crate::kitchen::{Kitchen, Reader};

/// A kitchen given as a base plus a delta: the base (shared by every kitchen of the set built
/// on it), the items added and the items removed. The kitchen is the base without the
/// removed items, then the added ones.
#[derive(Debug, Clone)]
pub struct Delta {
    pub base: Arc<Kitchen>,
    pub add: Kitchen,
    pub remove: Kitchen,
}

/// One kitchen of a set: a kitchen given by its items, or a base plus a delta. A delta
/// kitchen is built from its base when it is asked for ([`Entry::kitchen`]) and not kept, so a
/// set of thousands of deltas over one large base costs the base once; its fingerprint is
/// kept once computed.
#[derive(Debug, Clone)]
pub struct Entry {
    items: Option<Arc<Kitchen>>,
    delta: Option<Delta>,
    fingerprint: OnceLock<u128>,
}

impl Entry {
    fn plain(kitchen: Arc<Kitchen>) -> Self {
        Self {
            items: Some(kitchen),
            delta: None,
            fingerprint: OnceLock::new(),
        }
    }

    fn of_delta(delta: Delta) -> Self {
        Self {
            items: None,
            delta: Some(delta),
            fingerprint: OnceLock::new(),
        }
    }

    /// The kitchen (for a delta kitchen: its base without the removed items, then the added
    /// ones, built now).
    pub fn kitchen(&self) -> Result<Arc<Kitchen>> {
        match (&self.items, &self.delta) {
            (Some(k), _) => Ok(Arc::clone(k)),
            (None, Some(d)) => Ok(Arc::new(d.base.without(&d.remove).with(&d.add)?)),
            (None, None) => Ok(Arc::new(Kitchen::new())),
        }
    }

    /// [`Kitchen::fingerprint`] of [`Entry::kitchen`] (computed once).
    pub fn fingerprint(&self) -> Result<u128> {
        if let Some(f) = self.fingerprint.get() {
            return Ok(*f);
        }
        let f = match &self.delta {
            // From the base's, in the size of the delta.
            Some(d) if self.items.is_none() => d.base.fingerprint_with_changes(&d.add, &d.remove),
            _ => self.kitchen()?.fingerprint(),
        };
        Ok(*self.fingerprint.get_or_init(|| f))
    }

    /// The base and delta of a delta kitchen.
    pub fn delta(&self) -> Option<&Delta> {
        self.delta.as_ref()
    }
}

/// Named kitchens (ids unique, in the order they were given).
#[derive(Debug, Clone, Default)]
pub struct KitchenSet {
    ids: Vec<String>,
    entries: Vec<Entry>,
    index: FxHashMap<String, usize>,
}

/// The magic of [`KitchenSet::to_bytes`]: the format's name and version.
const MAGIC: &[u8; 8] = b"FOONKS01";

fn bytes_error(why: &str) -> Error {
    Error::Invalid(format!("not a valid serialised kitchen set: {why}"))
}

impl KitchenSet {
    /// An empty set.
    pub fn new() -> Self {
        Self::default()
    }

    /// A set of `kitchens`, in order; a repeated id is an error.
    pub fn from_kitchens(
        kitchens: impl IntoIterator<Item = (String, Arc<Kitchen>)>,
    ) -> Result<Self> {
        let mut s = Self::new();
        for (id, k) in kitchens {
            s.push(id, Entry::plain(k))
                .map_err(|id| Error::Invalid(format!("kitchen id '{id}' is given twice")))?;
        }
        Ok(s)
    }

    /// A set of kitchens each made from `base`: for each id, the base without the items of
    /// its `remove`, then the items of its `add`. A repeated id is an error.
    pub fn with_deltas(
        base: &Arc<Kitchen>,
        deltas: impl IntoIterator<Item = (String, Kitchen, Kitchen)>,
    ) -> Result<Self> {
        let mut s = Self::new();
        for (id, add, remove) in deltas {
            let delta = Delta {
                base: Arc::clone(base),
                add,
                remove,
            };
            s.push(id, Entry::of_delta(delta))
                .map_err(|id| Error::Invalid(format!("kitchen id '{id}' is given twice")))?;
        }
        Ok(s)
    }

    /// Adds a kitchen; the id back when it is already there.
    fn push(&mut self, id: String, entry: Entry) -> std::result::Result<(), String> {
        if self.index.contains_key(&id) {
            return Err(id);
        }
        self.index.insert(id.clone(), self.ids.len());
        self.ids.push(id);
        self.entries.push(entry);
        Ok(())
    }

    /// The ids, in order.
    pub fn ids(&self) -> &[String] {
        &self.ids
    }

    pub fn len(&self) -> usize {
        self.ids.len()
    }

    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// The position of `id`.
    pub fn position(&self, id: &str) -> Option<usize> {
        self.index.get(id).copied()
    }

    /// The kitchen at position `i`.
    pub fn entry(&self, i: usize) -> &Entry {
        &self.entries[i]
    }

    /// The kitchen of `id` (see [`Entry::kitchen`]).
    pub fn get(&self, id: &str) -> Option<Result<Arc<Kitchen>>> {
        self.position(id).map(|i| self.entries[i].kitchen())
    }

    /// The fingerprint of the whole set: XXH3-128 of a tag, the number of kitchens and, per
    /// kitchen in order, its id (length-prefixed) and [`Kitchen::fingerprint`], all
    /// little-endian (the same on every platform).
    pub fn fingerprint(&self) -> Result<u128> {
        let mut b = Vec::with_capacity(32 + self.len() * 40);
        b.extend_from_slice(b"foon-kitchen-set-1");
        b.extend_from_slice(&(self.len() as u64).to_le_bytes());
        for (id, e) in self.ids.iter().zip(&self.entries) {
            b.extend_from_slice(&(id.len() as u64).to_le_bytes());
            b.extend_from_slice(id.as_bytes());
            b.extend_from_slice(&e.fingerprint()?.to_le_bytes());
        }
        Ok(xxhash_rust::xxh3::xxh3_128(&b))
    }

    /// Reads a kitchen set: a folder of kitchen files, or a JSON file of either object form.
    pub fn load(path: &Path) -> Result<Self> {
        if path.is_dir() {
            return Self::load_folder(path);
        }
        let data = crate::parse::read_file(path)?;
        Self::parse(&data, Some(path))
    }

    /// Reads every kitchen file of a folder (id: the file name without its extension), in
    /// file-name order. Hidden files and sub-folders are skipped; two files with the same
    /// id are an error, and so is any other entry that is not a file to read (a broken
    /// link, a pipe: a kitchen missing from the set would otherwise show only as queries
    /// of an unknown kitchen, and a pipe could block the read).
    pub fn load_folder(dir: &Path) -> Result<Self> {
        let read = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
        let mut files: Vec<PathBuf> = Vec::new();
        for entry in read {
            let entry = entry.map_err(|e| Error::io(dir, e))?;
            let p = entry.path();
            if entry.file_name().to_string_lossy().starts_with('.') {
                continue;
            }
            // Links are followed: a link to a file is that file, to a folder a sub-folder.
            match std::fs::metadata(&p) {
                Ok(m) if m.is_dir() => {}
                Ok(m) if m.is_file() => files.push(p),
                Ok(_) => {
                    return Err(Error::io(
                        &p,
                        std::io::Error::new(
                            std::io::ErrorKind::InvalidInput,
                            "not a kitchen file (not a regular file)",
                        ),
                    ));
                }
                Err(e) => return Err(Error::io(&p, e)),
            }
        }
        files.sort();
        let mut s = Self::new();
        for p in files {
            let id = p
                .file_stem()
                .map(|x| x.to_string_lossy().into_owned())
                .unwrap_or_default();
            let k = Kitchen::load(&p)?;
            s.push(id, Entry::plain(Arc::new(k))).map_err(|id| {
                Error::parse(
                    InputKind::Kitchen,
                    Some(&p),
                    1,
                    1,
                    format!("kitchen id '{id}' is given twice (two files named '{id}.*')"),
                )
            })?;
        }
        Ok(s)
    }

    /// Parses the JSON forms of a kitchen set (`path` names the source in messages; relative
    /// base paths are relative to its folder): `{id: [items]}`, or `{"base": [items] |
    /// "path", "kitchens": {id: {"add": [items], "remove": [items]}}}`.
    pub fn parse(data: &[u8], path: Option<&Path>) -> Result<Self> {
        let data = data.strip_prefix(b"\xef\xbb\xbf").unwrap_or(data);
        let text = std::str::from_utf8(data).map_err(|e| {
            let (line, column) = position(data, e.valid_up_to());
            parse_error(path, line, column, "invalid UTF-8")
        })?;
        let top = entries(text, path, "a JSON object of kitchens")?;
        let is_delta = top.iter().any(|(k, _, _)| k == "base" || k == "kitchens");
        if !is_delta {
            let mut s = Self::new();
            for (id, raw, key_at) in top {
                let k = kitchen_at(text, raw, path)?;
                s.push(id, Entry::plain(Arc::new(k))).map_err(|id| {
                    at_error(
                        text,
                        path,
                        key_at,
                        format!("kitchen id '{id}' is given twice"),
                    )
                })?;
            }
            return Ok(s);
        }
        let mut base = None;
        let mut kitchens = None;
        for (key, raw, key_at) in top {
            match key.as_str() {
                "base" if base.is_none() => base = Some(raw),
                "kitchens" if kitchens.is_none() => kitchens = Some(raw),
                "base" | "kitchens" => {
                    return Err(at_error(
                        text,
                        path,
                        key_at,
                        format!("'{key}' is given twice"),
                    ));
                }
                _ => {
                    return Err(at_error(
                        text,
                        path,
                        key_at,
                        format!("unknown field '{key}' (expected base, kitchens)"),
                    ));
                }
            }
        }
        let (Some(base), Some(kitchens)) = (base, kitchens) else {
            return Err(parse_error(
                path,
                1,
                1,
                "a kitchen set with a base needs both 'base' and 'kitchens'",
            ));
        };
        let base = if base.get().trim_start().starts_with('"') {
            let rel: String = serde_json::from_str(base.get())
                .map_err(|e| at_error(text, path, offset(text, base), e.to_string()))?;
            let dir = path.and_then(Path::parent).unwrap_or(Path::new(""));
            // A base that cannot be read is an error of the set, at its 'base' field; one
            // that is malformed, of the base's own file.
            Kitchen::load(&dir.join(&rel)).map_err(|e| match e {
                Error::Io { path: p, source } => at_error(
                    text,
                    path,
                    offset(text, base),
                    format!(
                        "the base kitchen '{rel}' cannot be read ({}: {source})",
                        p.display()
                    ),
                ),
                e => e,
            })?
        } else {
            kitchen_at(text, base, path)?
        };
        let at = offset(text, kitchens);
        let mut deltas = Vec::new();
        let mut seen = rustc_hash::FxHashSet::default();
        for (id, raw, key_at) in entries(kitchens.get(), path, "a JSON object of kitchens")
            .map_err(|e| shift(e, text, at))?
        {
            let key_at = key_at + at;
            if !seen.insert(id.clone()) {
                return Err(at_error(
                    text,
                    path,
                    key_at,
                    format!("kitchen id '{id}' is given twice"),
                ));
            }
            let raw_at = offset(text, raw);
            let mut add = Kitchen::new();
            let mut remove = Kitchen::new();
            for (field, v, f_at) in entries(raw.get(), path, "an object with add, remove")
                .map_err(|e| shift(e, text, raw_at))?
            {
                match field.as_str() {
                    "add" => add = kitchen_at(text, v, path)?,
                    "remove" => remove = kitchen_at(text, v, path)?,
                    _ => {
                        return Err(at_error(
                            text,
                            path,
                            f_at + raw_at,
                            format!("unknown field '{field}' (expected add, remove)"),
                        ));
                    }
                }
            }
            deltas.push((id, add, remove));
        }
        Self::with_deltas(&Arc::new(base), deltas)
    }

    /// The set as bytes (for pickling to other processes): a magic, the count, then per
    /// kitchen its id and either its kitchen's bytes or (for a delta kitchen) the index of its
    /// base and its add and remove kitchens; bases once each. All little-endian.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::new();
        out.extend_from_slice(MAGIC);
        let mut bases: Vec<&Arc<Kitchen>> = Vec::new();
        for e in &self.entries {
            if let Some(d) = &e.delta {
                if !bases.iter().any(|b| Arc::ptr_eq(b, &d.base)) {
                    bases.push(&d.base);
                }
            }
        }
        put_u32(&mut out, bases.len() as u32);
        for b in &bases {
            put_blob(&mut out, &b.to_bytes());
        }
        put_u32(&mut out, self.len() as u32);
        for (id, e) in self.ids.iter().zip(&self.entries) {
            put_blob(&mut out, id.as_bytes());
            match &e.delta {
                None => {
                    put_u32(&mut out, u32::MAX);
                    let k = e
                        .items
                        .as_deref()
                        .map_or_else(|| Kitchen::new().to_bytes(), Kitchen::to_bytes);
                    put_blob(&mut out, &k);
                }
                Some(d) => {
                    let b = bases.iter().position(|b| Arc::ptr_eq(b, &d.base));
                    put_u32(&mut out, b.unwrap_or(0) as u32);
                    put_blob(&mut out, &d.add.to_bytes());
                    put_blob(&mut out, &d.remove.to_bytes());
                }
            }
        }
        out
    }

    /// Reads [`KitchenSet::to_bytes`] (anything else is an error, never a panic).
    pub fn from_bytes(data: &[u8]) -> Result<Self> {
        let mut r = Reader::new(data, bytes_error);
        if r.take(8)? != MAGIC {
            return Err(bytes_error("wrong magic or version"));
        }
        let nb = r.count()?;
        let mut bases = Vec::with_capacity(nb);
        for _ in 0..nb {
            bases.push(Arc::new(Kitchen::from_bytes(r.blob()?)?));
        }
        let n = r.count()?;
        let mut s = Self::new();
        for _ in 0..n {
            let id = std::str::from_utf8(r.blob()?)
                .map_err(|_| bytes_error("invalid UTF-8"))?
                .to_owned();
            let tag = r.u32()?;
            let entry = if tag == u32::MAX {
                Entry::plain(Arc::new(Kitchen::from_bytes(r.blob()?)?))
            } else {
                let base = bases
                    .get(tag as usize)
                    .ok_or_else(|| bytes_error("a base index is out of range"))?;
                let add = Kitchen::from_bytes(r.blob()?)?;
                let remove = Kitchen::from_bytes(r.blob()?)?;
                Entry::of_delta(Delta {
                    base: Arc::clone(base),
                    add,
                    remove,
                })
            };
            s.push(id, entry)
                .map_err(|_| bytes_error("a kitchen id is repeated"))?;
        }
        if !r.rest.is_empty() {
            return Err(bytes_error("trailing bytes"));
        }
        Ok(s)
    }
}

fn put_u32(out: &mut Vec<u8>, x: u32) {
    out.extend_from_slice(&x.to_le_bytes());
}

fn put_blob(out: &mut Vec<u8>, b: &[u8]) {
    out.extend_from_slice(&(b.len() as u64).to_le_bytes());
    out.extend_from_slice(b);
}

/// 1-based line and character column of byte `at` of `data`.
fn position(data: &[u8], at: usize) -> (u64, u32) {
    let before = &data[..at.min(data.len())];
    let line = memchr::memchr_iter(b'\n', before).count() as u64 + 1;
    let start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    let col = String::from_utf8_lossy(&before[start..]).chars().count() as u32 + 1;
    (line, col)
}

fn parse_error(path: Option<&Path>, line: u64, column: u32, reason: impl Into<String>) -> Error {
    Error::parse(InputKind::Kitchen, path, line, column, reason)
}

/// An error at byte `at` of `text`.
fn at_error(text: &str, path: Option<&Path>, at: usize, reason: impl Into<String>) -> Error {
    let (line, column) = position(text.as_bytes(), at);
    parse_error(path, line, column, reason)
}

/// The byte offset of `raw` (a slice of `text`) in `text`.
fn offset(text: &str, raw: &RawValue) -> usize {
    (raw.get().as_ptr() as usize).saturating_sub(text.as_ptr() as usize)
}

/// A parse error of a piece of `text` starting at byte `at`, moved to its place in `text`.
fn shift(e: Error, text: &str, at: usize) -> Error {
    match e {
        Error::Parse {
            at: loc,
            kind,
            reason,
        } => {
            let (line0, col0) = position(text.as_bytes(), at);
            let line = line0 + loc.line - 1;
            let column = if loc.line == 1 {
                col0 + loc.column - 1
            } else {
                loc.column
            };
            Error::Parse {
                at: crate::error::Location {
                    line,
                    column,
                    ..loc
                },
                kind,
                reason,
            }
        }
        e => e,
    }
}

/// The kitchen of the JSON value `raw` (a slice of `text`), errors at their place in `text`.
fn kitchen_at(text: &str, raw: &RawValue, path: Option<&Path>) -> Result<Kitchen> {
    let at = offset(text, raw);
    if !raw.get().trim_start().starts_with('[') {
        return Err(at_error(text, path, at, "expected a JSON list of objects"));
    }
    Kitchen::parse(raw.get().as_bytes(), path).map_err(|e| shift(e, text, at))
}

/// The entries of a JSON object, in order, each (key, value, byte offset of the key in
/// `text`); repeated keys are kept (the callers say what a repeat means).
fn entries<'a>(
    text: &'a str,
    path: Option<&Path>,
    what: &str,
) -> Result<Vec<(String, &'a RawValue, usize)>> {
    struct Entries<'a>(&'a str);
    impl<'de> Visitor<'de> for Entries<'de> {
        type Value = Vec<(String, &'de RawValue, usize)>;
        fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("a JSON object")
        }
        fn visit_map<A: MapAccess<'de>>(
            self,
            mut m: A,
        ) -> std::result::Result<Self::Value, A::Error> {
            let mut out = Vec::new();
            while let Some(k) = m.next_key::<String>()? {
                let v: &'de RawValue = m.next_value()?;
                // The key ends just before the value's colon: find its opening quote.
                let vat = (v.get().as_ptr() as usize).saturating_sub(self.0.as_ptr() as usize);
                let head = &self.0[..vat];
                let kat = head
                    .rfind(':')
                    .and_then(|c| head[..c].rfind('"'))
                    .and_then(|q| head[..q].rfind('"'))
                    .unwrap_or(vat);
                out.push((k, v, kat));
            }
            Ok(out)
        }
    }
    let mut de = serde_json::Deserializer::from_str(text);
    if !text.trim_start().starts_with('{') {
        let at = text.len() - text.trim_start().len();
        return Err(at_error(text, path, at, format!("expected {what}")));
    }
    let v = de
        .deserialize_map(Entries(text))
        .and_then(|v| de.end().map(|()| v))
        .map_err(|e| json_error(text, path, &e))?;
    Ok(v)
}

fn json_error(text: &str, path: Option<&Path>, e: &serde_json::Error) -> Error {
    let msg = e.to_string();
    let reason = msg
        .rsplit_once(" at line ")
        .map_or(msg.as_str(), |(r, _)| r)
        .to_owned();
    let line = e.line().max(1);
    let column = text.split('\n').nth(line - 1).map_or(e.column(), |l| {
        let mut b = e.column().saturating_sub(1).min(l.len());
        while !l.is_char_boundary(b) {
            b -= 1;
        }
        l[..b].chars().count() + 1
    });
    parse_error(path, line as u64, column.max(1) as u32, reason)
}
