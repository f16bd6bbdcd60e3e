//! Loads the real FOON data set (from `../shared` beside the repository) and checks the
//! counts and the course golden outputs. Skips with a message when the data is absent
//! (it is always present in CI, where `FOON_REQUIRE_DATA=1` turns the skip into a failure).

use std::path::{Path, PathBuf};

use foon_core::InputKind;
use foon_core::companion::{load_objects, load_rates, load_utensils};
use foon_core::search::{Compat, Context, Count, Method, Query};
use foon_core::{ParseOptions, load_foon, write};

fn shared() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared");
    if p.join("data/foon/FOON.txt").is_file() {
        return Some(p);
    }
    assert!(
        std::env::var_os("FOON_REQUIRE_DATA").is_none(),
        "FOON_REQUIRE_DATA is set but ../shared/data/foon is missing"
    );
    eprintln!("skipped: ../shared/data/foon (the real FOON data) is not beside the repository");
    None
}

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
