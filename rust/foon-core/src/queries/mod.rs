//! Queries in, results out: many (kitchen, goal, method) questions over one FOON in one call.
//!
//! - A [`KitchenSet`] names the kitchens; a [`QueryRow`] names a kitchen, a goal (a JSON
//!   object or a label, resolved by the rules of `foon plan --goal/--label`), a method (any
//!   name of [`Method`]) and options (a JSON object, see [`RowOptions`]).
//! - [`run_queries`] checks every row first (each distinct goal and options text read once):
//!   a row it cannot plan (unknown kitchen or method, bad options or goal) becomes an
//!   [`Answer`] with its [`Failure`], never an error of the batch. The other rows are grouped
//!   by (kitchen, level, default rate); the groups are prepared a wave at a time
//!   ([`wave_size`], at most 64) by [`prepare_wave`] (through the [`PreparedCache`]: the
//!   kitchens the cache lacks in one 64-lane pass of [`prepare_many`], a kitchen given as a
//!   base plus a delta from its base kitchen's preparation, [`DeltaPreparation`]), then
//!   planned on the crate's batch thread pool (the policy of [`crate::search::batch`]:
//!   threads, `FOON_THREADS`, cancel): a worker takes a group, derives its delta kitchen and
//!   plans its first row of each query, then every other row of the wave runs on every
//!   worker. Only one wave's prepared kitchens are held at a time.
//! - Answers are in row order and identical for every thread count (a `time_limit` aside).
//!   The only errors of the batch are a cancelled batch and a bad thread count.
//!
//! The formats (kitchen sets, query rows, options, failure codes) are in `docs/BATCH.md`.

mod kitchens;

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

use rustc_hash::FxHashMap;

pub use kitchens::{Delta, Entry, KitchenSet};

use crate::cache::{CacheKey, PreparedCache};
use crate::error::{Error, InputKind, Result};
use crate::index::Foon;
use crate::kitchen::Kitchen;
use crate::model::{MotionRates, ObjectSpec, check_rate};
use crate::multi::prepare_many;
use crate::prepare::{Prepared, PreparedBase};
use crate::search::batch::{BatchOptions, in_pool};
use crate::search::{Compat, Context, Count, Method, Plan, Query, SharedObjective, SharedOptions};

/// How many kitchens are prepared and held at once at most (one lane pass of
/// [`prepare_many`]).
pub const WAVE: usize = 64;

/// The bytes a wave's prepared kitchens may take, about: a wave holds fewer than [`WAVE`]
/// kitchens when the FOON is large ([`wave_size`]).
pub const WAVE_BYTES: usize = 256 << 20;

/// How many kitchens a wave holds over `foon`: [`WAVE`], or fewer so that their flags and
/// ranks (about 8 bytes per object each) stay within [`WAVE_BYTES`]; at least 1.
pub fn wave_size(foon: &Foon) -> usize {
    (WAVE_BYTES / (8 * foon.object_count()).max(1)).clamp(1, WAVE)
}

/// Why a query row has no tree (the codes of `docs/BATCH.md`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Failure {
    GoalNotFound,
    GoalAmbiguous,
    BadGoal,
    UnknownKitchen,
    UnknownMethod,
    BadOption,
    NotDerivable,
    Cycle,
    Unresolved,
    MissingRate,
    Error,
}

impl Failure {
    pub const ALL: [Failure; 11] = [
        Self::GoalNotFound,
        Self::GoalAmbiguous,
        Self::BadGoal,
        Self::UnknownKitchen,
        Self::UnknownMethod,
        Self::BadOption,
        Self::NotDerivable,
        Self::Cycle,
        Self::Unresolved,
        Self::MissingRate,
        Self::Error,
    ];

    /// The code results carry.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::GoalNotFound => "goal-not-found",
            Self::GoalAmbiguous => "goal-ambiguous",
            Self::BadGoal => "bad-goal",
            Self::UnknownKitchen => "unknown-kitchen",
            Self::UnknownMethod => "unknown-method",
            Self::BadOption => "bad-option",
            Self::NotDerivable => "not-derivable",
            Self::Cycle => "cycle",
            Self::Unresolved => "unresolved",
            Self::MissingRate => "missing-rate",
            Self::Error => "error",
        }
    }

    /// Whether the answer keeps the error's text as its message.
    pub fn has_message(self) -> bool {
        matches!(
            self,
            Self::BadGoal | Self::BadOption | Self::Error | Self::MissingRate
        )
    }
}

/// One question: the kitchen's id, the goal (a JSON object or a label), the method's name,
/// and the options (`None`, empty, `null`, or a JSON object). `None` for a field is a bad row.
#[derive(Debug, Clone, Copy, Default)]
pub struct QueryRow<'a> {
    pub kitchen: Option<&'a str>,
    pub goal: Option<&'a str>,
    pub method: Option<&'a str>,
    pub options: Option<&'a str>,
}

/// The options of one row (the same meanings as `Foon.plan`'s arguments).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RowOptions {
    pub compat: Compat,
    pub count: Count,
    pub shared: SharedOptions,
    /// The identity level (1, 2 or 3).
    pub level: u8,
    /// A default rate for this row, replacing the batch's.
    pub default_rate: Option<f64>,
}

impl Default for RowOptions {
    fn default() -> Self {
        Self {
            compat: Compat::Sound,
            count: Count::Nodes,
            shared: SharedOptions::default(),
            level: 3,
            default_rate: None,
        }
    }
}

/// The option names a row may give.
pub const OPTION_NAMES: [&str; 7] = [
    "compat",
    "count",
    "objective",
    "level",
    "node_limit",
    "time_limit",
    "default_rate",
];

