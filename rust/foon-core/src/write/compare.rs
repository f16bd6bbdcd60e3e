//! A comparison of planning methods over goals: one row per (method, goal), one summary row
//! per method. Built here from the plans, so every format writes the same figures.

use serde::Serialize;

use crate::index::Foon;
use crate::search::Plan;

/// One goal planned by one method.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CompareRow {
    /// The goal, described on one line.
    pub goal: String,
    /// The method's name, with ` (course)` for course-compatible runs.
    pub method: String,
    pub solved: bool,
    pub fu_count: Option<usize>,
    pub height: Option<u32>,
    pub success: Option<f64>,
    pub leaf_inputs: Option<usize>,
    pub expanded: Option<u64>,
    pub peak_frontier: Option<usize>,
    pub seconds: Option<f64>,
    /// Why the goal could not be planned at all (not found in the FOON, ...).
    pub error: Option<String>,
    /// The identity level the kitchen and the goals were matched at (3: full identity).
    pub level: u8,
    /// `optimal-shared`: what `bound` measures (`units` or `success`), the proven bound on
    /// the tree's figure, whether the search finished and |figure - bound|; `None` for the
    /// other methods (and for an unsolved goal, all but `objective`).
    pub objective: Option<&'static str>,
    pub bound: Option<f64>,
    pub proven: Option<bool>,
    pub gap: Option<f64>,
    /// With `foon compare --split M`: the budget M of human steps, and for the row's goal
    /// the best success of the exact robot/human split and of the lab's fixed-tree method
    /// with at most M human steps (`None` when the goal has no tree); `None` without.
    pub max_human: Option<u32>,
    pub split_success: Option<f64>,
    pub fixed_tree_success: Option<f64>,
}

impl CompareRow {
    /// The row of a plan.
    pub fn of_plan(foon: &Foon, method: &str, plan: &Plan) -> Self {
        let solved = plan.solved;
        Self {
            goal: super::object_line(foon, plan.goal),
            method: method.to_owned(),
            solved,
            fu_count: solved.then_some(plan.units.len()),
            height: plan.height,
            success: plan.success.filter(|_| solved),
            leaf_inputs: solved.then_some(plan.leaf_inputs),
            expanded: Some(plan.expanded),
            peak_frontier: Some(plan.peak_frontier),
            seconds: Some(plan.seconds),
            error: None,
            level: 3,
            objective: plan.objective.map(crate::search::SharedObjective::as_str),
            bound: plan.bound,
            proven: plan.proven,
            gap: plan.gap(),
            max_human: None,
            split_success: None,
            fixed_tree_success: None,
        }
    }

    /// The row of a method that gives only a tree's size and success (the robot/human split
    /// and the lab's fixed-tree method: `success` is the success they maximise, as tree cost
    /// counts it; no height, leaves or peak).
    #[allow(clippy::too_many_arguments)]
    pub fn of_figures(
        foon: &Foon,
        method: &str,
        goal: u32,
        solved: bool,
        fu_count: Option<usize>,
        success: Option<f64>,
        expanded: u64,
        seconds: f64,
    ) -> Self {
        Self {
            solved,
            fu_count: fu_count.filter(|_| solved),
            success: success.filter(|_| solved),
            expanded: Some(expanded),
            seconds: Some(seconds),
            ..Self::blank(super::object_line(foon, goal), method)
        }
    }

    /// The row of a goal that could not be planned.
    pub fn failed(goal: String, method: &str, error: String) -> Self {
        Self {
            error: Some(error),
            ..Self::blank(goal, method)
        }
    }

    /// A row with no figure (level 3).
    fn blank(goal: String, method: &str) -> Self {
        Self {
            goal,
            method: method.to_owned(),
            solved: false,
            fu_count: None,
            height: None,
            success: None,
            leaf_inputs: None,
            expanded: None,
            peak_frontier: None,
            seconds: None,
            error: None,
            level: 3,
            objective: None,
            bound: None,
            proven: None,
            gap: None,
            max_human: None,
            split_success: None,
            fixed_tree_success: None,
        }
    }

    /// The row at identity level `level`.
    #[must_use]
    pub fn at_level(mut self, level: u8) -> Self {
        self.level = level;
        self
    }

