//! Task-tree retrieval over the compact index: dispatch of a [`Query`] to its search. Every
//! search is a plain function of an immutable [`Context`] (no global state), so many goals can
//! be planned in parallel ([`batch`]). The exact definitions are in `docs/METHODS.md`.

pub mod batch;
mod context;
mod course;
mod greedy;
mod heuristic;
pub(crate) mod ids;
pub mod kbest;
pub(crate) mod optimal;
pub mod paths;
mod plan;
mod query;
pub(crate) mod radix;
mod scratch;
mod shared;
pub mod split;
mod tree;

use std::time::Instant;

pub use context::Context;
pub use plan::{Explanation, Plan};
pub use query::{Compat, Count, Method, Query};
pub use shared::{SharedObjective, SharedOptions};

use crate::error::{Error, Result};

impl Context<'_> {
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
        query.check()?;
        let mut plan = match (query.compat, query.method) {
            (Compat::Course, _) => course::plan(self, goal, query)?,
            (Compat::Sound, method) => {
                if self.in_kitchen(goal) {
                    let mut p = Plan::empty(goal, query);
                    // Nothing to do: success 1, no unit, the goal itself as the one input.
                    p.cost = match method {
                        Method::OptimalSuccess | Method::OptimalInputs => Some(1.0),
                        Method::OptimalUnits => Some(0.0),
                        Method::OptimalShared => {
                            let success =
                                self.shared_options().objective == SharedObjective::Success;
                            p.bound = Some(if success { 1.0 } else { 0.0 });
                            p.proven = Some(true);
                            p.bound
                        }
                        _ => None,
                    };
                    p
                } else if self.ranks().rank(goal).is_none() {
                    let mut p = Plan::empty(goal, query);
                    p.solved = false;
                    p.explanation = Some(optimal::explain(self, goal)?);
                    p
                } else {
                    match method {
                        Method::Ids => ids::plan(self, goal, query)?,
                        Method::GreedySuccess | Method::GreedyInputs => {
                            greedy::plan(self, goal, query)?
                        }
                        Method::OptimalShared => shared::plan(self, goal, query)?,
                        _ => optimal::plan(self, goal, query)?,
                    }
                }
            }
        };
        self.fill_metrics(&mut plan);
        if query.method == Method::OptimalShared {
            plan.objective = Some(self.shared_options().objective);
        }
        plan.seconds = start.elapsed().as_secs_f64();
        Ok(plan)
    }

    fn fill_metrics(&self, plan: &mut Plan) {
        let m = self.metrics(&plan.units, plan.goal);
        plan.height = m.height;
        plan.success = m.success;
        plan.unrated = m.unrated;
        plan.leaf_inputs = m.leaf_inputs;
    }
}

/// Computes the kitchen's optimum of `objective` (what the optimal methods and, for
/// `Objective::Shopping`, the explanations of goals that cannot be made read), unless the
/// context plans from scratch (which keeps nothing).
pub(crate) fn compute_optimum(
    ctx: &Context<'_>,
    objective: crate::prepare::Objective,
) -> Result<()> {
    if ctx.is_from_scratch() {
        return Ok(());
    }
    optimal::optimum(ctx, objective).map(|_| ())
}
