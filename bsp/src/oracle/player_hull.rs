//! The player's clip hulls of games that keep none (Quake 2, Quake 3): the brushes
//! moved out by the player's box, carved into the hull-0 tree.
//!
//! GoldSrc and Quake store a tree per player size (clip hulls 1 and 3), built by the
//! compiler from the brushes expanded by the box. Quake 2 and 3 collide the box with
//! the brushes at run time instead (`CM_BoxTrace`), which answers one box at one
//! place but cannot be walked as a tree: the tools that drop players onto floors,
//! follow routes and trace the player (`standing`, the camera replay, flow-tile
//! regions) walk clip hull 1. So the hull is built here the way the compilers build
//! theirs: every blocking brush's side planes moved out by the box's support distance
//! (the files keep each brush's axial and edge bevels, so this is the exact Minkowski
//! sum), carved into the cells of the hull-0 tree, whose solid leaves stay solid.

use super::{Hull, HullNode, PlayerHull, hull_node_on};
use crate::carve::{CarveBrush, Carver, Cell, LeafLists};
use crate::map::Node;
use crate::{Bsp, Game, contents, quake2, quake3};

type P = [f64; 3];

/// Margin around the world's bounds of the box the hull's cells are cut from.
const MARGIN: f64 = 128.0;

fn quake2_player(flags: i32) -> i32 {
    if flags & quake2::contents::MASK_PLAYERSOLID != 0 {
        contents::SOLID
    } else {
        quake2::to_quake_contents(flags)
    }
}

fn quake3_player(flags: i32) -> i32 {
    if flags & quake3::contents::MASK_PLAYERSOLID != 0 {
        contents::SOLID
    } else {
        quake3::to_quake_contents(flags)
    }
}