    /// The row with its goal's split columns (`foon compare --split M`): the best success of
    /// the exact split and of the lab's fixed-tree method with at most `max_human` human
    /// steps.
    #[must_use]
    pub fn with_split(mut self, max_human: u32, split: Option<f64>, fixed: Option<f64>) -> Self {
        self.max_human = Some(max_human);
        self.split_success = split;
        self.fixed_tree_success = fixed;
        self
    }
}

/// One method over all goals: the solved count, the number of goals, means of the tree
/// measures over the solved goals (of `expanded` and `peak_frontier` over the planned goals)
/// and the total planning time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SummaryRow {
    pub method: String,
    pub solved_count: usize,
    pub goals: usize,
    pub fu_count: Option<f64>,
    pub height: Option<f64>,
    pub success: Option<f64>,
    pub leaf_inputs: Option<f64>,
    pub expanded: Option<f64>,
    pub peak_frontier: Option<f64>,
    pub seconds_total: f64,
    /// `optimal-shared`: how many goals its search proved optimal and the mean gap over the
    /// solved ones; `None` for the other methods.
    pub proven_count: Option<usize>,
    pub gap: Option<f64>,
    /// With `--split M`: the mean over the method's goals of their split and fixed-tree
    /// successes (over the goals that have them).
    pub split_success: Option<f64>,
    pub fixed_tree_success: Option<f64>,
}

/// Rows in the order given (methods, then goals), and a summary per method in order of
/// first appearance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    pub rows: Vec<CompareRow>,
    pub summary: Vec<SummaryRow>,
}

fn mean<'a, T: Copy + Into<f64> + 'a>(vals: impl Iterator<Item = Option<T>>) -> Option<f64> {
    let (mut n, mut sum) = (0usize, 0.0f64);
    for v in vals.flatten() {
        n += 1;
        sum += v.into();
    }
    (n > 0).then(|| sum / n as f64)
}

impl Comparison {
    pub fn new(rows: Vec<CompareRow>) -> Self {
        let mut methods: Vec<&str> = Vec::new();
        for r in &rows {
            if !methods.contains(&r.method.as_str()) {
                methods.push(&r.method);
            }
        }
        let summary = methods
            .iter()
            .map(|&m| {
                let rs: Vec<&CompareRow> = rows.iter().filter(|r| r.method == m).collect();
                let planned = || rs.iter().filter(|r| r.error.is_none());
                let ok = || rs.iter().filter(|r| r.solved);
                SummaryRow {
                    method: m.to_owned(),
                    solved_count: ok().count(),
                    goals: rs.len(),
                    fu_count: mean(ok().map(|r| r.fu_count.map(|v| v as f64))),
                    height: mean(ok().map(|r| r.height)),
                    success: mean(ok().map(|r| r.success)),
                    leaf_inputs: mean(ok().map(|r| r.leaf_inputs.map(|v| v as f64))),
                    expanded: mean(planned().map(|r| r.expanded.map(|v| v as f64))),
                    peak_frontier: mean(planned().map(|r| r.peak_frontier.map(|v| v as f64))),
                    seconds_total: planned().filter_map(|r| r.seconds).sum(),
                    proven_count: rs
                        .iter()
                        .any(|r| r.objective.is_some())
                        .then(|| rs.iter().filter(|r| r.proven == Some(true)).count()),
                    gap: mean(ok().map(|r| r.gap)),
                    split_success: mean(rs.iter().map(|r| r.split_success)),
                    fixed_tree_success: mean(rs.iter().map(|r| r.fixed_tree_success)),
                }
            })
            .collect();
        Self { rows, summary }
    }
}

/// How a table cell shows a figure: `-` when absent, a rate as a percentage with two
/// decimals, seconds as milliseconds with three, other fractions with one.
#[derive(Clone, Copy)]
pub(super) enum Cell {
    Plain,
    Percent,
    Millis,
}

/// A figure in a table cell (see [`Cell`]); whole numbers as they are.
pub(super) fn cell_f64(v: Option<f64>, kind: Cell) -> String {
    match (v, kind) {
        (None, _) => "-".to_owned(),
        (Some(v), Cell::Percent) => format!("{:.2}%", 100.0 * v),
        (Some(v), Cell::Millis) => format!("{:.3}", 1000.0 * v),
        (Some(v), Cell::Plain) => format!("{v:.1}"),
    }
}

pub(super) fn cell_int(v: Option<impl std::fmt::Display>) -> String {
    v.map_or_else(|| "-".to_owned(), |v| v.to_string())
}

