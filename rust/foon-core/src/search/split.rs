//! The robot/human split: for each budget m = 0..M, the tree and the assignment of at most m
//! of its steps to a human that maximise the tree's success (`docs/METHODS.md`, "The
//! robot/human split").
//!
//! Knuth's algorithm with a label per budget: `label(o)[m]` is the least cost (the sum of
//! `-ln rate` over the tree's steps, a sub-goal counted once per use, as tree cost does) of
//! making `o` with at most m human steps. A unit's label is its own choice (robot at level 0,
//! the better of robot and human above) convolved, in min-plus, with its needed inputs'
//! labels, in input order. Budget levels are settled one after the other; at level m a unit
//! is evaluated when its last needed input is final at level m (the lower levels are final
//! already), so each level is one run of Knuth's algorithm over the goal's ancestry.

use std::collections::BinaryHeap;

use rustc_hash::{FxHashMap, FxHashSet};

use super::optimal::Entry;
use super::scratch::IdMap;
use super::{Context, Explanation, optimal};
use crate::error::{Error, Result};
use crate::index::{Foon, NONE};
use crate::model::MotionRates;
use crate::parse::RateOverrides;

/// One success profile: a motion table, a default rate for motions it lacks, and per-unit
/// overrides (which win over both).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Profile {
    pub rates: Option<MotionRates>,
    pub default_rate: Option<f64>,
    pub overrides: RateOverrides,
}

impl Profile {
    /// Every unit at rate 1 (the human's profile when none is given).
    pub fn certain() -> Self {
        Self {
            rates: None,
            default_rate: Some(1.0),
            overrides: RateOverrides::default(),
        }
    }

    /// The rate of unit `f`: its override, else its motion's rate, else the default rate, else
    /// the error naming the motion.
    pub fn rate(&self, foon: &Foon, f: u32) -> Result<f64> {
        if let Some(r) = self.overrides.get(f) {
            return Ok(r);
        }
        let motion = foon.motion_text(f);
        self.rates
            .as_ref()
            .and_then(|t| t.get(motion))
            .or(self.default_rate)
            .ok_or_else(|| Error::MissingRate {
                motion: motion.to_owned(),
            })
    }
}

/// Who does a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Actor {
    Robot,
    Human,
}

impl Actor {
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Robot => "robot",
            Self::Human => "human",
        }
    }
}

/// One making in a split tree: `unit` makes `object` (with the budget `budget` for its own
/// step and everything below it), done by `actor`, `times` times (a sub-goal used twice is
/// made twice).
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    pub unit: u32,
    pub object: u32,
    pub actor: Actor,
    pub budget: u32,
    pub times: u64,
}

/// A point of the front: at most `human` human steps (exactly that many when it improves on
/// the point before), the success, and the tree.
#[derive(Debug, Clone, PartialEq)]
pub struct SplitPoint {
    pub human: u32,
    pub success: f64,
    /// Makings in execution order (depth-first post-order, needed inputs in input order),
    /// each distinct making once with how many times it is done.
    pub steps: Vec<Step>,
    /// The distinct units of `steps`, in order of first appearance.
    pub units: Vec<u32>,
}

/// A budget of the lab's fixed-tree method: the best robot tree with its `human` step
/// instances of lowest robot rate given to the human.
#[derive(Debug, Clone, PartialEq)]
pub struct FixedPoint {
    pub human: u32,
    /// `exp(-cost)`, the cost summing `times * -ln(rate)` over `steps` in order.
    pub success: f64,
    /// The tree's makings in execution order: (unit, who, how many times); a making whose
    /// instances are shared between both is listed twice, the human's first.
    pub steps: Vec<(u32, Actor, u64)>,
}

/// What [`split`] returns.
#[derive(Debug, Clone, PartialEq)]
pub struct Split {
    pub goal: u32,
    pub max_human: u32,
    pub solved: bool,
    /// Per budget m = 0..=M: the best success with at most m human steps (`None`: no tree).
    pub best: Vec<Option<f64>>,
    /// The budgets that improve on every smaller one, with their trees.
    pub front: Vec<SplitPoint>,
    /// With `fixed_tree`: the lab's method for m = 0..=min(M, the tree's units).
    pub fixed: Option<Vec<FixedPoint>>,
    /// A goal that cannot be made: why (as the sound methods explain it).
    pub explanation: Option<Explanation>,
    /// (object, budget) labels settled over all levels.
    pub expanded: u64,
}

