//! `GraphML`: the object–motion bipartite directed graph of a task tree or a FOON.
//!
//! Every unit is a *motion* node and every object it uses or makes is an *object* node;
//! edges go input → motion → output, one edge per (object, unit, direction) with the number
//! of times the object appears in that list as `count` (FOON lists may repeat an object),
//! so the graph is a simple directed graph (a networkx `DiGraph`). Node ids are `o<object
//! id>` and `m<unit index>`. The attributes, declared with `<key>`:
//!
//! - graph: `kind` (`foon` or `tree`), `title`, `goal` (the goal or object in focus, as one
//!   line), and for trees `method`, `solved`, `units`, `height`, `success`, `explanation`;
//!   a goal that could not be planned is an empty graph with `goal`, `method` and `error`.
//! - node: `kind` (`object` or `motion`), `label` (the object's label, or the motion);
//!   objects: `object` (id), `states` and `ingredients` (JSON arrays of strings, in the
//!   order of the object's first written form), `container` (absent when none), `goal`,
//!   `kitchen` (when planning inputs are known); motions: `fu` (unit index), `motion`,
//!   `line` (where the unit starts in its file), `rate` (when known), `step` (trees: the
//!   unit's 1-based position in the tree's unit list, its execution order).
//! - edge: `role` (`input` or `output`), `count`.
//!
//! Several trees in one document are one `<graph>` each (`GraphML` allows any number), in
//! the order given. Text is escaped for XML; a character that XML 1.0 cannot hold (a
//! control character other than tab, newline and carriage return, U+FFFE, U+FFFF) is an
//! output error ([`Error::Output`]), and nothing is written.

use std::fmt::Write as _;
use std::io;

use super::{Failed, FoonDoc, Options, TreeDoc, TreeFormat, put};
use crate::error::{Error, Result};
use crate::index::Foon;
use crate::model::ObjectSpec;

const HEADER: &str = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
<graphml xmlns=\"http://graphml.graphdrawing.org/xmlns\" \
xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" \
xsi:schemaLocation=\"http://graphml.graphdrawing.org/xmlns \
http://graphml.graphdrawing.org/xmlns/1.0/graphml.xsd\">\n";

/// The keys: (domain, name, type). The key id is `<domain>.<name>`.
const KEYS: &[(&str, &str, &str)] = &[
    ("graph", "kind", "string"),
    ("graph", "title", "string"),
    ("graph", "goal", "string"),
    ("graph", "method", "string"),
    ("graph", "solved", "boolean"),
    ("graph", "units", "int"),
    ("graph", "height", "int"),
    ("graph", "success", "double"),
    ("graph", "explanation", "string"),
    ("graph", "error", "string"),
    ("node", "kind", "string"),
    ("node", "label", "string"),
    ("node", "object", "int"),
    ("node", "states", "string"),
    ("node", "ingredients", "string"),
    ("node", "container", "string"),
    ("node", "goal", "boolean"),
    ("node", "kitchen", "boolean"),
    ("node", "fu", "int"),
    ("node", "motion", "string"),
    ("node", "line", "int"),
    ("node", "rate", "double"),
    ("node", "step", "int"),
    ("edge", "role", "string"),
    ("edge", "count", "int"),
];

fn header() -> String {
    let mut out = String::from(HEADER);
    for (domain, name, ty) in KEYS {
        let _ = writeln!(
            out,
            "  <key id=\"{domain}.{name}\" for=\"{domain}\" attr.name=\"{name}\" \
             attr.type=\"{ty}\"/>"
        );
    }
    out
}

const FOOTER: &str = "</graphml>\n";

/// `s` escaped as XML character data, or the error naming `what` when it has a character
/// that XML 1.0 cannot hold.
fn escape_into(out: &mut String, s: &str, what: &dyn Fn() -> String) -> Result<()> {
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            // Parsers turn a raw carriage return into a newline: keep it as a reference.
            '\r' => out.push_str("&#13;"),
            '\t' | '\n' => out.push(c),
            c if c < ' ' || c == '\u{fffe}' || c == '\u{ffff}' => {
                return Err(Error::Output(format!(
                    "{} has the character U+{:04X}, which GraphML (XML 1.0) cannot hold",
                    what(),
                    u32::from(c)
                )));
            }
            c => out.push(c),
        }
    }
    Ok(())
}