impl RowOptions {
    /// Reads a row's options: `None`, empty or `null` for none, else a JSON object with any
    /// of [`OPTION_NAMES`] (each may be `null` for its default). `compat`: `"course"` or
    /// `"sound"`; `count`: `"nodes"` or `"ingredients"`; `objective`: `"units"` or
    /// `"success"`; `level`: 1, 2 or 3; `node_limit`: a non-negative integer; `time_limit`:
    /// a non-negative number of seconds; `default_rate`: a rate in [0, 1]. The objective and
    /// limits are for `optimal-shared` only (checked against `method`).
    pub fn parse(text: Option<&str>, method: Method) -> Result<Self> {
        let mut o = Self::default();
        let Some(text) = text
            .map(str::trim)
            .filter(|t| !t.is_empty() && *t != "null")
        else {
            return Ok(o);
        };
        let bad = |m: String| Error::Invalid(m);
        let v: serde_json::Value = serde_json::from_str(text)
            .map_err(|e| bad(format!("options are not valid JSON: {e}")))?;
        let serde_json::Value::Object(map) = v else {
            return Err(bad(format!("options must be a JSON object, not {text}")));
        };
        let string = |k: &str, v: &serde_json::Value| {
            v.as_str()
                .map(str::to_owned)
                .ok_or_else(|| bad(format!("option '{k}' must be a string, not {v}")))
        };
        for (k, v) in &map {
            if v.is_null() {
                if !OPTION_NAMES.contains(&k.as_str()) {
                    return Err(unknown_option(k));
                }
                continue;
            }
            match k.as_str() {
                "compat" => o.compat = string(k, v)?.parse()?,
                "count" => o.count = string(k, v)?.parse()?,
                "objective" => o.shared.objective = string(k, v)?.parse::<SharedObjective>()?,
                "level" => {
                    o.level = match v.as_u64() {
                        Some(l @ 1..=3) => l as u8,
                        _ => return Err(bad(format!("option 'level' must be 1, 2 or 3, not {v}"))),
                    }
                }
                "node_limit" => {
                    o.shared.node_limit = Some(v.as_u64().ok_or_else(|| {
                        bad(format!(
                            "option 'node_limit' must be an integer >= 0, not {v}"
                        ))
                    })?);
                }
                "time_limit" => {
                    o.shared.time_limit = Some(v.as_f64().ok_or_else(|| {
                        bad(format!(
                            "option 'time_limit' must be a number of seconds, not {v}"
                        ))
                    })?);
                }
                "default_rate" => {
                    let r = v.as_f64().ok_or_else(|| {
                        bad(format!("option 'default_rate' must be a number, not {v}"))
                    })?;
                    o.default_rate = Some(check_rate(None, r)?);
                }
                _ => return Err(unknown_option(k)),
            }
        }
        o.shared.check_for(method)?;
        Ok(o)
    }
}

fn unknown_option(k: &str) -> Error {
    Error::Invalid(format!(
        "unknown option '{k}' (choose from {})",
        OPTION_NAMES.join(", ")
    ))
}

/// A goal as a row gives it.
#[derive(Debug, Clone, PartialEq)]
pub enum GoalText {
    /// A label that one object has.
    Label(String),
    /// An object's fields.
    Object(ObjectSpec),
}

impl GoalText {
    /// Reads a row's goal: a JSON object (the text starts with `{`, read by the goal loader
    /// of `foon plan --goal`, one object), else a label.
    pub fn parse(text: &str) -> Result<Self> {
        if !text.trim_start().starts_with('{') {
            return Ok(Self::Label(text.to_owned()));
        }
        let mut v = crate::parse::parse_objects(text.as_bytes(), None, InputKind::Goal)?;
        match v.len() {
            1 => Ok(Self::Object(v.remove(0))),
            n => Err(Error::Invalid(format!("a goal is one object, not {n}"))),
        }
    }

    /// The goal's object in `foon` at level 3 ([`Foon::goal_by_label`] or
    /// [`Foon::goal_by_spec`]), which does not depend on the kitchen.
    pub fn resolve_by_identity(&self, foon: &Foon) -> Result<u32> {
        match self {
            Self::Label(l) => foon.goal_by_label(l),
            Self::Object(s) => foon.goal_by_spec(s),
        }
    }

    /// The goal's object in `ctx`'s FOON, matched at `level` (3: [`Foon::goal_by_label`] or
    /// [`Foon::goal_by_spec`]; below 3: [`crate::levels::goal_at_level`], a label standing
    /// for the label-only object).
    pub fn resolve(&self, ctx: &Context<'_>, level: u8) -> Result<u32> {
        match (self, level) {
            (_, 3) => self.resolve_by_identity(ctx.foon),
            (Self::Label(l), _) => {
                let s = ObjectSpec {
                    label: l.clone(),
                    ..ObjectSpec::default()
                };
                crate::levels::goal_at_level(ctx, &s, level)
            }
            (Self::Object(s), _) => crate::levels::goal_at_level(ctx, s, level),
        }
    }
}

/// The answer to one row.
#[derive(Debug, Clone, PartialEq)]
pub struct Answer {
    /// The plan, when the row was planned (solved or not).
    pub plan: Option<Plan>,
    /// `None` when solved.
    pub failure: Option<Failure>,
    /// The missing items (not derivable), or the unresolved inputs (course methods), each
    /// described on one line ([`ObjectSpec::describe`]).
    pub missing: Vec<String>,
    /// The text of an `error`, `missing-rate` or `bad-*` failure.
    pub message: Option<String>,
}

impl Answer {
    fn failed(failure: Failure, e: &Error) -> Self {
        Self {
            plan: None,
            failure: Some(failure),
            missing: Vec::new(),
            message: failure.has_message().then(|| e.to_string()),
        }
    }

    /// Whether a tree was found.
    pub fn solved(&self) -> bool {
        self.failure.is_none()
    }