/// `-ln r`, written `0.0 - ln r` so that a rate of 1 weighs +0 (see `optimal::plan`).
fn weight(r: f64) -> f64 {
    0.0 - r.ln()
}

/// The goal's ancestry in local numbering, and the labels of every level.
struct Labels {
    /// Local object -> object id, and back.
    objs: Vec<u32>,
    local: IdMap<u32>,
    leaf: Vec<bool>,
    /// Local unit -> FU id, its robot and human weights.
    fus: Vec<u32>,
    w_robot: Vec<f64>,
    w_human: Vec<f64>,
    /// Needed inputs of each local unit (local objects), flattened.
    ins_start: Vec<usize>,
    ins: Vec<u32>,
    /// Outputs of each local unit whose cost it may set (local objects), flattened.
    outs_start: Vec<usize>,
    outs: Vec<u32>,
    /// For each local object, the local units that need it (one entry per slot).
    by_start: Vec<usize>,
    by: Vec<u32>,
    /// Levels 0..=M.
    levels: usize,
    /// label[o * levels + m].
    label: Vec<f64>,
    /// choice[o * levels + m]: local unit, or NONE.
    choice: Vec<u32>,
    /// depth[o * levels + m]: the tie key of `optimal::tie_depth` at level m.
    depth: Vec<u32>,
    /// Per local unit u, (inputs(u) + 1) partial convolutions of `levels` values each,
    /// starting at `acc_start[u]`: `acc_0` is the unit's own choice, `acc_i` adds input i.
    acc_start: Vec<usize>,
    acc: Vec<f64>,
    expanded: u64,
}

