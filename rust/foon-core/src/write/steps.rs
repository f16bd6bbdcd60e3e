//! Numbered plain-English steps, in execution order: `3. Chop the whole onion on the
//! cutting board with the knife.`
//!
//! # Roles
//!
//! Each unit's objects are given roles from the unit's own structure (no outside word list
//! is needed to tell a tool from food):
//!
//! - a **tool** is an input that carries nothing (no ingredients, no container, no state
//!   but `empty`, `clean` or `dirty`), holds no other object of the unit, is not an
//!   ingredient of an output, and leaves the unit the same way or not at all (`knife`,
//!   `spoon (empty)`);
//! - an object **holds** another when it is the other's container (`[bowl]`) before or after
//!   the unit; of two objects that hold each other (`stove in [pot]`, `pot in [stove]`) the
//!   one with ingredients is taken as the one held;
//! - the **moved** objects (transfer motions) are the inputs, not tools and holding nothing,
//!   whose container changes (`macaroni in [jar]` → `macaroni in [pot]`), else those used up
//!   (no output of their label), else the changed ones; they come **from** their container
//!   and go **to** their new container, or else to the input that gains ingredients (the
//!   one holding nothing else first);
//! - the **acted-on** objects (other motions) are the changed inputs that are not tools and
//!   hold nothing, else the changed ones, else every input but the tools; they are worked
//!   **at** their container; what the unit **makes** are its outputs of new labels.
//!
//! # Wording
//!
//! An object reads `the` + its states as adjectives + its label (`the whole onion`); the
//! states `on` and `off` are left out (the motion says them) and so are states holding
//! brackets. Ingredients read `the bowl of lettuce and tomato` for a vessel (a label that
//! some object of the FOON has `empty`) and `the bread with butter` otherwise; acted on, a
//! vessel with ingredients reads `the lettuce and tomato in the bowl`. Places read `on` /
//! `onto` for surfaces (a label ending in board, plate, tray, sheet, table, surface, counter,
//! griddle, grill, stove, paper, foil, rack, napkin, tortilla, bread, bun, dough, pancake,
//! patty or pizza) and `in` / `into` otherwise. Runs of white space become one space and
//! every step ends with a period.
//!
//! # Templates
//!
//! The course's most frequent motions have their own sentence ([`TEMPLATES`], 58 motions
//! covering more than 90% of the course FOON's units). A template is a list of patterns;
//! the first whose required slots (outside `[...]`) are all filled is used, and a `[...]`
//! part is left out when one of its slots is empty. Slots: `{moved}`, `{from}`, `{dst}`
//! with `{to}` (into / onto), `{it}` (it / them), `{obj}`, `{at}` with `{in}` (in / on),
//! `{tools}`, `{make}`. Every template names each word of its motion, so a step always
//! says its motion.
//!
//! # Fallback
//!
//! Every other motion (and a template none of whose patterns fits) reads
//! `{Motion} {obj}[ {in} {at}][ with {tools}][ to get {made}].`: the motion as written, the
//! acted-on objects, their place, the tools, and the outputs that differ from the inputs
//! (tools left out). A unit without inputs reads `{Motion}[ to get {made}].`.

use std::fmt::Write as _;
use std::io;

use rustc_hash::FxHashSet;

use super::{Failed, TreeDoc, TreeFormat, put};
use crate::error::Result;
use crate::index::{Foon, NONE};

