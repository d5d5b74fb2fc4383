//! Tile sets: the parameters that define which tiles exist, how to count and
//! enumerate them, and their rotational symmetry classes (paper §3.1–3.2).
//!
//! A tile is indexed by eight numbers (paper Fig. 2): the integer flux multiple
//! on each edge and the index of the velocity at each corner. Fluxes are
//! positive towards +x (left/right edges) and +y (bottom/top edges), so the
//! divergence-free condition is `m_left + m_bottom = m_right + m_top`.

use std::fmt;

/// Inclusive range of flux multiples allowed on one family of edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FluxRange {
    /// Smallest multiple of `f_base`.
    pub min: i32,
    /// Largest multiple of `f_base`.
    pub max: i32,
}

impl FluxRange {
    /// The range with `count` options centred on zero, as the paper's
    /// `(M_x, M_y, c)` triples assume: 3 → `-1..=1`, 5 → `-2..=2`, 4 → `-1..=2`.
    pub fn centered(count: u32) -> FluxRange {
        // Clamped so absurd counts stay representable; TileSet::new rejects them.
        let count = count.clamp(1, MAX_FLUX_OPTIONS as u32 + 1) as i32;
        let min = -((count - 1) / 2);
        FluxRange {
            min,
            max: min + count - 1,
        }
    }

    /// Number of options in the range.
    pub fn len(&self) -> u32 {
        (self.max as i64 - self.min as i64 + 1).clamp(0, u32::MAX as i64) as u32
    }

    /// True when the range is empty (min > max).
    pub fn is_empty(&self) -> bool {
        self.max < self.min
    }

    /// True when `m` lies inside the range.
    pub fn contains(&self, m: i32) -> bool {
        self.min <= m && m <= self.max
    }
}

/// The eight indices that identify one tile.
///
/// Corner order is bottom-left, bottom-right, top-right, top-left.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TileKey {
    /// Flux multiple across the left edge (positive = flowing in, towards +x).
    pub left: i32,
    /// Flux multiple across the bottom edge (positive = flowing in, towards +y).
    pub bottom: i32,
    /// Flux multiple across the right edge (positive = flowing out, towards +x).
    pub right: i32,
    /// Flux multiple across the top edge (positive = flowing out, towards +y).
    pub top: i32,
    /// Corner velocity indices: bottom-left, bottom-right, top-right, top-left.
    pub corners: [u16; 4],
}

impl TileKey {
    /// The key with fluxes `f` (left, bottom, right, top, as
    /// [`TileKey::fluxes`] returns them) and these corners.
    pub fn from_fluxes(f: [i32; 4], corners: [u16; 4]) -> TileKey {
        let [left, bottom, right, top] = f;
        TileKey {
            left,
            bottom,
            right,
            top,
            corners,
        }
    }

    /// The fluxes in the order left, bottom, right, top.
    pub fn fluxes(&self) -> [i32; 4] {
        [self.left, self.bottom, self.right, self.top]
    }

    /// True when the key conserves mass (`left + bottom == right + top`).
    pub fn is_divergence_free(&self) -> bool {
        self.left + self.bottom == self.right + self.top
    }
}

impl fmt::Display for TileKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "(l{} b{} r{} t{} | c{},{},{},{})",
            self.left,
            self.bottom,
            self.right,
            self.top,
            self.corners[0],
            self.corners[1],
            self.corners[2],
            self.corners[3]
        )
    }
}

/// Errors in tile set parameters.
#[derive(Clone, Debug, PartialEq)]
pub enum TileSetError {
    /// Tile resolution below 3 cells (the corner construction needs 4×4 known nodes).
    ResolutionTooSmall(usize),
    /// Resolution so large a tile would not fit in memory sensibly.
    ResolutionTooLarge(usize),
    /// An empty or absurdly large flux range.
    BadFluxRange(&'static str, i32, i32),
    /// No corner velocity options, or too many.
    BadCornerCount(usize),
    /// A corner velocity or the base flux is not finite.
    NotFinite(&'static str),
    /// Symmetry classes need equal x/y ranges and a rotation-closed corner set.
    NotRotationInvariant(String),
}

impl fmt::Display for TileSetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TileSetError::ResolutionTooSmall(n) => {
                write!(f, "tile resolution {n} is below the minimum of 3 cells")
            }
            TileSetError::ResolutionTooLarge(n) => {
                write!(
                    f,
                    "tile resolution {n} exceeds the maximum of {MAX_RESOLUTION}"
                )
            }
            TileSetError::BadFluxRange(axis, lo, hi) => write!(
                f,
                "flux range for {axis} edges [{lo}, {hi}] is empty, wider than {MAX_FLUX_OPTIONS} options or beyond ±{MAX_FLUX_MULTIPLE}"
            ),
            TileSetError::BadCornerCount(c) => write!(
                f,
                "{c} corner velocity options; need between 1 and {MAX_CORNER_OPTIONS}"
            ),
            TileSetError::NotFinite(what) => {
                write!(f, "{what} is not a finite number of magnitude at most 1e12")
            }
            TileSetError::NotRotationInvariant(why) => {
                write!(f, "tile set is not closed under 90° rotation: {why}")
            }
        }
    }
}

