//! Every output format, behind one interface: a [`Format`] (its name, extension and MIME
//! type) and three writers over [`io::Write`]: [`write_tree`] for a task tree
//! ([`TreeDoc`]), [`write_foon`] for a whole FOON or a part of it ([`FoonDoc`]) and
//! [`write_comparison`] for a comparison of methods ([`Comparison`]); [`write_explanation`]
//! and [`write_split`] draw what `foon explain` and `foon split` find. The CLI, the Python API
//! and the tests go through these; nothing else formats output.

mod chart;
mod compare;
mod doc;
mod dot;
mod explain;
mod graphml;
mod html;
pub mod json;
pub mod pddl;
pub mod render;
mod split;
mod steps;
mod text;

use std::io;
use std::str::FromStr;

pub use compare::{CompareRow, Comparison, SummaryRow};
pub use doc::{FoonDoc, TreeDoc, neighbourhood};
pub use explain::{blocking_nodes, write_explanation};
pub use split::write_split;
pub use text::{explanation_text, foon_text, fu_text, object_line, tree_text};

use crate::error::{Error, Result};
use crate::model::ObjectSpec;
use crate::search::Method;

/// An output format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// The course's text form (`//`, `O`, `S`, `M` lines); for a comparison, a table.
    Text,
    /// JSON (see `schema/foon.schema.json`).
    Json,
    /// Comma-separated values (comparisons only).
    Csv,
    /// Graphviz DOT in the FOON visual language.
    Dot,
    /// SVG, PNG or PDF: the DOT picture rendered by Graphviz's `dot`.
    Svg,
    Png,
    Pdf,
    /// One self-contained HTML page: picture, steps, figures.
    Html,
    /// Numbered plain-English steps.
    Steps,
    /// A PDDL domain and problem.
    Pddl,
    /// `GraphML` (the object–motion bipartite graph).
    Graphml,
}

impl Format {
    pub const ALL: [Format; 11] = [
        Self::Text,
        Self::Json,
        Self::Csv,
        Self::Dot,
        Self::Svg,
        Self::Png,
        Self::Pdf,
        Self::Html,
        Self::Steps,
        Self::Pddl,
        Self::Graphml,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            Self::Text => "text",
            Self::Json => "json",
            Self::Csv => "csv",
            Self::Dot => "dot",
            Self::Svg => "svg",
            Self::Png => "png",
            Self::Pdf => "pdf",
            Self::Html => "html",
            Self::Steps => "steps",
            Self::Pddl => "pddl",
            Self::Graphml => "graphml",
        }
    }

    /// The file name extension, with its dot.
    pub fn extension(self) -> &'static str {
        match self {
            Self::Text | Self::Steps => ".txt",
            Self::Json => ".json",
            Self::Csv => ".csv",
            Self::Dot => ".dot",
            Self::Svg => ".svg",
            Self::Png => ".png",
            Self::Pdf => ".pdf",
            Self::Html => ".html",
            Self::Pddl => ".pddl",
            Self::Graphml => ".graphml",
        }
    }

    /// The MIME type.
    pub fn mime(self) -> &'static str {
        match self {
            Self::Text | Self::Steps | Self::Pddl => "text/plain",
            Self::Json => "application/json",
            Self::Csv => "text/csv",
            Self::Dot => "text/vnd.graphviz",
            Self::Svg => "image/svg+xml",
            Self::Png => "image/png",
            Self::Pdf => "application/pdf",
            Self::Html => "text/html",
            Self::Graphml => "application/graphml+xml",
        }
    }

    /// Whether the output is bytes rather than UTF-8 text.
    pub fn is_binary(self) -> bool {
        matches!(self, Self::Png | Self::Pdf)
    }

    /// Whether writing runs Graphviz's `dot` (see [`render`]).
    pub fn needs_dot(self) -> bool {
        matches!(self, Self::Svg | Self::Png | Self::Pdf | Self::Html)
    }

    /// Whether this format can hold a task tree, a FOON and a comparison.
    pub fn writes_tree(self) -> bool {
        !matches!(self, Self::Csv)
    }
    pub fn writes_foon(self) -> bool {
        matches!(
            self,
            Self::Text
                | Self::Json
                | Self::Dot
                | Self::Svg
                | Self::Png
                | Self::Pdf
                | Self::Pddl
                | Self::Graphml
        )
    }
    pub fn writes_comparison(self) -> bool {
        matches!(self, Self::Text | Self::Json | Self::Csv | Self::Html)
    }

    fn names(pred: impl Fn(Self) -> bool) -> String {
        let mut seen = Vec::new();
        for f in Self::ALL {
            if pred(f) && !seen.contains(&f.as_str()) {
                seen.push(f.as_str());
            }
        }
        seen.join(", ")
    }

    fn unsupported(self, what: &str, pred: impl Fn(Self) -> bool) -> Error {
        Error::Invalid(format!(
            "the {} format cannot write {what} (choose from {})",
            self.as_str(),
            Self::names(pred)
        ))
    }
}

