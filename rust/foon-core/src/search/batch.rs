//! Batch planning: many goals over one prepared kitchen, spread over worker threads.
//!
//! This is the one batch policy of the crate (the Python bindings and the command line use it
//! as it is):
//!
//! - [`BatchOptions::threads`] is always honoured: `Some(1)` plans on the calling thread, `Some(n)`
//!   uses `n` workers. It is capped to the available parallelism
//!   ([`std::thread::available_parallelism`]) and to the number of goals, since more workers
//!   than cores or goals only add start-up cost. `None` means the environment variable
//!   `FOON_THREADS` when it is set, else the available parallelism (then capped the same way).
//! - The workers run on one thread pool per process, sized to the cap and built on first use;
//!   a call with fewer threads runs that many workers on it. Calls with different thread
//!   counts never leave extra pools or threads behind.
//! - Fork guard: a pool built in a parent process is never used in a forked child (its
//!   threads do not exist there); the child builds its own on first use. Forking while another
//!   thread of the parent is inside a batch is not supported (as with any threaded library).
//! - [`BatchOptions::cancel`] is polled by every worker before each goal and, through
//!   [`Context::with_cancel`], during each search; once it answers true the batch returns
//!   [`Error::Cancelled`].
//! - Results are in goal order and identical for every thread count. On an error, the error of
//!   the first failing goal (in goal order) is returned.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock, PoisonError};

use super::{Compat, Context, Method, Plan, Query, SharedOptions};
use crate::error::{Error, Result};
use crate::index::Foon;
use crate::prepare::{Objective, Prepared};

/// The environment variable that gives the default thread count.
pub const THREADS_ENV: &str = "FOON_THREADS";

/// How a batch runs.
#[derive(Clone, Copy, Default)]
pub struct BatchOptions<'a> {
    /// Worker threads (see the module documentation for the cap and the default).
    pub threads: Option<usize>,
    /// Called now and then by every worker; `true` stops the batch with [`Error::Cancelled`].
    pub cancel: Option<&'a (dyn Fn() -> bool + Sync)>,
    /// The options of `optimal-shared` for every goal.
    pub shared: SharedOptions,
}

impl std::fmt::Debug for BatchOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BatchOptions")
            .field("threads", &self.threads)
            .field("cancel", &self.cancel.is_some())
            .field("shared", &self.shared)
            .finish()
    }
}

impl<'a> BatchOptions<'a> {
    /// `threads` workers (or the default when `None`), no cancel callback.
    pub fn threads(threads: Option<usize>) -> Self {
        Self {
            threads,
            cancel: None,
            shared: SharedOptions::default(),
        }
    }

    /// The same options with these `optimal-shared` options.
    #[must_use]
    pub fn with_shared(mut self, shared: SharedOptions) -> Self {
        self.shared = shared;
        self
    }

    /// The same options with a cancel callback.
    #[must_use]
    pub fn with_cancel(mut self, cancel: &'a (dyn Fn() -> bool + Sync)) -> Self {
        self.cancel = Some(cancel);
        self
    }

    /// The number of workers a batch of `goals` goals runs on: the requested (or default)
    /// count, capped to [`max_threads`] and to `goals`, at least 1. Errors on `Some(0)` and on
    /// a `FOON_THREADS` that is not a positive integer.
    pub fn workers(&self, goals: usize) -> Result<usize> {
        let wanted = match self.threads {
            Some(0) => return Err(Error::Invalid("threads must be at least 1, not 0".into())),
            Some(n) => n,
            None => env_threads()?.unwrap_or_else(max_threads),
        };
        Ok(wanted.min(max_threads()).min(goals).max(1))
    }
}

/// The cap on worker threads: the available parallelism of this process (1 when unknown),
/// read on first use.
pub fn max_threads() -> usize {
    // Read once per process: on Linux it reads the cgroup files, which costs more than a
    // small plan.
    static CAP: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    *CAP.get_or_init(|| std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get))
}

fn env_threads() -> Result<Option<usize>> {
    let Some(v) = std::env::var_os(THREADS_ENV) else {
        return Ok(None);
    };
    let text = v.to_string_lossy();
    match text.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(Some(n)),
        _ if text.trim().is_empty() => Ok(None),
        _ => Err(Error::Invalid(format!(
            "{THREADS_ENV} must be a positive integer, not '{text}'"
        ))),
    }
}

/// The process's one worker pool, with the process that built it (the fork guard).
struct Pool {
    pid: u32,
    pool: Arc<rayon::ThreadPool>,
}

