//! Graphviz DOT in the FOON visual language.
//!
//! - A motion is a red square labelled with its motion; in a task tree it is numbered by
//!   execution order (`3. slice`).
//! - An object is a green circle labelled with its label, then its states in parentheses,
//!   its ingredients in braces and its container (`in [bowl]`), long lines wrapped.
//! - The goal (of a tree, or the object in focus of a FOON picture) is purple.
//! - Kitchen items are drawn with a double border: in a tree, the kitchen items it uses as
//!   leaves ([`TreeDoc::leaves`]); in a FOON picture with planning inputs, every kitchen item.
//! - Arrows go input → motion → output (one arrow per distinct object of a unit).
//! - A legend (a cluster named `clusterlegend`) says what the shapes and colours mean; it
//!   lists the goal and the double border only when the picture has them. Its name has no
//!   `cluster_` so that the `cluster_` names are those of the picture's content.
//!
//! Every node carries an SVG class that survives rendering (`class="node motion"` in the
//! SVG): `motion` for motions, `object` for objects, plus `goal` for the goal and `leaf` for
//! kitchen items; legend nodes carry `legend` only, so counting `g.node.motion` counts units.
//!
//! Several trees in one picture get one cluster each (`cluster_t0`, `cluster_t1`, ...,
//! labelled with the goal), their node names prefixed `t0_`, `t1_`, ... so that each tree
//! draws its own copy of shared objects. A FOON picture whose units form several connected
//! pieces (units linked through shared objects) draws each piece in its own cluster
//! (`cluster_p0`, ...), pieces in the order of their first unit.
//!
//! Size: SVG, PNG and PDF are refused above [`Options::max_nodes`] objects + motions (legend
//! not counted; default [`render::MAX_NODES`]) with a message that says how to narrow the
//! picture or raise the limit. DOT itself is text and is written at any size (for other
//! Graphviz layouts, such as `sfdp`, or other tools).
//!
//! Text is quoted for both the DOT parser and Graphviz's label escapes: `"` and `\` are
//! escaped, a newline becomes a line break, `&` is written `&amp;` (Graphviz decodes HTML
//! entities in labels, so `&lt;` would otherwise show as `<`), and control characters other
//! than the newline, and U+FFFE and U+FFFF (which SVG, as XML, cannot hold), become U+FFFD.
//! The output depends only on the input: same input, same bytes.

use std::fmt::Write as _;
use std::io;

use super::{FoonDoc, Format, Options, TreeDoc, TreeFormat, put, render};
use crate::error::{Error, Result};
use crate::index::Foon;

pub(super) const RED: &str = "#e74c3c";
pub(super) const GREEN: &str = "#8fd18f";
pub(super) const PURPLE: &str = "#9b59b6";
/// Object label lines longer than this many characters are wrapped at spaces.
const WRAP: usize = 24;
/// Titles (of the picture and of its clusters) are wrapped at this width.
const WRAP_TITLE: usize = 64;

/// A title, wrapped and quoted.
pub(super) fn quote_title(s: &str) -> String {
    let mut w = String::new();
    for (i, l) in s.split('\n').enumerate() {
        if i > 0 {
            w.push('\n');
        }
        wrap_into(l, WRAP_TITLE, &mut w);
    }
    quote(&w)
}

