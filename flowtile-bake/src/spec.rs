//! Tiling spec files (TOML): grid, tile set, boundary conditions, mask and
//! seed. See `testdata/flowtiles/*.toml` for examples.
//!
//! ```toml
//! seed = 7
//! fill_forced = false      # place forced slots before the random fill
//! background = "top.png"   # optional picture under the grid in the editor (relative to the spec)
//! [tileset]
//! mx = 5                   # options on vertical edges: a count (centred) or [min, max]
//! my = 3                   # options on horizontal edges
//! corners = 5              # a count of default options, or [[vx, vy], ...]
//! f_base = 1.0
//! n = 8                    # cells per tile side
//! [grid]
//! width = 24
//! height = 8
//! border_x = "free"        # left/right: free | zero | periodic
//! border_y = "zero"        # bottom/top
//! mask = """               # optional, top row first, '#' = blocked
//! ...
//! """
//! [[flux]]                 # fixed flux multiples; x and y are a number or [first, last]
//! edge = "v"               # "v": vertical edge at x (0..=W) in row y; "h": horizontal at y in column x
//! x = 0
//! y = [0, 7]
//! m = 1
//! [[corner]]               # fixed corner velocity (index into the options) at vertex (x, y)
//! x = 3
//! y = 4
//! velocity = 1
//! [[tile]]                 # a tile fixed by the designer (the editor writes these);
//! x = 2                    # placed before the fill, which completes the rest
//! y = 3
//! fluxes = [1, 0, 1, 0]    # left, bottom, right, top
//! corners = [0, 0, 0, 0]   # bottom-left, bottom-right, top-right, top-left
//! [prefer]                 # optional designed flow: weights on the random choice
//! straight = 1.0           # favour tiles whose flow leaves opposite where it enters
//! reuse = 4.0              # favour tiles already placed (fewer distinct tiles)
//! [[prefer.direction]]     # main direction of a region of slots (overlaps add up)
//! x = [0, 23]
//! y = [0, 7]
//! direction = [1.0, 0.0]
//! strength = 2.0
//! ```

use std::fmt;

use serde::Deserialize;

use crate::prefer::{DirectionRegion, Preferences};
use crate::tileset::{FluxRange, TileKey, TileSet, default_corner_options};
use crate::tiling::{
    Border, Conditions, Edge, MAX_SIDE, MAX_SLOTS, Tiling, TilingError, parse_mask,
};

/// A spec that failed to parse or describes an impossible problem.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecError(pub String);

impl fmt::Display for SpecError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SpecError {}

#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
enum CountOrRange {
    Count(u32),
    Range([i32; 2]),
}

#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
enum CornerSpec {
    Count(usize),
    List(Vec<[f64; 2]>),
}

#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(untagged)]
enum Span {
    One(u32),
    Range([u32; 2]),
}

