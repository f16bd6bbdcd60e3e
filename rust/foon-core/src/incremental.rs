//! Incremental kitchens: a kitchen given as a base kitchen's preparation plus a delta (items
//! added, items removed) is prepared from the base's, touching only what the delta changes,
//! with every result equal to a preparation from scratch ([`Prepared::with_delta`]).
//!
//! What the base kitchen has computed is moved to the new kitchen by the pass of `relax.rs`
//! (Ramalingam and Reps's algorithm: the objects whose value the change may raise are reset,
//! then Knuth's algorithm runs from them and from the new leaves, lowering what it reaches):
//!
//! - the ranks and the choices of `ids` at once, since nearly every query reads them;
//! - each optimal objective's costs and choices on use, and only as far as the use needs: a
//!   plan runs its objective's pass until its goal is final ([`Pending`]; the objects of its
//!   tree are final then too), a later plan runs it further, and work that reads whole columns
//!   (or many goals at once) runs it to the end. Adding an object that much of the FOON is
//!   made from lowers the cost of all of it, so a pass to the end can cost a large share of a
//!   preparation from scratch; a plan pays only for the objects cheaper than its goal.
//!
//! The derived kitchen keeps its values as [`Layered`] columns over the base's, so it costs
//! what the delta reaches in memory too.

use std::sync::Arc;

use rustc_hash::{FxHashMap, FxHashSet};

use crate::error::{Error, Result};
use crate::forward::Ranks;
use crate::hint::Ahead;
use crate::index::{Foon, NONE};
use crate::kitchen::Kitchen;
use crate::layered::Layered;
use crate::model::ObjectSpec;
use crate::prepare::{Objective, Optimum, Prepared, Slot};
use crate::relax::{Combine, Reached, Relax, Rules};
use crate::search::ids::unit_rank;

/// A pass that reaches more than one object in `REACH_SHARE` (and more than `REACH_MIN`)
/// stops: the part is then computed from scratch, which costs less than an update of that
/// size (a delta that removes an item much of the FOON is made from).
const REACH_SHARE: usize = 4;
const REACH_MIN: usize = 1024;

/// The most objects a pass over `foon` may reach (see [`REACH_SHARE`]).
fn reach_limit(foon: &Foon) -> usize {
    REACH_MIN.max(foon.object_count() / REACH_SHARE)
}

/// An optimal objective's rules, over its optimum before the change.
struct OptimumRules<'a> {
    objective: Objective,
    before: &'a Layered<Slot>,
    /// The kitchen before the change, and the new kitchen's preparation.
    was: &'a Layered<bool>,
    prep: &'a Prepared,
    foon: &'a Foon,
}

impl OptimumRules<'_> {
    /// Whether `o` is a raw item, a leaf of the shopping costs.
    #[inline]
    fn raw_leaf(&self, o: u32) -> bool {
        self.objective == Objective::Shopping && self.foon.producers(o).is_empty()
    }
}

impl Rules for OptimumRules<'_> {
    const COMBINE: Combine = Combine::Sum;
    const CHOICES: bool = true;

    #[inline]
    fn before(&self, o: u32) -> Slot {
        self.before.get(o)
    }
    #[inline]
    fn prefetch(&self, o: u32) {
        self.before.prefetch(o);
    }
    #[inline]
    fn prefetch_leaf(&self, o: u32) {
        self.prep.kitchen_flags().prefetch(o);
    }
    #[inline]
    fn old_choice(&self, o: u32) -> u32 {
        self.before.get(o).choice
    }
    #[inline]
    fn was_leaf(&self, o: u32) -> bool {
        self.was.get(o) || self.raw_leaf(o)
    }
    #[inline]
    fn is_leaf(&self, o: u32) -> bool {
        self.prep.in_kitchen(o) || self.raw_leaf(o)
    }
    #[inline]
    fn leaf(&self) -> (f64, u32) {
        match self.objective {
            Objective::Success | Objective::Units => (0.0, 0),
            Objective::Inputs | Objective::Shopping => (1.0, 0),
        }
    }
    #[inline]
    fn weight(&self, f: u32) -> f64 {
        match self.objective {
            // `0.0 - ln r`, as from scratch (`search::optimal`): a rate of 1 weighs +0.
            Objective::Success => 0.0 - self.prep.fu_rates()[f as usize].ln(),
            Objective::Units => 1.0,
            Objective::Inputs | Objective::Shopping => 0.0,
        }
    }
}

/// Ranks' rules, over the ranks before the change (kitchen objects rank 0).
struct RankRules<'a> {
    rank: &'a Ranks,
    /// The choice of `ids` before the change, when computed.
    ids: Option<&'a Layered<u32>>,
    old: &'a Prepared,
    prep: &'a Prepared,
    foon: &'a Foon,
}

