//! Optimal trees (Knuth's generalisation of Dijkstra over the AND-OR graph, tree cost) and
//! the explanation of failed searches.
//!
//! Costs and choices depend on the kitchen only, not on the goal, so they are computed once
//! per kitchen and objective over the whole FOON ([`knuth_all`], kept in the
//! [`Prepared`](crate::prepare::Prepared) inputs), and a plan reads its tree from them. This
//! gives the trees of the search from the goal ([`knuth`], still used when some motion has no
//! rate, and by [`Context::from_scratch`]): the units that can set the cost or the choice of
//! an object of the goal's ancestry are those producing it, whose needed inputs are in the
//! ancestry, so the heap entries of the ancestry are pushed and popped in the same order
//! whatever else the heap holds, and every object of a tree is final before the goal is.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::radix::RadixQueue;
use super::scratch::IdMap;
use super::{Context, Explanation, Method, Plan, Query, tree};
use crate::error::Result;
use crate::index::NONE;
use crate::prepare::{Objective, Optimum, OptimumAt, Slot};

/// An entry of the heap of Knuth's algorithm: a min-heap on (cost, depth, object id), the
/// depth being the tie key of [`tie_depth`] (0 for the searches that do not use it). The
/// searches built on it (k best, fewest distinct units, the robot/human split) share it.
#[derive(PartialEq)]
pub(crate) struct Entry {
    pub(crate) cost: f64,
    pub(crate) depth: u32,
    pub(crate) obj: u32,
}

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        // Min-heap on (cost, depth, object id).
        other
            .cost
            .total_cmp(&self.cost)
            .then(other.depth.cmp(&self.depth))
            .then(other.obj.cmp(&self.obj))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// The tie key of a unit of cost `c` whose needed inputs have the (cost, depth) pairs
/// `inputs`: one more than the largest depth of an input that costs exactly `c` (a step that
/// does not raise the cost), 0 when every input costs less. Objects are ordered by (cost,
/// depth): a unit's (cost, depth) is then above each of its inputs', so ties never depend on
/// the order in which equal-cost objects are finalised (see `docs/METHODS.md`).
#[inline]
pub(crate) fn tie_depth(c: f64, inputs: impl IntoIterator<Item = (f64, u32)>) -> u32 {
    let mut d = 0;
    for (xc, xd) in inputs {
        // Exact equality on purpose: only a step that leaves the sum unchanged counts.
        #[allow(clippy::float_cmp)]
        if xc == c {
            d = d.max(xd + 1);
        }
    }
    d
}

/// Whether a unit offering (`c`, `d`) as unit `f` beats the current (`old_c`, `old_d`) with
/// choice `old_f`: a lower (cost, depth), or the same with a lower unit index. Costs are
/// compared exactly.
#[inline]
pub(crate) fn better(c: f64, d: u32, f: u32, old_c: f64, old_d: u32, old_f: u32) -> bool {
    match c.total_cmp(&old_c).then(d.cmp(&old_d)) {
        Ordering::Less => true,
        Ordering::Equal => f < old_f,
        Ordering::Greater => false,
    }
}

/// Whether (`c`, `d`) is strictly below (`old_c`, `old_d`).
#[inline]
pub(crate) fn lower(c: f64, d: u32, old_c: f64, old_d: u32) -> bool {
    c.total_cmp(&old_c).then(d.cmp(&old_d)) == Ordering::Less
}

/// The part of the FOON that can matter for a goal: the objects from which it can be reached
/// backwards (through producers and their needed inputs, not past a leaf), and the FUs that
/// produce one of them that is not a leaf. The cost, derivability and choice of every object
/// in it depend on these FUs alone, so a search from the goal needs nothing else: its cost
/// follows the goal's ancestry, not the size of the FOON.
struct Ancestry {
    objects: Vec<u32>,
    fus: Vec<u32>,
    has_object: IdMap<bool>,
    has_fu: IdMap<bool>,
}

fn ancestry(ctx: &Context<'_>, goal: u32, is_leaf: &dyn Fn(u32) -> bool) -> Result<Ancestry> {
    let foon = ctx.foon;
    let mut a = Ancestry {
        objects: vec![goal],
        fus: Vec::new(),
        has_object: ctx.id_map(foon.object_count(), false),
        has_fu: ctx.id_map(foon.fu_count(), false),
    };
    a.has_object.set(goal, true);
    let mut next = 0;
    while let Some(&o) = a.objects.get(next) {
        next += 1;
        if next % 4096 == 0 {
            ctx.check_stop()?;
        }
        if is_leaf(o) {
            continue;
        }
        for &f in foon.producers(o) {
            if a.has_fu.replace(f, true) {
                continue;
            }
            a.fus.push(f);
            for &x in ctx.needed(f) {
                if !a.has_object.replace(x, true) {
                    a.objects.push(x);
                }
            }
        }
    }
    Ok(a)
}

