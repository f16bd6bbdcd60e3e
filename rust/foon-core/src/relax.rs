//! The pass that moves per-object values (ranks, or one optimal objective's costs) from a
//! kitchen to the same kitchen changed at a few objects, touching only what the change
//! reaches, and that can stop and go on: it settles objects in (value, depth) order, so it
//! can run only as far as one goal needs (`incremental.rs` keeps it half-run in a prepared
//! kitchen and runs it further, or to the end, on later use).
//!
//! Ranks and each optimal objective's (cost, depth) are the least fixpoint of superior
//! functions (a unit's value is above each of its needed inputs', and never decreases when
//! one of them increases), so a change of the leaves moves only the values that depend on it:
//!
//! - the *affected* objects are the leaves removed (and the leaves added whose leaf value is
//!   not below their value before, as with an object some unit makes from nothing at cost 0
//!   when a leaf costs 1) and every object whose choice (the producer that achieves its
//!   value before the change) needs an affected object: every other object keeps a tree that
//!   the change leaves intact or cheaper, so its value can only decrease;
//! - the affected objects are reset, seeded from their producers whose needed inputs are all
//!   unaffected, and one run of Knuth's algorithm in (value, depth) order goes from them and
//!   from the other new leaves through the units of every object it settles, lowering what
//!   it reaches (Ramalingam and Reps's algorithm for both kinds of change at once).
//!
//! The choices follow from the final values alone (the lowest-index producer whose (value,
//! depth) is the object's, `docs/METHODS.md`) and every sum is formed as from scratch (the
//! unit's weight, then its inputs in input order), so the values, depths and choices are
//! bit-identical to a computation from scratch.
//!
//! **Stopping early.** A unit's (value, depth) is strictly above each of its needed inputs'
//! (the tie depth, `search::optimal::tie_depth`), so every value still to be found is above
//! the least key in the queue (the *frontier*). An object whose current (value, depth) is at
//! most the frontier's is final, choice included (an offer that could tie it would come from
//! an input settled later, so it would be strictly above). A goal is *settled* once that
//! holds for it, and then so does every object of its tree (each strictly below it): a plan
//! can be read before the pass has run to the end.
//!
//! **Levels.** For the same reason every object queued at the least key is final at once:
//! the pass settles them together, in any order, and computes each unit they are needed by
//! once (a unit two of them are needed by is not computed twice). The final values do not
//! depend on the order of the offers (the choice is the least of them in (value, depth,
//! producer) order).
//!
//! The pass keeps the values it changed apart (a hash map, then arrays once they are many,
//! marked by one bit per object) and reads every other value from the values before the
//! change, so it costs what it reaches:
//! O((A + L) log A) plus the needed and output slots of the units it reaches, for A affected
//! and L lowered objects.

use rustc_hash::FxHashMap;

use crate::error::Result;
use crate::hint::{AHEAD, Ahead};
use crate::index::{Foon, NONE};
use crate::prepare::{Prepared, Slot};
use crate::search::optimal::{Entry, better, lower, tie_depth};
use crate::search::radix::RadixQueue;

/// How a unit's value follows from its needed inputs' values.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Combine {
    /// The unit's weight plus its inputs' costs, in input order; the depth is the tie key.
    Sum,
    /// One more than the largest rank of its inputs; depth 0.
    Rank,
}

