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

const EPSILON: f64 = f64::EPSILON / 2.0;
/// Shewchuk's first-stage error bound factors (as in `robust`).
const O3D_ERRBOUND_A: f64 = (7.0 + 56.0 * EPSILON) * EPSILON;
const ISP_ERRBOUND_A: f64 = (16.0 + 224.0 * EPSILON) * EPSILON;
/// Static (semi-static) bounds: with `M` the largest absolute coordinate difference, the
/// permanent of Shewchuk's first stage is at most `6 M³` (orient3d: 3 terms of
/// |z|·(|x y| + |x y|)) and `72 M⁵` (insphere: 4 lifts ≤ 3M² times 3×3 permanents ≤ 6M³),
/// so `A · 6 M³` and `A · 72 M⁵` bound the error of the float determinant. They need no
/// permanent, which saves a third of the filter's flops; the margin covers the rounding of
/// the bound itself. Outside `M ∈ [2^-100, 2^100]` (no underflow or overflow of M⁵)
/// the exact stages are used.
const O3D_STATIC: f64 = O3D_ERRBOUND_A * 6.0 * (1.0 + 1e-10);
const ISP_STATIC: f64 = ISP_ERRBOUND_A * 72.0 * (1.0 + 1e-10);
const STATIC_MIN: f64 = 7.888609052210118e-31; // 2^-100
const STATIC_MAX: f64 = 1.2676506002282294e30; // 2^100

/// `max` without `f64::max`'s NaN handling (one `maxsd`): differences of finite inputs
/// are never NaN.
#[inline(always)]
fn fmax(a: f64, b: f64) -> f64 {
    if a > b { a } else { b }
}

/// Exact sign of the orientation determinant of `a, b, c, d`. The magnitude is the float
/// estimate when the filter decides, otherwise only the sign is meaningful.
///
/// Three stages: the float evaluation with Shewchuk's error bound; if that is inconclusive
/// and all coordinate differences are exact dyadic numbers of at most 40 significant bits
/// (always the case for grid-aligned wall samples), the determinant in 128-bit integers —
/// or, for small-integer points close together, the float value itself, which is then
/// exact (see [`small_int_points`]); otherwise `robust`'s adaptive expansion arithmetic.
#[inline]
pub fn orient3d(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> f64 {
    let (adx, bdx, cdx) = (a[0] - d[0], b[0] - d[0], c[0] - d[0]);
    let (ady, bdy, cdy) = (a[1] - d[1], b[1] - d[1], c[1] - d[1]);
    let (adz, bdz, cdz) = (a[2] - d[2], b[2] - d[2], c[2] - d[2]);
    let bdxcdy = bdx * cdy;
    let cdxbdy = cdx * bdy;
    let cdxady = cdx * ady;
    let adxcdy = adx * cdy;
    let adxbdy = adx * bdy;
    let bdxady = bdx * ady;
    let det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    let m = [adx, bdx, cdx, ady, bdy, cdy, adz, bdz, cdz]
        .iter()
        .fold(0.0, |m, x| fmax(m, x.abs()));
    let errbound = O3D_STATIC * (m * m * m);
    if (det > errbound || -det > errbound) && (STATIC_MIN..=STATIC_MAX).contains(&m) {
        return det;
    }
    orient3d_slow(a, b, c, d, det, m)
}

/// Largest coordinate difference for which the float evaluation of [`orient3d`] is exact
/// on small-integer points (see [`small_int_points`]): every product and partial sum is an
/// integer of magnitude at most `6 M³ ≤ 2^51`.
const O3D_EXACT_M: f64 = 65536.0; // 2^16
/// The same for [`insphere`]: magnitudes at most `72 M⁵ < 2^52`.
const ISP_EXACT_M: f64 = 512.0; // 2^9

/// Whether every coordinate of `pts` is an integer of magnitude below 2^22: then every
/// coordinate difference is an integer below 2^23, exact in f64, and the float evaluation
/// of a determinant is exact when no intermediate result exceeds 2^53 (see `O3D_EXACT_M`,
/// `ISP_EXACT_M`). Grid-aligned wall samples are such points, and their exact ties are
/// the common case of an inconclusive filter: the float value, zero included, is then
/// already the exact answer.
#[inline(always)]
fn small_int_points<const P: usize>(pts: [&[f64; 3]; P]) -> bool {
    const LIMIT: f64 = 4_194_304.0; // 2^22
    // Adding 1.5 · 2^52 rounds any |x| < 2^51 to an integer (the sum's unit in the last
    // place is 1) and subtracting it back is exact: `x` is an integer iff it survives.
    const ROUND: f64 = 6_755_399_441_055_744.0;
    let mut ok = true;
    for p in pts {
        for x in *p {
            // `&` rather than `&&`: no branches, the compiler pairs the lanes in SSE2.
            ok &= (x.abs() < LIMIT) & ((x + ROUND) - ROUND == x);
        }
    }
    ok
}

/// The exact stages of [`orient3d`]; `det` and `m` are the float determinant and the
/// largest absolute coordinate difference from the filter.
#[cold]
#[inline(never)]
fn orient3d_slow(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3], det: f64, m: f64) -> f64 {
    if m <= O3D_EXACT_M && small_int_points([a, b, c, d]) {
        return det;
    }
    orient3d_exact(a, b, c, d)
}

