//! Sound greedy best-first (`greedy-success`, `greedy-inputs`): a depth-first resolution
//! from the goal that tries producers in heuristic order and never uses a producer that
//! needs an object on the current path. Choices, once made, are kept. Own stack, no
//! recursion.
//!
//! Failures are remembered (`docs/METHODS.md`, "Remembered failures"): an *epoch* is the
//! number of choices made so far. A call for `o` that fails without making a choice is
//! recorded with its epoch and its *dependencies*: the objects of the path outside the call
//! whose presence on the path made it skip a producer somewhere inside the call. While the
//! epoch is the same and those objects are all on the path, a new call for `o` would fail the
//! same way without a side effect, so it is answered from the record. The trees are those of
//! the plain definition.

use super::scratch::IdMap;
use super::{Context, Plan, Query, heuristic, tree};
use crate::error::Result;
use crate::index::NONE;

struct Frame {
    obj: u32,
    /// Range of this frame's ordered candidates in the shared buffer.
    cands: (usize, usize),
    cand: usize,
    input: usize,
    checked: bool,
    /// The epoch (number of choices) when the frame was pushed.
    epoch: u32,
    /// This frame's dependencies are `deps[deps_start..]` (a frame's own segment ends where
    /// its child's begins; duplicates are allowed until the frame fails).
    deps_start: usize,
    /// Length of the segment after its last deduplication.
    deps_clean: usize,
}

/// A remembered failure of one object: the epoch it happened in, its dependencies
/// (`arena[start..end]`, sorted, distinct) and the previous record of the same object.
struct Record {
    start: usize,
    end: usize,
    next: u32,
}

/// Remembered failures of the current epoch (all are forgotten when a choice is made).
struct Memo {
    /// Per object: (epoch, index of its latest record); stale when the epoch differs.
    head: IdMap<(u32, u32)>,
    records: Vec<Record>,
    arena: Vec<u32>,
}

impl Memo {
    /// A record of `o` in `epoch` whose dependencies are all on the path, if any.
    fn find(&self, o: u32, epoch: u32, depth: &IdMap<u32>) -> Option<(usize, usize)> {
        let (e, mut r) = self.head.get(o);
        if e != epoch {
            return None;
        }
        while r != NONE {
            let rec = &self.records[r as usize];
            if self.arena[rec.start..rec.end]
                .iter()
                .all(|&d| depth.get(d) != NONE)
            {
                return Some((rec.start, rec.end));
            }
            r = rec.next;
        }
        None
    }

    fn record(&mut self, o: u32, epoch: u32, deps: &[u32]) {
        let (e, r) = self.head.get(o);
        let next = if e == epoch { r } else { NONE };
        let start = self.arena.len();
        self.arena.extend_from_slice(deps);
        self.records.push(Record {
            start,
            end: self.arena.len(),
            next,
        });
        self.head.set(o, (epoch, (self.records.len() - 1) as u32));
    }

    /// A choice was made: every record is stale.
    fn new_epoch(&mut self) {
        self.records.clear();
        self.arena.clear();
    }
}

/// Sorts and deduplicates `v[from..]`.
fn dedup_tail(v: &mut Vec<u32>, from: usize) {
    v[from..].sort_unstable();
    let mut w = from;
    for r in from..v.len() {
        if w == from || v[r] != v[w - 1] {
            v[w] = v[r];
            w += 1;
        }
    }
    v.truncate(w);
}

