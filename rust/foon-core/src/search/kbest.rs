//! The k best trees of an optimal objective, lazily, in cost order (`docs/METHODS.md`, "The k
//! best trees").
//!
//! A tree is an acyclic choice of one producer per object, closed from the goal. The trees are
//! enumerated by a best-first partition of the choice assignments (Lawler's method): the best
//! tree of a *subspace* (some objects fixed to one producer, some producers banned at some
//! objects) is Knuth's optimum over the goal's ancestry with those producers removed, which is
//! exact because every constraint restricts the producers of one object, and one choice per
//! object is all a tree is. Taking a subspace's best tree T out leaves, for each object `o_i` of T
//! in pre-order, the trees that agree with T on `o_1 .. o_(i-1)` and choose another producer at `o_i`:
//! a partition of the rest. Subspaces are solved only when their lower bound (the cost of the
//! tree they were cut from, raised by the rise of the object they differ at to its next
//! producer: see `Partition::children`) comes first; they are listed in (cost, place in the
//! partition) order. Assignments that give a set of units already listed are skipped, so
//! every set comes once, at its lowest cost.

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::sync::{Arc, Mutex};

use rustc_hash::{FxHashMap, FxHashSet};

use super::optimal::Entry;
use super::scratch::IdMap;
use super::{Context, Method, Plan, Query, optimal, tree};
use crate::error::{Error, Result};
use crate::evaluate::{self, ShapeBuf, StampedMarks, TreeMetrics, TreeView};
use crate::index::NONE;
use crate::prepare::{Objective, Optimum};

/// The kitchen's optimum of an optimal method, when plans read it (`optimal::plan`): not from
/// scratch, and for `optimal-success` only when every motion has a rate.
fn prepared<'c>(ctx: &'c Context<'_>, method: Method) -> Result<Option<&'c Optimum>> {
    let Some(objective) = method.objective() else {
        return Ok(None);
    };
    if ctx.is_from_scratch() || (objective == Objective::Success && !ctx.all_rated()) {
        return Ok(None);
    }
    optimal::optimum(ctx, objective).map(Some)
}

/// The goal's ancestry as a small graph of local ids (derivable objects, and the units whose
/// needed inputs are all derivable: nothing else is in a tree) (objects and units in id order, so every
/// tie is broken as in the global search).
pub(super) struct Local {
    /// Global id of each local object.
    objs: Vec<u32>,
    leaf: Vec<bool>,
    /// Global id of each local unit.
    fus: Vec<u32>,
    needed: Lists,
    /// Outputs a unit can set: in the ancestry, not a leaf, not bare.
    outs: Lists,
    /// Units needing an object, once per needed slot.
    needed_by: Lists,
    /// Units that can set an object (those with it in `outs`).
    made_by: Lists,
    weight: Vec<f64>,
    leaf_cost: f64,
    goal: u32,
    /// The kitchen's optimum in local ids, when prepared: the best tree of the whole space,
    /// and every object's best completion outside a subspace's constraints.
    opt: Option<Opt>,
    /// With the optimum: the objects whose optimum's unit needs each object (once per needed
    /// slot).
    opt_users: Lists,
    /// Buffers of finished enumerations over this graph, for the next ones (at most
    /// `Buffers::KEPT`).
    pool: Mutex<Vec<Buffers>>,
}

/// The buffers of one enumeration over a [`Local`] (all sized to it), kept between calls.
struct Buffers {
    work: Work,
    read: ReadScratch,
    bounds: Bounds,
    part: PartBufs,
}

impl Buffers {
    /// How many a graph keeps (one per thread enumerating it at once).
    const KEPT: usize = 4;
    /// How many emptied listed subspaces (their vectors) a kept `PartBufs` holds at most.
    const SPARE: usize = 64;
    /// The room a kept `PartBufs` keeps at most: entries of its heap and map (and 16 times
    /// as many choices).
    const ROOM: usize = 4096;
}

/// The containers of a `Partition`, kept with their room (emptied between calls).
#[derive(Default)]
struct PartBufs {
    heap: BinaryHeap<Item>,
    /// Emptied `Parent`s, for their room.
    spare: Vec<Parent>,
    /// The constraints of the subspace being solved (or whose children are pushed).
    cons: Constraints,
    /// The listed sets of units, by `set_key`: the last parent listed with each (the others
    /// through `Parent::same`).
    listed: FxHashMap<u128, u32>,
    /// The choices of every `Found::Over` solved.
    arena: Vec<(u32, u32)>,
    metrics: MetricsScratch,
}

impl Local {
    fn lock_pool(&self) -> std::sync::MutexGuard<'_, Vec<Buffers>> {
        // A poisoned lock only means a thread panicked while holding it: the list is whole.
        self.pool
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Buffers for an enumeration: kept ones, or new.
    fn buffers(&self) -> Buffers {
        self.lock_pool().pop().unwrap_or_else(|| Buffers {
            work: Work::new(self),
            read: ReadScratch::new(self),
            bounds: Bounds::default(),
            part: PartBufs::default(),
        })
    }

    /// Keeps an enumeration's buffers for the next one.
    fn keep(&self, b: Buffers) {
        let mut pool = self.lock_pool();
        if pool.len() < Buffers::KEPT {
            pool.push(b);
        }
    }
}

/// The kitchen's optimum over a goal's ancestry, in local ids: each object's final cost, tie
/// key (`optimal::tie_depth`) and choice (`NONE`: none, or a leaf).
struct Opt {
    cost: Vec<f64>,
    depth: Vec<u32>,
    choice: Vec<u32>,
}

/// The goals' ancestries of one prepared kitchen ([`Local`], with the weights and the
/// kitchen's optimum over it), per (goal, optimal objective), kept for later k-best and
/// enumeration calls on the same kitchen: they depend on nothing else. At most
/// [`AncestryCache::GOALS`] are kept; when it is full, it is emptied before the next one is
/// kept. Plans from scratch neither read nor fill it.
#[derive(Default)]
pub(crate) struct AncestryCache {
    map: Mutex<FxHashMap<(u32, u8), Arc<Local>>>,
    /// An object-indexed array of `Local::new` (every entry `NONE` between calls), kept so
    /// that a build costs its ancestry, not a pass over the FOON's objects.
    at: Mutex<Vec<u32>>,
}

impl AncestryCache {
    /// How many ancestries a kitchen keeps at most.
    pub(crate) const GOALS: usize = 64;