/// One kind of value's rules for a pass, and the values before the change.
pub(crate) trait Rules: Sync {
    const COMBINE: Combine;
    /// Whether choices are kept with the values (else an offer that only ties is no change).
    const CHOICES: bool;
    /// Whether the pass keeps the value of each unit it computes ([`Relax::unit_values`]).
    const UNIT_VALUES: bool = false;
    /// The (value, depth) of `o` before the change (`f64::INFINITY` when it had none) and its
    /// choice as kept with the values (`NONE` when none is kept: ties are then broken by the
    /// pass alone, which values do not depend on).
    fn before(&self, o: u32) -> Slot;
    /// The producer that achieves `o`'s value before the change (`NONE` for a leaf or an
    /// object without a finite value): what decides whether `o` is affected.
    fn old_choice(&self, o: u32) -> u32;
    /// Whether `o` is a leaf before and after the change.
    fn was_leaf(&self, o: u32) -> bool;
    fn is_leaf(&self, o: u32) -> bool;
    /// The (value, depth) of a leaf.
    fn leaf(&self) -> (f64, u32);
    /// The weight of unit `f` ([`Combine::Sum`]).
    fn weight(&self, f: u32) -> f64;
    /// Brings in what [`Rules::before`] reads for `o` (a hint).
    #[inline]
    fn prefetch(&self, _o: u32) {}
    /// Brings in what [`Rules::is_leaf`] reads for `o` (a hint).
    #[inline]
    fn prefetch_leaf(&self, _o: u32) {}
}

/// No value: an object the pass reset, or one it found no finite value for.
const NO_SLOT: Slot = Slot {
    cost: f64::INFINITY,
    choice: NONE,
    depth: 0,
};

/// Whether bit `o` of `bits` is set.
#[inline]
fn bit(bits: &[u64], o: u32) -> bool {
    (bits[o as usize >> 6] >> (o & 63)) & 1 != 0
}

#[inline]
fn set_bit(bits: &mut [u64], o: u32) {
    bits[o as usize >> 6] |= 1 << (o & 63);
}

/// The values the pass changed: in a hash map (marked by one bit per object) while they are
/// few, then in an array over every object once they pass a share of the FOON
/// ([`DENSE_SHARE`]): no rehash as they grow, one read per value, and the array (16 bytes per
/// object, allocated zeroed: a page is mapped when first written) is kept for the next pass
/// once this one ends ([`DENSE_POOL`]). Two more bits per object mark the objects the pass
/// reset (*affected*) and those it settled (*done*).
struct Changed {
    /// One bit per object: whether it is present (read first: it stays in the caches).
    bits: Vec<u64>,
    affected: Vec<u64>,
    done: Vec<u64>,
    values: Values,
}

enum Values {
    Sparse(FxHashMap<u32, Slot>),
    /// Per object, its value (read only where `bits` says the object is present); the
    /// objects present, in the order they were first changed.
    Dense {
        slots: Direct,
        present: Vec<u32>,
    },
}

/// A value as a dense store keeps it: the cost's bits, then the choice and the depth.
type Packed = [u64; 2];

#[inline]
fn pack(s: Slot) -> Packed {
    [
        s.cost.to_bits(),
        u64::from(s.choice) | (u64::from(s.depth) << 32),
    ]
}

#[inline]
fn unpack([c, cd]: Packed) -> Slot {
    Slot {
        cost: f64::from_bits(c),
        choice: cd as u32,
        depth: (cd >> 32) as u32,
    }
}

/// The bytes of the values `v`.
fn size_of_values(v: &[Packed]) -> usize {
    std::mem::size_of_val(v)
}

/// The values of a dense store, one per object, kept for the next pass when this one ends
/// (see [`DENSE_POOL`]).
struct Direct(Vec<Packed>);

/// Arrays of passes that ended, kept for the next passes over a FOON of the same size (a
/// few, as many as passes run at once in a batch, and at most [`DENSE_POOL_BYTES`] in all:
/// the memory they hold after the last pass). A pass that reaches objects all over the FOON
/// writes in most pages of its array, and the system zeroes each page as it is first
/// touched; a kept array costs none of that. What an earlier pass left in it is never read:
/// a value is read only for an object that `bits` marks present, and every such object's
/// value was written by this pass.
static DENSE_POOL: std::sync::Mutex<Vec<Vec<Packed>>> = std::sync::Mutex::new(Vec::new());
const DENSE_POOL_KEEP: usize = 4;
const DENSE_POOL_BYTES: usize = 64 << 20;

