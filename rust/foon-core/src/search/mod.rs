//! Task-tree retrieval over the compact index. Every search is a plain function of an
//! immutable [`Context`] (no global state), so many goals can be planned in parallel.
//! The exact definitions are in `docs/METHODS.md`.

pub mod batch;
mod course;
mod forward;
mod greedy;
mod heuristic;
mod ids;
mod optimal;
mod scratch;
mod tree;

use std::str::FromStr;
use std::sync::OnceLock;
use std::time::Instant;

use rustc_hash::{FxHashMap, FxHashSet};

use crate::error::{Error, Result};
use crate::index::{Csr, Foon, NONE};
use crate::model::{MotionRates, ObjectSpec};

pub use forward::Ranks;

/// A planning method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    Bfs,
    Ids,
    GreedySuccess,
    GreedyInputs,
    OptimalSuccess,
    OptimalUnits,
    OptimalInputs,
}

impl Method {
    pub const ALL: [Method; 7] = [
        Self::Bfs,
        Self::Ids,
        Self::GreedySuccess,
        Self::GreedyInputs,
        Self::OptimalSuccess,
        Self::OptimalUnits,
        Self::OptimalInputs,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            Self::Bfs => "bfs",
            Self::Ids => "ids",
            Self::GreedySuccess => "greedy-success",
            Self::GreedyInputs => "greedy-inputs",
            Self::OptimalSuccess => "optimal-success",
            Self::OptimalUnits => "optimal-units",
            Self::OptimalInputs => "optimal-inputs",
        }
    }

    /// Whether this method needs motion rates to choose.
    pub fn uses_rates(self) -> bool {
        matches!(self, Self::GreedySuccess | Self::OptimalSuccess)
    }
}

impl FromStr for Method {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|m| m.as_str() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|m| m.as_str()).collect();
                Error::Invalid(format!(
                    "unknown method '{s}' (choose from {})",
                    names.join(", ")
                ))
            })
    }
}

/// Which semantics: the course code's, or sound (always executable) trees.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Compat {
    #[default]
    Sound,
    Course,
}

impl FromStr for Compat {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "sound" | "none" => Ok(Self::Sound),
            "course" => Ok(Self::Course),
            _ => Err(Error::Invalid(format!(
                "unknown compatibility '{s}' (choose from course, sound)"
            ))),
        }
    }
}

/// How `greedy-inputs` counts the inputs of an FU.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Count {
    #[default]
    Nodes,
    Ingredients,
}

impl FromStr for Count {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "nodes" => Ok(Self::Nodes),
            "ingredients" => Ok(Self::Ingredients),
            _ => Err(Error::Invalid(format!(
                "unknown count '{s}' (choose from nodes, ingredients)"
            ))),
        }
    }
}

/// Options of one planning call.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Query {
    pub method: Method,
    pub compat: Compat,
    pub count: Count,
}

impl Default for Query {
    fn default() -> Self {
        Self {
            method: Method::Ids,
            compat: Compat::Sound,
            count: Count::Nodes,
        }
    }
}

/// Why a sound search failed.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Explanation {
    /// Raw items outside the kitchen that a tree would need (ids, in id order).
    pub missing: Vec<u32>,
    /// When only cycles block the goal: the objects of one blocking cycle, in order, and the
    /// FUs that lead from each to the next.
    pub cycle: Vec<u32>,
    pub cycle_units: Vec<u32>,
}

/// A planning result.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    pub goal: u32,
    pub query: Query,
    pub solved: bool,
    /// FU indices, in output order.
    pub units: Vec<u32>,
    /// Course methods: objects reached that are neither in the kitchen nor produced.
    pub unresolved: Vec<u32>,
    /// Sound methods that failed: why.
    pub explanation: Option<Explanation>,
    pub height: Option<u32>,
    /// Product of the motion rates of the units; `None` without a rate table, or when a unit's
    /// motion has no rate (then `unrated` names the first such unit).
    pub success: Option<f64>,
    /// When a rate table was given: the first unit (in output order) whose motion has no
    /// rate, which is why `success` is `None`. Only methods that do not choose by rate can
    /// return such a tree (the others fail with [`Error::MissingRate`]).
    pub unrated: Option<u32>,
    /// Optimal methods: the optimum of the cost they minimise.
    pub cost: Option<f64>,
    pub leaf_inputs: usize,
    pub expanded: u64,
    pub peak_frontier: usize,
    pub seconds: f64,
}

