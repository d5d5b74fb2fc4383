use super::*;
use crate::editor::commands::{Command, ViewSettings, run_script};
use crate::tiling::Edge;

/// The tiling can still be completed: a copy fills completely, and the
/// document's slots are exactly the tiling's tiles.
fn assert_completable(ed: &Editor) {
    let (w, h) = ed.size();
    for y in 0..h {
        for x in 0..w {
            assert_eq!(
                ed.slot(x, y).map(|s| s.0),
                ed.tiling().tile(x, y),
                "document and tiling disagree at ({x}, {y})"
            );
        }
    }
    let mut t = ed.tiling().clone();
    t.random_fill(&mut Rng::new(99))
        .expect("the editor's tiling must stay completable");
    assert!(t.is_complete());
}

fn spec(text: &str) -> Editor {
    Editor::new(Problem::from_toml(text).unwrap()).unwrap()
}

/// 3×1 corridor with walls; 2 units in on the left, 2 out on the right.
fn corridor() -> Editor {
    spec(
        "[tileset]\nmx = 5\nmy = 3\ncorners = 1\n[grid]\nwidth = 3\nheight = 1\nborder_x = \"zero\"\nborder_y = \"zero\"\n\
         [[flux]]\nedge = \"v\"\nx = 0\ny = 0\nm = 2\n[[flux]]\nedge = \"v\"\nx = 3\ny = 0\nm = 2\n",
    )
}

fn key(f: [i32; 4], c: [u16; 4]) -> TileKey {
    TileKey::from_fluxes(f, c)
}

#[test]
fn palette_is_exact_against_trial_placement() {
    // Every tile of the set at every slot of a few problems: the palette
    // allows it exactly when placing it keeps a completion.
    let problems = [
        corridor(),
        spec(
            "[tileset]\nmx = 3\nmy = 3\ncorners = 2\n[grid]\nwidth = 3\nheight = 3\nborder_x = \"periodic\"\nborder_y = \"zero\"\nmask = \"\"\"\n...\n.#.\n...\n\"\"\"\n",
        ),
        spec(
            "[tileset]\nmx = 3\nmy = 3\n[grid]\nwidth = 4\nheight = 2\nborder_y = \"zero\"\n[[flux]]\nedge = \"v\"\nx = 0\ny = [0, 1]\nm = 1\n",
        ),
    ];
    let mut greyed_by_completion = 0;
    for mut ed in problems {
        // One designer tile first, so some reasons are tiles.
        let k = ed.palette(0, 0).unwrap().allowed().last().unwrap();
        ed.place(0, 0, k).unwrap();
        let (w, h) = ed.size();
        for y in 0..h {
            for x in 0..w {
                if ed.tiling().is_blocked(x, y) || ed.slot(x, y).is_some() {
                    continue;
                }
                let p = ed.palette(x, y).unwrap();
                let mut allowed = 0;
                for k in ed.tiling().set().keys() {
                    let fits = ed.tiling().clone().place(x, y, k).is_ok();
                    let why = p.why_not(&k);
                    assert_eq!(fits, why.is_none(), "({x}, {y}) {k}: {why:?}");
                    allowed += fits as u64;
                    if why == Some(Why::NoCompletion) {
                        greyed_by_completion += 1;
                    }
                }
                assert_eq!(allowed, p.allowed_count());
            }
        }
    }
    assert!(
        greyed_by_completion > 0,
        "no tile was greyed for completion"
    );
}

