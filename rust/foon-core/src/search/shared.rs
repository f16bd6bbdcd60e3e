//! `optimal-shared`: the valid tree with the fewest distinct FUs (or, with the success
//! objective, the highest product of rates over its distinct FUs), by branch and bound over
//! acyclic choice closures, with Knuth's max-cost (`h_max`, the FUs already chosen counted free)
//! as the admissible bound and the best optimal tree as the first incumbent. The exact
//! definitions are in `docs/METHODS.md` ("Fewest distinct units").

use std::collections::BinaryHeap;
use std::time::Instant;

use super::optimal::Entry;
use super::scratch::IdMap;
use super::{Context, Explanation, Method, Plan, Query, optimal, tree};
use crate::error::{Error, Result};
use crate::index::NONE;

/// What `optimal-shared` minimises over the distinct FUs of a tree.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum SharedObjective {
    /// The number of distinct FUs.
    #[default]
    Units,
    /// `-ln` of the product of the motion rates of the distinct FUs (the highest success).
    Success,
}

impl SharedObjective {
    /// The name results and options use (`"units"` or `"success"`).
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Units => "units",
            Self::Success => "success",
        }
    }
}

impl std::str::FromStr for SharedObjective {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "units" => Ok(Self::Units),
            "success" => Ok(Self::Success),
            _ => Err(Error::Invalid(format!(
                "unknown objective '{s}' (choose from units, success)"
            ))),
        }
    }
}

/// Options of `optimal-shared`: the objective and when to stop early (the best tree found so
/// far is returned, with its proven bound). A node limit gives the same result on every run;
/// a time limit does not.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SharedOptions {
    pub objective: SharedObjective,
    /// Stop after this many search nodes (choices tried).
    pub node_limit: Option<u64>,
    /// Stop after this many seconds.
    pub time_limit: Option<f64>,
}

impl SharedOptions {
    /// Checks the limits (a time limit must be a non-negative number).
    pub fn check(&self) -> Result<()> {
        self.check_for(Method::OptimalShared)
    }

    /// Checks the limits, and that options other than the defaults are given only to
    /// `optimal-shared` (another method would ignore them).
    pub fn check_for(&self, method: Method) -> Result<()> {
        if method != Method::OptimalShared && *self != Self::default() {
            return Err(Error::Invalid(format!(
                "the objective, node limit and time limit are options of optimal-shared, not of {}",
                method.as_str()
            )));
        }
        match self.time_limit {
            Some(t) if t.is_nan() || t < 0.0 => Err(Error::Invalid(format!(
                "the time limit is {t}, not a number of seconds >= 0"
            ))),
            _ => Ok(()),
        }
    }
}

/// The goal's ancestry with local ids: the objects outside the kitchen from which the goal
/// can be reached backwards, and their producers whose needed inputs are all derivable and
/// whose weight is finite (no other FU can be in a tree of finite cost).
struct Local {
    obj: Vec<u32>,
    fu: Vec<u32>,
    w: Vec<f64>,
    /// Needed inputs outside the kitchen (local objects), each once, in input order.
    needed: Vec<Vec<u32>>,
    /// Produced outputs that are local objects.
    outputs: Vec<Vec<u32>>,
    producers: Vec<Vec<u32>>,
    needed_by: Vec<Vec<u32>>,
}

