use super::*;
use crate::guard::{check_corners, guard_interpolation};
use crate::raise::{raise_to_walls, raise_to_walls_and_corners};
use crate::sample::sample_polygon;

/// Samples on the six walls of the box [0,a]×[0,b]×[0,c] at spacing m.
fn box_samples(size: [f64; 3], m: f64) -> Vec<[f64; 3]> {
    let [a, b, c] = size;
    let faces = [
        [[0.0, 0.0, 0.0], [a, 0.0, 0.0], [a, b, 0.0], [0.0, b, 0.0]],
        [[0.0, 0.0, c], [a, 0.0, c], [a, b, c], [0.0, b, c]],
        [[0.0, 0.0, 0.0], [a, 0.0, 0.0], [a, 0.0, c], [0.0, 0.0, c]],
        [[0.0, b, 0.0], [a, b, 0.0], [a, b, c], [0.0, b, c]],
        [[0.0, 0.0, 0.0], [0.0, b, 0.0], [0.0, b, c], [0.0, 0.0, c]],
        [[a, 0.0, 0.0], [a, b, 0.0], [a, b, c], [a, 0.0, c]],
    ];
    let mut grid = PointGrid::new(0.01);
    for f in faces {
        for p in sample_polygon(&f, m, usize::MAX).0 {
            if grid.nearest_within(p, 1e-9).is_none() {
                grid.insert(p);
            }
        }
    }
    grid.points().to_vec()
}

/// The inside of the box [0,a]×[0,b]×[0,c].
struct BoxRoom([f64; 3]);

impl FreeSpace for BoxRoom {
    fn is_free(&self, p: [f64; 3]) -> bool {
        (0..3).all(|i| p[i] > 0.0 && p[i] < self.0[i])
    }
    // The box is convex: a segment is inside when both ends are.
    fn segment_free(&self, a: [f64; 3], b: [f64; 3]) -> bool {
        self.is_free(a) && self.is_free(b)
    }
    fn wall_distance(&self, p: [f64; 3]) -> f64 {
        wall_distance(self.0, p)
    }
}

/// Nothing is free.
struct Solid;

impl FreeSpace for Solid {
    fn is_free(&self, _: [f64; 3]) -> bool {
        false
    }
    fn segment_free(&self, _: [f64; 3], _: [f64; 3]) -> bool {
        false
    }
    fn wall_distance(&self, _: [f64; 3]) -> f64 {
        0.0
    }
}

/// Everything but a ball of radius 40 at the origin: a convex obstacle, where
/// interpolated clearance overshoots the true distance.
struct Pillar;

