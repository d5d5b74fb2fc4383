//! Reduction of the Voronoi Distance Graph (thesis ch. 4, 6.1.5;
//! docs/design/reduction.md).
//!
//! The unreduced graph has hundreds of thousands of vertices; the reduction
//! removes them one at a time, cheapest first, where the cost of a vertex is
//! the free-space volume its removal loses (4.4, volume model 4.3). A vertex
//! is removed by edge swaps that lower its edge degree (4.5) until it can be
//! taken out as a vertex with one face or with two or three faces (4.6).
//! Every operation keeps the conditions of 4.2: A — the described free space
//! never grows (proven per operation, see the `swap` module, and checked in
//! debug builds); B, C — topology and connected components are kept, and
//! non-manifold edges are never swapped.
//!
//! Speed (the thesis needed 19 min to 1 h 50 min per map): adjacency is a
//! face list per vertex; costing a vertex runs its removal on a read-only
//! overlay (`mesh::Edit`), so all initial costs are computed in parallel
//! with rayon, and the main loop works in batches: the 64 cheapest queued
//! vertices that lie more than three edges apart (so that no removal reads
//! what another one writes) are costed in parallel, then applied one by
//! one in heap order, while the next batch is picked. A lazy-deletion
//! heap holds the costs; after a removal the changed neighbours are only
//! marked, and a popped vertex whose fresh cost exceeds the next key goes
//! back into the heap (with its result, reused if its two-ring is still
//! unchanged when it comes up again). Within a removal the candidate swaps
//! are evaluated by branch and bound (see `swap::Candidates::best`), and
//! face shapes and volumes are cached. Ties break by vertex id and the
//! batch size is fixed, so the output is byte-identical for any thread
//! count.
//!
//! Deviations from the thesis, all conservative: the clearance bound at the
//! foot point `q` is the exact face clearance (never less than the thesis'
//! `c_p − d`); a swap may not create an edge that exists unless it merges
//! into an existing face on a seam of sheets; an isolated face is kept (it
//! is a connected component); vertices with more than 20 neighbours wait
//! until their degree drops; nearly parallel edge pairs are skipped instead
//! of "jerking" a vertex. Not conservative but deliberate: the face volume
//! is the thesis formula as printed (a full cylinder per edge and face) and
//! the cost of an operation is the magnitude of the model volume change,
//! never negative (see `volume::loss`). Before stopping for want of
//! removable vertices all vertices are costed once more (a change two
//! rings away can make a vertex removable without re-queuing it).
//!
//! Not in the thesis: a second phase for the vertices the thesis' cases
//! cannot remove (seam and border vertices, a few per cent of the graph on
//! most maps): when the loop stops with nothing removable above the
//! limit, it goes on with three more operations that keep A–C, the seam
//! contraction and the collapse along an edge (module `seam`, which gives
//! their design and proofs) and the fan removal for border vertices and
//! the corners where a seam ends at its sheets' borders (module `border`).
//! A map the thesis' cases reduce to the limit gets the same graph as
//! without them.
//!
//! Not in the thesis, and off in [`ReduceOptions::new`]: the queue may order
//! by the lost volume divided by the removed vertex's clearance squared
//! ([`ReductionCost::Relative`], the compiler's default), so the small
//! vertices near the walls go last.
//!
//! Not in the thesis: after the loop the clearances the operations lowered
//! are raised again as far as condition A against the unreduced volume
//! allows (the `raise` module; the per-operation proofs lower more than
//! needed, and the lowerings compound), unless [`ReduceOptions::raise`] is
//! off (the compiler raises towards the walls instead).

mod border;
// The per-operation check of condition A: debug builds run it on every
// removal, and the tests use it in release builds too.
#[cfg(any(debug_assertions, test))]
mod check;
mod keep;
mod mesh;
mod options;
mod queue;
mod raise_back;
mod remove;
mod seam;
mod stats;
mod swap;
mod volume;

use std::time::{Duration, Instant};

use rayon::prelude::*;

pub use options::{ReduceOptions, ReductionCost};
pub use stats::{RaisedBack, ReduceStats, StopReason, Tick};

use crate::graph::Graph;
use crate::progress::{Progress, Ticker};
use keep::{KEEP_MARGIN, Keep};
use mesh::{Changes, Edit, Mesh, Op};
use queue::CostQueue;
use remove::Refusal;

/// Reduces `graph` (see the module docs).
///
/// ```
/// use bsp2vdg::reduce::{reduce, ReduceOptions};
/// use bsp2vdg::graph::Graph;
/// // A flat 4x4 grid of squares split into triangles, clearance 8.
/// let n = 5;
/// let mut g = Graph { vertices: vec![], clearance: vec![], faces: vec![] };
/// for y in 0..n { for x in 0..n { g.vertices.push([x as f64 * 10.0, y as f64 * 10.0, 0.0]); g.clearance.push(8.0); } }
/// for y in 0..n - 1 { for x in 0..n - 1 {
///     let v = (y * n + x) as u32;
///     g.faces.push([v, v + 1, v + n as u32]);
///     g.faces.push([v + 1, v + n as u32 + 1, v + n as u32]);
/// } }
/// let (r, stats) = reduce(&g, &ReduceOptions::new(0.2), &bsp2vdg::progress::NoProgress);
/// assert!(r.vertices.len() < g.vertices.len());
/// assert_eq!(stats.vertices_after, r.vertices.len());
/// ```
pub fn reduce(
    graph: &Graph,
    options: &ReduceOptions,
    progress: &dyn Progress,
) -> (Graph, ReduceStats) {
    reduce_with_ticks(graph, options, progress, &mut |_| {})
}

