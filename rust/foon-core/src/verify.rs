//! Checking a task-tree file: are its units executable in the order written, from the
//! kitchen, and do they make the goal? Are they units of the FOON at all?

use crate::error::Result;
use crate::evaluate::run_in_order;
use crate::index::Foon;
use crate::kitchen::Kitchen;
use crate::model::ObjectSpec;
use crate::prepare::Prepared;

/// The first unit of a tree that cannot run in the order written.
#[derive(Debug, Clone, PartialEq)]
pub struct Blocked {
    /// Position of the unit in the tree (0-based).
    pub position: usize,
    /// Line where the unit starts in the tree file.
    pub line: u32,
    /// Its needed inputs that are neither in the kitchen nor made by an earlier unit.
    pub missing: Vec<ObjectSpec>,
}

/// What `verify_tree` found.
#[derive(Debug, Clone, PartialEq)]
pub struct TreeReport {
    pub units: usize,
    pub first_blocked: Option<Blocked>,
    /// The goal is in the kitchen or made by a unit that could run.
    pub goal_made: bool,
    /// The goal is not even an object of the tree file (nor in the kitchen).
    pub goal_absent: bool,
    /// Positions (with their lines) of tree units that are not units of the FOON.
    pub foreign_units: Vec<(usize, u32)>,
}

impl TreeReport {
    pub fn is_valid(&self) -> bool {
        self.first_blocked.is_none() && self.goal_made
    }
}

/// Checks the units of `tree` (a parsed task-tree file) in their order against `foon`.
pub fn verify_tree(
    foon: &Foon,
    tree: &Foon,
    kitchen: &Kitchen,
    utensils: &[String],
    goal: &ObjectSpec,
) -> Result<TreeReport> {
    let prep = Prepared::with_objects(tree, &kitchen.match_in(tree), utensils, None, None)?;
    let n = tree.fu_count() as u32;
    let units: Vec<u32> = (0..n).collect();
    let (blocked, avail) = run_in_order(tree, &prep, &units);
    let first_blocked = blocked.map(|(position, missing)| Blocked {
        position,
        line: tree.fu_line(position as u32),
        missing: missing
            .iter()
            .map(|&o| ObjectSpec::of_object(tree, o))
            .collect(),
    });
    let goal_id = goal.find_in(tree);
    let in_kitchen = kitchen.contains(goal);
    let goal_made = in_kitchen || goal_id.is_some_and(|g| avail[g as usize]);
    let foreign_units = (0..n)
        .filter(|&f| !has_unit(foon, tree, f))
        .map(|f| (f as usize, tree.fu_line(f)))
        .collect();
    Ok(TreeReport {
        units: n as usize,
        first_blocked,
        goal_made,
        goal_absent: goal_id.is_none() && !in_kitchen,
        foreign_units,
    })
}

/// Whether unit `f` of `tree` is a unit of `foon`: one with the same identity (motion,
/// multiset of inputs, multiset of outputs), found by that identity.
fn has_unit(foon: &Foon, tree: &Foon, f: u32) -> bool {
    let map = |objs: &[u32]| -> Option<Vec<u32>> {
        objs.iter()
            .map(|&o| ObjectSpec::of_object(tree, o).find_in(foon))
            .collect()
    };
    let (Some(ins), Some(outs)) = (map(tree.inputs(f)), map(tree.outputs(f))) else {
        return false;
    };
    let Some(motion) = foon.strings().get(tree.motion_text(f)) else {
        return false;
    };
    foon.find_fu(motion, &ins, &outs).is_some()
}
