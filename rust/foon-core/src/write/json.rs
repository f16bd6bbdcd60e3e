//! Every JSON `foon` writes, through serde, in the shapes of `schema/foon.schema.json`:
//! task trees (`JsonTrees`, one object or a streamed list), FOONs in the lab's dialect
//! (`write_foon`), kitchens and goals ([`objects_json`]), comparisons, verify reports
//! ([`verify_json`]), check findings ([`check_json`]) and statistics ([`stats_json`]).
//!
//! Task trees, comparisons, reports, findings and statistics are indented by 2 spaces;
//! FOONs and kitchens by 4, as the lab's and the course's files are.

use std::io;

use serde::Serialize;

use super::{Failed, FoonDoc, TreeDoc, TreeFormat, explanation_text, put};
use crate::error::{Error, Result};
use crate::index::{Foon, NONE, Stats};
use crate::lint::Finding;
use crate::model::ObjectSpec;
use crate::verify::TreeReport;

/// The version of the schema the output follows (its `$id` ends with it).
pub const SCHEMA_VERSION: &str = "1";

/// Serialises `v` with `indent` spaces per level.
fn to_vec(v: &impl Serialize, indent: &[u8]) -> Result<Vec<u8>> {
    let mut buf = Vec::new();
    let fmt = serde_json::ser::PrettyFormatter::with_indent(indent);
    let mut ser = serde_json::Serializer::with_formatter(&mut buf, fmt);
    v.serialize(&mut ser)
        .map_err(|e| Error::Invalid(format!("cannot write JSON: {e}")))?;
    Ok(buf)
}

/// `v` as a JSON document indented by 2 spaces, with a final newline.
pub fn to_json(v: &impl Serialize) -> Result<String> {
    let mut b = to_vec(v, b"  ")?;
    b.push(b'\n');
    Ok(String::from_utf8(b).unwrap_or_default())
}

/// An object in the kitchen and goal shape.
#[derive(Serialize)]
struct JsonObject<'a> {
    label: &'a str,
    states: Vec<&'a str>,
    ingredients: Vec<&'a str>,
    container: Option<&'a str>,
}

impl<'a> From<&'a ObjectSpec> for JsonObject<'a> {
    fn from(o: &'a ObjectSpec) -> Self {
        Self {
            label: &o.label,
            states: o.states.iter().map(String::as_str).collect(),
            ingredients: o.ingredients.iter().map(String::as_str).collect(),
            container: o.container.as_deref(),
        }
    }
}

/// A node of a functional unit: the object as written there (its variant), with its
/// in-motion flag when the source gave one.
#[derive(Serialize)]
struct JsonNode<'a> {
    label: &'a str,
    states: Vec<&'a str>,
    ingredients: Vec<&'a str>,
    container: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    in_motion: Option<u8>,
}

fn node(foon: &Foon, var: u32, flag: u8) -> JsonNode<'_> {
    let obj = foon.variant_object(var);
    let c = foon.container(obj);
    JsonNode {
        label: foon.label_text(obj),
        states: foon
            .variant_states(var)
            .iter()
            .map(|&s| foon.text(s))
            .collect(),
        ingredients: foon
            .variant_ingredients(var)
            .iter()
            .map(|&s| foon.text(s))
            .collect(),
        container: (c != NONE).then(|| foon.text(c)),
        in_motion: (flag < 2).then_some(flag),
    }
}

/// A functional unit in the lab's dialect, with its motion metadata when it has some.
#[derive(Serialize)]
struct JsonFu<'a> {
    input_nodes: Vec<JsonNode<'a>>,
    motion_node: &'a str,
    output_nodes: Vec<JsonNode<'a>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    motion_meta: Option<&'a str>,
}

fn unit(foon: &Foon, fu: u32) -> JsonFu<'_> {
    let nodes = |vars: &[u32], flags: &[u8]| -> Vec<JsonNode<'_>> {
        vars.iter()
            .zip(flags)
            .map(|(&v, &f)| node(foon, v, f))
            .collect()
    };
    JsonFu {
        input_nodes: nodes(foon.input_variants(fu), foon.input_in_motion(fu)),
        motion_node: foon.motion_text(fu),
        output_nodes: nodes(foon.output_variants(fu), foon.output_in_motion(fu)),
        motion_meta: foon.motion_meta(fu),
    }
}

/// Writes `items` as a JSON list, one item at a time (memory stays flat), each indented by
/// `indent`.
fn write_list<T: Serialize>(
    items: impl Iterator<Item = T>,
    indent: &[u8],
    out: &mut dyn io::Write,
) -> Result<()> {
    let mut first = true;
    for item in items {
        put(out, if first { b"[\n" } else { b",\n" })?;
        first = false;
        put(out, &indented(&to_vec(&item, indent)?, indent))?;
    }
    put(out, if first { b"[]\n" } else { b"\n]\n" })
}

