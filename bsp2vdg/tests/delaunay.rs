//! Property tests of the 3D Delaunay triangulation on random, grid, coplanar, cospherical,
//! duplicate-heavy and wall-sample inputs. Every check is exact (`Triangulation::validate`
//! uses `robust` directly) or compares against an independent count (qhull).

use std::collections::HashSet;
use std::io::Write;
use std::process::{Command, Stdio};

use bsp2vdg::delaunay::{DelaunayError, INFINITE, Triangulation};

/// SplitMix64, seeded: reproducible inputs without a dev-dependency.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

fn uniform(n: usize, seed: u64) -> Vec<[f64; 3]> {
    let mut r = Rng(seed);
    (0..n).map(|_| [r.unit(), r.unit(), r.unit()]).collect()
}

fn grid(nx: usize, ny: usize, nz: usize, step: f64) -> Vec<[f64; 3]> {
    let mut p = Vec::new();
    for x in 0..nx {
        for y in 0..ny {
            for z in 0..nz {
                p.push([x as f64 * step, y as f64 * step, z as f64 * step]);
            }
        }
    }
    p
}

/// Wall samples of a small box level: rooms of 8×8×4 cells of 24 units, walls one cell
/// thick, points on the 24-grid of every wall, floor and ceiling (exactly degenerate).
fn box_level(rooms_x: i64, rooms_y: i64) -> Vec<[f64; 3]> {
    let mut set = HashSet::new();
    let (room, height) = (8i64, 4i64);
    for a in 0..rooms_x {
        for b in 0..rooms_y {
            let (x0, y0) = (a * (room + 1), b * (room + 1));
            for i in 0..=room {
                for j in 0..=room {
                    for k in 0..=height {
                        let on_face =
                            i == 0 || i == room || j == 0 || j == room || k == 0 || k == height;
                        if on_face {
                            set.insert((x0 + i, y0 + j, k));
                        }
                    }
                }
            }
        }
    }
    let mut v: Vec<_> = set.into_iter().collect();
    v.sort_unstable();
    let mut r = Rng(3);
    for i in (1..v.len()).rev() {
        v.swap(i, r.below(i as u64 + 1) as usize);
    }
    v.into_iter()
        .map(|(x, y, z)| [x as f64 * 24.0, y as f64 * 24.0, z as f64 * 24.0])
        .collect()
}

fn check(points: &[[f64; 3]]) -> Triangulation {
    let tri = Triangulation::new(points).expect("triangulation");
    if let Err(e) = tri.validate() {
        panic!("{e}");
    }
    tri
}

#[test]
fn uniform_random_is_valid_for_several_seeds() {
    for seed in 1..=4 {
        let pts = uniform(3000, seed);
        let tri = check(&pts);
        assert_eq!(tri.num_vertices(), pts.len());
        // ~6.5 tetrahedra per point in a uniform cube.
        let ratio = tri.num_finite_cells() as f64 / pts.len() as f64;
        assert!((5.5..7.0).contains(&ratio), "{ratio}");
    }
}

#[test]
fn regular_grids_are_valid() {
    // Every unit cube has 8 cospherical corners; every row is collinear.
    check(&grid(12, 12, 12, 1.0));
    check(&grid(30, 30, 2, 0.5));
    // Very small and large magnitudes and a non-dyadic step (no integer stage).
    check(&grid(7, 6, 5, 1e-3));
    check(&grid(7, 6, 5, 1e6 / 3.0));
}

#[test]
fn wall_samples_exact_and_jittered_are_valid() {
    let pts = box_level(3, 2);
    let tri = check(&pts);
    assert_eq!(tri.num_vertices(), pts.len());
    let mut r = Rng(11);
    let jittered: Vec<[f64; 3]> = pts
        .iter()
        .map(|p| p.map(|c| c + (r.unit() - 0.5) * 2e-3))
        .collect();
    check(&jittered);
}

#[test]
fn mostly_coplanar_input_is_valid() {
    // A dense planar grid plus a few points off the plane (on both sides and on a line).
    let mut pts = grid(40, 40, 1, 1.0);
    pts.extend([
        [3.5, 2.5, 1.0],
        [20.0, 20.0, -3.0],
        [-5.0, 0.0, 0.0],
        [45.0, 0.0, 0.0],
    ]);
    let tri = check(&pts);
    assert!(tri.num_finite_cells() > 0);
    // Two parallel planes of points: the gap between them is filled.
    let mut two = grid(15, 15, 1, 1.0);
    two.extend(grid(15, 15, 1, 1.0).iter().map(|p| [p[0] + 0.5, p[1], 2.0]));
    check(&two);
}

