//! The face volume model of thesis 4.3 (the vector maths is `toolbox::vec3`'s).
//!
//! The cost of an operation is the free-space volume it loses (thesis 4.4).
//! The thesis estimates the volume of a face from seven parts — the slab
//! over and under the triangle, a half cylinder along each edge and the
//! corner sphere pieces lumped into one ball of the mean radius — because it
//! is cheap and parts shared by neighbouring faces cancel in differences.
//! Whether an operation is *allowed* (condition A) is decided separately and
//! exactly with [`vdgformat::triangle_clearance`].

use std::f64::consts::PI;

pub(crate) use toolbox::vec3::{P3, add, cross, dist, dot, norm, scale, sub};

/// Thesis 4.3: `|k1k2 × k1k3|·r̄ + Σ_edges |e|·π·((ra+rb)/2)² + 4/3·π·r̄³`
/// with `r̄` the mean clearance, as the formula is printed: a full cylinder
/// per edge and face. (The prose speaks of "Zylinderhälften"; half
/// cylinders, used before, weigh the edges half as much and lost more of
/// the far-from-wall coverage at the same reduction ratio.)
pub(crate) fn face_volume(p: [P3; 3], r: [f64; 3]) -> f64 {
    shape_volume(&face_shape(p), r)
}

/// What [`face_volume`] needs of a face's geometry: twice its area and its
/// edge lengths `|p0p1|, |p1p2|, |p2p0|`. Positions never change during
/// the reduction, so the mesh keeps this per face.
pub(crate) type Shape = [f64; 4];

pub(crate) fn face_shape(p: [P3; 3]) -> Shape {
    [
        norm(cross(sub(p[1], p[0]), sub(p[2], p[0]))),
        dist(p[0], p[1]),
        dist(p[1], p[2]),
        dist(p[2], p[0]),
    ]
}

/// [`face_volume`] of a face of shape `s` with clearances `r`.
#[inline]
pub(crate) fn shape_volume(s: &Shape, r: [f64; 3]) -> f64 {
    let mean = (r[0] + r[1] + r[2]) / 3.0;
    let slab = s[0] * mean;
    let mut cylinders = 0.0;
    for (i, (a, b)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
        let rr = 0.5 * (r[a] + r[b]);
        cylinders += s[1 + i] * PI * rr * rr;
    }
    slab + cylinders + 4.0 / 3.0 * PI * mean * mean * mean
}

/// The cost of an operation from the model volume before and after it
/// (thesis 4.4: the lost volume). The true described volume never grows
/// (condition A), but the model's parts overlap — every face carries its
/// own edge cylinders and corner ball — so a swap that replaces the edge
/// `k1–k2` by a longer `k3–k4` between larger clearances makes the model
/// volume *grow*, by millions of cubic units when the new edge's cylinders
/// outweigh the old one's. Such an operation changes the
/// description as much as a loss of that size does, so its magnitude is
/// the cost (clamping at zero instead made those operations free and lost
/// more coverage).
#[inline]
pub(crate) fn loss(before: f64, after: f64) -> f64 {
    (before - after).abs()
}

/// Closest points of the lines `p1 + tp·(p2 − p1)` and `p3 + tq·(p4 − p3)`:
/// the perpendicular feet `p`, `q` of thesis fig. 4.10, as `(tp, tq)`.
/// `None` when the lines are (nearly) parallel — the thesis "jerks" a point
/// there (`JerkPoint`); the reduction simply does not use that pair.
pub(crate) fn perpendicular_feet(p1: P3, p2: P3, p3: P3, p4: P3) -> Option<(f64, f64)> {
    let u = sub(p2, p1);
    let v = sub(p4, p3);
    let w = sub(p1, p3);
    let (a, b, c) = (dot(u, u), dot(u, v), dot(v, v));
    let (d, e) = (dot(u, w), dot(v, w));
    let den = a * c - b * b;
    if den.is_nan() || den <= 1e-9 * a * c {
        return None;
    }
    Some(((b * e - c * d) / den, (a * e - b * d) / den))
}

/// Thesis 6.1.5 `OptimalLinearReduction`: radii `h1` at 0 and `h2` at 1 must
/// be lowered so that the line through them passes at or below `h` at `f`,
/// keeping the area under the line, `(h1' + h2')/2`, as large as possible.
/// One unit of height at `f` buys `1/(1−f)` of `h1'` or `1/f` of `h2'`, so
/// the end farther from `f` is kept as high as possible and the near end is
/// lowered (fig. 6.10, `e'` or `e''`). `None` when `h < 0`.
pub(crate) fn optimal_linear_reduction(h1: f64, h2: f64, f: f64, h: f64) -> Option<(f64, f64)> {
    let f = f.clamp(0.0, 1.0);
    if h < 0.0 {
        return None;
    }
    if (1.0 - f) * h1 + f * h2 <= h {
        return Some((h1, h2));
    }
    // Weight of each end at f; fill the end with the smaller weight first:
    // one unit of `h` buys 1/weight units of radius there.
    let (w1, w2) = (1.0 - f, f);
    let r = if w1 <= w2 {
        let a = if w1 > 0.0 { h1.min(h / w1) } else { h1 };
        let b = if w2 > 0.0 {
            ((h - w1 * a) / w2).clamp(0.0, h2)
        } else {
            h2
        };
        (a, b)
    } else {
        let b = if w2 > 0.0 { h2.min(h / w2) } else { h2 };
        let a = if w1 > 0.0 {
            ((h - w2 * b) / w1).clamp(0.0, h1)
        } else {
            h1
        };
        (a, b)
    };
    Some(r)
}

