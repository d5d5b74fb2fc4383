//! The editor's command language: one command a line, `#` starts a
//! comment. Scripted sessions (`flowtile-bake edit --script FILE`) apply a
//! file of them to the [`Editor`]; the window's buttons and keys call the
//! same [`Command`]s, so what a script does is what a designer does.
//!
//! Coordinates: slot `(x, y)` has `x` to the right and `y` up from the
//! bottom-left slot `(0, 0)`; vertical edge `v X Y` is the left edge of slot
//! `(X, Y)` (`X` = width is the right border), horizontal edge `h X Y` the
//! bottom edge of slot `(X, Y)`; vertex `(X, Y)` is the lower-left corner of
//! slot `(X, Y)`. Fluxes are multiples of the base flux towards +x / +y.
//!
//! | command | what it does |
//! |---|---|
//! | `block X Y [X1 Y1]` | paint slots (a rectangle) blocked: walls, no flow; their tiles go |
//! | `open X Y [X1 Y1]` | erase blocked slots: open them to flow |
//! | `border x\|y free\|zero\|periodic` | the left/right (`x`) or bottom/top (`y`) borders |
//! | `flux v\|h X Y M` / `flux v\|h X Y free` | fix an edge's flux to `M`, or free it |
//! | `corner X Y V` / `corner X Y free` | fix the velocity (option index) at a vertex, or free it |
//! | `place X Y L B R T [C0 C1 C2 C3]` | place the tile with these fluxes (and corners; default the first allowed each) |
//! | `place X Y pick N` | place the palette's `N`-th allowed tile (0-based) |
//! | `clear X Y [X1 Y1]` | clear tiles (always allowed) |
//! | `clear fill` | clear every tile the fill placed, keep the designer's |
//! | `fill [SEED]` | fill the empty slots at random with the spec's preferences |
//! | `undo`, `redo` | |
//! | `seed N` | the spec's seed |
//! | `prefer straight W`, `prefer reuse W` | weights of "favour straight" and "favour reuse" |
//! | `prefer direction X0 Y0 X1 Y1 DX DY [S]` | a main direction for a rectangle of slots (strength `S`, default 1) |
//! | `prefer clear` | remove the main directions |
//! | `palette X Y` | print the palette of a slot (allowed and greyed with reasons) |
//! | `save PATH`, `bake PATH` | write the spec (TOML) / the baked tiling (.ftb) |
//! | `expect-error COMMAND` | run `COMMAND`, which must be refused (a script checks refusals) |
//! | `select X Y` / `select none` | view: open the palette of a slot |
//! | `style arrows\|streamlines` | view: how tiles are drawn |
//! | `time T` | view: particle time in seconds (screenshots are taken at a fixed time) |
//! | `particles on\|off` | view: live particles |
//!
//! ```
//! use flowtile_bake::editor::commands::Command;
//! assert_eq!(Command::parse("flux v 0 2 1").unwrap().to_string(), "flux v 0 2 1");
//! assert!(Command::parse("flux q 0 2 1").is_err());
//! ```

use std::fmt;
use std::path::PathBuf;

use super::model::{EditError, Editor};
use crate::prefer::DirectionRegion;
use crate::tileset::TileKey;
use crate::tiling::{Border, Edge};

/// How the view draws tiles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TileStyle {
    /// One arrow per cell group.
    Arrows,
    /// Short streamlines per tile.
    Streamlines,
}

/// View settings that scripts set (not part of the document, not undone).
#[derive(Clone, Debug, PartialEq)]
pub struct ViewSettings {
    /// The slot whose palette is open.
    pub selected: Option<(u32, u32)>,
    /// How tiles are drawn.
    pub style: TileStyle,
    /// Particle time in seconds.
    pub time: f64,
    /// Live particles.
    pub particles: bool,
    /// The last message (shown in the status bar).
    pub status: String,
}

impl Default for ViewSettings {
    fn default() -> Self {
        ViewSettings {
            selected: None,
            style: TileStyle::Arrows,
            time: 0.0,
            particles: true,
            status: String::new(),
        }
    }
}

