//! `foon._foon.derivable_many`: derivability (or ranks) of goals in many kitchens at once,
//! from the core's 64-kitchen pass (`foon_core::multi`); `foon._foon.match_kitchens`: the
//! kitchens matched to a FOON's objects once, so that what is timed or repeated after it is
//! the preparation alone.

use foon_core::PreparedBase;
use foon_core::multi;
use foon_core::search::batch::BatchOptions;
use pyo3::prelude::*;

use crate::convert::{str_list_field, threads_arg};
use crate::errors::enter;
use crate::foon::{PyFoon, check_object};
use crate::kitchen::PyKitchen;

/// For each kitchen (matched at identity `level`), for each goal (object ids): whether the
/// goal is derivable there (`ranks=False`), or its rank, `None` when it is not derivable.
/// `mode`: `"lanes"` (the 64-kitchen pass), or, to compare with it, `"separate"` (each
/// kitchen prepared from scratch, `Prepared::with_objects`, and its ranks computed) or
/// `"shared"` (one base, each kitchen prepared on it, `Prepared::with_base`, and its ranks).
/// Kitchens matched to one FOON's objects at one level (opaque; for `derivable_many`).
#[pyclass(frozen, module = "foon._foon", name = "MatchedKitchens")]
pub(crate) struct PyMatchedKitchens {
    /// The FOON's content fingerprint, the level and each kitchen's object ids.
    foon: [u8; 16],
    level: u8,
    ids: Vec<Vec<u32>>,
}

#[pymethods]
impl PyMatchedKitchens {
    fn __len__(&self) -> usize {
        self.ids.len()
    }

    #[getter]
    fn level(&self) -> u8 {
        self.level
    }
}

/// Matches each kitchen to `foon`'s objects at `level` (in the core, off the GIL).
#[pyfunction]
#[pyo3(signature = (foon, kitchens, level = 3))]
pub(crate) fn match_kitchens(
    py: Python<'_>,
    foon: &PyFoon,
    kitchens: Vec<PyRef<'_, PyKitchen>>,
    level: u8,
) -> PyResult<PyMatchedKitchens> {
    let f = &*foon.inner;
    let ks: Vec<_> = kitchens
        .iter()
        .map(|k| std::sync::Arc::clone(&k.inner))
        .collect();
    let ids = enter(py, |_| {
        let refs: Vec<&foon_core::Kitchen> = ks.iter().map(|k| &**k).collect();
        foon_core::Kitchen::match_many(&refs, f, level)
    })?;
    Ok(PyMatchedKitchens {
        foon: f.fingerprint(),
        level,
        ids,
    })
}

#[pyfunction]
#[pyo3(signature = (foon, kitchens, goals, utensils, level = 3, ranks = false, threads = None, mode = "lanes"))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn derivable_many(
    py: Python<'_>,
    foon: &PyFoon,
    kitchens: &Bound<'_, PyAny>,
    goals: Vec<u32>,
    utensils: &Bound<'_, PyAny>,
    level: u8,
    ranks: bool,
    threads: Option<&Bound<'_, PyAny>>,
    mode: &str,
) -> PyResult<Py<PyAny>> {
    if !matches!(mode, "lanes" | "separate" | "shared") {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "mode must be 'lanes', 'separate' or 'shared', not '{mode}'"
        )));
    }
    let utensils = str_list_field("utensils", utensils)?;
    let threads = threads_arg(threads)?;
    let f = &*foon.inner;
    for &g in &goals {
        check_object(f, g)?;
    }
    // Kitchens, or kitchens already matched (to this FOON, at this level).
    let matched = kitchens.cast::<PyMatchedKitchens>().ok().map(Bound::get);
    let ks: Vec<_> = match matched {
        Some(m) => {
            if m.foon != f.fingerprint() || m.level != level {
                return Err(pyo3::exceptions::PyValueError::new_err(
                    "the kitchens were matched to another FOON or at another level",
                ));
            }
            Vec::new()
        }
        None => kitchens
            .extract::<Vec<PyRef<'_, PyKitchen>>>()?
            .iter()
            .map(|k| std::sync::Arc::clone(&k.inner))
            .collect(),
    };
    let goals_ref = &goals;
    let out = enter(py, |cancel| {
        let owned;
        let ids = if let Some(m) = matched {
            &m.ids
        } else {
            let refs: Vec<&foon_core::Kitchen> = ks.iter().map(|k| &**k).collect();
            owned = foon_core::Kitchen::match_many(&refs, f, level)?;
            &owned
        };
        let refs: Vec<&[u32]> = ids.iter().map(Vec::as_slice).collect();
        if mode != "lanes" {
            let base = std::sync::Arc::new(PreparedBase::new(f, &utensils, None, None)?);
            let mut rows = Vec::with_capacity(refs.len());
            for k in &refs {
                if cancel() {
                    return Err(foon_core::Error::Cancelled);
                }
                let p = if mode == "separate" {
                    foon_core::Prepared::with_objects(f, k, &utensils, None, None)?
                } else {
                    foon_core::Prepared::with_base(f, std::sync::Arc::clone(&base), k)?
                };
                let ctx = foon_core::Context::with(f, &p)?;
                let r = ctx.ranks();
                rows.push(goals_ref.iter().map(|&g| r.rank(g)).collect::<Vec<_>>());
            }
            return Ok(if ranks {
                Err(rows)
            } else {
                Ok(rows
                    .into_iter()
                    .map(|row| row.into_iter().map(|r| r.is_some()).collect())
                    .collect())
            });
        }
        let base = PreparedBase::new(f, &utensils, None, None)?;
        let opts = BatchOptions::threads(threads).with_cancel(cancel);
        if ranks {
            let r = multi::ranks_many(f, &base, &refs, &opts)?;
            Ok(Err((0..refs.len())
                .map(|k| goals_ref.iter().map(|&g| r.rank(k, g)).collect::<Vec<_>>())
                .collect::<Vec<_>>()))
        } else {
            let d = multi::derivable_many(f, &base, &refs, &opts)?;
            Ok(Ok((0..refs.len())
                .map(|k| {
                    goals_ref
                        .iter()
                        .map(|&g| d.is_derivable(k, g))
                        .collect::<Vec<_>>()
                })
                .collect::<Vec<_>>()))
        }
    })?;
    Ok(match out {
        Ok(d) => d.into_pyobject(py)?.into_any().unbind(),
        Err(r) => r.into_pyobject(py)?.into_any().unbind(),
    })
}
