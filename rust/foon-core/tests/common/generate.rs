//! A generator of small FOON texts for property tests: a small vocabulary, so that objects
//! are shared by many units (several producers, cycles, self-loops and duplicate units).

use std::fmt::Write as _;

use proptest::prelude::*;

pub(crate) const LABELS: [&str; 6] = ["egg", "bowl", "ice", "tea", "pan", "salt"];
pub(crate) const STATES: [&str; 3] = ["whole", "hot", "mixed"];
pub(crate) const UTENSILS: [&str; 2] = ["bowl", "pan"];
pub(crate) const MOTIONS: [&str; 4] = ["pour", "mix", "heat", "cut"];

/// An object: label, states, ingredient, container (indices into the vocabularies).
pub(crate) type Obj = (usize, Vec<usize>, Option<usize>, Option<usize>);

fn obj() -> impl Strategy<Value = Obj> {
    (
        0..LABELS.len(),
        prop::collection::vec(0..STATES.len(), 0..2),
        prop::option::weighted(0.2, 0..LABELS.len()),
        prop::option::weighted(0.2, 0..UTENSILS.len()),
    )
}

fn text_of(o: &Obj, out: &mut String) {
    let _ = writeln!(out, "O\t{}", LABELS[o.0]);
    for &s in &o.1 {
        let _ = writeln!(out, "S\t{}", STATES[s]);
    }
    if let Some(i) = o.2 {
        let _ = writeln!(out, "S\tcontains\t{{{}}}", LABELS[i]);
    }
    if let Some(c) = o.3 {
        let _ = writeln!(out, "S\tin\t[{}]", UTENSILS[c]);
    }
}

/// A FOON of up to 80 units over a small vocabulary, so that objects are shared by many
/// units (several producers, cycles, self-loops and duplicate units all occur).
pub(crate) fn foon_text() -> impl Strategy<Value = String> {
    prop::collection::vec(
        (
            prop::collection::vec(obj(), 0..4),
            0..MOTIONS.len(),
            prop::collection::vec(obj(), 1..3),
        ),
        1..80,
    )
    .prop_map(|units| {
        let mut t = String::from("//\n");
        for (ins, m, outs) in units {
            for o in &ins {
                text_of(o, &mut t);
            }
            let _ = writeln!(t, "M\t{}", MOTIONS[m]);
            for o in &outs {
                text_of(o, &mut t);
            }
            t.push_str("//\n");
        }
        t
    })
}
