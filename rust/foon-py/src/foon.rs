//! `foon._foon.Foon`: a parsed FOON, immutable and shared between threads.

use std::path::PathBuf;
use std::sync::Arc;

use foon_core::ObjectSpec;
use foon_core::{ParseOptions, verify, write};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyString, PyTuple};

use crate::convert::{
    ObjTuple, fu_index, location, object_index, opt_path_arg, path_arg, spec_of, text_bytes,
    tuple_of,
};
use crate::errors::{Cancel, PyFoonErr, enter};
use crate::serial;

/// Reads a FOON file; the core's loader asks `cancel` now and then and stops on Ctrl-C, and
/// counts the bytes read in `progress`.
fn load_foon(
    path: &std::path::Path,
    opts: ParseOptions,
    cancel: Cancel<'_>,
    progress: &foon_core::progress::Progress,
) -> foon_core::Result<foon_core::Foon> {
    let ctl = foon_core::parse::ParseControl {
        progress: Some(progress),
        ..Default::default()
    };
    foon_core::parse::load_foon_with(path, opts, cancel, ctl)
}

/// Parses FOON text (see [`load_foon`] for `cancel`).
fn parse_foon(
    data: &[u8],
    path: Option<&std::path::Path>,
    opts: ParseOptions,
    cancel: Cancel<'_>,
) -> foon_core::Result<foon_core::Foon> {
    foon_core::parse::parse_foon_cancellable(data, path, opts, cancel)
}

/// A parsed FOON (immutable; safe to share between threads).
#[pyclass(frozen, module = "foon._foon", name = "Foon")]
pub(crate) struct PyFoon {
    pub(crate) inner: Arc<foon_core::Foon>,
}

impl PyFoon {
    pub(crate) fn new(foon: foon_core::Foon) -> Self {
        Self {
            inner: Arc::new(foon),
        }
    }

    /// The first 8 bytes of the content fingerprint, for `__hash__`.
    fn hash_key(&self) -> u64 {
        let fp = self.inner.fingerprint();
        u64::from_le_bytes([fp[0], fp[1], fp[2], fp[3], fp[4], fp[5], fp[6], fp[7]])
    }
}

/// Builds one index from several FOON files (any dialect each), in the given order.
fn load_sources(
    paths: &[PathBuf],
    opts: ParseOptions,
    cancel: Cancel<'_>,
    progress: &foon_core::progress::Progress,
) -> foon_core::Result<foon_core::Foon> {
    let files = foon_core::merge::expand_paths(paths)?;
    let mut b = foon_core::index::Builder::new();
    for p in &files {
        if foon_core::index::file::is_index_file(p) {
            return Err(foon_core::Error::Invalid(format!(
                "{}: an index file cannot be a source of another index (give its FOON files)",
                p.display()
            )));
        }
        let ctl = foon_core::parse::ParseControl {
            progress: Some(progress),
            ..Default::default()
        };
        foon_core::parse::load_into(&mut b, p, opts, None, cancel, ctl)?;
    }
    b.try_finish()
}

/// Dropped duplicate units: (line of the dropped copy, index of the kept one).
type Duplicate = (u32, u32);

