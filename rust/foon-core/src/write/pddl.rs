//! PDDL: one goal of a FOON (or one task tree) as a STRIPS planning problem, in one text
//! that holds a domain and a problem.
//!
//! # Layout
//! The text is the domain, then a line [`PROBLEM_LINE`] (`;; ---- problem ----`, a PDDL
//! comment), then the problem; [`split`] cuts it into the two files a planner reads.
//!
//! # What is written
//! - **Predicates**: one 0-ary predicate per object the problem mentions (a needed input or a
//!   made output of one of its actions, the goal, a kitchen item among those), in object id
//!   order, each followed by a comment with the object in its text form. Names are the
//!   object's text made into a PDDL name: ASCII letters and digits lower-cased, every other
//!   run of characters one `-`, at most 60 characters; a name that starts with a digit gets
//!   `o-` in front, an empty one is `item`. A name already taken (by an object with a lower
//!   id) or a PDDL word (`and`, `not`, `either`, `total-cost`, ...) gets the first free
//!   suffix `-2`, `-3`, ... So names are valid, unique and the same for the same input.
//! - **Actions**: one per unit, named `fu<index>-<motion>` (the unit's index in the FOON,
//!   then its motion made into a name): a plan maps back to units by that index. The
//!   precondition is the unit's needed inputs (the container rule applied, see
//!   SEMANTICS.md), the effect adds its outputs. Nothing is deleted: FOON objects are not
//!   consumed. A task tree is valid when its units can be ordered so that each one's needed
//!   inputs are in the kitchen or made by an earlier unit (SEMANTICS.md), and one object may
//!   feed several units (the cutting board, the knife, a sauce used twice); deleting inputs
//!   would reject such valid trees and make the planner's plans disagree with `foon verify`.
//!   With add effects only, the plans are exactly the executable orders of valid trees. An
//!   output with no state, ingredient or container is not indexed as made (course rule), so
//!   it is no effect either.
//! - For a FOON ([`write_foon`](super::write_foon) with the goal in focus): the units are
//!   the goal's ancestry: every unit that makes an object, not in the kitchen, that the goal
//!   needs, going backwards from the goal through every producer and its needed inputs (a
//!   kitchen item is not expanded: it is true from the start). Units that can never run
//!   from the kitchen (a needed input that no sequence of units makes, see ranks in
//!   SEMANTICS.md) are left out: with add effects only this removes no plan. When the FOON
//!   document selects some units (`depth`, `units`) the ancestry stays within them.
//! - For a task tree ([`TreeWriter`](super::TreeWriter), one tree a document): the units
//!   are the tree's units (the FOON-to-PDDL approach: the retrieved tree is handed to a
//!   planner, which orders it). The problem is solvable exactly when the tree is valid,
//!   which every solved tree of a sound method is; the planner's plan then uses a subset of
//!   the tree's units. The problem of the goal itself is `write_foon`'s.
//! - **Initial state**: the kitchen items the problem mentions (the others change nothing).
//!   **Goal**: the goal object.
//! - **Costs**: when motion rates were given (a table or a default rate) and
//!   [`Options::cost_scale`] is not 0, the domain requires `:action-costs`, each action
//!   ends with `(increase (total-cost) N)`, `N = round(-ln(rate) * cost_scale)` (default
//!   scale 1000: a rate of 0.9 costs 105, 0.1 costs 2303, 1 costs 0), and the problem says
//!   `(:metric minimize (total-cost))`. A unit whose motion has rate 0 never succeeds: it is
//!   left out (a comment names it), as `optimal-success` never uses it; a unit whose motion has
//!   no rate is an error that names the motion, as in planning. Without rates (or with scale
//!   0) the problem has no costs: plain STRIPS, every plan as good as another, which planners
//!   without cost support (pyperplan) solve.
//!
//! The cheapest plan can cost less than the `optimal-success` tree: a tree counts a shared
//! sub-goal each time it is used, a plan makes it once; they agree when the tree shares no
//! sub-goal, no cheaper plan shares one, and rounding each cost to an integer makes no other
//! way cheaper.

use std::fmt::Write as _;
use std::io;

use rustc_hash::FxHashSet;

