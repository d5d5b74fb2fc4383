//! Circulation with bounds, kept feasible incrementally on its residual graph.
//!
//! The tiling constraints (paper §4.1, Fig. 6) are a network-flow problem: one
//! node per tile slot plus one "outside" node, one arc per tile edge carrying
//! that edge's flux multiple between a lower and an upper bound, and
//! conservation at every slot. Instead of two linear programs per edge (the
//! paper) we keep one feasible integral circulation and answer every question
//! with augmenting paths on its residual graph:
//!
//! * the largest value of arc `e = (a → b)` is reached by pushing flow around
//!   cycles `a → b ⇝ a`, i.e. augmenting paths `b ⇝ a` that avoid `e`; when
//!   none is left the max-flow/min-cut theorem proves the value is maximal;
//! * fixing an arc to a value is "move it there, then clamp its bounds";
//! * tentative changes are journalled and rolled back.
//!
//! Paths are found by a bidirectional breadth-first search that stops as soon
//! as either side runs dry, so a query costs the size of the smaller side of
//! the cut — a handful of slots in scan-line tiling, not the whole grid.

use std::collections::VecDeque;

/// Index of an arc.
pub type ArcId = usize;

/// One arc: flux from `tail` to `head` within `[lo, hi]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Arc {
    /// Node the flux leaves.
    pub tail: u32,
    /// Node the flux enters.
    pub head: u32,
    /// Lower bound.
    pub lo: i32,
    /// Upper bound.
    pub hi: i32,
    /// Current flux.
    pub x: i32,
}

/// A journal entry: the arc's full state before a change.
#[derive(Clone, Copy, Debug)]
struct Undo {
    arc: ArcId,
    before: Arc,
}

/// A circulation network with bounds and a current feasible circulation.
///
/// ```
/// use flowtile_bake::flow::Network;
/// // Two nodes joined by two parallel arcs: whatever goes one way returns.
/// let mut net = Network::new(2);
/// let a = net.add_arc(0, 1, -2, 2);
/// let b = net.add_arc(1, 0, 0, 1);
/// net.make_feasible().unwrap();
/// assert_eq!(net.range(a), (0, 1));
/// assert!(net.fix(a, 1));
/// assert_eq!(net.arc(b).x, 1);
/// ```
#[derive(Clone, Debug)]
pub struct Network {
    nodes: usize,
    arcs: Vec<Arc>,
    /// CSR adjacency: arcs incident to node v are `adj[start[v]..start[v+1]]`.
    start: Vec<u32>,
    adj: Vec<u32>,
    built: bool,
    journal: Vec<Undo>,
    journalling: bool,
    search: Search,
    /// Most nodes one search may visit before giving up (see
    /// [`Network::move_bounded`]); unlimited otherwise.
    budget: usize,
    /// A search gave up on the budget since the last bounded move began.
    cut_off: bool,
}

/// Scratch state of the bidirectional search, reused between queries.
#[derive(Clone, Debug, Default)]
struct Search {
    stamp: u32,
    fwd_mark: Vec<u32>,
    bwd_mark: Vec<u32>,
    /// Arc used to reach the node (forward: into it; backward: out of it).
    fwd_via: Vec<u32>,
    bwd_via: Vec<u32>,
    fwd_queue: Fifo,
    bwd_queue: Fifo,
}

/// A first-in first-out queue that is cleared before every search: a vector
/// and a read position (no wrap-around bookkeeping on the hot path).
#[derive(Clone, Debug, Default)]
struct Fifo {
    items: Vec<u32>,
    head: usize,
}

impl Fifo {
    fn clear(&mut self) {
        self.items.clear();
        self.head = 0;
    }
    fn push_back(&mut self, v: u32) {
        self.items.push(v);
    }
    fn pop_front(&mut self) -> Option<u32> {
        let v = *self.items.get(self.head)?;
        self.head += 1;
        Some(v)
    }
    fn len(&self) -> usize {
        self.items.len() - self.head
    }
}

/// The feasibility search failed: the bounds admit no circulation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Infeasible {
    /// A node whose imbalance could not be routed.
    pub node: u32,
}

const NONE: u32 = u32::MAX;

/// Up to three (from node, arc) steps, the number used, and the bottleneck.
type ShortPath = ([(u32, usize); 3], usize, i32);

