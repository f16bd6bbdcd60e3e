//! Preparing the planning inputs of one FOON, the stage below every search, check and lint:
//! the kitchen matched to objects, the container rule (needed inputs), the motion rate of
//! every FU, and derivability from the kitchen ([`Ranks`], computed once, by the forward
//! chaining of `forward.rs`), and what the sound searches compute once per kitchen, on first
//! use: each optimal objective's costs and choices over the whole FOON, the cheapest shopping
//! costs of failure explanations, the choice of `ids`.

use std::sync::{Arc, Mutex, MutexGuard, OnceLock};

use rustc_hash::{FxHashMap, FxHashSet};

use crate::error::{Error, Result};
use crate::forward;
use crate::hint::{AHEAD, Ahead};

pub use crate::forward::Ranks;
use crate::incremental::Pending;
use crate::index::{Csr, Foon, NONE, Rows};
use crate::layered::{Layered, Value};
use crate::model::{MotionRates, ObjectSpec, check_rate};
use crate::relax::Reached;

/// Planning inputs prepared for one FOON: the kitchen matched to objects, on a
/// [`PreparedBase`] (the container rule applied, the motion rate of every FU), shared with
/// every other kitchen prepared on it. It owns its data, so it can be kept and reused for any
/// number of plans ([`Context::with`](crate::search::Context::with)); it is `Send + Sync`.
/// What depends on the kitchen (ranks; each optimal objective's costs and choices; the
/// shopping costs of explanations; the choices of `ids`) is computed on first use, once, in
/// one pass over the FOON, and kept for every later plan of any thread.
pub struct Prepared {
    /// Content fingerprint of the FOON these inputs were prepared for.
    foon: [u8; 16],
    /// What does not depend on the kitchen: needed inputs, rates, greedy orders.
    base: Arc<PreparedBase>,
    in_kitchen: Layered<bool>,
    kitchen_objects: Vec<u32>,
    ranks: OnceLock<Ranks>,
    /// Per [`Objective`]: final costs and choices from the kitchen over the whole FOON.
    optima: [OnceLock<Optimum>; Objective::COUNT],
    /// Per [`Objective`], for a kitchen derived from another by a delta: the update of the
    /// other's optimum, run as far as the plans so far needed (`incremental.rs`); moved to
    /// `optima` once it has run to the end.
    pending: [Mutex<Option<Box<Pending>>>; Objective::COUNT],
    /// `ids`: the first producer of each object that achieves its rank (`NONE` when none).
    ids_choice: OnceLock<Layered<u32>>,
    /// The identity level the kitchen was matched at (1, 2 or 3; results report it).
    level: u8,
    /// Whether the kitchen was derived from another by a delta, sharing its columns
    /// ([`Prepared::with_parts`]).
    derived: bool,
    /// The goals' ancestries the k best trees were computed over, kept for later calls.
    pub(crate) kbest: crate::search::kbest::AncestryCache,
}

/// The part of [`Prepared`] that does not depend on the kitchen, computed once per (FOON,
/// utensils, rates, default rate) and shared (an [`Arc`]) by every kitchen prepared on it
/// ([`Prepared::with_base`]): the needed inputs of every FU under the container rule, the FUs
/// that need each object, the rate of every FU's motion, and (on first use) the producer
/// order of each greedy heuristic, whose keys depend on the rates and the inputs only.
pub struct PreparedBase {
    /// Content fingerprint of the FOON.
    foon: [u8; 16],
    /// [`PreparedBase::key_of`] the utensils, rates and default rate.
    key: u128,
    object_count: usize,
    /// Per FU, one row: the number k of its needed inputs (container rule applied), those
    /// inputs in input order, then its outputs that are not bare, in output order. A search
    /// that goes from a unit's inputs to its outputs reads one row (one place in memory)
    /// instead of one row of each.
    needed: Csr,
    /// For each object, the FUs where it is a needed input (one entry per slot).
    needed_by: Csr,
    fu_rate: Vec<f64>,
    rates_given: bool,
    /// Whether every FU's motion has a rate.
    all_rated: bool,
    /// One bit per object: whether it is bare ([`Foon::is_bare`], read by every search's
    /// inner loop, here without the index's columns).
    bare: Vec<u64>,
    /// Per greedy heuristic: each object's producers in its order, and the course's choice.
    greedy: [OnceLock<Greedy>; Greedy::COUNT],
}

/// One greedy heuristic's producer order for every object, computed once per
/// [`PreparedBase`] (the keys depend on the rates and the inputs only, not on the kitchen, the
/// goal or the path).
pub(crate) struct Greedy {
    /// Each object's producers, best first, ties by FU index (the sound search's order).
    pub(crate) order: Csr,
    /// Each object's first best producer in file order, `NONE` when it has none (the course
    /// loop's choice).
    pub(crate) first: Vec<u32>,
}

impl Greedy {
    /// `greedy-success`, `greedy-inputs` counting nodes, `greedy-inputs` counting ingredients.
    pub(crate) const COUNT: usize = 3;
}

