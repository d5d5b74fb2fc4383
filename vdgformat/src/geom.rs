//! Small f64 vector maths and the exact clearance of a point for one face.
//!
//! Queries read f32 from the file and compute in f64: the clearance is a
//! difference of lengths of similar size, and the visibility certificate
//! relies on its sign being right to well below a game unit.

use std::ops::{Add, Mul, Sub};

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct V3(pub f64, pub f64, pub f64);

impl V3 {
    #[inline]
    pub fn from_f32(p: [f32; 3]) -> V3 {
        V3(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))
    }
    #[inline]
    pub fn to_f32(self) -> [f32; 3] {
        [self.0 as f32, self.1 as f32, self.2 as f32]
    }
    #[inline]
    pub fn dot(self, o: V3) -> f64 {
        self.0 * o.0 + self.1 * o.1 + self.2 * o.2
    }
    #[inline]
    pub fn cross(self, o: V3) -> V3 {
        V3(
            self.1 * o.2 - self.2 * o.1,
            self.2 * o.0 - self.0 * o.2,
            self.0 * o.1 - self.1 * o.0,
        )
    }
    #[inline]
    pub fn norm2(self) -> f64 {
        self.dot(self)
    }
    #[inline]
    pub fn norm(self) -> f64 {
        self.norm2().sqrt()
    }
}

impl Add for V3 {
    type Output = V3;
    #[inline]
    fn add(self, o: V3) -> V3 {
        V3(self.0 + o.0, self.1 + o.1, self.2 + o.2)
    }
}

impl Sub for V3 {
    type Output = V3;
    #[inline]
    fn sub(self, o: V3) -> V3 {
        V3(self.0 - o.0, self.1 - o.1, self.2 - o.2)
    }
}

impl Mul<f64> for V3 {
    type Output = V3;
    #[inline]
    fn mul(self, s: f64) -> V3 {
        V3(self.0 * s, self.1 * s, self.2 * s)
    }
}

/// A sphere-swept corner: a point with a radius (a vertex and its clearance).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ball {
    pub c: V3,
    pub r: f64,
}

/// `max_{t∈[0,1]} r(t) − |p − q(t)|` over the segment `a`–`b` with linearly
/// interpolated radius: the clearance of `p` for the "round cone" of two balls.
///
/// Along the line the objective is `r_a + k·s − sqrt((s − s_p)² + h²)` (s the
/// arc length, k the radius slope, h the distance of p to the line). It is
/// concave; for |k| < 1 its stationary point is `s_p + k·h / sqrt(1 − k²)`,
/// otherwise it is monotone. Clamping to the segment gives the exact maximum.
#[inline]
pub(crate) fn edge_clearance(a: Ball, b: Ball, p: V3) -> f64 {
    let d = b.c - a.c;
    let len2 = d.norm2();
    let ap = p - a.c;
    if len2 <= f64::MIN_POSITIVE {
        return a.r.max(b.r) - ap.norm();
    }
    let len = len2.sqrt();
    let along = ap.dot(d) / len; // arc length of the foot point
    let h = (ap.norm2() - along * along).max(0.0).sqrt();
    let k = (b.r - a.r) / len;
    let s = if k >= 1.0 {
        len
    } else if k <= -1.0 {
        0.0
    } else {
        (along + k * h / (1.0 - k * k).sqrt()).clamp(0.0, len)
    };
    let t = s / len;
    let q = a.c + d * t;
    a.r + (b.r - a.r) * t - (p - q).norm()
}

