//! `foon._foon.Kitchen`: a handle on the core's [`Kitchen`] (read, matched and compared in
//! Rust; Python sees its items only when it asks for them).

use std::sync::Arc;

use foon_core::Kitchen;
use foon_core::write::json;
use pyo3::exceptions::PyIndexError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::convert::{ObjTuple, opt_path_arg, path_arg, spec_of, text_bytes, tuple_of};
use crate::errors::{PyFoonErr, enter};

/// A kitchen: a set of object identities in the order of first appearance (immutable; safe
/// to share between threads).
#[pyclass(frozen, module = "foon._foon", name = "Kitchen")]
pub(crate) struct PyKitchen {
    pub(crate) inner: Arc<Kitchen>,
}

impl PyKitchen {
    pub(crate) fn of(k: Kitchen) -> Self {
        Self { inner: Arc::new(k) }
    }
}

#[pymethods]
impl PyKitchen {
    /// A kitchen of object tuples (checked by the Python layer), in order, repeats once.
    #[new]
    #[pyo3(signature = (items = Vec::new()))]
    fn new(items: Vec<ObjTuple>) -> PyResult<Self> {
        let specs: Vec<_> = items.into_iter().map(spec_of).collect();
        Ok(Self::of(Kitchen::from_specs(&specs).map_err(PyFoonErr)?))
    }

    /// Reads a kitchen file (a JSON list of objects or FOON object blocks).
    #[staticmethod]
    fn load(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<Self> {
        let path = path_arg("path", path)?;
        Ok(Self::of(enter(py, |_| Kitchen::load(&path))?))
    }

    /// Parses a kitchen from text; `path` only names the source in messages.
    #[staticmethod]
    #[pyo3(signature = (text, path = None))]
    fn parse(
        py: Python<'_>,
        text: &Bound<'_, PyAny>,
        path: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let data = text_bytes("text", text)?;
        let path = opt_path_arg("path", path)?;
        Ok(Self::of(enter(py, |_| {
            Kitchen::parse(&data, path.as_deref())
        })?))
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    /// Item `i` as (label, states, ingredients, container), as first written.
    fn get(&self, i: usize) -> PyResult<ObjTuple> {
        self.inner
            .get(i)
            .map(tuple_of)
            .ok_or_else(|| PyIndexError::new_err(format!("kitchen item {i} out of range")))
    }

    /// Items `start..stop` (clamped to the kitchen), as `get` gives them.
    fn slice(&self, start: usize, stop: usize) -> Vec<ObjTuple> {
        let stop = stop.min(self.inner.len());
        (start.min(stop)..stop)
            .filter_map(|i| self.inner.get(i))
            .map(tuple_of)
            .collect()
    }

    /// Every item, as `get` gives them.
    fn tuples(&self) -> Vec<ObjTuple> {
        self.inner.iter().map(tuple_of).collect()
    }

    /// Whether an item has this object's identity.
    fn contains(&self, o: ObjTuple) -> bool {
        self.inner.contains(&spec_of(o))
    }

    /// Whether both kitchens have the same set of identities (in any order).
    fn equals(&self, py: Python<'_>, other: &Self) -> bool {
        let (a, b) = (&*self.inner, &*other.inner);
        py.detach(|| a == b)
    }

    /// The fingerprint of the set of identities: 32 hex digits, the same on every machine
    /// and for every order of the items.
    #[getter]
    fn fingerprint(&self, py: Python<'_>) -> String {
        let k = &*self.inner;
        format!("{:032x}", py.detach(|| k.fingerprint()))
    }

    /// The items of this kitchen that are not items of `drop`, in order.
    fn without(&self, py: Python<'_>, drop: &Self) -> Self {
        let (a, b) = (&*self.inner, &*drop.inner);
        Self::of(py.detach(|| a.without(b)))
    }

    /// The items of this kitchen, then those of `add` not in it.
    fn with_items(&self, py: Python<'_>, add: &Self) -> PyResult<Self> {
        let (a, b) = (&*self.inner, &*add.inner);
        Ok(Self::of(enter(py, |_| a.with(b))?))
    }

    /// This kitchen after a chain of `(add, remove)` steps, each `without(remove)` then
    /// `with_items(add)`, in one pass (`foon_core::Kitchen::with_steps`).
    fn with_steps(
        &self,
        py: Python<'_>,
        steps: Vec<(PyRef<'_, Self>, PyRef<'_, Self>)>,
    ) -> PyResult<Self> {
        let k = &*self.inner;
        let owned: Vec<(Arc<Kitchen>, Arc<Kitchen>)> = steps
            .iter()
            .map(|(a, r)| (Arc::clone(&a.inner), Arc::clone(&r.inner)))
            .collect();
        Ok(Self::of(enter(py, |_| {
            let refs: Vec<(&Kitchen, &Kitchen)> = owned.iter().map(|(a, r)| (&**a, &**r)).collect();
            k.with_steps(&refs)
        })?))
    }

    /// The kitchen's compact, platform-independent bytes (for pickling).
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        let k = &*self.inner;
        PyBytes::new(py, &py.detach(|| k.to_bytes()))
    }

    /// A kitchen from `to_bytes`; anything else is a `ValueError`.
    #[staticmethod]
    fn from_bytes(py: Python<'_>, data: &[u8]) -> PyResult<Self> {
        Ok(Self::of(enter(py, |_| Kitchen::from_bytes(data))?))
    }

    /// The kitchen as a JSON list of objects (the kitchen file shape).
    fn to_json(&self, py: Python<'_>) -> PyResult<String> {
        let k = &*self.inner;
        enter(py, |_| json::objects_json(&k.specs()))
    }

    /// Heap bytes of the kitchen's columns and string table.
    fn heap_bytes(&self) -> usize {
        self.inner.heap_bytes()
    }

    fn __repr__(&self) -> String {
        format!("<foon._foon.Kitchen of {} items>", self.inner.len())
    }
}