impl Rules for RankRules<'_> {
    const COMBINE: Combine = Combine::Rank;
    const CHOICES: bool = false;
    const UNIT_VALUES: bool = true;

    #[inline]
    fn before(&self, o: u32) -> Slot {
        let r = self.rank.raw(o);
        Slot {
            cost: if r == NONE {
                f64::INFINITY
            } else {
                f64::from(r)
            },
            choice: NONE,
            depth: 0,
        }
    }
    #[inline]
    fn prefetch(&self, o: u32) {
        self.rank.layered().prefetch(o);
    }
    #[inline]
    fn prefetch_leaf(&self, o: u32) {
        self.prep.kitchen_flags().prefetch(o);
    }
    /// The first producer that achieves an object's rank: the choice of `ids`.
    fn old_choice(&self, y: u32) -> u32 {
        if let Some(c) = self.ids {
            return c.get(y);
        }
        let ry = self.rank.raw(y);
        if ry == NONE || self.old.in_kitchen(y) {
            return NONE;
        }
        ids_choice_with(self.foon, self.old, |x| self.rank.raw(x), y, ry)
    }
    #[inline]
    fn was_leaf(&self, o: u32) -> bool {
        self.old.in_kitchen(o)
    }
    #[inline]
    fn is_leaf(&self, o: u32) -> bool {
        self.prep.in_kitchen(o)
    }
    fn leaf(&self) -> (f64, u32) {
        (0.0, 0)
    }
    fn weight(&self, _: u32) -> f64 {
        0.0
    }
}

/// The first producer of `o` (of rank `r`) whose needed inputs' largest rank (by `rank`,
/// `NONE` when not derivable) is `r - 1`: the choice of `ids` (`NONE` when none).
fn ids_choice_with(foon: &Foon, prep: &Prepared, rank: impl Fn(u32) -> u32, o: u32, r: u32) -> u32 {
    foon.producers(o)
        .iter()
        .copied()
        .find(|&f| unit_rank(prep.needed(f), &rank) == r)
        .unwrap_or(NONE)
}

/// The choice of `ids` after a change (`before`, the choice before it), for the ranks `rank`
/// of the kitchen of `prep`, `touched` holding every object whose rank or kitchen flag may
/// have changed. An object's choice is the first producer whose value (one more than the
/// largest rank of its needed inputs) is its rank; it can change only when its rank changes
/// (computed again) or when the value of one of its producers changes, that is a unit
/// needing a touched object: the choice is computed again when that unit was the choice and
/// no longer achieves the rank, and becomes that unit when it achieves the rank and comes
/// first. `known` holds the values of units the pass of the ranks computed (as
/// [`Relax::unit_values`]); the others are computed here.
fn delta_ids_choice(
    foon: &Foon,
    prep: &Prepared,
    rank: &Layered<u32>,
    before: &Layered<u32>,
    touched: &[u32],
    known: &FxHashMap<u32, f64>,
) -> Layered<u32> {
    let rank_of = |x: u32| if prep.in_kitchen(x) { 0 } else { rank.get(x) };
    // What a unit's value (when not known) and its outputs' choices read, brought in ahead
    // (a hint).
    let bring = |f: u32, needed: &[u32], outputs: &[u32]| {
        let needed = if known.contains_key(&f) { &[] } else { needed };
        for &x in needed.iter().chain(outputs) {
            rank.prefetch(x);
            prep.kitchen_flags().prefetch(x);
        }
        for &y in outputs {
            before.prefetch(y);
        }
    };
    let again: FxHashSet<u32> = touched.iter().copied().collect();
    // The units needing a touched object, each once, in unit order (rows read in memory
    // order, each unit's row and the values it reads brought in a few units ahead).
    let mut units: Vec<u32> = touched
        .iter()
        .flat_map(|&x| prep.needed_by(x))
        .copied()
        .collect();
    units.sort_unstable();
    units.dedup();
    let mut recompute: Vec<u32> = touched.to_vec();
    let mut first: Vec<(u32, u32)> = Vec::new();
    // Outputs that are bare have no rank, so no choice: a unit's row holds the others.
    prep.flows()
        .each_flow_ahead(&units, |at, f, needed, outputs| match at {
            Ahead::Far => bring(f, needed, outputs),
            Ahead::Now => {
                let v = match known.get(&f) {
                    Some(&c) if c.is_finite() => c as u32,
                    Some(_) => NONE,
                    None => unit_rank(needed, rank_of),
                };
                for &y in outputs {
                    if again.contains(&y) {
                        continue;
                    }
                    let r = rank.get(y);
                    if r == NONE || prep.in_kitchen(y) {
                        continue;
                    }
                    let c = before.get(y);
                    if c == f && v != r {
                        recompute.push(y);
                    } else if v == r && f < c {
                        first.push((y, f));
                    }
                }
            }
        });
    let mut choice = before.edit();
    for &(y, f) in &first {
        if f < choice.get(y) {
            choice.set(y, f);
        }
    }
    // Last: a choice computed again wins over a unit found above. The producers of the
    // objects computed again are read as one pipeline, in order, each object's first
    // producer that achieves its rank kept (kitchen objects and objects without a rank have
    // no choice).
    let mut producers: Vec<u32> = Vec::new();
    // Per producer read: the object it may be the choice of, and that object's rank.
    let mut owner: Vec<(u32, u32)> = Vec::new();
    for y in recompute {
        choice.set(y, NONE);
        let r = rank.get(y);
        if r == NONE || prep.in_kitchen(y) {
            continue;
        }
        for &f in foon.producers(y) {
            producers.push(f);
            owner.push((y, r));
        }
    }
    let mut at = 0;
    prep.flows()
        .each_flow_ahead(&producers, |step, f, needed, _| match step {
            Ahead::Far => {
                for &x in needed {
                    rank.prefetch(x);
                    prep.kitchen_flags().prefetch(x);
                }
            }
            Ahead::Now => {
                let (y, r) = owner[at];
                at += 1;
                if choice.get(y) == NONE && unit_rank(needed, rank_of) == r {
                    choice.set(y, f);
                }
            }
        });
    choice.finish()
}

