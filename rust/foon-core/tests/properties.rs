//! Property tests on generated FOONs (proptest): writing and parsing back gives the same
//! graph; every sound method returns a valid tree in execution order or fails exactly when
//! the goal is not derivable, with an explanation; `ids` trees have the goal's rank as height;
//! the sound greedy search (which remembers failures) gives the trees of its plain,
//! recursive definition.

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

/// The sound greedy search exactly as `docs/METHODS.md` defines it (recursive, no memory of
/// failures), then the tree of its choices in depth-first post-order. `None` when the goal does
/// not resolve.
fn plain_greedy(ctx: &Context<'_>, goal: u32, method: Method) -> Option<Vec<u32>> {
    fn resolve(
        ctx: &Context<'_>,
        method: Method,
        o: u32,
        path: &mut Vec<u32>,
        choice: &mut Vec<Option<u32>>,
    ) -> bool {
        if ctx.in_kitchen(o) || choice[o as usize].is_some() {
            return true;
        }
        if !ctx.ranks().is_derivable(o) {
            return false;
        }
        let mut cands = ctx.foon.producers(o).to_vec();
        match method {
            Method::GreedySuccess => cands.sort_by(|&a, &b| {
                let (ra, rb) = (ctx.rate(a).unwrap(), ctx.rate(b).unwrap());
                rb.partial_cmp(&ra).unwrap().then(a.cmp(&b))
            }),
            _ => cands.sort_by_key(|&f| (ctx.foon.inputs(f).len(), f)),
        }
        for f in cands {
            let needed = ctx.needed(f);
            if needed.iter().any(|&x| x == o || path.contains(&x)) {
                continue;
            }
            path.push(o);
            let ok = needed
                .iter()
                .all(|&x| resolve(ctx, method, x, path, choice));
            path.pop();
            if ok {
                choice[o as usize] = Some(f);
                return true;
            }
        }
        false
    }
    fn emit(
        ctx: &Context<'_>,
        o: u32,
        choice: &[Option<u32>],
        seen: &mut Vec<bool>,
        out: &mut Vec<u32>,
    ) {
        if ctx.in_kitchen(o) || seen[o as usize] {
            return;
        }
        seen[o as usize] = true;
        let f = choice[o as usize].unwrap();
        if out.contains(&f) {
            return;
        }
        for &x in ctx.needed(f) {
            emit(ctx, x, choice, seen, out);
        }
        if !out.contains(&f) {
            out.push(f);
        }
    }
    let n = ctx.foon.object_count();
    let mut choice = vec![None; n];
    if !resolve(ctx, method, goal, &mut Vec::new(), &mut choice) {
        return None;
    }
    let mut out = Vec::new();
    emit(ctx, goal, &choice, &mut vec![false; n], &mut out);
    Some(out)
}

/// A ladder of `levels` rungs and `width` ways per rung whose bottom needs rung `back_to` (0:
/// the goal), its units rotated left by `rotate` (which moves the ties), and a plain producer of
/// the goal and of rung `back_to`.
fn ladder_text(levels: usize, width: usize, back_to: usize, rotate: usize) -> String {
    let mut units = vec![format!(
        "O\trung\nS\tr1\nO\tk\nS\tk0\nM\tmix\nO\tdish\nS\tdone\n//\n"
    )];
    for i in 1..=levels {
        let below = if i < levels {
            format!("O\trung\nS\tr{}\n", i + 1)
        } else if back_to == 0 {
            "O\tdish\nS\tdone\n".to_owned()
        } else {
            format!("O\trung\nS\tr{back_to}\n")
        };
        for j in 0..width {
            units.push(format!(
                "{below}O\tk\nS\tk{j}\nM\tmix\nO\trung\nS\tr{i}\n//\n"
            ));
        }
    }
    if back_to > 0 {
        units.push(format!(
            "O\tk\nS\tk0\nO\tk\nS\tk1\nM\theat\nO\trung\nS\tr{back_to}\n//\n"
        ));
    }
    units.push("O\tk\nS\tk0\nO\tk\nS\tk1\nM\tpour\nO\tdish\nS\tdone\n//\n".to_owned());
    let r = rotate % units.len();
    units.rotate_left(r);
    units.concat()
}

/// The shape of `expo_units` in `tests/workloads.py` (every path gives the bottom rung another
/// set of dependencies; no object below the dish can lead to a choice), with a chain of `chain`
/// objects `c{i}` from the kitchen to the dish (so that the pruning must keep a live region),
/// plus `extra` units (an output and one to three inputs, indices into the shape's objects and
/// the two kitchen items), its units rotated left by `rotate`.
fn expo_text(levels: usize, chain: usize, extra: &[(usize, Vec<usize>)], rotate: usize) -> String {
    let o = |l: &str, s: String| format!("O\t{l}\nS\t{s}\n");
    let r = |i: usize| o("rung", format!("r{i}"));
    let a = |i: usize| o("a", format!("a{i}"));
    let b = |i: usize| o("b", format!("b{i}"));
    let (k0, k1) = (o("k", "k0".into()), o("k", "k1".into()));
    let dish = o("dish", "done".into());
    let u = |ins: &[&String], out: &String| {
        let ins: String = ins.iter().map(|s| s.as_str()).collect();
        format!("{ins}M\tmix\n{out}//\n")
    };
    let mut units = vec![u(&[&r(1), &k0], &dish)];
    for i in 1..=levels {
        units.push(u(&[&a(i), &k0], &r(i)));
        units.push(u(&[&b(i), &k1], &r(i)));
        units.push(u(&[&r(i + 1), &k0], &a(i)));
        units.push(u(&[&r(i + 1), &k1], &b(i)));
    }
    for i in 1..=levels {
        units.push(u(&[&a(i), &k0], &r(levels + 1)));
    }
    units.push(u(&[&dish, &k0], &r(levels + 1)));
    let c = |i: usize| o("c", format!("c{i}"));
    if chain > 0 {
        units.push(u(&[&c(1), &k1], &dish));
        for i in 1..chain {
            units.push(u(&[&c(i + 1), &k0], &c(i)));
        }
        units.push(u(&[&k1, &k0], &c(chain)));
    }
    units.push(u(&[&k0, &k1], &dish));
    // Objects for the extra units: the dish, the rungs, the a's, b's and c's, then the kitchen.
    let mut objs = vec![dish.clone()];
    objs.extend((1..=levels + 1).map(r));
    objs.extend((1..=levels).map(a));
    objs.extend((1..=levels).map(b));
    objs.extend((1..=chain).map(c));
    let made = objs.len();
    objs.extend([k0, k1]);
    for (out, ins) in extra {
        let ins: Vec<&String> = ins.iter().map(|&i| &objs[i % objs.len()]).collect();
        units.push(u(&ins, &objs[out % made]));
    }
    let n = units.len();
    units.rotate_left(rotate % n);
    units.concat()
}