fn local(ctx: &Context<'_>, goal: u32, weight: &dyn Fn(u32) -> Result<f64>) -> Result<Local> {
    let foon = ctx.foon;
    let ranks = ctx.ranks();
    let mut id: IdMap<u32> = ctx.id_map(foon.object_count(), NONE);
    let mut fu_id: IdMap<u32> = ctx.id_map(foon.fu_count(), NONE);
    let mut l = Local {
        obj: vec![goal],
        fu: Vec::new(),
        w: Vec::new(),
        needed: Vec::new(),
        outputs: Vec::new(),
        producers: vec![Vec::new()],
        needed_by: vec![Vec::new()],
    };
    id.set(goal, 0);
    let mut next = 0;
    while next < l.obj.len() {
        let o = l.obj[next];
        let lo = next as u32;
        next += 1;
        if next % 4096 == 0 {
            ctx.check_stop()?;
        }
        for &f in foon.producers(o) {
            let known = fu_id.get(f);
            if known != NONE {
                if known != u32::MAX - 1 {
                    l.producers[lo as usize].push(known);
                }
                continue;
            }
            let ins = ctx.needed(f);
            if ins.iter().any(|&x| ranks.rank(x).is_none()) {
                fu_id.set(f, u32::MAX - 1);
                continue;
            }
            let w = weight(f)?;
            if !w.is_finite() {
                fu_id.set(f, u32::MAX - 1);
                continue;
            }
            let lf = l.fu.len() as u32;
            fu_id.set(f, lf);
            l.fu.push(f);
            l.w.push(w);
            let mut needed = Vec::new();
            for &x in ins {
                if ctx.in_kitchen(x) {
                    continue;
                }
                let mut lx = id.get(x);
                if lx == NONE {
                    lx = l.obj.len() as u32;
                    id.set(x, lx);
                    l.obj.push(x);
                    l.producers.push(Vec::new());
                    l.needed_by.push(Vec::new());
                }
                if !needed.contains(&lx) {
                    needed.push(lx);
                    l.needed_by[lx as usize].push(lf);
                }
            }
            l.needed.push(needed);
            l.producers[lo as usize].push(lf);
        }
    }
    for &f in &l.fu {
        let outs = foon
            .outputs(f)
            .iter()
            .filter(|&&y| !foon.is_bare(y) && !ctx.in_kitchen(y))
            .map(|&y| id.get(y))
            .filter(|&y| y != NONE)
            .collect::<Vec<u32>>();
        let mut outs_once = Vec::new();
        for y in outs {
            if !outs_once.contains(&y) {
                outs_once.push(y);
            }
        }
        l.outputs.push(outs_once);
    }
    Ok(l)
}

/// `h_max` over the local graph with the FUs of `free` weighing 0: cost(o) = min over producers
/// of w(f) + the largest cost of f's needed inputs (0 for none). With `open`, it stops as soon
/// as every open object is final, returning the largest of their costs, or as soon as the
/// next cost to finalise is >= `limit`, returning infinity (some open object costs that much).
struct Hmax {
    h: Vec<f64>,
    left: Vec<u32>,
    done: Vec<bool>,
    heap: BinaryHeap<Entry>,
}

impl Hmax {
    fn new(l: &Local) -> Self {
        Self {
            h: vec![f64::INFINITY; l.obj.len()],
            left: vec![0; l.fu.len()],
            done: vec![false; l.obj.len()],
            heap: BinaryHeap::new(),
        }
    }

    fn run(
        &mut self,
        l: &Local,
        free: &dyn Fn(u32) -> bool,
        open: Option<(&[u32], &[bool])>,
        limit: f64,
    ) -> f64 {
        self.h.fill(f64::INFINITY);
        self.done.fill(false);
        self.heap.clear();
        let w = |f: u32| if free(f) { 0.0 } else { l.w[f as usize] };
        let mut to_go = open.map_or(usize::MAX, |(o, _)| o.len());
        let mut worst = 0.0f64;
        for (f, ins) in l.needed.iter().enumerate() {
            self.left[f] = ins.len() as u32;
        }
        let fire = |f: u32, base: f64, h: &mut Vec<f64>, heap: &mut BinaryHeap<Entry>| {
            let c = w(f) + base;
            for &y in &l.outputs[f as usize] {
                if c < h[y as usize] {
                    h[y as usize] = c;
                    heap.push(Entry {
                        cost: c,
                        depth: 0,
                        obj: y,
                    });
                }
            }
        };
        for f in 0..l.fu.len() as u32 {
            if self.left[f as usize] == 0 {
                fire(f, 0.0, &mut self.h, &mut self.heap);
            }
        }
        while let Some(Entry {
            cost: c, obj: o, ..
        }) = self.heap.pop()
        {
            if self.done[o as usize] || c > self.h[o as usize] {
                continue;
            }
            if c >= limit {
                return f64::INFINITY;
            }
            self.done[o as usize] = true;
            if let Some((_, is_open)) = open
                && is_open[o as usize]
            {
                worst = worst.max(c);
                to_go -= 1;
                if to_go == 0 {
                    return worst;
                }
            }
            for &f in &l.needed_by[o as usize] {
                let left = &mut self.left[f as usize];
                *left -= 1;
                if *left == 0 {
                    // The last needed input to become final has the largest cost.
                    fire(f, c, &mut self.h, &mut self.heap);
                }
            }
        }
        if open.is_some() { f64::INFINITY } else { worst }
    }
}

/// One resolution applied: the object, its FU, whether the FU was new, and where its newly
/// opened inputs start on the trail.
#[derive(Clone, Copy)]
struct Applied {
    o: u32,
    /// Where `o` was in the open list (restored there, so that undoing restores the list).
    at: usize,
    f: u32,
    new: bool,
    trail: usize,
}

