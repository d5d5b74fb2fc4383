//! Median time per query on a ~200k-face synthetic graph, or on a real
//! `.vdg` when `VDG_BENCH_FILE` is set. `VDG_BENCH_BB` overrides the leaf
//! size (`-bb`) of the synthetic graph (default 256).
//!
//! `cargo bench -p vdgformat --bench queries`
//!
//! Each query is timed on its own (the clock's overhead is negligible next
//! to the queries); the cheap single-face evaluation is timed in batches.
//! Medians and p90 are printed, because shared machines are noisy.

use std::hint::black_box;
use std::time::Instant;

use vdgformat::{Vdg, VdgBuilder, VdgFile};

/// The workspace's one generator, with the draws these benchmarks use.
struct Rng(toolbox::SplitMix64);

impl Rng {
    fn f(&mut self) -> f32 {
        self.0.next_f32()
    }
    fn sym(&mut self, r: f32) -> f32 {
        (self.f() * 2.0 - 1.0) * r
    }
    fn below(&mut self, n: usize) -> usize {
        self.0.below(n)
    }
}

/// 320 × 320 cells of 8 units (204 800 faces) on a wavy surface with
/// clearance between 8 and 24 — the density of an unreduced graph.
fn synthetic(bb: f32) -> Vec<u8> {
    let (n, cell) = (320usize, 8.0f32);
    let mut b = VdgBuilder::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 * cell, j as f32 * cell);
            let z = 96.0 * (x / 300.0).sin() * (y / 220.0).cos();
            let c = 16.0 + 8.0 * (x / 90.0).cos() * (y / 130.0).sin();
            b.add_vertex([x, y, z], c);
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..n {
        for i in 0..n {
            b.add_face([id(i, j), id(i + 1, j), id(i, j + 1)]);
            b.add_face([id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    b.set_leaf_size(bb);
    b.to_bytes().expect("valid synthetic graph")
}

/// A point inside the volume: a vertex plus an offset within its clearance.
fn point_near_vertex(g: &Vdg<'_>, rng: &mut Rng) -> [f32; 3] {
    let v = g.vertices()[rng.below(g.vertex_count())];
    let r = v.clearance * 0.5;
    [
        v.pos[0] + rng.sym(r),
        v.pos[1] + rng.sym(r),
        v.pos[2] + rng.sym(r),
    ]
}

fn report(name: &str, mut times_ns: Vec<f64>, extra: &str) {
    times_ns.sort_by(f64::total_cmp);
    let med = times_ns[times_ns.len() / 2];
    let p90 = times_ns[times_ns.len() * 9 / 10];
    println!(
        "{name:<28} n={:<6} median {:>10.2} µs   p90 {:>10.2} µs  {extra}",
        times_ns.len(),
        med / 1e3,
        p90 / 1e3
    );
}

fn time<T>(f: impl FnOnce() -> T) -> (f64, T) {
    let t = Instant::now();
    let out = black_box(f());
    (t.elapsed().as_nanos() as f64, out)
}

fn main() {
    let file = open_graph();
    let g = file.graph();
    let info = g.info();
    println!(
        "vertices {}  faces {}  tree nodes {}  bytes {}",
        g.vertex_count(),
        g.face_count(),
        info.tree_node_count,
        file.as_bytes().len()
    );
    let mut rng = Rng(toolbox::SplitMix64::new(42));
    let n = 2000;
    bench_face_clearance(&g, &mut rng);
    let inside = bench_point_queries(&g, &mut rng, n);
    bench_track(&g, &mut rng);
    bench_visible(&g, &mut rng, n);
    bench_paths(&g, &mut rng, n);
    bench_reachable(&g, &inside, n);
}

/// `VDG_BENCH_FILE`, or the synthetic graph built and opened (both timed).
fn open_graph() -> VdgFile {
    let t0 = Instant::now();
    match std::env::var_os("VDG_BENCH_FILE") {
        Some(path) => {
            println!("graph: {}", path.to_string_lossy());
            VdgFile::open(&path).expect("VDG_BENCH_FILE must be a valid .vdg")
        }
        None => {
            let bb: f32 = std::env::var("VDG_BENCH_BB")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(256.0);
            println!("graph: synthetic 320×320 wavy grid, -bb {bb}");
            let bytes = synthetic(bb);
            println!("built in {:.2} s", t0.elapsed().as_secs_f64());
            let t = Instant::now();
            let f = VdgFile::from_bytes(&bytes).expect("valid");
            println!(
                "open (copy + validate {} bytes): {:.2} ms",
                bytes.len(),
                t.elapsed().as_secs_f64() * 1e3
            );
            f
        }
    }
}

/// Single face evaluation, batched.
fn bench_face_clearance(g: &Vdg<'_>, rng: &mut Rng) {
    let pts: Vec<[f32; 3]> = (0..4096).map(|_| point_near_vertex(g, rng)).collect();
    let faces: Vec<u32> = (0..4096)
        .map(|_| rng.below(g.face_count()) as u32)
        .collect();
    let mut batch = Vec::new();
    for _ in 0..50 {
        let (t, _) = time(|| {
            let mut acc = 0.0;
            for (p, f) in pts.iter().zip(&faces) {
                acc += g.face_clearance(*f, *p);
            }
            acc
        });
        batch.push(t / pts.len() as f64);
    }
    report("face_clearance (1 face)", batch, "");
}

/// Clearance, nearest face and containment at points inside and outside
/// the volume; returns the inside points.
fn bench_point_queries(g: &Vdg<'_>, rng: &mut Rng, n: usize) -> Vec<[f32; 3]> {
    let inside: Vec<[f32; 3]> = (0..n).map(|_| point_near_vertex(g, rng)).collect();
    let times = inside.iter().map(|&p| time(|| g.clearance(p)).0).collect();
    report("clearance (inside)", times, "");
    let times = inside
        .iter()
        .map(|&p| time(|| g.nearest_face(p)).0)
        .collect();
    report("nearest_face (inside)", times, "");
    let outside: Vec<[f32; 3]> = (0..n)
        .map(|_| {
            let mut p = point_near_vertex(g, rng);
            p[2] += 60.0 + rng.f() * 200.0;
            p
        })
        .collect();
    let times = outside
        .iter()
        .map(|&p| time(|| g.nearest_face(p)).0)
        .collect();
    report(
        "nearest_face (outside)",
        times,
        "(60–260 units off the volume)",
    );
    let times = inside.iter().map(|&p| time(|| g.contains(p)).0).collect();
    report("contains (inside)", times, "");
    let times = outside.iter().map(|&p| time(|| g.contains(p)).0).collect();
    report("contains (outside)", times, "");
    inside
}

/// Tracking a random walk of 2-unit steps.
fn bench_track(g: &Vdg<'_>, rng: &mut Rng) {
    let mut times = Vec::new();
    let mut fallbacks = 0;
    for _ in 0..20 {
        let mut p = point_near_vertex(g, rng);
        let mut hit = g.nearest_face(p).expect("faces");
        for _ in 0..100 {
            let q = [
                p[0] + rng.sym(2.0),
                p[1] + rng.sym(2.0),
                p[2] + rng.sym(2.0),
            ];
            if g.clearance(q) <= 0.0 {
                fallbacks += 1;
                continue;
            }
            p = q;
            let (t, h) = time(|| g.track(hit.face, p));
            hit = h.expect("faces");
            times.push(t);
        }
    }
    report(
        "track (2-unit steps)",
        times,
        &format!("({fallbacks} steps left the volume, skipped)"),
    );
}

/// Visibility between nearby points (distance up to ~250 units).
fn bench_visible(g: &Vdg<'_>, rng: &mut Rng, n: usize) {
    let mut times = Vec::new();
    let mut yes = 0;
    for _ in 0..n {
        let s = point_near_vertex(g, rng);
        let e = [
            s[0] + rng.sym(180.0),
            s[1] + rng.sym(180.0),
            s[2] + rng.sym(40.0),
        ];
        let (t, v) = time(|| g.visible(s, e));
        yes += usize::from(v);
        times.push(t);
    }
    report(
        "visible (≤ 250 units)",
        times,
        &format!("({yes}/{n} visible)"),
    );
}

/// VDistance between points ~500 units apart: A*, the reusable
/// PathFinder, and vertex-to-vertex paths between the same places.
fn bench_paths(g: &Vdg<'_>, rng: &mut Rng, n: usize) {
    let mut times = Vec::new();
    let mut lens = Vec::new();
    let mut pairs = Vec::new();
    for _ in 0..n / 4 {
        let p = point_near_vertex(g, rng);
        let mut q = point_near_vertex(g, rng);
        for _ in 0..50 {
            let d = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
            if (300.0..700.0).contains(&d) {
                break;
            }
            q = point_near_vertex(g, rng);
        }
        let (t, d) = time(|| g.vdistance(p, q));
        if let Some(d) = d {
            lens.push(d);
        }
        times.push(t);
        pairs.push((p, q));
    }
    lens.sort_by(f32::total_cmp);
    let med_len = lens.get(lens.len() / 2).copied().unwrap_or(0.0);
    report(
        "vdistance (A*)",
        times,
        &format!("(median path length {med_len:.0} units)"),
    );

    let mut finder = vdgformat::query::PathFinder::new();
    let times = pairs
        .iter()
        .map(|&(p, q)| time(|| finder.path(g, p, q).map(|x| x.length)).0)
        .collect();
    report(
        "vdistance (PathFinder)",
        times,
        "(same pairs, reused scratch)",
    );
    let vpairs: Vec<(u32, u32)> = pairs
        .iter()
        .map(|&(p, q)| {
            let f = |x| g.face(g.nearest_face(x).expect("faces").face)[0];
            (f(p), f(q))
        })
        .collect();
    let times = vpairs
        .iter()
        .map(|&(a, b)| time(|| g.vertex_path(a, b).map(|x| x.length)).0)
        .collect();
    report("vertex_path (A* only)", times, "(hash-map state)");
    let times = vpairs
        .iter()
        .map(|&(a, b)| time(|| finder.vertex_path(g, a, b).map(|x| x.length)).0)
        .collect();
    report("vertex_path (PathFinder)", times, "(stamped arrays)");
}

/// Reachable around points inside the volume.
fn bench_reachable(g: &Vdg<'_>, inside: &[[f32; 3]], n: usize) {
    let mut times = Vec::new();
    for &p in inside.iter().take(n / 2) {
        if let Some(h) = g.nearest_face(p) {
            times.push(time(|| g.reachable(p, h.face)).0);
        }
    }
    report("reachable", times, "");
}
