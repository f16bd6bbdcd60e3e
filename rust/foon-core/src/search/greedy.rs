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
//! same way without a side effect, so it is answered from the record. At most
//! [`RECORDS_PER_OBJECT`] records are kept per object and epoch (the newest), so a look-up
//! costs a bounded number of dependency tests.
//!
//! Dead regions are pruned (`docs/METHODS.md`, "Dead regions"): once an epoch has expanded
//! many objects, the objects that cannot lead to a choice in it, whatever the path, are
//! computed once for the epoch ([`Live`]); such an object fails at once, with no dependency.
//! The trees are those of the plain definition.

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
    /// The liveness computation whose path dependencies this frame has already taken.
    live_stamp: u32,
}

/// A remembered failure of one object: its dependencies (`arena[start..end]`, sorted,
/// distinct) and the previous (older) record of the same object in the same epoch.
struct Record {
    start: usize,
    end: usize,
    next: u32,
}

/// The most records kept per object and epoch: a new failure beyond it replaces the oldest.
/// Only the cost changes (a forgotten record may make a call be expanded again), never a
/// result.
const RECORDS_PER_OBJECT: u32 = 16;

/// Remembered failures of the current epoch (all are forgotten when a choice is made).
struct Memo {
    /// Per object: (epoch, index of its newest record, number of its records); stale when the
    /// epoch differs.
    head: IdMap<(u32, u32, u32)>,
    records: Vec<Record>,
    arena: Vec<u32>,
    /// Arena entries of replaced records (reclaimed by [`Memo::compact`]).
    garbage: usize,
    /// The objects with records in the current epoch.
    touched: Vec<u32>,
}

impl Memo {
    /// A record of `o` in `epoch` whose dependencies are all on the path, if any.
    fn find(&self, o: u32, epoch: u32, depth: &IdMap<u32>) -> Option<(usize, usize)> {
        let (e, mut r, _) = self.head.get(o);
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
        let (e, r, count) = self.head.get(o);
        let (next, count) = if e == epoch {
            (r, count)
        } else {
            self.touched.push(o);
            (NONE, 0)
        };
        let start = self.arena.len();
        self.arena.extend_from_slice(deps);
        self.records.push(Record {
            start,
            end: self.arena.len(),
            next,
        });
        let newest = (self.records.len() - 1) as u32;
        if count < RECORDS_PER_OBJECT {
            self.head.set(o, (epoch, newest, count + 1));
            return;
        }
        // Drop the oldest: the chain holds `RECORDS_PER_OBJECT` records after the new one.
        self.head.set(o, (epoch, newest, count));
        let mut last = newest;
        for _ in 1..RECORDS_PER_OBJECT {
            last = self.records[last as usize].next;
        }
        let oldest = std::mem::replace(&mut self.records[last as usize].next, NONE);
        let rec = &self.records[oldest as usize];
        self.garbage += rec.end - rec.start + 1;
        if self.garbage > 4096 && 2 * self.garbage > self.arena.len() + self.records.len() {
            self.compact(epoch);
        }
    }

    /// Rebuilds the arena and the records without the replaced ones (same order), so that
    /// memory stays proportional to the records kept.
    fn compact(&mut self, epoch: u32) {
        let mut records = Vec::new();
        let mut arena = Vec::new();
        let mut chain = Vec::new();
        for &o in &self.touched {
            let (e, mut r, count) = self.head.get(o);
            debug_assert_eq!(e, epoch);
            chain.clear();
            while r != NONE {
                chain.push(r);
                r = self.records[r as usize].next;
            }
            let mut next = NONE;
            for &r in chain.iter().rev() {
                let rec = &self.records[r as usize];
                let start = arena.len();
                arena.extend_from_slice(&self.arena[rec.start..rec.end]);
                records.push(Record {
                    start,
                    end: arena.len(),
                    next,
                });
                next = (records.len() - 1) as u32;
            }
            self.head.set(o, (epoch, next, count));
        }
        self.records = records;
        self.arena = arena;
        self.garbage = 0;
    }

