//! The priority list of thesis 6.1.5 (`m_ErrorList`) as a lazy-deletion
//! binary heap: re-costing a vertex pushes a new entry and bumps the vertex's
//! version, stale entries are skipped when popped. Ties in cost are broken by
//! the vertex id, so the order never depends on timing.
//!
//! Entries popped and put back at once (the vertices a batch looked at but
//! could not take, most of those popped) wait in a short
//! sorted list beside the heap instead of going through it again: they are
//! cheaper than everything left, so they go to its front.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, VecDeque};

/// Orders f64 costs as unsigned integers (total order, negatives first).
#[inline]
fn key(cost: f64) -> u64 {
    let b = cost.to_bits();
    if b >> 63 == 1 { !b } else { b | (1 << 63) }
}

#[derive(Debug)]
pub(crate) struct CostQueue {
    heap: BinaryHeap<Reverse<(u64, u32, u32)>>,
    version: Vec<u32>,
    /// Whether the vertex's current version has an entry in the heap.
    queued: Vec<bool>,
    /// Entries put back by [`CostQueue::put_back`], cheapest first; stale ones
    /// are skipped like the heap's.
    front: VecDeque<(u64, u32, u32)>,
}

impl CostQueue {
    pub fn new(vertices: usize) -> CostQueue {
        CostQueue {
            heap: BinaryHeap::new(),
            version: vec![0; vertices],
            queued: vec![false; vertices],
            front: VecDeque::new(),
        }
    }

    /// The cheapest current entry of the heap and of `front`, without taking it;
    /// `true` when it is `front`'s. Stale entries on top are dropped.
    fn top(&mut self) -> Option<((u64, u32, u32), bool)> {
        while let Some(&(_, v, ver)) = self.front.front() {
            if self.version[v as usize] == ver {
                break;
            }
            self.front.pop_front();
        }
        while let Some(&Reverse((_, v, ver))) = self.heap.peek() {
            if self.version[v as usize] == ver {
                break;
            }
            self.heap.pop();
        }
        match (self.front.front(), self.heap.peek()) {
            (Some(&f), Some(&Reverse(h))) => Some(if f < h { (f, true) } else { (h, false) }),
            (Some(&f), None) => Some((f, true)),
            (None, Some(&Reverse(h))) => Some((h, false)),
            (None, None) => None,
        }
    }

    /// Sets the cost of `v` (`None`: cannot be removed now), replacing any
    /// earlier entry.
    pub fn set(&mut self, v: u32, cost: Option<f64>) {
        self.version[v as usize] = self.version[v as usize].wrapping_add(1);
        self.queued[v as usize] = cost.is_some();
        if let Some(c) = cost {
            self.heap
                .push(Reverse((key(c), v, self.version[v as usize])));
        }
    }

    /// The cheapest current vertex with its cost key, removed from the queue.
    pub fn pop(&mut self) -> Option<(u32, u64)> {
        let ((k, v, ver), in_front) = self.top()?;
        if in_front {
            self.front.pop_front();
        } else {
            self.heap.pop();
        }
        self.version[v as usize] = ver.wrapping_add(1);
        self.queued[v as usize] = false;
        Some((v, k))
    }

    /// Puts back entries just popped, in the order [`CostQueue::pop`] gave them,
    /// with their keys: they come out again first, in that order, as if
    /// re-inserted with [`CostQueue::push_key`] (nothing left in the queue is
    /// cheaper than what was popped before it).
    pub fn put_back(&mut self, popped: impl DoubleEndedIterator<Item = (u32, u64)>) {
        for (v, key) in popped.rev() {
            self.version[v as usize] = self.version[v as usize].wrapping_add(1);
            self.queued[v as usize] = true;
            debug_assert!(
                self.front
                    .front()
                    .is_none_or(|&f| self.version[f.1 as usize] != f.2 || (key, v) < (f.0, f.1)),
                "put_back out of order"
            );
            self.front.push_front((key, v, self.version[v as usize]));
        }
    }

    /// Re-inserts a popped vertex with the key it had.
    pub fn push_key(&mut self, v: u32, key: u64) {
        self.version[v as usize] = self.version[v as usize].wrapping_add(1);
        self.queued[v as usize] = true;
        self.heap.push(Reverse((key, v, self.version[v as usize])));
    }

    /// Re-inserts a popped vertex with a new cost.
    pub fn push_back(&mut self, v: u32, cost: f64) {
        self.set(v, Some(cost));
    }

    /// Cost key of the cheapest current entry (skips stale ones).
    pub fn peek_key(&mut self) -> Option<u64> {
        self.top().map(|((k, _, _), _)| k)
    }

    /// Marks `v` for re-costing when its neighbourhood changed. A queued
    /// vertex keeps its entry (it is re-costed when popped); one that could
    /// not be removed is queued first in line, so it is looked at again soon.
    pub fn mark_dirty(&mut self, v: u32) {
        if !self.queued[v as usize] {
            self.set(v, Some(f64::NEG_INFINITY));
        }
    }

    pub fn key_of(cost: f64) -> u64 {
        key(cost)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pops_by_cost_then_id_and_skips_stale_entries() {
        let mut q = CostQueue::new(5);
        q.set(3, Some(1.0));
        q.set(1, Some(1.0));
        q.set(2, Some(-0.5));
        q.set(4, Some(7.0));
        q.set(4, Some(0.0)); // re-cost: the 7.0 entry goes stale
        q.set(0, Some(2.0));
        q.set(0, None); // no longer removable
        let order: Vec<u32> = std::iter::from_fn(|| q.pop().map(|x| x.0)).collect();
        assert_eq!(order, vec![2, 4, 1, 3]);
    }

    /// Entries put back come out exactly as re-inserting them would give.
    #[test]
    fn put_back_pops_as_push_key_would() {
        let mut rng = toolbox::SplitMix64::new(7);
        let (mut a, mut b) = (CostQueue::new(300), CostQueue::new(300));
        for v in 0..300 {
            let c = Some((rng.range(0.0, 8.0) as i64) as f64); // many ties
            a.set(v, c);
            b.set(v, c);
        }
        for round in 0..200 {
            let take = 1 + round % 9;
            let popped_a: Vec<_> = std::iter::from_fn(|| a.pop()).take(take).collect();
            let popped_b: Vec<_> = std::iter::from_fn(|| b.pop()).take(take).collect();
            assert_eq!(popped_a, popped_b);
            // Put back every other one; re-cost one vertex now and then.
            let back: Vec<_> = popped_a.iter().copied().step_by(2).collect();
            a.put_back(back.iter().copied());
            for &(v, k) in &back {
                b.push_key(v, k);
            }
            if round % 5 == 0 {
                let v = (round * 37 % 300) as u32;
                a.set(v, Some(3.0));
                b.set(v, Some(3.0));
            }
            assert_eq!(a.peek_key(), b.peek_key());
        }
        let rest_a: Vec<_> = std::iter::from_fn(|| a.pop()).collect();
        let rest_b: Vec<_> = std::iter::from_fn(|| b.pop()).collect();
        assert_eq!(rest_a, rest_b);
    }

    #[test]
    fn key_is_monotone() {
        let xs = [-1e9, -1.0, -0.0, 0.0, 1e-300, 1.0, 1e9];
        for w in xs.windows(2) {
            assert!(key(w[0]) <= key(w[1]));
        }
    }
}