/// A DOT double-quoted string holding `s` as Graphviz shows it.
pub(super) fn quote(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '&' => out.push_str("&amp;"),
            // XML (SVG) cannot hold U+FFFE and U+FFFF either.
            c if c.is_control() || c == '\u{fffe}' || c == '\u{ffff}' => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// `line` broken at spaces into lines of at most `wrap` characters (a longer word stays
/// whole), appended to `out` with newlines between them.
fn wrap_into(line: &str, wrap: usize, out: &mut String) {
    let mut width = 0;
    for (i, word) in line.split(' ').enumerate() {
        let n = word.chars().count();
        if i > 0 {
            if width > 0 && width + 1 + n > wrap {
                out.push('\n');
                width = 0;
            } else {
                out.push(' ');
                width += 1;
            }
        }
        out.push_str(word);
        width += n;
    }
}

/// An object's label: its label, `(states)`, `{ingredients}`, `in [container]`, one line
/// each, long lines wrapped.
pub(super) fn object_label(foon: &Foon, o: u32) -> String {
    let spec = crate::model::ObjectSpec::of_object(foon, o);
    let mut lines = vec![spec.label.clone()];
    if !spec.states.is_empty() {
        lines.push(format!("({})", spec.states.join(", ")));
    }
    if !spec.ingredients.is_empty() {
        lines.push(format!("{{{}}}", spec.ingredients.join(", ")));
    }
    if let Some(c) = &spec.container {
        lines.push(format!("in [{c}]"));
    }
    let mut s = String::new();
    for (i, l) in lines.iter().enumerate() {
        if i > 0 {
            s.push('\n');
        }
        wrap_into(l, WRAP, &mut s);
    }
    s
}

/// What a picture has, for its legend.
#[derive(Default, Clone, Copy)]
struct Seen {
    goal: bool,
    leaf: bool,
}

/// One group of units drawn together (a tree, or a connected piece of a FOON).
struct Part<'a> {
    foon: &'a Foon,
    units: &'a [u32],
    /// Motion labels are numbered by position in `units` (execution order).
    numbered: bool,
    goal: Option<u32>,
    leaf: &'a dyn Fn(u32) -> bool,
    prefix: &'a str,
    indent: &'a str,
}

/// The distinct objects of `units` (inputs then outputs, unit by unit), then `extra` when it
/// is not among them.
fn objects_of(foon: &Foon, units: &[u32], extra: Option<u32>) -> Vec<u32> {
    let mut seen = rustc_hash::FxHashSet::default();
    let mut objects = Vec::new();
    for &f in units {
        for &o in foon.inputs(f).iter().chain(foon.outputs(f)) {
            if seen.insert(o) {
                objects.push(o);
            }
        }
    }
    if let Some(g) = extra {
        if seen.insert(g) {
            objects.push(g);
        }
    }
    objects
}

/// The number of nodes (objects + motions) of `units` and `extra`.
fn node_count(foon: &Foon, units: &[u32], extra: Option<u32>) -> usize {
    objects_of(foon, units, extra).len() + units.len()
}

impl Part<'_> {
    /// Appends the nodes and edges of this part to `out`.
    fn write(&self, out: &mut String, seen: &mut Seen) {
        let (foon, p, ind) = (self.foon, self.prefix, self.indent);
        for o in objects_of(foon, self.units, self.goal) {
            let goal = Some(o) == self.goal;
            let leaf = (self.leaf)(o);
            seen.goal |= goal;
            seen.leaf |= leaf;
            let class = match (goal, leaf) {
                (true, true) => "object goal leaf",
                (true, false) => "object goal",
                (false, true) => "object leaf",
                (false, false) => "object",
            };
            let (fill, font) = if goal {
                (PURPLE, "white")
            } else {
                (GREEN, "black")
            };
            let _ = writeln!(
                out,
                "{ind}{p}o{o} [id=\"{p}o{o}\", class=\"{class}\", shape=circle, \
                 fillcolor=\"{fill}\", fontcolor={font}, peripheries={}, label={}];",
                if leaf { 2 } else { 1 },
                quote(&object_label(foon, o))
            );
        }
        for (i, &f) in self.units.iter().enumerate() {
            let label = if self.numbered {
                format!("{}. {}", i + 1, foon.motion_text(f))
            } else {
                foon.motion_text(f).to_owned()
            };
            let _ = writeln!(
                out,
                "{ind}{p}m{f} [id=\"{p}m{f}\", class=\"motion\", shape=square, \
                 fillcolor=\"{RED}\", fontcolor=white, label={}];",
                quote(&label)
            );
        }
        for &f in self.units {
            let mut drawn = rustc_hash::FxHashSet::default();
            for &o in foon.inputs(f) {
                if drawn.insert(o) {
                    let _ = writeln!(out, "{ind}{p}o{o} -> {p}m{f};");
                }
            }
            drawn.clear();
            for &o in foon.outputs(f) {
                if drawn.insert(o) {
                    let _ = writeln!(out, "{ind}{p}m{f} -> {p}o{o};");
                }
            }
        }
    }
}