/// The update of one optimal objective's costs and choices from a kitchen that computed them
/// to a kitchen derived from it (by one delta or a chain of them), kept by the derived kitchen
/// and run as far as its uses need ([`Prepared::optimum_at`]).
pub(crate) struct Pending {
    objective: Objective,
    /// The optimum of the kitchen it is updated from, and that kitchen's flags.
    before: Layered<Slot>,
    was: Layered<bool>,
    /// The objects whose kitchen flag may differ between the two kitchens.
    flipped: Vec<u32>,
    limit: usize,
    /// The pass, once started.
    relax: Option<Relax>,
}

impl Pending {
    fn rules<'a>(
        objective: Objective,
        before: &'a Layered<Slot>,
        was: &'a Layered<bool>,
        foon: &'a Foon,
        prep: &'a Prepared,
    ) -> OptimumRules<'a> {
        OptimumRules {
            objective,
            before,
            was,
            prep,
            foon,
        }
    }

    /// The update of `objective` from `from` (the kitchen a delta at `flipped` is applied
    /// to): from its optimum when computed, else from where its own pending update starts
    /// (the flipped objects of both deltas). `None` when `from` has neither.
    pub(crate) fn derive(
        from: &Prepared,
        foon: &Foon,
        objective: Objective,
        flipped: &[u32],
    ) -> Option<Self> {
        let limit = reach_limit(foon);
        if let Some(o) = from.computed_optimum(objective) {
            return Some(Self {
                objective,
                before: o.slots.clone(),
                was: from.kitchen_flags().clone(),
                flipped: flipped.to_vec(),
                limit,
                relax: None,
            });
        }
        from.with_pending(objective, |p| {
            let p = p?;
            let mut all: Vec<u32> = p.flipped.iter().chain(flipped).copied().collect();
            all.sort_unstable();
            all.dedup();
            Some(Self {
                objective,
                before: p.before.clone(),
                was: p.was.clone(),
                flipped: all,
                limit: p.limit.min(limit),
                relax: None,
            })
        })
    }

    /// Runs the pass (started on first call) until `goal` is final, or to the end.
    pub(crate) fn advance(
        &mut self,
        foon: &Foon,
        prep: &Prepared,
        goal: Option<u32>,
        stop: &dyn Fn() -> Result<()>,
    ) -> Result<Reached> {
        let rules = Self::rules(self.objective, &self.before, &self.was, foon, prep);
        let relax = match &mut self.relax {
            Some(r) => r,
            slot @ None => match Relax::start(foon, prep, &rules, &self.flipped, self.limit) {
                Some(r) => slot.insert(r),
                None => return Ok(Reached::TooFar),
            },
        };
        relax.advance(prep, &rules, goal, self.limit, stop)
    }

    /// The current value of `o` (final once the pass settled it).
    pub(crate) fn slot(&self, o: u32) -> Slot {
        self.relax
            .as_ref()
            .and_then(|r| r.changed(o))
            .unwrap_or_else(|| self.before.get(o))
    }

    /// The optimum, once the pass has run to the end.
    pub(crate) fn finish(self) -> Optimum {
        let slots = match self.relax {
            Some(r) => {
                let count = r.changed_count();
                self.before.changed(r.changes(), count)
            }
            None => self.before,
        };
        Optimum { slots }
    }

    /// Whether the pass has started.
    #[cfg(test)]
    pub(crate) fn started(&self) -> bool {
        self.relax.is_some()
    }

    pub(crate) fn heap_bytes(&self) -> usize {
        4 * self.flipped.capacity() + self.relax.as_ref().map_or(0, Relax::heap_bytes)
    }
}