/// An objective computed once per kitchen over the whole FOON by Knuth's algorithm.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Objective {
    /// `optimal-success`: leaves 0, an FU weighs `-ln rate`.
    Success,
    /// `optimal-units`: leaves 0, an FU weighs 1.
    Units,
    /// `optimal-inputs`: leaves 1, an FU weighs 0.
    Inputs,
    /// Failure explanations: leaves are the kitchen and the raw items (K'), 1 each; an FU
    /// weighs 0.
    Shopping,
}

impl Objective {
    const COUNT: usize = 4;
    /// Every objective, in the order of [`Prepared`]'s optima.
    pub(crate) const ALL: [Objective; Objective::COUNT] = [
        Objective::Success,
        Objective::Units,
        Objective::Inputs,
        Objective::Shopping,
    ];
}

/// One object's entry in an [`Optimum`]: its final cost, choice and tie key side by side
/// (one cache line read per look-up on a FOON far larger than the caches).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Slot {
    pub(crate) cost: f64,
    pub(crate) choice: u32,
    /// The tie key (`search::optimal::tie_depth`; 0 for an object that is not final).
    pub(crate) depth: u32,
}

impl Value for Slot {
    #[inline]
    fn same(self, other: Self) -> bool {
        self.cost.to_bits() == other.cost.to_bits()
            && self.choice == other.choice
            && self.depth == other.depth
    }
}

/// Final cost and choice of every object for one [`Objective`] (`f64::INFINITY` and `NONE`
/// for an object that is not finalised).
/// Kept as a [`Layered`] column, so that a kitchen derived from another by a delta shares it.
#[derive(Clone)]
pub(crate) struct Optimum {
    pub(crate) slots: Layered<Slot>,
}

impl Optimum {
    pub(crate) fn from_slots(slots: Vec<Slot>) -> Self {
        Self {
            slots: Layered::from_vec(slots),
        }
    }

    #[inline]
    pub(crate) fn cost(&self, o: u32) -> f64 {
        self.slots.get(o).cost
    }

    #[inline]
    pub(crate) fn choice(&self, o: u32) -> u32 {
        self.slots.get(o).choice
    }

    #[inline]
    pub(crate) fn depth(&self, o: u32) -> u32 {
        self.slots.get(o).depth
    }

    fn heap_bytes(&self, own: bool) -> usize {
        self.slots.heap_bytes(own)
    }
}

/// An optimum as far as one goal needs it: the whole column, or a kitchen's pending update
/// of it ([`Prepared::optimum_at`]) run until the goal and every object of its tree are final
/// (reading other objects gives values that may not be).
pub(crate) enum OptimumAt<'a> {
    Whole(&'a Optimum),
    Partial(MutexGuard<'a, Option<Box<Pending>>>),
}

impl OptimumAt<'_> {
    fn slot(&self, o: u32) -> Slot {
        match self {
            Self::Whole(k) => k.slots.get(o),
            Self::Partial(p) => match p.as_deref() {
                Some(p) => p.slot(o),
                // `optimum_at` returns a guard on a pending update only.
                None => Slot {
                    cost: f64::INFINITY,
                    choice: NONE,
                    depth: 0,
                },
            },
        }
    }

    #[inline]
    pub(crate) fn cost(&self, o: u32) -> f64 {
        self.slot(o).cost
    }

    #[inline]
    pub(crate) fn choice(&self, o: u32) -> u32 {
        self.slot(o).choice
    }
}

/// Locks a pending update; one left half-done by a panicking thread is dropped (the optimum
/// is then computed from scratch on use).
fn lock(cell: &Mutex<Option<Box<Pending>>>) -> MutexGuard<'_, Option<Box<Pending>>> {
    match cell.lock() {
        Ok(g) => g,
        Err(poisoned) => {
            let mut g = poisoned.into_inner();
            *g = None;
            cell.clear_poison();
            g
        }
    }
}

/// The value in `cell`, computing it with `init` when it is not there yet. An error (a
/// cancelled computation) is returned and nothing is kept, so a later call computes again;
/// two threads may compute the same value at once, and the first one stored is kept.
fn once<T>(cell: &OnceLock<T>, init: impl FnOnce() -> Result<T>) -> Result<&T> {
    if let Some(v) = cell.get() {
        return Ok(v);
    }
    let v = init()?;
    Ok(cell.get_or_init(|| v))
}

impl Prepared {
    /// Prepares `kitchen`, `utensils` and `rates` for `foon`. `rates` may be `None`;
    /// `default_rate` fills motions missing from it.
    pub fn new(
        foon: &Foon,
        kitchen: &[ObjectSpec],
        utensils: &[String],
        rates: Option<&MotionRates>,
        default_rate: Option<f64>,
    ) -> Result<Self> {
        let mut ids: Vec<u32> = kitchen
            .iter()
            .filter_map(|item| item.find_in(foon))
            .collect();
        ids.sort_unstable();
        ids.dedup();
        Self::with_objects(foon, &ids, utensils, rates, default_rate)
    }

