//! From bytes to a validated [`Bsp`]: the 19-lump directory, both record widths, the
//! contents and surface flags mapped onto the common model.

use super::raw;
use crate::entities::parse_entities;
use crate::error::BspError;
use crate::lumps::{Directory, check_finite, read_planes};
use crate::map::*;
use crate::validate::{LumpNames, validate};

const LUMP_NAMES: [&str; 19] = [
    "entities",
    "planes",
    "vertices",
    "visibility",
    "nodes",
    "texinfo",
    "faces",
    "lighting",
    "leaves",
    "leaffaces",
    "leafbrushes",
    "edges",
    "surfedges",
    "models",
    "brushes",
    "brushsides",
    "pop",
    "areas",
    "areaportals",
];
const ENTITIES: usize = 0;
const PLANES: usize = 1;
const VERTICES: usize = 2;
const NODES: usize = 4;
const TEXINFO: usize = 5;
const FACES: usize = 6;
const LEAVES: usize = 8;
const LEAFFACES: usize = 9;
const LEAFBRUSHES: usize = 10;
const EDGES: usize = 11;
const SURFEDGES: usize = 12;
const MODELS: usize = 13;
const BRUSHES: usize = 14;
const BRUSHSIDES: usize = 15;

const NAMES: LumpNames = LumpNames {
    nodes: "nodes",
    leaves: "leaves",
    marksurfaces: "leaffaces",
    models: "models",
    clipnodes: "clipnodes",
    leafbrushes: "leafbrushes",
    brushes: "brushes",
    brushsides: "brushsides",
};

/// Reads a Quake 2 map (IBSP 38 or Qbism's QBSP 38).
pub fn parse(bytes: &[u8]) -> Result<Bsp, BspError> {
    let wide = bytes.starts_with(b"QBSP");
    let version = if wide {
        BspVersion::Quake2Qbism
    } else {
        BspVersion::Quake2
    };
    let dir = Directory::new(bytes, 8, &LUMP_NAMES)?;
    let entities = parse_entities(dir.lump(ENTITIES)?)?;
    let planes = read_planes(&dir, PLANES)?;
    let vertices: Vec<[f32; 3]> = dir.records(VERTICES)?;
    check_finite(LUMP_NAMES[VERTICES], vertices.iter().map(|v| v.as_slice()))?;
    let (texinfo, textures) = read_texinfo(&dir)?;
    let surfedges: Vec<i32> = dir.records(SURFEDGES)?;
    let models = read_models(&dir)?;
    let brushes = dir
        .records::<raw::Brush>(BRUSHES)?
        .into_iter()
        .map(|b| Brush {
            first_side: b.first_side as u32,
            num_sides: b.num_sides as u32,
            contents: b.contents,
        })
        .collect();
    let mut bsp = Bsp {
        version,
        file_size: bytes.len(),
        entities,
        planes,
        textures,
        vertices,
        nodes: Vec::new(),
        texinfo,
        faces: Vec::new(),
        clipnodes: Vec::new(),
        leaves: Vec::new(),
        marksurfaces: Vec::new(),
        edges: Vec::new(),
        surfedges,
        models,
        leaf_brushes: Vec::new(),
        brushes,
        brush_sides: Vec::new(),
        unused_bad_records: 0,
        unusable_faces: Vec::new(),
        game: Game::Quake,
        game_reason: String::new(),
    };
    if wide {
        read_wide(&dir, &mut bsp)?;
    } else {
        read_narrow(&dir, &mut bsp)?;
    }
    validate(&mut bsp, &NAMES)?;
    Ok(bsp)
}

/// Texture projections with their surface flags; the texture names (Quake 2 keeps
/// them in the texinfo, the pixels in external files) become the texture list.
fn read_texinfo(dir: &Directory) -> Result<(Vec<TexInfo>, Vec<Option<Texture>>), BspError> {
    let raw: Vec<raw::TexInfo> = dir.records(TEXINFO)?;
    let mut names: Vec<Option<Texture>> = Vec::new();
    let mut index = std::collections::HashMap::new();
    let texinfo = raw
        .iter()
        .map(|t| {
            let len = t.texture.iter().position(|&b| b == 0).unwrap_or(32);
            let name = String::from_utf8_lossy(&t.texture[..len]).into_owned();
            let miptex = *index.entry(name.clone()).or_insert_with(|| {
                names.push(Some(Texture {
                    name,
                    width: 0,
                    height: 0,
                }));
                names.len() as i32 - 1
            });
            TexInfo {
                contents: 0,
                vecs: t.vecs,
                miptex,
                flags: t.flags,
            }
        })
        .collect();
    Ok((texinfo, names))
}

