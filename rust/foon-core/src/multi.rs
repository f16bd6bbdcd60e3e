//! Many kitchens at once: derivability, and ranks, for up to 64 kitchens in one forward
//! chaining over the FOON, one `u64` word per object (lane `k` of the word is kitchen `k` of
//! the batch), and batches of 64 kitchens spread over the core's worker pool.
//!
//! The rule is the one of [`Prepared::ranks`](crate::prepare::Prepared) (`forward.rs`): an
//! object is derivable when it is in the kitchen, or some producer has every needed input
//! derivable; outputs that are bare (no state, no ingredient, no container) are never made;
//! rank 0 for a kitchen object, else the fewest rounds of parallel steps that make it. The
//! pass runs level by level, as the one-kitchen forward chaining does, in every lane at once:
//! each FU keeps, per lane, the number of its needed slots still missing, in bit-sliced
//! counters (bit `j` of that number for the 64 lanes in one word, as many words as the
//! largest count needs). When an object gains lanes in round `r`, every FU that needs it
//! counts down by one in those lanes; an FU fires in the lanes whose count reaches zero (its
//! last needed input arrived in round `r`, the largest rank among its inputs), and its
//! outputs that lack those lanes gain them in round `r + 1`. So the round in which a lane of
//! an object is first set is its rank in that kitchen: the result is exact, for derivability
//! and for ranks, and does not depend on the order of the work within a round. The rare FU
//! with more needed inputs than the counters hold ("wide") is decided instead by the AND of
//! its inputs' words each time one of them gains lanes.
//!
//! Cost of one batch: each (object, round in which it gains lanes) counts down once at each
//! FU that needs it, a few word operations on that FU's counters, so the work is that of one
//! forward chaining times the number of distinct ranks an object has across the 64 kitchens
//! (1.5 on the synthetic 1M FOON with kitchens differing by random drops). A round runs as
//! sweeps over lists: the needed slots of the objects that gained lanes, sorted by blocks of
//! FUs so that the counters they touch are near in memory; the firing FUs' outputs; the
//! gains, applied in object order. Memory per batch: 8 bytes per object (the derivable lanes)
//! and 8 bytes per FU per counter plane while it runs, the lists, and buffers kept from batch
//! to batch by each worker; the result keeps 8 bytes per object per batch of 64 kitchens,
//! and, for ranks, 16 bytes per (object, round in which it gained lanes).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

use crate::error::{Error, Result};
use crate::forward::Ranks;
use crate::index::{Foon, NONE};
use crate::prepare::{Prepared, PreparedBase};
use crate::search::batch::{BatchOptions, in_pool};

/// Kitchens per batch: the bits of a word.
pub const LANES: usize = 64;

/// Which objects are derivable in which kitchen ([`derivable_many`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DerivableSets {
    kitchens: usize,
    objects: usize,
    /// Per batch of [`LANES`] kitchens, one word per object: bit `k` is kitchen
    /// `batch * 64 + k`.
    words: Vec<Vec<u64>>,
}

impl DerivableSets {
    /// The number of kitchens.
    pub fn kitchen_count(&self) -> usize {
        self.kitchens
    }

    /// The number of objects of the FOON.
    pub fn object_count(&self) -> usize {
        self.objects
    }

    /// Whether `object` is derivable in kitchen `kitchen` (its position in the list given);
    /// false for a kitchen or an object out of range.
    #[inline]
    pub fn is_derivable(&self, kitchen: usize, object: u32) -> bool {
        self.words
            .get(kitchen / LANES)
            .and_then(|w| w.get(object as usize))
            .is_some_and(|&w| w >> (kitchen % LANES) & 1 == 1)
    }

    /// The word of `object` in batch `batch` (kitchens `64 * batch ..`): bit `k` is set when
    /// the object is derivable in kitchen `64 * batch + k`. 0 out of range.
    pub fn word(&self, batch: usize, object: u32) -> u64 {
        self.words
            .get(batch)
            .and_then(|w| w.get(object as usize))
            .copied()
            .unwrap_or(0)
    }

