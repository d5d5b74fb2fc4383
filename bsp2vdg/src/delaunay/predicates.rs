//! Exact geometric predicates and the symbolic perturbation of the insphere test.
//!
//! `orient3d` and `insphere` are Shewchuk's adaptive predicates from the `robust` crate: a
//! floating-point evaluation with a proven error bound answers almost every call, and only
//! when the sign is uncertain are the exact expansions evaluated. The signs returned are
//! therefore exact for any finite `f64` input.
//!
//! Sign conventions (Shewchuk's): `orient3d(a, b, c, d) > 0` when `d` lies below the plane
//! through `a, b, c` seen counter-clockwise from above. Every finite tetrahedron of the
//! triangulation is stored with `orient3d > 0`. `insphere(a, b, c, d, e) > 0` when `e` lies
//! strictly inside the sphere through a positively oriented `a, b, c, d`.

use robust::Coord3D;

#[inline(always)]
fn coord(p: &[f64; 3]) -> Coord3D<f64> {
    Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

/// Exact sign (and approximate value) of the orientation determinant of `a, b, c, d`.
#[inline]
pub fn orient3d(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> f64 {
    robust::orient3d(coord(a), coord(b), coord(c), coord(d))
}

/// Exact sign of the insphere determinant; `a, b, c, d` must be positively oriented.
#[inline]
pub fn insphere(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3], e: &[f64; 3]) -> f64 {
    robust::insphere(coord(a), coord(b), coord(c), coord(d), coord(e))
}

/// Exact 2D orientation in one of the coordinate planes (`axes` picks the two coordinates).
#[inline]
fn orient2d_proj(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], axes: (usize, usize)) -> f64 {
    let p = |q: &[f64; 3]| robust::Coord {
        x: q[axes.0],
        y: q[axes.1],
    };
    robust::orient2d(p(a), p(b), p(c))
}

/// Whether three points lie exactly on one line (all three axis projections are degenerate).
pub fn collinear(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> bool {
    orient2d_proj(a, b, c, (0, 1)) == 0.0
        && orient2d_proj(a, b, c, (1, 2)) == 0.0
        && orient2d_proj(a, b, c, (0, 2)) == 0.0
}

/// Orientation of the tetrahedron `ids` (vertex ids into `pts`).
#[inline]
pub fn orient_ids(pts: &[[f64; 3]], ids: [u32; 4]) -> f64 {
    orient3d(
        &pts[ids[0] as usize],
        &pts[ids[1] as usize],
        &pts[ids[2] as usize],
        &pts[ids[3] as usize],
    )
}

/// Is the point `q` in conflict with (strictly inside the circumsphere of) the positively
/// oriented finite tetrahedron `tet`, after symbolic perturbation?
///
/// Exact ties (five cospherical points) are broken as if every point `p_i` were lifted to
/// `|p_i|² + ε^(N − id_i)` on the paraboloid: the point with the largest id receives the
/// dominant perturbation. Expanding the 5×5 lifted determinant in ε, the coefficient of that
/// point's term is the orientation of the four *other* points, so the sign of the perturbed
/// determinant is the sign of the first non-zero orientation in decreasing id order. This is
/// the scheme of Devillers & Teillaud ("Perturbations for Delaunay and weighted Delaunay 3D
/// triangulations", CGAL's `side_of_oriented_sphere`). Because it is a genuine perturbation
/// of the lifted points, all decisions are mutually consistent: the result is the (unique)
/// Delaunay triangulation of the perturbed points, which is a Delaunay triangulation of the
/// real points with no flat cells. At most two terms are needed: if the four points other
/// than the largest are coplanar, the four other than the second largest cannot be (the
/// tetrahedron itself is not flat).
#[inline]
pub fn in_conflict(pts: &[[f64; 3]], tet: [u32; 4], q: u32) -> bool {
    let p = |i: u32| &pts[i as usize];
    let s = insphere(p(tet[0]), p(tet[1]), p(tet[2]), p(tet[3]), p(q));
    if s > 0.0 {
        true
    } else if s < 0.0 {
        false
    } else {
        perturbed_in_conflict(pts, tet, q)
    }
}

/// The symbolic tie-break of [`in_conflict`] for exactly cospherical `tet` and `q`.
#[cold]
pub fn perturbed_in_conflict(pts: &[[f64; 3]], tet: [u32; 4], q: u32) -> bool {
    let mut ids = [tet[0], tet[1], tet[2], tet[3], q];
    ids.sort_unstable_by(|a, b| b.cmp(a));
    for &m in &ids[..2] {
        if m == q {
            // Raising q's own lift pushes it outside the sphere.
            return false;
        }
        let k = tet
            .iter()
            .position(|&v| v == m)
            .expect("m is a vertex of tet");
        let mut w = tet;
        w[k] = q;
        // Raising vertex m's lift tilts the lifted plane up over q exactly when q's
        // barycentric coordinate for m is positive.
        let o = orient_ids(pts, w);
        if o != 0.0 {
            return o > 0.0;
        }
    }
    debug_assert!(
        false,
        "perturbation needs at most two terms for a non-flat tetrahedron"
    );
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orientation_convention_matches_doc() {
        let a = [0.0, 0.0, 0.0];
        let b = [1.0, 0.0, 0.0];
        let c = [0.0, 1.0, 0.0];
        // d below the plane of counter-clockwise a, b, c.
        assert!(orient3d(&a, &b, &c, &[0.0, 0.0, -1.0]) > 0.0);
        assert!(orient3d(&a, &b, &c, &[0.0, 0.0, 1.0]) < 0.0);
        assert_eq!(orient3d(&a, &b, &c, &[5.0, 7.0, 0.0]), 0.0);
    }

    #[test]
    fn perturbation_breaks_cospherical_ties_consistently() {
        // Cube corners: all 8 cospherical. Two tetrahedra sharing the diagonal facet must
        // not both claim the other's opposite vertex.
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
        ];
        let mut t = [0, 1, 2, 3];
        if orient_ids(&pts, t) < 0.0 {
            t.swap(0, 1);
        }
        assert_eq!(insphere(&pts[0], &pts[1], &pts[2], &pts[3], &pts[4]), 0.0);
        // Vertex 4 has the largest id: it is never inside.
        assert!(!in_conflict(&pts, t, 4));
        // The tetrahedron on the other side of facet (1,2,3) must agree that the facet is
        // locally Delaunay: 0 is not inside (1,2,3,4) either (symmetry of the lifting).
        let mut u = [1, 2, 3, 4];
        if orient_ids(&pts, u) < 0.0 {
            u.swap(0, 1);
        }
        assert!(!in_conflict(&pts, u, 0));
        assert!(collinear(&pts[0], &[2.0, 0.0, 0.0], &pts[1]));
        assert!(!collinear(&pts[0], &pts[1], &pts[2]));
    }
}