/// What a tile to place is given by.
#[derive(Clone, Debug, PartialEq)]
pub enum TileChoice {
    /// Fluxes and optionally corners.
    Key([i32; 4], Option<[u16; 4]>),
    /// The `n`-th allowed tile of the palette.
    Nth(u64),
}

/// One editor command.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Block or open a rectangle of slots.
    Mask {
        /// Corner slots of the rectangle.
        from: (u32, u32),
        /// Other corner.
        to: (u32, u32),
        /// Block (true) or open.
        blocked: bool,
    },
    /// Set a pair of borders (`x`: left/right).
    Border {
        /// Left/right (true) or bottom/top.
        x_axis: bool,
        /// The border.
        border: Border,
    },
    /// Fix or free an edge's flux.
    Flux(Edge, Option<i32>),
    /// Fix or free a vertex's velocity.
    Corner((u32, u32), Option<u16>),
    /// Place a tile.
    Place((u32, u32), TileChoice),
    /// Clear a rectangle of tiles.
    Clear((u32, u32), (u32, u32)),
    /// Clear the fill's tiles.
    ClearFill,
    /// Fill the rest.
    Fill(Option<u64>),
    /// Undo.
    Undo,
    /// Redo.
    Redo,
    /// Set the seed.
    Seed(u64),
    /// Favour straight.
    Straight(f64),
    /// Favour reuse.
    Reuse(f64),
    /// A main direction.
    Direction(DirectionRegion),
    /// Remove the main directions.
    ClearDirections,
    /// Print a palette.
    Palette(u32, u32),
    /// Save the spec.
    Save(PathBuf),
    /// Bake the file.
    Bake(PathBuf),
    /// The inner command must be refused.
    ExpectError(Box<Command>),
    /// View: open a slot's palette.
    Select(Option<(u32, u32)>),
    /// View: tile style.
    Style(TileStyle),
    /// View: particle time.
    Time(f64),
    /// View: particles on or off.
    Particles(bool),
}

fn num<T: std::str::FromStr>(w: &str, what: &str) -> Result<T, String> {
    w.parse()
        .map_err(|_| format!("{what}: expected a number, got {w:?}"))
}

fn finite(w: &str, what: &str) -> Result<f64, String> {
    let v: f64 = num(w, what)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("{what}: {w} is not a finite number"))
    }
}

fn border(w: &str) -> Result<Border, String> {
    match w {
        "free" => Ok(Border::Free),
        "zero" | "wall" => Ok(Border::Zero),
        "periodic" => Ok(Border::Periodic),
        _ => Err(format!("border {w:?}: use free, zero or periodic")),
    }
}

/// Two corner slots of a rectangle.
type SlotRect = ((u32, u32), (u32, u32));

/// A slot rectangle from 2 or 4 numbers.
fn rect(args: &[&str], cmd: &str) -> Result<SlotRect, String> {
    let n: Vec<u32> = args.iter().map(|a| num(a, cmd)).collect::<Result<_, _>>()?;
    match n.as_slice() {
        [x, y] => Ok(((*x, *y), (*x, *y))),
        [x0, y0, x1, y1] => Ok(((*x0, *y0), (*x1, *y1))),
        _ => Err(format!("{cmd}: expected X Y or X0 Y0 X1 Y1")),
    }
}

/// The arguments of `place`: `X Y L B R T [C0 C1 C2 C3]` or `X Y pick N`.
fn parse_place(args: &[&str]) -> Result<Command, String> {
    if args.len() < 3 {
        return Err("place: expected X Y L B R T [C0 C1 C2 C3] or X Y pick N".into());
    }
    let slot = (num(args[0], "place X")?, num(args[1], "place Y")?);
    let choice = if args[2] == "pick" {
        if args.len() != 4 {
            return Err("place X Y pick N: expected one number N".into());
        }
        TileChoice::Nth(num(args[3], "place pick N")?)
    } else {
        let v: Vec<i32> = args[2..]
            .iter()
            .map(|a| num(a, "place"))
            .collect::<Result<_, _>>()?;
        match v.as_slice() {
            [l, b, r, t] => TileChoice::Key([*l, *b, *r, *t], None),
            [l, b, r, t, c @ ..] if c.len() == 4 => {
                let c: Vec<u16> = c
                    .iter()
                    .map(|&c| u16::try_from(c).map_err(|_| format!("corner {c}")))
                    .collect::<Result<_, _>>()?;
                TileChoice::Key([*l, *b, *r, *t], Some([c[0], c[1], c[2], c[3]]))
            }
            _ => {
                return Err("place: expected 4 fluxes (L B R T) and optionally 4 corners".into());
            }
        }
    };
    Ok(Command::Place(slot, choice))
}

