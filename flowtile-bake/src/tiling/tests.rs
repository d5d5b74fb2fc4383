//! Selection against a brute-force enumeration of complete tilings, and
//! random tilings over random boundary conditions.

use std::collections::HashSet;

use super::*;
use crate::flow::ArcId;
use crate::rng::Rng;
use crate::tileset::{TileKey, TileSet};

/// Every complete assignment of fluxes to the distinct arcs (within their
/// current bounds) that conserves mass at every slot; returns, per slot, the
/// set of flux tuples that occur.
fn brute_force(t: &Tiling) -> Option<Vec<HashSet<[i32; 4]>>> {
    let slots: Vec<(u32, u32)> = (0..t.height)
        .flat_map(|y| (0..t.width).map(move |x| (x, y)))
        .filter(|&(x, y)| !t.is_blocked(x, y))
        .collect();
    let arcs: Vec<[ArcId; 4]> = slots.iter().map(|&(x, y)| t.slot_arcs(x, y)).collect();
    let mut value: Vec<Option<i32>> = vec![None; t.net.arc_count()];
    let mut out = vec![HashSet::new(); slots.len()];
    let mut budget = 3_000_000u64;
    fn rec(
        t: &Tiling,
        arcs: &[[ArcId; 4]],
        k: usize,
        value: &mut Vec<Option<i32>>,
        out: &mut Vec<HashSet<[i32; 4]>>,
        budget: &mut u64,
    ) -> bool {
        if *budget == 0 {
            return false;
        }
        *budget -= 1;
        if k == arcs.len() {
            for (s, a) in arcs.iter().enumerate() {
                out[s].insert(a.map(|e| value[e].expect("all assigned")));
            }
            return true;
        }
        // First unassigned arc of this slot, or check conservation.
        let open: Vec<ArcId> = arcs[k]
            .iter()
            .copied()
            .filter(|&e| value[e].is_none())
            .collect();
        if let Some(&e) = open.first() {
            let a = t.net.arc(e);
            for v in a.lo..=a.hi {
                value[e] = Some(v);
                if !rec(t, arcs, k, value, out, budget) {
                    value[e] = None;
                    return false;
                }
            }
            value[e] = None;
            return true;
        }
        let [l, b, r, tp] = arcs[k].map(|e| value[e].expect("assigned"));
        if l + b == r + tp {
            return rec(t, arcs, k + 1, value, out, budget);
        }
        true
    }
    let complete = rec(t, &arcs, 0, &mut value, &mut out, &mut budget);
    if !complete {
        return None;
    }
    // Map back to full slot indexing.
    let mut full = vec![HashSet::new(); (t.width * t.height) as usize];
    for (i, &(x, y)) in slots.iter().enumerate() {
        full[(y * t.width + x) as usize] = std::mem::take(&mut out[i]);
    }
    Some(full)
}

fn random_preferences(rng: &mut Rng, w: u32, h: u32) -> crate::prefer::Preferences {
    let mut p = crate::prefer::Preferences {
        regions: Vec::new(),
        straight: [0.0, 1.0, 5.0][rng.below(3) as usize],
        reuse: [0.0, 4.0, 100.0][rng.below(3) as usize],
    };
    for _ in 0..rng.below(3) {
        let (x0, y0) = (rng.below(w as u64) as u32, rng.below(h as u64) as u32);
        p.regions.push(crate::prefer::DirectionRegion {
            x: (x0, x0 + rng.below((w - x0) as u64) as u32),
            y: (y0, y0 + rng.below((h - y0) as u64) as u32),
            direction: [rng.unit() - 0.5, rng.unit() - 0.5],
            strength: [1.0, 8.0, 50.0][rng.below(3) as usize],
        });
    }
    p
}

fn random_border(rng: &mut Rng) -> Border {
    match rng.below(3) {
        0 => Border::Free,
        1 => Border::Zero,
        _ => Border::Periodic,
    }
}

