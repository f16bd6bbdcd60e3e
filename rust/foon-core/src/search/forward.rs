//! Forward chaining from the kitchen: derivable objects and their ranks (the fewest parallel
//! steps that make them), in one pass over the index (breadth-first by rank).

use std::collections::VecDeque;

use rustc_hash::FxHashMap;

use super::Context;
use crate::index::NONE;

/// Rank of every object (`NONE` when not derivable).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Ranks {
    rank: Vec<u32>,
}

impl Ranks {
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
pub(crate) fn ranks(ctx: &Context<'_>, extra: Option<&[bool]>) -> Ranks {
    let foon = ctx.foon;
    let n = foon.object_count();
    let n_fu = foon.fu_count();
    let mut rank = vec![NONE; n];
    let mut queue = VecDeque::new();
    for o in 0..n as u32 {
        if ctx.in_kitchen(o) || extra.is_some_and(|e| e[o as usize]) {
            rank[o as usize] = 0;
            queue.push_back(o);
        }
    }
    let mut left: Vec<u32> = (0..n_fu as u32)
        .map(|f| ctx.needed(f).len() as u32)
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
        for &f in ctx.needed_by.row(o) {
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

/// Ranks of the objects made by the FUs `units` alone, from the kitchen: the same least
/// fixpoint as [`ranks`] restricted to those FUs, but in time proportional to the units, not
/// to the whole FOON. Kitchen objects are not in the map (their rank is 0); ids out of range
/// and repeated units are ignored.
pub(crate) fn unit_ranks(ctx: &Context<'_>, units: &[u32]) -> FxHashMap<u32, u32> {
    let foon = ctx.foon;
    let mut us: Vec<u32> = units
        .iter()
        .copied()
        .filter(|&f| (f as usize) < foon.fu_count())
        .collect();
    us.sort_unstable();
    us.dedup();
    // Needed slots of each unit that wait for an object outside the kitchen, and for each such
    // object the units (by position in `us`) where it is a needed slot.
    let mut left = vec![0u32; us.len()];
    let mut waiting: FxHashMap<u32, Vec<u32>> = FxHashMap::default();
    for (i, &f) in us.iter().enumerate() {
        for &x in ctx.needed(f) {
            if !ctx.in_kitchen(x) {
                left[i] += 1;
                waiting.entry(x).or_default().push(i as u32);
            }
        }
    }
    let mut rank: FxHashMap<u32, u32> = FxHashMap::default();
    let mut queue = VecDeque::new();
    let fire = |f: u32, r: u32, rank: &mut FxHashMap<u32, u32>, queue: &mut VecDeque<u32>| {
        for &y in foon.outputs(f) {
            if !ctx.in_kitchen(y) && !foon.is_bare(y) && !rank.contains_key(&y) {
                rank.insert(y, r);
                queue.push_back(y);
            }
        }
    };
    // Units whose needed inputs are all in the kitchen (or that need none) run first.
    for (i, &f) in us.iter().enumerate() {
        if left[i] == 0 {
            fire(f, 1, &mut rank, &mut queue);
        }
    }
    while let Some(o) = queue.pop_front() {
        let r = rank[&o];
        if let Some(ws) = waiting.get(&o) {
            for &i in ws {
                let l = &mut left[i as usize];
                *l -= 1;
                if *l == 0 {
                    fire(us[i as usize], r + 1, &mut rank, &mut queue);
                }
            }
        }
    }
    rank
}
