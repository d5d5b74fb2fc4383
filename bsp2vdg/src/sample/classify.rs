//! Which faces bound the free space (thesis 6.1.2): by the map's own face classes
//! (texture names or surface flags, see [`bsp::faces`], re-exported here) and by the
//! BSP's contents on either side of a face ([`classify_by_contents`]).

pub use bsp::faces::{FaceClass, SkipReason, classify_texture};

/// Which side of a face is free, as the map's BSP says, decides whether it bounds the
/// free space. Texture names cannot tell this for every map: compilers emit faces
/// between sky and solid, both sides of liquid surfaces, and some maps ship without
/// texture names. `is_free` is the oracle's point test.
pub fn classify_by_contents(
    polygon: &[[f64; 3]],
    normal: [f64; 3],
    is_free: impl Fn([f64; 3]) -> bool,
) -> Option<SkipReason> {
    const EPS: f64 = 0.25;
    let at = |c: [f64; 3], s: f64| {
        [
            c[0] + s * normal[0],
            c[1] + s * normal[1],
            c[2] + s * normal[2],
        ]
    };
    // Several interior points: a face partly covered by another brush may have its
    // centre under it; it is a wall if free space meets an obstacle anywhere on it.
    let points = interior_points(polygon);
    if points.is_empty() {
        return None;
    }
    let mut verdict = None;
    for c in points {
        if !is_free(at(c, EPS)) {
            verdict = verdict.or(Some(SkipReason::NotFacingFree));
        } else if is_free(at(c, -EPS)) {
            verdict = verdict.or(Some(SkipReason::FreeBehind));
        } else {
            return None;
        }
    }
    verdict
}

/// The centroids of the fan triangles (of non-zero area): inside a convex polygon and,
/// for all but slivers, away from its edges where the side test would be ambiguous.
fn interior_points(p: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    for i in 1..p.len().saturating_sub(1) {
        let (a, b, c) = (p[0], p[i], p[i + 1]);
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        if n[0] * n[0] + n[1] * n[1] + n[2] * n[2] > 1e-6 {
            out.push([0, 1, 2].map(|k| (a[k] + b[k] + c[k]) / 3.0));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contents_decide_which_faces_bound_free_space() {
        // Free space is z > 0 and x > 0 (a wall at x = 0 and a floor at z = 0).
        let free = |p: [f64; 3]| p[2] > 0.0 && p[0] > 0.0;
        let floor = [
            [1.0, 0.0, 0.0],
            [9.0, 0.0, 0.0],
            [9.0, 9.0, 0.0],
            [1.0, 9.0, 0.0],
        ];
        assert_eq!(classify_by_contents(&floor, [0.0, 0.0, 1.0], free), None);
        assert_eq!(
            classify_by_contents(&floor, [0.0, 0.0, -1.0], free),
            Some(SkipReason::NotFacingFree)
        );
        let hanging = [
            [1.0, 0.0, 5.0],
            [9.0, 0.0, 5.0],
            [9.0, 9.0, 5.0],
            [1.0, 9.0, 5.0],
        ];
        assert_eq!(
            classify_by_contents(&hanging, [0.0, 0.0, 1.0], free),
            Some(SkipReason::FreeBehind)
        );
        let degenerate = [[1.0, 0.0, 5.0], [2.0, 0.0, 5.0], [3.0, 0.0, 5.0]];
        assert_eq!(
            classify_by_contents(&degenerate, [0.0, 0.0, 1.0], free),
            None
        );
    }
}