/// The three-vertex version used when a degree-3 vertex with three faces is
/// replaced by one face (thesis 4.6.2): lower the radii `r` so that the
/// barycentric interpolation with weights `w` is at most `h`, keeping
/// `Σ r'` (the area under the radius plane) as large as possible — a linear
/// program whose optimum fills the vertices in order of increasing weight.
pub(crate) fn optimal_planar_reduction(r: [f64; 3], w: [f64; 3], h: f64) -> Option<[f64; 3]> {
    if h < 0.0 {
        return None;
    }
    if (0..3).map(|i| r[i] * w[i]).sum::<f64>() <= h {
        return Some(r);
    }
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| w[a].total_cmp(&w[b]).then(a.cmp(&b)));
    let mut out = [0.0; 3];
    let mut budget = h;
    for &i in &order {
        let v = if w[i] <= 0.0 {
            r[i]
        } else {
            r[i].min((budget / w[i]).max(0.0))
        };
        out[i] = v;
        budget -= w[i] * v;
    }
    Some(out)
}

/// Closest point of triangle `abc` to `p`, with its barycentric weights
/// (Ericson, Real-Time Collision Detection 5.1.5).
pub(crate) fn closest_on_triangle(p: P3, a: P3, b: P3, c: P3) -> (P3, [f64; 3]) {
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(p, a);
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, [1.0, 0.0, 0.0]);
    }
    let bp = sub(p, b);
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, [0.0, 1.0, 0.0]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (add(a, scale(ab, v)), [1.0 - v, v, 0.0]);
    }
    let cp = sub(p, c);
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, [0.0, 0.0, 1.0]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (add(a, scale(ac, w)), [1.0 - w, 0.0, w]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (add(b, scale(sub(c, b), w)), [0.0, 1.0 - w, w]);
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (add(a, add(scale(ab, v), scale(ac, w))), [1.0 - v - w, v, w])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_face_volume_grows_with_clearance_and_size() {
        let p = [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0]];
        let v1 = face_volume(p, [1.0; 3]);
        let v2 = face_volume(p, [2.0; 3]);
        assert!(v2 > v1 && v1 > 0.0);
        let big = [[0.0, 0.0, 0.0], [20.0, 0.0, 0.0], [0.0, 20.0, 0.0]];
        assert!(face_volume(big, [1.0; 3]) > v1);
        // Slab part: |cross| = 100, mean 1; a full cylinder per edge.
        let cyl: f64 = [10.0, 200f64.sqrt(), 10.0].iter().map(|l| l * PI).sum();
        assert!((v1 - (100.0 + cyl + 4.0 / 3.0 * PI)).abs() < 1e-9);
    }

    #[test]
    fn feet_of_skew_lines() {
        let (tp, tq) = perpendicular_feet(
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            [3.0, -5.0, 2.0],
            [3.0, 5.0, 2.0],
        )
        .unwrap();
        assert!((tp - 0.3).abs() < 1e-12 && (tq - 0.5).abs() < 1e-12);
        assert!(
            perpendicular_feet([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [2.0, 1.0, 0.0])
                .is_none()
        );
    }

    #[test]
    fn linear_reduction_meets_the_target_and_keeps_the_far_end() {
        for &(h1, h2, f, h) in &[
            (10.0, 10.0, 0.8, 5.0),
            (10.0, 4.0, 0.2, 3.0),
            (5.0, 5.0, 0.5, 1.0),
        ] {
            let (a, b) = optimal_linear_reduction(h1, h2, f, h).unwrap();
            assert!((1.0 - f) * a + f * b <= h + 1e-9, "{a} {b}");
            assert!(a <= h1 && b <= h2 && a >= 0.0 && b >= 0.0);
            // Brute force: no feasible pair has a larger sum.
            let mut best: f64 = 0.0;
            for i in 0..=200 {
                let x = h1 * i as f64 / 200.0;
                let y = ((h - (1.0 - f) * x) / f).min(h2);
                if y >= 0.0 {
                    best = best.max(x + y);
                }
            }
            assert!(a + b >= best - 1e-6, "{a}+{b} < {best}");
        }
        assert_eq!(
            optimal_linear_reduction(3.0, 4.0, 0.5, 10.0),
            Some((3.0, 4.0))
        );
        assert!(optimal_linear_reduction(3.0, 4.0, 0.5, -1.0).is_none());
    }

    #[test]
    fn planar_reduction_meets_the_target() {
        let w = [0.2, 0.3, 0.5];
        let r = optimal_planar_reduction([10.0, 10.0, 10.0], w, 4.0).unwrap();
        let at: f64 = (0..3).map(|i| r[i] * w[i]).sum();
        assert!(at <= 4.0 + 1e-9 && r.iter().all(|&x| (0.0..=10.0).contains(&x)));
        assert_eq!(r[0], 10.0);
    }

    #[test]
    fn closest_point_on_triangle_regions() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0]);
        let (q, w) = closest_on_triangle([2.0, 3.0, 5.0], a, b, c);
        assert_eq!(q, [2.0, 3.0, 0.0]);
        assert!((w[0] - 0.5).abs() < 1e-12);
        let (q, _) = closest_on_triangle([-5.0, -5.0, 1.0], a, b, c);
        assert_eq!(q, a);
        let (q, _) = closest_on_triangle([5.0, -3.0, 0.0], a, b, c);
        assert_eq!(q, [5.0, 0.0, 0.0]);
    }
}
