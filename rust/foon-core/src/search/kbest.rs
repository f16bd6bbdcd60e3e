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
//! tree they were cut from) comes first. Assignments that give a set of units already listed
//! are skipped, so every set comes once, at its lowest cost.

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap, HashSet};

use super::{Context, Method, Plan, Query};
use crate::error::{Error, Result};
use crate::index::NONE;

/// The goal's ancestry as a small graph of local ids (derivable objects, and the units whose
/// needed inputs are all derivable: nothing else is in a tree) (objects and units in id order, so every
/// tie is broken as in the global search).
pub(super) struct Local {
    /// Global id of each local object.
    objs: Vec<u32>,
    leaf: Vec<bool>,
    /// Global id of each local unit.
    fus: Vec<u32>,
    needed: Vec<Vec<u32>>,
    /// Outputs a unit can set: in the ancestry, not a leaf, not bare.
    outs: Vec<Vec<u32>>,
    /// Units needing an object, once per needed slot.
    needed_by: Vec<Vec<u32>>,
    weight: Vec<f64>,
    leaf_cost: f64,
    goal: u32,
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

impl Local {
    pub(super) fn new(ctx: &Context<'_>, goal: u32, method: Method) -> Result<Self> {
        let foon = ctx.foon;
        let ranks = ctx.ranks();
        let mut objs = vec![goal];
        let mut seen_o = HashSet::from([goal]);
        let mut fus = Vec::new();
        let mut seen_f = HashSet::new();
        let mut next = 0;
        while let Some(&o) = objs.get(next) {
            next += 1;
            if next % 4096 == 0 {
                ctx.check_stop()?;
            }
            if ctx.in_kitchen(o) {
                continue;
            }
            for &f in foon.producers(o) {
                // A unit with an input that cannot be made is in no tree.
                if !ranks
                    .rank(o)
                    .is_some_and(|_| ctx.needed(f).iter().all(|&x| ranks.rank(x).is_some()))
                    || !seen_f.insert(f)
                {
                    continue;
                }
                fus.push(f);
                for &x in ctx.needed(f) {
                    if seen_o.insert(x) {
                        objs.push(x);
                    }
                }
            }
        }
        objs.sort_unstable();
        fus.sort_unstable();
        let at: HashMap<u32, u32> = objs
            .iter()
            .enumerate()
            .map(|(i, &o)| (o, i as u32))
            .collect();
        let leaf: Vec<bool> = objs.iter().map(|&o| ctx.in_kitchen(o)).collect();
        let mut needed_by = vec![Vec::new(); objs.len()];
        let mut needed = Vec::with_capacity(fus.len());
        let mut outs = Vec::with_capacity(fus.len());
        for (i, &f) in fus.iter().enumerate() {
            let ins: Vec<u32> = ctx.needed(f).iter().map(|x| at[x]).collect();
            for &x in &ins {
                needed_by[x as usize].push(i as u32);
            }
            needed.push(ins);
            let mut os: Vec<u32> = foon
                .outputs(f)
                .iter()
                .filter(|&&y| !foon.is_bare(y))
                .filter_map(|y| at.get(y).copied())
                .filter(|&y| !leaf[y as usize])
                .collect();
            os.dedup();
            outs.push(os);
        }
        let (weight, leaf_cost) = weights(ctx, method, &fus)?;
        Ok(Self {
            goal: at[&goal],
            objs,
            leaf,
            fus,
            needed,
            outs,
            needed_by,
            weight,
            leaf_cost,
        })
    }
}

#[derive(PartialEq)]
struct Entry {
    cost: f64,
    obj: u32,
}

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        // Min-heap on (cost, object id).
        other
            .cost
            .total_cmp(&self.cost)
            .then(other.obj.cmp(&self.obj))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Constraints of a subspace: (object, unit) pairs in local ids.
#[derive(Clone, Default)]
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
}

/// Reusable per-run state of Knuth's algorithm over the local graph.
struct Work {
    cost: Vec<f64>,
    choice: Vec<u32>,
    done: Vec<bool>,
    left: Vec<u32>,
    fixed: Vec<u32>,
    banned: Vec<bool>,
    heap: BinaryHeap<Entry>,
}

impl Work {
    fn new(g: &Local) -> Self {
        Self {
            cost: vec![f64::INFINITY; g.objs.len()],
            choice: vec![NONE; g.objs.len()],
            done: vec![false; g.objs.len()],
            left: vec![0; g.fus.len()],
            fixed: vec![NONE; g.objs.len()],
            banned: vec![false; g.objs.len()],
            heap: BinaryHeap::new(),
        }
    }
}