impl FreeSpace for Pillar {
    fn is_free(&self, p: [f64; 3]) -> bool {
        self.wall_distance(p) > 0.0
    }
    fn segment_free(&self, _: [f64; 3], _: [f64; 3]) -> bool {
        true
    }
    fn wall_distance(&self, p: [f64; 3]) -> f64 {
        (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 40.0
    }
}

fn wall_distance(size: [f64; 3], p: [f64; 3]) -> f64 {
    (0..3)
        .map(|i| p[i].min(size[i] - p[i]))
        .fold(f64::INFINITY, f64::min)
}

fn box_graph(size: [f64; 3], m: f64) -> (Graph, VoronoiStats) {
    let tri = Triangulation::new(&box_samples(size, m)).unwrap();
    extract(
        &tri,
        &BoxRoom(size),
        &VoronoiOptions {
            spacing: m,
            min_clearance: 0.0,
        },
    )
}

#[test]
fn box_room_graph_lies_inside_with_conservative_clearance() {
    let size = [512.0, 384.0, 256.0];
    let m = 24.0;
    let (g, stats) = box_graph(size, m);
    assert!(
        stats.inner_vertices > 0 && stats.inner_faces > 0,
        "{stats:?}"
    );
    // Spurious vertices close to the walls (C ≤ m, clearance below m / 2) are removed.
    assert!(stats.removed_low_clearance > 0, "{stats:?}");
    assert!(g.faces.len() > 100, "{stats:?}");
    let mut worst_gap = 0.0f64;
    for (p, &c) in g.vertices.iter().zip(&g.clearance) {
        let d = wall_distance(size, *p);
        assert!(d > 0.0, "vertex {p:?} outside the room");
        // Clearance is the exact wall distance.
        assert!(
            (c - d).abs() < 1e-9,
            "clearance {c} != true distance {d} at {p:?}"
        );
        worst_gap = worst_gap.max(d - c);
    }
    // ... and not a wildly pessimistic one.
    assert!(worst_gap < m, "worst underestimate {worst_gap}");
    // Every face index is in range and no face is degenerate in its ids.
    for f in &g.faces {
        assert!(f.iter().all(|&v| (v as usize) < g.vertices.len()));
        assert!(f[0] != f[1] && f[1] != f[2] && f[0] != f[2]);
    }
}

#[test]
fn medial_axis_of_a_slab_is_its_mid_plane() {
    // A wide, low room: away from the side walls the medial axis is the plane z = c/2.
    let size = [960.0, 960.0, 128.0];
    let (g, _) = box_graph(size, 16.0);
    let central: Vec<&[f64; 3]> = g
        .vertices
        .iter()
        .filter(|p| (200.0..760.0).contains(&p[0]) && (200.0..760.0).contains(&p[1]))
        .collect();
    assert!(central.len() > 50);
    for p in central {
        assert!(
            (p[2] - 64.0).abs() < 16.0,
            "vertex {p:?} far from the mid plane"
        );
    }
}

#[test]
fn minimum_clearance_removes_vertices_and_extraction_is_deterministic() {
    let size = [384.0, 256.0, 192.0];
    let tri = Triangulation::new(&box_samples(size, 24.0)).unwrap();
    let room = BoxRoom(size);
    let loose = extract(
        &tri,
        &room,
        &VoronoiOptions {
            spacing: 24.0,
            min_clearance: 0.0,
        },
    );
    let strict = extract(
        &tri,
        &room,
        &VoronoiOptions {
            spacing: 24.0,
            min_clearance: 60.0,
        },
    );
    assert!(strict.0.vertices.len() < loose.0.vertices.len());
    assert!(strict.0.clearance.iter().all(|&c| c >= 60.0));
    let again = extract(
        &tri,
        &room,
        &VoronoiOptions {
            spacing: 24.0,
            min_clearance: 0.0,
        },
    );
    assert_eq!(loose, again);
}

#[test]
fn nothing_is_kept_when_nothing_is_free() {
    let size = [256.0, 256.0, 256.0];
    let tri = Triangulation::new(&box_samples(size, 32.0)).unwrap();
    let (g, s) = extract(
        &tri,
        &Solid,
        &VoronoiOptions {
            spacing: 32.0,
            min_clearance: 0.0,
        },
    );
    assert_eq!(
        (
            g.vertices.len(),
            g.faces.len(),
            s.inner_vertices,
            s.inner_faces
        ),
        (0, 0, 0, 0)
    );
}

#[test]
fn convex_polygons_triangulate_completely() {
    // A regular 12-gon: 10 triangles covering its area.
    let positions: Vec<[f64; 3]> = (0..12)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 12.0;
            [10.0 * a.cos(), 10.0 * a.sin(), 5.0]
        })
        .collect();
    let ids: Vec<u32> = (0..12).collect();
    let tris = polygon::triangulate(&ids, &positions);
    assert_eq!(tris.len(), 10);
    let area: f64 = tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            let u = [b[0] - a[0], b[1] - a[1]];
            let v = [c[0] - a[0], c[1] - a[1]];
            0.5 * (u[0] * v[1] - u[1] * v[0]).abs()
        })
        .sum();
    let exact = 0.5 * 12.0 * 100.0 * (std::f64::consts::TAU / 12.0).sin();
    assert!((area - exact).abs() < 1e-9);
}

#[test]
fn guard_keeps_interpolated_balls_off_a_convex_obstacle() {
    // Three vertices around a ball obstacle, with exact clearance: linear interpolation
    // between them overshoots the true distance in the middle of the face.
    let vertices = vec![[60.0, -30.0, 0.0], [60.0, 30.0, 0.0], [45.0, 0.0, 40.0]];
    let clearance: Vec<f64> = vertices.iter().map(|&p| Pillar.wall_distance(p)).collect();
    let graph = Graph {
        vertices,
        clearance,
        faces: vec![[0, 1, 2]],
    };
    let overshoot = |g: &Graph| {
        let mut worst = f64::NEG_INFINITY;
        for i in 0..=40 {
            for j in 0..=(40 - i) {
                let b = [i as f64 / 40.0, j as f64 / 40.0, (40 - i - j) as f64 / 40.0];
                let q = [0, 1, 2].map(|a| (0..3).map(|k| b[k] * g.vertices[k][a]).sum::<f64>());
                let r: f64 = (0..3).map(|k| b[k] * g.clearance[k]).sum();
                worst = worst.max(r - Pillar.wall_distance(q));
            }
        }
        worst
    };
    let before = overshoot(&graph);
    assert!(
        before > 0.1,
        "the test case must overshoot before the guard"
    );
    let (guarded, stats) = guard_interpolation(graph, &Pillar, 0.0);
    assert_eq!(guarded.faces.len(), 1);
    assert!(
        overshoot(&guarded) <= 0.0,
        "still overshoots by {}",
        overshoot(&guarded)
    );
    // The lowering is the true overshoot plus a small curvature margin, no more.
    assert!(
        stats.lowered == 3 && stats.max_lowering < before + 4.0,
        "{stats:?}, overshoot {before}"
    );
}

