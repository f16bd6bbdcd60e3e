//! A bounded, thread-safe cache of prepared kitchens, for whoever prepares many kitchens
//! (batches of queries over thousands of kitchens).
//!
//! - **Key**: ([`Foon::fingerprint`], [`PreparedBase::key`], kitchen fingerprint, level): the
//!   FOON's content, the utensils and rates, the kitchen and the identity level it was matched
//!   at. The kitchen fingerprint is [`Kitchen::fingerprint`] for a kitchen given by its items,
//!   or [`objects_fingerprint`] for one given as object ids (level 0 then, so the two kinds
//!   never meet). All are fixed-width and the same on every platform, so keys can be computed
//!   in one process and compared in another.
//! - **Bound**: at most [`CacheLimits::max_entries`] kitchens and
//!   [`CacheLimits::max_bytes`] bytes, least recently used first out. The bytes of an entry are
//!   [`Prepared::heap_bytes`]: its own data, not the shared base (counted once, in the base
//!   cache), measured when it is inserted and again each time it is returned, since what a
//!   prepared kitchen computes on first use (ranks, optima) makes it grow after insertion.
//!   An entry larger than the whole byte budget is returned but not kept. Bases are kept apart,
//!   at most [`CacheLimits::max_bases`] of them, least recently used first out.
//! - **Threads**: one mutex around the tables, never held while a kitchen or a base is
//!   prepared: two threads that miss the same key at once both prepare it, and the first
//!   one stored is kept and returned to both.

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use rustc_hash::FxHashMap;

use crate::error::Result;
use crate::index::Foon;
use crate::kitchen::Kitchen;
use crate::model::MotionRates;
use crate::prepare::{Prepared, PreparedBase};

/// The key of a prepared kitchen (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CacheKey {
    /// [`Foon::fingerprint`].
    pub foon: [u8; 16],
    /// [`PreparedBase::key`]: the utensils, rates and default rate.
    pub base: u128,
    /// [`Kitchen::fingerprint`], or [`objects_fingerprint`] for object ids.
    pub kitchen: u128,
    /// The identity level the kitchen was matched at (1, 2, 3), or 0 for object ids.
    pub level: u8,
}

/// The fingerprint of a kitchen given as object ids: XXH3-128 of its distinct ids in
/// increasing order, little-endian, after a tag (any order and repeats give the same).
pub fn objects_fingerprint(ids: &[u32]) -> u128 {
    let mut v = ids.to_vec();
    v.sort_unstable();
    v.dedup();
    let mut bytes = Vec::with_capacity(16 + 4 * v.len());
    bytes.extend_from_slice(b"foon-objects-1");
    bytes.extend_from_slice(&(v.len() as u64).to_le_bytes());
    for o in v {
        bytes.extend_from_slice(&o.to_le_bytes());
    }
    xxhash_rust::xxh3::xxh3_128(&bytes)
}

/// The bounds of a [`PreparedCache`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CacheLimits {
    /// Prepared kitchens kept at most.
    pub max_entries: usize,
    /// Bytes of prepared kitchens kept at most ([`Prepared::heap_bytes`]).
    pub max_bytes: usize,
    /// Bases kept at most.
    pub max_bases: usize,
}

impl Default for CacheLimits {
    /// 1,024 kitchens, 1 GiB, 4 bases.
    fn default() -> Self {
        Self {
            max_entries: 1024,
            max_bytes: 1 << 30,
            max_bases: 4,
        }
    }
}

/// Counters of a [`PreparedCache`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CacheStats {
    /// Prepared kitchens kept now.
    pub entries: usize,
    /// Their bytes, as last measured.
    pub bytes: usize,
    /// Bases kept now.
    pub bases: usize,
    /// Look-ups of a kitchen that found it.
    pub hits: u64,
    /// Look-ups of a kitchen that did not.
    pub misses: u64,
    /// Kitchens dropped to stay within the bounds.
    pub evictions: u64,
}