/// Result of Knuth's algorithm: final cost and choice of every object reached.
pub(super) struct Knuth {
    pub(super) cost: IdMap<f64>,
    pub(super) choice: IdMap<u32>,
    pub(super) expanded: u64,
    pub(super) peak: usize,
}

/// Knuth's algorithm for `goal`, over its ancestry: leaves (`is_leaf`) cost `leaf`, an FU
/// weighs `weight`. Objects are finalised in (cost, depth, id) order until the goal is (the
/// depth of [`tie_depth`]); an object's choice is the lowest-index producer that sets its
/// final (cost, depth), all its needed inputs being final before it. When the goal cannot be
/// reached, every object of its ancestry that can is final at the end.
pub(super) fn knuth(
    ctx: &Context<'_>,
    goal: u32,
    is_leaf: &dyn Fn(u32) -> bool,
    leaf: f64,
    weight: &dyn Fn(u32) -> Result<f64>,
) -> Result<Knuth> {
    let foon = ctx.foon;
    let sub = ancestry(ctx, goal, is_leaf)?;
    let mut cost = ctx.id_map(foon.object_count(), f64::INFINITY);
    let mut depth = ctx.id_map(foon.object_count(), 0u32);
    let mut choice = ctx.id_map(foon.object_count(), NONE);
    let mut done = ctx.id_map(foon.object_count(), false);
    let mut left = ctx.id_map(foon.fu_count(), 0u32);
    for &f in &sub.fus {
        left.set(f, ctx.needed(f).len() as u32);
    }
    let mut heap = BinaryHeap::new();
    let mut expanded = 0u64;
    let mut peak = 0usize;
    // Leaves have a fixed cost: no unit may lower it.
    for &o in &sub.objects {
        if is_leaf(o) {
            cost.set(o, leaf);
            heap.push(Entry {
                cost: leaf,
                depth: 0,
                obj: o,
            });
        }
    }
    let fire = |f: u32,
                cost: &mut IdMap<f64>,
                depth: &mut IdMap<u32>,
                choice: &mut IdMap<u32>,
                done: &IdMap<bool>,
                heap: &mut BinaryHeap<Entry>|
     -> Result<()> {
        let mut c = weight(f)?;
        for &x in ctx.needed(f) {
            c += cost.get(x);
        }
        if c == f64::INFINITY {
            // A unit of infinite cost (a motion of rate 0) sets nothing.
            return Ok(());
        }
        let d = tie_depth(
            c,
            ctx.needed(f).iter().map(|&x| (cost.get(x), depth.get(x))),
        );
        for &y in foon.outputs(f) {
            if !sub.has_object.get(y) || done.get(y) || is_leaf(y) || foon.is_bare(y) {
                continue;
            }
            let (old_cost, old_depth) = (cost.get(y), depth.get(y));
            if better(c, d, f, old_cost, old_depth, choice.get(y)) {
                if lower(c, d, old_cost, old_depth) {
                    heap.push(Entry {
                        cost: c,
                        depth: d,
                        obj: y,
                    });
                }
                cost.set(y, c);
                depth.set(y, d);
                choice.set(y, f);
            }
        }
        Ok(())
    };
    for &f in &sub.fus {
        if left.get(f) == 0 {
            fire(f, &mut cost, &mut depth, &mut choice, &done, &mut heap)?;
        }
    }
    while let Some(Entry {
        cost: c,
        depth: d,
        obj: o,
    }) = heap.pop()
    {
        if done.get(o) || lower(cost.get(o), depth.get(o), c, d) {
            continue;
        }
        done.set(o, true);
        expanded += 1;
        if expanded % 4096 == 0 {
            ctx.check_stop()?;
        }
        if o == goal {
            break;
        }
        for &f in ctx.needed_by(o) {
            if !sub.has_fu.get(f) {
                continue;
            }
            let l = left.get(f) - 1;
            left.set(f, l);
            if l == 0 {
                fire(f, &mut cost, &mut depth, &mut choice, &done, &mut heap)?;
            }
        }
        peak = peak.max(heap.len());
    }
    for &o in &sub.objects {
        if !done.get(o) {
            cost.set(o, f64::INFINITY);
            choice.set(o, NONE);
        }
    }
    Ok(Knuth {
        cost,
        choice,
        expanded,
        peak,
    })
}