/// The legend: a cluster of sample nodes (class `legend`) for what the picture has.
fn legend(seen: Seen) -> String {
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
        "motion",
    );
    item(
        "object",
        &format!("shape=circle, fillcolor=\"{GREEN}\""),
        "object\n(states)",
    );
    if seen.goal {
        item(
            "goal",
            &format!("shape=circle, fillcolor=\"{PURPLE}\", fontcolor=white"),
            "goal",
        );
    }
    if seen.leaf {
        item(
            "leaf",
            &format!("shape=circle, fillcolor=\"{GREEN}\", peripheries=2"),
            "from the\nkitchen",
        );
    }
    out.push_str("    legend_object -> legend_motion [label=\" input\", fontsize=9];\n");
    out.push_str("  }\n");
    out
}

/// The whole document: graph attributes, the legend, then `body`.
fn document(title: &str, seen: Seen, body: &str) -> String {
    let mut out = String::from("digraph foon {\n");
    let _ = writeln!(
        out,
        "  graph [label={}, labelloc=t, fontname=\"Helvetica\", fontsize=14, rankdir=TB, \
         nodesep=0.3, ranksep=0.35];",
        quote_title(title)
    );
    out.push_str(
        "  node [fontname=\"Helvetica\", fontsize=10, style=filled, color=\"#333333\"];\n  \
         edge [color=\"#444444\", arrowsize=0.7, fontname=\"Helvetica\"];\n",
    );
    out.push_str(&legend(seen));
    out.push_str(body);
    out.push_str("}\n");
    out
}

/// How a FOON picture is narrowed (`foon draw`, `foon export`).
const NARROW_FOON: &str = "--goal, --depth";
/// How a picture of task trees is narrowed (`foon plan` takes no `--depth`).
const NARROW_TREES: &str = "fewer goals, or one picture per goal with --out DIR";

/// Refuses a rendered picture of more than `opts.max_nodes` nodes (DOT text is not refused);
/// `narrow` says how to make it smaller.
pub(super) fn check_size(
    format: Format,
    nodes: usize,
    opts: &Options,
    what: &str,
    narrow: &str,
) -> Result<()> {
    if format != Format::Dot && nodes > opts.max_nodes {
        return Err(Error::Output(format!(
            "{what} has {nodes} nodes (objects and motions), more than the {} a {} picture \
             holds: narrow it ({narrow}) or raise the limit (--max-nodes); \
             --format dot writes it at any size",
            opts.max_nodes,
            format.as_str()
        )));
    }
    Ok(())
}

/// Writes DOT text in `format` (dot itself, or svg/png/pdf through Graphviz).
pub(super) fn emit(format: Format, text: &str, out: &mut dyn io::Write) -> Result<()> {
    if format == Format::Dot {
        put(out, text.as_bytes())
    } else {
        put(out, &render::render(text, format.as_str())?)
    }
}

/// Task trees as one picture (a cluster per tree when there are several). Pictures are
/// drawn at the end; trees that could not be planned have no place in them.
pub(super) struct DotTrees {
    format: Format,
    opts: Options,
    many: bool,
    /// Each tree's title and drawn body.
    parts: Vec<(String, String)>,
    nodes: usize,
    seen: Seen,
}

impl DotTrees {
    pub(super) fn new(format: Format, opts: &Options, many: bool) -> Self {
        Self {
            format,
            opts: opts.clone(),
            many,
            parts: Vec::new(),
            nodes: 0,
            seen: Seen::default(),
        }
    }
}

/// A tree's title: its goal, and `(not solved)` when the search found no tree.
fn tree_title(doc: &TreeDoc<'_>) -> String {
    let goal = super::object_line(doc.foon, doc.goal());
    if doc.plan.solved {
        goal
    } else {
        format!("{goal} (not solved)")
    }
}