impl Prepared {
    /// The kitchen of these inputs (`self`, the base kitchen's preparation) without the
    /// objects `removed` and with the objects `added` (object ids of `foon`, any order,
    /// repeats allowed; an id in both lists is added), prepared incrementally: equal in every
    /// result to [`Prepared::with_base`] on the same base with the new kitchen. What the base
    /// kitchen has computed (ranks, the choice of `ids`, each optimal objective's costs and
    /// choices) is updated from it, touching only the objects the change reaches (the
    /// optimal objectives on use, as far as the use needs: see the module documentation);
    /// what it has not computed is computed on first use, as for a kitchen prepared from
    /// scratch. The level is the base kitchen's.
    pub fn with_delta(&self, foon: &Foon, added: &[u32], removed: &[u32]) -> Result<Prepared> {
        self.with_delta_reaching(foon, added, removed, reach_limit(foon))
    }

    /// [`Prepared::with_delta`], a pass of the ranks that reaches more than `limit` objects
    /// leaving them to be computed from scratch on first use.
    fn with_delta_reaching(
        &self,
        foon: &Foon,
        added: &[u32],
        removed: &[u32],
        limit: usize,
    ) -> Result<Prepared> {
        self.check_foon(foon)?;
        let n = foon.object_count();
        for &o in added.iter().chain(removed) {
            if o as usize >= n {
                return Err(Error::Invalid(format!(
                    "kitchen object id {o} is not an object of this FOON ({n} objects)"
                )));
            }
        }
        let old = self.kitchen_flags();
        let mut in_kitchen = old.edit();
        for &o in removed {
            in_kitchen.set(o, false);
        }
        for &o in added {
            in_kitchen.set(o, true);
        }
        let mut flipped: Vec<u32> = added
            .iter()
            .chain(removed)
            .copied()
            .filter(|&o| old.get(o) != in_kitchen.get(o))
            .collect();
        flipped.sort_unstable();
        flipped.dedup();
        // The kitchen objects, in id order: the old ones that stay, merged with the new ones.
        let gone: FxHashSet<u32> = flipped.iter().copied().filter(|&o| old.get(o)).collect();
        let new: Vec<u32> = flipped.iter().copied().filter(|&o| !old.get(o)).collect();
        let mut kitchen_objects = Vec::with_capacity(self.kitchen_objects().len() + new.len());
        let mut it = new.iter().copied().peekable();
        for &o in self.kitchen_objects() {
            if gone.contains(&o) {
                continue;
            }
            while let Some(x) = it.next_if(|&x| x < o) {
                kitchen_objects.push(x);
            }
            kitchen_objects.push(o);
        }
        kitchen_objects.extend(it);
        // The new kitchen's flags and objects, on this base; what is computed is set below.
        let out = self.with_parts(in_kitchen.finish(), kitchen_objects);
        if flipped.is_empty() {
            // Nothing changed: everything computed is the same, and so is every update.
            let optima = Objective::ALL.map(|o| self.computed_optimum(o).cloned());
            out.set_computed(
                self.computed_ranks().cloned(),
                optima,
                self.computed_ids_choice().cloned(),
            );
        } else {
            let (ranks, ids) =
                crate::search::batch::in_pool(|| self.delta_ranks(foon, &out, &flipped, limit))?;
            out.set_computed(ranks, Default::default(), ids);
        }
        for objective in Objective::ALL {
            if !out.has_optimum(objective)
                && let Some(p) = Pending::derive(self, foon, objective, &flipped)
            {
                out.set_pending(objective, p);
            }
        }
        Ok(out)
    }

    /// The ranks and the choice of `ids` of `new_prep` (this kitchen changed at `flipped`),
    /// updated from this kitchen's, for those computed here.
    fn delta_ranks(
        &self,
        foon: &Foon,
        new_prep: &Prepared,
        flipped: &[u32],
        limit: usize,
    ) -> (Option<Ranks>, Option<Layered<u32>>) {
        let Some(r) = self.computed_ranks() else {
            return (None, None);
        };
        let rules = RankRules {
            rank: r,
            ids: self.computed_ids_choice(),
            old: self,
            prep: new_prep,
            foon,
        };
        let never = || Ok(());
        let Some(mut relax) = Relax::start(foon, new_prep, &rules, flipped, limit) else {
            // Too much changes: both are computed on first use, from scratch.
            return (None, None);
        };
        if !matches!(
            relax.advance(new_prep, &rules, None, limit, &never),
            Ok(Reached::End)
        ) {
            return (None, None);
        }
        let known = relax.unit_values();
        let count = relax.changed_count();
        let changes: Vec<(u32, u32)> = relax
            .changes()
            .map(|(o, s)| {
                (
                    o,
                    if s.cost.is_finite() {
                        s.cost as u32
                    } else {
                        NONE
                    },
                )
            })
            .collect();
        let touched: Vec<u32> = changes.iter().map(|&(o, _)| o).collect();
        let rank = r.layered().changed(changes, count);
        let ids = self
            .computed_ids_choice()
            .map(|c| delta_ids_choice(foon, new_prep, &rank, c, &touched, &known));
        (Some(Ranks::from_layered(rank)), ids)
    }