impl Hull {
    /// The world's clip hull for the player's box `hull`, built from the brushes, for
    /// the games that keep brushes and no clip hulls (Quake 2, 3); `None` otherwise.
    ///
    /// Three steps in one function, marked by comments: every brush's planes moved out
    /// by the box (the Minkowski sum the game's trace computes on the fly), the world
    /// tree's leaves carved by those expanded brushes, and the unreached nodes pruned.
    /// They share the carver's node and leaf lists, which a split would pass around.
    pub fn from_brushes(bsp: &Bsp, hull: PlayerHull) -> Option<Hull> {
        let (mins, maxs, classify, mask): (P, P, fn(i32) -> i32, i32) = match bsp.game {
            Game::Quake2 => {
                let (lo, hi) = hull.quake2_box();
                use quake2::contents as c;
                (
                    lo,
                    hi,
                    quake2_player,
                    c::MASK_PLAYERSOLID | c::LAVA | c::SLIME | c::WATER,
                )
            }
            Game::Quake3 => {
                let (lo, hi) = hull.quake3_box();
                use quake3::contents as c;
                (
                    lo,
                    hi,
                    quake3_player,
                    c::MASK_PLAYERSOLID | c::LAVA | c::SLIME | c::WATER,
                )
            }
            Game::Quake | Game::GoldSrc => return None,
        };
        if bsp.brushes.is_empty() || bsp.nodes.is_empty() || bsp.models[0].headnode[0] < 0 {
            return None;
        }
        let mut planes: Vec<(P, f64)> = bsp
            .planes
            .iter()
            .map(|p| (p.normal.map(f64::from), p.dist as f64))
            .collect();
        // Every relevant brush, its planes moved out by the box, with its box.
        let (lo_w, hi_w) = bsp.bounds();
        let lo_w = [0, 1, 2].map(|i| lo_w[i] as f64 + mins[i] - MARGIN);
        let hi_w = [0, 1, 2].map(|i| hi_w[i] as f64 + maxs[i] + MARGIN);
        let mut brushes = Vec::new();
        for b in super::brushes::listed_brushes(bsp, 0) {
            let brush = &bsp.brushes[b as usize];
            if brush.contents & mask == 0 {
                continue;
            }
            let mut ids = Vec::new();
            let (mut lo, mut hi) = (lo_w, hi_w);
            for s in bsp.brush_sides(brush) {
                let p = &bsp.planes[s.plane as usize];
                let n = p.normal.map(f64::from);
                let support: f64 = (0..3).map(|i| (n[i] * mins[i]).min(n[i] * maxs[i])).sum();
                let d = p.dist as f64 - support;
                for i in 0..3 {
                    if n[i] == 1.0 {
                        hi[i] = hi[i].min(d);
                    } else if n[i] == -1.0 {
                        lo[i] = lo[i].max(-d);
                    }
                }
                ids.push(planes.len() as u32);
                planes.push((n, d));
            }
            brushes.push(CarveBrush {
                planes: ids,
                contents: brush.contents,
                lo,
                hi,
            });
        }
        // Blocking brushes first: their pieces need no further carving.
        let mut order: Vec<u32> = (0..brushes.len() as u32).collect();
        order.sort_by_key(|&i| brushes[i as usize].contents & mask & !(contents_liquids(bsp)) == 0);
        let mut carver = Carver {
            planes: &planes,
            split_planes: Vec::new(),
            brushes: &brushes,
            nodes: bsp.nodes.clone(),
            leaves: Vec::new(),
            classify,
        };
        let mut reached = vec![false; bsp.nodes.len()];
        let root = bsp.models[0].headnode[0];
        let mut stack: Vec<(usize, Option<Cell>)> =
            vec![(root as usize, Some(Cell::cube(lo_w, hi_w)))];
        while let Some((n, cell)) = stack.pop() {
            reached[n] = true;
            let node: Node = bsp.nodes[n];
            let (nrm, d) = planes[node.plane as usize];
            let pieces = Cell::pieces(cell, nrm, d);
            for (side, piece) in pieces.into_iter().enumerate() {
                let c = node.children[side];
                if c >= 0 {
                    if !reached[c as usize] {
                        stack.push((c as usize, piece));
                    }
                    continue;
                }
                let leaf = &bsp.leaves[(-(c + 1)) as usize];
                let new = if let (false, Some(cell)) = (leaf.contents == contents::SOLID, &piece) {
                    let (clo, chi) = cell.bounds();
                    let list: Vec<u32> = order
                        .iter()
                        .copied()
                        .filter(|&b| {
                            let br = &brushes[b as usize];
                            (0..3).all(|i| br.lo[i] < chi[i] && br.hi[i] > clo[i])
                        })
                        .collect();
                    carver.carve(
                        piece,
                        &list,
                        leaf.native_contents & mask,
                        LeafLists::default(),
                    )
                } else {
                    let flags = if leaf.contents == contents::SOLID {
                        mask
                    } else {
                        leaf.native_contents
                    };
                    carver.carve(None, &[], flags, LeafLists::default())
                };
                carver.nodes[n].children[side] = new;
            }
        }
        let Carver {
            nodes: carved,
            leaves,
            split_planes,
            ..
        } = carver;
        planes.extend(split_planes);
        let leaves = &leaves;
        let child = |c: i32| {
            if c >= 0 {
                c
            } else {
                leaves[(-(c + 1)) as usize].contents
            }
        };
        let nodes: Vec<HullNode> = carved
            .iter()
            .enumerate()
            .map(|(i, n)| {
                let (nrm, d) = planes[n.plane as usize];
                // Nodes of the brush models' trees are not the world's: solid.
                let children = if i < reached.len() && !reached[i] {
                    [contents::SOLID; 2]
                } else {
                    n.children.map(child)
                };
                hull_node_on(nrm.map(|x| x as f32), d as f32, children)
            })
            .collect();
        Some(Hull { nodes, root })
    }
}

/// The liquid flags of the map's game (liquids do not end the carving of a piece).
fn contents_liquids(bsp: &Bsp) -> i32 {
    match bsp.game {
        Game::Quake2 => quake2::contents::LAVA | quake2::contents::SLIME | quake2::contents::WATER,
        _ => quake3::contents::LAVA | quake3::contents::SLIME | quake3::contents::WATER,
    }
}