impl Local {
    /// Knuth's algorithm under `c` with weights `w`: the best tree, or `None` when the
    /// subspace is empty (or every tree in it costs +infinity).
    fn solve(&self, w: &[f64], c: &Constraints, work: &mut Work) -> Option<Solved> {
        let n = self.objs.len();
        work.cost.fill(f64::INFINITY);
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
                    obj: o as u32,
                });
            }
        }
        let allowed = |work: &Work, y: u32, f: u32| {
            let fx = work.fixed[y as usize];
            (fx == NONE || fx == f) && !(work.banned[y as usize] && c.banned.contains(&(y, f)))
        };
        let fire = |f: u32, work: &mut Work| {
            let mut cost = w[f as usize];
            for &x in &self.needed[f as usize] {
                cost += work.cost[x as usize];
            }
            for &y in &self.outs[f as usize] {
                let yi = y as usize;
                if work.done[yi] || !allowed(work, y, f) {
                    continue;
                }
                let (old_cost, old_choice) = (work.cost[yi], work.choice[yi]);
                #[allow(clippy::float_cmp)]
                let better = cost < old_cost || (cost == old_cost && f < old_choice);
                if better {
                    if cost < old_cost {
                        work.heap.push(Entry { cost, obj: y });
                    }
                    work.cost[yi] = cost;
                    work.choice[yi] = f;
                }
            }
        };
        for f in 0..self.fus.len() as u32 {
            if work.left[f as usize] == 0 {
                fire(f, work);
            }
        }
        while let Some(Entry { cost, obj: o }) = work.heap.pop() {
            let oi = o as usize;
            if work.done[oi] || cost > work.cost[oi] {
                continue;
            }
            work.done[oi] = true;
            if o == self.goal {
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
        let g = self.goal as usize;
        if !work.done[g] || !work.cost[g].is_finite() {
            return None;
        }
        let (preorder, units) = self.read(&|o| work.choice[o as usize]);
        Some(Solved {
            cost: work.cost[g],
            preorder,
            units,
        })
    }

    /// The tree of the choices from the goal: (pre-order objects with their choices, units in
    /// depth-first post-order), as `tree::emit` reads them.
    fn read(&self, choice: &dyn Fn(u32) -> u32) -> (Vec<(u32, u32)>, Vec<u32>) {
        let mut seen = vec![false; self.objs.len()];
        let mut emitted = vec![false; self.fus.len()];
        let mut pre = Vec::new();
        let mut units = Vec::new();
        let mut stack: Vec<(u32, usize)> = Vec::new();
        let mut visit = |o: u32, stack: &mut Vec<(u32, usize)>, emitted: &[bool]| {
            if self.leaf[o as usize] || seen[o as usize] {
                return;
            }
            seen[o as usize] = true;
            let f = choice(o);
            pre.push((o, f));
            if !emitted[f as usize] {
                stack.push((f, 0));
            }
        };
        visit(self.goal, &mut stack, &emitted);
        while let Some(&mut (f, ref mut i)) = stack.last_mut() {
            let ins = &self.needed[f as usize];
            if *i < ins.len() {
                let x = ins[*i];
                *i += 1;
                visit(x, &mut stack, &emitted);
            } else {
                stack.pop();
                if !emitted[f as usize] {
                    emitted[f as usize] = true;
                    units.push(self.fus[f as usize]);
                }
            }
        }
        (pre, units)
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

enum Node {
    Open(Constraints),
    Done(Constraints, Solved),
}

struct Item {
    key: f64,
    /// 0 for a solved subspace, 1 for one to solve: on equal keys a solved tree comes first.
    rank: u8,
    seq: u64,
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
            .then(other.rank.cmp(&self.rank))
            .then(other.seq.cmp(&self.seq))
    }
}
impl PartialOrd for Item {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Every tree of the local graph under the weights `w`, in (cost, partition order), each set of
/// units once.
struct Partition {
    w: Vec<f64>,
    heap: BinaryHeap<Item>,
    seq: u64,
    listed: HashSet<Vec<u32>>,
    work: Work,
    /// Subspaces solved so far.
    solved: u64,
}

impl Partition {
    fn new(g: &Local, w: Vec<f64>) -> Self {
        let mut p = Self {
            w,
            heap: BinaryHeap::new(),
            seq: 0,
            listed: HashSet::new(),
            work: Work::new(g),
            solved: 0,
        };
        p.push(f64::NEG_INFINITY, 1, Node::Open(Constraints::default()));
        p
    }

    fn push(&mut self, key: f64, rank: u8, node: Node) {
        self.seq += 1;
        self.heap.push(Item {
            key,
            rank,
            seq: self.seq,
            node,
        });
    }

    /// The next tree (cost, pre-order choices, units), or `None` when every tree was listed.
    fn next(&mut self, g: &Local, ctx: &Context<'_>) -> Result<Option<Solved>> {
        while let Some(item) = self.heap.pop() {
            match item.node {
                Node::Open(c) => {
                    self.solved += 1;
                    ctx.check_stop()?;
                    if let Some(s) = g.solve(&self.w, &c, &mut self.work) {
                        self.push(s.cost, 0, Node::Done(c, s));
                    }
                }
                Node::Done(c, s) => {
                    // The rest of this subspace: agree on the first i - 1 objects, differ at i.
                    let mut fixed = c.fixed.clone();
                    for &(o, f) in &s.preorder {
                        if !c.fixed.iter().any(|&(x, _)| x == o) {
                            let mut banned = c.banned.clone();
                            banned.push((o, f));
                            let child = Constraints {
                                fixed: fixed.clone(),
                                banned,
                            };
                            self.push(s.cost, 1, Node::Open(child));
                            fixed.push((o, f));
                        }
                    }
                    let mut set = s.units.clone();
                    set.sort_unstable();
                    if self.listed.insert(set) {
                        return Ok(Some(s));
                    }
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
}

/// The k best trees of `goal` for an optimal method, lazily (see the module comment).
pub struct KBest {
    goal: u32,
    method: Method,
    /// `None` when the goal is in the kitchen (one tree, empty) or has no tree.
    graph: Option<Local>,
    part: Option<Partition>,
    /// The goal in the kitchen: the empty tree is still to be given.
    trivial: bool,
    diverse: bool,
    /// Diverse mode: the sets listed so far, and how many of them use each local unit.
    earlier: HashSet<Vec<u32>>,
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
    /// Prepares the enumeration (the goal's ancestry and its weights); no tree is computed yet.
    pub fn new(ctx: &Context<'_>, goal: u32, method: Method, diverse: bool) -> Result<Self> {
        if goal as usize >= ctx.foon.object_count() {
            return Err(Error::Invalid(format!("object {goal} is out of range")));
        }
        let trivial = ctx.in_kitchen(goal);
        let graph = if trivial {
            // Still checks the method.
            weights(ctx, method, &[])?;
            None
        } else {
            Some(Local::new(ctx, goal, method)?)
        };
        let part = graph.as_ref().map(|g| Partition::new(g, g.weight.clone()));
        let uses = graph.as_ref().map_or(Vec::new(), |g| vec![0; g.fus.len()]);
        Ok(Self {
            goal,
            method,
            graph,
            part,
            trivial,
            diverse,
            earlier: HashSet::new(),
            uses,
            evaluations: 0,
        })
    }

    /// Subspaces solved so far (Knuth runs over the goal's ancestry).
    pub fn evaluations(&self) -> u64 {
        self.evaluations + self.part.as_ref().map_or(0, |p| p.solved)
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
            }));
        }
        let (Some(g), Some(part)) = (&self.graph, &mut self.part) else {
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
        let cost = if self.diverse {
            // Penalise this tree's units for the next one, and restart the partition.
            let at: HashMap<u32, usize> = g.fus.iter().enumerate().map(|(i, &f)| (f, i)).collect();
            for f in &s.units {
                self.uses[at[f]] += 1;
            }
            let penalty = diverse_penalty(self.method);
            let w: Vec<f64> = g
                .weight
                .iter()
                .zip(&self.uses)
                .map(|(&w, &u)| w + penalty * f64::from(u))
                .collect();
            self.evaluations += part.solved;
            *part = Partition::new(g, w);
            g.tree_cost(&g.weight, &s.preorder)
        } else {
            s.cost
        };
        let cost = if self.method == Method::OptimalSuccess {
            (-cost).exp()
        } else {
            cost
        };
        Ok(Some(Ranked {
            units: s.units,
            cost,
        }))
    }

    /// A tree as a plan of this method (metrics filled in).
    pub fn plan_of(&self, ctx: &Context<'_>, r: &Ranked) -> Plan {
        let mut p = Plan::empty(
            self.goal,
            Query {
                method: self.method,
                ..Query::default()
            },
        );
        p.units.clone_from(&r.units);
        p.cost = Some(r.cost);
        p.expanded = self.evaluations();
        ctx.fill_metrics(&mut p);
        p
    }
}

impl Context<'_> {
    /// The `k` best trees of `goal` for an optimal method, in cost order (fewer when there are
    /// fewer trees; none when the goal cannot be made).
    pub fn plan_k(&self, goal: u32, method: Method, k: usize, diverse: bool) -> Result<Vec<Plan>> {
        let mut it = KBest::new(self, goal, method, diverse)?;
        let mut out = Vec::new();
        while out.len() < k {
            let Some(r) = it.next_tree(self)? else { break };
            out.push(it.plan_of(self, &r));
        }
        Ok(out)
    }
}