    /// As [`Prepared::with_delta`], with the new kitchen given whole (object ids of `foon`,
    /// any order, repeats allowed): the delta is its difference with this kitchen.
    pub fn with_kitchen(&self, foon: &Foon, kitchen: &[u32]) -> Result<Prepared> {
        let n = foon.object_count();
        let mut ids = kitchen.to_vec();
        ids.sort_unstable();
        ids.dedup();
        if let Some(&o) = ids.last().filter(|&&o| o as usize >= n) {
            return Err(Error::Invalid(format!(
                "kitchen object id {o} is not an object of this FOON ({n} objects)"
            )));
        }
        let added: Vec<u32> = ids
            .iter()
            .copied()
            .filter(|&o| !self.in_kitchen(o))
            .collect();
        let keep: FxHashSet<u32> = ids.iter().copied().collect();
        let removed: Vec<u32> = self
            .kitchen_objects()
            .iter()
            .copied()
            .filter(|o| !keep.contains(o))
            .collect();
        self.with_delta(foon, &added, &removed)
    }

    /// As [`Prepared::with_delta`], the change given as kitchen items: the kitchen of these
    /// inputs without the items of `remove`, then with those of `add` ([`Kitchen::without`],
    /// [`Kitchen::with`]). At level 3 an item is one object, so only `add` and `remove` are
    /// matched; at levels 1 and 2 one item may match several objects and several items one
    /// (an item removed can leave its objects in the kitchen through another item), so the
    /// new kitchen, from `kitchen`, is matched whole.
    pub fn with_kitchen_changes(
        &self,
        foon: &Foon,
        add: &Kitchen,
        remove: &Kitchen,
        kitchen: impl FnOnce() -> Result<Arc<Kitchen>>,
    ) -> Result<Prepared> {
        if self.level() == 3 {
            return self.with_delta(foon, &add.match_in(foon), &remove.match_in(foon));
        }
        let ids = kitchen()?.match_at_level(foon, self.level())?;
        self.with_kitchen(foon, &ids)
    }

    /// As [`Prepared::with_delta`], with kitchen items: those found in `foon` (at level 3;
    /// the others are ignored, as in [`Prepared::new`]).
    pub fn with_items(
        &self,
        foon: &Foon,
        added: &[ObjectSpec],
        removed: &[ObjectSpec],
    ) -> Result<Prepared> {
        let find = |items: &[ObjectSpec]| -> Vec<u32> {
            items.iter().filter_map(|item| item.find_in(foon)).collect()
        };
        self.with_delta(foon, &find(added), &find(removed))
    }
}

#[cfg(test)]
mod tests {
    use std::fmt::Write as _;

    use crate::index::Foon;
    use crate::model::MotionRates;
    use crate::parse::{ParseOptions, parse_foon};
    use crate::prepare::{Objective, Optimum, Prepared};
    use crate::search::{Context, Method, Query};

    /// A small xorshift generator (the tests are seeded, so every failure repeats).
    struct Rng(u64);

