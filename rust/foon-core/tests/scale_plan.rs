//! What the sound methods compute once per kitchen (each optimal objective's costs and
//! choices, the shopping costs of explanations, the choices of `ids`) gives the plans of the
//! search from each goal ([`Context::from_scratch`]), on generated FOONs with cycles,
//! self-loops, duplicates and shared intermediates, with kitchens of several densities and
//! rate tables that are complete, partial (some motion without a rate) or a default rate.

use std::fmt::Write as _;

use foon_core::search::{Compat, Context, Count, Method, Plan, Query};
use foon_core::{MotionRates, ObjectSpec, ParseOptions, parse_foon};
use proptest::prelude::*;

mod common;
use common::generate::{UTENSILS, foon_text};

/// Everything of a plan but its time and its implementation-defined counts.
fn key(p: &Plan) -> String {
    format!(
        "{} {:?} {:?} {:?} {:?} {:?} {:?} {:?} {} {:?}",
        p.solved,
        p.units,
        p.unresolved,
        p.explanation,
        p.height,
        p.success.map(f64::to_bits),
        p.unrated,
        p.cost.map(f64::to_bits),
        p.leaf_inputs,
        p.query,
    )
}

fn queries() -> Vec<Query> {
    let mut out = Vec::new();
    for method in [
        Method::Ids,
        Method::GreedySuccess,
        Method::GreedyInputs,
        Method::OptimalSuccess,
        Method::OptimalUnits,
        Method::OptimalInputs,
    ] {
        for count in [Count::Nodes, Count::Ingredients] {
            out.push(Query {
                method,
                compat: Compat::Sound,
                count,
            });
        }
    }
    // The course loop reads the greedy choices computed once per kitchen too.
    for method in [Method::Bfs, Method::GreedySuccess, Method::GreedyInputs] {
        for count in [Count::Nodes, Count::Ingredients] {
            out.push(Query {
                method,
                compat: Compat::Course,
                count,
            });
        }
    }
    out
}

/// Plans every goal with every method on one context (so what is computed once is
/// reused from the second goal on) and from scratch, and compares the results (errors by
/// their message).
fn same_plans(text: &str, density: u8, kseed: &[u8], rates: u8) -> Result<usize, TestCaseError> {
    let foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
    let kitchen: Vec<ObjectSpec> = (0..foon.object_count() as u32)
        .filter(|&o| kseed[o as usize % kseed.len()] % 4 < density)
        .map(|o| ObjectSpec::of_object(&foon, o))
        .collect();
    let utensils: Vec<String> = UTENSILS.iter().map(|s| (*s).to_owned()).collect();
    // Rate 0 and rate 1 make ties and infinite costs; `cut` has no rate in the partial table.
    let all = [("pour", 0.9), ("mix", 0.5), ("heat", 1.0), ("cut", 0.0)];
    let pairs: Vec<(String, f64)> = all
        .iter()
        .take(if rates == 1 { 3 } else { 4 })
        .map(|&(m, r)| (m.to_owned(), r))
        .collect();
    let table = MotionRates::from_pairs(pairs).unwrap();
    let (table, default) = match rates {
        0 | 1 => (Some(&table), None),
        2 => (None, Some(0.5)),
        _ => (None, None),
    };
    let shared = Context::new(&foon, &kitchen, &utensils, table, default).unwrap();
    let scratch = Context::new(&foon, &kitchen, &utensils, table, default)
        .unwrap()
        .from_scratch();
    let mut failed = 0;
    for q in queries() {
        for goal in 0..foon.object_count() as u32 {
            let a = shared
                .plan(goal, q)
                .map(|p| key(&p))
                .map_err(|e| e.to_string());
            let b = scratch
                .plan(goal, q)
                .map(|p| key(&p))
                .map_err(|e| e.to_string());
            prop_assert_eq!(&a, &b, "{:?} goal {}\n{}", q, goal, text);
            failed += usize::from(a.is_ok_and(|k| k.starts_with("false")));
        }
    }
    Ok(failed)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn what_is_computed_once_gives_the_plans_from_scratch(
        text in foon_text(),
        density in 0..5u8,
        kseed in prop::collection::vec(any::<u8>(), 1..64),
        rates in 0..4u8,
    ) {
        same_plans(&text, density, &kseed, rates)?;
    }
}

/// The generated cases reach failures, explanations with missing items, and trees.
#[test]
fn the_comparison_reaches_failures_and_trees() {
    let mut text = String::from("//\n");
    for i in 0..30 {
        let _ = write!(
            text,
            "O\tegg\nS\ts{i}\nO\tsalt\nS\ts{}\nM\tmix\nO\tegg\nS\ts{}\n//\n",
            i % 7,
            i + 1
        );
        // A cycle and a self-loop.
        let _ = write!(
            text,
            "O\tegg\nS\ts{}\nM\theat\nO\tegg\nS\ts{i}\n//\nO\tegg\nS\ts{i}\nM\tpour\nO\tegg\nS\ts{i}\n//\n",
            i + 2
        );
    }
    let mut failed = 0;
    for density in 0..5 {
        for rates in 0..4 {
            failed += same_plans(&text, density, &[3, 1, 0, 2, 1], rates).unwrap();
        }
    }
    assert!(failed > 0);
}