    fn key(goal: u32, method: Method) -> (u32, u8) {
        (goal, method as u8)
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, FxHashMap<(u32, u8), Arc<Local>>> {
        // A poisoned lock only means a thread panicked while holding it: the map is whole.
        self.map
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    fn lock_at(&self) -> std::sync::MutexGuard<'_, Vec<u32>> {
        // A poisoned lock only means a thread panicked while holding it: the array is whole
        // (it is taken out while in use).
        self.at
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// The ancestry of `goal` for `method` kept by the context's kitchen, if any.
    fn get(ctx: &Context<'_>, goal: u32, method: Method) -> Option<Arc<Local>> {
        if ctx.is_from_scratch() {
            return None;
        }
        ctx.kbest.lock().get(&Self::key(goal, method)).cloned()
    }

    /// The ancestry of `goal` for `method`: the one kept, or built (and kept).
    fn local(ctx: &Context<'_>, goal: u32, method: Method) -> Result<Arc<Local>> {
        if let Some(g) = Self::get(ctx, goal, method) {
            return Ok(g);
        }
        let g = Arc::new(Local::new(ctx, goal, method)?);
        if !ctx.is_from_scratch() {
            let mut map = ctx.kbest.lock();
            if map.len() >= Self::GOALS {
                map.clear();
            }
            map.insert(Self::key(goal, method), Arc::clone(&g));
        }
        Ok(g)
    }
}

/// Which cost a k-best search minimises.
fn weights(ctx: &Context<'_>, method: Method, fus: &[u32]) -> Result<(Vec<f64>, f64)> {
    Ok(match method {
        // `0.0 - ln r`: a rate of 1 weighs +0, as a leaf costs (see `optimal::plan`).
        Method::OptimalSuccess => (
            fus.iter()
                .map(|&f| ctx.rate(f).map(|r| 0.0 - r.ln()))
                .collect::<Result<_>>()?,
            0.0,
        ),
        Method::OptimalUnits => (vec![1.0; fus.len()], 0.0),
        Method::OptimalInputs => (vec![0.0; fus.len()], 1.0),
        m => {
            return Err(Error::Invalid(format!(
                "the k best trees need an optimal method (optimal-success, optimal-units or \
                 optimal-inputs), not {}",
                m.as_str()
            )));
        }
    })
}

/// One list of local ids per local object or unit, in one flat array: list `i` is
/// `data[start[i]..start[i + 1]]`.
struct Lists {
    start: Vec<u32>,
    data: Vec<u32>,
}

impl Lists {
    fn with_capacity(n: usize) -> Self {
        let mut start = Vec::with_capacity(n + 1);
        start.push(0);
        Self {
            start,
            data: Vec::with_capacity(n * 2),
        }
    }

    /// Ends the list being filled (the elements pushed on `data` since the last one).
    fn close(&mut self) {
        self.start.push(self.data.len() as u32);
    }

    fn lists(&self) -> impl Iterator<Item = &[u32]> {
        (0..self.start.len() - 1).map(|i| &self[i])
    }

    /// The lists of the other side: list `x` holds every `i` whose list holds `x`, once per
    /// occurrence, in increasing `i`.
    fn transpose(&self, n: usize) -> Self {
        let mut start = vec![0u32; n + 1];
        for &x in &self.data {
            start[x as usize + 1] += 1;
        }
        for j in 0..n {
            start[j + 1] += start[j];
        }
        let mut fill = start[..n].to_vec();
        let mut data = vec![0u32; self.data.len()];
        for (i, l) in self.lists().enumerate() {
            for &x in l {
                data[fill[x as usize] as usize] = i as u32;
                fill[x as usize] += 1;
            }
        }
        Self { start, data }
    }
}

impl std::ops::Index<usize> for Lists {
    type Output = [u32];
    fn index(&self, i: usize) -> &[u32] {
        &self.data[self.start[i] as usize..self.start[i + 1] as usize]
    }
}

impl Local {
    pub(super) fn new(ctx: &Context<'_>, goal: u32, method: Method) -> Result<Self> {
        let foon = ctx.foon;
        let ranks = ctx.ranks();
        // Global id -> local id (NONE: not in the ancestry); 0 marks "seen" until the ids are
        // sorted. An array kept by the kitchen when the FOON is small enough for one (else a
        // map of the entries set), all `NONE` again when it is given back.
        let n = foon.object_count();
        let pooled = n <= ctx.scratch_limit();
        let kept = if pooled {
            let mut v = std::mem::take(&mut *ctx.kbest.lock_at());
            if v.len() != n {
                v = vec![NONE; n];
            }
            Some(v)
        } else {
            None
        };
        let mut at = match kept {
            Some(v) => IdMap::Dense(v),
            None => ctx.id_map(n, NONE),
        };
        let mut seen_f = ctx.id_map(foon.fu_count(), false);
        let mut objs = Vec::with_capacity(256);
        objs.push(goal);
        at.set(goal, 0);
        let mut fus = Vec::with_capacity(256);
        let mut next = 0;
        while let Some(&o) = objs.get(next) {
            next += 1;
            if next % 4096 == 0 {
                ctx.check_stop()?;
            }
            if ctx.in_kitchen(o) || ranks.rank(o).is_none() {
                continue;
            }
            for &f in foon.producers(o) {
                // A unit with an input that cannot be made is in no tree.
                if seen_f.get(f) || !ctx.needed(f).iter().all(|&x| ranks.rank(x).is_some()) {
                    continue;
                }
                seen_f.set(f, true);
                fus.push(f);
                for &x in ctx.needed(f) {
                    if at.get(x) == NONE {
                        at.set(x, 0);
                        objs.push(x);
                    }
                }
            }
        }
        objs.sort_unstable();
        fus.sort_unstable();
        for (i, &o) in objs.iter().enumerate() {
            at.set(o, i as u32);
        }
        let leaf: Vec<bool> = objs.iter().map(|&o| ctx.in_kitchen(o)).collect();
        let mut needed = Lists::with_capacity(fus.len());
        let mut outs = Lists::with_capacity(fus.len());
        for &f in &fus {
            needed.data.extend(ctx.needed(f).iter().map(|&x| at.get(x)));
            needed.close();
            let from = outs.data.len();
            for &o in foon.outputs(f) {
                let y = at.get(o);
                // Repeats in a row once, as the unit's output list is read.
                if y != NONE
                    && !leaf[y as usize]
                    && (outs.data.len() == from || outs.data.last() != Some(&y))
                    && !foon.is_bare(o)
                {
                    outs.data.push(y);
                }
            }
            outs.close();
        }
        let needed_by = needed.transpose(objs.len());
        let made_by = outs.transpose(objs.len());
        let (weight, leaf_cost) = weights(ctx, method, &fus)?;
        let opt = prepared(ctx, method)?.and_then(|o| {
            let cost: Vec<f64> = objs.iter().map(|&x| o.cost(x)).collect();
            let depth: Vec<u32> = objs.iter().map(|&x| o.depth(x)).collect();
            let choice = objs
                .iter()
                .map(|&x| match o.choice(x) {
                    NONE => Some(NONE),
                    f => fus.binary_search(&f).ok().map(|i| i as u32),
                })
                .collect::<Option<Vec<u32>>>()?;
            Some(Opt {
                cost,
                depth,
                choice,
            })
        });
        let mut opt_needs = Lists::with_capacity(objs.len());
        if let Some(Opt { choice, .. }) = &opt {
            for &f in choice {
                if f != NONE {
                    opt_needs.data.extend_from_slice(&needed[f as usize]);
                }
                opt_needs.close();
            }
        }
        let opt_users = opt_needs.transpose(if opt.is_some() { objs.len() } else { 0 });
        let goal = at.get(goal);
        if let (true, IdMap::Dense(mut v)) = (pooled, at) {
            // Only the ancestry's entries were set.
            for &o in &objs {
                v[o as usize] = NONE;
            }
            *ctx.kbest.lock_at() = v;
        }
        Ok(Self {
            goal,
            objs,
            leaf,
            fus,
            needed,
            outs,
            needed_by,
            made_by,
            weight,
            leaf_cost,
            opt,
            opt_users,
            pool: Mutex::new(Vec::new()),
        })
    }
}

/// Constraints of a subspace: (object, unit) pairs in local ids.
#[derive(Default)]
struct Constraints {
    fixed: Vec<(u32, u32)>,
    banned: Vec<(u32, u32)>,
}

/// A subspace's best tree.
struct Solved {
    cost: f64,
    /// Objects outside the kitchen in pre-order, with their choices (local ids).
    preorder: Vec<(u32, u32)>,
    /// Units (global ids) in depth-first post-order.
    units: Vec<u32>,
    /// Per pre-order position: the object's cost in the tree.
    vals: Vec<f64>,
}

/// Where `Local::read` puts a tree: `Solved`'s pre-order, units and values.
type TreeOut<'a> = (&'a mut Vec<(u32, u32)>, &'a mut Vec<u32>, &'a mut Vec<f64>);

impl Solved {
    fn new(cost: f64) -> Self {
        Self {
            cost,
            preorder: Vec::new(),
            units: Vec::new(),
            vals: Vec::new(),
        }
    }

    fn out(&mut self) -> TreeOut<'_> {
        (&mut self.preorder, &mut self.units, &mut self.vals)
    }
}