impl FromStr for Format {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|f| f.as_str() == s)
            .ok_or_else(|| {
                Error::Invalid(format!(
                    "unknown format '{s}' (choose from {})",
                    Self::names(|_| true)
                ))
            })
    }
}

/// Options shared by the writers (each reads the ones that concern it).
#[derive(Debug, Clone)]
pub struct Options {
    /// A title for pictures and pages (default: the goal, or the FOON's file name).
    pub title: Option<String>,
    /// Pictures and pages refuse graphs of more nodes than this (objects + motions): `dot`
    /// takes minutes on them and nobody can read the result. See [`render::MAX_NODES`].
    pub max_nodes: usize,
    /// PDDL: action costs are `round(-ln(rate) * cost_scale)`.
    pub cost_scale: u32,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            title: None,
            max_nodes: render::MAX_NODES,
            cost_scale: 1000,
        }
    }
}

pub(crate) fn put(out: &mut dyn io::Write, bytes: &[u8]) -> Result<()> {
    out.write_all(bytes).map_err(|e| Error::Io {
        path: "<output>".into(),
        source: e,
    })
}

/// A goal that could not be planned (not in the FOON, ambiguous, a motion without a rate):
/// it has its own entry in the formats that list goals (JSON), and none in pictures.
#[derive(Debug, Clone, PartialEq)]
pub struct Failed {
    /// The goal as given; `label_only` when only its label was given.
    pub goal: ObjectSpec,
    pub label_only: bool,
    pub method: Method,
    pub error: String,
}

impl Failed {
    /// The goal as given, on one line: its label alone when only the label was given.
    pub fn goal_text(&self) -> String {
        if self.label_only {
            self.goal.label.clone()
        } else {
            self.goal.describe()
        }
    }
}