/// Planning inputs prepared for one FOON: the kitchen matched to objects, the container rule
/// applied (needed inputs), the motion rate of every FU. It owns its data, so it can be kept
/// and reused for any number of plans ([`Context::with`]); it is `Send + Sync`.
pub struct Prepared {
    objects: usize,
    fus: usize,
    in_kitchen: Vec<bool>,
    kitchen_objects: Vec<u32>,
    /// Needed inputs of each FU (container rule applied), in input order.
    needed: Csr,
    /// For each object, the FUs where it is a needed input (one entry per slot).
    needed_by: Csr,
    fu_rate: Vec<f64>,
    rates_given: bool,
    ranks: OnceLock<Ranks>,
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
        if let Some(r) = default_rate {
            crate::check_rate(None, r)?;
        }
        let n = foon.object_count();
        let mut in_kitchen = vec![false; n];
        let mut kitchen_objects = Vec::new();
        for item in kitchen {
            if let Some(o) = item.find_in(foon) {
                if !in_kitchen[o as usize] {
                    in_kitchen[o as usize] = true;
                    kitchen_objects.push(o);
                }
            }
        }
        kitchen_objects.sort_unstable();
        let utensil_ids: FxHashSet<u32> = utensils
            .iter()
            .filter_map(|u| foon.strings().get(u))
            .collect();
        let needed = needed_inputs(foon, &utensil_ids);
        let n_fu = foon.fu_count() as u32;
        let needed_by = Csr::from_pairs(
            n,
            (0..n_fu).flat_map(|f| needed.row(f).iter().map(move |&o| (o, f))),
        );
        let fu_rate = (0..n_fu)
            .map(|f| {
                rates
                    .and_then(|r| r.get(foon.motion_text(f)))
                    .or(default_rate)
                    .unwrap_or(f64::NAN)
            })
            .collect();
        Ok(Self {
            objects: n,
            fus: n_fu as usize,
            in_kitchen,
            kitchen_objects,
            needed,
            needed_by,
            fu_rate,
            rates_given: rates.is_some() || default_rate.is_some(),
            ranks: OnceLock::new(),
        })
    }
}

enum Prep<'a> {
    Owned(Box<Prepared>),
    Borrowed(&'a Prepared),
}

/// Everything planning needs besides the goal: the FOON and its [`Prepared`] inputs. Shared by
/// any number of searches and threads.
pub struct Context<'a> {
    pub foon: &'a Foon,
    prep: Prep<'a>,
    cancel: Option<&'a (dyn Fn() -> bool + Sync)>,
    /// Searches keep per-object state in arrays up to this many ids, in hash maps beyond.
    scratch_limit: usize,
}

impl std::ops::Deref for Context<'_> {
    type Target = Prepared;
    fn deref(&self) -> &Prepared {
        match &self.prep {
            Prep::Owned(p) => p,
            Prep::Borrowed(p) => p,
        }
    }
}

impl<'a> Context<'a> {
    /// Builds the context (see [`Prepared::new`]).
    pub fn new(
        foon: &'a Foon,
        kitchen: &[ObjectSpec],
        utensils: &[String],
        rates: Option<&MotionRates>,
        default_rate: Option<f64>,
    ) -> Result<Self> {
        let p = Prepared::new(foon, kitchen, utensils, rates, default_rate)?;
        Ok(Self {
            foon,
            prep: Prep::Owned(Box::new(p)),
            cancel: None,
            scratch_limit: scratch::DENSE_MAX,
        })
    }

    /// A context over inputs prepared earlier for this same FOON.
    pub fn with(foon: &'a Foon, prep: &'a Prepared) -> Result<Self> {
        if prep.objects != foon.object_count() || prep.fus != foon.fu_count() {
            return Err(Error::Invalid(
                "these planning inputs were prepared for another FOON".into(),
            ));
        }
        Ok(Self {
            foon,
            prep: Prep::Borrowed(prep),
            cancel: None,
            scratch_limit: scratch::DENSE_MAX,
        })
    }

    /// Makes long searches call `cancel` every few thousand steps and return
    /// [`Error::Cancelled`] once it answers true.
    #[must_use]
    pub fn with_cancel(mut self, cancel: &'a (dyn Fn() -> bool + Sync)) -> Self {
        self.cancel = Some(cancel);
        self
    }

