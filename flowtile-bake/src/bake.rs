//! Baked tiling files: the stream functions of the tiles a tiling uses, the
//! grid of tile ids and the parameters, in a small versioned binary format
//! (specified in `FORMAT.md`) that is validated completely on read.

use std::fmt;
use std::path::Path;

use crate::fill::{Tile, fill_tile};
use crate::tileset::{FluxRange, TileKey, TileSet};
use crate::tiling::{Border, MAX_SLOTS, Tiling};

/// File magic.
pub const MAGIC: [u8; 4] = *b"FTBK";
/// Current format version.
pub const VERSION: u32 = 1;
/// Grid entry of a blocked slot.
pub const BLOCKED: u32 = u32::MAX;
/// Bytes before the corner table.
const HEADER_BYTES: usize = 56;
/// Bytes per tile key (four i32 fluxes, four u16 corners).
const KEY_BYTES: usize = 24;
/// Flag bits.
const FLAG_PERIODIC_X: u32 = 1;
const FLAG_PERIODIC_Y: u32 = 2;

/// A tiling ready for use at runtime: only the tiles it uses, filled.
#[derive(Clone, Debug, PartialEq)]
pub struct BakedTiling {
    /// The tile set parameters (flux ranges, base flux, corners, resolution).
    pub set: TileSet,
    /// Grid width in tiles.
    pub width: u32,
    /// Grid height in tiles.
    pub height: u32,
    /// The grid wraps around left/right.
    pub periodic_x: bool,
    /// The grid wraps around bottom/top.
    pub periodic_y: bool,
    /// The distinct tiles used, sorted by key.
    pub tiles: Vec<Tile>,
    /// Row-major (bottom row first) index into `tiles`, or [`BLOCKED`].
    pub grid: Vec<u32>,
}

/// Errors reading or writing baked files.
#[derive(Debug)]
pub enum BakeError {
    /// The file could not be read or written.
    Io(String, std::io::Error),
    /// The tiling still has empty slots.
    Incomplete,
    /// The bytes are not a valid baked tiling.
    Corrupt(String),
    /// A newer or unknown format version.
    Version(u32),
}

impl fmt::Display for BakeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BakeError::Io(path, e) => write!(f, "{path}: {e}"),
            BakeError::Incomplete => {
                write!(f, "the tiling has empty slots; complete it before baking")
            }
            BakeError::Corrupt(why) => write!(f, "not a valid baked tiling: {why}"),
            BakeError::Version(v) => write!(
                f,
                "baked tiling format version {v} is not supported (this build reads version {VERSION})"
            ),
        }
    }
}

impl std::error::Error for BakeError {}

fn corrupt(why: impl Into<String>) -> BakeError {
    BakeError::Corrupt(why.into())
}

impl BakedTiling {
    /// Fills the tiles `tiling` uses (and only those) and records the grid.
    ///
    /// ```
    /// use flowtile_bake::{bake::BakedTiling, rng::Rng, tileset::TileSet};
    /// use flowtile_bake::tiling::{Border, Conditions, Tiling};
    /// let set = TileSet::paper(3, 3, 1, 4).unwrap();
    /// let mut t = Tiling::new(set, 4, 4, &Conditions::borders(Border::Zero, Border::Zero)).unwrap();
    /// t.random_fill(&mut Rng::new(2)).unwrap();
    /// let baked = BakedTiling::from_tiling(&t).unwrap();
    /// let bytes = baked.to_bytes();
    /// assert_eq!(BakedTiling::from_bytes(&bytes).unwrap(), baked);
    /// ```
    pub fn from_tiling(tiling: &Tiling) -> Result<BakedTiling, BakeError> {
        if !tiling.is_complete() {
            return Err(BakeError::Incomplete);
        }
        let keys = tiling.tiles_used();
        let tiles: Vec<Tile> = keys.iter().map(|k| fill_tile(tiling.set(), k)).collect();
        let (w, h) = (tiling.width(), tiling.height());
        let mut grid = Vec::with_capacity((w * h) as usize);
        for y in 0..h {
            for x in 0..w {
                grid.push(match tiling.tile(x, y) {
                    Some(k) => keys.binary_search(&k).map_err(|_| BakeError::Incomplete)? as u32,
                    None => BLOCKED,
                });
            }
        }
        let (bx, by) = tiling.borders();
        Ok(BakedTiling {
            set: tiling.set().clone(),
            width: w,
            height: h,
            periodic_x: bx == Border::Periodic,
            periodic_y: by == Border::Periodic,
            tiles,
            grid,
        })
    }

