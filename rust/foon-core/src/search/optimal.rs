//! Optimal trees (Knuth's generalisation of Dijkstra over the AND-OR graph, tree cost) and
//! the explanation of failed searches.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::forward;
use super::{Context, Explanation, Method, Plan, Query, tree};
use crate::error::Result;
use crate::index::NONE;

#[derive(PartialEq)]
struct Entry {
    cost: f64,
    obj: u32,
}

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        // Min-heap on (cost, object id).
        other
            .cost
            .total_cmp(&self.cost)
            .then(other.obj.cmp(&self.obj))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Result of Knuth's algorithm: final cost and choice of every object reached.
pub(super) struct Knuth {
    pub(super) cost: Vec<f64>,
    pub(super) choice: Vec<u32>,
    pub(super) expanded: u64,
    pub(super) peak: usize,
}

/// Knuth's algorithm from the kitchen (plus `extra`), with FU weight `weight` and leaf cost
/// `leaf`. An object's choice is the lowest-index producer that set its final cost with all
/// its needed inputs already final.
pub(super) fn knuth(
    ctx: &Context<'_>,
    extra: Option<&[bool]>,
    leaf: f64,
    weight: &dyn Fn(u32) -> Result<f64>,
    stop_at: Option<u32>,
) -> Result<Knuth> {
    let foon = ctx.foon;
    let n = foon.object_count();
    let n_fu = foon.fu_count();
    let mut cost = vec![f64::INFINITY; n];
    let mut choice = vec![NONE; n];
    let mut done = vec![false; n];
    let mut left: Vec<u32> = (0..n_fu as u32)
        .map(|f| ctx.needed(f).len() as u32)
        .collect();
    let mut heap = BinaryHeap::new();
    let mut expanded = 0u64;
    let mut peak = 0usize;
    // Leaves (the kitchen, plus `extra`) have a fixed cost: no unit may lower it.
    let leaf_of: Vec<bool> = (0..n as u32)
        .map(|o| ctx.in_kitchen(o) || extra.is_some_and(|e| e[o as usize]))
        .collect();
    for o in 0..n as u32 {
        if leaf_of[o as usize] {
            cost[o as usize] = leaf;
            heap.push(Entry { cost: leaf, obj: o });
        }
    }
    let fire = |f: u32,
                cost: &mut Vec<f64>,
                choice: &mut Vec<u32>,
                done: &[bool],
                heap: &mut BinaryHeap<Entry>|
     -> Result<()> {
        let mut c = weight(f)?;
        for &x in ctx.needed(f) {
            c += cost[x as usize];
        }
        for &y in foon.outputs(f) {
            let yi = y as usize;
            if done[yi] || leaf_of[yi] || foon.is_bare(y) {
                continue;
            }
            // Equal costs are compared exactly on purpose: the tie goes to the lower index.
            #[allow(clippy::float_cmp)]
            let better = c < cost[yi] || (c == cost[yi] && f < choice[yi]);
            if better {
                if c < cost[yi] {
                    heap.push(Entry { cost: c, obj: y });
                }
                cost[yi] = c;
                choice[yi] = f;
            }
        }
        Ok(())
    };
    for f in 0..n_fu as u32 {
        if left[f as usize] == 0 {
            fire(f, &mut cost, &mut choice, &done, &mut heap)?;
        }
    }
    while let Some(Entry { cost: c, obj: o }) = heap.pop() {
        if done[o as usize] || c > cost[o as usize] {
            continue;
        }
        done[o as usize] = true;
        expanded += 1;
        if expanded % 4096 == 0 {
            ctx.check_stop()?;
        }
        if stop_at == Some(o) {
            break;
        }
        for &f in ctx.needed_by.row(o) {
            let l = &mut left[f as usize];
            *l -= 1;
            if *l == 0 {
                fire(f, &mut cost, &mut choice, &done, &mut heap)?;
            }
        }
        peak = peak.max(heap.len());
    }
    for o in 0..n {
        if !done[o] {
            cost[o] = f64::INFINITY;
            choice[o] = NONE;
        }
    }
    Ok(Knuth {
        cost,
        choice,
        expanded,
        peak,
    })
}

pub(super) fn plan(ctx: &Context<'_>, goal: u32, query: Query) -> Result<Plan> {
    let (leaf, weight): (f64, Box<dyn Fn(u32) -> Result<f64>>) = match query.method {
        // `0.0 - ln r`, not `-ln r`: a rate of 1 must weigh +0, as the leaves do. A -0 would
        // sort before every +0 in the heap's total order and finalise such objects out of
        // (cost, id) order.
        Method::OptimalSuccess => (0.0, Box::new(|f| ctx.rate(f).map(|r| 0.0 - r.ln()))),
        Method::OptimalUnits => (0.0, Box::new(|_| Ok(1.0))),
        _ => (1.0, Box::new(|_| Ok(0.0))),
    };
    let k = knuth(ctx, None, leaf, &weight, Some(goal))?;
    let c = k.cost[goal as usize];
    if !c.is_finite() {
        // Derivable, but every way to make it uses a motion of rate 0: nothing is missing and
        // no cycle blocks it, so the explanation is empty (the rates are the reason).
        let mut p = ctx.empty_plan(goal, query);
        p.solved = false;
        p.explanation = Some(Explanation::default());
        return Ok(p);
    }
    let units = tree::emit(ctx, goal, &k.choice);
    let cost = if query.method == Method::OptimalSuccess {
        (-c).exp()
    } else {
        c
    };
    Ok(Plan {
        units,
        cost: Some(cost),
        expanded: k.expanded,
        peak_frontier: k.peak,
        ..ctx.empty_plan(goal, query)
    })
}

/// Why `goal` cannot be made: the raw items that are missing, or the blocking cycle.
pub(super) fn explain(ctx: &Context<'_>, goal: u32) -> Result<Explanation> {
    let foon = ctx.foon;
    let n = foon.object_count();
    let raw: Vec<bool> = (0..n as u32)
        .map(|o| foon.producers(o).is_empty())
        .collect();
    let k = knuth(ctx, Some(&raw), 1.0, &|_| Ok(0.0), Some(goal))?;
    if k.cost[goal as usize].is_finite() {
        let units = tree::emit(ctx, goal, &k.choice);
        let mut missing: Vec<u32> = units
            .iter()
            .flat_map(|&f| ctx.needed(f).iter().copied())
            .filter(|&x| !ctx.in_kitchen(x) && raw[x as usize])
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
    // Blocked by cycles only: follow first producers through underivable inputs.
    let r = forward::ranks(ctx, Some(&raw));
    let mut cycle = vec![goal];
    let mut cycle_units = Vec::new();
    let mut pos = vec![NONE; n];
    pos[goal as usize] = 0;
    let mut o = goal;
    loop {
        let step = foon.producers(o).iter().find_map(|&f| {
            ctx.needed(f)
                .iter()
                .find(|&&x| !r.is_derivable(x))
                .map(|&x| (f, x))
        });
        let Some((f, x)) = step else { break };
        cycle_units.push(f);
        if pos[x as usize] != NONE {
            let start = pos[x as usize] as usize;
            cycle.drain(..start);
            cycle_units.drain(..start);
            cycle.push(x);
            break;
        }
        pos[x as usize] = cycle.len() as u32;
        cycle.push(x);
        o = x;
    }
    Ok(Explanation {
        missing: Vec::new(),
        cycle,
        cycle_units,
    })
}
