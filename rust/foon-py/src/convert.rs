//! Arguments in, values out: Python values become typed native values here, with errors that
//! name the argument and the expected type.

use std::path::PathBuf;

use foon_core::ObjectSpec;
use pyo3::exceptions::{PyIndexError, PyOverflowError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyString, PyTuple};

use crate::errors::PyFoonErr;

/// An object as Python sees it: (label, states, ingredients, container).
pub(crate) type ObjTuple = (String, Vec<String>, Vec<String>, Option<String>);

/// A location as Python sees it: (path, line, column).
pub(crate) fn location(at: &foon_core::Location) -> (Option<String>, u64, u32) {
    (
        at.path.as_ref().map(|p| p.display().to_string()),
        at.line,
        at.column,
    )
}

/// The name of `v`'s type, for messages.
pub(crate) fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type()
        .name()
        .map_or_else(|_| "object".to_owned(), |n| n.to_string())
}

/// A path argument: `str`, `bytes` or any `os.PathLike`.
pub(crate) fn path_arg(name: &str, v: &Bound<'_, PyAny>) -> PyResult<PathBuf> {
    let py = v.py();
    let fspath = py.import("os")?.getattr("fspath")?;
    let Ok(p) = fspath.call1((v,)) else {
        return Err(PyTypeError::new_err(format!(
            "{name} must be a path (str, bytes or os.PathLike), not {}",
            type_name(v)
        )));
    };
    if let Ok(b) = p.cast::<PyBytes>() {
        return Ok(bytes_path(b.as_bytes()));
    }
    p.extract::<PathBuf>()
}

#[cfg(unix)]
fn bytes_path(b: &[u8]) -> PathBuf {
    use std::os::unix::ffi::OsStrExt;
    PathBuf::from(std::ffi::OsStr::from_bytes(b))
}

#[cfg(not(unix))]
fn bytes_path(b: &[u8]) -> PathBuf {
    PathBuf::from(String::from_utf8_lossy(b).into_owned())
}

/// An optional path argument (`None` stays `None`).
pub(crate) fn opt_path_arg(name: &str, v: Option<&Bound<'_, PyAny>>) -> PyResult<Option<PathBuf>> {
    match v {
        Some(v) if !v.is_none() => path_arg(name, v).map(Some),
        _ => Ok(None),
    }
}

/// Text given as `str` or `bytes`.
pub(crate) fn text_bytes(name: &str, text: &Bound<'_, PyAny>) -> PyResult<Vec<u8>> {
    if let Ok(s) = text.cast::<PyString>() {
        Ok(s.to_str()?.as_bytes().to_vec())
    } else if let Ok(b) = text.cast::<PyBytes>() {
        Ok(b.as_bytes().to_vec())
    } else {
        Err(PyTypeError::new_err(format!(
            "{name} must be str or bytes, not {}",
            type_name(text)
        )))
    }
}

/// An index into a FOON's objects or units: an `int` in `0..len`, else `IndexError` (for a
/// negative or huge `int` too) or `TypeError`.
pub(crate) fn index_arg(v: &Bound<'_, PyAny>, what: &str, len: usize, unit: &str) -> PyResult<u32> {
    if v.is_instance_of::<PyBool>() {
        return Err(PyTypeError::new_err(format!(
            "{what} must be an int, not bool"
        )));
    }
    let out_of_range = || {
        PyIndexError::new_err(format!(
            "{what} {v} is out of range (the FOON has {len}{unit})"
        ))
    };
    match v.extract::<i64>() {
        Ok(i) if i >= 0 && (i as u64) < len as u64 => Ok(i as u32),
        Ok(_) => Err(out_of_range()),
        Err(e) if e.is_instance_of::<PyOverflowError>(v.py()) => Err(out_of_range()),
        Err(_) => Err(PyTypeError::new_err(format!(
            "{what} must be an int, not {}",
            type_name(v)
        ))),
    }
}

pub(crate) fn object_index(foon: &foon_core::Foon, v: &Bound<'_, PyAny>) -> PyResult<u32> {
    index_arg(v, "object id", foon.object_count(), " objects")
}

pub(crate) fn fu_index(foon: &foon_core::Foon, v: &Bound<'_, PyAny>) -> PyResult<u32> {
    index_arg(v, "functional unit", foon.fu_count(), "")
}

/// A count or a limit (`k`, `node_limit`, `max_trees`, ...): an `int` at least `least`, or
/// `None` where the argument may be left out. An `int` too large for the native type is its
/// largest value (no count or limit reaches it); a `bool` is not a count.
pub(crate) fn count_arg<T: TryFrom<u64> + Bounded>(
    name: &str,
    v: Option<&Bound<'_, PyAny>>,
    least: u64,
) -> PyResult<Option<T>> {
    match v.filter(|v| !v.is_none()) {
        None => Ok(None),
        Some(v) => count(name, v, least, "an int or None").map(Some),
    }
}