    /// As [`Prepared::new`], with the kitchen already matched to object ids of `foon` (any
    /// order, repeats allowed). An id that is not an object of `foon` is an error.
    pub fn with_objects(
        foon: &Foon,
        kitchen: &[u32],
        utensils: &[String],
        rates: Option<&MotionRates>,
        default_rate: Option<f64>,
    ) -> Result<Self> {
        let base = PreparedBase::new(foon, utensils, rates, default_rate)?;
        Self::with_base(foon, Arc::new(base), kitchen)
    }

    /// The kitchen `kitchen` (object ids of `foon`, any order, repeats allowed) prepared on
    /// `base`, which must have been built for `foon`. It costs the kitchen's size (plus one
    /// zeroed flag per object); what depends on the kitchen is computed on first use, as
    /// for [`Prepared::with_objects`], whose result this equals.
    pub fn with_base(foon: &Foon, base: Arc<PreparedBase>, kitchen: &[u32]) -> Result<Self> {
        base.check_foon(foon)?;
        let n = base.object_count;
        let mut in_kitchen = vec![false; n];
        let mut kitchen_objects = Vec::with_capacity(kitchen.len());
        for &o in kitchen {
            let Some(flag) = in_kitchen.get_mut(o as usize) else {
                return Err(Error::Invalid(format!(
                    "kitchen object id {o} is not an object of this FOON ({n} objects)"
                )));
            };
            if !*flag {
                *flag = true;
                kitchen_objects.push(o);
            }
        }
        kitchen_objects.sort_unstable();
        Ok(Self {
            foon: base.foon,
            base,
            in_kitchen: Layered::from_vec(in_kitchen),
            kitchen_objects,
            ranks: OnceLock::new(),
            optima: Default::default(),
            pending: Default::default(),
            ids_choice: OnceLock::new(),
            level: 3,
            derived: false,
            kbest: crate::search::kbest::AncestryCache::default(),
        })
    }

    /// The kitchen-independent part these inputs were prepared on (shared with every other
    /// kitchen prepared on it).
    pub fn base(&self) -> &Arc<PreparedBase> {
        &self.base
    }

    /// Sets the ranks from the kitchen, computed elsewhere (the lanes of
    /// [`multi::ranks_many`](crate::multi::ranks_many)); they must be those of this kitchen.
    pub(crate) fn set_ranks(&self, ranks: Ranks) {
        let _ = self.ranks.set(ranks);
    }

    /// Heap bytes of what belongs to this kitchen: its flags and objects and whatever it has
    /// computed so far (ranks, optima, the `ids` choice); not the shared base.
    ///
    /// A kitchen derived from another by a delta (`incremental.rs`) shares the columns of
    /// the kitchen it was derived from and counts only its changes: the shared columns are
    /// counted by the kitchen that computed them.
    pub fn heap_bytes(&self) -> usize {
        let own = !self.derived;
        let mut b = self.in_kitchen.heap_bytes(own) + 4 * self.kitchen_objects.capacity();
        if let Some(r) = self.ranks.get() {
            b += r.heap_bytes(own);
        }
        for o in self.optima.iter().filter_map(OnceLock::get) {
            b += o.heap_bytes(own);
        }
        for cell in &self.pending {
            if let Some(p) = lock(cell).as_deref() {
                b += p.heap_bytes();
            }
        }
        if let Some(c) = self.ids_choice.get() {
            b += c.heap_bytes(own);
        }
        b
    }

    /// These inputs, recorded as matched at identity `level` (see
    /// [`Kitchen::match_at_level`](crate::kitchen::Kitchen::match_at_level); 3 by default).
    #[must_use]
    pub fn at_level(mut self, level: u8) -> Self {
        self.level = level;
        self
    }

    /// The identity level the kitchen and the goals were matched at (1, 2 or 3).
    pub fn level(&self) -> u8 {
        self.level
    }

    /// Errors when these inputs were prepared for another FOON than `foon`.
    pub(crate) fn check_foon(&self, foon: &Foon) -> Result<()> {
        if self.foon != foon.fingerprint() {
            return Err(Error::Invalid(
                "these planning inputs were prepared for another FOON".into(),
            ));
        }
        Ok(())
    }

    #[inline]
    pub fn in_kitchen(&self, o: u32) -> bool {
        self.in_kitchen.get(o)
    }

    /// Per object: whether it is in the kitchen.
    pub(crate) fn kitchen_flags(&self) -> &Layered<bool> {
        &self.in_kitchen
    }

    /// Kitchen objects of the FOON, in id order.
    pub fn kitchen_objects(&self) -> &[u32] {
        &self.kitchen_objects
    }

    /// Needed inputs of `fu` (after the container rule).
    #[inline]
    pub fn needed(&self, fu: u32) -> &[u32] {
        self.base.needed(fu)
    }

