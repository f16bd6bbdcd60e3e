//! The picture of `foon explain`: the part of the FOON that blocks a goal, in the FOON visual
//! language (see [`dot`](super::dot)), and the page around it.
//!
//! A blocked goal is drawn with its producers (red squares, arrows to the goal), each
//! producer's blocking inputs (green circles, arrows to the producer) and the blocking cycle
//! (its units and objects, its arrows drawn thick and orange). Every node is drawn once: an
//! object that blocks two producers, or a producer on the cycle, is one node. A blocking
//! input is marked by its kind, by its border and by a last label line:
//!
//! | kind            | border | last label line    | SVG class                      |
//! |-----------------|--------|--------------------|--------------------------------|
//! | missing         | dashed | `[missing]`        | `object blocker missing`       |
//! | cycle           | bold   | `[cycle]`          | `object blocker cycle`         |
//! | not derivable   | dotted | `[not derivable]`  | `object blocker not-derivable` |
//!
//! Objects and units of the blocking cycle carry the class `on-cycle` too, producers the
//! class `producer`, the goal `goal` (it is purple). A goal that is in the kitchen or
//! derivable has no blocking part: its picture is that of its best tree (as `foon plan`
//! draws it).
//!
//! Formats: dot, svg, png, pdf (the picture) and html (the picture inlined, with the
//! explanation's text). The size limit of pictures ([`Options::max_nodes`]) holds.

use std::fmt::Write as _;
use std::io;

use rustc_hash::FxHashSet;

use super::dot::{GREEN, PURPLE, RED, check_size, emit, object_label, quote, quote_title};
use super::html::{escape, inline_svg, page};
use super::{Format, Options, TreeDoc, put, write_tree};
use crate::error::{Error, Result};
use crate::explain::{BlockKind, Explain, Status};
use crate::index::Foon;
use crate::prepare::Prepared;
use crate::search::Context;

/// The colour of the blocking cycle's arrows (orange: none of the node colours).
const CYCLE: &str = "#e67e22";

/// The formats an explanation is written in.
fn writes_explanation(f: Format) -> bool {
    matches!(
        f,
        Format::Dot | Format::Svg | Format::Png | Format::Pdf | Format::Html
    )
}

fn kind_style(kind: BlockKind) -> (&'static str, &'static str) {
    match kind {
        BlockKind::Missing => ("filled,dashed", "[missing]"),
        BlockKind::Cycle => ("filled,bold", "[cycle]"),
        BlockKind::NotDerivable => ("filled,dotted", "[not derivable]"),
    }
}

/// The nodes of the blocking part: (objects, motions) in drawing order, each once.
pub fn blocking_nodes(e: &Explain) -> (Vec<u32>, Vec<u32>) {
    let mut objects = vec![e.goal];
    let mut motions = Vec::new();
    let push = |v: &mut Vec<u32>, x: u32| {
        if !v.contains(&x) {
            v.push(x);
        }
    };
    for p in &e.producers {
        push(&mut motions, p.unit);
        for b in &p.blockers {
            push(&mut objects, b.object);
        }
    }
    for &f in &e.cycle_units {
        push(&mut motions, f);
    }
    for &o in &e.cycle {
        push(&mut objects, o);
    }
    (objects, motions)
}

