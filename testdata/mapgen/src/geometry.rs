//! Small exact-ish 3D geometry: vectors, planes, convex polygons and convex
//! cells (polytopes), with the clipping operations the BSP builder needs.
//!
//! Everything is `f64`. Side tests use [`EPS`]: the generated worlds have
//! integer coordinates (multiples of 8), so every real feature is far larger
//! than the tolerance and only rounding noise is absorbed by it.

use std::ops::{Add, Mul, Neg, Sub};

/// Tolerance of side-of-plane tests (units).
pub const EPS: f64 = 1e-6;

/// Half size of the polygon that stands for a whole plane before clipping.
const BASE_POLYGON_HALF_SIZE: f64 = 65536.0;

/// A 3D vector / point.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct V3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

impl V3 {
    /// The zero vector.
    pub const ZERO: V3 = V3::new(0.0, 0.0, 0.0);

    /// A vector from its components.
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        V3 { x, y, z }
    }
    /// The unit vector along axis `i` (0 = x, 1 = y, 2 = z).
    pub fn axis(i: usize) -> Self {
        let mut a = [0.0; 3];
        a[i] = 1.0;
        a.into()
    }
    pub fn dot(self, o: V3) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    pub fn cross(self, o: V3) -> V3 {
        V3::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    pub fn length(self) -> f64 {
        self.dot(self).sqrt()
    }
    pub fn normalized(self) -> V3 {
        self * (1.0 / self.length())
    }
    pub fn abs(self) -> V3 {
        V3::new(self.x.abs(), self.y.abs(), self.z.abs())
    }
    pub fn min(self, o: V3) -> V3 {
        V3::new(self.x.min(o.x), self.y.min(o.y), self.z.min(o.z))
    }
    pub fn max(self, o: V3) -> V3 {
        V3::new(self.x.max(o.x), self.y.max(o.y), self.z.max(o.z))
    }
    pub fn to_array(self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }
    /// Component `i` (0 = x, 1 = y, 2 = z).
    pub fn get(self, i: usize) -> f64 {
        self.to_array()[i]
    }
    /// Copy with component `i` replaced.
    pub fn with(self, i: usize, v: f64) -> V3 {
        let mut a = self.to_array();
        a[i] = v;
        a.into()
    }
}

impl From<[f64; 3]> for V3 {
    fn from(a: [f64; 3]) -> Self {
        V3::new(a[0], a[1], a[2])
    }
}
impl From<V3> for [f64; 3] {
    fn from(v: V3) -> Self {
        v.to_array()
    }
}
impl Add for V3 {
    type Output = V3;
    fn add(self, o: V3) -> V3 {
        V3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}
impl Sub for V3 {
    type Output = V3;
    fn sub(self, o: V3) -> V3 {
        V3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}
impl Mul<f64> for V3 {
    type Output = V3;
    fn mul(self, s: f64) -> V3 {
        V3::new(self.x * s, self.y * s, self.z * s)
    }
}
impl Neg for V3 {
    type Output = V3;
    fn neg(self) -> V3 {
        V3::new(-self.x, -self.y, -self.z)
    }
}

/// An oriented plane `normal · p = dist` with a unit normal. Its front side is
/// where `normal · p > dist`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    pub normal: V3,
    pub dist: f64,
}

impl Plane {
    /// A plane from a (not necessarily unit) normal and a point on it.
    pub fn through(normal: V3, point: V3) -> Self {
        let n = snap_normal(normal.normalized());
        Plane {
            normal: n,
            dist: n.dot(point),
        }
    }
    /// Signed distance of `p` (positive in front).
    pub fn distance(&self, p: V3) -> f64 {
        self.normal.dot(p) - self.dist
    }
    /// The same plane facing the other way.
    pub fn flipped(&self) -> Plane {
        Plane {
            normal: -self.normal,
            dist: -self.dist,
        }
    }
    /// The axis this plane is perpendicular to, if it is axial.
    pub fn axial(&self) -> Option<usize> {
        let a = self.normal.to_array();
        (0..3).find(|&i| a[i].abs() == 1.0)
    }
    /// Index of the largest normal component (ties go to the lower axis).
    pub fn dominant_axis(&self) -> usize {
        let a = self.normal.abs();
        if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        }
    }
}