    /// The rows of [`Flows::flow`] (each unit's needed inputs and outputs that are not bare)
    /// and [`Prepared::needed_by`] as plain slices, for the passes that read many of them.
    #[inline]
    pub(crate) fn flows(&self) -> Flows<'_> {
        self.base.flows()
    }

    /// [`Foon::is_bare`] of object `o` of the FOON these inputs were prepared for.
    #[inline]
    pub(crate) fn is_bare(&self, o: u32) -> bool {
        (self.base.bare[o as usize >> 6] >> (o & 63)) & 1 != 0
    }

    /// The FUs where `o` is a needed input (one entry per slot).
    #[inline]
    pub(crate) fn needed_by(&self, o: u32) -> &[u32] {
        self.base.needed_by.row(o)
    }

    /// Whether a rate table or a default rate was given.
    pub(crate) fn rates_given(&self) -> bool {
        self.base.rates_given
    }

    /// The rate of every FU's motion, NaN when it has none.
    pub(crate) fn fu_rates(&self) -> &[f64] {
        &self.base.fu_rate
    }

    /// Success rate of `fu`'s motion (`foon` is the FOON these inputs were prepared for), or
    /// the error naming the motion.
    pub(crate) fn rate(&self, foon: &Foon, fu: u32) -> Result<f64> {
        let r = self.base.fu_rate[fu as usize];
        if r.is_nan() {
            Err(Error::MissingRate {
                motion: foon.motion_text(fu).to_owned(),
            })
        } else {
            Ok(r)
        }
    }

    /// Ranks and derivability from the kitchen (computed once, on first use; `foon` is the
    /// FOON these inputs were prepared for).
    pub(crate) fn ranks(&self, foon: &Foon) -> &Ranks {
        self.ranks.get_or_init(|| forward::ranks(foon, self, None))
    }

    /// Whether every FU's motion has a rate (from the table or the default rate).
    pub(crate) fn all_rated(&self) -> bool {
        self.base.all_rated
    }

    /// The optimum of `objective`: its pending update run to the end when there is one
    /// (`foon` is the FOON these inputs were prepared for; `stop` is called now and then, and
    /// its error stops the update where it is), else computed by `init` on first use (see
    /// [`once`]).
    pub(crate) fn optimum(
        &self,
        foon: &Foon,
        objective: Objective,
        stop: &dyn Fn() -> Result<()>,
        init: impl FnOnce() -> Result<Optimum>,
    ) -> Result<&Optimum> {
        let cell = &self.optima[objective as usize];
        if let Some(o) = cell.get() {
            return Ok(o);
        }
        if let Some(o) = self.finish_pending(foon, objective, stop)? {
            return Ok(o);
        }
        once(cell, init)
    }

    /// The optimum of `objective` as far as `goal` needs it: the whole column when it is
    /// computed, else its pending update run until `goal` and every object of its tree are
    /// final (the guard held while the tree is read). `None` when there is neither (or the
    /// update reached too far and was dropped): the caller computes it ([`Prepared::optimum`]).
    pub(crate) fn optimum_at(
        &self,
        foon: &Foon,
        objective: Objective,
        goal: u32,
        stop: &dyn Fn() -> Result<()>,
    ) -> Result<Option<OptimumAt<'_>>> {
        let cell = &self.optima[objective as usize];
        if let Some(o) = cell.get() {
            return Ok(Some(OptimumAt::Whole(o)));
        }
        let mut g = lock(&self.pending[objective as usize]);
        let Some(p) = g.as_deref_mut() else {
            // None, or run to the end by another thread.
            return Ok(cell.get().map(OptimumAt::Whole));
        };
        match p.advance(foon, self, Some(goal), stop)? {
            Reached::Settled => Ok(Some(OptimumAt::Partial(g))),
            Reached::End => {
                let o = g.take().map(|p| p.finish());
                Ok(o.map(|o| OptimumAt::Whole(cell.get_or_init(|| o))))
            }
            Reached::TooFar => {
                *g = None;
                Ok(None)
            }
        }
    }

    /// Runs the pending update of `objective` to the end and keeps its optimum; `None` when
    /// there is none (or it reached too far and was dropped).
    fn finish_pending(
        &self,
        foon: &Foon,
        objective: Objective,
        stop: &dyn Fn() -> Result<()>,
    ) -> Result<Option<&Optimum>> {
        let cell = &self.optima[objective as usize];
        let mut g = lock(&self.pending[objective as usize]);
        let Some(p) = g.as_deref_mut() else {
            return Ok(cell.get());
        };
        match p.advance(foon, self, None, stop)? {
            Reached::End => {
                let o = g.take().map(|p| p.finish());
                // Kept before the lock is released: a thread that finds no pending update
                // then finds the optimum.
                Ok(o.map(|o| cell.get_or_init(|| o)))
            }
            Reached::Settled | Reached::TooFar => {
                *g = None;
                Ok(None)
            }
        }
    }

    /// Runs to the end the updates a kitchen derived by a delta ([`Prepared::with_delta`])
    /// keeps pending: the optimal objectives the kitchen it was derived from had computed,
    /// which plans otherwise update only as far as their goals need. Plans of many goals at
    /// once do this first; a caller that will plan many goals one by one, from several
    /// threads, or wants the later plans' times even, can do it once. `cancel` is called now
    /// and then; once it answers true the updates stop where they are (to go on later) and
    /// [`Error::Cancelled`] is returned.
    pub fn finish_updates(&self, foon: &Foon, cancel: &(dyn Fn() -> bool + Sync)) -> Result<()> {
        self.check_foon(foon)?;
        self.finish_all_pending(foon, &|| {
            if cancel() {
                Err(Error::Cancelled)
            } else {
                Ok(())
            }
        })
    }

    /// Runs every pending update to the end, at once on the core's pool (for work that will
    /// read many goals' trees: a batch of plans).
    pub(crate) fn finish_all_pending(
        &self,
        foon: &Foon,
        stop: &(dyn Fn() -> Result<()> + Sync),
    ) -> Result<()> {
        self.finish_pending_of(foon, &Objective::ALL, stop)
    }

    /// Runs the pending updates of `objectives` to the end, at once on the core's pool.
    pub(crate) fn finish_pending_of(
        &self,
        foon: &Foon,
        objectives: &[Objective],
        stop: &(dyn Fn() -> Result<()> + Sync),
    ) -> Result<()> {
        use rayon::prelude::*;
        let todo: Vec<Objective> = objectives
            .iter()
            .copied()
            .filter(|&o| self.has_pending(o))
            .collect();
        match todo.len() {
            0 => Ok(()),
            1 => self.finish_pending(foon, todo[0], stop).map(|_| ()),
            _ => crate::search::batch::in_pool(|| {
                todo.par_iter()
                    .try_for_each(|&o| self.finish_pending(foon, o, stop).map(|_| ()))
            })?,
        }
    }

    /// Whether the optimum of `objective` is computed.
    pub(crate) fn has_optimum(&self, objective: Objective) -> bool {
        self.optima[objective as usize].get().is_some()
    }

    /// Whether the optimum of `objective` has a pending update.
    pub(crate) fn has_pending(&self, objective: Objective) -> bool {
        lock(&self.pending[objective as usize]).is_some()
    }

    /// Whether the pending update of `objective` has started (and not run to the end).
    #[cfg(test)]
    pub(crate) fn pending_started(&self, objective: Objective) -> bool {
        lock(&self.pending[objective as usize])
            .as_deref()
            .is_some_and(Pending::started)
    }

    /// Sets the pending update of `objective` (a kitchen just derived, `incremental.rs`).
    pub(crate) fn set_pending(&self, objective: Objective, p: Pending) {
        *lock(&self.pending[objective as usize]) = Some(Box::new(p));
    }

    /// A copy of the pending update of `objective`'s parts, to derive another kitchen from
    /// (see [`Pending::derive`]).
    pub(crate) fn with_pending<T>(
        &self,
        objective: Objective,
        f: impl FnOnce(Option<&Pending>) -> T,
    ) -> T {
        f(lock(&self.pending[objective as usize]).as_deref())
    }

    /// The choice of `ids` for every object, computed by `init` on first use.
    pub(crate) fn ids_choice(
        &self,
        init: impl FnOnce() -> Result<Vec<u32>>,
    ) -> Result<&Layered<u32>> {
        once(&self.ids_choice, || init().map(Layered::from_vec))
    }

    /// The producer order of greedy heuristic `which` (`0..Greedy::COUNT`), computed by
    /// `init` on first use, once per base (shared by every kitchen prepared on it).
    pub(crate) fn greedy(
        &self,
        which: usize,
        init: impl FnOnce() -> Result<Greedy>,
    ) -> Result<&Greedy> {
        once(&self.base.greedy[which], init)
    }

    /// The ranks, when computed already.
    pub(crate) fn computed_ranks(&self) -> Option<&Ranks> {
        self.ranks.get()
    }

    /// The optimum of `objective`, when computed already.
    pub(crate) fn computed_optimum(&self, objective: Objective) -> Option<&Optimum> {
        self.optima[objective as usize].get()
    }

    /// The choice of `ids`, when computed already.
    pub(crate) fn computed_ids_choice(&self) -> Option<&Layered<u32>> {
        self.ids_choice.get()
    }

    /// A kitchen prepared on this one's base and level from its flags and objects (in id
    /// order), nothing computed yet (see [`Prepared::set_computed`] and `incremental.rs`).
    pub(crate) fn with_parts(&self, in_kitchen: Layered<bool>, kitchen_objects: Vec<u32>) -> Self {
        Self {
            foon: self.foon,
            base: Arc::clone(&self.base),
            in_kitchen,
            derived: true,
            kitchen_objects,
            ranks: OnceLock::new(),
            optima: Default::default(),
            pending: Default::default(),
            ids_choice: OnceLock::new(),
            level: self.level,
            kbest: crate::search::kbest::AncestryCache::default(),
        }
    }

    /// Sets what is computed already (each must be that of this kitchen); a part already
    /// set is kept.
    pub(crate) fn set_computed(
        &self,
        ranks: Option<Ranks>,
        optima: [Option<Optimum>; Objective::COUNT],
        ids_choice: Option<Layered<u32>>,
    ) {
        if let Some(r) = ranks {
            let _ = self.ranks.set(r);
        }
        for (cell, o) in self.optima.iter().zip(optima) {
            if let Some(o) = o {
                let _ = cell.set(o);
            }
        }
        if let Some(c) = ids_choice {
            let _ = self.ids_choice.set(c);
        }
    }

    /// Ranks from the kitchen plus the objects marked in `extra`.
    pub(crate) fn ranks_with(&self, foon: &Foon, extra: &[bool]) -> Ranks {
        forward::ranks(foon, self, Some(extra))
    }
}