impl Direct {
    /// An array of `len` values: a kept one, else a new one (zeroed, mapped on first use).
    fn take(len: usize) -> Self {
        let kept = DENSE_POOL.lock().ok().and_then(|mut pool| {
            let i = pool.iter().position(|m| m.len() == len)?;
            Some(pool.swap_remove(i))
        });
        Self(kept.unwrap_or_else(|| vec![[0; 2]; len]))
    }

    /// Bytes held.
    fn bytes(&self) -> usize {
        size_of_values(&self.0)
    }
}

impl Drop for Direct {
    fn drop(&mut self) {
        // An array larger than the whole pool is not kept; the oldest make room for another.
        let m = std::mem::take(&mut self.0);
        if size_of_values(&m) <= DENSE_POOL_BYTES
            && let Ok(mut pool) = DENSE_POOL.lock()
        {
            while !pool.is_empty()
                && (pool.len() >= DENSE_POOL_KEEP
                    || pool.iter().map(|k| size_of_values(k)).sum::<usize>() + size_of_values(&m)
                        > DENSE_POOL_BYTES)
            {
                pool.remove(0);
            }
            pool.push(m);
        }
    }
}

/// A pass that changes more than one object in `DENSE_SHARE` of the FOON (and more than
/// `DENSE_FROM`) keeps them in arrays. (The unit tests' FOONs are small: they take the
/// arrays from 4 objects, so that both ways run.)
const DENSE_FROM: usize = if cfg!(test) { 4 } else { 4096 };
const DENSE_SHARE: usize = 64;

impl Changed {
    fn new(n: usize) -> Self {
        let words = n.div_ceil(64);
        Self {
            bits: vec![0; words],
            affected: vec![0; words],
            done: vec![0; words],
            values: Values::Sparse(FxHashMap::default()),
        }
    }

    #[inline]
    fn has(&self, o: u32) -> bool {
        bit(&self.bits, o)
    }

    #[inline]
    fn is_affected(&self, o: u32) -> bool {
        bit(&self.affected, o)
    }

    #[inline]
    fn is_done(&self, o: u32) -> bool {
        bit(&self.done, o)
    }

    /// The value of `o`, present or not (read only where `bits` says it is).
    #[inline]
    fn value(&self, o: u32) -> Slot {
        match &self.values {
            Values::Sparse(map) => map.get(&o).copied().unwrap_or(NO_SLOT),
            Values::Dense { slots, .. } => unpack(slots.0[o as usize]),
        }
    }

    #[inline]
    fn get(&self, o: u32) -> Option<Slot> {
        self.has(o).then(|| self.value(o))
    }

    /// Brings in the value of `o` when it is present in the array (a hint). Whether `o` is
    /// present (its value is then read here, not from the values before the change).
    #[inline]
    fn prefetch(&self, o: u32) -> bool {
        if !self.has(o) {
            return false;
        }
        if let Values::Dense { slots, .. } = &self.values {
            crate::hint::prefetch(&slots.0[o as usize]);
        }
        true
    }

    #[inline]
    fn put(&mut self, o: u32, l: Slot) {
        let new = !self.has(o);
        set_bit(&mut self.bits, o);
        match &mut self.values {
            Values::Sparse(map) => {
                map.insert(o, l);
                let n = self.bits.len() * 64;
                if map.len() > DENSE_FROM.max(n / DENSE_SHARE) {
                    self.densify(n);
                }
            }
            Values::Dense { slots, present } => {
                if new {
                    present.push(o);
                }
                slots.0[o as usize] = pack(l);
            }
        }
    }

    /// Moves the changes of a sparse store into arrays over the `n` (rounded) objects.
    #[cold]
    fn densify(&mut self, n: usize) {
        let Values::Sparse(map) = &mut self.values else {
            return;
        };
        let mut slots = Direct::take(n);
        let map = std::mem::take(map);
        let mut present = Vec::with_capacity(4 * map.len());
        for (o, l) in map {
            slots.0[o as usize] = pack(l);
            present.push(o);
        }
        self.values = Values::Dense { slots, present };
    }

