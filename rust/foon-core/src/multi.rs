//! Many kitchens at once: derivability, and ranks, for up to 64 kitchens in one forward
//! chaining over the FOON, one `u64` word per object (lane `k` of the word is kitchen `k` of
//! the batch), and batches of 64 kitchens spread over the core's worker pool.
//!
//! The rule is the one of [`Prepared::ranks`](crate::prepare::Prepared) (`forward.rs`): an
//! object is derivable when it is in the kitchen, or some producer has every needed input
//! derivable; outputs that are bare (no state, no ingredient, no container) are never made;
//! rank 0 for a kitchen object, else the fewest rounds of parallel steps that make it. The
//! pass runs level by level (round `r` fires, in each lane, the FUs whose needed inputs are
//! all derivable at rank at most `r` in that lane and that have not fired there yet), so the
//! round in which a lane of an object is first set is its rank in that kitchen: the result is
//! exact, for derivability and for ranks, and does not depend on the order of the work.
//!
//! Cost of one batch: each round looks only at the FUs that need an object that gained a lane
//! in the round before, and evaluates each such FU once per round (a bitwise AND over its
//! needed inputs), so the work is at most that of one forward chaining per distinct round in
//! which an object gains lanes, and in practice a small multiple of one forward chaining,
//! for 64 kitchens. Memory per batch: 8 bytes per object (the derivable lanes) and per FU
//! (the lanes where it fired) while it runs; the result keeps 8 bytes per object per batch
//! of 64 kitchens, and, for ranks, 16 bytes per (object, round in which it gained lanes).

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
    let never = || false;
    let cancel: &(dyn Fn() -> bool + Sync) = opts.cancel.unwrap_or(&never);
    // The FUs with no needed input fire in every lane in the first round.
    let free: Vec<u32> = (0..foon.fu_count() as u32)
        .filter(|&f| base.needed(f).is_empty())
        .collect();
    // Bare outputs are never made (read once here, not once per firing).
    let bare: Vec<bool> = (0..n as u32).map(|o| foon.is_bare(o)).collect();
    let one = |c: &[&[u32]]| lane_pass(foon, base, c, &free, &bare, log, cancel);
    if workers <= 1 {
        return chunks.iter().map(|c| one(c)).collect();
    }
    let slots: Vec<OnceLock<Result<Batch>>> = chunks.iter().map(|_| OnceLock::new()).collect();
    let next = AtomicUsize::new(0);
    let failed = AtomicBool::new(false);
    let work = || {
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            if i >= chunks.len() || failed.load(Ordering::Relaxed) {
                break;
            }
            let r = one(chunks[i]);
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

/// One batch of at most 64 kitchens: forward chaining round by round over the lanes (see the
/// module documentation). `free`: the FUs with no needed input. With `log`, the rounds in
/// which each object gained lanes. `bare`: per object, whether it is bare.
fn lane_pass(
    foon: &Foon,
    base: &PreparedBase,
    kitchens: &[&[u32]],
    free: &[u32],
    bare: &[bool],
    log: bool,
    cancel: &(dyn Fn() -> bool + Sync),
) -> Result<Batch> {
    debug_assert!(kitchens.len() <= LANES);
    let n = foon.object_count();
    let n_fu = foon.fu_count();
    let all: u64 = if kitchens.len() == LANES {
        u64::MAX
    } else {
        (1u64 << kitchens.len()) - 1
    };
    let mut d = vec![0u64; n];
    let mut frontier: Vec<u32> = Vec::new();
    for (lane, kitchen) in kitchens.iter().enumerate() {
        for &o in *kitchen {
            let w = &mut d[o as usize];
            if *w == 0 {
                frontier.push(o);
            }
            *w |= 1 << lane;
        }
    }
    // (object, round, lanes gained) in round order.
    let mut log_ev: Vec<(u32, u32, u64)> = Vec::new();
    if log {
        log_ev.extend(frontier.iter().map(|&o| (o, 0, d[o as usize])));
    }
    let mut fired = vec![0u64; n_fu];
    // The round in which an FU was last looked at, plus one (0: never).
    let mut seen = vec![0u32; n_fu];
    let mut gain = vec![0u64; n];
    let mut next: Vec<u32> = Vec::new();
    let mut cands: Vec<u32> = Vec::new();
    let mut round: u32 = 0;
    loop {
        if cancel() {
            return Err(Error::Cancelled);
        }
        cands.clear();
        let stamp = round + 1;
        if round == 0 {
            for &f in free {
                seen[f as usize] = stamp;
                cands.push(f);
            }
        }
        for &o in &frontier {
            for &f in base.needed_by(o) {
                let s = &mut seen[f as usize];
                if *s != stamp {
                    *s = stamp;
                    cands.push(f);
                }
            }
        }
        for &f in &cands {
            let mut m = all & !fired[f as usize];
            for &x in base.needed(f) {
                if m == 0 {
                    break;
                }
                m &= d[x as usize];
            }
            if m == 0 {
                continue;
            }
            fired[f as usize] |= m;
            for &y in foon.outputs(f) {
                if bare[y as usize] {
                    continue;
                }
                let g = &mut gain[y as usize];
                let nb = m & !d[y as usize] & !*g;
                if nb != 0 {
                    if *g == 0 {
                        next.push(y);
                    }
                    *g |= nb;
                }
            }
        }
        if next.is_empty() {
            break;
        }
        round += 1;
        for &y in &next {
            let g = std::mem::take(&mut gain[y as usize]);
            d[y as usize] |= g;
            if log {
                log_ev.push((y, round, g));
            }
        }
        std::mem::swap(&mut frontier, &mut next);
        next.clear();
    }
    let events = log.then(|| {
        // Counting sort by object; stable, so each object's rounds stay increasing.
        let mut off = vec![0u32; n + 1];
        for &(o, _, _) in &log_ev {
            off[o as usize + 1] += 1;
        }
        for i in 0..n {
            off[i + 1] += off[i];
        }
        let mut at = off.clone();
        let mut rank = vec![0u32; log_ev.len()];
        let mut lanes = vec![0u64; log_ev.len()];
        for &(o, r, m) in &log_ev {
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