/// The arguments of `prefer`: `straight W`, `reuse W`, `clear` or
/// `direction X0 Y0 X1 Y1 DX DY [S]`.
fn parse_prefer(args: &[&str]) -> Result<Command, String> {
    Ok(match args {
        ["straight", w] => Command::Straight(finite(w, "prefer straight")?),
        ["reuse", w] => Command::Reuse(finite(w, "prefer reuse")?),
        ["clear"] => Command::ClearDirections,
        ["direction", rest @ ..] if rest.len() == 6 || rest.len() == 7 => {
            let s = if rest.len() == 7 {
                finite(rest[6], "strength")?
            } else {
                1.0
            };
            Command::Direction(DirectionRegion {
                x: (num(rest[0], "X0")?, num(rest[2], "X1")?),
                y: (num(rest[1], "Y0")?, num(rest[3], "Y1")?),
                direction: [finite(rest[4], "DX")?, finite(rest[5], "DY")?],
                strength: s,
            })
        }
        _ => {
            return Err(
                "prefer: straight W | reuse W | direction X0 Y0 X1 Y1 DX DY [S] | clear".into(),
            );
        }
    })
}

impl Command {
    /// Parses one line (without comment); `Ok(None)` for a blank line.
    pub fn parse_line(line: &str) -> Result<Option<Command>, String> {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            return Ok(None);
        }
        Command::parse(line).map(Some)
    }

    /// Parses one command.
    pub fn parse(line: &str) -> Result<Command, String> {
        let words: Vec<&str> = line.split_whitespace().collect();
        let Some((&cmd, args)) = words.split_first() else {
            return Err("empty command".into());
        };
        let want = |n: usize| -> Result<(), String> {
            if args.len() == n {
                Ok(())
            } else {
                Err(format!("{cmd}: expected {n} arguments, got {}", args.len()))
            }
        };
        Ok(match cmd {
            "block" | "open" => {
                let (from, to) = rect(args, cmd)?;
                Command::Mask {
                    from,
                    to,
                    blocked: cmd == "block",
                }
            }
            "border" => {
                want(2)?;
                let x_axis = match args[0] {
                    "x" => true,
                    "y" => false,
                    a => {
                        return Err(format!(
                            "border {a:?}: use x (left/right) or y (bottom/top)"
                        ));
                    }
                };
                Command::Border {
                    x_axis,
                    border: border(args[1])?,
                }
            }
            "flux" => {
                want(4)?;
                let (x, y) = (num(args[1], "flux X")?, num(args[2], "flux Y")?);
                let edge = match args[0] {
                    "v" => Edge::Vertical { x, y },
                    "h" => Edge::Horizontal { x, y },
                    a => return Err(format!("flux edge {a:?}: use v or h")),
                };
                let m = match args[3] {
                    "free" => None,
                    m => Some(num(m, "flux M")?),
                };
                Command::Flux(edge, m)
            }
            "corner" => {
                want(3)?;
                let v = match args[2] {
                    "free" => None,
                    v => Some(num(v, "corner V")?),
                };
                Command::Corner((num(args[0], "corner X")?, num(args[1], "corner Y")?), v)
            }
            "place" => parse_place(args)?,
            "clear" if args == ["fill"] => Command::ClearFill,
            "clear" => {
                let (a, b) = rect(args, cmd)?;
                Command::Clear(a, b)
            }
            "fill" => match args {
                [] => Command::Fill(None),
                [s] => Command::Fill(Some(num(s, "fill SEED")?)),
                _ => return Err("fill: expected at most a seed".into()),
            },
            "undo" => {
                want(0)?;
                Command::Undo
            }
            "redo" => {
                want(0)?;
                Command::Redo
            }
            "seed" => {
                want(1)?;
                Command::Seed(num(args[0], "seed")?)
            }
            "prefer" => parse_prefer(args)?,
            "palette" => {
                want(2)?;
                Command::Palette(num(args[0], "palette X")?, num(args[1], "palette Y")?)
            }
            "save" | "bake" => {
                if args.is_empty() {
                    return Err(format!("{cmd}: expected a path"));
                }
                let p = PathBuf::from(args.join(" "));
                if cmd == "save" {
                    Command::Save(p)
                } else {
                    Command::Bake(p)
                }
            }
            "expect-error" => {
                let rest = line[cmd.len()..].trim();
                let inner = Command::parse(rest)?;
                if matches!(inner, Command::ExpectError(_)) {
                    return Err("expect-error cannot nest".into());
                }
                Command::ExpectError(Box::new(inner))
            }
            "select" => match args {
                ["none"] => Command::Select(None),
                [x, y] => Command::Select(Some((num(x, "select X")?, num(y, "select Y")?))),
                _ => return Err("select: expected X Y or none".into()),
            },
            "style" => match args {
                ["arrows"] => Command::Style(TileStyle::Arrows),
                ["streamlines"] => Command::Style(TileStyle::Streamlines),
                _ => return Err("style: arrows or streamlines".into()),
            },
            "time" => {
                want(1)?;
                let t = finite(args[0], "time")?;
                if t < 0.0 {
                    return Err("time must not be negative".into());
                }
                Command::Time(t)
            }
            "particles" => match args {
                ["on"] => Command::Particles(true),
                ["off"] => Command::Particles(false),
                _ => return Err("particles: on or off".into()),
            },
            other => return Err(format!("unknown command {other:?}")),
        })
    }

    /// True for commands that change only the view.
    pub fn is_view(&self) -> bool {
        matches!(
            self,
            Command::Select(_) | Command::Style(_) | Command::Time(_) | Command::Particles(_)
        )
    }

    /// Applies the command; returns a one-line message for the log or the
    /// status bar. A refused edit changes nothing and returns the reason.
    pub fn apply(&self, ed: &mut Editor, view: &mut ViewSettings) -> Result<String, EditError> {
        Ok(match self {
            Command::Mask { from, to, blocked } => {
                let n = ed.set_blocked(*from, *to, *blocked)?;
                format!("{} {n} slots", if *blocked { "blocked" } else { "opened" })
            }
            Command::Border { x_axis, border } => {
                ed.set_border(*x_axis, *border)?;
                format!("{self}")
            }
            Command::Flux(e, m) => {
                ed.set_flux(*e, *m)?;
                format!("{self}")
            }
            Command::Corner((x, y), v) => {
                ed.set_corner(*x, *y, *v)?;
                format!("{self}")
            }
            Command::Place((x, y), choice) => {
                let key = match choice {
                    TileChoice::Nth(n) => {
                        let p = ed.palette(*x, *y)?;
                        if *n >= p.allowed_count() {
                            return Err(EditError::Invalid(format!(
                                "slot ({x}, {y}) allows {} tiles; pick {n} is not one",
                                p.allowed_count()
                            )));
                        }
                        p.selection.key(*n)
                    }
                    TileChoice::Key(f, Some(c)) => TileKey::from_fluxes(*f, *c),
                    TileChoice::Key(f, None) => {
                        let p = ed.palette(*x, *y)?;
                        let first = |k: usize| {
                            p.corners[k]
                                .iter()
                                .find(|c| c.why_not.is_none())
                                .map_or(0, |c| c.index)
                        };
                        TileKey::from_fluxes(*f, [first(0), first(1), first(2), first(3)])
                    }
                };
                ed.place(*x, *y, key)?;
                format!("placed {key} at ({x}, {y})")
            }
            Command::Clear(a, b) => format!("cleared {} tiles", ed.clear(*a, *b)?),
            Command::ClearFill => format!("cleared {} filled tiles", ed.clear_filled()?),
            Command::Fill(seed) => {
                let n = ed.fill(*seed)?;
                format!("filled {n} slots")
            }
            Command::Undo => {
                ed.undo()?;
                "undone".into()
            }
            Command::Redo => {
                ed.redo()?;
                "redone".into()
            }
            Command::Seed(s) => {
                ed.set_seed(*s)?;
                format!("seed {s}")
            }
            Command::Straight(w) => {
                ed.set_weights(Some(*w), None)?;
                format!("{self}")
            }
            Command::Reuse(w) => {
                ed.set_weights(None, Some(*w))?;
                format!("{self}")
            }
            Command::Direction(r) => {
                ed.add_direction(r.clone())?;
                format!("{self}")
            }
            Command::ClearDirections => {
                ed.clear_directions()?;
                "main directions cleared".into()
            }
            Command::Palette(x, y) => describe_palette(&ed.palette(*x, *y)?),
            Command::Save(p) => {
                ed.save(p)
                    .map_err(|e| EditError::Io(format!("{}: {e}", p.display())))?;
                format!("saved {}", p.display())
            }
            Command::Bake(p) => {
                let n = ed
                    .bake(p)
                    .map_err(|e| EditError::Io(format!("{}: {e}", p.display())))?;
                format!("baked {} ({n} bytes)", p.display())
            }
            Command::ExpectError(inner) => match inner.apply(ed, view) {
                Ok(msg) => {
                    return Err(EditError::Invalid(format!(
                        "expected `{inner}` to be refused, but it did: {msg}"
                    )));
                }
                Err(e) => format!("refused as expected: {e}"),
            },
            Command::Select(s) => {
                if let Some((x, y)) = s {
                    ed.palette(*x, *y)?;
                }
                view.selected = *s;
                format!("{self}")
            }
            Command::Style(s) => {
                view.style = *s;
                format!("{self}")
            }
            Command::Time(t) => {
                view.time = *t;
                format!("{self}")
            }
            Command::Particles(on) => {
                view.particles = *on;
                format!("{self}")
            }
        })
    }
}