/// One entry of a stream of task trees.
pub enum Item<'a> {
    Tree(TreeDoc<'a>),
    Failed(&'a Failed),
}

/// What each format does with a stream of task trees: write as they come (text, JSON,
/// steps) or keep what it needs and write everything at the end (pictures, pages).
pub(crate) trait TreeFormat {
    fn begin(&mut self, out: &mut dyn io::Write) -> Result<()> {
        let _ = out;
        Ok(())
    }
    fn tree(&mut self, doc: &TreeDoc<'_>, out: &mut dyn io::Write) -> Result<()>;
    fn failed(&mut self, failed: &Failed, out: &mut dyn io::Write) -> Result<()> {
        let _ = (failed, out);
        Ok(())
    }
    fn end(&mut self, out: &mut dyn io::Write) -> Result<()> {
        let _ = out;
        Ok(())
    }
}

/// Writes task trees in one format: one tree as its own document (`many` false), or any
/// number of them as one document (`many` true: a JSON list, a picture with a cluster per
/// tree, a page with a section per tree, text with a `# goal:` line before each tree).
/// Call [`begin`](Self::begin), [`item`](Self::item) for each entry, then
/// [`end`](Self::end); streaming formats write as items come, so memory stays flat.
pub struct TreeWriter {
    format: Format,
    many: bool,
    items: usize,
    inner: Box<dyn TreeFormat + Send>,
}

impl TreeWriter {
    pub fn new(format: Format, opts: &Options, many: bool) -> Result<Self> {
        let inner: Box<dyn TreeFormat + Send> = match format {
            Format::Text => Box::new(text::TextTrees::new(many)),
            Format::Json => Box::new(json::JsonTrees::new(many)),
            Format::Steps => Box::new(steps::StepTrees::new(many)),
            Format::Dot | Format::Svg | Format::Png | Format::Pdf => {
                Box::new(dot::DotTrees::new(format, opts, many))
            }
            Format::Html => Box::new(html::HtmlTrees::new(opts, many)),
            Format::Graphml => Box::new(graphml::GraphmlTrees::new(opts, many)),
            Format::Pddl if many => {
                return Err(Error::Invalid(
                    "PDDL holds one goal's problem: give one goal or --out DIR".to_owned(),
                ));
            }
            Format::Pddl => Box::new(pddl::PddlTree::new(opts)),
            f @ Format::Csv => return Err(f.unsupported("a task tree", Format::writes_tree)),
        };
        Ok(Self {
            format,
            many,
            items: 0,
            inner,
        })
    }

    pub fn format(&self) -> Format {
        self.format
    }

    pub fn begin(&mut self, out: &mut dyn io::Write) -> Result<()> {
        self.inner.begin(out)
    }

    pub fn item(&mut self, item: &Item<'_>, out: &mut dyn io::Write) -> Result<()> {
        if !self.many && self.items > 0 {
            return Err(Error::Invalid(format!(
                "a {} document holds one task tree",
                self.format.as_str()
            )));
        }
        self.items += 1;
        match item {
            Item::Tree(doc) => self.inner.tree(doc, out),
            Item::Failed(f) => self.inner.failed(f, out),
        }
    }

    pub fn end(&mut self, out: &mut dyn io::Write) -> Result<()> {
        self.inner.end(out)
    }
}

/// Writes one task tree as its own document in `format`.
pub fn write_tree(
    format: Format,
    doc: &TreeDoc<'_>,
    opts: &Options,
    out: &mut dyn io::Write,
) -> Result<()> {
    let mut w = TreeWriter::new(format, opts, false)?;
    w.begin(out)?;
    w.item(&Item::Tree(TreeDoc::new(doc.foon, doc.prep, doc.plan)), out)?;
    w.end(out)
}

/// Writes a FOON (or the part of it that `doc` selects) in `format`.
pub fn write_foon(
    format: Format,
    doc: &FoonDoc<'_>,
    opts: &Options,
    out: &mut dyn io::Write,
) -> Result<()> {
    match format {
        Format::Text => put(out, tree_text(doc.foon, &doc.units()).as_bytes()),
        Format::Json => json::write_foon(doc, out),
        Format::Dot | Format::Svg | Format::Png | Format::Pdf => {
            dot::write_foon(format, doc, opts, out)
        }
        Format::Graphml => graphml::write_foon(doc, opts, out),
        Format::Pddl => pddl::write_foon(doc, opts, out),
        f => Err(f.unsupported("a FOON", Format::writes_foon)),
    }
}

/// Writes a comparison of methods in `format`.
pub fn write_comparison(
    format: Format,
    doc: &Comparison,
    opts: &Options,
    out: &mut dyn io::Write,
) -> Result<()> {
    match format {
        Format::Text => put(out, compare::table_text(doc).as_bytes()),
        Format::Csv => put(out, compare::table_csv(doc).as_bytes()),
        Format::Html => html::write_comparison(doc, opts, out),
        Format::Json => json::write_comparison(doc, out),
        f => Err(f.unsupported("a comparison", Format::writes_comparison)),
    }
}

/// Writes into a byte buffer (what the bindings hand to Python).
pub fn to_bytes(f: impl FnOnce(&mut dyn io::Write) -> Result<()>) -> Result<Vec<u8>> {
    let mut buf = Vec::new();
    f(&mut buf)?;
    Ok(buf)
}