/// What `solve_seeded` found: the best tree, no tree, or that the full run is needed.
enum Seeded {
    Tree(Found),
    Empty,
    Full,
}

/// A subspace's best tree: read, or its cost and the choices of its affected objects (the
/// tree is read from the optimum's choices and these, by `Local::read_over`, only when it is
/// listed: most solved subspaces never are).
enum Found {
    Tree(Box<Solved>),
    /// The choices: a range of `Partition::arena`.
    Over {
        cost: f64,
        choices: (u32, u32),
    },
}

impl Found {
    fn cost(&self) -> f64 {
        match self {
            Found::Tree(s) => s.cost,
            Found::Over { cost, .. } => *cost,
        }
    }
}

/// Reusable per-run state of Knuth's algorithm over the local graph.
struct Work {
    cost: Vec<f64>,
    /// The tie key of `optimal::tie_depth`.
    depth: Vec<u32>,
    choice: Vec<u32>,
    done: Vec<bool>,
    left: Vec<u32>,
    fixed: Vec<u32>,
    banned: Vec<bool>,
    heap: BinaryHeap<Entry>,
    /// `solve_seeded`: the run's stamp on affected objects, relevant units and the seeded
    /// objects; the affected objects and the relevant units.
    epoch: u32,
    stamp: Vec<u32>,
    ustamp: Vec<u32>,
    fstamp: Vec<u32>,
    list: Vec<u32>,
    units: Vec<u32>,
}

impl Work {
    /// A new stamp for `stamp`, `ustamp` and `fstamp`.
    fn next_epoch(&mut self) -> u32 {
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.stamp.fill(0);
            self.ustamp.fill(0);
            self.fstamp.fill(0);
            self.epoch = 1;
        }
        self.epoch
    }

    /// Knuth's relaxation: `f` makes `y` at (`cost`, `depth`); it becomes `y`'s choice when
    /// lower, or as low with a lower unit index (pushed on the heap only when lower).
    fn offer(&mut self, y: u32, f: u32, cost: f64, depth: u32) {
        if cost == f64::INFINITY {
            return;
        }
        let yi = y as usize;
        let (old_cost, old_depth, old_choice) = (self.cost[yi], self.depth[yi], self.choice[yi]);
        if optimal::better(cost, depth, f, old_cost, old_depth, old_choice) {
            if optimal::lower(cost, depth, old_cost, old_depth) {
                self.heap.push(Entry {
                    cost,
                    depth,
                    obj: y,
                });
            }
            self.cost[yi] = cost;
            self.depth[yi] = depth;
            self.choice[yi] = f;
        }
    }

    /// The (cost, depth) `f` offers its outputs, weighing `w`, from the current costs.
    fn value(&self, w: f64, needed: &[u32]) -> (f64, u32) {
        let mut cost = w;
        for &x in needed {
            cost += self.cost[x as usize];
        }
        let d = optimal::tie_depth(
            cost,
            needed
                .iter()
                .map(|&x| (self.cost[x as usize], self.depth[x as usize])),
        );
        (cost, d)
    }

    fn new(g: &Local) -> Self {
        Self {
            cost: vec![f64::INFINITY; g.objs.len()],
            depth: vec![0; g.objs.len()],
            choice: vec![NONE; g.objs.len()],
            done: vec![false; g.objs.len()],
            left: vec![0; g.fus.len()],
            fixed: vec![NONE; g.objs.len()],
            banned: vec![false; g.objs.len()],
            heap: BinaryHeap::new(),
            epoch: 0,
            stamp: vec![0; g.objs.len()],
            ustamp: vec![0; g.fus.len()],
            fstamp: vec![0; g.objs.len()],
            list: Vec::new(),
            units: Vec::new(),
        }
    }
}

impl Local {
    /// Knuth's algorithm under `c` with weights `w`: the best tree, or `None` when the
    /// subspace is empty (or every tree in it costs +infinity).
    fn solve(
        &self,
        w: &[f64],
        c: &Constraints,
        work: &mut Work,
        scratch: &mut ReadScratch,
    ) -> Option<Solved> {
        self.knuth(w, c, work, false);
        let g = self.goal as usize;
        if !work.done[g] || !work.cost[g].is_finite() {
            return None;
        }
        let mut s = Solved::new(work.cost[g]);
        self.read(w, |o| work.choice[o as usize], scratch, s.out());
        Some(s)
    }

    /// Every object's cost over the whole ancestry under the weights `w` (no constraint; +inf
    /// for an object with no tree): a lower bound on its cost in every subspace.
    fn costs(&self, w: &[f64], work: &mut Work) -> Vec<f64> {
        self.knuth(w, &Constraints::default(), work, true);
        work.cost.clone()
    }

    /// Knuth's algorithm under `c` with weights `w`, stopped when the goal is final unless
    /// `to_end`; the costs, choices and final flags are left in `work`.
    fn knuth(&self, w: &[f64], c: &Constraints, work: &mut Work, to_end: bool) {
        let n = self.objs.len();
        work.cost.fill(f64::INFINITY);
        work.depth.fill(0);
        work.choice.fill(NONE);
        work.done.fill(false);
        work.heap.clear();
        for (f, l) in work.left.iter_mut().enumerate() {
            *l = self.needed[f].len() as u32;
        }
        for &(o, f) in &c.fixed {
            work.fixed[o as usize] = f;
        }
        for &(o, _) in &c.banned {
            work.banned[o as usize] = true;
        }
        for o in 0..n {
            if self.leaf[o] {
                work.cost[o] = self.leaf_cost;
                work.heap.push(Entry {
                    cost: self.leaf_cost,
                    depth: 0,
                    obj: o as u32,
                });
            }
        }
        let allowed = |work: &Work, y: u32, f: u32| {
            let fx = work.fixed[y as usize];
            (fx == NONE || fx == f) && !(work.banned[y as usize] && c.banned.contains(&(y, f)))
        };
        let fire = |f: u32, work: &mut Work| {
            let (cost, d) = work.value(w[f as usize], &self.needed[f as usize]);
            for &y in &self.outs[f as usize] {
                let yi = y as usize;
                if work.done[yi] || !allowed(work, y, f) {
                    continue;
                }
                work.offer(y, f, cost, d);
            }
        };
        for f in 0..self.fus.len() as u32 {
            if work.left[f as usize] == 0 {
                fire(f, work);
            }
        }
        while let Some(Entry {
            cost,
            depth,
            obj: o,
        }) = work.heap.pop()
        {
            let oi = o as usize;
            if work.done[oi] || optimal::lower(work.cost[oi], work.depth[oi], cost, depth) {
                continue;
            }
            work.done[oi] = true;
            if o == self.goal && !to_end {
                break;
            }
            for &f in &self.needed_by[oi] {
                let l = &mut work.left[f as usize];
                *l -= 1;
                if *l == 0 {
                    fire(f, work);
                }
            }
        }
        for &(o, _) in &c.fixed {
            work.fixed[o as usize] = NONE;
        }
        for &(o, _) in &c.banned {
            work.banned[o as usize] = false;
        }
    }

