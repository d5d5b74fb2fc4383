//! Vector maths on plain `[f64; 3]` points, the one dialect the tools' geometry uses
//! (the map crate, the compiler, the check, the viewer). Plain arrays rather than a
//! vector type keep the points in the same form as the map's lumps and the samples, and
//! these few functions are all the geometry needs; the runtime keeps its own `f32`
//! type, which it stores in the file.

/// A point or a vector.
pub type P3 = [f64; 3];

/// `a - b`.
#[inline]
pub fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a + b`.
#[inline]
pub fn add(a: P3, b: P3) -> P3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a · s`.
#[inline]
pub fn scale(a: P3, s: f64) -> P3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// The dot product.
#[inline]
pub fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The cross product.
#[inline]
pub fn cross(a: P3, b: P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The length.
#[inline]
pub fn norm(a: P3) -> f64 {
    dot(a, a).sqrt()
}

/// The distance between two points.
#[inline]
pub fn dist(a: P3, b: P3) -> f64 {
    norm(sub(a, b))
}

/// The area of a planar polygon (its vertices in order).
///
/// ```
/// let square = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 2.0, 0.0], [0.0, 2.0, 0.0]];
/// assert_eq!(toolbox::vec3::polygon_area(&square), 4.0);
/// ```
pub fn polygon_area(p: &[P3]) -> f64 {
    let mut n = [0.0f64; 3];
    for i in 1..p.len().saturating_sub(1) {
        let (a, b) = (sub(p[i], p[0]), sub(p[i + 1], p[0]));
        let c = cross(a, b);
        n = [n[0] + c[0], n[1] + c[1], n[2] + c[2]];
    }
    0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cross_is_right_handed_and_orthogonal() {
        let (x, y) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        assert_eq!(cross(x, y), [0.0, 0.0, 1.0]);
        let (a, b) = ([1.5, -2.0, 0.25], [-0.5, 3.0, 4.0]);
        let c = cross(a, b);
        assert!(dot(c, a).abs() < 1e-12 && dot(c, b).abs() < 1e-12);
        assert_eq!(dist(add(a, scale(b, 2.0)), a), 2.0 * norm(b));
    }
}
