//! Small shared helpers: a seedable generator and the few vector operations the
//! geometry modules share (points are plain `[f64; 3]` throughout the map crate and
//! the compiler, which re-exports this module as `bsp2vdg::util`).

/// `a - b`.
#[inline]
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The dot product.
#[inline]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The cross product.
#[inline]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Area of a planar polygon.
pub fn polygon_area(p: &[[f64; 3]]) -> f64 {
    let mut n = [0.0f64; 3];
    for i in 1..p.len().saturating_sub(1) {
        let (a, b) = (sub(p[i], p[0]), sub(p[i + 1], p[0]));
        let c = cross(a, b);
        n = [n[0] + c[0], n[1] + c[1], n[2] + c[2]];
    }
    0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
}
