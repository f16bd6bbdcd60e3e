//! `foon._foon`: the thin `PyO3` layer over `foon-core`, cut along the pipeline: arguments in
//! (`convert`), loaders (`loaders`), the parsed FOON (`foon`, with its serialised form in
//! `serial`), planning (`planner`, results in `plan`) and errors out (`errors`, with the one
//! helper every heavy call goes through). No algorithm lives here.
// PyO3 hands arguments over as owned values extracted from Python objects.
#![allow(clippy::needless_pass_by_value)]

mod convert;
mod errors;
mod explain;
mod foon;
mod json;
mod kbest;
mod kitchen;
mod loaders;
mod merge;
mod multi;
mod plan;
mod planner;
mod progress;
mod serial;
mod split;
mod synth;
mod writers;
// Queries in, results out.
mod batch;
mod incremental;

#[pyo3::pymodule]
mod _foon {
    #[pymodule_export]
    use super::explain::{PyExplanation, PyFindIndex, explain, goal_at_level};
    #[pymodule_export]
    use super::foon::PyFoon;
    #[pymodule_export]
    use super::json::{check_json, objects_json, stats_json, verify_json};
    #[pymodule_export]
    use super::kbest::{PyPaths, plan_k};
    #[pymodule_export]
    use super::kitchen::PyKitchen;
    #[pymodule_export]
    use super::merge::{
        fu_sources, fu_support, load_merged, merge_paths, merge_texts, merged_text, parse_merged,
        provenance_text,
    };
    #[pymodule_export]
    use super::plan::PyPlan;
    #[pymodule_export]
    use super::planner::PyPlanner;
    #[pymodule_export]
    use super::writers::{
        PyTreeWriter, explanation, formats, split_pddl, write_comparison, write_foon, write_tree,
    };

    #[pymodule_export]
    use super::loaders::{
        check, check_rates, load_objects, load_rates, load_utensils, max_threads, methods,
        object_fields, object_fields_of_mapping, object_identity, object_text, parse_objects,
        parse_rates, parse_utensils,
    };

    #[pymodule_export]
    use super::split::{PySplit, load_overrides, parse_overrides, plan_split};
    #[pymodule_export]
    use super::synth::{
        synth_goals, synth_kitchen, synth_motions, synth_side, synth_text, synth_write,
    };

    #[pymodule_export]
    use super::multi::{PyMatchedKitchens, derivable_many, match_kitchens};

    #[pymodule_export]
    use super::incremental::planner_with_changes;

    #[pymodule_export]
    use super::errors::{FoonError, GoalNotFoundError, MissingRateError, OutputError, ParseError};

    #[pymodule_export]
    use super::batch::{
        PyKitchenSet, batch_cache_stats, clear_batch_cache, failure_codes, plan_query_columns,
    };

    #[pymodule_init]
    fn init(m: &pyo3::Bound<'_, pyo3::types::PyModule>) -> pyo3::PyResult<()> {
        use pyo3::types::PyModuleMethods;
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        m.add("MAX_PICTURE_NODES", foon_core::write::render::MAX_NODES)?;
        Ok(())
    }
}
