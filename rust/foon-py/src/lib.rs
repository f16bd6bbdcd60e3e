//! `foon._foon`: the thin `PyO3` layer over `foon-core` (conversions, errors, GIL release).
//! No algorithm lives here.
// PyO3 hands arguments over as owned values extracted from Python objects.
#![allow(clippy::needless_pass_by_value)]

mod errors;

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use foon_core::companion::{self, MotionRates, ObjectSpec};
use foon_core::search::{self, Compat, Context, Count, Method, Plan, Prepared, Query};
use foon_core::{InputKind, ParseOptions, verify, write};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyString};

use errors::run_detached;

/// An object as Python sees it: (label, states, ingredients, container).
type ObjTuple = (String, Vec<String>, Vec<String>, Option<String>);

/// (valid in some order, height, first position whose needed inputs are unavailable).
type TreeCheck = (bool, Option<u32>, Option<(usize, Vec<u32>)>);

fn spec_of(t: ObjTuple) -> ObjectSpec {
    ObjectSpec {
        label: t.0,
        states: t.1,
        ingredients: t.2,
        container: t.3,
    }
}

fn tuple_of(s: ObjectSpec) -> ObjTuple {
    (s.label, s.states, s.ingredients, s.container)
}

fn kind_of(kind: &str) -> PyResult<InputKind> {
    match kind {
        "kitchen" => Ok(InputKind::Kitchen),
        "goal" => Ok(InputKind::Goal),
        _ => Err(pyo3::exceptions::PyValueError::new_err(format!(
            "unknown object list kind '{kind}'"
        ))),
    }
}

fn text_bytes(text: &Bound<'_, PyAny>) -> PyResult<Vec<u8>> {
    if let Ok(s) = text.cast::<PyString>() {
        Ok(s.to_str()?.as_bytes().to_vec())
    } else if let Ok(b) = text.cast::<PyBytes>() {
        Ok(b.as_bytes().to_vec())
    } else {
        Err(pyo3::exceptions::PyTypeError::new_err(
            "expected str or bytes",
        ))
    }
}

/// A parsed FOON (immutable; safe to share between threads).
#[pyclass(frozen, module = "foon._foon", name = "Foon")]
struct PyFoon {
    inner: Arc<foon_core::Foon>,
}

/// One planning result, read by `foon.TaskTree` (object and FU ids; the Python layer turns
/// them into objects only when asked).
#[pyclass(frozen, module = "foon._foon", name = "Plan")]
struct PyPlan {
    plan: Plan,
}

fn str_compat(c: Compat) -> &'static str {
    if c == Compat::Course {
        "course"
    } else {
        "sound"
    }
}

fn str_count(c: Count) -> &'static str {
    if c == Count::Ingredients {
        "ingredients"
    } else {
        "nodes"
    }
}

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
        str_compat(self.plan.query.compat)
    }
    #[getter]
    fn count(&self) -> &'static str {
        str_count(self.plan.query.count)
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
        self.plan
            .explanation
            .as_ref()
            .map(|e| e.missing.clone())
            .unwrap_or_default()
    }
    #[getter]
    fn cycle(&self) -> Vec<u32> {
        self.plan
            .explanation
            .as_ref()
            .map(|e| e.cycle.clone())
            .unwrap_or_default()
    }
    #[getter]
    fn cycle_units(&self) -> Vec<u32> {
        self.plan
            .explanation
            .as_ref()
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
}

#[pymethods]
impl PyFoon {
    /// Reads and parses a FOON file (any dialect).
    #[staticmethod]
    #[pyo3(signature = (path, *, strict = false))]
    fn load(py: Python<'_>, path: PathBuf, strict: bool) -> PyResult<Self> {
        let foon = run_detached(py, || foon_core::load_foon(&path, ParseOptions { strict }))?;
        Ok(Self {
            inner: Arc::new(foon),
        })
    }

    /// Parses FOON text (`str` or `bytes`); `path` only names the source in messages.
    #[staticmethod]
    #[pyo3(signature = (text, *, strict = false, path = None))]
    fn from_text(
        py: Python<'_>,
        text: &Bound<'_, PyAny>,
        strict: bool,
        path: Option<PathBuf>,
    ) -> PyResult<Self> {
        let data = text_bytes(text)?;
        let foon = run_detached(py, || {
            foon_core::parse_foon(&data, path.as_deref(), ParseOptions { strict })
        })?;
        Ok(Self {
            inner: Arc::new(foon),
        })
    }