    /// The solved plan.
    pub fn solved_plan(&self) -> Option<&Plan> {
        self.plan.as_ref().filter(|p| p.solved)
    }

    /// The answer to a planned row.
    fn of_plan(foon: &Foon, plan: Plan) -> Self {
        let describe = |ids: &[u32]| -> Vec<String> {
            ids.iter()
                .map(|&o| ObjectSpec::of_object(foon, o).describe())
                .collect()
        };
        let (failure, missing) = if plan.solved {
            (None, Vec::new())
        } else if plan.query.compat == Compat::Course {
            (Some(Failure::Unresolved), describe(&plan.unresolved))
        } else {
            let e = plan.explanation.as_ref();
            let missing = e.map(|e| describe(&e.missing)).unwrap_or_default();
            if e.is_some_and(|e| !e.cycle.is_empty()) {
                (Some(Failure::Cycle), missing)
            } else {
                (Some(Failure::NotDerivable), missing)
            }
        };
        Self {
            plan: Some(plan),
            failure,
            missing,
            message: None,
        }
    }

    /// The answer to a row whose planning failed with `e`.
    fn of_error(e: &Error) -> Self {
        let f = match e {
            Error::GoalNotFound { .. } => Failure::GoalNotFound,
            Error::GoalAmbiguous { .. } => Failure::GoalAmbiguous,
            Error::MissingRate { .. } => Failure::MissingRate,
            _ => Failure::Error,
        };
        Self::failed(f, e)
    }
}

/// How a batch of queries runs.
#[derive(Clone, Copy, Default)]
pub struct RunOptions<'a> {
    /// Threads and cancel callback (the policy of [`crate::search::batch`]).
    pub batch: BatchOptions<'a>,
    pub utensils: &'a [String],
    pub rates: Option<&'a MotionRates>,
    /// The default rate of rows whose options give none.
    pub default_rate: Option<f64>,
    /// How kitchens given as a base plus a delta are prepared (see [`prepare_wave`]).
    pub deltas: DeltaPreparation,
}

/// The group of a row: its kitchen's position, its level and its default rate's bits.
type GroupKey = (usize, u8, Option<u64>);

/// A checked row: where it goes and what it asks.
struct Checked {
    group: usize,
    /// The row's goal: its position among the batch's distinct goals ([`Memo`]).
    goal: usize,
    /// The goal's object, when it does not depend on the kitchen (level 3).
    goal_id: Option<u32>,
    query: Query,
    options: RowOptions,
}

/// A text read: its value, or the answer of the rows that give it.
type Read<T> = std::result::Result<T, Box<Answer>>;

/// What a batch reads once per distinct text: its goals (parsed, and at level 3 resolved)
/// and its options (per method, which they are checked against).
#[derive(Default)]
struct Memo<'a> {
    goal_of: FxHashMap<&'a str, usize>,
    goals: Vec<std::result::Result<GoalText, Box<Answer>>>,
    /// Per goal, its object at level 3, once asked for.
    resolved: Vec<Option<std::result::Result<u32, Box<Answer>>>>,
    options: FxHashMap<(Option<&'a str>, Method), Read<RowOptions>>,
}

impl<'a> Memo<'a> {
    /// The position of goal `text` and its parse.
    fn goal(&mut self, text: &'a str) -> (usize, &std::result::Result<GoalText, Box<Answer>>) {
        let n = self.goals.len();
        let i = *self.goal_of.entry(text).or_insert(n);
        if i == n {
            self.goals.push(
                GoalText::parse(text).map_err(|e| Box::new(Answer::failed(Failure::BadGoal, &e))),
            );
            self.resolved.push(None);
        }
        (i, &self.goals[i])
    }

    /// The goal text of `goal`, parsed (only for the goals [`Memo::goal`] parsed well).
    fn goal_text(&self, goal: usize) -> Option<&GoalText> {
        self.goals.get(goal).and_then(|g| g.as_ref().ok())
    }
}

/// Checks one row: its group key (kitchen position, level, default rate) and what it asks.
fn check_row<'a>(
    set: &KitchenSet,
    row: &QueryRow<'a>,
    default_rate: Option<f64>,
    memo: &mut Memo<'a>,
) -> std::result::Result<(GroupKey, Checked), Box<Answer>> {
    let missing = |f: Failure, what: &str| Answer {
        plan: None,
        failure: Some(f),
        missing: Vec::new(),
        message: f.has_message().then(|| format!("no {what}")),
    };
    let Some(kid) = row.kitchen else {
        return Err(Box::new(missing(Failure::UnknownKitchen, "kitchen id")));
    };
    let Some(kitchen) = set.position(kid) else {
        return Err(Box::new(Answer::failed(
            Failure::UnknownKitchen,
            &Error::Invalid(format!("unknown kitchen id '{kid}'")),
        )));
    };
    let Some(method) = row.method else {
        return Err(Box::new(missing(Failure::UnknownMethod, "method")));
    };
    let method: Method = method
        .parse()
        .map_err(|e| Box::new(Answer::failed(Failure::UnknownMethod, &e)))?;
    let options = memo
        .options
        .entry((row.options, method))
        .or_insert_with(|| {
            RowOptions::parse(row.options, method)
                .map_err(|e| Box::new(Answer::failed(Failure::BadOption, &e)))
        })
        .clone()?;
    // An optimal method in its course form is a bad option, found with the others.
    let query = Query {
        method,
        compat: options.compat,
        count: options.count,
    };
    query
        .check()
        .map_err(|e| Box::new(Answer::failed(Failure::BadOption, &e)))?;
    let Some(goal) = row.goal else {
        return Err(Box::new(missing(Failure::BadGoal, "goal")));
    };
    let (goal, parsed) = memo.goal(goal);
    if let Err(a) = parsed {
        return Err(a.clone());
    }
    let rate = options.default_rate.or(default_rate).map(f64::to_bits);
    let checked = Checked {
        group: usize::MAX,
        goal,
        goal_id: None,
        query,
        options,
    };
    Ok(((kitchen, options.level, rate), checked))
}