    /// A choice was made: every record is stale.
    fn new_epoch(&mut self) {
        self.records.clear();
        self.arena.clear();
        self.touched.clear();
        self.garbage = 0;
    }
}

/// An epoch expands this many objects before its dead region is computed (and at least as many
/// as the last computation's region held, which pays for the next one).
const LIVE_AFTER: u64 = 256;

/// The objects that can still lead to a choice in one epoch, given the path
/// (`docs/METHODS.md`, "Dead regions").
///
/// Within an epoch, a call for `x` explores, for each producer `f` of `x` it does not skip, only
/// `f`'s first needed input that is neither in the kitchen nor chosen (its *first open* input):
/// if there is none, `f` succeeds and the epoch ends; if it is not derivable, `f` fails; if its
/// call succeeds, the epoch ends. The *epoch graph* over a set B of objects on the path has an
/// edge `x -> first_open(f)` for every producer `f` of an open derivable `x` that needs neither
/// `x` nor an object of B, and whose first open input is derivable. `x` is *live* when it
/// reaches, in that graph, an object with a producer that has no open needed input. Skips for
/// the path only remove edges, so while every object of B that removed an edge (the
/// *blockers*) is on the path, a call for an object that is not live fails, without a side
/// effect. B is the path when the computation is made, and the graph is explored from the
/// object of the top frame: every call below it is for an object it reaches.
struct Live {
    /// Per object: the computation that reached it (a stamp) and whether it is live.
    mark: IdMap<(u32, bool)>,
    /// Per object: the computation for which it is a blocker (a stamp).
    blocker: IdMap<u32>,
    blockers: Vec<u32>,
    /// Blockers of the last computation that are not on the path now.
    off_path: usize,
    stamp: u32,
    /// The epoch of the last computation (`NONE`: none yet).
    epoch: u32,
    /// Objects the last computation reached.
    region: u64,
    queue: Vec<u32>,
    /// Edges of the epoch graph, as (to, from).
    edges: Vec<(u32, u32)>,
}

impl Live {
    /// Whether the last computation holds now (same epoch, every blocker on the path).
    fn holds(&self, epoch: u32) -> bool {
        self.epoch == epoch && self.off_path == 0
    }

    /// Whether `x` is known not to be live in `epoch` on the current path.
    fn dead(&self, x: u32, epoch: u32) -> bool {
        self.holds(epoch) && self.mark.get(x) == (self.stamp, false)
    }

    /// `o` leaves the path.
    fn popped(&mut self, o: u32) {
        if self.blocker.get(o) == self.stamp {
            self.off_path += 1;
        }
    }

    /// `o` comes on the path.
    fn pushed(&mut self, o: u32) {
        if self.blocker.get(o) == self.stamp && self.off_path > 0 {
            self.off_path -= 1;
        }
    }

