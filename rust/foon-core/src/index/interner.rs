//! The string interner of the index: every label, state, ingredient, container and motion
//! stored once.

use super::col::Col;
use super::hash::{Table, hash_str};
use crate::error::{Error, Result};

/// A list of strings in one UTF-8 text column with end offsets (`u64`, so the text may pass
/// 4 GB). Valid by construction, or checked when an index file is opened (ends increasing,
/// on character boundaries, the last one at the end of the text).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct StrList {
    pub(crate) text: Col<u8>,
    pub(crate) ends: Col<u64>,
}

impl StrList {
    #[inline]
    pub(crate) fn get(&self, i: usize) -> &str {
        let ends: &[u64] = &self.ends;
        let Some(&end) = ends.get(i) else { return "" };
        let start = if i == 0 { 0 } else { ends[i - 1] };
        self.text
            .get(start as usize..end as usize)
            .and_then(|b| std::str::from_utf8(b).ok())
            .unwrap_or("")
    }

    pub(crate) fn push(&mut self, s: &str) {
        self.text.extend_from_slice(s.as_bytes());
        self.ends.push(self.text.len() as u64);
    }

    pub(crate) fn len(&self) -> usize {
        self.ends.len()
    }

    pub(crate) fn heap_bytes(&self) -> usize {
        self.text.heap_bytes() + self.ends.heap_bytes()
    }
}

/// String interner: every label, state, ingredient, container and motion is stored once, in
/// one text column with end offsets; a flat table of ids finds a string by its hash, which is
/// kept per string.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Interner {
    pub(crate) list: StrList,
    pub(crate) hashes: Col<u32>,
    pub(crate) table: Table,
}

impl Interner {
    /// The id of `s`, added when new.
    ///
    /// # Panics
    /// Past `u32::MAX` strings (see [`Interner::try_intern`]).
    pub fn intern(&mut self, s: &str) -> u32 {
        match self.try_intern(s) {
            Ok(id) => id,
            Err(e) => panic!("{e}"),
        }
    }

    /// The id of `s`, added when new; [`Error::TooLarge`] past `u32::MAX` strings.
    pub fn try_intern(&mut self, s: &str) -> Result<u32> {
        let h = hash_str(s);
        if let Some(id) = self.find(h, s) {
            return Ok(id);
        }
        let id = Error::check_id(self.list.len(), "distinct strings")?;
        self.list.push(s);
        self.hashes.push(h);
        self.table.insert(h, id, &self.hashes)?;
        Ok(id)
    }

    /// Adds `s`, not present yet, of hash `h` (`hash_str(s)`), without the look-up table,
    /// which [`Interner::finish`] builds (for a builder that keeps its own).
    pub(crate) fn push_new(&mut self, s: &str, h: u32) -> Result<u32> {
        let id = Error::check_id(self.list.len(), "distinct strings")?;
        self.list.push(s);
        self.hashes.push(h);
        Ok(id)
    }

    #[inline]
    fn find(&self, h: u32, s: &str) -> Option<u32> {
        self.table
            .find(h, &self.hashes, |id| self.list.get(id as usize) == s)
    }

    pub fn get(&self, s: &str) -> Option<u32> {
        self.find(hash_str(s), s)
    }

    /// The text of id `id` (empty for [`NONE`](super::NONE) or an unknown id).
    #[inline]
    pub fn text(&self, id: u32) -> &str {
        self.list.get(id as usize)
    }

    pub fn len(&self) -> usize {
        self.list.len()
    }

    pub fn is_empty(&self) -> bool {
        self.list.len() == 0
    }

    /// Heap bytes used (or mapped): text, ends, hashes and table.
    pub fn heap_bytes(&self) -> usize {
        self.list.heap_bytes() + self.hashes.heap_bytes() + self.table.heap_bytes()
    }

    /// Rebuilds the table at its canonical size (see [`Table::rebuild`]).
    pub(crate) fn finish(&mut self) -> Result<()> {
        self.table = Table::rebuild(&self.hashes, 0)?;
        self.list.text.shrink_to_fit();
        self.list.ends.shrink_to_fit();
        self.hashes.shrink_to_fit();
        Ok(())
    }

    /// Reserves room for `n` strings of `bytes` bytes in all (the look-up table is built by
    /// [`Interner::finish`]).
    pub(crate) fn reserve(&mut self, n: usize, bytes: usize) {
        self.list.ends.make_mut().reserve(n);
        self.list.text.make_mut().reserve(bytes);
        self.hashes.make_mut().reserve(n);
    }
}