use super::{Failed, FoonDoc, Options, TreeDoc, TreeFormat, object_line, put};
use crate::error::{Error, Result};
use crate::index::Foon;
use crate::prepare::Prepared;

/// The line between the domain and the problem.
pub const PROBLEM_LINE: &str = ";; ---- problem ----";

/// The domain and the problem of a text written in the PDDL format (`None` when the text
/// has no [`PROBLEM_LINE`]).
pub fn split(text: &str) -> Option<(&str, &str)> {
    let mut at = 0;
    for line in text.split_inclusive('\n') {
        if line.trim_end() == PROBLEM_LINE {
            return Some((&text[..at], &text[at + line.len()..]));
        }
        at += line.len();
    }
    None
}

/// Longest name made from an object's text (before a `-N` suffix).
const NAME_MAX: usize = 60;

/// Words a name must not be (PDDL keywords and the cost function).
const RESERVED: &[&str] = &[
    "all",
    "always",
    "and",
    "assign",
    "at",
    "decrease",
    "define",
    "domain",
    "either",
    "end",
    "exists",
    "forall",
    "imply",
    "increase",
    "maximize",
    "minimize",
    "not",
    "number",
    "object",
    "or",
    "over",
    "preference",
    "problem",
    "scale-down",
    "scale-up",
    "sometime",
    "start",
    "total-cost",
    "total-time",
    "when",
    "within",
];

/// `s` as a PDDL name part: ASCII letters and digits lower-cased, other runs one `-`.
fn slug(s: &str, max: usize) -> String {
    let mut out = String::new();
    let mut gap = false;
    for c in s.chars() {
        if c.is_ascii_alphanumeric() {
            if gap && !out.is_empty() {
                if out.len() + 1 >= max {
                    break;
                }
                out.push('-');
            }
            gap = false;
            out.push(c.to_ascii_lowercase());
            if out.len() >= max {
                break;
            }
        } else {
            gap = true;
        }
    }
    out
}

/// Unique predicate names for `objects` (in the order given).
fn object_names(foon: &Foon, objects: &[u32]) -> Vec<String> {
    let mut taken: FxHashSet<String> = RESERVED.iter().map(|&s| s.to_owned()).collect();
    objects
        .iter()
        .map(|&o| {
            let mut base = slug(&object_line(foon, o), NAME_MAX);
            if base.is_empty() {
                base.push_str("item");
            } else if base.starts_with(|c: char| c.is_ascii_digit()) {
                base.insert_str(0, "o-");
            }
            let mut name = base.clone();
            let mut k = 2u32;
            while taken.contains(&name) {
                name = format!("{base}-{k}");
                k += 1;
            }
            taken.insert(name.clone());
            name
        })
        .collect()
}

fn action_name(foon: &Foon, fu: u32) -> String {
    let m = slug(foon.motion_text(fu), NAME_MAX);
    if m.is_empty() {
        format!("fu{fu}")
    } else {
        format!("fu{fu}-{m}")
    }
}

/// Text on one comment line.
fn comment(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

/// `round(-ln(rate) * scale)` for a rate in (0, 1].
#[allow(
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    reason = "the value is finite, at least 0 and at most 745 * u32::MAX"
)]
fn action_cost(rate: f64, scale: u32) -> u64 {
    (-rate.ln() * f64::from(scale)).round().max(0.0) as u64
}

struct Action {
    fu: u32,
    pre: Vec<u32>,
    eff: Vec<u32>,
    cost: Option<u64>,
    rate: Option<f64>,
}

fn dedup(items: impl Iterator<Item = u32>) -> Vec<u32> {
    let mut seen = FxHashSet::default();
    items.filter(|&x| seen.insert(x)).collect()
}

