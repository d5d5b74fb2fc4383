//! `navmesh` reads Counter-Strike bot navigation meshes (`.nav`, versions 1–5, as
//! written by the Half-Life SDK's `game_shared/bot/nav_file.cpp`): the walkable areas
//! of a level as axis-aligned floor rectangles with corner heights, their
//! connections, crouch flags and place names. The replay harness of `vdgview` walks
//! routes along them and `flowtile-bake region --nav` turns them into a tiling's
//! mask; neither needs the other, so the reader lives here, with no dependencies.
//!
//! Layout (little endian): magic `0xFEEDFACE`, version, the source BSP's size (v ≥ 4),
//! the place directory (v ≥ 5: count, then length-prefixed names), the area count and
//! the areas: id, attribute byte, extent (6 floats), the heights of the NE and SW
//! corners, connections per direction (count + ids), hiding spots (v1: positions;
//! else id, position, flags), approach areas, encounter paths (v < 3 in the old
//! layout), and (v ≥ 5) a place entry. Every read is bounds-checked: a truncated or
//! corrupt file is a one-line error, never a panic or a huge allocation.
//!
//! ```no_run
//! let mesh = navmesh::NavMesh::open("maps/de_dust2.nav".as_ref())?;
//! let a = &mesh.areas[0];
//! println!("v{}: {} areas; area {} floor at its centre {:?}", mesh.version,
//!     mesh.areas.len(), a.id, a.center());
//! let chain = mesh.area_path(0, mesh.areas.len() - 1);
//! # Ok::<(), String>(())
//! ```

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};

/// First four bytes of every `.nav` file.
pub const NAV_MAGIC: u32 = 0xFEED_FACE;
/// The area must be crossed crouched.
pub const NAV_CROUCH: u8 = 0x01;

/// One walkable area: an axis-aligned rectangle on the floor with corner heights.
#[derive(Debug, Clone, PartialEq)]
pub struct NavArea {
    /// The area's id (connections name areas by id, not by index).
    pub id: u32,
    /// Attribute bits ([`NAV_CROUCH`], jump, no-jump, ...).
    pub flags: u8,
    /// North-west corner (x, y, z).
    pub lo: [f32; 3],
    /// South-east corner (x, y, z).
    pub hi: [f32; 3],
    /// Floor height of the north-east corner.
    pub ne_z: f32,
    /// Floor height of the south-west corner.
    pub sw_z: f32,
    /// Ids of the areas reachable from here, per direction (north, east, south, west).
    pub connections: [Vec<u32>; 4],
    /// Index + 1 into [`NavMesh::places`] (0: no place; always 0 before version 5).
    pub place: u16,
}

impl NavArea {
    /// Floor height at `(x, y)` from the four corner heights (the SDK's `GetZ`).
    pub fn z_at(&self, x: f32, y: f32) -> f32 {
        let u = ((x - self.lo[0]) / (self.hi[0] - self.lo[0]).max(1e-3)).clamp(0.0, 1.0);
        let v = ((y - self.lo[1]) / (self.hi[1] - self.lo[1]).max(1e-3)).clamp(0.0, 1.0);
        let north = self.lo[2] + u * (self.ne_z - self.lo[2]);
        let south = self.sw_z + u * (self.hi[2] - self.sw_z);
        north + v * (south - north)
    }

    /// Centre of the rectangle, on the floor.
    pub fn center(&self) -> [f32; 3] {
        let (x, y) = (
            (self.lo[0] + self.hi[0]) / 2.0,
            (self.lo[1] + self.hi[1]) / 2.0,
        );
        [x, y, self.z_at(x, y)]
    }
}

/// A parsed `.nav` file.
#[derive(Debug, Clone, PartialEq)]
pub struct NavMesh {
    /// File version (1..=5).
    pub version: u32,
    /// Size of the BSP the mesh was made for (0 before version 4).
    pub bsp_size: u32,
    /// Place names (version 5: "BombsiteA", ...).
    pub places: Vec<String>,
    /// The walkable areas in file order.
    pub areas: Vec<NavArea>,
}

struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.b.len());
        match end {
            Some(e) => {
                let s = &self.b[self.at..e];
                self.at = e;
                Ok(s)
            }
            None => Err(format!(
                "truncated at byte {} (reading {what}, file has {} bytes)",
                self.at,
                self.b.len()
            )),
        }
    }
    fn u8(&mut self, what: &str) -> Result<u8, String> {
        Ok(self.take(1, what)?[0])
    }
    fn u16(&mut self, what: &str) -> Result<u16, String> {
        Ok(u16::from_le_bytes(self.take(2, what)?.try_into().unwrap()))
    }
    fn u32(&mut self, what: &str) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.take(4, what)?.try_into().unwrap()))
    }
    fn f32(&mut self, what: &str) -> Result<f32, String> {
        let v = f32::from_le_bytes(self.take(4, what)?.try_into().unwrap());
        if v.is_finite() {
            Ok(v)
        } else {
            Err(format!("non-finite {what} at byte {}", self.at - 4))
        }
    }
    /// A count of items of at least `min_size` bytes each that must fit in the rest.
    fn count(&mut self, n: usize, min_size: usize, what: &str) -> Result<usize, String> {
        if n.saturating_mul(min_size) > self.b.len() - self.at {
            return Err(format!(
                "{what} count {n} at byte {} does not fit in the file",
                self.at
            ));
        }
        Ok(n)
    }
}

impl NavMesh {
    /// Parses a `.nav` file; the error is one line naming the problem.
    pub fn parse(bytes: &[u8]) -> Result<NavMesh, String> {
        let mut r = Reader { b: bytes, at: 0 };
        let magic = r.u32("magic")?;
        if magic != NAV_MAGIC {
            return Err(format!(
                "not a nav file (magic {magic:#010x}, expected 0xfeedface)"
            ));
        }
        let version = r.u32("version")?;
        if !(1..=5).contains(&version) {
            return Err(format!(
                "unsupported nav version {version} (GoldSrc writes 1..5)"
            ));
        }
        let bsp_size = if version >= 4 { r.u32("bsp size")? } else { 0 };
        let mut places = Vec::new();
        if version >= 5 {
            let n = r.u16("place count")? as usize;
            let n = r.count(n, 2, "place")?;
            for _ in 0..n {
                let len = r.u16("place name length")? as usize;
                if len >= 256 {
                    return Err(format!("place name of {len} bytes at byte {}", r.at - 2));
                }
                let raw = r.take(len, "place name")?;
                let s = raw.split(|&c| c == 0).next().unwrap_or(&[]);
                places.push(String::from_utf8_lossy(s).into_owned());
            }
        }
        let n = r.u32("area count")? as usize;
        let n = r.count(n, 50, "area")?;
        let mut areas = Vec::with_capacity(n);
        for _ in 0..n {
            areas.push(read_area(&mut r, version)?);
        }
        Ok(NavMesh {
            version,
            bsp_size,
            places,
            areas,
        })
    }

    /// Reads and parses a file.
    pub fn open(path: &std::path::Path) -> Result<NavMesh, String> {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        NavMesh::parse(&bytes).map_err(|e| format!("{}: {e}", path.display()))
    }
}

fn read_area(r: &mut Reader<'_>, version: u32) -> Result<NavArea, String> {
    let id = r.u32("area id")?;
    let flags = r.u8("area flags")?;
    let mut e = [0.0f32; 6];
    for v in &mut e {
        *v = r.f32("area extent")?;
    }
    let ne_z = r.f32("area corner height")?;
    let sw_z = r.f32("area corner height")?;
    let mut connections: [Vec<u32>; 4] = Default::default();
    for dir in &mut connections {
        let n = r.u32("connection count")? as usize;
        let n = r.count(n, 4, "connection")?;
        for _ in 0..n {
            dir.push(r.u32("connection id")?);
        }
    }
    let spots = r.u8("hiding spot count")? as usize;
    let spot_size = if version == 1 { 12 } else { 17 };
    r.take(spots * spot_size, "hiding spots")?;
    let approaches = r.u8("approach count")? as usize;
    r.take(approaches * 14, "approach areas")?;
    let encounters = r.u32("encounter path count")? as usize;
    let encounters = r.count(
        encounters,
        if version < 3 { 33 } else { 11 },
        "encounter path",
    )?;
    for _ in 0..encounters {
        if version < 3 {
            r.take(32, "encounter path")?;
            let spots = r.u8("encounter spot count")? as usize;
            r.take(spots * 16, "encounter spots")?;
        } else {
            r.take(10, "encounter path")?;
            let spots = r.u8("encounter spot count")? as usize;
            r.take(spots * 5, "encounter spots")?;
        }
    }
    let place = if version >= 5 {
        r.u16("place entry")?
    } else {
        0
    };
    Ok(NavArea {
        id,
        flags,
        lo: [e[0], e[1], e[2]],
        hi: [e[3], e[4], e[5]],
        ne_z,
        sw_z,
        connections,
        place,
    })
}

