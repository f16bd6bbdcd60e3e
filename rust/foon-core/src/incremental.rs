//! Incremental kitchens: a kitchen given as a base kitchen's preparation plus a delta (items
//! added, items removed) is prepared from the base's, touching only what the delta changes,
//! with every result equal to a preparation from scratch ([`Prepared::with_delta`]).
//!
//! Ranks and each optimal objective's (cost, depth) are the least fixpoint of superior
//! functions (a unit's value is above each of its needed inputs', and never decreases when
//! one of them increases), so a change of the leaves (the kitchen, for the shopping costs
//! the kitchen and the raw items) moves only the values that depend on it:
//!
//! - the *affected* objects are the leaves that changed and every object whose choice (for
//!   ranks: the first producer that achieves its rank) needs an affected object: every other
//!   object keeps a tree that the change leaves intact, so its value can only decrease;
//! - the affected objects are reset, seeded from their producers whose needed inputs are all
//!   unaffected, and one pass of Knuth's algorithm in (value, depth) order runs from them and
//!   from the new leaves, through the units of every object whose value it finalises, lowering
//!   what it reaches (Ramalingam and Reps's algorithm for both kinds of change at once).
//!
//! The choices follow from the final values alone (the lowest-index producer whose (cost,
//! depth) is the object's, `docs/METHODS.md`), so they are the from-scratch ones, and every
//! sum is formed as from scratch (the unit's weight, then its inputs in input order), so the
//! costs are bit-identical. The pass costs O((A + L) log A) plus the needed and output slots
//! of the units it reaches, for A affected and L lowered objects; copying the per-object
//! vectors of the base is the only part linear in the FOON.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::sync::Arc;

use rayon::prelude::*;
use rustc_hash::FxHashSet;

use crate::error::{Error, Result};
use crate::forward::Ranks;
use crate::index::{Foon, NONE};
use crate::kitchen::Kitchen;
use crate::layered::{Editor, Layered};
use crate::model::ObjectSpec;
use crate::prepare::{Objective, Optimum, Prepared};
use crate::search::{better, lower, tie_depth};

/// The per-object values one pass updates: (value, depth) and the choice of each object.
trait Store {
    fn get(&self, o: u32) -> (f64, u32);
    fn choice(&self, o: u32) -> u32;
    fn set(&mut self, o: u32, v: (f64, u32), choice: u32);
}

/// An optimum being updated: its cost, depth and choice columns.
struct OptimumEdit {
    cost: Editor<f64>,
    depth: Editor<u32>,
    choice: Editor<u32>,
}

impl OptimumEdit {
    fn of(o: &Optimum) -> Self {
        Self {
            cost: o.cost.edit(),
            depth: o.depth.edit(),
            choice: o.choice.edit(),
        }
    }

    fn finish(self) -> Optimum {
        Optimum {
            cost: self.cost.finish(),
            choice: self.choice.finish(),
            depth: self.depth.finish(),
        }
    }
}

impl Store for OptimumEdit {
    #[inline]
    fn get(&self, o: u32) -> (f64, u32) {
        (self.cost.get(o), self.depth.get(o))
    }
    #[inline]
    fn choice(&self, o: u32) -> u32 {
        self.choice.get(o)
    }
    #[inline]
    fn set(&mut self, o: u32, v: (f64, u32), choice: u32) {
        self.cost.set(o, v.0);
        self.depth.set(o, v.1);
        self.choice.set(o, choice);
    }
}

/// Ranks as values (depth 0; `NONE` is +infinity); no choice is kept.
struct RankStore(Editor<u32>);

impl Store for RankStore {
    #[inline]
    fn get(&self, o: u32) -> (f64, u32) {
        match self.0.get(o) {
            NONE => (f64::INFINITY, 0),
            r => (f64::from(r), 0),
        }
    }
    #[inline]
    fn choice(&self, _: u32) -> u32 {
        NONE
    }
    #[inline]
    fn set(&mut self, o: u32, v: (f64, u32), _: u32) {
        self.0
            .set(o, if v.0.is_finite() { v.0 as u32 } else { NONE });
    }
}