#[test]
fn palette_reasons_name_what_fixes_an_edge() {
    let mut ed = corridor();
    // Middle slot: every edge is free locally, yet only 2 through fits.
    let p = ed.palette(1, 0).unwrap();
    let ok: Vec<[i32; 4]> = p.allowed_fluxes().collect();
    assert_eq!(ok, vec![[2, 0, 2, 0]]);
    assert_eq!(
        p.why_not(&key([1, 0, 1, 0], [0; 4])),
        Some(Why::NoCompletion)
    );
    assert_eq!(Why::NoCompletion.to_string(), "would leave no completion");
    // Left slot: the left edge is the spec's inflow, top and bottom walls.
    let p = ed.palette(0, 0).unwrap();
    assert_eq!(
        p.why_not(&key([1, 0, 1, 0], [0; 4])),
        Some(Why::EdgeFixed {
            side: Side::Left,
            value: 2,
            by: FixedBy::Spec
        })
    );
    assert_eq!(
        p.why_not(&key([2, 1, 2, 1], [0; 4])),
        Some(Why::EdgeFixed {
            side: Side::Bottom,
            value: 0,
            by: FixedBy::Wall
        })
    );
    // A placed tile fixes its neighbour's edge.
    ed.place(1, 0, key([2, 0, 2, 0], [0; 4])).unwrap();
    let p = ed.palette(2, 0).unwrap();
    match p.why_not(&key([1, 0, 1, 0], [0; 4])) {
        Some(Why::EdgeFixed { side, value, by }) => {
            assert_eq!((side, value, by), (Side::Left, 2, FixedBy::Tile(1, 0)));
        }
        other => panic!("{other:?}"),
    }
    // Greyed placements are refused with the palette's reason.
    let err = ed.place(2, 0, key([1, 0, 1, 0], [0; 4])).unwrap_err();
    assert!(
        err.to_string().contains("fixed by the tile at (1, 0)"),
        "{err}"
    );
    assert_completable(&ed);
}

#[test]
fn corner_reasons_and_blocked_neighbours() {
    let mut ed = spec(
        "[tileset]\nmx = 3\nmy = 3\ncorners = 3\n[grid]\nwidth = 3\nheight = 2\nmask = \"\"\"\n...\n#..\n\"\"\"\n",
    );
    let p = ed.palette(1, 0).unwrap();
    // The blocked slot (0, 0) fixes the left edge to 0 and the left corners to zero.
    assert!(matches!(
        p.why_not(&key([1, 0, 1, 0], [0; 4])),
        Some(Why::EdgeFixed {
            side: Side::Left,
            by: FixedBy::Blocked(0, 0),
            ..
        })
    ));
    let zero = ed.tiling().set().zero_corner().unwrap();
    let other = (0..3).find(|&c| c != zero).unwrap();
    assert!(matches!(
        p.why_not(&key([0, 0, 0, 0], [other, zero, zero, zero])),
        Some(Why::CornerFixed {
            corner: 0,
            by: FixedBy::Blocked(0, 0),
            ..
        })
    ));
    // A placed tile fixes the shared corner of its neighbour.
    ed.place(2, 1, key([0, 0, 0, 0], [other, other, other, other]))
        .unwrap();
    let p = ed.palette(1, 1).unwrap();
    assert!(matches!(
        p.why_not(&key([0, 0, 0, 0], [zero, zero, zero, zero])),
        Some(Why::CornerFixed {
            corner: 1,
            by: FixedBy::Tile(2, 1),
            ..
        })
    ));
    // A spec corner fixes a corner; one that disagrees with a tile is refused.
    ed.set_corner(0, 2, Some(other)).unwrap();
    let p = ed.palette(0, 1).unwrap();
    assert!(matches!(
        p.why_not(&key([0, 0, 0, 0], [zero, zero, zero, zero])),
        Some(Why::CornerFixed {
            corner: 3,
            by: FixedBy::Spec,
            ..
        })
    ));
    let err = ed.set_corner(3, 2, Some(zero)).unwrap_err();
    assert!(
        matches!(err, EditError::Conflict { slot: (2, 1), .. }),
        "{err}"
    );
    assert_completable(&ed);
}

#[test]
fn spec_edits_that_admit_no_tiling_are_refused_and_change_nothing() {
    let mut ed = corridor();
    let before = ed.spec().to_toml();
    // Outflow 1 where 2 flow in: flux cannot balance.
    let err = ed
        .set_flux(Edge::Vertical { x: 3, y: 0 }, Some(1))
        .unwrap_err();
    assert!(matches!(err, EditError::NoTiling(_)), "{err}");
    assert!(err.to_string().contains("admits no tiling"), "{err}");
    // Blocking the middle cuts the corridor.
    let err = ed.set_blocked((1, 0), (1, 0), true).unwrap_err();
    assert!(matches!(err, EditError::NoTiling(_)), "{err}");
    assert_eq!(ed.spec().to_toml(), before);
    assert_eq!(ed.history(), (0, 0));
    // A tile in the way of a spec edit is named.
    let mut ed =
        spec("[tileset]\nmx = 3\nmy = 3\n[grid]\nwidth = 3\nheight = 1\nborder_y = \"zero\"\n");
    ed.place(1, 0, key([1, 0, 1, 0], [0; 4])).unwrap();
    let err = ed.set_blocked((0, 0), (0, 0), true).unwrap_err();
    assert!(
        matches!(err, EditError::Conflict { slot: (1, 0), .. }),
        "{err}"
    );
    assert!(err.to_string().contains("clear that tile first"), "{err}");
    let err = ed.set_border(true, Border::Zero).unwrap_err();
    assert!(matches!(err, EditError::Conflict { .. }), "{err}");
    assert_completable(&ed);
}

