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
/// Newest format version (this build reads 1 and 2).
pub const VERSION: u32 = 2;
/// Version 1: every distinct tile stored, grid entries are tile indices.
pub const VERSION_PLAIN: u32 = 1;
/// Version 2: one tile per symmetry class, grid entries `index << 3 | symmetry`.
pub const VERSION_ROTATED: u32 = 2;
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
                "baked tiling format version {v} is not supported (this build reads versions 1 and {VERSION})"
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
        // Each tile is its symmetry class's representative transformed, exactly as
        // a version-2 reader rebuilds it, so files round-trip bit for bit.
        let set = tiling.set();
        let group = set.symmetries();
        let tiles: Vec<Tile> = keys
            .iter()
            .map(|k| {
                let (rep, g) = set.symmetry_class(&group, k);
                fill_tile(set, &rep)
                    .transformed(set, g)
                    .expect("members of a class stay in the set")
            })
            .collect();
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

    /// Serialises to the format described in `FORMAT.md`: version 2 (one
    /// tile per symmetry class, each slot naming its class and the rotation
    /// or mirror that makes its tile) when that stores fewer tiles, else
    /// version 1.
    pub fn to_bytes(&self) -> Vec<u8> {
        match self.symmetry_plan() {
            Some((reps, grid)) if reps.len() < self.tiles.len() => {
                self.encode(VERSION_ROTATED, &reps.iter().collect::<Vec<_>>(), &grid)
            }
            _ => self.encode(
                VERSION_PLAIN,
                &self.tiles.iter().collect::<Vec<_>>(),
                &self.grid,
            ),
        }
    }

    /// Bytes of the version-1 and version-2 files of this tiling (the
    /// second `None` when no two tiles share a symmetry class).
    pub fn storage_bytes(&self) -> (usize, Option<usize>) {
        let (n, c, slots) = (self.set.n, self.set.corners.len(), self.grid.len());
        let plain = expected_len(n, c, self.tiles.len(), slots).unwrap_or(usize::MAX);
        let rotated = self
            .symmetry_plan()
            .filter(|(reps, _)| reps.len() < self.tiles.len())
            .and_then(|(reps, _)| expected_len(n, c, reps.len(), slots));
        (plain, rotated)
    }

    /// Number of symmetry classes (rotations and mirrors that map the tile
    /// set onto itself) among the tiles used.
    pub fn symmetry_classes_used(&self) -> usize {
        self.symmetry_plan()
            .map_or(self.tiles.len(), |(reps, _)| reps.len())
    }

    /// The tiles to store when one tile stands for its symmetry class, and
    /// the grid of `index << 3 | symmetry` entries. `None` when some stored
    /// tile is not the transformed representative of its class (tiles
    /// baked by other means than [`BakedTiling::from_tiling`]).
    fn symmetry_plan(&self) -> Option<(Vec<Tile>, Vec<u32>)> {
        let group = self.set.symmetries();
        let mut reps: Vec<TileKey> = Vec::new();
        let mut turns = Vec::with_capacity(self.tiles.len());
        for t in &self.tiles {
            let (rep, g) = self.set.symmetry_class(&group, &t.key);
            reps.push(rep);
            turns.push(g as u32);
        }
        let mut classes = reps.clone();
        classes.sort_unstable();
        classes.dedup();
        let stored: Vec<Tile> = classes.iter().map(|c| fill_tile(&self.set, c)).collect();
        // Every tile must be exactly its representative turned (the reader
        // rebuilds it that way).
        for (t, (rep, &k)) in self.tiles.iter().zip(reps.iter().zip(&turns)) {
            let i = classes.binary_search(rep).ok()?;
            if stored[i].transformed(&self.set, k as u8)? != *t {
                return None;
            }
        }
        let grid = self
            .grid
            .iter()
            .map(|&id| {
                if id == BLOCKED {
                    return BLOCKED;
                }
                let i = classes
                    .binary_search(&reps[id as usize])
                    .expect("class listed");
                ((i as u32) << 3) | turns[id as usize]
            })
            .collect();
        Some((stored, grid))
    }

    fn encode(&self, version: u32, tiles: &[&Tile], grid: &[u32]) -> Vec<u8> {
        let n = self.set.n;
        let mut out = Vec::with_capacity(
            expected_len(n, self.set.corners.len(), tiles.len(), grid.len()).unwrap_or(0),
        );
        out.extend_from_slice(&MAGIC);
        let flags =
            (self.periodic_x as u32 * FLAG_PERIODIC_X) | (self.periodic_y as u32 * FLAG_PERIODIC_Y);
        for v in [
            version,
            n as u32,
            self.width,
            self.height,
            flags,
            self.set.corners.len() as u32,
            tiles.len() as u32,
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
        for t in tiles {
            for m in t.key.fluxes() {
                out.extend_from_slice(&m.to_le_bytes());
            }
            for c in t.key.corners {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
        for t in tiles {
            for s in &t.stream {
                out.extend_from_slice(&s.to_le_bytes());
            }
        }
        for id in grid {
            out.extend_from_slice(&id.to_le_bytes());
        }
        let sum = fnv1a(&out);
        out.extend_from_slice(&sum.to_le_bytes());
        out
    }

    /// Parses and validates a baked tiling; never panics and never allocates
    /// more than the input's size justifies.
    pub fn from_bytes(bytes: &[u8]) -> Result<BakedTiling, BakeError> {
        let (mut r, head) = read_header(bytes)?;
        let mut corners = Vec::with_capacity(head.corner_count);
        for _ in 0..head.corner_count {
            corners.push([r.f64()?, r.f64()?]);
        }
        let set = TileSet::new(head.mx, head.my, head.f_base, corners, head.n)
            .map_err(|e| corrupt(e.to_string()))?;
        let keys = read_keys(&mut r, &set, head.tile_count)?;
        let mut tiles = read_tiles(&mut r, &set, keys, &head)?;
        let mut grid = read_grid(&mut r, &head)?;
        if head.version == VERSION_ROTATED {
            (tiles, grid) = unfold_rotations(&set, &tiles, &grid)?;
        }
        let baked = BakedTiling {
            set,
            width: head.width,
            height: head.height,
            periodic_x: head.flags & FLAG_PERIODIC_X != 0,
            periodic_y: head.flags & FLAG_PERIODIC_Y != 0,
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

/// Version 2 → memory: every (class, symmetry) a slot names becomes its
/// transformed tile; the tiles sorted by key and unique, the grid re-indexed.
fn unfold_rotations(
    set: &TileSet,
    reps: &[Tile],
    grid: &[u32],
) -> Result<(Vec<Tile>, Vec<u32>), BakeError> {
    let mut pairs: Vec<u32> = grid.iter().copied().filter(|&e| e != BLOCKED).collect();
    pairs.sort_unstable();
    pairs.dedup();
    let mut turned: Vec<(u32, Tile)> = Vec::with_capacity(pairs.len());
    for &e in &pairs {
        let rep = &reps[(e >> 3) as usize];
        let t = rep.transformed(set, (e & 7) as u8).ok_or_else(|| {
            corrupt(format!(
                "tile {} under symmetry {} leaves the tile set",
                rep.key,
                e & 7
            ))
        })?;
        turned.push((e, t));
    }
    let mut tiles: Vec<Tile> = turned.iter().map(|(_, t)| t.clone()).collect();
    tiles.sort_by_key(|t| t.key);
    tiles.dedup_by(|a, b| a.key == b.key);
    let index = |e: u32| -> u32 {
        let i = pairs.binary_search(&e).expect("listed");
        let key = turned[i].1.key;
        tiles.binary_search_by(|t| t.key.cmp(&key)).expect("listed") as u32
    };
    let grid = grid
        .iter()
        .map(|&e| if e == BLOCKED { BLOCKED } else { index(e) })
        .collect();
    Ok((tiles, grid))
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

/// The header of a baked file, checked: sizes within limits, the file's
/// length what they declare, the checksum right.
struct Header {
    version: u32,
    n: usize,
    width: u32,
    height: u32,
    flags: u32,
    corner_count: usize,
    tile_count: usize,
    f_base: f64,
    mx: FluxRange,
    my: FluxRange,
}

/// Reads and checks the header of `bytes` (see [`Header`]); returns it with
/// the reader at the corner velocities that follow it.
fn read_header(bytes: &[u8]) -> Result<(Reader<'_>, Header), BakeError> {
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
    if version != VERSION_PLAIN && version != VERSION_ROTATED {
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
    let head = Header {
        version,
        n,
        width,
        height,
        flags,
        corner_count,
        tile_count,
        f_base,
        mx,
        my,
    };
    Ok((r, head))
}

/// The `count` tile keys: each in the set, strictly sorted.
fn read_keys(r: &mut Reader<'_>, set: &TileSet, count: usize) -> Result<Vec<TileKey>, BakeError> {
    let mut keys = Vec::with_capacity(count);
    for i in 0..count {
        let fluxes = [r.i32()?, r.i32()?, r.i32()?, r.i32()?];
        let corners = [r.u16()?, r.u16()?, r.u16()?, r.u16()?];
        let key = TileKey::from_fluxes(fluxes, corners);
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
    Ok(keys)
}

/// The stream functions of the stored tiles (finite, with the fluxes their
/// keys name; in version 2 each the representative of its symmetry class).
fn read_tiles(
    r: &mut Reader<'_>,
    set: &TileSet,
    keys: Vec<TileKey>,
    head: &Header,
) -> Result<Vec<Tile>, BakeError> {
    let n = head.n;
    let nodes = (n + 1) * (n + 1);
    let mut tiles = Vec::with_capacity(keys.len());
    let group = set.symmetries();
    for key in keys {
        if head.version == VERSION_ROTATED && set.symmetry_class(&group, &key) != (key, 0) {
            return Err(corrupt(format!(
                "tile {key} is not the representative of its symmetry class"
            )));
        }
        let mut stream = Vec::with_capacity(nodes);
        for _ in 0..nodes {
            let s = r.f64()?;
            if !s.is_finite() {
                return Err(corrupt(format!("tile {key} has a non-finite stream value")));
            }
            stream.push(s);
        }
        let tile = Tile { key, n, stream };
        check_tile_fluxes(set, &tile)?;
        tiles.push(tile);
    }
    Ok(tiles)
}

/// The grid's entries: [`BLOCKED`] or a stored tile (version 2: a tile and
/// its symmetry in the low 3 bits).
fn read_grid(r: &mut Reader<'_>, head: &Header) -> Result<Vec<u32>, BakeError> {
    let slots = (head.width * head.height) as usize;
    let tile_count = head.tile_count;
    let mut grid = Vec::with_capacity(slots);
    for i in 0..slots {
        let id = r.u32()?;
        let tile = if head.version == VERSION_ROTATED {
            id >> 3
        } else {
            id
        };
        if id != BLOCKED && tile as usize >= tile_count {
            return Err(corrupt(format!(
                "slot {i} refers to tile {tile} of {tile_count}"
            )));
        }
        grid.push(id);
    }
    Ok(grid)
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

    fn version_of(bytes: &[u8]) -> u32 {
        u32::from_le_bytes(bytes[4..8].try_into().unwrap())
    }

    /// A tiling of a rotation-closed set where most tiles have a turned or
    /// mirrored twin.
    fn square_sample() -> BakedTiling {
        let set = TileSet::paper(3, 3, 5, 6).unwrap();
        let mut t = Tiling::new(
            set,
            14,
            12,
            &Conditions::borders(Border::Zero, Border::Free),
        )
        .unwrap();
        t.random_fill(&mut Rng::new(4)).unwrap();
        BakedTiling::from_tiling(&t).unwrap()
    }

    #[test]
    fn symmetry_classes_store_fewer_tiles_and_round_trip_exactly() {
        let small = sample();
        assert_eq!(
            small.symmetry_classes_used(),
            small.tiles.len(),
            "no twins in 15 slots"
        );
        assert_eq!(version_of(&small.to_bytes()), VERSION_PLAIN);
        let b = square_sample();
        let bytes = b.to_bytes();
        let classes = b.symmetry_classes_used();
        let (plain, rotated) = b.storage_bytes();
        assert!(classes < b.tiles.len(), "{classes} of {}", b.tiles.len());
        assert_eq!(version_of(&bytes), VERSION_ROTATED);
        assert_eq!(Some(bytes.len()), rotated);
        assert!(bytes.len() < plain);
        let back = BakedTiling::from_bytes(&bytes).unwrap();
        assert_eq!(back, b, "bit-exact tiles after unfolding");
        assert_eq!(back.to_bytes(), bytes);
        // The same tiling stored plainly reads back to the same thing.
        let v1 = b.encode(VERSION_PLAIN, &b.tiles.iter().collect::<Vec<_>>(), &b.grid);
        assert_eq!(v1.len(), plain);
        assert_eq!(BakedTiling::from_bytes(&v1).unwrap(), b);
    }

    #[test]
    fn sets_without_symmetry_are_stored_plainly() {
        // m_x -1..3 is not symmetric: only the top-bottom mirror maps the
        // set onto itself; corner options (0, 0) and (0.5, 0) do not mirror
        // left-right either.
        let set = TileSet::new(
            FluxRange { min: -1, max: 3 },
            FluxRange { min: -1, max: 1 },
            1.0,
            vec![[0.0, 0.0], [0.5, 0.0]],
            5,
        )
        .unwrap();
        assert_eq!(set.symmetries(), vec![0, 4]);
        assert_eq!(TileSet::paper(3, 3, 1, 4).unwrap().symmetries().len(), 8);
        assert_eq!(
            TileSet::paper(5, 3, 5, 4).unwrap().symmetries(),
            vec![0, 2, 4, 6]
        );
        let no_mirror = TileSet::new(
            FluxRange { min: -1, max: 3 },
            FluxRange { min: 0, max: 2 },
            1.0,
            vec![[0.0, 0.0]],
            4,
        )
        .unwrap();
        assert_eq!(no_mirror.symmetries(), vec![0]);
        let mut t = Tiling::new(
            no_mirror,
            5,
            4,
            &Conditions::borders(Border::Free, Border::Free),
        )
        .unwrap();
        t.random_fill(&mut Rng::new(3)).unwrap();
        let b = BakedTiling::from_tiling(&t).unwrap();
        let bytes = b.to_bytes();
        assert_eq!(version_of(&bytes), VERSION_PLAIN);
        assert_eq!(b.storage_bytes(), (bytes.len(), None));
        assert_eq!(BakedTiling::from_bytes(&bytes).unwrap(), b);
    }

    /// The fill commutes with the square's symmetries (up to rounding): a
    /// stored representative turned or mirrored is the tile the fill would
    /// have made, not merely some valid tile with the same key.
    #[test]
    fn transforms_commute_with_the_fill() {
        for set in [
            TileSet::paper(3, 3, 5, 6).unwrap(),
            TileSet::paper(5, 5, 9, 7).unwrap(),
            TileSet::paper(5, 3, 5, 5).unwrap(),
        ] {
            let step = (set.count() / 300).max(1);
            let mut worst = 0.0f64;
            for i in (0..set.count()).step_by(step as usize) {
                let key = set.key_at(i).unwrap();
                let tile = fill_tile(&set, &key);
                for g in set.symmetries() {
                    let moved = tile
                        .transformed(&set, g)
                        .unwrap_or_else(|| panic!("{key} under {g} in {:?}", set.corners));
                    let direct = fill_tile(&set, &moved.key);
                    for (a, b) in moved.stream.iter().zip(&direct.stream) {
                        worst = worst.max((a - b).abs());
                    }
                }
            }
            assert!(worst <= 1e-12, "max difference {worst}");
        }
    }

    #[test]
    fn version_2_content_is_checked() {
        let b = square_sample();
        let bytes = b.to_bytes();
        let reseal = |mut v: Vec<u8>| {
            let end = v.len() - 8;
            let sum = fnv1a(&v[..end]);
            v[end..].copy_from_slice(&sum.to_le_bytes());
            v
        };
        let (n, c, t) = (b.set.n, b.set.corners.len(), b.symmetry_classes_used());
        let grid_at = HEADER_BYTES + 16 * c + KEY_BYTES * t + 8 * t * (n + 1) * (n + 1);
        // A slot naming a symmetry that breaks its neighbours' agreement.
        let mut rejected = 0;
        for g in 1..8u32 {
            let mut bad = bytes.clone();
            let e = u32::from_le_bytes(bad[grid_at..grid_at + 4].try_into().unwrap());
            bad[grid_at..grid_at + 4].copy_from_slice(&((e & !7) | ((e + g) & 7)).to_le_bytes());
            if let Err(err) = BakedTiling::from_bytes(&reseal(bad)) {
                assert!(!err.to_string().contains('\n'));
                rejected += 1;
            }
        }
        assert!(rejected >= 5, "{rejected}");
        // A stored tile that is not its class's smallest member.
        let mut bad = bytes.clone();
        let key_at = HEADER_BYTES + 16 * c;
        let first = b.tiles.iter().map(|t| t.key).min().unwrap();
        let other = b
            .set
            .symmetries()
            .into_iter()
            .filter_map(|g| b.set.transform(&first, g))
            .find(|k| *k != first);
        if let Some(k) = other {
            let mut raw = Vec::new();
            for m in k.fluxes() {
                raw.extend_from_slice(&m.to_le_bytes());
            }
            for x in k.corners {
                raw.extend_from_slice(&x.to_le_bytes());
            }
            bad[key_at..key_at + KEY_BYTES].copy_from_slice(&raw);
            assert!(BakedTiling::from_bytes(&reseal(bad)).is_err());
        }
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