/// A `<data>` element of text.
fn data_text(
    out: &mut String,
    indent: &str,
    key: &str,
    value: &str,
    what: &dyn Fn() -> String,
) -> Result<()> {
    let _ = write!(out, "{indent}<data key=\"{key}\">");
    escape_into(out, value, what)?;
    out.push_str("</data>\n");
    Ok(())
}

/// A `<data>` element of a number or boolean (nothing to escape).
fn data(out: &mut String, indent: &str, key: &str, value: impl std::fmt::Display) {
    let _ = writeln!(out, "{indent}<data key=\"{key}\">{value}</data>");
}

fn json_list(items: &[String]) -> String {
    serde_json::to_string(items).unwrap_or_default()
}

/// What one graph shows, beyond its units.
struct Marks<'a> {
    goal: Option<u32>,
    kitchen: Option<&'a dyn Fn(u32) -> bool>,
    rate: &'a dyn Fn(u32) -> Option<f64>,
    /// Trees number their units.
    steps: bool,
}

/// The nodes and edges of `units` of `foon`.
fn body(foon: &Foon, units: &[u32], marks: &Marks<'_>, out: &mut String) -> Result<()> {
    const IN: &str = "      ";
    let mut objects: Vec<u32> = Vec::new();
    let mut seen = rustc_hash::FxHashSet::default();
    for &f in units {
        for &o in foon.inputs(f).iter().chain(foon.outputs(f)) {
            if seen.insert(o) {
                objects.push(o);
            }
        }
    }
    if let Some(g) = marks.goal {
        if seen.insert(g) {
            objects.push(g);
        }
    }
    for &o in &objects {
        let spec = ObjectSpec::of_object(foon, o);
        let what = || format!("object {o} ({})", spec.describe().escape_debug());
        let _ = writeln!(out, "    <node id=\"o{o}\">");
        data(out, IN, "node.kind", "object");
        data_text(out, IN, "node.label", &spec.label, &what)?;
        data(out, IN, "node.object", o);
        data_text(out, IN, "node.states", &json_list(&spec.states), &what)?;
        data_text(
            out,
            IN,
            "node.ingredients",
            &json_list(&spec.ingredients),
            &what,
        )?;
        if let Some(c) = &spec.container {
            data_text(out, IN, "node.container", c, &what)?;
        }
        data(out, IN, "node.goal", Some(o) == marks.goal);
        if let Some(k) = marks.kitchen {
            data(out, IN, "node.kitchen", k(o));
        }
        out.push_str("    </node>\n");
    }
    for (i, &f) in units.iter().enumerate() {
        let motion = foon.motion_text(f);
        let what = || format!("the motion of unit {f} ({})", motion.escape_debug());
        let _ = writeln!(out, "    <node id=\"m{f}\">");
        data(out, IN, "node.kind", "motion");
        data_text(out, IN, "node.label", motion, &what)?;
        data(out, IN, "node.fu", f);
        data_text(out, IN, "node.motion", motion, &what)?;
        data(out, IN, "node.line", foon.fu_line(f));
        if let Some(r) = (marks.rate)(f).filter(|r| r.is_finite()) {
            data(out, IN, "node.rate", r);
        }
        if marks.steps {
            data(out, IN, "node.step", i + 1);
        }
        out.push_str("    </node>\n");
    }
    for &f in units {
        for (role, list) in [("input", foon.inputs(f)), ("output", foon.outputs(f))] {
            let mut done: Vec<u32> = Vec::new();
            for &o in list {
                if done.contains(&o) {
                    continue;
                }
                done.push(o);
                let count = list.iter().filter(|&&x| x == o).count();
                let (s, t) = if role == "input" {
                    (format!("o{o}"), format!("m{f}"))
                } else {
                    (format!("m{f}"), format!("o{o}"))
                };
                let _ = writeln!(out, "    <edge source=\"{s}\" target=\"{t}\">");
                data(out, IN, "edge.role", role);
                data(out, IN, "edge.count", count);
                out.push_str("    </edge>\n");
            }
        }
    }
    Ok(())
}