    /// The objects derivable in kitchen `kitchen`, in id order.
    pub fn derivable_objects(&self, kitchen: usize) -> Vec<u32> {
        let Some(w) = self.words.get(kitchen / LANES) else {
            return Vec::new();
        };
        let bit = kitchen % LANES;
        (0..w.len() as u32)
            .filter(|&o| w[o as usize] >> bit & 1 == 1)
            .collect()
    }

    /// Heap bytes of the words.
    pub fn heap_bytes(&self) -> usize {
        self.words.iter().map(|w| 8 * w.capacity()).sum()
    }
}

/// The ranks of every object in every kitchen ([`ranks_many`]), with derivability.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RanksMany {
    derivable: DerivableSets,
    /// Per batch: each object's rounds, in increasing order, with the lanes it gained in each.
    events: Vec<Events>,
}

/// Per object, the rounds in which it gained lanes and the lanes gained (compressed rows).
#[derive(Debug, Clone, PartialEq, Eq)]
struct Events {
    off: Vec<u32>,
    rank: Vec<u32>,
    lanes: Vec<u64>,
}

impl Events {
    fn of(&self, o: u32) -> std::ops::Range<usize> {
        self.off[o as usize] as usize..self.off[o as usize + 1] as usize
    }
}

impl RanksMany {
    /// Derivability in every kitchen (the same as [`derivable_many`] gives).
    pub fn derivable(&self) -> &DerivableSets {
        &self.derivable
    }

    /// The number of kitchens.
    pub fn kitchen_count(&self) -> usize {
        self.derivable.kitchens
    }

    /// The rank of `object` in kitchen `kitchen`, `None` when it is not derivable there (or
    /// out of range).
    pub fn rank(&self, kitchen: usize, object: u32) -> Option<u32> {
        if !self.derivable.is_derivable(kitchen, object) {
            return None;
        }
        let ev = &self.events[kitchen / LANES];
        let bit = 1u64 << (kitchen % LANES);
        ev.of(object)
            .find(|&i| ev.lanes[i] & bit != 0)
            .map(|i| ev.rank[i])
    }

    /// The ranks of every object in kitchen `kitchen` (all `NONE` for one out of range).
    pub fn ranks(&self, kitchen: usize) -> Ranks {
        let n = self.derivable.objects;
        let mut rank = vec![NONE; n];
        if let Some(ev) = self.events.get(kitchen / LANES) {
            let bit = 1u64 << (kitchen % LANES);
            for (o, r) in (0..n as u32).zip(rank.iter_mut()) {
                if let Some(i) = ev.of(o).find(|&i| ev.lanes[i] & bit != 0) {
                    *r = ev.rank[i];
                }
            }
        }
        Ranks::from_vec(rank)
    }

    /// The ranks of every kitchen of batch `batch` (kitchens `64 * batch ..`), in kitchen
    /// order: one pass over the batch's rounds, each lane written where it was gained.
    fn batch_ranks(&self, batch: usize) -> Vec<Ranks> {
        let n = self.derivable.objects;
        let lanes = (self.derivable.kitchens - batch * LANES).min(LANES);
        let mut ranks: Vec<Vec<u32>> = (0..lanes).map(|_| vec![NONE; n]).collect();
        let ev = &self.events[batch];
        for o in 0..n as u32 {
            for i in ev.of(o) {
                let mut m = ev.lanes[i];
                while m != 0 {
                    let k = m.trailing_zeros() as usize;
                    m &= m - 1;
                    ranks[k][o as usize] = ev.rank[i];
                }
            }
        }
        ranks.into_iter().map(Ranks::from_vec).collect()
    }

