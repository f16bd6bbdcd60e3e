//! Times planning in the core alone (no Python):
//! `cargo run --release --example plan_time -- DATA_DIR [METHOD] [COMPAT] [ROUNDS]`
//! with `DATA_DIR` holding `FOON.txt`, `kitchen.json`, `motion.txt`, `utensils.txt` and
//! `goal_nodes_25.json`. Prints plans per second on one thread and over all cores.
use std::path::Path;
use std::time::Instant;

use foon_core::InputKind;
use foon_core::Prepared;
use foon_core::parse::{load_objects, load_rates, load_utensils};
use foon_core::search::batch::{BatchOptions, plan_batch};
use foon_core::search::{Context, Count, Query};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let dir = args
        .next()
        .ok_or("usage: plan_time DATA_DIR [METHOD] [COMPAT] [ROUNDS]")?;
    let method = args.next().unwrap_or_else(|| "ids".into()).parse()?;
    let compat = args.next().unwrap_or_else(|| "sound".into()).parse()?;
    let rounds: usize = args.next().map_or(Ok(200), |s| s.parse())?;
    let d = Path::new(&dir);
    let foon = foon_core::load_foon(&d.join("FOON.txt"), foon_core::ParseOptions::default())?;
    let kitchen = load_objects(&d.join("kitchen.json"), InputKind::Kitchen)?;
    let rates = load_rates(&d.join("motion.txt"))?;
    let utensils = load_utensils(&d.join("utensils.txt"))?;
    let prep = Prepared::new(&foon, &kitchen, &utensils, Some(&rates), None)?;
    let ctx = Context::with(&foon, &prep)?;
    let goals: Vec<u32> = load_objects(&d.join("goal_nodes_25.json"), InputKind::Goal)?
        .iter()
        .map(|g| ctx.goal(g))
        .collect::<Result<_, _>>()?;
    let query = Query {
        method,
        compat,
        count: Count::Nodes,
    };
    let batch: Vec<u32> = goals
        .iter()
        .copied()
        .cycle()
        .take(goals.len() * rounds)
        .collect();
    let t = Instant::now();
    for &g in &batch {
        std::hint::black_box(ctx.plan(g, query)?);
    }
    let one = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let opts = BatchOptions::threads(None);
    std::hint::black_box(plan_batch(&foon, &prep, &batch, query, &opts)?);
    let all = t.elapsed().as_secs_f64();
    let n = batch.len() as f64;
    eprintln!(
        "{} plans: 1 thread {:.0}/s, {} threads {:.0}/s",
        batch.len(),
        n / one,
        std::thread::available_parallelism().map_or(1, std::num::NonZero::get),
        n / all
    );
    Ok(())
}