#[test]
fn cospherical_input_is_valid() {
    // All integer points on the sphere x² + y² + z² = 2925 (hundreds of exactly
    // cospherical points), plus the center.
    let r2 = 2925i64;
    let mut pts = Vec::new();
    for x in -54i64..=54 {
        for y in -54i64..=54 {
            let z2 = r2 - x * x - y * y;
            if z2 < 0 {
                continue;
            }
            let z = (z2 as f64).sqrt() as i64;
            if z * z == z2 {
                pts.push([x as f64, y as f64, z as f64]);
                if z != 0 {
                    pts.push([x as f64, y as f64, -z as f64]);
                }
            }
        }
    }
    assert!(pts.len() > 200, "{}", pts.len());
    check(&pts);
    pts.push([0.0, 0.0, 0.0]);
    let tri = check(&pts);
    // The center is a vertex of every cell: all cells are cones over the hull.
    let center = (pts.len() - 1) as u32;
    assert!(
        tri.cells()
            .take(tri.num_finite_cells())
            .all(|c| c.contains(&center))
    );
}

#[test]
fn duplicates_are_skipped_and_reported() {
    let base = uniform(300, 9);
    let mut r = Rng(5);
    let pts: Vec<[f64; 3]> = (0..4000).map(|_| base[r.below(300) as usize]).collect();
    let distinct: HashSet<[u64; 3]> = pts.iter().map(|p| p.map(f64::to_bits)).collect();
    let tri = check(&pts);
    assert_eq!(tri.num_vertices(), distinct.len());
    assert_eq!(tri.duplicates().len(), pts.len() - distinct.len());
    for &(d, kept) in tri.duplicates() {
        assert_ne!(d, kept);
        assert_eq!(pts[d as usize], pts[kept as usize]);
    }
    // Duplicates of a grid (exactly degenerate and duplicated).
    let mut g = grid(8, 8, 8, 2.0);
    g.extend(grid(8, 8, 8, 2.0));
    let tri = check(&g);
    assert_eq!(tri.duplicates().len(), 512);
}

#[test]
fn bad_inputs_are_errors() {
    let flat = grid(10, 10, 1, 1.0);
    assert!(matches!(
        Triangulation::new(&flat),
        Err(DelaunayError::Degenerate { .. })
    ));
    let line = [
        [0.0, 0.0, 0.0],
        [1.0, 1.0, 1.0],
        [2.0, 2.0, 2.0],
        [3.0, 3.0, 3.0],
    ];
    assert!(matches!(
        Triangulation::new(&line),
        Err(DelaunayError::Degenerate { .. })
    ));
    assert!(matches!(
        Triangulation::new(&[]),
        Err(DelaunayError::Degenerate { .. })
    ));
    let same = [[1.0, 2.0, 3.0]; 10];
    assert!(matches!(
        Triangulation::new(&same),
        Err(DelaunayError::Degenerate { .. })
    ));
    let mut nan = uniform(10, 1);
    nan[7][1] = f64::NAN;
    assert_eq!(
        Triangulation::new(&nan).unwrap_err(),
        DelaunayError::NonFinite { index: 7 }
    );
    nan[7][1] = f64::INFINITY;
    assert!(Triangulation::new(&nan).is_err());
    // The message names the problem.
    let msg = Triangulation::new(&flat).unwrap_err().to_string();
    assert!(msg.contains("coplanar"), "{msg}");
}

#[test]
fn output_is_deterministic() {
    for pts in [uniform(5000, 21), box_level(2, 2)] {
        let a = Triangulation::new(&pts).unwrap();
        let b = Triangulation::new(&pts).unwrap();
        assert!(a.cells().eq(b.cells()));
        assert_eq!(a.num_finite_cells(), b.num_finite_cells());
        for t in 0..a.num_cells() as u32 {
            for i in 0..4 {
                assert_eq!(a.neighbor(t, i), b.neighbor(t, i));
            }
        }
    }
}

#[test]
fn circumspheres_pass_through_the_vertices() {
    for pts in [uniform(2000, 4), box_level(2, 1)] {
        let tri = Triangulation::new(&pts).unwrap();
        let spheres = tri.circumspheres();
        assert_eq!(spheres.len(), tri.num_finite_cells());
        for (t, &(c, r)) in spheres.iter().enumerate() {
            assert!(c.iter().all(|x| x.is_finite()) && r > 0.0);
            assert_eq!(c, tri.circumcenter(t as u32));
            for v in tri.cell(t as u32) {
                let p = pts[v as usize];
                let d =
                    ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2) + (p[2] - c[2]).powi(2)).sqrt();
                assert!((d - r).abs() <= 1e-9 * r.max(1.0), "cell {t}: {d} vs {r}");
            }
        }
    }
}