/// The motions with their own sentence, each with its patterns (see the module doc).
pub(super) const TEMPLATES: &[(&str, &[&str])] = &[
    (
        "pour",
        &["Pour {moved}[ from {from}][ {to} {dst}][ with {tools}]."],
    ),
    (
        "pick-and-place",
        &["Pick up {moved}[ from {from}] and place {it}[ {to} {dst}][ with {tools}]."],
    ),
    (
        "sprinkle",
        &["Sprinkle {moved}[ from {from}][ {to} {dst}][ with {tools}]."],
    ),
    (
        "mix",
        &["Mix {obj}[ {in} {at}][ with {tools}][ to make {make}]."],
    ),
    (
        "stir",
        &["Stir {obj}[ {in} {at}][ with {tools}][ to make {make}]."],
    ),
    (
        "scoop and pour",
        &["Scoop {moved}[ from {from}] and pour {it}[ {to} {dst}][ with {tools}]."],
    ),
    (
        "scrape",
        &["Scrape {moved}[ from {from}][ {to} {dst}][ with {tools}]."],
    ),
    (
        "cook and stir",
        &["Cook and stir {obj}[ {in} {at}][ with {tools}][ to make {make}]."],
    ),
    (
        "cook",
        &["Cook {obj}[ {in} {at}][ with {tools}][ to make {make}]."],
    ),
    ("remove", &["Remove {moved}[ from {from}][ with {tools}]."]),
    ("chop", &["Chop {obj}[ {in} {at}][ with {tools}]."]),
    ("cut", &["Cut {obj}[ {in} {at}][ with {tools}]."]),
    (
        "pour and scrape",
        &["Pour and scrape {moved}[ from {from}][ {to} {dst}][ with {tools}]."],
    ),
    (
        "scoop",
        &["Scoop {moved}[ from {from}][ {to} {dst}][ with {tools}]."],
    ),
    ("slice", &["Slice {obj}[ {in} {at}][ with {tools}]."]),
    ("peel", &["Peel {obj}[ {in} {at}][ with {tools}]."]),
    ("spread", &["Spread {moved}[ on {dst}][ with {tools}]."]),
    (
        "put inside",
        &[
            "Put {moved} inside {dst}[ with {tools}].",
            "Put {moved} inside.",
        ],
    ),
    ("turn on", &["Turn on {obj}."]),
    ("turn off", &["Turn off {obj}."]),
    ("heat", &["Heat {obj}[ {in} {at}][ with {tools}]."]),
    ("flip", &["Flip {obj}[ {in} {at}][ with {tools}]."]),
    (
        "bake",
        &["Bake {obj}[ {in} {at}][ with {tools}][ to make {make}]."],
    ),
    (
        "beat",
        &["Beat {obj}[ {in} {at}][ with {tools}][ to make {make}]."],
    ),
    ("grate", &["Grate {moved}[ {to} {dst}][ with {tools}]."]),
    ("open", &["Open {obj}[ with {tools}]."]),
    ("grind", &["Grind {moved}[ {to} {dst}][ with {tools}]."]),
    (
        "cover",
        &["Cover {dst} with {moved}.", "Cover {obj}[ with {tools}]."],
    ),
    (
        "blend",
        &["Blend {obj}[ {in} {at}][ with {tools}][ to make {make}]."],
    ),
    (
        "uncover",
        &["Uncover {from} by lifting off {moved}.", "Uncover {obj}."],
    ),
    ("crack", &["Crack {moved}[ {to} {dst}][ with {tools}]."]),
    ("wash", &["Wash {obj}[ {in} {at}][ with {tools}]."]),
    ("squeeze", &["Squeeze {moved}[ {to} {dst}][ with {tools}]."]),
    ("detach", &["Detach {moved}[ from {from}][ with {tools}]."]),
    ("shake", &["Shake {obj}[ {in} {at}][ with {tools}]."]),
    ("roll", &["Roll {obj}[ {in} {at}][ with {tools}]."]),
    ("dice", &["Dice {obj}[ {in} {at}][ with {tools}]."]),
    ("insert", &["Insert {moved}[ into {dst}][ with {tools}]."]),
    ("attach", &["Attach {moved}[ to {dst}][ with {tools}]."]),
    (
        "shape",
        &["Shape {obj}[ {in} {at}][ with {tools}][ to make {make}]."],
    ),
    ("place", &["Place {moved}[ {to} {dst}][ with {tools}]."]),
    ("boil", &["Boil {obj}[ {in} {at}][ with {tools}]."]),
    ("spray", &["Spray {moved}[ {to} {dst}][ with {tools}]."]),
    (
        "scrape and pour",
        &["Scrape {moved}[ from {from}] and pour {it}[ {to} {dst}][ with {tools}]."],
    ),
    ("press", &["Press {obj}[ {in} {at}][ with {tools}]."]),
    ("mash", &["Mash {obj}[ {in} {at}][ with {tools}]."]),
    ("fold", &["Fold {obj}[ {in} {at}][ with {tools}]."]),
    ("drain", &["Drain {obj}[ {in} {at}][ with {tools}]."]),
    ("dip", &["Dip {moved}[ into {dst}][ with {tools}]."]),
    ("rinse", &["Rinse {obj}[ {in} {at}][ with {tools}]."]),
    ("preheat", &["Preheat {obj}."]),
    (
        "pour and stir",
        &["Pour {moved}[ {to} {dst}] and stir[ with {tools}]."],
    ),
    ("measure", &["Measure {moved}[ {to} {dst}][ with {tools}]."]),
    ("knead", &["Knead {obj}[ {in} {at}][ with {tools}]."]),
    ("simmer", &["Simmer {obj}[ {in} {at}][ with {tools}]."]),
    ("melt", &["Melt {obj}[ {in} {at}][ with {tools}]."]),
    ("chill", &["Chill {obj}[ {in} {at}]."]),
    (
        "pour and mix",
        &["Pour {moved}[ {to} {dst}] and mix[ with {tools}]."],
    ),
];