/// Exact clearance of `p` for the face volume of triangle `(a, b, c)`:
/// `max_{q ∈ triangle} r(q) − |p − q|` with `r` linearly interpolated
/// (thesis 3.7/3.8: the volume is the union of the balls `B(q, r(q))`,
/// positive inside).
///
/// The objective is concave (affine minus a norm). Writing `g` for the
/// in-plane gradient of `r` and `h` for the distance of `p` to the plane, the
/// unconstrained maximiser is `foot(p) + g·h / sqrt(1 − |g|²)` when `|g| < 1`
/// with value `r(foot(p)) − h·sqrt(1 − |g|²)`. If it lies in the triangle it
/// is the answer; otherwise the maximum of a concave function over a convex
/// set sits on the boundary, i.e. on one of the three edges
/// ([`edge_clearance`]). Degenerate (collinear) triangles are their edges.
#[inline]
pub(crate) fn face_clearance(a: Ball, b: Ball, c: Ball, p: V3) -> f64 {
    let e1 = b.c - a.c;
    let e2 = c.c - a.c;
    let g11 = e1.norm2();
    let g12 = e1.dot(e2);
    let g22 = e2.norm2();
    let det = g11 * g22 - g12 * g12;
    if det > 1e-12 * g11 * g22 {
        let d1 = b.r - a.r;
        let d2 = c.r - a.r;
        // In-plane gradient g = α e1 + β e2 with g·e1 = d1, g·e2 = d2.
        let alpha = (g22 * d1 - g12 * d2) / det;
        let beta = (g11 * d2 - g12 * d1) / det;
        let grad = e1 * alpha + e2 * beta;
        let grad2 = grad.norm2();
        if grad2 < 1.0 {
            let n = e1.cross(e2);
            let ap = p - a.c;
            let h_signed = ap.dot(n) / n.norm();
            let h = h_signed.abs();
            let w = (1.0 - grad2).sqrt();
            // Optimum relative to a: foot point plus the gradient shift.
            let foot = ap - n * (ap.dot(n) / n.norm2());
            let q = foot + grad * (h / w);
            let x = (g22 * q.dot(e1) - g12 * q.dot(e2)) / det;
            let y = (g11 * q.dot(e2) - g12 * q.dot(e1)) / det;
            if x >= 0.0 && y >= 0.0 && x + y <= 1.0 {
                return a.r + grad.dot(ap) - h * w;
            }
        }
    }
    edge_clearance(a, b, p)
        .max(edge_clearance(b, c, p))
        .max(edge_clearance(c, a, p))
}