/// A count that may not be left out ([`count_arg`]).
pub(crate) fn required_count<T: TryFrom<u64> + Bounded>(
    name: &str,
    v: &Bound<'_, PyAny>,
    least: u64,
) -> PyResult<T> {
    count(name, v, least, "an int")
}

fn count<T: TryFrom<u64> + Bounded>(
    name: &str,
    v: &Bound<'_, PyAny>,
    least: u64,
    expected: &str,
) -> PyResult<T> {
    let wrong_type =
        || PyTypeError::new_err(format!("{name} must be {expected}, not {}", type_name(v)));
    if v.is_instance_of::<PyBool>() {
        return Err(wrong_type());
    }
    let too_small = || {
        PyValueError::new_err(if least == 0 {
            format!("{name} must not be negative, not {v}")
        } else {
            format!("{name} must be at least {least}, not {v}")
        })
    };
    let n = match v.extract::<i64>() {
        Ok(n) => u64::try_from(n).map_err(|_| too_small())?,
        Err(e) if e.is_instance_of::<PyOverflowError>(v.py()) => {
            if v.lt(0)? {
                return Err(too_small());
            }
            u64::MAX
        }
        Err(_) => return Err(wrong_type()),
    };
    if n < least {
        return Err(too_small());
    }
    Ok(T::try_from(n).unwrap_or(T::MAX))
}

/// The largest value of a native count type ([`count_arg`]).
pub(crate) trait Bounded {
    const MAX: Self;
}

impl Bounded for u64 {
    const MAX: Self = u64::MAX;
}

impl Bounded for usize {
    const MAX: Self = usize::MAX;
}

impl Bounded for u32 {
    const MAX: Self = u32::MAX;
}

/// The `threads` argument: `None` or a positive `int`. Zero is refused by the core's batch
/// options; a negative or huge `int` here, with the same kind of message.
pub(crate) fn threads_arg(v: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    let Some(v) = v.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    if v.is_instance_of::<PyBool>() {
        return Err(PyTypeError::new_err(
            "threads must be an int or None, not bool",
        ));
    }
    match v.extract::<i64>() {
        Ok(n) if n < 0 => Err(PyValueError::new_err(format!(
            "threads must be at least 1, not {n}"
        ))),
        Ok(n) => Ok(Some(usize::try_from(n).unwrap_or(usize::MAX))),
        Err(e) if e.is_instance_of::<PyOverflowError>(v.py()) => {
            Err(PyOverflowError::new_err(format!(
                "threads={v} is too large (at most {}; threads are capped to the available \
                 parallelism, {} here)",
                i64::MAX,
                foon_core::search::batch::max_threads()
            )))
        }
        Err(_) => Err(PyTypeError::new_err(format!(
            "threads must be an int or None, not {}",
            type_name(v)
        ))),
    }
}

/// A `str` argument or field (`TypeError` naming it otherwise).
pub(crate) fn str_field(field: &str, v: &Bound<'_, PyAny>) -> PyResult<String> {
    match v.cast::<PyString>() {
        Ok(s) => Ok(s.to_str()?.to_owned()),
        Err(_) => Err(PyTypeError::new_err(format!(
            "{field} must be a str, not {}",
            type_name(v)
        ))),
    }
}

/// A list-of-strings field of an object: any sequence (or iterable) of `str`, but not a `str`
/// itself (which would be read as its characters).
pub(crate) fn str_list_field(field: &str, v: &Bound<'_, PyAny>) -> PyResult<Vec<String>> {
    let expected = || format!("{field} must be a sequence of str");
    if v.is_instance_of::<PyString>() || v.is_instance_of::<PyBytes>() {
        return Err(PyTypeError::new_err(format!(
            "{}, not a single {} (write [{}])",
            expected(),
            type_name(v),
            v.repr()?
        )));
    }
    let is_mapping = v
        .py()
        .import("collections.abc")?
        .getattr("Mapping")
        .and_then(|m| v.is_instance(&m))
        .unwrap_or(false);
    let iter = if is_mapping { None } else { v.try_iter().ok() };
    let Some(iter) = iter else {
        return Err(PyTypeError::new_err(format!(
            "{}, not {}",
            expected(),
            type_name(v)
        )));
    };
    let mut out = Vec::new();
    for (i, item) in iter.enumerate() {
        let item = item?;
        match item.cast::<PyString>() {
            Ok(s) => out.push(s.to_str()?.to_owned()),
            Err(_) => {
                return Err(PyTypeError::new_err(format!(
                    "{field}[{i}] must be a str, not {}",
                    type_name(&item)
                )));
            }
        }
    }
    Ok(out)
}

/// Checks a spec the way the core checks the objects of kitchen and goal files.
fn checked(spec: ObjectSpec) -> foon_core::Result<ObjectSpec> {
    ObjectSpec::new(spec.label, spec.states, spec.ingredients, spec.container)
}

