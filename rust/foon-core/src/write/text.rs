//! The course text form of FUs, task trees and FOONs, and one-line object and failure text.

use std::fmt::Write as _;

use crate::index::{Foon, NONE};

/// Appends one object occurrence (variant `var`) in the course form.
fn object_text(foon: &Foon, var: u32, out: &mut String) {
    let obj = foon.variant_object(var);
    out.push_str("O\t");
    out.push_str(foon.label_text(obj));
    out.push('\n');
    for &s in foon.variant_states(var) {
        out.push_str("S\t");
        out.push_str(foon.text(s));
        out.push('\n');
    }
    let ing = foon.variant_ingredients(var);
    if !ing.is_empty() {
        out.push_str("S\tcontains\t{");
        for (i, &s) in ing.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            out.push_str(foon.text(s));
        }
        out.push_str("}\n");
    }
    let c = foon.container(obj);
    if c != NONE {
        let _ = writeln!(out, "S\tin\t[{}]", foon.text(c));
    }
}

/// Appends FU `fu` in the course form: inputs, `M<TAB>motion`, outputs, `//` (no newline
/// after the `//`).
pub fn fu_text(foon: &Foon, fu: u32, out: &mut String) {
    for &v in foon.input_variants(fu) {
        object_text(foon, v, out);
    }
    out.push_str("M\t");
    out.push_str(foon.motion_text(fu));
    out.push('\n');
    for &v in foon.output_variants(fu) {
        object_text(foon, v, out);
    }
    out.push_str("//");
}

/// A task tree in the course output file form: `//` then each FU, each followed by a newline.
pub fn tree_text(foon: &Foon, units: &[u32]) -> String {
    let mut out = String::from("//\n");
    for &f in units {
        fu_text(foon, f, &mut out);
        out.push('\n');
    }
    out
}

/// A whole FOON written back in the course form (a `//` line first, as course files have).
pub fn foon_text(foon: &Foon) -> String {
    let all: Vec<u32> = (0..foon.fu_count() as u32).collect();
    tree_text(foon, &all)
}

/// One object, in its first written form, on one line: `label (s1, s2) {a,b} in [c]`.
pub fn object_line(foon: &Foon, obj: u32) -> String {
    crate::model::ObjectSpec::of_object(foon, obj).describe()
}

/// One line saying why a plan's goal could not be made (empty when it was solved).
pub fn explanation_text(foon: &Foon, plan: &crate::search::Plan) -> String {
    if plan.solved {
        return String::new();
    }
    let list = |ids: &[u32], sep: &str| {
        ids.iter()
            .map(|&o| object_line(foon, o))
            .collect::<Vec<_>>()
            .join(sep)
    };
    if !plan.unresolved.is_empty() {
        return format!(
            "not in the kitchen and not produced by any unit: {}",
            list(&plan.unresolved, "; ")
        );
    }
    let e = plan.explanation.clone().unwrap_or_default();
    if !e.missing.is_empty() {
        return format!("missing from the kitchen: {}", list(&e.missing, "; "));
    }
    if !e.cycle.is_empty() {
        return format!(
            "every way to make it relies on a circular step: {}",
            list(&e.cycle, " -> ")
        );
    }
    if plan.query.method == crate::search::Method::OptimalSuccess {
        return "every way to make it uses a motion whose success rate is 0".to_owned();
    }
    "no task tree exists".to_owned()
}

/// Task trees in the course form; with `many`, each after a `# goal: ...` line.
pub(super) struct TextTrees {
    many: bool,
}

impl TextTrees {
    pub(super) fn new(many: bool) -> Self {
        Self { many }
    }
}

impl super::TreeFormat for TextTrees {
    fn tree(
        &mut self,
        doc: &super::TreeDoc<'_>,
        out: &mut dyn std::io::Write,
    ) -> crate::Result<()> {
        let mut s = String::new();
        if self.many {
            let _ = writeln!(s, "# goal: {}", object_line(doc.foon, doc.goal()));
        }
        if !doc.plan.units.is_empty() || doc.plan.solved {
            s.push_str(&tree_text(doc.foon, &doc.plan.units));
        }
        super::put(out, s.as_bytes())
    }

    fn failed(&mut self, f: &super::Failed, out: &mut dyn std::io::Write) -> crate::Result<()> {
        if self.many {
            return super::put(out, format!("# goal: {}\n", f.goal_text()).as_bytes());
        }
        Ok(())
    }
}