/// A least-recently-used table: values with their size, and the use order.
struct Lru<K, V> {
    map: FxHashMap<K, (V, u64, usize)>,
    order: BTreeMap<u64, K>,
    tick: u64,
    bytes: usize,
}

impl<K: Copy + Eq + std::hash::Hash, V: Clone> Lru<K, V> {
    fn new() -> Self {
        Self {
            map: FxHashMap::default(),
            order: BTreeMap::new(),
            tick: 0,
            bytes: 0,
        }
    }

    /// The value of `key`, now the most recently used, its size updated by `size`.
    fn get(&mut self, key: &K, size: impl FnOnce(&V) -> usize) -> Option<V> {
        let (v, stamp, bytes) = self.map.get_mut(key)?;
        self.order.remove(stamp);
        self.tick += 1;
        *stamp = self.tick;
        self.order.insert(self.tick, *key);
        let now = size(v);
        self.bytes = self.bytes - *bytes + now;
        *bytes = now;
        Some(v.clone())
    }

    /// Stores `value` unless `key` is there; the value kept.
    fn insert(&mut self, key: K, value: V, bytes: usize) -> V {
        if let Some(v) = self.get(&key, |_| bytes) {
            return v;
        }
        self.tick += 1;
        self.order.insert(self.tick, key);
        self.bytes += bytes;
        self.map.insert(key, (value.clone(), self.tick, bytes));
        value
    }

    /// Drops the least recently used values until at most `entries` and `bytes` are kept;
    /// how many were dropped.
    fn trim(&mut self, entries: usize, bytes: usize) -> u64 {
        let mut dropped = 0;
        while self.map.len() > entries || self.bytes > bytes {
            let Some((_, key)) = self.order.pop_first() else {
                break;
            };
            if let Some((_, _, b)) = self.map.remove(&key) {
                self.bytes -= b;
                dropped += 1;
            }
        }
        dropped
    }
}

struct State {
    kitchens: Lru<CacheKey, Arc<Prepared>>,
    bases: Lru<([u8; 16], u128), Arc<PreparedBase>>,
    hits: u64,
    misses: u64,
    evictions: u64,
}

/// A bounded, thread-safe cache of prepared kitchens and their bases (see the module
/// documentation).
pub struct PreparedCache {
    limits: CacheLimits,
    state: Mutex<State>,
}

impl Default for PreparedCache {
    fn default() -> Self {
        Self::new(CacheLimits::default())
    }
}