fn read_models(dir: &Directory) -> Result<Vec<Model>, BspError> {
    let raw: Vec<raw::Model> = dir.records(MODELS)?;
    if raw.is_empty() {
        return Err(BspError::Malformed {
            lump: "models",
            reason: "no world model".into(),
        });
    }
    raw.iter()
        .enumerate()
        .map(|(i, m)| {
            check_finite(
                "models",
                [&m.mins[..], &m.maxs[..], &m.origin[..]].into_iter(),
            )?;
            let count = |field: &'static str, v: i32| {
                u32::try_from(v).map_err(|_| BspError::BadIndex {
                    lump: "models",
                    record: i,
                    field,
                    value: v as i64,
                    limit: i32::MAX as usize,
                })
            };
            Ok(Model {
                mins: m.mins,
                maxs: m.maxs,
                origin: m.origin,
                // No clip hulls: the clip roots stay 0 over an empty clip node list.
                headnode: [m.headnode, 0, 0, 0],
                first_face: count("first_face", m.first_face)?,
                num_faces: count("num_faces", m.num_faces)?,
            })
        })
        .collect()
}

fn leaf(
    contents: i32,
    mins: [f32; 3],
    maxs: [f32; 3],
    faces: (u32, u32),
    brushes: (u32, u32),
) -> Leaf {
    Leaf {
        contents: super::to_quake_contents(contents),
        native_contents: contents,
        mins,
        maxs,
        first_marksurface: faces.0,
        num_marksurfaces: faces.1,
        first_brush: brushes.0,
        num_brushes: brushes.1,
    }
}

fn read_narrow(dir: &Directory, bsp: &mut Bsp) -> Result<(), BspError> {
    bsp.nodes = dir
        .records::<raw::Node>(NODES)?
        .into_iter()
        .map(|n| Node {
            plane: n.plane as u32,
            children: n.children,
            first_face: n.first_face.into(),
            num_faces: n.num_faces.into(),
        })
        .collect();
    bsp.leaves = dir
        .records::<raw::Leaf>(LEAVES)?
        .into_iter()
        .map(|l| {
            leaf(
                l.contents,
                l.mins.map(f32::from),
                l.maxs.map(f32::from),
                (l.first_leaf_face.into(), l.num_leaf_faces.into()),
                (l.first_leaf_brush.into(), l.num_leaf_brushes.into()),
            )
        })
        .collect();
    bsp.faces = dir
        .records::<raw::Face>(FACES)?
        .into_iter()
        .map(|f| Face {
            plane: f.plane.into(),
            back_side: f.side != 0,
            first_edge: f.first_edge as u32,
            num_edges: f.num_edges as u16 as u32,
            texinfo: f.texinfo as u16 as u32,
        })
        .collect();
    bsp.edges = dir
        .records::<[u16; 2]>(EDGES)?
        .into_iter()
        .map(|e| e.map(u32::from))
        .collect();
    bsp.marksurfaces = dir
        .records::<u16>(LEAFFACES)?
        .into_iter()
        .map(u32::from)
        .collect();
    bsp.leaf_brushes = dir
        .records::<u16>(LEAFBRUSHES)?
        .into_iter()
        .map(u32::from)
        .collect();
    bsp.brush_sides = dir
        .records::<raw::BrushSide>(BRUSHSIDES)?
        .into_iter()
        .map(|s| BrushSide {
            plane: s.plane.into(),
            texinfo: s.texinfo.into(),
        })
        .collect();
    Ok(())
}

fn read_wide(dir: &Directory, bsp: &mut Bsp) -> Result<(), BspError> {
    bsp.nodes = dir
        .records::<raw::NodeQbism>(NODES)?
        .into_iter()
        .map(|n| Node {
            plane: n.plane as u32,
            children: n.children,
            first_face: n.first_face,
            num_faces: n.num_faces,
        })
        .collect();
    bsp.leaves = dir
        .records::<raw::LeafQbism>(LEAVES)?
        .into_iter()
        .map(|l| {
            leaf(
                l.contents,
                l.mins,
                l.maxs,
                (l.first_leaf_face, l.num_leaf_faces),
                (l.first_leaf_brush, l.num_leaf_brushes),
            )
        })
        .collect();
    bsp.faces = dir
        .records::<raw::FaceQbism>(FACES)?
        .into_iter()
        .map(|f| Face {
            plane: f.plane,
            back_side: f.side != 0,
            first_edge: f.first_edge as u32,
            num_edges: f.num_edges as u32,
            texinfo: f.texinfo as u32,
        })
        .collect();
    bsp.edges = dir.records::<[u32; 2]>(EDGES)?;
    bsp.marksurfaces = dir.records::<u32>(LEAFFACES)?;
    bsp.leaf_brushes = dir.records::<u32>(LEAFBRUSHES)?;
    bsp.brush_sides = dir
        .records::<raw::BrushSideQbism>(BRUSHSIDES)?
        .into_iter()
        .map(|s| BrushSide {
            plane: s.plane,
            texinfo: s.texinfo,
        })
        .collect();
    Ok(())
}
