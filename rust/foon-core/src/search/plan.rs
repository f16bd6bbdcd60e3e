//! What a planning call returns: the [`Plan`], and for a failed sound search its
//! [`Explanation`].

use super::{Query, SharedObjective};

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
    /// return such a tree (the others fail with [`Error::MissingRate`](crate::Error::MissingRate)).
    pub unrated: Option<u32>,
    /// Optimal methods: the optimum of the cost they minimise.
    pub cost: Option<f64>,
    /// `optimal-shared`: the proven bound on `cost` (a lower bound on the unit count, an
    /// upper bound on the success), equal to `cost` when `proven`.
    pub bound: Option<f64>,
    /// `optimal-shared`: whether `cost` is proven optimal (false when a limit stopped the
    /// search first).
    pub proven: Option<bool>,
    /// `optimal-shared`: the objective `cost` and `bound` are in (a unit count, or a
    /// success).
    pub objective: Option<SharedObjective>,
    pub leaf_inputs: usize,
    pub expanded: u64,
    pub peak_frontier: usize,
    pub seconds: f64,
}

impl Plan {
    /// A solved plan of no unit for `goal` (the searches fill in the rest).
    pub(crate) fn empty(goal: u32, query: Query) -> Self {
        Self {
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
            bound: None,
            proven: None,
            objective: None,
            leaf_inputs: 0,
            expanded: 0,
            peak_frontier: 0,
            seconds: 0.0,
        }
    }

    /// `optimal-shared`: how far the cost may be from the optimum, `|cost - bound|` (0 when
    /// proven).
    pub fn gap(&self) -> Option<f64> {
        Some((self.cost? - self.bound?).abs())
    }
}