impl Network {
    /// An empty network on `nodes` nodes.
    pub fn new(nodes: usize) -> Network {
        Network {
            nodes,
            arcs: Vec::new(),
            start: Vec::new(),
            adj: Vec::new(),
            built: false,
            journal: Vec::new(),
            journalling: false,
            search: Search::default(),
            budget: usize::MAX,
            cut_off: false,
        }
    }

    /// Adds an arc `tail → head` with bounds `[lo, hi]`; returns its id.
    pub fn add_arc(&mut self, tail: u32, head: u32, lo: i32, hi: i32) -> ArcId {
        debug_assert!(lo <= hi);
        self.built = false;
        self.arcs.push(Arc {
            tail,
            head,
            lo,
            hi,
            x: 0.clamp(lo, hi),
        });
        self.arcs.len() - 1
    }

    /// Replaces the bounds of arc `e` and clamps its flux into them; call
    /// [`Network::make_feasible`] afterwards to restore conservation.
    pub fn set_bounds(&mut self, e: ArcId, lo: i32, hi: i32) {
        let a = &mut self.arcs[e];
        a.lo = lo;
        a.hi = hi;
        a.x = a.x.clamp(lo, hi);
    }

    /// Number of arcs.
    pub fn arc_count(&self) -> usize {
        self.arcs.len()
    }

    /// The arc with id `e`.
    pub fn arc(&self, e: ArcId) -> Arc {
        self.arcs[e]
    }

    fn build(&mut self) {
        let mut deg = vec![0u32; self.nodes + 1];
        for a in &self.arcs {
            deg[a.tail as usize] += 1;
            if a.head != a.tail {
                deg[a.head as usize] += 1;
            }
        }
        let mut start = vec![0u32; self.nodes + 1];
        for v in 0..self.nodes {
            start[v + 1] = start[v] + deg[v];
        }
        let mut fill = start.clone();
        let mut adj = vec![0u32; start[self.nodes] as usize];
        for (e, a) in self.arcs.iter().enumerate() {
            adj[fill[a.tail as usize] as usize] = e as u32;
            fill[a.tail as usize] += 1;
            if a.head != a.tail {
                adj[fill[a.head as usize] as usize] = e as u32;
                fill[a.head as usize] += 1;
            }
        }
        self.start = start;
        self.adj = adj;
        let s = &mut self.search;
        s.fwd_mark = vec![0; self.nodes];
        s.bwd_mark = vec![0; self.nodes];
        s.fwd_via = vec![NONE; self.nodes];
        s.bwd_via = vec![NONE; self.nodes];
        s.stamp = 0;
        self.built = true;
    }

    /// Net inflow minus outflow at every node for the current fluxes.
    fn imbalances(&self) -> Vec<i64> {
        let mut ex = vec![0i64; self.nodes];
        for a in &self.arcs {
            ex[a.head as usize] += a.x as i64;
            ex[a.tail as usize] -= a.x as i64;
        }
        ex
    }

