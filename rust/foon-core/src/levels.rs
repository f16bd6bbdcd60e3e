//! Planning at an identity level below full identity (`--level 1|2`): the kitchen and the
//! goal match every object equal to them at the level ([`Kitchen::match_at_level`], whose
//! level rule is merging's, [`level_key`](crate::merge::level_key)). The rules are in
//! `docs/METHODS.md` ("Hierarchy levels").

use crate::error::Result;
use crate::kitchen::Kitchen;
use crate::model::ObjectSpec;
use crate::search::Context;

/// The objects equal to `goal` at `level`, in id order.
pub fn goal_candidates(ctx: &Context<'_>, goal: &ObjectSpec, level: u8) -> Result<Vec<u32>> {
    Kitchen::from_specs([goal])?.match_at_level(ctx.foon, level)
}

/// The object that stands for `goal` at `level`: among the objects equal to it at the level,
/// the first in the kitchen; else the derivable one of lowest rank (ties: lowest id); else
/// the lowest id. [`Error::GoalNotFound`](crate::Error::GoalNotFound) when no object is equal to it at the level.
pub fn goal_at_level(ctx: &Context<'_>, goal: &ObjectSpec, level: u8) -> Result<u32> {
    let cands = goal_candidates(ctx, goal, level)?;
    let Some(&first) = cands.first() else {
        return Err(crate::find::goal_not_found(
            ctx.foon,
            format!("{} (at level {level})", goal.describe()),
            &goal.label,
            &goal.states,
            goal.container.as_deref(),
        ));
    };
    if let Some(&o) = cands.iter().find(|&&o| ctx.in_kitchen(o)) {
        return Ok(o);
    }
    let ranks = ctx.ranks();
    Ok(cands
        .iter()
        .filter_map(|&o| ranks.rank(o).map(|r| (r, o)))
        .min()
        .map_or(first, |(_, o)| o))
}
