//! `foon explain`: why a goal can or cannot be made from a kitchen, as a person needs it.
//!
//! Built on what the sound searches prepare once per kitchen: the ranks (derivability from
//! the kitchen K), the shopping costs of failure explanations (the `optimal-inputs` tree from
//! K' = K plus every object without a producer) and the blocking cycle of
//! [`Explanation`](crate::search::Explanation). The exact rules are in `docs/METHODS.md`
//! ("Explaining a goal").

use std::fmt::Write as _;

use crate::error::Result;
use crate::search::{Compat, Context, Plan, Query};
use crate::write::object_line;

/// How many objects of a blocking cycle are tried as a way to unblock it.
pub const MAX_UNBLOCK_TRIES: usize = 16;

/// Where the goal stands with the kitchen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// The goal is a kitchen object: nothing to do.
    InKitchen,
    /// A task tree makes it from the kitchen.
    Derivable,
    /// No task tree makes it from the kitchen.
    Blocked,
}

impl Status {
    pub fn as_str(self) -> &'static str {
        match self {
            Self::InKitchen => "in-kitchen",
            Self::Derivable => "derivable",
            Self::Blocked => "blocked",
        }
    }
}

/// Why one needed input of a producer of the goal cannot be made from the kitchen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BlockKind {
    /// A raw item (no unit produces it) that is not in the kitchen.
    Missing,
    /// Not derivable even with every raw item (K'), and it needs the goal itself: the goal
    /// or an object from which the goal is reached through producers and needed inputs that
    /// are not derivable from K'.
    Cycle,
    /// Not derivable from the kitchen for another reason: it needs missing raw items (then
    /// `buyable`), or a cycle that does not go through the goal.
    NotDerivable,
}

impl BlockKind {
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Missing => "missing",
            Self::Cycle => "cycle",
            Self::NotDerivable => "not-derivable",
        }
    }
}

/// One needed input that blocks a producer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Blocker {
    pub object: u32,
    pub kind: BlockKind,
    /// Derivable from K' (buying raw items would make it).
    pub buyable: bool,
}

/// A producer of the goal and its needed inputs that are not derivable from the kitchen (in
/// input order, each once).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ProducerBlock {
    pub unit: u32,
    pub blockers: Vec<Blocker>,
}

/// An object of the blocking cycle whose addition to the kitchen unblocks the goal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Unblock {
    pub object: u32,
    /// Adding it alone makes the goal derivable; otherwise it does so together with every
    /// raw item (the goal is then derivable from K' plus it, and a shopping list exists).
    pub alone: bool,
}

/// The explanation of one goal.
#[derive(Debug, Clone, PartialEq)]
pub struct Explain {
    pub goal: u32,
    pub status: Status,
    /// Rank from the kitchen (`None` when blocked).
    pub rank: Option<u32>,
    /// The best tree for the query (in the kitchen or derivable).
    pub plan: Option<Plan>,
    /// Blocked: whether the goal is derivable from K'.
    pub buyable: bool,
    /// Blocked and buyable: the raw items outside the kitchen of the `optimal-inputs` tree
    /// from K' (ids, in id order). Adding them to the kitchen makes the goal derivable.
    pub shopping: Vec<u32>,
    /// Blocked: every producer of the goal, in file order, with what blocks it.
    pub producers: Vec<ProducerBlock>,
    /// Blocked and not buyable: the blocking cycle reached from the goal by following first
    /// producers and their first needed input not derivable from K' (`cycle[i]` is made by
    /// `cycle_units[i]`, which needs `cycle[i + 1]`; the last object repeats an earlier one).
    pub cycle: Vec<u32>,
    pub cycle_units: Vec<u32>,
    /// Blocked and not buyable: the objects whose addition to the kitchen unblocks the goal,
    /// among the first [`MAX_UNBLOCK_TRIES`] of: the blocking inputs of the goal's producers
    /// that are not derivable from K' (producers in file order, inputs in input order), then
    /// the objects of the blocking cycle, in cycle order (each once, never the goal).
    pub unblock: Vec<Unblock>,
}

