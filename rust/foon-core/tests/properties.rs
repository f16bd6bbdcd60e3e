//! Property tests on generated FOONs (proptest): writing and parsing back gives the same
//! graph; every sound method returns a valid tree in execution order or fails exactly when
//! the goal is not derivable, with an explanation; `ids` trees have the goal's rank as height.

use std::fmt::Write as _;

use foon_core::search::{Compat, Context, Count, Method, Query};
use foon_core::{ObjectSpec, ParseOptions, parse_foon, write};
use proptest::prelude::*;

const LABELS: [&str; 5] = ["egg", "bowl", "ice", "tea", "pan"];
const STATES: [&str; 4] = ["whole", "hot", "empty", "mixed"];
const UTENSILS: [&str; 2] = ["bowl", "pan"];

#[derive(Debug, Clone)]
struct Obj {
    label: usize,
    states: Vec<usize>,
    ingredient: Option<usize>,
    container: Option<usize>,
}

fn obj() -> impl Strategy<Value = Obj> {
    (
        0..LABELS.len(),
        prop::collection::vec(0..STATES.len(), 0..3),
        prop::option::of(0..LABELS.len()),
        prop::option::of(0..UTENSILS.len()),
    )
        .prop_map(|(label, states, ingredient, container)| Obj {
            label,
            states,
            ingredient,
            container,
        })
}

fn text_of(o: &Obj, out: &mut String) {
    let _ = writeln!(out, "O\t{}", LABELS[o.label]);
    for &s in &o.states {
        let _ = writeln!(out, "S\t{}", STATES[s]);
    }
    if let Some(i) = o.ingredient {
        let _ = writeln!(out, "S\tcontains\t{{{}}}", LABELS[i]);
    }
    if let Some(c) = o.container {
        let _ = writeln!(out, "S\tin\t[{}]", UTENSILS[c]);
    }
}

/// A FOON text of 1..20 units over a small vocabulary: shared objects, cycles, self-loops,
/// duplicates and several producers per object all occur.
fn foon_text() -> impl Strategy<Value = String> {
    prop::collection::vec(
        (
            prop::collection::vec(obj(), 0..3),
            0..3usize,
            prop::collection::vec(obj(), 1..3),
        ),
        1..20,
    )
    .prop_map(|units| {
        let mut t = String::from("//\n");
        for (ins, m, outs) in units {
            for o in &ins {
                text_of(o, &mut t);
            }
            let _ = writeln!(t, "M\t{}", ["pour", "mix", "heat"][m]);
            for o in &outs {
                text_of(o, &mut t);
            }
            t.push_str("//\n");
        }
        t
    })
}

/// The FOON of `text`, with the objects that `kmask` picks (cyclically, by id) as the
/// kitchen, the utensils and the motion rates.
fn planning_inputs(
    text: &str,
    kmask: &[bool],
) -> (
    foon_core::Foon,
    Vec<ObjectSpec>,
    Vec<String>,
    foon_core::MotionRates,
) {
    let foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
    let kitchen: Vec<ObjectSpec> = (0..foon.object_count() as u32)
        .filter(|&o| kmask[o as usize % kmask.len()])
        .map(|o| ObjectSpec::of_object(&foon, o))
        .collect();
    let utensils: Vec<String> = UTENSILS.iter().map(|s| (*s).to_owned()).collect();
    let rates = foon_core::MotionRates::from_pairs([
        ("pour".to_owned(), 0.9),
        ("mix".to_owned(), 0.5),
        ("heat".to_owned(), 0.7),
    ])
    .unwrap();
    (foon, kitchen, utensils, rates)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, .. ProptestConfig::default() })]

    #[test]
    fn write_then_parse_gives_the_same_graph(text in foon_text()) {
        let a = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
        let back = write::foon_text(&a);
        let b = parse_foon(back.as_bytes(), None, ParseOptions::default()).unwrap();
        prop_assert_eq!(a.fu_count(), b.fu_count());
        prop_assert_eq!(a.object_count(), b.object_count());
        for f in 0..a.fu_count() as u32 {
            prop_assert_eq!(a.inputs(f), b.inputs(f));
            prop_assert_eq!(a.outputs(f), b.outputs(f));
            prop_assert_eq!(a.motion_text(f), b.motion_text(f));
        }
        prop_assert_eq!(write::foon_text(&b), back);
    }

    #[test]
    fn sound_methods_are_valid_or_explained(text in foon_text(), kmask in prop::collection::vec(any::<bool>(), 64), goal_pick in any::<prop::sample::Index>()) {
        let (foon, kitchen, utensils, rates) = planning_inputs(&text, &kmask);
        let n = foon.object_count();
        prop_assume!(n > 0);
        let ctx = Context::new(&foon, &kitchen, &utensils, Some(&rates), None).unwrap();
        let goal = goal_pick.index(n) as u32;
        let rank = ctx.ranks().rank(goal);
        for method in [Method::Ids, Method::GreedySuccess, Method::GreedyInputs, Method::OptimalSuccess, Method::OptimalUnits, Method::OptimalInputs] {
            let plan = ctx.plan(goal, Query { method, compat: Compat::Sound, count: Count::Nodes }).unwrap();
            prop_assert_eq!(plan.solved, rank.is_some(), "{:?}", method);
            if plan.solved {
                // In execution order, and the goal is made.
                prop_assert!(ctx.first_unavailable(&plan.units).is_none(), "{:?} order", method);
                prop_assert!(ctx.is_valid(&plan.units, goal));
                let h = plan.height.unwrap();
                prop_assert!(h >= rank.unwrap(), "{:?} lower than the rank", method);
                if method == Method::Ids {
                    prop_assert_eq!(h, rank.unwrap());
                }
            } else {
                let e = plan.explanation.unwrap();
                prop_assert!(!e.missing.is_empty() || !e.cycle.is_empty());
            }
        }
        // Course methods never panic and list units that exist.
        for method in [Method::Bfs, Method::GreedySuccess, Method::GreedyInputs] {
            let plan = ctx.plan(goal, Query { method, compat: Compat::Course, count: Count::Ingredients }).unwrap();
            prop_assert!(plan.units.iter().all(|&f| (f as usize) < foon.fu_count()));
        }
    }

    #[test]
    fn sparse_search_state_gives_the_same_plans(text in foon_text(), kmask in prop::collection::vec(any::<bool>(), 64), goal_pick in any::<prop::sample::Index>()) {
        // Searches keep their per-object state in arrays on small FOONs and in hash maps on
        // large ones; forcing the hash maps on a small FOON must change nothing.
        let (foon, kitchen, utensils, rates) = planning_inputs(&text, &kmask);
        let n = foon.object_count();
        prop_assume!(n > 0);
        let dense = Context::new(&foon, &kitchen, &utensils, Some(&rates), None).unwrap();
        let sparse = Context::new(&foon, &kitchen, &utensils, Some(&rates), None).unwrap().with_scratch_limit(0);
        let goal = goal_pick.index(n) as u32;
        for method in Method::ALL {
            for compat in [Compat::Sound, Compat::Course] {
                for count in [Count::Nodes, Count::Ingredients] {
                    let q = Query { method, compat, count };
                    match (dense.plan(goal, q), sparse.plan(goal, q)) {
                        (Ok(mut a), Ok(mut b)) => {
                            a.seconds = 0.0;
                            b.seconds = 0.0;
                            prop_assert_eq!(a, b, "{:?}", q);
                        }
                        (a, b) => prop_assert_eq!(a.is_err(), b.is_err(), "{:?}", q),
                    }
                }
            }
        }
    }
}