#[test]
fn every_command_and_undo_redo() {
    let mut ed = Editor::blank(6, 4).unwrap();
    let mut view = ViewSettings::default();
    let script = "\
        border y zero\n\
        border x periodic\n\
        border x free\n\
        block 2 1 3 2\n\
        open 3 2\n\
        flux v 0 0 1\n\
        flux v 0 0 free\n\
        flux h 0 0 0\n\
        corner 1 1 0\n\
        corner 1 1 free\n\
        place 0 0 pick 0\n\
        place 5 3 0 0 0 0\n\
        seed 7\n\
        prefer straight 1\n\
        prefer reuse 2\n\
        prefer direction 0 0 5 3 1 0 2\n\
        prefer clear\n\
        palette 4 0\n\
        fill\n\
        clear 5 3\n\
        clear fill\n\
        fill 3\n\
        undo\n\
        redo\n\
        select 4 1\n\
        style streamlines\n\
        time 1.5\n\
        particles off\n\
        expect-error place 2 1 0 0 0 0\n";
    let mut steps = 0;
    for line in script.lines() {
        let cmd = Command::parse_line(line).unwrap().unwrap();
        let before = ed.history().0;
        let msg = cmd.apply(&mut ed, &mut view).unwrap();
        assert!(!msg.is_empty());
        assert_completable(&ed);
        if !cmd.is_view()
            && !matches!(
                cmd,
                Command::Palette(..) | Command::Undo | Command::Redo | Command::ExpectError(_)
            )
        {
            assert_eq!(ed.history().0, before + 1, "{cmd} left no undo step");
        }
        steps += 1;
    }
    assert_eq!(steps, 29);
    assert!(ed.tiling().is_complete());
    assert_eq!(view.selected, Some((4, 1)));
    assert_eq!(view.time, 1.5);
    // Undo everything, then redo everything: back to the same tiling.
    let done: Vec<Option<TileKey>> = (0..24).map(|i| ed.tiling().tile(i % 6, i / 6)).collect();
    let n = ed.history().0;
    for _ in 0..n {
        ed.undo().unwrap();
        assert_completable(&ed);
    }
    assert!(ed.undo().is_err());
    assert_eq!(
        ed.spec().to_toml(),
        Editor::blank(6, 4).unwrap().spec().to_toml()
    );
    for _ in 0..n {
        ed.redo().unwrap();
        assert_completable(&ed);
    }
    assert!(ed.redo().is_err());
    let again: Vec<Option<TileKey>> = (0..24).map(|i| ed.tiling().tile(i % 6, i / 6)).collect();
    assert_eq!(done, again);
}

#[test]
fn a_new_edit_after_undo_drops_the_redo_steps() {
    let mut ed = Editor::blank(3, 3).unwrap();
    ed.fill(None).unwrap();
    ed.undo().unwrap();
    assert_eq!(ed.history(), (0, 1));
    ed.set_seed(5).unwrap();
    assert_eq!(ed.history(), (1, 0));
}

#[test]
fn blocking_a_tiled_slot_removes_its_tile() {
    let mut ed = Editor::blank(3, 3).unwrap();
    ed.set_border(true, Border::Zero).unwrap();
    ed.set_border(false, Border::Zero).unwrap();
    ed.fill(None).unwrap();
    // Blocking keeps only what still fits: clear first, then block.
    ed.clear((0, 0), (2, 2)).unwrap();
    ed.place(1, 1, key([0, 0, 0, 0], [0; 4])).unwrap();
    assert_eq!(ed.set_blocked((1, 1), (1, 1), true).unwrap(), 1);
    assert_eq!(ed.slot(1, 1), None);
    assert!(ed.tiling().is_blocked(1, 1));
    assert_completable(&ed);
}

