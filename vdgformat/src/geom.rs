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
/// This one-off form is what the compiler's reduction checks its edits
/// with (through [`crate::segment_clearance`]); it stays exactly as it was
/// so compiled graphs do not change with the runtime's faster evaluators
/// ([`EdgeEval`]), which agree with it to rounding.
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
/// positive inside). The compiler's form (through
/// [`crate::triangle_clearance`]), kept bit for bit; the queries use
/// [`FaceEval`], which agrees with it to rounding.
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

/// How the optimum of an edge's clearance moves with the query point.
#[derive(Clone, Copy, Debug, PartialEq)]
enum EdgeMode {
    /// The two centres coincide: the bigger ball.
    Point,
    /// The radius falls faster than the edge runs (`k ≤ −1`): ball `a`
    /// swallows the rest.
    AtA,
    /// The radius grows faster than the edge runs (`k ≥ 1`): ball `b`.
    AtB,
    /// `|k| < 1`: the optimum slides along the edge.
    Lateral,
}

/// The clearance function of one edge (two balls and the round cone
/// between them) with its invariants — direction, length, radius slope —
/// worked out once.
///
/// Along the line the objective is `r_a + k·s − sqrt((s − s_p)² + h²)` (s the
/// arc length, k the radius slope, h the distance of p to the line). It is
/// concave; for |k| < 1 its stationary point is `s_p + k·h / sqrt(1 − k²)`,
/// otherwise it is monotone. Clamping to the segment gives the exact maximum.
#[derive(Clone, Copy, Debug)]
pub(crate) struct EdgeEval {
    a: Ball,
    b: Ball,
    /// Unit direction a → b.
    dir: V3,
    len: f64,
    /// Radius slope per unit length.
    k: f64,
    /// `sqrt(1 − k²)` (lateral mode).
    c: f64,
    mode: EdgeMode,
}

impl EdgeEval {
    #[inline]
    pub(crate) fn new(a: Ball, b: Ball) -> EdgeEval {
        let d = b.c - a.c;
        let len2 = d.norm2();
        let mut e = EdgeEval {
            a,
            b,
            dir: V3(0.0, 0.0, 0.0),
            len: 0.0,
            k: 0.0,
            c: 1.0,
            mode: EdgeMode::Point,
        };
        if len2 <= f64::MIN_POSITIVE {
            return e;
        }
        e.len = len2.sqrt();
        let inv_len = 1.0 / e.len;
        e.dir = d * inv_len;
        e.k = (b.r - a.r) * inv_len;
        e.mode = if e.k >= 1.0 {
            EdgeMode::AtB
        } else if e.k <= -1.0 {
            EdgeMode::AtA
        } else {
            e.c = (1.0 - e.k * e.k).sqrt();
            EdgeMode::Lateral
        };
        e
    }

    /// The clearance of `p` for this edge. Where the optimum lies inside
    /// the edge its value is `r_a + k·s_p − sqrt(1 − k²)·h` (s_p the arc
    /// length of the foot point): no square root beyond the one for `h`.
    #[inline]
    pub(crate) fn eval(&self, p: V3) -> f64 {
        let ap = p - self.a.c;
        match self.mode {
            EdgeMode::Point => self.a.r.max(self.b.r) - ap.norm(),
            EdgeMode::AtA => self.a.r - ap.norm(),
            EdgeMode::AtB => self.b.r - (p - self.b.c).norm(),
            EdgeMode::Lateral => {
                let along = ap.dot(self.dir); // arc length of the foot point
                // The distance to the line from the offset vector, not from
                // |ap|² − along²: that difference cancels for points near
                // the line far from `a` (an error of 1e-5 at 500 units),
                // and `h` enters the value directly.
                let h = (ap - self.dir * along).norm();
                // The optimum `along + k·h / c`, times c (> 0).
                let s_c = along * self.c + self.k * h;
                if s_c <= 0.0 {
                    self.a.r - ap.norm()
                } else if s_c >= self.len * self.c {
                    self.b.r - (p - self.b.c).norm()
                } else {
                    self.a.r + self.k * along - self.c * h
                }
            }
        }
    }

