//! Evaluating a set of FUs against inputs prepared for their FOON: a tree's metrics (height,
//! success, leaf inputs), whether it is valid in some order, and running it in a given order.
//! Used by the searches (the metrics of every plan) and by `verify` (a tree file); the public
//! entry points are the methods of [`Context`](crate::Context) of the same names. Every
//! function takes the FOON and inputs prepared for it.

use rustc_hash::{FxBuildHasher, FxHashMap};

use crate::index::{Foon, NONE};
use crate::prepare::Prepared;

/// Metrics of a tree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TreeMetrics {
    pub height: Option<u32>,
    /// `None` without a rate table or when a unit's motion has no rate (`unrated`).
    pub success: Option<f64>,
    /// With a rate table: the first unit whose motion has no rate.
    pub unrated: Option<u32>,
    pub leaf_inputs: usize,
}

/// A set of units to evaluate, over one id space of objects and units (the whole FOON, or a
/// goal's ancestry in local ids): what the rule of [`shape`] reads.
pub(crate) trait TreeView {
    /// The needed inputs of unit `f`.
    fn needed(&self, f: u32) -> &[u32];
    /// Calls `each` on every object unit `f` makes available: its outputs that are not bare
    /// and not in the kitchen (repeats allowed). Outputs no unit of the view can need may be
    /// left out.
    fn for_made(&self, f: u32, each: impl FnMut(u32));
    fn in_kitchen(&self, o: u32) -> bool;
}

/// Per-object marks of [`shape`] (a rank, and the head of a list of waiting slots), `NONE`
/// when unset; [`Marks::reset`] unsets every mark.
pub(crate) trait Marks {
    fn reset(&mut self);
    fn rank(&self, o: u32) -> u32;
    fn set_rank(&mut self, o: u32, r: u32);
    fn head(&self, o: u32) -> u32;
    fn set_head(&mut self, o: u32, h: u32);
}

/// [`Marks`] in object-indexed arrays, stamped: a reset costs nothing (the arrays are
/// allocated once, for ids below the length given to [`StampedMarks::new`]).
pub(crate) struct StampedMarks {
    epoch: u32,
    stamp: Vec<u32>,
    rank: Vec<u32>,
    head: Vec<u32>,
}

impl StampedMarks {
    pub(crate) fn new(len: usize) -> Self {
        Self {
            epoch: 1,
            stamp: vec![0; len],
            rank: vec![NONE; len],
            head: vec![NONE; len],
        }
    }

    /// Makes the marks of `o` current (unset when they were stamped by an earlier reset).
    #[inline]
    fn touch(&mut self, o: u32) {
        let i = o as usize;
        if self.stamp[i] != self.epoch {
            self.stamp[i] = self.epoch;
            self.rank[i] = NONE;
            self.head[i] = NONE;
        }
    }
}

impl Marks for StampedMarks {
    fn reset(&mut self) {
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.stamp.fill(0);
            self.epoch = 1;
        }
    }
    #[inline]
    fn rank(&self, o: u32) -> u32 {
        if self.stamp[o as usize] == self.epoch {
            self.rank[o as usize]
        } else {
            NONE
        }
    }
    #[inline]
    fn set_rank(&mut self, o: u32, r: u32) {
        self.touch(o);
        self.rank[o as usize] = r;
    }
    #[inline]
    fn head(&self, o: u32) -> u32 {
        if self.stamp[o as usize] == self.epoch {
            self.head[o as usize]
        } else {
            NONE
        }
    }
    #[inline]
    fn set_head(&mut self, o: u32, h: u32) {
        self.touch(o);
        self.head[o as usize] = h;
    }
}

/// [`Marks`] of the objects a small tree touches only, in a hash map.
impl Marks for FxHashMap<u32, (u32, u32)> {
    fn reset(&mut self) {
        self.clear();
    }
    fn rank(&self, o: u32) -> u32 {
        self.get(&o).map_or(NONE, |m| m.0)
    }
    fn set_rank(&mut self, o: u32, r: u32) {
        self.entry(o).or_insert((NONE, NONE)).0 = r;
    }
    fn head(&self, o: u32) -> u32 {
        self.get(&o).map_or(NONE, |m| m.1)
    }
    fn set_head(&mut self, o: u32, h: u32) {
        self.entry(o).or_insert((NONE, NONE)).1 = h;
    }
}

