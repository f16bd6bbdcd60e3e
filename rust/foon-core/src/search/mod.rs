//! Task-tree retrieval over the compact index. Every search is a plain function of an
//! immutable [`Context`] (no global state), so many goals can be planned in parallel.
//! The exact definitions are in `docs/METHODS.md`.

pub mod batch;
mod course;
mod greedy;
mod heuristic;
mod ids;
mod optimal;
mod scratch;
mod tree;

use std::str::FromStr;
use std::time::Instant;

use crate::error::{Error, Result};
use crate::evaluate::{self, TreeMetrics};
use crate::index::Foon;
use crate::model::{MotionRates, ObjectSpec};
use crate::prepare::{Prepared, Ranks};

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
        self.prep()
    }
}

impl<'a> Context<'a> {
    fn prep(&self) -> &Prepared {
        match &self.prep {
            Prep::Owned(p) => p,
            Prep::Borrowed(p) => p,
        }
    }

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
        prep.check_foon(foon)?;
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

    /// Success rate of `fu`'s motion, or the error naming the motion.
    pub fn rate(&self, fu: u32) -> Result<f64> {
        self.prep().rate(self.foon, fu)
    }

    /// Ranks and derivability from the kitchen (computed once, on first use).
    pub fn ranks(&self) -> &Ranks {
        self.prep().ranks(self.foon)
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

    /// Height, success and leaf count of a set of FUs for `goal`.
    pub fn metrics(&self, units: &[u32], goal: u32) -> TreeMetrics {
        evaluate::metrics(self.foon, self, units, goal)
    }

    /// Whether the FUs `units` can be ordered so that every one of them runs (its needed
    /// inputs in the kitchen or made by an earlier one) and the goal is in the kitchen or made.
    pub fn is_valid(&self, units: &[u32], goal: u32) -> bool {
        evaluate::is_valid(self.foon, self, units, goal)
    }

    /// Checks `units` in the given order: returns the position of the first FU with a needed
    /// input that is neither in the kitchen nor made by an earlier FU, with those inputs.
    pub fn first_unavailable(&self, units: &[u32]) -> Option<(usize, Vec<u32>)> {
        evaluate::first_unavailable(self.foon, self, units)
    }

    /// Runs `units` in the given order from the kitchen: a unit runs when its needed inputs
    /// are available, and then makes its (produced) outputs available. Returns the first unit
    /// that could not run (position, missing inputs) and what is available at the end.
    pub fn run_in_order(&self, units: &[u32]) -> (Option<(usize, Vec<u32>)>, Vec<bool>) {
        evaluate::run_in_order(self.foon, self, units)
    }

    fn fill_metrics(&self, plan: &mut Plan) {
        let m = self.metrics(&plan.units, plan.goal);
        plan.height = m.height;
        plan.success = m.success;
        plan.unrated = m.unrated;
        plan.leaf_inputs = m.leaf_inputs;
    }
}