/// The domain and the problem of making `goal` from the kitchen of `prep` with `units`
/// (sorted, distinct); `what` says where the units come from, `notes` are extra comment
/// lines for the header.
fn problem_text(
    foon: &Foon,
    prep: &Prepared,
    goal: u32,
    units: &[u32],
    what: &str,
    notes: &[String],
    opts: &Options,
) -> Result<String> {
    let costs = prep.rates_given() && opts.cost_scale > 0;
    let mut actions = Vec::with_capacity(units.len());
    let mut never = Vec::new();
    for &f in units {
        let (cost, rate) = if costs {
            let r = prep.rate(foon, f)?;
            if r <= 0.0 {
                never.push(f);
                continue;
            }
            (Some(action_cost(r, opts.cost_scale)), Some(r))
        } else {
            (None, None)
        };
        actions.push(Action {
            fu: f,
            pre: dedup(prep.needed(f).iter().copied()),
            eff: dedup(
                foon.outputs(f)
                    .iter()
                    .copied()
                    .filter(|&o| !foon.is_bare(o)),
            ),
            cost,
            rate,
        });
    }
    let mut mentioned = vec![goal];
    for a in &actions {
        mentioned.extend(&a.pre);
        mentioned.extend(&a.eff);
    }
    mentioned.sort_unstable();
    mentioned.dedup();
    let names = object_names(foon, &mentioned);
    let name = |o: u32| {
        let i = mentioned.binary_search(&o).unwrap_or_default();
        names[i].as_str()
    };
    let atoms = |objs: &[u32]| {
        let mut s = String::from("(and");
        for &o in objs {
            let _ = write!(s, " ({})", name(o));
        }
        s.push(')');
        s
    };

    let mut s = String::new();
    s.push_str("; A FOON planning problem in PDDL: the domain, then the problem after the line\n");
    let _ = writeln!(s, "; \"{PROBLEM_LINE}\".");
    let _ = writeln!(s, "; goal: {}", comment(&object_line(foon, goal)));
    let _ = writeln!(s, "; actions: {} units of {what}", actions.len());
    if costs {
        let _ = writeln!(
            s,
            "; action costs: round(-ln(success rate) * {})",
            opts.cost_scale
        );
    } else {
        s.push_str("; no action costs (no motion rates)\n");
    }
    for n in notes {
        let _ = writeln!(s, "; {}", comment(n));
    }
    for &f in &never {
        let _ = writeln!(
            s,
            "; unit {f} ({}) is left out: its motion's success rate is 0",
            comment(foon.motion_text(f))
        );
    }
    s.push_str("(define (domain foon)\n");
    if costs {
        s.push_str("  (:requirements :strips :action-costs)\n");
    } else {
        s.push_str("  (:requirements :strips)\n");
    }
    s.push_str("  (:predicates\n");
    for (o, n) in mentioned.iter().zip(&names) {
        let _ = writeln!(s, "    ({n}) ; {}", comment(&object_line(foon, *o)));
    }
    s.push_str("  )\n");
    if costs {
        s.push_str("  (:functions (total-cost) - number)\n");
    }
    for a in &actions {
        let _ = writeln!(s, "  (:action {}", action_name(foon, a.fu));
        let _ = write!(
            s,
            "    ; unit {} (line {}): {}",
            a.fu,
            foon.fu_line(a.fu),
            comment(foon.motion_text(a.fu))
        );
        if let Some(r) = a.rate {
            let _ = write!(s, ", success rate {r}");
        }
        s.push('\n');
        s.push_str("    :parameters ()\n");
        let _ = writeln!(s, "    :precondition {}", atoms(&a.pre));
        let mut eff = atoms(&a.eff);
        if let Some(c) = a.cost {
            eff.pop();
            let _ = write!(eff, " (increase (total-cost) {c}))");
        }
        let _ = writeln!(s, "    :effect {eff}\n  )");
    }
    s.push_str(")\n");
    s.push_str(PROBLEM_LINE);
    s.push('\n');
    s.push_str("(define (problem make-");
    s.push_str(name(goal));
    s.push_str(")\n  (:domain foon)\n  (:init");
    for &o in &mentioned {
        if prep.in_kitchen(o) {
            let _ = write!(s, "\n    ({})", name(o));
        }
    }
    if costs {
        s.push_str("\n    (= (total-cost) 0)");
    }
    s.push_str(")\n");
    let _ = writeln!(s, "  (:goal ({}))", name(goal));
    if costs {
        s.push_str("  (:metric minimize (total-cost))\n");
    }
    s.push_str(")\n");
    Ok(s)
}