/// Explains `goal` with the context's kitchen; `query` names the objective of the best tree
/// (a sound method).
pub fn explain(ctx: &Context<'_>, goal: u32, query: Query) -> Result<Explain> {
    let foon = ctx.foon;
    let query = Query {
        compat: Compat::Sound,
        ..query
    };
    let plan = ctx.plan(goal, query)?;
    let mut e = Explain {
        goal,
        status: Status::Derivable,
        rank: ctx.ranks().rank(goal),
        plan: None,
        buyable: false,
        shopping: Vec::new(),
        producers: Vec::new(),
        cycle: Vec::new(),
        cycle_units: Vec::new(),
        unblock: Vec::new(),
    };
    if ctx.in_kitchen(goal) {
        e.status = Status::InKitchen;
        e.plan = Some(plan);
        return Ok(e);
    }
    if e.rank.is_some() {
        e.plan = Some(plan);
        return Ok(e);
    }
    e.status = Status::Blocked;
    let n = foon.object_count();
    let raw: Vec<bool> = (0..n as u32)
        .map(|o| foon.producers(o).is_empty())
        .collect();
    let with_raw = ctx.ranks_with(foon, &raw);
    let from_k2 = |o: u32| with_raw.is_derivable(o);
    e.buyable = from_k2(goal);
    let expl = plan.explanation.unwrap_or_default();
    if e.buyable {
        e.shopping = expl.missing;
    } else {
        e.cycle = expl.cycle;
        e.cycle_units = expl.cycle_units;
    }
    // The objects not derivable from K' that need the goal: those from which the goal is
    // reached through producers and their needed inputs not derivable from K' (a search
    // from the goal to the outputs of the units that need it).
    let mut reach = vec![false; n];
    let mut stack = Vec::new();
    if !from_k2(goal) {
        reach[goal as usize] = true;
        stack.push(goal);
    }
    while let Some(y) = stack.pop() {
        for &f in ctx.needed_by(y) {
            for &z in foon.outputs(f) {
                if !foon.is_bare(z) && !from_k2(z) && !reach[z as usize] {
                    reach[z as usize] = true;
                    stack.push(z);
                }
            }
        }
    }
    let ranks = ctx.ranks();
    for &f in foon.producers(goal) {
        let mut blockers: Vec<Blocker> = Vec::new();
        for &x in ctx.needed(f) {
            if ranks.is_derivable(x) || blockers.iter().any(|b| b.object == x) {
                continue;
            }
            let kind = if raw[x as usize] {
                BlockKind::Missing
            } else if !from_k2(x) && reach[x as usize] {
                BlockKind::Cycle
            } else {
                BlockKind::NotDerivable
            };
            blockers.push(Blocker {
                object: x,
                kind,
                buyable: from_k2(x),
            });
        }
        e.producers.push(ProducerBlock { unit: f, blockers });
    }
    // Candidates: the inputs of the goal's producers that only cycles block (not derivable
    // from K'), then the objects of the blocking cycle.
    let mut cands: Vec<u32> = e
        .producers
        .iter()
        .flat_map(|p| p.blockers.iter())
        .filter(|b| b.kind != BlockKind::Missing && !b.buyable)
        .map(|b| b.object)
        .collect();
    cands.extend(e.cycle.iter().copied());
    let mut tried: Vec<u32> = Vec::new();
    for &c in &cands {
        if c == goal || tried.contains(&c) || tried.len() >= MAX_UNBLOCK_TRIES {
            continue;
        }
        tried.push(c);
        let mut extra = vec![false; n];
        extra[c as usize] = true;
        if ctx.ranks_with(foon, &extra).is_derivable(goal) {
            e.unblock.push(Unblock {
                object: c,
                alone: true,
            });
            continue;
        }
        let mut extra = raw.clone();
        extra[c as usize] = true;
        if ctx.ranks_with(foon, &extra).is_derivable(goal) {
            e.unblock.push(Unblock {
                object: c,
                alone: false,
            });
        }
    }
    Ok(e)
}