    /// The largest `t` with clearance above `eps` at `s + d·t`.
    ///
    /// The round cone shrunk by `eps` is the two balls of radius `r − eps`
    /// and, between the planes where the cone touches them (arc lengths
    /// `−k·r_a'` and `len − k·r_b'`), the cone `sqrt(1 − k²)·h < r_a' + k·s`.
    /// Each piece meets the line in an interval found in closed form, and
    /// the pieces' union is the volume (so the largest end is the exit).
    fn line_exit(&self, s: V3, d: V3, eps: f64) -> f64 {
        let ra = self.a.r - eps;
        let rb = self.b.r - eps;
        match self.mode {
            EdgeMode::Point | EdgeMode::AtA | EdgeMode::AtB => {
                // The balls are added by the face; these edges add nothing.
                f64::NEG_INFINITY
            }
            EdgeMode::Lateral => {
                let m = s - self.a.c;
                let (a0, a1) = (m.dot(self.dir), d.dot(self.dir));
                let (mp, dp) = (m - self.dir * a0, d - self.dir * a1);
                let (l0, l1) = (ra + self.k * a0, self.k * a1);
                let c2 = self.c * self.c;
                let qa = c2 * dp.norm2() - l1 * l1;
                let qb = c2 * mp.dot(dp) - l0 * l1;
                let qc = c2 * mp.norm2() - l0 * l0;
                let mut best = f64::NEG_INFINITY;
                for iv in quadratic_below_zero(qa, qb, qc) {
                    let iv = iv
                        .clip(l0, l1) // the nappe where the radius is positive
                        .clip(a0 + self.k * ra, a1) // past the plane touching ball a
                        .clip(self.len - self.k * rb - a0, -a1); // before the one touching b
                    if iv.lo < iv.hi {
                        best = best.max(iv.hi);
                    }
                }
                best
            }
        }
    }
}

/// Whether a piece whose exit is at most `bound` may pass `best` (a NaN
/// bound proves nothing).
#[inline]
fn may_pass(bound: f64, best: f64) -> bool {
    bound > best || bound.is_nan()
}

/// A parameter interval `(lo, hi)` of a line; empty unless `lo < hi`.
#[derive(Clone, Copy, Debug)]
struct Interval {
    lo: f64,
    hi: f64,
}

impl Interval {
    const ALL: Interval = Interval {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };
    const EMPTY: Interval = Interval {
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
    };

    /// The part where `u0 + u1·t ≥ 0`.
    #[inline]
    fn clip(self, u0: f64, u1: f64) -> Interval {
        let mut r = self;
        if u1 > 0.0 {
            r.lo = r.lo.max(-u0 / u1);
        } else if u1 < 0.0 {
            r.hi = r.hi.min(-u0 / u1);
        } else if u0 < 0.0 || u0.is_nan() || u1.is_nan() {
            return Interval::EMPTY;
        }
        r
    }
}

/// Where `qa·t² + 2·qb·t + qc < 0`: up to two intervals (two when the
/// parabola opens downwards), roots from the cancellation-free formula.
fn quadratic_below_zero(qa: f64, qb: f64, qc: f64) -> [Interval; 2] {
    let disc = qb * qb - qa * qc;
    if qa == 0.0 {
        return [Interval::ALL.clip(-qc, -2.0 * qb), Interval::EMPTY];
    }
    if disc.is_nan() || disc <= 0.0 {
        // No sign change (or NaN): negative everywhere or nowhere.
        return if qa < 0.0 && disc <= 0.0 {
            [Interval::ALL, Interval::EMPTY]
        } else {
            [Interval::EMPTY, Interval::EMPTY]
        };
    }
    let q = -(qb + disc.sqrt().copysign(qb));
    let (r1, r2) = (q / qa, qc / q);
    let (r1, r2) = if r1 <= r2 { (r1, r2) } else { (r2, r1) };
    if qa > 0.0 {
        [Interval { lo: r1, hi: r2 }, Interval::EMPTY]
    } else {
        [
            Interval {
                lo: f64::NEG_INFINITY,
                hi: r1,
            },
            Interval {
                lo: r2,
                hi: f64::INFINITY,
            },
        ]
    }
}