impl std::error::Error for TileSetError {}

/// Largest tile resolution accepted (cells per side).
pub const MAX_RESOLUTION: usize = 1024;
/// Largest number of flux options per axis.
pub const MAX_FLUX_OPTIONS: i32 = 64;
/// Largest |flux multiple| (keeps every sum of fluxes far from overflow).
pub const MAX_FLUX_MULTIPLE: i32 = 1 << 20;
/// Largest number of corner velocity options.
pub const MAX_CORNER_OPTIONS: usize = 256;

/// A flow tile set: flux ranges, base flux, corner velocity options and the
/// tile resolution. Tiles themselves are created lazily by [`crate::fill`].
///
/// ```
/// use flowtile_bake::tileset::TileSet;
/// let set = TileSet::paper(3, 3, 1, 8).unwrap();
/// assert_eq!(set.count(), 19);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct TileSet {
    /// Flux multiples allowed on vertical edges (left/right, flux along x).
    pub mx: FluxRange,
    /// Flux multiples allowed on horizontal edges (bottom/top, flux along y).
    pub my: FluxRange,
    /// The unit of flux; an edge with multiple `m` carries `m * f_base`.
    pub f_base: f64,
    /// Corner velocity options in tile lengths per unit time.
    pub corners: Vec<[f64; 2]>,
    /// Cells per tile side (the stream function has `(n+1)²` nodes).
    pub n: usize,
    /// Dense rank of each (left, bottom, right) triple, or -1; see [`TileSet::index_of`].
    rank: Vec<i32>,
    /// Flux tuples (l, b, r, t) in rank order.
    tuples: Vec<[i32; 4]>,
}

impl TileSet {
    /// Builds and validates a tile set.
    pub fn new(
        mx: FluxRange,
        my: FluxRange,
        f_base: f64,
        corners: Vec<[f64; 2]>,
        n: usize,
    ) -> Result<TileSet, TileSetError> {
        if n < 3 {
            return Err(TileSetError::ResolutionTooSmall(n));
        }
        if n > MAX_RESOLUTION {
            return Err(TileSetError::ResolutionTooLarge(n));
        }
        for (name, r) in [("vertical (x)", mx), ("horizontal (y)", my)] {
            if r.is_empty()
                || r.len() > MAX_FLUX_OPTIONS as u32
                || r.min < -MAX_FLUX_MULTIPLE
                || r.max > MAX_FLUX_MULTIPLE
            {
                return Err(TileSetError::BadFluxRange(name, r.min, r.max));
            }
        }
        if corners.is_empty() || corners.len() > MAX_CORNER_OPTIONS {
            return Err(TileSetError::BadCornerCount(corners.len()));
        }
        let sane = |v: f64| v.is_finite() && v.abs() <= 1e12;
        if !sane(f_base) {
            return Err(TileSetError::NotFinite("base flux"));
        }
        if corners.iter().flatten().any(|&v| !sane(v)) {
            return Err(TileSetError::NotFinite("a corner velocity"));
        }
        let (nx, ny) = (mx.len() as usize, my.len() as usize);
        let mut rank = vec![-1i32; nx * ny * nx];
        let mut tuples = Vec::new();
        for l in mx.min..=mx.max {
            for b in my.min..=my.max {
                for r in mx.min..=mx.max {
                    let t = l + b - r;
                    if my.contains(t) {
                        let slot = ((l - mx.min) as usize * ny + (b - my.min) as usize) * nx
                            + (r - mx.min) as usize;
                        rank[slot] = tuples.len() as i32;
                        tuples.push([l, b, r, t]);
                    }
                }
            }
        }
        Ok(TileSet {
            mx,
            my,
            f_base,
            corners,
            n,
            rank,
            tuples,
        })
    }