impl PreparedBase {
    /// The kitchen-independent inputs for `foon` (see [`Prepared::new`] for `utensils`,
    /// `rates` and `default_rate`): the container rule applied to every FU, the FUs that need
    /// each object, every FU's rate. Linear in the FOON.
    pub fn new(
        foon: &Foon,
        utensils: &[String],
        rates: Option<&MotionRates>,
        default_rate: Option<f64>,
    ) -> Result<Self> {
        if let Some(r) = default_rate {
            check_rate(None, r)?;
        }
        let n = foon.object_count();
        let utensil_ids: FxHashSet<u32> = utensils
            .iter()
            .filter_map(|u| foon.strings().get(u))
            .collect();
        let needed = needed_inputs(foon, &utensil_ids);
        let n_fu = foon.fu_count() as u32;
        let needed_by = Csr::from_pairs(
            n,
            (0..n_fu).flat_map(|f| {
                let row = needed.row(f);
                let k = row.first().map_or(0, |&k| k as usize);
                row.get(1..=k).unwrap_or(&[]).iter().map(move |&o| (o, f))
            }),
        );
        let fu_rate: Vec<f64> = (0..n_fu)
            .map(|f| {
                rates
                    .and_then(|r| r.get(foon.motion_text(f)))
                    .or(default_rate)
                    .unwrap_or(f64::NAN)
            })
            .collect();
        let all_rated = fu_rate.iter().all(|r| !r.is_nan());
        let mut bare = vec![0u64; n.div_ceil(64)];
        for o in 0..n as u32 {
            if foon.is_bare(o) {
                bare[o as usize >> 6] |= 1 << (o & 63);
            }
        }
        Ok(Self {
            foon: foon.fingerprint(),
            key: Self::key_of(utensils, rates, default_rate),
            object_count: n,
            needed,
            needed_by,
            fu_rate,
            rates_given: rates.is_some() || default_rate.is_some(),
            all_rated,
            bare,
            greedy: Default::default(),
        })
    }