/// Cleans rounding noise off a unit normal: components within 1e-12 of 0 or
/// ±1 become exact, so axial planes stay exactly axial.
pub fn snap_normal(n: V3) -> V3 {
    let snap = |c: f64| {
        if c.abs() < 1e-12 {
            0.0
        } else if (c.abs() - 1.0).abs() < 1e-12 {
            c.signum()
        } else {
            c
        }
    };
    let s = V3::new(snap(n.x), snap(n.y), snap(n.z));
    if s.x.abs() == 1.0 || s.y.abs() == 1.0 || s.z.abs() == 1.0 {
        s
    } else {
        s.normalized()
    }
}

/// A convex polygon; vertices counter-clockwise around its facing normal.
pub type Polygon = Vec<V3>;

/// Where a polygon lies relative to a plane.
#[derive(Debug)]
pub enum Side {
    Front,
    Back,
    /// In the plane (within [`EPS`]).
    On,
    /// Cut in two: (front part, back part).
    Spanning(Polygon, Polygon),
}

/// Classifies / splits a convex polygon by a plane. Intersection points on an
/// axial plane get that coordinate set exactly.
pub fn split_polygon(poly: &[V3], plane: &Plane) -> Side {
    let d: Vec<f64> = poly.iter().map(|&p| plane.distance(p)).collect();
    let front = d.iter().any(|&x| x > EPS);
    let back = d.iter().any(|&x| x < -EPS);
    match (front, back) {
        (false, false) => return Side::On,
        (true, false) => return Side::Front,
        (false, true) => return Side::Back,
        _ => {}
    }
    let axial = plane.axial();
    let (mut f, mut b) = (Vec::new(), Vec::new());
    for i in 0..poly.len() {
        let (p, dp) = (poly[i], d[i]);
        let j = (i + 1) % poly.len();
        let (q, dq) = (poly[j], d[j]);
        if dp >= -EPS {
            f.push(p);
        }
        if dp <= EPS {
            b.push(p);
        }
        if (dp > EPS && dq < -EPS) || (dp < -EPS && dq > EPS) {
            let t = dp / (dp - dq);
            let mut m = p + (q - p) * t;
            if let Some(ax) = axial {
                m = m.with(ax, plane.dist * plane.normal.get(ax));
            }
            f.push(m);
            b.push(m);
        }
    }
    Side::Spanning(clean(f), clean(b))
}

/// Keeps the part of `poly` behind `plane` (None when nothing of area is left).
pub fn clip_behind(poly: &[V3], plane: &Plane) -> Option<Polygon> {
    match split_polygon(poly, plane) {
        Side::Back | Side::On => Some(poly.to_vec()),
        Side::Front => None,
        Side::Spanning(_, b) => (b.len() >= 3 && polygon_area(&b) > EPS).then_some(b),
    }
}

/// Removes consecutive duplicate vertices.
fn clean(mut p: Polygon) -> Polygon {
    p.dedup_by(|a, b| (*a - *b).length() < EPS);
    while p.len() > 1 && (p[0] - p[p.len() - 1]).length() < EPS {
        p.pop();
    }
    p
}

/// A large square on `plane`, counter-clockwise around its normal.
pub fn base_polygon(plane: &Plane) -> Polygon {
    let n = plane.normal;
    let up = if plane.dominant_axis() == 2 {
        V3::new(1.0, 0.0, 0.0)
    } else {
        V3::new(0.0, 0.0, 1.0)
    };
    let u = (up - n * up.dot(n)).normalized();
    let v = n.cross(u);
    let o = n * plane.dist;
    let s = BASE_POLYGON_HALF_SIZE;
    vec![
        o + u * s + v * s,
        o - u * s + v * s,
        o - u * s - v * s,
        o + u * s - v * s,
    ]
}