impl TreeFormat for DotTrees {
    fn tree(&mut self, doc: &TreeDoc<'_>, _out: &mut dyn io::Write) -> Result<()> {
        let i = self.parts.len();
        let units = doc.units();
        self.nodes += node_count(doc.foon, units, Some(doc.goal()));
        // Refuse as soon as the picture is too big, before drawing more of it.
        check_size(
            self.format,
            self.nodes,
            &self.opts,
            "the picture",
            NARROW_TREES,
        )?;
        let prefix = if self.many {
            format!("t{i}_")
        } else {
            String::new()
        };
        let leaves: rustc_hash::FxHashSet<u32> = doc.leaves().into_iter().collect();
        let part = Part {
            foon: doc.foon,
            units,
            numbered: true,
            goal: Some(doc.goal()),
            leaf: &|o| leaves.contains(&o),
            prefix: &prefix,
            indent: if self.many { "    " } else { "  " },
        };
        let mut text = String::new();
        part.write(&mut text, &mut self.seen);
        self.parts.push((tree_title(doc), text));
        Ok(())
    }

    fn end(&mut self, out: &mut dyn io::Write) -> Result<()> {
        check_size(
            self.format,
            self.nodes,
            &self.opts,
            "the picture",
            NARROW_TREES,
        )?;
        let text = if self.many {
            let mut b = String::new();
            for (i, (title, part)) in self.parts.iter().enumerate() {
                let _ = writeln!(
                    b,
                    "  subgraph cluster_t{i} {{\n    label={};\n    style=rounded;\n    \
                     color=\"#888888\";",
                    quote_title(title)
                );
                b.push_str(part);
                b.push_str("  }\n");
            }
            document(
                self.opts.title.as_deref().unwrap_or("task trees"),
                self.seen,
                &b,
            )
        } else {
            let (title, part) = self
                .parts
                .first()
                .map_or(("", ""), |(t, p)| (t.as_str(), p.as_str()));
            document(self.opts.title.as_deref().unwrap_or(title), self.seen, part)
        };
        emit(self.format, &text, out)
    }
}

/// The connected pieces of `units` (units linked through shared objects), each in FOON
/// order, pieces in the order of their first unit.
fn pieces(foon: &Foon, units: &[u32]) -> Vec<Vec<u32>> {
    fn find(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            let up = parent[parent[x as usize] as usize];
            parent[x as usize] = up;
            x = up;
        }
        x
    }
    // Union-find over units: each object joins the units it appears in.
    let mut parent: Vec<u32> = (0..units.len() as u32).collect();
    let mut owner: rustc_hash::FxHashMap<u32, u32> = rustc_hash::FxHashMap::default();
    for (i, &f) in units.iter().enumerate() {
        for &o in foon.inputs(f).iter().chain(foon.outputs(f)) {
            match owner.get(&o) {
                Some(&j) => {
                    let (a, b) = (find(&mut parent, i as u32), find(&mut parent, j));
                    if a != b {
                        parent[a.max(b) as usize] = a.min(b);
                    }
                }
                None => {
                    owner.insert(o, i as u32);
                }
            }
        }
    }
    let mut slot: rustc_hash::FxHashMap<u32, usize> = rustc_hash::FxHashMap::default();
    let mut out: Vec<Vec<u32>> = Vec::new();
    for (i, &f) in units.iter().enumerate() {
        let root = find(&mut parent, i as u32);
        let k = *slot.entry(root).or_insert_with(|| {
            out.push(Vec::new());
            out.len() - 1
        });
        out[k].push(f);
    }
    out
}