    /// The paper's `(M_x, M_y, c)` set: centred flux ranges, unit base flux,
    /// and `c` corner velocities (zero first, then unit vectors scaled by ½
    /// along ±x, ±y, then the diagonals and further rings).
    pub fn paper(mx: u32, my: u32, c: usize, n: usize) -> Result<TileSet, TileSetError> {
        TileSet::new(
            FluxRange::centered(mx),
            FluxRange::centered(my),
            1.0,
            default_corner_options(c),
            n,
        )
    }

    /// Number of distinct flux tuples `(l, b, r, t)` that conserve mass.
    pub fn flux_tuple_count(&self) -> u64 {
        self.tuples.len() as u64
    }

    /// The flux tuples `(l, b, r, t)` in index order.
    pub fn flux_tuples(&self) -> &[[i32; 4]] {
        &self.tuples
    }

    /// Number of corner combinations per flux tuple (`c⁴`).
    pub fn corner_combinations(&self) -> u64 {
        (self.corners.len() as u64).pow(4)
    }

    /// Total number of tiles in the complete set (`tuples × c⁴`).
    pub fn count(&self) -> u64 {
        self.flux_tuple_count() * self.corner_combinations()
    }

    /// The dense index of a tile key, or `None` if it is not in the set.
    pub fn index_of(&self, key: &TileKey) -> Option<u64> {
        let (nx, ny) = (self.mx.len() as usize, self.my.len() as usize);
        if !self.mx.contains(key.left) || !self.my.contains(key.bottom) {
            return None;
        }
        if !self.mx.contains(key.right) || !self.my.contains(key.top) || !key.is_divergence_free() {
            return None;
        }
        let c = self.corners.len() as u64;
        if key.corners.iter().any(|&k| k as u64 >= c) {
            return None;
        }
        let slot = ((key.left - self.mx.min) as usize * ny + (key.bottom - self.my.min) as usize)
            * nx
            + (key.right - self.mx.min) as usize;
        let rank = self.rank[slot] as u64;
        let corner = key.corners.iter().fold(0u64, |acc, &k| acc * c + k as u64);
        Some(rank * self.corner_combinations() + corner)
    }

    /// The tile key with dense index `index` (inverse of [`TileSet::index_of`]).
    pub fn key_at(&self, index: u64) -> Option<TileKey> {
        if index >= self.count() {
            return None;
        }
        let combos = self.corner_combinations();
        let fluxes = self.tuples[(index / combos) as usize];
        let c = self.corners.len() as u64;
        let mut rest = index % combos;
        let mut corners = [0u16; 4];
        for k in (0..4).rev() {
            corners[k] = (rest % c) as u16;
            rest /= c;
        }
        Some(TileKey::from_fluxes(fluxes, corners))
    }

