//! `foon._foon.KitchenSet` and `plan_query_columns`: the batch of query rows of
//! `foon_core::queries`, its answers handed back as Arrow-shaped byte buffers (validity
//! bitmaps, little-endian values, `int32` offsets) that `foon._arrow` wraps without copying
//! row by row.

use std::sync::{Arc, OnceLock};

use foon_core::cache::{CacheLimits, PreparedCache};
use foon_core::queries::{self, Answer, DeltaPreparation, KitchenSet, QueryRow, RunOptions};
use foon_core::search::batch::BatchOptions;
use foon_core::{Kitchen, MotionRates};
use pyo3::exceptions::PyKeyError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyTuple};

use crate::convert::{path_arg, rate_arg, rate_pairs_arg, str_list_field, threads_arg};
use crate::errors::{PyFoonErr, enter, enter_until};
use crate::foon::PyFoon;
use crate::kitchen::PyKitchen;

/// Named kitchens (immutable; safe to share between threads).
#[pyclass(frozen, module = "foon._foon", name = "KitchenSet")]
pub(crate) struct PyKitchenSet {
    pub(crate) inner: Arc<KitchenSet>,
}

impl PyKitchenSet {
    fn of(s: KitchenSet) -> Self {
        Self { inner: Arc::new(s) }
    }
}

#[pymethods]
impl PyKitchenSet {
    /// A set of (id, kitchen) pairs, in order; a repeated id is a `ValueError`.
    #[new]
    fn new(kitchens: Vec<(String, PyRef<'_, PyKitchen>)>) -> PyResult<Self> {
        let v: Vec<(String, Arc<Kitchen>)> = kitchens
            .into_iter()
            .map(|(id, k)| (id, Arc::clone(&k.inner)))
            .collect();
        Ok(Self::of(KitchenSet::from_kitchens(v).map_err(PyFoonErr)?))
    }

    /// Kitchens made from `base`: (id, add, remove) each.
    #[staticmethod]
    fn with_deltas(
        base: &PyKitchen,
        deltas: Vec<(String, PyRef<'_, PyKitchen>, PyRef<'_, PyKitchen>)>,
    ) -> PyResult<Self> {
        let v: Vec<(String, Kitchen, Kitchen)> = deltas
            .into_iter()
            .map(|(id, a, r)| (id, (*a.inner).clone(), (*r.inner).clone()))
            .collect();
        let s = KitchenSet::with_deltas(&base.inner, v).map_err(PyFoonErr)?;
        Ok(Self::of(s))
    }

    /// Reads a kitchen set: a folder of kitchen files or a JSON file.
    #[staticmethod]
    fn load(py: Python<'_>, path: &Bound<'_, PyAny>) -> PyResult<Self> {
        let path = path_arg("path", path)?;
        Ok(Self::of(enter(py, |_| KitchenSet::load(&path))?))
    }

    /// Parses a kitchen set's JSON text; `path` names the source in messages and is the
    /// folder relative base paths start from.
    #[staticmethod]
    #[pyo3(signature = (text, path = None))]
    fn parse(
        py: Python<'_>,
        text: &Bound<'_, PyAny>,
        path: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let data = crate::convert::text_bytes("text", text)?;
        let path = crate::convert::opt_path_arg("path", path)?;
        Ok(Self::of(enter(py, |_| {
            KitchenSet::parse(&data, path.as_deref())
        })?))
    }

    /// The ids, in order.
    #[getter]
    fn ids(&self) -> Vec<String> {
        self.inner.ids().to_vec()
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    fn __contains__(&self, id: &str) -> bool {
        self.inner.position(id).is_some()
    }

    /// The kitchen of `id` (`KeyError` when there is none).
    fn get(&self, py: Python<'_>, id: &str) -> PyResult<PyKitchen> {
        let i = self
            .inner
            .position(id)
            .ok_or_else(|| PyKeyError::new_err(id.to_owned()))?;
        let e = self.inner.entry(i);
        Ok(PyKitchen {
            inner: enter(py, |_| e.kitchen())?,
        })
    }

    /// Whether the kitchen of `id` is a base plus a delta.
    fn is_delta(&self, id: &str) -> PyResult<bool> {
        let i = self
            .inner
            .position(id)
            .ok_or_else(|| PyKeyError::new_err(id.to_owned()))?;
        Ok(self.inner.entry(i).delta().is_some())
    }

    /// The fingerprint of the whole set: 32 hex digits, the same on every machine.
    #[getter]
    fn fingerprint(&self, py: Python<'_>) -> PyResult<String> {
        let s = &*self.inner;
        Ok(format!("{:032x}", enter(py, |_| s.fingerprint())?))
    }

    /// The set's platform-independent bytes (for pickling).
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        let s = &*self.inner;
        PyBytes::new(py, &py.detach(|| s.to_bytes()))
    }

    /// A set from `to_bytes`; anything else is a `ValueError`.
    #[staticmethod]
    fn from_bytes(py: Python<'_>, data: &[u8]) -> PyResult<Self> {
        Ok(Self::of(enter(py, |_| KitchenSet::from_bytes(data))?))
    }

    fn __repr__(&self) -> String {
        format!("<foon._foon.KitchenSet of {} kitchens>", self.inner.len())
    }
}

/// The process's cache of prepared kitchens, shared by every batch: at most 1,024 kitchens
/// and 256 MiB, 4 bases.
fn cache() -> &'static PreparedCache {
    static CACHE: OnceLock<PreparedCache> = OnceLock::new();
    CACHE.get_or_init(|| {
        PreparedCache::new(CacheLimits {
            max_entries: 1024,
            max_bytes: 256 << 20,
            max_bases: 4,
        })
    })
}