struct Frame {
    o: u32,
    cands: Vec<u32>,
    next: usize,
    lb: f64,
    applied: Option<Applied>,
}

struct Search<'l> {
    l: &'l Local,
    /// Static `h_max` (nothing free): the order of open objects and candidates.
    h0: Vec<f64>,
    choice: Vec<u32>,
    uses: Vec<u32>,
    cost: f64,
    open: Vec<u32>,
    is_open: Vec<bool>,
    trail: Vec<u32>,
    hmax: Hmax,
    mark: Vec<u32>,
    stamp: u32,
    fu_mark: Vec<u32>,
    fu_stamp: u32,
    incumbent: f64,
    best: Option<Vec<u32>>,
}

impl Search<'_> {
    /// Whether `x` reaches `o` through the choices made (x's chosen FU's needed inputs, ...).
    fn reaches(&mut self, x: u32, o: u32) -> bool {
        self.stamp += 1;
        let stamp = self.stamp;
        let mut stack = vec![x];
        while let Some(y) = stack.pop() {
            if y == o {
                return true;
            }
            if self.mark[y as usize] == stamp {
                continue;
            }
            self.mark[y as usize] = stamp;
            let f = self.choice[y as usize];
            if f != NONE {
                stack.extend_from_slice(&self.l.needed[f as usize]);
            }
        }
        false
    }

    /// A second admissible bound on what the open objects still cost: open objects that no
    /// chosen FU makes, greedily taken (in open order) when none of their producers makes an
    /// object taken before; each needs its own new FU, so their cheapest producers' weights
    /// add up.
    fn packing(&mut self) -> f64 {
        self.fu_stamp += 1;
        let stamp = self.fu_stamp;
        let l = self.l;
        let mut total = 0.0;
        for &o in &self.open {
            let ps = &l.producers[o as usize];
            if ps
                .iter()
                .any(|&f| self.uses[f as usize] > 0 || self.fu_mark[f as usize] == stamp)
            {
                continue;
            }
            let mut cheapest = f64::INFINITY;
            for &f in ps {
                self.fu_mark[f as usize] = stamp;
                cheapest = cheapest.min(l.w[f as usize]);
            }
            total += cheapest;
        }
        total
    }

    fn apply(&mut self, o: u32, f: u32) -> Applied {
        let at = self.open.iter().position(|&x| x == o).unwrap_or(0);
        self.open.remove(at);
        self.is_open[o as usize] = false;
        self.choice[o as usize] = f;
        let trail = self.trail.len();
        self.uses[f as usize] += 1;
        let new = self.uses[f as usize] == 1;
        if new {
            self.cost += self.l.w[f as usize];
            for &x in &self.l.needed[f as usize] {
                if self.choice[x as usize] == NONE && !self.is_open[x as usize] {
                    self.is_open[x as usize] = true;
                    self.open.push(x);
                    self.trail.push(x);
                }
            }
        }
        Applied {
            o,
            at,
            f,
            new,
            trail,
        }
    }

    fn undo(&mut self, a: Applied) {
        for &x in &self.trail[a.trail..] {
            self.is_open[x as usize] = false;
        }
        let opened = self.trail.len() - a.trail;
        self.open.truncate(self.open.len() - opened);
        self.trail.truncate(a.trail);
        if a.new {
            self.cost -= self.l.w[a.f as usize];
        }
        self.uses[a.f as usize] -= 1;
        self.choice[a.o as usize] = NONE;
        self.is_open[a.o as usize] = true;
        self.open.insert(a.at, a.o);
    }

    /// Evaluates the current state: records it when it is a better complete tree, and returns
    /// the frame of its children when its bound leaves room for a better one.
    fn expand(&mut self) -> Option<Frame> {
        if self.open.is_empty() {
            if self.cost < self.incumbent {
                self.incumbent = self.cost;
                self.best = Some(self.choice.clone());
            }
            return None;
        }
        let limit = self.incumbent - self.cost;
        let uses = &self.uses;
        let h = self.hmax.run(
            self.l,
            &|f| uses[f as usize] > 0,
            Some((&self.open, &self.is_open)),
            limit,
        );
        let lb = self.cost + h.max(self.packing());
        if lb >= self.incumbent {
            return None;
        }
        // The open object with the largest static cost (ties: lowest local id).
        let o = self
            .open
            .iter()
            .copied()
            .max_by(|&a, &b| {
                self.h0[a as usize]
                    .total_cmp(&self.h0[b as usize])
                    .then(b.cmp(&a))
            })
            .unwrap_or(0);
        let l = self.l;
        let mut cands: Vec<(bool, f64, u32, u32)> = Vec::new();
        for &f in &l.producers[o as usize] {
            let ins = &l.needed[f as usize];
            if ins.contains(&o) {
                continue;
            }
            let mut cyclic = false;
            for &x in ins {
                if self.choice[x as usize] != NONE && self.reaches(x, o) {
                    cyclic = true;
                    break;
                }
            }
            if cyclic {
                continue;
            }
            let reuse = self.uses[f as usize] > 0;
            let key = if reuse {
                0.0
            } else {
                l.w[f as usize] + ins.iter().map(|&x| self.h0[x as usize]).fold(0.0, f64::max)
            };
            cands.push((!reuse, key, l.fu[f as usize], f));
        }
        cands.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
        Some(Frame {
            o,
            cands: cands.into_iter().map(|c| c.3).collect(),
            next: 0,
            lb,
            applied: None,
        })
    }
}

