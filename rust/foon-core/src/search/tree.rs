//! Turning per-object choices into a tree listed in execution order (depth-first
//! post-order from the goal, needed inputs in input order; no call-stack recursion).

use super::Context;
use super::scratch::IdMap;
use crate::index::NONE;

/// The tree of the choices from `goal` (`choice(o)` is the FU chosen for `o`, or `NONE`).
pub(super) fn emit(ctx: &Context<'_>, goal: u32, choice: impl Fn(u32) -> u32) -> Vec<u32> {
    emit_counted(ctx, goal, choice).units
}

/// A tree with what its extraction examined.
pub(super) struct Emitted {
    pub(super) units: Vec<u32>,
    /// Objects outside the kitchen whose choice was read.
    pub(super) visited: u64,
    /// Deepest stack of units in progress.
    pub(super) peak: usize,
}

/// As [`emit`], counting what the extraction examined (the `expanded` and `peak_frontier` of
/// a plan read from choices computed beforehand).
pub(super) fn emit_counted(ctx: &Context<'_>, goal: u32, choice: impl Fn(u32) -> u32) -> Emitted {
    let foon = ctx.foon;
    let mut seen = ctx.id_map(foon.object_count(), false);
    let mut emitted = ctx.id_map(foon.fu_count(), false);
    let mut out = Vec::new();
    let mut visited = 0u64;
    let mut peak = 0usize;
    // (fu, next input position)
    let mut stack: Vec<(u32, usize)> = Vec::new();
    let mut visit =
        |o: u32, stack: &mut Vec<(u32, usize)>, seen: &mut IdMap<bool>, emitted: &IdMap<bool>| {
            if ctx.in_kitchen(o) || seen.replace(o, true) {
                return;
            }
            visited += 1;
            let f = choice(o);
            if f != NONE && !emitted.get(f) {
                stack.push((f, 0));
                peak = peak.max(stack.len());
            }
        };
    visit(goal, &mut stack, &mut seen, &emitted);
    while let Some(&mut (f, ref mut i)) = stack.last_mut() {
        let ins = ctx.needed(f);
        if *i < ins.len() {
            let x = ins[*i];
            *i += 1;
            visit(x, &mut stack, &mut seen, &emitted);
        } else {
            stack.pop();
            if !emitted.replace(f, true) {
                out.push(f);
            }
        }
    }
    Emitted {
        units: out,
        visited,
        peak,
    }
}