/// The integer, dynamic-filter and expansion stages of [`orient3d`] (kept out of
/// [`orient3d_slow`] so the frequent exact-float answer needs no large stack frame).
#[cold]
#[inline(never)]
fn orient3d_exact(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> f64 {
    // Exact ties on grid-aligned input are the common case here: integers first, then the
    // dynamic (permanent-based) filter, tighter than the static one, then expansions.
    if let Some(v) = orient3d_int(a, b, c, d) {
        return v;
    }
    let quick = robust_orient3d_filter(a, b, c, d);
    if quick != 0.0 {
        return quick;
    }
    robust::orient3d(coord(a), coord(b), coord(c), coord(d))
}

/// The float filter of [`orient3d`] for the four tetrahedra made by replacing each vertex of
/// `v` in turn by `q` (the point location's question: which facets of a cell separate it
/// from `q`). Returns the determinants `det[i] ≈ orient3d(v with v[i] = q)` and one error
/// bound: `det[i]`'s sign is exact when `|det[i]| > bound`, otherwise the caller asks
/// [`orient3d`] (the bound is infinite when the filter cannot apply at all).
///
/// All four share the differences `v[j] − q` and their six 2×2 minors. Each determinant is
/// the expression [`orient3d`] evaluates for the tetrahedron with `q` moved to the last
/// place (an odd or even number of swaps, hence the signs), term for term — a minor taken
/// with its rows swapped is its exact negation — so [`orient3d`]'s static error bound
/// holds; it is taken over the largest of all twelve differences, which only loosens it.
#[inline(always)]
pub fn facet_orientations(v: [&[f64; 3]; 4], q: &[f64; 3]) -> ([f64; 4], f64) {
    let d = v.map(|p| [p[0] - q[0], p[1] - q[1], p[2] - q[2]]);
    let minor = |a: usize, b: usize| d[a][0] * d[b][1] - d[b][0] * d[a][1];
    let (m01, m02, m03) = (minor(0, 1), minor(0, 2), minor(0, 3));
    let (m12, m13, m23) = (minor(1, 2), minor(1, 3), minor(2, 3));
    let z = |j: usize| d[j][2];
    let det = [
        // q in place 0: (q, v1, v2, v3) is an odd permutation of (v1, v2, v3, q).
        -((z(1) * m23 - z(2) * m13) + z(3) * m12),
        // q in place 1: (v0, q, v2, v3) is even.
        (z(0) * m23 - z(2) * m03) + z(3) * m02,
        // q in place 2: (v0, v1, q, v3) is odd.
        -((z(0) * m13 - z(1) * m03) + z(3) * m01),
        // q in place 3: orient3d's own form.
        (z(0) * m12 - z(1) * m02) + z(2) * m01,
    ];
    let m = d.iter().flatten().fold(0.0, |m, &x| fmax(m, x.abs()));
    let bound = if (STATIC_MIN..=STATIC_MAX).contains(&m) {
        O3D_STATIC * (m * m * m)
    } else {
        f64::INFINITY
    };
    (det, bound)
}

/// Exact sign of the insphere determinant; `a, b, c, d` must be positively oriented.
/// Same three stages as [`orient3d`] (integer stage: differences of at most 23 bits).
#[inline]
pub fn insphere(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3], e: &[f64; 3]) -> f64 {
    let (det, m) = insphere_det_and_max(a, b, c, d, e);
    let m2 = m * m;
    let errbound = ISP_STATIC * (m2 * m2 * m);
    if (det > errbound || -det > errbound) && (STATIC_MIN..=STATIC_MAX).contains(&m) {
        return det;
    }
    insphere_slow(a, b, c, d, e, det, m)
}

/// The float insphere determinant (Shewchuk's expansion order) and the largest absolute
/// coordinate difference. The conflict test runs this ~45 times per inserted point, so on
/// x86-64 it is evaluated two rows at a time in SSE2 registers
/// ([`insphere_det_and_max_sse2`]); every lane performs exactly the scalar operations of
/// [`insphere_det_and_max_scalar`] in the same order, so both give identical bits and the
/// static error bound applies unchanged.
#[inline(always)]
fn insphere_det_and_max(
    a: &[f64; 3],
    b: &[f64; 3],
    c: &[f64; 3],
    d: &[f64; 3],
    e: &[f64; 3],
) -> (f64, f64) {
    #[cfg(target_arch = "x86_64")]
    {
        insphere_det_and_max_sse2(a, b, c, d, e)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        insphere_det_and_max_scalar(a, b, c, d, e)
    }
}