/// A sliver whose orientation needs the exact stages: the circumcenter must still use the
/// determinant's value, not just its sign.
#[test]
fn circumcenter_of_a_sliver_is_accurate() {
    let h = 2f64.powi(-30);
    let pts = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, h],
    ];
    let tri = check(&pts);
    assert_eq!(tri.num_finite_cells(), 1);
    let c = tri.circumcenter(0);
    let r = tri.circumradius(0);
    assert!(r > 1e6, "{r}");
    for p in pts {
        let d = ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2) + (p[2] - c[2]).powi(2)).sqrt();
        assert!((d - r).abs() <= 1e-6 * r, "{d} vs {r}");
    }
}

#[test]
fn edge_rings_cover_every_edge_once_in_order() {
    for pts in [uniform(3000, 8), box_level(2, 1)] {
        let tri = Triangulation::new(&pts).unwrap();
        let mut all_edges = HashSet::new();
        for c in tri.cells() {
            for i in 0..4 {
                for j in i + 1..4 {
                    if c[i] != INFINITE && c[j] != INFINITE {
                        all_edges.insert((c[i].min(c[j]), c[i].max(c[j])));
                    }
                }
            }
        }
        let mut seen = HashSet::new();
        let mut ring_cells = 0;
        tri.for_each_edge_ring(|ring| {
            assert!(ring.a < ring.b);
            assert!(seen.insert((ring.a, ring.b)), "edge reported twice");
            assert!(ring.cells.len() >= 3);
            ring_cells += ring.cells.len();
            let n = ring.cells.len();
            let mut infinite = 0;
            for k in 0..n {
                let (t, u) = (ring.cells[k], ring.cells[(k + 1) % n]);
                let (ct, cu) = (tri.cell(t), tri.cell(u));
                assert!(ct.contains(&ring.a) && ct.contains(&ring.b));
                assert!(
                    tri.neighbors(t).contains(&u),
                    "consecutive cells must be adjacent"
                );
                let shared = ct.iter().filter(|v| cu.contains(v)).count();
                assert_eq!(shared, 3);
                infinite += usize::from(!tri.is_finite(t));
            }
            assert_eq!(ring.touches_infinity, infinite > 0);
            if ring.touches_infinity {
                assert_eq!(infinite, 2);
                assert!(!tri.is_finite(ring.cells[n - 1]) && !tri.is_finite(ring.cells[n - 2]));
            } else {
                // The Voronoi face turns positively about a → b (Newell normal).
                let cs: Vec<[f64; 3]> = ring.cells.iter().map(|&t| tri.circumcenter(t)).collect();
                let mut normal = [0.0; 3];
                for k in 0..n {
                    let (p, q) = (cs[k], cs[(k + 1) % n]);
                    normal[0] += (p[1] - q[1]) * (p[2] + q[2]);
                    normal[1] += (p[2] - q[2]) * (p[0] + q[0]);
                    normal[2] += (p[0] - q[0]) * (p[1] + q[1]);
                }
                let (pa, pb) = (pts[ring.a as usize], pts[ring.b as usize]);
                let axis = [pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]];
                let dot: f64 = (0..3).map(|k| normal[k] * axis[k]).sum();
                assert!(
                    dot >= 0.0,
                    "ring of ({}, {}) turns the wrong way",
                    ring.a,
                    ring.b
                );
            }
        });
        assert_eq!(seen.len(), all_edges.len());
        // Every (cell, finite edge) incidence appears in exactly one ring.
        let incidences: usize = tri
            .cells()
            .map(|c| {
                let finite = c.iter().filter(|&&v| v != INFINITE).count();
                finite * (finite - 1) / 2
            })
            .sum();
        assert_eq!(ring_cells, incidences);
    }
}

/// Number of tetrahedra from `qdelaunay Qt i` (first output line), or `None` if qhull is
/// not installed.
fn qhull_count(pts: &[[f64; 3]]) -> Option<usize> {
    let mut child = match Command::new("qdelaunay")
        .args(["Qt", "i"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
    {
        Ok(c) => c,
        Err(_) => {
            eprintln!(
                "qdelaunay not installed (apt-get install qhull-bin): skipping the comparison"
            );
            return None;
        }
    };
    let mut input = format!("3\n{}\n", pts.len());
    for p in pts {
        input += &format!("{:?} {:?} {:?}\n", p[0], p[1], p[2]);
    }
    child
        .stdin
        .take()
        .unwrap()
        .write_all(input.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    Some(text.lines().next()?.trim().parse().unwrap())
}

#[test]
fn tetrahedron_count_matches_qhull_in_general_position() {
    for (n, seed) in [(2000, 31), (10000, 32)] {
        let pts = uniform(n, seed);
        let tri = check(&pts);
        let Some(expected) = qhull_count(&pts) else {
            return;
        };
        assert_eq!(tri.num_finite_cells(), expected, "n = {n}");
    }
}
