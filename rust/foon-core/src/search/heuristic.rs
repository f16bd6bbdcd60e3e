//! The heuristic order of candidate FUs (`docs/METHODS.md`, Terms), written once for every
//! method that uses one: the course loop takes the first best producer in file order
//! ([`best`]), the sound greedy search tries the producers best first ([`order`]); both compare
//! the same [`key`], and ties always go to the lower FU index.

use rayon::prelude::*;

use super::batch::in_pool;
use super::{Context, Count, Method, Query};
use crate::error::Result;
use crate::index::{Csr, NONE};
use crate::prepare::Greedy;

/// The heuristic key of `fu` for `query`: smaller is better. `greedy-success`: a higher motion
/// rate (the error naming the motion when it has none); `greedy-inputs`: fewer input nodes or
/// distinct ingredient labels (all inputs, before the container rule); any other method has
/// no heuristic (every key is 0, so the FU index decides).
pub(super) fn key(ctx: &Context<'_>, fu: u32, query: Query) -> Result<u64> {
    Ok(match query.method {
        Method::GreedySuccess => {
            // `+ 0.0` makes a rate of -0 equal to 0 (the bit pattern of -0 would rank it
            // below 0); rates are never NaN here.
            let r = ctx.rate(fu)? + 0.0;
            !ordered_bits(r)
        }
        Method::GreedyInputs => input_count(ctx, fu, query.count) as u64,
        _ => 0,
    })
}

/// The bits of a float, ordered as the float (IEEE total order): a higher float, a higher key.
fn ordered_bits(x: f64) -> u64 {
    let b = x.to_bits();
    if b >> 63 == 1 { !b } else { b | (1 << 63) }
}

/// `greedy-inputs`: the inputs of `fu` as `count` counts them.
fn input_count(ctx: &Context<'_>, fu: u32, count: Count) -> usize {
    let foon = ctx.foon;
    let ins = foon.inputs(fu);
    match count {
        Count::Nodes => ins.len(),
        Count::Ingredients => {
            let mut labels: Vec<u32> = Vec::new();
            for &o in ins {
                let ing = foon.ingredients(o);
                if ing.is_empty() {
                    labels.push(foon.label(o));
                } else {
                    labels.extend_from_slice(ing);
                }
            }
            labels.sort_unstable();
            labels.dedup();
            labels.len()
        }
    }
}

/// The first best of `cands` (in their order) for `query`: the course's choice among the
/// producers of an object. Every candidate's key is computed (a missing rate is an error even
/// when another candidate would win). `cands` is not empty.
pub(super) fn best(ctx: &Context<'_>, cands: &[u32], query: Query) -> Result<u32> {
    if !matches!(query.method, Method::GreedySuccess | Method::GreedyInputs) {
        // Every key is 0 and can fail for no candidate: the first one wins.
        return Ok(cands[0]);
    }
    let mut best = cands[0];
    let mut best_key = key(ctx, best, query)?;
    for &f in &cands[1..] {
        let k = key(ctx, f, query)?;
        if k < best_key {
            best = f;
            best_key = k;
        }
    }
    Ok(best)
}

/// Sorts `cands` best first for `query`, ties by FU index.
pub(super) fn order(ctx: &Context<'_>, cands: &mut [u32], query: Query) -> Result<()> {
    if !matches!(query.method, Method::GreedySuccess | Method::GreedyInputs) {
        cands.sort_unstable();
        return Ok(());
    }
    let mut keyed = cands
        .iter()
        .map(|&f| Ok((key(ctx, f, query)?, f)))
        .collect::<Result<Vec<_>>>()?;
    keyed.sort_unstable();
    for (slot, (_, f)) in cands.iter_mut().zip(keyed) {
        *slot = f;
    }
    Ok(())
}

/// The producer order and course choice of every object for `query`'s heuristic, computed
/// once per kitchen; `None` for a method without a heuristic, for plans from scratch, and for
/// `greedy-success` when some motion has no rate (which rate is missing, and so the error,
/// depends on the objects expanded: those plans compute their keys as they go).
pub(super) fn shared<'c>(ctx: &'c Context<'_>, query: Query) -> Result<Option<&'c Greedy>> {
    let which = match (query.method, query.count) {
        (Method::GreedySuccess, _) if ctx.all_rated() => 0,
        (Method::GreedyInputs, Count::Nodes) => 1,
        (Method::GreedyInputs, Count::Ingredients) => 2,
        _ => return Ok(None),
    };
    if ctx.is_from_scratch() {
        return Ok(None);
    }
    ctx.greedy(which, || greedy(ctx, query)).map(Some)
}

/// Every FU's key once, then each object's producers sorted by (key, FU) and its first best
/// producer in file order: the same as [`order`] and [`best`] on its producers.
fn greedy(ctx: &Context<'_>, query: Query) -> Result<Greedy> {
    let foon = ctx.foon;
    let keys = in_pool(|| {
        (0..foon.fu_count() as u32)
            .into_par_iter()
            .map(|f| key(ctx, f, query))
            .collect::<Result<Vec<u64>>>()
    })??;
    ctx.check_stop()?;
    let n = foon.object_count();
    let mut order = Csr::with_capacity(n, 0);
    let mut row: Vec<u32> = Vec::new();
    let mut first = vec![NONE; n];
    let mut keyed: Vec<(u64, u32)> = Vec::new();
    for (o, slot) in (0..).zip(first.iter_mut()) {
        if o % 65_536 == 0 {
            ctx.check_stop()?;
        }
        let prods = foon.producers(o);
        match prods {
            [] => order.push_row(prods),
            [f] => {
                *slot = *f;
                order.push_row(prods);
            }
            _ => {
                keyed.clear();
                keyed.extend(prods.iter().map(|&f| (keys[f as usize], f)));
                let mut best = keyed[0];
                for &k in &keyed[1..] {
                    if k.0 < best.0 {
                        best = k;
                    }
                }
                *slot = best.1;
                keyed.sort_unstable();
                row.clear();
                row.extend(keyed.iter().map(|&(_, f)| f));
                order.push_row(&row);
            }
        }
    }
    Ok(Greedy { order, first })
}

#[cfg(test)]
mod tests {
    use super::ordered_bits;

    #[test]
    fn ordered_bits_follow_the_floats() {
        let xs = [
            f64::NEG_INFINITY,
            -1.0,
            -1e-300,
            0.0,
            1e-300,
            0.25,
            0.5,
            1.0,
            2.0,
        ];
        for w in xs.windows(2) {
            assert!(ordered_bits(w[0]) < ordered_bits(w[1]), "{w:?}");
        }
        assert_eq!(ordered_bits(-0.0 + 0.0), ordered_bits(0.0));
    }
}