/// One tree as a `<graph>` with id `id`.
fn tree_graph(doc: &TreeDoc<'_>, id: &str, title: Option<&str>) -> Result<String> {
    const IN: &str = "    ";
    let plan = doc.plan;
    let foon = doc.foon;
    let mut out = String::new();
    let _ = writeln!(out, "  <graph id=\"{id}\" edgedefault=\"directed\">");
    data(&mut out, IN, "graph.kind", "tree");
    let goal = super::object_line(foon, doc.goal());
    let what = || "the goal".to_owned();
    data_text(&mut out, IN, "graph.title", title.unwrap_or(&goal), &|| {
        "the title".to_owned()
    })?;
    data_text(&mut out, IN, "graph.goal", &goal, &what)?;
    data(&mut out, IN, "graph.method", plan.query.method.as_str());
    data(&mut out, IN, "graph.solved", plan.solved);
    data(&mut out, IN, "graph.units", plan.units.len());
    if let Some(h) = plan.height {
        data(&mut out, IN, "graph.height", h);
    }
    if let Some(s) = plan.success.filter(|s| s.is_finite()) {
        data(&mut out, IN, "graph.success", s);
    }
    let why = super::explanation_text(foon, plan);
    if !why.is_empty() {
        data_text(&mut out, IN, "graph.explanation", &why, &|| {
            "the explanation".to_owned()
        })?;
    }
    let kitchen = |o| doc.in_kitchen(o);
    let rate = |f| doc.rate(f);
    let marks = Marks {
        goal: Some(doc.goal()),
        kitchen: Some(&kitchen),
        rate: &rate,
        steps: true,
    };
    body(foon, doc.units(), &marks, &mut out)?;
    out.push_str("  </graph>\n");
    Ok(out)
}

/// A goal that could not be planned, as an empty `<graph>`.
fn failed_graph(failed: &Failed, id: &str) -> Result<String> {
    const IN: &str = "    ";
    let mut out = String::new();
    let _ = writeln!(out, "  <graph id=\"{id}\" edgedefault=\"directed\">");
    data(&mut out, IN, "graph.kind", "tree");
    let goal = failed.goal_text();
    data_text(&mut out, IN, "graph.title", &goal, &|| {
        "the goal".to_owned()
    })?;
    data_text(&mut out, IN, "graph.goal", &goal, &|| "the goal".to_owned())?;
    data(&mut out, IN, "graph.method", failed.method.as_str());
    data(&mut out, IN, "graph.solved", false);
    data(&mut out, IN, "graph.units", 0);
    data_text(&mut out, IN, "graph.error", &failed.error, &|| {
        "the error".to_owned()
    })?;
    out.push_str("  </graph>\n");
    Ok(out)
}

/// Task trees as one `GraphML` document: one `<graph>` per tree (`tree` for a single one,
/// `tree0`, `tree1`, ... for several), written at the end so that an error writes nothing.
pub(super) struct GraphmlTrees {
    title: Option<String>,
    many: bool,
    graphs: Vec<String>,
}

impl GraphmlTrees {
    pub(super) fn new(opts: &Options, many: bool) -> Self {
        Self {
            title: opts.title.clone(),
            many,
            graphs: Vec::new(),
        }
    }

    fn id(&self) -> String {
        if self.many {
            format!("tree{}", self.graphs.len())
        } else {
            "tree".to_owned()
        }
    }
}

impl TreeFormat for GraphmlTrees {
    fn tree(&mut self, doc: &TreeDoc<'_>, _out: &mut dyn io::Write) -> Result<()> {
        let g = tree_graph(doc, &self.id(), self.title.as_deref())?;
        self.graphs.push(g);
        Ok(())
    }

