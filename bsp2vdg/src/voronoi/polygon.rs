//! Triangulating one Voronoi face: a convex polygon in the bisector plane of its
//! Delaunay edge. A fan from one corner would give slivers on the long, many-sided faces
//! that cospherical samples produce; the 2D Delaunay triangulation of the corners
//! maximises the smallest angle, and for a convex polygon it covers exactly the polygon.

use spade::{DelaunayTriangulation, HasPosition, Point2, Triangulation as _};
use toolbox::vec3::{cross, dot, sub};

struct Corner {
    at: Point2<f64>,
    id: u32,
}

impl HasPosition for Corner {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.at
    }
}

/// Triangles over the polygon `ids` (graph vertex ids in cyclic order), using `positions`.
pub fn triangulate(ids: &[u32], positions: &[[f64; 3]]) -> Vec<[u32; 3]> {
    match ids.len() {
        0..=2 => Vec::new(),
        3 => vec![[ids[0], ids[1], ids[2]]],
        _ => delaunay_2d(ids, positions),
    }
}

fn normalise(a: [f64; 3]) -> Option<[f64; 3]> {
    let l = dot(a, a).sqrt();
    (l > 0.0 && l.is_finite()).then(|| a.map(|x| x / l))
}

fn delaunay_2d(ids: &[u32], positions: &[[f64; 3]]) -> Vec<[u32; 3]> {
    let p: Vec<[f64; 3]> = ids.iter().map(|&i| positions[i as usize]).collect();
    let o = p[0];
    // The polygon's plane: Newell's normal is robust for nearly degenerate polygons.
    let mut n = [0.0; 3];
    for k in 0..p.len() {
        let c = cross(sub(p[k], o), sub(p[(k + 1) % p.len()], o));
        n = [n[0] + c[0], n[1] + c[1], n[2] + c[2]];
    }
    let fan = || {
        (1..ids.len() - 1)
            .map(|k| [ids[0], ids[k], ids[k + 1]])
            .collect()
    };
    let Some(n) = normalise(n) else { return fan() };
    let helper = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let Some(u) = normalise(cross(n, helper)) else {
        return fan();
    };
    let v = cross(n, u);
    let mut dt: DelaunayTriangulation<Corner> = DelaunayTriangulation::new();
    for (k, &q) in p.iter().enumerate() {
        let d = sub(q, o);
        // Corners that coincide in the plane are dropped by spade (it merges them).
        if dt
            .insert(Corner {
                at: Point2::new(dot(d, u), dot(d, v)),
                id: ids[k],
            })
            .is_err()
        {
            return fan();
        }
    }
    let tris: Vec<[u32; 3]> = dt
        .inner_faces()
        .map(|f| f.vertices().map(|h| h.data().id))
        .collect();
    if tris.is_empty() { fan() } else { tris }
}