    /// Iterates over every tile key of the complete set in index order.
    pub fn keys(&self) -> impl Iterator<Item = TileKey> + '_ {
        (0..self.count()).filter_map(|i| self.key_at(i))
    }

    /// The index of the zero corner velocity, if the set has one.
    pub fn zero_corner(&self) -> Option<u16> {
        self.corners
            .iter()
            .position(|v| v[0] == 0.0 && v[1] == 0.0)
            .map(|i| i as u16)
    }

    /// The key rotated by 90° counter-clockwise about the tile centre, or an
    /// error when the rotated tile is not in the set.
    ///
    /// Fluxes map `(l, b, r, t) → (-t, l, -b, r)`; velocities rotate
    /// `(x, y) → (-y, x)` and move one corner on (bottom-left → bottom-right).
    pub fn rotate(&self, key: &TileKey) -> Result<TileKey, TileSetError> {
        let mut corners = [0u16; 4];
        for (k, &c) in key.corners.iter().enumerate() {
            let [vx, vy] = self.corners[c as usize];
            let rotated = [-vy, vx];
            let idx = self
                .corners
                .iter()
                .position(|o| {
                    (o[0] - rotated[0]).abs() < 1e-12 && (o[1] - rotated[1]).abs() < 1e-12
                })
                .ok_or_else(|| {
                    TileSetError::NotRotationInvariant(format!(
                        "corner velocity ({vx}, {vy}) rotates to ({}, {}) which is not an option",
                        rotated[0], rotated[1]
                    ))
                })?;
            corners[(k + 1) % 4] = idx as u16;
        }
        let rotated = TileKey {
            left: -key.top,
            bottom: key.left,
            right: -key.bottom,
            top: key.right,
            corners,
        };
        if self.index_of(&rotated).is_none() {
            return Err(TileSetError::NotRotationInvariant(format!(
                "{key} rotates to {rotated}, outside the flux ranges"
            )));
        }
        Ok(rotated)
    }

    /// Symmetry `g` of the square applied to `key`: bit 2 mirrors top to
    /// bottom first (`y → 1 − y`: fluxes `(l, b, r, t) → (l, −t, r, −b)`,
    /// velocities `(x, y) → (x, −y)`, bottom and top corners trade places),
    /// bits 0–1 then count quarter turns counter-clockwise as in
    /// [`TileSet::rotate`]. `None` when the result is not in the set (only
    /// the result counts: a half turn of a set with `m_x ≠ m_y` is fine).
    pub fn transform(&self, key: &TileKey, g: u8) -> Option<TileKey> {
        let [mut l, mut b, mut r, mut t] = key.fluxes();
        let mut v = key.corners.map(|c| self.corners[c as usize]);
        if g & 4 != 0 {
            (b, t) = (-t, -b);
            let [bl, br, tr, tl] = v;
            v = [tl, tr, br, bl].map(|[x, y]| [x, -y]);
        }
        for _ in 0..g & 3 {
            (l, b, r, t) = (-t, l, -b, r);
            let [bl, br, tr, tl] = v.map(|[x, y]| [-y, x]);
            v = [tl, bl, br, tr];
        }
        let option = |w: [f64; 2]| {
            self.corners
                .iter()
                .position(|o| (o[0] - w[0]).abs() < 1e-12 && (o[1] - w[1]).abs() < 1e-12)
                .map(|i| i as u16)
        };
        let moved = TileKey {
            left: l,
            bottom: b,
            right: r,
            top: t,
            corners: [option(v[0])?, option(v[1])?, option(v[2])?, option(v[3])?],
        };
        self.index_of(&moved).map(|_| moved)
    }

    /// The symmetries of the square (codes as in [`TileSet::transform`])
    /// that map the whole set onto itself: all eight for square sets with
    /// symmetric ranges and corner options, `{0, 4}` for the river's
    /// asymmetric `m_x` with symmetric `m_y`, `{0}` at least.
    pub fn symmetries(&self) -> Vec<u8> {
        let velocity = |[mut vx, mut vy]: [f64; 2], g: u8| {
            if g & 4 != 0 {
                vy = -vy;
            }
            for _ in 0..g & 3 {
                (vx, vy) = (-vy, vx);
            }
            [vx, vy]
        };
        let fluxes = |[mut l, mut b, mut r, mut t]: [i32; 4], g: u8| {
            if g & 4 != 0 {
                (b, t) = (-t, -b);
            }
            for _ in 0..g & 3 {
                (l, b, r, t) = (-t, l, -b, r);
            }
            [l, b, r, t]
        };
        let closed = |g: u8| {
            self.corners.iter().all(|&v| {
                let w = velocity(v, g);
                self.corners
                    .iter()
                    .any(|o| (o[0] - w[0]).abs() < 1e-12 && (o[1] - w[1]).abs() < 1e-12)
            }) && self.tuples.iter().all(|&f| {
                let key = TileKey::from_fluxes(fluxes(f, g), [0; 4]);
                self.index_of(&key).is_some()
            })
        };
        (0..8).filter(|&g| closed(g)).collect()
    }

    /// The class of `key` under the symmetries `group` (from
    /// [`TileSet::symmetries`]): its smallest member, and the first symmetry
    /// that takes that member to `key`.
    pub fn symmetry_class(&self, group: &[u8], key: &TileKey) -> (TileKey, u8) {
        let rep = group
            .iter()
            .filter_map(|&g| self.transform(key, g))
            .min()
            .unwrap_or(*key);
        let g = group
            .iter()
            .copied()
            .find(|&g| self.transform(&rep, g) == Some(*key))
            .unwrap_or(0);
        (rep, g)
    }

    /// Partitions the complete set into rotational symmetry classes; each
    /// class is listed by its member indices, smallest first.
    pub fn rotation_classes(&self) -> Result<Vec<Vec<u64>>, TileSetError> {
        let total = self.count();
        if total > 50_000_000 {
            return Err(TileSetError::NotRotationInvariant(
                "set too large to enumerate classes".into(),
            ));
        }
        let mut seen = vec![false; total as usize];
        let mut classes = Vec::new();
        for i in 0..total {
            if seen[i as usize] {
                continue;
            }
            let mut class = Vec::with_capacity(4);
            let mut key = self.key_at(i).expect("index in range");
            for _ in 0..4 {
                let idx = self.index_of(&key).expect("rotated key checked");
                if !seen[idx as usize] {
                    seen[idx as usize] = true;
                    class.push(idx);
                }
                key = self.rotate(&key)?;
            }
            class.sort_unstable();
            classes.push(class);
        }
        Ok(classes)
    }
}