pub(super) fn plan(ctx: &Context<'_>, goal: u32, query: Query) -> Result<Plan> {
    let foon = ctx.foon;
    let ranks = ctx.ranks();
    let n = foon.object_count();
    let mut choice = ctx.id_map(n, NONE);
    // Position on the path (1 for the goal), NONE when not on it.
    let mut depth = ctx.id_map(n, NONE);
    let mut memo = Memo {
        head: ctx.id_map(n, (NONE, NONE)),
        records: Vec::new(),
        arena: Vec::new(),
    };
    let mut epoch = 0u32;
    let mut deps: Vec<u32> = Vec::new();
    let mut buf: Vec<u32> = Vec::new();
    let mut stack: Vec<Frame> = Vec::new();
    let mut expanded = 0u64;
    let mut peak = 1usize;

    let push = |o: u32,
                epoch: u32,
                stack: &mut Vec<Frame>,
                buf: &mut Vec<u32>,
                deps: &[u32],
                depth: &mut IdMap<u32>|
     -> Result<()> {
        let start = buf.len();
        buf.extend_from_slice(foon.producers(o));
        heuristic::order(ctx, &mut buf[start..], query)?;
        stack.push(Frame {
            obj: o,
            cands: (start, buf.len()),
            cand: 0,
            input: 0,
            checked: false,
            epoch,
            deps_start: deps.len(),
            deps_clean: 0,
        });
        depth.set(o, stack.len() as u32);
        Ok(())
    };
    // The goal is derivable and not in the kitchen (the caller checked).
    push(goal, epoch, &mut stack, &mut buf, &deps, &mut depth)?;
    expanded += 1;
    let mut child: Option<bool> = None;
    'frames: while let Some(top) = stack.last_mut() {
        if let Some(ok) = child.take() {
            if ok {
                top.input += 1;
            } else {
                top.cand += 1;
                top.input = 0;
                top.checked = false;
            }
        }
        // Whether this call has made no choice yet (only then do its dependencies matter).
        let clean = top.epoch == epoch;
        loop {
            let (a, b) = top.cands;
            if a + top.cand >= b {
                // No producer works: fail.
                let (o, from) = (top.obj, top.deps_start);
                depth.set(o, NONE);
                buf.truncate(a);
                stack.pop();
                if clean {
                    dedup_tail(&mut deps, from);
                    memo.record(o, epoch, &deps[from..]);
                    // The parent inherits the dependencies, except its own object.
                    if let Some(parent) = stack.last_mut() {
                        let mut w = from;
                        for r in from..deps.len() {
                            if deps[r] != parent.obj {
                                deps[w] = deps[r];
                                w += 1;
                            }
                        }
                        deps.truncate(w);
                        // Keep the parent's segment within twice its distinct size.
                        if deps.len() - parent.deps_start > 2 * parent.deps_clean + 16 {
                            dedup_tail(&mut deps, parent.deps_start);
                            parent.deps_clean = deps.len() - parent.deps_start;
                        }
                    }
                } else {
                    deps.truncate(from);
                }
                child = Some(false);
                continue 'frames;
            }
            let f = buf[a + top.cand];
            let ins = ctx.needed(f);
            if !top.checked {
                // The input on the path nearest to this frame explains the skip (a dependency
                // unless it is this frame's own object).
                let nearest = ins
                    .iter()
                    .filter_map(|&x| {
                        let d = depth.get(x);
                        (d != NONE).then_some((d, x))
                    })
                    .max();
                if let Some((_, x)) = nearest {
                    if clean && x != top.obj {
                        deps.push(x);
                    }
                    top.cand += 1;
                    continue;
                }
                top.checked = true;
            }
            if top.input == ins.len() {
                let o = top.obj;
                choice.set(o, f);
                epoch += 1;
                memo.new_epoch();
                depth.set(o, NONE);
                buf.truncate(a);
                deps.truncate(top.deps_start);
                stack.pop();
                child = Some(true);
                continue 'frames;
            }
            let x = ins[top.input];
            if ctx.in_kitchen(x) || choice.get(x) != NONE {
                top.input += 1;
            } else if !ranks.is_derivable(x) {
                top.cand += 1;
                top.input = 0;
                top.checked = false;
            } else if let Some((s, e)) = memo.find(x, epoch, &depth) {
                // `x` fails again, for the same reasons.
                if clean {
                    let o = top.obj;
                    deps.extend(memo.arena[s..e].iter().copied().filter(|&d| d != o));
                }
                top.cand += 1;
                top.input = 0;
                top.checked = false;
            } else {
                push(x, epoch, &mut stack, &mut buf, &deps, &mut depth)?;
                expanded += 1;
                peak = peak.max(stack.len());
                if expanded % 4096 == 0 {
                    ctx.check_stop()?;
                }
                continue 'frames;
            }
        }
    }
    let units = tree::emit(ctx, goal, |o| choice.get(o));
    Ok(Plan {
        units,
        expanded,
        peak_frontier: peak,
        ..Plan::empty(goal, query)
    })
}