/// A load warning: (path, line, column, kind, message).
type WarningTuple = (Option<String>, u64, u32, &'static str, String);

#[pymethods]
impl PyFoon {
    /// Reads and parses a FOON file (any dialect).
    #[staticmethod]
    #[pyo3(signature = (path, *, strict = false, progress = false))]
    fn load(
        py: Python<'_>,
        path: &Bound<'_, PyAny>,
        strict: bool,
        progress: bool,
    ) -> PyResult<Self> {
        let path = path_arg("path", path)?;
        let foon = crate::progress::enter_progress(py, progress, true, |cancel, bar| {
            load_foon(&path, ParseOptions { strict }, cancel, bar)
        })?;
        Ok(Self::new(foon))
    }

    /// Builds one index from several FOON files and folders (a folder: its `.txt` and `.json`
    /// files, sorted), in the given order: an FU found again keeps its first copy and records
    /// every (source, line) it was found at.
    #[staticmethod]
    #[pyo3(signature = (paths, *, strict = false, progress = false))]
    fn load_sources(
        py: Python<'_>,
        paths: Vec<Bound<'_, PyAny>>,
        strict: bool,
        progress: bool,
    ) -> PyResult<Self> {
        let paths = paths
            .iter()
            .map(|p| path_arg("paths", p))
            .collect::<PyResult<Vec<_>>>()?;
        let foon = crate::progress::enter_progress(py, progress, true, |cancel, bar| {
            load_sources(&paths, ParseOptions { strict }, cancel, bar)
        })?;
        Ok(Self::new(foon))
    }

    /// Opens an index file again for unpickling: a clear error when the file is gone or its
    /// content (fingerprint, as hexadecimal) is not the pickled one.
    #[staticmethod]
    fn reopen(py: Python<'_>, path: &Bound<'_, PyAny>, fingerprint: &str) -> PyResult<Self> {
        let path = path_arg("path", path)?;
        let want = fingerprint.to_owned();
        let foon = enter(py, |_| {
            let f = foon_core::Foon::open_index(&path)?;
            let have = f.fingerprint_hex();
            if have == want {
                Ok(f)
            } else {
                Err(foon_core::Error::BadIndex {
                    path: path.clone(),
                    reason: format!(
                        "the index file changed since the FOON was pickled \
                         (fingerprint {want}, now {have})"
                    ),
                })
            }
        })?;
        Ok(Self::new(foon))
    }

    /// Writes the index as a `.foonidx` file, atomically (never over one of its inputs).
    fn write_index(&self, py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<()> {
        let path = path_arg("path", path)?;
        let foon = &self.inner;
        enter(py, |_| foon.write_index_file(&path))
    }

    /// Verifies the data checksum of a FOON opened from an index file (nothing to verify for
    /// one built in memory).
    fn verify_checksum(&self, py: Python<'_>) -> PyResult<()> {
        let foon = &self.inner;
        enter(py, |_| foon.verify_checksum())
    }

    /// The content fingerprint, as 32 hexadecimal digits.
    #[getter]
    fn fingerprint(&self) -> String {
        self.inner.fingerprint_hex()
    }

    /// The index file this FOON was opened from, if any.
    #[getter]
    fn index_path(&self) -> Option<String> {
        self.inner.index_path().map(|p| p.display().to_string())
    }

    /// Parses FOON text (`str` or `bytes`); `path` only names the source in messages.
    #[staticmethod]
    #[pyo3(signature = (text, *, strict = false, path = None))]
    fn from_text(
        py: Python<'_>,
        text: &Bound<'_, PyAny>,
        strict: bool,
        path: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let data = text_bytes("text", text)?;
        let path = opt_path_arg("path", path)?;
        let foon = enter(py, |cancel| {
            parse_foon(&data, path.as_deref(), ParseOptions { strict }, cancel)
        })?;
        Ok(Self::new(foon))
    }

    /// The stable serialised form (what pickling stores for a FOON not opened from an index
    /// file): its index bytes and its load report.
    fn to_bytes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let foon = &self.inner;
        let data = enter(py, |_| Ok(serial::encode(foon)))?;
        Ok(PyBytes::new(py, &data))
    }

    /// Rebuilds a FOON from the output of `to_bytes`.
    #[staticmethod]
    fn from_bytes(py: Python<'_>, data: &Bound<'_, PyBytes>) -> PyResult<Self> {
        let data = data.as_bytes().to_vec();
        let foon = enter(py, |_| {
            serial::decode(&data)
                .map_err(|e| foon_core::Error::Invalid(format!("not a serialised FOON: {e}")))
        })?;
        Ok(Self::new(foon))
    }

    /// A FOON opened from an index file pickles as (path, fingerprint) and is opened again
    /// when unpickled; any other pickles as its serialised form.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let me = slf.get();
        if let Some(path) = me.inner.index_path() {
            let f = slf.get_type().getattr("reopen")?;
            let args = (path.display().to_string(), me.inner.fingerprint_hex());
            return Ok((f, args.into_pyobject(py)?));
        }
        let f = slf.get_type().getattr("from_bytes")?;
        let data = me.to_bytes(py)?;
        Ok((f, PyTuple::new(py, [data])?))
    }

    /// Immutable: a copy is the same object.
    fn __copy__(slf: Bound<'_, Self>) -> Bound<'_, Self> {
        slf
    }

    fn __deepcopy__<'py>(slf: Bound<'py, Self>, _memo: &Bound<'py, PyAny>) -> Bound<'py, Self> {
        slf
    }

    /// Equal when the serialised forms are equal (same units, objects, lines, warnings and
    /// source).
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        let Ok(o) = other.cast::<PyFoon>() else {
            return false;
        };
        let o = o.get();
        Arc::ptr_eq(&self.inner, &o.inner)
            || (self.inner.fingerprint() == o.inner.fingerprint()
                && serial::encode(&self.inner) == serial::encode(&o.inner))
    }

    fn __hash__(&self) -> u64 {
        self.hash_key()
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
    fn warnings(&self) -> Vec<WarningTuple> {
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
    fn duplicates(&self) -> Vec<Duplicate> {
        self.inner
            .duplicates()
            .iter()
            .map(|d| (d.line, d.of))
            .collect()
    }

    /// Object `o` in its first written form: (label, states, ingredients, container).
    fn object(&self, o: &Bound<'_, PyAny>) -> PyResult<ObjTuple> {
        let o = object_index(&self.inner, o)?;
        Ok(tuple_of(ObjectSpec::of_object(&self.inner, o)))
    }

    /// FU `f`: (motion, input object ids, output object ids, source line).
    fn fu(&self, f: &Bound<'_, PyAny>) -> PyResult<(String, Vec<u32>, Vec<u32>, u32)> {
        let f = fu_index(&self.inner, f)?;
        let foon = &self.inner;
        Ok((
            foon.motion_text(f).to_owned(),
            foon.inputs(f).to_vec(),
            foon.outputs(f).to_vec(),
            foon.fu_line(f),
        ))
    }

    /// FU `f` in the course text form (ends with `//`).
    fn fu_text(&self, f: &Bound<'_, PyAny>) -> PyResult<String> {
        let f = fu_index(&self.inner, f)?;
        let mut s = String::new();
        write::fu_text(&self.inner, f, &mut s);
        Ok(s)
    }

    /// A task tree in the course output file form.
    fn tree_text(&self, units: Vec<u32>) -> PyResult<String> {
        for &f in &units {
            check_fu(&self.inner, f)?;
        }
        Ok(write::tree_text(&self.inner, &units))
    }

    /// The whole FOON in the course text form.
    fn to_text(&self, py: Python<'_>) -> PyResult<String> {
        let foon = &self.inner;
        enter(py, |_| Ok(write::foon_text(foon)))
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

    /// Resolves a goal: an object id, a label only one object has, or an object's fields
    /// (label, states, ingredients, container); `GoalNotFoundError` otherwise.
    fn goal_id(&self, goal: &Bound<'_, PyAny>) -> PyResult<u32> {
        let foon = &self.inner;
        let found = if let Ok(label) = goal.cast::<PyString>() {
            foon.goal_by_label(label.to_str()?)
        } else if let Ok(t) = goal.cast::<PyTuple>() {
            foon.goal_by_spec(&spec_of(t.extract::<ObjTuple>()?))
        } else {
            match goal.extract::<i64>() {
                Ok(i) => u32::try_from(i).map_or_else(
                    |_| {
                        Err(foon_core::Error::GoalNotFound {
                            goal: format!("object id {i}"),
                            nearest: Vec::new(),
                        })
                    },
                    |i| foon.goal_by_id(i),
                ),
                Err(_) => Err(foon_core::Error::GoalNotFound {
                    goal: format!("object id {goal}"),
                    nearest: Vec::new(),
                }),
            }
        };
        Ok(found.map_err(PyFoonErr)?)
    }

    fn objects_with_label(&self, label: &str) -> Vec<u32> {
        self.inner.objects_with_label(label)
    }

    fn producers(&self, o: &Bound<'_, PyAny>) -> PyResult<Vec<u32>> {
        let o = object_index(&self.inner, o)?;
        Ok(self.inner.producers(o).to_vec())
    }

    fn consumers(&self, o: &Bound<'_, PyAny>) -> PyResult<Vec<u32>> {
        let o = object_index(&self.inner, o)?;
        Ok(self.inner.consumers(o).to_vec())
    }

    /// Checks the task tree in `tree` (a parsed tree file) against this FOON, in its order.
    fn verify_tree<'py>(
        &self,
        py: Python<'py>,
        tree: &PyFoon,
        kitchen: PyRef<'_, crate::kitchen::PyKitchen>,
        utensils: Vec<String>,
        goal: ObjTuple,
    ) -> PyResult<Bound<'py, PyDict>> {
        let kitchen = std::sync::Arc::clone(&kitchen.inner);
        let goal = spec_of(goal);
        let (foon, tree) = (&self.inner, &tree.inner);
        let r = enter(py, |_| {
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
}

pub(crate) fn check_object(foon: &foon_core::Foon, o: u32) -> PyResult<()> {
    if (o as usize) < foon.object_count() {
        Ok(())
    } else {
        Err(pyo3::exceptions::PyIndexError::new_err(format!(
            "object id {o} is out of range (the FOON has {} objects)",
            foon.object_count()
        )))
    }
}

pub(crate) fn check_fu(foon: &foon_core::Foon, f: u32) -> PyResult<()> {
    if (f as usize) < foon.fu_count() {
        Ok(())
    } else {
        Err(pyo3::exceptions::PyIndexError::new_err(format!(
            "functional unit {f} is out of range (the FOON has {})",
            foon.fu_count()
        )))
    }
}
