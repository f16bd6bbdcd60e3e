//! Sound greedy best-first (`greedy-success`, `greedy-inputs`): a depth-first resolution
//! from the goal that tries producers in heuristic order and never uses a producer that
//! needs an object on the current path. Choices, once made, are kept. Own stack, no
//! recursion.

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
}

pub(super) fn plan(ctx: &Context<'_>, goal: u32, query: Query) -> Result<Plan> {
    let foon = ctx.foon;
    let ranks = ctx.ranks();
    let n = foon.object_count();
    let mut choice = ctx.id_map(n, NONE);
    let mut on_path = ctx.id_map(n, false);
    let mut buf: Vec<u32> = Vec::new();
    let mut stack: Vec<Frame> = Vec::new();
    let mut expanded = 0u64;
    let mut peak = 1usize;

    let push = |o: u32,
                stack: &mut Vec<Frame>,
                buf: &mut Vec<u32>,
                on_path: &mut IdMap<bool>|
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
        });
        on_path.set(o, true);
        Ok(())
    };
    // The goal is derivable and not in the kitchen (the caller checked).
    push(goal, &mut stack, &mut buf, &mut on_path)?;
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
        loop {
            let (a, b) = top.cands;
            if a + top.cand >= b {
                // No producer works: fail.
                on_path.set(top.obj, false);
                buf.truncate(a);
                stack.pop();
                child = Some(false);
                continue 'frames;
            }
            let f = buf[a + top.cand];
            let ins = ctx.needed(f);
            if !top.checked {
                if ins.iter().any(|&x| on_path.get(x)) {
                    top.cand += 1;
                    continue;
                }
                top.checked = true;
            }
            if top.input == ins.len() {
                let o = top.obj;
                choice.set(o, f);
                on_path.set(o, false);
                buf.truncate(a);
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
            } else {
                push(x, &mut stack, &mut buf, &mut on_path)?;
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
        ..ctx.empty_plan(goal, query)
    })
}