/// Random conditions on a small grid: borders, a few blocked slots, a few
/// fixed fluxes (which may make the problem infeasible).
fn random_conditions(rng: &mut Rng, set: &TileSet, w: u32, h: u32) -> Conditions {
    let mut c = Conditions::borders(random_border(rng), random_border(rng));
    if rng.below(3) == 0 {
        c.blocked = (0..w * h).map(|_| rng.below(6) == 0).collect();
    }
    for _ in 0..rng.below(4) {
        let edge = if rng.below(2) == 0 {
            Edge::Vertical {
                x: rng.below(w as u64 + 1) as u32,
                y: rng.below(h as u64) as u32,
            }
        } else {
            Edge::Horizontal {
                x: rng.below(w as u64) as u32,
                y: rng.below(h as u64 + 1) as u32,
            }
        };
        let r = match edge {
            Edge::Vertical { .. } => set.mx,
            Edge::Horizontal { .. } => set.my,
        };
        let m = r.min + rng.below(r.len() as u64) as i32;
        if !c.fluxes.iter().any(|(e, _)| *e == edge) {
            c.fluxes.push((edge, m));
        }
    }
    c
}

/// Compares the selection of every empty slot with brute force, places a
/// random offered tile in a random empty slot, and repeats until complete.
fn check_against_brute_force(t: &mut Tiling, rng: &mut Rng) -> usize {
    let mut compared = 0;
    loop {
        let Some(reference) = brute_force(t) else {
            return compared; // too large to enumerate
        };
        let empty: Vec<(u32, u32)> = (0..t.height)
            .flat_map(|y| (0..t.width).map(move |x| (x, y)))
            .filter(|&(x, y)| !t.is_blocked(x, y) && t.tile(x, y).is_none())
            .collect();
        if empty.is_empty() {
            return compared;
        }
        for &(x, y) in &empty {
            let sel = t.select(x, y).unwrap();
            let got: HashSet<[i32; 4]> = sel.fluxes.iter().copied().collect();
            assert_eq!(got.len(), sel.fluxes.len(), "duplicate tuples");
            let want = &reference[(y * t.width + x) as usize];
            assert_eq!(
                &got,
                want,
                "slot ({x}, {y}) {}x{} {:?} {:?}",
                t.width,
                t.height,
                t.borders(),
                (0..t.net.arc_count())
                    .map(|a| t.net.arc(a))
                    .collect::<Vec<_>>()
            );
            assert!(t.net.is_feasible());
            compared += 1;
        }
        // Edge intervals equal brute-force min/max.
        let (x, y) = empty[rng.below(empty.len() as u64) as usize];
        let want = &reference[(y * t.width + x) as usize];
        let right = t.edge_interval(Edge::Vertical { x: x + 1, y }).unwrap();
        let lo = want.iter().map(|v| v[2]).min().unwrap();
        let hi = want.iter().map(|v| v[2]).max().unwrap();
        assert_eq!(right, (lo, hi), "right edge interval of ({x}, {y})");
        let sel = t.select(x, y).unwrap();
        let key = sel.key(rng.below(sel.len()));
        t.place(x, y, key).unwrap();
    }
}

#[test]
fn selection_equals_brute_force_on_small_grids() {
    let mut rng = Rng::new(0x5e1ec7);
    let mut compared = 0;
    let mut problems = 0;
    for round in 0..150 {
        let set = if round % 2 == 0 {
            TileSet::paper(3, 3, 1, 3).unwrap()
        } else {
            TileSet::paper(5, 3, 2, 3).unwrap()
        };
        let (w, h) = (1 + rng.below(3) as u32, 1 + rng.below(3) as u32);
        let cond = random_conditions(&mut rng, &set, w, h);
        let t = Tiling::new(set, w, h, &cond);
        let Ok(mut t) = t else {
            // Construction may only refuse what brute force also refuses.
            let err = t.unwrap_err();
            if let TilingError::Infeasible(_) = err {
                let set = TileSet::paper(if round % 2 == 0 { 3 } else { 5 }, 3, 2, 3).unwrap();
                let mut relaxed = cond.clone();
                relaxed.corners.clear();
                if let Ok(probe) = Tiling::new(
                    set,
                    w,
                    h,
                    &Conditions {
                        fluxes: vec![],
                        ..relaxed
                    },
                ) {
                    let mut probe = probe;
                    for &(e, m) in &cond.fluxes {
                        let a = probe.edge_arc(e).unwrap();
                        probe.net.set_bounds(a, m, m);
                    }
                    if let Some(r) = brute_force(&probe) {
                        assert!(
                            r.iter()
                                .zip(&probe.blocked)
                                .all(|(s, b)| *b || s.is_empty())
                        );
                    }
                }
            }
            continue;
        };
        problems += 1;
        compared += check_against_brute_force(&mut t, &mut rng);
        assert!(t.is_complete() || brute_force(&t).is_none());
    }
    assert!(problems > 40, "only {problems} feasible problems");
    assert!(compared > 500, "only {compared} selections compared");
}