/// The cells of one table row: goal (or summary text), method, units, height, success,
/// leaves, expanded, peak frontier and the last cell (milliseconds, or `not found`), then the
/// optional columns of [`Extras`].
pub(super) const TABLE_HEAD: [&str; 9] = [
    "goal", "method", "units", "height", "success", "leaves", "expanded", "peak", "ms",
];

/// The optional column groups of a comparison's tables: the identity `level` (when not 3),
/// `optimal-shared`'s bound, gap and proven (when it is compared) and the split columns
/// (with `--split M`).
#[derive(Clone, Copy)]
pub(super) struct Extras {
    level: bool,
    shared: bool,
    split: Option<u32>,
}

impl Comparison {
    pub(super) fn extras(&self) -> Extras {
        Extras {
            level: self.rows.iter().any(|r| r.level != 3),
            shared: self.rows.iter().any(|r| r.objective.is_some()),
            split: self.rows.iter().find_map(|r| r.max_human),
        }
    }
}

impl Extras {
    /// The headers of the optional columns.
    pub(super) fn head(self) -> Vec<String> {
        let mut h = Vec::new();
        if self.level {
            h.push("level".to_owned());
        }
        if self.shared {
            h.extend(["bound", "gap", "proven"].map(str::to_owned));
        }
        if let Some(m) = self.split {
            h.push(format!("split M={m}"));
            h.push(format!("fixed-tree M={m}"));
        }
        h
    }
}

/// `optimal-shared`'s bound or gap in a cell: a success as a percentage, a unit count as a
/// whole number when it is one.
fn cell_figure(v: Option<f64>, objective: Option<&str>) -> String {
    match (v, objective) {
        (Some(v), Some("success")) => cell_f64(Some(v), Cell::Percent),
        (Some(v), _) if v.fract() == 0.0 && v.abs() < 1e15 => format!("{v:.0}"),
        (v, _) => cell_f64(v, Cell::Plain),
    }
}

impl CompareRow {
    /// The row's cells under [`TABLE_HEAD`] (the goal cut to 48 characters).
    pub(super) fn cells(&self) -> Vec<String> {
        vec![
            self.goal.chars().take(48).collect(),
            self.method.clone(),
            cell_int(self.fu_count),
            cell_int(self.height),
            cell_f64(self.success, Cell::Percent),
            cell_int(self.leaf_inputs),
            cell_int(self.expanded),
            cell_int(self.peak_frontier),
            if self.error.is_some() {
                "not found".to_owned()
            } else {
                cell_f64(self.seconds, Cell::Millis)
            },
        ]
    }

    /// The row's cells under [`Extras::head`].
    pub(super) fn extra_cells(&self, x: Extras) -> Vec<String> {
        let mut c = Vec::new();
        if x.level {
            c.push(self.level.to_string());
        }
        if x.shared {
            c.push(cell_figure(self.bound, self.objective));
            c.push(cell_figure(self.gap, self.objective));
            c.push(match self.proven {
                Some(true) => "yes".to_owned(),
                Some(false) => "no".to_owned(),
                None => "-".to_owned(),
            });
        }
        if x.split.is_some() {
            c.push(cell_f64(self.split_success, Cell::Percent));
            c.push(cell_f64(self.fixed_tree_success, Cell::Percent));
        }
        c
    }
}

impl SummaryRow {
    /// The row's cells under [`TABLE_HEAD`].
    pub(super) fn cells(&self) -> Vec<String> {
        vec![
            format!(
                "(all: {}/{} solved; means, total ms)",
                self.solved_count, self.goals
            ),
            self.method.clone(),
            cell_f64(self.fu_count, Cell::Plain),
            cell_f64(self.height, Cell::Plain),
            cell_f64(self.success, Cell::Percent),
            cell_f64(self.leaf_inputs, Cell::Plain),
            cell_f64(self.expanded, Cell::Plain),
            cell_f64(self.peak_frontier, Cell::Plain),
            cell_f64(Some(self.seconds_total), Cell::Millis),
        ]
    }

    /// The row's cells under [`Extras::head`]: no level or bound; the mean gap, the proven
    /// count, the mean split successes.
    pub(super) fn extra_cells(&self, x: Extras) -> Vec<String> {
        let mut c = Vec::new();
        if x.level {
            c.push("-".to_owned());
        }
        if x.shared {
            c.push("-".to_owned());
            c.push(cell_f64(self.gap, Cell::Plain));
            c.push(
                self.proven_count
                    .map_or_else(|| "-".to_owned(), |n| format!("{n}/{}", self.solved_count)),
            );
        }
        if x.split.is_some() {
            c.push(cell_f64(self.split_success, Cell::Percent));
            c.push(cell_f64(self.fixed_tree_success, Cell::Percent));
        }
        c
    }
}

