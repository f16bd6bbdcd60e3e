//! Graphviz DOT in the FOON visual language: motions red squares, objects green circles,
//! the goal purple, arrows input → motion → output.

use std::fmt::Write as _;

use std::io;

use super::{FoonDoc, Format, Options, TreeDoc, TreeFormat, put, render};
use crate::error::{Error, Result};
use crate::index::Foon;

fn quote(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn object_label(foon: &Foon, o: u32) -> String {
    let spec = crate::model::ObjectSpec::of_object(foon, o);
    let mut s = spec.label.clone();
    if !spec.states.is_empty() {
        let _ = write!(s, "\n({})", spec.states.join(", "));
    }
    if !spec.ingredients.is_empty() {
        let _ = write!(s, "\n{{{}}}", spec.ingredients.join(", "));
    }
    if let Some(c) = &spec.container {
        let _ = write!(s, "\nin [{c}]");
    }
    s
}

/// The nodes and edges of `units` of `foon` (node names start with `prefix`), `goal`
/// purple, objects for which `leaf` holds marked as kitchen items (double border). Returns
/// the text and the number of nodes.
fn body(
    foon: &Foon,
    units: &[u32],
    goal: Option<u32>,
    leaf: &dyn Fn(u32) -> bool,
    prefix: &str,
    indent: &str,
) -> (String, usize) {
    let mut out = String::new();
    let mut objects: Vec<u32> = Vec::new();
    let mut seen = rustc_hash::FxHashSet::default();
    for &f in units {
        for &o in foon.inputs(f).iter().chain(foon.outputs(f)) {
            if seen.insert(o) {
                objects.push(o);
            }
        }
    }
    if let Some(g) = goal {
        if seen.insert(g) {
            objects.push(g);
        }
    }
    for &o in &objects {
        let fill = if Some(o) == goal {
            "#9b59b6"
        } else {
            "#8fd18f"
        };
        let periph = if leaf(o) { 2 } else { 1 };
        let class = if Some(o) == goal {
            "object goal"
        } else {
            "object"
        };
        let _ = writeln!(
            out,
            "{indent}{prefix}o{o} [shape=circle, style=filled, fillcolor=\"{fill}\", \
             peripheries={periph}, class={}, label={}];",
            quote(class),
            quote(&object_label(foon, o))
        );
    }
    for (i, &f) in units.iter().enumerate() {
        let _ = writeln!(
            out,
            "{indent}{prefix}m{f} [shape=square, style=filled, fillcolor=\"#e74c3c\", \
             fontcolor=white, class=\"motion\", label={}];",
            quote(&format!("{}. {}", i + 1, foon.motion_text(f)))
        );
        for &o in foon.inputs(f) {
            let _ = writeln!(out, "{indent}{prefix}o{o} -> {prefix}m{f};");
        }
        for &o in foon.outputs(f) {
            let _ = writeln!(out, "{indent}{prefix}m{f} -> {prefix}o{o};");
        }
    }
    (out, objects.len() + units.len())
}

fn wrap(title: &str, body: &str) -> String {
    let mut out = String::new();
    out.push_str("digraph foon {\n");
    let _ = writeln!(out, "  label={};", quote(title));
    out.push_str("  labelloc=t;\n  rankdir=TB;\n");
    out.push_str("  node [fontname=\"Helvetica\", fontsize=10];\n  edge [color=\"#444444\"];\n");
    out.push_str(body);
    out.push_str("}\n");
    out
}

fn check_size(nodes: usize, opts: &Options, what: &str) -> Result<()> {
    if nodes > opts.max_nodes {
        return Err(Error::Output(format!(
            "{what} has {nodes} nodes, more than the {} a picture holds: narrow it (--goal, \
             --depth) or raise the limit (--max-nodes)",
            opts.max_nodes
        )));
    }
    Ok(())
}

/// Renders DOT text in `format` (dot itself, or svg/png/pdf through Graphviz).
fn emit(format: Format, text: &str, out: &mut dyn io::Write) -> Result<()> {
    if format == Format::Dot {
        put(out, text.as_bytes())
    } else {
        put(out, &render::render(text, format.as_str())?)
    }
}

/// Task trees as one picture (a cluster per tree when there are several).
pub(super) struct DotTrees {
    format: Format,
    opts: Options,
    many: bool,
    parts: Vec<(String, String)>,
    nodes: usize,
}

impl DotTrees {
    pub(super) fn new(format: Format, opts: &Options, many: bool) -> Self {
        Self {
            format,
            opts: opts.clone(),
            many,
            parts: Vec::new(),
            nodes: 0,
        }
    }
}

impl TreeFormat for DotTrees {
    fn tree(&mut self, doc: &TreeDoc<'_>, _out: &mut dyn io::Write) -> Result<()> {
        let i = self.parts.len();
        let prefix = if self.many {
            format!("t{i}_")
        } else {
            String::new()
        };
        let indent = if self.many { "    " } else { "  " };
        let (text, n) = body(
            doc.foon,
            doc.units(),
            Some(doc.goal()),
            &|o| doc.in_kitchen(o),
            &prefix,
            indent,
        );
        self.nodes += n;
        self.parts
            .push((super::object_line(doc.foon, doc.goal()), text));
        Ok(())
    }

    fn end(&mut self, out: &mut dyn io::Write) -> Result<()> {
        check_size(self.nodes, &self.opts, "the picture")?;
        let text = if self.many {
            let mut b = String::new();
            for (i, (goal, part)) in self.parts.iter().enumerate() {
                let _ = writeln!(b, "  subgraph cluster_{i} {{\n    label={};", quote(goal));
                b.push_str(part);
                b.push_str("  }\n");
            }
            wrap(self.opts.title.as_deref().unwrap_or("task trees"), &b)
        } else {
            let (goal, part) = self.parts.first().map_or(("", ""), |(g, p)| (g, p));
            wrap(self.opts.title.as_deref().unwrap_or(goal), part)
        };
        emit(self.format, &text, out)
    }
}

/// A FOON or part of it, in `format` (dot, svg, png, pdf).
pub(super) fn write_foon(
    format: Format,
    doc: &FoonDoc<'_>,
    opts: &Options,
    out: &mut dyn io::Write,
) -> Result<()> {
    let title = opts.title.clone().unwrap_or_else(|| {
        doc.foon
            .source()
            .and_then(|p| p.file_name())
            .map_or_else(|| "FOON".to_owned(), |n| n.to_string_lossy().into_owned())
    });
    let units = doc.units();
    let (b, n) = body(
        doc.foon,
        &units,
        doc.focus,
        &|o| doc.in_kitchen(o),
        "",
        "  ",
    );
    if format != Format::Dot {
        check_size(n, opts, "the FOON")?;
    }
    emit(format, &wrap(&title, &b), out)
}
