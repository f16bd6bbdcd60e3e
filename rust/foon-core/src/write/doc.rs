//! What the writers write: a task tree with everything its formats need ([`TreeDoc`]), and
//! a FOON or a part of it ([`FoonDoc`]).

use crate::error::{Error, Result};
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

    /// The units within `depth` steps of `focus` (see [`neighbourhood`]), `focus` drawn as
    /// the goal. An object id out of range gives a document that [`check`](Self::check)
    /// (and so every writer) refuses.
    pub fn around(foon: &'a Foon, focus: u32, depth: u32) -> Self {
        Self {
            foon,
            units: Some(neighbourhood(foon, focus, depth).unwrap_or_default()),
            focus: Some(focus),
            prep: None,
        }
    }

    /// The same as [`around`](Self::around), with an out-of-range object id as an error.
    pub fn try_around(foon: &'a Foon, focus: u32, depth: u32) -> Result<Self> {
        let units = neighbourhood(foon, focus, depth)?;
        Ok(Self {
            foon,
            units: Some(units),
            focus: Some(focus),
            prep: None,
        })
    }

    /// Checks that the object in focus and the units are in the FOON (writers call this
    /// first, so a bad id is an error, never an empty or partial picture).
    pub fn check(&self) -> Result<()> {
        if let Some(o) = self.focus {
            check_object(self.foon, o)?;
        }
        if let Some(units) = &self.units {
            let n = self.foon.fu_count();
            if let Some(&u) = units.iter().find(|&&u| u as usize >= n) {
                return Err(Error::Invalid(format!(
                    "unit {u} is out of range (the FOON has {n} units)"
                )));
            }
        }
        Ok(())
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

fn check_object(foon: &Foon, o: u32) -> Result<()> {
    let n = foon.object_count();
    if o == NONE || o as usize >= n {
        return Err(Error::Invalid(format!(
            "object {o} is out of range (the FOON has {n} objects)"
        )));
    }
    Ok(())
}

/// The units within `depth` steps of the object `focus`, in FOON order: breadth-first over
/// the object–unit graph in both directions, a step going from an object to a unit that
/// makes or uses it (has it as an output or an input). Depth 0 selects the units that make or use `focus`; depth `d + 1` adds
/// the units that make or use any object of a unit selected at depth `d`. An object id out
/// of range is an error.
pub fn neighbourhood(foon: &Foon, focus: u32, depth: u32) -> Result<Vec<u32>> {
    check_object(foon, focus)?;
    // Where each object appears (as an input or an output), unit by unit. Not the FOON's
    // producer lists: they leave out units whose output has no state, ingredient or
    // container (the course rule), which still make that object in the picture.
    let (n_obj, n_fu) = (foon.object_count(), foon.fu_count());
    let mut start = vec![0u32; n_obj + 1];
    let objects_of = |f: u32| foon.inputs(f).iter().chain(foon.outputs(f)).copied();
    for f in 0..n_fu as u32 {
        for o in objects_of(f) {
            start[o as usize + 1] += 1;
        }
    }
    for i in 0..n_obj {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut appears = vec![0u32; start[n_obj] as usize];
    for f in 0..n_fu as u32 {
        for o in objects_of(f) {
            appears[fill[o as usize] as usize] = f;
            fill[o as usize] += 1;
        }
    }
    let mut fu_seen = vec![false; n_fu];
    let mut obj_seen = vec![false; n_obj];
    obj_seen[focus as usize] = true;
    let mut frontier = vec![focus];
    for level in 0..=depth {
        if frontier.is_empty() {
            break;
        }
        let mut next = Vec::new();
        for &o in &frontier {
            let row = &appears[start[o as usize] as usize..start[o as usize + 1] as usize];
            for &f in row {
                if fu_seen[f as usize] {
                    continue;
                }
                fu_seen[f as usize] = true;
                if level < depth {
                    for x in objects_of(f) {
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
    Ok((0..foon.fu_count() as u32)
        .filter(|&f| fu_seen[f as usize])
        .collect())
}