/// Knuth's algorithm from the kitchen over the whole FOON, to the end: leaves (`is_leaf`)
/// cost `leaf`, an FU weighs `weight`; the same rules as [`knuth`], in time near-linear in the
/// FOON (one queue entry per improvement of an object's cost). Each object's cost, choice,
/// depth and state sit side by side (one cache line read per look-up on a FOON far larger
/// than the caches), and the queue is the radix heap of `radix.rs`, whose pops are those of a
/// binary heap of [`Entry`].
pub(crate) fn knuth_all(
    ctx: &Context<'_>,
    is_leaf: &dyn Fn(u32) -> bool,
    leaf: f64,
    weight: &dyn Fn(u32) -> f64,
) -> Result<Optimum> {
    // The low two bits of `tag` are the state, the others the depth.
    const OPEN: u32 = 0;
    const DONE: u32 = 1;
    // A leaf not yet final, or an object whose cost no unit sets (a bare output).
    const FIXED: u32 = 2;
    const STATE: u32 = 3;
    #[derive(Clone, Copy)]
    struct Work {
        cost: f64,
        choice: u32,
        tag: u32,
    }
    impl Work {
        #[inline]
        fn depth(self) -> u32 {
            self.tag >> 2
        }
        #[inline]
        fn state(self) -> u32 {
            self.tag & STATE
        }
    }
    let foon = ctx.foon;
    let n = foon.object_count();
    let mut slots = vec![
        Work {
            cost: f64::INFINITY,
            choice: NONE,
            tag: OPEN,
        };
        n
    ];
    // The leaves, final in id order at their fixed cost: a sorted run merged with the queue
    // (the same pops as with them in the queue, without their entries).
    let mut leaves = Vec::new();
    for (o, slot) in (0..n as u32).zip(slots.iter_mut()) {
        if is_leaf(o) {
            slot.cost = leaf;
            slot.tag = FIXED;
            leaves.push(o);
        } else if foon.is_bare(o) {
            slot.tag = FIXED;
        }
    }
    let mut left: Vec<u32> = (0..foon.fu_count() as u32)
        .map(|f| ctx.needed(f).len() as u32)
        .collect();
    let mut queue = RadixQueue::new();
    let fire = |f: u32, slots: &mut [Work], queue: &mut RadixQueue| {
        let mut c = weight(f);
        for &x in ctx.needed(f) {
            c += slots[x as usize].cost;
        }
        if c == f64::INFINITY {
            // A unit of infinite cost (a motion of rate 0) sets nothing.
            return;
        }
        let d = tie_depth(
            c,
            ctx.needed(f).iter().map(|&x| {
                let s = slots[x as usize];
                (s.cost, s.depth())
            }),
        );
        for &y in foon.outputs(f) {
            let s = &mut slots[y as usize];
            if s.state() != OPEN {
                continue;
            }
            if better(c, d, f, s.cost, s.depth(), s.choice) {
                if lower(c, d, s.cost, s.depth()) {
                    queue.push(Entry {
                        cost: c,
                        depth: d,
                        obj: y,
                    });
                }
                s.cost = c;
                s.choice = f;
                s.tag = (d << 2) | OPEN;
            }
        }
    };
    for f in 0..foon.fu_count() as u32 {
        if left[f as usize] == 0 {
            fire(f, &mut slots, &mut queue);
        }
    }
    let mut next_leaf = 0;
    let mut finalised = 0u64;
    loop {
        let from_leaves = match (queue.peek(), leaves.get(next_leaf)) {
            (None, None) => break,
            (None, Some(_)) => true,
            (Some(_), None) => false,
            // `Entry` orders the least as the greatest (a min-heap).
            (Some(top), Some(&l)) => {
                Entry {
                    cost: leaf,
                    depth: 0,
                    obj: l,
                } > *top
            }
        };
        let o = if from_leaves {
            next_leaf += 1;
            leaves[next_leaf - 1]
        } else {
            let Some(Entry {
                cost: c,
                depth: d,
                obj: o,
            }) = queue.pop()
            else {
                break;
            };
            let s = slots[o as usize];
            if s.state() == DONE || lower(s.cost, s.depth(), c, d) {
                continue;
            }
            o
        };
        let s = &mut slots[o as usize];
        s.tag = (s.tag & !STATE) | DONE;
        finalised += 1;
        if finalised % 4096 == 0 {
            ctx.check_stop()?;
        }
        for &f in ctx.needed_by(o) {
            let l = &mut left[f as usize];
            *l -= 1;
            if *l == 0 {
                fire(f, &mut slots, &mut queue);
            }
        }
    }
    // In place (the same size and alignment): an object not finalised has no cost.
    let slots: Vec<Slot> = slots
        .into_iter()
        .map(|s| {
            if s.state() == DONE {
                Slot {
                    cost: s.cost,
                    choice: s.choice,
                    depth: s.depth(),
                }
            } else {
                Slot {
                    cost: f64::INFINITY,
                    choice: NONE,
                    depth: 0,
                }
            }
        })
        .collect();
    Ok(Optimum::from_slots(slots))
}