/// The DOT text of a blocked goal's blocking part.
fn blocking_dot(foon: &Foon, e: &Explain, title: &str) -> String {
    let (objects, motions) = blocking_nodes(e);
    let kind_of = |o: u32| {
        e.producers
            .iter()
            .flat_map(|p| p.blockers.iter())
            .find(|b| b.object == o)
            .map(|b| b.kind)
    };
    let on_cycle_obj: FxHashSet<u32> = e.cycle.iter().copied().collect();
    let on_cycle_unit: FxHashSet<u32> = e.cycle_units.iter().copied().collect();
    let producer: FxHashSet<u32> = e.producers.iter().map(|p| p.unit).collect();
    let mut kinds: Vec<BlockKind> = Vec::new();
    let mut body = String::new();
    for &o in &objects {
        let goal = o == e.goal;
        let kind = kind_of(o);
        let mut class = String::from("object");
        let mut label = object_label(foon, o);
        let mut style = "filled";
        if goal {
            class.push_str(" goal");
        }
        if let Some(k) = kind {
            if !kinds.contains(&k) {
                kinds.push(k);
            }
            let (s, suffix) = kind_style(k);
            style = s;
            let _ = write!(class, " blocker {}", k.as_str());
            label.push('\n');
            label.push_str(suffix);
        }
        if on_cycle_obj.contains(&o) {
            class.push_str(" on-cycle");
        }
        let (fill, font) = if goal {
            (PURPLE, "white")
        } else {
            (GREEN, "black")
        };
        let _ = writeln!(
            body,
            "  o{o} [id=\"o{o}\", class=\"{class}\", shape=circle, style=\"{style}\", \
             fillcolor=\"{fill}\", fontcolor={font}, label={}];",
            quote(&label)
        );
    }
    for &f in &motions {
        let mut class = String::from("motion");
        if producer.contains(&f) {
            class.push_str(" producer");
        }
        if on_cycle_unit.contains(&f) {
            class.push_str(" on-cycle");
        }
        let _ = writeln!(
            body,
            "  m{f} [id=\"m{f}\", class=\"{class}\", shape=square, fillcolor=\"{RED}\", \
             fontcolor=white, label={}];",
            quote(&format!("{}\nunit {f}", foon.motion_text(f)))
        );
    }
    // Arrows, each once: the cycle's first (drawn thick), then the producers'.
    let mut drawn: FxHashSet<(bool, u32, u32)> = FxHashSet::default();
    for (i, &f) in e.cycle_units.iter().enumerate() {
        let (made, needed) = (e.cycle[i], e.cycle[i + 1]);
        for (from_obj, a, b) in [(true, needed, f), (false, f, made)] {
            if drawn.insert((from_obj, a, b)) {
                let (x, y) = if from_obj {
                    (format!("o{a}"), format!("m{b}"))
                } else {
                    (format!("m{a}"), format!("o{b}"))
                };
                let _ = writeln!(
                    body,
                    "  {x} -> {y} [class=\"cycle\", color=\"{CYCLE}\", penwidth=2.5];"
                );
            }
        }
    }
    for p in &e.producers {
        if drawn.insert((false, p.unit, e.goal)) {
            let _ = writeln!(body, "  m{} -> o{};", p.unit, e.goal);
        }
        for b in &p.blockers {
            if drawn.insert((true, b.object, p.unit)) {
                let _ = writeln!(body, "  o{} -> m{};", b.object, p.unit);
            }
        }
    }
    let mut out = String::from("digraph foon {\n");
    let _ = writeln!(
        out,
        "  graph [label={}, labelloc=t, fontname=\"Helvetica\", fontsize=14, rankdir=BT, \
         nodesep=0.3, ranksep=0.35];",
        quote_title(title)
    );
    out.push_str(
        "  node [fontname=\"Helvetica\", fontsize=10, style=filled, color=\"#333333\"];\n  \
         edge [color=\"#444444\", arrowsize=0.7, fontname=\"Helvetica\"];\n",
    );
    out.push_str(&legend(&kinds, !e.cycle.is_empty()));
    out.push_str(&body);
    out.push_str("}\n");
    out
}