/// The counters of the process's cache of prepared kitchens ([`cache`]): (kitchens kept,
/// their bytes, bases kept, hits, misses, evictions).
#[pyfunction]
pub(crate) fn batch_cache_stats() -> (usize, usize, usize, u64, u64, u64) {
    let s = cache().stats();
    (s.entries, s.bytes, s.bases, s.hits, s.misses, s.evictions)
}

/// Drops every prepared kitchen and base of the process's cache (the counters stay).
#[pyfunction]
pub(crate) fn clear_batch_cache() {
    cache().clear();
}

/// A validity (or boolean) bitmap, least significant bit first.
#[derive(Default)]
struct Bits {
    bytes: Vec<u8>,
    len: usize,
}

impl Bits {
    fn push(&mut self, v: bool) {
        if self.len % 8 == 0 {
            self.bytes.push(0);
        }
        if v {
            self.bytes[self.len / 8] |= 1 << (self.len % 8);
        }
        self.len += 1;
    }
}

/// A nullable fixed-width column: validity and little-endian values.
#[derive(Default)]
struct Fixed {
    valid: Bits,
    values: Vec<u8>,
}

impl Fixed {
    fn u32(&mut self, v: Option<u32>) {
        self.valid.push(v.is_some());
        self.values.extend_from_slice(&v.unwrap_or(0).to_le_bytes());
    }

    fn f64(&mut self, v: Option<f64>) {
        self.valid.push(v.is_some());
        self.values
            .extend_from_slice(&v.unwrap_or(0.0).to_le_bytes());
    }
}

/// A nullable string column: validity, `int32` offsets, UTF-8 data.
struct Strings {
    valid: Bits,
    offsets: Vec<u8>,
    data: Vec<u8>,
}

impl Strings {
    fn new() -> Self {
        Self {
            valid: Bits::default(),
            offsets: 0i32.to_le_bytes().to_vec(),
            data: Vec::new(),
        }
    }

    fn offset(&self) -> i32 {
        i32::try_from(self.data.len()).unwrap_or(i32::MAX)
    }