impl Span {
    fn bounds(self) -> (u32, u32) {
        match self {
            Span::One(v) => (v, v),
            Span::Range([a, b]) => (a.min(b), a.max(b)),
        }
    }
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TileSetSpec {
    mx: CountOrRange,
    my: CountOrRange,
    #[serde(default = "one_corner")]
    corners: CornerSpec,
    #[serde(default = "unit")]
    f_base: f64,
    #[serde(default = "eight")]
    n: usize,
}

fn one_corner() -> CornerSpec {
    CornerSpec::Count(1)
}
fn unit() -> f64 {
    1.0
}
fn eight() -> usize {
    8
}

#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
enum BorderSpec {
    Free,
    Zero,
    Periodic,
}

impl From<BorderSpec> for Border {
    fn from(b: BorderSpec) -> Border {
        match b {
            BorderSpec::Free => Border::Free,
            BorderSpec::Zero => Border::Zero,
            BorderSpec::Periodic => Border::Periodic,
        }
    }
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct GridSpec {
    width: u32,
    height: u32,
    #[serde(default = "free")]
    border_x: BorderSpec,
    #[serde(default = "free")]
    border_y: BorderSpec,
    #[serde(default)]
    mask: Option<String>,
}

fn free() -> BorderSpec {
    BorderSpec::Free
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FluxSpec {
    edge: String,
    x: Span,
    y: Span,
    m: i32,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CornerFix {
    x: Span,
    y: Span,
    velocity: u16,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct DirectionSpec {
    x: Span,
    y: Span,
    direction: [f64; 2],
    #[serde(default = "unit")]
    strength: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TileFix {
    x: u32,
    y: u32,
    fluxes: [i32; 4],
    corners: [u16; 4],
}

#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct PreferSpec {
    #[serde(default)]
    straight: f64,
    #[serde(default)]
    reuse: f64,
    #[serde(default)]
    direction: Vec<DirectionSpec>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SpecFile {
    #[serde(default)]
    seed: u64,
    #[serde(default)]
    fill_forced: bool,
    #[serde(default)]
    description: Option<String>,
    #[serde(default)]
    background: Option<String>,
    tileset: TileSetSpec,
    grid: GridSpec,
    #[serde(default)]
    flux: Vec<FluxSpec>,
    #[serde(default)]
    corner: Vec<CornerFix>,
    #[serde(default)]
    tile: Vec<TileFix>,
    #[serde(default)]
    prefer: PreferSpec,
}

/// A tiling problem read from a spec.
#[derive(Clone, Debug)]
pub struct Problem {
    /// The tile set.
    pub set: TileSet,
    /// Grid width in tiles.
    pub width: u32,
    /// Grid height in tiles.
    pub height: u32,
    /// Boundary conditions.
    pub conditions: Conditions,
    /// Seed of the random fill.
    pub seed: u64,
    /// Fill forced slots before the random fill.
    pub fill_forced: bool,
    /// Free text from the spec.
    pub description: Option<String>,
    /// Picture under the grid in the editor (a PNG spanning the grid, path
    /// relative to the spec).
    pub background: Option<String>,
    /// Designed-flow weights for the random fill.
    pub preferences: Preferences,
    /// Tiles fixed by the designer at slots `(x, y)`, placed before the fill.
    pub tiles: Vec<((u32, u32), TileKey)>,
}

fn flux_range(r: &CountOrRange, axis: &str) -> Result<FluxRange, SpecError> {
    match *r {
        CountOrRange::Count(0) => Err(SpecError(format!(
            "tileset.{axis} must offer at least one flux"
        ))),
        CountOrRange::Count(c) => Ok(FluxRange::centered(c)),
        CountOrRange::Range([a, b]) => Ok(FluxRange { min: a, max: b }),
    }
}

impl Problem {
    /// A problem of a tile set, a grid and its conditions alone: seed 1, no
    /// forced fill, description, background, preferences or fixed tiles.
    pub fn new(set: TileSet, width: u32, height: u32, conditions: Conditions) -> Problem {
        Problem {
            set,
            width,
            height,
            conditions,
            seed: 1,
            fill_forced: false,
            description: None,
            background: None,
            preferences: Default::default(),
            tiles: Vec::new(),
        }
    }

    /// Parses and checks a spec (feasibility is checked later, by
    /// [`crate::tiling::Tiling::new`]).
    ///
    /// ```
    /// let p = flowtile_bake::spec::Problem::from_toml(r#"
    ///     [tileset]
    ///     mx = 3
    ///     my = 3
    ///     [grid]
    ///     width = 4
    ///     height = 2
    ///     border_y = "zero"
    ///     [[flux]]
    ///     edge = "v"
    ///     x = 0
    ///     y = [0, 1]
    ///     m = 1
    /// "#).unwrap();
    /// assert_eq!(p.conditions.fluxes.len(), 2);
    /// ```
    pub fn from_toml(text: &str) -> Result<Problem, SpecError> {
        let spec: SpecFile =
            toml::from_str(text).map_err(|e| SpecError(format!("spec: {}", e.message())))?;
        let ts = &spec.tileset;
        let corners = match &ts.corners {
            CornerSpec::Count(c) if *c == 0 || *c > crate::tileset::MAX_CORNER_OPTIONS => {
                return Err(SpecError(format!("tileset.corners = {c} is out of range")));
            }
            CornerSpec::Count(c) => default_corner_options(*c),
            CornerSpec::List(l) => l.clone(),
        };
        let set = TileSet::new(
            flux_range(&ts.mx, "mx")?,
            flux_range(&ts.my, "my")?,
            ts.f_base,
            corners,
            ts.n,
        )
        .map_err(|e| SpecError(format!("tileset: {e}")))?;
        let g = &spec.grid;
        let (w, h) = (g.width, g.height);
        if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE || w as u64 * h as u64 > MAX_SLOTS {
            return Err(SpecError(format!("grid {w}x{h} is empty or too large")));
        }
        let mut conditions = Conditions::borders(g.border_x.into(), g.border_y.into());
        if let Some(mask) = &g.mask {
            conditions.blocked = parse_mask(mask, w, h).map_err(|e| SpecError(e.to_string()))?;
        }
        for (i, f) in spec.flux.iter().enumerate() {
            let (x0, x1) = f.x.bounds();
            let (y0, y1) = f.y.bounds();
            let vertical = match f.edge.as_str() {
                "v" | "vertical" => true,
                "h" | "horizontal" => false,
                other => {
                    return Err(SpecError(format!(
                        "flux[{i}].edge = {other:?}; use \"v\" or \"h\""
                    )));
                }
            };
            let (xmax, ymax) = if vertical { (w, h - 1) } else { (w - 1, h) };
            if x1 > xmax || y1 > ymax {
                return Err(SpecError(format!(
                    "flux[{i}] reaches edge ({x1}, {y1}); {} edges go up to ({xmax}, {ymax})",
                    if vertical { "vertical" } else { "horizontal" }
                )));
            }
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let e = if vertical {
                        Edge::Vertical { x, y }
                    } else {
                        Edge::Horizontal { x, y }
                    };
                    conditions.fluxes.push((e, f.m));
                }
            }
        }
        for (i, c) in spec.corner.iter().enumerate() {
            let (x0, x1) = c.x.bounds();
            let (y0, y1) = c.y.bounds();
            if x1 > w || y1 > h {
                return Err(SpecError(format!(
                    "corner[{i}] reaches vertex ({x1}, {y1}) outside the grid"
                )));
            }
            for y in y0..=y1 {
                for x in x0..=x1 {
                    conditions.corners.push(((x, y), c.velocity));
                }
            }
        }
        let mut preferences = Preferences {
            regions: Vec::new(),
            straight: spec.prefer.straight,
            reuse: spec.prefer.reuse,
        };
        for (i, d) in spec.prefer.direction.iter().enumerate() {
            let (x0, x1) = d.x.bounds();
            let (y0, y1) = d.y.bounds();
            if x1 >= w || y1 >= h {
                return Err(SpecError(format!(
                    "prefer.direction[{i}] reaches slot ({x1}, {y1}) outside the {w}x{h} grid"
                )));
            }
            preferences.regions.push(DirectionRegion {
                x: (x0, x1),
                y: (y0, y1),
                direction: d.direction,
                strength: d.strength,
            });
        }
        preferences
            .validate()
            .map_err(|e| SpecError(format!("prefer: {e}")))?;
        let mut tiles = Vec::with_capacity(spec.tile.len());
        for (i, t) in spec.tile.iter().enumerate() {
            if t.x >= w || t.y >= h {
                return Err(SpecError(format!(
                    "tile[{i}] at slot ({}, {}) lies outside the {w}x{h} grid",
                    t.x, t.y
                )));
            }
            let key = TileKey::from_fluxes(t.fluxes, t.corners);
            if set.index_of(&key).is_none() {
                return Err(SpecError(format!(
                    "tile[{i}] {key} is not in the tile set (fluxes must conserve mass and lie in the ranges)"
                )));
            }
            if tiles.iter().any(|&(s, _)| s == (t.x, t.y)) {
                return Err(SpecError(format!(
                    "tile[{i}]: slot ({}, {}) holds two tiles",
                    t.x, t.y
                )));
            }
            tiles.push(((t.x, t.y), key));
        }
        Ok(Problem {
            set,
            width: w,
            height: h,
            conditions,
            seed: spec.seed,
            fill_forced: spec.fill_forced,
            description: spec.description,
            background: spec.background,
            preferences,
            tiles,
        })
    }

    /// The problem's tiling before the fill: empty slots under the
    /// conditions, with the designer's fixed tiles placed (an error names a
    /// fixed tile that would leave no completion).
    pub fn tiling(&self) -> Result<Tiling, TilingError> {
        let mut t = Tiling::new(self.set.clone(), self.width, self.height, &self.conditions)?;
        for &((x, y), key) in &self.tiles {
            t.place(x, y, key)?;
        }
        Ok(t)
    }

    /// Writes the problem as a spec that [`Problem::from_toml`] reads back
    /// to an equal problem (the editor's "save"). Fixed fluxes, corners and
    /// tiles are written one entry each; floats in Rust's shortest
    /// round-trip form.
    ///
    /// ```
    /// use flowtile_bake::spec::Problem;
    /// let p = Problem::from_toml("[tileset]\nmx = 3\nmy = 3\n[grid]\nwidth = 4\nheight = 2\n").unwrap();
    /// let q = Problem::from_toml(&p.to_toml()).unwrap();
    /// assert_eq!(q.to_toml(), p.to_toml());
    /// ```
    pub fn to_toml(&self) -> String {
        use std::fmt::Write;
        let border = |b: Border| match b {
            Border::Free => "free",
            Border::Zero => "zero",
            Border::Periodic => "periodic",
        };
        let f = |v: f64| format!("{v:?}");
        let mut s = String::new();
        if let Some(d) = &self.description {
            let _ = writeln!(s, "description = {}", toml_string(d));
        }
        if let Some(b) = &self.background {
            let _ = writeln!(s, "background = {}", toml_string(b));
        }
        let _ = writeln!(s, "seed = {}", self.seed);
        if self.fill_forced {
            s += "fill_forced = true\n";
        }
        let set = &self.set;
        let corners: Vec<String> = set
            .corners
            .iter()
            .map(|c| format!("[{}, {}]", f(c[0]), f(c[1])))
            .collect();
        let _ = write!(
            s,
            "\n[tileset]\nmx = [{}, {}]\nmy = [{}, {}]\ncorners = [{}]\nf_base = {}\nn = {}\n",
            set.mx.min,
            set.mx.max,
            set.my.min,
            set.my.max,
            corners.join(", "),
            f(set.f_base),
            set.n
        );
        let c = &self.conditions;
        let _ = write!(
            s,
            "\n[grid]\nwidth = {}\nheight = {}\nborder_x = \"{}\"\nborder_y = \"{}\"\n",
            self.width,
            self.height,
            border(c.border_x),
            border(c.border_y)
        );
        if c.blocked.iter().any(|&b| b) {
            s += "mask = \"\"\"\n";
            for y in (0..self.height).rev() {
                for x in 0..self.width {
                    s.push(if c.blocked[(y * self.width + x) as usize] {
                        '#'
                    } else {
                        '.'
                    });
                }
                s.push('\n');
            }
            s += "\"\"\"\n";
        }
        for &(e, m) in &c.fluxes {
            let (kind, x, y) = match e {
                Edge::Vertical { x, y } => ("v", x, y),
                Edge::Horizontal { x, y } => ("h", x, y),
            };
            let _ = write!(
                s,
                "\n[[flux]]\nedge = \"{kind}\"\nx = {x}\ny = {y}\nm = {m}\n"
            );
        }
        for &((x, y), v) in &c.corners {
            let _ = write!(s, "\n[[corner]]\nx = {x}\ny = {y}\nvelocity = {v}\n");
        }
        for &((x, y), k) in &self.tiles {
            let _ = write!(
                s,
                "\n[[tile]]\nx = {x}\ny = {y}\nfluxes = [{}, {}, {}, {}]\ncorners = [{}, {}, {}, {}]\n",
                k.left,
                k.bottom,
                k.right,
                k.top,
                k.corners[0],
                k.corners[1],
                k.corners[2],
                k.corners[3]
            );
        }
        let p = &self.preferences;
        if !p.is_uniform() || !p.regions.is_empty() {
            let _ = write!(
                s,
                "\n[prefer]\nstraight = {}\nreuse = {}\n",
                f(p.straight),
                f(p.reuse)
            );
            for r in &p.regions {
                let _ = write!(
                    s,
                    "\n[[prefer.direction]]\nx = [{}, {}]\ny = [{}, {}]\ndirection = [{}, {}]\nstrength = {}\n",
                    r.x.0,
                    r.x.1,
                    r.y.0,
                    r.y.1,
                    f(r.direction[0]),
                    f(r.direction[1]),
                    f(r.strength)
                );
            }
        }
        s
    }
}

/// A TOML basic string (quotes, backslashes and control characters escaped).
///
/// ```
/// assert_eq!(flowtile_bake::spec::toml_string("a\"b"), "\"a\\\"b\"");
/// ```
pub fn toml_string(text: &str) -> String {
    let mut s = String::from("\"");
    for ch in text.chars() {
        match ch {
            '"' => s += "\\\"",
            '\\' => s += "\\\\",
            c if (c as u32) < 0x20 || c as u32 == 0x7f => s += &format!("\\u{:04X}", c as u32),
            c => s.push(c),
        }
    }
    s.push('"');
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn example_specs_tile_completely() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../testdata/flowtiles");
        let mut seen = 0;
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                let p = Problem::from_toml(&std::fs::read_to_string(&path).unwrap())
                    .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                let mut t = Tiling::new(p.set, p.width, p.height, &p.conditions)
                    .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                if p.fill_forced {
                    t.fill_forced().unwrap();
                }
                t.random_fill_preferring(&mut Rng::new(p.seed), &p.preferences)
                    .unwrap();
                assert!(t.is_complete());
                seen += 1;
            }
        }
        assert!(seen >= 3);
    }