    /// Finds a feasible circulation from the current fluxes (each starts at the
    /// bound value nearest zero) by routing every node's surplus to deficits:
    /// Dinic's algorithm with all surplus nodes as sources and all deficit
    /// nodes as sinks (a level graph by breadth-first search, then blocking
    /// flows by depth-first search with current-arc pointers). Exact: fails
    /// only when no feasible circulation exists.
    pub fn make_feasible(&mut self) -> Result<(), Infeasible> {
        if !self.built {
            self.build();
        }
        let mut ex = self.imbalances();
        let nodes = self.nodes;
        let mut level = vec![u32::MAX; nodes];
        let mut next_arc = vec![0u32; nodes];
        let mut queue = VecDeque::new();
        let mut path: Vec<(u32, usize)> = Vec::new();
        while let Some(first) = ex.iter().position(|&e| e > 0) {
            // Level graph from every surplus node up to the nearest deficits.
            level.fill(u32::MAX);
            queue.clear();
            for v in 0..nodes {
                if ex[v] > 0 {
                    level[v] = 0;
                    queue.push_back(v as u32);
                }
            }
            let mut sink_level = u32::MAX;
            while let Some(v) = queue.pop_front() {
                let lv = level[v as usize];
                if lv > sink_level {
                    break;
                }
                if ex[v as usize] < 0 {
                    sink_level = lv;
                    continue;
                }
                if lv == sink_level {
                    continue;
                }
                for k in self.start[v as usize]..self.start[v as usize + 1] {
                    let e = self.adj[k as usize] as usize;
                    if let Some(w) = self.residual_out(v, e)
                        && level[w as usize] == u32::MAX
                    {
                        level[w as usize] = lv + 1;
                        queue.push_back(w);
                    }
                }
            }
            if sink_level == u32::MAX {
                return Err(Infeasible { node: first as u32 });
            }
            // Blocking flow.
            next_arc.copy_from_slice(&self.start[..nodes]);
            for src in 0..nodes as u32 {
                while ex[src as usize] > 0 && level[src as usize] == 0 {
                    path.clear();
                    let mut cur = src;
                    loop {
                        let lc = level[cur as usize];
                        if lc == sink_level && ex[cur as usize] < 0 {
                            let mut amount = ex[src as usize].min(-ex[cur as usize]);
                            for &(from, e) in &path {
                                amount = amount.min(self.cap_from(from, e) as i64);
                            }
                            for &(from, e) in &path {
                                self.push(from, e, amount as i32);
                            }
                            ex[src as usize] -= amount;
                            ex[cur as usize] += amount;
                            break;
                        }
                        let end = self.start[cur as usize + 1];
                        let mut advanced = false;
                        while lc < sink_level && next_arc[cur as usize] < end {
                            let e = self.adj[next_arc[cur as usize] as usize] as usize;
                            if let Some(w) = self.residual_out(cur, e)
                                && level[w as usize] == lc + 1
                            {
                                path.push((cur, e));
                                cur = w;
                                advanced = true;
                                break;
                            }
                            next_arc[cur as usize] += 1;
                        }
                        if advanced {
                            continue;
                        }
                        // Dead end: drop the node from this phase and retreat.
                        level[cur as usize] = u32::MAX;
                        match path.pop() {
                            Some((prev, _)) => {
                                next_arc[prev as usize] += 1;
                                cur = prev;
                            }
                            None => break,
                        }
                    }
                }
            }
        }
        if let Some(node) = ex.iter().position(|&e| e != 0) {
            return Err(Infeasible { node: node as u32 });
        }
        Ok(())
    }

    fn next_stamp(&mut self) {
        if self.search.stamp == u32::MAX - 1 {
            self.search.fwd_mark.fill(0);
            self.search.bwd_mark.fill(0);
            self.search.stamp = 0;
        }
        self.search.stamp += 1;
    }

    /// If flow can leave `v` along arc `e` in the residual graph, the node it
    /// reaches.
    #[inline]
    fn residual_out(&self, v: u32, e: usize) -> Option<u32> {
        let a = &self.arcs[e];
        if a.tail == a.head {
            None // a self-loop never helps a path
        } else if a.tail == v && a.x < a.hi {
            Some(a.head)
        } else if a.head == v && a.x > a.lo {
            Some(a.tail)
        } else {
            None
        }
    }

    /// If flow can enter `v` along arc `e` in the residual graph, the node it
    /// comes from.
    #[inline]
    fn residual_in(&self, v: u32, e: usize) -> Option<u32> {
        let a = &self.arcs[e];
        if a.tail == a.head {
            None
        } else if a.head == v && a.x < a.hi {
            Some(a.tail)
        } else if a.tail == v && a.x > a.lo {
            Some(a.head)
        } else {
            None
        }
    }

    /// Residual capacity of arc `e` when traversed from `from`.
    #[inline]
    fn cap_from(&self, from: u32, e: usize) -> i32 {
        let a = &self.arcs[e];
        if a.tail == from {
            a.hi - a.x
        } else {
            a.x - a.lo
        }
    }

    /// Moves `amount` along arc `e` starting at node `from`.
    fn push(&mut self, from: u32, e: usize, amount: i32) {
        if self.journalling {
            self.journal.push(Undo {
                arc: e,
                before: self.arcs[e],
            });
        }
        let a = &mut self.arcs[e];
        if a.tail == from {
            a.x += amount;
        } else {
            a.x -= amount;
        }
    }

    /// Bottleneck of the forward-tree path ending at `v`.
    fn tree_capacity(&self, mut v: u32) -> i32 {
        let mut cap = i32::MAX;
        while self.search.fwd_via[v as usize] != NONE {
            let e = self.search.fwd_via[v as usize] as usize;
            let a = &self.arcs[e];
            let from = if a.head == v && a.tail != v {
                a.tail
            } else {
                a.head
            };
            cap = cap.min(self.cap_from(from, e));
            v = from;
        }
        cap
    }

