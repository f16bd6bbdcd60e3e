//! The writers: every output format of a task tree, a FOON or a comparison, through the
//! core's one interface (`foon_core::write`). Python gets bytes (text formats are UTF-8).

use std::collections::HashMap;
use std::str::FromStr;

use std::sync::{Mutex, PoisonError};

use foon_core::write::{
    self, CompareRow, Comparison, Failed, FoonDoc, Format, Item, Options, TreeDoc, TreeWriter,
};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::convert::{ObjTuple, object_index, spec_of};
use crate::errors::{PyFoonErr, enter};
use crate::foon::PyFoon;
use crate::plan::PyPlan;
use crate::planner::PyPlanner;

fn format_arg(name: &str) -> PyResult<Format> {
    Format::from_str(name).map_err(|e| PyFoonErr(e).into())
}

fn options(title: Option<String>, max_nodes: Option<usize>, cost_scale: Option<u32>) -> Options {
    let mut o = Options {
        title,
        ..Options::default()
    };
    if let Some(n) = max_nodes {
        o.max_nodes = n;
    }
    if let Some(s) = cost_scale {
        o.cost_scale = s;
    }
    o
}

/// A format's (name, extension, MIME type, binary, needs `dot`, writes a tree, writes a FOON,
/// writes a comparison).
type FormatRow = (
    &'static str,
    &'static str,
    &'static str,
    bool,
    bool,
    bool,
    bool,
    bool,
);

/// Every format: (name, extension, MIME type, binary, needs `dot`, writes a tree, writes a
/// FOON, writes a comparison).
#[pyfunction]
pub(crate) fn formats() -> Vec<FormatRow> {
    Format::ALL
        .iter()
        .map(|&f| {
            (
                f.as_str(),
                f.extension(),
                f.mime(),
                f.is_binary(),
                f.needs_dot(),
                f.writes_tree(),
                f.writes_foon(),
                f.writes_comparison(),
            )
        })
        .collect()
}

/// A task tree (the plan, made by `planner`) in `format`.
#[pyfunction]
#[pyo3(signature = (planner, plan, format, *, title = None, max_nodes = None, cost_scale = None))]
pub(crate) fn write_tree<'py>(
    py: Python<'py>,
    planner: &PyPlanner,
    plan: &PyPlan,
    format: &str,
    title: Option<String>,
    max_nodes: Option<usize>,
    cost_scale: Option<u32>,
) -> PyResult<Bound<'py, PyBytes>> {
    let fmt = format_arg(format)?;
    let opts = options(title, max_nodes, cost_scale);
    let (foon, prep, plan) = (&planner.foon, &planner.prep, &plan.plan);
    let bytes = enter(py, |_| {
        write::to_bytes(|out| write::write_tree(fmt, &TreeDoc::new(foon, prep, plan), &opts, out))
    })?;
    Ok(PyBytes::new(py, &bytes))
}

/// A stream of task trees written in one format (see `foon_core::write::TreeWriter`): each
/// call returns the bytes to write now (formats that draw everything at once return them
/// from `end`).
#[pyclass(frozen, module = "foon._foon", name = "TreeWriter")]
pub(crate) struct PyTreeWriter {
    inner: Mutex<TreeWriter>,
}

impl PyTreeWriter {
    fn run<'py>(
        &self,
        py: Python<'py>,
        f: impl FnOnce(&mut TreeWriter, &mut Vec<u8>) -> foon_core::Result<()> + Send,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let bytes = enter(py, |_| {
            let mut w = self.inner.lock().unwrap_or_else(PoisonError::into_inner);
            write::to_bytes(|out| {
                let mut buf = Vec::new();
                f(&mut w, &mut buf)?;
                out.write_all(&buf)
                    .map_err(|e| foon_core::Error::Invalid(e.to_string()))
            })
        })?;
        Ok(PyBytes::new(py, &bytes))
    }
}

#[pymethods]
impl PyTreeWriter {
    #[new]
    #[pyo3(signature = (format, many, *, title = None, max_nodes = None, cost_scale = None))]
    fn new(
        format: &str,
        many: bool,
        title: Option<String>,
        max_nodes: Option<usize>,
        cost_scale: Option<u32>,
    ) -> PyResult<Self> {
        let opts = options(title, max_nodes, cost_scale);
        let w = TreeWriter::new(format_arg(format)?, &opts, many).map_err(PyFoonErr)?;
        Ok(Self {
            inner: Mutex::new(w),
        })
    }

    fn begin<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        self.run(py, |w, out| w.begin(out))
    }

    /// A planned tree (`plan`, made by `planner`).
    fn tree<'py>(
        &self,
        py: Python<'py>,
        planner: &PyPlanner,
        plan: &PyPlan,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let (foon, prep, plan) = (&planner.foon, &planner.prep, &plan.plan);
        self.run(py, |w, out| {
            w.item(&Item::Tree(TreeDoc::new(foon, prep, plan)), out)
        })
    }

    /// A goal that could not be planned: the goal as given (label only when `label_only`),
    /// the method and why.
    fn failed<'py>(
        &self,
        py: Python<'py>,
        goal: ObjTuple,
        label_only: bool,
        method: &str,
        error: String,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let method = method.parse().map_err(PyFoonErr)?;
        let f = Failed {
            goal: spec_of(goal),
            label_only,
            method,
            error,
        };
        self.run(py, |w, out| w.item(&Item::Failed(&f), out))
    }

    fn end<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        self.run(py, |w, out| w.end(out))
    }
}