/// The legend: motion, goal, and the kinds of blocking input (and the cycle) drawn.
fn legend(kinds: &[BlockKind], cycle: bool) -> String {
    let mut out = String::from(
        "  subgraph clusterlegend {\n    label=\"legend\";\n    style=rounded;\n    \
         color=\"#aaaaaa\";\n    fontsize=10;\n",
    );
    let mut item = |name: &str, attrs: &str, label: &str| {
        let _ = writeln!(
            out,
            "    legend_{name} [id=\"legend_{name}\", class=\"legend\", {attrs}, label={}];",
            quote(label)
        );
    };
    item(
        "motion",
        &format!("shape=square, fillcolor=\"{RED}\", fontcolor=white"),
        "producer",
    );
    item(
        "goal",
        &format!("shape=circle, fillcolor=\"{PURPLE}\", fontcolor=white"),
        "goal",
    );
    for &k in [
        BlockKind::Missing,
        BlockKind::Cycle,
        BlockKind::NotDerivable,
    ]
    .iter()
    .filter(|k| kinds.contains(k))
    {
        let (style, suffix) = kind_style(k);
        let what = match k {
            BlockKind::Missing => "raw item not\nin the kitchen",
            BlockKind::Cycle => "needs the goal\n(a cycle)",
            BlockKind::NotDerivable => "cannot be made\nfrom the kitchen",
        };
        item(
            &k.as_str().replace('-', "_"),
            &format!("shape=circle, style=\"{style}\", fillcolor=\"{GREEN}\""),
            &format!("{what}\n{suffix}"),
        );
    }
    if cycle {
        let _ = write!(
            out,
            "    legend_cycle_a [id=\"legend_cycle_a\", class=\"legend\", shape=point];\n    \
             legend_cycle_b [id=\"legend_cycle_b\", class=\"legend\", shape=point];\n    \
             legend_cycle_a -> legend_cycle_b [label=\" blocking cycle\", fontsize=9, \
             color=\"{CYCLE}\", penwidth=2.5];\n"
        );
    }
    out.push_str("  }\n");
    out
}

/// The default title.
fn title(foon: &Foon, e: &Explain) -> String {
    let goal = super::object_line(foon, e.goal);
    match e.status {
        Status::Blocked => format!("why {goal} cannot be made"),
        Status::Derivable => format!("{goal}: derivable"),
        Status::InKitchen => format!("{goal}: in the kitchen"),
    }
}

/// Writes the explanation `e` (computed with `prep`, the kitchen's prepared inputs) as a
/// picture or a page: for a blocked goal its blocking part, for another its best tree.
pub fn write_explanation(
    format: Format,
    foon: &Foon,
    prep: &Prepared,
    e: &Explain,
    opts: &Options,
    out: &mut dyn io::Write,
) -> Result<()> {
    if !writes_explanation(format) {
        return Err(Error::Invalid(format!(
            "the {} format cannot write an explanation (choose from dot, svg, png, pdf, html; \
             or --json)",
            format.as_str()
        )));
    }
    let ctx = Context::with(foon, prep)?;
    let title = opts.title.clone().unwrap_or_else(|| title(foon, e));
    if e.status != Status::Blocked {
        let Some(plan) = &e.plan else {
            return Err(Error::Invalid("the explanation has no tree".to_owned()));
        };
        if format == Format::Html {
            let own = Options {
                title: None,
                ..opts.clone()
            };
            let svg = super::to_bytes(|o| {
                write_tree(Format::Svg, &TreeDoc::new(foon, prep, plan), &own, o)
            })?;
            return put(out, explain_page(&title, &e.text(&ctx), &svg).as_bytes());
        }
        let own = Options {
            title: Some(title),
            ..opts.clone()
        };
        return write_tree(format, &TreeDoc::new(foon, prep, plan), &own, out);
    }
    let (objects, motions) = blocking_nodes(e);
    check_size(
        format,
        objects.len() + motions.len(),
        opts,
        "the blocking part",
        "--max-nodes",
    )?;
    let dot = blocking_dot(foon, e, &title);
    if format == Format::Html {
        let svg = super::render::render(&dot, "svg")?;
        return put(out, explain_page(&title, &e.text(&ctx), &svg).as_bytes());
    }
    emit(format, &dot, out)
}