impl Explain {
    /// The explanation for people, several lines, each ending with a newline.
    pub fn text(&self, ctx: &Context<'_>) -> String {
        let foon = ctx.foon;
        let obj = |o: u32| object_line(foon, o);
        let unit = |f: u32| {
            format!(
                "unit {f} (line {}): {}",
                foon.fu_line(f),
                foon.motion_text(f)
            )
        };
        let mut s = String::new();
        let _ = writeln!(s, "goal: {}", obj(self.goal));
        match self.status {
            Status::InKitchen => {
                let _ = writeln!(s, "in the kitchen: nothing to do");
            }
            Status::Derivable => {
                let _ = write!(
                    s,
                    "derivable from the kitchen, rank {}",
                    self.rank.unwrap_or(0)
                );
                if let Some(p) = &self.plan {
                    let _ = write!(
                        s,
                        "; best {} tree: {} units",
                        p.query.method.as_str(),
                        p.units.len()
                    );
                    if let Some(h) = p.height {
                        let _ = write!(s, ", height {h}");
                    }
                    if let Some(x) = p.success {
                        let _ = write!(s, ", success {x:.6}");
                    }
                    if let Some(c) = p.cost {
                        let _ = write!(s, ", cost {c}");
                    }
                }
                s.push('\n');
            }
            Status::Blocked => {
                s.push_str("not derivable from the kitchen\n");
                if self.buyable {
                    let _ = writeln!(
                        s,
                        "shopping list ({} raw items outside the kitchen of the optimal-inputs \
                         tree from the kitchen plus every raw item):",
                        self.shopping.len()
                    );
                    for &o in &self.shopping {
                        let _ = writeln!(s, "  - {}", obj(o));
                    }
                } else {
                    s.push_str(
                        "no shopping list: the goal cannot be made even with every raw item\n",
                    );
                }
                if self.producers.is_empty() {
                    s.push_str("no unit produces the goal: it is a raw item\n");
                } else {
                    let _ = writeln!(s, "producers ({}):", self.producers.len());
                }
                for p in &self.producers {
                    let _ = writeln!(s, "  {}", unit(p.unit));
                    for b in &p.blockers {
                        let why = match (b.kind, b.buyable) {
                            (BlockKind::Missing, _) => "missing from the kitchen (a raw item)",
                            (BlockKind::Cycle, _) => "on a cycle through the goal",
                            (BlockKind::NotDerivable, true) => {
                                "not derivable: it needs raw items outside the kitchen"
                            }
                            (BlockKind::NotDerivable, false) => {
                                "not derivable: a cycle that does not go through the goal"
                            }
                        };
                        let _ = writeln!(s, "    needs {}: {why}", obj(b.object));
                    }
                }
                if !self.cycle.is_empty() {
                    let _ = writeln!(s, "blocking cycle: {}", self.chain(ctx));
                    if self.unblock.is_empty() {
                        s.push_str("no single object tried unblocks the goal\n");
                    }
                    for u in &self.unblock {
                        let how = if u.alone {
                            "unblocks the goal"
                        } else {
                            "unblocks the goal together with raw items (then explain again \
                             for the shopping list)"
                        };
                        let _ = writeln!(s, "  adding {} {how}", obj(u.object));
                    }
                }
            }
        }
        s
    }

    /// The blocking cycle as a chain in the direction things are made:
    /// `A --[unit 12: mix]--> B --[unit 3: pour]--> A`.
    pub fn chain(&self, ctx: &Context<'_>) -> String {
        let foon = ctx.foon;
        let mut s = String::new();
        let Some(&last) = self.cycle.last() else {
            return s;
        };
        s.push_str(&object_line(foon, last));
        for i in (0..self.cycle_units.len()).rev() {
            let f = self.cycle_units[i];
            let _ = write!(
                s,
                " --[unit {f}: {}]--> {}",
                foon.motion_text(f),
                object_line(foon, self.cycle[i])
            );
        }
        s
    }
}