/// One objective's rules for a pass.
struct Rules<'a> {
    /// Whether an object is a leaf before and after the change.
    was_leaf: &'a dyn Fn(u32) -> bool,
    is_leaf: &'a dyn Fn(u32) -> bool,
    /// The (value, depth) of a leaf.
    leaf: (f64, u32),
    /// A unit's (value, depth) from the current values of its needed inputs (all finite).
    value: &'a dyn Fn(&dyn Store, u32) -> (f64, u32),
    /// The choice of an object before the change (`NONE` for a leaf or an infinite one).
    old_choice: &'a dyn Fn(&dyn Store, u32) -> u32,
}

/// Heap key: (value bits, depth, object); values are never negative, so their bits order as
/// they do.
type Key = Reverse<(u64, u32, u32)>;

/// A pass that reaches more than one object in `REACH_SHARE` (and more than `REACH_MIN`)
/// stops: the part is then computed from scratch on first use, which costs less than an
/// update of that size (a delta that removes an item much of the FOON is made from).
const REACH_SHARE: usize = 4;
const REACH_MIN: usize = 1024;

/// Updates `store` (the values before the change) to the values after it, the leaves that
/// changed being among `flipped`. Returns the objects whose value or choice may have
/// changed, or `None` when the change reaches too much of the FOON to be worth updating
/// (see [`REACH_SHARE`]; `store` is then left half updated, to be dropped).
fn pass(
    foon: &Foon,
    prep: &Prepared,
    store: &mut dyn Store,
    flipped: &[u32],
    rules: &Rules<'_>,
    limit: usize,
) -> Option<Vec<u32>> {
    // Per object: AFFECTED, DONE (final in this pass). Zeroed pages cost nothing until
    // touched, so the marks cost what the pass reaches.
    const AFFECTED: u8 = 1;
    const DONE: u8 = 2;
    let mut mark = vec![0u8; foon.object_count()];
    let mut list: Vec<u32> = Vec::new();
    for &o in flipped {
        if (rules.was_leaf)(o) != (rules.is_leaf)(o) && mark[o as usize] & AFFECTED == 0 {
            mark[o as usize] |= AFFECTED;
            list.push(o);
        }
    }
    // Every object whose choice needs an affected object, transitively (read before any
    // value changes).
    let mut i = 0;
    while let Some(&x) = list.get(i) {
        i += 1;
        if list.len() > limit {
            return None;
        }
        for &f in prep.needed_by(x) {
            for &y in foon.outputs(f) {
                if mark[y as usize] & AFFECTED == 0 && (rules.old_choice)(&*store, y) == f {
                    mark[y as usize] |= AFFECTED;
                    list.push(y);
                }
            }
        }
    }
    for &y in &list {
        store.set(y, (f64::INFINITY, 0), NONE);
    }
    let mut lowered: Vec<u32> = Vec::new();
    let mut heap: BinaryHeap<Key> = BinaryHeap::new();
    let available = |store: &dyn Store, mark: &[u8], f: u32| {
        prep.needed(f).iter().all(|&x| {
            let m = mark[x as usize];
            store.get(x).0.is_finite() && (m & AFFECTED == 0 || m & DONE != 0)
        })
    };
    let offer =
        |store: &mut dyn Store, heap: &mut BinaryHeap<Key>, y: u32, f: u32, v: (f64, u32)| {
            let old = store.get(y);
            if better(v.0, v.1, f, old.0, old.1, store.choice(y)) {
                if lower(v.0, v.1, old.0, old.1) {
                    heap.push(Reverse((v.0.to_bits(), v.1, y)));
                }
                store.set(y, v, f);
            }
        };
    for &y in &list {
        if (rules.is_leaf)(y) {
            store.set(y, rules.leaf, NONE);
            heap.push(Reverse((rules.leaf.0.to_bits(), rules.leaf.1, y)));
        } else if !prep.is_bare(y) {
            for &f in foon.producers(y) {
                if available(&*store, &mark, f) {
                    let v = (rules.value)(&*store, f);
                    if v.0 != f64::INFINITY {
                        offer(store, &mut heap, y, f, v);
                    }
                }
            }
        }
    }
    while let Some(Reverse((bits, depth, o))) = heap.pop() {
        let now = store.get(o);
        if mark[o as usize] & DONE != 0 || (now.0.to_bits(), now.1) != (bits, depth) {
            continue;
        }
        mark[o as usize] |= DONE;
        if mark[o as usize] & AFFECTED == 0 {
            lowered.push(o);
            if lowered.len() > limit {
                return None;
            }
        }
        for &f in prep.needed_by(o) {
            if !available(&*store, &mark, f) {
                continue;
            }
            let v = (rules.value)(&*store, f);
            if v.0 == f64::INFINITY {
                continue;
            }
            for &y in foon.outputs(f) {
                if (rules.is_leaf)(y) || prep.is_bare(y) || mark[y as usize] & DONE != 0 {
                    continue;
                }
                offer(store, &mut heap, y, f, v);
            }
        }
    }
    for &y in &list {
        if mark[y as usize] & DONE == 0 {
            store.set(y, (f64::INFINITY, 0), NONE);
        }
    }
    list.extend(lowered);
    Some(list)
}

