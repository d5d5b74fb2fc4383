//! Validation shared by every format of the Quake family tree: the records the
//! engines read, reached from the models' trees and face ranges, are checked once so
//! the tools can index freely; records nothing reaches are neutralised, not refused.

use crate::error::BspError;
use crate::map::*;

/// The names the format gives the lumps validation reports on.
pub(crate) struct LumpNames {
    pub nodes: &'static str,
    pub leaves: &'static str,
    pub marksurfaces: &'static str,
    pub models: &'static str,
    pub clipnodes: &'static str,
    pub leafbrushes: &'static str,
    pub brushes: &'static str,
    pub brushsides: &'static str,
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
///
/// One function on purpose: it is the format's checklist, lump by lump in the order
/// later checks rely on (planes before nodes, nodes before leaves, edges before
/// faces), each item a few lines; read top to bottom it says what the reader trusts.
pub(crate) fn validate(bsp: &mut Bsp, names: &LumpNames) -> Result<(), BspError> {
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
        check_node_child(names.models, i, m.headnode[0], nn, nl)?;
        check_range(
            names.models,
            i,
            "face range end",
            m.first_face,
            m.num_faces,
            nf,
        )?;
        mark(&mut face_used, m.first_face, m.num_faces);
        if m.headnode[0] < 0 {
            leaf_used[(-(m.headnode[0] as i64 + 1)) as usize] = true;
        }
    }
    // Hull 0: every node reached from a model, its plane, children and faces.
    walk_tree(
        names.nodes,
        nn,
        bsp.models.iter().map(|m| m.headnode[0]),
        &mut node_used,
        |i| {
            let n = &bsp.nodes[i];
            check(names.nodes, i, "plane", n.plane as i32 as i64, np)?;
            for c in n.children {
                check_node_child(names.nodes, i, c, nn, nl)?;
                if c < 0 {
                    leaf_used[(-(c as i64 + 1)) as usize] = true;
                }
            }
            check_range(
                names.nodes,
                i,
                "face range end",
                n.first_face,
                n.num_faces,
                nf,
            )?;
            mark(&mut face_used, n.first_face, n.num_faces);
            Ok(n.children)
        },
    )?;
    let mut mark_used = vec![false; bsp.marksurfaces.len()];
    for (i, l) in bsp.leaves.iter().enumerate().filter(|(i, _)| leaf_used[*i]) {
        check_range(
            names.leaves,
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
        check(names.marksurfaces, i, "face", m as i64, nf)?;
        face_used[m as usize] = true;
    }
    // Brushes listed in reached leaves (Quake 2): the leaf's range, each brush, its
    // sides and their planes.
    let mut leafbrush_used = vec![false; bsp.leaf_brushes.len()];
    for (i, l) in bsp.leaves.iter().enumerate().filter(|(i, _)| leaf_used[*i]) {
        check_range(
            names.leaves,
            i,
            "leaf brush range end",
            l.first_brush,
            l.num_brushes,
            bsp.leaf_brushes.len(),
        )?;
        mark(&mut leafbrush_used, l.first_brush, l.num_brushes);
    }
    let mut brush_used = vec![false; bsp.brushes.len()];
    for (i, &b) in bsp
        .leaf_brushes
        .iter()
        .enumerate()
        .filter(|(i, _)| leafbrush_used[*i])
    {
        check(names.leafbrushes, i, "brush", b as i64, bsp.brushes.len())?;
        brush_used[b as usize] = true;
    }
    for (i, b) in bsp
        .brushes
        .iter()
        .enumerate()
        .filter(|(i, _)| brush_used[*i])
    {
        check_range(
            names.brushes,
            i,
            "side range end",
            b.first_side,
            b.num_sides,
            bsp.brush_sides.len(),
        )?;
        for (k, s) in bsp.brush_sides[b.first_side as usize..][..b.num_sides as usize]
            .iter()
            .enumerate()
        {
            check(
                names.brushsides,
                b.first_side as usize + k,
                "plane",
                s.plane as i32 as i64,
                np,
            )?;
        }
    }
    // Faces: a face whose plane, texture or edge chain cannot be resolved is one the
    // engine never draws (a protector's garbage, or a face it has no use for); it is
    // not an error but an unusable face, named in `Bsp::unusable_faces` and given no
    // edges. The walls it would have shown are still found from the tree.
    let mut surfedge_used = vec![false; bsp.surfedges.len()];
    let mut edge_used = vec![false; bsp.edges.len()];
    let mut unusable = Vec::new();
    for (i, f) in bsp.faces.iter().enumerate().filter(|(i, _)| face_used[*i]) {
        match face_problem(bsp, f) {
            Some(reason) => unusable.push(UnusableFace {
                index: i as u32,
                reason,
            }),
            None => {
                mark(&mut surfedge_used, f.first_edge, f.num_edges);
                for &se in &bsp.surfedges[f.first_edge as usize..][..f.num_edges as usize] {
                    edge_used[se.unsigned_abs() as usize] = true;
                }
            }
        }
    }
    for u in &unusable {
        bsp.faces[u.index as usize] = Face {
            plane: 0,
            back_side: false,
            first_edge: 0,
            num_edges: 0,
            texinfo: 0,
        };
    }
    bsp.unusable_faces = unusable;
    // Clip hulls: the engines copy the headnodes unchecked and trace a hull only for
    // the model's own entity. Compilers write the clip node count as the headnode of a
    // hull that has no node at all, so an out-of-range headnode is an unused hull
    // (see `Model::clip_headnode`), not an error.
    let nc = bsp.clipnodes.len();
    let mut clip_used = vec![false; nc];
    walk_tree(
        names.clipnodes,
        nc,
        bsp.models
            .iter()
            .flat_map(|m| m.headnode[1..].iter().copied())
            .filter(|&h| (h as i64) < nc as i64),
        &mut clip_used,
        |i| {
            let c = &bsp.clipnodes[i];
            check(names.clipnodes, i, "plane", c.plane as i32 as i64, np)?;
            for child in c.children {
                if child >= 0 {
                    check(names.clipnodes, i, "child", child as i64, nc)?;
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
    (bsp.game, bsp.game_reason) = crate::game::decide(bsp);
    Ok(())
}

/// Why the engine could not draw a face, or `None` when every index it holds
/// resolves: plane, texture, at least three edges, each edge and its vertices.
fn face_problem(bsp: &Bsp, f: &Face) -> Option<String> {
    let (np, nt, ns, ne, nv) = (
        bsp.planes.len(),
        bsp.texinfo.len(),
        bsp.surfedges.len(),
        bsp.edges.len(),
        bsp.vertices.len(),
    );
    if f.plane as usize >= np {
        return Some(format!("plane {} out of range (0..{np})", f.plane as i32));
    }
    if f.texinfo as usize >= nt {
        return Some(format!(
            "texinfo {} out of range (0..{nt})",
            f.texinfo as i32
        ));
    }
    if f.num_edges < 3 {
        return Some(format!("{} edges (at least 3 needed)", f.num_edges));
    }
    // Quake 3 takes a face's surface and contents flags from its shader: a shader
    // record whose name is no name was read from bytes that are not shaders (a lump
    // offset off by a few records), and its flags are garbage too.
    if bsp.version == BspVersion::Quake3 {
        let name = bsp.face_texture_name(f);
        if name.is_empty() || !name.bytes().all(|b| b.is_ascii_graphic()) {
            return Some(format!("shader {:?} is not a shader name", name));
        }
    }
    let end = f.first_edge as u64 + f.num_edges as u64;
    if end > ns as u64 {
        return Some(format!(
            "edges {}..{end} out of range (0..{ns})",
            f.first_edge as i32
        ));
    }
    for (k, &se) in bsp.surfedges[f.first_edge as usize..][..f.num_edges as usize]
        .iter()
        .enumerate()
    {
        let e = se.unsigned_abs() as usize;
        let Some(edge) = bsp.edges.get(e) else {
            return Some(format!(
                "surfedge {} has edge {e} out of range (0..{ne})",
                f.first_edge as usize + k
            ));
        };
        if let Some(&v) = edge.iter().find(|&&v| v as usize >= nv) {
            return Some(format!("edge {e} has vertex {v} out of range (0..{nv})"));
        }
    }
    None
}

fn check(
    lump: &'static str,
    record: usize,
    field: &'static str,
    value: i64,
    limit: usize,
) -> Result<(), BspError> {
    if value < 0 || value >= limit as i64 {
        Err(BspError::BadIndex {
            lump,
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
    lump: &'static str,
    record: usize,
    field: &'static str,
    first: u32,
    count: u32,
    limit: usize,
) -> Result<(), BspError> {
    let end = first as i64 + count as i64;
    if end > limit as i64 {
        Err(BspError::BadIndex {
            lump,
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
    lump: &'static str,
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
            lump,
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
    lump: &'static str,
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
                        lump,
                        reason: format!("node {child} is its own ancestor (the tree has a cycle)"),
                    });
                }
                _ => {}
            }
        }
    }
    Ok(())
}
