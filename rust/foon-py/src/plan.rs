//! `foon._foon.Plan`: one planning result, read by `foon.TaskTree` (object and unit ids; the
//! Python layer turns them into objects only when asked).

use foon_core::search::{Explanation, Plan};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::errors::PyFoonErr;

#[pyclass(frozen, module = "foon._foon", name = "Plan")]
pub(crate) struct PyPlan {
    pub(crate) plan: Plan,
}

/// The pickled form of a plan: (goal, method, compat, count), (solved, units, unresolved,
/// explanation), (height, success, unrated, cost, leaf inputs, expanded, peak frontier,
/// seconds), (bound, proven, objective).
type PlanState = (
    (u32, String, String, String),
    (
        bool,
        Vec<u32>,
        Vec<u32>,
        Option<(Vec<u32>, Vec<u32>, Vec<u32>)>,
    ),
    (
        Option<u32>,
        Option<f64>,
        Option<u32>,
        Option<f64>,
        usize,
        u64,
        usize,
        f64,
    ),
    (Option<f64>, Option<bool>, Option<String>),
);

#[pymethods]
impl PyPlan {
    #[getter]
    fn goal(&self) -> u32 {
        self.plan.goal
    }
    #[getter]
    fn method(&self) -> &'static str {
        self.plan.query.method.as_str()
    }
    #[getter]
    fn compat(&self) -> &'static str {
        self.plan.query.compat.as_str()
    }
    #[getter]
    fn count(&self) -> &'static str {
        self.plan.query.count.as_str()
    }
    #[getter]
    fn solved(&self) -> bool {
        self.plan.solved
    }
    #[getter]
    fn units(&self) -> Vec<u32> {
        self.plan.units.clone()
    }
    #[getter]
    fn unresolved(&self) -> Vec<u32> {
        self.plan.unresolved.clone()
    }
    #[getter]
    fn missing(&self) -> Vec<u32> {
        self.explanation()
            .map(|e| e.missing.clone())
            .unwrap_or_default()
    }
    #[getter]
    fn cycle(&self) -> Vec<u32> {
        self.explanation()
            .map(|e| e.cycle.clone())
            .unwrap_or_default()
    }
    #[getter]
    fn cycle_units(&self) -> Vec<u32> {
        self.explanation()
            .map(|e| e.cycle_units.clone())
            .unwrap_or_default()
    }
    #[getter]
    fn height(&self) -> Option<u32> {
        self.plan.height
    }
    #[getter]
    fn success(&self) -> Option<f64> {
        self.plan.success
    }
    #[getter]
    fn cost(&self) -> Option<f64> {
        self.plan.cost
    }
    /// `optimal-shared`: the proven bound on the cost.
    #[getter]
    fn bound(&self) -> Option<f64> {
        self.plan.bound
    }
    /// `optimal-shared`: whether the cost is proven optimal.
    #[getter]
    fn proven(&self) -> Option<bool> {
        self.plan.proven
    }
    /// `optimal-shared`: `|cost - bound|`.
    #[getter]
    fn gap(&self) -> Option<f64> {
        self.plan.gap()
    }
    /// `optimal-shared`: the objective of the cost (`"units"` or `"success"`).
    #[getter]
    fn objective(&self) -> Option<&'static str> {
        self.plan.objective.map(foon_core::SharedObjective::as_str)
    }
    #[getter]
    fn leaf_inputs(&self) -> usize {
        self.plan.leaf_inputs
    }
    #[getter]
    fn expanded(&self) -> u64 {
        self.plan.expanded
    }
    #[getter]
    fn peak_frontier(&self) -> usize {
        self.plan.peak_frontier
    }
    #[getter]
    fn seconds(&self) -> f64 {
        self.plan.seconds
    }
    /// The first unit of the tree whose motion has no rate (None when every motion has one,
    /// or when no rate table was given).
    #[getter]
    fn unrated(&self) -> Option<u32> {
        self.plan.unrated
    }

    /// Equal when every field but the planning time is equal.
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.cast::<PyPlan>().is_ok_and(|o| {
            let o = &o.get().plan;
            let mut a = self.plan.clone();
            a.seconds = o.seconds;
            a == *o
        })
    }

    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let p = &slf.get().plan;
        let state: PlanState = (
            (
                p.goal,
                p.query.method.as_str().to_owned(),
                p.query.compat.as_str().to_owned(),
                p.query.count.as_str().to_owned(),
            ),
            (
                p.solved,
                p.units.clone(),
                p.unresolved.clone(),
                p.explanation
                    .as_ref()
                    .map(|e| (e.missing.clone(), e.cycle.clone(), e.cycle_units.clone())),
            ),
            (
                p.height,
                p.success,
                p.unrated,
                p.cost,
                p.leaf_inputs,
                p.expanded,
                p.peak_frontier,
                p.seconds,
            ),
            (
                p.bound,
                p.proven,
                p.objective.map(|o| o.as_str().to_owned()),
            ),
        );
        let f = slf.get_type().getattr("_from_state")?;
        Ok((f, PyTuple::new(slf.py(), [state.into_pyobject(slf.py())?])?))
    }

    /// Rebuilds a plan from its pickled form.
    #[staticmethod]
    fn _from_state(state: PlanState) -> PyResult<Self> {
        let ((goal, method, compat, count), (solved, units, unresolved, expl), metrics, shared) =
            state;
        let (bound, proven, objective) = shared;
        let objective = objective
            .map(|o| o.parse())
            .transpose()
            .map_err(PyFoonErr)?;
        let (height, success, unrated, cost, leaf_inputs, expanded, peak_frontier, seconds) =
            metrics;
        let query = foon_core::Query {
            method: method.parse().map_err(PyFoonErr)?,
            compat: compat.parse().map_err(PyFoonErr)?,
            count: count.parse().map_err(PyFoonErr)?,
        };
        Ok(Self {
            plan: Plan {
                goal,
                query,
                solved,
                units,
                unresolved,
                explanation: expl.map(|(missing, cycle, cycle_units)| Explanation {
                    missing,
                    cycle,
                    cycle_units,
                }),
                height,
                success,
                unrated,
                cost,
                bound,
                proven,
                objective,
                leaf_inputs,
                expanded,
                peak_frontier,
                seconds,
            },
        })
    }
}

impl PyPlan {
    fn explanation(&self) -> Option<&Explanation> {
        self.plan.explanation.as_ref()
    }
}
