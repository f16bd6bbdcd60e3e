//! Identity hashing and the flat look-up tables of the index.
//!
//! Hashes are fixed-width (`u32`), seeded and platform independent, so that an index file
//! built on one machine answers the same look-ups on another:
//! - strings: the low 32 bits of XXH3-64 of the UTF-8 bytes with seed [`SEED`];
//! - rows of ids (object and FU identities): [`hash_words`], which folds each `u32` word into
//!   a 64-bit state (`h = (rotl(h, 5) ^ w) * K`, starting from [`SEED`]), then applies the
//!   `MurmurHash3` 64-bit finaliser to `h ^ count` and keeps the low 32 bits.
//!
//! A [`Table`] is an open-addressing table of `u32` ids: its size is a power of two, an empty
//! slot holds [`EMPTY`], probing is linear from `hash & (size - 1)`, and it is kept at most
//! half full (so it always has an empty slot). Each entry's hash is kept in a column beside
//! the table, so growing (and rebuilding it when an index is finished) never recomputes a
//! hash from the rows.

use super::col::Col;
use crate::error::{Error, Result};

/// The seed of every identity hash (format version 1).
pub const SEED: u64 = 0x464f_4f4e_4944_5831; // "FOONIDX1"

/// An empty table slot.
pub const EMPTY: u32 = u32::MAX;

const K: u64 = 0x9e37_79b9_7f4a_7c15;

/// Hash of a string (see the module documentation).
#[inline]
pub fn hash_str(s: &str) -> u32 {
    xxhash_rust::xxh3::xxh3_64_with_seed(s.as_bytes(), SEED) as u32
}

/// Incremental form of [`hash_words`].
#[derive(Clone, Copy)]
pub(crate) struct WordHasher {
    h: u64,
    n: u64,
}

impl WordHasher {
    #[inline]
    pub(crate) fn new() -> Self {
        Self { h: SEED, n: 0 }
    }

    #[inline]
    pub(crate) fn word(&mut self, w: u32) {
        self.h = (self.h.rotate_left(5) ^ u64::from(w)).wrapping_mul(K);
        self.n += 1;
    }

    #[inline]
    pub(crate) fn words(&mut self, ws: &[u32]) {
        for &w in ws {
            self.word(w);
        }
    }

    #[inline]
    pub(crate) fn finish(self) -> u32 {
        let mut x = self.h ^ self.n;
        x ^= x >> 33;
        x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
        x ^= x >> 33;
        x = x.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        x ^= x >> 33;
        x as u32
    }
}

/// Hash of a row of ids (see the module documentation).
#[inline]
pub fn hash_words(ws: &[u32]) -> u32 {
    let mut h = WordHasher::new();
    h.words(ws);
    h.finish()
}

/// An open-addressing table of ids (see the module documentation).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Table {
    pub(crate) slots: Col<u32>,
}

/// The table size for `n` entries: the smallest power of two at least `2 n`, and at least 8.
fn size_for(n: usize) -> Result<usize> {
    n.checked_mul(2)
        .and_then(usize::checked_next_power_of_two)
        .filter(|&s| s <= 1 << 32)
        .map(|s| s.max(8))
        .ok_or(Error::TooLarge {
            what: "table entries",
            limit: u64::from(u32::MAX / 2),
        })
}

impl Table {
    /// A table for `n` entries.
    pub(crate) fn with_capacity(n: usize) -> Result<Self> {
        Ok(Self {
            slots: vec![EMPTY; size_for(n)?].into(),
        })
    }

    /// Builds the table of ids `0..hashes.len()` at its canonical size, inserting in id order
    /// (so the same entries always give the same slots).
    pub(crate) fn rebuild(hashes: &[u32], hint: usize) -> Result<Self> {
        let mut t = Self::with_capacity(hashes.len().max(hint))?;
        let slots = t.slots.make_mut();
        let mask = slots.len() - 1;
        for (id, &h) in hashes.iter().enumerate() {
            let mut i = h as usize & mask;
            while slots[i] != EMPTY {
                i = (i + 1) & mask;
            }
            slots[i] = id as u32;
        }
        Ok(t)
    }

    /// The first id whose hash is `h` and for which `eq` holds. Ends on an empty slot, which a
    /// valid table always has (checked when an index file is opened).
    #[inline]
    pub(crate) fn find(
        &self,
        h: u32,
        hashes: &[u32],
        mut eq: impl FnMut(u32) -> bool,
    ) -> Option<u32> {
        let slots: &[u32] = &self.slots;
        if slots.is_empty() {
            return None;
        }
        let mask = slots.len() - 1;
        let mut i = h as usize & mask;
        for _ in 0..slots.len() {
            let id = slots[i];
            if id == EMPTY {
                return None;
            }
            if hashes.get(id as usize) == Some(&h) && eq(id) {
                return Some(id);
            }
            i = (i + 1) & mask;
        }
        None
    }