impl Labels {
    fn build(
        ctx: &Context<'_>,
        goal: u32,
        robot: &Profile,
        human: &Profile,
        levels: usize,
    ) -> Result<Self> {
        let foon = ctx.foon;
        let mut local = ctx.id_map(foon.object_count(), NONE);
        let mut seen_fu = ctx.id_map(foon.fu_count(), false);
        let mut objs = vec![goal];
        local.set(goal, 0);
        let mut fus = Vec::new();
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
                if seen_fu.replace(f, true) {
                    continue;
                }
                fus.push(f);
                for &x in ctx.needed(f) {
                    if local.get(x) == NONE {
                        local.set(x, objs.len() as u32);
                        objs.push(x);
                    }
                }
            }
        }
        let leaf: Vec<bool> = objs.iter().map(|&o| ctx.in_kitchen(o)).collect();
        let mut w_robot = Vec::with_capacity(fus.len());
        let mut w_human = Vec::with_capacity(fus.len());
        let (mut ins_start, mut ins) = (vec![0], Vec::new());
        let (mut outs_start, mut outs) = (vec![0], Vec::new());
        let mut acc_start = Vec::with_capacity(fus.len());
        let mut acc_len = 0;
        for &f in &fus {
            w_robot.push(weight(robot.rate(foon, f)?));
            w_human.push(weight(human.rate(foon, f)?));
            ins.extend(ctx.needed(f).iter().map(|&x| local.get(x)));
            ins_start.push(ins.len());
            for &y in foon.outputs(f) {
                let l = local.get(y);
                if l != NONE && !leaf[l as usize] && !foon.is_bare(y) {
                    outs.push(l);
                }
            }
            outs_start.push(outs.len());
            acc_start.push(acc_len);
            acc_len += (ctx.needed(f).len() + 1) * levels;
        }
        let n = objs.len();
        let mut count = vec![0usize; n + 1];
        for &x in &ins {
            count[x as usize + 1] += 1;
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let by_start = count.clone();
        let mut by = vec![0u32; ins.len()];
        for u in 0..fus.len() {
            for &x in &ins[ins_start[u]..ins_start[u + 1]] {
                by[count[x as usize]] = u as u32;
                count[x as usize] += 1;
            }
        }
        Ok(Self {
            objs,
            local,
            leaf,
            fus,
            w_robot,
            w_human,
            ins_start,
            ins,
            outs_start,
            outs,
            by_start,
            by,
            levels,
            label: vec![f64::INFINITY; n * levels],
            choice: vec![NONE; n * levels],
            depth: vec![0; n * levels],
            acc_start,
            acc: vec![f64::INFINITY; acc_len],
            expanded: 0,
        })
    }

    fn inputs(&self, u: usize) -> &[u32] {
        &self.ins[self.ins_start[u]..self.ins_start[u + 1]]
    }

    /// `acc_i[t]` of unit u.
    fn acc_at(&self, u: usize, i: usize, t: usize) -> f64 {
        self.acc[self.acc_start[u] + i * self.levels + t]
    }

    /// The unit's own weight with a budget of t for itself (robot, or the better of both).
    fn own(&self, u: usize, t: usize) -> f64 {
        if t == 0 {
            self.w_robot[u]
        } else {
            self.w_robot[u].min(self.w_human[u])
        }
    }

    /// One term of `acc_i[t]`: `acc_{i-1}[a] + label(input i)[t - a]` (for i >= 1).
    fn term(&self, u: usize, i: usize, t: usize, a: usize) -> f64 {
        let x = self.inputs(u)[i - 1] as usize;
        self.acc_at(u, i - 1, a) + self.label[x * self.levels + t - a]
    }

    /// Fills `acc_i[m]` for every i of unit u (levels below m already filled) and returns the
    /// unit's value at level m.
    fn convolve(&mut self, u: usize, m: usize) -> f64 {
        let k = self.inputs(u).len();
        let base = self.acc_start[u];
        self.acc[base + m] = self.own(u, m);
        for i in 1..=k {
            let mut best = f64::INFINITY;
            for a in 0..=m {
                let v = self.term(u, i, m, a);
                if v < best {
                    best = v;
                }
            }
            self.acc[base + i * self.levels + m] = best;
        }
        self.acc[base + k * self.levels + m]
    }

    /// Settles level m: Knuth's algorithm over the ancestry with the lower levels fixed.
    fn level(&mut self, ctx: &Context<'_>, m: usize) -> Result<()> {
        let n = self.objs.len();
        let lv = self.levels;
        let mut done = vec![false; n];
        let mut fired = vec![false; self.fus.len()];
        let mut left: Vec<u32> = (0..self.fus.len())
            .map(|u| (self.ins_start[u + 1] - self.ins_start[u]) as u32)
            .collect();
        let mut heap = BinaryHeap::new();
        for o in 0..n {
            if self.leaf[o] {
                self.label[o * lv + m] = 0.0;
                self.depth[o * lv + m] = 0;
                heap.push(Entry {
                    cost: 0.0,
                    depth: 0,
                    obj: self.objs[o],
                });
            }
        }
        let mut fire = |s: &mut Self, u: usize, heap: &mut BinaryHeap<Entry>, done: &[bool]| {
            fired[u] = true;
            let c = s.convolve(u, m);
            if c == f64::INFINITY {
                // A unit of infinite cost sets nothing.
                return;
            }
            let d = optimal::tie_depth(
                c,
                s.inputs(u).iter().map(|&x| {
                    let i = x as usize * lv + m;
                    (s.label[i], s.depth[i])
                }),
            );
            let f = s.fus[u];
            for j in s.outs_start[u]..s.outs_start[u + 1] {
                let y = s.outs[j] as usize;
                if done[y] {
                    continue;
                }
                let i = y * lv + m;
                let (old, old_depth, old_choice) = (s.label[i], s.depth[i], s.choice[i]);
                let old_fu = if old_choice == NONE {
                    NONE
                } else {
                    s.fus[old_choice as usize]
                };
                // Costs are compared exactly: the tie goes to the lower (depth, unit index).
                if optimal::better(c, d, f, old, old_depth, old_fu) {
                    if optimal::lower(c, d, old, old_depth) {
                        heap.push(Entry {
                            cost: c,
                            depth: d,
                            obj: s.objs[y],
                        });
                    }
                    s.label[i] = c;
                    s.depth[i] = d;
                    s.choice[i] = u as u32;
                }
            }
        };
        for (u, &l) in left.iter().enumerate() {
            if l == 0 {
                fire(self, u, &mut heap, &done);
            }
        }
        while let Some(Entry {
            cost: c,
            depth: d,
            obj,
        }) = heap.pop()
        {
            let o = self.local.get(obj) as usize;
            if done[o] || optimal::lower(self.label[o * lv + m], self.depth[o * lv + m], c, d) {
                continue;
            }
            done[o] = true;
            self.expanded += 1;
            if self.expanded % 4096 == 0 {
                ctx.check_stop()?;
            }
            for j in self.by_start[o]..self.by_start[o + 1] {
                let u = self.by[j] as usize;
                left[u] -= 1;
                if left[u] == 0 {
                    fire(self, u, &mut heap, &done);
                }
            }
        }
        for (o, &d) in done.iter().enumerate() {
            if !d {
                self.label[o * lv + m] = f64::INFINITY;
                self.choice[o * lv + m] = NONE;
            }
        }
        // Units that never ran at this level still need their partial sums at it.
        for (u, &fu) in fired.iter().enumerate() {
            if !fu {
                self.convolve(u, m);
            }
        }
        Ok(())
    }

    /// How the choice of (o, m) spends its budget: (human for the unit itself, the budget of
    /// each needed input). The first minimal split in ascending order, as `convolve` found it.
    fn split_of(&self, u: usize, m: usize) -> (bool, Vec<usize>) {
        let k = self.inputs(u).len();
        let mut budgets = vec![0; k];
        let mut t = m;
        for i in (1..=k).rev() {
            let want = self.acc_at(u, i, t);
            // Exact equality: the same sum as `convolve` computed.
            #[allow(clippy::float_cmp)]
            let a = (0..=t)
                .find(|&a| self.term(u, i, t, a) == want)
                .unwrap_or(0);
            budgets[i - 1] = t - a;
            t = a;
        }
        let human = t > 0 && self.w_human[u] < self.w_robot[u];
        (human, budgets)
    }

    /// The tree of (goal, m): the makings of the distinct (object, budget) states it reaches,
    /// in depth-first post-order, each with the number of times it is made.
    fn tree(&self, goal: usize, m: usize) -> Vec<Step> {
        let lv = self.levels;
        // Post-order of the states (no call-stack recursion).
        let mut order: Vec<(usize, usize)> = Vec::new();
        let mut pos: FxHashMap<(usize, usize), usize> = FxHashMap::default();
        let mut parts: Vec<(bool, Vec<usize>)> = Vec::new();
        let mut stack: Vec<(usize, usize, usize, bool, Vec<usize>)> = Vec::new();
        let push = |o: usize,
                    b: usize,
                    stack: &mut Vec<(usize, usize, usize, bool, Vec<usize>)>,
                    pos: &FxHashMap<(usize, usize), usize>| {
            // In a DAG of states, one not yet listed is never on the stack twice.
            if self.leaf[o] || pos.contains_key(&(o, b)) {
                return;
            }
            let u = self.choice[o * lv + b] as usize;
            let (h, budgets) = self.split_of(u, b);
            stack.push((o, b, 0, h, budgets));
        };
        push(goal, m, &mut stack, &pos);
        while let Some(top) = stack.last_mut() {
            let (o, b, i) = (top.0, top.1, top.2);
            let u = self.choice[o * lv + b] as usize;
            let ins = self.inputs(u);
            if i < ins.len() {
                top.2 += 1;
                let (x, xb) = (ins[i] as usize, top.4[i]);
                push(x, xb, &mut stack, &pos);
            } else {
                let (o, b, _, h, budgets) = stack.pop().expect("the top is there");
                pos.insert((o, b), order.len());
                order.push((o, b));
                parts.push((h, budgets));
            }
        }
        // Times each state is made: the root once, and each use by a making adds its times
        // (parents come after their children in post-order).
        let mut times = vec![0u64; order.len()];
        if let Some(last) = times.last_mut() {
            *last = 1;
        }
        for s in (0..order.len()).rev() {
            let (o, b) = order[s];
            let u = self.choice[o * lv + b] as usize;
            for (i, &x) in self.inputs(u).iter().enumerate() {
                if let Some(&c) = pos.get(&(x as usize, parts[s].1[i])) {
                    times[c] = times[c].saturating_add(times[s]);
                }
            }
        }
        order
            .iter()
            .enumerate()
            .map(|(s, &(o, b))| {
                let u = self.choice[o * lv + b] as usize;
                Step {
                    unit: self.fus[u],
                    object: self.objs[o],
                    actor: if parts[s].0 {
                        Actor::Human
                    } else {
                        Actor::Robot
                    },
                    budget: b as u32,
                    times: times[s],
                }
            })
            .collect()
    }
}