/// How a batch prepares the kitchens given as a base plus a delta ([`Entry::delta`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum DeltaPreparation {
    /// From the preparation of the base kitchen (prepared once, through the cache, like any
    /// kitchen), by [`Prepared::with_kitchen`]: what the base has computed (ranks, the
    /// choice of `ids`, each optimal objective's costs and choices) is updated, touching
    /// only what the delta changes. The default.
    #[default]
    Incremental,
    /// From the delta kitchen's own items, as a kitchen given by its items (in the 64-lane
    /// pass of [`prepare_many`]).
    FromScratch,
}

/// What the base of delta kitchens should compute before the delta kitchens are derived
/// from it: called with the base's preparation and the positions in the wave of the delta
/// kitchens to be derived from it (see [`prepare_wave`]).
pub type Warm<'a> = &'a (dyn Fn(&Prepared, &[usize]) -> Result<()> + Sync);

/// A kitchen of a wave as [`prepare_wave`] leaves it: prepared, or to be derived from its
/// base kitchen's preparation ([`WaveKitchen::prepared`]).
pub enum WaveKitchen {
    Ready(Arc<Prepared>),
    Delta {
        /// The base kitchen's preparation.
        from: Arc<Prepared>,
        /// The delta kitchen's key in the cache.
        key: CacheKey,
    },
}

impl WaveKitchen {
    /// The prepared kitchen: for a delta kitchen, prepared from its base kitchen's
    /// preparation by [`Prepared::with_kitchen_changes`] (at level 3 only the delta's items
    /// are matched; the level is the base kitchen's preparation's), then kept in `cache`.
    pub fn prepared(
        &self,
        foon: &Foon,
        cache: &PreparedCache,
        entry: &Entry,
    ) -> Result<Arc<Prepared>> {
        match self {
            Self::Ready(p) => Ok(Arc::clone(p)),
            // `prepare_wave` leaves only delta kitchens to be derived, and found none of `key`
            // in the cache.
            Self::Delta { from, key } => {
                let d = entry.delta().ok_or_else(|| {
                    Error::Invalid("a kitchen given by its items has no base".into())
                })?;
                let p = from.with_kitchen_changes(foon, &d.add, &d.remove, || entry.kitchen())?;
                // Its rows read many trees: each update the base computed is run to the end
                // at once, not goal by goal under its lock.
                p.finish_all_pending(foon, &|| Ok(()))?;
                Ok(cache.insert(*key, p))
            }
        }
    }
}

/// Prepares the kitchens of one wave: `(base, entry, level)` each, in order. The one place
/// kitchens of a batch are prepared, each through `cache` (keyed by the FOON's, the base's
/// and the kitchen's fingerprints and the level):
///
/// - the kitchens given by their items (and, with [`DeltaPreparation::FromScratch`], the
///   delta kitchens) that the cache lacks, in one 64-lane pass per base ([`prepare_many`]):
///   one pass over the FOON for up to 64 kitchens, which no per-kitchen update beats for
///   kitchens that share nothing;
/// - with [`DeltaPreparation::Incremental`], each delta kitchen the cache lacks is left to
///   be derived from the preparation of its base kitchen ([`WaveKitchen::Delta`]): the base
///   kitchen is prepared once, through the cache under its own key (so the deltas of one
///   base, in this wave and the next, share it), and `warm` computes on it what the
///   deltas' rows will use, which each delta kitchen then updates rather than computes.
///
/// Every result is that of a preparation from scratch.
pub fn prepare_wave(
    foon: &Foon,
    cache: &PreparedCache,
    wave: &[(Arc<PreparedBase>, &Entry, u8)],
    opts: &BatchOptions<'_>,
    deltas: DeltaPreparation,
    warm: Option<Warm<'_>>,
) -> Result<Vec<WaveKitchen>> {
    let keys: Vec<CacheKey> = wave
        .iter()
        .map(|(b, e, l)| {
            Ok(CacheKey {
                foon: foon.fingerprint(),
                base: b.key(),
                kitchen: e.fingerprint()?,
                level: *l,
            })
        })
        .collect::<Result<_>>()?;
    let mut out: Vec<Option<WaveKitchen>> = keys
        .iter()
        .map(|k| cache.get(k).map(WaveKitchen::Ready))
        .collect();
    // The misses: by base for the 64-lane pass, by (base, base kitchen, level) for deltas.
    let mut by_base: FxHashMap<u128, Vec<usize>> = FxHashMap::default();
    let mut by_delta_base: FxHashMap<(u128, u128, u8), Vec<usize>> = FxHashMap::default();
    for (i, w) in wave.iter().enumerate() {
        if out[i].is_some() {
            continue;
        }
        match w.1.delta() {
            Some(d) if deltas == DeltaPreparation::Incremental => {
                let key = (w.0.key(), d.base.fingerprint(), w.2);
                by_delta_base.entry(key).or_default().push(i);
            }
            _ => by_base.entry(w.0.key()).or_default().push(i),
        }
    }
    let mut bases: Vec<_> = by_base.into_iter().collect();
    bases.sort_unstable_by_key(|(_, v)| v[0]);
    for (_, idx) in bases {
        // The kitchens matched together, per level (`Kitchen::match_many`: each distinct
        // string and item looked up once).
        let kitchens: Vec<Arc<Kitchen>> = idx
            .iter()
            .map(|&i| wave[i].1.kitchen())
            .collect::<Result<_>>()?;
        let mut ids: Vec<Vec<u32>> = vec![Vec::new(); idx.len()];
        let mut levels: Vec<u8> = idx.iter().map(|&i| wave[i].2).collect();
        levels.sort_unstable();
        levels.dedup();
        for level in levels {
            let at: Vec<usize> = (0..idx.len())
                .filter(|&j| wave[idx[j]].2 == level)
                .collect();
            let ks: Vec<&Kitchen> = at.iter().map(|&j| &*kitchens[j]).collect();
            for (j, m) in at.into_iter().zip(Kitchen::match_many(&ks, foon, level)?) {
                ids[j] = m;
            }
        }
        let refs: Vec<&[u32]> = ids.iter().map(Vec::as_slice).collect();
        let prepared = prepare_many(foon, &wave[idx[0]].0, &refs, opts)?;
        for (&i, p) in idx.iter().zip(prepared) {
            // `cache.get` missed for every kitchen here.
            out[i] = Some(WaveKitchen::Ready(
                cache.insert(keys[i], p.at_level(wave[i].2)),
            ));
        }
    }
    let mut delta_bases: Vec<_> = by_delta_base.into_values().collect();
    delta_bases.sort_unstable_by_key(|v| v[0]);
    for idx in delta_bases {
        let (base, entry, level) = &wave[idx[0]];
        let Some(d) = entry.delta() else { continue };
        let from = cache.kitchen(foon, base, &d.base, *level)?;
        if let Some(warm) = warm {
            warm(&from, &idx)?;
        }
        for &i in &idx {
            out[i] = Some(WaveKitchen::Delta {
                from: Arc::clone(&from),
                key: keys[i],
            });
        }
    }
    out.into_iter()
        .map(|p| p.ok_or_else(|| Error::Invalid("a kitchen was not prepared".into())))
        .collect()
}