    #[getter]
    fn fu_count(&self) -> usize {
        self.inner.fu_count()
    }

    #[getter]
    fn object_count(&self) -> usize {
        self.inner.object_count()
    }

    #[getter]
    fn source(&self) -> Option<String> {
        self.inner.source().map(|p| p.display().to_string())
    }

    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.inner.stats();
        let d = PyDict::new(py);
        d.set_item("functional_units", s.functional_units)?;
        d.set_item("objects", s.objects)?;
        d.set_item("produced_objects", s.produced_objects)?;
        d.set_item("motions", s.motions)?;
        d.set_item("strings", s.strings)?;
        d.set_item("input_edges", s.input_edges)?;
        d.set_item("output_edges", s.output_edges)?;
        d.set_item("duplicates_dropped", s.duplicates_dropped)?;
        d.set_item("warnings", s.warnings)?;
        d.set_item("index_bytes", s.index_bytes)?;
        Ok(d)
    }

    /// Warnings of the load: (path, line, column, kind, message).
    fn warnings(&self) -> Vec<(Option<String>, u64, u32, &'static str, String)> {
        self.inner
            .warnings()
            .iter()
            .map(|w| {
                let (p, line, col) = location(&w.at);
                (p, line, col, w.kind.as_str(), w.message.clone())
            })
            .collect()
    }

    /// Dropped duplicate FUs: (line of the dropped copy, index of the kept one).
    fn duplicates(&self) -> Vec<(u32, u32)> {
        self.inner
            .duplicates()
            .iter()
            .map(|d| (d.line, d.of))
            .collect()
    }

    /// Object `o` in its first written form: (label, states, ingredients, container).
    fn object(&self, o: u32) -> PyResult<ObjTuple> {
        self.check_object(o)?;
        Ok(tuple_of(ObjectSpec::of_object(&self.inner, o)))
    }

    /// FU `f`: (motion, input object ids, output object ids, source line).
    fn fu(&self, f: u32) -> PyResult<(String, Vec<u32>, Vec<u32>, u32)> {
        self.check_fu(f)?;
        let foon = &self.inner;
        Ok((
            foon.motion_text(f).to_owned(),
            foon.inputs(f).to_vec(),
            foon.outputs(f).to_vec(),
            foon.fu_line(f),
        ))
    }

    /// FU `f` in the course text form (ends with `//`).
    fn fu_text(&self, f: u32) -> PyResult<String> {
        self.check_fu(f)?;
        let mut s = String::new();
        write::fu_text(&self.inner, f, &mut s);
        Ok(s)
    }

    /// A task tree in the course output file form.
    fn tree_text(&self, units: Vec<u32>) -> PyResult<String> {
        for &f in &units {
            self.check_fu(f)?;
        }
        Ok(write::tree_text(&self.inner, &units))
    }

    /// The whole FOON in the course text form.
    fn to_text(&self, py: Python<'_>) -> String {
        let foon = &self.inner;
        py.detach(|| write::foon_text(foon))
    }

    /// The id of the object with this identity, or None.
    #[pyo3(signature = (label, states, ingredients, container))]
    fn find(
        &self,
        label: &str,
        states: Vec<String>,
        ingredients: Vec<String>,
        container: Option<String>,
    ) -> Option<u32> {
        let s: Vec<&str> = states.iter().map(String::as_str).collect();
        let i: Vec<&str> = ingredients.iter().map(String::as_str).collect();
        self.inner.find_object(label, &s, &i, container.as_deref())
    }

    fn objects_with_label(&self, label: &str) -> Vec<u32> {
        self.inner.objects_with_label(label)
    }

    fn producers(&self, o: u32) -> PyResult<Vec<u32>> {
        self.check_object(o)?;
        Ok(self.inner.producers(o).to_vec())
    }

    fn consumers(&self, o: u32) -> PyResult<Vec<u32>> {
        self.check_object(o)?;
        Ok(self.inner.consumers(o).to_vec())
    }

    /// Checks the task tree in `tree` (a parsed tree file) against this FOON, in its order.
    fn verify_tree<'py>(
        &self,
        py: Python<'py>,
        tree: &PyFoon,
        kitchen: Vec<ObjTuple>,
        utensils: Vec<String>,
        goal: ObjTuple,
    ) -> PyResult<Bound<'py, PyDict>> {
        self.verify_tree_impl(py, &tree.inner, kitchen, utensils, goal)
    }
}

