//! `foon._foon.Planner`: a FOON with its planning inputs prepared once, for any number of plans.

use std::sync::Arc;

use foon_core::MotionRates;
use foon_core::search::batch::{self, BatchOptions};
use foon_core::{Context, Prepared, Query, SharedObjective, SharedOptions};
use pyo3::prelude::*;

use crate::convert::{count_arg, rate_arg, rate_pairs_arg, str_field, str_list_field, threads_arg};
use crate::errors::{Cancel, PyFoonErr, enter, enter_here};
use crate::foon::{PyFoon, check_fu, check_object};
use crate::kitchen::PyKitchen;
use crate::plan::PyPlan;

/// (valid in some order, height, first position whose needed inputs are unavailable).
type TreeCheck = (bool, Option<u32>, Option<(usize, Vec<u32>)>);

#[pyclass(frozen, module = "foon._foon", name = "Planner")]
pub(crate) struct PyPlanner {
    pub(crate) foon: Arc<foon_core::Foon>,
    pub(crate) prep: Arc<Prepared>,
}

#[pymethods]
impl PyPlanner {
    #[new]
    #[pyo3(signature = (foon, kitchen, utensils, rates = None, default_rate = None, level = 3))]
    fn new(
        py: Python<'_>,
        foon: &PyFoon,
        kitchen: &PyKitchen,
        utensils: &Bound<'_, PyAny>,
        rates: Option<&Bound<'_, PyAny>>,
        default_rate: Option<&Bound<'_, PyAny>>,
        level: u8,
    ) -> PyResult<Self> {
        let utensils = str_list_field("utensils", utensils)?;
        let rates = rates
            .filter(|r| !r.is_none())
            .map(|r| rate_pairs_arg("motions", r))
            .transpose()?;
        let default_rate = default_rate
            .filter(|r| !r.is_none())
            .map(|r| rate_arg("default_rate", r))
            .transpose()?;
        let rates = rates
            .map(MotionRates::from_pairs)
            .transpose()
            .map_err(PyFoonErr)?;
        let f = Arc::clone(&foon.inner);
        let kitchen = &*kitchen.inner;
        // The kitchen is matched in the core, through the FOON's string table (at an
        // identity level below 3: every object equal to an item at that level).
        let prep = enter(py, |_| {
            let ids = kitchen.match_at_level(&f, level)?;
            Prepared::with_objects(&f, &ids, &utensils, rates.as_ref(), default_rate)
                .map(|p| p.at_level(level))
        })?;
        Ok(Self {
            foon: f,
            prep: Arc::new(prep),
        })
    }

    /// Plans every goal (object ids), in order, on `threads` worker threads (see
    /// `foon_core::search::batch` for the cap and the default).
    /// `objective` (`"units"` or `"success"`), `node_limit` and `time_limit` (seconds) are
    /// the options of `optimal-shared`.
    #[pyo3(signature = (goals, method, compat, count, threads = None, objective = None, node_limit = None, time_limit = None))]
    #[allow(clippy::too_many_arguments)]
    fn plan(
        &self,
        py: Python<'_>,
        goals: Vec<u32>,
        method: &Bound<'_, PyAny>,
        compat: &Bound<'_, PyAny>,
        count: &Bound<'_, PyAny>,
        threads: Option<&Bound<'_, PyAny>>,
        objective: Option<&Bound<'_, PyAny>>,
        node_limit: Option<&Bound<'_, PyAny>>,
        time_limit: Option<f64>,
    ) -> PyResult<Vec<Py<PyPlan>>> {
        let threads = threads_arg(threads)?;
        let node_limit = count_arg("node_limit", node_limit, 0)?;
        let shared = SharedOptions {
            objective: match objective {
                Some(o) => str_field("objective", o)?.parse().map_err(PyFoonErr)?,
                None => SharedObjective::default(),
            },
            node_limit,
            time_limit,
        };
        let method = str_field("method", method)?;
        let compat = str_field("compat", compat)?;
        let count = str_field("count", count)?;
        let query = Query {
            method: method.parse().map_err(PyFoonErr)?,
            compat: compat.parse().map_err(PyFoonErr)?,
            count: count.parse().map_err(PyFoonErr)?,
        };
        shared.check_for(query.method).map_err(PyFoonErr)?;
        for &g in &goals {
            check_object(&self.foon, g)?;
        }
        let opts = BatchOptions::threads(threads).with_shared(shared);
        let workers = opts.workers(goals.len()).map_err(PyFoonErr)?;
        let (foon, prep) = (&*self.foon, &*self.prep);
        let run = |cancel: Cancel<'_>| {
            batch::plan_batch(foon, prep, &goals, query, &opts.with_cancel(cancel))
        };
        // One worker runs on this thread (no thread to start for a single plan); several
        // run on the pool while this thread watches for Ctrl-C.
        let plans = if workers <= 1 {
            enter_here(py, run)?
        } else {
            enter(py, run)?
        };
        plans
            .into_iter()
            .map(|plan| Py::new(py, PyPlan { plan }))
            .collect()
    }

    /// Checks a tree: (valid in some order, height, first position in the given order whose
    /// needed inputs are unavailable with those inputs).
    fn check_tree(&self, py: Python<'_>, units: Vec<u32>, goal: u32) -> PyResult<TreeCheck> {
        check_object(&self.foon, goal)?;
        for &f in &units {
            check_fu(&self.foon, f)?;
        }
        let (foon, prep) = (&*self.foon, &*self.prep);
        enter(py, |cancel| {
            let ctx = Context::with(foon, prep)?.with_cancel(cancel);
            let m = ctx.metrics(&units, goal);
            Ok((
                ctx.is_valid(&units, goal),
                m.height,
                ctx.first_unavailable(&units),
            ))
        })
    }

    /// Rank of every object (None when not derivable from the kitchen).
    fn ranks(&self, py: Python<'_>) -> PyResult<Vec<Option<u32>>> {
        let (foon, prep) = (&*self.foon, &*self.prep);
        enter(py, |cancel| {
            let ctx = Context::with(foon, prep)?.with_cancel(cancel);
            let r = ctx.ranks();
            Ok((0..foon.object_count() as u32).map(|o| r.rank(o)).collect())
        })
    }

    /// Runs to the end the updates a planner from `with_changes` keeps pending (see
    /// `foon_core::Prepared::finish_updates`).
    fn finish_updates(&self, py: Python<'_>) -> PyResult<()> {
        let (foon, prep) = (&*self.foon, &*self.prep);
        enter(py, |cancel| prep.finish_updates(foon, cancel))
    }

    /// Object ids of the kitchen items found in the FOON, in id order.
    fn kitchen_objects(&self) -> PyResult<Vec<u32>> {
        let ctx = Context::with(&self.foon, &self.prep).map_err(PyFoonErr)?;
        Ok(ctx.kitchen_objects().to_vec())
    }

    fn __repr__(&self) -> String {
        format!(
            "<foon._foon.Planner over {} units, {} kitchen objects>",
            self.foon.fu_count(),
            Context::with(&self.foon, &self.prep).map_or(0, |c| c.kitchen_objects().len())
        )
    }
}