    fn failed(&mut self, failed: &Failed, _out: &mut dyn io::Write) -> Result<()> {
        let g = failed_graph(failed, &self.id())?;
        self.graphs.push(g);
        Ok(())
    }

    fn end(&mut self, out: &mut dyn io::Write) -> Result<()> {
        let mut text = header();
        for g in &self.graphs {
            text.push_str(g);
        }
        text.push_str(FOOTER);
        put(out, text.as_bytes())
    }
}

/// A FOON, or the part of it that `doc` selects, as one `<graph id="foon">`.
pub(super) fn write_foon(doc: &FoonDoc<'_>, opts: &Options, out: &mut dyn io::Write) -> Result<()> {
    const IN: &str = "    ";
    let foon = doc.foon;
    let title = opts.title.clone().unwrap_or_else(|| {
        foon.source()
            .and_then(|p| p.file_name())
            .map_or_else(|| "FOON".to_owned(), |n| n.to_string_lossy().into_owned())
    });
    let units = doc.units();
    let mut text = header();
    text.push_str("  <graph id=\"foon\" edgedefault=\"directed\">\n");
    data(&mut text, IN, "graph.kind", "foon");
    data_text(&mut text, IN, "graph.title", &title, &|| {
        "the title".to_owned()
    })?;
    if let Some(f) = doc.focus {
        let goal = super::object_line(foon, f);
        data_text(&mut text, IN, "graph.goal", &goal, &|| {
            "the goal".to_owned()
        })?;
    }
    data(&mut text, IN, "graph.units", units.len());
    let kitchen = |o| doc.in_kitchen(o);
    let rate = |f: u32| {
        doc.prep
            .map(|p| p.fu_rates()[f as usize])
            .filter(|r| !r.is_nan())
    };
    let marks = Marks {
        goal: doc.focus,
        kitchen: doc
            .prep
            .is_some()
            .then_some(&kitchen as &dyn Fn(u32) -> bool),
        rate: &rate,
        steps: false,
    };
    body(foon, &units, &marks, &mut text)?;
    text.push_str("  </graph>\n");
    text.push_str(FOOTER);
    put(out, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::super::{FoonDoc, Format, Options, to_bytes, write_foon};
    use crate::parse::{ParseOptions, parse_foon};

    fn graphml(text: &str) -> crate::Result<String> {
        let foon = parse_foon(text.as_bytes(), None, ParseOptions::default())?;
        let bytes = to_bytes(|out| {
            write_foon(
                Format::Graphml,
                &FoonDoc::whole(&foon),
                &Options::default(),
                out,
            )
        })?;
        Ok(String::from_utf8(bytes).expect("GraphML is UTF-8"))
    }

    #[test]
    fn markup_in_text_is_escaped() {
        let g = graphml("O\ta<b>&c\nS\t\"q\"\nM\tcut & <dice>\nO\tx\nS\tdone\n//\n").unwrap();
        assert!(g.contains("<data key=\"node.label\">a&lt;b&gt;&amp;c</data>"));
        assert!(g.contains("<data key=\"node.states\">[\"\\\"q\\\"\"]</data>"));
        assert!(g.contains("<data key=\"node.motion\">cut &amp; &lt;dice&gt;</data>"));
        assert!(!g.contains("<b>"));
    }

    #[test]
    fn a_character_xml_cannot_hold_is_a_clear_error() {
        let err = graphml("O\tbad\u{1}label\nM\tcut\nO\tx\nS\tdone\n//\n").unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains("U+0001"), "{msg}");
        assert!(msg.contains("XML"), "{msg}");
    }

    #[test]
    fn repeated_inputs_are_one_edge_with_their_count() {
        let g = graphml("O\tegg\nO\tegg\nM\tcrack\nO\tegg\nS\tcracked\n//\n").unwrap();
        assert_eq!(g.matches("<edge source=\"o0\" target=\"m0\">").count(), 1);
        assert!(g.contains("<data key=\"edge.count\">2</data>"));
    }
}