/// Last words of labels read as surfaces (`on the cutting board`).
const SURFACES: &[&str] = &[
    "board", "plate", "tray", "sheet", "table", "surface", "counter", "griddle", "grill", "stove",
    "paper", "foil", "rack", "napkin", "tortilla", "bread", "bun", "dough", "pancake", "patty",
    "pizza",
];

/// States that a tool may have.
const TOOL_STATES: &[&str] = &["empty", "clean", "dirty"];

/// States left out of the wording.
const SILENT_STATES: &[&str] = &["on", "off"];

fn is_surface(label: &str) -> bool {
    let last = label.rsplit([' ', '-']).next().unwrap_or(label);
    SURFACES.contains(&last.to_lowercase().as_str())
}

fn capitalised(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map_or_else(String::new, |f| f.to_uppercase().chain(c).collect())
}

fn join(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [a] => a.clone(),
        [a, b] => format!("{a} and {b}"),
        [rest @ .., last] => format!("{}, and {last}", rest.join(", ")),
    }
}

/// What the wording of one FOON needs: its vessel labels (computed once per FOON).
struct Words<'a> {
    foon: &'a Foon,
    vessels: &'a FxHashSet<u32>,
}

impl<'a> Words<'a> {
    fn new(foon: &'a Foon) -> Self {
        Self {
            foon,
            vessels: foon.empty_labels(),
        }
    }

    /// The object's states that read as adjectives, in its written order.
    fn adjectives(&self, o: u32) -> Vec<&'a str> {
        let foon = self.foon;
        foon.variant_states(foon.first_variant(o))
            .iter()
            .map(|&s| foon.text(s).trim())
            .filter(|s| {
                !s.is_empty()
                    && !SILENT_STATES.contains(s)
                    && !s.contains(['[', ']', '(', ')', '{', '}'])
            })
            .collect()
    }

    /// The object's ingredients, in written order, repeats and empty names and `skip`
    /// left out.
    fn ingredients(&self, o: u32, skip: &[u32]) -> Vec<String> {
        let foon = self.foon;
        let mut seen = FxHashSet::default();
        foon.variant_ingredients(foon.first_variant(o))
            .iter()
            .filter(|&&s| !skip.contains(&s) && !foon.text(s).trim().is_empty() && seen.insert(s))
            .map(|&s| foon.text(s).trim().to_owned())
            .collect()
    }

    /// `the` + adjectives + label.
    fn plain(&self, o: u32) -> String {
        let mut s = String::from("the ");
        let adj = self.adjectives(o);
        if !adj.is_empty() {
            s.push_str(&adj.join(", "));
            s.push(' ');
        }
        s.push_str(self.foon.label_text(o).trim());
        s
    }

    /// An object with its ingredients (`skip` left out): `the bowl of salt`, `the bread
    /// with butter`; acted on, a vessel reads `the salt in the bowl`.
    fn object(&self, o: u32, skip: &[u32], acted_on: bool) -> String {
        let ing = self.ingredients(o, skip);
        if ing.is_empty() {
            return self.plain(o);
        }
        let vessel = self.vessels.contains(&self.foon.label(o));
        if vessel && acted_on {
            format!("the {} in {}", join(&ing), self.plain(o))
        } else if vessel {
            format!("{} of {}", self.plain(o), join(&ing))
        } else {
            format!("{} with {}", self.plain(o), join(&ing))
        }
    }

    fn objects(&self, objs: &[u32], skip: &[u32], acted_on: bool) -> String {
        let v: Vec<String> = objs
            .iter()
            .map(|&o| self.object(o, skip, acted_on))
            .collect();
        join(&v)
    }
}