    /// The number of objects present.
    fn len(&self) -> usize {
        match &self.values {
            Values::Sparse(map) => map.len(),
            Values::Dense { present, .. } => present.len(),
        }
    }

    /// Every object present, with its value.
    fn into_iter(self) -> Box<dyn Iterator<Item = (u32, Slot)>> {
        match self.values {
            Values::Sparse(map) => Box::new(map.into_iter()),
            Values::Dense { slots, present } => Box::new(
                present
                    .into_iter()
                    .map(move |o| (o, unpack(slots.0[o as usize]))),
            ),
        }
    }

    fn heap_bytes(&self) -> usize {
        8 * (self.bits.capacity() + self.affected.capacity() + self.done.capacity())
            + match &self.values {
                Values::Sparse(map) => (std::mem::size_of::<(u32, Slot)>() + 1) * map.capacity(),
                // The array's pages touched, at most: one per object present.
                Values::Dense { slots, present } => {
                    4 * present.capacity() + slots.bytes().min(4096 * present.len())
                }
            }
    }
}

/// How often a pass calls its `stop` callback: when it starts to run and then after every
/// `STOP_EVERY` objects, between two levels (every level in the unit tests, so that they stop
/// passes anywhere).
const STOP_EVERY: usize = if cfg!(test) { 1 } else { 4096 };

/// How far [`Relax::advance`] went.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Reached {
    /// The goal asked for is settled; the pass can go on.
    Settled,
    /// The pass ran to the end: every value is final.
    End,
    /// The pass reached more objects than its limit: what it computed is to be dropped.
    TooFar,
}

/// A pass under way (see the module documentation).
pub(crate) struct Relax {
    local: Changed,
    queue: RadixQueue,
    /// The affected objects.
    affected: Vec<u32>,
    /// Objects settled that were not affected (lowered, or offered a tie).
    lowered: usize,
    end: bool,
    /// The objects of the level being settled, and the units they are needed by, each once
    /// (kept to be reused); one bit per unit, set while it is in `units`.
    level: Vec<u32>,
    units: Vec<u32>,
    unit_bits: Vec<u64>,
    /// The value of each unit computed, in the order computed (with [`Rules::UNIT_VALUES`]).
    unit_values: Vec<(u32, f64)>,
}

impl Relax {
    /// Starts a pass from the values of `rules` to those of the leaves after the change,
    /// the leaves that changed being among `flipped` (object ids, any order): marks the
    /// affected objects (read before any value changes), resets and seeds them. `None` when
    /// more than `limit` objects are affected.
    pub(crate) fn start<R: Rules>(
        foon: &Foon,
        prep: &Prepared,
        rules: &R,
        flipped: &[u32],
        limit: usize,
    ) -> Option<Self> {
        let n = foon.object_count();
        let mut r = Self {
            local: Changed::new(n),
            queue: RadixQueue::by_key(),
            affected: Vec::new(),
            lowered: 0,
            end: false,
            level: Vec::new(),
            units: Vec::new(),
            unit_bits: vec![0; foon.fu_count().div_ceil(64)],
            unit_values: Vec::new(),
        };
        // A leaf removed (or added with a value not below its value before) may raise what
        // is made from it; a leaf added below its value before only lowers it (seeded below).
        let (leaf, leaf_depth) = rules.leaf();
        let lowers = |o: u32| {
            let b = rules.before(o);
            rules.is_leaf(o) && lower(leaf, leaf_depth, b.cost, b.depth)
        };
        for &o in flipped {
            if rules.was_leaf(o) != rules.is_leaf(o) && !lowers(o) && !r.local.is_affected(o) {
                r.reset(o);
            }
        }
        // Every object whose choice needs an affected object, transitively.
        let mut i = 0;
        while let Some(&x) = r.affected.get(i) {
            i += 1;
            if r.affected.len() > limit {
                return None;
            }
            for &f in prep.needed_by(x) {
                for &y in foon.outputs(f) {
                    if !r.local.is_affected(y) && rules.old_choice(y) == f {
                        r.reset(y);
                    }
                }
            }
        }
        let leaf_slot = Slot {
            cost: leaf,
            choice: NONE,
            depth: leaf_depth,
        };
        let leaf_entry = |obj| Entry {
            cost: leaf,
            depth: leaf_depth,
            obj,
        };
        for &o in flipped {
            if !rules.was_leaf(o) && lowers(o) && !r.local.is_affected(o) {
                r.local.put(o, leaf_slot);
                r.queue.push(leaf_entry(o));
            }
        }
        for i in 0..r.affected.len() {
            let y = r.affected[i];
            if rules.is_leaf(y) {
                r.local.put(y, leaf_slot);
                r.queue.push(leaf_entry(y));
            } else if !prep.is_bare(y) {
                for &f in foon.producers(y) {
                    if let Some((c, d)) = r.unit(rules, f, prep.needed(f)) {
                        r.offer(rules, y, f, c, d);
                    }
                }
            }
        }
        Some(r)
    }

