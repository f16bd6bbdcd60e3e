//! Incremental kitchens on the course FOON (`Prepared::with_delta`, `with_kitchen`,
//! `with_items`): a kitchen given as the course kitchen's preparation plus a delta gives the
//! ranks and every method's plans of a preparation from scratch, whether the base had
//! computed its parts or not.

use std::sync::Arc;

use foon_core::parse::{load_objects, load_rates, load_utensils};
use foon_core::search::Context;
use foon_core::{InputKind, ParseOptions, Prepared, load_foon};

mod common;
use common::{all_plans, shared};

#[test]
fn course_deltas_give_the_preparation_from_scratch() {
    let Some(s) = shared() else { return };
    let d = s.join("data/foon");
    let foon = load_foon(&d.join("FOON.txt"), ParseOptions::default()).unwrap();
    let kitchen = load_objects(&d.join("kitchen.json"), InputKind::Kitchen).unwrap();
    let rates = load_rates(&d.join("motion.txt")).unwrap();
    let utensils = load_utensils(&d.join("utensils.txt")).unwrap();
    let n = foon.object_count();
    let goals: Vec<u32> = (0..n as u32).step_by(23).collect();
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = |k: usize| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % k as u64) as usize
    };
    for round in 0..12 {
        let base = Prepared::new(&foon, &kitchen, &utensils, Some(&rates), None).unwrap();
        let warm = round % 3 != 2;
        if warm {
            all_plans(&Context::with(&foon, &base).unwrap(), &goals);
        }
        let own = base.kitchen_objects().to_vec();
        let size = [1, 3, 10][round % 3];
        let added: Vec<u32> = (0..size).map(|_| next(n) as u32).collect();
        let removed: Vec<u32> = if round % 4 == 0 {
            Vec::new()
        } else {
            (0..size).map(|_| own[next(own.len())]).collect()
        };
        let inc = base.with_delta(&foon, &added, &removed).unwrap();
        let mut new: Vec<u32> = own
            .iter()
            .copied()
            .filter(|o| !removed.contains(o))
            .chain(added.iter().copied())
            .collect();
        new.sort_unstable();
        new.dedup();
        assert_eq!(inc.kitchen_objects(), &new[..]);
        let fresh = Prepared::with_base(&foon, Arc::clone(base.base()), &new).unwrap();
        let (a, b) = (
            Context::with(&foon, &inc).unwrap(),
            Context::with(&foon, &fresh).unwrap(),
        );
        assert_eq!(a.ranks(), b.ranks(), "round {round}");
        assert_eq!(
            all_plans(&a, &goals),
            all_plans(&b, &goals),
            "round {round}"
        );
        // The whole new kitchen gives the same preparation.
        let whole = base.with_kitchen(&foon, &new).unwrap();
        assert_eq!(whole.kitchen_objects(), &new[..]);
        let c = Context::with(&foon, &whole).unwrap();
        assert_eq!(all_plans(&c, &goals[..20]), all_plans(&b, &goals[..20]));
    }
    // Kitchen items: removing the first three items of the course kitchen.
    let base = Prepared::new(&foon, &kitchen, &utensils, Some(&rates), None).unwrap();
    all_plans(&Context::with(&foon, &base).unwrap(), &goals);
    let inc = base.with_items(&foon, &[], &kitchen[..3]).unwrap();
    let fresh = Prepared::new(&foon, &kitchen[3..], &utensils, Some(&rates), None).unwrap();
    let (a, b) = (
        Context::with(&foon, &inc).unwrap(),
        Context::with(&foon, &fresh).unwrap(),
    );
    assert_eq!(all_plans(&a, &goals), all_plans(&b, &goals));
}