    /// The best tree of a subspace from the kitchen's optimum: read from it for the whole
    /// space; otherwise Knuth's algorithm over the *affected* objects only (those whose
    /// optimum's tree breaks a constraint: fixed to another unit than the optimum's choice, or
    /// that choice banned; and every object whose optimum's tree holds one of them), seeded
    /// with the optimum's final costs of the unaffected inputs of their units: the others keep
    /// the optimum's cost and choice (their optimum's tree is in the subspace, and a
    /// constraint only raises costs and tie keys, so it is still the best, with the same lowest
    /// unit index among those that set the (cost, tie key)). The unaffected inputs are final at
    /// the optimum's (cost, tie key), which are theirs in the subspace: Knuth's algorithm over
    /// the affected objects then gives their final (cost, tie key) and choices as the full run
    /// does (a unit's (cost, tie key) is above each of its inputs', so every unit that can set
    /// an object's final key fires before the object is final).
    fn solve_seeded(
        &self,
        w: &[f64],
        c: &Constraints,
        work: &mut Work,
        scratch: &mut ReadScratch,
        arena: &mut Vec<(u32, u32)>,
    ) -> Seeded {
        let Some(opt) = self.opt.as_ref() else {
            return Seeded::Full;
        };
        let (ocost, ochoice) = (&opt.cost, &opt.choice);
        let g = self.goal as usize;
        if c.fixed.is_empty() && c.banned.is_empty() {
            if !ocost[g].is_finite() {
                return Seeded::Empty;
            }
            let mut s = Box::new(Solved::new(ocost[g]));
            self.read(w, |o| ochoice[o as usize], scratch, s.out());
            return Seeded::Tree(Found::Tree(s));
        }
        let e = work.next_epoch();
        let mut list = std::mem::take(&mut work.list);
        let mut units = std::mem::take(&mut work.units);
        list.clear();
        units.clear();
        // The objects whose optimum's tree breaks a constraint (fixed to another unit than
        // its choice, or its choice banned), and those whose optimum's tree holds one of them.
        let seeds = c
            .fixed
            .iter()
            .filter(|&&(o, f)| ochoice[o as usize] != f)
            .chain(c.banned.iter().filter(|&&(o, f)| ochoice[o as usize] == f));
        for &(o, _) in seeds {
            if work.stamp[o as usize] != e {
                work.stamp[o as usize] = e;
                list.push(o);
            }
        }
        let mut i = 0;
        while let Some(&o) = list.get(i) {
            i += 1;
            for &y in &self.opt_users[o as usize] {
                if work.stamp[y as usize] != e {
                    work.stamp[y as usize] = e;
                    list.push(y);
                }
            }
        }
        // The goal is affected in every subspace but the whole space (the optimum's tree was
        // listed first); otherwise the full run.
        let affected = work.stamp[g] == e;
        if affected {
            self.run_seeded(w, c, work, &list, &mut units, opt);
        }
        work.list = list;
        work.units = units;
        if !affected {
            return Seeded::Full;
        }
        if !work.done[g] || !work.cost[g].is_finite() {
            return Seeded::Empty;
        }
        if arena.len() + work.list.len() > u32::MAX as usize {
            // No room left in the arena's ranges: the tree is read now.
            let mut s = Box::new(Solved::new(work.cost[g]));
            let choices: Vec<(u32, u32)> = work
                .list
                .iter()
                .map(|&o| (o, work.choice[o as usize]))
                .collect();
            self.read_over(w, &choices, work, scratch, s.out());
            return Seeded::Tree(Found::Tree(s));
        }
        let start = arena.len() as u32;
        arena.extend(work.list.iter().map(|&o| (o, work.choice[o as usize])));
        Seeded::Tree(Found::Over {
            cost: work.cost[g],
            choices: (start, arena.len() as u32),
        })
    }

    /// The tree of the kitchen's optimum's choices with `choices` in place of theirs (a
    /// `Found::Over`), as `read` gives it.
    fn read_over(
        &self,
        w: &[f64],
        choices: &[(u32, u32)],
        work: &mut Work,
        scratch: &mut ReadScratch,
        out: TreeOut<'_>,
    ) {
        let ochoice = &self
            .opt
            .as_ref()
            .expect("a seeded tree has an optimum")
            .choice;
        let e = work.next_epoch();
        for &(o, f) in choices {
            work.stamp[o as usize] = e;
            work.choice[o as usize] = f;
        }
        self.read(
            w,
            |o| {
                if work.stamp[o as usize] == e {
                    work.choice[o as usize]
                } else {
                    ochoice[o as usize]
                }
            },
            scratch,
            out,
        );
    }

    /// Knuth's algorithm over the affected objects `list` (see `solve_seeded`).
    fn run_seeded(
        &self,
        w: &[f64],
        c: &Constraints,
        work: &mut Work,
        list: &[u32],
        units: &mut Vec<u32>,
        opt: &Opt,
    ) {
        let ocost = &opt.cost;
        let e = work.epoch;
        work.heap.clear();
        for &y in list {
            let yi = y as usize;
            work.cost[yi] = f64::INFINITY;
            work.depth[yi] = 0;
            work.choice[yi] = NONE;
            work.done[yi] = false;
            for &f in &self.made_by[yi] {
                if work.ustamp[f as usize] != e {
                    work.ustamp[f as usize] = e;
                    units.push(f);
                }
            }
        }
        // An unaffected input is final at the optimum's (cost, tie key): it is not put on the
        // heap, and a unit waits only for its affected inputs (it never runs with an input of
        // infinite cost, as in the full run). A unit may so run before some object is final
        // that it would run after in the full run; it then offers it more than that object's
        // (cost, tie key), which changes nothing.
        for &f in units.iter() {
            let mut left = 0;
            for &x in &self.needed[f as usize] {
                let xi = x as usize;
                if work.stamp[xi] == e {
                    left += 1;
                    continue;
                }
                if work.fstamp[xi] != e {
                    work.fstamp[xi] = e;
                    work.done[xi] = true;
                    work.cost[xi] = ocost[xi];
                    work.depth[xi] = opt.depth[xi];
                }
                if !ocost[xi].is_finite() {
                    left += 1;
                }
            }
            work.left[f as usize] = left;
        }
        for &(o, f) in &c.fixed {
            work.fixed[o as usize] = f;
        }
        for &(o, _) in &c.banned {
            work.banned[o as usize] = true;
        }
        let allowed = |work: &Work, y: u32, f: u32| {
            let fx = work.fixed[y as usize];
            (fx == NONE || fx == f) && !(work.banned[y as usize] && c.banned.contains(&(y, f)))
        };
        let fire = |f: u32, work: &mut Work| {
            let (cost, d) = work.value(w[f as usize], &self.needed[f as usize]);
            for &y in &self.outs[f as usize] {
                let yi = y as usize;
                if work.stamp[yi] != e || work.done[yi] || !allowed(work, y, f) {
                    continue;
                }
                work.offer(y, f, cost, d);
            }
        };
        for &f in units.iter() {
            if work.left[f as usize] == 0 {
                fire(f, work);
            }
        }
        while let Some(Entry {
            cost,
            depth,
            obj: o,
        }) = work.heap.pop()
        {
            let oi = o as usize;
            if work.done[oi] || optimal::lower(work.cost[oi], work.depth[oi], cost, depth) {
                continue;
            }
            work.done[oi] = true;
            if o == self.goal {
                break;
            }
            for &f in &self.needed_by[oi] {
                if work.ustamp[f as usize] != e {
                    continue;
                }
                let l = &mut work.left[f as usize];
                *l -= 1;
                if *l == 0 {
                    fire(f, work);
                }
            }
        }
        for &(o, _) in &c.fixed {
            work.fixed[o as usize] = NONE;
        }
        for &(o, _) in &c.banned {
            work.banned[o as usize] = false;
        }
    }