/// Plans `goal` (derivable, not in the kitchen) with `optimal-shared`.
pub(super) fn plan(ctx: &Context<'_>, goal: u32, query: Query) -> Result<Plan> {
    let start = Instant::now();
    let opts = ctx.shared_options();
    opts.check()?;
    let weight: Box<dyn Fn(u32) -> Result<f64>> = match opts.objective {
        SharedObjective::Units => Box::new(|_| Ok(1.0)),
        // `0.0 - ln r`: a rate of 1 weighs +0 (see `optimal`).
        SharedObjective::Success => Box::new(|f| ctx.rate(f).map(|r| 0.0 - r.ln())),
    };
    // The first incumbent: the best of the optimal trees under this objective.
    let mut first: Option<(f64, Vec<u32>)> = None;
    let methods: &[Method] = match opts.objective {
        SharedObjective::Units => &[Method::OptimalUnits],
        SharedObjective::Success => &[Method::OptimalSuccess, Method::OptimalUnits],
    };
    for &m in methods {
        let p = optimal::plan(
            ctx,
            goal,
            Query {
                method: m,
                ..Query::default()
            },
        )?;
        if !p.solved {
            continue;
        }
        let mut c = 0.0;
        for &f in &p.units {
            c += weight(f)?;
        }
        if first.as_ref().is_none_or(|(b, _)| c < *b) {
            first = Some((c, p.units));
        }
    }
    let l = local(ctx, goal, &*weight)?;
    let mut hmax = Hmax::new(&l);
    hmax.run(&l, &|_| false, None, f64::INFINITY);
    let h0 = hmax.h.clone();
    let root = h0[0];
    let n = l.obj.len();
    let mut s = Search {
        l: &l,
        h0,
        choice: vec![NONE; n],
        uses: vec![0; l.fu.len()],
        cost: 0.0,
        open: vec![0],
        is_open: {
            let mut v = vec![false; n];
            v[0] = true;
            v
        },
        trail: Vec::new(),
        hmax,
        mark: vec![0; n],
        stamp: 0,
        fu_mark: vec![0; l.fu.len()],
        fu_stamp: 0,
        incumbent: first.as_ref().map_or(f64::INFINITY, |(c, _)| *c),
        best: None,
    };
    let mut nodes = 0u64;
    let mut peak = 0usize;
    let mut stopped = false;
    let mut stack: Vec<Frame> = Vec::new();
    if let Some(fr) = s.expand() {
        stack.push(fr);
    }
    while let Some(top) = stack.last_mut() {
        if let Some(a) = top.applied.take() {
            s.undo(a);
        }
        if top.next == top.cands.len() || top.lb >= s.incumbent {
            stack.pop();
            continue;
        }
        if opts.node_limit.is_some_and(|m| nodes >= m) {
            stopped = true;
            break;
        }
        if nodes % 256 == 255 {
            ctx.check_stop()?;
            if opts
                .time_limit
                .is_some_and(|t| start.elapsed().as_secs_f64() >= t)
            {
                stopped = true;
                break;
            }
        }
        let (o, f) = (top.o, top.cands[top.next]);
        top.next += 1;
        top.applied = Some(s.apply(o, f));
        nodes += 1;
        if let Some(fr) = s.expand() {
            stack.push(fr);
            peak = peak.max(stack.len());
        }
    }
    let incumbent = s.incumbent;
    let bound = if stopped {
        stack
            .iter()
            .map(|fr| fr.lb)
            .fold(incumbent, f64::min)
            .max(root.min(incumbent))
    } else {
        incumbent
    };
    let units = match &s.best {
        Some(choice) => {
            let mut global: IdMap<u32> = ctx.id_map(ctx.foon.object_count(), NONE);
            for (o, &f) in choice.iter().enumerate() {
                if f != NONE {
                    global.set(l.obj[o], l.fu[f as usize]);
                }
            }
            tree::emit(ctx, goal, |o| global.get(o))
        }
        None => match first {
            Some((c, units)) if c.is_finite() => units,
            _ => {
                // Every tree uses a motion of rate 0 (see `optimal-success`).
                let mut p = Plan::empty(goal, query);
                p.solved = false;
                p.explanation = Some(Explanation::default());
                p.expanded = nodes;
                return Ok(p);
            }
        },
    };
    let scale = |c: f64| match opts.objective {
        SharedObjective::Units => c,
        SharedObjective::Success => (-c).exp(),
    };
    Ok(Plan {
        units,
        cost: Some(scale(incumbent)),
        bound: Some(scale(bound)),
        proven: Some(!stopped),
        expanded: nodes,
        peak_frontier: peak,
        ..Plan::empty(goal, query)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse::{ParseOptions, parse_foon};
    use crate::{ObjectSpec, index::Foon};

    /// A dish made from `width` parts, each made alone from the kitchen, or all at once by one
    /// unit that needs a base made in two steps: the tree cost prefers the singles (width + 1
    /// units), the fewest distinct units the shared unit (4).
    fn wide(width: usize) -> Foon {
        use std::fmt::Write as _;
        let mut t = String::new();
        let parts: String = (0..width).fold(String::new(), |mut s, i| {
            let _ = write!(s, "O\tpart\nS\tp{i}\n");
            s
        });
        for i in 0..width {
            let _ = write!(t, "O\tnode\nS\tn0\nM\tmix\nO\tpart\nS\tp{i}\n//\n");
        }
        t.push_str("O\tnode\nS\tn0\nM\tmix\nO\tbase\nS\tb1\n//\n");
        t.push_str("O\tbase\nS\tb1\nM\tmix\nO\tbase\nS\tb2\n//\n");
        let _ = write!(t, "O\tbase\nS\tb2\nM\tmix\n{parts}//\n");
        let _ = write!(t, "{parts}M\tmix\nO\tdish\nS\tdone\n//\n");
        parse_foon(t.as_bytes(), None, ParseOptions::default()).unwrap()
    }

    fn plan(foon: &Foon, opts: SharedOptions) -> Plan {
        let kitchen = [ObjectSpec {
            label: "node".into(),
            states: vec!["n0".into()],
            ..Default::default()
        }];
        let ctx = Context::new(foon, &kitchen, &[], None, None)
            .unwrap()
            .with_shared(opts);
        let goal = ctx
            .goal(&ObjectSpec {
                label: "dish".into(),
                states: vec!["done".into()],
                ..Default::default()
            })
            .unwrap();
        let query = Query {
            method: Method::OptimalShared,
            ..Query::default()
        };
        let mut p = ctx.plan(goal, query).unwrap();
        assert!(ctx.is_valid(&p.units, goal));
        p.seconds = 0.0;
        p
    }

    #[test]
    fn a_shared_unit_is_found_and_proven() {
        let foon = wide(6);
        let p = plan(&foon, SharedOptions::default());
        assert_eq!(p.units.len(), 4);
        assert_eq!(
            (p.cost, p.bound, p.proven),
            (Some(4.0), Some(4.0), Some(true))
        );
    }

    #[test]
    fn a_node_limit_is_deterministic_and_keeps_the_bound() {
        let foon = wide(6);
        for limit in 0..12 {
            let opts = SharedOptions {
                node_limit: Some(limit),
                ..SharedOptions::default()
            };
            let (a, b) = (plan(&foon, opts), plan(&foon, opts));
            assert_eq!(a, b);
            let (cost, bound) = (a.cost.unwrap(), a.bound.unwrap());
            assert!(bound <= 4.0 && 4.0 <= cost, "{limit}: {bound} {cost}");
            if a.proven == Some(true) {
                assert!((bound - cost).abs() < 1e-12);
            } else {
                assert_eq!(a.expanded, limit);
            }
        }
    }

    #[test]
    fn bad_options_are_errors() {
        let opts = SharedOptions {
            time_limit: Some(f64::NAN),
            ..SharedOptions::default()
        };
        assert!(opts.check().is_err());
        assert!("fewest".parse::<SharedObjective>().is_err());
        assert_eq!(
            "success".parse::<SharedObjective>().unwrap().as_str(),
            "success"
        );
    }
}
