//! The stable serialised form of a parsed FOON, for pickling: its index as `.foonidx` bytes
//! (strings, objects, units with every object occurrence as written, lines, sources and
//! provenance: unit indices and object ids come back as they were), then its load report
//! (the duplicates it dropped, its warnings and notes), which an index file does not carry.

use std::path::{Path, PathBuf};

use foon_core::index::DuplicateFu;
use foon_core::{Foon, Location, Report, Warning, WarningKind};

const MAGIC: &[u8] = b"FOON-PICKLE\x02";

/// Every warning kind, by its code in the serialised form (the index in this list).
const KINDS: [WarningKind; 9] = [
    WarningKind::NoMotion,
    WarningKind::TwoMotions,
    WarningKind::Unterminated,
    WarningKind::SpacedIngredient,
    WarningKind::DuplicateIngredient,
    WarningKind::EmptyContainer,
    WarningKind::TwoContainers,
    WarningKind::TwoIngredientLists,
    WarningKind::EmptyIngredient,
];

fn kind_code(k: WarningKind) -> u8 {
    // Exhaustive: a new kind does not compile until it has a code here and in KINDS.
    match k {
        WarningKind::NoMotion => 0,
        WarningKind::TwoMotions => 1,
        WarningKind::Unterminated => 2,
        WarningKind::SpacedIngredient => 3,
        WarningKind::DuplicateIngredient => 4,
        WarningKind::EmptyContainer => 5,
        WarningKind::TwoContainers => 6,
        WarningKind::TwoIngredientLists => 7,
        WarningKind::EmptyIngredient => 8,
    }
}

struct Out(Vec<u8>);

impl Out {
    fn u8(&mut self, v: u8) {
        self.0.push(v);
    }
    fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn u64(&mut self, v: u64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn len(&mut self, n: usize) {
        self.u32(n as u32);
    }
    fn str(&mut self, s: &str) {
        self.len(s.len());
        self.0.extend_from_slice(s.as_bytes());
    }
    fn opt_str(&mut self, s: Option<&str>) {
        match s {
            Some(s) => {
                self.u8(1);
                self.str(s);
            }
            None => self.u8(0),
        }
    }
}

/// Serialises `foon` (see the module documentation).
pub(crate) fn encode(foon: &Foon) -> Vec<u8> {
    let index = foon.index_bytes();
    let mut o = Out(Vec::with_capacity(index.len() + 64));
    o.0.extend_from_slice(MAGIC);
    o.u64(index.len() as u64);
    o.0.extend_from_slice(&index);
    drop(index);
    o.len(foon.duplicates().len());
    for d in foon.duplicates() {
        o.u32(d.line);
        o.u32(d.of);
        o.u32(d.source);
    }
    for list in [foon.warnings(), foon.notes()] {
        o.len(list.len());
        for w in list {
            let path = w.at.path.as_ref().map(|p| p.to_string_lossy().into_owned());
            o.opt_str(path.as_deref());
            o.u64(w.at.line);
            o.u32(w.at.column);
            o.u8(kind_code(w.kind));
            o.str(&w.message);
        }
    }
    o.0
}

struct In<'a> {
    data: &'a [u8],
}

type Res<T> = Result<T, String>;

impl<'a> In<'a> {
    fn take(&mut self, n: usize) -> Res<&'a [u8]> {
        if self.data.len() < n {
            return Err("the data ends too early".into());
        }
        let (a, b) = self.data.split_at(n);
        self.data = b;
        Ok(a)
    }
    fn u8(&mut self) -> Res<u8> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Res<u32> {
        Ok(u32::from_le_bytes(
            self.take(4)?.try_into().unwrap_or_default(),
        ))
    }
    fn u64(&mut self) -> Res<u64> {
        Ok(u64::from_le_bytes(
            self.take(8)?.try_into().unwrap_or_default(),
        ))
    }
    fn len(&mut self) -> Res<usize> {
        let n = self.u32()? as usize;
        // Every element takes at least one byte: a longer count is corrupt data.
        if n > self.data.len() {
            return Err("a count is larger than the data".into());
        }
        Ok(n)
    }
    fn str(&mut self) -> Res<&'a str> {
        let n = self.len()?;
        std::str::from_utf8(self.take(n)?).map_err(|_| "a string is not UTF-8".to_owned())
    }
    fn opt_str(&mut self) -> Res<Option<&'a str>> {
        match self.u8()? {
            0 => Ok(None),
            1 => self.str().map(Some),
            _ => Err("bad optional string".into()),
        }
    }
}

/// Rebuilds a FOON from [`encode`]'s output.
pub(crate) fn decode(data: &[u8]) -> Res<Foon> {
    let mut r = In { data };
    if r.take(MAGIC.len())? != MAGIC {
        return Err("not a serialised FOON of this version".into());
    }
    let n = usize::try_from(r.u64()?).map_err(|_| "a count is larger than the data")?;
    let index = r.take(n)?;
    let mut foon =
        Foon::from_index_bytes(index, Path::new("<pickle>")).map_err(|e| e.to_string())?;
    let mut report = Report::default();
    let n_dup = r.len()?;
    for _ in 0..n_dup {
        let line = r.u32()?;
        let of = r.u32()?;
        let source = r.u32()?;
        if of as usize >= foon.fu_count() || source as usize >= foon.source_count() {
            return Err("a duplicate of an unknown unit or source".into());
        }
        report.duplicates.push(DuplicateFu { line, of, source });
    }
    for notes in [false, true] {
        let n = r.len()?;
        for _ in 0..n {
            let path = r.opt_str()?.map(PathBuf::from);
            let line = r.u64()?;
            let column = r.u32()?;
            let kind = *KINDS
                .get(r.u8()? as usize)
                .ok_or("an unknown warning kind")?;
            let message = r.str()?.to_owned();
            let w = Warning {
                at: Location { path, line, column },
                kind,
                message,
            };
            if notes {
                report.notes.push(w);
            } else {
                report.warnings.push(w);
            }
        }
    }
    if !r.data.is_empty() {
        return Err("data after the end".into());
    }
    foon.set_report(report);
    Ok(foon)
}