/// The optimum of `objective` for the context's kitchen (computed on first use). The
/// objectives of the optimal methods are computed together, on the thread pool (one plan of
/// any of them makes the others free): `optimal-success`'s only when every motion has a rate.
pub(super) fn optimum<'c>(ctx: &'c Context<'_>, objective: Objective) -> Result<&'c Optimum> {
    if objective != Objective::Shopping
        && !ctx.has_optimum(objective)
        && !ctx.has_pending(objective)
    {
        let success = || {
            if ctx.all_rated() {
                one_optimum(ctx, Objective::Success).map(|_| ())
            } else {
                Ok(())
            }
        };
        let ((s, u), i) = super::batch::in_pool(|| {
            rayon::join(
                || rayon::join(success, || one_optimum(ctx, Objective::Units)),
                || one_optimum(ctx, Objective::Inputs),
            )
        })?;
        s?;
        u?;
        i?;
    }
    one_optimum(ctx, objective)
}

/// The optimum of `objective` alone (computed on first use).
fn one_optimum<'c>(ctx: &'c Context<'_>, objective: Objective) -> Result<&'c Optimum> {
    ctx.optimum(ctx.foon, objective, &|| ctx.check_stop(), || {
        let kitchen = |o: u32| ctx.in_kitchen(o);
        let zero = |_: u32| 0.0;
        match objective {
            // `0.0 - ln r`: see `plan`. Every FU has a rate here (the caller checked).
            Objective::Success => {
                let rates = ctx.fu_rates();
                knuth_all(ctx, &kitchen, 0.0, &|f| 0.0 - rates[f as usize].ln())
            }
            Objective::Units => knuth_all(ctx, &kitchen, 0.0, &|_| 1.0),
            Objective::Inputs => knuth_all(ctx, &kitchen, 1.0, &zero),
            Objective::Shopping => knuth_all(
                ctx,
                &|o| ctx.in_kitchen(o) || ctx.foon.producers(o).is_empty(),
                1.0,
                &zero,
            ),
        }
    })
}

/// Final cost and choice of every object needed for `goal`: read from the kitchen's optimum
/// (or as much of its pending update as the goal needs), or searched from the goal.
enum Costs<'c> {
    At(OptimumAt<'c>),
    Own(Knuth),
}

impl Costs<'_> {
    fn cost(&self, o: u32) -> f64 {
        match self {
            Self::At(k) => k.cost(o),
            Self::Own(k) => k.cost.get(o),
        }
    }

    fn choice(&self, o: u32) -> u32 {
        match self {
            Self::At(k) => k.choice(o),
            Self::Own(k) => k.choice.get(o),
        }
    }
}

/// The optimum of `objective` as far as `goal` needs it (see [`Prepared::optimum_at`]),
/// computed whole when the kitchen has neither it nor a pending update of it.
///
/// [`Prepared::optimum_at`]: crate::prepare::Prepared::optimum_at
fn optimum_at<'c>(ctx: &'c Context<'_>, objective: Objective, goal: u32) -> Result<OptimumAt<'c>> {
    match ctx.optimum_at(ctx.foon, objective, goal, &|| ctx.check_stop())? {
        Some(k) => Ok(k),
        None => optimum(ctx, objective).map(OptimumAt::Whole),
    }
}

