//! What the writers write: a task tree with everything its formats need ([`TreeDoc`]), and
//! a FOON or a part of it ([`FoonDoc`]).

use crate::index::{Foon, NONE};
use crate::prepare::Prepared;
use crate::search::Plan;

/// A task tree with what every writer needs: the FOON it came from, the planning inputs it
/// was made with (kitchen, utensils, rates) and the plan (goal, units, figures).
pub struct TreeDoc<'a> {
    pub foon: &'a Foon,
    pub prep: &'a Prepared,
    pub plan: &'a Plan,
}

impl<'a> TreeDoc<'a> {
    pub fn new(foon: &'a Foon, prep: &'a Prepared, plan: &'a Plan) -> Self {
        Self { foon, prep, plan }
    }

    pub fn goal(&self) -> u32 {
        self.plan.goal
    }

    pub fn units(&self) -> &[u32] {
        &self.plan.units
    }

    /// The success rate the tree used for `fu`'s motion (`None` without one).
    pub fn rate(&self, fu: u32) -> Option<f64> {
        let r = self.prep.fu_rates()[fu as usize];
        (!r.is_nan()).then_some(r)
    }

    /// Needed inputs of `fu` (the container rule applied).
    pub fn needed(&self, fu: u32) -> &[u32] {
        self.prep.needed(fu)
    }

    /// The kitchen items the tree uses as leaves: needed inputs of its units that are in the
    /// kitchen, in order of first use (execution order, then input order); the goal itself
    /// when it is in the kitchen and the tree is empty.
    pub fn leaves(&self) -> Vec<u32> {
        let mut seen = rustc_hash::FxHashSet::default();
        let mut out = Vec::new();
        for &f in &self.plan.units {
            for &o in self.prep.needed(f) {
                if self.prep.in_kitchen(o) && seen.insert(o) {
                    out.push(o);
                }
            }
        }
        if out.is_empty() && self.plan.units.is_empty() && self.prep.in_kitchen(self.plan.goal) {
            out.push(self.plan.goal);
        }
        out
    }

    /// Whether object `o` is a kitchen item.
    pub fn in_kitchen(&self, o: u32) -> bool {
        self.prep.in_kitchen(o)
    }
}

/// A FOON, or the part of it made of some of its units, with an optional object in focus
/// (drawn as the goal) and optional planning inputs (kitchen items marked; PDDL's initial
/// state).
pub struct FoonDoc<'a> {
    pub foon: &'a Foon,
    /// The units to write, in FOON order; `None` for all.
    pub units: Option<Vec<u32>>,
    /// The object shown as the goal.
    pub focus: Option<u32>,
    pub prep: Option<&'a Prepared>,
}

impl<'a> FoonDoc<'a> {
    /// The whole FOON.
    pub fn whole(foon: &'a Foon) -> Self {
        Self {
            foon,
            units: None,
            focus: None,
            prep: None,
        }
    }

    /// The units within `depth` steps of `focus` (a step goes from an object to a unit that
    /// makes or uses it, and on to that unit's other objects); `depth` 0 selects the units
    /// that make or use `focus`.
    pub fn around(foon: &'a Foon, focus: u32, depth: u32) -> Self {
        Self {
            foon,
            units: Some(neighbourhood(foon, focus, depth)),
            focus: Some(focus),
            prep: None,
        }
    }

    /// The units written, in FOON order.
    pub fn units(&self) -> Vec<u32> {
        match &self.units {
            Some(u) => u.clone(),
            None => (0..self.foon.fu_count() as u32).collect(),
        }
    }

    /// Whether object `o` is a kitchen item (false without planning inputs).
    pub fn in_kitchen(&self, o: u32) -> bool {
        self.prep.is_some_and(|p| p.in_kitchen(o))
    }
}

/// The units within `depth` steps of `focus`, in FOON order (breadth-first over the
/// object–unit graph, both directions).
pub fn neighbourhood(foon: &Foon, focus: u32, depth: u32) -> Vec<u32> {
    if focus == NONE || focus as usize >= foon.object_count() {
        return Vec::new();
    }
    let mut fu_seen = vec![false; foon.fu_count()];
    let mut obj_seen = vec![false; foon.object_count()];
    obj_seen[focus as usize] = true;
    let mut frontier = vec![focus];
    for level in 0..=depth {
        let mut next = Vec::new();
        for &o in &frontier {
            for &f in foon.producers(o).iter().chain(foon.consumers(o)) {
                if fu_seen[f as usize] {
                    continue;
                }
                fu_seen[f as usize] = true;
                if level < depth {
                    for &x in foon.inputs(f).iter().chain(foon.outputs(f)) {
                        if !obj_seen[x as usize] {
                            obj_seen[x as usize] = true;
                            next.push(x);
                        }
                    }
                }
            }
        }
        frontier = next;
    }
    (0..foon.fu_count() as u32)
        .filter(|&f| fu_seen[f as usize])
        .collect()
}
