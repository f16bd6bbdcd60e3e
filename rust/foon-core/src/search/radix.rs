//! A monotone priority queue for Knuth's algorithm: a radix heap on the bits of the cost, with
//! exactly the pops of a binary min-heap on (cost, depth, object id).
//!
//! Knuth's algorithm over non-negative weights pushes costs that are never below the last one
//! popped (a unit's cost is its weight plus its inputs' costs, and adding non-negative floats
//! never decreases a sum). For such a sequence a radix heap (Ahuja, Mehlhorn, Orlin and
//! Tarjan, 1990) pushes in O(1) and pops in amortised O(log C) bucket moves, touching memory
//! in runs instead of the binary heap's random walk down a tree of a million entries. The
//! cost of a non-negative `f64` orders as its bit pattern, so the buckets hold the index of
//! the highest bit in which an entry's cost differs from the last popped one.
//!
//! Ties: the searches break equal costs by depth and object id (the order of [`Entry`]), so the entries
//! whose cost equals the last popped one (bucket 0) are kept in order: those moved down at
//! once when a bucket is emptied into bucket 0, sorted in one go (cheaper than a heap's sift
//! per entry: they are often hundreds of one cost), and those pushed at that cost afterwards in
//! a small binary heap of [`Entry`], a pop taking the least of the two. An entry pushed below
//! the last popped cost (which the searches never do) also goes to the heap, so the pops are
//! always those of a binary heap of [`Entry`]: everything in bucket 0 is at most the last
//! popped cost, everything elsewhere above it.

use std::collections::BinaryHeap;

use super::optimal::{Entry, lower};

/// A min-queue on (cost, depth, object id) for non-negative, monotone costs (see the module
/// documentation).
pub(crate) struct RadixQueue {
    /// Bits of the last cost that bucket 0 was refilled at.
    last: u64,
    /// Entries whose cost is at most `last`: those moved down by the last refill, the least
    /// last, and those pushed since, popped in [`Entry`] order.
    sorted: Vec<Entry>,
    low: BinaryHeap<Entry>,
    /// `buckets[i]`: entries whose cost first differs from `last` in bit `i` (from 0, the
    /// lowest), as (cost bits, depth, object).
    buckets: Vec<Vec<(u64, u32, u32)>>,
    /// Whether entries of equal (cost, depth) pop in object id order (else in any order).
    by_id: bool,
}

impl RadixQueue {
    pub(crate) fn new() -> Self {
        Self {
            last: 0,
            sorted: Vec::new(),
            low: BinaryHeap::new(),
            buckets: (0..64).map(|_| Vec::new()).collect(),
            by_id: true,
        }
    }

    /// A queue that pops in (cost, depth) order, entries of equal (cost, depth) in any
    /// order: for a search that takes a level of equal keys at once (no sort of the entries
    /// of one cost when they are all of one depth).
    pub(crate) fn by_key() -> Self {
        Self {
            by_id: false,
            ..Self::new()
        }
    }

    #[inline]
    pub(crate) fn push(&mut self, e: Entry) {
        // A cost with its sign bit set (below every other, as `Entry` orders floats) goes
        // with the least ones.
        let k = e.cost.to_bits();
        if e.cost.is_sign_negative() || k <= self.last {
            self.low.push(e);
        } else {
            let b = 63 - (k ^ self.last).leading_zeros() as usize;
            self.buckets[b].push((k, e.depth, e.obj));
        }
    }