/// `c` default corner velocity options: zero, then ½·(±x, ±y), then diagonals,
/// then rings of growing radius (so any `c` gives a usable, mostly
/// rotation-closed set).
pub fn default_corner_options(c: usize) -> Vec<[f64; 2]> {
    let mut out = vec![[0.0, 0.0]];
    let mut ring = 1.0f64;
    while out.len() < c {
        let s = 0.5 * ring;
        for v in [[s, 0.0], [0.0, s], [-s, 0.0], [0.0, -s]] {
            out.push(v);
        }
        let d = s * std::f64::consts::FRAC_1_SQRT_2;
        for v in [[d, d], [-d, d], [-d, -d], [d, -d]] {
            out.push(v);
        }
        ring += 1.0;
    }
    out.truncate(c.max(1));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_counts() {
        assert_eq!(TileSet::paper(3, 3, 1, 4).unwrap().count(), 19);
        assert_eq!(TileSet::paper(5, 5, 1, 4).unwrap().count(), 85);
        assert_eq!(TileSet::paper(3, 3, 5, 4).unwrap().count(), 11_875);
    }

    #[test]
    fn count_matches_brute_force() {
        for (mx, my) in [(2, 3), (3, 5), (4, 4), (5, 3)] {
            let set = TileSet::paper(mx, my, 2, 3).unwrap();
            let (x, y) = (set.mx, set.my);
            let mut n = 0u64;
            for l in x.min..=x.max {
                for r in x.min..=x.max {
                    for b in y.min..=y.max {
                        for t in y.min..=y.max {
                            n += (l + b == r + t) as u64;
                        }
                    }
                }
            }
            assert_eq!(set.count(), n * 16, "({mx},{my},2)");
        }
    }

    #[test]
    fn index_round_trip() {
        let set = TileSet::paper(3, 5, 2, 3).unwrap();
        for i in 0..set.count() {
            let key = set.key_at(i).unwrap();
            assert!(key.is_divergence_free());
            assert_eq!(set.index_of(&key), Some(i));
        }
        assert_eq!(set.key_at(set.count()), None);
        let bad = TileKey {
            left: 1,
            bottom: 1,
            right: 0,
            top: 0,
            corners: [0; 4],
        };
        assert_eq!(set.index_of(&bad), None);
    }

    #[test]
    fn six_rotation_classes_for_331() {
        let set = TileSet::paper(3, 3, 1, 4).unwrap();
        let classes = set.rotation_classes().unwrap();
        assert_eq!(classes.len(), 6);
        let mut sizes: Vec<usize> = classes.iter().map(|c| c.len()).collect();
        sizes.sort_unstable();
        assert_eq!(sizes, vec![1, 2, 4, 4, 4, 4]);
        // Rotating four times is the identity.
        for key in set.keys() {
            let mut k = key;
            for _ in 0..4 {
                k = set.rotate(&k).unwrap();
            }
            assert_eq!(k, key);
        }
    }

    #[test]
    fn rotation_classes_need_square_ranges() {
        let set = TileSet::paper(5, 3, 1, 4).unwrap();
        assert!(set.rotation_classes().is_err());
    }

    #[test]
    fn rejects_bad_parameters() {
        assert!(TileSet::paper(3, 3, 1, 2).is_err());
        assert!(TileSet::paper(3, 3, 0, 4).is_ok()); // clamps to one corner option
        let r = FluxRange { min: 2, max: 1 };
        assert!(TileSet::new(r, r, 1.0, vec![[0.0, 0.0]], 4).is_err());
        let huge = FluxRange {
            min: i32::MIN,
            max: i32::MAX,
        };
        assert!(TileSet::new(huge, huge, 1.0, vec![[0.0, 0.0]], 4).is_err());
        let far = FluxRange {
            min: i32::MAX - 2,
            max: i32::MAX,
        };
        assert!(TileSet::new(far, far, 1.0, vec![[0.0, 0.0]], 4).is_err());
        assert!(TileSet::paper(u32::MAX, 3, 1, 4).is_err());
        assert!(
            TileSet::new(
                FluxRange::centered(3),
                FluxRange::centered(3),
                f64::NAN,
                vec![[0.0, 0.0]],
                4
            )
            .is_err()
        );
    }
}