/// A JSON value shifted right by one level (strings hold no raw line breaks, so every line
/// break of the text is between tokens).
fn indented(v: &[u8], indent: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(v.len() + v.len() / 8);
    out.extend_from_slice(indent);
    for &c in v {
        out.push(c);
        if c == b'\n' {
            out.extend_from_slice(indent);
        }
    }
    out
}

/// A FOON (or the units `doc` selects) in the lab's JSON dialect, a unit at a time.
pub(super) fn write_foon(doc: &FoonDoc<'_>, out: &mut dyn io::Write) -> Result<()> {
    let foon = doc.foon;
    match &doc.units {
        Some(us) => write_list(us.iter().map(|&f| unit(foon, f)), b"    ", out),
        None => write_list(
            (0..foon.fu_count() as u32).map(|f| unit(foon, f)),
            b"    ",
            out,
        ),
    }
}

/// A list of objects (a kitchen, goals) in the kitchen and goal shape, indented by 4
/// spaces, with no final newline.
pub fn objects_json(items: &[ObjectSpec]) -> Result<String> {
    let v: Vec<JsonObject<'_>> = items.iter().map(JsonObject::from).collect();
    Ok(String::from_utf8(to_vec(&v, b"    ")?).unwrap_or_default())
}

/// A task tree: the plan's result and figures (with the identity `level` the goal and the
/// kitchen were matched at, and `optimal-shared`'s `bound`, `proven`, `gap` and `objective`,
/// `null` for the other methods), and what makes it self-contained: the kitchen
/// items it uses (`leaves`), the rate each unit used (`rates`, `null` without a rate table),
/// the units themselves in the lab's dialect (`functional_units`) and the FOON it came from.
#[derive(Serialize)]
struct JsonTree<'a> {
    goal: JsonObject<'a>,
    method: &'static str,
    compat: &'static str,
    count: &'static str,
    level: u8,
    solved: bool,
    units: &'a [u32],
    fu_count: usize,
    height: Option<u32>,
    success: Option<f64>,
    unrated_motion: Option<&'a str>,
    cost: Option<f64>,
    bound: Option<f64>,
    proven: Option<bool>,
    gap: Option<f64>,
    objective: Option<&'static str>,
    leaf_inputs: usize,
    expanded: u64,
    peak_frontier: usize,
    seconds: f64,
    unresolved: Vec<ObjectSpec>,
    missing: Vec<ObjectSpec>,
    cycle: Vec<ObjectSpec>,
    cycle_units: &'a [u32],
    explanation: String,
    leaves: Vec<ObjectSpec>,
    rates: Option<Vec<Option<f64>>>,
    functional_units: Vec<JsonFu<'a>>,
    source: Option<String>,
}

impl Serialize for ObjectSpec {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        JsonObject::from(self).serialize(s)
    }
}

fn tree_value<'a>(doc: &'a TreeDoc<'a>, goal: &'a ObjectSpec) -> JsonTree<'a> {
    let (foon, plan) = (doc.foon, doc.plan);
    let objects = |ids: &[u32]| -> Vec<ObjectSpec> {
        ids.iter()
            .map(|&o| ObjectSpec::of_object(foon, o))
            .collect()
    };
    let e = plan.explanation.as_ref();
    JsonTree {
        goal: JsonObject::from(goal),
        method: plan.query.method.as_str(),
        compat: plan.query.compat.as_str(),
        count: plan.query.count.as_str(),
        level: doc.prep.level(),
        solved: plan.solved,
        units: &plan.units,
        fu_count: plan.units.len(),
        height: plan.height,
        success: plan.success,
        unrated_motion: plan.unrated.map(|u| foon.motion_text(u)),
        cost: plan.cost,
        bound: plan.bound,
        proven: plan.proven,
        gap: plan.gap(),
        objective: plan.objective.map(crate::search::SharedObjective::as_str),
        leaf_inputs: plan.leaf_inputs,
        expanded: plan.expanded,
        peak_frontier: plan.peak_frontier,
        seconds: plan.seconds,
        unresolved: objects(&plan.unresolved),
        missing: e.map(|e| objects(&e.missing)).unwrap_or_default(),
        cycle: e.map(|e| objects(&e.cycle)).unwrap_or_default(),
        cycle_units: e.map_or(&[], |e| &e.cycle_units),
        explanation: explanation_text(foon, plan),
        leaves: objects(&doc.leaves()),
        rates: doc
            .prep
            .rates_given()
            .then(|| plan.units.iter().map(|&f| doc.rate(f)).collect()),
        functional_units: plan.units.iter().map(|&f| unit(foon, f)).collect(),
        source: foon.source().map(|p| p.display().to_string()),
    }
}

/// A goal that could not be planned.
#[derive(Serialize)]
struct JsonFailed<'a> {
    goal: FailedGoal<'a>,
    method: &'static str,
    solved: bool,
    error: &'a str,
}