/// An object from its four fields, each of the expected type (`TypeError` naming the field
/// otherwise), checked by the core's rule.
pub(crate) fn spec_arg(
    label: &Bound<'_, PyAny>,
    states: &Bound<'_, PyAny>,
    ingredients: &Bound<'_, PyAny>,
    container: &Bound<'_, PyAny>,
) -> PyResult<ObjectSpec> {
    let spec = ObjectSpec {
        label: str_field("label", label)?,
        states: str_list_field("states", states)?,
        ingredients: str_list_field("ingredients", ingredients)?,
        container: if container.is_none() {
            None
        } else {
            Some(str_field("container", container).map_err(|_| {
                PyTypeError::new_err(format!(
                    "container must be a str or None, not {}",
                    type_name(container)
                ))
            })?)
        },
    };
    Ok(checked(spec).map_err(PyFoonErr)?)
}

/// The object fields of a mapping shaped like a kitchen or goal JSON object.
pub(crate) fn spec_of_mapping(d: &Bound<'_, PyAny>) -> PyResult<ObjectSpec> {
    const FIELDS: [&str; 4] = ["label", "states", "ingredients", "container"];
    let py = d.py();
    let mapping = py.import("collections.abc")?.getattr("Mapping")?;
    if !d.is_instance(&mapping)? {
        return Err(PyTypeError::new_err(format!(
            "an object must be a mapping with the fields label, states, ingredients and \
             container, not {}",
            type_name(d)
        )));
    }
    for key in d.try_iter()? {
        let key = key?;
        let known = key
            .cast::<PyString>()
            .ok()
            .and_then(|k| k.to_str().ok().map(|k| FIELDS.contains(&k)))
            .unwrap_or(false);
        if !known {
            return Err(PyValueError::new_err(format!(
                "unknown field {} in an object (expected label, states, ingredients, container)",
                key.repr()?
            )));
        }
    }
    let get = |k: &str| -> PyResult<Option<Bound<'_, PyAny>>> {
        if d.contains(k)? {
            Ok(Some(d.get_item(k)?))
        } else {
            Ok(None)
        }
    };
    let Some(label) = get("label")? else {
        return Err(PyValueError::new_err(format!(
            "an object needs a 'label': {}",
            d.repr()?
        )));
    };
    let empty = PyTuple::empty(py).into_any();
    let none = py.None().into_bound(py);
    let states = get("states")?.unwrap_or_else(|| empty.clone());
    let ingredients = get("ingredients")?.unwrap_or_else(|| empty.clone());
    let container = get("container")?.unwrap_or(none);
    spec_arg(&label, &states, &ingredients, &container)
}

/// A spec as Python's `Object` fields: (label, states tuple, ingredients tuple, container).
pub(crate) fn spec_fields(py: Python<'_>, s: ObjectSpec) -> PyResult<Bound<'_, PyTuple>> {
    let states = PyTuple::new(py, s.states)?;
    let ingredients = PyTuple::new(py, s.ingredients)?;
    (s.label, states, ingredients, s.container).into_pyobject(py)
}

/// A list of object tuples as specs (the Python layer gives checked objects).
pub(crate) fn specs_of(items: Vec<ObjTuple>) -> Vec<ObjectSpec> {
    items.into_iter().map(spec_of).collect()
}

pub(crate) fn spec_of(t: ObjTuple) -> ObjectSpec {
    ObjectSpec {
        label: t.0,
        states: t.1,
        ingredients: t.2,
        container: t.3,
    }
}

pub(crate) fn tuple_of(s: ObjectSpec) -> ObjTuple {
    (s.label, s.states, s.ingredients, s.container)
}

/// A rate argument: a real number (`int` or `float`, not `bool` nor `str`).
pub(crate) fn rate_arg(name: &str, v: &Bound<'_, PyAny>) -> PyResult<f64> {
    let ok = !v.is_instance_of::<PyBool>()
        && (v.is_instance_of::<pyo3::types::PyFloat>() || v.is_instance_of::<pyo3::types::PyInt>());
    if !ok {
        return Err(PyTypeError::new_err(format!(
            "{name} must be a number between 0 and 1, not {}",
            type_name(v)
        )));
    }
    v.extract::<f64>()
}

/// Motion rates given as (motion, rate) pairs: each motion a `str`, each rate a number.
pub(crate) fn rate_pairs_arg(name: &str, v: &Bound<'_, PyAny>) -> PyResult<Vec<(String, f64)>> {
    let Ok(iter) = v.try_iter() else {
        return Err(PyTypeError::new_err(format!(
            "{name} must be (motion, rate) pairs, not {}",
            type_name(v)
        )));
    };
    let mut out = Vec::new();
    for item in iter {
        let item = item?;
        let pair: (Bound<'_, PyAny>, Bound<'_, PyAny>) = item.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "{name} must be (motion, rate) pairs, not {}",
                type_name(&item)
            ))
        })?;
        let motion = str_field(&format!("a motion of {name}"), &pair.0)?;
        let rate = rate_arg(&format!("the rate of '{motion}' in {name}"), &pair.1)?;
        out.push((motion, rate));
    }
    Ok(out)
}