impl fmt::Display for Command {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let b = |b: &Border| match b {
            Border::Free => "free",
            Border::Zero => "zero",
            Border::Periodic => "periodic",
        };
        let opt = |v: Option<String>| v.unwrap_or_else(|| "free".into());
        match self {
            Command::Mask { from, to, blocked } => write!(
                f,
                "{} {} {} {} {}",
                if *blocked { "block" } else { "open" },
                from.0,
                from.1,
                to.0,
                to.1
            ),
            Command::Border { x_axis, border } => {
                write!(
                    f,
                    "border {} {}",
                    if *x_axis { "x" } else { "y" },
                    b(border)
                )
            }
            Command::Flux(e, m) => {
                let (k, x, y) = match e {
                    Edge::Vertical { x, y } => ("v", x, y),
                    Edge::Horizontal { x, y } => ("h", x, y),
                };
                write!(f, "flux {k} {x} {y} {}", opt(m.map(|m| m.to_string())))
            }
            Command::Corner((x, y), v) => {
                write!(f, "corner {x} {y} {}", opt(v.map(|v| v.to_string())))
            }
            Command::Place((x, y), TileChoice::Nth(n)) => write!(f, "place {x} {y} pick {n}"),
            Command::Place((x, y), TileChoice::Key(k, c)) => {
                write!(f, "place {x} {y} {} {} {} {}", k[0], k[1], k[2], k[3])?;
                if let Some(c) = c {
                    write!(f, " {} {} {} {}", c[0], c[1], c[2], c[3])?;
                }
                Ok(())
            }
            Command::Clear(a, c) => write!(f, "clear {} {} {} {}", a.0, a.1, c.0, c.1),
            Command::ClearFill => f.write_str("clear fill"),
            Command::Fill(None) => f.write_str("fill"),
            Command::Fill(Some(s)) => write!(f, "fill {s}"),
            Command::Undo => f.write_str("undo"),
            Command::Redo => f.write_str("redo"),
            Command::Seed(s) => write!(f, "seed {s}"),
            Command::Straight(w) => write!(f, "prefer straight {w}"),
            Command::Reuse(w) => write!(f, "prefer reuse {w}"),
            Command::Direction(r) => write!(
                f,
                "prefer direction {} {} {} {} {} {} {}",
                r.x.0, r.y.0, r.x.1, r.y.1, r.direction[0], r.direction[1], r.strength
            ),
            Command::ClearDirections => f.write_str("prefer clear"),
            Command::Palette(x, y) => write!(f, "palette {x} {y}"),
            Command::Save(p) => write!(f, "save {}", p.display()),
            Command::Bake(p) => write!(f, "bake {}", p.display()),
            Command::ExpectError(c) => write!(f, "expect-error {c}"),
            Command::Select(None) => f.write_str("select none"),
            Command::Select(Some((x, y))) => write!(f, "select {x} {y}"),
            Command::Style(TileStyle::Arrows) => f.write_str("style arrows"),
            Command::Style(TileStyle::Streamlines) => f.write_str("style streamlines"),
            Command::Time(t) => write!(f, "time {t}"),
            Command::Particles(on) => write!(f, "particles {}", if *on { "on" } else { "off" }),
        }
    }
}