/// [`reduce`] calling `tick` about once a second with the state so far.
pub fn reduce_with_ticks(
    graph: &Graph,
    options: &ReduceOptions,
    progress: &dyn Progress,
    tick: &mut dyn FnMut(&Tick),
) -> (Graph, ReduceStats) {
    reduce_keeping(graph, options, &[], progress, tick)
}

/// [`reduce_with_ticks`] keeping the points of `keep` that the graph's volume
/// contains inside the reduced volume (e.g. where a standing player is, see
/// [`crate::standing`]), each with a ball of `KEEP_MARGIN` (8 units) around it
/// where the unreduced volume holds one: a removal that would take one out is refused, so
/// the reduction may stop above the limit.
pub fn reduce_keeping(
    graph: &Graph,
    options: &ReduceOptions,
    keep: &[[f64; 3]],
    progress: &dyn Progress,
    tick: &mut dyn FnMut(&Tick),
) -> (Graph, ReduceStats) {
    // The main loop forks a parallel batch tens of thousands of times; from
    // a thread outside the pool each fork wakes a worker and puts the caller
    // to sleep. So the loop runs on a worker, and its ticks come back to
    // this thread.
    let ordered = in_hilbert_order(graph);
    let graph = &ordered;
    let (mut mesh, mut stats, ops) = if rayon::current_thread_index().is_some() {
        run(graph, options, keep, progress, tick)
    } else {
        let (tx, rx) = std::sync::mpsc::channel::<Tick>();
        std::thread::scope(|s| {
            let worker = s.spawn(move || {
                rayon::scope(|_| {
                    run(graph, options, keep, progress, &mut |t| {
                        let _ = tx.send(*t);
                    })
                })
            });
            for t in rx {
                tick(&t);
            }
            worker
                .join()
                .unwrap_or_else(|e| std::panic::resume_unwind(e))
        })
    };
    stats.swaps = ops[Op::Swap as usize] as usize;
    stats.one_face = ops[Op::OneFace as usize] as usize;
    stats.three_faces = ops[Op::ThreeFaces as usize] as usize;
    stats.three_faces_existing = ops[Op::ThreeFacesExisting as usize] as usize;
    stats.two_faces_concave = ops[Op::TwoFacesConcave as usize] as usize;
    stats.seam_contractions = ops[Op::SeamContract as usize] as usize;
    stats.seam_collapses = ops[Op::SeamCollapse as usize] as usize;
    stats.fan_removals = ops[Op::FanRemove as usize] as usize;
    if stats.stop == StopReason::NothingRemovable {
        stats.refusals = histogram(&mesh);
        if std::env::var_os("BSP2VDG_REDUCE_REFUSALS").is_some() {
            toolbox::errln!(
                "reduce: refusals of the {} vertices left:",
                mesh.live_vertices()
            );
            for (name, n) in &stats.refusals {
                toolbox::errln!("  {name:<30} {n}");
            }
            let mut classes = std::collections::BTreeMap::<String, usize>::new();
            for v in 0..mesh.pos.len() as u32 {
                if mesh.vfaces[v as usize].is_empty() {
                    continue;
                }
                let e = Edit::new(&mesh);
                let why = remove::remove_vertex_why(&mut Edit::new(&mesh), v)
                    .err()
                    .map_or("removable", |r| r.as_str());
                *classes
                    .entry(format!("{} {}", seam::describe(&e, v), why))
                    .or_default() += 1;
            }
            let mut classes: Vec<_> = classes.into_iter().collect();
            classes.sort_by_key(|c| std::cmp::Reverse(c.1));
            for (name, n) in classes.iter().take(40) {
                toolbox::errln!("  {name:<50} {n}");
            }
        }
    }
    if options.raise {
        let t = Instant::now();
        // The raise needs the unreduced graph with the mesh's vertex ids.
        let raised = raise_back::raise(graph, &mut mesh);
        stats.raised_back = Some(RaisedBack {
            vertices: raised.raised,
            total: raised.total,
            seconds: t.elapsed().as_secs_f64(),
        });
    }
    let out = mesh.to_graph();
    stats.vertices_after = out.vertices.len();
    stats.faces_after = out.faces.len();
    (out, stats)
}

