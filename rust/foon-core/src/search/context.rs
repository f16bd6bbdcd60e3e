//! The planning context: a FOON with its [`Prepared`] inputs (owned or borrowed, checked to
//! belong to it), the cancel callback and the per-search state policy; and the public entry
//! points over it (rates, ranks, goals, and the evaluation of a tree).

use super::SharedOptions;
use super::scratch;
use crate::error::{Error, Result};
use crate::evaluate::{self, TreeMetrics};
use crate::index::Foon;
use crate::model::{MotionRates, ObjectSpec};
use crate::prepare::{Prepared, Ranks};

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
    /// Plan every goal from scratch, without what is computed once per kitchen.
    from_scratch: bool,
    /// The options of `optimal-shared`.
    shared: SharedOptions,
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
            from_scratch: false,
            shared: SharedOptions::default(),
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
            from_scratch: false,
            shared: SharedOptions::default(),
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

    /// Makes every plan search from its goal, without what the sound methods compute once
    /// per kitchen (each objective's optimum, the shopping costs of explanations, the choices
    /// of `ids`). Results never depend on it; tests use it to compare both paths.
    #[doc(hidden)]
    #[must_use]
    pub fn from_scratch(mut self) -> Self {
        self.from_scratch = true;
        self
    }

    /// Sets the options of `optimal-shared` (objective, node and time limits).
    #[must_use]
    pub fn with_shared(mut self, opts: SharedOptions) -> Self {
        self.shared = opts;
        self
    }

    /// The options of `optimal-shared`.
    pub(super) fn shared_options(&self) -> SharedOptions {
        self.shared
    }

    /// Whether plans search from their goal (see [`Context::from_scratch`]).
    pub(super) fn is_from_scratch(&self) -> bool {
        self.from_scratch
    }

    /// Id spaces up to this many entries use arrays (`id_map`).
    pub(super) fn scratch_limit(&self) -> usize {
        self.scratch_limit
    }

    /// Per-search state over `len` ids (objects or FUs), all at `default`.
    pub(super) fn id_map<T: Copy + PartialEq>(&self, len: usize, default: T) -> scratch::IdMap<T> {
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

    pub(super) fn check_stop(&self) -> Result<()> {
        match self.cancel {
            Some(c) if c() => Err(Error::Cancelled),
            _ => Ok(()),
        }
    }

    /// The goal object for a spec, or the course's error.
    pub fn goal(&self, spec: &ObjectSpec) -> Result<u32> {
        self.foon.goal_by_spec(spec)
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
}
