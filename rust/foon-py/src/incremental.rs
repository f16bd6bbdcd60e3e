//! `foon._foon.planner_with_kitchen`: a planner for another kitchen, prepared incrementally
//! from a planner's preparation (`foon_core::Prepared::with_kitchen`).

use std::sync::Arc;

use pyo3::prelude::*;

use crate::errors::enter;
use crate::kitchen::PyKitchen;
use crate::planner::PyPlanner;

/// A planner over the same FOON, utensils, rates and level as `planner`, for `kitchen`
/// (matched at the planner's level): the difference with the planner's kitchen is applied to
/// its preparation, whose computed parts are updated rather than computed again. Its results
/// equal those of a planner prepared from scratch.
#[pyfunction]
pub(crate) fn planner_with_kitchen(
    py: Python<'_>,
    planner: &PyPlanner,
    kitchen: &PyKitchen,
) -> PyResult<PyPlanner> {
    let foon = Arc::clone(&planner.foon);
    let (f, base, items) = (&*foon, &*planner.prep, &*kitchen.inner);
    let prep = enter(py, |_| {
        let ids = items.match_at_level(f, base.level())?;
        base.with_kitchen(f, &ids)
    })?;
    Ok(PyPlanner {
        foon,
        prep: Arc::new(prep),
    })
}