#[test]
fn paper_figure_5_situation_is_avoided() {
    // 3×3 with zero borders, (3,3,1): any order, any choice, always completes.
    let mut rng = Rng::new(5);
    for _ in 0..200 {
        let set = TileSet::paper(3, 3, 1, 3).unwrap();
        let mut t =
            Tiling::new(set, 3, 3, &Conditions::borders(Border::Zero, Border::Zero)).unwrap();
        let mut order: Vec<(u32, u32)> = (0..9).map(|i| (i % 3, i / 3)).collect();
        for i in (1..order.len()).rev() {
            order.swap(i, rng.below(i as u64 + 1) as usize);
        }
        for (x, y) in order {
            let sel = t.select(x, y).unwrap();
            assert!(!sel.is_empty());
            t.place(x, y, sel.key(rng.below(sel.len()))).unwrap();
        }
        assert!(t.is_complete());
    }
}

#[test]
fn ten_thousand_random_tilings_complete() {
    let mut rng = Rng::new(10_000);
    let mut completed = 0;
    let mut attempts = 0;
    while completed < 10_000 {
        attempts += 1;
        let set = match rng.below(3) {
            0 => TileSet::paper(3, 3, 1, 3).unwrap(),
            1 => TileSet::paper(5, 5, 2, 3).unwrap(),
            _ => TileSet::paper(5, 3, 5, 3).unwrap(),
        };
        let (w, h) = (1 + rng.below(6) as u32, 1 + rng.below(6) as u32);
        let mut cond = random_conditions(&mut rng, &set, w, h);
        if rng.below(2) == 0 {
            // Guaranteed-feasible conditions: the border fluxes of a random
            // complete tiling of the free problem.
            let free = Conditions {
                fluxes: vec![],
                corners: vec![],
                ..cond.clone()
            };
            if let Ok(mut full) = Tiling::new(set.clone(), w, h, &free) {
                full.random_fill(&mut rng).unwrap();
                cond.fluxes.clear();
                for y in 0..h {
                    for x in [0, w] {
                        let e = Edge::Vertical { x, y };
                        cond.fluxes
                            .push((e, full.net.arc(full.edge_arc(e).unwrap()).x));
                    }
                }
                for x in 0..w {
                    for y in [0, h] {
                        let e = Edge::Horizontal { x, y };
                        cond.fluxes
                            .push((e, full.net.arc(full.edge_arc(e).unwrap()).x));
                    }
                }
            }
        }
        let Ok(mut t) = Tiling::new(set, w, h, &cond) else {
            continue;
        };
        // Half the fills with random designed-flow preferences: weights must
        // never break completability.
        if rng.below(2) == 0 {
            let prefs = random_preferences(&mut rng, w, h);
            t.random_fill_preferring(&mut rng, &prefs).unwrap();
        } else {
            t.random_fill(&mut rng).unwrap();
        }
        assert!(t.is_complete());
        assert!(t.net.is_feasible());
        // Neighbouring tiles agree on every shared edge and corner.
        for y in 0..h {
            for x in 0..w {
                let Some(k) = t.tile(x, y) else { continue };
                assert!(k.is_divergence_free());
                if let Some(r) = (x + 1 < w).then(|| t.tile(x + 1, y)).flatten() {
                    assert_eq!(k.right, r.left);
                    assert_eq!([k.corners[1], k.corners[2]], [r.corners[0], r.corners[3]]);
                }
                if let Some(u) = (y + 1 < h).then(|| t.tile(x, y + 1)).flatten() {
                    assert_eq!(k.top, u.bottom);
                    assert_eq!([k.corners[3], k.corners[2]], [u.corners[0], u.corners[1]]);
                }
            }
        }
        completed += 1;
    }
    assert!(
        attempts < 40_000,
        "too many infeasible problems: {attempts}"
    );
}

