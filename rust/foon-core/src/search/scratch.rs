//! Per-search state indexed by object or FU id, sized to the work rather than to the FOON.
//!
//! A search from one goal usually touches a few dozen objects, however large the FOON. An
//! array with a slot per object costs its whole length to create, on every plan; on a merged
//! FOON of millions of objects that dwarfs the search. [`IdMap`] is an array for FOONs small
//! enough that creating one is cheaper than hashing, and otherwise a hash map of the entries
//! actually set, which becomes an array once it holds a sixteenth of the ids (a search that
//! covers much of the FOON, such as a plan to the end of a long chain, then runs at array
//! speed; the switch costs at most sixteen times the work already done). A plan's cost thus
//! follows the tree it explores.

use rustc_hash::{FxBuildHasher, FxHashMap};

/// Id spaces up to this many entries use an array (creating it is a short `memset`); larger
/// ones a hash map.
pub(crate) const DENSE_MAX: usize = 1 << 15;

/// A map from ids in `0..len` to `T`, every id starting at `default`.
pub(crate) enum IdMap<T: Copy + PartialEq> {
    Dense(Vec<T>),
    Sparse {
        map: FxHashMap<u32, T>,
        default: T,
        len: usize,
    },
}

/// A hash map holding more than `len / SPARSE_SHARE` entries becomes an array.
const SPARSE_SHARE: usize = 16;

/// Entries a hash map has room for from the start: a plan's tree usually holds a few dozen
/// to a few hundred objects, and a map grown from nothing to that size is rehashed at every
/// doubling (a tenth of a batch's time before it had this room).
const SPARSE_START: usize = 256;

impl<T: Copy + PartialEq> IdMap<T> {
    /// A map over `len` ids, all at `default`: an array when `len <= dense_max`, else a hash
    /// map.
    pub(crate) fn new(len: usize, default: T, dense_max: usize) -> Self {
        if len <= dense_max {
            Self::Dense(vec![default; len])
        } else {
            Self::Sparse {
                map: FxHashMap::with_capacity_and_hasher(
                    SPARSE_START.min(len / SPARSE_SHARE),
                    FxBuildHasher,
                ),
                default,
                len,
            }
        }
    }

    #[inline]
    pub(crate) fn get(&self, id: u32) -> T {
        match self {
            Self::Dense(v) => v[id as usize],
            Self::Sparse { map, default, .. } => map.get(&id).copied().unwrap_or(*default),
        }
    }

    #[inline]
    pub(crate) fn set(&mut self, id: u32, value: T) {
        match self {
            Self::Dense(v) => v[id as usize] = value,
            Self::Sparse { map, default, len } => {
                if value == *default {
                    map.remove(&id);
                } else if map.insert(id, value).is_none() && map.len() * SPARSE_SHARE > *len {
                    let mut dense = vec![*default; *len];
                    for (&i, &v) in map.iter() {
                        dense[i as usize] = v;
                    }
                    *self = Self::Dense(dense);
                }
            }
        }
    }

    /// Sets `id` to `value` and returns what it was.
    #[inline]
    pub(crate) fn replace(&mut self, id: u32, value: T) -> T {
        let old = self.get(id);
        if old != value {
            self.set(id, value);
        }
        old
    }
}

#[cfg(test)]
mod tests {
    use super::IdMap;

    #[test]
    fn dense_and_sparse_agree() {
        let mut dense = IdMap::new(100, 7u32, 100);
        let mut sparse = IdMap::new(100, 7u32, 10);
        assert!(matches!(dense, IdMap::Dense(_)));
        assert!(matches!(sparse, IdMap::Sparse { .. }));
        for (i, v) in [(3, 1), (99, 7), (3, 7), (50, 2), (0, 0)] {
            assert_eq!(dense.replace(i, v), sparse.replace(i, v));
        }
        for i in 0..100 {
            assert_eq!(dense.get(i), sparse.get(i), "{i}");
        }
        assert_eq!(sparse.get(3), 7);
        assert_eq!(sparse.get(50), 2);
        if let IdMap::Sparse { map, .. } = &sparse {
            // Entries set back to the default are not kept.
            assert_eq!(map.len(), 2);
        }
    }

    #[test]
    fn a_full_hash_map_becomes_an_array_with_its_entries() {
        let mut m = IdMap::new(160, 0u32, 10);
        for i in 0..10 {
            m.set(i * 3, i + 1);
        }
        assert!(matches!(m, IdMap::Sparse { .. }));
        m.set(100, 42); // the 11th entry: more than 160 / 16
        assert!(matches!(m, IdMap::Dense(_)));
        for i in 0..10 {
            assert_eq!(m.get(i * 3), i + 1);
            assert_eq!(m.get(i * 3 + 1), 0);
        }
        assert_eq!(m.get(100), 42);
    }
}