/// The largest `t` with `|s + d·t − centre| < radius`, `−∞` if none.
#[inline]
fn ball_exit(centre: V3, radius: f64, s: V3, d: V3) -> f64 {
    if radius.is_nan() || radius <= 0.0 {
        return f64::NEG_INFINITY;
    }
    let m = s - centre;
    let iv = quadratic_below_zero(d.norm2(), m.dot(d), m.norm2() - radius * radius);
    iv.iter()
        .filter(|iv| iv.lo < iv.hi)
        .fold(f64::NEG_INFINITY, |e, iv| e.max(iv.hi))
}

/// The plane part of a face's clearance: valid when the triangle is not
/// degenerate and the radius gradient is below 1.
#[derive(Clone, Copy, Debug)]
struct Plane {
    /// Unit normal.
    n: V3,
    /// In-plane gradient of the radius.
    grad: V3,
    /// Dual basis of the edges: the barycentric coordinates of an in-plane
    /// offset `q` from `a` are `(q·u1, q·u2)`.
    u1: V3,
    u2: V3,
    /// `sqrt(1 − |grad|²)`.
    w: f64,
    /// How far the optimum slides per unit of height, in barycentric
    /// coordinates (`α / w`, `β / w` for `grad = α·e1 + β·e2`).
    sx: f64,
    sy: f64,
}

/// One face's clearance function with its invariants (edges, inverse Gram
/// matrix, radius gradient, unit normal) worked out once, so that the many
/// evaluations of one face in an exit search cost a few dot products each;
/// and the exact exit of a line from the face volume, in closed form.
///
/// The objective `r(q) − |p − q|` is concave (affine minus a norm). Writing
/// `g` for the in-plane gradient of `r` and `h` for the distance of `p` to the
/// plane, the unconstrained maximiser is `foot(p) + g·h / sqrt(1 − |g|²)` when
/// `|g| < 1`, with value `r(foot(p)) − h·sqrt(1 − |g|²)`. If it lies in the
/// triangle it is the answer. Otherwise the maximum of a concave function
/// over a convex set sits on the boundary — and only on an edge whose
/// constraint the maximiser violates (between the constrained and the free
/// maximiser the objective rises, so the way from one to the other leaves
/// the triangle through such an edge): one edge usually, two near a corner.
/// When `|g| ≥ 1` the objective never falls along `g`, so the maximum sits on
/// an edge that `g` points out of, which is a property of the face alone.
/// Degenerate (collinear) triangles are their three edges. Every value
/// returned is the objective at a point of the triangle, so it never
/// overstates the clearance.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FaceEval {
    balls: [Ball; 3],
    plane: Option<Plane>,
    /// Edges that may hold the optimum when there is no plane part (bit 0:
    /// a–b, bit 1: b–c, bit 2: c–a).
    edges: u8,
}

const EDGE_AB: u8 = 1;
const EDGE_BC: u8 = 2;
const EDGE_CA: u8 = 4;
const ALL_EDGES: u8 = 7;