/// Buffers of [`shape`], kept between calls.
#[derive(Default)]
pub(crate) struct ShapeBuf {
    left: Vec<u32>,
    /// Waiting needed slots: (position of the unit in `units`, next slot of the same object).
    slots: Vec<(u32, u32)>,
    queue: Vec<(u32, u32)>,
}

/// The rule of a tree's height and leaf inputs, for the distinct units `units` of `view`:
/// each object the units make from the kitchen has a **rank**, the least fixpoint of one more
/// than the largest rank of the needed inputs of a unit making it (kitchen objects rank 0;
/// breadth first, so the first unit to make an object sets it); the height is the goal's rank
/// (0 in the kitchen, `None` when the units do not make it), and the leaf inputs are the
/// distinct kitchen objects the units need. Afterwards `marks` holds a rank (not `NONE`) for
/// every object made and every kitchen object needed. Time and space linear in the units'
/// needed and made slots (with stamped or hashed marks).
pub(crate) fn shape<V: TreeView, M: Marks>(
    view: &V,
    units: &[u32],
    goal: u32,
    marks: &mut M,
    buf: &mut ShapeBuf,
) -> (Option<u32>, usize) {
    let ShapeBuf { left, slots, queue } = buf;
    marks.reset();
    left.clear();
    left.resize(units.len(), 0);
    slots.clear();
    queue.clear();
    // Room for a few needed slots and made objects per unit from the start.
    slots.reserve(3 * units.len());
    queue.reserve(2 * units.len());
    let mut leaves = 0;
    for (i, &f) in units.iter().enumerate() {
        for &x in view.needed(f) {
            if !view.in_kitchen(x) {
                left[i] += 1;
                slots.push((i as u32, marks.head(x)));
                marks.set_head(x, slots.len() as u32 - 1);
            } else if marks.rank(x) == NONE {
                // Rank 0 marks a kitchen object counted.
                marks.set_rank(x, 0);
                leaves += 1;
            }
        }
    }
    // First in, first out: `queue[next..]` is still to be read.
    let fire = |f: u32, r: u32, marks: &mut M, queue: &mut Vec<(u32, u32)>| {
        view.for_made(f, |y| {
            if marks.rank(y) == NONE {
                marks.set_rank(y, r);
                queue.push((y, r));
            }
        });
    };
    for (i, &f) in units.iter().enumerate() {
        if left[i] == 0 {
            fire(f, 1, marks, queue);
        }
    }
    let mut next = 0;
    while let Some(&(o, r)) = queue.get(next) {
        next += 1;
        let mut slot = marks.head(o);
        while slot != NONE {
            let (i, after) = slots[slot as usize];
            left[i as usize] -= 1;
            if left[i as usize] == 0 {
                // The last needed input to arrive has the largest rank.
                fire(units[i as usize], r + 1, marks, queue);
            }
            slot = after;
        }
    }
    let height = if view.in_kitchen(goal) {
        Some(0)
    } else {
        match marks.rank(goal) {
            NONE => None,
            r => Some(r),
        }
    };
    (height, leaves)
}

/// The success of a tree's units (`units`: global ids, in execution order) and its first unit
/// whose motion has no rate: the product of the rates when a rate table was given and every
/// unit has a rate, else `None`; the unrated unit only with a rate table.
fn rated(prep: &Prepared, units: &[u32]) -> (Option<f64>, Option<u32>) {
    let unrated = if prep.rates_given() {
        units
            .iter()
            .copied()
            .find(|&f| prep.fu_rates().get(f as usize).is_none_or(|r| r.is_nan()))
    } else {
        None
    };
    let success = (prep.rates_given() && unrated.is_none()).then(|| {
        units
            .iter()
            .fold(1.0, |acc, &f| acc * prep.fu_rates()[f as usize])
    });
    (success, unrated)
}

/// The metrics of a tree: [`shape`] over `view` (`local`: the tree's distinct units in the
/// view's ids, `goal` in the view's ids) and [`rated`] of its units (`units`: global ids, in
/// execution order).
pub(crate) fn tree_metrics<V: TreeView, M: Marks>(
    view: &V,
    prep: &Prepared,
    units: &[u32],
    local: &[u32],
    goal: u32,
    marks: &mut M,
    buf: &mut ShapeBuf,
) -> TreeMetrics {
    let (height, leaf_inputs) = shape(view, local, goal, marks, buf);
    let (success, unrated) = rated(prep, units);
    TreeMetrics {
        height,
        success,
        unrated,
        leaf_inputs,
    }
}