    /// Sets how many ids a search's per-object state may hold in plain arrays before it
    /// switches to hash maps (default 32,768). Results never depend on it; tests use it to run
    /// both forms on the same FOON.
    #[doc(hidden)]
    #[must_use]
    pub fn with_scratch_limit(mut self, ids: usize) -> Self {
        self.scratch_limit = ids;
        self
    }

    /// Per-search state over `len` ids (objects or FUs), all at `default`.
    fn id_map<T: Copy + PartialEq>(&self, len: usize, default: T) -> scratch::IdMap<T> {
        scratch::IdMap::new(len, default, self.scratch_limit)
    }

    #[inline]
    pub fn in_kitchen(&self, o: u32) -> bool {
        self.in_kitchen[o as usize]
    }

    /// Kitchen objects of the FOON, in id order.
    pub fn kitchen_objects(&self) -> &[u32] {
        &self.kitchen_objects
    }

    /// Needed inputs of `fu` (after the container rule).
    #[inline]
    pub fn needed(&self, fu: u32) -> &[u32] {
        self.needed.row(fu)
    }

    /// Success rate of `fu`'s motion, or the error naming the motion.
    pub fn rate(&self, fu: u32) -> Result<f64> {
        let r = self.fu_rate[fu as usize];
        if r.is_nan() {
            Err(Error::MissingRate {
                motion: self.foon.motion_text(fu).to_owned(),
            })
        } else {
            Ok(r)
        }
    }

    /// Ranks from the kitchen plus the objects marked in `extra`.
    pub fn ranks_with(&self, extra: &[bool]) -> Ranks {
        forward::ranks(self, Some(extra))
    }

    /// Ranks and derivability from the kitchen (computed once, on first use).
    pub fn ranks(&self) -> &Ranks {
        self.ranks.get_or_init(|| forward::ranks(self, None))
    }

    fn check_stop(&self) -> Result<()> {
        match self.cancel {
            Some(c) if c() => Err(Error::Cancelled),
            _ => Ok(()),
        }
    }

    /// The goal object for a spec, or the course's error.
    pub fn goal(&self, spec: &ObjectSpec) -> Result<u32> {
        self.foon.goal_by_spec(spec)
    }

    /// Plans one goal.
    pub fn plan(&self, goal: u32, query: Query) -> Result<Plan> {
        let start = Instant::now();
        if goal as usize >= self.foon.object_count() {
            return Err(Error::Invalid(format!("object {goal} is out of range")));
        }
        // `bfs` is the course loop, whatever compatibility was asked for: its trees are
        // labelled course, never sound.
        let query = if query.method == Method::Bfs {
            Query {
                compat: Compat::Course,
                ..query
            }
        } else {
            query
        };
        let mut plan = match (query.compat, query.method) {
            (
                Compat::Course,
                Method::OptimalSuccess | Method::OptimalUnits | Method::OptimalInputs,
            ) => {
                return Err(Error::Invalid(format!(
                    "method {} has no course-compatible form",
                    query.method.as_str()
                )));
            }
            (Compat::Course, _) => course::plan(self, goal, query)?,
            (Compat::Sound, method) => {
                if self.in_kitchen(goal) {
                    let mut p = self.empty_plan(goal, query);
                    // Nothing to do: success 1, no unit, the goal itself as the one input.
                    p.cost = match method {
                        Method::OptimalSuccess | Method::OptimalInputs => Some(1.0),
                        Method::OptimalUnits => Some(0.0),
                        _ => None,
                    };
                    p
                } else if self.ranks().rank(goal).is_none() {
                    let mut p = self.empty_plan(goal, query);
                    p.solved = false;
                    p.explanation = Some(optimal::explain(self, goal)?);
                    p
                } else {
                    match method {
                        Method::Ids => ids::plan(self, goal, query)?,
                        Method::GreedySuccess | Method::GreedyInputs => {
                            greedy::plan(self, goal, query)?
                        }
                        _ => optimal::plan(self, goal, query)?,
                    }
                }
            }
        };
        self.fill_metrics(&mut plan);
        plan.seconds = start.elapsed().as_secs_f64();
        Ok(plan)
    }

