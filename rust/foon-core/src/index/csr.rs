//! Compressed sparse rows: the one adjacency layout of the index (a flat offset vector and a
//! flat data vector of `u32`).

/// Compressed sparse rows: row `i` is `data[off[i]..off[i + 1]]`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Csr {
    off: Vec<u32>,
    data: Vec<u32>,
}

impl Csr {
    pub fn new() -> Self {
        Self {
            off: vec![0],
            data: Vec::new(),
        }
    }

    /// Appends a row.
    pub fn push_row(&mut self, row: &[u32]) {
        self.data.extend_from_slice(row);
        self.off.push(self.data.len() as u32);
    }

    /// Row `i`; empty when out of range.
    #[inline]
    pub fn row(&self, i: u32) -> &[u32] {
        let i = i as usize;
        match (self.off.get(i), self.off.get(i + 1)) {
            (Some(&a), Some(&b)) => &self.data[a as usize..b as usize],
            _ => &[],
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

    /// Builds the transposed relation: for `rows` rows, the list of `(row, value)` pairs given
    /// by `pairs`, each row keeping the order in which its pairs come.
    pub fn from_pairs(rows: usize, pairs: impl Iterator<Item = (u32, u32)> + Clone) -> Self {
        let mut off = vec![0u32; rows + 1];
        for (r, _) in pairs.clone() {
            off[r as usize + 1] += 1;
        }
        for i in 0..rows {
            off[i + 1] += off[i];
        }
        let mut fill: Vec<u32> = off[..rows].to_vec();
        let mut data = vec![0u32; off[rows] as usize];
        for (r, v) in pairs {
            let slot = &mut fill[r as usize];
            data[*slot as usize] = v;
            *slot += 1;
        }
        Self { off, data }
    }

    /// Heap bytes used.
    pub fn heap_bytes(&self) -> usize {
        (self.off.capacity() + self.data.capacity()) * 4
    }
}
