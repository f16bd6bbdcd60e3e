//! `foon-core`: parsing, compact index and task-tree retrieval for FOON (Functional
//! Object-Oriented Networks). Pure Rust, no Python.
//!
//! The modules follow the pipeline: [`model`] (objects given by their text, rate tables) →
//! [`parse`] (every text input) → [`index`] (the immutable [`Foon`]) → [`prepare`] (a kitchen,
//! utensils and rates made ready for one FOON: the container rule, derivability) → [`search`]
//! (task trees for goals) → [`evaluate`] (a tree's metrics and validity, for search and
//! verify) → [`write`](mod@write) (text back out). [`lint`] and [`verify`] check files with parse,
//! prepare and evaluate, not with search; [`error`] is shared by all.
// One `unsafe` block in the crate: mapping an index file read-only (`index::file`).
#![deny(unsafe_code)]

pub mod atomic;
pub mod error;
pub mod evaluate;
pub mod explain;
pub mod find;
mod forward;
mod hint;
pub mod index;
pub mod kitchen;
pub mod levels;
pub mod lint;
pub mod merge;
pub mod model;
pub mod parse;
pub mod prepare;
pub mod progress;
pub mod search;
pub mod synth;
pub mod verify;
pub mod write;

// Many kitchens at once: the shared base, the 64-lane pass, the cache of prepared kitchens.
pub mod cache;
mod incremental;
mod layered;
pub mod multi;
mod relax;
pub use prepare::PreparedBase;

pub use error::{Error, InputKind, Location, Result, Warning, WarningKind};
pub use index::{Foon, NONE, Report, Stats};
pub use kitchen::Kitchen;
pub use model::{MotionRates, ObjectSpec, check_rate};
pub use parse::{
    ParseOptions, load_foon, load_foon_cancellable, parse_foon, parse_foon_cancellable,
};
pub use prepare::{Prepared, Ranks};
pub use search::{
    Compat, Context, Count, Explanation, Method, Plan, Query, SharedObjective, SharedOptions,
};
pub use search::{kbest::KBest, paths::Paths};

// Queries in, results out: named kitchens and batches of query rows.
pub mod queries;
pub use queries::KitchenSet;
