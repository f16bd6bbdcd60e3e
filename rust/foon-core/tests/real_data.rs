//! Loads the real FOON data set (from `../shared` beside the repository) and checks the
//! counts and the course golden outputs. Skips with a message when the data is absent
//! (it is always present in CI, where `FOON_REQUIRE_DATA=1` turns the skip into a failure).

use std::fmt::Write as _;

use foon_core::InputKind;
use foon_core::parse::{load_objects, load_rates, load_utensils};
use foon_core::search::{Compat, Context, Count, Method, Query};
use foon_core::{ParseOptions, load_foon, write};

mod common;
use common::{all_plans, shared};

#[test]
fn course_foon_counts() {
    let Some(s) = shared() else { return };
    let foon = load_foon(&s.join("data/foon/FOON.txt"), ParseOptions::default()).unwrap();
    let st = foon.stats();
    assert_eq!(st.functional_units, 2376);
    assert_eq!(st.objects, 4305);
    assert_eq!(st.produced_objects, 3371);
    assert_eq!(st.motions, 129);
    assert!(foon.warnings().is_empty());
}

#[test]
fn course_golden_outputs() {
    let Some(s) = shared() else { return };
    let d = s.join("data/foon");
    let foon = load_foon(&d.join("FOON.txt"), ParseOptions::default()).unwrap();
    let kitchen = load_objects(&d.join("kitchen.json"), InputKind::Kitchen).unwrap();
    let goals = load_objects(&d.join("goal_nodes.json"), InputKind::Goal).unwrap();
    let rates = load_rates(&d.join("motion.txt")).unwrap();
    let utensils = load_utensils(&d.join("utensils.txt")).unwrap();
    let ctx = Context::new(&foon, &kitchen, &utensils, Some(&rates), None).unwrap();
    for (dir, method) in [
        ("bfs", Method::Bfs),
        ("greedy-success", Method::GreedySuccess),
        ("greedy-inputs", Method::GreedyInputs),
    ] {
        for g in &goals {
            let goal = ctx.goal(g).unwrap();
            let q = Query {
                method,
                compat: Compat::Course,
                count: Count::Nodes,
            };
            let plan = ctx.plan(goal, q).unwrap();
            assert!(plan.solved, "{dir} {}", g.label);
            let text = write::tree_text(&foon, &plan.units);
            let name = format!("{}.txt", g.label.replace(' ', "_"));
            let want = std::fs::read_to_string(s.join("data/golden-course").join(dir).join(&name))
                .unwrap();
            assert_eq!(text, want, "{dir}/{name}");
        }
    }
}

#[test]
fn plans_do_not_depend_on_the_size_of_the_foon() {
    // The course FOON followed by 7 renamed copies of itself (34,440 objects: the searches keep
    // their state in hash maps, not arrays). The copies share nothing with the kitchen or the
    // goals, and the first copy keeps the course ids, so every plan must be the same.
    let Some(s) = shared() else { return };
    let d = s.join("data/foon");
    let text = std::fs::read_to_string(d.join("FOON.txt")).unwrap();
    let mut big = text.clone();
    for k in 1..8 {
        for line in text.lines() {
            match line.strip_prefix("O\t") {
                Some(label) => writeln!(big, "O\t{label} copy{k}").unwrap(),
                None => writeln!(big, "{line}").unwrap(),
            }
        }
    }
    let course = foon_core::parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
    let large = foon_core::parse_foon(big.as_bytes(), None, ParseOptions::default()).unwrap();
    assert_eq!(large.object_count(), 8 * course.object_count());
    let kitchen = load_objects(&d.join("kitchen.json"), InputKind::Kitchen).unwrap();
    let goals = load_objects(&d.join("goal_nodes_25.json"), InputKind::Goal).unwrap();
    let rates = load_rates(&d.join("motion.txt")).unwrap();
    let utensils = load_utensils(&d.join("utensils.txt")).unwrap();
    let small_ctx = Context::new(&course, &kitchen, &utensils, Some(&rates), None).unwrap();
    let large_ctx = Context::new(&large, &kitchen, &utensils, Some(&rates), None).unwrap();
    let ids: Vec<u32> = goals.iter().map(|g| small_ctx.goal(g).unwrap()).collect();
    let want = all_plans(&small_ctx, &ids);
    assert_eq!(all_plans(&large_ctx, &ids), want);
    // The same FOON with the hash-map state forced: the same plans, for every object as goal
    // with the non-optimal methods (the optimal ones searched from the kitchen are covered by
    // the 25 goals above).
    let sparse = Context::new(&course, &kitchen, &utensils, Some(&rates), None)
        .unwrap()
        .with_scratch_limit(0);
    assert_eq!(all_plans(&sparse, &ids), want);
    for method in [
        Method::Bfs,
        Method::Ids,
        Method::GreedySuccess,
        Method::GreedyInputs,
    ] {
        for compat in [Compat::Sound, Compat::Course] {
            let q = Query {
                method,
                compat,
                count: Count::Nodes,
            };
            for g in 0..course.object_count() as u32 {
                let (mut a, mut b) = (small_ctx.plan(g, q).unwrap(), sparse.plan(g, q).unwrap());
                a.seconds = 0.0;
                b.seconds = 0.0;
                assert_eq!(a, b, "{q:?} goal {g}");
            }
        }
    }
}
