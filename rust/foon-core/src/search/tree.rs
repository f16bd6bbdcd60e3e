//! Turning per-object choices into a tree listed in execution order (depth-first
//! post-order from the goal, needed inputs in input order; no call-stack recursion).

use super::Context;
use crate::index::NONE;

pub(super) fn emit(ctx: &Context<'_>, goal: u32, choice: &[u32]) -> Vec<u32> {
    let foon = ctx.foon;
    let mut seen = vec![false; foon.object_count()];
    let mut emitted = vec![false; foon.fu_count()];
    let mut out = Vec::new();
    // (fu, next input position)
    let mut stack: Vec<(u32, usize)> = Vec::new();
    let visit = |o: u32, stack: &mut Vec<(u32, usize)>, seen: &mut Vec<bool>, emitted: &[bool]| {
        if ctx.in_kitchen(o) || std::mem::replace(&mut seen[o as usize], true) {
            return;
        }
        let f = choice[o as usize];
        if f != NONE && !emitted[f as usize] {
            stack.push((f, 0));
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
            if !emitted[f as usize] {
                emitted[f as usize] = true;
                out.push(f);
            }
        }
    }
    out
}
