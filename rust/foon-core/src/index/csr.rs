//! Compressed sparse rows: the one adjacency layout of the index (a flat offset column and a
//! flat data column of `u32`, owned or mapped, see [`Col`]).

use super::col::Col;
use crate::error::{Error, Result};
use crate::hint::prefetch;

/// Compressed sparse rows: row `i` is `data[off[i]..off[i + 1]]`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Csr {
    pub(crate) off: Col<u32>,
    pub(crate) data: Col<u32>,
}

/// The rows of a [`Csr`] as plain slices ([`Csr::view`]): the same rows, read without
/// looking the columns up each time.
#[derive(Clone, Copy)]
pub(crate) struct Rows<'a> {
    off: &'a [u32],
    data: &'a [u32],
}

impl<'a> Rows<'a> {
    /// Row `i`; empty when out of range.
    #[inline]
    pub(crate) fn row(self, i: u32) -> &'a [u32] {
        let i = i as usize;
        match (self.off.get(i), self.off.get(i + 1)) {
            (Some(&a), Some(&b)) => self.data.get(a as usize..b as usize).unwrap_or(&[]),
            _ => &[],
        }
    }

    /// Brings in where row `i` starts, or with `row` its first entries (reading where it
    /// starts) ([`prefetch`]: a hint).
    #[inline]
    pub(crate) fn prefetch(self, i: u32, row: bool) {
        let Some(a) = self.off.get(i as usize) else {
            return;
        };
        if !row {
            prefetch(a);
        } else if let Some(x) = self.data.get(*a as usize) {
            prefetch(x);
        }
    }
}

impl Csr {
    pub fn new() -> Self {
        Self {
            off: vec![0].into(),
            data: Col::default(),
        }
    }

    /// An empty CSR with room for `rows` rows of `data` entries in all.
    pub fn with_capacity(rows: usize, data: usize) -> Self {
        let mut off = Vec::with_capacity(rows + 1);
        off.push(0);
        Self {
            off: off.into(),
            data: Vec::with_capacity(data).into(),
        }
    }

    /// Appends a row.
    ///
    /// # Panics
    /// When the data would pass `u32::MAX` entries (use [`Csr::try_push_row`] to get an
    /// error instead).
    pub fn push_row(&mut self, row: &[u32]) {
        if let Err(e) = self.try_push_row(row, "row entries") {
            panic!("{e}");
        }
    }

    /// Appends a row, or [`Error::TooLarge`] naming `what` when the data would pass
    /// `u32::MAX` entries (nothing is appended then).
    pub fn try_push_row(&mut self, row: &[u32], what: &'static str) -> Result<()> {
        let end = Error::check_offset(self.data.len() + row.len(), what)?;
        if self.off.is_empty() {
            self.off.push(0);
        }
        self.data.extend_from_slice(row);
        self.off.push(end);
        Ok(())
    }

    /// Row `i`; empty when out of range.
    #[inline]
    pub fn row(&self, i: u32) -> &[u32] {
        self.view().row(i)
    }

    /// The rows as plain slices, for loops that read many of them: a column of a mapped
    /// index is found in its backing on each read of [`Csr::row`], once here.
    #[inline]
    pub(crate) fn view(&self) -> Rows<'_> {
        Rows {
            off: &self.off,
            data: &self.data,
        }
    }

    /// First position of row `i` in [`Csr::data`].
    #[inline]
    pub fn row_start(&self, i: u32) -> usize {
        self.off.get(i as usize).map_or(0, |&a| a as usize)
    }

    pub fn rows(&self) -> usize {
        self.off.len().saturating_sub(1)
    }

    pub fn data(&self) -> &[u32] {
        &self.data
    }

    /// The offsets: `rows() + 1` entries from 0 to `data().len()`.
    pub fn offsets(&self) -> &[u32] {
        &self.off
    }

    /// Builds the transposed relation: for `rows` rows, the list of `(row, value)` pairs given
    /// by `pairs`, each row keeping the order in which its pairs come.
    ///
    /// # Panics
    /// When there are more than `u32::MAX` pairs (see [`Csr::try_from_pairs`]).
    pub fn from_pairs(rows: usize, pairs: impl Iterator<Item = (u32, u32)> + Clone) -> Self {
        match Self::try_from_pairs(rows, pairs, "row entries") {
            Ok(c) => c,
            Err(e) => panic!("{e}"),
        }
    }

    /// As [`Csr::from_pairs`], or [`Error::TooLarge`] naming `what` when there are more than
    /// `u32::MAX` pairs.
    pub fn try_from_pairs(
        rows: usize,
        pairs: impl Iterator<Item = (u32, u32)> + Clone,
        what: &'static str,
    ) -> Result<Self> {
        let mut count = vec![0usize; rows + 1];
        for (r, _) in pairs.clone() {
            count[r as usize + 1] += 1;
        }
        for i in 0..rows {
            count[i + 1] += count[i];
        }
        Error::check_offset(count[rows], what)?;
        let off: Vec<u32> = count.iter().map(|&c| c as u32).collect();
        drop(count);
        let mut fill: Vec<u32> = off[..rows].to_vec();
        let mut data = vec![0u32; off[rows] as usize];
        for (r, v) in pairs {
            let slot = &mut fill[r as usize];
            data[*slot as usize] = v;
            *slot += 1;
        }
        Ok(Self {
            off: off.into(),
            data: data.into(),
        })
    }

    /// Heap bytes used (or mapped).
    pub fn heap_bytes(&self) -> usize {
        self.off.heap_bytes() + self.data.heap_bytes()
    }

    pub(crate) fn shrink_to_fit(&mut self) {
        self.off.shrink_to_fit();
        self.data.shrink_to_fit();
    }
}

#[cfg(test)]
mod tests {
    use super::Csr;
    use crate::error::Error;

    /// The offsets are checked where they would pass `u32::MAX`, without building 4 GB.
    #[test]
    fn offsets_past_u32_are_too_large() {
        assert_eq!(
            Error::check_offset(u32::MAX as usize, "x").unwrap(),
            u32::MAX
        );
        let e = Error::check_offset(u32::MAX as usize + 1, "input edges").unwrap_err();
        assert_eq!(e.to_string(), "too large: more than 4294967295 input edges");
        assert_eq!(
            Error::check_id(u32::MAX as usize - 1, "x").unwrap(),
            u32::MAX - 1
        );
        let e = Error::check_id(u32::MAX as usize, "objects").unwrap_err();
        assert_eq!(e.to_string(), "too large: more than 4294967295 objects");
        let mut c = Csr::new();
        c.try_push_row(&[1, 2], "x").unwrap();
        assert_eq!((c.rows(), c.row(0), c.row(1)), (1, &[1, 2][..], &[][..]));
    }
}
