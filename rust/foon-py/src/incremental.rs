//! `foon._foon.planner_with_changes`: a planner for a changed kitchen, prepared incrementally
//! from a planner's preparation (`foon_core::Prepared::with_delta`).

use std::sync::Arc;

use pyo3::prelude::*;

use crate::errors::enter;
use crate::kitchen::PyKitchen;
use crate::planner::PyPlanner;

/// A planner over the same FOON, utensils, rates and level as `planner`, for its kitchen
/// without the items of `remove` and with those of `add` (`kitchen`, that new kitchen,
/// matched whole at levels 1 and 2, where one item may match several objects and several
/// items one object; at level 3 an item is one object, so only the changes are matched). The
/// change is applied to the planner's preparation, whose computed parts are updated rather
/// than computed again; its results equal those of a planner prepared from scratch.
#[pyfunction]
pub(crate) fn planner_with_changes(
    py: Python<'_>,
    planner: &PyPlanner,
    add: &PyKitchen,
    remove: &PyKitchen,
    kitchen: Option<&PyKitchen>,
) -> PyResult<PyPlanner> {
    let foon = Arc::clone(&planner.foon);
    let (f, base) = (&*foon, &*planner.prep);
    let (add, remove) = (&*add.inner, &*remove.inner);
    let kitchen = kitchen.map(|k| Arc::clone(&k.inner));
    let prep = enter(py, |_| {
        base.with_kitchen_changes(f, add, remove, || {
            kitchen.ok_or_else(|| {
                foon_core::error::Error::Invalid(
                    "the new kitchen is needed at identity levels 1 and 2".into(),
                )
            })
        })
    })?;
    Ok(PyPlanner {
        foon,
        prep: Arc::new(prep),
    })
}