/// The whole FOON as a [`TreeView`].
struct Global<'a> {
    foon: &'a Foon,
    prep: &'a Prepared,
}

impl TreeView for Global<'_> {
    #[inline]
    fn needed(&self, f: u32) -> &[u32] {
        self.prep.needed(f)
    }
    #[inline]
    fn for_made(&self, f: u32, mut each: impl FnMut(u32)) {
        for &y in self.foon.outputs(f) {
            if !self.prep.in_kitchen(y) && !self.prep.is_bare(y) {
                each(y);
            }
        }
    }
    #[inline]
    fn in_kitchen(&self, o: u32) -> bool {
        self.prep.in_kitchen(o)
    }
}

/// Runs [`shape`] over the FOON for `units` (ids out of range and repeats ignored), with
/// object-indexed marks when the units are a large part of the FOON and hashed ones
/// otherwise, and gives the result and the marks to `then`.
fn global_shape<R>(
    foon: &Foon,
    prep: &Prepared,
    units: &[u32],
    goal: u32,
    then: impl FnOnce((Option<u32>, usize), &dyn Fn(u32) -> bool) -> R,
) -> R {
    let mut us: Vec<u32> = units
        .iter()
        .copied()
        .filter(|&f| (f as usize) < foon.fu_count())
        .collect();
    us.sort_unstable();
    us.dedup();
    let view = Global { foon, prep };
    let mut buf = ShapeBuf::default();
    if us.len().saturating_mul(8) > foon.object_count() {
        let mut marks = StampedMarks::new(foon.object_count());
        let s = shape(&view, &us, goal, &mut marks, &mut buf);
        then(s, &|x| marks.rank(x) != NONE)
    } else {
        // Room for the objects of the units (a few per unit) from the start: no rehash.
        let mut marks = FxHashMap::with_capacity_and_hasher(4 * us.len(), FxBuildHasher);
        let s = shape(&view, &us, goal, &mut marks, &mut buf);
        then(s, &|x| Marks::rank(&marks, x) != NONE)
    }
}

/// Height, success and leaf count of a set of FUs for `goal`.
pub(crate) fn metrics(foon: &Foon, prep: &Prepared, units: &[u32], goal: u32) -> TreeMetrics {
    let (height, leaf_inputs) = global_shape(foon, prep, units, goal, |s, _| s);
    let (success, unrated) = rated(prep, units);
    TreeMetrics {
        height,
        success,
        unrated,
        leaf_inputs,
    }
}

/// Whether the FUs `units` can be ordered so that every one of them runs (its needed
/// inputs in the kitchen or made by an earlier one) and the goal is in the kitchen or made.
pub(crate) fn is_valid(foon: &Foon, prep: &Prepared, units: &[u32], goal: u32) -> bool {
    global_shape(foon, prep, units, goal, |(height, _), marked| {
        let made = |x: u32| prep.in_kitchen(x) || marked(x);
        let all_run = units
            .iter()
            .all(|&f| (f as usize) < foon.fu_count() && prep.needed(f).iter().all(|&x| made(x)));
        all_run && height.is_some()
    })
}

/// Checks `units` in the given order: returns the position of the first FU with a needed
/// input that is neither in the kitchen nor made by an earlier FU, with those inputs.
pub(crate) fn first_unavailable(
    foon: &Foon,
    prep: &Prepared,
    units: &[u32],
) -> Option<(usize, Vec<u32>)> {
    run_in_order(foon, prep, units).0
}

/// Runs `units` in the given order from the kitchen: a unit runs when its needed inputs
/// are available, and then makes its (produced) outputs available. Returns the first unit
/// that could not run (position, missing inputs) and what is available at the end.
pub(crate) fn run_in_order(
    foon: &Foon,
    prep: &Prepared,
    units: &[u32],
) -> (Option<(usize, Vec<u32>)>, Vec<bool>) {
    let mut avail = prep.kitchen_flags().to_vec();
    let mut first = None;
    for (i, &f) in units.iter().enumerate() {
        let missing: Vec<u32> = prep
            .needed(f)
            .iter()
            .copied()
            .filter(|&x| !avail[x as usize])
            .collect();
        if !missing.is_empty() {
            first.get_or_insert((i, missing));
            continue;
        }
        for &y in foon.outputs(f) {
            if !foon.is_bare(y) {
                avail[y as usize] = true;
            }
        }
    }
    (first, avail)
}