    /// Moves the entries of the lowest non-empty bucket down, the cheapest into `low`, when
    /// `low` is empty.
    fn refill(&mut self) {
        if !self.low.is_empty() || !self.sorted.is_empty() {
            return;
        }
        let Some(b) = self.buckets.iter().position(|v| !v.is_empty()) else {
            return;
        };
        let mut moved = std::mem::take(&mut self.buckets[b]);
        let least = moved.iter().map(|&(k, _, _)| k).min().unwrap_or(self.last);
        self.last = least;
        for &(k, depth, obj) in &moved {
            if k == least {
                self.sorted.push(Entry {
                    cost: f64::from_bits(k),
                    depth,
                    obj,
                });
            } else {
                let to = 63 - (k ^ least).leading_zeros() as usize;
                // Every entry of bucket `b` agrees with `least` above bit `b`, so it moves to
                // a lower bucket.
                debug_assert!(to < b);
                self.buckets[to].push((k, depth, obj));
            }
        }
        moved.clear();
        // Keep the allocation for the next entries of this bucket.
        self.buckets[b] = moved;
        // They all cost `least`: ordered by (depth, id), the least last, as one integer key
        // (by depth alone, when ids need no order, and only when depths differ).
        if self.by_id {
            self.sorted.sort_unstable_by_key(|e| {
                std::cmp::Reverse((u64::from(e.depth) << 32) | u64::from(e.obj))
            });
        } else if let Some(first) = self.sorted.first().map(|e| e.depth)
            && self.sorted.iter().any(|e| e.depth != first)
        {
            self.sorted
                .sort_unstable_by_key(|e| std::cmp::Reverse(e.depth));
        }
    }

    /// Whether the next pop takes the end of `sorted` (else the top of `low`).
    #[inline]
    fn next_is_sorted(&self) -> bool {
        match (self.sorted.last(), self.low.peek()) {
            (Some(a), Some(b)) => a > b,
            (a, _) => a.is_some(),
        }
    }

    /// The least entry (cost, then depth, then object id), without removing it.
    #[inline]
    pub(crate) fn peek(&mut self) -> Option<&Entry> {
        self.refill();
        if self.next_is_sorted() {
            self.sorted.last()
        } else {
            self.low.peek()
        }
    }

    #[inline]
    pub(crate) fn pop(&mut self) -> Option<Entry> {
        self.refill();
        if self.next_is_sorted() {
            self.sorted.pop()
        } else {
            self.low.pop()
        }
    }

    /// The least entry when its (cost, depth) is at most (`cost`, `depth`): the next entry of a
    /// level of equal keys, `cost` being that of an entry popped since the last push below it.
    /// Such a cost is at most the one bucket 0 was refilled at, and every entry of the other
    /// buckets is above: they are not refilled (a refill would move that cost up, and the
    /// level's offers still to come, below it, to the binary heap).
    #[inline]
    pub(crate) fn pop_up_to(&mut self, cost: f64, depth: u32) -> Option<Entry> {
        let up_to = |e: &Entry| !lower(cost, depth, e.cost, e.depth);
        if cost.is_sign_negative() || cost.to_bits() > self.last {
            return match self.peek() {
                Some(e) if up_to(e) => self.pop(),
                _ => None,
            };
        }
        if self.low.is_empty() || self.next_is_sorted() {
            if self.sorted.last().is_some_and(up_to) {
                self.sorted.pop()
            } else {
                None
            }
        } else if self.low.peek().is_some_and(up_to) {
            self.low.pop()
        } else {
            None
        }
    }

    /// An entry likely to be popped `k` pops from now (the `k`-th of those moved down by the
    /// last refill, counting from the next; pushes since are not counted): for hints only.
    #[inline]
    pub(crate) fn ahead(&self, k: usize) -> Option<&Entry> {
        self.sorted
            .len()
            .checked_sub(k + 1)
            .and_then(|i| self.sorted.get(i))
    }

