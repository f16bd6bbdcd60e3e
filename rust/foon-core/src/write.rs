//! Writing FUs and task trees back as text, in the course form.

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