    impl Rng {
        fn below(&mut self, n: usize) -> usize {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 % n as u64) as usize
        }
    }

    /// A random FOON over a few objects: shared objects, cycles, self-loops, duplicates,
    /// units with no input, bare outputs.
    fn random_foon(rng: &mut Rng) -> Foon {
        let objects = 3 + rng.below(10);
        let mut text = String::new();
        let obj = |rng: &mut Rng, text: &mut String| {
            let i = rng.below(objects);
            if i == 0 {
                text.push_str("O\tbare\n");
            } else {
                let _ = writeln!(text, "O\to{i}\nS\ts");
            }
        };
        for _ in 0..=rng.below(25) {
            for _ in 0..rng.below(4) {
                obj(rng, &mut text);
            }
            let _ = writeln!(text, "M\tm{}", rng.below(4));
            for _ in 0..=rng.below(2) {
                obj(rng, &mut text);
            }
            text.push_str("//\n");
        }
        parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap()
    }

    /// Computes on `prep` what `parts` asks for (bit 0: ranks, 1: ids, 2: the optimal
    /// objectives, 3: shopping costs).
    fn compute(foon: &Foon, prep: &Prepared, parts: u8) {
        let ctx = Context::with(foon, prep).unwrap();
        if parts & 1 != 0 {
            ctx.ranks();
        }
        let query = |method| Query {
            method,
            ..Query::default()
        };
        for o in 0..foon.object_count() as u32 {
            let derivable = ctx.ranks().is_derivable(o) && !prep.in_kitchen(o);
            if parts & 2 != 0 && derivable {
                ctx.plan(o, query(Method::Ids)).unwrap();
            }
            if parts & 4 != 0 && derivable {
                ctx.plan(o, query(Method::OptimalUnits)).unwrap();
            }
            if parts & 8 != 0 && !ctx.ranks().is_derivable(o) {
                ctx.plan(o, query(Method::OptimalUnits)).unwrap();
            }
        }
    }

    /// Whether `prep` has the optimum of `objective`, computed or pending.
    fn has(prep: &Prepared, objective: Objective) -> bool {
        prep.has_optimum(objective) || prep.has_pending(objective)
    }

    /// Every component computed on `inc` (its pending updates run to the end first) equals
    /// the one computed from scratch on `fresh`, bit for bit, and `inc` has every optimum
    /// `had` says (`None`: passes limited to a few objects may have left theirs, to be
    /// computed from scratch on use), the ranks and choices of `ids` when `base` has them.
    fn assert_same(
        foon: &Foon,
        base: &Prepared,
        inc: &Prepared,
        fresh: &Prepared,
        had: Option<[bool; 4]>,
    ) {
        inc.finish_all_pending(foon, &|| Ok(())).unwrap();
        let parts = |a: bool, b: bool| {
            if had.is_some() {
                assert!(a || !b);
            }
        };
        assert_eq!(inc.kitchen_flags(), fresh.kitchen_flags());
        assert_eq!(inc.kitchen_objects(), fresh.kitchen_objects());
        parts(
            inc.computed_ranks().is_some(),
            base.computed_ranks().is_some(),
        );
        if let Some(r) = inc.computed_ranks() {
            assert_eq!(r, fresh.ranks(foon));
        }
        parts(
            inc.computed_ids_choice().is_some(),
            base.computed_ids_choice().is_some(),
        );
        if let Some(c) = inc.computed_ids_choice() {
            compute(foon, fresh, 2);
            match fresh.computed_ids_choice() {
                Some(want) => assert_eq!(c, want),
                // Nothing to plan: no object has a choice.
                None => assert!(c.iter().all(|f| f == crate::NONE)),
            }
        }
        for (i, objective) in Objective::ALL.into_iter().enumerate() {
            assert!(!inc.has_pending(objective));
            let got = inc.computed_optimum(objective);
            if let Some(had) = had {
                assert!(got.is_some() || !had[i], "{objective:?}");
            }
            let Some(got) = got else { continue };
            let ctx = Context::with(foon, fresh).unwrap();
            crate::search::compute_optimum(&ctx, objective).unwrap();
            let want = fresh.computed_optimum(objective).unwrap();
            let bits = |o: &Optimum| {
                o.slots
                    .iter()
                    .map(|s| (s.cost.to_bits(), s.choice, s.depth))
                    .collect::<Vec<_>>()
            };
            assert_eq!(bits(got), bits(want), "{objective:?}");
        }
    }

    /// The kitchen `kitchen` without `removed`, then with `added`: sorted, each once.
    fn changed_kitchen(kitchen: &[u32], added: &[u32], removed: &[u32]) -> Vec<u32> {
        let mut new: Vec<u32> = kitchen
            .iter()
            .copied()
            .filter(|o| !removed.contains(o))
            .chain(added.iter().copied())
            .collect();
        new.sort_unstable();
        new.dedup();
        new
    }

    const METHODS: [Method; 4] = [
        Method::Ids,
        Method::OptimalUnits,
        Method::OptimalInputs,
        Method::OptimalSuccess,
    ];

    /// Plans of `goals` (each with a method of [`METHODS`], in turn) read from `inc` (through
    /// its pending updates, run goal by goal) equal plans from scratch on `fresh`: the units,
    /// the cost and the explanation of a failure.
    fn plans_agree(foon: &Foon, inc: &Prepared, fresh: &Prepared, goals: &[u32]) {
        let (a, b) = (
            Context::with(foon, inc).unwrap(),
            Context::with(foon, fresh).unwrap(),
        );
        for (i, &o) in goals.iter().enumerate() {
            let q = Query {
                method: METHODS[i % METHODS.len()],
                ..Query::default()
            };
            let (x, y) = (a.plan(o, q).unwrap(), b.plan(o, q).unwrap());
            assert_eq!(
                (x.units, x.solved, x.cost.map(f64::to_bits), x.explanation),
                (y.units, y.solved, y.cost.map(f64::to_bits), y.explanation),
                "goal {o} {:?}",
                q.method
            );
        }
    }

    /// Random FOONs, kitchens and deltas (additions, removals, both, an id in both lists,
    /// repeats): plans read from the incremental preparation while its updates have run only
    /// as far as the goals so far needed equal plans from scratch; a delta of that kitchen
    /// (derived from updates part run) does too; every component, once run to the end, equals
    /// the one from scratch.
    #[test]
    fn deltas_give_the_preparation_from_scratch() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let (mut changed, mut part_run) = (0, 0);
        for round in 0..600 {
            let foon = random_foon(&mut rng);
            let n = foon.object_count();
            let rates = MotionRates::from_pairs(
                (0..4).map(|m| (format!("m{m}"), [0.0, 0.5, 0.9, 1.0, 1.0][rng.below(5)])),
            )
            .unwrap();
            let kitchen: Vec<u32> = (0..n as u32).filter(|_| rng.below(3) == 0).collect();
            let base = Prepared::with_objects(&foon, &kitchen, &[], Some(&rates), None).unwrap();
            let parts = if round % 5 == 0 {
                rng.below(16) as u8
            } else {
                15
            };
            compute(&foon, &base, parts);
            let had = Objective::ALL.map(|o| base.has_optimum(o));
            let pick = |rng: &mut Rng| -> Vec<u32> {
                (0..rng.below(4)).map(|_| rng.below(n) as u32).collect()
            };
            let (added, removed) = (pick(&mut rng), pick(&mut rng));
            // Every third round, passes limited to a few objects: those that reach further
            // leave their part to be computed from scratch.
            let limit = if round % 3 == 0 {
                rng.below(4)
            } else {
                usize::MAX
            };
            let inc = base
                .with_delta_reaching(&foon, &added, &removed, limit)
                .unwrap();
            let new = changed_kitchen(&kitchen, &added, &removed);
            changed += usize::from(new != kitchen);
            let fresh = Prepared::with_base(&foon, base.base().clone(), &new).unwrap();
            // Goals read through the pending updates: a few, or every object in a random
            // order.
            let mut goals: Vec<u32> = if round % 2 == 0 {
                (0..rng.below(4)).map(|_| rng.below(n) as u32).collect()
            } else {
                (0..n as u32).collect()
            };
            for i in (1..goals.len()).rev() {
                goals.swap(i, rng.below(i + 1));
            }
            plans_agree(&foon, &inc, &fresh, &goals);
            part_run += usize::from(
                Objective::ALL
                    .into_iter()
                    .any(|o| inc.pending_started(o) && inc.has_pending(o)),
            );
            // A delta of the derived kitchen, its updates part run: its changes are layered on
            // the first's, its updates start where the first's do.
            let (added2, removed2) = (pick(&mut rng), pick(&mut rng));
            let inc2 = inc
                .with_delta_reaching(&foon, &added2, &removed2, limit)
                .unwrap();
            let new2 = changed_kitchen(&new, &added2, &removed2);
            let fresh2 = Prepared::with_base(&foon, base.base().clone(), &new2).unwrap();
            let had2 = Objective::ALL.map(|o| has(&inc, o));
            let exact = limit == usize::MAX;
            assert_same(&foon, &base, &inc, &fresh, exact.then_some(had));
            assert_same(&foon, &inc, &inc2, &fresh2, exact.then_some(had2));
            // Plans read from either are the same (what is not computed is computed now).
            let all: Vec<u32> = (0..n as u32).collect();
            plans_agree(&foon, &inc, &fresh, &all);
            plans_agree(&foon, &inc2, &fresh2, &all);
        }
        assert!(changed > 400, "only {changed} deltas changed the kitchen");
        assert!(part_run > 30, "only {part_run} updates were read part run");
    }

    /// A random FOON (every motion at `rate`) and kitchen whose preparation has computed
    /// every part, the kitchen changed by the delta `added`, `removed` draw (from the FOON's
    /// object count): the FOON, the incremental preparation and the one from scratch.
    fn delta_case(
        rng: &mut Rng,
        rate: f64,
        added: impl Fn(&mut Rng, usize) -> Vec<u32>,
        removed: impl Fn(&mut Rng, usize) -> Vec<u32>,
    ) -> (Foon, Prepared, Prepared) {
        let foon = random_foon(rng);
        let n = foon.object_count();
        let kitchen: Vec<u32> = (0..n as u32).filter(|_| rng.below(3) == 0).collect();
        let rates = MotionRates::from_pairs((0..4).map(|m| (format!("m{m}"), rate))).unwrap();
        let base = Prepared::with_objects(&foon, &kitchen, &[], Some(&rates), None).unwrap();
        compute(&foon, &base, 15);
        let (added, removed) = (added(rng, n), removed(rng, n));
        let inc = base.with_delta(&foon, &added, &removed).unwrap();
        let new = changed_kitchen(&kitchen, &added, &removed);
        let fresh = Prepared::with_base(&foon, base.base().clone(), &new).unwrap();
        (foon, inc, fresh)
    }

    /// Threads planning at once on one kitchen whose updates are pending (each plan runs the
    /// update a little further under its lock) get the plans from scratch.
    #[test]
    fn threads_share_a_pending_update() {
        let mut rng = Rng(0x9e37_79b9);
        for _ in 0..40 {
            let added = |rng: &mut Rng, n: usize| (0..3).map(|_| rng.below(n) as u32).collect();
            let (foon, inc, fresh) = delta_case(&mut rng, 0.5, added, |_, _| Vec::new());
            let n = foon.object_count();
            let all: Vec<u32> = (0..n as u32).collect();
            std::thread::scope(|s| {
                for t in 0..4 {
                    let mut goals = all.clone();
                    goals.rotate_left(t * n / 4);
                    let (foon, inc, fresh) = (&foon, &inc, &fresh);
                    s.spawn(move || plans_agree(foon, inc, fresh, &goals));
                }
            });
        }
    }

    /// A batch of plans on several threads runs to the end the pending updates its method
    /// reads, and only those: the shopping costs of explanations, and the optimum of an
    /// optimal method (a batch of `ids` leaves the optimal objectives pending). The plans are
    /// those from scratch either way.
    #[test]
    fn batches_finish_what_they_read() {
        use crate::search::batch::{BatchOptions, plan_batch};
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let mut kept = 0;
        for _ in 0..60 {
            let added = |rng: &mut Rng, n: usize| (0..3).map(|_| rng.below(n) as u32).collect();
            let (foon, inc, fresh) = delta_case(&mut rng, 0.5, added, |_, _| Vec::new());
            let pending = |o| inc.has_pending(o);
            let before = Objective::ALL.map(pending);
            let goals: Vec<u32> = (0..foon.object_count() as u32).collect();
            let opts = BatchOptions::threads(Some(2));
            for method in [Method::Ids, Method::OptimalUnits] {
                let q = Query {
                    method,
                    ..Query::default()
                };
                let a = plan_batch(&foon, &inc, &goals, q, &opts).unwrap();
                let b = plan_batch(&foon, &fresh, &goals, q, &opts).unwrap();
                for (x, y) in a.iter().zip(&b) {
                    assert_eq!(
                        (&x.units, x.solved, x.cost.map(f64::to_bits)),
                        (&y.units, y.solved, y.cost.map(f64::to_bits))
                    );
                }
                // Sound plans explain the goals the kitchen cannot make.
                let read = |o| {
                    o == Objective::Shopping
                        || (method == Method::OptimalUnits && o == Objective::Units)
                };
                for (i, o) in Objective::ALL.into_iter().enumerate() {
                    if read(o) {
                        assert!(!pending(o), "{method:?} left {o:?} pending");
                    } else if before[i] {
                        assert!(pending(o), "{method:?} ran {o:?}, which it does not read");
                        kept += 1;
                    }
                }
            }
        }
        assert!(kept > 20, "only {kept} updates were pending");
    }

    /// Plans cancelled while they run an update (the update stops between two objects) and
    /// asked again give the plans from scratch: a stopped update goes on where it stopped.
    #[test]
    fn cancelled_updates_go_on() {
        use std::sync::atomic::{AtomicU64, Ordering};
        let mut rng = Rng(0x51_7cc1_b727_220a);
        let mut cancelled = 0;
        for _ in 0..200 {
            let two = |rng: &mut Rng, n: usize| (0..2).map(|_| rng.below(n) as u32).collect();
            let (foon, inc, fresh) = delta_case(&mut rng, 0.9, two, two);
            let n = foon.object_count();
            // Every third look at the callback cancels.
            let calls = AtomicU64::new(rng.below(3) as u64);
            let cancel = || calls.fetch_add(1, Ordering::Relaxed) % 3 == 0;
            let a = Context::with(&foon, &inc).unwrap().with_cancel(&cancel);
            let b = Context::with(&foon, &fresh).unwrap();
            for o in 0..n as u32 {
                for method in METHODS {
                    let q = Query {
                        method,
                        ..Query::default()
                    };
                    let x = loop {
                        match a.plan(o, q) {
                            Err(crate::Error::Cancelled) => cancelled += 1,
                            r => break r.unwrap(),
                        }
                    };
                    let y = b.plan(o, q).unwrap();
                    assert_eq!(
                        (x.units, x.solved, x.cost.map(f64::to_bits)),
                        (y.units, y.solved, y.cost.map(f64::to_bits))
                    );
                }
            }
        }
        assert!(cancelled > 100, "only {cancelled} plans were cancelled");
    }

    /// An id out of range is an error; an empty delta keeps everything.
    #[test]
    fn bad_ids_and_empty_deltas() {
        let mut rng = Rng(7);
        let foon = random_foon(&mut rng);
        let base = Prepared::with_objects(&foon, &[0], &[], None, None).unwrap();
        compute(&foon, &base, 1);
        let n = foon.object_count() as u32;
        assert!(base.with_delta(&foon, &[n], &[]).is_err());
        assert!(base.with_delta(&foon, &[], &[n + 5]).is_err());
        let same = base.with_delta(&foon, &[], &[]).unwrap();
        assert_eq!(same.computed_ranks(), base.computed_ranks());
        assert_eq!(same.kitchen_objects(), base.kitchen_objects());
    }
}