    /// Heap bytes of the derivable words and the rounds.
    pub fn heap_bytes(&self) -> usize {
        self.derivable.heap_bytes()
            + self
                .events
                .iter()
                .map(|e| 4 * e.off.capacity() + 4 * e.rank.capacity() + 8 * e.lanes.capacity())
                .sum::<usize>()
    }
}

/// Which objects are derivable in each of `kitchens` (object ids of `foon`, any order,
/// repeats allowed), the needed inputs and bare outputs of `base` (built for `foon`). Batches
/// of 64 kitchens run on `opts.threads` workers of the core's pool (the policy of
/// [`crate::search::batch`]; `opts.cancel` is polled each round). An object id out of range is
/// an error, naming the kitchen.
pub fn derivable_many(
    foon: &Foon,
    base: &PreparedBase,
    kitchens: &[&[u32]],
    opts: &BatchOptions<'_>,
) -> Result<DerivableSets> {
    let batches = run_batches(foon, base, kitchens, opts, false)?;
    Ok(DerivableSets {
        kitchens: kitchens.len(),
        objects: foon.object_count(),
        words: batches.into_iter().map(|(w, _)| w).collect(),
    })
}

/// As [`derivable_many`], with the rank of every object in every kitchen.
pub fn ranks_many(
    foon: &Foon,
    base: &PreparedBase,
    kitchens: &[&[u32]],
    opts: &BatchOptions<'_>,
) -> Result<RanksMany> {
    let batches = run_batches(foon, base, kitchens, opts, true)?;
    let mut words = Vec::with_capacity(batches.len());
    let mut events = Vec::with_capacity(batches.len());
    for (w, e) in batches {
        words.push(w);
        events.push(e.unwrap_or_else(|| Events {
            off: vec![0; foon.object_count() + 1],
            rank: Vec::new(),
            lanes: Vec::new(),
        }));
    }
    Ok(RanksMany {
        derivable: DerivableSets {
            kitchens: kitchens.len(),
            objects: foon.object_count(),
            words,
        },
        events,
    })
}

/// Every kitchen of `kitchens` prepared on `base` (see [`Prepared::with_base`]), in order,
/// with its ranks already set from one lane-wise pass per 64 kitchens ([`ranks_many`]): the
/// same values as each kitchen's own [`Prepared::with_objects`] would compute.
pub fn prepare_many(
    foon: &Foon,
    base: &Arc<PreparedBase>,
    kitchens: &[&[u32]],
    opts: &BatchOptions<'_>,
) -> Result<Vec<Prepared>> {
    let ranks = ranks_many(foon, base, kitchens, opts)?;
    let mut out = Vec::with_capacity(kitchens.len());
    for batch in 0..ranks.events.len() {
        let lo = batch * LANES;
        for (k, r) in (lo..).zip(ranks.batch_ranks(batch)) {
            let p = Prepared::with_base(foon, Arc::clone(base), kitchens[k])?;
            p.set_ranks(r);
            out.push(p);
        }
    }
    Ok(out)
}

type Batch = (Vec<u64>, Option<Events>);

/// Bit planes of a counter at most: an FU with more than `2^MAX_PLANES` needed inputs is
/// always wide.
const MAX_PLANES: usize = 4;

/// FUs per block of counters sorted together (`2^BLOCK_BITS`; a block's counters, at most 32
/// bytes per FU, fit in a core's cache).
const BLOCK_BITS: u32 = 13;

/// What every batch of one call shares, read once from the FOON and the base.
struct Shared<'a> {
    foon: &'a Foon,
    base: &'a PreparedBase,
    /// The FUs with no needed input (they fire in every lane in the first round).
    free: Vec<u32>,
    /// Bit planes per counter (1 to [`MAX_PLANES`]): an FU with at most `2^planes` needed
    /// inputs is counted, one with more is wide.
    planes: usize,
    /// Per FU, the initial counter: its number of needed inputs minus one (0 when it has
    /// none or is wide).
    start: Vec<u8>,
    /// Per FU, one bit: whether it is wide (empty when none is).
    wide: Vec<u64>,
    /// Per object, one bit: whether it is bare (never made).
    bare: Vec<u64>,
}

