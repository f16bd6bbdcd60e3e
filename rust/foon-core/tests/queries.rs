//! Batches of query rows (`foon_core::queries`): kitchen sets read from every form (errors
//! with their file, line and column), serialised and fingerprinted; every answer of
//! `run_queries` equal to planning its row alone, for 1 and 2 threads, on generated FOONs
//! (cycles, self-loops, duplicate units) and on the course FOON; bad rows as failure codes.

use std::fmt::Write as _;
use std::sync::Arc;

use foon_core::cache::PreparedCache;
use foon_core::queries::{
    Answer, DeltaPreparation, Failure, GoalText, KitchenSet, QueryRow, RunOptions,
};
use foon_core::search::batch::BatchOptions;
use foon_core::{
    Compat, Context, Error, Foon, Kitchen, Method, ObjectSpec, ParseOptions, Prepared, Query,
    parse_foon,
};
use proptest::prelude::*;

mod common;
use common::generate::{LABELS, STATES, UTENSILS, foon_text};
use common::shared;

fn kitchen(text: &str) -> Kitchen {
    Kitchen::parse(text.as_bytes(), None).unwrap()
}

/// A chain of units: `item` in state `s0` makes it in `s1`, ..., `s10` makes `s11`.
fn chain_foon() -> Foon {
    let mut text = String::new();
    for i in 0..11 {
        let _ = writeln!(
            text,
            "O\titem\nS\ts{i}\nM\tstep\nO\titem\nS\ts{}\n//",
            i + 1
        );
    }
    parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap()
}

fn parse_err(text: &str) -> String {
    KitchenSet::parse(text.as_bytes(), Some("set.json".as_ref()))
        .unwrap_err()
        .to_string()
}

