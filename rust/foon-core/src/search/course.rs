//! The course loop (`bfs`, and `greedy-*` with course compatibility): breadth-first from the
//! goal, one producer per object, exactly as the course code, except that an object with no
//! producer is reported instead of crashing.

use std::collections::VecDeque;

use super::{Context, Plan, Query, heuristic};
use crate::error::Result;

pub(super) fn plan(ctx: &Context<'_>, goal: u32, query: Query) -> Result<Plan> {
    let foon = ctx.foon;
    let shared = heuristic::shared(ctx, query)?;
    let mut queue = VecDeque::from([goal]);
    let mut in_queue = ctx.id_map(foon.object_count(), false);
    let mut visited = ctx.id_map(foon.object_count(), false);
    let mut in_tree = ctx.id_map(foon.fu_count(), false);
    in_queue.set(goal, true);
    let mut tree = Vec::new();
    let mut unresolved = Vec::new();
    let mut expanded = 0u64;
    let mut peak = 1usize;
    while let Some(o) = queue.pop_front() {
        in_queue.set(o, false);
        if visited.replace(o, true) {
            continue;
        }
        if ctx.in_kitchen(o) {
            continue;
        }
        expanded += 1;
        if expanded % 4096 == 0 {
            ctx.check_stop()?;
        }
        let prods = foon.producers(o);
        if prods.is_empty() {
            unresolved.push(o);
            continue;
        }
        let f = match shared {
            Some(g) => g.first[o as usize],
            None => heuristic::best(ctx, prods, query)?,
        };
        if in_tree.replace(f, true) {
            continue;
        }
        tree.push(f);
        for &x in ctx.needed(f) {
            if !in_queue.replace(x, true) {
                queue.push_back(x);
            }
        }
        peak = peak.max(queue.len());
    }
    tree.reverse();
    Ok(Plan {
        solved: unresolved.is_empty(),
        units: tree,
        unresolved,
        expanded,
        peak_frontier: peak,
        ..Plan::empty(goal, query)
    })
}