/// The worker pool of this process, built on first use with [`max_threads`] threads. In a
/// forked child the parent's pool is abandoned (its threads do not exist there) and a new one
/// is built.
fn pool() -> Result<Arc<rayon::ThreadPool>> {
    static POOL: Mutex<Option<Pool>> = Mutex::new(None);
    let mut slot = POOL.lock().unwrap_or_else(PoisonError::into_inner);
    let pid = std::process::id();
    if let Some(p) = slot.as_ref() {
        if p.pid == pid {
            return Ok(Arc::clone(&p.pool));
        }
    }
    if let Some(stale) = slot.take() {
        // Built by the parent: its threads are gone in this process, and dropping it would
        // wait on them. Leak it instead.
        std::mem::forget(stale);
    }
    let n = max_threads();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .thread_name(|i| format!("foon-worker-{i}"))
        .build()
        .map_err(|e| Error::Invalid(format!("could not start {n} planning threads: {e}")))?;
    let pool = Arc::new(pool);
    *slot = Some(Pool {
        pid,
        pool: Arc::clone(&pool),
    });
    Ok(pool)
}

/// Runs `f` on the process's worker pool (the fork guard included), so that the parallel
/// iterators and joins inside it never touch rayon's global pool: every parallel step of the
/// crate (parsing, building the index, what a prepared kitchen computes once) goes through
/// here, and a child forked after any of them builds its own threads. On a worker of the pool
/// `f` runs in place.
pub(crate) fn in_pool<R: Send>(f: impl FnOnce() -> R + Send) -> Result<R> {
    if ONE_THREAD.with(std::cell::Cell::get) {
        return Ok(f());
    }
    Ok(pool()?.install(f))
}

thread_local! {
    /// Whether this thread runs [`on_one_thread`]'s work.
    static ONE_THREAD: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `f` on one thread: on a pool of one worker built for the call, where every
/// [`in_pool`] inside `f` runs in place, so every parallel step of the crate inside it (what
/// a prepared kitchen computes once included) runs on that thread alone. How a batch asked
/// for one thread keeps to one.
pub(crate) fn on_one_thread<R: Send>(f: impl FnOnce() -> R + Send) -> Result<R> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .thread_name(|_| "foon-one".into())
        .build()
        .map_err(|e| Error::Invalid(format!("could not start a planning thread: {e}")))?;
    Ok(pool.install(|| {
        ONE_THREAD.with(|c| c.set(true));
        let r = f();
        ONE_THREAD.with(|c| c.set(false));
        r
    }))
}

