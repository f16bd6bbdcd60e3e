//! The k best trees (`plan_k`) and the bounded enumeration of trees (`Paths`) of a prepared
//! planner: thin calls into `foon_core::search::{kbest, paths}`.

use std::sync::{Arc, Mutex};

use foon_core::{Context, Method, Paths, Prepared};
use pyo3::prelude::*;

use crate::convert::{count_arg, required_count, str_field};
use crate::errors::{PyFoonErr, enter_here};
use crate::foon::check_object;
use crate::plan::PyPlan;
use crate::planner::PyPlanner;

/// The `k` best trees of `goal` for an optimal method, in cost order (fewer when there are
/// fewer; none when the goal cannot be made).
#[pyfunction]
#[pyo3(signature = (planner, goal, method, k, diverse = false))]
pub(crate) fn plan_k(
    py: Python<'_>,
    planner: &PyPlanner,
    goal: u32,
    method: &Bound<'_, PyAny>,
    k: &Bound<'_, PyAny>,
    diverse: bool,
) -> PyResult<Vec<Py<PyPlan>>> {
    let k: usize = required_count("k", k, 1)?;
    check_object(&planner.foon, goal)?;
    let method: Method = str_field("method", method)?.parse().map_err(PyFoonErr)?;
    let (foon, prep) = (&*planner.foon, &*planner.prep);
    // On this thread: a short call costs no thread; Ctrl-C is seen between subspaces.
    let plans = enter_here(py, |cancel| {
        Context::with(foon, prep)?
            .with_cancel(cancel)
            .plan_k(goal, method, k, diverse)
    })?;
    plans
        .into_iter()
        .map(|plan| Py::new(py, PyPlan { plan }))
        .collect()
}

/// Every valid tree of a goal up to the limits, lazily: an iterator of plans.
#[pyclass(frozen, module = "foon._foon", name = "Paths")]
pub(crate) struct PyPaths {
    foon: Arc<foon_core::Foon>,
    prep: Arc<Prepared>,
    state: Mutex<Paths>,
}

#[pymethods]
impl PyPaths {
    #[new]
    #[pyo3(signature = (planner, goal, max_trees = None, max_height = None))]
    fn new(
        py: Python<'_>,
        planner: &PyPlanner,
        goal: u32,
        max_trees: Option<&Bound<'_, PyAny>>,
        max_height: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let max_trees = count_arg("max_trees", max_trees, 0)?;
        let max_height = count_arg("max_height", max_height, 0)?;
        check_object(&planner.foon, goal)?;
        let (foon, prep) = (&*planner.foon, &*planner.prep);
        let state = enter_here(py, |cancel| {
            let ctx = Context::with(foon, prep)?.with_cancel(cancel);
            Paths::new(&ctx, goal, max_trees, max_height)
        })?;
        Ok(Self {
            foon: Arc::clone(&planner.foon),
            prep: Arc::clone(&planner.prep),
            state: Mutex::new(state),
        })
    }

    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__(&self, py: Python<'_>) -> PyResult<Option<Py<PyPlan>>> {
        let (foon, prep) = (&*self.foon, &*self.prep);
        let next = enter_here(py, |cancel| {
            let ctx = Context::with(foon, prep)?.with_cancel(cancel);
            // A poisoned lock only means an earlier call panicked: the state is still whole.
            let mut state = self
                .state
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            state.next_plan(&ctx)
        })?;
        next.map(|plan| Py::new(py, PyPlan { plan })).transpose()
    }
}