/// The (cost, depth) of unit `f` weighing `w`: the weight, plus the costs of its needed
/// inputs in input order, as Knuth's algorithm forms it from scratch.
#[inline]
fn unit_value(prep: &Prepared, store: &dyn Store, f: u32, w: f64) -> (f64, u32) {
    let needed = prep.needed(f);
    let mut c = w;
    for &x in needed {
        c += store.get(x).0;
    }
    (c, tie_depth(c, needed.iter().map(|&x| store.get(x))))
}

/// The rank a unit gives its outputs: one more than the largest rank of its needed inputs.
#[inline]
fn rank_value(prep: &Prepared, store: &dyn Store, f: u32) -> f64 {
    let mut m = 0.0f64;
    for &x in prep.needed(f) {
        m = m.max(store.get(x).0);
    }
    m + 1.0
}

/// The choice of `ids` of every object in `objects`, from the ranks `rank` and the kitchen of
/// `prep`: the first producer whose value is the object's rank (`NONE` for kitchen objects
/// and objects that are not derivable), as `search::ids` computes it.
fn ids_choice_of(foon: &Foon, prep: &Prepared, rank: &Layered<u32>, o: u32) -> u32 {
    let r = rank.get(o);
    if r == NONE || prep.in_kitchen(o) {
        return NONE;
    }
    let value = |f: u32| {
        let mut m = 0;
        for &x in prep.needed(f) {
            let rx = if prep.in_kitchen(x) { 0 } else { rank.get(x) };
            if rx == NONE {
                return NONE;
            }
            m = m.max(rx);
        }
        m + 1
    };
    foon.producers(o)
        .iter()
        .copied()
        .find(|&f| value(f) == r)
        .unwrap_or(NONE)
}

impl Prepared {
    /// The kitchen of these inputs (`self`, the base kitchen's preparation) without the
    /// objects `removed` and with the objects `added` (object ids of `foon`, any order,
    /// repeats allowed; an id in both lists is added), prepared incrementally: equal in every
    /// result to [`Prepared::with_base`] on the same base with the new kitchen. What the base
    /// kitchen has computed (ranks, the choice of `ids`, each optimal objective's costs and
    /// choices) is updated from it, touching only the objects the change reaches; what it
    /// has not computed is computed on first use, as for a kitchen prepared from scratch.
    /// The level is the base kitchen's.
    pub fn with_delta(&self, foon: &Foon, added: &[u32], removed: &[u32]) -> Result<Prepared> {
        let limit = REACH_MIN.max(foon.object_count() / REACH_SHARE);
        self.with_delta_reaching(foon, added, removed, limit)
    }

