//! Index columns: a flat run of little-endian integers, either owned (a `Vec`, while building
//! or after a parse) or borrowed from a shared read-only buffer (a memory-mapped `.foonidx`
//! file, or its bytes copied into aligned memory). Both dereference to `&[T]`, so the search
//! code is the same on either.

use std::ops::{Deref, DerefMut};
use std::sync::Arc;

use bytemuck::Pod;

/// The bytes a mapped column borrows from: a read-only memory map of an index file, or index
/// bytes copied into 8-byte aligned memory.
#[derive(Debug)]
pub(crate) enum Backing {
    Map(memmap2::Mmap),
    /// `len` bytes held in 64-bit words (so that every column offset that is a multiple of 8
    /// is aligned for every element type).
    Words(Vec<u64>, usize),
}

impl Backing {
    pub(crate) fn bytes(&self) -> &[u8] {
        match self {
            Self::Map(m) => m,
            Self::Words(w, len) => {
                let all: &[u8] = bytemuck::cast_slice(w);
                &all[..(*len).min(all.len())]
            }
        }
    }

    /// A copy of `data` in aligned memory.
    pub(crate) fn copy_of(data: &[u8]) -> Self {
        let mut w = vec![0u64; data.len().div_ceil(8)];
        bytemuck::cast_slice_mut::<u64, u8>(&mut w)[..data.len()].copy_from_slice(data);
        Self::Words(w, data.len())
    }
}

#[derive(Debug, Clone)]
enum Store<T> {
    Owned(Vec<T>),
    /// `len` elements at byte `off` of the backing (checked when the file was opened).
    Mapped {
        map: Arc<Backing>,
        off: usize,
        len: usize,
    },
}

/// One column of the index (see the module documentation).
#[derive(Debug, Clone)]
pub struct Col<T> {
    store: Store<T>,
}

impl<T> Default for Col<T> {
    fn default() -> Self {
        Self {
            store: Store::Owned(Vec::new()),
        }
    }
}

impl<T> From<Vec<T>> for Col<T> {
    fn from(v: Vec<T>) -> Self {
        Self {
            store: Store::Owned(v),
        }
    }
}

impl<T: Pod> Col<T> {
    /// A column of `len` elements at byte `off` of `map`. The caller has checked that the range
    /// lies inside the backing and that `off` is a multiple of 8; a range that does not reads
    /// as an empty column rather than panicking.
    pub(crate) fn mapped(map: &Arc<Backing>, off: usize, len: usize) -> Self {
        Self {
            store: Store::Mapped {
                map: Arc::clone(map),
                off,
                len,
            },
        }
    }

    /// The elements, as a slice.
    #[inline]
    pub fn as_slice(&self) -> &[T] {
        match &self.store {
            Store::Owned(v) => v,
            Store::Mapped { map, off, len } => {
                let bytes = map.bytes();
                let end = off.saturating_add(len.saturating_mul(size_of::<T>()));
                bytes
                    .get(*off..end)
                    .and_then(|b| bytemuck::try_cast_slice(b).ok())
                    .unwrap_or(&[])
            }
        }
    }

    /// The owned vector, copying a mapped column first (used only while building).
    pub fn make_mut(&mut self) -> &mut Vec<T> {
        if let Store::Mapped { .. } = self.store {
            self.store = Store::Owned(self.as_slice().to_vec());
        }
        match &mut self.store {
            Store::Owned(v) => v,
            Store::Mapped { .. } => unreachable!("made owned above"),
        }
    }

    /// True when the column borrows from a file or buffer rather than owning its elements.
    pub fn is_mapped(&self) -> bool {
        matches!(self.store, Store::Mapped { .. })
    }

    pub fn push(&mut self, x: T) {
        self.make_mut().push(x);
    }

    pub fn extend_from_slice(&mut self, xs: &[T]) {
        self.make_mut().extend_from_slice(xs);
    }

    /// Heap bytes owned by the column (its capacity), or the bytes it borrows when mapped.
    pub fn heap_bytes(&self) -> usize {
        match &self.store {
            Store::Owned(v) => v.capacity() * size_of::<T>(),
            Store::Mapped { len, .. } => len * size_of::<T>(),
        }
    }

    /// Frees unused capacity of an owned column.
    pub fn shrink_to_fit(&mut self) {
        if let Store::Owned(v) = &mut self.store {
            v.shrink_to_fit();
        }
    }
}

impl<T: Pod> Extend<T> for Col<T> {
    fn extend<I: IntoIterator<Item = T>>(&mut self, iter: I) {
        self.make_mut().extend(iter);
    }
}

impl<T: Pod> Deref for Col<T> {
    type Target = [T];
    #[inline]
    fn deref(&self) -> &[T] {
        self.as_slice()
    }
}

impl<T: Pod> DerefMut for Col<T> {
    fn deref_mut(&mut self) -> &mut [T] {
        self.make_mut()
    }
}

impl<T: Pod + PartialEq> PartialEq for Col<T> {
    fn eq(&self, other: &Self) -> bool {
        self.as_slice() == other.as_slice()
    }
}

impl<T: Pod + Eq> Eq for Col<T> {}