/// The goal's ancestry (see the module documentation), in FOON order, within `allowed`
/// units when given.
fn ancestry(foon: &Foon, prep: &Prepared, goal: u32, allowed: Option<&[bool]>) -> Vec<u32> {
    let ranks = prep.ranks(foon);
    let mut fu_seen = vec![false; foon.fu_count()];
    let mut obj_seen = vec![false; foon.object_count()];
    obj_seen[goal as usize] = true;
    let mut stack = vec![goal];
    while let Some(o) = stack.pop() {
        if prep.in_kitchen(o) {
            continue;
        }
        for &f in foon.producers(o) {
            if fu_seen[f as usize]
                || allowed.is_some_and(|a| !a[f as usize])
                || !prep.needed(f).iter().all(|&x| ranks.is_derivable(x))
            {
                continue;
            }
            fu_seen[f as usize] = true;
            for &x in prep.needed(f) {
                if !obj_seen[x as usize] {
                    obj_seen[x as usize] = true;
                    stack.push(x);
                }
            }
        }
    }
    (0..foon.fu_count() as u32)
        .filter(|&f| fu_seen[f as usize])
        .collect()
}

/// The problem of making `doc.focus` from the kitchen of `doc.prep` (see the module
/// documentation).
pub(super) fn write_foon(doc: &FoonDoc<'_>, opts: &Options, out: &mut dyn io::Write) -> Result<()> {
    let foon = doc.foon;
    let goal = doc.focus.ok_or_else(|| {
        Error::Invalid("a PDDL problem needs a goal: give one (--goal)".to_owned())
    })?;
    let prep = doc.prep.ok_or_else(|| {
        Error::Invalid(
            "a PDDL problem needs a kitchen for its initial state: give one (--kitchen)".to_owned(),
        )
    })?;
    prep.check_foon(foon)?;
    if goal as usize >= foon.object_count() {
        return Err(Error::Invalid(format!(
            "object {goal} is not in the FOON (it has {} objects)",
            foon.object_count()
        )));
    }
    let allowed = doc.units.as_ref().map(|us| {
        let mut a = vec![false; foon.fu_count()];
        for &u in us {
            if let Some(x) = a.get_mut(u as usize) {
                *x = true;
            }
        }
        a
    });
    let units = ancestry(foon, prep, goal, allowed.as_deref());
    let what = if doc.units.is_some() {
        "the goal's ancestry within the units selected"
    } else {
        "the goal's ancestry"
    };
    let text = problem_text(foon, prep, goal, &units, what, &[], opts)?;
    put(out, text.as_bytes())
}

/// A task tree as a problem whose actions are the tree's units (one tree a document).
pub(super) struct PddlTree {
    opts: Options,
}

impl PddlTree {
    pub(super) fn new(opts: &Options) -> Self {
        Self { opts: opts.clone() }
    }
}

impl TreeFormat for PddlTree {
    fn tree(&mut self, doc: &TreeDoc<'_>, out: &mut dyn io::Write) -> Result<()> {
        doc.prep.check_foon(doc.foon)?;
        let mut units = doc.units().to_vec();
        units.sort_unstable();
        units.dedup();
        let mut notes = Vec::new();
        if !doc.plan.solved {
            let why = super::explanation_text(doc.foon, doc.plan);
            notes.push(if why.is_empty() {
                "the tree is not a solution".to_owned()
            } else {
                format!("the tree is not a solution: {why}")
            });
        }
        let text = problem_text(
            doc.foon,
            doc.prep,
            doc.goal(),
            &units,
            "the task tree",
            &notes,
            &self.opts,
        )?;
        put(out, text.as_bytes())
    }

