//! Per-object columns that a kitchen prepared from another by a delta shares with it
//! (`incremental.rs`): the values of the kitchen it was derived from, shared (an [`Arc`]),
//! and the few values the delta changed, kept apart with one bit per object saying which.
//!
//! A delta of a few items reaches a few hundred objects of a FOON of a million, so a kitchen
//! derived from another costs what the delta reaches, in time and in memory, and thousands of
//! such kitchens fit where a few copies of the base would not. A read is one test of a bit
//! (always false for a column with no changes) and, for a changed object, a hash look-up.
//! When the changes grow past a fraction of the column ([`DENSE_SHARE`]) the column is
//! written out whole instead, so a chain of deltas never reads slower than a copy.

use std::sync::Arc;

use rustc_hash::FxHashMap;

/// A column with more than one changed value in `DENSE_SHARE`, and more than `SPARSE_MIN`,
/// is written out whole.
const DENSE_SHARE: usize = 16;
const SPARSE_MIN: usize = 64;

/// A value of a column, compared bit for bit (a change back to the shared value is no
/// change; costs are compared by their bits, as every result of the core is).
pub(crate) trait Value: Copy + Send + Sync + 'static {
    fn same(self, other: Self) -> bool;
}

impl Value for u32 {
    #[inline]
    fn same(self, other: Self) -> bool {
        self == other
    }
}

impl Value for bool {
    #[inline]
    fn same(self, other: Self) -> bool {
        self == other
    }
}

impl Value for f64 {
    #[inline]
    fn same(self, other: Self) -> bool {
        self.to_bits() == other.to_bits()
    }
}

/// The values that differ from the shared column, and a bit per object marking them.
#[derive(Debug)]
struct Changes<T> {
    bits: Vec<u64>,
    values: FxHashMap<u32, T>,
}

impl<T: Copy> Changes<T> {
    /// The changed value of `i` (marked in `bits`): out of the readers' inner loops.
    #[inline(never)]
    fn changed(&self, i: u32) -> T {
        self.values[&i]
    }
}

/// One value per object: a shared column and the changes of this kitchen (see the module
/// documentation). Cloning it shares both.
#[derive(Debug, Clone)]
pub(crate) struct Layered<T> {
    shared: Arc<Vec<T>>,
    changes: Option<Arc<Changes<T>>>,
}

impl<T: Value> Layered<T> {
    /// A column of these values, none changed.
    pub(crate) fn from_vec(v: Vec<T>) -> Self {
        Self {
            shared: Arc::new(v),
            changes: None,
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.shared.len()
    }

    /// The value of object `i` (`i < len`).
    #[inline]
    pub(crate) fn get(&self, i: u32) -> T {
        let u = i as usize;
        if let Some(c) = &self.changes
            && (c.bits[u >> 6] >> (u & 63)) & 1 != 0
        {
            return c.changed(i);
        }
        self.shared[u]
    }

    /// Brings in the shared value of object `i` (a hint: the value most reads take).
    #[inline]
    pub(crate) fn prefetch(&self, i: u32) {
        if let Some(v) = self.shared.get(i as usize) {
            crate::hint::prefetch(v);
        }
    }

    /// The values in object order.
    pub(crate) fn iter(&self) -> impl Iterator<Item = T> + '_ {
        (0..self.len() as u32).map(|i| self.get(i))
    }

    pub(crate) fn to_vec(&self) -> Vec<T> {
        match &self.changes {
            None => self.shared.to_vec(),
            Some(_) => self.iter().collect(),
        }
    }

    /// Heap bytes of this kitchen's own part: the changes, or the whole column when it is
    /// not shared with the kitchen it was derived from (`own`).
    pub(crate) fn heap_bytes(&self, own: bool) -> usize {
        let mut b = 0;
        if own {
            b += std::mem::size_of::<T>() * self.shared.capacity();
        }
        if let Some(c) = &self.changes {
            b += 8 * c.bits.capacity() + (4 + std::mem::size_of::<T>() + 1) * c.values.capacity();
        }
        b
    }

    /// Whether the shared column is this kitchen's own (no change kept apart).
    #[cfg(test)]
    pub(crate) fn is_flat(&self) -> bool {
        self.changes.is_none()
    }

    /// An editor of a copy of this column: the copy shares the column and these changes
    /// until [`Editor::finish`].
    pub(crate) fn edit(&self) -> Editor<T> {
        let n = self.len();
        let mut bits = vec![0u64; n.div_ceil(64)];
        let values = match &self.changes {
            None => FxHashMap::default(),
            Some(c) => {
                for &i in c.values.keys() {
                    bits[i as usize >> 6] |= 1 << (i & 63);
                }
                c.values.clone()
            }
        };
        let mut e = Editor {
            shared: Arc::clone(&self.shared),
            bits,
            values,
            dense: None,
        };
        if e.values.len() > e.sparse_limit() {
            e.write_out();
        }
        e
    }
}