    fn push(&mut self, s: Option<&str>) {
        self.valid.push(s.is_some());
        self.data.extend_from_slice(s.unwrap_or("").as_bytes());
        let o = self.offset();
        self.offsets.extend_from_slice(&o.to_le_bytes());
    }

    /// A value of a list of strings (no validity).
    fn value(&mut self, s: &str) {
        self.data.extend_from_slice(s.as_bytes());
        let o = self.offset();
        self.offsets.extend_from_slice(&o.to_le_bytes());
    }
}

/// The answers as buffers (see `foon._arrow`).
struct Columns {
    solved: Bits,
    fu_count: Fixed,
    height: Fixed,
    success: Fixed,
    cost: Fixed,
    leaf_count: Fixed,
    unit_offsets: Vec<u8>,
    units: Vec<u8>,
    failure: Strings,
    missing_offsets: Vec<u8>,
    missing: Strings,
    message: Strings,
}

impl Columns {
    fn of(answers: &[Answer]) -> foon_core::Result<Self> {
        let too_large = || foon_core::Error::TooLarge {
            what: "list values in one batch",
            limit: i32::MAX as u64,
        };
        let mut c = Self {
            solved: Bits::default(),
            fu_count: Fixed::default(),
            height: Fixed::default(),
            success: Fixed::default(),
            cost: Fixed::default(),
            leaf_count: Fixed::default(),
            unit_offsets: 0i32.to_le_bytes().to_vec(),
            units: Vec::new(),
            failure: Strings::new(),
            missing_offsets: 0i32.to_le_bytes().to_vec(),
            missing: Strings::new(),
            message: Strings::new(),
        };
        let (mut n_units, mut n_missing) = (0usize, 0usize);
        for a in answers {
            let p = a.solved_plan();
            c.solved.push(p.is_some());
            c.fu_count.u32(p.map(|p| p.units.len() as u32));
            c.height.u32(p.and_then(|p| p.height));
            c.success.f64(p.and_then(|p| p.success));
            c.cost.f64(p.and_then(|p| p.cost));
            c.leaf_count.u32(p.map(|p| p.leaf_inputs as u32));
            if let Some(p) = p {
                for &u in &p.units {
                    c.units.extend_from_slice(&u.to_le_bytes());
                }
                n_units += p.units.len();
            }
            let o = i32::try_from(n_units).map_err(|_| too_large())?;
            c.unit_offsets.extend_from_slice(&o.to_le_bytes());
            c.failure.push(a.failure.map(queries::Failure::as_str));
            for m in &a.missing {
                c.missing.value(m);
            }
            n_missing += a.missing.len();
            let o = i32::try_from(n_missing).map_err(|_| too_large())?;
            c.missing_offsets.extend_from_slice(&o.to_le_bytes());
            c.message.push(a.message.as_deref());
        }
        if c.missing.data.len() > i32::MAX as usize || c.message.data.len() > i32::MAX as usize {
            return Err(too_large());
        }
        Ok(c)
    }
}

/// A string column as Arrow lays it out: the array's offset, its validity bitmap (`None`
/// when no value is null), its offsets (`int32`, or `int64` when `large`) and its UTF-8 data.
type ArrowStrings<'py> = (
    usize,
    Option<Bound<'py, PyBytes>>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    bool,
);