    /// Computes the live objects that the epoch graph over the current path reaches from
    /// `top` (the object of the top frame, on the path).
    fn compute(
        &mut self,
        ctx: &Context<'_>,
        top: u32,
        choice: &IdMap<u32>,
        on_path: &dyn Fn(u32) -> bool,
        epoch: u32,
    ) -> Result<()> {
        let ranks = ctx.ranks();
        self.stamp += 1;
        self.epoch = epoch;
        self.off_path = 0;
        self.blockers.clear();
        let stamp = self.stamp;
        self.queue.clear();
        self.edges.clear();
        let open = |y: u32| !ctx.in_kitchen(y) && choice.get(y) == NONE;
        // Forward: the region, its edges, and the objects with a producer ready to run.
        let mut ready = Vec::new();
        self.mark.set(top, (stamp, false));
        self.queue.push(top);
        let mut i = 0;
        while let Some(&x) = self.queue.get(i) {
            i += 1;
            if i % 4096 == 0 {
                ctx.check_stop()?;
            }
            let mut is_ready = false;
            for &f in ctx.foon.producers(x) {
                let ins = ctx.needed(f);
                if ins.contains(&x) {
                    continue;
                }
                if let Some(&b) = ins.iter().find(|&&y| on_path(y)) {
                    if self.blocker.get(b) != stamp {
                        self.blocker.set(b, stamp);
                        self.blockers.push(b);
                    }
                    continue;
                }
                match ins.iter().copied().find(|&y| open(y)) {
                    None => is_ready = true,
                    Some(y) if ranks.is_derivable(y) => {
                        self.edges.push((y, x));
                        if self.mark.get(y).0 != stamp {
                            self.mark.set(y, (stamp, false));
                            self.queue.push(y);
                        }
                    }
                    Some(_) => {}
                }
            }
            if is_ready {
                ready.push(x);
            }
        }
        self.region = self.queue.len() as u64;
        // Backward from the ready objects: everything that reaches one is live.
        self.edges.sort_unstable();
        self.queue.clear();
        for x in ready {
            self.mark.set(x, (stamp, true));
            self.queue.push(x);
        }
        while let Some(y) = self.queue.pop() {
            let from = self.edges.partition_point(|&(to, _)| to < y);
            for &(to, x) in &self.edges[from..] {
                if to != y {
                    break;
                }
                if self.mark.get(x) != (stamp, true) {
                    self.mark.set(x, (stamp, true));
                    self.queue.push(x);
                }
            }
        }
        Ok(())
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
    let shared = heuristic::shared(ctx, query)?;
    let n = foon.object_count();
    let mut choice = ctx.id_map(n, NONE);
    // Position on the path (1 for the goal), NONE when not on it.
    let mut depth = ctx.id_map(n, NONE);
    let mut memo = Memo {
        head: ctx.id_map(n, (NONE, NONE, 0)),
        records: Vec::new(),
        arena: Vec::new(),
        garbage: 0,
        touched: Vec::new(),
    };
    let new_live = || Live {
        mark: ctx.id_map(n, (0, false)),
        blocker: ctx.id_map(n, 0),
        blockers: Vec::new(),
        off_path: 0,
        stamp: 0,
        epoch: NONE,
        region: 0,
        queue: Vec::new(),
        edges: Vec::new(),
    };
    // `live` is computed from the goal with only the goal taken as on the path (it holds for
    // the whole epoch); `near`, computed when that was not enough, from the top frame with
    // the whole path (it holds while its blockers stay on the path).
    let mut live = new_live();
    let mut near = new_live();
    // Objects expanded in the current epoch, and how many it may expand before its dead
    // region is computed.
    let mut epoch_expanded = 0u64;
    let mut live_after = LIVE_AFTER;
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
        if let Some(g) = shared {
            buf.extend_from_slice(g.order.row(o));
        } else {
            buf.extend_from_slice(foon.producers(o));
            heuristic::order(ctx, &mut buf[start..], query)?;
        }
        stack.push(Frame {
            obj: o,
            cands: (start, buf.len()),
            cand: 0,
            input: 0,
            checked: false,
            epoch,
            deps_start: deps.len(),
            deps_clean: 0,
            live_stamp: 0,
        });
        depth.set(o, stack.len() as u32);
        Ok(())
    };
    // The goal is derivable and not in the kitchen (the caller checked).
    push(goal, epoch, &mut stack, &mut buf, &deps, &mut depth)?;
    // The objects of the stack's frames, bottom first (the path).
    let mut path: Vec<u32> = vec![goal];
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
                live.popped(o);
                near.popped(o);
                buf.truncate(a);
                stack.pop();
                path.pop();
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
                epoch_expanded = 0;
                memo.new_epoch();
                depth.set(o, NONE);
                live.popped(o);
                near.popped(o);
                buf.truncate(a);
                deps.truncate(top.deps_start);
                stack.pop();
                path.pop();
                child = Some(true);
                continue 'frames;
            }
            let x = ins[top.input];
            if ctx.in_kitchen(x) || choice.get(x) != NONE {
                top.input += 1;
                continue;
            }
            if epoch_expanded >= live_after {
                if live.epoch != epoch {
                    live.compute(ctx, goal, &choice, &|y| y == goal, epoch)?;
                    epoch_expanded = 0;
                    live_after = LIVE_AFTER.max(live.region);
                } else if !near.holds(epoch) {
                    // The shallowest prefix of the path that shows `x` dead: its verdicts
                    // hold for as long as its (fewer, deeper-rooted) blockers stay on the
                    // path. Prefixes of 2, 4, 8, ... frames, then the whole path.
                    let mut len = 2.min(path.len());
                    loop {
                        let on_path = |y: u32| {
                            let d = depth.get(y);
                            d != NONE && d as usize <= len
                        };
                        near.compute(ctx, path[len - 1], &choice, &on_path, epoch)?;
                        if len == path.len() || near.dead(x, epoch) {
                            break;
                        }
                        len = (2 * len).min(path.len());
                    }
                    epoch_expanded = 0;
                    live_after = LIVE_AFTER.max(live.region).max(near.region);
                }
            }
            if !ranks.is_derivable(x) || live.dead(x, epoch) {
                // `x` fails on every path of this epoch.
                top.cand += 1;
                top.input = 0;
                top.checked = false;
            } else if near.dead(x, epoch) {
                // `x` fails while the blockers are on the path: they are dependencies.
                if clean && top.live_stamp != near.stamp {
                    top.live_stamp = near.stamp;
                    let o = top.obj;
                    deps.extend(near.blockers.iter().copied().filter(|&d| d != o));
                }
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
                live.pushed(x);
                path.push(x);
                near.pushed(x);
                expanded += 1;
                epoch_expanded += 1;
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

#[cfg(test)]
mod tests {
    use super::{IdMap, Memo, NONE, RECORDS_PER_OBJECT};

    fn memo(n: usize) -> Memo {
        Memo {
            head: IdMap::new(n, (NONE, NONE, 0), n),
            records: Vec::new(),
            arena: Vec::new(),
            garbage: 0,
            touched: Vec::new(),
        }
    }

    fn chain(m: &Memo, o: u32) -> Vec<Vec<u32>> {
        let (_, mut r, _) = m.head.get(o);
        let mut out = Vec::new();
        while r != NONE {
            let rec = &m.records[r as usize];
            out.push(m.arena[rec.start..rec.end].to_vec());
            r = rec.next;
        }
        out
    }

    /// An object's records were one unbounded list, scanned in full by every look-up: at most
    /// `RECORDS_PER_OBJECT` are kept (the newest), through compactions, in order.
    #[test]
    fn records_per_object_are_capped_newest_first() {
        let n = 4000;
        let mut m = memo(n);
        let mut depth = IdMap::new(n, NONE, n);
        for d in 0..3000u32 {
            m.record(1, 7, &[d, d + 1]);
            m.record(2, 7, &[d]);
        }
        assert!(m.arena.len() < 2 * 4096 + 64, "arena {}", m.arena.len());
        let keep = RECORDS_PER_OBJECT;
        let c1 = chain(&m, 1);
        assert_eq!(c1.len(), keep as usize);
        assert_eq!(c1[0], [2999, 3000]);
        assert_eq!(c1[keep as usize - 1], [3000 - keep, 3001 - keep]);
        assert_eq!(chain(&m, 2)[0], [2999]);
        // A kept record applies when its dependencies are on the path; a replaced one no more.
        depth.set(2990, 1);
        depth.set(2991, 2);
        assert!(m.find(1, 7, &depth).is_some());
        assert!(m.find(1, 8, &depth).is_none());
        let mut old = IdMap::new(n, NONE, n);
        old.set(5, 1);
        old.set(6, 2);
        assert!(m.find(1, 7, &old).is_none());
        // A new epoch (a choice) forgets them all.
        m.new_epoch();
        assert!(m.find(1, 8, &depth).is_none());
        m.record(1, 8, &[2990]);
        assert_eq!(chain(&m, 1), [[2990]]);
        assert!(m.find(1, 8, &depth).is_some());
    }
}