    /// The number of entries (counted, for the tests).
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.sorted.len() + self.low.len() + self.buckets.iter().map(Vec::len).sum::<usize>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Pops equal a binary heap's under Knuth's discipline (a push is never below the
        /// last pop), ties by object id, including repeated costs, zeros and stale entries,
        /// and pops of the rest of a level ([`RadixQueue::pop_up_to`] the last pop's key);
        /// a queue [`RadixQueue::by_key`] pops the same keys, each level's objects in any
        /// order.
        #[test]
        fn pops_as_a_binary_heap(ops in proptest::collection::vec(
            (0u8..5, 0u32..50, 0u32..40, 0u32..3), 1..400), by_id in any::<bool>()) {
            let mut radix = if by_id { RadixQueue::new() } else { RadixQueue::by_key() };
            let mut heap = BinaryHeap::new();
            let mut floor = (0.0f64, 0u32);
            let mut popped = false;
            // Objects popped at each key, from either queue.
            let (mut got, mut want) = (Vec::new(), Vec::new());
            for (kind, obj, step, depth) in ops {
                if kind == 0 || (kind == 4 && popped) {
                    let (a, b) = if kind == 0 {
                        (radix.pop(), heap.pop())
                    } else {
                        let (c, d) = floor;
                        let b = heap.peek().is_some_and(|e: &Entry| !lower(c, d, e.cost, e.depth));
                        (radix.pop_up_to(c, d), if b { heap.pop() } else { None })
                    };
                    let key = |e: &Entry| (e.cost, e.depth);
                    prop_assert_eq!(a.as_ref().map(key), b.as_ref().map(key));
                    if by_id {
                        prop_assert_eq!(a.as_ref().map(|e| e.obj), b.as_ref().map(|e| e.obj));
                    }
                    if let (Some(a), Some(b)) = (a, b) {
                        floor = (a.cost, a.depth);
                        popped = true;
                        got.push((a.cost.to_bits(), a.depth, a.obj));
                        want.push((b.cost.to_bits(), b.depth, b.obj));
                    }
                } else {
                    // Costs from the last pop upward, often equal, some fractional,
                    // and -0.0 beside 0.0.
                    let mut cost = floor.0 + f64::from(step / 4) * if kind == 1 { 0.37 } else { 1.0 };
                    if cost == 0.0 && step % 2 == 1 {
                        cost = -0.0;
                    }
                    radix.push(Entry { cost, depth, obj });
                    heap.push(Entry { cost, depth, obj });
                    // A push below the last pop's key ends its level.
                    popped &= !lower(cost, depth, floor.0, floor.1);
                }
                prop_assert_eq!(radix.len(), heap.len());
                let key = |e: &Entry| (e.cost, e.depth);
                prop_assert_eq!(radix.peek().map(key), heap.peek().map(key));
                if by_id {
                    prop_assert_eq!(radix.peek().map(|e| e.obj), heap.peek().map(|e| e.obj));
                }
            }
            while let Some(b) = heap.pop() {
                let a = radix.pop().expect("as many entries as the heap");
                prop_assert_eq!((a.cost, a.depth), (b.cost, b.depth));
                got.push((a.cost.to_bits(), a.depth, a.obj));
                want.push((b.cost.to_bits(), b.depth, b.obj));
            }
            prop_assert!(radix.pop().is_none());
            got.sort_unstable();
            want.sort_unstable();
            prop_assert_eq!(got, want);
        }

        /// A push below the last pop (never made by the searches) still pops in order.
        #[test]
        fn pushes_below_the_floor_still_pop_in_order(costs in proptest::collection::vec(
            0u32..20, 1..100)) {
            let mut radix = RadixQueue::new();
            let mut heap = BinaryHeap::new();
            for (i, &c) in costs.iter().enumerate() {
                let e = || Entry { cost: f64::from(c), depth: (i % 2) as u32, obj: i as u32 };
                radix.push(e());
                heap.push(e());
                if i % 3 == 0 {
                    prop_assert_eq!(radix.pop().map(|e| (e.cost, e.obj)),
                        heap.pop().map(|e| (e.cost, e.obj)));
                }
            }
            while let Some(b) = heap.pop() {
                prop_assert_eq!(radix.pop().map(|e| (e.cost, e.obj)), Some((b.cost, b.obj)));
            }
        }
    }
}