/// The roles of one unit's objects (see the module doc).
#[derive(Default)]
struct Roles {
    tools: Vec<u32>,
    moved: Vec<u32>,
    /// Where the moved objects come from (a container name).
    from: u32,
    /// Where they go: an input object, else a container name.
    dst_obj: Option<u32>,
    dst_name: u32,
    obj: Vec<u32>,
    /// Where the acted-on objects are (a container name).
    at: u32,
    make: Vec<u32>,
    made: Vec<u32>,
}

fn roles(foon: &Foon, fu: u32) -> Roles {
    let ins = foon.inputs(fu);
    let outs = foon.outputs(fu);
    let label = |o: u32| foon.label(o);
    let tool_state = |s: u32| TOOL_STATES.contains(&foon.text(s).trim());
    let bare = |o: u32| {
        foon.ingredients(o).is_empty()
            && foon.container(o) == NONE
            && foon.states(o).iter().all(|&s| tool_state(s))
    };
    // The output that continues input `i`: itself, else the first of its label.
    let succ = |i: u32| {
        if outs.contains(&i) {
            Some(i)
        } else {
            outs.iter().copied().find(|&o| label(o) == label(i))
        }
    };
    let out_container = |i: u32| succ(i).map_or(NONE, |o| foon.container(o));
    // `i` holds `x` (see the module doc).
    let holds = |i: u32, x: u32| {
        if i == x {
            return false;
        }
        let li = label(i);
        let direct = foon.container(x) == li || (ins.contains(&x) && out_container(x) == li);
        let lx = label(x);
        let mutual = foon.container(i) == lx || out_container(i) == lx;
        direct && !(mutual && !foon.ingredients(i).is_empty() && foon.ingredients(x).is_empty())
    };
    let all: Vec<u32> = ins.iter().chain(outs).copied().collect();
    let holder = |i: u32| all.iter().any(|&x| holds(i, x));
    let in_output_ingredients = |i: u32| {
        outs.iter()
            .any(|&o| foon.ingredients(o).contains(&label(i)))
    };
    let mut r = Roles {
        from: NONE,
        dst_name: NONE,
        at: NONE,
        ..Roles::default()
    };
    for &i in ins {
        let is_tool = bare(i)
            && succ(i).is_none_or(bare)
            && !holder(i)
            && !in_output_ingredients(i)
            && !r.tools.contains(&i);
        if is_tool {
            r.tools.push(i);
        }
    }
    let cands: Vec<u32> = ins
        .iter()
        .copied()
        .filter(|i| !r.tools.contains(i))
        .collect();
    let changed = |i: u32| !outs.contains(&i);
    let moved = |i: u32| succ(i).is_some_and(|o| o != i && foon.container(o) != foon.container(i));
    let used_up = |i: u32| succ(i).is_none();
    let pick = |tests: &[&dyn Fn(u32) -> bool]| -> Vec<u32> {
        for t in tests {
            let mut v: Vec<u32> = Vec::new();
            for &i in &cands {
                if t(i) && !v.contains(&i) {
                    v.push(i);
                }
            }
            if !v.is_empty() {
                return v;
            }
        }
        Vec::new()
    };
    r.moved = pick(&[
        &|i| moved(i) && !holder(i),
        &|i| used_up(i) && !holder(i),
        &|i| moved(i),
        &|i| changed(i),
        &|_| true,
    ]);
    r.obj = pick(&[&|i| changed(i) && !holder(i), &|i| changed(i), &|_| true]);
    if let Some(&m) = r.moved.first() {
        r.from = foon.container(m);
        if moved(m) {
            r.dst_name = out_container(m);
        }
        let names: Vec<u32> = r.moved.iter().map(|&o| label(o)).collect();
        if r.dst_name == NONE {
            // The input that gains ingredients, one holding nothing else first.
            let gains = |i: u32| {
                !r.moved.contains(&i)
                    && !r.tools.contains(&i)
                    && succ(i).is_some_and(|o| {
                        let before = foon.ingredients(i);
                        foon.ingredients(o).iter().any(|s| !before.contains(s))
                    })
            };
            let gaining: Vec<u32> = ins.iter().copied().filter(|&i| gains(i)).collect();
            r.dst_obj = gaining
                .iter()
                .copied()
                .find(|&i| !gaining.iter().any(|&x| holds(i, x)))
                .or_else(|| gaining.first().copied());
            if r.dst_obj.is_none() && r.from != NONE {
                // Used up from a container: it goes where its label shows up as contents.
                r.dst_obj = ins.iter().copied().find(|&i| {
                    !r.moved.contains(&i)
                        && label(i) != r.from
                        && succ(i)
                            .is_some_and(|o| names.iter().any(|n| foon.ingredients(o).contains(n)))
                });
            }
        } else {
            r.dst_obj = ins
                .iter()
                .copied()
                .find(|&i| label(i) == r.dst_name && !r.moved.contains(&i));
        }
        if let Some(d) = r.dst_obj {
            r.dst_name = label(d);
        }
        if r.dst_name == r.from {
            r.from = NONE;
        }
    }
    if let Some(&o) = r.obj.first() {
        r.at = foon.container(o);
    }
    let in_labels: Vec<u32> = ins.iter().map(|&i| label(i)).collect();
    for &o in outs {
        if r.tools.contains(&o) || r.make.contains(&o) {
            continue;
        }
        if !in_labels.contains(&label(o)) {
            r.make.push(o);
        }
        if !ins.contains(&o) && !r.made.contains(&o) {
            r.made.push(o);
        }
    }
    r
}