/// The reduction proper, on `graph` in Hilbert order (see
/// [`in_hilbert_order`]): the mesh at the end, the statistics so far and
/// the operation counts.
///
/// One function on purpose: every step of the main loop — picking a batch while the
/// previous one is costed, committing it in heap order, putting risen costs back,
/// the sweeps before giving up, the switch to the seam phase, the ticks — reads and
/// writes the same state (the mesh, the queue, the claims, the epochs, the
/// timers); split up, each piece would take most of it as arguments. The phases
/// are marked by comments.
fn run(
    graph: &Graph,
    options: &ReduceOptions,
    keep: &[[f64; 3]],
    progress: &dyn Progress,
    tick: &mut dyn FnMut(&Tick),
) -> (Mesh, ReduceStats, [u64; Op::COUNT]) {
    let start = Instant::now();
    let mut mesh = Mesh::new(graph);
    mesh.cost = options.cost;
    let guards = options.coverage_guards;
    let mut kept = (guards && !keep.is_empty()).then(|| Keep::new(&mesh, keep, KEEP_MARGIN));
    let keeping = kept.as_ref().map_or(0, Keep::len);
    let mut live = mesh.live_vertices();
    let mut faces = mesh.live_faces();
    let mut stats = ReduceStats {
        vertices_before: live,
        faces_before: faces,
        target: options.target(live),
        cost: options.cost,
        kept_points: keeping,
        ..ReduceStats::default()
    };
    let mut queue = CostQueue::new(mesh.pos.len());
    // The work reported: every vertex's first costing, then every vertex removed.
    let removals = live.saturating_sub(stats.target) as u64;
    progress.start("Reduce", mesh.pos.len() as u64 + removals);
    let ticker = Ticker::within(progress, Ticker::BLOCK);
    let initial: Vec<Option<f64>> = (0..mesh.pos.len() as u32)
        .into_par_iter()
        .map_init(
            || ticker.local(),
            |done, v| {
                done.tick();
                cost_of(&mesh, kept.as_ref(), None, v)
            },
        )
        .collect();
    // Per vertex, the removal after which its costing last found it not
    // removable (`NOT_REFUSED` if it did not): the sweeps below skip it while
    // nothing within its two rings changed since, as the batches reuse results.
    let mut refused_at = vec![NOT_REFUSED; mesh.pos.len()];
    for (v, c) in initial.into_iter().enumerate() {
        if c.is_none() {
            refused_at[v] = 0;
        }
        queue.set(v as u32, c);
    }
    stats.seconds_initial = start.elapsed().as_secs_f64();
    let mut last_tick = Instant::now();
    let mut ops = [0u64; Op::COUNT];
    stats.stop = if options.floor_sets_target(live) {
        StopReason::FloorReached
    } else {
        StopReason::LimitReached
    };
    // Removals applied so far, and per vertex the removal that last changed
    // its faces or clearance: a result computed after removal `e` is still
    // valid while nothing within two rings of its vertex changed after `e`.
    let mut epoch = 0u32;
    let mut changed_at = vec![0u32; mesh.pos.len()];
    // Results of vertices put back into the queue because their fresh cost
    // exceeded the next key: when popped again with an unchanged
    // neighbourhood they are applied without costing them again.
    let mut saved: Vec<Option<Box<Costed>>> = Vec::new();
    saved.resize_with(mesh.pos.len(), || None);
    let mut removals_at_sweep = usize::MAX;
    let mut seam_start: Option<Instant> = None;
    // The second phase's deep points (see `deep_points`).
    let mut deep: Option<Keep> = None;
    let mut claims = Claims::new(mesh.pos.len());
    // The batches: the cheapest vertices whose removals cannot interact
    // (see `Claims`), costed in parallel against the same mesh and committed
    // one by one in heap order. While one batch is costed the next one is
    // picked, away from the first one's claims, so that picking costs no
    // time on two threads. Batch sizes and order are fixed, so the output
    // does not depend on the thread count.
    let mut following = claims.select(&mut queue, &mesh);
    'outer: while live > stats.target {
        let mut batch = std::mem::take(&mut following);
        if batch.is_empty() {
            // The last commits may have queued vertices after the batch
            // was picked.
            batch = claims.select(&mut queue, &mesh);
        }
        if batch.is_empty() {
            // Only vertices whose own faces or clearance changed are
            // re-queued, but a change two rings away can make a refused
            // vertex removable: before giving up, cost every vertex again.
            if stats.removals == removals_at_sweep {
                if !mesh.seam_ops {
                    // Second phase: the thesis' cases are exhausted; the
                    // seam operations may take the vertices left.
                    mesh.seam_ops = true;
                    // The second phase removes what the first refused.
                    refused_at.fill(NOT_REFUSED);
                    deep = guards.then(|| deep_points(graph, &mesh));
                    stats.seam_deep_points = deep.as_ref().map_or(0, Keep::len);
                    stats.seam_phase_at = Some(live);
                    seam_start = Some(Instant::now());
                    removals_at_sweep = usize::MAX;
                    continue;
                }
                stats.stop = StopReason::NothingRemovable;
                break;
            }
            removals_at_sweep = stats.removals;
            let sweep_start = Instant::now();
            let costs: Vec<Option<Option<f64>>> = (0..mesh.pos.len() as u32)
                .into_par_iter()
                .map(|v| {
                    let at = refused_at[v as usize];
                    // A refusal stands while the two rings it read are as they were.
                    (at == NOT_REFUSED || !unchanged_since(&mesh, v, &changed_at, at))
                        .then(|| cost_of(&mesh, kept.as_ref(), deep.as_ref(), v))
                })
                .collect();
            stats.sweeps += 1;
            for (v, c) in costs.into_iter().enumerate() {
                match c {
                    None => stats.sweep_skipped += 1,
                    Some(None) => refused_at[v] = epoch,
                    Some(c @ Some(_)) => {
                        refused_at[v] = NOT_REFUSED;
                        queue.set(v as u32, c);
                        saved[v] = None;
                    }
                }
            }
            stats.seconds_sweeps += sweep_start.elapsed().as_secs_f64();
            continue;
        }
        let mut results: Vec<Option<Box<Costed>>> = batch
            .iter()
            .map(|&(v, _)| {
                saved[v as usize]
                    .take()
                    .filter(|c| unchanged_since(&mesh, v, &changed_at, c.epoch))
            })
            .collect();
        let batch_epoch = epoch;
        stats.batches += 1;
        stats.costed += results.iter().filter(|r| r.is_none()).count();
        let costing = Instant::now();
        let (fresh, next_batch) = rayon::join(
            || {
                batch
                    .par_iter()
                    .zip(&results)
                    .map(|(&(v, _), r)| match r {
                        Some(_) => None,
                        None => costed(&mesh, kept.as_ref(), deep.as_ref(), v, batch_epoch),
                    })
                    .collect::<Vec<Option<Box<Costed>>>>()
            },
            || {
                let t = Instant::now();
                let next = claims.select(&mut queue, &mesh);
                (next, t.elapsed().as_secs_f64())
            },
        );
        following = next_batch.0;
        stats.seconds_picking += next_batch.1;
        stats.seconds_batches += costing.elapsed().as_secs_f64();
        let committing = Instant::now();
        for ((r, f), &(v, _)) in results.iter_mut().zip(fresh).zip(&batch) {
            if r.is_none() {
                refused_at[v as usize] = if f.is_none() {
                    batch_epoch
                } else {
                    NOT_REFUSED
                };
                *r = f;
            }
        }
        let keys: Vec<u64> = batch.iter().map(|x| x.1).collect();
        for (i, (&(v, key), res)) in batch.iter().zip(results).enumerate() {
            if live <= stats.target {
                for &(u, k) in batch[i..].iter().chain(&following) {
                    queue.push_key(u, k);
                }
                stats.seconds_commits += committing.elapsed().as_secs_f64();
                break 'outer;
            }
            let Some(c) = res else {
                continue; // not removable now; re-costed when its neighbourhood changes
            };
            // The batch's vertices are independent (see `Claims`): the
            // commits before this one left its two-ring as it was.
            debug_assert!(unchanged_since(&mesh, v, &changed_at, c.epoch));
            // Lazy re-evaluation: the stored cost may be stale (only the
            // direct neighbours are marked after a removal).
            let now = CostQueue::key_of(c.cost);
            let next = keys[i + 1..]
                .iter()
                .chain(following.first().map(|x| &x.1))
                .copied()
                .chain(queue.peek_key())
                .min();
            if now > key && next.is_some_and(|top| now > top) {
                queue.push_back(v, c.cost);
                stats.requeued += 1;
                saved[v as usize] = Some(c);
                continue;
            }
            let Costed {
                cost,
                volume,
                changes: ch,
                ..
            } = *c;
            let touched = ch.touched();
            epoch += 1;
            for &t in &touched {
                changed_at[t as usize] = epoch;
            }
            let before: usize = touched
                .iter()
                .filter(|&&t| !mesh.vfaces[t as usize].is_empty())
                .count();
            for (o, n) in ops.iter_mut().zip(ch.ops) {
                *o += u64::from(n);
            }
            let dead_faces = ch.removed.len();
            let new_faces = ch.new_faces.len();
            let at_risk = kept
                .as_ref()
                .map(|k| k.before_apply(&ch, &mesh))
                .unwrap_or_default();
            let deep_at_risk = deep
                .as_ref()
                .map(|k| k.before_apply(&ch, &mesh))
                .unwrap_or_default();
            let first_new = mesh.faces.len() as u32;
            mesh.apply(ch);
            if let Some(k) = kept.as_mut() {
                k.rehome(&mesh, &at_risk, first_new, &touched);
            }
            if let Some(k) = deep.as_mut() {
                k.rehome(&mesh, &deep_at_risk, first_new, &touched);
            }
            let after: usize = touched
                .iter()
                .filter(|&&t| !mesh.vfaces[t as usize].is_empty())
                .count();
            let gone = before - after;
            live -= gone;
            faces = faces + new_faces - dead_faces;
            stats.removals += 1;
            stats.lost_volume += volume;
            progress.advance(gone as u64);
            for &t in &touched {
                if mesh.vfaces[t as usize].is_empty() {
                    queue.set(t, None);
                    saved[t as usize] = None;
                } else {
                    queue.mark_dirty(t);
                }
            }
            if last_tick.elapsed() >= Duration::from_secs(1) {
                last_tick = Instant::now();
                tick(&Tick {
                    seconds: start.elapsed().as_secs_f64(),
                    vertices: live,
                    faces,
                    cost,
                    reduction: live as f64 / stats.vertices_before.max(1) as f64,
                });
            }
        }
        stats.seconds_commits += committing.elapsed().as_secs_f64();
    }
    progress.finish();
    stats.seam_phase_seconds = seam_start.map_or(0.0, |t| t.elapsed().as_secs_f64());
    stats.seconds_rest =
        start.elapsed().as_secs_f64() - stats.seconds_initial - stats.seconds_batches;
    (mesh, stats, ops)
}