/// Reference evaluation of [`insphere_det_and_max`], one operation at a time.
#[cfg_attr(target_arch = "x86_64", allow(dead_code))]
#[inline(always)]
fn insphere_det_and_max_scalar(
    a: &[f64; 3],
    b: &[f64; 3],
    c: &[f64; 3],
    d: &[f64; 3],
    e: &[f64; 3],
) -> (f64, f64) {
    let (aex, bex, cex, dex) = (a[0] - e[0], b[0] - e[0], c[0] - e[0], d[0] - e[0]);
    let (aey, bey, cey, dey) = (a[1] - e[1], b[1] - e[1], c[1] - e[1], d[1] - e[1]);
    let (aez, bez, cez, dez) = (a[2] - e[2], b[2] - e[2], c[2] - e[2], d[2] - e[2]);
    let ab = aex * bey - bex * aey;
    let bc = bex * cey - cex * bey;
    let cd = cex * dey - dex * cey;
    let da = dex * aey - aex * dey;
    let ac = aex * cey - cex * aey;
    let bd = bex * dey - dex * bey;
    let abc = aez * bc - bez * ac + cez * ab;
    let bcd = bez * cd - cez * bd + dez * bc;
    let cda = cez * da + dez * ac + aez * cd;
    let dab = dez * ab + aez * bd + bez * da;
    let alift = aex * aex + aey * aey + aez * aez;
    let blift = bex * bex + bey * bey + bez * bez;
    let clift = cex * cex + cey * cey + cez * cez;
    let dlift = dex * dex + dey * dey + dez * dez;
    let det = (dlift * abc - clift * dab) + (blift * cda - alift * bcd);
    let m = [aex, bex, cex, dex, aey, bey, cey, dey, aez, bez, cez, dez]
        .iter()
        .fold(0.0, |m, x| fmax(m, x.abs()));
    (det, m)
}

/// [`insphere_det_and_max_scalar`] with rows `(a, c)` in the two lanes of one register and
/// `(b, d)` in another (SSE2 is part of the x86-64 baseline). Written out lane by lane:
/// `[ab, cd] = X0·Y1 − X1·Y0`, `[bc, da] = X1·Y0' − X0'·Y1` (`'` swaps lanes),
/// `[ac, bd]` from the cross products `X0·Y0'` and `X1·Y1'`; then
/// `[abc, cda] = (Z0·[bc, da] + [−bez, dez]·ac) + Z0'·[ab, cd]`,
/// `[bcd, dab] = (Z1·[cd, ab] + [−cez, aez]·bd) + Z1'·[bc, da]` and
/// `det = (dlift·abc − clift·dab) + (blift·cda − alift·bcd)` as the sum of the two lanes of
/// `[dlift, blift]·[abc, cda] − [clift, alift]·[dab, bcd]` — the scalar expressions with the
/// same association (`x − y·z` as `x + (−y)·z`, which rounds identically).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn insphere_det_and_max_sse2(
    a: &[f64; 3],
    b: &[f64; 3],
    c: &[f64; 3],
    d: &[f64; 3],
    e: &[f64; 3],
) -> (f64, f64) {
    use std::arch::x86_64::*;
    // SAFETY: SSE2 is part of the x86-64 baseline, so these intrinsics are always available;
    // no memory is accessed through pointers.
    unsafe {
        // `_mm_set_pd(hi, lo)`: lane 0 is the second argument.
        let pair = |lo: f64, hi: f64| _mm_set_pd(hi, lo);
        let swap = |v: __m128d| _mm_shuffle_pd::<1>(v, v);
        let (ex, ey, ez) = (_mm_set1_pd(e[0]), _mm_set1_pd(e[1]), _mm_set1_pd(e[2]));
        let x0 = _mm_sub_pd(pair(a[0], c[0]), ex); // [aex, cex]
        let y0 = _mm_sub_pd(pair(a[1], c[1]), ey);
        let z0 = _mm_sub_pd(pair(a[2], c[2]), ez);
        let x1 = _mm_sub_pd(pair(b[0], d[0]), ex); // [bex, dex]
        let y1 = _mm_sub_pd(pair(b[1], d[1]), ey);
        let z1 = _mm_sub_pd(pair(b[2], d[2]), ez);
        let ab_cd = _mm_sub_pd(_mm_mul_pd(x0, y1), _mm_mul_pd(x1, y0));
        let bc_da = _mm_sub_pd(_mm_mul_pd(x1, swap(y0)), _mm_mul_pd(swap(x0), y1));
        let p = _mm_mul_pd(x0, swap(y0)); // [aex·cey, cex·aey]
        let q = _mm_mul_pd(x1, swap(y1)); // [bex·dey, dex·bey]
        let ac_bd = _mm_sub_pd(_mm_unpacklo_pd(p, q), _mm_unpackhi_pd(p, q));
        let ac_ac = _mm_unpacklo_pd(ac_bd, ac_bd);
        let bd_bd = _mm_unpackhi_pd(ac_bd, ac_bd);
        let neg_lo = _mm_set_pd(0.0, -0.0);
        let abc_cda = _mm_add_pd(
            _mm_add_pd(
                _mm_mul_pd(z0, bc_da),
                _mm_mul_pd(_mm_xor_pd(z1, neg_lo), ac_ac),
            ),
            _mm_mul_pd(swap(z0), ab_cd),
        );
        let bcd_dab = _mm_add_pd(
            _mm_add_pd(
                _mm_mul_pd(z1, swap(ab_cd)),
                _mm_mul_pd(_mm_xor_pd(swap(z0), neg_lo), bd_bd),
            ),
            _mm_mul_pd(swap(z1), bc_da),
        );
        let lift0 = _mm_add_pd(
            _mm_add_pd(_mm_mul_pd(x0, x0), _mm_mul_pd(y0, y0)),
            _mm_mul_pd(z0, z0),
        ); // [alift, clift]
        let lift1 = _mm_add_pd(
            _mm_add_pd(_mm_mul_pd(x1, x1), _mm_mul_pd(y1, y1)),
            _mm_mul_pd(z1, z1),
        ); // [blift, dlift]
        let u = _mm_sub_pd(
            _mm_mul_pd(swap(lift1), abc_cda),
            _mm_mul_pd(swap(lift0), swap(bcd_dab)),
        );
        let det = _mm_cvtsd_f64(_mm_add_sd(u, _mm_unpackhi_pd(u, u)));
        let abs_mask = _mm_castsi128_pd(_mm_set1_epi64x(i64::MAX));
        let abs = |v: __m128d| _mm_and_pd(v, abs_mask);
        let mx = _mm_max_pd(
            _mm_max_pd(_mm_max_pd(abs(x0), abs(x1)), _mm_max_pd(abs(y0), abs(y1))),
            _mm_max_pd(abs(z0), abs(z1)),
        );
        let m = _mm_cvtsd_f64(_mm_max_sd(mx, _mm_unpackhi_pd(mx, mx)));
        (det, m)
    }
}