    /// A fixed-width key of the inputs a base is built from besides the FOON, the same on
    /// every platform: XXH3-128 of the utensils (sorted, each once), the rate table (sorted
    /// by motion, each rate's bits) and the default rate, every string length-prefixed and
    /// every number little-endian. Equal inputs give equal keys; the order of the utensils
    /// and of the table does not matter.
    pub fn key_of(
        utensils: &[String],
        rates: Option<&MotionRates>,
        default_rate: Option<f64>,
    ) -> u128 {
        let mut bytes: Vec<u8> = b"foon-base-1".to_vec();
        let put_str = |bytes: &mut Vec<u8>, s: &str| {
            bytes.extend_from_slice(&(s.len() as u64).to_le_bytes());
            bytes.extend_from_slice(s.as_bytes());
        };
        let mut us: Vec<&str> = utensils.iter().map(String::as_str).collect();
        us.sort_unstable();
        us.dedup();
        bytes.extend_from_slice(&(us.len() as u64).to_le_bytes());
        for u in us {
            put_str(&mut bytes, u);
        }
        match rates {
            None => bytes.push(0),
            Some(r) => {
                bytes.push(1);
                let mut es: Vec<(&str, f64)> =
                    r.entries.iter().map(|(m, v)| (m.as_str(), *v)).collect();
                es.sort_unstable_by(|a, b| a.0.cmp(b.0));
                bytes.extend_from_slice(&(es.len() as u64).to_le_bytes());
                for (m, v) in es {
                    put_str(&mut bytes, m);
                    bytes.extend_from_slice(&v.to_bits().to_le_bytes());
                }
            }
        }
        match default_rate {
            None => bytes.push(0),
            Some(r) => {
                bytes.push(1);
                bytes.extend_from_slice(&r.to_bits().to_le_bytes());
            }
        }
        xxhash_rust::xxh3::xxh3_128(&bytes)
    }

    /// The key of the utensils, rates and default rate this base was built from
    /// ([`PreparedBase::key_of`]).
    pub fn key(&self) -> u128 {
        self.key
    }

    /// The content fingerprint of the FOON this base was built for.
    pub fn foon_fingerprint(&self) -> [u8; 16] {
        self.foon
    }

    /// Errors when this base was built for another FOON than `foon`.
    pub(crate) fn check_foon(&self, foon: &Foon) -> Result<()> {
        if self.foon != foon.fingerprint() || self.object_count != foon.object_count() {
            return Err(Error::Invalid(
                "these planning inputs were prepared for another FOON".into(),
            ));
        }
        Ok(())
    }

    /// Needed inputs of `fu` (after the container rule).
    #[inline]
    pub fn needed(&self, fu: u32) -> &[u32] {
        self.flow(fu).0
    }

    /// Needed inputs of `fu` (after the container rule) and its outputs that are not bare.
    #[inline]
    pub(crate) fn flow(&self, fu: u32) -> (&[u32], &[u32]) {
        self.flows().flow(fu)
    }

    /// The FUs where `o` is a needed input (one entry per slot).
    #[inline]
    pub(crate) fn needed_by(&self, o: u32) -> &[u32] {
        self.needed_by.row(o)
    }

