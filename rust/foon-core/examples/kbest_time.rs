//! Times the k best trees in the core alone (no Python):
//! `cargo run --release --example kbest_time -- DATA_DIR [METHOD] [K] [ROUNDS]`
//! with `DATA_DIR` holding `FOON.txt`, `kitchen.json`, `motion.txt`, `utensils.txt` and
//! `goal_nodes_25.json`. The kitchen is prepared and its optimum computed first; prints the
//! time of one optimal plan and of `plan_k` for each of the 25 goals (total over the goals,
//! best round) and their ratio, for the first call on a fresh kitchen and on later calls.
use std::path::Path;
use std::time::Instant;

use foon_core::InputKind;
use foon_core::Prepared;
use foon_core::parse::{load_objects, load_rates, load_utensils};
use foon_core::search::{Context, Method, Query};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let dir = args
        .next()
        .ok_or("usage: kbest_time DATA_DIR [METHOD] [K] [ROUNDS]")?;
    let method: Method = args
        .next()
        .unwrap_or_else(|| "optimal-units".into())
        .parse()?;
    let k: usize = args.next().map_or(Ok(10), |s| s.parse())?;
    let rounds: usize = args.next().map_or(Ok(20), |s| s.parse())?;
    let d = Path::new(&dir);
    let foon = foon_core::load_foon(&d.join("FOON.txt"), foon_core::ParseOptions::default())?;
    let kitchen = load_objects(&d.join("kitchen.json"), InputKind::Kitchen)?;
    let rates = load_rates(&d.join("motion.txt"))?;
    let utensils = load_utensils(&d.join("utensils.txt"))?;
    let specs = load_objects(&d.join("goal_nodes_25.json"), InputKind::Goal)?;
    let query = Query {
        method,
        ..Query::default()
    };
    let fresh = || -> Result<Prepared, Box<dyn std::error::Error>> {
        let prep = Prepared::new(&foon, &kitchen, &utensils, Some(&rates), None)?;
        // The kitchen's optimum, computed once.
        let ctx = Context::with(&foon, &prep)?;
        let g = ctx.goal(&specs[0])?;
        std::hint::black_box(ctx.plan(g, query)?);
        Ok(prep)
    };
    let (mut plan, mut cold, mut warm) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
    for _ in 0..rounds {
        let prep = fresh()?;
        let ctx = Context::with(&foon, &prep)?;
        let goals: Vec<u32> = specs
            .iter()
            .map(|g| ctx.goal(g))
            .collect::<Result<_, _>>()?;
        cold = cold.min(first_kbests(&ctx, &goals, method, k)?);
        warm = warm.min(kbests(&ctx, &goals, method, k)?);
        plan = plan.min(plans(&ctx, &goals, query)?);
    }
    eprintln!(
        "{} k={k}: plan {:.1} µs, k cold {:.1} µs ({:.1}x), k warm {:.1} µs ({:.1}x) (25 goals, best of {rounds})",
        method.as_str(),
        plan * 1e6,
        cold * 1e6,
        cold / plan,
        warm * 1e6,
        warm / plan
    );
    Ok(())
}

/// The time of `plan_k` for every goal, on a kitchen that has not computed them yet.
#[inline(never)]
fn first_kbests(
    ctx: &Context<'_>,
    goals: &[u32],
    method: Method,
    k: usize,
) -> foon_core::Result<f64> {
    let t = Instant::now();
    for &g in goals {
        std::hint::black_box(ctx.plan_k(g, method, k, false)?);
    }
    // Not merged with `kbests` (a profile tells them apart by name).
    std::hint::black_box("first");
    Ok(t.elapsed().as_secs_f64())
}

/// The time of `plan_k` for every goal.
#[inline(never)]
fn kbests(ctx: &Context<'_>, goals: &[u32], method: Method, k: usize) -> foon_core::Result<f64> {
    let t = Instant::now();
    for &g in goals {
        std::hint::black_box(ctx.plan_k(g, method, k, false)?);
    }
    Ok(t.elapsed().as_secs_f64())
}

/// The time of one plan for every goal.
#[inline(never)]
fn plans(ctx: &Context<'_>, goals: &[u32], query: Query) -> foon_core::Result<f64> {
    let t = Instant::now();
    for &g in goals {
        std::hint::black_box(ctx.plan(g, query)?);
    }
    Ok(t.elapsed().as_secs_f64())
}