impl FaceEval {
    #[inline]
    pub(crate) fn new(a: Ball, b: Ball, c: Ball) -> FaceEval {
        let mut fe = FaceEval {
            balls: [a, b, c],
            plane: None,
            edges: ALL_EDGES,
        };
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
            let inv_det = 1.0 / det;
            let alpha = (g22 * d1 - g12 * d2) * inv_det;
            let beta = (g11 * d2 - g12 * d1) * inv_det;
            let grad = e1 * alpha + e2 * beta;
            let grad2 = grad.norm2();
            if grad2 < 1.0 {
                let n = e1.cross(e2);
                let w = (1.0 - grad2).sqrt();
                let inv_w = 1.0 / w;
                fe.plane = Some(Plane {
                    n: n * (1.0 / n.norm()),
                    grad,
                    u1: (e1 * g22 - e2 * g12) * inv_det,
                    u2: (e2 * g11 - e1 * g12) * inv_det,
                    w,
                    sx: alpha * inv_w,
                    sy: beta * inv_w,
                });
            } else {
                // Edges that g points out of: y = 0 (a–b) if β < 0,
                // x + y = 1 (b–c) if α + β > 0, x = 0 (c–a) if α < 0.
                let out = (u8::from(beta < 0.0) * EDGE_AB)
                    | (u8::from(alpha + beta > 0.0) * EDGE_BC)
                    | (u8::from(alpha < 0.0) * EDGE_CA);
                if out != 0 {
                    fe.edges = out;
                }
            }
        }
        fe
    }

    #[inline]
    fn edge(&self, i: usize) -> EdgeEval {
        EdgeEval::new(self.balls[i], self.balls[(i + 1) % 3])
    }

    /// The clearance of `p` for this face.
    #[inline]
    pub(crate) fn eval(&self, p: V3) -> f64 {
        let a = self.balls[0];
        let mut edges = self.edges;
        if let Some(pl) = &self.plane {
            let ap = p - a.c;
            let h = ap.dot(pl.n).abs();
            // Barycentric coordinates of the unconstrained optimum.
            let x = ap.dot(pl.u1) + pl.sx * h;
            let y = ap.dot(pl.u2) + pl.sy * h;
            if x >= 0.0 && y >= 0.0 && x + y <= 1.0 {
                return a.r + pl.grad.dot(ap) - h * pl.w;
            }
            edges = (u8::from(y < 0.0) * EDGE_AB)
                | (u8::from(x + y > 1.0) * EDGE_BC)
                | (u8::from(x < 0.0) * EDGE_CA);
            if edges == 0 {
                // Only a NaN gets here: let every edge say so.
                edges = ALL_EDGES;
            }
        }
        // NaN only if every edge is NaN (`max` skips a NaN operand).
        let mut best = f64::NAN;
        for i in 0..3 {
            if edges & (1 << i) != 0 {
                best = best.max(self.edge(i).eval(p));
            }
        }
        best
    }

    /// [`Self::eval`] when the clearance at `p` may exceed `floor`;
    /// otherwise some value below `floor`. Outside the triangle's prism
    /// the exact value needs one or two edge evaluations, but the plane's
    /// unconstrained optimum (three dot products) bounds it from above:
    /// a point well outside the volume is told so without them. The bound
    /// must clear `floor` by a relative 1e-9, far above the rounding of
    /// either value, so the answer to "above `floor`?" is the exact one.
    #[inline]
    pub(crate) fn eval_above(&self, p: V3, floor: f64) -> f64 {
        if let Some(pl) = &self.plane {
            let a = self.balls[0];
            let ap = p - a.c;
            let h = ap.dot(pl.n).abs();
            let bound = a.r + pl.grad.dot(ap) - h * pl.w;
            if bound < floor - 1e-9 * (1.0 + floor.abs() + bound.abs()) {
                return bound;
            }
        }
        self.eval(p)
    }

    /// The largest `t` with clearance above `eps` at `s + d·t` (`−∞` when
    /// the line misses the shrunk volume): the exit of a segment from the
    /// face volume, in closed form.
    ///
    /// The volume is the union of the plane part (points whose optimum lies
    /// inside the triangle: on each side of the plane five linear
    /// conditions) and the round cones of the edges that may hold the
    /// optimum ([`EdgeEval::line_exit`], plus the vertex balls). A line meets
    /// the convex volume in one interval, so its end is the largest end over
    /// the pieces. Rounding makes this a guide, not a proof: callers certify
    /// the point they keep with [`Self::eval`].
    pub(crate) fn line_exit(&self, s: V3, d: V3, eps: f64) -> f64 {
        let a = self.balls[0];
        let mut best = f64::NEG_INFINITY;
        let mut edges = self.edges;
        if let Some(pl) = &self.plane {
            edges = ALL_EDGES;
            let m = s - a.c;
            let (h0, h1) = (m.dot(pl.n), d.dot(pl.n));
            let (x0, x1) = (m.dot(pl.u1), d.dot(pl.u1));
            let (y0, y1) = (m.dot(pl.u2), d.dot(pl.u2));
            let (v0, v1) = (a.r - eps + pl.grad.dot(m), pl.grad.dot(d));
            for side in [1.0, -1.0] {
                // h = side·(h0 + h1 t) ≥ 0 on this side.
                let (hs0, hs1) = (side * h0, side * h1);
                let iv = Interval::ALL
                    .clip(hs0, hs1)
                    .clip(x0 + pl.sx * hs0, x1 + pl.sx * hs1)
                    .clip(y0 + pl.sy * hs0, y1 + pl.sy * hs1)
                    .clip(
                        1.0 - x0 - y0 - (pl.sx + pl.sy) * hs0,
                        -x1 - y1 - (pl.sx + pl.sy) * hs1,
                    )
                    .clip(v0 - pl.w * hs0, v1 - pl.w * hs1);
                if iv.lo < iv.hi {
                    best = best.max(iv.hi);
                }
            }
        }
        // Every piece of an edge lies in the hull of its two balls, whose
        // points project on the line no farther than `(c − s)·d + r·|d|`:
        // a piece that cannot pass the best exit so far is skipped (most
        // cones, once a ball or the plane part has answered).
        let d2 = d.norm2();
        let prune = d2 > 0.0 && d2.is_finite();
        let dl = d2.sqrt();
        let reach = self.balls.map(|b| {
            if prune {
                ((b.c - s).dot(d) + (b.r - eps).max(0.0) * dl) / d2
            } else {
                f64::INFINITY
            }
        });
        let mut balls = 0u8;
        for i in 0..3 {
            if edges & (1 << i) != 0 {
                balls |= (1 << i) | (1 << ((i + 1) % 3));
            }
        }
        for (i, ball) in self.balls.iter().enumerate() {
            if balls & (1 << i) != 0 && may_pass(reach[i], best) {
                best = best.max(ball_exit(ball.c, ball.r - eps, s, d));
            }
        }
        for i in 0..3 {
            let j = (i + 1) % 3;
            if edges & (1 << i) != 0 && may_pass(reach[i].max(reach[j]), best) {
                best = best.max(self.edge(i).line_exit(s, d, eps));
            }
        }
        best
    }
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

    fn random_face(rng: &mut toolbox::SplitMix64) -> (Ball, Ball, Ball) {
        let mut ball = || Ball {
            c: V3(
                rng.next_f64() * 20. - 10.,
                rng.next_f64() * 20. - 10.,
                rng.next_f64() * 20. - 10.,
            ),
            r: rng.next_f64() * 12.0,
        };
        (ball(), ball(), ball())
    }

    /// The edge pruning gives the value of trying all three edges (the
    /// compiler's [`face_clearance`]).
    #[test]
    fn pruned_edges_match_all_edges() {
        let mut rng = toolbox::SplitMix64::new(11);
        let (mut worst, mut pruned) = (0.0f64, 0);
        for i in 0..20000 {
            let (a, b, mut c) = random_face(&mut rng);
            if i % 3 == 0 {
                // Steep gradients (|g| ≥ 1) are common in real graphs.
                c.r += 20.0;
            }
            let p = V3(
                rng.next_f64() * 30. - 15.,
                rng.next_f64() * 30. - 15.,
                rng.next_f64() * 30. - 15.,
            );
            let v = FaceEval::new(a, b, c).eval(p);
            worst = worst.max((v - face_clearance(a, b, c, p)).abs());
            pruned += usize::from(FaceEval::new(a, b, c).edges != ALL_EDGES);
        }
        assert!(pruned > 1000, "steep faces not pruned ({pruned})");
        assert!(worst < 1e-9, "worst deviation {worst}");
    }

    /// Points on an edge's axis far from its first vertex: the distance to
    /// the line must not come from a cancelling difference of squares (it
    /// enters the value directly; that form was off by 1e-5 here).
    #[test]
    fn edge_eval_is_accurate_on_the_edge_line() {
        let mut rng = toolbox::SplitMix64::new(3);
        let mut worst = 0.0f64;
        for _ in 0..2000 {
            let a = Ball {
                c: V3(
                    rng.next_f64() * 1000.0,
                    rng.next_f64() * 1000.0,
                    rng.next_f64() * 1000.0,
                ),
                r: 0.2 + rng.next_f64(),
            };
            let dir = V3(
                rng.next_f64() - 0.5,
                rng.next_f64() - 0.5,
                rng.next_f64() - 0.5,
            );
            let b = Ball {
                c: a.c + dir * 800.0,
                r: 0.2 + rng.next_f64(),
            };
            let u = rng.next_f64();
            let p = a.c + dir * (800.0 * u);
            // On the axis the optimum is the foot point itself.
            let want = a.r + (b.r - a.r) * u;
            let v = EdgeEval::new(a, b).eval(p);
            worst = worst.max((v - want).abs());
        }
        assert!(worst < 1e-10, "worst deviation {worst}");
    }

    /// The closed-form exit of a line agrees with a bisection on the
    /// evaluated clearance (concave along the line, so one interval).
    #[test]
    fn line_exit_matches_bisection() {
        let mut rng = toolbox::SplitMix64::new(5);
        let (mut checked, mut worst) = (0, 0.0f64);
        for i in 0..6000 {
            let (a, b, mut c) = random_face(&mut rng);
            if i % 3 == 0 {
                c.r += 20.0;
            }
            if i % 7 == 0 {
                // Nearly collinear: the degenerate path.
                c.c = a.c + (b.c - a.c) * 0.3;
            }
            let eps = [1e-4, 0.5, 3.0][i % 3];
            let fe = FaceEval::new(a, b, c);
            let s = V3(
                rng.next_f64() * 16. - 8.,
                rng.next_f64() * 16. - 8.,
                rng.next_f64() * 16. - 8.,
            );
            let d = V3(
                rng.next_f64() * 2. - 1.,
                rng.next_f64() * 2. - 1.,
                rng.next_f64() * 2. - 1.,
            );
            let g = |t: f64| fe.eval(s + d * t) - eps;
            let exit = fe.line_exit(s, d, eps);
            // Sample the line; the last inside sample and the next bracket the exit.
            let n = 4000;
            let at = |k: usize| -100.0 + 200.0 * k as f64 / n as f64;
            let Some(last) = (0..=n).rev().find(|&k| g(at(k)) > 0.0) else {
                assert!(
                    exit == f64::NEG_INFINITY || exit.is_finite() && g(exit - 0.05) < 1e-6,
                    "line misses the volume but exit is {exit}"
                );
                continue;
            };
            if last == n {
                assert!(exit >= at(n) - 1e-9, "still inside at the end, exit {exit}");
                continue;
            }
            let (mut lo, mut hi) = (at(last), at(last + 1));
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if g(mid) > 0.0 { lo = mid } else { hi = mid }
            }
            checked += 1;
            worst = worst.max((exit - lo).abs());
        }
        assert!(checked > 3000, "only {checked} lines met a volume");
        assert!(worst < 1e-7, "worst exit deviation {worst}");
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
