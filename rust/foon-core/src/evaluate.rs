//! Evaluating a set of FUs against inputs prepared for their FOON: a tree's metrics (height,
//! success, leaf inputs), whether it is valid in some order, and running it in a given order.
//! Used by the searches (the metrics of every plan) and by `verify` (a tree file); the public
//! entry points are the methods of [`Context`](crate::Context) of the same names. Every
//! function takes the FOON and inputs prepared for it.

use rustc_hash::FxHashSet;

use crate::forward;
use crate::index::Foon;
use crate::prepare::Prepared;

/// Metrics of a tree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreeMetrics {
    pub height: Option<u32>,
    /// `None` without a rate table or when a unit's motion has no rate (`unrated`).
    pub success: Option<f64>,
    /// With a rate table: the first unit whose motion has no rate.
    pub unrated: Option<u32>,
    pub leaf_inputs: usize,
}

/// Height, success and leaf count of a set of FUs for `goal`.
pub(crate) fn metrics(foon: &Foon, prep: &Prepared, units: &[u32], goal: u32) -> TreeMetrics {
    let height = if prep.in_kitchen(goal) {
        Some(0)
    } else {
        forward::unit_ranks(foon, prep, units).made(goal)
    };
    let unrated = if prep.rates_given() {
        units
            .iter()
            .copied()
            .find(|&f| prep.fu_rates().get(f as usize).is_none_or(|r| r.is_nan()))
    } else {
        None
    };
    let success = if prep.rates_given() && unrated.is_none() {
        Some(
            units
                .iter()
                .fold(1.0, |acc, &f| acc * prep.fu_rates()[f as usize]),
        )
    } else {
        None
    };
    let mut seen = FxHashSet::default();
    for &f in units {
        for &x in prep.needed(f) {
            if prep.in_kitchen(x) {
                seen.insert(x);
            }
        }
    }
    TreeMetrics {
        height,
        success,
        unrated,
        leaf_inputs: seen.len(),
    }
}

/// Whether the FUs `units` can be ordered so that every one of them runs (its needed
/// inputs in the kitchen or made by an earlier one) and the goal is in the kitchen or made.
pub(crate) fn is_valid(foon: &Foon, prep: &Prepared, units: &[u32], goal: u32) -> bool {
    let r = forward::unit_ranks(foon, prep, units);
    let made = |x: u32| prep.in_kitchen(x) || r.made(x).is_some();
    let all_run = units
        .iter()
        .all(|&f| (f as usize) < foon.fu_count() && prep.needed(f).iter().all(|&x| made(x)));
    all_run && made(goal)
}

/// Checks `units` in the given order: returns the position of the first FU with a needed
/// input that is neither in the kitchen nor made by an earlier FU, with those inputs.
pub(crate) fn first_unavailable(
    foon: &Foon,
    prep: &Prepared,
    units: &[u32],
) -> Option<(usize, Vec<u32>)> {
    run_in_order(foon, prep, units).0
}

/// Runs `units` in the given order from the kitchen: a unit runs when its needed inputs
/// are available, and then makes its (produced) outputs available. Returns the first unit
/// that could not run (position, missing inputs) and what is available at the end.
pub(crate) fn run_in_order(
    foon: &Foon,
    prep: &Prepared,
    units: &[u32],
) -> (Option<(usize, Vec<u32>)>, Vec<bool>) {
    let mut avail = prep.kitchen_flags().to_vec();
    let mut first = None;
    for (i, &f) in units.iter().enumerate() {
        let missing: Vec<u32> = prep
            .needed(f)
            .iter()
            .copied()
            .filter(|&x| !avail[x as usize])
            .collect();
        if !missing.is_empty() {
            first.get_or_insert((i, missing));
            continue;
        }
        for &y in foon.outputs(f) {
            if !foon.is_bare(y) {
                avail[y as usize] = true;
            }
        }
    }
    (first, avail)
}