    fn failed(&mut self, f: &Failed, _out: &mut dyn io::Write) -> Result<()> {
        let goal = f.goal_text();
        Err(Error::Invalid(format!(
            "no PDDL problem for {goal}: {}",
            f.error
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{MotionRates, ObjectSpec};
    use crate::parse::{ParseOptions, parse_foon};

    fn foon(text: &str) -> Foon {
        parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap()
    }

    fn item(label: &str, states: &[&str]) -> ObjectSpec {
        ObjectSpec {
            label: label.to_owned(),
            states: states.iter().map(|&s| s.to_owned()).collect(),
            ..ObjectSpec::default()
        }
    }

    #[test]
    fn names_avoid_pddl_words_and_each_other() {
        let f = foon(
            "O\tand\nM\tmix\nO\tand\nS\tx\n//\n\
             O\tand x\nM\tmix\nO\t7up\nS\t!\n//\n\
             O\t\u{e9}\nM\tstir\nO\tand\nS\t2\n//\n",
        );
        let all: Vec<u32> = (0..f.object_count() as u32).collect();
        let names = object_names(&f, &all);
        // and, and (x), and x, 7up (!), é, and (2)
        assert_eq!(
            names,
            ["and-2", "and-x", "and-x-2", "o-7up", "item", "and-2-2"]
        );
    }

    #[test]
    fn a_problem_with_and_without_costs() {
        let f = foon(
            "O\tegg\nS\twhole\nM\tcrack\nO\tegg\nS\tcracked\n//\n\
             O\tegg\nS\tcracked\nM\tfry\nO\tegg\nS\tfried\nO\tpan\n//\n",
        );
        let kitchen = [item("egg", &["whole"]), item("pan", &[])];
        let goal = f.goal_by_spec(&item("egg", &["fried"])).unwrap();
        let rates =
            MotionRates::from_pairs([("crack".to_owned(), 0.5), ("fry".to_owned(), 1.0)]).unwrap();
        let opts = Options::default();
        let plain = Prepared::new(&f, &kitchen, &[], None, None).unwrap();
        let text = problem_text(&f, &plain, goal, &[0, 1], "x", &[], &opts).unwrap();
        let (d, p) = split(&text).unwrap();
        assert!(d.contains(":precondition (and (egg-whole))\n"), "{d}");
        // A bare output (the pan) is no effect; nothing is deleted.
        assert!(d.contains(":effect (and (egg-fried))\n"), "{d}");
        assert!(!d.contains("not") && !d.contains("total-cost"), "{d}");
        assert!(
            p.contains("(:init\n    (egg-whole))\n  (:goal (egg-fried))\n"),
            "{p}"
        );
        let rated = Prepared::new(&f, &kitchen, &[], Some(&rates), None).unwrap();
        let text = problem_text(&f, &rated, goal, &[0, 1], "x", &[], &opts).unwrap();
        assert!(text.contains("(increase (total-cost) 693))"), "{text}");
        assert!(text.contains("(increase (total-cost) 0))"), "{text}");
        assert!(text.contains("(:metric minimize (total-cost))"), "{text}");
        let partial = MotionRates::from_pairs([("fry".to_owned(), 1.0)]).unwrap();
        let missing = Prepared::new(&f, &kitchen, &[], Some(&partial), None).unwrap();
        let err = problem_text(&f, &missing, goal, &[0, 1], "x", &[], &opts).unwrap_err();
        assert!(matches!(err, Error::MissingRate { ref motion } if motion == "crack"));
    }

    #[test]
    fn slugs_are_pddl_names() {
        assert_eq!(
            slug("onion (chopped) in [cutting board]", 60),
            "onion-chopped-in-cutting-board"
        );
        assert_eq!(slug("  ", 60), "");
        assert_eq!(slug("Jalapeño", 60), "jalape-o");
        assert!(slug(&"ab ".repeat(50), 60).len() <= 60);
        assert!(!slug(&"ab ".repeat(50), 60).ends_with('-'));
    }

    #[test]
    fn split_finds_the_problem_line() {
        let t = format!("(define (domain d))\n{PROBLEM_LINE}\n(define (problem p))\n");
        assert_eq!(
            split(&t),
            Some(("(define (domain d))\n", "(define (problem p))\n"))
        );
        assert_eq!(split("(define (domain d))\n"), None);
    }

    #[test]
    fn costs_round_minus_log_rate() {
        assert_eq!(action_cost(1.0, 1000), 0);
        assert_eq!(action_cost(0.9, 1000), 105);
        assert_eq!(action_cost(0.1, 1000), 2303);
        assert!(action_cost(f64::MIN_POSITIVE, u32::MAX) > 3_000_000_000_000);
    }
}
