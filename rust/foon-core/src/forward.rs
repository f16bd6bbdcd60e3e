//! Forward chaining from the kitchen: derivable objects and their ranks (the fewest parallel
//! steps that make them), in one pass over the index (breadth-first by rank), over the whole
//! FOON ([`ranks`], for [`Prepared::ranks`]; the same rule over the units of one tree is
//! `evaluate::shape`).

use std::collections::VecDeque;

use crate::index::{Foon, NONE};
use crate::layered::Layered;
use crate::prepare::Prepared;

/// Rank of every object (`NONE` when not derivable); equal when the ranks are.
#[derive(Debug, Clone, PartialEq)]
pub struct Ranks {
    rank: Layered<u32>,
}

impl Eq for Ranks {}

impl Ranks {
    /// Ranks given per object (`NONE` when not derivable), computed elsewhere
    /// ([`crate::multi`]).
    pub(crate) fn from_vec(rank: Vec<u32>) -> Self {
        Self {
            rank: Layered::from_vec(rank),
        }
    }

    /// Ranks kept as a [`Layered`] column (`incremental.rs`).
    pub(crate) fn from_layered(rank: Layered<u32>) -> Self {
        Self { rank }
    }

    pub(crate) fn layered(&self) -> &Layered<u32> {
        &self.rank
    }

    /// The rank of `o` (`None` when it is not derivable or not an object).
    #[inline]
    pub fn rank(&self, o: u32) -> Option<u32> {
        if o as usize >= self.rank.len() {
            return None;
        }
        Some(self.rank.get(o)).filter(|&r| r != NONE)
    }

    /// The rank of object `o` of the FOON, `NONE` when it is not derivable.
    #[inline]
    pub fn raw(&self, o: u32) -> u32 {
        self.rank.get(o)
    }

    pub fn is_derivable(&self, o: u32) -> bool {
        self.rank(o).is_some()
    }

    /// The number of objects.
    pub fn len(&self) -> usize {
        self.rank.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rank.len() == 0
    }

    /// Every object's rank in object order, `NONE` when not derivable.
    pub fn to_vec(&self) -> Vec<u32> {
        self.rank.to_vec()
    }

    /// Largest finite rank.
    pub fn max_rank(&self) -> u32 {
        self.rank.iter().filter(|&r| r != NONE).max().unwrap_or(0)
    }

    pub(crate) fn heap_bytes(&self, own: bool) -> usize {
        self.rank.heap_bytes(own)
    }
}

/// Ranks from the kitchen (plus `extra` objects, if given).
pub(crate) fn ranks(foon: &Foon, prep: &Prepared, extra: Option<&[bool]>) -> Ranks {
    let n = foon.object_count();
    let n_fu = foon.fu_count();
    let mut rank = vec![NONE; n];
    let mut queue = VecDeque::new();
    for o in 0..n as u32 {
        if prep.in_kitchen(o) || extra.is_some_and(|e| e[o as usize]) {
            rank[o as usize] = 0;
            queue.push_back(o);
        }
    }
    let mut left: Vec<u32> = (0..n_fu as u32)
        .map(|f| prep.needed(f).len() as u32)
        .collect();
    let fire = |f: u32, r: u32, rank: &mut Vec<u32>, queue: &mut VecDeque<u32>| {
        for &y in foon.outputs(f) {
            if rank[y as usize] == NONE && !prep.is_bare(y) {
                rank[y as usize] = r;
                queue.push_back(y);
            }
        }
    };
    // FUs with no needed input can run at once.
    for f in 0..n_fu as u32 {
        if left[f as usize] == 0 {
            fire(f, 1, &mut rank, &mut queue);
        }
    }
    while let Some(o) = queue.pop_front() {
        let r = rank[o as usize];
        for &f in prep.needed_by(o) {
            let l = &mut left[f as usize];
            *l -= 1;
            if *l == 0 {
                // `o` is the last needed input to arrive, so it has the largest rank.
                fire(f, r + 1, &mut rank, &mut queue);
            }
        }
    }
    Ranks::from_vec(rank)
}