    /// The tree of the choices from the goal: (pre-order objects with their choices, units in
    /// depth-first post-order, each object's cost in the tree under the weights `w`), as
    /// `tree::emit` reads them, into `pre`, `units` and `vals` (emptied first). An object's
    /// cost is its unit's weight plus its inputs' costs, added in input order.
    fn read(
        &self,
        w: &[f64],
        choice: impl Fn(u32) -> u32,
        scratch: &mut ReadScratch,
        (pre, units, vals): TreeOut<'_>,
    ) {
        let e = scratch.next_epoch(self);
        let ReadScratch {
            seen,
            emitted,
            stack,
            size,
            oval,
            uval,
            ..
        } = scratch;
        // Room for a tree as large as the last one read, and a few more.
        pre.clear();
        vals.clear();
        units.clear();
        pre.reserve(size.0 + 8);
        vals.reserve(size.0 + 8);
        units.reserve(size.1 + 8);
        stack.clear();
        // An object's unit is pushed (with the object's place in `pre`) unless emitted
        // already: then the object's cost is that unit's (the choices are acyclic, so a unit
        // on the stack is never reached again from its inputs).
        let mut next = Some(self.goal);
        loop {
            if let Some(o) = next.take() {
                let oi = o as usize;
                if !self.leaf[oi] && seen[oi] != e {
                    seen[oi] = e;
                    let f = choice(o);
                    let j = pre.len() as u32;
                    pre.push((o, f));
                    if emitted[f as usize] == e {
                        oval[oi] = uval[f as usize];
                        vals.push(uval[f as usize]);
                    } else {
                        vals.push(f64::NAN);
                        stack.push((f, 0, j));
                    }
                }
            }
            let Some(&mut (f, ref mut i, j)) = stack.last_mut() else {
                break;
            };
            let ins = &self.needed[f as usize];
            if let Some(&x) = ins.get(*i) {
                *i += 1;
                next = Some(x);
                continue;
            }
            stack.pop();
            let fi = f as usize;
            if emitted[fi] != e {
                emitted[fi] = e;
                let mut v = w[fi];
                for &x in ins {
                    v += if self.leaf[x as usize] {
                        self.leaf_cost
                    } else {
                        oval[x as usize]
                    };
                }
                uval[fi] = v;
                units.push(self.fus[fi]);
            }
            oval[pre[j as usize].0 as usize] = uval[fi];
            vals[j as usize] = uval[fi];
        }
        *size = (pre.len(), units.len());
    }

    /// `Context::metrics` of a tree of this graph (`preorder`: its objects with their local
    /// choices; `units`: its units, global ids, in execution order): the rule of
    /// `evaluate::shape` over the local ids, in time linear in the tree (every needed input of
    /// a unit of the ancestry is in it, and so is every output another unit of it can need).
    fn metrics(
        &self,
        ctx: &Context<'_>,
        preorder: &[(u32, u32)],
        units: &[u32],
        m: &mut MetricsScratch,
    ) -> TreeMetrics {
        let MetricsScratch {
            us,
            seen,
            epoch,
            marks,
            buf,
        } = m;
        // The distinct units, in pre-order (the rule does not depend on their order).
        if seen.len() != self.fus.len() {
            *seen = vec![0; self.fus.len()];
            *epoch = 0;
        }
        *epoch = epoch.wrapping_add(1);
        if *epoch == 0 {
            seen.fill(0);
            *epoch = 1;
        }
        us.clear();
        for &(_, f) in preorder {
            if seen[f as usize] != *epoch {
                seen[f as usize] = *epoch;
                us.push(f);
            }
        }
        let marks = marks.get_or_insert_with(|| StampedMarks::new(self.objs.len()));
        evaluate::tree_metrics(self, ctx, units, us, self.goal, marks, buf)
    }

    /// The cost of a tree under the weights `w`, by the definition (a shared sub-goal counts
    /// once per use; inputs summed in input order after the unit's weight).
    fn tree_cost(&self, w: &[f64], preorder: &[(u32, u32)]) -> f64 {
        let mut choice = vec![NONE; self.objs.len()];
        for &(o, f) in preorder {
            choice[o as usize] = f;
        }
        // Post-order over the choices (acyclic), memoised.
        let mut cost = vec![f64::NAN; self.objs.len()];
        let mut stack = vec![(self.goal, 0usize)];
        while let Some(&mut (o, ref mut i)) = stack.last_mut() {
            let oi = o as usize;
            if self.leaf[oi] {
                cost[oi] = self.leaf_cost;
                stack.pop();
                continue;
            }
            let f = choice[oi] as usize;
            let ins = &self.needed[f];
            if *i < ins.len() {
                let x = ins[*i];
                *i += 1;
                if cost[x as usize].is_nan() {
                    stack.push((x, 0));
                }
            } else {
                let mut c = w[f];
                for &x in ins {
                    c += cost[x as usize];
                }
                cost[oi] = c;
                stack.pop();
            }
        }
        cost[self.goal as usize]
    }
}

/// Buffers of `Local::metrics`, kept between trees (the marks over the local objects, once
/// the graph is known).
#[derive(Default)]
struct MetricsScratch {
    us: Vec<u32>,
    /// Per local unit: the epoch of the tree that holds it.
    seen: Vec<u32>,
    epoch: u32,
    marks: Option<StampedMarks>,
    buf: ShapeBuf,
}

impl TreeView for Local {
    #[inline]
    fn needed(&self, f: u32) -> &[u32] {
        &self.needed[f as usize]
    }
    #[inline]
    fn for_made(&self, f: u32, mut each: impl FnMut(u32)) {
        for &y in &self.outs[f as usize] {
            each(y);
        }
    }
    #[inline]
    fn in_kitchen(&self, o: u32) -> bool {
        self.leaf[o as usize]
    }
}

/// Stamped marks of `Local::read` (objects seen, units emitted) and its stack, kept between
/// reads: nothing the size of the ancestry is allocated per subspace.
struct ReadScratch {
    epoch: u32,
    seen: Vec<u32>,
    emitted: Vec<u32>,
    stack: Vec<(u32, usize, u32)>,
    /// The last tree read: its pre-order's and its units' lengths.
    size: (usize, usize),
    /// The costs in the tree being read: of its objects, and of its units.
    oval: Vec<f64>,
    uval: Vec<f64>,
}

impl ReadScratch {
    fn new(g: &Local) -> Self {
        Self {
            epoch: 0,
            seen: vec![0; g.objs.len()],
            emitted: vec![0; g.fus.len()],
            stack: Vec::new(),
            size: (0, 0),
            oval: vec![0.0; g.objs.len()],
            uval: vec![0.0; g.fus.len()],
        }
    }

    fn next_epoch(&mut self, g: &Local) -> u32 {
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.seen.clear();
            self.seen.resize(g.objs.len(), 0);
            self.emitted.clear();
            self.emitted.resize(g.fus.len(), 0);
            self.epoch = 1;
        }
        self.epoch
    }
}

/// Scratch of `Partition::children`: a listed tree's objects (their pre-order position and
/// their cost in the tree).
#[derive(Default)]
struct Bounds {
    epoch: u32,
    /// Per local object: the epoch of the tree it is in, and its pre-order position.
    stamp: Vec<u32>,
    pos: Vec<u32>,
    /// Per pre-order position: cost in the tree.
    val: Vec<f64>,
}

impl Bounds {
    /// The per-tree values of a listed subspace's tree (its pre-order `preorder` and its
    /// `Solved::vals`): its objects' pre-order positions and their costs in the tree.
    fn setup(&mut self, g: &Local, preorder: &[(u32, u32)], vals: &[f64]) {
        let b = self;
        let no = g.objs.len();
        if b.stamp.len() != no {
            b.stamp = vec![0; no];
            b.pos = vec![0; no];
            b.epoch = 0;
        }
        b.epoch = b.epoch.wrapping_add(1);
        if b.epoch == 0 {
            b.stamp.fill(0);
            b.epoch = 1;
        }
        let e = b.epoch;
        for (j, &(o, _)) in preorder.iter().enumerate() {
            b.stamp[o as usize] = e;
            b.pos[o as usize] = j as u32;
        }
        b.val.clear();
        b.val.extend_from_slice(vals);
    }
}

enum Node {
    /// The subspace `at` of the listed subspace `parent` (an index into `Partition::parents`):
    /// its pre-order objects before `at` fixed to their choices, the choice at `at` banned.
    Open { parent: u32, at: u32 },
    /// That subspace solved: its best tree.
    Done { parent: u32, at: u32, found: Found },
}