/// A small dense graph as a FOON: node `i` is `n i`, made from each input list of
/// `producers[i]` (node 0, `n 0`, is the kitchen; its producers are dropped).
fn graph_text(producers: &[Vec<Vec<usize>>]) -> String {
    let mut t = String::new();
    for (o, ways) in producers.iter().enumerate().skip(1) {
        for ins in ways {
            for x in ins {
                let _ = write!(t, "O\tn\nS\t{x}\n");
            }
            let _ = write!(t, "M\tmix\nO\tn\nS\t{o}\n//\n");
        }
    }
    t
}

/// Every derivable object as a goal: the greedy search gives the plain definition's tree.
fn assert_greedy_is_plain(text: &str, kmask: &[bool]) -> Result<(), TestCaseError> {
    let (foon, kitchen, utensils, rates) = planning_inputs(text, kmask);
    let ctx = Context::new(&foon, &kitchen, &utensils, Some(&rates), None).unwrap();
    for goal in 0..foon.object_count() as u32 {
        if ctx.in_kitchen(goal) || !ctx.ranks().is_derivable(goal) {
            continue;
        }
        for method in [Method::GreedySuccess, Method::GreedyInputs] {
            let q = Query {
                method,
                compat: Compat::Sound,
                count: Count::Nodes,
            };
            let plan = ctx.plan(goal, q).unwrap();
            prop_assert_eq!(
                Some(plan.units),
                plain_greedy(&ctx, goal, method),
                "{:?} goal {}",
                method,
                goal
            );
        }
    }
    Ok(())
}

/// A graph on which a memory of failures that ignored the path would give another tree for
/// node 4 (found by a random search; also in `tests/test_adversarial.py`).
#[test]
fn a_failure_that_depends_on_the_path_is_not_reused_off_it() {
    let g: Vec<Vec<Vec<usize>>> = vec![
        vec![],
        vec![vec![3], vec![2], vec![0]],
        vec![vec![6, 3, 1], vec![1, 7], vec![6, 5, 7]],
        vec![vec![6], vec![3, 6, 2]],
        vec![vec![1, 3, 8]],
        vec![vec![0, 6]],
        vec![vec![3], vec![0, 4, 3], vec![7, 9]],
        vec![vec![9, 3], vec![1]],
        vec![vec![0, 6], vec![2, 4, 7], vec![0]],
        vec![vec![1, 7], vec![8], vec![6, 0, 5]],
    ];
    let text = graph_text(&g);
    let foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
    let kmask: Vec<bool> = (0..foon.object_count() as u32)
        .map(|o| foon.text(foon.states(o)[0]) == "0")
        .collect();
    assert_greedy_is_plain(&text, &kmask).unwrap();
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

    #[test]
    fn greedy_gives_the_plain_definitions_trees(text in foon_text(), kmask in prop::collection::vec(any::<bool>(), 64)) {
        assert_greedy_is_plain(&text, &kmask)?;
    }

    #[test]
    fn greedy_gives_the_plain_definitions_trees_on_dense_graphs(producers in prop::collection::vec(prop::collection::vec(prop::collection::vec(0..8usize, 1..4), 1..4), 3..9)) {
        // Failures that depend on the path they happened on are common in such graphs.
        let text = graph_text(&producers);
        let foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
        let kmask: Vec<bool> = (0..foon.object_count() as u32).map(|o| foon.text(foon.states(o)[0]) == "0").collect();
        assert_greedy_is_plain(&text, &kmask)?;
    }

    #[test]
    fn greedy_gives_the_plain_definitions_trees_on_dead_regions(levels in 1..11usize, chain in 0..4usize, extra in prop::collection::vec((0..64usize, prop::collection::vec(0..64usize, 1..4)), 0..4), rotate in 0..80usize) {
        // Deep enough for the dead region to be computed and pruned (over 256 expansions).
        let text = expo_text(levels, chain, &extra, rotate);
        let foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
        let kmask: Vec<bool> = (0..foon.object_count() as u32).map(|o| foon.label_text(o) == "k").collect();
        assert_greedy_is_plain(&text, &kmask)?;
    }

    #[test]
    fn greedy_gives_the_plain_definitions_trees_on_ladders(levels in 1..9usize, width in 1..4usize, back in 0..9usize, rotate in 0..40usize) {
        // The kitchen is every `k` object (their labels are not in LABELS, so by name).
        let text = ladder_text(levels, width, back % (levels + 1), rotate);
        let foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
        let kmask: Vec<bool> = (0..foon.object_count() as u32).map(|o| foon.label_text(o) == "k").collect();
        assert_greedy_is_plain(&text, &kmask)?;
    }
}
