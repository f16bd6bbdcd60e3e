//! `foon._foon.explain` and `foon._foon.FindIndex`: the explanation of one goal and the
//! similarity look-up of objects (both computed in `foon-core`).

use std::sync::Arc;

use foon_core::explain::Explain;
use foon_core::find::FindIndex;
use foon_core::queries::GoalText;
use foon_core::write::{self, Format, Options};
use foon_core::{Context, Query};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::convert::{ObjTuple, required_count, spec_of, str_field};
use crate::errors::{PyFoonErr, enter, enter_here};
use crate::foon::{PyFoon, check_object};
use crate::plan::PyPlan;
use crate::planner::PyPlanner;

/// (unit, [(object, kind, buyable)]).
type ProducerTuple = (u32, Vec<(u32, &'static str, bool)>);

/// (status, rank, best plan, buyable, shopping, producers, cycle, cycle units,
/// unblock [(object, alone)], text, the explanation for its writers).
type ExplainTuple = (
    &'static str,
    Option<u32>,
    Option<Py<PyPlan>>,
    bool,
    Vec<u32>,
    Vec<ProducerTuple>,
    Vec<u32>,
    Vec<u32>,
    Vec<(u32, bool)>,
    String,
    Py<PyExplanation>,
);

/// One explanation as the core holds it, for its pictures and page
/// (`foon_core::write::write_explanation`).
#[pyclass(frozen, module = "foon._foon", name = "Explanation")]
pub(crate) struct PyExplanation {
    foon: Arc<foon_core::Foon>,
    prep: Arc<foon_core::Prepared>,
    inner: Explain,
}

#[pymethods]
impl PyExplanation {
    /// The blocking part (or, for a goal that is not blocked, its best tree) in `format`:
    /// dot, svg, png, pdf or html.
    #[pyo3(signature = (format, *, title = None, max_nodes = None))]
    fn write<'py>(
        &self,
        py: Python<'py>,
        format: &str,
        title: Option<String>,
        max_nodes: Option<usize>,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let fmt: Format = format.parse().map_err(PyFoonErr)?;
        let mut opts = Options {
            title,
            ..Options::default()
        };
        if let Some(n) = max_nodes {
            opts.max_nodes = n;
        }
        let (foon, prep, e) = (&*self.foon, &*self.prep, &self.inner);
        let bytes = enter(py, |_| {
            write::to_bytes(|out| write::write_explanation(fmt, foon, prep, e, &opts, out))
        })?;
        Ok(PyBytes::new(py, &bytes))
    }
}

/// Explains `goal` (an object id) with the planner's kitchen; `method` and `count` name the
/// objective of the best tree.
#[pyfunction]
pub(crate) fn explain(
    py: Python<'_>,
    planner: &PyPlanner,
    goal: u32,
    method: &Bound<'_, PyAny>,
    count: &Bound<'_, PyAny>,
) -> PyResult<ExplainTuple> {
    check_object(&planner.foon, goal)?;
    let query = Query {
        method: str_field("method", method)?.parse().map_err(PyFoonErr)?,
        count: str_field("count", count)?.parse().map_err(PyFoonErr)?,
        ..Query::default()
    };
    let (foon, prep) = (&*planner.foon, &*planner.prep);
    let (e, text): (Explain, String) = enter(py, |cancel| {
        let ctx = Context::with(foon, prep)?.with_cancel(cancel);
        let e = foon_core::explain::explain(&ctx, goal, query)?;
        let text = e.text(&ctx);
        Ok((e, text))
    })?;
    let native = Py::new(
        py,
        PyExplanation {
            foon: Arc::clone(&planner.foon),
            prep: Arc::clone(&planner.prep),
            inner: e.clone(),
        },
    )?;
    let plan = e
        .plan
        .map(|plan| Py::new(py, PyPlan { plan }))
        .transpose()?;
    Ok((
        e.status.as_str(),
        e.rank,
        plan,
        e.buyable,
        e.shopping,
        e.producers
            .into_iter()
            .map(|p| {
                (
                    p.unit,
                    p.blockers
                        .iter()
                        .map(|b| (b.object, b.kind.as_str(), b.buyable))
                        .collect(),
                )
            })
            .collect(),
        e.cycle,
        e.cycle_units,
        e.unblock.iter().map(|u| (u.object, u.alone)).collect(),
        text,
        native,
    ))
}

/// The similarity index of one FOON (built once; see `foon_core::find`).
#[pyclass(frozen, module = "foon._foon", name = "FindIndex")]
pub(crate) struct PyFindIndex {
    foon: Arc<foon_core::Foon>,
    index: FindIndex,
}

#[pymethods]
impl PyFindIndex {
    #[new]
    fn new(py: Python<'_>, foon: &PyFoon) -> Self {
        let f = Arc::clone(&foon.inner);
        let index = py.detach(|| FindIndex::build(&f));
        Self { foon: f, index }
    }

    /// The `k` objects most similar to `text`, best first: (object id, score).
    fn find(&self, py: Python<'_>, text: &str, k: &Bound<'_, PyAny>) -> PyResult<Vec<(u32, f64)>> {
        let k: usize = required_count("k", k, 0)?;
        let (foon, index) = (&*self.foon, &self.index);
        Ok(py.detach(|| {
            index
                .find(foon, text, k)
                .into_iter()
                .map(|f| (f.object, f.score))
                .collect()
        }))
    }
}

/// The object that stands for a goal (a label, or an object's fields) at identity `level`
/// with the planner's kitchen: the rule of a batch row's goal,
/// `foon_core::queries::GoalText::resolve` (level 3: the object itself; below: a label stands
/// for the label-only object, see `foon_core::levels::goal_at_level`).
#[pyfunction]
pub(crate) fn goal_at_level(
    py: Python<'_>,
    planner: &PyPlanner,
    goal: LabelOrObject,
    level: u8,
) -> PyResult<u32> {
    let goal = match goal {
        LabelOrObject::Label(l) => GoalText::Label(l),
        LabelOrObject::Object(t) => GoalText::Object(spec_of(t)),
    };
    let (foon, prep) = (&*planner.foon, &*planner.prep);
    // A look-up: on this thread, as every plan call resolves its goal through here.
    enter_here(py, |cancel| {
        let ctx = Context::with(foon, prep)?.with_cancel(cancel);
        goal.resolve(&ctx, level)
    })
}

/// A goal given by its label or by an object's fields.
#[derive(FromPyObject)]
pub(crate) enum LabelOrObject {
    Label(String),
    Object(ObjTuple),
}