#[derive(PartialEq)]
struct Open(f32, usize);
impl Eq for Open {}
impl Ord for Open {
    fn cmp(&self, o: &Self) -> Ordering {
        o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
    }
}
impl PartialOrd for Open {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

fn dist(a: [f32; 3], b: [f32; 3]) -> f32 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

impl NavArea {
    /// Midpoint (x, y) of the shared edge (or gap) between this area's rectangle
    /// and `b`'s: where a walker crosses from one to the other.
    pub fn portal(&self, b: &NavArea) -> [f32; 2] {
        let mid = |lo: f32, hi: f32| (lo + hi) / 2.0;
        [
            mid(self.lo[0].max(b.lo[0]), self.hi[0].min(b.hi[0])),
            mid(self.lo[1].max(b.lo[1]), self.hi[1].min(b.hi[1])),
        ]
    }

    /// Straight-line distance between the two areas' centres.
    pub fn center_distance(&self, b: &NavArea) -> f32 {
        dist(self.center(), b.center())
    }

    /// Whether `(x, y)` lies on the rectangle (edges included).
    pub fn contains_xy(&self, x: f32, y: f32) -> bool {
        (self.lo[0]..=self.hi[0]).contains(&x) && (self.lo[1]..=self.hi[1]).contains(&y)
    }
}

impl NavMesh {
    /// Shortest chain of areas (indices) from `from` to `to` along connections.
    pub fn area_path(&self, from: usize, to: usize) -> Option<Vec<usize>> {
        let by_id: HashMap<u32, usize> = self
            .areas
            .iter()
            .enumerate()
            .map(|(i, a)| (a.id, i))
            .collect();
        let mut cost = vec![f32::INFINITY; self.areas.len()];
        let mut parent = vec![usize::MAX; self.areas.len()];
        let goal = self.areas[to].center();
        cost[from] = 0.0;
        let mut open = BinaryHeap::from([Open(dist(self.areas[from].center(), goal), from)]);
        while let Some(Open(_, i)) = open.pop() {
            if i == to {
                let mut out = vec![to];
                while let Some(&p) = out
                    .last()
                    .map(|&k| &parent[k])
                    .filter(|&&p| p != usize::MAX)
                {
                    out.push(p);
                }
                out.reverse();
                return Some(out);
            }
            let c = self.areas[i].center();
            for id in self.areas[i].connections.iter().flatten() {
                let Some(&j) = by_id.get(id) else { continue };
                let g = cost[i] + dist(c, self.areas[j].center());
                if g < cost[j] {
                    cost[j] = g;
                    parent[j] = i;
                    open.push(Open(g + dist(self.areas[j].center(), goal), j));
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use toolbox::SplitMix64;

    /// Writes a version-5 file with `areas` rectangles in a row, each connected east
    /// to the next (the SDK's layout, built byte by byte).
    pub fn synthetic(areas: usize, with_extras: bool) -> Vec<u8> {
        let mut b = Vec::new();
        let u32 = |b: &mut Vec<u8>, v: u32| b.extend_from_slice(&v.to_le_bytes());
        let f = |b: &mut Vec<u8>, v: f32| b.extend_from_slice(&v.to_le_bytes());
        u32(&mut b, NAV_MAGIC);
        u32(&mut b, 5);
        u32(&mut b, 123_456);
        b.extend_from_slice(&1u16.to_le_bytes());
        b.extend_from_slice(&6u16.to_le_bytes());
        b.extend_from_slice(b"Ramp\0\0");
        u32(&mut b, areas as u32);
        for k in 0..areas {
            u32(&mut b, k as u32 + 1);
            b.push(if k == 1 { NAV_CROUCH } else { 0 });
            let x = k as f32 * 100.0;
            for v in [x, 0.0, 0.0, x + 100.0, 100.0, 10.0] {
                f(&mut b, v);
            }
            f(&mut b, 0.0);
            f(&mut b, 10.0);
            for d in 0..4 {
                let next = (d == 1 && k + 1 < areas) as u32;
                let prev = (d == 3 && k > 0) as u32;
                u32(&mut b, next + prev);
                if next == 1 {
                    u32(&mut b, k as u32 + 2);
                }
                if prev == 1 {
                    u32(&mut b, k as u32);
                }
            }
            if with_extras {
                b.push(1); // one hiding spot
                u32(&mut b, 7);
                for v in [x + 5.0, 5.0, 0.0] {
                    f(&mut b, v);
                }
                b.push(2);
                b.push(1); // one approach area
                b.extend_from_slice(&[0u8; 14]);
                u32(&mut b, 1); // one encounter path with two spots
                b.extend_from_slice(&[0u8; 10]);
                b.push(2);
                b.extend_from_slice(&[0u8; 10]);
            } else {
                b.push(0);
                b.push(0);
                u32(&mut b, 0);
            }
            b.extend_from_slice(&1u16.to_le_bytes());
        }
        b
    }

    #[test]
    fn reads_a_synthetic_v5_file() {
        for extras in [false, true] {
            let m = NavMesh::parse(&synthetic(4, extras)).unwrap();
            assert_eq!((m.version, m.bsp_size, m.areas.len()), (5, 123_456, 4));
            assert_eq!(m.places, vec!["Ramp".to_string()]);
            assert_eq!(m.areas[1].flags, NAV_CROUCH);
            assert_eq!(m.areas[2].connections[1], vec![4]);
            assert_eq!(m.areas[2].connections[3], vec![2]);
            assert_eq!(m.areas[3].place, 1);
            // Corner heights: NW 0, NE 0, SE 10, SW 10 → a ramp rising to the south.
            assert!((m.areas[0].z_at(50.0, 50.0) - 5.0).abs() < 1e-4);
            assert_eq!(m.area_path(0, 3), Some(vec![0, 1, 2, 3]));
            assert_eq!(m.area_path(3, 0), Some(vec![3, 2, 1, 0]));
            assert_eq!(m.areas[0].portal(&m.areas[1]), [100.0, 50.0], "shared edge");
            assert_eq!(m.areas[0].center_distance(&m.areas[2]), 200.0);
            assert!(m.areas[1].contains_xy(150.0, 0.0) && !m.areas[1].contains_xy(99.0, 50.0));
        }
    }

    #[test]
    fn truncated_or_random_bytes_are_one_line_errors() {
        let good = synthetic(5, true);
        for cut in 0..good.len() {
            let e = NavMesh::parse(&good[..cut]).unwrap_err();
            assert!(!e.contains('\n') && !e.is_empty(), "{e}");
        }
        let mut rng = SplitMix64::new(7);
        for round in 0..4000 {
            let mut b = if round % 2 == 0 {
                good.clone()
            } else {
                let n = rng.below(300);
                (0..n).map(|_| rng.next_u64() as u8).collect()
            };
            if round % 2 == 0 {
                for _ in 0..1 + rng.below(8) {
                    let i = rng.below(b.len());
                    b[i] = rng.next_u64() as u8;
                }
            } else if b.len() >= 8 {
                b[..4].copy_from_slice(&NAV_MAGIC.to_le_bytes());
                b[4..8].copy_from_slice(&(1 + rng.below(5) as u32).to_le_bytes());
            }
            if let Err(e) = NavMesh::parse(&b) {
                assert!(!e.contains('\n'), "{e}");
            }
        }
        assert!(
            NavMesh::parse(b"GARBAGE!")
                .unwrap_err()
                .contains("not a nav file")
        );
    }

    #[test]
    fn the_shared_meshes_parse_when_present() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../shared/testmaps/goldsrc/nonfree");
        let Ok(entries) = std::fs::read_dir(&dir) else {
            eprintln!("skipped: {} absent", dir.display());
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.extension().is_some_and(|x| x == "nav") {
                let m = NavMesh::open(&p).unwrap();
                let bsp = p.with_extension("bsp");
                let size = std::fs::metadata(&bsp).map(|m| m.len()).unwrap_or(0);
                assert!(m.areas.len() > 100, "{}", p.display());
                eprintln!(
                    "{}: v{} {} areas, {} places, bsp size {} (file {size})",
                    p.display(),
                    m.version,
                    m.areas.len(),
                    m.places.len(),
                    m.bsp_size
                );
            }
        }
    }
}