    #[allow(clippy::unused_self)]
    fn empty_plan(&self, goal: u32, query: Query) -> Plan {
        Plan {
            goal,
            query,
            solved: true,
            units: Vec::new(),
            unresolved: Vec::new(),
            explanation: None,
            height: None,
            success: None,
            unrated: None,
            cost: None,
            leaf_inputs: 0,
            expanded: 0,
            peak_frontier: 0,
            seconds: 0.0,
        }
    }

    fn fill_metrics(&self, plan: &mut Plan) {
        let m = self.metrics(&plan.units, plan.goal);
        plan.height = m.height;
        plan.success = m.success;
        plan.unrated = m.unrated;
        plan.leaf_inputs = m.leaf_inputs;
    }

    /// Height, success and leaf count of a set of FUs for `goal`.
    pub fn metrics(&self, units: &[u32], goal: u32) -> TreeMetrics {
        let height = if self.in_kitchen(goal) {
            Some(0)
        } else {
            forward::unit_ranks(self, units).made(goal)
        };
        let unrated = if self.rates_given {
            units
                .iter()
                .copied()
                .find(|&f| self.fu_rate.get(f as usize).is_none_or(|r| r.is_nan()))
        } else {
            None
        };
        let success = if self.rates_given && unrated.is_none() {
            Some(
                units
                    .iter()
                    .fold(1.0, |acc, &f| acc * self.fu_rate[f as usize]),
            )
        } else {
            None
        };
        let mut seen = FxHashSet::default();
        for &f in units {
            for &x in self.needed(f) {
                if self.in_kitchen(x) {
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
    pub fn is_valid(&self, units: &[u32], goal: u32) -> bool {
        let r = forward::unit_ranks(self, units);
        let made = |x: u32| self.in_kitchen(x) || r.made(x).is_some();
        let all_run = units.iter().all(|&f| {
            (f as usize) < self.foon.fu_count() && self.needed(f).iter().all(|&x| made(x))
        });
        all_run && made(goal)
    }

    /// Checks `units` in the given order: returns the position of the first FU with a needed
    /// input that is neither in the kitchen nor made by an earlier FU, with those inputs.
    pub fn first_unavailable(&self, units: &[u32]) -> Option<(usize, Vec<u32>)> {
        self.run_in_order(units).0
    }

    /// Runs `units` in the given order from the kitchen: a unit runs when its needed inputs
    /// are available, and then makes its (produced) outputs available. Returns the first unit
    /// that could not run (position, missing inputs) and what is available at the end.
    pub fn run_in_order(&self, units: &[u32]) -> (Option<(usize, Vec<u32>)>, Vec<bool>) {
        let mut avail = self.in_kitchen.clone();
        let mut first = None;
        for (i, &f) in units.iter().enumerate() {
            let missing: Vec<u32> = self
                .needed(f)
                .iter()
                .copied()
                .filter(|&x| !avail[x as usize])
                .collect();
            if !missing.is_empty() {
                first.get_or_insert((i, missing));
                continue;
            }
            for &y in self.foon.outputs(f) {
                if !self.foon.is_bare(y) {
                    avail[y as usize] = true;
                }
            }
        }
        (first, avail)
    }
}

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

/// Needed inputs of every FU: the container rule removes an input whose label is a utensil
/// and whose ingredients are exactly `[x]` when another input of the FU is labelled `x` and
/// sits in that utensil. Linear in the inputs: the (label, container) pairs of an FU's inputs
/// are counted once, and an input's own pair is not "another input".
fn needed_inputs(foon: &Foon, utensils: &FxHashSet<u32>) -> Csr {
    let mut out = Csr::new();
    let mut row = Vec::new();
    let mut held: FxHashMap<(u32, u32), u32> = FxHashMap::default();
    for f in 0..foon.fu_count() as u32 {
        let ins = foon.inputs(f);
        row.clear();
        // Only an input that holds one ingredient in a utensil can be skipped.
        let holder = |o: u32| foon.ingredients(o).len() == 1 && utensils.contains(&foon.label(o));
        if !ins.iter().any(|&o| holder(o)) {
            out.push_row(ins);
            continue;
        }
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
                assert_eq!(linear.row(f), quadratic(&foon, &utensils, f), "{text}");
                skipped += foon.inputs(f).len() - linear.row(f).len();
            }
        }
        assert!(skipped > 100, "the rule skipped only {skipped} inputs");
    }
}