impl PyFoon {
    /// Checks a task-tree file's units in their order (see `foon_core::verify`).
    fn verify_tree_impl<'py>(
        &self,
        py: Python<'py>,
        tree: &foon_core::Foon,
        kitchen: Vec<ObjTuple>,
        utensils: Vec<String>,
        goal: ObjTuple,
    ) -> PyResult<Bound<'py, PyDict>> {
        let kitchen: Vec<ObjectSpec> = kitchen.into_iter().map(spec_of).collect();
        let goal = spec_of(goal);
        let foon = &self.inner;
        let r = run_detached(py, || {
            verify::verify_tree(foon, tree, &kitchen, &utensils, &goal)
        })?;
        let d = PyDict::new(py);
        d.set_item("units", r.units)?;
        d.set_item("valid", r.is_valid())?;
        d.set_item("goal_made", r.goal_made)?;
        d.set_item("goal_absent", r.goal_absent)?;
        d.set_item("foreign_units", r.foreign_units)?;
        match r.first_blocked {
            Some(b) => {
                let missing: Vec<ObjTuple> = b.missing.into_iter().map(tuple_of).collect();
                d.set_item("blocked", (b.position, b.line, missing))?;
            }
            None => d.set_item("blocked", py.None())?,
        }
        Ok(d)
    }

    fn check_object(&self, o: u32) -> PyResult<()> {
        check_object(&self.inner, o)
    }

    fn check_fu(&self, f: u32) -> PyResult<()> {
        check_fu(&self.inner, f)
    }
}

/// A FOON with its planning inputs (kitchen, utensils, motion rates) prepared once, for any
/// number of plans.
#[pyclass(frozen, module = "foon._foon", name = "Planner")]
struct PyPlanner {
    foon: Arc<foon_core::Foon>,
    prep: Arc<Prepared>,
}

#[pymethods]
impl PyPlanner {
    #[new]
    #[pyo3(signature = (foon, kitchen, utensils, rates = None, default_rate = None))]
    fn new(
        py: Python<'_>,
        foon: &PyFoon,
        kitchen: Vec<ObjTuple>,
        utensils: Vec<String>,
        rates: Option<Vec<(String, f64)>>,
        default_rate: Option<f64>,
    ) -> PyResult<Self> {
        let kitchen: Vec<ObjectSpec> = kitchen.into_iter().map(spec_of).collect();
        let rates = rates
            .map(MotionRates::from_pairs)
            .transpose()
            .map_err(errors::PyFoonErr)?;
        let f = Arc::clone(&foon.inner);
        let prep = run_detached(py, || {
            Prepared::new(&f, &kitchen, &utensils, rates.as_ref(), default_rate)
        })?;
        Ok(Self {
            foon: f,
            prep: Arc::new(prep),
        })
    }

