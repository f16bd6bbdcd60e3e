//! Regression inputs: each feeds one input that once went wrong (a crash or a wrong location,
//! found by fuzzing or by reading the parsers) to the same function, and checks that it now
//! returns `Ok` or a located `Err` without panicking. Fuzz crash inputs are kept as byte
//! strings here (the fuzz corpus and artifacts are not committed).

use foon_core::parse::{parse_objects, parse_rates, parse_utensils};
use foon_core::{Error, InputKind, ParseOptions, parse_foon};

/// The (line, column) of a parse error.
fn at<T: std::fmt::Debug>(r: Result<T, Error>) -> (u64, u32) {
    match r {
        Err(Error::Parse { at, .. }) => (at.line, at.column),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

fn reason<T: std::fmt::Debug>(r: Result<T, Error>) -> String {
    match r {
        Err(Error::Parse { reason, .. }) => reason,
        other => panic!("expected a parse error, got {other:?}"),
    }
}

// --- wrong locations found by reading the parsers ------------------------------------------

/// The rate column was computed from the trimmed motion name, so blanks around the name
/// moved it left of the rate (`  chop  <TAB>x` gave column 6, the rate is at column 10).
#[test]
fn rate_column_counts_blanks_around_the_name() {
    assert_eq!(at(parse_rates(b"  chop  \t-0.1\n", None)), (1, 10));
    assert_eq!(at(parse_rates(b"chop\t0.5\n \tx\n", None)), (2, 1)); // empty name
    assert_eq!(at(parse_rates(b"chop\t0.5\n slice\tfast\n", None)), (2, 8));
}

/// JSON kitchens were read through an untagged enum, so every shape error (a list of
/// strings, a missing label, an unknown field, a wrong type) came out at 1:1 with a generic
/// message instead of the JSON parser's location and reason.
#[test]
fn json_shape_errors_have_the_parsers_location() {
    let k = InputKind::Kitchen;
    let r = parse_objects(b"[\n  \"onion\",\n  \"knife\"\n]\n", None, k);
    assert_eq!(
        at(parse_objects(b"[\n  \"onion\",\n  \"knife\"\n]\n", None, k)),
        (2, 9)
    );
    assert!(reason(r).contains("expected struct ObjectSpec"));
    let missing = b"[\n  {\"label\": \"a\"},\n  {\"states\": [\"x\"]}\n]";
    assert_eq!(at(parse_objects(missing, None, k)), (3, 19));
    assert!(reason(parse_objects(missing, None, k)).contains("missing field `label`"));
    let goal = b"{\n  \"states\": [\"cooked\"]\n}";
    assert_eq!(at(parse_objects(goal, None, InputKind::Goal)), (3, 1));
    // A single object is still a goal, and still not a kitchen.
    assert_eq!(
        parse_objects(b"{\"label\": \"a\"}", None, InputKind::Goal)
            .unwrap()
            .len(),
        1
    );
    assert_eq!(at(parse_objects(b"{\"label\": \"a\"}", None, k)), (1, 1));
}

/// An empty label in a JSON list was reported at 1:1 whatever its place.
#[test]
fn empty_json_label_is_located() {
    let data = b"[\n  {\"label\": \"onion\"},\n  {\"label\": \"\"}\n]\n";
    assert_eq!(at(parse_objects(data, None, InputKind::Kitchen)), (3, 15));
}

/// Invalid UTF-8 in a JSON kitchen was reported at 1:1; it is at the first bad byte.
#[test]
fn invalid_utf8_in_json_is_located() {
    let data = b"[\n  {\"label\": \"onion\"},\n  {\"label\": \"cr\xe8me\"}\n]\n";
    assert_eq!(at(parse_objects(data, None, InputKind::Kitchen)), (3, 16));
}

/// `serde_json` counts columns in bytes; ours are characters (`è` is two bytes).
#[test]
fn json_columns_are_characters() {
    let data = "[\n  {\"label\": \"crème\", \"colour\": \"white\"}\n]\n";
    assert_eq!(
        at(parse_objects(data.as_bytes(), None, InputKind::Kitchen)),
        (2, 29)
    );
}

// --- never a panic ---------------------------------------------------------------------------

/// Inputs around the edges of the line and field handling: each returns Ok or Err.
#[test]
fn edge_inputs_do_not_panic() {
    let inputs: &[&[u8]] = &[
        b"",
        b"\n",
        b"\xEF\xBB\xBF",
        b"\xEF\xBB",
        b"\r",
        b"\t",
        b"O",
        b"O\t",
        b"O\t\t\t",
        b"M\tm\n//",
        b"//\n//\n",
        b"O\ta\nS\t\t{}\nM\tm\n//\n",
        b"O\ta\nS\t\t[]\nM\tm\nO\ta\nS\tx\n//\n",
        b"O\t\xc3\xa9\nS\tx\t{\xc3\xa9\nM\tm\n",
        b"\xff",
        b"O\ta\x00",
        b"[",
        b"{",
        b"[{\"label\": \"a\", \"states\": [\"\xff\"]}]",
    ];
    for data in inputs {
        let _ = parse_foon(data, None, ParseOptions::default());
        let _ = parse_foon(data, None, ParseOptions { strict: true });
        let _ = parse_objects(data, None, InputKind::Kitchen);
        let _ = parse_objects(data, None, InputKind::Goal);
        let _ = parse_rates(data, None);
        let _ = parse_utensils(data, None);
    }
}

// --- planning ----------------------------------------------------------------------------------

use std::fmt::Write as _;

use foon_core::search::{Compat, Context, Count, Method, Query};
use foon_core::{Foon, MotionRates, ObjectSpec};

fn spec(label: &str, state: &str) -> ObjectSpec {
    ObjectSpec {
        label: label.into(),
        states: vec![state.into()],
        ingredients: Vec::new(),
        container: None,
    }
}

fn unit(text: &mut String, ins: &[(&str, &str)], motion: &str, outs: &[(&str, &str)]) {
    for (l, s) in ins {
        let _ = write!(text, "O\t{l}\nS\t{s}\n");
    }
    let _ = writeln!(text, "M\t{motion}");
    for (l, s) in outs {
        let _ = write!(text, "O\t{l}\nS\t{s}\n");
    }
    text.push_str("//\n");
}

/// A ladder (as `tests/workloads.py` builds it): the dish is made first from rung 1, rung `i`
/// in `width` ways from rung `i + 1` and a kitchen item, the last rung from the dish (on the
/// path), and the dish last from kitchen items alone.
fn ladder(levels: usize, width: usize) -> String {
    let k: Vec<String> = (0..=width).map(|j| format!("k{j}")).collect();
    let rung: Vec<String> = (0..=levels + 1).map(|i| format!("r{i}")).collect();
    let mut t = String::new();
    unit(
        &mut t,
        &[("rung", &rung[1]), ("spice", &k[0])],
        "mix",
        &[("dish", "done")],
    );
    for i in 1..=levels {
        let below = if i < levels {
            ("rung", rung[i + 1].as_str())
        } else {
            ("dish", "done")
        };
        for kj in k.iter().take(width) {
            unit(
                &mut t,
                &[below, ("spice", kj)],
                "mix",
                &[("rung", &rung[i])],
            );
        }
    }
    unit(
        &mut t,
        &[("spice", &k[0]), ("spice", &k[1])],
        "mix",
        &[("dish", "done")],
    );
    t
}

fn load(text: &str) -> Foon {
    parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap()
}

fn query(method: Method, compat: Compat) -> Query {
    Query {
        method,
        compat,
        count: Count::Nodes,
    }
}

/// The sound greedy search never remembered a failure: on a ladder of `n` rungs it expanded
/// `2^n` objects (28 rungs took 35 s). The trees are unchanged: the dish's plain unit.
#[test]
fn greedy_search_is_polynomial_on_a_ladder() {
    for (levels, width) in [(20, 2), (12, 3)] {
        let foon = load(&ladder(levels, width));
        let kitchen: Vec<ObjectSpec> = (0..=width)
            .map(|j| spec("spice", &format!("k{j}")))
            .collect();
        let ctx = Context::new(&foon, &kitchen, &[], None, Some(0.5)).unwrap();
        let goal = ctx.goal(&spec("dish", "done")).unwrap();
        let last = foon.fu_count() as u32 - 1;
        for method in [Method::GreedySuccess, Method::GreedyInputs] {
            let plan = ctx.plan(goal, query(method, Compat::Sound)).unwrap();
            assert_eq!(plan.units, [last], "{method:?} {levels}x{width}");
            assert!(
                plan.expanded < 10 * foon.fu_count() as u64,
                "{method:?} {levels}x{width}: {} expanded",
                plan.expanded
            );
        }
    }
}

/// A shape on which every path gives the bottom rung a different set of dependencies
/// (`expo_units` of `tests/workloads.py`): the dish is made first from rung 1; rung `i` from
/// `a{i}` or `b{i}`, each made from rung `i + 1`; the bottom rung from any `a{j}` or from the
/// dish; the dish last from kitchen items alone.
fn expo(levels: usize) -> String {
    let (k0, k1) = (("spice", "k0"), ("spice", "k1"));
    let r: Vec<String> = (0..=levels + 1).map(|i| format!("r{i}")).collect();
    let a: Vec<String> = (0..=levels).map(|i| format!("a{i}")).collect();
    let b: Vec<String> = (0..=levels).map(|i| format!("b{i}")).collect();
    let mut t = String::new();
    unit(&mut t, &[("rung", &r[1]), k0], "mix", &[("dish", "done")]);
    for i in 1..=levels {
        unit(&mut t, &[("a", &a[i]), k0], "mix", &[("rung", &r[i])]);
        unit(&mut t, &[("b", &b[i]), k1], "mix", &[("rung", &r[i])]);
        unit(&mut t, &[("rung", &r[i + 1]), k0], "mix", &[("a", &a[i])]);
        unit(&mut t, &[("rung", &r[i + 1]), k1], "mix", &[("b", &b[i])]);
    }
    for ai in a.iter().skip(1) {
        unit(&mut t, &[("a", ai), k0], "mix", &[("rung", &r[levels + 1])]);
    }
    unit(
        &mut t,
        &[("dish", "done"), k0],
        "mix",
        &[("rung", &r[levels + 1])],
    );
    unit(&mut t, &[k0, k1], "mix", &[("dish", "done")]);
    t
}

/// Remembered failures did not help on `expo`: the bottom rung failed with another set of
/// dependencies on every path, so the search expanded `2^(n+2) - 2` objects (16 levels took
/// 35 s), and the records of one object were scanned one by one. No object below the dish can
/// lead to a choice in the first epoch: the dead region is pruned.
#[test]
fn greedy_search_prunes_dead_regions() {
    for levels in [12, 20, 200, 2_000] {
        let foon = load(&expo(levels));
        let kitchen = [spec("spice", "k0"), spec("spice", "k1")];
        let ctx = Context::new(&foon, &kitchen, &[], None, Some(0.5)).unwrap();
        let goal = ctx.goal(&spec("dish", "done")).unwrap();
        let last = foon.fu_count() as u32 - 1;
        for method in [Method::GreedySuccess, Method::GreedyInputs] {
            let plan = ctx.plan(goal, query(method, Compat::Sound)).unwrap();
            assert_eq!(plan.units, [last], "{method:?} {levels}");
            assert!(
                plan.expanded < 50 * foon.fu_count() as u64,
                "{method:?} {levels}: {} expanded",
                plan.expanded
            );
        }
    }
}

/// `bfs` ran the course loop but reported compat "sound" (and `solved` for trees that cannot
/// run) when asked for the sound form.
#[test]
fn bfs_is_always_labelled_course() {
    // The dish's first producer needs the dish itself: the course tree cannot run.
    let text = "O\tdish\nS\tdone\nM\tmix\nO\tdish\nS\tdone\n//\n";
    let foon = load(text);
    let ctx = Context::new(&foon, &[], &[], None, None).unwrap();
    for compat in [Compat::Sound, Compat::Course] {
        let plan = ctx.plan(0, query(Method::Bfs, compat)).unwrap();
        assert_eq!(plan.query.compat, Compat::Course);
        assert_eq!(plan.units, [0]);
        assert!(!ctx.is_valid(&plan.units, 0));
    }
}

/// A tree whose motion is missing from a given rate table got `success: None` from `bfs` and
/// `ids` without saying why; methods that choose by rate fail with the motion's name.
#[test]
fn a_missing_rate_is_named() {
    // a (kitchen) -chop-> b -mix-> c; "chop" has no rate.
    let text = "O\ta\nS\tx\nM\tchop\nO\tb\nS\tx\n//\nO\tb\nS\tx\nM\tmix\nO\tc\nS\tx\n//\n";
    let foon = load(text);
    let kitchen = [spec("a", "x")];
    let rates = MotionRates::from_pairs([("mix".to_owned(), 0.5)]).unwrap();
    let ctx = Context::new(&foon, &kitchen, &[], Some(&rates), None).unwrap();
    let c = ctx.goal(&spec("c", "x")).unwrap();
    for q in [
        query(Method::Bfs, Compat::Course),
        query(Method::Ids, Compat::Sound),
        query(Method::Ids, Compat::Course),
        query(Method::GreedyInputs, Compat::Sound),
        query(Method::GreedyInputs, Compat::Course),
        query(Method::OptimalUnits, Compat::Sound),
        query(Method::OptimalInputs, Compat::Sound),
    ] {
        let plan = ctx.plan(c, q).unwrap();
        assert_eq!(plan.units, [0, 1], "{q:?}");
        assert_eq!((plan.success, plan.unrated), (None, Some(0)), "{q:?}");
    }
    for q in [
        query(Method::GreedySuccess, Compat::Sound),
        query(Method::GreedySuccess, Compat::Course),
        query(Method::OptimalSuccess, Compat::Sound),
    ] {
        match ctx.plan(c, q) {
            Err(Error::MissingRate { motion }) => assert_eq!(motion, "chop", "{q:?}"),
            other => panic!("{q:?}: {other:?}"),
        }
    }
    // A default rate fills the gap; without a table nothing is missing.
    let with_default = Context::new(&foon, &kitchen, &[], Some(&rates), Some(0.25)).unwrap();
    let no_table = Context::new(&foon, &kitchen, &[], None, None).unwrap();
    for method in Method::ALL {
        let plan = with_default.plan(c, query(method, Compat::Sound)).unwrap();
        assert_eq!(
            (plan.success, plan.unrated),
            (Some(0.125), None),
            "{method:?}"
        );
        if !method.uses_rates() {
            let plan = no_table.plan(c, query(method, Compat::Sound)).unwrap();
            assert_eq!((plan.success, plan.unrated), (None, None), "{method:?}");
        }
    }
}