/// Answers every row of `rows` over `foon` with the kitchens of `set` (see the module
/// documentation). Errors only when cancelled or given a bad thread count. On one thread
/// (`threads` 1, or one row) every step keeps to one thread, what a prepared kitchen
/// computes once included.
pub fn run_queries(
    foon: &Foon,
    set: &KitchenSet,
    rows: &[QueryRow<'_>],
    cache: &PreparedCache,
    opts: &RunOptions<'_>,
) -> Result<Vec<Answer>> {
    let workers = opts.batch.workers(rows.len())?;
    if workers <= 1 {
        return crate::search::batch::on_one_thread(|| {
            answer_rows(foon, set, rows, cache, opts, 1)
        })?;
    }
    answer_rows(foon, set, rows, cache, opts, workers)
}

/// [`run_queries`] on `workers` workers.
fn answer_rows(
    foon: &Foon,
    set: &KitchenSet,
    rows: &[QueryRow<'_>],
    cache: &PreparedCache,
    opts: &RunOptions<'_>,
    workers: usize,
) -> Result<Vec<Answer>> {
    let never = || false;
    let cancel: &(dyn Fn() -> bool + Sync) = opts.batch.cancel.unwrap_or(&never);
    let mut answers: Vec<Option<Answer>> = Vec::with_capacity(rows.len());
    let mut groups: Vec<GroupKey> = Vec::new();
    let mut group_of: FxHashMap<GroupKey, usize> = FxHashMap::default();
    let mut checked: Vec<(usize, Checked)> = Vec::new();
    // Each distinct goal and options text is read once. At level 3 a goal does not depend
    // on the kitchen: it is resolved once, and a row whose goal is not found needs no
    // kitchen.
    let mut memo = Memo::default();
    for (i, row) in rows.iter().enumerate() {
        match check_row(set, row, opts.default_rate, &mut memo) {
            Ok((key, mut c)) => {
                if c.options.level == 3 {
                    let g = c.goal;
                    if memo.resolved[g].is_none() {
                        let r = memo
                            .goal_text(g)
                            .map_or_else(
                                || Err(Error::Invalid("a goal was not read".into())),
                                |t| t.resolve_by_identity(foon),
                            )
                            .map_err(|e| Box::new(Answer::of_error(&e)));
                        memo.resolved[g] = Some(r);
                    }
                    match &memo.resolved[g] {
                        Some(Ok(o)) => c.goal_id = Some(*o),
                        Some(Err(a)) => {
                            answers.push(Some((**a).clone()));
                            continue;
                        }
                        None => {}
                    }
                }
                c.group = *group_of.entry(key).or_insert_with(|| {
                    groups.push(key);
                    groups.len() - 1
                });
                checked.push((i, c));
                answers.push(None);
            }
            Err(a) => answers.push(Some(*a)),
        }
    }
    let goals: Vec<Option<&GoalText>> = (0..memo.goals.len()).map(|g| memo.goal_text(g)).collect();
    // Rows by group (stable: row order within a group), by counting.
    let checked = {
        let mut at = vec![0usize; groups.len() + 1];
        for (_, c) in &checked {
            at[c.group + 1] += 1;
        }
        for g in 0..groups.len() {
            at[g + 1] += at[g];
        }
        let mut slots: Vec<Option<(usize, Checked)>> = (0..checked.len()).map(|_| None).collect();
        for rc in checked {
            let g = rc.1.group;
            slots[at[g]] = Some(rc);
            at[g] += 1;
        }
        slots.into_iter().flatten().collect::<Vec<_>>()
    };
    let mut start = 0;
    let wave_len = wave_size(foon);
    for wave_lo in (0..groups.len()).step_by(wave_len) {
        if cancel() {
            return Err(Error::Cancelled);
        }
        let wave_hi = (wave_lo + wave_len).min(groups.len());
        let end = start + checked[start..].partition_point(|(_, c)| c.group < wave_hi);
        let rows_here = &checked[start..end];
        start = end;
        // The bases of the wave (one per default rate), then its kitchens.
        let mut wave = Vec::new();
        // The group of each kitchen of the wave.
        let mut wave_group = Vec::new();
        let mut bad: Vec<Option<Answer>> = Vec::new();
        for (g, &(k, level, rate)) in (wave_lo..).zip(&groups[wave_lo..wave_hi]) {
            let base = cache.base(foon, opts.utensils, opts.rates, rate.map(f64::from_bits));
            match base {
                Ok(b) => {
                    wave.push((b, set.entry(k), level));
                    wave_group.push(g);
                    bad.push(None);
                }
                Err(e) => bad.push(Some(Answer::of_error(&e))),
            }
        }
        // The rows of each group of the wave.
        let mut ranges = Vec::with_capacity(wave_hi - wave_lo);
        let mut lo = 0;
        for g in wave_lo..wave_hi {
            let hi = lo + rows_here[lo..].partition_point(|(_, c)| c.group <= g);
            ranges.push(lo..hi);
            lo = hi;
        }
        let warm = |from: &Prepared, positions: &[usize]| {
            warm_base(
                foon,
                from,
                &goals,
                positions
                    .iter()
                    .flat_map(|&p| &rows_here[ranges[wave_group[p] - wave_lo].clone()])
                    .map(|(_, c)| c),
                cancel,
            )
        };
        let kitchens = match prepare_wave(foon, cache, &wave, &opts.batch, opts.deltas, Some(&warm))
        {
            Ok(p) => p.into_iter().map(Ok).collect::<Vec<_>>(),
            Err(Error::Cancelled) => return Err(Error::Cancelled),
            Err(e) => wave.iter().map(|_| Err(e.to_string())).collect(),
        };
        // Per group of the wave: what prepares its kitchen (and where in the wave), or the
        // answer of its rows.
        let mut pending: Vec<std::result::Result<(usize, WaveKitchen), Answer>> = Vec::new();
        let mut next = kitchens.into_iter().enumerate();
        for b in bad {
            pending.push(match b {
                Some(a) => Err(a),
                None => match next.next() {
                    Some((w, Ok(k))) => Ok((w, k)),
                    Some((_, Err(m))) => Err(Answer::of_error(&Error::Invalid(m))),
                    None => Err(Answer::of_error(&Error::Invalid(
                        "a kitchen was not prepared".into(),
                    ))),
                },
            });
        }
        // Per group: its prepared kitchen (a delta kitchen is derived by the worker that
        // takes the group), or the answer of its rows.
        let preps: Vec<OnceLock<std::result::Result<Arc<Prepared>, Answer>>> =
            pending.iter().map(|_| OnceLock::new()).collect();
        #[allow(clippy::result_large_err)] // the answer is cloned for each of the group's rows
        let prep_of = |j: usize| -> Result<&std::result::Result<Arc<Prepared>, Answer>> {
            if let Some(p) = preps[j].get() {
                return Ok(p);
            }
            let p = match &pending[j] {
                Err(a) => Err(a.clone()),
                Ok((w, k)) => match k.prepared(foon, cache, wave[*w].1) {
                    Ok(p) => Ok(p),
                    Err(Error::Cancelled) => return Err(Error::Cancelled),
                    Err(e) => Err(Answer::of_error(&e)),
                },
            };
            Ok(preps[j].get_or_init(|| p))
        };
        let one = |c: &Checked| -> Result<Answer> {
            let prep = match prep_of(c.group - wave_lo)? {
                Ok(p) => p,
                Err(a) => return Ok(a.clone()),
            };
            let goal = goals[c.goal].ok_or_else(|| Error::Invalid("a goal was not read".into()))?;
            answer(foon, prep, goal, c, cancel)
        };
        let slots: Vec<OnceLock<Result<Answer>>> =
            rows_here.iter().map(|_| OnceLock::new()).collect();
        // What a prepared kitchen computes on first use (ranks, optima, the choices of
        // `ids`) is computed by the first row of each (kitchen, query) alone: a worker takes
        // a group, prepares its kitchen and plans those rows, and the group's other rows run
        // after them, so that two workers do not compute the same thing for one kitchen at
        // once.
        let mut leaders: Vec<Vec<usize>> = vec![Vec::new(); wave_hi - wave_lo];
        let mut followers = Vec::new();
        let mut seen = rustc_hash::FxHashSet::default();
        for (j, (_, c)) in rows_here.iter().enumerate() {
            if seen.insert((c.group, c.query)) {
                leaders[c.group - wave_lo].push(j);
            } else {
                followers.push(j);
            }
        }
        let run_row = |j: usize| {
            let _ = slots[j].set(one(&rows_here[j].1));
            slots[j].get().is_some_and(Result::is_ok)
        };
        // One schedule ([`Schedule`]): the groups (each a worker's: its kitchen, then its
        // leading rows), then the other rows in blocks of one group, a block taken once its
        // group's leading rows are done (set even when they fail, so no row waits for ever):
        // the rows of the groups done run while a long group is prepared.
        let sched = Schedule::new(
            &followers,
            |j| rows_here[j].1.group - wave_lo,
            wave_hi - wave_lo,
        );
        plan_rows(workers, cancel, &sched, &|step| match step {
            Step::Lead(g) => leaders[g].iter().all(|&j| !cancel() && run_row(j)),
            Step::Follow(r) => followers[r].iter().all(|&j| !cancel() && run_row(j)),
        })?;
        for (slot, (i, _)) in slots.into_iter().zip(rows_here) {
            match slot.into_inner() {
                Some(Ok(a)) => answers[*i] = Some(a),
                Some(Err(e)) => return Err(e),
                None => return Err(Error::Cancelled),
            }
        }
    }
    answers
        .into_iter()
        .map(|a| a.ok_or_else(|| Error::Invalid("a query row was not answered".into())))
        .collect()
}

/// Rows of a wave that follow their group's leading rows, taken this many at a time.
const FOLLOW_BLOCK: usize = 16;

/// What a worker of a wave runs next ([`Schedule::next`]).
#[derive(Debug, Clone, PartialEq, Eq)]
enum Step {
    /// The leading rows of group `g` (its kitchen's preparation with them).
    Lead(usize),
    /// These positions of the following rows, all of one group whose leading rows are done.
    Follow(std::ops::Range<usize>),
}

/// The order in which the workers of a wave take its rows: every group's leading rows, one
/// group at a time in group order, then the following rows in blocks of at most
/// [`FOLLOW_BLOCK`] of one group, the first block (in group order) of a group whose leading
/// rows are done. A worker waits only when every block left belongs to a group still led.
/// On one worker this is the leading rows of every group, then every other row in order.
struct Schedule {
    next_group: AtomicUsize,
    led: Vec<AtomicBool>,
    /// Per group: its blocks, as a range of `blocks`.
    group_blocks: Vec<std::ops::Range<usize>>,
    /// Per group: how many of its blocks were taken (may pass their number).
    taken: Vec<AtomicUsize>,
    /// The blocks, as ranges of the positions of the following rows.
    blocks: Vec<std::ops::Range<usize>>,
}

/// [`Schedule::next`]'s answer.
#[derive(Debug, PartialEq, Eq)]
enum Next {
    Run(Step),
    /// Every block left waits for a group still led.
    Wait,
    Done,
}

impl Schedule {
    /// The schedule of `n_groups` groups whose following rows are `followers` (in group
    /// order), `group_of` giving each one's group.
    fn new(followers: &[usize], group_of: impl Fn(usize) -> usize, n_groups: usize) -> Self {
        let mut blocks = Vec::new();
        let mut group_blocks = vec![0..0; n_groups];
        let mut i = 0;
        while i < followers.len() {
            let g = group_of(followers[i]);
            let lo = blocks.len();
            let mut j = i;
            while j < followers.len() && group_of(followers[j]) == g {
                j += 1;
            }
            let mut at = i;
            while at < j {
                let end = (at + FOLLOW_BLOCK).min(j);
                blocks.push(at..end);
                at = end;
            }
            group_blocks[g] = lo..blocks.len();
            i = j;
        }
        Self {
            next_group: AtomicUsize::new(0),
            led: (0..n_groups).map(|_| AtomicBool::new(false)).collect(),
            taken: (0..n_groups).map(|_| AtomicUsize::new(0)).collect(),
            group_blocks,
            blocks,
        }
    }

    fn next(&self) -> Next {
        let g = self.next_group.fetch_add(1, Ordering::Relaxed);
        if g < self.led.len() {
            return Next::Run(Step::Lead(g));
        }
        let mut waiting = false;
        for (g, range) in self.group_blocks.iter().enumerate() {
            let n = range.len();
            if self.taken[g].load(Ordering::Relaxed) >= n {
                continue;
            }
            if !self.led[g].load(Ordering::Acquire) {
                waiting = true;
                continue;
            }
            let b = self.taken[g].fetch_add(1, Ordering::Relaxed);
            if b < n {
                return Next::Run(Step::Follow(self.blocks[range.start + b].clone()));
            }
        }
        if waiting { Next::Wait } else { Next::Done }
    }

    /// Step `step` ran: a group's leading rows are done.
    fn ran(&self, step: &Step) {
        if let Step::Lead(g) = step {
            self.led[*g].store(true, Ordering::Release);
        }
    }
}

/// Runs every step of `sched` with `run`, on up to `workers` workers of the batch pool (on
/// this thread for one), until `run` answers false (a row failed: the batch stops) or
/// `cancel` answers true ([`Error::Cancelled`]). A worker with nothing to run until a group
/// is led runs other work of the pool meanwhile (a part of a kitchen's preparation computed
/// in parallel), else sleeps briefly.
fn plan_rows(
    workers: usize,
    cancel: &(dyn Fn() -> bool + Sync),
    sched: &Schedule,
    run: &(dyn Fn(Step) -> bool + Sync),
) -> Result<()> {
    let stop = AtomicBool::new(false);
    let cancelled = AtomicBool::new(false);
    let work = || {
        while !stop.load(Ordering::Relaxed) {
            if cancel() {
                cancelled.store(true, Ordering::Relaxed);
                stop.store(true, Ordering::Relaxed);
                break;
            }
            match sched.next() {
                Next::Run(step) => {
                    let ok = run(step.clone());
                    sched.ran(&step);
                    if !ok {
                        stop.store(true, Ordering::Relaxed);
                    }
                }
                Next::Wait => {
                    if rayon::yield_now() != Some(rayon::Yield::Executed) {
                        std::thread::sleep(std::time::Duration::from_micros(200));
                    }
                }
                Next::Done => break,
            }
        }
    };
    let steps = sched.led.len() + sched.blocks.len();
    let n_workers = workers.min(steps).max(1);
    if n_workers <= 1 {
        work();
    } else {
        in_pool(|| {
            rayon::scope(|s| {
                for _ in 0..n_workers {
                    s.spawn(|_| work());
                }
            });
        })?;
    }
    if cancelled.load(Ordering::Relaxed) {
        return Err(Error::Cancelled);
    }
    Ok(())
}

/// Tries on a base kitchen's preparation `from` a few rows of the delta kitchens about to be
/// derived from it (`rows`, their goals in `goals`), so that it computes what they will use
/// (its ranks, and what planning their queries computes once per kitchen: the choice of
/// `ids`, the optimal objectives), which every delta kitchen then updates rather than
/// computes: up to [`WARM_TRIES`] rows per query, until one is solved. When a row is sound
/// and some object cannot be made in the base, the shopping costs of explanations are
/// computed too, alongside the rows (on the pool: they need only the kitchen). The answers
/// are dropped (only a cancel is an error).
fn warm_base<'c>(
    foon: &Foon,
    from: &Prepared,
    goals: &[Option<&GoalText>],
    rows: impl Iterator<Item = &'c Checked>,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<()> {
    let ctx = Context::with(foon, from)?.with_cancel(cancel);
    // `optimal-shared` reads the optima of `optimal-units` and `optimal-success`.
    let queries: Vec<(&Checked, Query)> = rows
        .map(|c| {
            let query = match c.query.method {
                Method::OptimalShared => Query {
                    method: Method::OptimalUnits,
                    ..c.query
                },
                _ => c.query,
            };
            (c, query)
        })
        .collect();
    let sound = queries
        .iter()
        .any(|(_, q)| q.compat == Compat::Sound && q.method != Method::Bfs);
    let ranks = ctx.ranks();
    let unmade = sound && (0..foon.object_count() as u32).any(|o| ranks.rank(o).is_none());
    let try_rows = || -> Result<()> {
        let mut tries: FxHashMap<Query, usize> = FxHashMap::default();
        for &(c, query) in &queries {
            let n = tries.entry(query).or_insert(0);
            if *n >= WARM_TRIES {
                continue;
            }
            *n += 1;
            let Some(text) = goals.get(c.goal).copied().flatten() else {
                continue;
            };
            let goal = match c
                .goal_id
                .map_or_else(|| text.resolve(&ctx, c.options.level), Ok)
            {
                Ok(g) => g,
                Err(Error::Cancelled) => return Err(Error::Cancelled),
                Err(_) => continue,
            };
            match ctx.plan(goal, query) {
                Ok(p) if p.solved => *n = WARM_TRIES,
                Err(Error::Cancelled) => return Err(Error::Cancelled),
                _ => {}
            }
        }
        Ok(())
    };
    let shopping = || {
        if unmade {
            crate::search::compute_optimum(&ctx, crate::prepare::Objective::Shopping)
        } else {
            Ok(())
        }
    };
    let (a, b) = in_pool(|| rayon::join(try_rows, shopping))?;
    match (a, b) {
        (Err(Error::Cancelled), _) | (_, Err(Error::Cancelled)) => Err(Error::Cancelled),
        _ => Ok(()),
    }
}

/// Rows per query tried on the base of delta kitchens, at most ([`warm_base`]).
const WARM_TRIES: usize = 4;

/// Plans one checked row on its prepared kitchen.
fn answer(
    foon: &Foon,
    prep: &Prepared,
    goal: &GoalText,
    c: &Checked,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Answer> {
    let ctx = Context::with(foon, prep)?
        .with_cancel(cancel)
        .with_shared(c.options.shared);
    let goal = match c
        .goal_id
        .map_or_else(|| goal.resolve(&ctx, c.options.level), Ok)
    {
        Ok(g) => g,
        Err(Error::Cancelled) => return Err(Error::Cancelled),
        Err(e) => return Ok(Answer::of_error(&e)),
    };
    match ctx.plan(goal, c.query) {
        Ok(p) => Ok(Answer::of_plan(foon, p)),
        Err(Error::Cancelled) => Err(Error::Cancelled),
        Err(e) => Ok(Answer::of_error(&e)),
    }
}

#[cfg(test)]
mod tests {
    use super::{FOLLOW_BLOCK, Next, Schedule, Step};

    /// Three groups: 0 with 40 following rows (three blocks), 1 with none, 2 with 3.
    fn schedule() -> Schedule {
        let group = |j: usize| match j {
            0..40 => 0,
            _ => 2,
        };
        Schedule::new(&(0..43).collect::<Vec<_>>(), group, 3)
    }

    #[test]
    fn leads_every_group_then_follows_only_led_groups() {
        let s = schedule();
        for g in 0..3 {
            assert_eq!(s.next(), Next::Run(Step::Lead(g)));
        }
        // No group is led yet: the following rows wait.
        assert_eq!(s.next(), Next::Wait);
        s.ran(&Step::Lead(2));
        assert_eq!(s.next(), Next::Run(Step::Follow(40..43)));
        assert_eq!(s.next(), Next::Wait);
        s.ran(&Step::Lead(0));
        s.ran(&Step::Lead(1));
        assert_eq!(s.next(), Next::Run(Step::Follow(0..FOLLOW_BLOCK)));
        assert_eq!(
            s.next(),
            Next::Run(Step::Follow(FOLLOW_BLOCK..2 * FOLLOW_BLOCK))
        );
        assert_eq!(s.next(), Next::Run(Step::Follow(2 * FOLLOW_BLOCK..40)));
        assert_eq!(s.next(), Next::Done);
        assert_eq!(s.next(), Next::Done);
    }

    #[test]
    fn one_worker_runs_rows_in_order() {
        // What one worker sees: each step done before the next is asked for.
        let s = schedule();
        let mut seen = Vec::new();
        loop {
            match s.next() {
                Next::Run(step) => {
                    s.ran(&step);
                    seen.push(step);
                }
                Next::Wait => panic!("one worker never waits"),
                Next::Done => break,
            }
        }
        let follows: Vec<usize> = seen
            .iter()
            .filter_map(|s| match s {
                Step::Follow(r) => Some(r.clone()),
                Step::Lead(_) => None,
            })
            .flatten()
            .collect();
        assert_eq!(&seen[..3], &[Step::Lead(0), Step::Lead(1), Step::Lead(2)]);
        assert_eq!(follows, (0..43).collect::<Vec<_>>());
    }
}