    /// The tile at slot `(x, y)`, or `None` if blocked.
    pub fn tile_at(&self, x: u32, y: u32) -> Option<&Tile> {
        let id = self.grid[(y * self.width + x) as usize];
        (id != BLOCKED).then(|| &self.tiles[id as usize])
    }

    /// Serialises to the version-1 format described in `FORMAT.md`.
    pub fn to_bytes(&self) -> Vec<u8> {
        let n = self.set.n;
        let mut out = Vec::with_capacity(
            expected_len(n, self.set.corners.len(), self.tiles.len(), self.grid.len()).unwrap_or(0),
        );
        out.extend_from_slice(&MAGIC);
        let flags =
            (self.periodic_x as u32 * FLAG_PERIODIC_X) | (self.periodic_y as u32 * FLAG_PERIODIC_Y);
        for v in [
            VERSION,
            n as u32,
            self.width,
            self.height,
            flags,
            self.set.corners.len() as u32,
            self.tiles.len() as u32,
        ] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out.extend_from_slice(&self.set.f_base.to_le_bytes());
        for v in [
            self.set.mx.min,
            self.set.mx.max,
            self.set.my.min,
            self.set.my.max,
        ] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        debug_assert_eq!(out.len(), HEADER_BYTES);
        for c in &self.set.corners {
            out.extend_from_slice(&c[0].to_le_bytes());
            out.extend_from_slice(&c[1].to_le_bytes());
        }
        for t in &self.tiles {
            for m in t.key.fluxes() {
                out.extend_from_slice(&m.to_le_bytes());
            }
            for c in t.key.corners {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
        for t in &self.tiles {
            for s in &t.stream {
                out.extend_from_slice(&s.to_le_bytes());
            }
        }
        for id in &self.grid {
            out.extend_from_slice(&id.to_le_bytes());
        }
        let sum = fnv1a(&out);
        out.extend_from_slice(&sum.to_le_bytes());
        out
    }

    /// Parses and validates a baked tiling; never panics and never allocates
    /// more than the input's size justifies.
    pub fn from_bytes(bytes: &[u8]) -> Result<BakedTiling, BakeError> {
        if bytes.len() < 8 {
            return Err(corrupt(format!(
                "{} bytes is too short for a header",
                bytes.len()
            )));
        }
        if bytes[..4] != MAGIC {
            return Err(corrupt("missing FTBK magic (not a flowtile-bake file)"));
        }
        let mut r = Reader { bytes, pos: 4 };
        let version = r.u32()?;
        if version != VERSION {
            return Err(BakeError::Version(version));
        }
        if bytes.len() < HEADER_BYTES + 8 {
            return Err(corrupt(format!(
                "{} bytes is too short for a header",
                bytes.len()
            )));
        }
        let n = r.u32()? as usize;
        let width = r.u32()?;
        let height = r.u32()?;
        let flags = r.u32()?;
        let corner_count = r.u32()? as usize;
        let tile_count = r.u32()? as usize;
        let f_base = r.f64()?;
        let mx = FluxRange {
            min: r.i32()?,
            max: r.i32()?,
        };
        let my = FluxRange {
            min: r.i32()?,
            max: r.i32()?,
        };
        if flags & !(FLAG_PERIODIC_X | FLAG_PERIODIC_Y) != 0 {
            return Err(corrupt(format!("unknown flag bits {flags:#x}")));
        }
        if width == 0 || height == 0 || width as u64 * height as u64 > MAX_SLOTS {
            return Err(corrupt(format!(
                "grid {width}x{height} is empty or too large"
            )));
        }
        let slots = (width * height) as usize;
        if tile_count > slots {
            return Err(corrupt(format!("{tile_count} tiles for {slots} slots")));
        }
        if !(3..=crate::tileset::MAX_RESOLUTION).contains(&n) {
            return Err(corrupt(format!("tile resolution {n} out of range")));
        }
        if corner_count == 0 || corner_count > crate::tileset::MAX_CORNER_OPTIONS {
            return Err(corrupt(format!("{corner_count} corner velocity options")));
        }
        let want = expected_len(n, corner_count, tile_count, slots)
            .ok_or_else(|| corrupt("declared sizes overflow"))?;
        if bytes.len() != want {
            return Err(corrupt(format!(
                "file is {} bytes, header declares {want} (truncated or padded)",
                bytes.len()
            )));
        }
        let body = &bytes[..want - 8];
        let stored = u64::from_le_bytes(
            bytes[want - 8..]
                .try_into()
                .map_err(|_| corrupt("checksum"))?,
        );
        if fnv1a(body) != stored {
            return Err(corrupt("checksum mismatch (file damaged)"));
        }
        let mut corners = Vec::with_capacity(corner_count);
        for _ in 0..corner_count {
            corners.push([r.f64()?, r.f64()?]);
        }
        let set = TileSet::new(mx, my, f_base, corners, n).map_err(|e| corrupt(e.to_string()))?;
        let mut keys = Vec::with_capacity(tile_count);
        for i in 0..tile_count {
            let [left, bottom, right, top] = [r.i32()?, r.i32()?, r.i32()?, r.i32()?];
            let corners = [r.u16()?, r.u16()?, r.u16()?, r.u16()?];
            let key = TileKey {
                left,
                bottom,
                right,
                top,
                corners,
            };
            if set.index_of(&key).is_none() {
                return Err(corrupt(format!(
                    "tile {i} has key {key} outside the tile set"
                )));
            }
            if i > 0 && keys.last().is_some_and(|k: &TileKey| *k >= key) {
                return Err(corrupt(format!(
                    "tile keys not strictly sorted at tile {i}"
                )));
            }
            keys.push(key);
        }
        let nodes = (n + 1) * (n + 1);
        let mut tiles = Vec::with_capacity(tile_count);
        for key in keys {
            let mut stream = Vec::with_capacity(nodes);
            for _ in 0..nodes {
                let s = r.f64()?;
                if !s.is_finite() {
                    return Err(corrupt(format!("tile {key} has a non-finite stream value")));
                }
                stream.push(s);
            }
            let tile = Tile { key, n, stream };
            check_tile_fluxes(&set, &tile)?;
            tiles.push(tile);
        }
        let mut grid = Vec::with_capacity(slots);
        for i in 0..slots {
            let id = r.u32()?;
            if id != BLOCKED && id as usize >= tile_count {
                return Err(corrupt(format!(
                    "slot {i} refers to tile {id} of {tile_count}"
                )));
            }
            grid.push(id);
        }
        let baked = BakedTiling {
            set,
            width,
            height,
            periodic_x: flags & FLAG_PERIODIC_X != 0,
            periodic_y: flags & FLAG_PERIODIC_Y != 0,
            tiles,
            grid,
        };
        baked.check_neighbours()?;
        Ok(baked)
    }

    /// Neighbouring slots must agree on their shared edge's flux and corners;
    /// a blocked neighbour means zero flux.
    fn check_neighbours(&self) -> Result<(), BakeError> {
        let (w, h) = (self.width, self.height);
        let key = |x: u32, y: u32| self.tile_at(x, y).map(|t| t.key);
        for y in 0..h {
            for x in 0..w {
                let Some(k) = key(x, y) else { continue };
                if x + 1 < w || self.periodic_x {
                    let nx = (x + 1) % w;
                    let ok = match key(nx, y) {
                        Some(r) => {
                            r.left == k.right
                                && r.corners[0] == k.corners[1]
                                && r.corners[3] == k.corners[2]
                        }
                        None => k.right == 0,
                    };
                    if !ok {
                        return Err(corrupt(format!(
                            "slots ({x}, {y}) and ({nx}, {y}) do not match"
                        )));
                    }
                }
                if y + 1 < h || self.periodic_y {
                    let ny = (y + 1) % h;
                    let ok = match key(x, ny) {
                        Some(u) => {
                            u.bottom == k.top
                                && u.corners[0] == k.corners[3]
                                && u.corners[1] == k.corners[2]
                        }
                        None => k.top == 0,
                    };
                    if !ok {
                        return Err(corrupt(format!(
                            "slots ({x}, {y}) and ({x}, {ny}) do not match"
                        )));
                    }
                }
            }
        }
        Ok(())
    }

    /// Writes the file atomically: a temporary file next to `path`, then a
    /// rename, so readers never see half a file.
    pub fn write(&self, path: &Path) -> Result<(), BakeError> {
        write_atomic(path, &self.to_bytes())
    }

    /// Reads and validates a baked file.
    pub fn read(path: &Path) -> Result<BakedTiling, BakeError> {
        let bytes =
            std::fs::read(path).map_err(|e| BakeError::Io(path.display().to_string(), e))?;
        BakedTiling::from_bytes(&bytes)
    }
}

/// Writes `bytes` to `path` through a synced temporary file and a rename
/// ([`toolbox::write_bytes_atomic`]).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), BakeError> {
    toolbox::write_bytes_atomic(path, bytes)
        .map_err(|e| BakeError::Io(path.display().to_string(), e))
}

/// The edge fluxes stored in a tile's stream function must equal its key's.
fn check_tile_fluxes(set: &TileSet, tile: &Tile) -> Result<(), BakeError> {
    let n = tile.n;
    let s = |i, j| tile.s(i, j);
    let f = set.f_base;
    let k = tile.key;
    let got = [
        s(0, 0) - s(0, n),
        s(n, 0) - s(0, 0),
        s(n, 0) - s(n, n),
        s(n, n) - s(0, n),
    ];
    let want = k.fluxes().map(|m| m as f64 * f);
    let tol = 1e-9 * (1.0 + f.abs() * 64.0);
    if got.iter().zip(&want).any(|(g, w)| (g - w).abs() > tol) {
        return Err(corrupt(format!(
            "tile {k}: stream function does not carry its fluxes"
        )));
    }
    Ok(())
}

fn expected_len(n: usize, corners: usize, tiles: usize, slots: usize) -> Option<usize> {
    let nodes = (n + 1).checked_mul(n + 1)?;
    HEADER_BYTES
        .checked_add(corners.checked_mul(16)?)?
        .checked_add(tiles.checked_mul(KEY_BYTES)?)?
        .checked_add(tiles.checked_mul(nodes)?.checked_mul(8)?)?
        .checked_add(slots.checked_mul(4)?)?
        .checked_add(8)
}

/// 64-bit FNV-1a, enough to catch damaged files (not an integrity seal).
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> Result<[u8; N], BakeError> {
        let end = self.pos.checked_add(N).filter(|&e| e <= self.bytes.len());
        let end =
            end.ok_or_else(|| corrupt(format!("unexpected end of file at byte {}", self.pos)))?;
        let mut a = [0u8; N];
        a.copy_from_slice(&self.bytes[self.pos..end]);
        self.pos = end;
        Ok(a)
    }
    fn u16(&mut self) -> Result<u16, BakeError> {
        Ok(u16::from_le_bytes(self.take()?))
    }
    fn u32(&mut self) -> Result<u32, BakeError> {
        Ok(u32::from_le_bytes(self.take()?))
    }
    fn i32(&mut self) -> Result<i32, BakeError> {
        Ok(i32::from_le_bytes(self.take()?))
    }
    fn f64(&mut self) -> Result<f64, BakeError> {
        Ok(f64::from_le_bytes(self.take()?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;
    use crate::tiling::{Conditions, parse_mask};

    fn sample() -> BakedTiling {
        let set = TileSet::paper(5, 3, 5, 5).unwrap();
        let mut cond = Conditions::borders(Border::Periodic, Border::Zero);
        cond.blocked = parse_mask("......\n.##...\n......", 6, 3).unwrap();
        let mut t = Tiling::new(set, 6, 3, &cond).unwrap();
        t.random_fill(&mut Rng::new(9)).unwrap();
        BakedTiling::from_tiling(&t).unwrap()
    }

    #[test]
    fn round_trip_is_exact() {
        let b = sample();
        let bytes = b.to_bytes();
        let back = BakedTiling::from_bytes(&bytes).unwrap();
        assert_eq!(back, b);
        assert_eq!(back.to_bytes(), bytes);
        assert!(b.tiles.len() < 16, "only used tiles are stored");
    }

    #[test]
    fn every_truncation_is_an_error() {
        let bytes = sample().to_bytes();
        for len in 0..bytes.len() {
            let err = BakedTiling::from_bytes(&bytes[..len]).unwrap_err();
            assert!(!err.to_string().is_empty());
        }
        let mut padded = bytes.clone();
        padded.push(0);
        assert!(BakedTiling::from_bytes(&padded).is_err());
    }

    #[test]
    fn every_flipped_byte_is_an_error() {
        let bytes = sample().to_bytes();
        let mut rng = Rng::new(1);
        for i in 0..bytes.len() {
            let mut bad = bytes.clone();
            bad[i] ^= 1 << rng.below(8);
            assert!(
                BakedTiling::from_bytes(&bad).is_err(),
                "byte {i} flip accepted"
            );
        }
    }

    #[test]
    fn huge_declared_sizes_are_refused_without_allocating() {
        let mut bytes = sample().to_bytes();
        bytes[12..16].copy_from_slice(&u32::MAX.to_le_bytes()); // width
        let msg = BakedTiling::from_bytes(&bytes).unwrap_err().to_string();
        assert!(msg.contains("too large"), "{msg}");
        let mut bytes = sample().to_bytes();
        bytes[4..8].copy_from_slice(&7u32.to_le_bytes());
        assert!(matches!(
            BakedTiling::from_bytes(&bytes),
            Err(BakeError::Version(7))
        ));
        assert!(
            BakedTiling::from_bytes(b"PNG\x00aaaaaaaa")
                .unwrap_err()
                .to_string()
                .contains("magic")
        );
    }

    #[test]
    fn inconsistent_content_with_valid_checksum_is_refused() {
        let b = sample();
        // Swap two grid entries that hold different tiles: checksum is
        // recomputed, so only the neighbour check can notice.
        let mut bad = b.clone();
        let (i, j) = (0..bad.grid.len())
            .flat_map(|i| (0..bad.grid.len()).map(move |j| (i, j)))
            .find(|&(i, j)| {
                bad.grid[i] != bad.grid[j] && bad.grid[i] != BLOCKED && bad.grid[j] != BLOCKED
            })
            .unwrap();
        bad.grid.swap(i, j);
        let err = BakedTiling::from_bytes(&bad.to_bytes());
        // Either the swap happens to be consistent or it is caught.
        if let Err(e) = err {
            assert!(e.to_string().contains("do not match"), "{e}");
        }
        let mut bad = b.clone();
        bad.tiles[0].stream[1] = f64::NAN;
        assert!(BakedTiling::from_bytes(&bad.to_bytes()).is_err());
        let mut bad = b;
        let n = bad.set.n;
        bad.tiles[0].stream[n] += 1.0; // corner (n, 0): bottom flux changes
        assert!(
            BakedTiling::from_bytes(&bad.to_bytes())
                .unwrap_err()
                .to_string()
                .contains("fluxes")
        );
    }

    #[test]
    fn atomic_write_and_read() {
        let dir = std::env::temp_dir().join(format!("ftbk-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.ftbk");
        let b = sample();
        b.write(&path).unwrap();
        assert_eq!(BakedTiling::read(&path).unwrap(), b);
        let missing = dir.join("no/such/dir/x.ftbk");
        assert!(matches!(b.write(&missing), Err(BakeError::Io(..))));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
