//! From bytes to a validated [`Bsp`]: header, lumps, normalisation, index checks.

use super::raw;
use crate::entities::parse_entities;
use crate::error::BspError;
use crate::lumps::{Directory, LumpEntry, check_finite, read_planes};
use crate::map::*;
use crate::validate::{LumpNames, validate};

const LUMP_NAMES: [&str; 15] = [
    "entities",
    "planes",
    "textures",
    "vertices",
    "visibility",
    "nodes",
    "texinfo",
    "faces",
    "lighting",
    "clipnodes",
    "leaves",
    "marksurfaces",
    "edges",
    "surfedges",
    "models",
];
const ENTITIES: usize = 0;
const PLANES: usize = 1;
const TEXTURES: usize = 2;
const VERTICES: usize = 3;
const NODES: usize = 5;
const TEXINFO: usize = 6;
const FACES: usize = 7;
const CLIPNODES: usize = 9;
const LEAVES: usize = 10;
const MARKSURFACES: usize = 11;
const EDGES: usize = 12;
const SURFEDGES: usize = 13;
const MODELS: usize = 14;

const HEADER_LEN: usize = 4 + 15 * 8;

const NAMES: LumpNames = LumpNames {
    nodes: "nodes",
    leaves: "leaves",
    marksurfaces: "marksurfaces",
    models: "models",
    clipnodes: "clipnodes",
    leafbrushes: "leafbrushes",
    brushes: "brushes",
    brushsides: "brushsides",
};

fn read_i32(bytes: &[u8], at: usize) -> i32 {
    i32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}

/// Reads a map of the Quake 1 family.
pub fn parse(bytes: &[u8]) -> Result<Bsp, BspError> {
    if bytes.len() < HEADER_LEN {
        return Err(BspError::TooShort {
            len: bytes.len(),
            need: HEADER_LEN,
        });
    }
    let version = match &bytes[0..4] {
        b"BSP2" => BspVersion::Bsp2,
        b"2PSB" => BspVersion::Bsp2psb,
        _ => match read_i32(bytes, 0) {
            29 => BspVersion::Bsp29,
            30 => BspVersion::GoldSrc30,
            v => {
                return Err(BspError::UnknownVersion {
                    found: describe_magic(&bytes[0..4], v),
                });
            }
        },
    };
    let mut dir = Directory::new(bytes, 4, &LUMP_NAMES)?;
    swap_blue_shift_lumps(bytes, &mut dir.entries);

    let entities = parse_entities(dir.lump(ENTITIES)?)?;
    let planes = read_planes(&dir, PLANES)?;
    let textures = read_textures(dir.lump(TEXTURES)?)?;
    let vertices: Vec<[f32; 3]> = dir.records(VERTICES)?;
    check_finite(LUMP_NAMES[VERTICES], vertices.iter().map(|v| v.as_slice()))?;
    let texinfo: Vec<TexInfo> = dir
        .records::<raw::TexInfo>(TEXINFO)?
        .into_iter()
        .map(|t| TexInfo {
            contents: 0,
            vecs: t.vecs,
            miptex: t.miptex,
            flags: t.flags,
        })
        .collect();
    let surfedges: Vec<i32> = dir.records(SURFEDGES)?;
    let models = read_models(&dir)?;

    let wide = matches!(version, BspVersion::Bsp2 | BspVersion::Bsp2psb);
    let (nodes, leaves, clipnodes, faces, edges, marksurfaces) = if wide {
        read_wide(&dir, version)?
    } else {
        read_narrow(&dir)?
    };

    let mut bsp = Bsp {
        version,
        file_size: bytes.len(),
        entities,
        planes,
        textures,
        vertices,
        nodes,
        texinfo,
        faces,
        clipnodes,
        leaves,
        marksurfaces,
        edges,
        surfedges,
        models,
        leaf_brushes: Vec::new(),
        brushes: Vec::new(),
        brush_sides: Vec::new(),
        unused_bad_records: 0,
        unusable_faces: Vec::new(),
        game: Game::Quake,
        game_reason: String::new(),
    };
    validate(&mut bsp, &NAMES)?;
    Ok(bsp)
}

fn describe_magic(magic: &[u8], as_int: i32) -> String {
    if magic.iter().all(|b| b.is_ascii_graphic()) {
        format!("{:?} ({})", String::from_utf8_lossy(magic), as_int)
    } else {
        as_int.to_string()
    }
}