#[test]
fn fixed_conditions_are_respected() {
    let set = TileSet::paper(5, 3, 5, 4).unwrap();
    let mut cond = Conditions::borders(Border::Free, Border::Zero);
    for y in 0..4 {
        cond.fluxes.push((Edge::Vertical { x: 0, y }, 1));
    }
    cond.corners.push(((5, 1), 1));
    cond.blocked = parse_mask("......\n..##..\n......\n......", 6, 4).unwrap();
    let mut t = Tiling::new(set, 6, 4, &cond).unwrap();
    t.random_fill(&mut Rng::new(3)).unwrap();
    for y in 0..4 {
        assert_eq!(t.tile(0, y).unwrap().left, 1);
        assert_eq!(
            t.tile(0, y).unwrap().bottom,
            if y == 0 {
                0
            } else {
                t.tile(0, y - 1).unwrap().top
            }
        );
    }
    // Right border carries the same total out.
    let out: i32 = (0..4).map(|y| t.tile(5, y).unwrap().right).sum();
    assert_eq!(out, 4);
    assert_eq!(t.tile(4, 0).unwrap().corners[2], 1);
    assert!(t.tile(2, 2).is_none() && t.is_blocked(2, 2));
    assert_eq!(t.tile(1, 2).unwrap().right, 0);
    assert_eq!(t.tile(1, 2).unwrap().corners[1], 0);
}

#[test]
fn forced_slots_are_filled() {
    // A 1-wide closed corridor with zero walls admits only the zero tile.
    let set = TileSet::paper(3, 3, 1, 3).unwrap();
    let mut t = Tiling::new(set, 1, 5, &Conditions::borders(Border::Zero, Border::Zero)).unwrap();
    assert_eq!(t.fill_forced().unwrap(), 5);
    assert!(t.is_complete());
    // A river with fixed inflow: after placing one tile, forced ones follow.
    let set = TileSet::paper(3, 3, 1, 3).unwrap();
    let mut cond = Conditions::borders(Border::Free, Border::Zero);
    cond.fluxes.push((Edge::Vertical { x: 0, y: 0 }, 1));
    let mut t = Tiling::new(set, 4, 1, &cond).unwrap();
    assert_eq!(t.fill_forced().unwrap(), 4);
    assert!((0..4).all(|x| t.tile(x, 0).unwrap().right == 1));
}

#[test]
fn infeasible_conditions_are_reported() {
    let set = TileSet::paper(3, 3, 1, 3).unwrap();
    let mut cond = Conditions::borders(Border::Zero, Border::Zero);
    cond.fluxes.push((Edge::Vertical { x: 1, y: 0 }, 1));
    // A single slot column between walls cannot carry net flux sideways out.
    let err = Tiling::new(set.clone(), 2, 1, &cond).unwrap_err();
    assert!(matches!(err, TilingError::Infeasible(_)), "{err}");
    let mut cond = Conditions::borders(Border::Zero, Border::Zero);
    cond.fluxes.push((Edge::Vertical { x: 0, y: 0 }, 1));
    cond.fluxes.push((Edge::Vertical { x: 0, y: 0 }, -1));
    assert!(matches!(
        Tiling::new(set.clone(), 2, 1, &cond).unwrap_err(),
        TilingError::Conflict(_)
    ));
    let mut cond = Conditions::borders(Border::Free, Border::Free);
    cond.fluxes.push((Edge::Horizontal { x: 0, y: 0 }, 2));
    assert!(matches!(
        Tiling::new(set.clone(), 2, 1, &cond).unwrap_err(),
        TilingError::FluxOutOfRange(..)
    ));
    assert!(matches!(
        Tiling::new(
            set.clone(),
            0,
            1,
            &Conditions::borders(Border::Free, Border::Free)
        ),
        Err(TilingError::BadGrid(0, 1))
    ));
    assert!(parse_mask("..\n.?", 2, 2).is_err());
    assert!(parse_mask("..", 2, 2).is_err());
    let no_zero = TileSet::new(set.mx, set.my, 1.0, vec![[0.5, 0.0]], 3).unwrap();
    assert_eq!(
        Tiling::new(
            no_zero,
            2,
            2,
            &Conditions::borders(Border::Zero, Border::Free)
        )
        .unwrap_err(),
        TilingError::NoZeroCorner
    );
}

#[test]
fn placement_accepts_exactly_the_selection() {
    let mut rng = Rng::new(77);
    let set = TileSet::paper(3, 3, 2, 3).unwrap();
    let mut refused = 0;
    for _ in 0..20 {
        let mut t = Tiling::new(
            set.clone(),
            3,
            3,
            &Conditions::borders(Border::Zero, Border::Zero),
        )
        .unwrap();
        for _ in 0..rng.below(5) {
            let (x, y) = (rng.below(3) as u32, rng.below(3) as u32);
            if t.tile(x, y).is_none() {
                let sel = t.select(x, y).unwrap();
                t.place(x, y, sel.key(rng.below(sel.len()))).unwrap();
            }
        }
        let (x, y) = (rng.below(3) as u32, rng.below(3) as u32);
        if t.tile(x, y).is_some() {
            continue;
        }
        let offered: HashSet<TileKey> = t.select(x, y).unwrap().keys().collect();
        for key in set.keys() {
            let mut probe = t.clone();
            let ok = probe.place(x, y, key).is_ok();
            assert_eq!(ok, offered.contains(&key), "{key} at ({x}, {y})");
            refused += !ok as usize;
            assert!(probe.net.is_feasible());
        }
    }
    assert!(refused > 0);
}