    /// The current (value, depth) and choice of `o` (final once [`Relax::is_settled`]).
    #[inline]
    pub(crate) fn get<R: Rules>(&self, rules: &R, o: u32) -> Slot {
        self.changed(o).unwrap_or_else(|| rules.before(o))
    }

    /// The value of `o` when the pass changed it (else it is the value before the change).
    #[inline]
    pub(crate) fn changed(&self, o: u32) -> Option<Slot> {
        self.local.get(o)
    }

    /// Whether the value and choice of `o` are final.
    pub(crate) fn is_settled<R: Rules>(&mut self, rules: &R, o: u32) -> bool {
        if self.end {
            return true;
        }
        if self.local.is_done(o) {
            return true;
        }
        let s = self.get(rules, o);
        match self.queue.peek() {
            None => true,
            Some(top) => !lower(top.cost, top.depth, s.cost, s.depth),
        }
    }

    /// Runs the pass until `goal` is settled (to the end with `None`), a level of equal keys
    /// at a time, calling `stop` as it starts and every few thousand settled objects (its
    /// error stops the pass where it is, to be run again later). Stops with
    /// [`Reached::TooFar`] once more than `limit` objects that were not affected have been
    /// settled.
    pub(crate) fn advance<R: Rules>(
        &mut self,
        prep: &Prepared,
        rules: &R,
        goal: Option<u32>,
        limit: usize,
        stop: &dyn Fn() -> Result<()>,
    ) -> Result<Reached> {
        if self.end {
            return Ok(Reached::End);
        }
        let flows = prep.flows();
        // Objects to settle before `stop` is next called (a level at a time: between two
        // levels, so that a stopped pass goes on where it stopped).
        let mut until_stop = 1;
        loop {
            if let Some(g) = goal
                && self.is_settled(rules, g)
            {
                return Ok(Reached::Settled);
            }
            if until_stop <= 1 {
                until_stop = STOP_EVERY;
                stop()?;
            }
            let Some(first) = self.queue.pop() else {
                break;
            };
            // Every queued object at the least key is final at once (an offer is strictly
            // above each input's key): they are settled together, and the units they are
            // needed by computed once each.
            let mut level = std::mem::take(&mut self.level);
            level.clear();
            let (cost, depth) = (first.cost, first.depth);
            let mut next = Some(first);
            while let Some(Entry {
                cost: c,
                depth: d,
                obj: o,
            }) = next
            {
                if let Some(l) = self.local.get(o)
                    && !self.local.is_done(o)
                    && (l.cost.to_bits(), l.depth) == (c.to_bits(), d)
                {
                    set_bit(&mut self.local.done, o);
                    if !self.local.is_affected(o) {
                        self.lowered += 1;
                        if self.lowered > limit {
                            return Ok(Reached::TooFar);
                        }
                    }
                    level.push(o);
                }
                if let Some(e) = self.queue.ahead(2 * AHEAD) {
                    self.local.prefetch(e.obj);
                }
                next = self.queue.pop_up_to(cost, depth);
            }
            until_stop = until_stop.saturating_sub(level.len());
            let mut units = std::mem::take(&mut self.units);
            units.clear();
            for (i, &o) in level.iter().enumerate() {
                if let Some(&p) = level.get(i + 2 * AHEAD) {
                    flows.prefetch_needed_by(p, false);
                }
                if let Some(&p) = level.get(i + AHEAD) {
                    flows.prefetch_needed_by(p, true);
                }
                for &f in flows.needed_by(o) {
                    if !bit(&self.unit_bits, f) {
                        set_bit(&mut self.unit_bits, f);
                        units.push(f);
                    }
                }
            }
            for &f in &units {
                self.unit_bits[f as usize >> 6] = 0;
            }
            // One row per unit: its needed inputs and its outputs that are not bare.
            flows.each_flow_ahead(&units, |at, f, needed, outputs| match at {
                Ahead::Far => {
                    for &x in needed {
                        if !self.local.prefetch(x) {
                            rules.prefetch(x);
                        }
                    }
                    for &y in outputs {
                        if !self.local.prefetch(y) {
                            rules.prefetch(y);
                        }
                        rules.prefetch_leaf(y);
                    }
                }
                Ahead::Now => {
                    let value = self.unit(rules, f, needed);
                    if R::UNIT_VALUES {
                        self.unit_values
                            .push((f, value.map_or(f64::INFINITY, |(c, _)| c)));
                    }
                    if let Some((c, d)) = value {
                        for &y in outputs {
                            self.offer(rules, y, f, c, d);
                        }
                    }
                }
            });
            self.level = level;
            self.units = units;
        }
        // Affected objects never reached have no value.
        for i in 0..self.affected.len() {
            let y = self.affected[i];
            if !self.local.is_done(y) {
                self.local.put(y, NO_SLOT);
            }
        }
        self.end = true;
        Ok(Reached::End)
    }