#[cold]
#[inline(never)]
fn insphere_slow(
    a: &[f64; 3],
    b: &[f64; 3],
    c: &[f64; 3],
    d: &[f64; 3],
    e: &[f64; 3],
    det: f64,
    m: f64,
) -> f64 {
    if m <= ISP_EXACT_M && small_int_points([a, b, c, d, e]) {
        return det;
    }
    insphere_exact(a, b, c, d, e)
}

/// The integer, dynamic-filter and expansion stages of [`insphere`] (kept out of
/// [`insphere_slow`] like [`orient3d_exact`]).
#[cold]
#[inline(never)]
fn insphere_exact(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3], e: &[f64; 3]) -> f64 {
    if let Some(v) = insphere_int(a, b, c, d, e) {
        return v;
    }
    let quick = robust_insphere_filter(a, b, c, d, e);
    if quick != 0.0 {
        return quick;
    }
    robust::insphere(coord(a), coord(b), coord(c), coord(d), coord(e))
}

/// Shewchuk's first-stage (dynamic) filter: the determinant if its sign is certain, else 0.
fn robust_orient3d_filter(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> f64 {
    let (adx, bdx, cdx) = (a[0] - d[0], b[0] - d[0], c[0] - d[0]);
    let (ady, bdy, cdy) = (a[1] - d[1], b[1] - d[1], c[1] - d[1]);
    let (adz, bdz, cdz) = (a[2] - d[2], b[2] - d[2], c[2] - d[2]);
    let bdxcdy = bdx * cdy;
    let cdxbdy = cdx * bdy;
    let cdxady = cdx * ady;
    let adxcdy = adx * cdy;
    let adxbdy = adx * bdy;
    let bdxady = bdx * ady;
    let det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    let permanent = (bdxcdy.abs() + cdxbdy.abs()) * adz.abs()
        + (cdxady.abs() + adxcdy.abs()) * bdz.abs()
        + (adxbdy.abs() + bdxady.abs()) * cdz.abs();
    let errbound = O3D_ERRBOUND_A * permanent;
    if det > errbound || -det > errbound {
        det
    } else {
        0.0
    }
}

/// Shewchuk's first-stage (dynamic) insphere filter: the determinant if certain, else 0.
fn robust_insphere_filter(
    a: &[f64; 3],
    b: &[f64; 3],
    c: &[f64; 3],
    d: &[f64; 3],
    e: &[f64; 3],
) -> f64 {
    let (aex, bex, cex, dex) = (a[0] - e[0], b[0] - e[0], c[0] - e[0], d[0] - e[0]);
    let (aey, bey, cey, dey) = (a[1] - e[1], b[1] - e[1], c[1] - e[1], d[1] - e[1]);
    let (aez, bez, cez, dez) = (a[2] - e[2], b[2] - e[2], c[2] - e[2], d[2] - e[2]);
    let aexbey = aex * bey;
    let bexaey = bex * aey;
    let ab = aexbey - bexaey;
    let bexcey = bex * cey;
    let cexbey = cex * bey;
    let bc = bexcey - cexbey;
    let cexdey = cex * dey;
    let dexcey = dex * cey;
    let cd = cexdey - dexcey;
    let dexaey = dex * aey;
    let aexdey = aex * dey;
    let da = dexaey - aexdey;
    let aexcey = aex * cey;
    let cexaey = cex * aey;
    let ac = aexcey - cexaey;
    let bexdey = bex * dey;
    let dexbey = dex * bey;
    let bd = bexdey - dexbey;
    let abc = aez * bc - bez * ac + cez * ab;
    let bcd = bez * cd - cez * bd + dez * bc;
    let cda = cez * da + dez * ac + aez * cd;
    let dab = dez * ab + aez * bd + bez * da;
    let alift = aex * aex + aey * aey + aez * aez;
    let blift = bex * bex + bey * bey + bez * bez;
    let clift = cex * cex + cey * cey + cez * cez;
    let dlift = dex * dex + dey * dey + dez * dez;
    let det = (dlift * abc - clift * dab) + (blift * cda - alift * bcd);
    let (aezp, bezp, cezp, dezp) = (aez.abs(), bez.abs(), cez.abs(), dez.abs());
    let permanent = ((cexdey.abs() + dexcey.abs()) * bezp
        + (dexbey.abs() + bexdey.abs()) * cezp
        + (bexcey.abs() + cexbey.abs()) * dezp)
        * alift
        + ((dexaey.abs() + aexdey.abs()) * cezp
            + (aexcey.abs() + cexaey.abs()) * dezp
            + (cexdey.abs() + dexcey.abs()) * aezp)
            * blift
        + ((aexbey.abs() + bexaey.abs()) * dezp
            + (bexdey.abs() + dexbey.abs()) * aezp
            + (dexaey.abs() + aexdey.abs()) * bezp)
            * clift
        + ((bexcey.abs() + cexbey.abs()) * aezp
            + (cexaey.abs() + aexcey.abs()) * bezp
            + (aexbey.abs() + bexaey.abs()) * cezp)
            * dlift;
    let errbound = ISP_ERRBOUND_A * permanent;
    if det > errbound || -det > errbound {
        det
    } else {
        0.0
    }
}

/// `x − y` if it is exact in f64 (Knuth's two-sum tail is zero).
#[inline]
fn exact_diff(x: f64, y: f64) -> Option<f64> {
    let d = x - y;
    let bvirt = x - d;
    let avirt = d + bvirt;
    let tail = (x - avirt) + (bvirt - y);
    (tail == 0.0).then_some(d)
}

/// Scale exact differences to integers: `Some(ints)` when all of them are dyadic numbers
/// spanning at most `bits` bits between the highest and lowest set bit over the whole set
/// (a common binary scale keeps ratios, so determinant signs are unchanged).
fn scaled_ints<const N: usize>(diffs: [f64; N], bits: i32) -> Option<[i64; N]> {
    let mut lo = i32::MAX;
    let mut hi = i32::MIN;
    for &x in &diffs {
        if x == 0.0 {
            continue;
        }
        let raw = x.to_bits();
        let exp = ((raw >> 52) & 0x7ff) as i32;
        if exp == 0 || exp == 0x7ff {
            return None; // subnormal or non-finite
        }
        let mant = (raw & ((1u64 << 52) - 1)) | (1u64 << 52);
        lo = lo.min(exp - 1075 + mant.trailing_zeros() as i32);
        hi = hi.max(exp - 1022); // |x| < 2^hi
    }
    if lo == i32::MAX {
        return Some([0; N]);
    }
    if hi - lo > bits {
        return None;
    }
    // x · 2^-lo is an integer below 2^bits: exact in f64 and in i64.
    let scale = f64::from_bits(((1023 - lo) as u64) << 52);
    if !(scale.is_finite() && scale > 0.0) {
        return None;
    }
    Some(diffs.map(|x| (x * scale) as i64))
}

/// Fast case of the integer stage: every coordinate an integer of magnitude below 2^22
/// (grid-aligned samples), so all differences are exact integers below 2^23 — no
/// per-difference analysis needed. Differences are `p[k] − origin[k]`, flattened.
#[inline]
fn small_int_diffs<const P: usize, const N: usize>(
    pts: [&[f64; 3]; P],
    origin: &[f64; 3],
) -> Option<[i64; N]> {
    const LIMIT: f64 = 4_194_304.0; // 2^22
    // (`as i64` round trip rather than `trunc`, which is a libm call on baseline x86-64.)
    let ok = |x: f64| x.abs() < LIMIT && (x as i64) as f64 == x;
    if !origin.iter().all(|&x| ok(x)) || !pts.iter().all(|p| p.iter().all(|&x| ok(x))) {
        return None;
    }
    let mut out = [0i64; N];
    for (i, p) in pts.iter().enumerate() {
        for k in 0..3 {
            out[3 * i + k] = p[k] as i64 - origin[k] as i64;
        }
    }
    Some(out)
}

fn orient3d_int(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> Option<f64> {
    let v = match small_int_diffs([a, b, c], d) {
        Some(v) => v,
        None => {
            let mut diffs = [0.0; 9];
            for k in 0..3 {
                diffs[k] = exact_diff(a[k], d[k])?;
                diffs[3 + k] = exact_diff(b[k], d[k])?;
                diffs[6 + k] = exact_diff(c[k], d[k])?;
            }
            // |entries| < 2^40: 2×2 minors < 2^81, the determinant < 2^123.
            scaled_ints(diffs, 40)?
        }
    }
    .map(|x| x as i128);
    let [adx, ady, adz, bdx, bdy, bdz, cdx, cdy, cdz] = v;
    let det = adz * (bdx * cdy - cdx * bdy)
        + bdz * (cdx * ady - adx * cdy)
        + cdz * (adx * bdy - bdx * ady);
    Some(det.signum() as f64)
}

fn insphere_int(
    a: &[f64; 3],
    b: &[f64; 3],
    c: &[f64; 3],
    d: &[f64; 3],
    e: &[f64; 3],
) -> Option<f64> {
    let ints = match small_int_diffs([a, b, c, d], e) {
        Some(v) => v,
        None => {
            let mut diffs = [0.0; 12];
            for k in 0..3 {
                diffs[k] = exact_diff(a[k], e[k])?;
                diffs[3 + k] = exact_diff(b[k], e[k])?;
                diffs[6 + k] = exact_diff(c[k], e[k])?;
                diffs[9 + k] = exact_diff(d[k], e[k])?;
            }
            scaled_ints(diffs, 23)?
        }
    };
    // |entries| < 2^23: 2×2 minors < 2^47 (i64), 3×3 < 2^72, lifts < 2^48, det < 2^122.
    let [aex, aey, aez, bex, bey, bez, cex, cey, cez, dex, dey, dez] = ints;
    let ab = (aex * bey - bex * aey) as i128;
    let bc = (bex * cey - cex * bey) as i128;
    let cd = (cex * dey - dex * cey) as i128;
    let da = (dex * aey - aex * dey) as i128;
    let ac = (aex * cey - cex * aey) as i128;
    let bd = (bex * dey - dex * bey) as i128;
    let (aez, bez, cez, dez) = (aez as i128, bez as i128, cez as i128, dez as i128);
    let abc = aez * bc - bez * ac + cez * ab;
    let bcd = bez * cd - cez * bd + dez * bc;
    let cda = cez * da + dez * ac + aez * cd;
    let dab = dez * ab + aez * bd + bez * da;
    let lift = |x: i64, y: i64, z: i128| (x * x + y * y) as i128 + z * z;
    let alift = lift(aex, aey, aez);
    let blift = lift(bex, bey, bez);
    let clift = lift(cex, cey, cez);
    let dlift = lift(dex, dey, dez);
    let det = (dlift * abc - clift * dab) + (blift * cda - alift * bcd);
    Some(det.signum() as f64)
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
    // The two largest of the five (distinct) ids, largest first.
    let mut top = [0u32; 2];
    for x in [tet[0], tet[1], tet[2], tet[3], q] {
        if x > top[0] {
            top = [x, top[0]];
        } else if x > top[1] {
            top[1] = x;
        }
    }
    for m in top {
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

    fn sign(x: f64) -> i32 {
        (x > 0.0) as i32 - (x < 0.0) as i32
    }

    /// `orient3d` of the first four points of `p` and `robust`'s value, whose signs must
    /// agree.
    fn orient3d_against_robust(p: &[[f64; 3]]) -> (f64, f64) {
        let o = orient3d(&p[0], &p[1], &p[2], &p[3]);
        let r = robust::orient3d(coord(&p[0]), coord(&p[1]), coord(&p[2]), coord(&p[3]));
        assert_eq!(sign(o), sign(r), "{p:?}");
        (o, r)
    }

    /// `insphere` of the five points of `p` and `robust`'s value, whose signs must agree.
    fn insphere_against_robust(p: &[[f64; 3]]) -> (f64, f64) {
        let i = insphere(&p[0], &p[1], &p[2], &p[3], &p[4]);
        let r = robust::insphere(
            coord(&p[0]),
            coord(&p[1]),
            coord(&p[2]),
            coord(&p[3]),
            coord(&p[4]),
        );
        assert_eq!(sign(i), sign(r), "{p:?}");
        (i, r)
    }

    /// The integer stage must agree with `robust` on near-degenerate dyadic inputs.
    #[test]
    fn integer_stage_agrees_with_robust() {
        let mut rng = toolbox::SplitMix64::new(99);
        let mut zeros = 0;
        // Quarter steps use the general dyadic analysis, whole steps the small-integer case.
        for i in 0..20000 {
            let step = if i % 2 == 0 { 0.25 } else { 24.0 };
            let mut pick = || ((rng.next_u64() % 9) as f64 - 4.0) * step + 1024.0;
            let p: Vec<[f64; 3]> = (0..5).map(|_| [pick(), pick(), pick()]).collect();
            let (o, r) = orient3d_against_robust(&p);
            assert_eq!(
                sign(orient3d_int(&p[0], &p[1], &p[2], &p[3]).unwrap()),
                sign(r)
            );
            if o > 0.0 {
                let (_, r) = insphere_against_robust(&p);
                assert_eq!(
                    sign(insphere_int(&p[0], &p[1], &p[2], &p[3], &p[4]).unwrap()),
                    sign(r)
                );
                zeros += usize::from(r == 0.0);
            }
        }
        assert!(zeros > 10, "the test must exercise exact ties");
        // Too many significant bits: the integer stage declines.
        assert!(
            orient3d_int(
                &[0.0; 3],
                &[1.0, 0.0, 0.0],
                &[0.0, 1.0, 0.0],
                &[1e-30, 0.0, 1.0]
            )
            .is_none()
        );
    }

    /// The exact float answers (small-integer points, differences up to `ISP_EXACT_M` and
    /// `O3D_EXACT_M`) must agree with `robust`, ties included, also at the limits: the
    /// largest allowed differences and coordinates just below 2^22.
    #[test]
    fn exact_float_answers_on_small_integers_agree_with_robust() {
        let mut rng = toolbox::SplitMix64::new(41);
        let (mut ties, mut shortcut) = (0, 0);
        for i in 0..40_000 {
            // Steps making the largest difference exactly the limit (4 steps of a 5-grid).
            let (step, limit) = if i % 2 == 0 {
                (ISP_EXACT_M / 4.0, ISP_EXACT_M)
            } else {
                (O3D_EXACT_M / 4.0, O3D_EXACT_M)
            };
            let origin = if i % 4 < 2 {
                -4_194_000.0
            } else {
                4_194_303.0 - 4.0 * step
            };
            let mut pick = || origin + (rng.next_u64() % 5) as f64 * step;
            let p: Vec<[f64; 3]> = (0..5).map(|_| [pick(), pick(), pick()]).collect();
            assert!(small_int_points([&p[0], &p[1], &p[2], &p[3], &p[4]]));
            let (o, _) = orient3d_against_robust(&p);
            if o > 0.0 && limit == ISP_EXACT_M {
                let (_, m) = insphere_det_and_max(&p[0], &p[1], &p[2], &p[3], &p[4]);
                shortcut += usize::from(m <= ISP_EXACT_M);
                let (_, r) = insphere_against_robust(&p);
                ties += usize::from(r == 0.0);
            }
        }
        assert!(
            ties > 10 && shortcut > 1000,
            "{ties} ties, {shortcut} shortcuts"
        );
        // Not small integers: a fraction, or a coordinate beyond 2^22.
        assert!(!small_int_points([&[0.5, 0.0, 0.0]]));
        assert!(!small_int_points([&[4_194_304.0, 0.0, 0.0]]));
        assert!(small_int_points([&[-4_194_303.0, 7.0, 0.0]]));
    }

    /// The shared-differences filter of the point location must give `orient3d`'s signs
    /// whenever it claims certainty, and claim it on ordinary input.
    #[test]
    fn facet_orientations_agree_with_orient3d() {
        let mut rng = toolbox::SplitMix64::new(77);
        let mut unit = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        let mut certain = 0;
        for i in 0..20_000 {
            let scale = [1e-3, 1.0, 3e3][i % 3];
            let mut pt = || [unit() * scale + 100.0, unit() * scale, unit() * scale];
            let mut v = [pt(), pt(), pt(), pt()];
            if i % 7 == 0 {
                v[3] = v[0]; // a degenerate cell: exact zeros must not be claimed certain
            }
            let q = if i % 5 == 0 { v[1] } else { pt() };
            let (det, bound) = facet_orientations([&v[0], &v[1], &v[2], &v[3]], &q);
            for k in 0..4 {
                let mut w = v;
                w[k] = q;
                let exact = orient3d(&w[0], &w[1], &w[2], &w[3]);
                if det[k] > bound || -det[k] > bound {
                    certain += 1;
                    assert_eq!(sign(det[k]), sign(exact), "{v:?} {q:?} {k}");
                }
            }
        }
        assert!(certain > 50_000, "{certain}");
    }

    /// The float stages (static and dynamic bounds) must agree with `robust` on nearly
    /// degenerate, non-dyadic inputs of every magnitude.
    #[test]
    fn float_filters_agree_with_robust_near_degeneracy() {
        let mut rng = toolbox::SplitMix64::new(17);
        let mut unit = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        for &scale in &[1e-6, 1.0, 3.7e3, 1e9] {
            for _ in 0..5000 {
                let off = [unit() * 100.0 * scale, unit() * scale, -unit() * scale];
                let r = |u: f64| u * scale;
                let a = [off[0] + r(unit()), off[1] + r(unit()), off[2] + r(unit())];
                let b = [off[0] + r(unit()), off[1] + r(unit()), off[2] + r(unit())];
                let c = [off[0] + r(unit()), off[1] + r(unit()), off[2] + r(unit())];
                // d nearly on the plane abc, e nearly on the sphere abcd.
                let (s, t, noise) = (unit(), unit(), (unit() - 0.5) * 1e-14 * scale);
                let d = [0, 1, 2].map(|k| a[k] + s * (b[k] - a[k]) + t * (c[k] - a[k]) + noise);
                let o = orient3d(&a, &b, &c, &d);
                let ro = robust::orient3d(coord(&a), coord(&b), coord(&c), coord(&d));
                assert_eq!(sign(o), sign(ro), "{a:?} {b:?} {c:?} {d:?}");
                let d2 = [d[0], d[1], d[2] + r(unit())];
                let (p, q) = if orient3d(&a, &b, &c, &d2) > 0.0 {
                    (a, b)
                } else {
                    (b, a)
                };
                // A point on the (float) circumsphere: its insphere sign is rounding noise.
                let sub = |u: [f64; 3], v: [f64; 3]| [u[0] - v[0], u[1] - v[1], u[2] - v[2]];
                let cross = |u: [f64; 3], v: [f64; 3]| {
                    [
                        u[1] * v[2] - u[2] * v[1],
                        u[2] * v[0] - u[0] * v[2],
                        u[0] * v[1] - u[1] * v[0],
                    ]
                };
                let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
                let (u, v, w) = (sub(q, p), sub(c, p), sub(d2, p));
                let den = 2.0 * dot(u, cross(v, w));
                let (vw, wu, uv) = (cross(v, w), cross(w, u), cross(u, v));
                let ctr = [0, 1, 2].map(|k| {
                    p[k] + (dot(u, u) * vw[k] + dot(v, v) * wu[k] + dot(w, w) * uv[k]) / den
                });
                let rad = dot(sub(p, ctr), sub(p, ctr)).sqrt();
                let dir = [unit() - 0.5, unit() - 0.5, unit() - 0.5];
                let len = dot(dir, dir).sqrt();
                let e = [0, 1, 2].map(|k| ctr[k] + rad * dir[k] / len);
                let i = insphere(&p, &q, &c, &d2, &e);
                let ri = robust::insphere(coord(&p), coord(&q), coord(&c), coord(&d2), coord(&e));
                assert_eq!(sign(i), sign(ri));
            }
        }
    }

    /// For two cells on either side of a facet, "the far apex is inside my sphere" must be
    /// decided identically from both sides — also for exact ties. This is what makes the
    /// perturbation a perturbation (a wrong sign in either rule breaks it).
    #[test]
    fn perturbed_local_delaunay_test_is_symmetric() {
        let mut rng = toolbox::SplitMix64::new(5);
        let mut pts: Vec<[f64; 3]> = Vec::new();
        for x in 0..3 {
            for y in 0..3 {
                for z in 0..3 {
                    pts.push([x as f64, y as f64, z as f64]);
                }
            }
        }
        let n = pts.len() as u32;
        let (mut ties, mut checked) = (0, 0);
        for _ in 0..60_000 {
            let ids = [0; 5].map(|_: u32| rng.below(n as usize) as u32);
            let [a, b, c, d, e] = ids;
            if (1..5).any(|i| ids[..i].contains(&ids[i])) {
                continue;
            }
            let mut t1 = [a, b, c, d];
            let mut t2 = [a, b, c, e];
            let (o1, o2) = (orient_ids(&pts, t1), orient_ids(&pts, t2));
            if o1 == 0.0 || o2 == 0.0 || (o1 > 0.0) == (o2 > 0.0) {
                continue; // need d and e strictly on opposite sides of (a, b, c)
            }
            if o1 < 0.0 {
                t1.swap(0, 1);
            }
            if o2 < 0.0 {
                t2.swap(0, 1);
            }
            let p = |i: u32| &pts[i as usize];
            ties += usize::from(insphere(p(t1[0]), p(t1[1]), p(t1[2]), p(t1[3]), p(e)) == 0.0);
            checked += 1;
            assert_eq!(
                in_conflict(&pts, t1, e),
                in_conflict(&pts, t2, d),
                "{ids:?}"
            );
        }
        assert!(ties > 100 && checked > 1000, "{ties} ties of {checked}");
    }

    /// The SSE2 evaluation of the insphere filter must give the scalar reference's bits.
    #[test]
    fn insphere_sse2_matches_scalar_bit_for_bit() {
        let mut rng = toolbox::SplitMix64::new(23);
        let mut unit = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        for &scale in &[1e-9, 1.0, 1234.5, 1e12] {
            for _ in 0..20_000 {
                let mut p = [[0.0; 3]; 5];
                for q in &mut p {
                    *q = [unit() * scale, unit() * scale + 7.0 * scale, unit() * scale];
                }
                let s = insphere_det_and_max_scalar(&p[0], &p[1], &p[2], &p[3], &p[4]);
                let v = insphere_det_and_max(&p[0], &p[1], &p[2], &p[3], &p[4]);
                assert_eq!(s.0.to_bits(), v.0.to_bits(), "{p:?}");
                assert_eq!(s.1.to_bits(), v.1.to_bits(), "{p:?}");
            }
        }
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