/// Blue Shift's maps store the planes lump first and the entities second. The entity
/// text starts with `{`, planes never do in practice, so the swap is detectable.
fn swap_blue_shift_lumps(bytes: &[u8], entries: &mut [LumpEntry]) {
    let starts_with_brace = |e: LumpEntry| {
        let (o, l) = (e.offset as usize, e.length as usize);
        e.offset >= 0
            && e.length > 0
            && o.checked_add(l).is_some_and(|end| end <= bytes.len())
            && bytes[o..o + l]
                .iter()
                .find(|b| !b.is_ascii_whitespace())
                .is_some_and(|&b| b == b'{')
    };
    if !starts_with_brace(entries[ENTITIES])
        && starts_with_brace(entries[PLANES])
        && entries[ENTITIES].length % 20 == 0
    {
        entries.swap(ENTITIES, PLANES);
    }
}

fn read_textures(bytes: &[u8]) -> Result<Vec<Option<Texture>>, BspError> {
    if bytes.is_empty() {
        return Ok(Vec::new());
    }
    let bad = |reason: String| BspError::Malformed {
        lump: "textures",
        reason,
    };
    if bytes.len() < 4 {
        return Err(bad("shorter than its texture count".into()));
    }
    let count = read_i32(bytes, 0);
    // The count is trusted only once its offset table is known to fit in the lump.
    if count < 0 || 4 + 4 * count as i64 > bytes.len() as i64 {
        return Err(bad(format!(
            "texture count {count} does not fit a lump of {} bytes",
            bytes.len()
        )));
    }
    let header_len = std::mem::size_of::<raw::MipTexHeader>();
    (0..count as usize)
        .map(|i| {
            let offset = read_i32(bytes, 4 + 4 * i);
            if offset == -1 {
                return Ok(None);
            }
            let start = usize::try_from(offset)
                .ok()
                .filter(|&o| o + header_len <= bytes.len())
                .ok_or_else(|| bad(format!("texture {i} has offset {offset} outside the lump")))?;
            let h: raw::MipTexHeader =
                bytemuck::pod_read_unaligned(&bytes[start..start + header_len]);
            let name_len = h.name.iter().position(|&b| b == 0).unwrap_or(16);
            Ok(Some(Texture {
                name: String::from_utf8_lossy(&h.name[..name_len]).into_owned(),
                width: h.width,
                height: h.height,
            }))
        })
        .collect()
}

fn read_models(dir: &Directory) -> Result<Vec<Model>, BspError> {
    let raw: Vec<raw::Model> = dir.records(MODELS)?;
    if raw.is_empty() {
        return Err(BspError::Malformed {
            lump: "models",
            reason: "no world model".into(),
        });
    }
    let mut models = Vec::with_capacity(raw.len());
    for (i, m) in raw.iter().enumerate() {
        check_finite(
            LUMP_NAMES[MODELS],
            [&m.mins[..], &m.maxs[..], &m.origin[..]].into_iter(),
        )?;
        models.push(Model {
            mins: m.mins,
            maxs: m.maxs,
            origin: m.origin,
            headnode: m.headnode,
            first_face: non_negative(MODELS, i, "first_face", m.first_face)?,
            num_faces: non_negative(MODELS, i, "num_faces", m.num_faces)?,
        });
    }
    Ok(models)
}

fn non_negative(lump: usize, record: usize, field: &'static str, v: i32) -> Result<u32, BspError> {
    u32::try_from(v).map_err(|_| BspError::BadIndex {
        lump: LUMP_NAMES[lump],
        record,
        field,
        value: v as i64,
        limit: i32::MAX as usize,
    })
}

type TreeLumps = (
    Vec<Node>,
    Vec<Leaf>,
    Vec<ClipNode>,
    Vec<Face>,
    Vec<[u32; 2]>,
    Vec<u32>,
);

fn bounds16(mins: [i16; 3], maxs: [i16; 3]) -> ([f32; 3], [f32; 3]) {
    (mins.map(f32::from), maxs.map(f32::from))
}