/// The page: the picture, then the explanation's text.
fn explain_page(title: &str, text: &str, svg: &[u8]) -> String {
    let mut body = String::new();
    let _ = writeln!(
        body,
        "<section class=\"explain\">\n<figure class=\"picture\">\n{}\n</figure>",
        inline_svg(svg, "e-")
    );
    let _ = writeln!(
        body,
        "<h2>Explanation</h2>\n<pre class=\"explanation\">{}</pre>\n</section>",
        escape(text.trim_end())
    );
    page(title, "explain", &body)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse::{ParseOptions, parse_foon};
    use crate::search::Query;

    /// `soup` is made by `cook` from `broth` (made from `soup`: a cycle) and `salt` (raw,
    /// missing); or by `heat` from `stock`, made from `bones` (raw, missing).
    const TEXT: &str = "O\tbroth\nS\thot\nO\tsalt\nS\tdry\nM\tcook\nO\tsoup\nS\thot\n//\n\
                        O\tsoup\nS\thot\nM\tboil\nO\tbroth\nS\thot\n//\n\
                        O\tstock\nS\tcold\nM\theat\nO\tsoup\nS\thot\n//\n\
                        O\tbones\nS\traw\nM\tsimmer\nO\tstock\nS\tcold\n//\n";

    /// Only the cycle: `soup` from `broth`, `broth` from `soup`.
    const CYCLIC: &str = "O\tbroth\nS\thot\nM\tcook\nO\tsoup\nS\thot\n//\n\
                          O\tsoup\nS\thot\nM\tboil\nO\tbroth\nS\thot\n//\n";

    fn explained() -> (Foon, Prepared, Explain) {
        explained_in(TEXT)
    }

    fn explained_in(text: &str) -> (Foon, Prepared, Explain) {
        let f = parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap();
        let prep = Prepared::new(&f, &[], &[], None, Some(1.0)).unwrap();
        let soup = (0..f.object_count() as u32)
            .find(|&o| super::super::object_line(&f, o) == "soup (hot)")
            .unwrap();
        let ctx = Context::with(&f, &prep).unwrap();
        let e = crate::explain::explain(&ctx, soup, Query::default()).unwrap();
        (f, prep, e)
    }

    #[test]
    fn the_blocking_part_in_the_visual_language() {
        let (f, prep, e) = explained();
        assert_eq!(e.status, Status::Blocked, "{e:?}");
        let bytes = super::super::to_bytes(|o| {
            write_explanation(Format::Dot, &f, &prep, &e, &Options::default(), o)
        })
        .unwrap();
        let dot = String::from_utf8(bytes).unwrap();
        let (objects, motions) = blocking_nodes(&e);
        assert_eq!(dot.matches("class=\"motion").count(), motions.len());
        assert_eq!(dot.matches("class=\"object").count(), objects.len());
        assert_eq!(dot.matches("class=\"object goal").count(), 1);
        assert!(dot.contains("[missing]"), "{dot}");
        assert!(dot.contains("style=\"filled,dashed\""));
        assert!(dot.contains("class=\"object blocker missing\""));
        // Same input, same bytes; a text format is refused.
        let again = super::super::to_bytes(|o| {
            write_explanation(Format::Dot, &f, &prep, &e, &Options::default(), o)
        })
        .unwrap();
        assert_eq!(dot.as_bytes(), again.as_slice());
        let err = write_explanation(
            Format::Text,
            &f,
            &prep,
            &e,
            &Options::default(),
            &mut Vec::new(),
        )
        .unwrap_err();
        assert!(err.to_string().contains("cannot write an explanation"));
        let small = Options {
            max_nodes: 2,
            ..Options::default()
        };
        let err =
            write_explanation(Format::Svg, &f, &prep, &e, &small, &mut Vec::new()).unwrap_err();
        assert!(matches!(err, Error::Output(_)), "{err}");
    }

    #[test]
    fn the_blocking_cycle_is_drawn() {
        let (f, prep, e) = explained_in(CYCLIC);
        assert!(!e.buyable && !e.cycle.is_empty(), "{e:?}");
        let bytes = super::super::to_bytes(|o| {
            write_explanation(Format::Dot, &f, &prep, &e, &Options::default(), o)
        })
        .unwrap();
        let dot = String::from_utf8(bytes).unwrap();
        // soup, broth; cook, boil; the cycle's four arrows (and the legend's).
        assert_eq!(dot.matches("class=\"object").count(), 2, "{dot}");
        assert_eq!(dot.matches("class=\"motion").count(), 2, "{dot}");
        assert_eq!(dot.matches("[class=\"cycle\"").count(), 4, "{dot}");
        assert!(
            dot.contains("class=\"object blocker cycle on-cycle\""),
            "{dot}"
        );
        assert!(dot.contains("[cycle]") && dot.contains("legend_cycle_a"));
    }
}
