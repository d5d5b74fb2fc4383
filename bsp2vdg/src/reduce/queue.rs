//! The priority list of thesis 6.1.5 (`m_ErrorList`) as a lazy-deletion
//! binary heap: re-costing a vertex pushes a new entry and bumps the vertex's
//! version, stale entries are skipped when popped. Ties in cost are broken by
//! the vertex id, so the order never depends on timing.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

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
}

impl CostQueue {
    pub fn new(vertices: usize) -> CostQueue {
        CostQueue {
            heap: BinaryHeap::new(),
            version: vec![0; vertices],
            queued: vec![false; vertices],
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
        while let Some(Reverse((k, v, ver))) = self.heap.pop() {
            if self.version[v as usize] == ver {
                self.version[v as usize] = ver.wrapping_add(1);
                self.queued[v as usize] = false;
                return Some((v, k));
            }
        }
        None
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
        while let Some(&Reverse((k, v, ver))) = self.heap.peek() {
            if self.version[v as usize] == ver {
                return Some(k);
            }
            self.heap.pop();
        }
        None
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

    #[test]
    fn key_is_monotone() {
        let xs = [-1e9, -1.0, -0.0, 0.0, 1e-300, 1.0, 1e9];
        for w in xs.windows(2) {
            assert!(key(w[0]) <= key(w[1]));
        }
    }
}
