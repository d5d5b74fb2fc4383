//! Query correctness against analytic volumes and brute force.

mod common;

use common::{Rng, flat, grid, open, random_soup, rect_distance};

/// Brute-force max of r(q) − |p − q| over the triangle: a 40×40 barycentric
/// grid, then a pattern search with shrinking steps from the best sample
/// (the objective is concave, so this converges to the maximum).
fn brute_face(v: [[f64; 4]; 3], p: [f64; 3]) -> f64 {
    let f = |x: f64, y: f64| {
        let (x, y) = (x.clamp(0.0, 1.0), y.clamp(0.0, 1.0));
        let (x, y) = if x + y > 1.0 {
            (x / (x + y), y / (x + y))
        } else {
            (x, y)
        };
        let w = 1.0 - x - y;
        let mut d2 = 0.0;
        for i in 0..3 {
            let q = w * v[0][i] + x * v[1][i] + y * v[2][i];
            d2 += (p[i] - q) * (p[i] - q);
        }
        (w * v[0][3] + x * v[1][3] + y * v[2][3] - d2.sqrt(), x, y)
    };
    let mut best = (f64::NEG_INFINITY, 0.0, 0.0);
    let n = 40;
    for i in 0..=n {
        for j in 0..=n - i {
            let s = f(i as f64 / n as f64, j as f64 / n as f64);
            if s.0 > best.0 {
                best = s;
            }
        }
    }
    let mut step = 1.0 / n as f64;
    while step > 1e-12 {
        let mut moved = false;
        for (dx, dy) in [
            (1., 0.),
            (-1., 0.),
            (0., 1.),
            (0., -1.),
            (1., -1.),
            (-1., 1.),
        ] {
            let s = f(best.1 + dx * step, best.2 + dy * step);
            if s.0 > best.0 {
                best = s;
                moved = true;
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    best.0
}

#[test]
fn face_clearance_matches_brute_force_sampling() {
    let mut rng = Rng::new(11);
    let b = random_soup(60, 300, &mut rng);
    let file = open(&b);
    let g = file.graph();
    let mut worst = 0.0f64;
    for k in 0..400 {
        let f = (k % g.face_count()) as u32;
        let tri = g.face(f).map(|v| {
            let v = g.vertices()[v as usize];
            [
                f64::from(v.pos[0]),
                f64::from(v.pos[1]),
                f64::from(v.pos[2]),
                f64::from(v.clearance),
            ]
        });
        let c = [0, 1, 2].map(|i| (tri[0][i] + tri[1][i] + tri[2][i]) / 3.0);
        let p = rng.point(
            [c[0] - 120.0, c[1] - 120.0, c[2] - 120.0],
            [c[0] + 120.0, c[1] + 120.0, c[2] + 120.0],
        );
        let exact = f64::from(g.face_clearance(f, p));
        let brute = brute_face(tri, p.map(f64::from));
        assert!(
            exact >= brute - 1e-4,
            "exact {exact} below a sampled value {brute}"
        );
        worst = worst.max((exact - brute).abs());
    }
    assert!(worst <= 1e-4, "worst |exact − brute| = {worst}");
}

#[test]
fn constant_clearance_grid_is_a_swept_sphere() {
    // Volume of a 10×6 grid of 32-unit cells with r = 24: all points closer
    // than 24 to the rectangle [0,320]×[0,192] in z = 0.
    let file = open(flat(10, 6, 32.0, 24.0).set_leaf_size(64.0));
    let g = file.graph();
    let mut rng = Rng::new(3);
    for _ in 0..3000 {
        let p = rng.point([-60.0, -60.0, -60.0], [380.0, 250.0, 60.0]);
        let want = 24.0 - rect_distance(p, 0.0, 320.0, 0.0, 192.0);
        let got = f64::from(g.clearance(p));
        assert!((got - want).abs() < 1e-4, "at {p:?}: {got} vs {want}");
    }
}

#[test]
fn tree_queries_equal_brute_force_over_all_faces() {
    let mut rng = Rng::new(5);
    for (nv, nf, bb) in [(400, 1500, 16.0), (2000, 6000, 64.0), (50, 80, 1000.0)] {
        let mut b = random_soup(nv, nf, &mut rng);
        b.set_leaf_size(bb);
        let file = open(&b);
        let g = file.graph();
        let info = g.info();
        let (lo, hi) = (info.volume_min, info.volume_max);
        for k in 0..1500 {
            // Mostly inside the volume bounds, some far outside.
            let pad = if k % 5 == 0 { 300.0 } else { 0.0 };
            let p = rng.point(
                lo.map(|x| f64::from(x) - pad),
                hi.map(|x| f64::from(x) + pad),
            );
            let brute = (0..g.face_count() as u32)
                .map(|f| g.face_clearance(f, p))
                .fold(f32::NEG_INFINITY, f32::max);
            let hit = g.nearest_face(p).expect("faces exist");
            assert_eq!(hit.clearance, brute, "at {p:?}");
            assert_eq!(g.face_clearance(hit.face, p), brute);
            let mut inside: Vec<u32> = (0..g.face_count() as u32)
                .filter(|&f| g.face_clearance(f, p) > 0.0)
                .collect();
            inside.sort_unstable();
            assert_eq!(g.contains(p), !inside.is_empty());
            assert_eq!(g.faces_containing(p), inside);
        }
    }
}

#[test]
fn visible_true_is_never_wrong_on_an_l_shape() {
    // L shape: a 12×12 grid of 32-unit cells without the upper-right 8×8
    // block, r = 20. Ground truth: dist to the L region < 20.
    let file = open(
        grid(12, 12, 32.0, |_, _| 0.0, |_, _| 20.0, |i, j| i < 4 || j < 4).set_leaf_size(32.0),
    );
    let g = file.graph();
    let truth = |p: [f32; 3]| {
        rect_distance(p, 0.0, 384.0, 0.0, 128.0).min(rect_distance(p, 0.0, 128.0, 0.0, 384.0))
    };
    let mut rng = Rng::new(9);
    let (mut yes, mut inside_segments, mut missed) = (0, 0, 0);
    for _ in 0..3000 {
        let s = rng.point([-25.0, -25.0, -22.0], [410.0, 410.0, 22.0]);
        let e = rng.point([-25.0, -25.0, -22.0], [410.0, 410.0, 22.0]);
        let vis = g.visible(s, e);
        let samples = 400;
        let min_margin = (0..=samples)
            .map(|i| {
                let t = i as f32 / samples as f32;
                let p = [0, 1, 2].map(|k| s[k] + t * (e[k] - s[k]));
                20.0 - truth(p)
            })
            .fold(f64::INFINITY, f64::min);
        if vis {
            yes += 1;
            assert!(min_margin > -1e-3, "visible through a wall: {s:?} → {e:?}");
        }
        if min_margin > 0.5 {
            inside_segments += 1;
            missed += usize::from(!vis);
        }
    }
    assert!(
        yes > 100,
        "only {yes} visible segments: test is not exercising"
    );
    // False negatives happen only at the volume's edge: none for segments
    // with half a unit of clearance to spare.
    assert_eq!(
        missed, 0,
        "{missed} of {inside_segments} clearly free segments not visible"
    );
}

/// A segment from near a random vertex to near one of the next 20 (vertex
/// order is spatial, so the ends lie close and the line crosses a few faces).
fn nearby_segment(g: &vdgformat::Vdg<'_>, rng: &mut Rng) -> ([f32; 3], [f32; 3]) {
    let v = rng.below(g.vertex_count() - 20);
    let w = v + rng.below(20);
    let s = g.vertices()[v]
        .pos
        .map(|x| x + rng.range(-20.0, 20.0) as f32);
    let e = g.vertices()[w]
        .pos
        .map(|x| x + rng.range(-20.0, 20.0) as f32);
    (s, e)
}

#[test]
fn visible_implies_positive_clearance_on_random_graphs() {
    let mut rng = Rng::new(21);
    let mut b = random_soup(800, 2400, &mut rng);
    b.set_leaf_size(40.0);
    let file = open(&b);
    let g = file.graph();
    let mut yes = 0;
    for _ in 0..1500 {
        let (s, e) = nearby_segment(&g, &mut rng);
        if g.visible(s, e) {
            yes += 1;
            for i in 0..=200 {
                let t = i as f32 / 200.0;
                let p = [0, 1, 2].map(|k| s[k] + t * (e[k] - s[k]));
                assert!(
                    g.clearance(p) > 0.0,
                    "visible {s:?}→{e:?} leaves the volume at {p:?}"
                );
            }
        }
        let f = g.nearest_face(s).unwrap();
        if f.clearance > 0.0 {
            // The hinted form agrees that "true" stays within the volume.
            if g.visible_from(f.face, s, e) {
                assert!(g.clearance(e) > 0.0);
            }
        }
    }
    assert!(yes > 150, "only {yes} visible segments");
}

#[test]
fn hinted_and_budgeted_tests_are_certified() {
    // A camera tests nearly the same sight line every frame: a hint from
    // the last test may change the way a cover takes, never the certainty
    // of a "visible"; a budget may only turn answers into "not visible".
    use vdgformat::{CoverBudget, CoverHint};
    let mut rng = Rng::new(33);
    let mut b = random_soup(800, 2400, &mut rng);
    b.set_leaf_size(40.0);
    let file = open(&b);
    let g = file.graph();
    let (mut yes, mut same, mut tested) = (0, 0, 0);
    for _ in 0..600 {
        let (s, e) = nearby_segment(&g, &mut rng);
        let f = g.nearest_face(s).unwrap();
        if f.clearance <= 0.0 {
            continue;
        }
        tested += 1;
        let plain = g.visible_from(f.face, s, e);
        let mut hint = CoverHint::default();
        let mut first = CoverBudget::UNBOUNDED;
        let a = g.visible_hinted(f.face, s, e, &mut first, Some(&mut hint));
        // The same line a little moved, with the hint of the first.
        let e2 = e.map(|x| x + 0.5);
        let mut second = CoverBudget::UNBOUNDED;
        let b2 = g.visible_hinted(f.face, s, e2, &mut second, Some(&mut hint));
        same += usize::from(a == plain);
        for (ok, end) in [(a, e), (b2, e2)] {
            if ok {
                yes += 1;
                for i in 0..=100 {
                    let t = i as f32 / 100.0;
                    let p = [0, 1, 2].map(|k| s[k] + t * (end[k] - s[k]));
                    assert!(
                        g.clearance(p) > 0.0,
                        "hinted visible {s:?}→{end:?} leaves the volume at {p:?}"
                    );
                }
            }
        }
        // A budget of no hops proves only one-face lines.
        let mut none = CoverBudget {
            hops: 0,
            leaf_searches: 0,
        };
        if g.visible_within(f.face, s, e2, &mut none) {
            assert!(
                g.face_clearance(f.face, e2) > 0.0,
                "no hops, yet visible beyond the first face"
            );
        }
    }
    assert!(
        yes > 60,
        "only {yes} visible segments: the test does not exercise covers"
    );
    // A test with an empty hint is the plain test.
    assert_eq!(same, tested, "hinted and plain answers differ");
}

#[test]
fn trace_stops_at_the_volume_boundary() {
    let file = open(&flat(4, 4, 50.0, 10.0));
    let g = file.graph();
    let f = g.nearest_face([60.0, 60.0, 0.0]).unwrap().face;
    // Going up, Volume(f) ends at height 10 − (nothing else: f's own volume).
    let p = g.trace(f, [60.0, 60.0, 0.0], [60.0, 60.0, 100.0]);
    assert!(g.face_clearance(f, p) > 0.0);
    assert!(g.face_clearance(f, [p[0], p[1], p[2] + 0.1]) <= 0.0);
}

#[test]
fn tracking_equals_from_scratch_on_random_walks() {
    // A wavy surface with smoothly varying clearance.
    let b = grid(
        30,
        30,
        24.0,
        |x, y| 30.0 * (x / 90.0).sin() * (y / 70.0).cos(),
        |x, y| 14.0 + 6.0 * (x / 50.0).cos() + 4.0 * (y / 40.0).sin(),
        |_, _| true,
    );
    let file = open(b.clone().set_leaf_size(48.0));
    let g = file.graph();
    let mut rng = Rng::new(17);
    let (mut steps, mut same_value, mut face_changes) = (0, 0, 0);
    for _ in 0..20 {
        let mut p = [rng.range(100.0, 600.0), rng.range(100.0, 600.0), 0.0];
        let mut hit = g.nearest_face(p.map(|x| x as f32)).unwrap();
        for _ in 0..300 {
            for c in &mut p {
                *c += rng.range(-3.0, 3.0);
            }
            p[0] = p[0].clamp(0.0, 720.0);
            p[1] = p[1].clamp(0.0, 720.0);
            p[2] = p[2].clamp(-40.0, 40.0);
            let q = p.map(|x| x as f32);
            let next = g.track(hit.face, q).unwrap();
            face_changes += usize::from(next.face != hit.face);
            hit = next;
            let scratch = g.nearest_face(q).unwrap();
            steps += 1;
            if (hit.clearance - scratch.clearance).abs() <= 1e-5 {
                same_value += 1;
            } else {
                // Outside the volume the tracker must defer to the tree.
                assert!(hit.clearance > 0.0, "tracker kept an outside face");
            }
        }
    }
    assert_eq!(same_value, steps, "tracking differed from the tree search");
    assert!(
        face_changes > steps / 10,
        "walk too short: {face_changes} face changes"
    );
}

/// Dijkstra over the edges of the faces, independent of the file's CSR.
fn dijkstra(g: &vdgformat::Vdg<'_>, from: u32, to: u32) -> Option<f64> {
    let n = g.vertex_count();
    let mut adj = vec![Vec::new(); n];
    for f in g.faces() {
        for i in 0..3 {
            for j in 0..3 {
                if i != j {
                    adj[f[i] as usize].push(f[j]);
                }
            }
        }
    }
    let pos = |v: u32| g.vertices()[v as usize].pos.map(f64::from);
    let mut dist = vec![f64::INFINITY; n];
    let mut done = vec![false; n];
    dist[from as usize] = 0.0;
    loop {
        let u = (0..n)
            .filter(|&u| !done[u] && dist[u].is_finite())
            .min_by(|&a, &b| dist[a].total_cmp(&dist[b]))?;
        if u == to as usize {
            return Some(dist[u]);
        }
        done[u] = true;
        for &w in &adj[u] {
            let (a, b) = (pos(u as u32), pos(w));
            let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
            if dist[u] + d < dist[w as usize] {
                dist[w as usize] = dist[u] + d;
            }
        }
    }
}

#[test]
fn astar_equals_dijkstra_on_random_graphs() {
    let mut rng = Rng::new(23);
    let mut found = 0;
    for round in 0..6 {
        let b = random_soup(150 + 50 * round, 200 + 60 * round, &mut rng);
        let file = open(&b);
        let g = file.graph();
        let mut finder = vdgformat::query::PathFinder::new();
        for _ in 0..40 {
            let a = rng.below(g.vertex_count()) as u32;
            let z = rng.below(g.vertex_count()) as u32;
            let want = dijkstra(&g, a, z);
            let got = g.vertex_path(a, z);
            // The reusable finder (one per graph round, reused) agrees exactly.
            assert_eq!(finder.vertex_path(&g, a, z), got);
            match (want, &got) {
                (None, None) => {}
                (Some(w), Some(path)) => {
                    found += 1;
                    assert!((f64::from(path.length) - w).abs() <= 1e-3 * (1.0 + w));
                    assert_eq!(path.vertices.first(), Some(&a));
                    assert_eq!(path.vertices.last(), Some(&z));
                    // The path uses graph edges and its length adds up.
                    let mut len = 0.0f64;
                    for w2 in path.vertices.windows(2) {
                        assert!(g.vertex_neighbours(w2[0]).contains(w2[1]));
                        let (p, q) = (
                            g.vertices()[w2[0] as usize].pos,
                            g.vertices()[w2[1] as usize].pos,
                        );
                        len += (0..3)
                            .map(|k| f64::from(p[k] - q[k]).powi(2))
                            .sum::<f64>()
                            .sqrt();
                    }
                    assert!((len - w).abs() <= 1e-3 * (1.0 + w));
                }
                _ => panic!("A* {got:?} vs Dijkstra {want:?} for {a}→{z}"),
            }
        }
    }
    assert!(found > 100, "only {found} connected pairs");
}

#[test]
fn vdistance_enters_and_leaves_at_face_vertices() {
    // Straight strip along x: VDistance between the ends is at least the
    // straight distance and at most it plus the detours to the vertices.
    let file = open(&flat(20, 1, 32.0, 16.0));
    let g = file.graph();
    let (p, q) = ([5.0, 16.0, 0.0], [630.0, 16.0, 0.0]);
    let path = g.path(p, q).unwrap();
    assert!(path.length >= 625.0 - 1e-3);
    assert!(path.length <= 625.0 + 2.0 * 16.0 + 1e-3, "{}", path.length);
    let fs = g.nearest_face(p).unwrap().face;
    let fg = g.nearest_face(q).unwrap().face;
    assert!(g.face(fs).contains(&path.vertices[0]));
    assert!(g.face(fg).contains(path.vertices.last().unwrap()));
    // Same face: the straight distance.
    assert_eq!(g.vdistance([1.0, 1.0, 0.0], [4.0, 5.0, 0.0]), Some(5.0));
}

#[test]
fn reachable_vertices_have_free_straight_lines() {
    let file = open(
        grid(12, 12, 32.0, |_, _| 0.0, |_, _| 20.0, |i, j| i < 4 || j < 4).set_leaf_size(32.0),
    );
    let g = file.graph();
    let mut rng = Rng::new(31);
    let mut total = 0;
    for _ in 0..300 {
        let p = rng.point([0.0, 0.0, -15.0], [384.0, 384.0, 15.0]);
        let Some(hit) = g.nearest_face(p) else {
            continue;
        };
        if hit.clearance <= 0.0 {
            continue;
        }
        let r = g.reachable(p, hit.face);
        // The face's own vertices are always reachable inside its volume.
        for v in g.face(hit.face) {
            assert!(r.contains(&v));
        }
        for &v in &r {
            let q = g.vertices()[v as usize].pos;
            for i in 0..=50 {
                let t = i as f32 / 50.0;
                let x = [0, 1, 2].map(|k| p[k] + t * (q[k] - p[k]));
                assert!(g.clearance(x) > 0.0);
            }
        }
        total += r.len();
    }
    assert!(total > 300 * 3);
}