    /// The designed flows of the example specs: the river flows
    /// downstream (≤ 1 % of its area upstream), every city street carries
    /// flow, and both reuse tiles.
    #[test]
    fn designed_flows_do_what_the_specs_ask() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../testdata/flowtiles");
        let bake = |name: &str| {
            let p = Problem::from_toml(&std::fs::read_to_string(dir.join(name)).unwrap()).unwrap();
            let mut t = Tiling::new(p.set.clone(), p.width, p.height, &p.conditions).unwrap();
            t.random_fill_preferring(&mut Rng::new(p.seed), &p.preferences)
                .unwrap();
            let b = crate::bake::BakedTiling::from_tiling(&t).unwrap();
            let dirs = p.preferences.slot_directions(p.width, p.height);
            (b, dirs)
        };
        let (river, dirs) = bake("river.toml");
        let up = crate::stats::against_fraction(&river, &dirs).unwrap();
        assert!(up <= 0.01, "river upstream area {:.2} %", up * 100.0);
        assert!(crate::stats::reuse_ratio(&river) < 0.5);
        let (city, _) = bake("city.toml");
        let streets = crate::stats::corridors(&city);
        assert_eq!(streets.len(), 58);
        let empty: Vec<_> = streets.iter().filter(|c| c.flux == 0).collect();
        assert!(empty.is_empty(), "streets without flow: {empty:?}");
        assert!(crate::stats::reuse_ratio(&city) < 0.25);
    }