/// Axis-aligned box in f32 (file precision).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Aabb {
    pub min: [f32; 3],
    pub max: [f32; 3],
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        min: [f32::INFINITY; 3],
        max: [f32::NEG_INFINITY; 3],
    };

    pub fn grow(&mut self, o: &Aabb) {
        for i in 0..3 {
            self.min[i] = self.min[i].min(o.min[i]);
            self.max[i] = self.max[i].max(o.max[i]);
        }
    }

    pub fn is_empty(&self) -> bool {
        (0..3).any(|i| self.min[i] > self.max[i])
    }

    /// Euclidean distance from `p` to the box (0 inside).
    #[inline]
    pub fn distance(&self, p: V3) -> f64 {
        self.distance2(p).sqrt()
    }

    /// Squared distance from `p` to the box (0 inside).
    #[inline]
    pub fn distance2(&self, p: V3) -> f64 {
        let mut d2 = 0.0;
        for (i, c) in [p.0, p.1, p.2].into_iter().enumerate() {
            let lo = f64::from(self.min[i]);
            let hi = f64::from(self.max[i]);
            let e = if c < lo {
                lo - c
            } else if c > hi {
                c - hi
            } else {
                0.0
            };
            d2 += e * e;
        }
        d2
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ball(x: f64, y: f64, z: f64, r: f64) -> Ball {
        Ball { c: V3(x, y, z), r }
    }

    /// Nested ternary search: the objective is jointly concave, so the
    /// maximum over y for fixed x is concave in x. An independent check of
    /// the closed form, accurate to ~1e-9.
    fn ternary_face(a: Ball, b: Ball, c: Ball, p: V3) -> f64 {
        let f = |x: f64, y: f64| {
            let q = a.c + (b.c - a.c) * x + (c.c - a.c) * y;
            a.r + (b.r - a.r) * x + (c.r - a.r) * y - (p - q).norm()
        };
        let inner = |x: f64| {
            let (mut lo, mut hi) = (0.0, 1.0 - x);
            for _ in 0..100 {
                let m1 = lo + (hi - lo) / 3.0;
                let m2 = hi - (hi - lo) / 3.0;
                if f(x, m1) < f(x, m2) {
                    lo = m1
                } else {
                    hi = m2
                }
            }
            f(x, 0.5 * (lo + hi))
        };
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        for _ in 0..100 {
            let m1 = lo + (hi - lo) / 3.0;
            let m2 = hi - (hi - lo) / 3.0;
            if inner(m1) < inner(m2) {
                lo = m1
            } else {
                hi = m2
            }
        }
        inner(0.5 * (lo + hi))
    }

    #[test]
    fn constant_radius_is_distance_to_triangle_minus_radius() {
        let (a, b, c) = (
            ball(0., 0., 0., 2.),
            ball(10., 0., 0., 2.),
            ball(0., 10., 0., 2.),
        );
        // Above the interior: r − height.
        assert!((face_clearance(a, b, c, V3(2., 2., 5.)) - (2. - 5.)).abs() < 1e-12);
        // Beyond vertex a: r − |p − a|.
        let v = face_clearance(a, b, c, V3(-3., -4., 0.));
        assert!((v - (2. - 5.)).abs() < 1e-12);
        // Beyond the hypotenuse, in plane.
        let v = face_clearance(a, b, c, V3(6., 6., 0.));
        let d = (12.0f64 - 10.0) / 2f64.sqrt();
        assert!((v - (2. - d)).abs() < 1e-12);
    }

    #[test]
    fn closed_form_matches_ternary_search_on_random_faces() {
        let mut rng = toolbox::SplitMix64::new(7);
        let mut worst = 0.0f64;
        for _ in 0..3000 {
            let mut pt = || {
                V3(
                    rng.next_f64() * 20. - 10.,
                    rng.next_f64() * 20. - 10.,
                    rng.next_f64() * 20. - 10.,
                )
            };
            let (pa, pb, pc, p) = (pt(), pt(), pt(), pt());
            let mut r = || rng.next_f64() * 12.0;
            let (a, b, c) = (
                Ball { c: pa, r: r() },
                Ball { c: pb, r: r() },
                Ball { c: pc, r: r() },
            );
            let exact = face_clearance(a, b, c, p);
            let brute = ternary_face(a, b, c, p);
            worst = worst.max((exact - brute).abs());
        }
        assert!(worst < 1e-6, "worst deviation {worst}");
    }

    #[test]
    fn steep_radius_gradient_uses_the_big_ball() {
        // |grad r| > 1: the big ball at c swallows the others.
        let (a, b, c) = (
            ball(0., 0., 0., 0.5),
            ball(1., 0., 0., 0.5),
            ball(0., 1., 0., 30.),
        );
        let p = V3(0., 20., 3.);
        let want = 30.0 - (p - c.c).norm();
        assert!((face_clearance(a, b, c, p) - want).abs() < 1e-12);
    }

    #[test]
    fn degenerate_triangle_is_its_longest_edge() {
        let (a, b, c) = (
            ball(0., 0., 0., 1.),
            ball(4., 0., 0., 1.),
            ball(2., 0., 0., 1.),
        );
        let v = face_clearance(a, b, c, V3(2., 3., 0.));
        assert!((v - (1. - 3.)).abs() < 1e-12);
    }

    #[test]
    fn box_distance() {
        let b = Aabb {
            min: [0.; 3],
            max: [1.; 3],
        };
        assert_eq!(b.distance(V3(0.5, 0.5, 0.5)), 0.0);
        assert!((b.distance(V3(4., 5., 0.5)) - 5.0).abs() < 1e-12);
    }
}
