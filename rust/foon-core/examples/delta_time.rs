//! Times a kitchen changed by a delta, prepared from the base kitchen's preparation against
//! prepared from scratch, in the core alone (no Python):
//! `cargo run --release --example delta_time -- FOON KITCHEN MOTIONS GOALS ADDED [REMOVED] [ROUNDS] [incremental]`
//! with `FOON` a FOON file (text or `.foonidx`), `KITCHEN` a kitchen file, `MOTIONS` a motion
//! table, `GOALS` a goal file (the first goal the base kitchen can make and lacks is planned)
//! and `ADDED`, `REMOVED` files of object ids, one per line (`-` for none). The base computes
//! the ranks, the choices of `ids` and the optimal objectives (a plan of `ids` and one of
//! `optimal-units`); each side then prepares the new kitchen and makes the same two plans;
//! the incremental side also runs its updates to the end (`Prepared::finish_updates`). Prints
//! the best time of each over `ROUNDS` (5) rounds, alternated. With `incremental`, each round
//! is the incremental side's delta and two plans alone (no preparation from scratch, no
//! updates run to the end): a loop to count what one delta costs, under a profiler (the
//! difference between two numbers of rounds).
use std::path::Path;
use std::time::Instant;

use foon_core::parse::{load_objects, load_rates};
use foon_core::search::{Compat, Context, Count, Method, Query};
use foon_core::{Foon, InputKind, Prepared};

fn ids(path: &str) -> Result<Vec<u32>, Box<dyn std::error::Error>> {
    if path == "-" {
        return Ok(Vec::new());
    }
    let text = std::fs::read_to_string(path)?;
    Ok(text
        .split_whitespace()
        .map(str::parse)
        .collect::<Result<_, _>>()?)
}

fn warm(foon: &Foon, prep: &Prepared, goal: u32) -> Result<(), foon_core::Error> {
    let ctx = Context::with(foon, prep)?;
    for method in [Method::Ids, Method::OptimalUnits] {
        let query = Query {
            method,
            compat: Compat::Sound,
            count: Count::Nodes,
        };
        std::hint::black_box(ctx.plan(goal, query)?);
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let usage =
        "usage: delta_time FOON KITCHEN MOTIONS GOALS ADDED [REMOVED] [ROUNDS] [incremental]";
    let mut args = std::env::args().skip(1);
    let foon_path = args.next().ok_or(usage)?;
    let kitchen_path = args.next().ok_or(usage)?;
    let motions_path = args.next().ok_or(usage)?;
    let goals_path = args.next().ok_or(usage)?;
    let added = ids(&args.next().ok_or(usage)?)?;
    let removed = ids(&args.next().unwrap_or_else(|| "-".into()))?;
    let rounds: usize = args.next().map_or(Ok(5), |s| s.parse())?;
    let only_incremental = match args.next().as_deref() {
        None => false,
        Some("incremental") => true,
        Some(_) => return Err(usage.into()),
    };
    let foon = if foon_path.ends_with(".foonidx") {
        Foon::open_index(Path::new(&foon_path))?
    } else {
        foon_core::load_foon(Path::new(&foon_path), foon_core::ParseOptions::default())?
    };
    let kitchen = load_objects(Path::new(&kitchen_path), InputKind::Kitchen)?;
    let rates = load_rates(Path::new(&motions_path))?;
    let base = Prepared::new(&foon, &kitchen, &[], Some(&rates), None)?;
    let ctx = Context::with(&foon, &base)?;
    let mut goal = None;
    for spec in load_objects(Path::new(&goals_path), InputKind::Goal)? {
        let g = ctx.goal(&spec)?;
        if ctx.ranks().is_derivable(g) && !base.in_kitchen(g) {
            goal = Some(g);
            break;
        }
    }
    drop(ctx);
    let goal = goal.ok_or("the base kitchen makes none of the goals")?;
    warm(&foon, &base, goal)?;
    let mut objects: Vec<u32> = base
        .kitchen_objects()
        .iter()
        .copied()
        .filter(|o| !removed.contains(o))
        .chain(added.iter().copied())
        .collect();
    objects.sort_unstable();
    objects.dedup();
    let (mut scratch, mut delta, mut whole) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
    if only_incremental {
        for _ in 0..rounds {
            let t = Instant::now();
            let inc = base.with_delta(&foon, &added, &removed)?;
            warm(&foon, &inc, goal)?;
            delta = delta.min(t.elapsed().as_secs_f64());
        }
        eprintln!("incremental {:.2} ms", delta * 1e3);
        return Ok(());
    }
    for _ in 0..rounds {
        let t = Instant::now();
        let fresh = Prepared::with_base(&foon, std::sync::Arc::clone(base.base()), &objects)?;
        warm(&foon, &fresh, goal)?;
        scratch = scratch.min(t.elapsed().as_secs_f64());
        drop(fresh);
        let t = Instant::now();
        let inc = base.with_delta(&foon, &added, &removed)?;
        warm(&foon, &inc, goal)?;
        delta = delta.min(t.elapsed().as_secs_f64());
        inc.finish_updates(&foon, &|| false)?;
        whole = whole.min(t.elapsed().as_secs_f64());
        drop(inc);
    }
    eprintln!(
        "{} added, {} removed: from scratch {:.1} ms; incremental {:.2} ms ({:.0}x), its updates \
         run to the end {:.2} ms ({:.0}x)",
        added.len(),
        removed.len(),
        scratch * 1e3,
        delta * 1e3,
        scratch / delta,
        whole * 1e3,
        scratch / whole,
    );
    Ok(())
}