    /// Plans every goal (object ids); one result dict per goal. With more than one goal the
    /// work is spread over `threads` threads (all cores when None).
    #[pyo3(signature = (goals, method, compat, count, threads = None))]
    fn plan(
        &self,
        py: Python<'_>,
        goals: Vec<u32>,
        method: &str,
        compat: &str,
        count: &str,
        threads: Option<usize>,
    ) -> PyResult<Vec<Py<PyPlan>>> {
        let query = Query {
            method: method.parse().map_err(errors::PyFoonErr)?,
            compat: compat.parse().map_err(errors::PyFoonErr)?,
            count: count.parse().map_err(errors::PyFoonErr)?,
        };
        for &g in &goals {
            check_object(&self.foon, g)?;
        }
        let (foon, prep) = (&*self.foon, &*self.prep);
        let plans = run_detached(py, || {
            // Threads cost more to start than a few small plans take: spread only batches
            // that are large in goals or in graph.
            let worth_threads =
                goals.len() >= 8 || (goals.len() >= 2 && foon.fu_count() >= 100_000);
            if threads == Some(1) || !worth_threads {
                // On this thread: look at Python's signals now and then, so Ctrl-C stops it.
                let interrupted = || Python::attach(|py| py.check_signals().is_err());
                let ctx = Context::with(foon, prep)?.with_cancel(&interrupted);
                goals
                    .iter()
                    .map(|&g| ctx.plan(g, query))
                    .collect::<Result<Vec<_>, _>>()
            } else {
                plan_batch(foon, prep, &goals, query, threads)
            }
        })?;
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
        run_detached(py, || {
            let ctx = Context::with(foon, prep)?;
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
        run_detached(py, || {
            let ctx = Context::with(foon, prep)?;
            let r = ctx.ranks();
            Ok((0..foon.object_count() as u32).map(|o| r.rank(o)).collect())
        })
    }

    /// Object ids of the kitchen items found in the FOON, in id order.
    fn kitchen_objects(&self) -> PyResult<Vec<u32>> {
        let ctx = Context::with(&self.foon, &self.prep).map_err(errors::PyFoonErr)?;
        Ok(ctx.kitchen_objects().to_vec())
    }
}

/// Thread pools by size, built once: building one costs more than planning a small batch.
/// `None` is rayon's global pool (one thread per core).
fn pool_of(threads: Option<usize>) -> foon_core::Result<Option<Arc<rayon::ThreadPool>>> {
    static POOLS: Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>> = Mutex::new(Vec::new());
    let Some(n) = threads.filter(|&n| n != rayon::current_num_threads()) else {
        return Ok(None);
    };
    let mut pools = POOLS
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some((_, p)) = pools.iter().find(|(k, _)| *k == n) {
        return Ok(Some(Arc::clone(p)));
    }
    let p = Arc::new(
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| foon_core::Error::Invalid(e.to_string()))?,
    );
    pools.push((n, Arc::clone(&p)));
    Ok(Some(p))
}

/// Plans a batch on a thread pool while this thread watches for Ctrl-C and tells the
/// workers to stop.
fn plan_batch(
    foon: &foon_core::Foon,
    prep: &Prepared,
    goals: &[u32],
    query: Query,
    threads: Option<usize>,
) -> foon_core::Result<Vec<Plan>> {
    let stop = AtomicBool::new(false);
    let stopped = || stop.load(Ordering::Relaxed);
    let ctx = Context::with(foon, prep)?.with_cancel(&stopped);
    let pool = pool_of(threads)?;
    let done = AtomicBool::new(false);
    let mut result = None;
    // The batch runs on the pool; this thread only watches for Ctrl-C.
    let mut work = || {
        result = Some(
            search::plan_many(&ctx, goals, query)
                .into_iter()
                .collect::<Result<Vec<_>, _>>(),
        );
        done.store(true, Ordering::Release);
    };
    let watcher = std::thread::current();
    let watch = || {
        while !done.load(Ordering::Acquire) {
            std::thread::park_timeout(std::time::Duration::from_millis(20));
            if Python::attach(|py| py.check_signals().is_err()) {
                stop.store(true, Ordering::Relaxed);
            }
        }
    };
    macro_rules! watched {
        ($($scope:tt)+) => {
            $($scope)+(|s| {
                s.spawn(|_| {
                    work();
                    watcher.unpark();
                });
                watch();
            })
        };
    }
    match &pool {
        Some(p) => watched!(p.in_place_scope),
        None => watched!(rayon::in_place_scope),
    }
    result.unwrap_or(Err(foon_core::Error::Invalid(
        "a planning thread stopped without a result".into(),
    )))
}

fn check_object(foon: &foon_core::Foon, o: u32) -> PyResult<()> {
    if (o as usize) < foon.object_count() {
        Ok(())
    } else {
        Err(pyo3::exceptions::PyIndexError::new_err(format!(
            "object id {o} is out of range (the FOON has {} objects)",
            foon.object_count()
        )))
    }
}

fn check_fu(foon: &foon_core::Foon, f: u32) -> PyResult<()> {
    if (f as usize) < foon.fu_count() {
        Ok(())
    } else {
        Err(pyo3::exceptions::PyIndexError::new_err(format!(
            "functional unit {f} is out of range (the FOON has {})",
            foon.fu_count()
        )))
    }
}

/// Reads a list of objects (kitchen or goal; JSON or FOON object blocks) from a file.
#[pyfunction]
fn load_objects(py: Python<'_>, path: PathBuf, kind: &str) -> PyResult<Vec<ObjTuple>> {
    let k = kind_of(kind)?;
    let v = run_detached(py, || companion::load_objects(&path, k))?;
    Ok(v.into_iter().map(tuple_of).collect())
}

/// Parses a list of objects from text; `path` only names the source in messages.
#[pyfunction]
#[pyo3(signature = (text, kind, path = None))]
fn parse_objects(
    text: &Bound<'_, PyAny>,
    kind: &str,
    path: Option<PathBuf>,
) -> PyResult<Vec<ObjTuple>> {
    let k = kind_of(kind)?;
    let data = text_bytes(text)?;
    let v = companion::parse_objects(&data, path.as_deref(), k).map_err(errors::PyFoonErr)?;
    Ok(v.into_iter().map(tuple_of).collect())
}

/// Reads a motion table: (motion, rate) pairs in file order.
#[pyfunction]
fn load_rates(py: Python<'_>, path: PathBuf) -> PyResult<Vec<(String, f64)>> {
    Ok(run_detached(py, || companion::load_rates(&path))?.entries)
}

#[pyfunction]
#[pyo3(signature = (text, path = None))]
fn parse_rates(text: &Bound<'_, PyAny>, path: Option<PathBuf>) -> PyResult<Vec<(String, f64)>> {
    let data = text_bytes(text)?;
    Ok(companion::parse_rates(&data, path.as_deref())
        .map_err(errors::PyFoonErr)?
        .entries)
}

/// Reads a utensil list.
#[pyfunction]
fn load_utensils(py: Python<'_>, path: PathBuf) -> PyResult<Vec<String>> {
    run_detached(py, || companion::load_utensils(&path))
}

#[pyfunction]
#[pyo3(signature = (text, path = None))]
fn parse_utensils(text: &Bound<'_, PyAny>, path: Option<PathBuf>) -> PyResult<Vec<String>> {
    let data = text_bytes(text)?;
    Ok(companion::parse_utensils(&data, path.as_deref()).map_err(errors::PyFoonErr)?)
}

/// A lint finding: (path, line, column, severity, code, message).
type FindingTuple = (Option<String>, u64, u32, &'static str, &'static str, String);

/// Checks FOON files: every error, warning and note of each, in line order.
#[pyfunction]
#[pyo3(signature = (paths, kitchen = None, rates = None, utensils = Vec::new()))]
fn check(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    kitchen: Option<Vec<ObjTuple>>,
    rates: Option<Vec<(String, f64)>>,
    utensils: Vec<String>,
) -> PyResult<Vec<FindingTuple>> {
    let kitchen: Option<Vec<ObjectSpec>> = kitchen.map(|k| k.into_iter().map(spec_of).collect());
    let rates = rates
        .map(MotionRates::from_pairs)
        .transpose()
        .map_err(errors::PyFoonErr)?;
    let findings = run_detached(py, || {
        let opts = foon_core::lint::LintOptions {
            kitchen: kitchen.as_deref(),
            rates: rates.as_ref(),
            utensils: &utensils,
        };
        let mut all = Vec::new();
        for p in &paths {
            all.extend(foon_core::lint::lint_file(p, &opts)?);
        }
        Ok(all)
    })?;
    Ok(findings
        .into_iter()
        .map(|f| {
            let (p, line, col) = location(&f.at);
            (p, line, col, f.severity.as_str(), f.code, f.message)
        })
        .collect())
}

/// A location as Python sees it: (path, line, column).
fn location(at: &foon_core::Location) -> (Option<String>, u64, u32) {
    (
        at.path.as_ref().map(|p| p.display().to_string()),
        at.line,
        at.column,
    )
}

/// Method names, in the order the comparison table lists them.
#[pyfunction]
fn methods() -> Vec<&'static str> {
    Method::ALL.iter().map(|m| m.as_str()).collect()
}

#[pymodule]
mod _foon {
    #[pymodule_export]
    use super::{
        PyFoon, PyPlan, PyPlanner, check, load_objects, load_rates, load_utensils, methods,
        parse_objects, parse_rates, parse_utensils,
    };

    #[pymodule_export]
    use super::errors::{FoonError, GoalNotFoundError, MissingRateError, ParseError};

    #[pymodule_init]
    fn init(m: &pyo3::Bound<'_, pyo3::types::PyModule>) -> pyo3::PyResult<()> {
        use pyo3::types::PyModuleMethods;
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        Ok(())
    }
}