/// Plans every goal of `goals` with `query` over inputs prepared for `foon` (see the module
/// documentation for threads, cancellation and errors). Results are in goal order.
pub fn plan_batch(
    foon: &Foon,
    prep: &Prepared,
    goals: &[u32],
    query: Query,
    opts: &BatchOptions<'_>,
) -> Result<Vec<Plan>> {
    let workers = opts.workers(goals.len())?;
    let never = || false;
    let cancel: &(dyn Fn() -> bool + Sync) = opts.cancel.unwrap_or(&never);
    let ctx = Context::with(foon, prep)?
        .with_cancel(cancel)
        .with_shared(opts.shared);
    if goals.is_empty() {
        return Ok(Vec::new());
    }
    if workers == 1 {
        return goals
            .iter()
            .map(|&g| {
                if cancel() {
                    return Err(Error::Cancelled);
                }
                ctx.plan(g, query)
            })
            .collect();
    }
    // Shared by every search: computed once, before the workers start (the updates of a
    // kitchen derived by a delta that the plans read run to the end, not goal by goal under
    // their locks: the method's optimum, `optimal-shared`'s any, and the shopping costs of
    // explanations of sound plans).
    let _ = ctx.ranks();
    let mut reads: Vec<Objective> = match query.method {
        Method::OptimalShared => Objective::ALL.to_vec(),
        m => m.objective().into_iter().collect(),
    };
    if query.compat == Compat::Sound {
        reads.push(Objective::Shopping);
    }
    prep.finish_pending_of(foon, &reads, &|| ctx.check_stop())?;
    let slots: Vec<OnceLock<Result<Plan>>> = goals.iter().map(|_| OnceLock::new()).collect();
    let next = AtomicUsize::new(0);
    // The index of the first goal that failed: goals after it are not started.
    let first_failed = AtomicUsize::new(usize::MAX);
    let cancelled = AtomicBool::new(false);
    let work = || {
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            if i >= goals.len() || i > first_failed.load(Ordering::Relaxed) {
                break;
            }
            let r = if cancelled.load(Ordering::Relaxed) || cancel() {
                cancelled.store(true, Ordering::Relaxed);
                Err(Error::Cancelled)
            } else {
                ctx.plan(goals[i], query)
            };
            if r.is_err() {
                first_failed.fetch_min(i, Ordering::Relaxed);
            }
            let _ = slots[i].set(r);
        }
    };
    pool()?.scope(|s| {
        for _ in 0..workers {
            s.spawn(|_| work());
        }
    });
    let mut plans = Vec::with_capacity(goals.len());
    for slot in slots {
        match slot.into_inner() {
            Some(Ok(p)) => plans.push(p),
            Some(Err(e)) => return Err(e),
            // Not started because an earlier goal failed: that error comes first.
            None => break,
        }
    }
    if plans.len() == goals.len() {
        Ok(plans)
    } else {
        Err(Error::Invalid(
            "a planning worker stopped without a result".into(),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse::{ParseOptions, parse_foon};
    use crate::search::Method;

    /// A chain `s0 -> s1 -> ... -> s{n}` with a side branch at every step.
    fn chain(n: usize) -> Foon {
        use std::fmt::Write as _;
        let mut t = String::new();
        for i in 0..n {
            let j = i + 1;
            let _ = write!(t, "O\titem\nS\ts{i}\nM\tstep\nO\titem\nS\ts{j}\n//\n");
            let _ = write!(
                t,
                "O\titem\nS\ts{i}\nO\textra\nM\tside\nO\titem\nS\tb{i}\n//\n"
            );
        }
        parse_foon(t.as_bytes(), None, ParseOptions::default()).unwrap()
    }

    fn prepared(foon: &Foon) -> Prepared {
        let kitchen = vec![crate::ObjectSpec {
            label: "item".into(),
            states: vec!["s0".into()],
            ..Default::default()
        }];
        Prepared::new(foon, &kitchen, &[], None, None).unwrap()
    }

    #[test]
    fn results_do_not_depend_on_the_thread_count() {
        let foon = chain(60);
        let prep = prepared(&foon);
        let goals: Vec<u32> = (0..foon.object_count() as u32).rev().collect();
        for method in [
            Method::Ids,
            Method::GreedyInputs,
            Method::OptimalUnits,
            Method::Bfs,
        ] {
            let query = Query {
                method,
                ..Query::default()
            };
            let strip = |v: Vec<Plan>| {
                v.into_iter()
                    .map(|mut p| {
                        p.seconds = 0.0;
                        p
                    })
                    .collect::<Vec<_>>()
            };
            let one = strip(
                plan_batch(&foon, &prep, &goals, query, &BatchOptions::threads(Some(1))).unwrap(),
            );
            assert!(one.iter().any(|p| p.solved) && one.iter().any(|p| !p.solved));
            for threads in [Some(2), Some(7), None] {
                let got = strip(
                    plan_batch(&foon, &prep, &goals, query, &BatchOptions::threads(threads))
                        .unwrap(),
                );
                assert_eq!(got, one, "{method:?} with {threads:?} threads");
            }
        }
    }

    #[test]
    fn threads_are_capped_and_zero_is_an_error() {
        let o = BatchOptions::threads(Some(1_000_000));
        assert_eq!(o.workers(1_000_000).unwrap(), max_threads());
        assert_eq!(o.workers(1).unwrap(), 1);
        assert_eq!(BatchOptions::threads(Some(1)).workers(50).unwrap(), 1);
        assert_eq!(BatchOptions::threads(Some(3)).workers(0).unwrap(), 1);
        let e = BatchOptions::threads(Some(0)).workers(5).unwrap_err();
        assert_eq!(e.to_string(), "threads must be at least 1, not 0");
    }

    #[test]
    fn a_cancelled_batch_stops_with_cancelled() {
        let foon = chain(20);
        let prep = prepared(&foon);
        let goals: Vec<u32> = (0..foon.object_count() as u32).collect();
        let yes = || true;
        for threads in [Some(1), Some(2)] {
            let opts = BatchOptions::threads(threads).with_cancel(&yes);
            let e = plan_batch(&foon, &prep, &goals, Query::default(), &opts).unwrap_err();
            assert!(matches!(e, Error::Cancelled), "{e}");
        }
    }

    #[test]
    fn the_first_failing_goal_gives_the_error() {
        let foon = chain(20);
        let prep = prepared(&foon);
        let n = foon.object_count() as u32;
        // Two bad goals: the earlier one is reported, whatever the thread count.
        let mut goals: Vec<u32> = (0..n).collect();
        goals.insert(5, n + 7);
        goals.push(n + 9);
        for threads in [Some(1), Some(2)] {
            let e = plan_batch(
                &foon,
                &prep,
                &goals,
                Query::default(),
                &BatchOptions::threads(threads),
            )
            .unwrap_err();
            assert_eq!(e.to_string(), format!("object {} is out of range", n + 7));
        }
    }

    #[test]
    fn planning_inputs_of_another_foon_are_refused() {
        let (a, b) = (chain(3), chain(4));
        let prep = prepared(&a);
        let e = plan_batch(&b, &prep, &[0], Query::default(), &BatchOptions::default());
        assert!(matches!(e, Err(Error::Invalid(_))));
    }
}