#[test]
fn same_seed_same_tiling() {
    let set = TileSet::paper(5, 5, 5, 4).unwrap();
    let run = |seed| {
        let mut t = Tiling::new(
            set.clone(),
            12,
            9,
            &Conditions::borders(Border::Periodic, Border::Free),
        )
        .unwrap();
        t.random_fill(&mut Rng::new(seed)).unwrap();
        (0..9)
            .flat_map(|y| (0..12).map(move |x| (x, y)))
            .map(|(x, y)| t.tile(x, y))
            .collect::<Vec<_>>()
    };
    assert_eq!(run(4), run(4));
    assert_ne!(run(4), run(5));
}

/// Exhaustive over first placements: for every slot and every tile the
/// selection offers there, place it and compare every remaining slot's
/// selection and every edge interval with brute force.
#[test]
fn every_first_placement_matches_brute_force() {
    let cases = [
        (3, 3, Border::Zero, Border::Zero),
        (2, 2, Border::Free, Border::Free),
        (3, 2, Border::Periodic, Border::Zero),
    ];
    let mut checked = 0;
    for (w, h, bx, by) in cases {
        let set = TileSet::paper(3, 3, 1, 3).unwrap();
        let base = Tiling::new(set, w, h, &Conditions::borders(bx, by)).unwrap();
        for (x, y) in (0..h).flat_map(|y| (0..w).map(move |x| (x, y))) {
            let mut probe = base.clone();
            let offered: Vec<TileKey> = probe.select(x, y).unwrap().keys().collect();
            let reference = brute_force(&base).unwrap();
            let want: HashSet<[i32; 4]> = reference[(y * w + x) as usize].clone();
            assert_eq!(
                offered.iter().map(|k| k.fluxes()).collect::<HashSet<_>>(),
                want
            );
            for key in offered {
                let mut t = base.clone();
                t.place(x, y, key).unwrap();
                let reference = brute_force(&t).unwrap();
                for (sx, sy) in (0..h).flat_map(|y| (0..w).map(move |x| (x, y))) {
                    if t.tile(sx, sy).is_some() {
                        continue;
                    }
                    let got: HashSet<[i32; 4]> =
                        t.select(sx, sy).unwrap().fluxes.into_iter().collect();
                    assert_eq!(
                        got,
                        reference[(sy * w + sx) as usize],
                        "after {key} at ({x}, {y})"
                    );
                    let (lo, hi) = t
                        .edge_interval(Edge::Horizontal { x: sx, y: sy + 1 })
                        .unwrap();
                    let tops = reference[(sy * w + sx) as usize].iter().map(|v| v[3]);
                    assert_eq!((lo, hi), (tops.clone().min().unwrap(), tops.max().unwrap()));
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 300, "{checked}");
}

/// The fill's shortcuts (ladders, the seam's column cycles) only move flux
/// around closed cycles: the circulation stays feasible, the arcs land where
/// asked when a cycle has room, and the fill that uses them completes.
#[test]
fn shortcut_cycles_keep_the_circulation_feasible() {
    let set = TileSet::paper(5, 5, 1, 4).unwrap();
    let cond = Conditions::borders(Border::Periodic, Border::Periodic);
    let mut rng = Rng::new(11);
    let mut t = Tiling::new(set, 20, 14, &cond).unwrap();
    for x in 0..7 {
        t.place_random(x, 0, &mut rng).unwrap();
    }
    let mut moved = 0;
    for x in 7..20 {
        let seam = t.slot_arcs(x, 0)[1];
        for target in [-2, 2, 0, 1] {
            t.column_move(x, target);
            assert!(t.net.is_feasible());
            moved += (t.net.arc(seam).x == target) as u32;
            t.ladder_move(x, 0, -target);
            assert!(t.net.is_feasible());
        }
    }
    assert!(moved > 30, "{moved} of 52 column moves landed");
    t.random_fill(&mut rng).unwrap();
    assert!(t.is_complete() && t.net.is_feasible());
}
