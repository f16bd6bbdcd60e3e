//! The k best trees from the kitchen's optimum (the first tree read from it, each subspace
//! solved over its affected objects only) are those of the full Knuth run per subspace
//! ([`Context::from_scratch`]): the same trees, costs, order and counts, with and without
//! `--diverse`, on generated FOONs with cycles, self-loops, duplicates and shared
//! intermediates, and rate tables with ties, rate 1 and rate 0.

use foon_core::search::{Context, Method};
use foon_core::{MotionRates, ObjectSpec, ParseOptions, parse_foon};
use proptest::prelude::*;

mod common;
use common::generate::{UTENSILS, foon_text};

fn same_trees(text: &str, density: u8, kseed: &[u8], rates: u8) -> Result<usize, TestCaseError> {
    let foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
    let kitchen: Vec<ObjectSpec> = (0..foon.object_count() as u32)
        .filter(|&o| kseed[o as usize % kseed.len()] % 4 < density)
        .map(|o| ObjectSpec::of_object(&foon, o))
        .collect();
    let utensils: Vec<String> = UTENSILS.iter().map(|s| (*s).to_owned()).collect();
    // Rate 1 makes units that cost no more than their inputs (the full run per subspace),
    // rate 0 infinite costs; the other tables give units that all cost more.
    let all: &[(&str, f64)] = match rates {
        0 => &[("pour", 0.9), ("mix", 0.5), ("heat", 1.0), ("cut", 0.0)],
        1 => &[("pour", 0.9), ("mix", 0.5), ("heat", 0.5), ("cut", 0.25)],
        _ => &[("pour", 0.5), ("mix", 0.5), ("heat", 0.5), ("cut", 0.5)],
    };
    let pairs: Vec<(String, f64)> = all.iter().map(|&(m, r)| (m.to_owned(), r)).collect();
    let table = MotionRates::from_pairs(pairs).unwrap();
    let shared = Context::new(&foon, &kitchen, &utensils, Some(&table), None).unwrap();
    let scratch = Context::new(&foon, &kitchen, &utensils, Some(&table), None)
        .unwrap()
        .from_scratch();
    let mut trees = 0;
    for method in [
        Method::OptimalSuccess,
        Method::OptimalUnits,
        Method::OptimalInputs,
    ] {
        for goal in 0..foon.object_count() as u32 {
            for (k, diverse) in [(12, false), (4, true)] {
                let key = |ctx: &Context<'_>| {
                    ctx.plan_k(goal, method, k, diverse)
                        .map(|ps| {
                            ps.iter()
                                .map(|p| (p.units.clone(), p.cost, p.expanded))
                                .collect::<Vec<_>>()
                        })
                        .map_err(|e| e.to_string())
                };
                let (a, b) = (key(&shared), key(&scratch));
                prop_assert_eq!(
                    &a,
                    &b,
                    "{:?} goal {} diverse {}\n{}",
                    method,
                    goal,
                    diverse,
                    text
                );
                trees += a.map_or(0, |v| v.len());
            }
        }
    }
    Ok(trees)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn the_optimum_gives_the_trees_of_the_full_runs(
        text in foon_text(),
        density in 0..5u8,
        kseed in prop::collection::vec(any::<u8>(), 1..64),
        rates in 0..3u8,
    ) {
        same_trees(&text, density, &kseed, rates)?;
    }
}
