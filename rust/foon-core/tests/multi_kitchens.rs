//! Many kitchens at once (`foon_core::multi`): every lane of the 64-kitchen pass equals its
//! kitchen's own preparation (derivability and ranks), on generated FOONs with random kitchens
//! (cycles, self-loops, duplicate units) and on the course FOON, for 1, 63, 64, 65 and 200
//! kitchens; a kitchen prepared on a shared base plans as one prepared from scratch.

use std::sync::Arc;

use foon_core::InputKind;
use foon_core::multi::{derivable_many, prepare_many, ranks_many};
use foon_core::parse::{load_objects, load_rates, load_utensils};
use foon_core::search::batch::BatchOptions;
use foon_core::{Foon, ParseOptions, Prepared, PreparedBase, parse_foon};
use proptest::prelude::*;

mod common;
use common::generate::{UTENSILS, foon_text};
use common::{all_plans, shared};

/// Checks every lane against `Prepared::with_objects` + ranks for each kitchen.
fn check_lanes(foon: &Foon, utensils: &[String], kitchens: &[Vec<u32>], threads: Option<usize>) {
    let base = Arc::new(PreparedBase::new(foon, utensils, None, None).unwrap());
    let ks: Vec<&[u32]> = kitchens.iter().map(Vec::as_slice).collect();
    let opts = BatchOptions::threads(threads);
    let d = derivable_many(foon, &base, &ks, &opts).unwrap();
    let r = ranks_many(foon, &base, &ks, &opts).unwrap();
    let preps = prepare_many(foon, &base, &ks, &opts).unwrap();
    assert_eq!(d.kitchen_count(), kitchens.len());
    for (k, kitchen) in kitchens.iter().enumerate() {
        let own = Prepared::with_objects(foon, kitchen, utensils, None, None).unwrap();
        let ctx = foon_core::Context::with(foon, &own).unwrap();
        let want = ctx.ranks();
        let on_base = foon_core::Context::with(foon, &preps[k]).unwrap();
        assert_eq!(on_base.ranks(), want, "kitchen {k}");
        assert_eq!(&r.ranks(k), want, "kitchen {k}");
        for o in 0..foon.object_count() as u32 {
            assert_eq!(
                d.is_derivable(k, o),
                want.is_derivable(o),
                "kitchen {k}, object {o}"
            );
            assert_eq!(r.rank(k, o), want.rank(o), "kitchen {k}, object {o}");
        }
    }
}

/// `count` kitchens from a seed: each object in with probability about `density / 8`.
fn kitchens(n: u32, count: usize, seed: u64, density: u64) -> Vec<Vec<u32>> {
    let mut s = seed | 1;
    let mut next = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    (0..count)
        .map(|_| (0..n).filter(|_| next() % 8 < density).collect())
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn lanes_equal_each_kitchen_on_generated_foons(
        text in foon_text(),
        seed in any::<u64>(),
        density in 0u64..5,
        count in prop::sample::select(vec![1usize, 63, 64, 65, 200]),
        use_utensils in any::<bool>(),
        threads in prop::sample::select(vec![Some(1usize), Some(2)]),
    ) {
        let foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
        let utensils: Vec<String> = if use_utensils {
            UTENSILS.iter().map(|u| (*u).to_owned()).collect()
        } else {
            Vec::new()
        };
        let ks = kitchens(foon.object_count() as u32, count, seed, density);
        check_lanes(&foon, &utensils, &ks, threads);
    }

    /// A kitchen prepared on a shared base gives the plans of one prepared from scratch, for
    /// every method (the greedy orders are computed once per base and shared).
    #[test]
    fn a_shared_base_plans_as_from_scratch(text in foon_text(), seed in any::<u64>()) {
        let foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
        let utensils: Vec<String> = UTENSILS.iter().map(|u| (*u).to_owned()).collect();
        let base = Arc::new(PreparedBase::new(&foon, &utensils, None, Some(0.5)).unwrap());
        let goals: Vec<u32> = (0..foon.object_count() as u32).collect();
        for kitchen in kitchens(foon.object_count() as u32, 3, seed, 3) {
            let own = Prepared::with_objects(&foon, &kitchen, &utensils, None, Some(0.5)).unwrap();
            let shared = Prepared::with_base(&foon, Arc::clone(&base), &kitchen).unwrap();
            let a = all_plans(&foon_core::Context::with(&foon, &own).unwrap(), &goals);
            let b = all_plans(&foon_core::Context::with(&foon, &shared).unwrap(), &goals);
            prop_assert_eq!(a, b);
        }
    }
}

#[test]
fn lanes_equal_each_kitchen_on_the_course_foon() {
    let Some(s) = shared() else { return };
    let d = s.join("data/foon");
    let foon = foon_core::load_foon(&d.join("FOON.txt"), ParseOptions::default()).unwrap();
    let kitchen = load_objects(&d.join("kitchen.json"), InputKind::Kitchen).unwrap();
    let goals = load_objects(&d.join("goal_nodes_25.json"), InputKind::Goal).unwrap();
    let utensils = load_utensils(&d.join("utensils.txt")).unwrap();
    let _ = load_rates(&d.join("motion.txt")).unwrap();
    let items: Vec<u32> = kitchen.iter().filter_map(|i| i.find_in(&foon)).collect();
    let goal_ids: Vec<u32> = goals.iter().filter_map(|g| g.find_in(&foon)).collect();
    assert_eq!(goal_ids.len(), 25);
    // The course kitchen; each goal's kitchen without one item (the goal's own id decides
    // which), with the goal added; then subsets of the course kitchen.
    let mut ks: Vec<Vec<u32>> = vec![items.clone()];
    for &g in &goal_ids {
        let mut k = items.clone();
        k.remove(g as usize % k.len());
        ks.push(k.clone());
        k.push(g);
        ks.push(k);
    }
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    while ks.len() < 200 {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        let keep = seed;
        ks.push(
            items
                .iter()
                .enumerate()
                .filter(|(i, _)| (keep >> (i % 64)) & 1 == 1 || i % 5 == 0)
                .map(|(_, &o)| o)
                .collect(),
        );
    }
    for count in [1, 63, 64, 65, 200] {
        check_lanes(&foon, &utensils, &ks[..count], Some(2));
    }
    // Some goals are derivable in the course kitchen and some are not.
    let base = PreparedBase::new(&foon, &utensils, None, None).unwrap();
    let one = derivable_many(&foon, &base, &[&items], &BatchOptions::default()).unwrap();
    let made = goal_ids.iter().filter(|&&g| one.is_derivable(0, g)).count();
    assert!(made > 0 && made < 25, "{made} of 25 goals derivable");
}
