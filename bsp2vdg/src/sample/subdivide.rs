//! Longest-edge subdivision of triangles with a true covering guarantee (thesis 3.5).
//!
//! The thesis splits until all edges are shorter than 2m, which leaves points of a
//! triangle farther than m from every vertex (an equilateral triangle of side 2m has
//! its centre 2m/√3 ≈ 1.15m away). We split instead until the triangle's *covering
//! radius* — the largest distance from any of its points to its nearest vertex — is at
//! most m. That radius is exact and cheap: the circumradius when the triangle is not
//! obtuse (the circumcentre lies inside), otherwise the distance from the obtuse
//! corner's bisector feet on the longest edge.

use toolbox::vec3::sub;

type P = [f64; 3];

fn len2(a: P) -> f64 {
    a[0] * a[0] + a[1] * a[1] + a[2] * a[2]
}

/// The midpoint, computed symmetrically so that both faces sharing an edge get the
/// bit-identical point.
pub fn midpoint(a: P, b: P) -> P {
    [
        (a[0] + b[0]) * 0.5,
        (a[1] + b[1]) * 0.5,
        (a[2] + b[2]) * 0.5,
    ]
}

/// The largest distance from a point of triangle `abc` to its nearest corner.
pub fn covering_radius(a: P, b: P, c: P) -> f64 {
    // Squared edge lengths; rotate so that `lc` (edge a–b) is the longest.
    let (mut la, mut lb, mut lc) = (len2(sub(b, c)), len2(sub(c, a)), len2(sub(a, b)));
    if la > lc && la >= lb {
        (la, lb, lc) = (lb, lc, la);
    } else if lb > lc {
        (la, lb, lc) = (lc, la, lb);
    }
    if lc == 0.0 {
        return 0.0;
    }
    if la + lb >= lc {
        // Not obtuse: the circumcentre is inside; R² = la·lb·lc / (16·area²).
        let area16 = 2.0 * (la * lb + lb * lc + lc * la) - (la * la + lb * lb + lc * lc);
        if area16 <= lc * lc * 1e-12 {
            // Degenerate with a doubled corner: a segment with two samples.
            return lc.sqrt() * 0.5;
        }
        (la * lb * lc / area16).sqrt()
    } else {
        // Obtuse at c: the farthest points are where the bisectors of c–a and c–b
        // meet the longest edge a–b.
        let s = lc.sqrt();
        let da = lb * s / (lb + lc - la);
        let db = la * s / (la + lc - lb);
        da.max(db)
    }
}

/// Subdivides triangle `abc` along longest edges until its covering radius is at most
/// `radius`. New vertices (midpoints) go to `out`; returns the number of final triangles.
/// Stops early once `out` holds `budget` points (the caller then retries coarser).
pub fn subdivide(a: P, b: P, c: P, radius: f64, out: &mut Vec<P>, budget: usize) -> usize {
    // Depth bound: each level halves an edge; 64 levels exceed f64 resolution anyway.
    fn rec(t: [P; 3], radius: f64, depth: u32, out: &mut Vec<P>, budget: usize) -> usize {
        if depth >= 64 || out.len() >= budget || covering_radius(t[0], t[1], t[2]) <= radius {
            return 1;
        }
        let l = [
            len2(sub(t[1], t[2])),
            len2(sub(t[2], t[0])),
            len2(sub(t[0], t[1])),
        ];
        // Longest edge is opposite corner k; ties go to the lowest k (deterministic).
        let k = if l[0] >= l[1] && l[0] >= l[2] {
            0
        } else if l[1] >= l[2] {
            1
        } else {
            2
        };
        let (apex, e0, e1) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
        let m = midpoint(e0, e1);
        out.push(m);
        rec([apex, e0, m], radius, depth + 1, out, budget)
            + rec([apex, m, e1], radius, depth + 1, out, budget)
    }
    rec([a, b, c], radius, 0, out, budget)
}

#[cfg(test)]
mod tests {
    use super::*;
    use toolbox::SplitMix64;

    /// Brute force: the covering radius by dense barycentric sampling (a lower bound
    /// that converges to the true value).
    fn brute_covering(a: P, b: P, c: P) -> f64 {
        let n = 300;
        let mut best = 0.0f64;
        for i in 0..=n {
            for j in 0..=(n - i) {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                let w = 1.0 - u - v;
                let p = [0, 1, 2].map(|k| u * a[k] + v * b[k] + w * c[k]);
                let d = [a, b, c]
                    .iter()
                    .map(|&q| len2(sub(p, q)).sqrt())
                    .fold(f64::INFINITY, f64::min);
                best = best.max(d);
            }
        }
        best
    }

    #[test]
    fn covering_radius_is_exact() {
        let mut rng = SplitMix64::new(3);
        for _ in 0..60 {
            let mut p = || {
                [
                    rng.range(-10.0, 10.0),
                    rng.range(-10.0, 10.0),
                    rng.range(-1.0, 1.0),
                ]
            };
            let (a, b, c) = (p(), p(), p());
            let exact = covering_radius(a, b, c);
            let brute = brute_covering(a, b, c);
            // Brute force is a lower bound within one grid step.
            assert!(exact >= brute - 1e-9, "{exact} < {brute}");
            assert!(exact - brute < 0.1, "{exact} vs {brute}");
        }
    }

    #[test]
    fn equilateral_triangle_of_side_2m_is_not_covered_at_m() {
        // The thesis' rule would accept this triangle; ours must not.
        let m = 24.0;
        let (a, b, c) = (
            [0.0, 0.0, 0.0],
            [2.0 * m, 0.0, 0.0],
            [m, m * 3f64.sqrt(), 0.0],
        );
        assert!((covering_radius(a, b, c) - 2.0 * m / 3f64.sqrt()).abs() < 1e-9);
        let mut out = Vec::new();
        assert!(subdivide(a, b, c, m, &mut out, usize::MAX) > 1);
    }

    #[test]
    fn degenerate_triangles_are_handled() {
        let (a, b) = ([0.0; 3], [10.0, 0.0, 0.0]);
        assert_eq!(covering_radius(a, a, a), 0.0);
        assert!((covering_radius(a, b, b) - 5.0).abs() < 1e-12);
        assert!((covering_radius(a, b, [4.0, 0.0, 0.0]) - 3.0).abs() < 1e-12);
        let mut out = Vec::new();
        let n = subdivide(a, b, [4.0, 0.0, 0.0], 1.0, &mut out, usize::MAX);
        assert!(n > 1 && out.len() == n - 1);
    }
}