/// A palette as text: the allowed flux tuples, the greyed ones with the
/// reason, and the corner options.
pub fn describe_palette(p: &super::model::Palette) -> String {
    use std::fmt::Write;
    let (x, y) = p.slot;
    let allowed: Vec<String> = p
        .allowed_fluxes()
        .map(|f| format!("{} {} {} {}", f[0], f[1], f[2], f[3]))
        .collect();
    let mut s = format!(
        "palette of ({x}, {y}): {} tiles allowed; {} of {} flux tuples (L B R T): {}",
        p.allowed_count(),
        allowed.len(),
        p.fluxes.len(),
        allowed.join(", ")
    );
    // Greyed tuples grouped by reason.
    let mut groups: Vec<(String, Vec<String>)> = Vec::new();
    for c in &p.fluxes {
        if let Some(why) = c.why_not {
            let f = c.fluxes;
            let t = format!("{} {} {} {}", f[0], f[1], f[2], f[3]);
            let why = why.to_string();
            match groups.iter_mut().find(|(w, _)| *w == why) {
                Some(g) => g.1.push(t),
                None => groups.push((why, vec![t])),
            }
        }
    }
    for (why, tuples) in groups {
        let _ = write!(
            s,
            "\n  greyed ({}): {why}: {}",
            tuples.len(),
            tuples.join(", ")
        );
    }
    for (k, list) in p.corners.iter().enumerate() {
        let ok: Vec<String> = list
            .iter()
            .filter(|c| c.why_not.is_none())
            .map(|c| c.index.to_string())
            .collect();
        let _ = write!(s, "\n  corner {k}: {}", ok.join(" "));
        if let Some(c) = list.iter().find_map(|c| c.why_not) {
            let _ = write!(s, " (others greyed: {c})");
        }
    }
    s
}

/// Runs a script (one command a line) on the editor. Returns the log (one
/// line per command: `N: command -> message`). Stops at the first line that
/// does not parse or whose command is refused, with an error naming the
/// line. View commands update `view` when given.
pub fn run_script(
    ed: &mut Editor,
    text: &str,
    view: Option<&mut ViewSettings>,
) -> Result<String, String> {
    let mut own = ViewSettings::default();
    let view = view.unwrap_or(&mut own);
    let mut log = String::new();
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        let cmd = match Command::parse_line(line) {
            Ok(None) => continue,
            Ok(Some(c)) => c,
            Err(e) => return Err(format!("line {n}: {e}")),
        };
        match cmd.apply(ed, view) {
            Ok(msg) => {
                log += &format!("{n}: {cmd} -> {msg}\n");
                view.status = msg;
            }
            Err(e) => return Err(format!("line {n}: `{cmd}` refused: {e}")),
        }
    }
    Ok(log)
}