    fn augment_forward_tree(&mut self, mut v: u32, amount: i32) {
        while self.search.fwd_via[v as usize] != NONE {
            let e = self.search.fwd_via[v as usize] as usize;
            let a = self.arcs[e];
            let from = if a.head == v && a.tail != v {
                a.tail
            } else {
                a.head
            };
            self.push(from, e, amount);
            v = from;
        }
    }

    /// Finds one augmenting path `src ⇝ dst` avoiding arc `skip` and pushes
    /// up to `limit` along it; returns the amount pushed (0: no path exists).
    fn augment(&mut self, src: u32, dst: u32, skip: usize, limit: i32) -> i32 {
        if limit <= 0 {
            return 0;
        }
        if !self.built {
            self.build();
        }
        if src == dst {
            return limit;
        }
        if let Some(got) = self.augment_short(src, dst, skip, limit) {
            return got;
        }
        self.next_stamp();
        let stamp = self.search.stamp;
        let s = &mut self.search;
        s.fwd_queue.clear();
        s.bwd_queue.clear();
        s.fwd_mark[src as usize] = stamp;
        s.fwd_via[src as usize] = NONE;
        s.bwd_mark[dst as usize] = stamp;
        s.bwd_via[dst as usize] = NONE;
        s.fwd_queue.push_back(src);
        s.bwd_queue.push_back(dst);
        let mut visited = 0usize;
        let meet = loop {
            let (fq, bq) = (self.search.fwd_queue.len(), self.search.bwd_queue.len());
            visited += 1;
            if visited > self.budget {
                self.cut_off = true;
                return 0;
            }
            if fq == 0 || bq == 0 {
                return 0;
            }
            let found = if fq <= bq {
                self.expand_forward(skip, stamp)
            } else {
                self.expand_backward(skip, stamp)
            };
            if let Some(m) = found {
                break m;
            }
        };
        // Bottleneck over both halves.
        let mut cap = limit.min(self.tree_capacity(meet));
        let mut v = meet;
        while self.search.bwd_via[v as usize] != NONE {
            let e = self.search.bwd_via[v as usize] as usize;
            cap = cap.min(self.cap_from(v, e));
            let a = &self.arcs[e];
            v = if a.tail == v { a.head } else { a.tail };
        }
        self.augment_forward_tree(meet, cap);
        let mut v = meet;
        while self.search.bwd_via[v as usize] != NONE {
            let e = self.search.bwd_via[v as usize] as usize;
            let a = self.arcs[e];
            self.push(v, e, cap);
            v = if a.tail == v { a.head } else { a.tail };
        }
        cap
    }