/// The `n` values of a string column given as Arrow buffers (`None` for a null), read
/// without a Python object per value; a `ValueError` when the buffers do not hold `n`
/// strings.
fn arrow_strings<'a>(
    col: &'a ArrowStrings<'_>,
    n: usize,
    name: &str,
) -> PyResult<Vec<Option<&'a str>>> {
    let (offset, valid, offsets, data, large) = col;
    let (valid, offsets, data) = (
        valid.as_ref().map(pyo3::types::PyBytesMethods::as_bytes),
        offsets.as_bytes(),
        data.as_bytes(),
    );
    let bad = |why: &str| {
        pyo3::exceptions::PyValueError::new_err(format!(
            "query column '{name}' is not a valid Arrow string array: {why}"
        ))
    };
    if n == 0 {
        return Ok(Vec::new());
    }
    let w = if *large { 8 } else { 4 };
    let end = offset
        .checked_add(n)
        .ok_or_else(|| bad("offset out of range"))?;
    if offsets.len() < (end + 1) * w {
        return Err(bad("too few offsets"));
    }
    if valid.is_some_and(|v| v.len() * 8 < end) {
        return Err(bad("too short a validity bitmap"));
    }
    let at = |i: usize| -> PyResult<usize> {
        let b = &offsets[i * w..(i + 1) * w];
        let v = if *large {
            i64::from_le_bytes(b.try_into().unwrap_or_default())
        } else {
            i64::from(i32::from_le_bytes(b.try_into().unwrap_or_default()))
        };
        usize::try_from(v).map_err(|_| bad("a negative offset"))
    };
    let mut out = Vec::with_capacity(n);
    let mut lo = at(*offset)?;
    for i in *offset..end {
        let hi = at(i + 1)?;
        if hi < lo || hi > data.len() {
            return Err(bad("offsets out of order or out of range"));
        }
        let null = valid.is_some_and(|v| v[i / 8] >> (i % 8) & 1 == 0);
        out.push(if null {
            None
        } else {
            Some(std::str::from_utf8(&data[lo..hi]).map_err(|_| bad("invalid UTF-8"))?)
        });
        lo = hi;
    }
    Ok(out)
}

/// Answers `n` query rows over `foon` with the kitchens of `kitchens`, on `threads` threads.
/// The columns come as Arrow string buffers ([`ArrowStrings`]; `options` may be absent), read
/// without a Python object per value. `deltas` is how delta kitchens are prepared
/// (`"incremental"`, the default, or `"from-scratch"`). `cancel` (a `threading.Event`)
/// stops the call once set, as Ctrl-C does. Returns the answers as buffers: (rows,
/// solved bitmap, then (validity, values) for `fu_count`, height, success, cost, `leaf_count`;
/// (offsets, values) for units; (validity, offsets, data) for failure; (list offsets, string
/// offsets, data) for missing; (validity, offsets, data) for message).
#[pyfunction]
#[pyo3(signature = (foon, kitchens, n, kitchen_ids, goals, methods, options = None, threads = None, utensils = None, rates = None, default_rate = None, deltas = None, cancel = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn plan_query_columns<'py>(
    py: Python<'py>,
    foon: &PyFoon,
    kitchens: &PyKitchenSet,
    n: usize,
    kitchen_ids: ArrowStrings<'py>,
    goals: ArrowStrings<'py>,
    methods: ArrowStrings<'py>,
    options: Option<ArrowStrings<'py>>,
    threads: Option<&Bound<'py, PyAny>>,
    utensils: Option<&Bound<'py, PyAny>>,
    rates: Option<&Bound<'py, PyAny>>,
    default_rate: Option<&Bound<'py, PyAny>>,
    deltas: Option<&str>,
    cancel: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyTuple>> {
    let kitchen_ids = arrow_strings(&kitchen_ids, n, "kitchen_id")?;
    let goals = arrow_strings(&goals, n, "goal")?;
    let methods = arrow_strings(&methods, n, "method")?;
    let options = options
        .as_ref()
        .map(|o| arrow_strings(o, n, "options"))
        .transpose()?;
    let rows: Vec<QueryRow<'_>> = (0..n)
        .map(|i| QueryRow {
            kitchen: kitchen_ids[i],
            goal: goals[i],
            method: methods[i],
            options: options.as_ref().and_then(|o| o[i]),
        })
        .collect();
    answer_rows(
        py,
        foon,
        kitchens,
        &rows,
        (threads, utensils, rates, default_rate),
        deltas,
        cancel.as_ref(),
    )
}