/// Area vector (normal times area) of a polygon.
pub fn polygon_area_vector(poly: &[V3]) -> V3 {
    let mut a = V3::ZERO;
    for i in 1..poly.len().saturating_sub(1) {
        a = a + (poly[i] - poly[0]).cross(poly[i + 1] - poly[0]);
    }
    a * 0.5
}

/// Area of a planar polygon.
pub fn polygon_area(poly: &[V3]) -> f64 {
    polygon_area_vector(poly).length()
}

/// Average of the vertices (an interior point of a convex polygon).
pub fn centroid(points: &[V3]) -> V3 {
    let s = points.iter().fold(V3::ZERO, |a, &p| a + p);
    s * (1.0 / points.len() as f64)
}

/// Distance from `p` to the segment `a`–`b`.
pub fn point_segment_distance(p: V3, a: V3, b: V3) -> f64 {
    let ab = b - a;
    let len2 = ab.dot(ab);
    let t = if len2 > 0.0 {
        ((p - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).length()
}

/// Exact Euclidean distance from `p` to a convex polygon with unit `normal`
/// (counter-clockwise around it).
pub fn point_polygon_distance(p: V3, poly: &[V3], normal: V3) -> f64 {
    let h = (p - poly[0]).dot(normal);
    if projects_inside(p - normal * h, poly, normal) {
        return h.abs();
    }
    (0..poly.len())
        .map(|i| point_segment_distance(p, poly[i], poly[(i + 1) % poly.len()]))
        .fold(f64::INFINITY, f64::min)
}

/// Whether the projection of `p` onto the polygon's plane lies inside it.
fn projects_inside(p: V3, poly: &[V3], normal: V3) -> bool {
    (0..poly.len()).all(|i| {
        let a = poly[i];
        let b = poly[(i + 1) % poly.len()];
        (b - a).cross(p - a).dot(normal) >= 0.0
    })
}

/// Distance between the segments `p1`–`q1` and `p2`–`q2` (Ericson,
/// "Real-Time Collision Detection", 5.1.9).
pub fn segment_segment_distance(p1: V3, q1: V3, p2: V3, q2: V3) -> f64 {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.dot(d1), d2.dot(d2), d2.dot(r));
    let (s, t);
    if a <= 1e-18 && e <= 1e-18 {
        return r.length();
    }
    if a <= 1e-18 {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(r);
        if e <= 1e-18 {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > 0.0 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    ((p1 + d1 * s) - (p2 + d2 * t)).length()
}

/// Exact distance between the segment `a`–`b` and a convex polygon with unit
/// `normal` (0 if the segment crosses it).
pub fn segment_polygon_distance(a: V3, b: V3, poly: &[V3], normal: V3) -> f64 {
    let (da, db) = ((a - poly[0]).dot(normal), (b - poly[0]).dot(normal));
    if da * db <= 0.0 && da != db {
        let x = a + (b - a) * (da / (da - db));
        if projects_inside(x, poly, normal) {
            return 0.0;
        }
    }
    let ends = point_polygon_distance(a, poly, normal).min(point_polygon_distance(b, poly, normal));
    (0..poly.len())
        .map(|i| segment_segment_distance(a, b, poly[i], poly[(i + 1) % poly.len()]))
        .fold(ends, f64::min)
}

/// A face of a [`ConvexCell`]: a polygon on a plane whose normal points out of
/// the cell. `plane_id` names the plane in the builder's plane set (None for
/// the faces of the outer bounding box).
#[derive(Clone, Debug)]
pub struct CellFace {
    pub plane: Plane,
    pub plane_id: Option<usize>,
    pub polygon: Polygon,
}

/// A bounded convex polytope given by its boundary faces.
#[derive(Clone, Debug)]
pub struct ConvexCell {
    pub faces: Vec<CellFace>,
}

impl ConvexCell {
    /// The axis-aligned box `[min, max]`.
    pub fn from_box(min: V3, max: V3) -> Self {
        let mut faces = Vec::with_capacity(6);
        for axis in 0..3 {
            for (sign, value) in [(-1.0, min.get(axis)), (1.0, max.get(axis))] {
                let plane = Plane {
                    normal: V3::axis(axis) * sign,
                    dist: sign * value,
                };
                let mut poly = base_polygon(&plane);
                for other in 0..3 {
                    if other == axis {
                        continue;
                    }
                    for (s2, v2) in [(-1.0, min.get(other)), (1.0, max.get(other))] {
                        let bound = Plane {
                            normal: V3::axis(other) * s2,
                            dist: s2 * v2,
                        };
                        poly = clip_behind(&poly, &bound).expect("box face");
                    }
                }
                faces.push(CellFace {
                    plane,
                    plane_id: None,
                    polygon: poly,
                });
            }
        }
        ConvexCell { faces }
    }

    /// The convex cell cut out of a large box by half-spaces `normal·p <= dist`.
    /// None if empty.
    pub fn from_halfspaces(bound_min: V3, bound_max: V3, planes: &[Plane]) -> Option<Self> {
        let mut cell = ConvexCell::from_box(bound_min, bound_max);
        for p in planes {
            cell = cell.split(p, None).1?;
        }
        Some(cell)
    }

    /// All vertices (with repeats).
    pub fn vertices(&self) -> impl Iterator<Item = V3> + '_ {
        self.faces.iter().flat_map(|f| f.polygon.iter().copied())
    }

    /// Bounding box (min, max).
    pub fn bounds(&self) -> (V3, V3) {
        let mut lo = V3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
        let mut hi = -lo;
        for v in self.vertices() {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        (lo, hi)
    }

    /// A point strictly inside (the vertex average of a convex cell).
    pub fn interior_point(&self) -> V3 {
        let v: Vec<V3> = self.faces.iter().map(|f| centroid(&f.polygon)).collect();
        centroid(&v)
    }

    /// Whether `p` is inside (or within `EPS` of) the cell.
    pub fn contains(&self, p: V3) -> bool {
        self.faces.iter().all(|f| f.plane.distance(p) <= EPS)
    }

    /// Splits the cell by `plane` into (front part, back part); a part is None
    /// when the plane does not cut the cell on that side.
    pub fn split(
        &self,
        plane: &Plane,
        plane_id: Option<usize>,
    ) -> (Option<ConvexCell>, Option<ConvexCell>) {
        let mut d_min = f64::INFINITY;
        let mut d_max = f64::NEG_INFINITY;
        for v in self.vertices() {
            let d = plane.distance(v);
            d_min = d_min.min(d);
            d_max = d_max.max(d);
        }
        if d_min >= -EPS {
            return (Some(self.clone()), None);
        }
        if d_max <= EPS {
            return (None, Some(self.clone()));
        }
        let mut cap = Some(base_polygon(plane));
        for f in &self.faces {
            cap = cap.and_then(|c| clip_behind(&c, &f.plane));
        }
        let Some(cap) = cap else {
            // Only grazes the cell: keep it whole on the bigger side.
            return if d_max > -d_min {
                (Some(self.clone()), None)
            } else {
                (None, Some(self.clone()))
            };
        };
        let (mut front, mut back) = (Vec::new(), Vec::new());
        for f in &self.faces {
            match split_polygon(&f.polygon, plane) {
                Side::Front => front.push(f.clone()),
                Side::Back => back.push(f.clone()),
                Side::On => {}
                Side::Spanning(a, b) => {
                    if a.len() >= 3 && polygon_area(&a) > EPS {
                        front.push(CellFace {
                            polygon: a,
                            ..f.clone()
                        });
                    }
                    if b.len() >= 3 && polygon_area(&b) > EPS {
                        back.push(CellFace {
                            polygon: b,
                            ..f.clone()
                        });
                    }
                }
            }
        }
        let mut reversed = cap.clone();
        reversed.reverse();
        front.push(CellFace {
            plane: plane.flipped(),
            plane_id,
            polygon: reversed,
        });
        back.push(CellFace {
            plane: *plane,
            plane_id,
            polygon: cap,
        });
        (
            Some(ConvexCell { faces: front }),
            Some(ConvexCell { faces: back }),
        )
    }
}

/// The set of distinct planes of a map, each stored once in canonical
/// orientation: axial planes with a positive normal, others with a positive
/// dominant component (the GoldSrc convention; faces record the side).
#[derive(Clone, Debug, Default)]
pub struct PlaneSet {
    planes: Vec<Plane>,
}

impl PlaneSet {
    /// Adds (or finds) `plane`; returns its index and whether the stored
    /// plane faces the opposite way.
    pub fn insert(&mut self, plane: Plane) -> (usize, bool) {
        let flip = plane.normal.get(plane.dominant_axis()) < 0.0;
        let c = if flip { plane.flipped() } else { plane };
        for (i, p) in self.planes.iter().enumerate() {
            if (p.normal - c.normal).length() < 1e-9 && (p.dist - c.dist).abs() < 1e-6 {
                return (i, flip);
            }
        }
        self.planes.push(c);
        (self.planes.len() - 1, flip)
    }
    /// The stored (canonical) plane `i`.
    pub fn get(&self, i: usize) -> Plane {
        self.planes[i]
    }
    pub fn len(&self) -> usize {
        self.planes.len()
    }
    pub fn is_empty(&self) -> bool {
        self.planes.is_empty()
    }
    pub fn iter(&self) -> impl Iterator<Item = &Plane> {
        self.planes.iter()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_cell_splits_into_two_boxes() {
        let c = ConvexCell::from_box(V3::ZERO, V3::new(2.0, 2.0, 2.0));
        let p = Plane {
            normal: V3::new(1.0, 0.0, 0.0),
            dist: 0.5,
        };
        let (f, b) = c.split(&p, None);
        let (f, b) = (f.unwrap(), b.unwrap());
        assert_eq!(f.faces.len(), 6);
        assert_eq!(b.faces.len(), 6);
        let area = |c: &ConvexCell| {
            c.faces
                .iter()
                .map(|f| polygon_area(&f.polygon))
                .sum::<f64>()
        };
        assert!((area(&b) - (8.0 + 4.0 * 1.0)).abs() < 1e-9);
        assert!((area(&f) - (8.0 + 4.0 * 3.0)).abs() < 1e-9);
        assert!(f.contains(V3::new(1.5, 1.0, 1.0)) && !f.contains(V3::new(0.2, 1.0, 1.0)));
    }

    #[test]
    fn faces_face_outwards() {
        let c = ConvexCell::from_box(V3::ZERO, V3::new(1.0, 2.0, 3.0));
        for f in &c.faces {
            let n = polygon_area_vector(&f.polygon).normalized();
            assert!((n - f.plane.normal).length() < 1e-9);
        }
    }

    #[test]
    fn polygon_distance_inside_and_outside() {
        let sq = vec![
            V3::new(0.0, 0.0, 0.0),
            V3::new(1.0, 0.0, 0.0),
            V3::new(1.0, 1.0, 0.0),
            V3::new(0.0, 1.0, 0.0),
        ];
        let n = V3::new(0.0, 0.0, 1.0);
        assert_eq!(point_polygon_distance(V3::new(0.5, 0.5, 2.0), &sq, n), 2.0);
        let d = point_polygon_distance(V3::new(2.0, 0.5, 1.0), &sq, n);
        assert!((d - 2f64.sqrt()).abs() < 1e-12);
        let seg = |a: [f64; 3], b: [f64; 3]| segment_polygon_distance(a.into(), b.into(), &sq, n);
        assert_eq!(seg([0.5, 0.5, 1.0], [0.5, 0.5, -1.0]), 0.0);
        assert!((seg([2.0, 0.5, 1.0], [2.0, 0.5, -1.0]) - 1.0).abs() < 1e-12);
        assert!((seg([-1.0, 0.5, 3.0], [2.0, 0.5, 3.0]) - 3.0).abs() < 1e-12);
        assert!((seg([2.0, -1.0, 0.0], [2.0, 2.0, 0.0]) - 1.0).abs() < 1e-12);
    }
}