/// `graph` with its vertices in Hilbert order and its faces by their first
/// vertex: a removal reads a few hundred vertices and faces around one
/// spot, and with neighbours close in memory it waits for far fewer cache
/// misses (the input order, from the tetrahedra, scatters a tenth of the
/// edges across the whole array).
fn in_hilbert_order(graph: &Graph) -> Graph {
    let keys = crate::delaunay::sort::hilbert_keys(&graph.vertices);
    let mut order: Vec<u32> = (0..graph.vertices.len() as u32).collect();
    order.par_sort_unstable_by_key(|&v| (keys[v as usize], v));
    let mut id = vec![0u32; order.len()];
    for (i, &v) in order.iter().enumerate() {
        id[v as usize] = i as u32;
    }
    let mut faces: Vec<[u32; 3]> = graph
        .faces
        .iter()
        .map(|f| f.map(|v| id.get(v as usize).copied().unwrap_or(u32::MAX)))
        .collect();
    faces.par_sort_by_key(|f| (f.iter().min().copied(), *f));
    Graph {
        vertices: order.iter().map(|&v| graph.vertices[v as usize]).collect(),
        clearance: order.iter().map(|&v| graph.clearance[v as usize]).collect(),
        faces,
    }
}

/// Why the vertices of `graph` cannot be removed right now: per refusal
/// reason (the first condition that fails for a vertex, see the `remove`
/// module), the number of vertices, largest first; vertices that can be
/// removed are counted as `"removable"`. A diagnostic for the reduction
/// stopping early; costs one removal attempt per vertex.
///
/// ```
/// use bsp2vdg::reduce::refusals;
/// use bsp2vdg::graph::Graph;
/// // A single face is a connected component of its own: never removed.
/// let g = Graph {
///     vertices: vec![[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0]],
///     clearance: vec![4.0; 3],
///     faces: vec![[0, 1, 2]],
/// };
/// assert_eq!(refusals(&g), vec![("isolated_face", 3)]);
/// ```
pub fn refusals(graph: &Graph) -> Vec<(&'static str, usize)> {
    let mut mesh = Mesh::new(graph);
    mesh.seam_ops = true;
    histogram(&mesh)
}