/// The planning arguments of a batch as Python gives them: threads, utensils, rates and
/// default rate.
type PlanArgs<'a, 'py> = (
    Option<&'a Bound<'py, PyAny>>,
    Option<&'a Bound<'py, PyAny>>,
    Option<&'a Bound<'py, PyAny>>,
    Option<&'a Bound<'py, PyAny>>,
);

/// Answers `rows` (see [`plan_query_columns`]).
fn answer_rows<'py>(
    py: Python<'py>,
    foon: &PyFoon,
    kitchens: &PyKitchenSet,
    rows: &[QueryRow<'_>],
    (threads, utensils, rates, default_rate): PlanArgs<'_, 'py>,
    deltas: Option<&str>,
    cancel: Option<&Py<PyAny>>,
) -> PyResult<Bound<'py, PyTuple>> {
    let n = rows.len();
    let threads = threads_arg(threads)?;
    let deltas = match deltas {
        None | Some("incremental") => DeltaPreparation::Incremental,
        Some("from-scratch") => DeltaPreparation::FromScratch,
        Some(other) => {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "deltas must be 'incremental' or 'from-scratch', not '{other}'"
            )));
        }
    };
    let utensils = match utensils.filter(|u| !u.is_none()) {
        Some(u) => str_list_field("utensils", u)?,
        None => Vec::new(),
    };
    let rates = rates
        .filter(|r| !r.is_none())
        .map(|r| rate_pairs_arg("motions", r))
        .transpose()?
        .map(MotionRates::from_pairs)
        .transpose()
        .map_err(PyFoonErr)?;
    let default_rate = default_rate
        .filter(|r| !r.is_none())
        .map(|r| rate_arg("default_rate", r))
        .transpose()?;
    if let Some(r) = default_rate {
        foon_core::check_rate(None, r).map_err(PyFoonErr)?;
    }
    let batch = BatchOptions::threads(threads);
    batch.workers(n).map_err(PyFoonErr)?;
    let (f, set) = (&*foon.inner, &*kitchens.inner);
    let run = |cancel: crate::errors::Cancel<'_>| {
        let opts = RunOptions {
            batch: batch.with_cancel(cancel),
            utensils: &utensils,
            rates: rates.as_ref(),
            default_rate,
            deltas,
        };
        let answers = queries::run_queries(f, set, rows, cache(), &opts)?;
        Columns::of(&answers)
    };
    // Even on one thread the work runs on a thread of its own (`run_queries` keeps to one),
    // which this one waits on while it looks at the signals (and at `cancel`).
    let c = enter_until(py, cancel, run)?;
    let b = |v: &[u8]| PyBytes::new(py, v).into_any();
    let items: Vec<Bound<'py, PyAny>> = vec![
        n.into_pyobject(py)?.into_any(),
        b(&c.solved.bytes),
        b(&c.fu_count.valid.bytes),
        b(&c.fu_count.values),
        b(&c.height.valid.bytes),
        b(&c.height.values),
        b(&c.success.valid.bytes),
        b(&c.success.values),
        b(&c.cost.valid.bytes),
        b(&c.cost.values),
        b(&c.leaf_count.valid.bytes),
        b(&c.leaf_count.values),
        b(&c.unit_offsets),
        b(&c.units),
        b(&c.failure.valid.bytes),
        b(&c.failure.offsets),
        b(&c.failure.data),
        b(&c.missing_offsets),
        b(&c.missing.offsets),
        b(&c.missing.data),
        b(&c.message.valid.bytes),
        b(&c.message.offsets),
        b(&c.message.data),
    ];
    PyTuple::new(py, items)
}

/// The failure codes of query answers, in documentation order.
#[pyfunction]
pub(crate) fn failure_codes() -> Vec<&'static str> {
    queries::Failure::ALL.iter().map(|f| f.as_str()).collect()
}
