//! Forward chaining from the kitchen: derivable objects and their ranks (the fewest parallel
//! steps that make them), in one pass over the index (breadth-first by rank), over the whole
//! FOON ([`ranks`], for [`Prepared::ranks`]; the same rule over the units of one tree is
//! `evaluate::shape`).

use std::collections::VecDeque;

use crate::index::{Foon, NONE};
use crate::prepare::Prepared;

/// Rank of every object (`NONE` when not derivable).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ranks {
    rank: Vec<u32>,
}

impl Ranks {
    /// Ranks given per object (`NONE` when not derivable), computed elsewhere
    /// ([`crate::multi`]).
    pub(crate) fn from_vec(rank: Vec<u32>) -> Self {
        Self { rank }
    }

    pub fn rank(&self, o: u32) -> Option<u32> {
        self.rank.get(o as usize).copied().filter(|&r| r != NONE)
    }

    pub fn is_derivable(&self, o: u32) -> bool {
        self.rank(o).is_some()
    }

    pub fn as_slice(&self) -> &[u32] {
        &self.rank
    }

    /// Largest finite rank.
    pub fn max_rank(&self) -> u32 {
        self.rank
            .iter()
            .copied()
            .filter(|&r| r != NONE)
            .max()
            .unwrap_or(0)
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
            if rank[y as usize] == NONE && !foon.is_bare(y) {
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
    Ranks { rank }
}