    /// Tries paths of at most three arcs first: in scan-line tiling almost
    /// every cycle closes around one grid vertex, and finding it this way
    /// needs no queue and no marks.
    fn augment_short(&mut self, src: u32, dst: u32, skip: usize, limit: i32) -> Option<i32> {
        let arcs_of = |v: u32| self.start[v as usize] as usize..self.start[v as usize + 1] as usize;
        let mut best: Option<ShortPath> = None;
        'outer: for k1 in arcs_of(src) {
            let e1 = self.adj[k1] as usize;
            if e1 == skip {
                continue;
            }
            let Some(n1) = self.residual_out(src, e1) else {
                continue;
            };
            let c1 = self.cap_from(src, e1);
            if n1 == dst {
                best = Some(([(src, e1), (0, 0), (0, 0)], 1, c1));
                break;
            }
            for k2 in arcs_of(n1) {
                let e2 = self.adj[k2] as usize;
                if e2 == skip || e2 == e1 {
                    continue;
                }
                let Some(n2) = self.residual_out(n1, e2) else {
                    continue;
                };
                if n2 == src {
                    continue;
                }
                let c2 = c1.min(self.cap_from(n1, e2));
                if n2 == dst {
                    best = Some(([(src, e1), (n1, e2), (0, 0)], 2, c2));
                    break 'outer;
                }
                for k3 in arcs_of(n2) {
                    let e3 = self.adj[k3] as usize;
                    if e3 == skip || e3 == e2 || e3 == e1 {
                        continue;
                    }
                    if self.residual_out(n2, e3) == Some(dst) {
                        let c3 = c2.min(self.cap_from(n2, e3));
                        best = Some(([(src, e1), (n1, e2), (n2, e3)], 3, c3));
                        break 'outer;
                    }
                }
            }
        }
        let (path, len, cap) = best?;
        let amount = cap.min(limit);
        debug_assert!(amount > 0);
        for &(from, e) in &path[..len] {
            self.push(from, e, amount);
        }
        Some(amount)
    }

    /// Expands one forward node; returns a node seen by both searches.
    fn expand_forward(&mut self, skip: usize, stamp: u32) -> Option<u32> {
        let v = self.search.fwd_queue.pop_front()?;
        for k in self.start[v as usize]..self.start[v as usize + 1] {
            let e = self.adj[k as usize] as usize;
            if e == skip {
                continue;
            }
            if let Some(w) = self.residual_out(v, e)
                && self.search.fwd_mark[w as usize] != stamp
            {
                self.search.fwd_mark[w as usize] = stamp;
                self.search.fwd_via[w as usize] = e as u32;
                if self.search.bwd_mark[w as usize] == stamp {
                    return Some(w);
                }
                self.search.fwd_queue.push_back(w);
            }
        }
        None
    }

    /// Expands one backward node; returns a node seen by both searches.
    fn expand_backward(&mut self, skip: usize, stamp: u32) -> Option<u32> {
        let v = self.search.bwd_queue.pop_front()?;
        for k in self.start[v as usize]..self.start[v as usize + 1] {
            let e = self.adj[k as usize] as usize;
            if e == skip {
                continue;
            }
            if let Some(w) = self.residual_in(v, e)
                && self.search.bwd_mark[w as usize] != stamp
            {
                self.search.bwd_mark[w as usize] = stamp;
                self.search.bwd_via[w as usize] = e as u32;
                if self.search.fwd_mark[w as usize] == stamp {
                    return Some(w);
                }
                self.search.bwd_queue.push_back(w);
            }
        }
        None
    }

    /// Pushes up to `limit` units around `cycle`, a closed walk given as
    /// (node the step leaves, arc) pairs, as far as the residual capacities
    /// allow; returns the amount pushed (0 when some step has no room). The
    /// caller supplies the cycle: a structure-aware shortcut (the tiling's
    /// ladders) that saves the general search when it applies.
    pub fn push_cycle(&mut self, cycle: &[(u32, ArcId)], limit: i32) -> i32 {
        debug_assert!(cycle.iter().enumerate().all(|(i, &(from, e))| {
            let a = &self.arcs[e];
            let to = if a.tail == from { a.head } else { a.tail };
            cycle[(i + 1) % cycle.len()].0 == to
        }));
        let mut amount = limit;
        for &(from, e) in cycle {
            amount = amount.min(self.cap_from(from, e));
        }
        if amount <= 0 {
            return 0;
        }
        for &(from, e) in cycle {
            self.push(from, e, amount);
        }
        amount
    }

    /// Residual room of arc `e` for flow leaving node `from` along it.
    pub fn room_from(&self, from: u32, e: ArcId) -> i32 {
        self.cap_from(from, e)
    }

    /// Moves the flux of arc `e` towards `target` with searches that give up
    /// after visiting `budget` nodes; returns whether one gave up (then the
    /// value reached proves nothing about feasibility). For callers that
    /// know a cheap way round when the near one is long.
    pub fn move_bounded(&mut self, e: ArcId, target: i32, budget: usize) -> bool {
        self.budget = budget;
        self.cut_off = false;
        if target > self.arcs[e].x {
            self.raise(e, target);
        } else {
            self.lower(e, target);
        }
        self.budget = usize::MAX;
        self.cut_off
    }

    /// Raises the flux of arc `e` towards `target` (at most its upper bound)
    /// keeping the circulation feasible; returns the value reached.
    pub fn raise(&mut self, e: ArcId, target: i32) -> i32 {
        let target = target.min(self.arcs[e].hi);
        if self.arcs[e].tail == self.arcs[e].head {
            self.set_self_loop(e, target.max(self.arcs[e].x));
        }
        while self.arcs[e].x < target {
            let a = self.arcs[e];
            let got = self.augment(a.head, a.tail, e, target - a.x);
            if got == 0 {
                break;
            }
            self.push(a.tail, e, got);
        }
        self.arcs[e].x
    }

    /// Lowers the flux of arc `e` towards `target` (at least its lower bound);
    /// returns the value reached.
    pub fn lower(&mut self, e: ArcId, target: i32) -> i32 {
        let target = target.max(self.arcs[e].lo);
        if self.arcs[e].tail == self.arcs[e].head {
            self.set_self_loop(e, target.min(self.arcs[e].x));
        }
        while self.arcs[e].x > target {
            let a = self.arcs[e];
            let got = self.augment(a.tail, a.head, e, a.x - target);
            if got == 0 {
                break;
            }
            self.push(a.head, e, got);
        }
        self.arcs[e].x
    }

    /// A self-loop (a periodic grid one slot wide) conserves any value.
    fn set_self_loop(&mut self, e: ArcId, value: i32) {
        if self.journalling {
            self.journal.push(Undo {
                arc: e,
                before: self.arcs[e],
            });
        }
        self.arcs[e].x = value;
    }

    /// The exact range of values arc `e` can take in a feasible circulation.
    /// Leaves the arc at its minimum.
    pub fn range(&mut self, e: ArcId) -> (i32, i32) {
        let hi = self.raise(e, i32::MAX);
        let lo = self.lower(e, i32::MIN);
        (lo, hi)
    }

    /// Moves arc `e` to `value` and clamps its bounds there. Returns false
    /// (changing nothing but fluxes) when no feasible circulation has that value.
    pub fn fix(&mut self, e: ArcId, value: i32) -> bool {
        let a = self.arcs[e];
        if value < a.lo || value > a.hi {
            return false;
        }
        if a.lo == a.hi {
            return true; // already fixed there (the fill's settled edges)
        }
        let reached = if value == a.x {
            value
        } else if value > a.x {
            self.raise(e, value)
        } else {
            self.lower(e, value)
        };
        if reached != value {
            return false;
        }
        if self.journalling {
            self.journal.push(Undo {
                arc: e,
                before: self.arcs[e],
            });
        }
        self.arcs[e].lo = value;
        self.arcs[e].hi = value;
        true
    }

    /// Keeps every change since the outermost checkpoint and stops recording.
    pub fn commit(&mut self) {
        self.journal.clear();
        self.journalling = false;
    }

    /// Starts recording changes; returns a mark for [`Network::rollback`].
    pub fn checkpoint(&mut self) -> usize {
        self.journalling = true;
        self.journal.len()
    }

    /// Undoes every change since `mark` and stops recording if it was the
    /// outermost checkpoint.
    pub fn rollback(&mut self, mark: usize) {
        while self.journal.len() > mark {
            let u = self.journal.pop().expect("journal length checked");
            self.arcs[u.arc] = u.before;
        }
        if mark == 0 {
            self.journalling = false;
        }
    }

    /// True when every bound and every conservation law holds.
    pub fn is_feasible(&self) -> bool {
        self.arcs.iter().all(|a| a.lo <= a.x && a.x <= a.hi)
            && self.imbalances().iter().all(|&e| e == 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ring 0 → 1 → 2 → 0 with a chord 0 → 2.
    fn ring() -> (Network, [ArcId; 4]) {
        let mut n = Network::new(3);
        let a = n.add_arc(0, 1, 0, 3);
        let b = n.add_arc(1, 2, -1, 2);
        let c = n.add_arc(2, 0, 1, 4);
        let d = n.add_arc(0, 2, -2, 2);
        (n, [a, b, c, d])
    }

    #[test]
    fn feasible_and_ranges() {
        let (mut n, [a, b, c, d]) = ring();
        n.make_feasible().unwrap();
        assert!(n.is_feasible());
        // a = b (node 1); c = a + d (node 0 balance), c in [1, 4].
        assert_eq!(n.range(a), (0, 2));
        assert_eq!(n.range(b), (0, 2));
        assert_eq!(n.range(c), (1, 4));
        assert_eq!(n.range(d), (-1, 2));
        assert!(n.is_feasible());
    }

    #[test]
    fn fix_and_rollback() {
        let (mut n, [a, _b, c, d]) = ring();
        n.make_feasible().unwrap();
        let mark = n.checkpoint();
        assert!(n.fix(a, 2));
        assert!(n.fix(d, 2));
        assert_eq!(n.arc(c).x, 4);
        assert!(!n.fix(c, 3));
        n.rollback(mark);
        assert!(n.is_feasible());
        assert_eq!(n.range(c), (1, 4));
    }

    #[test]
    fn infeasible_bounds_detected() {
        let mut n = Network::new(2);
        n.add_arc(0, 1, 1, 2);
        n.add_arc(0, 1, 0, 1);
        assert!(n.make_feasible().is_err());
    }
}