/// GoldSrc v30 and Quake BSP29: 16-bit indices.
fn read_narrow(dir: &Directory) -> Result<TreeLumps, BspError> {
    let nodes = dir
        .records::<raw::Node29>(NODES)?
        .into_iter()
        .map(|n| Node {
            plane: n.plane as u32,
            children: n.children.map(i32::from),
            first_face: n.first_face.into(),
            num_faces: n.num_faces.into(),
        })
        .collect();
    let leaves = dir
        .records::<raw::Leaf29>(LEAVES)?
        .into_iter()
        .map(|l| {
            let (mins, maxs) = bounds16(l.mins, l.maxs);
            Leaf {
                contents: l.contents,
                native_contents: l.contents,
                mins,
                maxs,
                first_marksurface: l.first_marksurface.into(),
                num_marksurfaces: l.num_marksurfaces.into(),
                first_brush: 0,
                num_brushes: 0,
            }
        })
        .collect();
    let clipnodes = dir
        .records::<raw::ClipNode29>(CLIPNODES)?
        .into_iter()
        .map(|c| ClipNode {
            plane: c.plane as u32,
            children: c.children.map(i32::from),
        })
        .collect();
    let faces = dir
        .records::<raw::Face29>(FACES)?
        .into_iter()
        .map(|f| Face {
            plane: f.plane.into(),
            back_side: f.side != 0,
            first_edge: f.first_edge as u32,
            num_edges: f.num_edges.into(),
            texinfo: f.texinfo.into(),
        })
        .collect();
    let edges = dir
        .records::<raw::Edge29>(EDGES)?
        .into_iter()
        .map(|e| e.v.map(u32::from))
        .collect();
    let marks = dir
        .records::<u16>(MARKSURFACES)?
        .into_iter()
        .map(u32::from)
        .collect();
    Ok((nodes, leaves, clipnodes, faces, edges, marks))
}

/// BSP2 and 2PSB: 32-bit indices.
fn read_wide(dir: &Directory, version: BspVersion) -> Result<TreeLumps, BspError> {
    let (nodes, leaves): (Vec<Node>, Vec<Leaf>) = if version == BspVersion::Bsp2 {
        let nodes = dir.records::<raw::NodeBsp2>(NODES)?.into_iter();
        let leaves = dir.records::<raw::LeafBsp2>(LEAVES)?.into_iter();
        (
            nodes
                .map(|n| wide_node(n.plane, n.children, n.first_face, n.num_faces))
                .collect(),
            leaves
                .map(|l| Leaf {
                    contents: l.contents,
                    native_contents: l.contents,
                    mins: l.mins,
                    maxs: l.maxs,
                    first_marksurface: l.first_marksurface,
                    num_marksurfaces: l.num_marksurfaces,
                    first_brush: 0,
                    num_brushes: 0,
                })
                .collect(),
        )
    } else {
        let nodes = dir.records::<raw::Node2psb>(NODES)?.into_iter();
        let leaves = dir.records::<raw::Leaf2psb>(LEAVES)?.into_iter();
        (
            nodes
                .map(|n| wide_node(n.plane, n.children, n.first_face, n.num_faces))
                .collect(),
            leaves
                .map(|l| {
                    let (mins, maxs) = bounds16(l.mins, l.maxs);
                    Leaf {
                        contents: l.contents,
                        native_contents: l.contents,
                        mins,
                        maxs,
                        first_marksurface: l.first_marksurface,
                        num_marksurfaces: l.num_marksurfaces,
                        first_brush: 0,
                        num_brushes: 0,
                    }
                })
                .collect(),
        )
    };
    let clipnodes = dir
        .records::<raw::ClipNodeBsp2>(CLIPNODES)?
        .into_iter()
        .map(|c| ClipNode {
            plane: c.plane as u32,
            children: c.children,
        })
        .collect();
    let faces = dir
        .records::<raw::FaceBsp2>(FACES)?
        .into_iter()
        .map(|f| Face {
            plane: f.plane as u32,
            back_side: f.side != 0,
            first_edge: f.first_edge as u32,
            num_edges: f.num_edges as u32,
            texinfo: f.texinfo as u32,
        })
        .collect();
    let edges = dir
        .records::<raw::EdgeBsp2>(EDGES)?
        .into_iter()
        .map(|e| e.v)
        .collect();
    let marks = dir.records::<u32>(MARKSURFACES)?;
    Ok((nodes, leaves, clipnodes, faces, edges, marks))
}

fn wide_node(plane: i32, children: [i32; 2], first_face: u32, num_faces: u32) -> Node {
    Node {
        plane: plane as u32,
        children,
        first_face,
        num_faces,
    }
}