/// Fills `pattern`; `None` when a required slot is empty.
fn fill(pattern: &str, slot: &dyn Fn(&str) -> String) -> Option<String> {
    let mut out = String::new();
    let mut rest = pattern;
    let mut optional: Option<(String, bool)> = None;
    while let Some(c) = rest.chars().next() {
        if c == '{' {
            let end = rest.find('}')?;
            let v = slot(&rest[1..end]);
            match &mut optional {
                Some((buf, ok)) => {
                    *ok &= !v.is_empty();
                    buf.push_str(&v);
                }
                None if v.is_empty() => return None,
                None => out.push_str(&v),
            }
            rest = &rest[end + 1..];
            continue;
        }
        match c {
            '[' => optional = Some((String::new(), true)),
            ']' => {
                if let Some((buf, true)) = optional.take() {
                    out.push_str(&buf);
                }
            }
            _ => match &mut optional {
                Some((buf, _)) => buf.push(c),
                None => out.push(c),
            },
        }
        rest = &rest[c.len_utf8()..];
    }
    Some(out)
}

fn name(foon: &Foon, s: u32) -> String {
    if s == NONE {
        String::new()
    } else {
        format!("the {}", foon.text(s).trim())
    }
}

fn step(w: &Words<'_>, fu: u32) -> String {
    let foon = w.foon;
    let r = roles(foon, fu);
    let moved_labels: Vec<u32> = r.moved.iter().map(|&o| foon.label(o)).collect();
    let place_word = |s: u32, on: &str, inside: &str| {
        if s != NONE && is_surface(foon.text(s)) {
            on.to_owned()
        } else {
            inside.to_owned()
        }
    };
    let slot = |k: &str| -> String {
        match k {
            "moved" => w.objects(&r.moved, &[], false),
            "it" => if r.moved.len() > 1 { "them" } else { "it" }.to_owned(),
            "from" => name(foon, r.from),
            "dst" => match r.dst_obj {
                Some(d) => w.object(d, &moved_labels, false),
                None => name(foon, r.dst_name),
            },
            "to" => place_word(r.dst_name, "onto", "into"),
            "obj" => w.objects(&r.obj, &[], true),
            "at" => name(foon, r.at),
            "in" => place_word(r.at, "on", "in"),
            "tools" => join(&r.tools.iter().map(|&t| w.plain(t)).collect::<Vec<_>>()),
            "make" => join(&r.make.iter().map(|&t| w.plain(t)).collect::<Vec<_>>()),
            "made" => w.objects(&r.made, &[], false),
            _ => String::new(),
        }
    };
    let motion = foon.motion_text(fu).trim();
    let key = motion.to_lowercase();
    let templated = TEMPLATES
        .iter()
        .find(|(m, _)| *m == key)
        .and_then(|(_, patterns)| patterns.iter().find_map(|p| fill(p, &slot)));
    let s = templated.unwrap_or_else(|| {
        let verb = if motion.is_empty() {
            "Carry out the unit".to_owned()
        } else {
            capitalised(motion)
        };
        let pattern =
            format!("{verb}[ {{obj}}][ {{in}} {{at}}][ with {{tools}}][ to get {{made}}].");
        fill(&pattern, &slot).unwrap_or_else(|| format!("{verb}."))
    });
    tidy(&s)
}