/// A listed subspace, kept while its children may still be solved: the subspace `at` of the
/// listed subspace `up` (`u32::MAX` for the whole space), and its best tree.
#[derive(Default)]
struct Parent {
    up: u32,
    at: u32,
    /// The listed subspace listed before it with the same `set_key` (`u32::MAX`: none).
    same: u32,
    preorder: Vec<(u32, u32)>,
    /// Its tree's `Solved::vals`.
    vals: Vec<f64>,
}

struct Item {
    /// The best tree's cost once solved; before that a lower bound on it.
    key: f64,
    /// The subspace's place in the partition: (listing number of the subspace it was cut
    /// from, its position in that tree's pre-order); (0, 0) for the whole space.
    ord: (u64, u32),
    node: Node,
}

impl PartialEq for Item {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Item {}
impl Ord for Item {
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .key
            .total_cmp(&self.key)
            .then(other.ord.cmp(&self.ord))
    }
}
impl PartialOrd for Item {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// A tree `Partition::next` lists: its cost and its units (global ids, in depth-first
/// post-order).
struct Listed {
    cost: f64,
    units: Vec<u32>,
}

/// A key of a set of distinct units, whatever their order: two sums of one hash of each
/// (sets with one key are compared by `same_units`).
fn set_key(units: &[u32]) -> u128 {
    let (mut a, mut b) = (0u64, 0u64);
    for &f in units {
        // SplitMix64's finaliser, of the unit and of the unit under another constant.
        let mix = |mut z: u64| {
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^ (z >> 31)
        };
        let x = u64::from(f);
        a = a.wrapping_add(mix(x.wrapping_add(0x9e37_79b9_7f4a_7c15)));
        b = b.wrapping_add(mix(x ^ 0xd6e8_feb8_6659_fd93));
    }
    (u128::from(a) << 64) | u128::from(b)
}

/// Whether two trees (their pre-order choices) hold the same units.
fn same_units(x: &[(u32, u32)], y: &[(u32, u32)]) -> bool {
    let set = |p: &[(u32, u32)]| {
        let mut v: Vec<u32> = p.iter().map(|&(_, f)| f).collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    set(x) == set(y)
}

/// Every tree of the local graph under the weights `w`, in (cost, partition order), each set of
/// units once.
struct Partition {
    /// The weights, `None` for the graph's own.
    w: Option<Vec<f64>>,
    /// Every object's cost over the whole ancestry under the weights: a lower bound in every
    /// subspace; `None` for the kitchen's optimum.
    lb: Option<Vec<f64>>,
    /// Subspaces listed (popped solved) so far, and those whose children may be in the heap.
    popped: u64,
    parents: Vec<Parent>,
    /// The heap and the other containers, kept between calls.
    bufs: PartBufs,
    work: Work,
    scratch: ReadScratch,
    bounds: Bounds,
    /// Subspaces solved so far.
    solved: u64,
    /// `w` is the plain weights and the kitchen's optimum is known: `solve_seeded` applies.
    seeded: bool,
    /// The last listed subspace's children are still to be pushed: its listing number and
    /// its tree's cost (it is the last of `parents`).
    deferred: Option<(u64, f64)>,
    /// Every weight and the leaf cost are whole numbers: the trees' sums are exact, and the
    /// children's bounds need no margin for rounding.
    exact: bool,
}

impl Partition {
    /// The partition under the weights `w` (`None`: the graph's own, and then the subspaces
    /// are solved from the kitchen's optimum when it is known).
    fn new(g: &Local, w: Option<Vec<f64>>) -> Self {
        let seeded = w.is_none() && g.opt.is_some();
        // Whole weights below 2^32: every sum of a tree is a whole number below 2^53 for any
        // tree that fits in memory, so exact.
        let whole = |x: f64| x.fract() == 0.0 && (0.0..4_294_967_296.0).contains(&x);
        let exact =
            whole(g.leaf_cost) && w.as_deref().unwrap_or(&g.weight).iter().all(|&x| whole(x));
        let Buffers {
            mut work,
            read: scratch,
            bounds,
            part: bufs,
        } = g.buffers();
        let lb = if seeded {
            None
        } else {
            Some(g.costs(w.as_deref().unwrap_or(&g.weight), &mut work))
        };
        let mut p = Self {
            w,
            lb,
            popped: 0,
            parents: Vec::new(),
            bufs,
            work,
            scratch,
            bounds,
            solved: 0,
            seeded,
            deferred: None,
            exact,
        };
        p.bufs.heap.push(Item {
            key: f64::NEG_INFINITY,
            ord: (0, 0),
            node: Node::Open {
                parent: u32::MAX,
                at: 0,
            },
        });
        p
    }

    /// Gives its buffers back to the graph, for a later enumeration.
    fn recycle(mut self, g: &Local) {
        // Emptied, and no larger than an enumeration of a few thousand trees needs: a long
        // one does not keep its peak room for the kitchen's lifetime.
        let b = &mut self.bufs;
        b.heap.clear();
        b.heap.shrink_to(Buffers::ROOM);
        b.listed.clear();
        b.listed.shrink_to(Buffers::ROOM);
        b.arena.clear();
        b.arena.shrink_to(Buffers::ROOM * 16);
        let room = Buffers::SPARE.saturating_sub(b.spare.len());
        b.spare.extend(self.parents.drain(..).take(room));
        g.keep(Buffers {
            work: self.work,
            read: self.scratch,
            bounds: self.bounds,
            part: self.bufs,
        });
    }

    /// `Local::metrics` of the tree `next` gave last (its units: `units`).
    fn last_metrics(&mut self, g: &Local, ctx: &Context<'_>, units: &[u32]) -> TreeMetrics {
        let preorder = self.parents.last().map_or(&[][..], |p| &p.preorder);
        g.metrics(ctx, preorder, units, &mut self.bufs.metrics)
    }

    /// The constraints of the subspace `at` of the listed subspace `parent` (`u32::MAX`: the
    /// whole space), into `c`: its parent's pre-order before `at` fixed (the parent's own fixed
    /// objects are the start of its pre-order: its tree reaches them first, through their fixed
    /// choices, as the tree it was cut from did), and the parent's choice at `at` banned with
    /// every choice banned in the parent's subspace (up the chain of parents).
    fn constraints(parents: &[Parent], parent: u32, at: u32, c: &mut Constraints) {
        c.fixed.clear();
        c.banned.clear();
        let Some(pa) = parents.get(parent as usize) else {
            return;
        };
        c.fixed.extend_from_slice(&pa.preorder[..at as usize]);
        c.banned.push(pa.preorder[at as usize]);
        let (mut up, mut at) = (pa.up, pa.at);
        while let Some(p) = parents.get(up as usize) {
            c.banned.push(p.preorder[at as usize]);
            (up, at) = (p.up, p.at);
        }
    }

    /// Pushes the subspaces that partition the rest of a listed subspace (constraints `c`, best
    /// tree `s`, listing number `n`, kept as `parent`), each keyed by a lower bound on its best
    /// tree's cost; a subspace whose bound is +infinity has no tree and is left out.
    ///
    /// The child at `o_i` keeps `o_1 .. o_(i-1)` fixed, so its best tree costs at least the
    /// tree's cost raised by `v - val(o_i)`, where `v` is the cheapest other allowed producer
    /// of `o_i` (its inputs at their cost in the tree, or over the whole ancestry): every
    /// object costs, in any subspace of this one, at least its cost in the tree (the tree is
    /// this subspace's optimum, and a constraint only raises optima); the objects on the
    /// tree's path from the goal to `o_i` come before it in pre-order, so they are fixed, and
    /// each one's cost is its unit's weight plus its inputs', one of them the next on the path:
    /// the rise at `o_i` reaches the goal at least once. With whole weights (`optimal-units`,
    /// `optimal-inputs`) the sums are exact and so is the bound. Otherwise every weight is
    /// non-negative, so the sums' rounding is a relative error of at most about 2^-52 per
    /// addition along a path, below 1e-9 for fewer than about four million additions; the
    /// bound is lowered by a relative 1e-9 to stay below the computed cost.
    fn children(&mut self, g: &Local, parent: u32) {
        let Self {
            parents, deferred, ..
        } = self;
        let Some((n, cost)) = deferred.take() else {
            return;
        };
        let pa = std::mem::take(&mut parents[parent as usize]);
        let mut c = std::mem::take(&mut self.bufs.cons);
        Self::constraints(&self.parents, pa.up, pa.at, &mut c);
        self.push_children(g, &pa, &c, cost, n, parent);
        self.bufs.cons = c;
        self.parents[parent as usize] = pa;
    }

    fn push_children(
        &mut self,
        g: &Local,
        pa: &Parent,
        c: &Constraints,
        cost: f64,
        n: u64,
        parent: u32,
    ) {
        let preorder = &pa.preorder[..];
        // The fixed objects, the start of the pre-order, have no child.
        let from = c.fixed.len();
        debug_assert!(preorder[..from].iter().all(|p| c.fixed.contains(p)));
        let w = self.w.as_deref().unwrap_or(&g.weight);
        let lb = match (&self.lb, &g.opt) {
            (Some(lb), _) => lb,
            (None, Some(opt)) => &opt.cost,
            // Not reached: a partition without bounds of its own is seeded.
            (None, None) => return,
        };
        let b = &mut self.bounds;
        b.setup(g, preorder, &pa.vals);
        debug_assert!(preorder.is_empty() || b.val[0].to_bits() == cost.to_bits());
        let e = b.epoch;
        // A lower bound on an input's cost in every child.
        let low = |b: &Bounds, x: u32| -> f64 {
            let xi = x as usize;
            if g.leaf[xi] {
                g.leaf_cost
            } else if b.stamp[xi] == e {
                b.val[b.pos[xi] as usize]
            } else {
                lb[xi]
            }
        };
        for (i, &(o, ci)) in preorder.iter().enumerate().skip(from) {
            let mut alt = f64::INFINITY;
            for &f in &g.made_by[o as usize] {
                if f == ci || c.banned.contains(&(o, f)) {
                    continue;
                }
                let mut v = w[f as usize];
                for &x in &g.needed[f as usize] {
                    v += low(b, x);
                }
                if v < alt {
                    alt = v;
                }
            }
            let v = alt.max(b.val[i]);
            if !v.is_finite() {
                continue;
            }
            #[allow(clippy::float_cmp)]
            let key = if v == b.val[i] {
                cost
            } else if i == 0 {
                v
            } else if self.exact {
                cost + (v - b.val[i])
            } else {
                let raised = cost + (v - b.val[i]);
                raised - raised * 1e-9
            };
            self.bufs.heap.push(Item {
                key: key.max(cost),
                ord: (n, i as u32),
                node: Node::Open {
                    parent,
                    at: i as u32,
                },
            });
        }
    }

    /// The pre-order choices of the tree `next` gave last.
    fn last_preorder(&self) -> &[(u32, u32)] {
        self.parents.last().map_or(&[], |p| &p.preorder)
    }

    /// The next tree (its pre-order choices: `last_preorder`), or `None` when every tree was
    /// listed.
    fn next(&mut self, g: &Local, ctx: &Context<'_>) -> Result<Option<Listed>> {
        if self.deferred.is_some() {
            self.children(g, self.parents.len() as u32 - 1);
        }
        while let Some(item) = self.bufs.heap.pop() {
            match item.node {
                Node::Open { parent, at } => {
                    self.solved += 1;
                    ctx.check_stop()?;
                    let mut c = std::mem::take(&mut self.bufs.cons);
                    Self::constraints(&self.parents, parent, at, &mut c);
                    let w = self.w.as_deref().unwrap_or(&g.weight);
                    let s = if self.seeded {
                        g.solve_seeded(
                            w,
                            &c,
                            &mut self.work,
                            &mut self.scratch,
                            &mut self.bufs.arena,
                        )
                    } else {
                        Seeded::Full
                    };
                    let s = match s {
                        Seeded::Tree(s) => Some(s),
                        Seeded::Empty => None,
                        Seeded::Full => g
                            .solve(w, &c, &mut self.work, &mut self.scratch)
                            .map(|s| Found::Tree(Box::new(s))),
                    };
                    self.bufs.cons = c;
                    if let Some(found) = s {
                        self.bufs.heap.push(Item {
                            key: found.cost(),
                            ord: item.ord,
                            node: Node::Done { parent, at, found },
                        });
                    }
                }
                Node::Done {
                    parent: up,
                    at,
                    found,
                } => {
                    let mut pa = self.bufs.spare.pop().unwrap_or_default();
                    let (cost, units) = match found {
                        Found::Tree(s) => {
                            let s = *s;
                            (pa.preorder, pa.vals) = (s.preorder, s.vals);
                            (s.cost, s.units)
                        }
                        Found::Over {
                            cost,
                            choices: (a, b),
                        } => {
                            let w = self.w.as_deref().unwrap_or(&g.weight);
                            let mut units = Vec::new();
                            g.read_over(
                                w,
                                &self.bufs.arena[a as usize..b as usize],
                                &mut self.work,
                                &mut self.scratch,
                                (&mut pa.preorder, &mut units, &mut pa.vals),
                            );
                            (cost, units)
                        }
                    };
                    (pa.up, pa.at, pa.same) = (up, at, u32::MAX);
                    // The rest of this subspace: agree on the first i - 1 objects, differ at i
                    // (pushed before the next pop: at once when the tree is passed over, else
                    // on the next call).
                    self.popped += 1;
                    let parent = self.parents.len() as u32;
                    let key = set_key(&units);
                    let head = self.bufs.listed.get(&key).copied().unwrap_or(u32::MAX);
                    let mut q = head;
                    let mut same = false;
                    while let Some(p) = self.parents.get(q as usize) {
                        if same_units(&p.preorder, &pa.preorder) {
                            same = true;
                            break;
                        }
                        q = p.same;
                    }
                    if !same {
                        pa.same = head;
                        self.bufs.listed.insert(key, parent);
                    }
                    self.parents.push(pa);
                    self.deferred = Some((self.popped, cost));
                    if !same {
                        return Ok(Some(Listed { cost, units }));
                    }
                    self.children(g, parent);
                }
            }
        }
        Ok(None)
    }
}

/// One tree of a k-best or bounded enumeration: its units in execution order and its cost
/// (the objective's figure: success probability, unit count or kitchen-input count).
#[derive(Debug, Clone, PartialEq)]
pub struct Ranked {
    pub units: Vec<u32>,
    pub cost: f64,
    /// Its metrics, when computed over the goal's ancestry.
    metrics: Option<TreeMetrics>,
}

/// The k best trees of `goal` for an optimal method, lazily (see the module comment).
pub struct KBest {
    goal: u32,
    method: Method,
    /// `None` when the goal is in the kitchen (one tree, empty) or has no tree, or until the
    /// second tree when the first is read from the kitchen's optimum.
    graph: Option<Arc<Local>>,
    part: Option<Partition>,
    /// The goal in the kitchen: the empty tree is still to be given.
    trivial: bool,
    /// The first tree is still to be read from the kitchen's optimum (as the optimal plan).
    pending: bool,
    /// The units of the first tree, given from the optimum: the partition is built on the
    /// next call.
    given: Option<Vec<u32>>,
    diverse: bool,
    /// Diverse mode: the sets listed so far, and how many of them use each local unit.
    earlier: FxHashSet<Vec<u32>>,
    uses: Vec<u32>,
    evaluations: u64,
}

/// The penalty `--diverse` adds to a unit's weight for each earlier tree that uses it.
pub fn diverse_penalty(method: Method) -> f64 {
    match method {
        Method::OptimalSuccess => std::f64::consts::LN_2,
        _ => 1.0,
    }
}

impl KBest {
    /// Prepares the enumeration; no tree is computed yet. With the kitchen's optimum known,
    /// an underivable goal answers at once, and the first tree is read from the optimum: over
    /// the goal's ancestry when the kitchen keeps it already (`AncestryCache`), else as
    /// the optimal plan reads it, the ancestry being built (and kept) only for a second tree.
    pub fn new(ctx: &Context<'_>, goal: u32, method: Method, diverse: bool) -> Result<Self> {
        if goal as usize >= ctx.foon.object_count() {
            return Err(Error::Invalid(format!("object {goal} is out of range")));
        }
        // Checks the method.
        weights(ctx, method, &[])?;
        let trivial = ctx.in_kitchen(goal);
        let mut pending = false;
        let graph = if trivial {
            None
        } else if let Some(o) = prepared(ctx, method)? {
            // No tree when the optimum is infinite (or the goal not derivable).
            if !o.cost(goal).is_finite() {
                None
            } else if let Some(g) = AncestryCache::get(ctx, goal, method) {
                Some(g)
            } else {
                pending = true;
                None
            }
        } else {
            Some(AncestryCache::local(ctx, goal, method)?)
        };
        let part = graph.as_deref().map(|g| Partition::new(g, None));
        let uses = graph.as_ref().map_or(Vec::new(), |g| vec![0; g.fus.len()]);
        Ok(Self {
            goal,
            method,
            graph,
            part,
            trivial,
            pending,
            given: None,
            diverse,
            earlier: FxHashSet::default(),
            uses,
            evaluations: 0,
        })
    }

    /// Builds the goal's ancestry now when the first tree would be read as the optimal plan
    /// reads it: for a caller that wants more than one tree (the first then comes from the
    /// ancestry too, the same tree with the same figures, and costs less than the plan's way).
    pub fn eager(&mut self, ctx: &Context<'_>) -> Result<()> {
        if self.pending {
            self.start(ctx)?;
            self.pending = false;
        }
        Ok(())
    }

    /// The goal's ancestry (kept by the kitchen, or built) and a partition over it, from the
    /// whole space.
    fn start(&mut self, ctx: &Context<'_>) -> Result<()> {
        let g = AncestryCache::local(ctx, self.goal, self.method)?;
        self.uses = vec![0; g.fus.len()];
        self.part = Some(Partition::new(&g, None));
        self.graph = Some(g);
        Ok(())
    }

    /// Subspaces solved so far (the first from the kitchen's optimum, the others by Knuth's
    /// algorithm over the goal's ancestry).
    pub fn evaluations(&self) -> u64 {
        self.evaluations + self.part.as_ref().map_or(0, |p| p.solved)
    }

    fn reported(&self, cost: f64) -> f64 {
        if self.method == Method::OptimalSuccess {
            (-cost).exp()
        } else {
            cost
        }
    }

    /// Diverse mode: counts the uses of a listed tree's units and restarts the partition
    /// under the penalised weights.
    fn penalise(&mut self, units: &[u32]) {
        let (Some(g), Some(part)) = (self.graph.as_deref(), &mut self.part) else {
            return;
        };
        for f in units {
            if let Ok(i) = g.fus.binary_search(f) {
                self.uses[i] += 1;
            }
        }
        let penalty = diverse_penalty(self.method);
        let w: Vec<f64> = g
            .weight
            .iter()
            .zip(&self.uses)
            .map(|(&w, &u)| w + penalty * f64::from(u))
            .collect();
        self.evaluations += part.solved;
        std::mem::replace(part, Partition::new(g, Some(w))).recycle(g);
    }

    /// The next tree, or `None` when there is none left.
    pub fn next_tree(&mut self, ctx: &Context<'_>) -> Result<Option<Ranked>> {
        if self.trivial {
            self.trivial = false;
            let cost = if self.method == Method::OptimalUnits {
                0.0
            } else {
                1.0
            };
            return Ok(Some(Ranked {
                units: Vec::new(),
                cost,
                metrics: None,
            }));
        }
        if self.pending {
            self.pending = false;
            if let Some(o) = prepared(ctx, self.method)? {
                let units = tree::emit(ctx, self.goal, |x| o.choice(x));
                let cost = self.reported(o.cost(self.goal));
                self.evaluations = 1;
                self.given = Some(units.clone());
                return Ok(Some(Ranked {
                    units,
                    cost,
                    metrics: None,
                }));
            }
        }
        if let Some(first) = self.given.take() {
            self.start(ctx)?;
            if let (false, Some(g), Some(part)) =
                (self.diverse, self.graph.as_deref(), &mut self.part)
            {
                // The root subspace again (its tree is the one given): listed, its children
                // pushed.
                let root = part.next(g, ctx)?;
                debug_assert!(root.is_some_and(|s| s.units == first));
                self.evaluations = 0;
            }
            if self.diverse {
                let mut set = first.clone();
                set.sort_unstable();
                self.earlier.insert(set);
                self.penalise(&first);
            }
        }
        let (Some(g), Some(part)) = (self.graph.as_deref(), &mut self.part) else {
            return Ok(None);
        };
        let Some(s) = (if self.diverse {
            loop {
                let Some(s) = part.next(g, ctx)? else {
                    break None;
                };
                let mut set = s.units.clone();
                set.sort_unstable();
                if self.earlier.insert(set) {
                    break Some(s);
                }
            }
        } else {
            part.next(g, ctx)?
        }) else {
            return Ok(None);
        };
        let metrics = Some(part.last_metrics(g, ctx, &s.units));
        // Under the penalised weights, the cost of the tree's assignment under the plain ones.
        let cost = if part.w.is_some() {
            g.tree_cost(&g.weight, part.last_preorder())
        } else {
            s.cost
        };
        if self.diverse {
            self.penalise(&s.units);
        }
        Ok(Some(Ranked {
            units: s.units,
            cost: self.reported(cost),
            metrics,
        }))
    }

    /// A tree as a plan of this method (metrics filled in).
    pub fn plan_of(&self, ctx: &Context<'_>, r: &Ranked) -> Plan {
        self.plan_from(ctx, r.clone())
    }

    /// [`KBest::plan_of`], the tree's units moved into the plan.
    pub(crate) fn plan_from(&self, ctx: &Context<'_>, r: Ranked) -> Plan {
        let mut p = Plan::empty(
            self.goal,
            Query {
                method: self.method,
                ..Query::default()
            },
        );
        p.units = r.units;
        p.cost = Some(r.cost);
        p.expanded = self.evaluations();
        match r.metrics {
            Some(m) => {
                debug_assert_eq!(m, ctx.metrics(&p.units, self.goal));
                p.height = m.height;
                p.success = m.success;
                p.unrated = m.unrated;
                p.leaf_inputs = m.leaf_inputs;
            }
            None => ctx.fill_metrics(&mut p),
        }
        p
    }
}

impl Drop for KBest {
    fn drop(&mut self) {
        if let (Some(g), Some(part)) = (self.graph.as_deref(), self.part.take()) {
            part.recycle(g);
        }
    }
}

impl Context<'_> {
    /// The `k` best trees of `goal` for an optimal method, in cost order (fewer when there are
    /// fewer trees; none when the goal cannot be made).
    pub fn plan_k(&self, goal: u32, method: Method, k: usize, diverse: bool) -> Result<Vec<Plan>> {
        let mut it = KBest::new(self, goal, method, diverse)?;
        if k > 1 {
            it.eager(self)?;
        }
        let mut out = Vec::with_capacity(k.min(16));
        while out.len() < k {
            let Some(r) = it.next_tree(self)? else { break };
            out.push(it.plan_from(self, r));
        }
        Ok(out)
    }
}