impl<'a> Shared<'a> {
    fn new(foon: &'a Foon, base: &'a PreparedBase) -> Self {
        let n = foon.object_count();
        let n_fu = foon.fu_count();
        let mut free = Vec::new();
        // How many FUs need more than 2^p inputs, for each p.
        let mut over = [0usize; MAX_PLANES + 1];
        for f in 0..n_fu as u32 {
            let l = base.needed(f).len();
            if l == 0 {
                free.push(f);
            }
            for (p, c) in over.iter_mut().enumerate() {
                *c += usize::from(l > 1 << p);
            }
        }
        // The fewest planes that leave at most one FU in 1024 wide (a wide FU costs its
        // needed inputs at each of its slots).
        let planes = (1..=MAX_PLANES)
            .find(|&p| over[p] * 1024 <= n_fu)
            .unwrap_or(MAX_PLANES);
        let mut start = Vec::with_capacity(n_fu);
        let mut wide = Vec::new();
        for f in 0..n_fu as u32 {
            let l = base.needed(f).len();
            if l > 1 << planes {
                if wide.is_empty() {
                    wide = vec![0u64; n_fu.div_ceil(64)];
                }
                wide[f as usize / 64] |= 1 << (f % 64);
                start.push(0);
            } else {
                start.push(l.saturating_sub(1) as u8);
            }
        }
        let mut bare = vec![0u64; n.div_ceil(64)];
        for o in 0..n as u32 {
            if foon.is_bare(o) {
                bare[o as usize / 64] |= 1 << (o % 64);
            }
        }
        Self {
            foon,
            base,
            free,
            planes,
            start,
            wide,
            bare,
        }
    }
}

/// One worker's buffers, reused from batch to batch.
#[derive(Default)]
struct Scratch {
    /// Per FU, `planes` words: bit `k` of word `j` is bit `j` of the number of its needed
    /// slots still missing in lane `k`, minus one (until it fires there). A wide FU keeps
    /// in word 0 the lanes where it fired.
    cnt: Vec<u64>,
    /// The objects that gained lanes in the round before, with the lanes gained.
    frontier: Vec<(u32, u64)>,
    /// The needed slots of the objects that gained lanes, with the lanes gained.
    slots: Vec<(u32, u64)>,
    /// `slots` by blocks of `2^BLOCK_BITS` FUs, and the counts of the blocks.
    by_block: Vec<(u32, u64)>,
    hist: Vec<u32>,
    /// The FUs firing this round, with their lanes.
    fired: Vec<(u32, u64)>,
    /// The outputs of this round's firings, with the lanes they may gain (repeats allowed).
    made: Vec<(u32, u64)>,
    /// (object, round, lanes gained), in round order.
    log: Vec<(u32, u32, u64)>,
}

