//! Forward chaining from the kitchen: derivable objects and their ranks (the fewest parallel
//! steps that make them), in one pass over the index (breadth-first by rank).

use std::collections::VecDeque;

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

/// Ranks from the kitchen (plus `extra` objects, if given), using only the FUs in `fus` (all
/// when `None`).
pub(crate) fn ranks(ctx: &Context<'_>, fus: Option<&[bool]>, extra: Option<&[bool]>) -> Ranks {
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
    let used = |f: u32| fus.is_none_or(|m| m[f as usize]);
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
        if left[f as usize] == 0 && used(f) {
            fire(f, 1, &mut rank, &mut queue);
        }
    }
    while let Some(o) = queue.pop_front() {
        let r = rank[o as usize];
        for &f in ctx.needed_by.row(o) {
            if !used(f) {
                continue;
            }
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