/// The largest `r − d` over a dense grid of every face: positive when a ball of the
/// interpolated volume reaches into a wall.
fn worst_overshoot(g: &Graph, space: &dyn FreeSpace) -> f64 {
    let radii: Vec<[f64; 3]> = g
        .faces
        .iter()
        .map(|f| f.map(|v| g.clearance[v as usize]))
        .collect();
    worst_corner_overshoot(g, &radii, space)
}

/// Whether every point of the segment (every unit) lies in the graph's volume.
fn segment_inside(g: &Graph, a: [f64; 3], b: [f64; 3]) -> bool {
    let len = (0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>().sqrt();
    let steps = len.ceil() as usize;
    (0..=steps).all(|s| {
        let t = s as f64 / steps as f64;
        let p = [0, 1, 2].map(|i| a[i] + t * (b[i] - a[i]));
        g.faces.iter().any(|f| {
            let balls = f.map(|v| (g.vertices[v as usize], g.clearance[v as usize]));
            triangle_clearance(balls, p) > 0.0
        })
    })
}

fn triangle_clearance(balls: [([f64; 3], f64); 3], p: [f64; 3]) -> f64 {
    vdgformat::triangle_clearance(balls, p)
}

#[test]
fn raise_to_walls_fills_the_skin_along_a_wall_and_stays_free() {
    // A reduced face across the box room's middle whose clearances an earlier
    // step lowered to 10: its volume misses the space along the walls, and a
    // sight line 20 units from the wall y = 0 leaves it.
    let room = BoxRoom([512.0, 384.0, 256.0]);
    let mut graph = Graph {
        vertices: vec![
            [100.0, 100.0, 128.0],
            [400.0, 100.0, 128.0],
            [250.0, 300.0, 128.0],
        ],
        clearance: vec![10.0; 3],
        faces: vec![[0, 1, 2]],
    };
    let (a, b) = ([150.0, 20.0, 128.0], [350.0, 20.0, 128.0]);
    assert!(
        !segment_inside(&graph, a, b),
        "the test case must miss the line"
    );
    let stats = raise_to_walls(&mut graph, &room);
    assert_eq!(stats.raised, 3, "{stats:?}");
    // Certified: no ball reaches a wall (checked on a grid 10 times finer than the
    // certificate's) ...
    let worst = worst_overshoot(&graph, &room);
    assert!(worst <= 0.0, "a ball reaches {worst} units into a wall");
    // ... and never above the wall distance at a vertex; but close to it, so the
    // line along the wall is inside now.
    for (p, &c) in graph.vertices.iter().zip(&graph.clearance) {
        let d = room.wall_distance(*p);
        assert!(
            c <= d && c > d - 12.0,
            "clearance {c} at {p:?}, wall distance {d}"
        );
    }
    assert!(segment_inside(&graph, a, b), "{:?}", graph.clearance);
}

#[test]
fn raise_to_walls_respects_a_convex_obstacle() {
    // The guard's face around the ball obstacle, lowered by 15 more: the raise may
    // give some back, never past the certificate.
    let vertices = vec![[60.0, -30.0, 0.0], [60.0, 30.0, 0.0], [45.0, 0.0, 40.0]];
    let clearance: Vec<f64> = vertices
        .iter()
        .map(|&p| Pillar.wall_distance(p) - 15.0)
        .collect();
    let mut graph = Graph {
        vertices,
        clearance,
        faces: vec![[0, 1, 2]],
    };
    let stats = raise_to_walls(&mut graph, &Pillar);
    assert!(stats.raised > 0, "{stats:?}");
    let worst = worst_overshoot(&graph, &Pillar);
    assert!(
        worst <= 0.0,
        "a ball reaches {worst} units into the obstacle"
    );
    assert!(worst > -15.0, "nothing given back: {worst}");
}

/// Two faces around the ball obstacle sharing vertex 0 (wall distance 30): the
/// first's edge 0–2 passes 13.8 units from the obstacle, where vertex 0 weighs
/// 0.43; the second points away from it, to vertices of clearance `far` (wall
/// distance 222.5, 210 between them).
fn shared_vertex_faces(far: f64) -> Graph {
    Graph {
        vertices: vec![
            [70.0, 0.0, 0.0],
            [70.0, 60.0, 0.0],
            [20.0, 60.0, 0.0],
            [250.0, 80.0, 0.0],
            [250.0, -80.0, 0.0],
        ],
        clearance: vec![1.0, 5.0, 5.0, far, far],
        faces: vec![[0, 1, 2], [0, 3, 4]],
    }
}

/// Corner radii never below their vertex's clearance (the reader refuses that) and
/// never into the ball obstacle (on a grid 10 times finer than the certificate's).
fn assert_corners_certified(graph: &Graph, radii: &[[f64; 3]]) {
    for (f, r) in graph.faces.iter().zip(radii) {
        for k in 0..3 {
            assert!(r[k] >= graph.clearance[f[k] as usize], "{r:?} {f:?}");
        }
    }
    let worst = worst_corner_overshoot(graph, radii, &Pillar);
    assert!(
        worst <= 0.0,
        "a ball reaches {worst} units into the obstacle"
    );
}

/// [`worst_overshoot`] with each face's own corner radii.
fn worst_corner_overshoot(g: &Graph, radii: &[[f64; 3]], space: &dyn FreeSpace) -> f64 {
    let mut worst = f64::NEG_INFINITY;
    for (f, r) in g.faces.iter().zip(radii) {
        for i in 0..=60 {
            for j in 0..=(60 - i) {
                let b = [i as f64 / 60.0, j as f64 / 60.0, (60 - i - j) as f64 / 60.0];
                let q = [0, 1, 2].map(|a| {
                    (0..3)
                        .map(|k| b[k] * g.vertices[f[k] as usize][a])
                        .sum::<f64>()
                });
                let rq: f64 = (0..3).map(|k| b[k] * r[k]).sum();
                worst = worst.max(rq - space.wall_distance(q));
            }
        }
    }
    worst
}

#[test]
fn face_corners_rise_where_only_their_own_face_must_stay_free() {
    // Vertex 0 (wall distance 30) is shared by a face whose edge 0–2 passes 13.8
    // units from the ball obstacle, where vertex 0 weighs 0.43 — that face holds
    // vertex 0's clearance down — and by a face that points away from the
    // obstacle, whose own corner at vertex 0 may rise to nearly 30. Its far
    // vertices start near their wall distance, so the vertex raise leaves that
    // face slack for its corner at the shared vertex.
    let graph = shared_vertex_faces(205.0);
    assert!(worst_overshoot(&graph, &Pillar) <= 0.0);
    let mut alone = graph.clone();
    raise_to_walls(&mut alone, &Pillar);
    let mut both = graph.clone();
    let (_, radii, stats) = raise_to_walls_and_corners(&mut both, &Pillar, &NoProgress);
    // The vertex raise is the same with or without the corners after it.
    assert_eq!(alone.clearance, both.clearance);
    assert_corners_certified(&both, &radii);
    // The far face's corner at the shared vertex near its wall distance, far above
    // the vertex's clearance, which the near face holds down: no vertex clearance
    // could give both faces theirs.
    let shared = both.clearance[0];
    assert!(radii[1][0] > 25.0, "far corner {}; {stats:?}", radii[1][0]);
    assert!(
        radii[1][0] > shared + 10.0,
        "{radii:?}, vertex 0 at {shared}"
    );
}

#[test]
fn corner_check_puts_an_overreaching_face_back_to_its_vertex_clearances() {
    // The near face of the test above with a corner ball that reaches into the
    // obstacle, beside the far face raised as the certificate allows.
    let mut graph = shared_vertex_faces(205.0);
    let (_, mut radii, _) = raise_to_walls_and_corners(&mut graph, &Pillar, &NoProgress);
    let far = radii[1];
    radii[0][2] = 30.0; // vertex 2 lies 23.2 units from the obstacle
    assert!(worst_corner_overshoot(&graph, &radii, &Pillar) > 0.0);
    assert_eq!(check_corners(&graph, &mut radii, &Pillar, &NoProgress), 1);
    assert_eq!(radii[0], [0, 1, 2].map(|v| graph.clearance[v]));
    assert_eq!(radii[1], far, "a certified face keeps its corners");
}

#[test]
fn every_costly_stage_stops_inside_itself_when_the_map_is_out_of_time() {
    use crate::guard::{GuardMode, guard_with};
    use crate::pipeline::stopped_in;
    use crate::progress::Ticker;
    let (size, m) = ([512.0, 384.0, 256.0], 12.0);
    let points = box_samples(size, m);
    assert!(
        points.len() as u64 > 4 * Ticker::BLOCK,
        "{} samples",
        points.len()
    );
    let stop = |stage: &str, work: &dyn Fn(&dyn Progress)| stopped_in(stage, work);
    // Each stage reports its work a block at a time, and the budget is checked at
    // every report: out of time, the stage unwinds from inside itself, named.
    let delaunay = stop("delaunay", &|p| {
        let _ = Triangulation::new_reporting(&points, p);
    });
    assert_eq!(delaunay.as_deref(), Some("delaunay"));
    let tri = Triangulation::new(&points).unwrap();
    let options = VoronoiOptions {
        spacing: m,
        min_clearance: 0.0,
    };
    let voronoi = stop("voronoi", &|p| {
        extract_reporting(&tri, &BoxRoom(size), &options, p);
    });
    assert_eq!(voronoi.as_deref(), Some("voronoi"));
    let (graph, _) = extract(&tri, &BoxRoom(size), &options);
    assert!(
        graph.faces.len() as u64 > Ticker::BLOCK,
        "{} faces",
        graph.faces.len()
    );
    for (stage, mode) in [("guard", GuardMode::Bound), ("check", GuardMode::Repair)] {
        let stopped = stop(stage, &|p| {
            guard_with(graph.clone(), &BoxRoom(size), 0.0, mode, p);
        });
        assert_eq!(stopped.as_deref(), Some(stage));
    }
    let reduce = stop("reduce", &|p| {
        crate::reduce::reduce(&graph, &crate::reduce::ReduceOptions::new(0.2), p);
    });
    assert_eq!(reduce.as_deref(), Some("reduce"));
    let raise = stop("wall_raise", &|p| {
        raise_to_walls_and_corners(&mut graph.clone(), &BoxRoom(size), p);
    });
    assert_eq!(raise.as_deref(), Some("wall_raise"));
    let corners = stop("corner_check", &|p| {
        let mut radii: Vec<[f64; 3]> = graph
            .faces
            .iter()
            .map(|f| f.map(|v| graph.clearance[v as usize] + 1.0))
            .collect();
        check_corners(&graph, &mut radii, &BoxRoom(size), p);
    });
    assert_eq!(corners.as_deref(), Some("corner_check"));
    // With no budget the same work runs to its end.
    let unbudgeted = crate::progress::NoProgress;
    assert!(Triangulation::new_reporting(&points, &unbudgeted).is_ok());
}

/// A shaft 40 units wide sampled at 24 (a drop hole of a Counter-Strike map at the
/// default spacing): its middle has a clearance of 20, so the Voronoi vertices there
/// lie nearer to a sample than the spacing. They are true free-space vertices and stay
/// (with the minimum clearance 16): the middle of the shaft is in the graph's volume.
/// The thesis' rule, which dropped every vertex with `C ≤ m`, left it out.
#[test]
fn a_shaft_narrower_than_twice_the_spacing_keeps_its_middle() {
    let size = [40.0, 160.0, 320.0];
    let m = 24.0;
    let tri = Triangulation::new(&box_samples(size, m)).unwrap();
    let (g, _) = extract(
        &tri,
        &BoxRoom(size),
        &VoronoiOptions {
            spacing: m,
            min_clearance: 16.0,
        },
    );
    // Points of the middle plane away from the ends, each in some vertex's ball.
    let (mut inside, mut total) = (0, 0);
    for y in (40..=120).step_by(8) {
        for z in (40..=280).step_by(8) {
            let p = [20.0, f64::from(y), f64::from(z)];
            total += 1;
            let held = g.vertices.iter().zip(&g.clearance).any(|(v, &c)| {
                let d2 = (0..3).map(|i| (v[i] - p[i]).powi(2)).sum::<f64>();
                d2 < c * c
            });
            inside += usize::from(held);
        }
    }
    assert!(
        inside == total,
        "{inside} of {total} points of the shaft's middle in a vertex ball ({} vertices)",
        g.vertices.len()
    );
}