    #[inline]
    pub(crate) fn flows(&self) -> Flows<'_> {
        Flows {
            needed: self.needed.view(),
            needed_by: self.needed_by.view(),
        }
    }

    /// Heap bytes of the base (what it has computed so far included).
    pub fn heap_bytes(&self) -> usize {
        let mut b =
            self.needed.heap_bytes() + self.needed_by.heap_bytes() + 8 * self.fu_rate.capacity();
        for g in self.greedy.iter().filter_map(OnceLock::get) {
            b += g.order.heap_bytes() + 4 * g.first.capacity();
        }
        b
    }
}

/// The rows of a [`PreparedBase`] that passes over units read ([`Prepared::flows`]): each
/// unit's needed inputs and outputs that are not bare, and each object's units.
#[derive(Clone, Copy)]
pub(crate) struct Flows<'a> {
    needed: Rows<'a>,
    needed_by: Rows<'a>,
}

impl<'a> Flows<'a> {
    /// Needed inputs of `fu` (after the container rule) and its outputs that are not bare.
    #[inline]
    pub(crate) fn flow(self, fu: u32) -> (&'a [u32], &'a [u32]) {
        match self.needed.row(fu).split_first() {
            Some((&k, rest)) => rest.split_at((k as usize).min(rest.len())),
            None => (&[], &[]),
        }
    }

    /// [`Prepared::needed_by`].
    #[inline]
    pub(crate) fn needed_by(self, o: u32) -> &'a [u32] {
        self.needed_by.row(o)
    }

    /// Brings in where the row of [`Flows::needed_by`] of `o` starts, or the row (reading
    /// where it starts) with `row` (a hint).
    #[inline]
    pub(crate) fn prefetch_needed_by(self, o: u32, row: bool) {
        self.needed_by.prefetch(o, row);
    }

    /// Brings in where the row of [`Flows::flow`] of `fu` starts, or the row (reading where
    /// it starts) with `row` (a hint).
    #[inline]
    pub(crate) fn prefetch_flow(self, fu: u32, row: bool) {
        self.needed.prefetch(fu, row);
    }

    /// Calls `visit` on the row of [`Flows::flow`] of each unit of `units` in order
    /// ([`Ahead::Now`]), and before, as a pipeline, on the row of the unit a few steps ahead
    /// ([`Ahead::Far`]) so that it can bring in the values it will read (the rows themselves,
    /// and where they start, are brought in before that): the misses of several units
    /// overlap instead of each waiting for the one before. Each row is read once.
    #[inline]
    pub(crate) fn each_flow_ahead(
        self,
        units: &[u32],
        mut visit: impl FnMut(Ahead, u32, &'a [u32], &'a [u32]),
    ) {
        const FAR: usize = 2 * AHEAD;
        // The rows of the units between the one computed and the one brought in.
        let mut rows: [(&'a [u32], &'a [u32]); FAR] = [(&[], &[]); FAR];
        for (i, &g) in units.iter().take(4 * AHEAD).enumerate() {
            self.prefetch_flow(g, false);
            if let Some(row) = rows.get_mut(i) {
                let (needed, outputs) = self.flow(g);
                visit(Ahead::Far, g, needed, outputs);
                *row = (needed, outputs);
            }
        }
        for (i, &f) in units.iter().enumerate() {
            if let Some(&g) = units.get(i + 4 * AHEAD) {
                self.prefetch_flow(g, false);
            }
            if let Some(&g) = units.get(i + 3 * AHEAD) {
                self.prefetch_flow(g, true);
            }
            let (needed, outputs) = rows[i % FAR];
            visit(Ahead::Now, f, needed, outputs);
            if let Some(&g) = units.get(i + FAR) {
                let (needed, outputs) = self.flow(g);
                visit(Ahead::Far, g, needed, outputs);
                rows[i % FAR] = (needed, outputs);
            }
        }
    }
}

/// Needed inputs of every FU, each row as [`PreparedBase`] keeps it (their number, the
/// inputs, the outputs that are not bare): the container rule removes an input whose label
/// is a utensil and whose ingredients are exactly `[x]` when another input of the FU is
/// labelled `x` and sits in that utensil. Linear in the inputs: the (label, container) pairs
/// of an FU's inputs are counted once, and an input's own pair is not "another input".
fn needed_inputs(foon: &Foon, utensils: &FxHashSet<u32>) -> Csr {
    let mut out = Csr::new();
    let mut row = Vec::new();
    let mut held: FxHashMap<(u32, u32), u32> = FxHashMap::default();
    for f in 0..foon.fu_count() as u32 {
        let ins = foon.inputs(f);
        row.clear();
        row.push(0);
        // Only an input that holds one ingredient in a utensil can be skipped.
        let holder = |o: u32| foon.ingredients(o).len() == 1 && utensils.contains(&foon.label(o));
        if ins.iter().any(|&o| holder(o)) {
            held.clear();
            for &p in ins {
                let c = foon.container(p);
                if c != NONE {
                    *held.entry((foon.label(p), c)).or_default() += 1;
                }
            }
            for &o in ins {
                let skip = holder(o) && {
                    let pair = (foon.ingredients(o)[0], foon.label(o));
                    let own = u32::from((foon.label(o), foon.container(o)) == pair);
                    held.get(&pair).copied().unwrap_or(0) > own
                };
                if !skip {
                    row.push(o);
                }
            }
        } else {
            row.extend_from_slice(ins);
        }
        row[0] = (row.len() - 1) as u32;
        row.extend(
            foon.outputs(f)
                .iter()
                .copied()
                .filter(|&o| !foon.is_bare(o)),
        );
        out.push_row(&row);
    }
    out
}