    /// The objects whose value or choice may have changed, with their final values (once
    /// the pass ran to the end).
    pub(crate) fn changes(self) -> impl Iterator<Item = (u32, Slot)> {
        debug_assert!(self.end);
        self.local.into_iter()
    }

    /// The value of every unit the pass computed, once it ran to the end (with
    /// [`Rules::UNIT_VALUES`]), `f64::INFINITY` for none: each unit's value is computed again
    /// whenever one of its needed inputs settles, so the last one computed reads final values
    /// only. A unit needing an object the pass changed is here unless that object was reset
    /// and given no value.
    pub(crate) fn unit_values(&mut self) -> FxHashMap<u32, f64> {
        debug_assert!(self.end);
        std::mem::take(&mut self.unit_values).into_iter().collect()
    }

    /// The number of objects [`Relax::changes`] gives.
    pub(crate) fn changed_count(&self) -> usize {
        self.local.len()
    }

    /// Heap bytes held by the pass.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.local.heap_bytes()
            + 4 * (self.affected.capacity() + self.level.capacity() + self.units.capacity())
            + 8 * self.unit_bits.capacity()
            + std::mem::size_of::<(u32, f64)>() * self.unit_values.capacity()
    }

    /// Marks `o` affected: reset, without a value until the pass gives it one.
    fn reset(&mut self, o: u32) {
        self.local.put(o, NO_SLOT);
        set_bit(&mut self.local.affected, o);
        self.affected.push(o);
    }

    /// The (value, depth) unit `f` offers its outputs from the current values, `None` when
    /// one of its needed inputs has no value yet (an infinite one, or an affected one not
    /// settled) or the value is infinite (a motion of rate 0).
    #[inline]
    fn unit<R: Rules>(&self, rules: &R, f: u32, needed: &[u32]) -> Option<(f64, u32)> {
        let read = |x: u32| -> Option<(f64, u32)> {
            let s = if self.local.has(x) {
                if self.local.is_affected(x) && !self.local.is_done(x) {
                    return None;
                }
                self.local.value(x)
            } else {
                rules.before(x)
            };
            s.cost.is_finite().then_some((s.cost, s.depth))
        };
        match R::COMBINE {
            Combine::Sum => {
                let mut c = rules.weight(f);
                let mut most = f64::NEG_INFINITY;
                for &x in needed {
                    let xc = read(x)?.0;
                    c += xc;
                    most = most.max(xc);
                }
                if c == f64::INFINITY {
                    return None;
                }
                // The tie depth counts inputs that cost exactly the sum: none when the sum is
                // above every input (most units; not always, as a sum may round to an input).
                let d = if c > most {
                    0
                } else {
                    tie_depth(c, needed.iter().filter_map(|&x| read(x)))
                };
                Some((c, d))
            }
            Combine::Rank => {
                let mut m = 0.0f64;
                for &x in needed {
                    m = m.max(read(x)?.0);
                }
                Some((m + 1.0, 0))
            }
        }
    }

    /// Offers `y` the value (`c`, `d`) of unit `f`: kept when it beats `y`'s current one
    /// (queued when strictly lower); a settled `y` and a leaf keep their values (whether `y`
    /// is a leaf is read last: most offers lose before).
    #[inline]
    fn offer<R: Rules>(&mut self, rules: &R, y: u32, f: u32, c: f64, d: u32) {
        let old = if self.local.has(y) {
            if self.local.is_done(y) {
                return;
            }
            self.local.value(y)
        } else {
            rules.before(y)
        };
        let wins = if R::CHOICES {
            better(c, d, f, old.cost, old.depth, old.choice)
        } else {
            lower(c, d, old.cost, old.depth)
        };
        if wins && !rules.is_leaf(y) {
            if !R::CHOICES || lower(c, d, old.cost, old.depth) {
                self.queue.push(Entry {
                    cost: c,
                    depth: d,
                    obj: y,
                });
            }
            self.local.put(
                y,
                Slot {
                    cost: c,
                    choice: f,
                    depth: d,
                },
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A kept array is reused as it was left (its pages not zeroed again), and a store that
    /// takes it reads only the values it wrote; an array larger than the pool is not kept.
    #[test]
    fn kept_arrays_are_reused_and_never_read_stale() {
        // A size no other test's FOON has (the pool is shared by the tests' threads).
        let n = 64 * 15_627;
        let mut a = Direct::take(n);
        a.0.fill([7, 7]);
        drop(a);
        let b = Direct::take(n);
        assert!(b.0.iter().all(|&x| x == [7, 7]), "the kept array is reused");
        drop(b);
        let mut c = Changed::new(n);
        let local = |o: u32| Slot {
            cost: f64::from(o),
            choice: o,
            depth: 0,
        };
        for o in (0..n as u32).step_by(40) {
            c.put(o, local(o));
        }
        assert!(matches!(c.values, Values::Dense { .. }));
        for o in 0..n as u32 {
            match c.get(o) {
                Some(l) => {
                    assert!(o % 40 == 0 && l.cost.to_bits() == f64::from(o).to_bits());
                    assert_eq!(l.choice, o);
                }
                None => assert!(o % 40 != 0, "{o}"),
            }
        }
        assert_eq!(c.len(), n.div_ceil(40));
        drop(c);
        let big = DENSE_POOL_BYTES / 16 + 1;
        drop(Direct::take(big));
        let pool = DENSE_POOL.lock().expect("the pool's lock");
        assert!(pool.iter().all(|m| m.len() != big));
        assert!(pool.len() <= DENSE_POOL_KEEP);
        assert!(pool.iter().map(|m| 16 * m.len()).sum::<usize>() <= DENSE_POOL_BYTES);
    }
}
