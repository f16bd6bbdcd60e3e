//! The string interner of the index: every label, state, ingredient, container and motion
//! stored once.

use std::hash::Hasher;

use hashbrown::HashTable;
use rustc_hash::FxHasher;

/// String interner: every label, state, ingredient, container and motion is stored once, in
/// one text buffer with end offsets; the hash table holds only ids.
#[derive(Debug, Clone, Default)]
pub struct Interner {
    text: String,
    ends: Vec<u64>,
    table: HashTable<u32>,
}

fn hash_str(s: &str) -> u64 {
    let mut h = FxHasher::default();
    h.write(s.as_bytes());
    h.finish()
}

fn slice<'a>(text: &'a str, ends: &[u64], id: u32) -> &'a str {
    let i = id as usize;
    let Some(&end) = ends.get(i) else { return "" };
    let start = if i == 0 { 0 } else { ends[i - 1] };
    text.get(start as usize..end as usize).unwrap_or("")
}

impl Interner {
    pub fn intern(&mut self, s: &str) -> u32 {
        let h = hash_str(s);
        let (text, ends) = (&self.text, &self.ends);
        if let Some(&id) = self.table.find(h, |&id| slice(text, ends, id) == s) {
            return id;
        }
        let id = self.ends.len() as u32;
        self.text.push_str(s);
        self.ends.push(self.text.len() as u64);
        let (text, ends) = (&self.text, &self.ends);
        self.table
            .insert_unique(h, id, |&id| hash_str(slice(text, ends, id)));
        id
    }

    pub fn get(&self, s: &str) -> Option<u32> {
        let (text, ends) = (&self.text, &self.ends);
        self.table
            .find(hash_str(s), |&id| slice(text, ends, id) == s)
            .copied()
    }

    /// The text of id `id` (empty for [`NONE`](super::NONE) or an unknown id).
    #[inline]
    pub fn text(&self, id: u32) -> &str {
        slice(&self.text, &self.ends, id)
    }

    pub fn len(&self) -> usize {
        self.ends.len()
    }

    pub fn is_empty(&self) -> bool {
        self.ends.is_empty()
    }

    /// Heap bytes used.
    pub fn heap_bytes(&self) -> usize {
        self.text.capacity() + self.ends.capacity() * 8 + self.table.capacity() * 5
    }
}