pub(super) fn plan(ctx: &Context<'_>, goal: u32, query: Query) -> Result<Plan> {
    // (Called for the three optimal methods alone.)
    let objective = query.method.objective().unwrap_or(Objective::Inputs);
    // Without a rate for every motion, which FUs are weighed (and so which missing rate is
    // the error) depends on the goal: search from it.
    let shared = !ctx.is_from_scratch() && (objective != Objective::Success || ctx.all_rated());
    let k = if shared {
        Costs::At(optimum_at(ctx, objective, goal)?)
    } else {
        let (leaf, weight): (f64, Box<dyn Fn(u32) -> Result<f64>>) = match query.method {
            // `0.0 - ln r`, not `-ln r`: a rate of 1 must weigh +0, as the leaves do. A -0
            // would sort before every +0 in the heap's total order and finalise such objects
            // out of (cost, id) order.
            Method::OptimalSuccess => (0.0, Box::new(|f| ctx.rate(f).map(|r| 0.0 - r.ln()))),
            Method::OptimalUnits => (0.0, Box::new(|_| Ok(1.0))),
            _ => (1.0, Box::new(|_| Ok(0.0))),
        };
        Costs::Own(knuth(ctx, goal, &|o| ctx.in_kitchen(o), leaf, &weight)?)
    };
    let c = k.cost(goal);
    if !c.is_finite() {
        // Derivable, but every way to make it uses a motion of rate 0: nothing is missing and
        // no cycle blocks it, so the explanation is empty (the rates are the reason).
        let mut p = Plan::empty(goal, query);
        p.solved = false;
        p.explanation = Some(Explanation::default());
        return Ok(p);
    }
    let e = tree::emit_counted(ctx, goal, |o| k.choice(o));
    let (expanded, peak) = match &k {
        Costs::At(_) => (e.visited, e.peak),
        Costs::Own(k) => (k.expanded, k.peak),
    };
    let cost = if query.method == Method::OptimalSuccess {
        (-c).exp()
    } else {
        c
    };
    Ok(Plan {
        units: e.units,
        cost: Some(cost),
        expanded,
        peak_frontier: peak,
        ..Plan::empty(goal, query)
    })
}

/// Why `goal` cannot be made: the raw items that are missing, or the blocking cycle.
/// K' is the kitchen plus every object without a producer (a raw item).
pub(super) fn explain(ctx: &Context<'_>, goal: u32) -> Result<Explanation> {
    let foon = ctx.foon;
    let raw = |o: u32| foon.producers(o).is_empty();
    let k = if ctx.is_from_scratch() {
        Costs::Own(knuth(
            ctx,
            goal,
            &|o| ctx.in_kitchen(o) || raw(o),
            1.0,
            &|_| Ok(0.0),
        )?)
    } else {
        // A goal K' cannot make needs the whole column (the cycle is found from costs that
        // are not its tree's): the part read for it is let go first.
        let mut at = Some(optimum_at(ctx, Objective::Shopping, goal)?);
        if at.as_ref().is_some_and(|k| !k.cost(goal).is_finite()) {
            at = None;
        }
        match at {
            Some(k) => Costs::At(k),
            None => Costs::At(OptimumAt::Whole(optimum(ctx, Objective::Shopping)?)),
        }
    };
    if k.cost(goal).is_finite() {
        let units = tree::emit(ctx, goal, |o| k.choice(o));
        let mut missing: Vec<u32> = units
            .iter()
            .flat_map(|&f| ctx.needed(f).iter().copied())
            .filter(|&x| !ctx.in_kitchen(x) && raw(x))
            .collect();
        if units.is_empty() && !ctx.in_kitchen(goal) {
            missing.push(goal);
        }
        missing.sort_unstable();
        missing.dedup();
        return Ok(Explanation {
            missing,
            ..Explanation::default()
        });
    }
    // Blocked by cycles only. The goal was never reached, so Knuth ran to the end: an object
    // of the goal's ancestry is derivable from K' exactly when its cost is finite. Follow
    // first producers through inputs that are not.
    let derivable = |x: u32| k.cost(x).is_finite();
    let mut cycle = vec![goal];
    let mut cycle_units = Vec::new();
    let mut pos = ctx.id_map(foon.object_count(), NONE);
    pos.set(goal, 0);
    let mut o = goal;
    loop {
        let step = foon.producers(o).iter().find_map(|&f| {
            ctx.needed(f)
                .iter()
                .find(|&&x| !derivable(x))
                .map(|&x| (f, x))
        });
        let Some((f, x)) = step else { break };
        cycle_units.push(f);
        let at = pos.get(x);
        if at != NONE {
            let start = at as usize;
            cycle.drain(..start);
            cycle_units.drain(..start);
            cycle.push(x);
            break;
        }
        pos.set(x, cycle.len() as u32);
        cycle.push(x);
        o = x;
    }
    Ok(Explanation {
        missing: Vec::new(),
        cycle,
        cycle_units,
    })
}
