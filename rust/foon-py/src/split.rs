//! `foon._foon.split`: the robot/human split (`foon_core::search::split`), and the per-unit
//! rate override files it reads.

use std::path::PathBuf;

use foon_core::parse::{self, RateOverrides};
use foon_core::search::split::{Profile, split as core_split};
use foon_core::{Context, MotionRates};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::sync::Arc;

use foon_core::search::split::Split;
use foon_core::write::{self, Format, Options};

use crate::convert::{opt_path_arg, path_arg, rate_arg, rate_pairs_arg, text_bytes};
use crate::errors::{PyFoonErr, enter};
use crate::foon::check_object;
use crate::planner::PyPlanner;

/// (unit, rate, line) entries of an override file.
type Triples = Vec<(u32, f64, u64)>;

/// Reads a rate override file: (unit, rate, line) entries, sorted by unit.
#[pyfunction]
pub(crate) fn load_overrides(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<Triples> {
    let path = path_arg("path", path)?;
    Ok(enter(py, |_| parse::load_overrides(&path))?.triples())
}

/// Parses the text of a rate override file (see [`load_overrides`]).
#[pyfunction]
#[pyo3(signature = (text, path = None))]
pub(crate) fn parse_overrides(
    py: Python<'_>,
    text: &Bound<'_, PyAny>,
    path: Option<&Bound<'_, PyAny>>,
) -> PyResult<Triples> {
    let data = text_bytes("text", text)?;
    let path = opt_path_arg("path", path)?;
    Ok(enter(py, |_| parse::parse_overrides(&data, path.as_deref()))?.triples())
}

type ProfileArg<'py> = (
    Option<Bound<'py, PyAny>>,
    Option<Bound<'py, PyAny>>,
    Triples,
    Option<Bound<'py, PyAny>>,
);

/// A profile from Python: (motion rate pairs or None, default rate or None, override
/// entries (unit, rate, line), the override file's path or None).
fn profile_arg(name: &str, v: &Bound<'_, PyAny>) -> PyResult<Profile> {
    let (rates, default, overrides, path): ProfileArg<'_> = v.extract()?;
    let rates = rates
        .filter(|r| !r.is_none())
        .map(|r| rate_pairs_arg(&format!("the motions of {name}"), &r))
        .transpose()?
        .map(MotionRates::from_pairs)
        .transpose()
        .map_err(PyFoonErr)?;
    let default_rate = default
        .filter(|r| !r.is_none())
        .map(|r| rate_arg(&format!("the default rate of {name}"), &r))
        .transpose()?;
    let path: Option<PathBuf> = opt_path_arg("path", path.as_ref())?;
    let overrides = RateOverrides::from_lines(overrides, path.as_deref()).map_err(PyFoonErr)?;
    Ok(Profile {
        rates,
        default_rate,
        overrides,
    })
}

/// The split of `goal` for budgets 0..=`max_human` over the planner's kitchen (its own rates
/// are not used: `robot` and `human` give them), as a dict.
#[pyfunction]
#[pyo3(signature = (planner, goal, robot, human, max_human, fixed_tree = false))]
pub(crate) fn plan_split<'py>(
    py: Python<'py>,
    planner: &PyPlanner,
    goal: u32,
    robot: &Bound<'_, PyAny>,
    human: &Bound<'_, PyAny>,
    max_human: u32,
    fixed_tree: bool,
) -> PyResult<Bound<'py, PyDict>> {
    check_object(&planner.foon, goal)?;
    let robot = profile_arg("the robot profile", robot)?;
    let human = profile_arg("the human profile", human)?;
    let (foon, prep) = (&*planner.foon, &*planner.prep);
    let s = enter(py, |cancel| {
        let ctx = Context::with(foon, prep)?.with_cancel(cancel);
        core_split(&ctx, goal, &robot, &human, max_human, fixed_tree)
    })?;
    let d = PyDict::new(py);
    d.set_item(
        "native",
        Py::new(
            py,
            PySplit {
                foon: Arc::clone(&planner.foon),
                inner: s.clone(),
            },
        )?,
    )?;
    d.set_item("goal", s.goal)?;
    d.set_item("max_human", s.max_human)?;
    d.set_item("solved", s.solved)?;
    d.set_item("best", s.best)?;
    let front: Vec<_> = s
        .front
        .into_iter()
        .map(|p| {
            let steps: Vec<_> = p
                .steps
                .iter()
                .map(|t| (t.unit, t.object, t.actor.as_str(), t.budget, t.times))
                .collect();
            (p.human, p.success, steps, p.units)
        })
        .collect();
    d.set_item("front", front)?;
    let fixed: Option<Vec<_>> = s.fixed.map(|v| {
        v.into_iter()
            .map(|p| {
                let steps: Vec<_> = p
                    .steps
                    .iter()
                    .map(|&(f, a, t)| (f, a.as_str(), t))
                    .collect();
                (p.human, p.success, steps)
            })
            .collect()
    });
    d.set_item("fixed", fixed)?;
    d.set_item(
        "explanation",
        s.explanation.map(|e| (e.missing, e.cycle, e.cycle_units)),
    )?;
    d.set_item("expanded", s.expanded)?;
    Ok(d)
}

/// One split as the core holds it, for its page (`foon_core::write::write_split`).
#[pyclass(frozen, module = "foon._foon", name = "Split")]
pub(crate) struct PySplit {
    foon: Arc<foon_core::Foon>,
    inner: Split,
}

#[pymethods]
impl PySplit {
    /// The split in `format` (html: the front as a chart, each point's steps).
    #[pyo3(signature = (format, *, title = None))]
    fn write<'py>(
        &self,
        py: Python<'py>,
        format: &str,
        title: Option<String>,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let fmt: Format = format.parse().map_err(PyFoonErr)?;
        let opts = Options {
            title,
            ..Options::default()
        };
        let (foon, s) = (&*self.foon, &self.inner);
        let bytes = enter(py, |_| {
            write::to_bytes(|out| write::write_split(fmt, foon, s, &opts, out))
        })?;
        Ok(PyBytes::new(py, &bytes))
    }
}
