//! Iterative deepening: a depth-limited search run with limits 1, 2, 4, ... until the goal is
//! found. The depth-limited search is memoised over the index (exact ranks once known, and the
//! largest limit each object failed at), which makes the whole deepening linear in practice,
//! and it keeps its own stack, so a chain a million steps deep needs no call stack.
//!
//! Its result depends on the kitchen only: the rank of every object it finds is the forward
//! rank, and the producer it keeps for an object is the first (in producer order) whose value
//! (one more than the largest rank of its needed inputs, all derivable) is the object's rank,
//! since a frame keeps a producer only when it is strictly better than the one before. So
//! that choice is computed once per kitchen over the whole FOON ([`choices`], linear in the
//! needed and producer slots), and a plan reads its tree from it; the deepening itself
//! ([`plan`] with [`Context::from_scratch`]) is the definition.

use super::scratch::IdMap;
use super::{Context, Plan, Query, tree};
use crate::error::Result;
use crate::index::NONE;

struct Memo {
    /// Exact rank, when known.
    rank: IdMap<u32>,
    /// `l + 1` where `l` is the largest limit known to fail (0: none).
    failed: IdMap<u32>,
    /// Lowest-index producer achieving the rank.
    choice: IdMap<u32>,
}

impl Memo {
    /// The answer of `dls(o, l)` when the memo already knows it: `Some(Some(rank))` found,
    /// `Some(None)` fails, `None` unknown.
    #[inline]
    #[allow(clippy::option_option)]
    fn quick(&self, ctx: &Context<'_>, o: u32, l: u32) -> Option<Option<u32>> {
        if ctx.in_kitchen(o) {
            return Some(Some(0));
        }
        let r = self.rank.get(o);
        if r != NONE {
            return Some((r <= l).then_some(r));
        }
        if l == 0 || self.failed.get(o) > l || !ctx.ranks().is_derivable(o) {
            return Some(None);
        }
        None
    }
}

struct Frame {
    obj: u32,
    limit: u32,
    /// Largest value still worth finding (the limit, then one less than the best so far).
    cap: u32,
    producer: usize,
    input: usize,
    max: u32,
    best: u32,
    best_fu: u32,
}

struct Stats {
    expanded: u64,
    peak: usize,
}

/// Depth-limited search: the rank of `root` if it is at most `limit`.
fn dls(
    ctx: &Context<'_>,
    memo: &mut Memo,
    root: u32,
    limit: u32,
    stats: &mut Stats,
) -> Result<Option<u32>> {
    if let Some(r) = memo.quick(ctx, root, limit) {
        return Ok(r);
    }
    let new_frame = |obj, limit| Frame {
        obj,
        limit,
        cap: limit,
        producer: 0,
        input: 0,
        max: 0,
        best: NONE,
        best_fu: NONE,
    };
    let mut stack = vec![new_frame(root, limit)];
    stats.expanded += 1;
    let mut child: Option<Option<u32>> = None;
    let mut result = None;
    'frames: while let Some(top) = stack.last_mut() {
        if let Some(r) = child.take() {
            if let Some(rx) = r {
                top.max = top.max.max(rx);
                top.input += 1;
            } else {
                top.producer += 1;
                top.input = 0;
                top.max = 0;
            }
        }
        let prods = ctx.foon.producers(top.obj);
        loop {
            if top.cap == 0 || top.producer >= prods.len() {
                let (o, l) = (top.obj, top.limit);
                let r = if top.best == NONE {
                    let f = memo.failed.get(o);
                    memo.failed.set(o, f.max(l + 1));
                    None
                } else {
                    memo.rank.set(o, top.best);
                    memo.choice.set(o, top.best_fu);
                    Some(top.best)
                };
                stack.pop();
                if stack.is_empty() {
                    result = r;
                } else {
                    child = Some(r);
                }
                continue 'frames;
            }
            let f = prods[top.producer];
            let ins = ctx.needed(f);
            if top.input == ins.len() {
                let value = top.max + 1;
                top.best = value;
                top.best_fu = f;
                top.cap = value - 1;
                top.producer += 1;
                top.input = 0;
                top.max = 0;
                continue;
            }
            let x = ins[top.input];
            match memo.quick(ctx, x, top.cap - 1) {
                Some(Some(r)) => {
                    top.max = top.max.max(r);
                    top.input += 1;
                }
                Some(None) => {
                    top.producer += 1;
                    top.input = 0;
                    top.max = 0;
                }
                None => {
                    let l = top.cap - 1;
                    stack.push(new_frame(x, l));
                    stats.expanded += 1;
                    stats.peak = stats.peak.max(stack.len());
                    if stats.expanded % 4096 == 0 {
                        ctx.check_stop()?;
                    }
                    continue 'frames;
                }
            }
        }
    }
    Ok(result)
}

/// The rank a unit gives its outputs: one more than the largest rank (by `rank`, kitchen
/// objects at 0) of its `needed` inputs, `NONE` when one of them is not derivable. A unit whose
/// value is an object's rank achieves it.
pub(crate) fn unit_rank(needed: &[u32], rank: impl Fn(u32) -> u32) -> u32 {
    let mut m = 0;
    for &x in needed {
        let r = rank(x);
        if r == NONE {
            return NONE;
        }
        m = m.max(r);
    }
    m + 1
}

/// The choice of `ids` for every object: the first producer whose value is the object's rank
/// (`NONE` for kitchen objects and objects that are not derivable).
fn choices(ctx: &Context<'_>) -> Result<Vec<u32>> {
    let foon = ctx.foon;
    let ranks = ctx.ranks();
    let rank = |x: u32| {
        if ctx.in_kitchen(x) { 0 } else { ranks.raw(x) }
    };
    let value: Vec<u32> = (0..foon.fu_count() as u32)
        .map(|f| unit_rank(ctx.needed(f), rank))
        .collect();
    let mut out = vec![NONE; foon.object_count()];
    for (o, slot) in (0..).zip(out.iter_mut()) {
        if o % 65_536 == 0 {
            ctx.check_stop()?;
        }
        let r = ranks.raw(o);
        if r == NONE || ctx.in_kitchen(o) {
            continue;
        }
        if let Some(&f) = foon.producers(o).iter().find(|&&f| value[f as usize] == r) {
            *slot = f;
        }
    }
    Ok(out)
}

pub(super) fn plan(ctx: &Context<'_>, goal: u32, query: Query) -> Result<Plan> {
    if !ctx.is_from_scratch() {
        let choice = ctx.ids_choice(|| choices(ctx))?;
        let e = tree::emit_counted(ctx, goal, |o| choice.get(o));
        return Ok(Plan {
            units: e.units,
            expanded: e.visited,
            peak_frontier: e.peak,
            ..Plan::empty(goal, query)
        });
    }
    let n = ctx.foon.object_count();
    let mut memo = Memo {
        rank: ctx.id_map(n, NONE),
        failed: ctx.id_map(n, 0),
        choice: ctx.id_map(n, NONE),
    };
    let mut stats = Stats {
        expanded: 0,
        peak: 1,
    };
    let mut limit = 1u32;
    // The goal is derivable (the caller checked), so some limit up to its rank succeeds.
    while dls(ctx, &mut memo, goal, limit, &mut stats)?.is_none() {
        limit = limit.saturating_mul(2);
    }
    let units = tree::emit(ctx, goal, |o| memo.choice.get(o));
    Ok(Plan {
        units,
        expanded: stats.expanded,
        peak_frontier: stats.peak,
        ..Plan::empty(goal, query)
    })
}