/// The comparison as a text table: a header, a rule, a row per (method, goal), a rule and a
/// summary row per method; the first two columns left-aligned, the others right-aligned.
/// Nothing at all when there is no row.
pub(super) fn table_text(doc: &Comparison) -> String {
    if doc.rows.is_empty() {
        return String::new();
    }
    let x = doc.extras();
    let mut head: Vec<String> = TABLE_HEAD.map(str::to_owned).to_vec();
    head.extend(x.head());
    let body: Vec<Vec<String>> = doc
        .rows
        .iter()
        .map(|r| [r.cells(), r.extra_cells(x)].concat())
        .chain(
            doc.summary
                .iter()
                .map(|s| [s.cells(), s.extra_cells(x)].concat()),
        )
        .collect();
    let mut widths = vec![0usize; head.len()];
    for row in std::iter::once(&head).chain(&body) {
        for (w, c) in widths.iter_mut().zip(row) {
            *w = (*w).max(c.chars().count());
        }
    }
    let line = |cells: &[String]| {
        let mut s = String::new();
        for (i, (c, &w)) in cells.iter().zip(&widths).enumerate() {
            if i > 0 {
                s.push_str("  ");
            }
            let pad = " ".repeat(w - c.chars().count());
            if i < 2 {
                s.push_str(c);
                s.push_str(&pad);
            } else {
                s.push_str(&pad);
                s.push_str(c);
            }
        }
        s.push('\n');
        s
    };
    let first = line(&head);
    let rule = format!("{}\n", "-".repeat(first.chars().count() - 1));
    let mut out = first;
    out.push_str(&rule);
    for (i, row) in body.iter().enumerate() {
        if i == doc.rows.len() {
            out.push_str(&rule);
        }
        out.push_str(&line(row));
    }
    out
}

/// A float as Python's `repr` writes it: the shortest digits that read back to the same
/// value, in fixed notation when the decimal point falls within 16 digits of the first
/// digit and after at most 3 leading zeros (`0.0001`, `123.0`), else in exponent notation
/// with a signed exponent of at least two digits (`1e-05`, `1.5e+16`).
pub(super) fn py_float(v: f64) -> String {
    if v.is_nan() {
        return "nan".to_owned();
    }
    if v.is_infinite() {
        return if v > 0.0 { "inf" } else { "-inf" }.to_owned();
    }
    let sci = format!("{:e}", v.abs());
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    let sign = if v.is_sign_negative() { "-" } else { "" };
    let point = exp + 1;
    if v == 0.0 {
        return format!("{sign}0.0");
    }
    if point > -4 && point <= 16 {
        let n = i32::try_from(digits.len()).unwrap_or(i32::MAX);
        let body = if point <= 0 {
            format!("0.{}{digits}", "0".repeat(point.unsigned_abs() as usize))
        } else if point >= n {
            format!("{digits}{}.0", "0".repeat((point - n) as usize))
        } else {
            let (a, b) = digits.split_at(point as usize);
            format!("{a}.{b}")
        };
        format!("{sign}{body}")
    } else {
        let (first, rest) = digits.split_at(1);
        let frac = if rest.is_empty() {
            String::new()
        } else {
            format!(".{rest}")
        };
        let esign = if exp < 0 { '-' } else { '+' };
        format!("{sign}{first}{frac}e{esign}{:02}", exp.unsigned_abs())
    }
}

/// A CSV field as Python's `csv` module writes it: quoted (quotes doubled) when it holds a
/// comma, a quote or a line break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\r', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_owned()
    }
}

fn py_opt_f64(v: Option<f64>) -> String {
    v.map(py_float).unwrap_or_default()
}

fn py_opt<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map(|v| v.to_string()).unwrap_or_default()
}