impl<T: Value> Layered<T> {
    /// This column with the values of `changes` (`count` of them at most) set: kept apart,
    /// or written out whole at once when they are more than [`Editor::finish`] would keep
    /// apart.
    pub(crate) fn changed(
        &self,
        changes: impl IntoIterator<Item = (u32, T)>,
        count: usize,
    ) -> Self {
        let mut e = self.edit();
        if e.dense.is_none() && e.values.len() + count > e.sparse_limit() {
            e.write_out();
        }
        for (i, v) in changes {
            e.set(i, v);
        }
        e.finish()
    }
}

impl<T: Value> PartialEq for Layered<T> {
    /// The same values, however they are kept.
    fn eq(&self, other: &Self) -> bool {
        self.len() == other.len() && self.iter().zip(other.iter()).all(|(a, b)| a.same(b))
    }
}

/// A column being changed (from [`Layered::edit`]): the changes kept apart while they are
/// few, the column written out whole (and changed in place) once they pass the share at
/// which [`Editor::finish`] would write it out, so a change that reaches much of the FOON
/// costs a copy of the column and no more.
pub(crate) struct Editor<T> {
    shared: Arc<Vec<T>>,
    bits: Vec<u64>,
    values: FxHashMap<u32, T>,
    /// The whole column, once written out.
    dense: Option<Vec<T>>,
}

impl<T: Value> Editor<T> {
    /// The most changes kept apart.
    fn sparse_limit(&self) -> usize {
        SPARSE_MIN.max(self.shared.len() / DENSE_SHARE)
    }

    #[inline]
    pub(crate) fn get(&self, i: u32) -> T {
        let u = i as usize;
        if let Some(d) = &self.dense {
            return d[u];
        }
        if (self.bits[u >> 6] >> (u & 63)) & 1 != 0 {
            return self.values[&i];
        }
        self.shared[u]
    }

    #[inline]
    pub(crate) fn set(&mut self, i: u32, v: T) {
        let u = i as usize;
        if let Some(d) = &mut self.dense {
            d[u] = v;
            return;
        }
        let bit = 1u64 << (u & 63);
        if v.same(self.shared[u]) {
            if self.bits[u >> 6] & bit != 0 {
                self.bits[u >> 6] &= !bit;
                self.values.remove(&i);
            }
        } else {
            self.bits[u >> 6] |= bit;
            self.values.insert(i, v);
            if self.values.len() > self.sparse_limit() {
                self.write_out();
            }
        }
    }

    /// Writes the column out whole, the changes applied.
    fn write_out(&mut self) {
        let mut v = self.shared.to_vec();
        for (&i, &x) in &self.values {
            v[i as usize] = x;
        }
        self.values = FxHashMap::default();
        self.bits = Vec::new();
        self.dense = Some(v);
    }

    /// The changed column: sharing the column it was made from, or written out whole when
    /// the changes pass a share of it.
    pub(crate) fn finish(mut self) -> Layered<T> {
        if let Some(v) = self.dense.take() {
            return Layered::from_vec(v);
        }
        if self.values.is_empty() {
            return Layered {
                shared: self.shared,
                changes: None,
            };
        }
        let mut values = self.values;
        values.shrink_to_fit();
        Layered {
            shared: self.shared,
            changes: Some(Arc::new(Changes {
                bits: self.bits,
                values,
            })),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Layered;

    /// Random edits, chained, against a plain vector.
    #[test]
    fn edits_read_as_a_vector() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = |n: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % n
        };
        for round in 0..200 {
            let n = 1 + next(3000) as usize;
            let mut want: Vec<f64> = (0..n).map(|i| i as f64).collect();
            let mut col = Layered::from_vec(want.clone());
            for _ in 0..=next(5) {
                let mut e = col.edit();
                let edits = if round % 7 == 0 { n } else { next(8) as usize };
                for _ in 0..edits {
                    let i = next(n as u64) as usize;
                    // Sometimes back to the value shared.
                    let v = if next(3) == 0 {
                        i as f64
                    } else {
                        next(50) as f64
                    };
                    e.set(i as u32, v);
                    want[i] = v;
                    assert_eq!(e.get(i as u32).to_bits(), v.to_bits());
                }
                col = e.finish();
                assert_eq!(col.to_vec(), want);
                assert!(col == Layered::from_vec(want.clone()));
                for (i, w) in want.iter().enumerate() {
                    assert_eq!(col.get(i as u32).to_bits(), w.to_bits());
                }
            }
        }
    }

    /// A change back to the shared value is no change; many changes write the column out.
    #[test]
    fn changes_are_kept_apart_only_while_few() {
        let col = Layered::from_vec(vec![0u32; 1000]);
        // 65 changes of 1,000: more than 64 and than one in 16.
        let mut e = col.edit();
        e.set(3, 7);
        e.set(3, 0);
        assert!(e.finish().is_flat());
        let mut e = col.edit();
        e.set(3, 7);
        let one = e.finish();
        assert!(!one.is_flat());
        assert_eq!(one.get(3), 7);
        let mut e = one.edit();
        for i in 0..65 {
            e.set(i, 1);
        }
        let many = e.finish();
        assert!(many.is_flat());
        assert_eq!(many.get(3), 1);
        assert_eq!(many.get(500), 0);
    }
}