fn histogram(mesh: &Mesh) -> Vec<(&'static str, usize)> {
    let why: Vec<Option<Refusal>> = (0..mesh.pos.len() as u32)
        .into_par_iter()
        .map(|v| {
            let mut e = Edit::new(mesh);
            remove::remove_vertex_why(&mut e, v).err()
        })
        .collect();
    let mut n = [0usize; Refusal::COUNT];
    let mut removable = 0;
    for w in why {
        match w {
            Some(r) => n[r as usize] += 1,
            None => removable += 1,
        }
    }
    let mut out: Vec<(&'static str, usize)> = Refusal::ALL
        .iter()
        .filter(|&&r| r != Refusal::Dead)
        .map(|&r| (r.as_str(), n[r as usize]))
        .chain(std::iter::once(("removable", removable)))
        .filter(|x| x.1 > 0)
        .collect();
    out.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    out
}

/// Vertices costed together per step of the main loop: enough work per
/// parallel fork that waking the other threads pays off.
const BATCH: usize = 64;

/// How many queue entries a batch looks at before it settles for fewer
/// than [`BATCH`] vertices.
const BATCH_SCAN: usize = 4 * BATCH;

/// [`run`]'s mark of a vertex whose last costing did not refuse it.
const NOT_REFUSED: u32 = u32::MAX;

/// Picks batches of vertices whose removals are independent: a removal
/// changes only the faces and clearances of its vertex's closed one-ring
/// and reads only its closed two-ring (the rings `unchanged_since`
/// checks), so two vertices more than three edges apart can be costed
/// against the same mesh and committed in any order with the same result.
/// A batch claims the closed two-rings of its vertices; a vertex whose
/// closed one-ring meets a claim is within three edges of a cheaper one
/// of the batch, goes back into the queue with its key and leads the next
/// batch.
struct Claims {
    /// Per vertex, the number of the batch that last claimed it.
    claimed: Vec<u32>,
    batch: u32,
    clashed: Vec<(u32, u64)>,
    /// Scratch: a closed one-ring, the faces of its vertices and theirs.
    ring: Vec<u32>,
    ring_faces: Vec<u32>,
    two_ring: Vec<u32>,
}

impl Claims {
    fn new(vertices: usize) -> Claims {
        Claims {
            claimed: vec![0; vertices],
            batch: 1,
            clashed: Vec::new(),
            ring: Vec::new(),
            ring_faces: Vec::new(),
            two_ring: Vec::new(),
        }
    }

    /// Pops the next batch, cheapest first, from `queue`, away from the
    /// claims of this batch and of the one before (which is being costed
    /// while this one is picked).
    fn select(&mut self, queue: &mut CostQueue, mesh: &Mesh) -> Vec<(u32, u64)> {
        self.batch += 1;
        let b = self.batch;
        let mut out = Vec::with_capacity(BATCH);
        let mut looked = 0;
        while out.len() < BATCH && looked < BATCH_SCAN {
            let Some((v, key)) = queue.pop() else { break };
            looked += 1;
            self.ring.clear();
            for &f in &mesh.vfaces[v as usize] {
                self.ring.extend(mesh.faces[f as usize]);
            }
            if self.ring.iter().any(|&u| self.claimed[u as usize] >= b - 1) {
                self.clashed.push((v, key));
                continue;
            }
            self.ring.sort_unstable();
            self.ring.dedup();
            // The two rings in three flat passes (face lists, faces, marks)
            // rather than one nested loop: the loads of a pass do not wait
            // for each other, and this walk waits on memory, not arithmetic.
            self.ring_faces.clear();
            for &u in &self.ring {
                self.ring_faces.extend_from_slice(&mesh.vfaces[u as usize]);
            }
            self.two_ring.clear();
            for &f in &self.ring_faces {
                self.two_ring.extend(mesh.faces[f as usize]);
            }
            for &w in &self.two_ring {
                self.claimed[w as usize] = b;
            }
            out.push((v, key));
        }
        queue.put_back(self.clashed.drain(..));
        out
    }
}

/// Cost of removing `v` from the mesh as it is, `None` if impossible (or if
/// it would leave a kept point outside the volume).
fn cost_of(mesh: &Mesh, keep: Option<&Keep>, deep: Option<&Keep>, v: u32) -> Option<f64> {
    removal(mesh, keep, deep, v).map(|x| ordered_cost(mesh, v, x.0))
}

/// The cost the queue orders by: `volume` as the options say (the mesh
/// carries [`ReduceOptions::cost`]).
fn ordered_cost(mesh: &Mesh, v: u32, volume: f64) -> f64 {
    mesh.cost.of(volume, mesh.clearance[v as usize])
}

/// The deep points of the second phase: every vertex of the unreduced graph
/// whose ball reaches deeper than [`seam::DEEP_CLEARANCE`], keeping its ball
/// shrunk by that clearance (or what the volume holds of it when the phase
/// begins) inside the volume. The points of clearance ≥ `DEEP_CLEARANCE` (the
/// coverage `vdgview check` measures) are about the union of those shrunk
/// balls (the free space is the union of its medial balls), so the second
/// phase loses next to no coverage: where coverage and ratio conflict,
/// coverage wins.
fn deep_points(graph: &Graph, mesh: &Mesh) -> Keep {
    let (points, reach): (Vec<[f64; 3]>, Vec<f64>) = graph
        .vertices
        .iter()
        .zip(&graph.clearance)
        .filter(|&(_, &r)| r > seam::DEEP_CLEARANCE)
        .map(|(&p, &r)| (p, r - seam::DEEP_CLEARANCE))
        .unzip();
    Keep::deep(mesh, &points, &reach)
}

/// The removal of `v`: the thesis' (module `remove`, with the seam
/// operations as its fallback) if it keeps the kept points inside the
/// volume, else the cheapest collapse of `v` along one of its edges that
/// does (module `seam`): where keeping the points and reducing conflict,
/// an operation that takes less volume near them may still be allowed.
fn removal<'m>(
    mesh: &'m Mesh,
    keep: Option<&Keep>,
    deep: Option<&Keep>,
    v: u32,
) -> Option<(f64, Edit<'m>)> {
    if mesh.vfaces[v as usize].is_empty() {
        return None;
    }
    let mut e = Edit::new(mesh);
    let cost = remove::remove_vertex(&mut e, v)?;
    let holds = |e: &Edit| keep.is_none_or(|k| k.holds(e)) && deep.is_none_or(|d| d.holds(e));
    if holds(&e) {
        return Some((cost, e));
    }
    if !mesh.seam_ops {
        return None;
    }
    let mut best: Option<(f64, Edit<'m>)> = None;
    let nb = Edit::new(mesh).neighbours(v);
    for &s in &nb {
        let mut t = Edit::new(mesh);
        if let Ok(c) = seam::collapse(&mut t, v, s, &nb)
            && best.as_ref().is_none_or(|b| c < b.0)
            && holds(&t)
        {
            best = Some((c, t));
        }
    }
    let mut t = Edit::new(mesh);
    if let Ok(c) = border::remove(&mut t, v)
        && best.as_ref().is_none_or(|b| c < b.0)
        && holds(&t)
    {
        best = Some((c, t));
    }
    best
}

/// A removal costed on an overlay of the mesh as it was after removal
/// `epoch` of the main loop.
struct Costed {
    epoch: u32,
    /// The queue's key ([`ReduceOptions::cost`]) and the model volume lost.
    cost: f64,
    volume: f64,
    changes: Changes,
}

/// Removes `v` on an overlay of the mesh: its cost and changes.
fn costed(
    mesh: &Mesh,
    keep: Option<&Keep>,
    deep: Option<&Keep>,
    v: u32,
    epoch: u32,
) -> Option<Box<Costed>> {
    let (volume, e) = removal(mesh, keep, deep, v)?;
    Some(Box::new(Costed {
        epoch,
        cost: ordered_cost(mesh, v, volume),
        volume,
        changes: e.into_changes(),
    }))
}

/// Whether no vertex within two rings of `v` (whose face lists and
/// clearances a removal of `v` reads) changed after removal `epoch`.
/// The rings of the current mesh suffice: if they differ from the rings
/// at `epoch`, a face list within one ring changed and with it a vertex.
fn unchanged_since(mesh: &Mesh, v: u32, changed_at: &[u32], epoch: u32) -> bool {
    let fresh = |u: u32| changed_at[u as usize] <= epoch;
    fresh(v)
        && mesh.vfaces[v as usize].iter().all(|&f| {
            mesh.faces[f as usize].iter().all(|&u| {
                fresh(u)
                    && mesh.vfaces[u as usize]
                        .iter()
                        .all(|&g| mesh.faces[g as usize].iter().all(|&w| fresh(w)))
            })
        })
}

/// An `n`×`n` grid of vertices (row by row; `at(x, y)` gives position and
/// clearance) cut into two triangles per square: the sheets the tests
/// reduce.
#[cfg(test)]
pub(crate) fn grid_sheet(n: usize, mut at: impl FnMut(usize, usize) -> ([f64; 3], f64)) -> Graph {
    let mut g = Graph::default();
    for y in 0..n {
        for x in 0..n {
            let (p, c) = at(x, y);
            g.vertices.push(p);
            g.clearance.push(c);
        }
    }
    let id = |x: usize, y: usize| (y * n + x) as u32;
    for y in 0..n.saturating_sub(1) {
        for x in 0..n - 1 {
            g.faces.push([id(x, y), id(x + 1, y), id(x, y + 1)]);
            g.faces.push([id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)]);
        }
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::NoProgress;
    use toolbox::SplitMix64;

    /// A wavy sheet with a fin standing on it along x = 5 (a seam of three
    /// sheets), varying clearances: swaps, merges and all removal cases occur.
    fn sheet(n: usize, seed: u64) -> Graph {
        let mut rng = SplitMix64::new(seed);
        let mut g = grid_sheet(n, |x, y| {
            let z = (x as f64 * 0.7).sin() * 3.0 + rng.range(-0.5, 0.5);
            ([x as f64 * 10.0, y as f64 * 10.0, z], rng.range(6.0, 12.0))
        });
        let id = |x: usize, y: usize| (y * n + x) as u32;
        // The fin: a strip above the line x = 5.
        let base = g.vertices.len() as u32;
        for y in 0..n {
            g.vertices.push([50.0, y as f64 * 10.0, 12.0]);
            g.clearance.push(rng.range(6.0, 12.0));
        }
        for y in 0..n - 1 {
            let (a, b) = (id(5, y), id(5, y + 1));
            let (c, d) = (base + y as u32, base + y as u32 + 1);
            g.faces.push([a, b, c]);
            g.faces.push([b, d, c]);
        }
        g
    }

    /// Whether `p` lies in the volume of some face of `g`.
    fn inside(g: &Graph, p: [f64; 3]) -> bool {
        g.faces.iter().any(|t| {
            let balls = t.map(|v| (g.vertices[v as usize], g.clearance[v as usize]));
            vdgformat::triangle_clearance(balls, p) > 0.0
        })
    }

    #[test]
    fn kept_points_stay_inside_the_volume() {
        // Ten times the sheet: the kept points' balls (`KEEP_MARGIN`, 8 units)
        // are small against its clearances, as on real maps.
        let mut g = sheet(14, 5);
        for p in &mut g.vertices {
            *p = p.map(|c| c * 10.0);
        }
        for r in &mut g.clearance {
            *r *= 10.0;
        }
        let mut rng = SplitMix64::new(9);
        // Points near the top of the volume, where lowered clearances lose them.
        let keep: Vec<[f64; 3]> = (0..100)
            .map(|_| {
                [
                    rng.range(0.0, 1300.0),
                    rng.range(0.0, 1300.0),
                    rng.range(40.0, 90.0),
                ]
            })
            .filter(|&p| inside(&g, p))
            .collect();
        assert!(keep.len() > 25);
        let options = ReduceOptions::new(0.0);
        let (plain, _) = reduce(&g, &options, &NoProgress);
        let lost = keep.iter().filter(|&&p| !inside(&plain, p)).count();
        assert!(
            lost > 0,
            "the plain reduction keeps every point: the test shows nothing"
        );
        let (kept, stats) = reduce_keeping(&g, &options, &keep, &NoProgress, &mut |_| {});
        assert_eq!(stats.kept_points, keep.len());
        let lost_kept: Vec<_> = keep.iter().filter(|&&p| !inside(&kept, p)).collect();
        assert!(
            lost_kept.is_empty(),
            "{} lost: {lost_kept:?}",
            lost_kept.len()
        );
        assert!(
            kept.vertices.len() < g.vertices.len() / 2,
            "{}",
            kept.vertices.len()
        );
        assert!(kept.vertices.len() > plain.vertices.len());
    }

    fn components(g: &Graph) -> usize {
        let mut parent: Vec<usize> = (0..g.vertices.len()).collect();
        fn find(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        for f in &g.faces {
            let a = find(&mut parent, f[0] as usize);
            for &v in &f[1..] {
                let b = find(&mut parent, v as usize);
                parent[b] = a;
            }
        }
        let mut used = vec![false; g.vertices.len()];
        for f in &g.faces {
            for &v in f {
                used[v as usize] = true;
            }
        }
        (0..g.vertices.len())
            .filter(|&v| used[v] && find(&mut parent, v) == v)
            .count()
    }

    #[test]
    fn reduces_a_sheet_keeping_components_and_never_growing_clearance() {
        let g = sheet(12, 7);
        let (r, s) = reduce(&g, &ReduceOptions::new(0.05), &NoProgress);
        assert!(s.vertices_after * 3 < s.vertices_before, "{s:?}");
        assert!(
            s.swaps > 0 && s.one_face + s.three_faces + s.two_faces_concave > 0,
            "{s:?}"
        );
        assert_eq!(components(&r), components(&g));
        // Every kept vertex is an original one with at most its old clearance
        // (condition A per operation is asserted inside `Mesh::apply`).
        for (p, &c) in r.vertices.iter().zip(&r.clearance) {
            let i = g
                .vertices
                .iter()
                .position(|q| q == p)
                .expect("an original vertex");
            assert!(c <= g.clearance[i]);
        }
        // The limit is respected or nothing more could go.
        match s.stop {
            StopReason::LimitReached | StopReason::FloorReached => {
                assert!(s.vertices_after <= s.target + 2)
            }
            StopReason::NothingRemovable => assert!(s.vertices_after > s.target),
        }
    }

    #[test]
    fn stops_only_when_no_vertex_is_removable() {
        for seed in 1..=12 {
            let g = sheet(16, seed);
            let (_, s) = reduce(&g, &ReduceOptions::new(0.0), &NoProgress);
            assert_eq!(s.stop, StopReason::NothingRemovable);
            // Taken when the loop stopped: the raise afterwards (the
            // `raise` module) can give a vertex room for a swap again.
            assert!(
                !s.refusals.iter().any(|x| x.0 == "removable"),
                "{:?}",
                s.refusals
            );
            assert!(s.lost_volume >= 0.0);
        }
    }

    /// Face-adjacency distances from `v` (u32::MAX: unreachable).
    fn distances(mesh: &Mesh, v: u32) -> Vec<u32> {
        let mut d = vec![u32::MAX; mesh.pos.len()];
        d[v as usize] = 0;
        let mut todo = std::collections::VecDeque::from([v]);
        while let Some(u) = todo.pop_front() {
            for &f in &mesh.vfaces[u as usize] {
                for w in mesh.faces[f as usize] {
                    if d[w as usize] == u32::MAX {
                        d[w as usize] = d[u as usize] + 1;
                        todo.push_back(w);
                    }
                }
            }
        }
        d
    }

    #[test]
    fn batches_are_cheapest_first_and_more_than_three_edges_apart() {
        let g = sheet(80, 5);
        let mesh = Mesh::new(&g);
        let mut queue = CostQueue::new(mesh.pos.len());
        let mut rng = SplitMix64::new(9);
        for v in 0..mesh.pos.len() as u32 {
            queue.set(v, Some(rng.range(0.0, 1.0)));
        }
        let mut claims = Claims::new(mesh.pos.len());
        let first = claims.select(&mut queue, &mesh);
        let second = claims.select(&mut queue, &mesh);
        assert!(
            first.len() > 8 && second.len() > 8,
            "{} {}",
            first.len(),
            second.len()
        );
        for batch in [&first, &second] {
            assert!(batch.windows(2).all(|w| w[0].1 <= w[1].1), "cheapest first");
        }
        // Within a batch, and between a batch and the one before it (which
        // is costed while the next is picked), vertices are >= 4 edges apart.
        let all: Vec<u32> = first.iter().chain(&second).map(|x| x.0).collect();
        for (i, &a) in all.iter().enumerate() {
            let d = distances(&mesh, a);
            for &b in &all[i + 1..] {
                assert!(
                    d[b as usize] >= 4,
                    "{a} and {b} are {} apart",
                    d[b as usize]
                );
            }
        }
        // What clashed went back into the queue: nothing was lost.
        let mut left = 0;
        while queue.pop().is_some() {
            left += 1;
        }
        assert_eq!(left + all.len(), mesh.pos.len());
    }

    #[test]
    fn limit_one_keeps_everything_and_threads_do_not_matter() {
        let g = sheet(10, 3);
        let (r, _) = reduce(&g, &ReduceOptions::new(1.0), &NoProgress);
        assert_eq!(r.faces.len(), g.faces.len());
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| reduce(&g, &ReduceOptions::new(0.1), &NoProgress).0)
        };
        let (a, b) = (run(1), run(2));
        assert_eq!(a.faces, b.faces);
        assert_eq!(a.clearance, b.clearance);
    }
}