impl PreparedCache {
    /// An empty cache with these bounds.
    pub fn new(limits: CacheLimits) -> Self {
        Self {
            limits,
            state: Mutex::new(State {
                kitchens: Lru::new(),
                bases: Lru::new(),
                hits: 0,
                misses: 0,
                evictions: 0,
            }),
        }
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        // Every update leaves the tables consistent before anything that can panic.
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The bounds.
    pub fn limits(&self) -> CacheLimits {
        self.limits
    }

    /// The counters.
    pub fn stats(&self) -> CacheStats {
        let s = self.lock();
        CacheStats {
            entries: s.kitchens.map.len(),
            bytes: s.kitchens.bytes,
            bases: s.bases.map.len(),
            hits: s.hits,
            misses: s.misses,
            evictions: s.evictions,
        }
    }

    /// Drops every kitchen and base (the counters stay).
    pub fn clear(&self) {
        let mut s = self.lock();
        s.kitchens = Lru::new();
        s.bases = Lru::new();
    }

    /// The base of `foon` with these utensils and rates (see [`PreparedBase::new`]), built
    /// on the first request and kept.
    pub fn base(
        &self,
        foon: &Foon,
        utensils: &[String],
        rates: Option<&MotionRates>,
        default_rate: Option<f64>,
    ) -> Result<Arc<PreparedBase>> {
        let key = (
            foon.fingerprint(),
            PreparedBase::key_of(utensils, rates, default_rate),
        );
        if let Some(b) = self.lock().bases.get(&key, |_| 0) {
            return Ok(b);
        }
        let built = Arc::new(PreparedBase::new(foon, utensils, rates, default_rate)?);
        let mut s = self.lock();
        let kept = s.bases.insert(key, built, 0);
        s.bases.trim(self.limits.max_bases, usize::MAX);
        Ok(kept)
    }

    /// The prepared kitchen of `key`, if it is kept (it becomes the most recently used).
    pub fn get(&self, key: &CacheKey) -> Option<Arc<Prepared>> {
        let mut s = self.lock();
        let got = s.kitchens.get(key, |p| p.heap_bytes());
        if got.is_some() {
            s.hits += 1;
            let dropped = s
                .kitchens
                .trim(self.limits.max_entries, self.limits.max_bytes);
            s.evictions += dropped;
        } else {
            s.misses += 1;
        }
        got
    }

    /// The prepared kitchen of `key`, prepared by `prepare` when it is not kept, then kept
    /// (within the bounds). An error of `prepare` is returned and nothing is kept.
    pub fn get_or_prepare(
        &self,
        key: CacheKey,
        prepare: impl FnOnce() -> Result<Prepared>,
    ) -> Result<Arc<Prepared>> {
        if let Some(p) = self.get(&key) {
            return Ok(p);
        }
        Ok(self.insert(key, prepare()?))
    }

    /// Keeps `p` under `key` (after a [`PreparedCache::get`] of `key` missed: the miss is
    /// counted there) and returns what is kept: `p`, or the kitchen another thread kept under
    /// `key` meanwhile.
    pub fn insert(&self, key: CacheKey, p: Prepared) -> Arc<Prepared> {
        let p = Arc::new(p);
        let bytes = p.heap_bytes();
        let mut s = self.lock();
        let kept = s.kitchens.insert(key, p, bytes);
        let dropped = s
            .kitchens
            .trim(self.limits.max_entries, self.limits.max_bytes);
        s.evictions += dropped;
        kept
    }

    /// `kitchen` matched in `foon` at identity `level` (see
    /// [`Kitchen::match_at_level`]) and prepared on `base` (built for `foon`), from the cache
    /// when it is there.
    pub fn kitchen(
        &self,
        foon: &Foon,
        base: &Arc<PreparedBase>,
        kitchen: &Kitchen,
        level: u8,
    ) -> Result<Arc<Prepared>> {
        let key = CacheKey {
            foon: foon.fingerprint(),
            base: base.key(),
            kitchen: kitchen.fingerprint(),
            level,
        };
        self.get_or_prepare(key, || {
            let ids = kitchen.match_at_level(foon, level)?;
            Ok(Prepared::with_base(foon, Arc::clone(base), &ids)?.at_level(level))
        })
    }

    /// The kitchen of object ids `ids` of `foon` prepared on `base`, from the cache when it is
    /// there.
    pub fn objects(
        &self,
        foon: &Foon,
        base: &Arc<PreparedBase>,
        ids: &[u32],
    ) -> Result<Arc<Prepared>> {
        let key = CacheKey {
            foon: foon.fingerprint(),
            base: base.key(),
            kitchen: objects_fingerprint(ids),
            level: 0,
        };
        self.get_or_prepare(key, || Prepared::with_base(foon, Arc::clone(base), ids))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse::{ParseOptions, parse_foon};

    fn foon() -> Foon {
        parse_foon(
            b"O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n",
            None,
            ParseOptions::default(),
        )
        .unwrap()
    }

    #[test]
    fn kitchens_are_kept_by_key_and_dropped_least_recent_first() {
        let f = foon();
        let cache = PreparedCache::new(CacheLimits {
            max_entries: 2,
            max_bytes: usize::MAX,
            max_bases: 1,
        });
        let base = cache.base(&f, &[], None, None).unwrap();
        assert!(Arc::ptr_eq(
            &base,
            &cache.base(&f, &[], None, None).unwrap()
        ));
        let a = cache.objects(&f, &base, &[0]).unwrap();
        // The same set in another order, with a repeat: the same entry.
        assert!(Arc::ptr_eq(&a, &cache.objects(&f, &base, &[0, 0]).unwrap()));
        let b = cache.objects(&f, &base, &[1]).unwrap();
        let _ = cache.objects(&f, &base, &[0]).unwrap(); // `a` is now the most recent
        let _c = cache.objects(&f, &base, &[]).unwrap(); // drops `b`
        let st = cache.stats();
        assert_eq!((st.entries, st.hits, st.misses, st.evictions), (2, 2, 3, 1));
        assert!(Arc::ptr_eq(&a, &cache.objects(&f, &base, &[0]).unwrap()));
        assert!(!Arc::ptr_eq(&b, &cache.objects(&f, &base, &[1]).unwrap()));
        // Another base (rates given) is another key; one base is kept.
        let rated = cache.base(&f, &[], None, Some(0.5)).unwrap();
        assert_ne!(rated.key(), base.key());
        assert_eq!(cache.stats().bases, 1);
        let r = cache.objects(&f, &rated, &[0]).unwrap();
        assert!(!Arc::ptr_eq(&r, &a));
        assert!(r.rates_given() && !a.rates_given());
    }

    #[test]
    fn bytes_are_bounded_and_remeasured() {
        let f = foon();
        let one = Prepared::with_objects(&f, &[0], &[], None, None).unwrap();
        let small = one.heap_bytes();
        let cache = PreparedCache::new(CacheLimits {
            max_entries: 100,
            max_bytes: 2 * small + 4,
            max_bases: 1,
        });
        let base = cache.base(&f, &[], None, None).unwrap();
        let a = cache.objects(&f, &base, &[0]).unwrap();
        let _ = cache.objects(&f, &base, &[1]).unwrap();
        assert_eq!(cache.stats().entries, 2);
        // Computing the ranks makes `a` larger; the next look-up measures it again and
        // drops the least recent entry to stay within the budget.
        let _ = a.ranks(&f);
        let got = cache.objects(&f, &base, &[0]).unwrap();
        assert!(Arc::ptr_eq(&a, &got));
        let st = cache.stats();
        assert_eq!(st.entries, 1);
        assert_eq!(st.bytes, a.heap_bytes());
        assert!(st.bytes > small);
    }

    #[test]
    fn a_failed_preparation_keeps_nothing() {
        let f = foon();
        let cache = PreparedCache::default();
        let base = cache.base(&f, &[], None, None).unwrap();
        assert!(cache.objects(&f, &base, &[7]).is_err());
        assert_eq!(cache.stats().entries, 0);
        assert!(cache.base(&f, &[], None, Some(2.0)).is_err());
    }

    #[test]
    fn fingerprints_are_fixed() {
        // Keys are compared across machines: a change here is a format change.
        assert_eq!(
            objects_fingerprint(&[3, 1, 3]),
            objects_fingerprint(&[1, 3])
        );
        assert_ne!(objects_fingerprint(&[1]), objects_fingerprint(&[]));
        assert_eq!(
            format!("{:032x}", objects_fingerprint(&[1, 3])),
            "b4f377c0e4b71b1bd91a73c42bb1941f"
        );
        assert_eq!(
            format!(
                "{:032x}",
                PreparedBase::key_of(&["bowl".into()], None, Some(0.5))
            ),
            "9ce33a4986aaba886e82a8e42351e391"
        );
        let a = PreparedBase::key_of(&["pan".into(), "bowl".into()], None, None);
        let b = PreparedBase::key_of(&["bowl".into(), "pan".into(), "bowl".into()], None, None);
        assert_eq!(a, b);
        assert_ne!(a, PreparedBase::key_of(&[], None, None));
        assert_ne!(
            PreparedBase::key_of(&[], None, Some(1.0)),
            PreparedBase::key_of(&[], None, None)
        );
    }
}
