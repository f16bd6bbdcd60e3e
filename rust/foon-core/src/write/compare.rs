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
        }
    }

    /// The row of a goal that could not be planned.
    pub fn failed(goal: String, method: &str, error: String) -> Self {
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
            error: Some(error),
        }
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
                }
            })
            .collect();
        Self { rows, summary }
    }
}
