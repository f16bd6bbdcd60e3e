//! Bounded enumeration of every valid tree of a goal (`docs/METHODS.md`, "The k best trees"):
//! the trees of the k-best partition for `optimal-units` (fewest units first), those higher
//! than a limit left out, stopping after a number of trees. Lazy and deterministic; each set
//! of units once.
//!
//! With a height limit H below the goal's rank (the least height of any of its trees) there
//! is no tree to give: the enumeration ends at once.

use super::kbest::{KBest, Ranked};
use super::{Context, Method, Plan};
use crate::error::Result;

/// Every valid tree of a goal up to the limits, lazily.
pub struct Paths {
    inner: KBest,
    max_trees: Option<usize>,
    max_height: Option<u32>,
    given: usize,
}

impl Paths {
    /// Prepares the enumeration; no tree is computed yet.
    pub fn new(
        ctx: &Context<'_>,
        goal: u32,
        max_trees: Option<usize>,
        max_height: Option<u32>,
    ) -> Result<Self> {
        // No tree of the goal is lower than its rank: none to give.
        let low = |h: u32| ctx.ranks().rank(goal).is_some_and(|r| r <= h);
        let max_trees = if max_height.is_some_and(|h| !low(h)) {
            Some(0)
        } else {
            max_trees
        };
        Ok(Self {
            inner: KBest::new(ctx, goal, Method::OptimalUnits, false)?,
            max_trees,
            max_height,
            given: 0,
        })
    }

    /// The next tree as a plan (`optimal-units`: its cost is its unit count), or `None` at
    /// the limit or when every tree was given.
    pub fn next_plan(&mut self, ctx: &Context<'_>) -> Result<Option<Plan>> {
        if self.max_trees.is_some_and(|m| self.given >= m) {
            return Ok(None);
        }
        loop {
            let Some(r): Option<Ranked> = self.inner.next_tree(ctx)? else {
                // Nothing more: later calls answer at once.
                self.max_trees = Some(self.given);
                return Ok(None);
            };
            let p = self.inner.plan_from(ctx, r);
            if self
                .max_height
                .is_some_and(|h| p.height.is_none_or(|x| x > h))
            {
                continue;
            }
            self.given += 1;
            return Ok(Some(p));
        }
    }
}
