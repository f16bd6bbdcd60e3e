//! Numbered plain-English steps, in execution order.

use std::fmt::Write as _;
use std::io;

use super::{Failed, TreeDoc, TreeFormat, put};
use crate::error::Result;
use crate::index::Foon;

/// An object in words: `the chopped onion`, `the bowl of salad`.
fn words(foon: &Foon, o: u32) -> String {
    let spec = crate::model::ObjectSpec::of_object(foon, o);
    let mut s = String::from("the ");
    if !spec.states.is_empty() {
        s.push_str(&spec.states.join(", "));
        s.push(' ');
    }
    s.push_str(&spec.label);
    if !spec.ingredients.is_empty() {
        let _ = write!(s, " with {}", spec.ingredients.join(", "));
    }
    s
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

/// The steps of a tree, one line each, numbered from 1.
pub(super) fn lines(doc: &TreeDoc<'_>) -> Vec<String> {
    let foon = doc.foon;
    doc.units()
        .iter()
        .enumerate()
        .map(|(i, &f)| {
            let ins: Vec<String> = foon.inputs(f).iter().map(|&o| words(foon, o)).collect();
            let outs: Vec<String> = foon.outputs(f).iter().map(|&o| words(foon, o)).collect();
            format!(
                "{}. {} {} to get {}.",
                i + 1,
                capitalised(foon.motion_text(f)),
                join(&ins),
                join(&outs)
            )
        })
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
            let goal = if f.label_only {
                f.goal.label.clone()
            } else {
                f.goal.describe()
            };
            return put(out, format!("# goal: {goal}\n").as_bytes());
        }
        Ok(())
    }
}
