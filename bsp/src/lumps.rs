//! The lump directory every BSP format opens with, and the record readers the format
//! folders share: a lump is checked to lie inside the file and to hold whole records
//! before any of its records is trusted.

use crate::error::BspError;
use crate::map::Plane;
use bytemuck::Pod;

/// One directory entry as stored.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct LumpEntry {
    pub offset: i32,
    pub length: i32,
}

/// The lump directory of a file, with the lumps' names for errors.
pub(crate) struct Directory<'a> {
    bytes: &'a [u8],
    pub entries: Vec<LumpEntry>,
    names: &'static [&'static str],
}

impl<'a> Directory<'a> {
    /// The directory of `names.len()` entries starting at byte `at`; every lump is
    /// checked to lie inside the file (lumps we do not read still tell a truncated
    /// file).
    pub fn new(
        bytes: &'a [u8],
        at: usize,
        names: &'static [&'static str],
    ) -> Result<Directory<'a>, BspError> {
        let need = at + 8 * names.len();
        if bytes.len() < need {
            return Err(BspError::TooShort {
                len: bytes.len(),
                need,
            });
        }
        let entries = bytemuck::pod_collect_to_vec(&bytes[at..need]);
        let dir = Directory {
            bytes,
            entries,
            names,
        };
        for i in 0..names.len() {
            dir.lump(i)?;
        }
        Ok(dir)
    }

    /// The bytes of lump `i`, checked to lie inside the file.
    pub fn lump(&self, i: usize) -> Result<&'a [u8], BspError> {
        let e = self.entries[i];
        let (offset, length) = (e.offset as i64, e.length as i64);
        let end = offset + length;
        if offset < 0 || length < 0 || end > self.bytes.len() as i64 {
            return Err(BspError::LumpOutOfBounds {
                lump: self.names[i],
                offset,
                length,
                file_len: self.bytes.len(),
            });
        }
        Ok(&self.bytes[offset as usize..end as usize])
    }

    /// Lump `i` read as an array of `T` records.
    pub fn records<T: Pod>(&self, i: usize) -> Result<Vec<T>, BspError> {
        let bytes = self.lump(i)?;
        let size = std::mem::size_of::<T>();
        if !bytes.len().is_multiple_of(size) {
            return Err(BspError::LumpSize {
                lump: self.names[i],
                length: bytes.len(),
                record: size,
            });
        }
        Ok(bytemuck::pod_collect_to_vec(bytes))
    }
}

/// Every number of every record must be finite.
pub(crate) fn check_finite<'a>(
    lump: &'static str,
    values: impl Iterator<Item = &'a [f32]>,
) -> Result<(), BspError> {
    for (i, v) in values.enumerate() {
        if !v.iter().all(|x| x.is_finite()) {
            return Err(BspError::Malformed {
                lump,
                reason: format!("record {i} holds a non-finite number"),
            });
        }
    }
    Ok(())
}

/// The planes lump (the same 20-byte record in Quake 1, GoldSrc and Quake 2): unit
/// normals and finite distances, or an error.
pub(crate) fn read_planes(dir: &Directory, lump: usize) -> Result<Vec<Plane>, BspError> {
    #[repr(C)]
    #[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
    struct Raw {
        normal: [f32; 3],
        dist: f32,
        kind: i32,
    }
    let planes: Vec<Plane> = dir
        .records::<Raw>(lump)?
        .into_iter()
        .map(|p| Plane {
            normal: p.normal,
            dist: p.dist,
            kind: p.kind,
        })
        .collect();
    for (i, p) in planes.iter().enumerate() {
        let n = p.normal;
        let len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        let finite = n.iter().all(|x| x.is_finite()) && p.dist.is_finite();
        if !(finite && (0.9..=1.1).contains(&len2)) {
            return Err(BspError::Malformed {
                lump: "planes",
                reason: format!("plane {i} has no unit normal or a non-finite distance"),
            });
        }
    }
    Ok(planes)
}