/// Runs every batch of 64 kitchens, on the pool when there are several and more than one
/// worker; results in batch order (the first error in batch order wins).
fn run_batches(
    foon: &Foon,
    base: &PreparedBase,
    kitchens: &[&[u32]],
    opts: &BatchOptions<'_>,
    log: bool,
) -> Result<Vec<Batch>> {
    base.check_foon(foon)?;
    let n = foon.object_count();
    for (k, kitchen) in kitchens.iter().enumerate() {
        if let Some(&o) = kitchen.iter().find(|&&o| o as usize >= n) {
            return Err(Error::Invalid(format!(
                "kitchen {k}: object id {o} is not an object of this FOON ({n} objects)"
            )));
        }
    }
    let chunks: Vec<&[&[u32]]> = kitchens.chunks(LANES).collect();
    let workers = opts.workers(chunks.len())?;
    if chunks.is_empty() {
        return Ok(Vec::new());
    }
    let never = || false;
    let cancel: &(dyn Fn() -> bool + Sync) = opts.cancel.unwrap_or(&never);
    let shared = Shared::new(foon, base);
    let one = |scratch: &mut Scratch, c: &[&[u32]]| lane_pass(&shared, scratch, c, log, cancel);
    if workers <= 1 {
        let mut scratch = Scratch::default();
        return chunks.iter().map(|c| one(&mut scratch, c)).collect();
    }
    let slots: Vec<OnceLock<Result<Batch>>> = chunks.iter().map(|_| OnceLock::new()).collect();
    let next = AtomicUsize::new(0);
    let failed = AtomicBool::new(false);
    let work = || {
        let mut scratch = Scratch::default();
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            if i >= chunks.len() || failed.load(Ordering::Relaxed) {
                break;
            }
            let r = one(&mut scratch, chunks[i]);
            if r.is_err() {
                failed.store(true, Ordering::Relaxed);
            }
            let _ = slots[i].set(r);
        }
    };
    in_pool(|| {
        rayon::scope(|s| {
            for _ in 0..workers {
                s.spawn(|_| work());
            }
        });
    })?;
    let mut out = Vec::with_capacity(chunks.len());
    // A batch not started (another one failed) has no slot; the failure is among them.
    for r in slots.into_iter().filter_map(OnceLock::into_inner) {
        out.push(r?);
    }
    if out.len() == chunks.len() {
        Ok(out)
    } else {
        Err(Error::Cancelled)
    }
}

