use super::*;
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

fn inside(size: [f64; 3]) -> impl Fn([f64; 3]) -> bool + Sync {
    move |p: [f64; 3]| (0..3).all(|i| p[i] > 0.0 && p[i] < size[i])
}

fn wall_distance(size: [f64; 3], p: [f64; 3]) -> f64 {
    (0..3)
        .map(|i| p[i].min(size[i] - p[i]))
        .fold(f64::INFINITY, f64::min)
}

fn box_graph(size: [f64; 3], m: f64) -> (Graph, VoronoiStats) {
    let tri = Triangulation::new(&box_samples(size, m)).unwrap();
    let free = inside(size);
    // The box is convex: a segment is inside when both ends are.
    let seg = |a: [f64; 3], b: [f64; 3]| free(a) && free(b);
    extract(
        &tri,
        &free,
        &seg,
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
    // Vertices close to the walls (C ≤ m) are removed by the clearance correction.
    assert!(stats.removed_low_clearance > 0, "{stats:?}");
    assert!(g.faces.len() > 100, "{stats:?}");
    let mut worst_gap = 0.0f64;
    for (p, &c) in g.vertices.iter().zip(&g.clearance) {
        let d = wall_distance(size, *p);
        assert!(d > 0.0, "vertex {p:?} outside the room");
        // The correction makes clearance a lower bound of the true wall distance.
        assert!(c <= d + 1e-6, "clearance {c} > true distance {d} at {p:?}");
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
    let free = inside(size);
    let seg = |a: [f64; 3], b: [f64; 3]| free(a) && free(b);
    let loose = extract(
        &tri,
        &free,
        &seg,
        &VoronoiOptions {
            spacing: 24.0,
            min_clearance: 0.0,
        },
    );
    let strict = extract(
        &tri,
        &free,
        &seg,
        &VoronoiOptions {
            spacing: 24.0,
            min_clearance: 60.0,
        },
    );
    assert!(strict.0.vertices.len() < loose.0.vertices.len());
    assert!(strict.0.clearance.iter().all(|&c| c >= 60.0));
    let again = extract(
        &tri,
        &free,
        &seg,
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
        &|_| false,
        &|_, _| false,
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