/// A FOON or part of it, in `format` (dot, svg, png, pdf): one cluster per connected piece
/// when there are several.
pub(super) fn write_foon(
    format: Format,
    doc: &FoonDoc<'_>,
    opts: &Options,
    out: &mut dyn io::Write,
) -> Result<()> {
    doc.check()?;
    let units = doc.units();
    check_size(
        format,
        node_count(doc.foon, &units, doc.focus),
        opts,
        "the FOON",
        NARROW_FOON,
    )?;
    let title = opts.title.clone().unwrap_or_else(|| {
        let name = doc
            .foon
            .source()
            .and_then(|p| p.file_name())
            .map_or_else(|| "FOON".to_owned(), |n| n.to_string_lossy().into_owned());
        match doc.focus {
            Some(o) => format!("{name}: around {}", super::object_line(doc.foon, o)),
            None => name,
        }
    });
    let leaf = |o| doc.in_kitchen(o);
    let mut seen = Seen::default();
    let mut body = String::new();
    let groups = pieces(doc.foon, &units);
    let mut focus_drawn = doc.focus.is_none();
    for (i, group) in groups.iter().enumerate() {
        let has_focus = doc
            .focus
            .is_some_and(|g| objects_of(doc.foon, group, None).contains(&g));
        focus_drawn |= has_focus;
        let part = Part {
            foon: doc.foon,
            units: group,
            numbered: false,
            goal: if has_focus { doc.focus } else { None },
            leaf: &leaf,
            prefix: "",
            indent: if groups.len() > 1 { "    " } else { "  " },
        };
        if groups.len() > 1 {
            let _ = writeln!(
                body,
                "  subgraph cluster_p{i} {{\n    label={};\n    style=dashed;\n    \
                 color=\"#bbbbbb\";",
                quote(&format!(
                    "piece {} ({} unit{})",
                    i + 1,
                    group.len(),
                    if group.len() == 1 { "" } else { "s" }
                ))
            );
            part.write(&mut body, &mut seen);
            body.push_str("  }\n");
        } else {
            part.write(&mut body, &mut seen);
        }
    }
    if !focus_drawn {
        // The object in focus is in none of the units drawn: it stands alone.
        let part = Part {
            foon: doc.foon,
            units: &[],
            numbered: false,
            goal: doc.focus,
            leaf: &leaf,
            prefix: "",
            indent: "  ",
        };
        part.write(&mut body, &mut seen);
    }
    emit(format, &document(&title, seen, &body), out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quote_escapes_for_dot_and_graphviz() {
        assert_eq!(quote("plain"), "\"plain\"");
        assert_eq!(quote("a\"b"), "\"a\\\"b\"");
        assert_eq!(quote("a\\b"), "\"a\\\\b\"");
        assert_eq!(quote("a\nb"), "\"a\\nb\"");
        assert_eq!(quote("x & y &lt;"), "\"x &amp; y &amp;lt;\"");
        assert_eq!(quote("a\u{1}\tb\r"), "\"a\u{fffd}\u{fffd}b\u{fffd}\"");
        assert_eq!(quote("{é} <中>"), "\"{é} <中>\"");
        // A backslash before a letter stays a backslash (not Graphviz's \N, \G, \l ...).
        assert_eq!(quote("\\N\\l"), "\"\\\\N\\\\l\"");
    }

    #[test]
    fn wrap_breaks_long_lines_at_spaces() {
        let mut s = String::new();
        wrap_into("short", WRAP, &mut s);
        assert_eq!(s, "short");
        let mut s = String::new();
        wrap_into(
            "{olive oil, red wine vinegar, salt, black pepper}",
            WRAP,
            &mut s,
        );
        assert!(s.lines().all(|l| l.chars().count() <= WRAP), "{s}");
        assert_eq!(
            s.replace('\n', " "),
            "{olive oil, red wine vinegar, salt, black pepper}"
        );
        let mut s = String::new();
        let long = "x".repeat(WRAP * 2);
        wrap_into(&format!("{long} y"), WRAP, &mut s);
        assert_eq!(s, format!("{long}\ny"));
    }

    use crate::parse::{ParseOptions, parse_foon};
    use crate::prepare::Prepared;
    use crate::search::{Context, Method, Query};

    /// Two pieces: `a (raw) -> [cut] -> a (cut) -> [cook] -> a (done)` with a knife, and a
    /// separate `b (x) -> [stir] -> b "q\&y (z)` (a label that needs escaping).
    const TEXT: &str = "O\ta\nS\traw\nO\tknife\nM\tcut\nO\ta\nS\tcut\n//\n\
                        O\ta\nS\tcut\nM\tcook\nO\ta\nS\tdone\n//\n\
                        O\tb\nS\tx\nM\tstir\nO\tb \"q\\&y\nS\tz\n//\n";

    fn foon() -> Foon {
        parse_foon(TEXT.as_bytes(), None, ParseOptions::default()).unwrap()
    }

    fn spec(label: &str, state: &str) -> crate::ObjectSpec {
        crate::ObjectSpec {
            label: label.into(),
            states: if state.is_empty() {
                vec![]
            } else {
                vec![state.into()]
            },
            ..Default::default()
        }
    }

    fn tree_dot(
        foon: &Foon,
        prep: &Prepared,
        goal: u32,
        format: Format,
        opts: &Options,
    ) -> Result<String> {
        let ctx = Context::with(foon, prep)?;
        let plan = ctx.plan(
            goal,
            Query {
                method: Method::Ids,
                ..Query::default()
            },
        )?;
        let bytes = super::super::to_bytes(|out| {
            super::super::write_tree(format, &TreeDoc::new(foon, prep, &plan), opts, out)
        })?;
        Ok(String::from_utf8(bytes).unwrap())
    }

    fn count(text: &str, needle: &str) -> usize {
        text.matches(needle).count()
    }

    #[test]
    fn a_tree_in_the_visual_language() {
        let f = foon();
        let kitchen = [spec("a", "raw"), spec("knife", "")];
        let prep = Prepared::new(&f, &kitchen, &[], None, Some(1.0)).unwrap();
        let done = (0..f.object_count() as u32)
            .find(|&o| crate::write::object_line(&f, o) == "a (done)")
            .unwrap();
        let dot = tree_dot(&f, &prep, done, Format::Dot, &Options::default()).unwrap();
        assert_eq!(count(&dot, "class=\"motion\""), 2);
        assert!(dot.contains("label=\"1. cut\"") && dot.contains("label=\"2. cook\""));
        // a (raw), knife (kitchen leaves), a (cut), a (done) (the goal).
        assert_eq!(count(&dot, "class=\"object"), 4);
        assert_eq!(count(&dot, "class=\"object leaf\""), 2);
        assert_eq!(count(&dot, "class=\"object goal\""), 1);
        assert_eq!(count(&dot, "class=\"legend\""), 4);
        assert_eq!(count(&dot, " -> "), 5 + 1); // 5 arrows and the legend's
        assert!(dot.contains("label=\"a\\n(done)\""));
        // Same input, same bytes.
        assert_eq!(
            dot,
            tree_dot(&f, &prep, done, Format::Dot, &Options::default()).unwrap()
        );
        // Above the limit: DOT is still written, pictures are refused with what to do.
        let small = Options {
            max_nodes: 4,
            ..Options::default()
        };
        assert_eq!(dot, tree_dot(&f, &prep, done, Format::Dot, &small).unwrap());
        let e = tree_dot(&f, &prep, done, Format::Svg, &small).unwrap_err();
        assert!(matches!(e, Error::Output(_)));
        let msg = e.to_string();
        // `foon plan` has no --depth: a tree picture is narrowed by drawing fewer trees.
        assert!(
            msg.contains("6 nodes") && msg.contains("--out DIR"),
            "{msg}"
        );
        assert!(!msg.contains("--depth"), "{msg}");
        assert!(msg.contains("--max-nodes"), "{msg}");
    }

    #[test]
    fn several_trees_get_a_cluster_each() {
        let f = foon();
        let kitchen = [spec("a", "raw"), spec("knife", ""), spec("b", "x")];
        let prep = Prepared::new(&f, &kitchen, &[], None, Some(1.0)).unwrap();
        let ctx = Context::with(&f, &prep).unwrap();
        let plans: Vec<_> = (0..f.object_count() as u32)
            .map(|o| ctx.plan(o, Query::default()).unwrap())
            .collect();
        let mut w = crate::write::TreeWriter::new(Format::Dot, &Options::default(), true).unwrap();
        let mut out = Vec::new();
        w.begin(&mut out).unwrap();
        for p in &plans {
            w.item(
                &crate::write::Item::Tree(TreeDoc::new(&f, &prep, p)),
                &mut out,
            )
            .unwrap();
        }
        w.end(&mut out).unwrap();
        let dot = String::from_utf8(out).unwrap();
        assert_eq!(count(&dot, "subgraph cluster_t"), plans.len());
        let motions: usize = plans.iter().map(|p| p.units.len()).sum();
        assert_eq!(count(&dot, "class=\"motion\""), motions);
        assert_eq!(count(&dot, "class=\"object goal"), plans.len());
        // Node names are unique: each tree has its own prefix.
        let mut names: Vec<&str> = dot
            .lines()
            .filter(|l| l.contains("[id=") && !l.contains("legend"))
            .map(|l| l.split_whitespace().next().unwrap())
            .collect();
        let n = names.len();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), n);
    }

    #[test]
    fn a_foon_is_clustered_per_connected_piece() {
        let f = foon();
        let bytes = crate::write::to_bytes(|out| {
            crate::write::write_foon(Format::Dot, &FoonDoc::whole(&f), &Options::default(), out)
        })
        .unwrap();
        let dot = String::from_utf8(bytes).unwrap();
        assert_eq!(count(&dot, "subgraph cluster_p"), 2);
        assert!(dot.contains("label=\"piece 1 (2 units)\""));
        assert!(dot.contains("label=\"piece 2 (1 unit)\""));
        assert_eq!(count(&dot, "class=\"motion\""), 3);
        assert_eq!(count(&dot, "class=\"object\""), f.object_count());
        // Motions of a FOON are not numbered; the odd label is escaped.
        assert!(dot.contains("label=\"stir\""));
        assert!(dot.contains("label=\"b \\\"q\\\\&amp;y\\n(z)\""), "{dot}");
        // One piece: no cluster.
        let doc = FoonDoc::around(&f, 0, 0);
        let bytes = crate::write::to_bytes(|out| {
            crate::write::write_foon(Format::Dot, &doc, &Options::default(), out)
        })
        .unwrap();
        let dot = String::from_utf8(bytes).unwrap();
        assert_eq!(count(&dot, "subgraph cluster_p"), 0);
        assert_eq!(count(&dot, "class=\"object goal\""), 1);
    }

    #[test]
    fn neighbourhoods() {
        let f = foon();
        let id = |line: &str| {
            (0..f.object_count() as u32)
                .find(|&o| crate::write::object_line(&f, o) == line)
                .unwrap()
        };
        // Depth 0: the units that make or use the object.
        assert_eq!(
            crate::write::neighbourhood(&f, id("a (cut)"), 0).unwrap(),
            [0, 1]
        );
        assert_eq!(
            crate::write::neighbourhood(&f, id("a (raw)"), 0).unwrap(),
            [0]
        );
        assert_eq!(
            crate::write::neighbourhood(&f, id("a (done)"), 0).unwrap(),
            [1]
        );
        // Depth 1: and those that make or use their objects.
        assert_eq!(
            crate::write::neighbourhood(&f, id("a (raw)"), 1).unwrap(),
            [0, 1]
        );
        assert_eq!(
            crate::write::neighbourhood(&f, id("b (x)"), 5).unwrap(),
            [2]
        );
        // Out of range: an error, from the function and from every writer.
        let n = f.object_count() as u32;
        assert!(crate::write::neighbourhood(&f, n, 0).is_err());
        assert!(crate::write::neighbourhood(&f, crate::index::NONE, 0).is_err());
        assert!(FoonDoc::try_around(&f, n, 0).is_err());
        let doc = FoonDoc::around(&f, n, 0);
        let e = crate::write::write_foon(Format::Dot, &doc, &Options::default(), &mut Vec::new())
            .unwrap_err();
        assert!(e.to_string().contains("out of range"), "{e}");
        let doc = FoonDoc {
            units: Some(vec![0, 3]),
            ..FoonDoc::whole(&f)
        };
        let e = crate::write::write_foon(Format::Dot, &doc, &Options::default(), &mut Vec::new())
            .unwrap_err();
        assert!(e.to_string().contains("unit 3 is out of range"), "{e}");
    }
}
