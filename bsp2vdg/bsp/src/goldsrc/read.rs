//! From bytes to a validated [`Bsp`]: header, lumps, normalisation, index checks.

use super::raw::{self, LumpEntry};
use crate::entities::parse_entities;
use crate::error::BspError;
use crate::map::*;
use bytemuck::Pod;

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

/// The lump directory after version detection.
struct Directory<'a> {
    bytes: &'a [u8],
    entries: [LumpEntry; 15],
}

impl<'a> Directory<'a> {
    /// The bytes of lump `i`, checked to lie inside the file.
    fn lump(&self, i: usize) -> Result<&'a [u8], BspError> {
        let e = self.entries[i];
        let (offset, length) = (e.offset as i64, e.length as i64);
        let end = offset + length;
        if offset < 0 || length < 0 || end > self.bytes.len() as i64 {
            return Err(BspError::LumpOutOfBounds {
                lump: LUMP_NAMES[i],
                offset,
                length,
                file_len: self.bytes.len(),
            });
        }
        Ok(&self.bytes[offset as usize..end as usize])
    }

    /// Lump `i` read as an array of `T` records.
    fn records<T: Pod>(&self, i: usize) -> Result<Vec<T>, BspError> {
        let bytes = self.lump(i)?;
        let size = std::mem::size_of::<T>();
        if bytes.len() % size != 0 {
            return Err(BspError::LumpSize {
                lump: LUMP_NAMES[i],
                length: bytes.len(),
                record: size,
            });
        }
        Ok(bytemuck::pod_collect_to_vec(bytes))
    }
}

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
    let mut entries: [LumpEntry; 15] = bytemuck::pod_read_unaligned(&bytes[4..HEADER_LEN]);
    swap_blue_shift_lumps(bytes, &mut entries);
    let dir = Directory { bytes, entries };
    // Lumps we do not read (visibility, lighting) still tell a truncated file.
    for i in 0..LUMP_NAMES.len() {
        dir.lump(i)?;
    }

    let entities = parse_entities(dir.lump(ENTITIES)?)?;
    let planes = read_planes(&dir)?;
    let textures = read_textures(dir.lump(TEXTURES)?)?;
    let vertices: Vec<[f32; 3]> = dir.records(VERTICES)?;
    check_finite(VERTICES, vertices.iter().map(|v| v.as_slice()))?;
    let texinfo: Vec<TexInfo> = dir
        .records::<raw::TexInfo>(TEXINFO)?
        .into_iter()
        .map(|t| TexInfo {
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
        unused_bad_records: 0,
    };
    validate(&mut bsp)?;
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
fn swap_blue_shift_lumps(bytes: &[u8], entries: &mut [LumpEntry; 15]) {
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

fn check_finite<'a>(lump: usize, values: impl Iterator<Item = &'a [f32]>) -> Result<(), BspError> {
    for (i, v) in values.enumerate() {
        if !v.iter().all(|x| x.is_finite()) {
            return Err(BspError::Malformed {
                lump: LUMP_NAMES[lump],
                reason: format!("record {i} holds a non-finite number"),
            });
        }
    }
    Ok(())
}

fn read_planes(dir: &Directory) -> Result<Vec<Plane>, BspError> {
    let planes: Vec<Plane> = dir
        .records::<raw::Plane>(PLANES)?
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
            MODELS,
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
                mins,
                maxs,
                first_marksurface: l.first_marksurface.into(),
                num_marksurfaces: l.num_marksurfaces.into(),
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
                    mins: l.mins,
                    maxs: l.maxs,
                    first_marksurface: l.first_marksurface,
                    num_marksurfaces: l.num_marksurfaces,
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
                        mins,
                        maxs,
                        first_marksurface: l.first_marksurface,
                        num_marksurfaces: l.num_marksurfaces,
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

/// Checks what the engines read: the records reachable from the models' trees and
/// face ranges, once, so that later stages can index without checks.
///
/// Records nothing reaches are never read by the game, and some maps fill them with
/// garbage to break decompilers (a clip node with plane -2136128596, a surfedge past
/// the edges). Those are not errors: their bad indices are replaced by harmless ones
/// (an unused node or clip node leads to solid, an unused face gets no edges), so that
/// code walking every record stays safe, and they are counted in
/// [`Bsp::unused_bad_records`].
fn validate(bsp: &mut Bsp) -> Result<(), BspError> {
    let (np, nn, nl, nf) = (
        bsp.planes.len(),
        bsp.nodes.len(),
        bsp.leaves.len(),
        bsp.faces.len(),
    );
    let mut face_used = vec![false; nf];
    let mut leaf_used = vec![false; nl];
    let mut node_used = vec![false; nn];
    for (i, m) in bsp.models.iter().enumerate() {
        check_node_child(MODELS, i, m.headnode[0], nn, nl)?;
        check_range(MODELS, i, "face range end", m.first_face, m.num_faces, nf)?;
        mark(&mut face_used, m.first_face, m.num_faces);
        if m.headnode[0] < 0 {
            leaf_used[(-(m.headnode[0] as i64 + 1)) as usize] = true;
        }
    }
    // Hull 0: every node reached from a model, its plane, children and faces.
    walk_tree(
        NODES,
        nn,
        bsp.models.iter().map(|m| m.headnode[0]),
        &mut node_used,
        |i| {
            let n = &bsp.nodes[i];
            check(NODES, i, "plane", n.plane as i32 as i64, np)?;
            for c in n.children {
                check_node_child(NODES, i, c, nn, nl)?;
                if c < 0 {
                    leaf_used[(-(c as i64 + 1)) as usize] = true;
                }
            }
            check_range(NODES, i, "face range end", n.first_face, n.num_faces, nf)?;
            mark(&mut face_used, n.first_face, n.num_faces);
            Ok(n.children)
        },
    )?;
    let mut mark_used = vec![false; bsp.marksurfaces.len()];
    for (i, l) in bsp.leaves.iter().enumerate().filter(|(i, _)| leaf_used[*i]) {
        check_range(
            LEAVES,
            i,
            "marksurface range end",
            l.first_marksurface,
            l.num_marksurfaces,
            bsp.marksurfaces.len(),
        )?;
        mark(&mut mark_used, l.first_marksurface, l.num_marksurfaces);
    }
    for (i, &m) in bsp
        .marksurfaces
        .iter()
        .enumerate()
        .filter(|(i, _)| mark_used[*i])
    {
        check(MARKSURFACES, i, "face", m as i64, nf)?;
        face_used[m as usize] = true;
    }
    let mut surfedge_used = vec![false; bsp.surfedges.len()];
    for (i, f) in bsp.faces.iter().enumerate().filter(|(i, _)| face_used[*i]) {
        check(FACES, i, "plane", f.plane as i32 as i64, np)?;
        check(
            FACES,
            i,
            "texinfo",
            f.texinfo as i32 as i64,
            bsp.texinfo.len(),
        )?;
        if f.num_edges < 3 {
            return Err(BspError::Malformed {
                lump: "faces",
                reason: format!("face {i} has {} edges (at least 3 needed)", f.num_edges),
            });
        }
        check(
            FACES,
            i,
            "first_edge",
            f.first_edge as i32 as i64,
            bsp.surfedges.len(),
        )?;
        check_range(
            FACES,
            i,
            "edge range end",
            f.first_edge,
            f.num_edges,
            bsp.surfedges.len(),
        )?;
        mark(&mut surfedge_used, f.first_edge, f.num_edges);
    }
    let mut edge_used = vec![false; bsp.edges.len()];
    for (i, &se) in bsp
        .surfedges
        .iter()
        .enumerate()
        .filter(|(i, _)| surfedge_used[*i])
    {
        check(
            SURFEDGES,
            i,
            "edge",
            se.unsigned_abs() as i64,
            bsp.edges.len(),
        )?;
        edge_used[se.unsigned_abs() as usize] = true;
    }
    for (i, e) in bsp.edges.iter().enumerate().filter(|(i, _)| edge_used[*i]) {
        for v in e {
            check(EDGES, i, "vertex", *v as i64, bsp.vertices.len())?;
        }
    }
    // Clip hulls: the engines copy the headnodes unchecked and trace a hull only for
    // the model's own entity. Compilers write the clip node count as the headnode of a
    // hull that has no node at all, so an out-of-range headnode is an unused hull
    // (see `Model::clip_headnode`), not an error.
    let nc = bsp.clipnodes.len();
    let mut clip_used = vec![false; nc];
    walk_tree(
        CLIPNODES,
        nc,
        bsp.models
            .iter()
            .flat_map(|m| m.headnode[1..].iter().copied())
            .filter(|&h| (h as i64) < nc as i64),
        &mut clip_used,
        |i| {
            let c = &bsp.clipnodes[i];
            check(CLIPNODES, i, "plane", c.plane as i32 as i64, np)?;
            for child in c.children {
                if child >= 0 {
                    check(CLIPNODES, i, "child", child as i64, nc)?;
                }
            }
            Ok(c.children)
        },
    )?;
    bsp.unused_bad_records = neutralise_unused(
        bsp,
        &node_used,
        &leaf_used,
        &mark_used,
        &face_used,
        &surfedge_used,
        &edge_used,
        &clip_used,
    );
    Ok(())
}

fn check(
    lump: usize,
    record: usize,
    field: &'static str,
    value: i64,
    limit: usize,
) -> Result<(), BspError> {
    if value < 0 || value >= limit as i64 {
        Err(BspError::BadIndex {
            lump: LUMP_NAMES[lump],
            record,
            field,
            value,
            limit,
        })
    } else {
        Ok(())
    }
}

/// A range [first, first + count) must fit into `limit` elements.
fn check_range(
    lump: usize,
    record: usize,
    field: &'static str,
    first: u32,
    count: u32,
    limit: usize,
) -> Result<(), BspError> {
    let end = first as i64 + count as i64;
    if end > limit as i64 {
        Err(BspError::BadIndex {
            lump: LUMP_NAMES[lump],
            record,
            field,
            value: end,
            limit: limit + 1,
        })
    } else {
        Ok(())
    }
}

/// Marks `first..first + count` (already checked to fit).
fn mark(used: &mut [bool], first: u32, count: u32) {
    used[first as usize..first as usize + count as usize].fill(true);
}

/// Replaces the bad indices of records no model reaches (see [`validate`]); returns
/// how many records were touched.
#[allow(clippy::too_many_arguments)]
fn neutralise_unused(
    bsp: &mut Bsp,
    node_used: &[bool],
    leaf_used: &[bool],
    mark_used: &[bool],
    face_used: &[bool],
    surfedge_used: &[bool],
    edge_used: &[bool],
    clip_used: &[bool],
) -> usize {
    let (np, nn, nl, nf) = (
        bsp.planes.len(),
        bsp.nodes.len(),
        bsp.leaves.len(),
        bsp.faces.len(),
    );
    let mut touched = 0;
    let bad_child = |c: i32| {
        if c >= 0 {
            c as usize >= nn
        } else {
            (-(c as i64 + 1)) as usize >= nl
        }
    };
    // Without planes or leaves no node is reachable; the unused ones are dropped
    // (nothing refers to them), otherwise each bad one becomes a node of two solid
    // leaf-0 children.
    if np == 0 || nl == 0 {
        touched += bsp.nodes.len();
        bsp.nodes.clear();
    } else {
        for (n, _) in bsp.nodes.iter_mut().zip(node_used).filter(|(_, u)| !**u) {
            let bad = n.plane as usize >= np
                || n.children.iter().any(|&c| bad_child(c))
                || n.first_face as u64 + n.num_faces as u64 > nf as u64;
            if bad {
                *n = Node {
                    plane: 0,
                    children: [-1, -1],
                    first_face: 0,
                    num_faces: 0,
                };
                touched += 1;
            }
        }
    }
    let nm = bsp.marksurfaces.len();
    for (l, _) in bsp.leaves.iter_mut().zip(leaf_used).filter(|(_, u)| !**u) {
        if l.first_marksurface as u64 + l.num_marksurfaces as u64 > nm as u64 {
            (l.first_marksurface, l.num_marksurfaces) = (0, 0);
            touched += 1;
        }
    }
    for (m, _) in bsp
        .marksurfaces
        .iter_mut()
        .zip(mark_used)
        .filter(|(_, u)| !**u)
    {
        if *m as usize >= nf {
            *m = 0;
            touched += 1;
        }
    }
    let (nt, ns) = (bsp.texinfo.len(), bsp.surfedges.len());
    for (f, _) in bsp.faces.iter_mut().zip(face_used).filter(|(_, u)| !**u) {
        let bad = f.plane as usize >= np
            || f.texinfo as usize >= nt
            || f.first_edge as u64 + f.num_edges as u64 > ns as u64;
        if bad {
            *f = Face {
                plane: 0,
                back_side: false,
                first_edge: 0,
                num_edges: 0,
                texinfo: 0,
            };
            touched += 1;
        }
    }
    let ne = bsp.edges.len();
    for (se, _) in bsp
        .surfedges
        .iter_mut()
        .zip(surfedge_used)
        .filter(|(_, u)| !**u)
    {
        if se.unsigned_abs() as usize >= ne {
            *se = 0;
            touched += 1;
        }
    }
    let nv = bsp.vertices.len();
    for (e, _) in bsp.edges.iter_mut().zip(edge_used).filter(|(_, u)| !**u) {
        if e.iter().any(|&v| v as usize >= nv) {
            *e = [0, 0];
            touched += 1;
        }
    }
    let nc = bsp.clipnodes.len();
    if np == 0 {
        touched += nc;
        bsp.clipnodes.clear();
    } else {
        for (c, _) in bsp
            .clipnodes
            .iter_mut()
            .zip(clip_used)
            .filter(|(_, u)| !**u)
        {
            if c.plane as usize >= np || c.children.iter().any(|&k| k >= 0 && k as usize >= nc) {
                *c = ClipNode {
                    plane: 0,
                    children: [contents::SOLID; 2],
                };
                touched += 1;
            }
        }
    }
    touched
}

fn check_node_child(
    lump: usize,
    record: usize,
    c: i32,
    nodes: usize,
    leaves: usize,
) -> Result<(), BspError> {
    let (field, value, limit) = if c >= 0 {
        ("child node", c as i64, nodes)
    } else {
        ("child leaf", -(c as i64 + 1), leaves)
    };
    if value >= limit as i64 {
        return Err(BspError::BadIndex {
            lump: LUMP_NAMES[lump],
            record,
            field,
            value,
            limit,
        });
    }
    Ok(())
}

/// Walks every tree from `roots` (negative roots are leaves), calling `visit` once per
/// node reached; `visit` checks the node and returns its children (node children
/// already checked to be in range). A corrupt file could make a walk loop forever, so
/// a cycle is an error; shared subtrees are allowed. `reached` marks the nodes seen.
fn walk_tree(
    lump: usize,
    count: usize,
    roots: impl Iterator<Item = i32>,
    reached: &mut [bool],
    mut visit: impl FnMut(usize) -> Result<[i32; 2], BspError>,
) -> Result<(), BspError> {
    const UNSEEN: u8 = 0;
    const OPEN: u8 = 1;
    const DONE: u8 = 2;
    let mut state = vec![UNSEEN; count];
    let mut stack: Vec<(usize, [i32; 2], u8)> = Vec::new();
    for root in roots {
        if root < 0 || state[root as usize] == DONE {
            continue;
        }
        state[root as usize] = OPEN;
        reached[root as usize] = true;
        stack.push((root as usize, visit(root as usize)?, 0));
        while let Some((node, children, next)) = stack.last_mut() {
            if *next == 2 {
                state[*node] = DONE;
                stack.pop();
                continue;
            }
            let child = children[*next as usize];
            *next += 1;
            if child < 0 {
                continue;
            }
            match state[child as usize] {
                UNSEEN => {
                    state[child as usize] = OPEN;
                    reached[child as usize] = true;
                    let grandchildren = visit(child as usize)?;
                    stack.push((child as usize, grandchildren, 0));
                }
                OPEN => {
                    return Err(BspError::Malformed {
                        lump: LUMP_NAMES[lump],
                        reason: format!("node {child} is its own ancestor (the tree has a cycle)"),
                    });
                }
                _ => {}
            }
        }
    }
    Ok(())
}