/// Distinct units of `steps` in order of first appearance.
fn distinct_units(steps: &[Step]) -> Vec<u32> {
    let mut seen = FxHashSet::default();
    steps
        .iter()
        .filter(|s| seen.insert(s.unit))
        .map(|s| s.unit)
        .collect()
}

/// The split of `goal` for budgets 0..=`max_human` (see the module documentation), with the
/// lab's fixed-tree method when `fixed_tree`. `robot` and `human` give every unit's rates
/// (a unit of the goal's ancestry without one is the error naming its motion).
pub fn split(
    ctx: &Context<'_>,
    goal: u32,
    robot: &Profile,
    human: &Profile,
    max_human: u32,
    fixed_tree: bool,
) -> Result<Split> {
    let foon = ctx.foon;
    if goal as usize >= foon.object_count() {
        return Err(Error::Invalid(format!("object {goal} is out of range")));
    }
    robot.overrides.check_units(foon.fu_count())?;
    human.overrides.check_units(foon.fu_count())?;
    let levels = max_human as usize + 1;
    let mut out = Split {
        goal,
        max_human,
        solved: true,
        best: vec![None; levels],
        front: Vec::new(),
        fixed: None,
        explanation: None,
        expanded: 0,
    };
    if ctx.in_kitchen(goal) {
        out.best = vec![Some(1.0); levels];
        out.front.push(SplitPoint {
            human: 0,
            success: 1.0,
            steps: Vec::new(),
            units: Vec::new(),
        });
        if fixed_tree {
            out.fixed = Some(vec![FixedPoint {
                human: 0,
                success: 1.0,
                steps: Vec::new(),
            }]);
        }
        return Ok(out);
    }
    if ctx.ranks().rank(goal).is_none() {
        out.solved = false;
        out.explanation = Some(optimal::explain(ctx, goal)?);
        return Ok(out);
    }
    let mut labels = Labels::build(ctx, goal, robot, human, levels)?;
    for m in 0..levels {
        labels.level(ctx, m)?;
    }
    out.expanded = labels.expanded;
    let g = 0usize;
    let mut last = f64::INFINITY;
    for m in 0..levels {
        let c = labels.label[g * levels + m];
        if c.is_finite() {
            out.best[m] = Some((-c).exp());
        }
        if c < last {
            last = c;
            let steps = labels.tree(g, m);
            out.front.push(SplitPoint {
                human: m as u32,
                success: (-c).exp(),
                units: distinct_units(&steps),
                steps,
            });
        }
    }
    if out.front.is_empty() {
        // Derivable, but every tree needs a step of rate 0 for whoever may do it.
        out.solved = false;
        out.explanation = Some(Explanation::default());
        return Ok(out);
    }
    if fixed_tree {
        out.fixed = labels.fixed(foon, robot, human, max_human)?;
    }
    Ok(out)
}