/// One batch of at most 64 kitchens (see the module documentation), with counters of
/// `shared.planes` bit planes. With `log`, the rounds in which each object gained lanes.
fn lane_pass(
    shared: &Shared<'_>,
    scratch: &mut Scratch,
    kitchens: &[&[u32]],
    log: bool,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Batch> {
    match shared.planes {
        1 => lane_pass_with::<1>(shared, scratch, kitchens, log, cancel),
        2 => lane_pass_with::<2>(shared, scratch, kitchens, log, cancel),
        3 => lane_pass_with::<3>(shared, scratch, kitchens, log, cancel),
        _ => lane_pass_with::<MAX_PLANES>(shared, scratch, kitchens, log, cancel),
    }
}

/// [`lane_pass`] with `P` bit planes per counter. Each round runs in three sweeps, each
/// over a list and free of the others' memory (so that their random accesses overlap): the
/// needed slots of the objects that gained lanes count down, giving the FUs that fire; the
/// outputs of those FUs gather the lanes they may gain; the gains are applied.
fn lane_pass_with<const P: usize>(
    shared: &Shared<'_>,
    scratch: &mut Scratch,
    kitchens: &[&[u32]],
    log: bool,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Batch> {
    debug_assert!(kitchens.len() <= LANES && P == shared.planes);
    let Shared {
        foon,
        base,
        ref free,
        ref start,
        ref wide,
        ref bare,
        ..
    } = *shared;
    let n = foon.object_count();
    let all: u64 = if kitchens.len() == LANES {
        u64::MAX
    } else {
        (1u64 << kitchens.len()) - 1
    };
    let Scratch {
        cnt,
        frontier,
        slots,
        by_block,
        hist,
        fired,
        made,
        log: log_ev,
    } = scratch;
    cnt.clear();
    cnt.resize(start.len() * P, 0);
    for (c, &l) in cnt.chunks_exact_mut(P).zip(start) {
        for (j, w) in c.iter_mut().enumerate() {
            *w = 0u64.wrapping_sub(u64::from(l >> j & 1));
        }
    }
    frontier.clear();
    log_ev.clear();
    // Per object, the lanes where it is derivable so far (up to the round being run).
    let mut d = vec![0u64; n];
    for (lane, kitchen) in kitchens.iter().enumerate() {
        for &o in *kitchen {
            let w = &mut d[o as usize];
            if *w == 0 {
                frontier.push((o, 0));
            }
            *w |= 1 << lane;
        }
    }
    frontier.sort_unstable_by_key(|e| e.0);
    for e in frontier.iter_mut() {
        e.1 = d[e.0 as usize];
        if log {
            log_ev.push((e.0, 0, e.1));
        }
    }
    let blocks = start.len().div_ceil(1 << BLOCK_BITS);
    let is_wide = |f: usize| !wide.is_empty() && wide[f / 64] >> (f % 64) & 1 == 1;
    let mut round: u32 = 0;
    loop {
        if cancel() {
            return Err(Error::Cancelled);
        }
        // 1. Count down: each needed slot of an object that gained lanes `g`, then the
        // counters of those slots (lanes at zero fire, the others count down by one).
        slots.clear();
        for &(x, g) in frontier.iter() {
            slots.extend(base.needed_by(x).iter().map(|&f| (f, g)));
        }
        // By blocks of FUs (a counting sort on the high bits of the FU), so that the
        // counters a stretch of slots touches stay in cache.
        hist.clear();
        hist.resize(blocks + 1, 0);
        for &(f, _) in slots.iter() {
            hist[(f >> BLOCK_BITS) as usize + 1] += 1;
        }
        for b in 0..blocks {
            hist[b + 1] += hist[b];
        }
        by_block.clear();
        by_block.resize(slots.len(), (0, 0));
        for &(f, g) in slots.iter() {
            let at = &mut hist[(f >> BLOCK_BITS) as usize];
            by_block[*at as usize] = (f, g);
            *at += 1;
        }
        let free_now: &[u32] = if round == 0 { free } else { &[] };
        fired.clear();
        fired.resize(slots.len() + free_now.len(), (0, 0));
        let mut nf = 0;
        for &f in free_now {
            fired[nf] = (f, all);
            nf += 1;
        }
        for &(f, g) in by_block.iter() {
            let fi = f as usize;
            let z = if is_wide(fi) {
                // Fires where every needed input is derivable and it has not fired.
                let mut m = g & !cnt[fi * P];
                for &x2 in base.needed(f) {
                    m &= d[x2 as usize];
                }
                cnt[fi * P] |= m;
                m
            } else {
                let c: &mut [u64; P] = (&mut cnt[fi * P..fi * P + P]).try_into().unwrap();
                let mut left = 0;
                for w in c.iter() {
                    left |= *w;
                }
                let mut borrow = g & left;
                for w in c.iter_mut() {
                    let v = *w;
                    *w = v ^ borrow;
                    borrow &= !v;
                }
                g & !left
            };
            fired[nf] = (f, z);
            nf += usize::from(z != 0);
        }
        fired.truncate(nf);
        // 2. The outputs of the firing FUs, with the lanes they may gain.
        made.clear();
        for &(f, z) in fired.iter() {
            made.extend(foon.outputs(f).iter().map(|&y| (y, z)));
        }
        // 3. In object order, the outputs that are not bare gain, at rank `round + 1`, the
        // lanes they lack.
        made.sort_unstable_by_key(|e| e.0);
        frontier.clear();
        let mut i = 0;
        while i < made.len() {
            let y = made[i].0;
            let mut nb = 0;
            while i < made.len() && made[i].0 == y {
                nb |= made[i].1;
                i += 1;
            }
            let yi = y as usize;
            let w = &mut d[yi];
            let g = nb & !*w;
            if g != 0 && bare[yi / 64] >> (yi % 64) & 1 == 0 {
                *w |= g;
                frontier.push((y, g));
                if log {
                    log_ev.push((y, round + 1, g));
                }
            }
        }
        if frontier.is_empty() {
            break;
        }
        round += 1;
    }
    let events = log.then(|| {
        // Counting sort by object; stable, so each object's rounds stay increasing.
        let mut off = vec![0u32; n + 1];
        for &(o, _, _) in log_ev.iter() {
            off[o as usize + 1] += 1;
        }
        for i in 0..n {
            off[i + 1] += off[i];
        }
        let mut at = off.clone();
        let mut rank = vec![0u32; log_ev.len()];
        let mut lanes = vec![0u64; log_ev.len()];
        for &(o, r, m) in log_ev.iter() {
            let i = at[o as usize] as usize;
            at[o as usize] += 1;
            rank[i] = r;
            lanes[i] = m;
        }
        Events { off, rank, lanes }
    });
    Ok((d, events))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse::{ParseOptions, parse_foon};

    fn foon(text: &str) -> Foon {
        parse_foon(text.as_bytes(), None, ParseOptions::default()).unwrap()
    }

    /// Every lane equals its kitchen's own forward chaining, for ranks and derivability.
    fn check(f: &Foon, kitchens: &[Vec<u32>], threads: Option<usize>) {
        let base = Arc::new(PreparedBase::new(f, &[], None, None).unwrap());
        let ks: Vec<&[u32]> = kitchens.iter().map(Vec::as_slice).collect();
        let opts = BatchOptions::threads(threads);
        let d = derivable_many(f, &base, &ks, &opts).unwrap();
        let r = ranks_many(f, &base, &ks, &opts).unwrap();
        assert_eq!(&d, r.derivable());
        let preps = prepare_many(f, &base, &ks, &opts).unwrap();
        for (k, kitchen) in kitchens.iter().enumerate() {
            let own = Prepared::with_objects(f, kitchen, &[], None, None).unwrap();
            let want = own.ranks(f);
            assert_eq!(&r.ranks(k), want, "kitchen {k}");
            assert_eq!(preps[k].ranks(f), want, "kitchen {k}");
            for o in 0..f.object_count() as u32 {
                assert_eq!(d.is_derivable(k, o), want.is_derivable(o));
                assert_eq!(r.rank(k, o), want.rank(o));
            }
        }
    }

    #[test]
    fn lanes_equal_one_kitchen_at_a_time() {
        // A chain a -> b -> c, a unit with no input making d, a self-loop on e, a bare output.
        let f = foon(
            "O\tx\nS\ta\nM\tm\nO\tx\nS\tb\n//\n\
             O\tx\nS\tb\nO\ty\nS\tq\nM\tm\nO\tx\nS\tc\n//\n\
             M\tm\nO\tx\nS\td\nO\tknife\n//\n\
             O\tx\nS\te\nM\tm\nO\tx\nS\te\n//\n\
             O\tx\nS\td\nO\tx\nS\tc\nM\tm\nO\tx\nS\tf\n//\n",
        );
        let n = f.object_count() as u32;
        for count in [1usize, 2, 63, 64, 65, 130] {
            let kitchens: Vec<Vec<u32>> = (0..count)
                .map(|k| (0..n).filter(|o| (k as u32 * 7 + o * 3) % 5 < 2).collect())
                .collect();
            for threads in [Some(1), Some(2)] {
                check(&f, &kitchens, threads);
            }
        }
    }

    /// A FOON of `units` units over `objects` objects (`x` in state `s<i>`, and bare tools
    /// `t<i>`), the number of inputs of unit `u` given by `inputs(u, random)`, inputs and outputs at
    /// random (so cycles and self-loops), from `seed`.
    fn random_foon(
        units: usize,
        objects: u64,
        seed: u64,
        mut inputs: impl FnMut(usize, u64) -> u64,
    ) -> Foon {
        let mut s = seed | 1;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        let obj = |o: u64| {
            if o % 9 == 8 {
                format!("O\tt{o}\n")
            } else {
                format!("O\tx\nS\ts{o}\n")
            }
        };
        let mut text = String::new();
        for u in 0..units {
            let l = inputs(u, next());
            let mut ins: Vec<u64> = (0..l).map(|_| next() % objects).collect();
            ins.sort_unstable();
            ins.dedup();
            for &o in &ins {
                text.push_str(&obj(o));
            }
            text.push_str("M\tm\n");
            for _ in 0..=(next() % 2) {
                text.push_str(&obj(next() % objects));
            }
            text.push_str("//\n");
        }
        foon(&text)
    }

    /// Random kitchens of `f`: `count` of them, each object in with probability `in8 / 8`.
    fn random_kitchens(f: &Foon, count: usize, seed: u64, in8: u64) -> Vec<Vec<u32>> {
        let mut s = seed | 1;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        (0..count)
            .map(|_| {
                (0..f.object_count() as u32)
                    .filter(|_| next() % 8 < in8)
                    .collect()
            })
            .collect()
    }

    #[test]
    fn counters_of_every_width_and_wide_units() {
        // (units, inputs per unit, the planes and whether some unit is wide).
        type Inputs = fn(usize, u64) -> u64;
        let cases: [(usize, Inputs, usize, bool); 6] = [
            (300, |_, r| 1 + r % 2, 1, false),
            (300, |_, r| 1 + r % 4, 2, false),
            (300, |_, r| 1 + r % 8, 3, false),
            (300, |_, r| 1 + r % 16, 4, false),
            // One unit in 2,000 with 20 inputs: counted FUs keep one plane.
            (2000, |u, r| if u == 700 { 20 } else { 1 + r % 2 }, 1, true),
            // Many units with up to 30 inputs: the widest counters, and wide units.
            (200, |_, r| 1 + r % 30, MAX_PLANES, true),
        ];
        for (i, (units, inputs, planes, wide)) in cases.into_iter().enumerate() {
            for seed in [3u64, 11] {
                // Few objects for many inputs, so that units overlap and fire.
                let objects = if planes > 2 { 60 } else { 400 };
                let f = random_foon(units, objects, seed * 31 + i as u64, inputs);
                let base = PreparedBase::new(&f, &[], None, None).unwrap();
                let sh = Shared::new(&f, &base);
                assert_eq!(sh.planes, planes, "case {i}");
                assert_eq!(!sh.wide.is_empty(), wide, "case {i}");
                // Sparse kitchens, and dense ones where wide units fire in later rounds.
                for in8 in [2, 7] {
                    check(&f, &random_kitchens(&f, 65, seed, in8), Some(1));
                }
            }
        }
    }

    #[test]
    fn bad_ids_and_another_foon_are_errors() {
        let f = foon("O\tx\nS\ta\nM\tm\nO\tx\nS\tb\n//\n");
        let g = foon("O\tx\nS\ta\nM\tn\nO\tx\nS\tb\n//\n");
        let base = PreparedBase::new(&f, &[], None, None).unwrap();
        let opts = BatchOptions::default();
        let e = derivable_many(&f, &base, &[&[0], &[9]], &opts).unwrap_err();
        assert_eq!(
            e.to_string(),
            "kitchen 1: object id 9 is not an object of this FOON (2 objects)"
        );
        assert!(derivable_many(&g, &base, &[&[0]], &opts).is_err());
        let none = derivable_many(&f, &base, &[], &opts).unwrap();
        assert_eq!(none.kitchen_count(), 0);
        assert!(!none.is_derivable(0, 0));
    }

    #[test]
    fn a_cancelled_pass_stops() {
        let f = foon("O\tx\nS\ta\nM\tm\nO\tx\nS\tb\n//\n");
        let base = PreparedBase::new(&f, &[], None, None).unwrap();
        let yes = || true;
        let ks: Vec<&[u32]> = vec![&[0]; 200];
        for threads in [Some(1), Some(2)] {
            let opts = BatchOptions::threads(threads).with_cancel(&yes);
            assert!(matches!(
                derivable_many(&f, &base, &ks, &opts),
                Err(Error::Cancelled)
            ));
        }
    }
}