/// One space between words, none at the ends, a period at the end.
fn tidy(s: &str) -> String {
    let mut out = s.split_whitespace().collect::<Vec<_>>().join(" ");
    if !out.ends_with('.') {
        out.push('.');
    }
    out
}

/// The steps of a tree, one line each, numbered from 1.
pub(super) fn lines(doc: &TreeDoc<'_>) -> Vec<String> {
    let w = Words::new(doc.foon);
    doc.units()
        .iter()
        .enumerate()
        .map(|(i, &f)| format!("{}. {}", i + 1, step(&w, f)))
        .collect()
}

/// Task trees as steps; with `many`, each after a `# goal: ...` line.
pub(super) struct StepTrees {
    many: bool,
}

impl StepTrees {
    pub(super) fn new(many: bool) -> Self {
        Self { many }
    }
}

impl TreeFormat for StepTrees {
    fn tree(&mut self, doc: &TreeDoc<'_>, out: &mut dyn io::Write) -> Result<()> {
        let mut s = String::new();
        if self.many {
            let _ = writeln!(s, "# goal: {}", super::object_line(doc.foon, doc.goal()));
        }
        for l in lines(doc) {
            s.push_str(&l);
            s.push('\n');
        }
        put(out, s.as_bytes())
    }

    fn failed(&mut self, f: &Failed, out: &mut dyn io::Write) -> Result<()> {
        if self.many {
            return put(out, format!("# goal: {}\n", f.goal_text()).as_bytes());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use rustc_hash::FxHashMap;

    use super::{TEMPLATES, Words, step};
    use crate::{ParseOptions, load_foon};

    /// The templates cover the course FOON's 30 most frequent motions and at least 80% of
    /// its units (frequencies counted here from the data).
    #[test]
    fn templates_cover_the_course_foon() {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/foon/FOON.txt");
        if !p.is_file() {
            assert!(
                std::env::var_os("FOON_REQUIRE_DATA").is_none(),
                "FOON_REQUIRE_DATA is set but ../shared/data/foon is missing"
            );
            eprintln!(
                "skipped: ../shared/data/foon (the real FOON data) is not beside the repository"
            );
            return;
        }
        let foon = load_foon(&p, ParseOptions::default()).unwrap();
        let mut count: FxHashMap<String, usize> = FxHashMap::default();
        for f in 0..foon.fu_count() as u32 {
            *count
                .entry(foon.motion_text(f).trim().to_lowercase())
                .or_default() += 1;
        }
        let mut by_freq: Vec<(String, usize)> = count.into_iter().collect();
        by_freq.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
        let templated = |m: &str| TEMPLATES.iter().any(|(t, _)| *t == m);
        for (m, _) in by_freq.iter().take(30) {
            assert!(templated(m), "no template for the frequent motion {m}");
        }
        let covered: usize = by_freq
            .iter()
            .filter(|(m, _)| templated(m))
            .map(|x| x.1)
            .sum();
        let share = covered as f64 / foon.fu_count() as f64;
        assert!(share >= 0.8, "templates cover {share:.3} of the units");
        // Every unit gets one tidy sentence naming its motion's words.
        let w = Words::new(&foon);
        for f in 0..foon.fu_count() as u32 {
            let s = step(&w, f);
            assert!(
                s.ends_with('.') && !s.contains("  ") && s == s.trim(),
                "{s}"
            );
            let said = s.to_lowercase();
            for word in foon
                .motion_text(f)
                .split([' ', '-'])
                .filter(|x| *x != "and")
            {
                assert!(said.contains(&word.to_lowercase()), "{s} ({word})");
            }
        }
    }

    #[test]
    fn every_template_names_its_motion_and_is_well_formed() {
        for (m, patterns) in TEMPLATES {
            assert_eq!(*m, m.trim().to_lowercase());
            for p in *patterns {
                assert_eq!(p.matches('[').count(), p.matches(']').count(), "{p}");
                assert!(p.ends_with('.'), "{p}");
                let lower = p.to_lowercase();
                for word in m.split([' ', '-']).filter(|x| *x != "and") {
                    assert!(lower.contains(word), "{p} does not say {word}");
                }
            }
        }
    }
}