impl Labels {
    /// The lab's method on the best robot tree (the makings of budget 0, as tree cost counts
    /// them): the `m` step instances of lowest robot rate (ties: the earlier making) are done
    /// by the human. `None` when no robot tree exists.
    fn fixed(
        &self,
        foon: &Foon,
        robot: &Profile,
        human: &Profile,
        max_human: u32,
    ) -> Result<Option<Vec<FixedPoint>>> {
        if !self.label[0].is_finite() {
            return Ok(None);
        }
        let steps = self.tree(0, 0);
        let rr: Vec<f64> = steps
            .iter()
            .map(|s| robot.rate(foon, s.unit))
            .collect::<Result<_>>()?;
        let hr: Vec<f64> = steps
            .iter()
            .map(|s| human.rate(foon, s.unit))
            .collect::<Result<_>>()?;
        let mut by_rate: Vec<usize> = (0..steps.len()).collect();
        by_rate.sort_by(|&a, &b| rr[a].total_cmp(&rr[b]).then(a.cmp(&b)));
        let total = steps.iter().fold(0u64, |t, s| t.saturating_add(s.times));
        let top = u64::from(max_human).min(total);
        let mut points = Vec::new();
        for m in 0..=top {
            let mut to_human = vec![0u64; steps.len()];
            let mut left = m;
            for &i in &by_rate {
                let h = left.min(steps[i].times);
                to_human[i] = h;
                left -= h;
            }
            let mut cost = 0.0;
            let mut out = Vec::new();
            for (i, s) in steps.iter().enumerate() {
                let (h, r) = (to_human[i], s.times - to_human[i]);
                if h > 0 {
                    cost += h as f64 * weight(hr[i]);
                    out.push((s.unit, Actor::Human, h));
                }
                if r > 0 {
                    cost += r as f64 * weight(rr[i]);
                    out.push((s.unit, Actor::Robot, r));
                }
            }
            points.push(FixedPoint {
                human: m as u32,
                success: (-cost).exp(),
                steps: out,
            });
        }
        Ok(Some(points))
    }
}
