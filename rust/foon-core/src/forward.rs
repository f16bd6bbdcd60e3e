//! Forward chaining from the kitchen: derivable objects and their ranks (the fewest parallel
//! steps that make them), in one pass over the index (breadth-first by rank), over the whole
//! FOON ([`ranks`], for [`Prepared::ranks`]) or over the units of one tree ([`unit_ranks`], for
//! [`crate::evaluate`]).

use std::collections::VecDeque;

use rustc_hash::FxHashMap;

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

/// Ranks of the objects made by the FUs of a tree alone, from the kitchen (see [`unit_ranks`]).
pub(crate) enum TreeRanks {
    /// Object-indexed, for trees that are a large part of the FOON.
    Dense(Vec<u32>),
    /// Only the objects the tree makes, for small trees in large FOONs.
    Sparse(FxHashMap<u32, u32>),
}

impl TreeRanks {
    /// Rank of an object the tree makes (`None` when it does not make it). Kitchen objects are
    /// for the caller to test first.
    pub(crate) fn made(&self, o: u32) -> Option<u32> {
        match self {
            Self::Dense(r) => r.get(o as usize).copied().filter(|&r| r != NONE),
            Self::Sparse(m) => m.get(&o).copied(),
        }
    }
}

/// Ranks of the objects made by the FUs `units` alone, from the kitchen: the same least
/// fixpoint as [`ranks`] restricted to those FUs, in time proportional to the units (not to the
/// whole FOON) when they are few. Ids out of range and repeated units are ignored.
pub(crate) fn unit_ranks(foon: &Foon, prep: &Prepared, units: &[u32]) -> TreeRanks {
    let mut us: Vec<u32> = units
        .iter()
        .copied()
        .filter(|&f| (f as usize) < foon.fu_count())
        .collect();
    us.sort_unstable();
    us.dedup();
    let dense = us.len().saturating_mul(8) > foon.object_count();
    // Needed slots of each unit still waiting for an object outside the kitchen.
    let mut left: Vec<u32> = us
        .iter()
        .map(|&f| {
            prep.needed(f)
                .iter()
                .filter(|&&x| !prep.in_kitchen(x))
                .count() as u32
        })
        .collect();
    // Who waits for an object: dense, the FOON's needed-by lists filtered by the position of
    // each FU in `us`; sparse, a linked list of slots per object (no allocation per object).
    let mut pos = Vec::new();
    let mut slot_unit: Vec<u32> = Vec::new();
    let mut slot_next: Vec<u32> = Vec::new();
    let mut head: FxHashMap<u32, u32> = FxHashMap::default();
    let mut rank = if dense {
        pos = vec![NONE; foon.fu_count()];
        for (i, &f) in us.iter().enumerate() {
            pos[f as usize] = i as u32;
        }
        TreeRanks::Dense(vec![NONE; foon.object_count()])
    } else {
        for (i, &f) in us.iter().enumerate() {
            for &x in prep.needed(f) {
                if !prep.in_kitchen(x) {
                    let slot = slot_unit.len() as u32;
                    slot_unit.push(i as u32);
                    slot_next.push(head.insert(x, slot).unwrap_or(NONE));
                }
            }
        }
        TreeRanks::Sparse(FxHashMap::default())
    };
    let mut queue = VecDeque::new();
    let fire = |f: u32, r: u32, rank: &mut TreeRanks, queue: &mut VecDeque<(u32, u32)>| {
        for &y in foon.outputs(f) {
            if prep.in_kitchen(y) || foon.is_bare(y) {
                continue;
            }
            let fresh = match rank {
                TreeRanks::Dense(v) => {
                    let slot = &mut v[y as usize];
                    let fresh = *slot == NONE;
                    if fresh {
                        *slot = r;
                    }
                    fresh
                }
                TreeRanks::Sparse(m) => match m.entry(y) {
                    std::collections::hash_map::Entry::Vacant(e) => {
                        e.insert(r);
                        true
                    }
                    std::collections::hash_map::Entry::Occupied(_) => false,
                },
            };
            if fresh {
                queue.push_back((y, r));
            }
        }
    };
    // Units whose needed inputs are all in the kitchen (or that need none) run first.
    for (i, &f) in us.iter().enumerate() {
        if left[i] == 0 {
            fire(f, 1, &mut rank, &mut queue);
        }
    }
    let mut arrive = |i: usize, r: u32, rank: &mut TreeRanks, queue: &mut VecDeque<(u32, u32)>| {
        left[i] -= 1;
        if left[i] == 0 {
            // The last needed input to arrive has the largest rank.
            fire(us[i], r + 1, rank, queue);
        }
    };
    while let Some((o, r)) = queue.pop_front() {
        if dense {
            for &f in prep.needed_by(o) {
                let i = pos[f as usize];
                if i != NONE {
                    arrive(i as usize, r, &mut rank, &mut queue);
                }
            }
        } else {
            let mut slot = head.get(&o).copied().unwrap_or(NONE);
            while slot != NONE {
                arrive(slot_unit[slot as usize] as usize, r, &mut rank, &mut queue);
                slot = slot_next[slot as usize];
            }
        }
    }
    rank
}