#[derive(Serialize)]
#[serde(untagged)]
enum FailedGoal<'a> {
    Label { label: &'a str },
    Object(JsonObject<'a>),
}

fn failed_value(f: &Failed) -> JsonFailed<'_> {
    JsonFailed {
        goal: if f.label_only {
            FailedGoal::Label {
                label: &f.goal.label,
            }
        } else {
            FailedGoal::Object(JsonObject::from(&f.goal))
        },
        method: f.method.as_str(),
        solved: false,
        error: &f.error,
    }
}

/// Task trees as JSON: one object (`many` false), or a list written an item at a time.
pub(super) struct JsonTrees {
    many: bool,
    items: usize,
}

impl JsonTrees {
    pub(super) fn new(many: bool) -> Self {
        Self { many, items: 0 }
    }

    fn item(&mut self, v: &impl Serialize, out: &mut dyn io::Write) -> Result<()> {
        if !self.many {
            let mut b = to_vec(v, b"  ")?;
            b.push(b'\n');
            return put(out, &b);
        }
        put(out, if self.items == 0 { b"[\n" } else { b",\n" })?;
        self.items += 1;
        put(out, &indented(&to_vec(v, b"  ")?, b"  "))
    }
}

impl TreeFormat for JsonTrees {
    fn tree(&mut self, doc: &TreeDoc<'_>, out: &mut dyn io::Write) -> Result<()> {
        let goal = ObjectSpec::of_object(doc.foon, doc.goal());
        self.item(&tree_value(doc, &goal), out)
    }

    fn failed(&mut self, failed: &Failed, out: &mut dyn io::Write) -> Result<()> {
        self.item(&failed_value(failed), out)
    }

    fn end(&mut self, out: &mut dyn io::Write) -> Result<()> {
        if !self.many {
            return Ok(());
        }
        put(out, if self.items == 0 { b"[]\n" } else { b"\n]\n" })
    }
}

/// A comparison: `{"rows": [...], "summary": [...]}`.
pub(super) fn write_comparison(doc: &super::Comparison, out: &mut dyn io::Write) -> Result<()> {
    put(out, to_json(doc)?.as_bytes())
}

#[derive(Serialize)]
struct JsonBlocked<'a> {
    position: usize,
    line: u32,
    missing: &'a [ObjectSpec],
}

#[derive(Serialize)]
struct JsonAt {
    position: usize,
    line: u32,
}

#[derive(Serialize)]
struct JsonReport<'a> {
    valid: bool,
    units: usize,
    goal_made: bool,
    goal_absent: bool,
    blocked: Option<JsonBlocked<'a>>,
    foreign_units: Vec<JsonAt>,
}

/// What `foon verify --json` prints: `valid`, `units`, `goal_made`, `goal_absent`, the
/// first unit that cannot run (`blocked`: its position, line and missing inputs) and the
/// units that are not units of the FOON.
pub fn verify_json(r: &TreeReport) -> Result<String> {
    to_json(&JsonReport {
        valid: r.is_valid(),
        units: r.units,
        goal_made: r.goal_made,
        goal_absent: r.goal_absent,
        blocked: r.first_blocked.as_ref().map(|b| JsonBlocked {
            position: b.position,
            line: b.line,
            missing: &b.missing,
        }),
        foreign_units: r
            .foreign_units
            .iter()
            .map(|&(position, line)| JsonAt { position, line })
            .collect(),
    })
}

/// One finding of `foon check`, as its JSON lists it.
#[derive(Debug, Clone, Serialize)]
pub struct CheckRow {
    pub path: Option<String>,
    pub line: u64,
    pub column: u32,
    pub severity: String,
    pub code: String,
    pub message: String,
}

impl From<&Finding> for CheckRow {
    fn from(f: &Finding) -> Self {
        Self {
            path: f.at.path.as_ref().map(|p| p.display().to_string()),
            line: f.at.line,
            column: f.at.column,
            severity: f.severity.as_str().to_owned(),
            code: f.code.to_owned(),
            message: f.message.clone(),
        }
    }
}

/// What `foon check --json` prints: a list of findings.
pub fn check_json(rows: &[CheckRow]) -> Result<String> {
    to_json(&rows)
}

#[derive(Serialize)]
struct JsonStats<'a> {
    file: &'a str,
    functional_units: usize,
    objects: usize,
    produced_objects: usize,
    motions: usize,
    strings: usize,
    input_edges: usize,
    output_edges: usize,
    duplicates_dropped: usize,
    warnings: usize,
    index_bytes: usize,
}

/// What `foon stats --json` prints: per file (named as given), its counts.
pub fn stats_json(rows: &[(&str, Stats)]) -> Result<String> {
    let v: Vec<JsonStats<'_>> = rows
        .iter()
        .map(|&(file, s)| JsonStats {
            file,
            functional_units: s.functional_units,
            objects: s.objects,
            produced_objects: s.produced_objects,
            motions: s.motions,
            strings: s.strings,
            input_edges: s.input_edges,
            output_edges: s.output_edges,
            duplicates_dropped: s.duplicates_dropped,
            warnings: s.warnings,
            index_bytes: s.index_bytes,
        })
        .collect();
    to_json(&v)
}
