//! The loaders and the model: one object loader for files and command-line text, rate tables
//! with repeated motions, conflicting annotations, strict-mode messages, cancellable loads,
//! identity (objects and units), and the goal look-ups.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use foon_core::MotionRates;
use foon_core::lint::{LintOptions, Severity, lint, lint_rates, lint_rates_data};
use foon_core::parse::{parse_objects, parse_rates, parse_utensils};
use foon_core::verify::verify_tree;
use foon_core::{
    Error, Foon, InputKind, ObjectSpec, ParseOptions, WarningKind, check_rate, parse_foon,
    parse_foon_cancellable,
};

fn foon(text: &str) -> Foon {
    parse_foon(
        text.as_bytes(),
        Some(Path::new("t.foon")),
        ParseOptions::default(),
    )
    .unwrap()
}

fn strict(text: &str) -> Error {
    parse_foon(
        text.as_bytes(),
        Some(Path::new("t.foon")),
        ParseOptions { strict: true },
    )
    .unwrap_err()
}

/// (line, column, reason) of a parse error.
fn at(e: &Error) -> (u64, u32, String) {
    match e {
        Error::Parse { at, reason, .. } => (at.line, at.column, reason.clone()),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

fn spec(label: &str, states: &[&str], ingredients: &[&str], container: Option<&str>) -> ObjectSpec {
    ObjectSpec::new(
        label,
        states.iter().map(|s| (*s).to_owned()).collect(),
        ingredients.iter().map(|s| (*s).to_owned()).collect(),
        container.map(str::to_owned),
    )
    .unwrap()
}

fn goal(text: &str) -> Result<Vec<ObjectSpec>, Error> {
    parse_objects(text.as_bytes(), Some(Path::new("--goal")), InputKind::Goal)
}

// --- verify: units are found by their own identity --------------------------------------

#[test]
fn verify_finds_a_unit_without_inputs_whose_first_output_is_bare() {
    // No inputs, and the first output has no state, ingredient or container: the producer
    // map does not index it, but the unit is a unit of the FOON all the same.
    let text = "M\ttake\nO\tknife\nO\tonion\nS\twhole\n//\nO\tonion\nS\twhole\nM\tchop\nO\tonion\nS\tchopped\n//\n";
    let f = foon(text);
    let tree = foon(text);
    let report = verify_tree(
        &f,
        &tree,
        &foon_core::Kitchen::new(),
        &[],
        &spec("onion", &["chopped"], &[], None),
    )
    .unwrap();
    assert_eq!(report.foreign_units, vec![]);
    assert!(report.is_valid());
    // A unit that is not in the FOON is still reported.
    let other = foon("M\ttake\nO\tfork\n//\n");
    let report = verify_tree(
        &f,
        &other,
        &foon_core::Kitchen::new(),
        &[],
        &spec("fork", &[], &[], None),
    )
    .unwrap();
    assert_eq!(report.foreign_units, vec![(0, 1)]);
}

#[test]
fn units_are_found_by_motion_and_multisets() {
    let f = foon("O\ta\nS\tx\nO\tk\nM\tm\nO\tb\nS\ty\nO\tk\n//\n");
    let (a, k, b) = (0, 1, 2);
    let m = f.strings().get("m").unwrap();
    assert_eq!(f.find_fu(m, &[k, a], &[k, b]), Some(0));
    assert_eq!(f.find_fu(m, &[a], &[b, k]), None);
    assert_eq!(f.find_fu(m, &[a, k, k], &[b, k]), None);
    let n = f.strings().get("x").unwrap();
    assert_eq!(f.find_fu(n, &[a, k], &[b, k]), None);
}

// --- motion tables: one rate per motion --------------------------------------------------

#[test]
fn a_motion_with_two_rates_is_an_error_naming_both_lines() {
    let data = b"pour\t0.8\nchop\t0.5\npour\t0.80\nmix\t0.9\n\n# x\nstir\t1\nboil\t1\nPour \t0.6\n";
    let e = parse_rates(data, Some(Path::new("m.txt"))).unwrap_err();
    assert_eq!(
        at(&e),
        (
            9,
            7,
            "motion 'pour' has two rates: 0.8 (line 1) and 0.6 (line 9)".to_owned()
        )
    );
    assert!(e.to_string().starts_with("m.txt:9:7: "), "{e}");
    // The same rate twice is one entry.
    let r = parse_rates(b"pour\t0.8\npour\t0.80\n", None).unwrap();
    assert_eq!(r.entries, vec![("pour".to_owned(), 0.8)]);
    assert_eq!(r.get("pour"), Some(0.8));
}

#[test]
fn from_pairs_rejects_two_rates_and_checks_each_rate() {
    let pairs = |v: &[(&str, f64)]| {
        v.iter()
            .map(|(m, r)| ((*m).to_owned(), *r))
            .collect::<Vec<_>>()
    };
    let e = MotionRates::from_pairs(pairs(&[("pour", 0.8), ("pour", 0.6)])).unwrap_err();
    assert_eq!(e.to_string(), "motion 'pour' has two rates: 0.8 and 0.6");
    let r = MotionRates::from_pairs(pairs(&[("pour", 0.8), ("mix", 0.5), ("pour", 0.8)])).unwrap();
    assert_eq!(r.len(), 2);
    for bad in [f64::NAN, -0.1, 1.5, f64::INFINITY] {
        let e = MotionRates::from_pairs(pairs(&[("pour", bad)])).unwrap_err();
        assert!(matches!(e, Error::Invalid(_)), "{e:?}");
        assert_eq!(
            e.to_string(),
            check_rate(Some("pour"), bad).unwrap_err().to_string()
        );
    }
}

#[test]
fn check_rate_is_the_one_range_check() {
    assert_eq!(check_rate(None, 0.0).unwrap().to_bits(), 0.0f64.to_bits());
    assert_eq!(
        check_rate(Some("m"), 1.0).unwrap().to_bits(),
        1.0f64.to_bits()
    );
    assert_eq!(
        check_rate(Some("m"), 1.5).unwrap_err().to_string(),
        "the rate of 'm' is 1.5, not between 0 and 1"
    );
    assert_eq!(
        check_rate(None, f64::NAN).unwrap_err().to_string(),
        "the default rate is NaN, not between 0 and 1"
    );
    // The table parser uses it (with the line and column of the rate).
    let e = parse_rates(b"chop\t1.5\n", None).unwrap_err();
    assert_eq!(
        at(&e),
        (
            1,
            6,
            "the rate of 'chop' is 1.5, not between 0 and 1".to_owned()
        )
    );
}

#[test]
fn the_linter_reports_rate_table_problems_as_findings() {
    let data = b"pour\t0.8\nchop\tx\npour\t0.6\nmix\t0.5\n";
    let (rates, findings) = lint_rates_data(data, Some(Path::new("m.txt")));
    let got: Vec<(u64, u32, &str, Severity)> = findings
        .iter()
        .map(|f| (f.at.line, f.at.column, f.code, f.severity))
        .collect();
    assert_eq!(
        got,
        vec![
            (2, 6, "syntax", Severity::Error),
            (3, 6, "two-rates", Severity::Error)
        ]
    );
    assert!(
        findings[1]
            .message
            .contains("0.8 (line 1) and 0.6 (line 3)")
    );
    // The good lines are kept for the cross-checks (of two rates, the first).
    assert_eq!(rates.get("pour"), Some(0.8));
    assert_eq!(rates.get("mix"), Some(0.5));
    assert_eq!(rates.get("chop"), None);
    // By path, and a missing file is an I/O error.
    let dir = std::env::temp_dir().join(format!("foon-lint-rates-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("m.txt");
    std::fs::write(&p, data).unwrap();
    let (_, by_path) = lint_rates(&p).unwrap();
    assert_eq!(by_path.len(), 2);
    assert_eq!(by_path[1].at.path.as_deref(), Some(p.as_path()));
    assert!(matches!(
        lint_rates(&dir.join("none.txt")),
        Err(Error::Io { .. })
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

// --- conflicting annotations ---------------------------------------------------------------

const TWO_CONTAINERS: &str =
    "O\tonion\nS\tin\t[bowl]\nS\tin\t[pan]\nM\tfry\nO\tonion\nS\tfried\n//\n";
const TWO_LISTS: &str =
    "O\tbowl\nS\tcontains\t{a,b}\nS\tcontains\t{c}\nM\tmix\nO\tbowl\nS\tmixed\n//\n";
const EMPTY_LIST: &str = "O\tbowl\nS\tcontains\t{}\nM\tmix\nO\tbowl\nS\tmixed\n//\n";

#[test]
fn two_containers_the_last_one_wins_with_a_finding() {
    let f = foon(TWO_CONTAINERS);
    assert_eq!(f.text(f.container(0)), "pan");
    assert!(f.warnings().is_empty(), "not a load warning");
    let n: Vec<_> = f
        .notes()
        .iter()
        .map(|w| (w.at.line, w.at.column, w.kind, w.message.as_str()))
        .collect();
    assert_eq!(
        n,
        vec![(
            3,
            6,
            WarningKind::TwoContainers,
            "object 'onion' has a second container: [pan] after [bowl]; the last one wins"
        )]
    );
    let e = strict(TWO_CONTAINERS);
    assert_eq!(
        at(&e),
        (
            3,
            6,
            "object 'onion' has a second container: [pan] after [bowl] (strict mode)".to_owned()
        )
    );
}

#[test]
fn two_ingredient_lists_the_last_one_wins_with_a_finding() {
    let f = foon(TWO_LISTS);
    let ing: Vec<&str> = f.ingredients(0).iter().map(|&i| f.text(i)).collect();
    assert_eq!(ing, vec!["c"]);
    let w = &f.notes()[0];
    assert_eq!(
        (w.at.line, w.at.column, w.kind),
        (3, 12, WarningKind::TwoIngredientLists)
    );
    assert_eq!(
        w.message,
        "object 'bowl' has a second ingredient list: {c} after {a,b}; the last one wins"
    );
    assert!(
        at(&strict(TWO_LISTS))
            .2
            .ends_with("{c} after {a,b} (strict mode)")
    );
}

#[test]
fn an_empty_ingredient_is_kept_as_the_course_reads_it() {
    // `{}` is one ingredient '' (the course splits "" on ","): a different object than one
    // without a list, written back as `{}`.
    let f = foon(EMPTY_LIST);
    let ing: Vec<&str> = f.ingredients(0).iter().map(|&i| f.text(i)).collect();
    assert_eq!(ing, vec![""]);
    assert_eq!(f.object_count(), 2);
    assert!(foon_core::write::foon_text(&f).contains("S\tcontains\t{}\n"));
    let w = &f.notes()[0];
    assert_eq!(
        (w.at.line, w.at.column, w.kind),
        (2, 13, WarningKind::EmptyIngredient)
    );
    assert_eq!(
        w.message,
        "empty ingredient name in '{}'; it is kept as the ingredient '' (course rule)"
    );
    // The column is the empty item's.
    let f = foon("O\tbowl\nS\tcontains\t{salt,}\nM\tmix\nO\tbowl\nS\tmixed\n//\n");
    assert_eq!(f.notes()[0].at.column, 18);
    assert_eq!(
        at(&strict(EMPTY_LIST)),
        (
            2,
            13,
            "empty ingredient name in '{}' (strict mode)".to_owned()
        )
    );
}

#[test]
fn check_reports_conflicts_as_warnings_with_codes() {
    for (text, code, line) in [
        (TWO_CONTAINERS, "two-containers", 3),
        (TWO_LISTS, "two-ingredient-lists", 3),
        (EMPTY_LIST, "empty-ingredient", 2),
    ] {
        let found = lint(
            text.as_bytes(),
            Some(Path::new("t.foon")),
            &LintOptions::default(),
        );
        let f = found
            .iter()
            .find(|f| f.code == code)
            .unwrap_or_else(|| panic!("{code}: {found:?}"));
        assert_eq!((f.at.line, f.severity), (line, Severity::Warning), "{code}");
    }
}

#[test]
fn object_blocks_follow_the_same_rules() {
    let kitchen = "O\tonion\nS\twhole\nS\tin\t[bowl]\nS\tin\t[pan]\nO\tbowl\nS\tcontains\t{a}\nS\tcontains\t{}\n";
    let list = parse_objects(kitchen.as_bytes(), None, InputKind::Kitchen).unwrap();
    assert_eq!(list[0].container.as_deref(), Some("pan"));
    assert_eq!(list[1].ingredients, vec![String::new()]);
    let found = lint(
        kitchen.as_bytes(),
        Some(Path::new("k.txt")),
        &LintOptions::default(),
    );
    let got: Vec<(u64, u32, &str)> = found
        .iter()
        .map(|f| (f.at.line, f.at.column, f.code))
        .collect();
    assert_eq!(
        got,
        vec![
            (4, 6, "two-containers"),
            (7, 12, "two-ingredient-lists"),
            (7, 13, "empty-ingredient")
        ]
    );
}

#[test]
fn the_third_field_grammar_is_the_same_in_both_parsers() {
    for (third, col, reason) in [
        (
            "cup",
            6,
            "expected '{ingredients}' or '[container]' in the third field, found 'cup'",
        ),
        ("[cup", 6, "container has no closing ']'"),
        ("{a,b", 6, "ingredient list has no closing '}'"),
    ] {
        let text = format!("O\tbowl\nS\tin\t{third}\n");
        let in_foon = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap_err();
        let in_list = parse_objects(text.as_bytes(), None, InputKind::Kitchen).unwrap_err();
        assert_eq!(at(&in_foon), (2, col, reason.to_owned()));
        assert_eq!(at(&in_list), (2, col, reason.to_owned()));
    }
}

// --- strict mode reads as an error ---------------------------------------------------------

#[test]
fn strict_mode_errors_read_as_errors_for_every_warning_kind() {
    let cases = [
        ("O\ta\nS\tx\n//\n", WarningKind::NoMotion),
        (
            "O\ta\nM\tm\nM\tn\nO\tb\nS\ty\n//\n",
            WarningKind::TwoMotions,
        ),
        ("O\ta\nM\tm\nO\tb\nS\ty\n", WarningKind::Unterminated),
        (TWO_CONTAINERS, WarningKind::TwoContainers),
        (TWO_LISTS, WarningKind::TwoIngredientLists),
        (EMPTY_LIST, WarningKind::EmptyIngredient),
    ];
    for (text, kind) in cases {
        let (line, column, reason) = at(&strict(text));
        assert!(reason.ends_with(" (strict mode)"), "{kind:?}: {reason}");
        let consequence = kind.consequence().unwrap();
        assert!(!reason.contains(consequence), "{kind:?}: {reason}");
        for word in ["dropped", "kept", "wins"] {
            assert!(!reason.contains(word), "{kind:?}: {reason}");
        }
        // Without strict mode the same fault is a warning (or a note) at the same place,
        // ending with what is done about it.
        let f = foon(text);
        let w = f
            .warnings()
            .iter()
            .chain(f.notes())
            .find(|w| w.kind == kind)
            .unwrap();
        assert_eq!((w.at.line, w.at.column), (line, column), "{kind:?}");
        let fault = reason.strip_suffix(" (strict mode)").unwrap();
        assert_eq!(w.message, format!("{fault}; {consequence}"));
    }
}

// --- one loader for objects ------------------------------------------------------------------

#[test]
fn wrong_json_types_are_errors_with_a_location_never_coerced() {
    let cases: [(&str, u64, u32, &str); 9] = [
        (
            r#"{"label": "ice", "container": 5}"#,
            1,
            31,
            "invalid type: integer `5`, expected a string",
        ),
        (
            r#"{"label": "ice", "states": [1]}"#,
            1,
            29,
            "invalid type: integer `1`, expected a string",
        ),
        (
            r#"{"label": "ice", "states": 5}"#,
            1,
            28,
            "invalid type: integer `5`, expected a sequence",
        ),
        (
            r#"{"label": "ice", "states": "crushed"}"#,
            1,
            36,
            "invalid type: string \"crushed\", expected a sequence",
        ),
        (
            r#"{"label": null}"#,
            1,
            14,
            "invalid type: null, expected a string",
        ),
        (
            r#"{"label": "ice", "states": [NaN]}"#,
            1,
            29,
            "expected value",
        ),
        (
            r#"{"label": "ice", "colour": "red"}"#,
            1,
            25,
            "unknown field `colour`",
        ),
        (r#"{"label": " "}"#, 1, 14, "an object has an empty label"),
        (
            r#"{"label": "ice", "states": ["a", ""]}"#,
            1,
            37,
            "an object has an empty state",
        ),
    ];
    for (text, line, column, reason) in cases {
        let e = goal(text).unwrap_err();
        let (l, c, r) = at(&e);
        assert_eq!((l, c), (line, column), "{text}: {r}");
        assert!(r.starts_with(reason), "{text}: {r}");
        assert!(
            e.to_string()
                .starts_with(&format!("--goal:{line}:{column}: goal error: "))
        );
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    // Typed reading stops at the first value of the wrong type, so no depth is recursed into
    // (and serde_json's recursion limit, 128, bounds any other path).
    let deep = format!("{}{}", "[".repeat(50_000), "]".repeat(50_000));
    for kind in [InputKind::Goal, InputKind::Kitchen] {
        let e = parse_objects(deep.as_bytes(), None, kind).unwrap_err();
        assert_eq!(
            at(&e),
            (
                1,
                1,
                "invalid type: sequence, expected struct ObjectSpec".to_owned()
            )
        );
    }
    let deep = format!(r#"{{"label": "x", "states": {}"#, "[".repeat(50_000));
    assert_eq!(
        at(&goal(&deep).unwrap_err()),
        (
            1,
            26,
            "invalid type: sequence, expected a string".to_owned()
        )
    );
    let deep = format!(
        "{}{}",
        r#"{"label": "x", "a": "#.repeat(50_000),
        "}".repeat(50_000)
    );
    assert!(
        at(&goal(&deep).unwrap_err())
            .2
            .starts_with("unknown field `a`")
    );
    // A list of field values is not an object.
    let e = goal(r#"[["ice", ["crushed"]]]"#).unwrap_err();
    assert_eq!(
        at(&e),
        (
            1,
            1,
            "invalid type: sequence, expected struct ObjectSpec".to_owned()
        )
    );
}

#[test]
fn null_lists_are_empty_lists_everywhere() {
    // One rule for files and command-line text: null is the same as an absent field.
    let one = r#"{"label": "ice", "states": null, "ingredients": null, "container": null}"#;
    assert_eq!(goal(one).unwrap(), vec![spec("ice", &[], &[], None)]);
    let list = format!("[{one}]");
    let kitchen = parse_objects(list.as_bytes(), None, InputKind::Kitchen).unwrap();
    assert_eq!(kitchen, vec![spec("ice", &[], &[], None)]);
}

#[test]
fn json_with_a_byte_order_mark_is_accepted() {
    let mut data = b"\xEF\xBB\xBF".to_vec();
    data.extend_from_slice(br#"[{"label": "ice", "states": ["crushed"]}]"#);
    for kind in [InputKind::Kitchen, InputKind::Goal] {
        let list = parse_objects(&data, None, kind).unwrap();
        assert_eq!(list, vec![spec("ice", &["crushed"], &[], None)]);
    }
    // Positions are counted after the mark, as in FOON files.
    let mut bad = b"\xEF\xBB\xBF".to_vec();
    bad.extend_from_slice(br#"[{"label": 5}]"#);
    assert_eq!(
        at(&parse_objects(&bad, None, InputKind::Kitchen).unwrap_err()).1,
        12
    );
}

#[test]
fn object_spec_new_validates() {
    assert!(ObjectSpec::new("ice", vec!["crushed".into()], vec![], None).is_ok());
    for (label, states) in [("", vec![]), ("  ", vec![]), ("ice", vec![String::new()])] {
        let e = ObjectSpec::new(label, states, vec![], None).unwrap_err();
        assert!(matches!(e, Error::Invalid(_)), "{e:?}");
    }
    // An empty ingredient ({} in FOON text) and an empty container ([]) are objects of real
    // files, so they are valid.
    assert!(ObjectSpec::new("bowl", vec![], vec![String::new()], Some(String::new())).is_ok());
}

// --- utensil lists -------------------------------------------------------------------------

#[test]
fn a_file_that_is_not_a_utensil_list_is_rejected() {
    let kitchen = br#"[
  {"label": "bowl", "states": ["empty"]}
]
"#;
    let e = parse_utensils(kitchen, Some(Path::new("kitchen.json"))).unwrap_err();
    let (line, column, reason) = at(&e);
    assert_eq!((line, column), (1, 1));
    assert!(reason.contains("looks like JSON"), "{reason}");
    assert!(
        e.to_string()
            .starts_with("kitchen.json:1:1: utensil list error: ")
    );
    assert_eq!(
        at(&parse_utensils(b"bowl\n  {\"a\"}\n", None).unwrap_err()).1,
        3
    );
    let foon_file = b"O\tbowl\nS\tempty\n";
    assert_eq!(at(&parse_utensils(foon_file, None).unwrap_err()).0, 1);
    assert_eq!(
        parse_utensils(b"bowl\n# c\n\nfrying pan  \n", None).unwrap(),
        vec!["bowl", "frying pan"]
    );
}

// --- cancellable loads -----------------------------------------------------------------------

fn chain(n: usize) -> String {
    let mut s = String::new();
    for i in 0..n {
        let _ = write!(s, "O\titem\nS\ts{i}\nM\tm\nO\titem\nS\ts{}\n//\n", i + 1);
    }
    s
}

#[test]
fn a_cancel_closure_stops_a_large_parse() {
    let text = chain(20_000); // 120,000 lines
    let calls = AtomicUsize::new(0);
    let cancel = || calls.fetch_add(1, Ordering::Relaxed) >= 3;
    let r = parse_foon_cancellable(text.as_bytes(), None, ParseOptions::default(), &cancel);
    assert!(matches!(r, Err(Error::Cancelled)), "{r:?}");
    assert_eq!(
        calls.load(Ordering::Relaxed),
        4,
        "stopped at the first true answer"
    );
    // Never cancelled: the same graph as parse_foon, with the closure asked regularly.
    let asked = AtomicUsize::new(0);
    let never = || {
        asked.fetch_add(1, Ordering::Relaxed);
        false
    };
    let f = parse_foon_cancellable(text.as_bytes(), None, ParseOptions::default(), &never).unwrap();
    assert_eq!(f.fu_count(), 20_000);
    assert!(asked.load(Ordering::Relaxed) >= 120_000 / 5000);
    let dir = std::env::temp_dir().join(format!("foon-cancel-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("chain.foon");
    std::fs::write(&p, &text).unwrap();
    let r = foon_core::load_foon_cancellable(&p, ParseOptions::default(), &|| true);
    assert!(matches!(r, Err(Error::Cancelled)));
    std::fs::remove_dir_all(&dir).unwrap();
}

// --- identity --------------------------------------------------------------------------------

#[test]
fn object_specs_are_equal_and_hash_by_identity() {
    let a = spec("bowl", &["hot", "empty"], &["b", "a"], Some("sink"));
    let b = spec("bowl", &["empty", "hot"], &["a", "b"], Some("sink"));
    assert_eq!(a, b);
    let set: HashSet<ObjectSpec> = [a.clone(), b].into_iter().collect();
    assert_eq!(set.len(), 1);
    // Multisets: a repeated state counts.
    assert_ne!(
        spec("bowl", &["hot", "hot"], &[], None),
        spec("bowl", &["hot"], &[], None)
    );
    assert_ne!(a, spec("bowl", &["hot", "empty"], &["a", "b"], None));
    // The FOON's identity is the same rule: both find the same object.
    let f = foon(
        "O\tbowl\nS\tempty\nS\thot\nS\tcontains\t{a,b}\nS\tin\t[sink]\nM\tm\nO\tx\nS\ty\n//\n",
    );
    assert_eq!(a.find_in(&f), Some(0));
}

// --- goal look-ups ----------------------------------------------------------------------------

#[test]
fn goals_by_spec_label_and_id() {
    let mut text = String::new();
    for i in 0..8 {
        let _ = write!(
            text,
            "O\tice\nS\ts{i}\nM\tm\nO\tice\nS\tt{i}\nS\tfrozen\n//\n"
        );
    }
    text.push_str("O\twater\nM\tfreeze\nO\tsnow\nS\tcold\n//\n");
    let f = foon(&text);
    assert_eq!(
        f.goal_by_spec(&spec("snow", &["cold"], &[], None)).unwrap(),
        17
    );
    let e = f
        .goal_by_spec(&spec("snow", &["warm"], &[], Some("cup")))
        .unwrap_err();
    assert!(matches!(e, Error::GoalNotFound { .. }));
    assert_eq!(
        e.to_string(),
        "The goal node does not exist: snow (warm) in [cup]; nearest: snow (cold)"
    );
    assert_eq!(f.goal_by_label("snow").unwrap(), 17);
    assert_eq!(
        f.goal_by_label("steam").unwrap_err().to_string(),
        "The goal node does not exist: steam; nearest: water"
    );
    let e = f.goal_by_label("ice").unwrap_err();
    assert!(matches!(e, Error::GoalAmbiguous { count: 16, .. }), "{e:?}");
    let msg = e.to_string();
    assert_eq!(
        msg,
        "the label 'ice' matches 16 objects: ice (s0); ice (t0, frozen); ice (s1); \
         ice (t1, frozen); ice (s2); and 11 more \u{2014} give the goal as JSON to choose one"
    );
    assert!(!msg.contains('\n'));
    assert_eq!(f.goal_by_id(3).unwrap(), 3);
    assert_eq!(
        f.goal_by_id(18).unwrap_err().to_string(),
        "The goal node does not exist: object id 18 (the FOON has 18 objects)"
    );
}

#[cfg(unix)]
#[test]
fn devices_are_refused_rather_than_read_without_end() {
    use foon_core::parse::{load_objects, load_rates, load_utensils};
    let zero = Path::new("/dev/zero");
    if !zero.exists() {
        return;
    }
    let e = foon_core::load_foon(zero, ParseOptions::default()).unwrap_err();
    assert!(e.to_string().contains("not a regular file"), "{e}");
    assert!(load_rates(zero).is_err());
    assert!(load_utensils(zero).is_err());
    assert!(load_objects(zero, foon_core::InputKind::Kitchen).is_err());
}

#[test]
fn rate_tables_built_in_code_name_motions_as_rate_files_do() {
    let r = MotionRates::from_pairs([("Mix ".to_owned(), 0.5), ("pour".to_owned(), 0.25)]).unwrap();
    assert_eq!(r.get("mix"), Some(0.5));
    let e =
        MotionRates::from_pairs([("mix".to_owned(), 0.5), ("MIX".to_owned(), 0.6)]).unwrap_err();
    assert!(e.to_string().contains("two rates"), "{e}");
    assert!(MotionRates::from_pairs([(" ".to_owned(), 0.5)]).is_err());
}