/// A FOON in `format`: all of it, the units `units`, or the units within `depth` steps of
/// the object `focus` (drawn as the goal); `planner` marks its kitchen (and is PDDL's initial
/// state).
#[pyfunction]
#[pyo3(signature = (foon, format, *, units = None, focus = None, depth = None, planner = None,
                    title = None, max_nodes = None, cost_scale = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn write_foon<'py>(
    py: Python<'py>,
    foon: &PyFoon,
    format: &str,
    units: Option<Vec<u32>>,
    focus: Option<&Bound<'_, PyAny>>,
    depth: Option<u32>,
    planner: Option<&PyPlanner>,
    title: Option<String>,
    max_nodes: Option<usize>,
    cost_scale: Option<u32>,
) -> PyResult<Bound<'py, PyBytes>> {
    let fmt = format_arg(format)?;
    let opts = options(title, max_nodes, cost_scale);
    let f = &foon.inner;
    if let Some(p) = planner {
        if !std::sync::Arc::ptr_eq(&p.foon, f) {
            return Err(PyFoonErr(foon_core::Error::Invalid(
                "the planner was made for another FOON".into(),
            ))
            .into());
        }
    }
    let focus = focus
        .filter(|o| !o.is_none())
        .map(|o| object_index(f, o))
        .transpose()?;
    if let Some(us) = &units {
        for &u in us {
            crate::foon::check_fu(f, u)?;
        }
    }
    let prep = planner.map(|p| &*p.prep);
    let bytes = enter(py, |_| {
        let mut doc = match (focus, depth) {
            (Some(o), Some(d)) => FoonDoc::around(f, o, d),
            _ => FoonDoc::whole(f),
        };
        if let Some(us) = units {
            let mut us = us;
            us.sort_unstable();
            us.dedup();
            doc.units = Some(us);
        }
        if doc.focus.is_none() {
            doc.focus = focus;
        }
        doc.prep = prep;
        write::to_bytes(|out| write::write_foon(fmt, &doc, &opts, out))
    })?;
    Ok(PyBytes::new(py, &bytes))
}

/// A comparison row given by its figures: (method, goal, solved, units, success, expanded,
/// seconds).
type Figures = (String, u32, bool, Option<usize>, Option<f64>, u64, f64);

/// A comparison: `rows` are (method, plan) for planned goals, (method, goal text, error)
/// for goals that could not be planned, and [`Figures`] for methods without a plan (the
/// robot/human split).
///
/// `level`: the identity level the planner matched at (a column of every row). `split`:
/// `(M, {goal id: (split success, fixed-tree success)})` of `foon compare --split M`, the
/// split columns of every row of those goals.
#[pyfunction]
#[pyo3(signature = (foon, rows, format, *, title = None, level = 3, split = None))]
#[allow(clippy::type_complexity)]
pub(crate) fn write_comparison<'py>(
    py: Python<'py>,
    foon: &PyFoon,
    rows: Vec<Bound<'py, PyAny>>,
    format: &str,
    title: Option<String>,
    level: u8,
    split: Option<(u32, HashMap<u32, (Option<f64>, Option<f64>)>)>,
) -> PyResult<Bound<'py, PyBytes>> {
    let fmt = format_arg(format)?;
    let opts = options(title, None, None);
    let mut out = Vec::with_capacity(rows.len());
    let mut goals: Vec<Option<u32>> = Vec::with_capacity(rows.len());
    for r in &rows {
        if let Ok((method, plan)) = r.extract::<(String, PyRef<'_, PyPlan>)>() {
            out.push(CompareRow::of_plan(&foon.inner, &method, &plan.plan));
            goals.push(Some(plan.plan.goal));
        } else if let Ok(fig) = r.extract::<Figures>() {
            let (method, goal, solved, units, success, expanded, seconds) = fig;
            crate::foon::check_object(&foon.inner, goal)?;
            out.push(CompareRow::of_figures(
                &foon.inner,
                &method,
                goal,
                solved,
                units,
                success,
                expanded,
                seconds,
            ));
            goals.push(Some(goal));
        } else {
            let (method, goal, error): (String, String, String) = r.extract()?;
            out.push(CompareRow::failed(goal, &method, error));
            goals.push(None);
        }
    }
    let out = out
        .into_iter()
        .zip(&goals)
        .map(|(row, goal)| {
            let row = row.at_level(level);
            match &split {
                Some((m, by)) => {
                    let (s, f) = goal.and_then(|g| by.get(&g).copied()).unwrap_or_default();
                    row.with_split(*m, s, f)
                }
                None => row,
            }
        })
        .collect();
    let doc = Comparison::new(out);
    let bytes = enter(py, |_| {
        write::to_bytes(|o| write::write_comparison(fmt, &doc, &opts, o))
    })?;
    Ok(PyBytes::new(py, &bytes))
}

/// One line saying why the plan's goal could not be made (empty when solved).
#[pyfunction]
pub(crate) fn explanation(foon: &PyFoon, plan: &PyPlan) -> String {
    write::explanation_text(&foon.inner, &plan.plan)
}

/// A PDDL text cut into its domain and its problem.
#[pyfunction]
pub(crate) fn split_pddl(text: &str) -> PyResult<(String, String)> {
    write::pddl::split(text)
        .map(|(d, p)| (d.to_owned(), p.to_owned()))
        .ok_or_else(|| {
            PyFoonErr(foon_core::Error::Invalid(format!(
                "not a foon PDDL text: no line '{}'",
                write::pddl::PROBLEM_LINE
            )))
            .into()
        })
}