    /// [`Prepared::with_delta`], a pass that reaches more than `limit` objects leaving its
    /// part to be computed from scratch on first use.
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
            // Nothing changed: everything computed is the same.
            let optima = Objective::ALL.map(|o| self.computed_optimum(o).cloned());
            out.set_computed(
                self.computed_ranks().cloned(),
                optima,
                self.computed_ids_choice().cloned(),
            );
            return Ok(out);
        }
        // The parts are independent: they are updated at once, on the core's pool.
        let ((ranks, ids), optima) = crate::search::batch::in_pool(|| {
            rayon::join(
                || self.delta_ranks(foon, &out, &flipped, limit),
                || {
                    let mut optima: [Option<Optimum>; 4] = Default::default();
                    let done: Vec<(usize, Optimum)> = Objective::ALL
                        .par_iter()
                        .enumerate()
                        .filter_map(|(i, &o)| {
                            self.delta_optimum(foon, &out, &flipped, o, limit)
                                .map(|x| (i, x))
                        })
                        .collect();
                    for (i, x) in done {
                        optima[i] = Some(x);
                    }
                    optima
                },
            )
        })?;
        out.set_computed(ranks, optima, ids);
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
        let old = self.kitchen_flags();
        let was_kitchen = |o: u32| old.get(o);
        let is_kitchen = |o: u32| new_prep.in_kitchen(o);
        // Ranks, and from them the choice of `ids`.
        let mut ranks = None;
        let mut ids = None;
        if let Some(r) = self.computed_ranks() {
            let mut store = RankStore(r.layered().edit());
            // The first producer that achieves an object's rank (before the change): the
            // choice of `ids`, when computed.
            let ids_before = self.computed_ids_choice();
            let old_choice = |_: &dyn Store, y: u32| {
                if let Some(c) = ids_before {
                    return c.get(y);
                }
                let ry = r.raw(y);
                if ry == NONE || old.get(y) {
                    return NONE;
                }
                foon.producers(y)
                    .iter()
                    .copied()
                    .find(|&f| {
                        let mut m = 0;
                        for &x in self.needed(f) {
                            let rx = r.raw(x);
                            if rx == NONE {
                                return false;
                            }
                            m = m.max(rx);
                        }
                        m + 1 == ry
                    })
                    .unwrap_or(NONE)
            };
            let value = |s: &dyn Store, f: u32| (rank_value(new_prep, s, f), 0);
            let rules = Rules {
                was_leaf: &was_kitchen,
                is_leaf: &is_kitchen,
                leaf: (0.0, 0),
                value: &value,
                old_choice: &old_choice,
            };
            let Some(touched) = pass(foon, new_prep, &mut store, flipped, &rules, limit) else {
                // Too much changes: both are computed on first use, from scratch.
                return (None, None);
            };
            let rank = store.0.finish();
            if let Some(c) = self.computed_ids_choice() {
                let mut choice = c.edit();
                let mut again: FxHashSet<u32> = touched.iter().copied().collect();
                for &x in &touched {
                    for &f in new_prep.needed_by(x) {
                        again.extend(foon.outputs(f).iter().copied());
                    }
                }
                for o in again {
                    choice.set(o, ids_choice_of(foon, new_prep, &rank, o));
                }
                ids = Some(choice.finish());
            }
            ranks = Some(Ranks::from_layered(rank));
        }
        (ranks, ids)
    }

    /// The optimum of `objective` of `new_prep` (this kitchen changed at `flipped`), updated
    /// from this kitchen's, when computed here.
    fn delta_optimum(
        &self,
        foon: &Foon,
        new_prep: &Prepared,
        flipped: &[u32],
        objective: Objective,
        limit: usize,
    ) -> Option<Optimum> {
        let old = self.kitchen_flags();
        let was_kitchen = |o: u32| old.get(o);
        let is_kitchen = |o: u32| new_prep.in_kitchen(o);
        let mut store = OptimumEdit::of(self.computed_optimum(objective)?);
        let rates = self.fu_rates();
        let success =
            |s: &dyn Store, f: u32| unit_value(new_prep, s, f, 0.0 - rates[f as usize].ln());
        let units = |s: &dyn Store, f: u32| unit_value(new_prep, s, f, 1.0);
        let inputs = |s: &dyn Store, f: u32| unit_value(new_prep, s, f, 0.0);
        let raw = |o: u32| foon.producers(o).is_empty();
        let was_shop = |o: u32| old.get(o) || raw(o);
        let is_shop = |o: u32| new_prep.in_kitchen(o) || raw(o);
        let old_choice = |s: &dyn Store, y: u32| s.choice(y);
        let rules = match objective {
            Objective::Success => Rules {
                was_leaf: &was_kitchen,
                is_leaf: &is_kitchen,
                leaf: (0.0, 0),
                value: &success,
                old_choice: &old_choice,
            },
            Objective::Units => Rules {
                was_leaf: &was_kitchen,
                is_leaf: &is_kitchen,
                leaf: (0.0, 0),
                value: &units,
                old_choice: &old_choice,
            },
            Objective::Inputs => Rules {
                was_leaf: &was_kitchen,
                is_leaf: &is_kitchen,
                leaf: (1.0, 0),
                value: &inputs,
                old_choice: &old_choice,
            },
            Objective::Shopping => Rules {
                was_leaf: &was_shop,
                is_leaf: &is_shop,
                leaf: (1.0, 0),
                value: &inputs,
                old_choice: &old_choice,
            },
        };
        pass(foon, new_prep, &mut store, flipped, &rules, limit)?;
        Some(store.finish())
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
    use crate::layered::Layered;
    use crate::model::MotionRates;
    use crate::parse::{ParseOptions, parse_foon};
    use crate::prepare::{Objective, Prepared};
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

    /// Every component computed on `inc` equals the one computed from scratch on `fresh`, bit
    /// for bit, and `inc` has computed exactly what `base` had (with `all`; else what it has
    /// computed is among what `base` had: a pass that reached too far left its part).
    fn assert_same(foon: &Foon, base: &Prepared, inc: &Prepared, fresh: &Prepared, all: bool) {
        let parts = |a: bool, b: bool| {
            if all {
                assert_eq!(a, b);
            } else {
                assert!(!a || b);
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
        for objective in Objective::ALL {
            let got = inc.computed_optimum(objective);
            parts(got.is_some(), base.computed_optimum(objective).is_some());
            let Some(got) = got else { continue };
            let ctx = Context::with(foon, fresh).unwrap();
            crate::search::compute_optimum(&ctx, objective).unwrap();
            let want = fresh.computed_optimum(objective).unwrap();
            let bits = |v: &Layered<f64>| v.iter().map(f64::to_bits).collect::<Vec<_>>();
            assert_eq!(bits(&got.cost), bits(&want.cost), "{objective:?} costs");
            assert_eq!(got.choice, want.choice, "{objective:?} choices");
            assert_eq!(got.depth, want.depth, "{objective:?} depths");
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

    /// Random FOONs, kitchens and deltas (additions, removals, both, an id in both lists,
    /// repeats): the incremental preparation equals the one from scratch in every component
    /// the base had computed, and plans from it equal plans from scratch.
    #[test]
    fn deltas_give_the_preparation_from_scratch() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let mut changed = 0;
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
            assert_same(&foon, &base, &inc, &fresh, limit == usize::MAX);
            // A delta of the derived kitchen: its changes are layered on the first's.
            let (added2, removed2) = (pick(&mut rng), pick(&mut rng));
            let inc2 = inc
                .with_delta_reaching(&foon, &added2, &removed2, limit)
                .unwrap();
            let new2 = changed_kitchen(&new, &added2, &removed2);
            let fresh2 = Prepared::with_base(&foon, base.base().clone(), &new2).unwrap();
            assert_same(&foon, &inc, &inc2, &fresh2, limit == usize::MAX);
            // Plans read from either are the same (what is not computed is computed now).
            let (a, b) = (
                Context::with(&foon, &inc).unwrap(),
                Context::with(&foon, &fresh).unwrap(),
            );
            for o in 0..n as u32 {
                for method in [Method::Ids, Method::OptimalInputs, Method::OptimalSuccess] {
                    let q = Query {
                        method,
                        ..Query::default()
                    };
                    let (x, y) = (a.plan(o, q).unwrap(), b.plan(o, q).unwrap());
                    assert_eq!((x.units, x.solved), (y.units, y.solved));
                }
            }
        }
        assert!(changed > 400, "only {changed} deltas changed the kitchen");
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