    /// Inserts id `id` (not present yet) with hash `h`; `hashes` holds the hash of every id
    /// (including `id`), from which the table grows when it would be more than half full.
    pub(crate) fn insert(&mut self, h: u32, id: u32, hashes: &[u32]) -> Result<()> {
        let n = hashes.len();
        if self.slots.is_empty() || n * 2 > self.slots.len() {
            *self = Self::rebuild(hashes, n.max(self.slots.len()))?;
            return Ok(());
        }
        let slots = self.slots.make_mut();
        let mask = slots.len() - 1;
        let mut i = h as usize & mask;
        while slots[i] != EMPTY {
            i = (i + 1) & mask;
        }
        slots[i] = id;
        Ok(())
    }

    pub(crate) fn heap_bytes(&self) -> usize {
        self.slots.heap_bytes()
    }
}

/// A build-time open-addressing table of `(hash, value)` pairs, the hash kept in the slot: a
/// probe compares hashes without reading the rows, and growing never reads them either. Its
/// size is a power of two, probing is linear from `hash & (size - 1)`, it is kept at most half
/// full. Values are `u32` below [`EMPTY`].
#[derive(Debug, Clone, Default)]
pub(crate) struct HashedTable {
    slots: Vec<u64>,
    len: usize,
}

const EMPTY_SLOT: u64 = u64::MAX;

impl HashedTable {
    /// A table for `n` entries.
    pub(crate) fn with_capacity(n: usize) -> Result<Self> {
        Ok(Self {
            slots: vec![EMPTY_SLOT; size_for(n)?],
            len: 0,
        })
    }

    /// The first value whose hash is `h` and for which `eq` holds.
    #[inline]
    pub(crate) fn find(&self, h: u32, mut eq: impl FnMut(u32) -> bool) -> Option<u32> {
        if self.slots.is_empty() {
            return None;
        }
        let mask = self.slots.len() - 1;
        let mut i = h as usize & mask;
        loop {
            let s = self.slots[i];
            if s == EMPTY_SLOT {
                return None;
            }
            if (s >> 32) as u32 == h && eq(s as u32) {
                return Some(s as u32);
            }
            i = (i + 1) & mask;
        }
    }

    /// Inserts `value` (not present yet, below [`EMPTY`]) with hash `h`.
    pub(crate) fn insert(&mut self, h: u32, value: u32) -> Result<()> {
        if (self.len + 1) * 2 > self.slots.len() {
            let mut t = Self::with_capacity((self.len + 1).max(self.slots.len()))?;
            for &s in &self.slots {
                if s != EMPTY_SLOT {
                    t.put(s);
                }
            }
            t.len = self.len;
            *self = t;
        }
        self.put(u64::from(h) << 32 | u64::from(value));
        self.len += 1;
        Ok(())
    }

    #[inline]
    fn put(&mut self, s: u64) {
        let mask = self.slots.len() - 1;
        let mut i = (s >> 32) as usize & mask;
        while self.slots[i] != EMPTY_SLOT {
            i = (i + 1) & mask;
        }
        self.slots[i] = s;
    }
}

#[cfg(test)]
mod tests {
    use super::{HashedTable, Table, hash_str, hash_words};

    /// The hashes are part of the file format: fixed values, whatever the platform.
    #[test]
    fn hashes_are_fixed() {
        assert_eq!(hash_words(&[]), hash_words(&[]));
        assert_ne!(hash_words(&[1, 2]), hash_words(&[2, 1]));
        assert_ne!(hash_words(&[0]), hash_words(&[0, 0]));
        assert_eq!(hash_str("egg"), hash_str("egg"));
        assert_ne!(hash_str("egg"), hash_str("eggs"));
        // Pinned: a change here is a new format version.
        assert_eq!(hash_words(&[]), 0xc1a6_b4aa);
        assert_eq!(hash_words(&[1, 2, 3]), 0xfcc0_0f2e);
        assert_eq!(hash_str("egg"), 0xb38e_27f2);
    }

    #[test]
    fn table_grows_from_kept_hashes() {
        let mut hashes = Vec::new();
        let mut t = Table::default();
        for id in 0..1000u32 {
            let h = hash_words(&[id % 300, id]);
            hashes.push(h);
            t.insert(h, id, &hashes).unwrap();
        }
        assert!(t.slots.len().is_power_of_two() && t.slots.len() >= 2000);
        for id in 0..1000u32 {
            assert_eq!(t.find(hashes[id as usize], &hashes, |x| x == id), Some(id));
        }
        assert_eq!(t.find(7, &hashes, |_| false), None);
        let canon = Table::rebuild(&hashes, 0).unwrap();
        assert_eq!(canon, Table::rebuild(&hashes, 0).unwrap());
    }

    #[test]
    fn hashed_table_grows_and_finds() {
        let mut t = HashedTable::default();
        for v in 0..1000u32 {
            t.insert(hash_words(&[v % 7]), v).unwrap();
        }
        for v in 0..1000u32 {
            assert_eq!(t.find(hash_words(&[v % 7]), |x| x == v), Some(v));
        }
        assert_eq!(t.find(hash_words(&[3]), |x| x == 5000), None);
    }
}