/// The comparison as CSV (what Python's `csv.DictWriter` writes, lines ending in CRLF):
/// the row fields, then `solved_count`, `goals` and `seconds_total`, then `level`,
/// `objective`, `bound`, `proven`, `gap`, `max_human`, `split_success`,
/// `fixed_tree_success` and `proven_count`; a row per (method,
/// goal), then a summary row per method with the goal `(all)`. Absent values are empty,
/// booleans `True`/`False`, fractions in Python's `repr` form.
pub(super) fn table_csv(doc: &Comparison) -> String {
    const HEAD: [&str; 23] = [
        "goal",
        "method",
        "solved",
        "fu_count",
        "height",
        "success",
        "leaf_inputs",
        "expanded",
        "peak_frontier",
        "seconds",
        "error",
        "solved_count",
        "goals",
        "seconds_total",
        "level",
        "objective",
        "bound",
        "proven",
        "gap",
        "max_human",
        "split_success",
        "fixed_tree_success",
        "proven_count",
    ];
    let mut out = String::new();
    let mut push = |fields: &[String]| {
        let line: Vec<String> = fields.iter().map(|f| csv_field(f)).collect();
        out.push_str(&line.join(","));
        out.push_str("\r\n");
    };
    push(&HEAD.map(str::to_owned));
    for r in &doc.rows {
        push(&[
            r.goal.clone(),
            r.method.clone(),
            if r.solved { "True" } else { "False" }.to_owned(),
            py_opt(r.fu_count),
            py_opt(r.height),
            py_opt_f64(r.success),
            py_opt(r.leaf_inputs),
            py_opt(r.expanded),
            py_opt(r.peak_frontier),
            py_opt_f64(r.seconds),
            r.error.clone().unwrap_or_default(),
            String::new(),
            String::new(),
            String::new(),
            r.level.to_string(),
            r.objective.unwrap_or_default().to_owned(),
            py_opt_f64(r.bound),
            r.proven
                .map(|p| if p { "True" } else { "False" }.to_owned())
                .unwrap_or_default(),
            py_opt_f64(r.gap),
            py_opt(r.max_human),
            py_opt_f64(r.split_success),
            py_opt_f64(r.fixed_tree_success),
            String::new(),
        ]);
    }
    for s in &doc.summary {
        push(&[
            "(all)".to_owned(),
            s.method.clone(),
            String::new(),
            py_opt_f64(s.fu_count),
            py_opt_f64(s.height),
            py_opt_f64(s.success),
            py_opt_f64(s.leaf_inputs),
            py_opt_f64(s.expanded),
            py_opt_f64(s.peak_frontier),
            String::new(),
            String::new(),
            s.solved_count.to_string(),
            s.goals.to_string(),
            py_float(s.seconds_total),
            String::new(),
            String::new(),
            String::new(),
            String::new(),
            py_opt_f64(s.gap),
            String::new(),
            py_opt_f64(s.split_success),
            py_opt_f64(s.fixed_tree_success),
            py_opt(s.proven_count),
        ]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_read_as_python_writes_them() {
        for (v, s) in [
            (0.0, "0.0"),
            (-0.0, "-0.0"),
            (1.0, "1.0"),
            (123.0, "123.0"),
            (0.5, "0.5"),
            (0.1, "0.1"),
            (0.0001, "0.0001"),
            (0.00001, "1e-05"),
            (1.5e-7, "1.5e-07"),
            (2.345_678e-6, "2.345678e-06"),
            (1e16, "1e+16"),
            (1_234_567_890_123_456.0, "1234567890123456.0"),
            (1.5e300, "1.5e+300"),
            (-0.25, "-0.25"),
            (0.1 + 0.2, "0.30000000000000004"),
            (f64::NAN, "nan"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(py_float(v), s, "{v}");
        }
    }

    #[test]
    fn csv_fields_are_quoted_only_when_needed() {
        assert_eq!(csv_field("onion"), "onion");
        assert_eq!(csv_field("a, b"), "\"a, b\"");
        assert_eq!(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
        assert_eq!(csv_field("two\nlines"), "\"two\nlines\"");
    }

    #[test]
    fn cells_round_half_to_even_as_python_does() {
        assert_eq!(cell_f64(Some(2.25), Cell::Plain), "2.2");
        assert_eq!(cell_f64(Some(0.00125), Cell::Percent), "0.12%");
        assert_eq!(cell_f64(None, Cell::Millis), "-");
        assert_eq!(cell_int(Some(3u32)), "3");
        assert_eq!(cell_int(None::<u32>), "-");
    }

    #[test]
    fn an_empty_comparison_has_no_table_and_a_csv_header() {
        let doc = Comparison::new(Vec::new());
        assert_eq!(table_text(&doc), "");
        assert_eq!(table_csv(&doc).lines().count(), 1);
    }
}