#[cfg(test)]
mod tests {
    use std::fmt::Write as _;

    use rustc_hash::FxHashSet;

    use super::needed_inputs;
    use crate::index::Foon;
    use crate::parse::{ParseOptions, parse_foon};

    /// The container rule as written in `docs/METHODS.md`: for each input, look at every other
    /// position of the FU's input list.
    fn quadratic(foon: &Foon, utensils: &FxHashSet<u32>, f: u32) -> Vec<u32> {
        let ins = foon.inputs(f);
        let mut row = Vec::new();
        for (i, &o) in ins.iter().enumerate() {
            let ing = foon.ingredients(o);
            let skip = ing.len() == 1
                && utensils.contains(&foon.label(o))
                && ins.iter().enumerate().any(|(j, &p)| {
                    j != i && foon.label(p) == ing[0] && foon.container(p) == foon.label(o)
                });
            if !skip {
                row.push(o);
            }
        }
        row
    }

    /// Planning inputs belong to the FOON they were prepared for: another FOON with the same
    /// counts (one unit, two objects) is told apart by its content fingerprint.
    #[test]
    fn prepared_inputs_are_keyed_by_the_fingerprint() {
        let a = parse_foon(
            b"O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n",
            None,
            ParseOptions::default(),
        )
        .unwrap();
        let b = parse_foon(
            b"O\tegg\nS\twhole\nM\tboil\nO\tegg\nS\tboiled\n//\n",
            None,
            ParseOptions::default(),
        )
        .unwrap();
        assert_eq!(
            (a.fu_count(), a.object_count()),
            (b.fu_count(), b.object_count())
        );
        let prep = super::Prepared::new(&a, &[], &[], None, None).unwrap();
        assert!(crate::search::Context::with(&a, &prep).is_ok());
        assert!(crate::search::Context::with(&b, &prep).is_err());
    }

    /// The linear container rule gives the quadratic definition's needed inputs on random
    /// FUs: utensils holding one or two ingredients, inputs in the right or another container,
    /// a utensil that holds itself and sits in itself, the same input several times.
    #[test]
    fn linear_container_rule_matches_the_definition() {
        const LABELS: [&str; 5] = ["bowl", "pot", "egg", "salt", "bowl2"];
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = |n: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % n) as usize
        };
        let mut skipped = 0;
        for round in 0..300 {
            let mut text = String::new();
            for _ in 0..=next(6) {
                let mut objs: Vec<String> = Vec::new();
                for _ in 0..next(12) {
                    let mut o = format!("O\t{}\n", LABELS[next(5)]);
                    match next(4) {
                        0 => {}
                        1 => {
                            let _ = writeln!(o, "S\tcontains\t{{{}}}", LABELS[next(5)]);
                        }
                        2 => {
                            let (a, b) = (LABELS[next(5)], LABELS[next(5)]);
                            let _ = writeln!(o, "S\tcontains\t{{{a},{b}}}");
                        }
                        _ => {
                            let _ = writeln!(o, "S\tcontains\t{{{}}}", LABELS[next(5)]);
                            let _ = writeln!(o, "S\tin\t[{}]", LABELS[next(5)]);
                        }
                    }
                    if next(2) == 0 {
                        let _ = writeln!(o, "S\tin\t[{}]", LABELS[next(5)]);
                    }
                    if next(3) == 0 && !objs.is_empty() {
                        o = objs[next(objs.len() as u64)].clone(); // a duplicate input
                    }
                    objs.push(o);
                }
                for o in &objs {
                    text.push_str(o);
                }
                text.push_str("M\tmix\nO\tdone\nS\tx\n//\n");
            }
            let foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
            let utensils: FxHashSet<u32> = ["bowl", "pot", "bowl2"]
                .iter()
                .take(1 + round % 3)
                .filter_map(|u| foon.strings().get(u))
                .collect();
            let linear = needed_inputs(&foon, &utensils);
            for f in 0..foon.fu_count() as u32 {
                // The row: the count k, the k needed inputs, the outputs that are not bare.
                let row = linear.row(f);
                let k = row[0] as usize;
                assert_eq!(&row[1..=k], quadratic(&foon, &utensils, f), "{text}");
                let outputs: Vec<u32> = foon
                    .outputs(f)
                    .iter()
                    .copied()
                    .filter(|&o| !foon.is_bare(o))
                    .collect();
                assert_eq!(&row[k + 1..], &outputs[..]);
                skipped += foon.inputs(f).len() - k;
            }
        }
        assert!(skipped > 100, "the rule skipped only {skipped} inputs");
    }
}