    #[test]
    fn bad_specs_name_the_problem() {
        let base = "[tileset]\nmx = 3\nmy = 3\n[grid]\nwidth = 4\nheight = 2\n";
        assert!(Problem::from_toml(base).is_ok());
        let cases = [
            (
                format!("{base}[[flux]]\nedge = \"q\"\nx = 0\ny = 0\nm = 1\n"),
                "edge",
            ),
            (
                format!("{base}[[flux]]\nedge = \"v\"\nx = 9\ny = 0\nm = 1\n"),
                "flux[0]",
            ),
            (
                format!("{base}[[corner]]\nx = 9\ny = 0\nvelocity = 0\n"),
                "corner[0]",
            ),
            (base.replace("width = 4", "width = 0"), "grid"),
            (base.replace("mx = 3", "mx = 0"), "mx"),
            (format!("{base}bogus = 1\n"), "bogus"),
            ("not toml [".to_string(), "spec"),
            (base.replace("[grid]", "[grid]\nmask = \"..\""), "mask"),
            (format!("{base}[prefer]\nreuse = -1\n"), "reuse"),
            (
                format!("{base}[[prefer.direction]]\nx = 9\ny = 0\ndirection = [1, 0]\n"),
                "prefer.direction[0]",
            ),
            (
                format!("{base}[[prefer.direction]]\nx = 0\ny = 0\ndirection = [0, 0]\n"),
                "non-zero",
            ),
        ];
        for (text, needle) in cases {
            let err = Problem::from_toml(&text).unwrap_err().to_string();
            assert!(err.contains(needle), "{needle}: {err}");
        }
    }
}