#[test]
fn saved_spec_reproduces_the_editors_fill_and_bake() {
    let dir = std::env::temp_dir().join(format!("ftb-editor-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../testdata/flowtiles/river.toml"),
    )
    .unwrap();
    let mut ed = Editor::new(Problem::from_toml(&text).unwrap()).unwrap();
    // The designer fixes two tiles; the fill does the rest.
    let k = ed.palette(5, 3).unwrap().allowed().next().unwrap();
    ed.place(5, 3, k).unwrap();
    let k = ed.palette(20, 6).unwrap().allowed().last().unwrap();
    ed.place(20, 6, k).unwrap();
    assert!(
        ed.bake(&dir.join("x.ftb")).is_err(),
        "incomplete bake refused"
    );
    ed.fill(None).unwrap();
    ed.save(&dir.join("river-edited.toml")).unwrap();
    assert!(!ed.is_modified());
    ed.bake(&dir.join("river-edited.ftb")).unwrap();
    // Reopen: the designer's tiles come back as such, the fill does not.
    let saved =
        Problem::from_toml(&std::fs::read_to_string(dir.join("river-edited.toml")).unwrap())
            .unwrap();
    assert_eq!(saved.tiles.len(), 2);
    let mut again = Editor::new(saved.clone()).unwrap();
    assert_eq!(again.slot(5, 3).map(|s| s.1), Some(Origin::Designer));
    assert_eq!(again.empty_slots(), ed.tiling().open_slots() - 2);
    // `tile` on the saved spec bakes the same bytes the editor baked.
    let mut t = saved.tiling().unwrap();
    t.random_fill_preferring(&mut Rng::new(saved.seed), &saved.preferences)
        .unwrap();
    let bytes = BakedTiling::from_tiling(&t).unwrap().to_bytes();
    assert_eq!(bytes, std::fs::read(dir.join("river-edited.ftb")).unwrap());
    again.fill(None).unwrap();
    assert_eq!(again.baked().unwrap().to_bytes(), bytes);
    // A baked file opens with every tile in place.
    let b = BakedTiling::read(&dir.join("river-edited.ftb")).unwrap();
    let opened = Editor::from_baked(&b).unwrap();
    assert!(opened.tiling().is_complete());
    assert_eq!(opened.baked().unwrap().to_bytes(), bytes);
    // Unwritable paths are reported, not panicked on.
    let err = ed.save(&dir.join("no/such/dir/x.toml")).unwrap_err();
    assert!(matches!(err, EditError::Io(_)), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn scripts_name_the_failing_line() {
    let mut ed = corridor();
    let err = run_script(&mut ed, "fill\n\nbogus 1\n", None).unwrap_err();
    assert!(err.starts_with("line 3:"), "{err}");
    let mut ed = corridor();
    let err = run_script(&mut ed, "# comment\nflux v 3 0 1\n", None).unwrap_err();
    assert!(
        err.starts_with("line 2:") && err.contains("admits no tiling"),
        "{err}"
    );
    let err = run_script(&mut ed, "expect-error fill\n", None).unwrap_err();
    assert!(err.contains("expected `fill` to be refused"), "{err}");
    for bad in [
        "place 1",
        "place 0 0 1 2",
        "flux v 0 0",
        "border z free",
        "border x sideways",
        "prefer straight nan",
        "time -1",
        "block 1 2 3",
        "expect-error expect-error fill",
        "seed -3",
    ] {
        assert!(Command::parse(bad).is_err(), "{bad} parsed");
    }
}

#[test]
fn commands_print_as_they_parse() {
    for line in [
        "block 1 2 3 4",
        "open 0 0 0 0",
        "border x periodic",
        "flux h 3 0 -1",
        "flux v 2 1 free",
        "corner 3 3 2",
        "place 1 1 1 0 1 0 0 0 0 0",
        "place 1 1 pick 4",
        "clear 0 0 2 2",
        "clear fill",
        "fill 9",
        "prefer direction 0 0 3 3 1 0 2",
        "select none",
        "time 2.5",
    ] {
        assert_eq!(Command::parse(line).unwrap().to_string(), line);
    }
}

/// Random command sequences on small grids: after every command the tiling
/// is completable and agrees with the document; a refused command changes
/// nothing.
#[test]
fn random_sessions_stay_completable() {
    let mut rng = Rng::new(2024);
    let mut refused = 0;
    let mut applied = 0;
    for session in 0..40 {
        let (w, h) = (2 + rng.below(4) as u32, 1 + rng.below(4) as u32);
        let mut ed = if session % 2 == 0 {
            Editor::blank(w, h).unwrap()
        } else {
            spec(&format!(
                "[tileset]\nmx = 3\nmy = [-1, 2]\ncorners = 2\n[grid]\nwidth = {w}\nheight = {h}\n"
            ))
        };
        let mut view = ViewSettings::default();
        for _ in 0..30 {
            let x = rng.below(w as u64 + 1) as u32;
            let y = rng.below(h as u64 + 1) as u32;
            let (sx, sy) = (x.min(w - 1), y.min(h - 1));
            let m = rng.below(5) as i32 - 2;
            let line = match rng.below(14) {
                0 => format!("block {sx} {sy}"),
                1 => format!("open {sx} {sy}"),
                2 => format!(
                    "border {} {}",
                    ["x", "y"][rng.below(2) as usize],
                    ["free", "zero", "periodic"][rng.below(3) as usize]
                ),
                3 => format!("flux v {x} {sy} {m}"),
                4 => format!("flux h {sx} {y} {m}"),
                5 => format!("corner {x} {y} {}", rng.below(2)),
                6 | 7 => format!("place {sx} {sy} pick {}", rng.below(50)),
                8 => format!("place {sx} {sy} {m} 0 {m} 0"),
                9 => format!("clear {sx} {sy}"),
                10 => "fill".to_string(),
                11 => "undo".to_string(),
                12 => "redo".to_string(),
                _ => "clear fill".to_string(),
            };
            let cmd = Command::parse(&line).unwrap();
            let before = (ed.spec().to_toml(), ed.document().slots.clone());
            match cmd.apply(&mut ed, &mut view) {
                Ok(_) => applied += 1,
                Err(_) => {
                    refused += 1;
                    assert_eq!(
                        (ed.spec().to_toml(), ed.document().slots.clone()),
                        before,
                        "refused `{line}` changed the document"
                    );
                }
            }
            assert_completable(&ed);
        }
    }
    assert!(
        applied > 300 && refused > 20,
        "{applied} applied, {refused} refused"
    );
}

/// Removing tiles in place leaves the same choices as building the tiling
/// again without them.
#[test]
fn removing_tiles_equals_rebuilding_without_them() {
    let mut rng = Rng::new(7);
    for (border, mask) in [("free", false), ("zero", true), ("periodic", false)] {
        let mask = if mask {
            "mask = \"\"\"\n.....\n.#...\n.....\n...#.\n\"\"\"\n"
        } else {
            ""
        };
        let mut ed = spec(&format!(
            "[tileset]\nmx = 3\nmy = 3\ncorners = 2\n[grid]\nwidth = 5\nheight = 4\nborder_x = \"{border}\"\nborder_y = \"{border}\"\n{mask}"
        ));
        ed.fill(Some(3)).unwrap();
        for _ in 0..8 {
            let (x, y) = (rng.below(5) as u32, rng.below(4) as u32);
            ed.clear((x, y), (x, y)).unwrap();
        }
        let rebuilt = build(ed.document(), "test").unwrap();
        for y in 0..4 {
            for x in 0..5 {
                if ed.tiling().is_blocked(x, y) || ed.slot(x, y).is_some() {
                    continue;
                }
                let a = ed.tiling().clone().select(x, y).unwrap();
                let b = rebuilt.clone().select(x, y).unwrap();
                assert_eq!(a, b, "{border}: slot ({x}, {y})");
            }
        }
        assert_completable(&ed);
    }
}

#[test]
fn a_painted_stroke_undoes_as_one_step() {
    let mut ed = Editor::blank(5, 3).unwrap();
    ed.set_seed(2).unwrap();
    let mark = ed.history().0;
    for x in 0..4 {
        ed.set_blocked((x, 1), (x, 1), true).unwrap();
    }
    assert_eq!(ed.history().0, mark + 4);
    ed.squash_undo(mark);
    assert_eq!(ed.history().0, mark + 1);
    ed.undo().unwrap();
    assert!((0..4).all(|x| !ed.tiling().is_blocked(x, 1)));
    assert_eq!(ed.problem().seed, 2);
    ed.redo().unwrap();
    assert!((0..4).all(|x| ed.tiling().is_blocked(x, 1)));
}