#[test]
fn kitchen_sets_are_read_from_each_form() {
    let s = KitchenSet::parse(
        br#"{"a": [{"label": "egg", "states": ["whole"]}], "b": [], "c": [{"label": "tea"}]}"#,
        None,
    )
    .unwrap();
    assert_eq!(s.ids(), ["a", "b", "c"]);
    assert_eq!(s.get("a").unwrap().unwrap().len(), 1);
    assert!(s.get("b").unwrap().unwrap().is_empty());
    assert!(s.get("d").is_none());

    let d = KitchenSet::parse(
        br#"{"base": [{"label": "egg"}, {"label": "tea"}],
             "kitchens": {"x": {"add": [{"label": "ice"}]}, "y": {"remove": [{"label": "egg"}]},
                          "z": {}}}"#,
        None,
    )
    .unwrap();
    assert_eq!(d.ids(), ["x", "y", "z"]);
    let base = kitchen(r#"[{"label": "egg"}, {"label": "tea"}]"#);
    let want_x = kitchen(r#"[{"label": "egg"}, {"label": "tea"}, {"label": "ice"}]"#);
    assert_eq!(
        d.get("x").unwrap().unwrap().fingerprint(),
        want_x.fingerprint()
    );
    assert_eq!(
        d.get("y").unwrap().unwrap().fingerprint(),
        kitchen(r#"[{"label": "tea"}]"#).fingerprint()
    );
    assert_eq!(
        d.get("z").unwrap().unwrap().fingerprint(),
        base.fingerprint()
    );
    let e = d.entry(d.position("x").unwrap());
    let delta = e.delta().unwrap();
    assert_eq!(delta.base.fingerprint(), base.fingerprint());
    assert_eq!(delta.add.len(), 1);
    assert!(delta.remove.is_empty());
}

#[test]
fn kitchen_sets_are_read_from_folders_and_relative_bases() {
    let dir = std::env::temp_dir().join(format!("foon-kset-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("ks")).unwrap();
    std::fs::write(dir.join("ks/one.json"), r#"[{"label": "egg"}]"#).unwrap();
    std::fs::write(dir.join("ks/two.txt"), "O\ttea\nS\thot\n").unwrap();
    std::fs::write(dir.join("ks/.hidden"), "junk").unwrap();
    let s = KitchenSet::load(&dir.join("ks")).unwrap();
    assert_eq!(s.ids(), ["one", "two"]);
    assert_eq!(
        s.get("two").unwrap().unwrap().fingerprint(),
        kitchen(r#"[{"label": "tea", "states": ["hot"]}]"#).fingerprint()
    );
    // Sub-folders (and links to them) are skipped; links to files are read.
    std::fs::create_dir_all(dir.join("ks/sub")).unwrap();
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(dir.join("ks/sub"), dir.join("ks/folder-link")).unwrap();
        std::os::unix::fs::symlink(dir.join("ks/one.json"), dir.join("ks/three.json")).unwrap();
    }
    let s = KitchenSet::load(&dir.join("ks")).unwrap();
    let want: &[&str] = if cfg!(unix) {
        &["one", "three", "two"]
    } else {
        &["one", "two"]
    };
    assert_eq!(s.ids(), want);
    // A broken link, or a pipe, is an error naming it (not a kitchen left out, nor a read
    // that waits for a writer).
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(dir.join("gone.json"), dir.join("ks/four.json")).unwrap();
        let e = KitchenSet::load(&dir.join("ks")).unwrap_err().to_string();
        assert!(
            e.starts_with(&dir.join("ks/four.json").display().to_string()),
            "{e}"
        );
        std::fs::remove_file(dir.join("ks/four.json")).unwrap();
        if std::process::Command::new("mkfifo")
            .arg(dir.join("ks/five.json"))
            .status()
            .is_ok_and(|s| s.success())
        {
            let e = KitchenSet::load(&dir.join("ks")).unwrap_err().to_string();
            assert!(
                e.contains("five.json: not a kitchen file (not a regular file)"),
                "{e}"
            );
            std::fs::remove_file(dir.join("ks/five.json")).unwrap();
        }
    }
    std::fs::write(dir.join("ks/one.txt"), "O\tice\n").unwrap();
    let e = KitchenSet::load(&dir.join("ks")).unwrap_err().to_string();
    assert!(e.contains("kitchen id 'one' is given twice"), "{e}");

    std::fs::write(dir.join("base.json"), r#"[{"label": "egg"}]"#).unwrap();
    std::fs::write(
        dir.join("set.json"),
        r#"{"base": "base.json", "kitchens": {"k": {"add": [{"label": "tea"}]}}}"#,
    )
    .unwrap();
    let s = KitchenSet::load(&dir.join("set.json")).unwrap();
    assert_eq!(s.get("k").unwrap().unwrap().len(), 2);
    std::fs::write(
        dir.join("bad.json"),
        "{\"base\": \"base.json\",\n \"kitchens\": {\"k\": {\"add\": [{\"label\": 3}]}}}",
    )
    .unwrap();
    let e = KitchenSet::load(&dir.join("bad.json"))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!("{}:2:", dir.join("bad.json").display())),
        "{e}"
    );
    // A base that cannot be read: an error of the set, at its 'base' field, naming both.
    std::fs::write(
        dir.join("lost.json"),
        "{\"kitchens\": {\"k\": {}},\n \"base\": \"gone.json\"}",
    )
    .unwrap();
    let e = KitchenSet::load(&dir.join("lost.json"))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!(
            "{}:2:10: kitchen error: the base kitchen 'gone.json' cannot be read ({}: ",
            dir.join("lost.json").display(),
            dir.join("gone.json").display()
        )),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_kitchen_sets_name_file_line_and_column() {
    let e = parse_err("{\"a\": [],\n \"a\": []}");
    assert_eq!(
        e,
        "set.json:2:2: kitchen error: kitchen id 'a' is given twice"
    );
    let e = parse_err("{\"a\": [],\n  \"b\": [{\"label\": \"egg\", \"colour\": 1}]}");
    assert!(e.starts_with("set.json:2:"), "{e}");
    assert!(e.contains("colour"), "{e}");
    let e = parse_err("[1, 2]");
    assert_eq!(
        e,
        "set.json:1:1: kitchen error: expected a JSON object of kitchens"
    );
    let e = parse_err("{\"a\": {\"label\": \"egg\"}}");
    assert_eq!(
        e,
        "set.json:1:7: kitchen error: expected a JSON list of objects"
    );
    let e = parse_err("{\"base\": [], \"kitchens\": {\"k\": {\"plus\": []}}}");
    assert_eq!(
        e,
        "set.json:1:33: kitchen error: unknown field 'plus' (expected add, remove)"
    );
    let e = parse_err("{\"base\": [], \"other\": {}}");
    assert!(e.contains("unknown field 'other'"), "{e}");
    let e = parse_err("{\"base\": []}");
    assert!(e.contains("needs both 'base' and 'kitchens'"), "{e}");
    let e = parse_err("{\"a\": [}");
    assert!(e.starts_with("set.json:1:8: kitchen error:"), "{e}");
    let e = KitchenSet::from_kitchens([
        ("a".to_owned(), Arc::new(Kitchen::new())),
        ("a".to_owned(), Arc::new(Kitchen::new())),
    ])
    .unwrap_err();
    assert_eq!(e.to_string(), "kitchen id 'a' is given twice");
}

#[test]
fn kitchen_sets_round_trip_through_bytes_and_have_fixed_fingerprints() {
    let plain = KitchenSet::parse(
        br#"{"a": [{"label": "egg", "states": ["whole"]}], "b": []}"#,
        None,
    )
    .unwrap();
    let delta = KitchenSet::parse(
        br#"{"base": [{"label": "egg"}], "kitchens": {"x": {"add": [{"label": "ice"}]},
             "y": {"remove": [{"label": "egg"}]}}}"#,
        None,
    )
    .unwrap();
    for s in [&plain, &delta] {
        let b = s.to_bytes();
        let back = KitchenSet::from_bytes(&b).unwrap();
        assert_eq!(back.ids(), s.ids());
        assert_eq!(back.fingerprint().unwrap(), s.fingerprint().unwrap());
        for i in 0..s.len() {
            assert_eq!(
                back.entry(i).delta().is_some(),
                s.entry(i).delta().is_some(),
                "kitchen {i}"
            );
        }
        // Every truncation is an error, never a panic.
        for cut in 0..b.len() {
            assert!(KitchenSet::from_bytes(&b[..cut]).is_err(), "cut at {cut}");
        }
    }
    // Fingerprints are compared across machines: a change here is a format change.
    assert_eq!(
        format!("{:032x}", KitchenSet::new().fingerprint().unwrap()),
        format!(
            "{:032x}",
            KitchenSet::from_bytes(&KitchenSet::new().to_bytes())
                .unwrap()
                .fingerprint()
                .unwrap()
        )
    );
    let order = KitchenSet::parse(
        br#"{"b": [], "a": [{"label": "egg", "states": ["whole"]}]}"#,
        None,
    )
    .unwrap();
    assert_ne!(order.fingerprint().unwrap(), plain.fingerprint().unwrap());
    assert_eq!(
        format!("{:032x}", plain.fingerprint().unwrap()),
        "9dae9bc182b58d65ec0fb8b3bb423a41"
    );
}

/// The answer of one row planned alone (the reference): the rules of the public per-query
/// calls, spelled out.
fn alone(foon: &Foon, set: &KitchenSet, row: &QueryRow<'_>, utensils: &[String]) -> Answer {
    let fail = |f: Failure| (f, None::<String>);
    let r: Result<Answer, (Failure, Option<String>)> = (|| {
        let k = set
            .get(row.kitchen.ok_or(fail(Failure::UnknownKitchen))?)
            .ok_or(fail(Failure::UnknownKitchen))?
            .unwrap();
        let method: Method = row
            .method
            .ok_or(fail(Failure::UnknownMethod))?
            .parse()
            .map_err(|_| fail(Failure::UnknownMethod))?;
        let opts = foon_core::queries::RowOptions::parse(row.options, method)
            .map_err(|e| (Failure::BadOption, Some(e.to_string())))?;
        let q = Query {
            method,
            compat: opts.compat,
            count: opts.count,
        };
        q.check()
            .map_err(|e| (Failure::BadOption, Some(e.to_string())))?;
        let goal = GoalText::parse(row.goal.ok_or(fail(Failure::BadGoal))?)
            .map_err(|e| (Failure::BadGoal, Some(e.to_string())))?;
        let ids = k.match_at_level(foon, opts.level).unwrap();
        let prep = Prepared::with_objects(foon, &ids, utensils, None, opts.default_rate)
            .unwrap()
            .at_level(opts.level);
        let ctx = Context::with(foon, &prep).unwrap().with_shared(opts.shared);
        let g = goal.resolve(&ctx, opts.level).map_err(|e| match e {
            Error::GoalNotFound { .. } => fail(Failure::GoalNotFound),
            Error::GoalAmbiguous { .. } => fail(Failure::GoalAmbiguous),
            e => (Failure::Error, Some(e.to_string())),
        })?;
        let plan = ctx.plan(g, q).map_err(|e| match e {
            Error::MissingRate { .. } => (Failure::MissingRate, Some(e.to_string())),
            e => (Failure::Error, Some(e.to_string())),
        })?;
        let describe = |ids: &[u32]| -> Vec<String> {
            ids.iter()
                .map(|&o| ObjectSpec::of_object(foon, o).describe())
                .collect()
        };
        let (failure, missing) = if plan.solved {
            (None, vec![])
        } else if plan.query.compat == Compat::Course {
            (Some(Failure::Unresolved), describe(&plan.unresolved))
        } else {
            let e = plan.explanation.clone().unwrap();
            let f = if e.cycle.is_empty() {
                Failure::NotDerivable
            } else {
                Failure::Cycle
            };
            (Some(f), describe(&e.missing))
        };
        Ok(Answer {
            plan: Some(plan),
            failure,
            missing,
            message: None,
        })
    })();
    r.unwrap_or_else(|(f, message)| Answer {
        plan: None,
        failure: Some(f),
        missing: vec![],
        message,
    })
}

fn strip(mut a: Vec<Answer>) -> Vec<Answer> {
    for x in &mut a {
        if let Some(p) = &mut x.plan {
            p.seconds = 0.0;
        }
    }
    a
}

/// Checks `run_queries` against each row alone, for 1 and 2 threads and a fresh or a warm
/// cache, with delta kitchens prepared incrementally and from scratch.
fn check(foon: &Foon, set: &KitchenSet, rows: &[QueryRow<'_>], utensils: &[String]) {
    let want: Vec<Answer> = rows.iter().map(|r| alone(foon, set, r, utensils)).collect();
    let want = strip(want);
    for deltas in [DeltaPreparation::Incremental, DeltaPreparation::FromScratch] {
        let cache = PreparedCache::default();
        for threads in [Some(1), Some(2), Some(2), Some(1)] {
            let opts = RunOptions {
                batch: BatchOptions::threads(threads),
                utensils,
                rates: None,
                default_rate: None,
                deltas,
            };
            let got =
                strip(foon_core::queries::run_queries(foon, set, rows, &cache, &opts).unwrap());
            assert_eq!(got.len(), want.len());
            for (i, (g, w)) in got.iter().zip(&want).enumerate() {
                assert_eq!(
                    g.failure, w.failure,
                    "row {i} ({:?}), {threads:?} threads, {deltas:?}",
                    rows[i]
                );
                assert_eq!(g.missing, w.missing, "row {i}, {deltas:?}");
                assert_eq!(g.plan, w.plan, "row {i}, {deltas:?}");
                if w.message.is_some() {
                    assert_eq!(g.message, w.message, "row {i}, {deltas:?}");
                }
            }
        }
    }
}

const OPTIONS: [Option<&str>; 9] = [
    None,
    Some(""),
    Some("null"),
    Some(r#"{"compat": "course"}"#),
    Some(r#"{"count": "ingredients", "level": 2}"#),
    Some(r#"{"level": 1}"#),
    Some(r#"{"default_rate": 0.5}"#),
    Some(r#"{"objective": "units", "node_limit": 50}"#),
    Some(r#"{"level": 7}"#),
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn every_answer_is_its_row_planned_alone(
        text in foon_text(),
        kitchens in prop::collection::vec(prop::collection::vec((0usize..6, 0usize..3), 0..6), 1..5),
        picks in prop::collection::vec((0usize..7, 0usize..12, 0usize..10, 0usize..9), 1..40),
    ) {
        let foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
        let utensils: Vec<String> = UTENSILS.iter().map(|s| (*s).to_owned()).collect();
        let ks: Vec<(String, Arc<Kitchen>)> = kitchens
            .iter()
            .enumerate()
            .map(|(i, items)| {
                let specs: Vec<ObjectSpec> = items
                    .iter()
                    .map(|&(l, s)| ObjectSpec {
                        label: LABELS[l].into(),
                        states: vec![STATES[s].into()],
                        ..Default::default()
                    })
                    .collect();
                (format!("k{i}"), Arc::new(Kitchen::from_specs(&specs).unwrap()))
            })
            .collect();
        let set = KitchenSet::from_kitchens(ks).unwrap();
        let kids: Vec<String> = (0..7).map(|i| format!("k{i}")).collect();
        let mut goals: Vec<String> = LABELS.iter().map(|l| (*l).to_owned()).collect();
        for l in LABELS {
            goals.push(format!(r#"{{"label": "{l}", "states": ["{}"]}}"#, STATES[l.len() % 3]));
        }
        goals.truncate(11);
        goals.push("{bad".into());
        let mut methods: Vec<String> = Method::ALL.iter().map(|m| m.as_str().to_owned()).collect();
        methods.push("nope".into());
        methods.push("IDS".into());
        let rows: Vec<QueryRow<'_>> = picks
            .iter()
            .map(|&(k, g, m, o)| QueryRow {
                kitchen: Some(kids[k].as_str()),
                goal: Some(goals[g].as_str()),
                method: Some(methods[m].as_str()),
                options: OPTIONS[o],
            })
            .collect();
        check(&foon, &set, &rows, &utensils);
    }
}

/// An item of a generated kitchen: a label, a state, and a second state (none when 3).
type Item = (usize, usize, usize);

fn item_specs(items: &[Item]) -> Vec<ObjectSpec> {
    items
        .iter()
        .map(|&(l, s, t)| {
            let mut states = vec![STATES[s].to_owned()];
            if t < STATES.len() && t != s {
                states.push(STATES[t].to_owned());
            }
            ObjectSpec {
                label: LABELS[l].into(),
                states,
                ..Default::default()
            }
        })
        .collect()
}

fn item() -> impl Strategy<Value = Item> {
    (0usize..6, 0usize..3, 0usize..4)
}

/// The goals and methods rows pick from (bad ones included).
fn goals_and_methods() -> (Vec<String>, Vec<String>) {
    let mut goals: Vec<String> = LABELS.iter().map(|l| (*l).to_owned()).collect();
    for l in LABELS {
        goals.push(format!(
            r#"{{"label": "{l}", "states": ["{}"]}}"#,
            STATES[l.len() % 3]
        ));
    }
    goals.truncate(11);
    goals.push("{bad".into());
    let mut methods: Vec<String> = Method::ALL.iter().map(|m| m.as_str().to_owned()).collect();
    methods.push("nope".into());
    (goals, methods)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Kitchens given as one base plus deltas (items added, items of the base or others
    /// removed, an item both added and removed): every answer, at every level and for every
    /// method, is its row planned alone on the kitchen built from scratch, whether the delta
    /// kitchens are prepared from the base's preparation or from their own items.
    #[test]
    fn delta_kitchens_answer_as_planned_alone(
        text in foon_text(),
        base in prop::collection::vec(item(), 0..8),
        deltas in prop::collection::vec(
            (
                prop::collection::vec(item(), 0..3),
                prop::collection::vec(0usize..8, 0..3),
                prop::collection::vec(item(), 0..2),
                any::<bool>(),
            ),
            1..6,
        ),
        picks in prop::collection::vec((0usize..6, 0usize..12, 0usize..9, 0usize..9), 1..40),
    ) {
        let foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
        let utensils: Vec<String> = UTENSILS.iter().map(|s| (*s).to_owned()).collect();
        let base_kitchen = Arc::new(Kitchen::from_specs(&item_specs(&base)).unwrap());
        let ds: Vec<(String, Kitchen, Kitchen)> = deltas
            .iter()
            .enumerate()
            .map(|(i, (add, drop, other, both))| {
                let mut remove: Vec<Item> = drop
                    .iter()
                    .filter(|_| !base.is_empty())
                    .map(|&j| base[j % base.len()])
                    .collect();
                remove.extend(other);
                let mut add = add.clone();
                if *both {
                    // An item both added and removed is in the kitchen.
                    add.extend(remove.first().copied());
                }
                (
                    format!("k{i}"),
                    Kitchen::from_specs(&item_specs(&add)).unwrap(),
                    Kitchen::from_specs(&item_specs(&remove)).unwrap(),
                )
            })
            .collect();
        let set = KitchenSet::with_deltas(&base_kitchen, ds).unwrap();
        let kids: Vec<String> = (0..6).map(|i| format!("k{i}")).collect();
        let (goals, methods) = goals_and_methods();
        let rows: Vec<QueryRow<'_>> = picks
            .iter()
            .map(|&(k, g, m, o)| QueryRow {
                kitchen: Some(kids[k].as_str()),
                goal: Some(goals[g].as_str()),
                method: Some(methods[m].as_str()),
                options: OPTIONS[o],
            })
            .collect();
        check(&foon, &set, &rows, &utensils);
    }
}

#[test]
fn bad_rows_are_failure_codes() {
    let foon = parse_foon(
        b"O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\nO\tegg\nS\tcracked\nM\theat\nO\tegg\nS\tfried\n//\n",
        None,
        ParseOptions::default(),
    )
    .unwrap();
    let set = KitchenSet::parse(
        br#"{"k": [{"label": "egg", "states": ["whole"]}], "none": []}"#,
        None,
    )
    .unwrap();
    let fried = r#"{"label": "egg", "states": ["fried"]}"#;
    let row =
        |k: &'static str, g: &'static str, m: &'static str, o: Option<&'static str>| QueryRow {
            kitchen: Some(k),
            goal: Some(g),
            method: Some(m),
            options: o,
        };
    let rows = [
        row("k", fried, "ids", None),
        row("zz", fried, "ids", None),
        row("k", "egg", "ids", None),
        row("k", "milk", "ids", None),
        row("k", "{\"label\": 1}", "ids", None),
        row("k", fried, "fast", None),
        row("k", fried, "ids", Some("{\"level\": 0}")),
        row("k", fried, "ids", Some("[1]")),
        row("k", fried, "ids", Some("{\"node_limit\": 3}")),
        row("none", fried, "ids", None),
        row("none", fried, "bfs", None),
        row(
            "k",
            fried,
            "optimal-units",
            Some("{\"compat\": \"course\"}"),
        ),
        QueryRow::default(),
    ];
    let cache = PreparedCache::default();
    let got = foon_core::queries::run_queries(&foon, &set, &rows, &cache, &RunOptions::default())
        .unwrap();
    let codes: Vec<Option<&str>> = got.iter().map(|a| a.failure.map(Failure::as_str)).collect();
    assert_eq!(
        codes,
        [
            None,
            Some("unknown-kitchen"),
            Some("goal-ambiguous"),
            Some("goal-not-found"),
            Some("bad-goal"),
            Some("unknown-method"),
            Some("bad-option"),
            Some("bad-option"),
            Some("bad-option"),
            Some("not-derivable"),
            Some("unresolved"),
            Some("bad-option"),
            Some("unknown-kitchen"),
        ]
    );
    assert_eq!(got[0].solved_plan().unwrap().units, [0, 1]);
    assert_eq!(got[9].missing, ["egg (whole)"]);
    assert_eq!(got[5].message, None, "unknown-method keeps no message");
    assert!(got[6].message.as_deref().unwrap().contains("level"));
    assert!(
        got[8]
            .message
            .as_deref()
            .unwrap()
            .contains("optimal-shared")
    );
    assert!(
        got[11]
            .message
            .as_deref()
            .unwrap()
            .contains("course-compatible")
    );
    // A cancelled batch is an error of the batch.
    let yes = || true;
    let opts = RunOptions {
        batch: BatchOptions::threads(Some(1)).with_cancel(&yes),
        ..RunOptions::default()
    };
    let e = foon_core::queries::run_queries(&foon, &set, &rows, &cache, &opts).unwrap_err();
    assert!(matches!(e, Error::Cancelled));
}

#[test]
fn course_batch_equals_rows_alone() {
    let Some(sh) = shared() else { return };
    let d = sh.join("data/foon");
    let foon = foon_core::load_foon(&d.join("FOON.txt"), ParseOptions::default()).unwrap();
    let utensils = foon_core::parse::load_utensils(&d.join("utensils.txt")).unwrap();
    let kitchen = Kitchen::load(&d.join("kitchen.json")).unwrap();
    let half = Kitchen::from_specs(&kitchen.specs()[..kitchen.len() / 2]).unwrap();
    let set = KitchenSet::from_kitchens([
        ("full".to_owned(), Arc::new(kitchen)),
        ("half".to_owned(), Arc::new(half)),
    ])
    .unwrap();
    let goals: Vec<String> = {
        let text = std::fs::read_to_string(d.join("goal_nodes_25.json")).unwrap();
        let v: Vec<serde_json::Value> = serde_json::from_str(&text).unwrap();
        v.iter().map(ToString::to_string).collect()
    };
    let methods: Vec<&str> = Method::ALL.iter().map(|m| m.as_str()).collect();
    let mut rows = Vec::new();
    for (i, g) in goals.iter().enumerate() {
        for (j, m) in methods.iter().enumerate() {
            rows.push(QueryRow {
                kitchen: Some(if (i + j) % 2 == 0 { "full" } else { "half" }),
                goal: Some(g.as_str()),
                method: Some(m),
                options: None,
            });
        }
    }
    check(&foon, &set, &rows, &utensils);
}

#[test]
fn many_waves_of_kitchens_and_delta_kitchens() {
    // A chain s0 -> s1 -> ... -> s11: kitchen i holds s(i % 12), so each goal is made in
    // some kitchens only; 150 kitchens take three waves of 64.
    let foon = chain_foon();
    let item = |i: usize| format!(r#"[{{"label": "item", "states": ["s{i}"]}}]"#);
    let plain = KitchenSet::from_kitchens(
        (0..150).map(|i| (format!("k{i}"), Arc::new(kitchen(&item(i % 12))))),
    )
    .unwrap();
    let base = Arc::new(kitchen(&item(0)));
    let deltas = KitchenSet::with_deltas(
        &base,
        (0..150).map(|i| (format!("k{i}"), kitchen(&item(i % 12)), kitchen(&item(0)))),
    )
    .unwrap();
    // The same kitchens either way.
    assert_eq!(plain.fingerprint().unwrap(), deltas.fingerprint().unwrap());
    let kids: Vec<String> = (0..150).map(|i| format!("k{i}")).collect();
    let goals: Vec<String> = (0..12)
        .map(|i| format!(r#"{{"label": "item", "states": ["s{i}"]}}"#))
        .collect();
    let rows: Vec<QueryRow<'_>> = (0..450)
        .map(|r| QueryRow {
            kitchen: Some(kids[(r * 7) % 150].as_str()),
            goal: Some(goals[r % 12].as_str()),
            method: Some(Method::ALL[r % 8].as_str()),
            options: None,
        })
        .collect();
    check(&foon, &plain, &rows, &[]);
    check(&foon, &deltas, &rows, &[]);
    let solved = strip(
        foon_core::queries::run_queries(
            &foon,
            &deltas,
            &rows,
            &PreparedCache::default(),
            &RunOptions::default(),
        )
        .unwrap(),
    );
    assert!(solved.iter().any(Answer::solved));
    assert!(
        solved
            .iter()
            .any(|a| a.failure == Some(Failure::NotDerivable))
    );
}

#[test]
fn course_delta_kitchens_equal_rows_alone() {
    let Some(sh) = shared() else { return };
    let d = sh.join("data/foon");
    let foon = foon_core::load_foon(&d.join("FOON.txt"), ParseOptions::default()).unwrap();
    let utensils = foon_core::parse::load_utensils(&d.join("utensils.txt")).unwrap();
    let kitchen = Arc::new(Kitchen::load(&d.join("kitchen.json")).unwrap());
    let specs = kitchen.specs();
    // Deltas of the course kitchen: every seventh item from an offset removed, and (for
    // some) items of another kitchen half added back or a new item added.
    let deltas = (0..6).map(|k| {
        let remove: Vec<ObjectSpec> = specs.iter().skip(k).step_by(7).cloned().collect();
        let add: Vec<ObjectSpec> = match k % 3 {
            0 => Vec::new(),
            1 => remove.iter().take(2).cloned().collect(),
            _ => vec![ObjectSpec {
                label: "water".into(),
                ..ObjectSpec::default()
            }],
        };
        (
            format!("d{k}"),
            Kitchen::from_specs(&add).unwrap(),
            Kitchen::from_specs(&remove).unwrap(),
        )
    });
    let set = KitchenSet::with_deltas(&kitchen, deltas).unwrap();
    let goals: Vec<String> = {
        let text = std::fs::read_to_string(d.join("goal_nodes_25.json")).unwrap();
        let v: Vec<serde_json::Value> = serde_json::from_str(&text).unwrap();
        v.iter().map(ToString::to_string).collect()
    };
    let methods: Vec<&str> = Method::ALL.iter().map(|m| m.as_str()).collect();
    let levels = [None, Some(r#"{"level": 2}"#), Some(r#"{"level": 1}"#)];
    let mut rows = Vec::new();
    for (i, g) in goals.iter().enumerate() {
        for (j, m) in methods.iter().enumerate() {
            rows.push(QueryRow {
                kitchen: Some(set.ids()[(i + j) % set.len()].as_str()),
                goal: Some(g.as_str()),
                method: Some(m),
                options: levels[(i + 2 * j) % 3],
            });
        }
    }
    check(&foon, &set, &rows, &utensils);
}

#[test]
fn a_wave_of_deltas_prepares_their_base_once() {
    // A chain s0 -> ... -> s11, a base kitchen of s0 and s5; 200 deltas each removing one of
    // them and adding another state (5 distinct kitchens, none the base), at level 3: the
    // cache then holds the base once and each distinct delta kitchen once.
    let foon = chain_foon();
    let item = |i: usize| format!(r#"{{"label": "item", "states": ["s{i}"]}}"#);
    let base = Arc::new(kitchen(&format!("[{}, {}]", item(0), item(5))));
    let set = KitchenSet::with_deltas(
        &base,
        (0..200).map(|i| {
            (
                format!("k{i}"),
                kitchen(&format!(
                    "[{}]",
                    item(if i % 2 == 0 { 1 + i % 4 } else { 6 + i % 6 })
                )),
                kitchen(&format!("[{}]", item(if i % 2 == 0 { 0 } else { 5 }))),
            )
        }),
    )
    .unwrap();
    let distinct: std::collections::HashSet<u128> = (0..set.len())
        .map(|i| set.entry(i).fingerprint().unwrap())
        .collect();
    assert_eq!(distinct.len(), 5);
    assert!(!distinct.contains(&base.fingerprint()));
    let goal = item(11);
    let rows: Vec<QueryRow<'_>> = set
        .ids()
        .iter()
        .map(|k| QueryRow {
            kitchen: Some(k.as_str()),
            goal: Some(goal.as_str()),
            method: Some("optimal-units"),
            options: None,
        })
        .collect();
    let cache = PreparedCache::default();
    let got = foon_core::queries::run_queries(&foon, &set, &rows, &cache, &RunOptions::default())
        .unwrap();
    assert!(got.iter().all(Answer::solved));
    let st = cache.stats();
    assert_eq!(st.entries, distinct.len() + 1);
    check(&foon, &set, &rows, &[]);
}
