//! Cross-checks `vdgview check`'s standing-place sampler against a Counter-Strike bot
//! navigation mesh (`.nav`, versions 1–5, the CS 1.6 / Condition Zero format): an
//! independent set of floor points, placed by the game's own tools where players walk.
//!
//! ```sh
//! cargo run --release -p lab --bin walkable_nav -- MAP.bsp MAP.nav [MAP.vdg] [N]
//! ```
//!
//! Prints, for N random points of each side:
//! - nav → sampler: the share of nav points (ground + 36) where the sampler finds a
//!   standing origin within 18 units (a stair step) in the same column;
//! - sampler → nav: the share of sampled standing places lying over a nav area within
//!   18 units of its interpolated height (the rest are floors no bot walks: roofs,
//!   ledges, the tops of clip brushes);
//! - with a graph: walkable coverage measured on the nav points beside the sampler's.
//!
//! The reader here takes only the areas' corners (self-contained on purpose; it can
//! later use a shared .nav reader).

use anyhow::{Context, Result, bail};
use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use bsp::player::{ORIGIN_ABOVE_GROUND, column_floors};
use toolbox::SplitMix64;
use vdgcheck::standing_places;

/// A nav area: a rectangle in x/y with the ground heights at its four corners.
#[derive(Debug, Clone, Copy)]
struct Area {
    lo: [f32; 3],
    hi: [f32; 3],
    /// Heights of the north-east (hi.x, lo.y) and south-west (lo.x, hi.y) corners.
    ne_z: f32,
    sw_z: f32,
}

impl Area {
    fn contains_xy(&self, x: f64, y: f64) -> bool {
        (self.lo[0] as f64..=self.hi[0] as f64).contains(&x)
            && (self.lo[1] as f64..=self.hi[1] as f64).contains(&y)
    }

    /// The ground height at (x, y), bilinear between the four corners.
    fn ground(&self, x: f64, y: f64) -> f64 {
        let u =
            ((x - self.lo[0] as f64) / (self.hi[0] - self.lo[0]).max(1e-6) as f64).clamp(0.0, 1.0);
        let v =
            ((y - self.lo[1] as f64) / (self.hi[1] - self.lo[1]).max(1e-6) as f64).clamp(0.0, 1.0);
        let (nw, ne, se, sw) = (
            self.lo[2] as f64,
            self.ne_z as f64,
            self.hi[2] as f64,
            self.sw_z as f64,
        );
        (1.0 - v) * ((1.0 - u) * nw + u * ne) + v * ((1.0 - u) * sw + u * se)
    }

    fn area(&self) -> f64 {
        ((self.hi[0] - self.lo[0]) as f64 * (self.hi[1] - self.lo[1]) as f64).max(0.0)
    }
}

struct Reader<'a> {
    b: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8]> {
        let s = self
            .b
            .get(self.at..self.at + n)
            .with_context(|| format!("nav file truncated at byte {}", self.at))?;
        self.at += n;
        Ok(s)
    }
    fn u8(&mut self) -> Result<u8> {
        Ok(self.take(1)?[0])
    }
    fn u16(&mut self) -> Result<u16> {
        Ok(u16::from_le_bytes(self.take(2)?.try_into()?))
    }
    fn u32(&mut self) -> Result<u32> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into()?))
    }
    fn f32(&mut self) -> Result<f32> {
        Ok(f32::from_le_bytes(self.take(4)?.try_into()?))
    }
    fn vec3(&mut self) -> Result<[f32; 3]> {
        Ok([self.f32()?, self.f32()?, self.f32()?])
    }
}

/// The areas of a CS 1.6 / CZ nav file (versions 1–5).
fn read_nav(bytes: &[u8]) -> Result<Vec<Area>> {
    let mut r = Reader { b: bytes, at: 0 };
    if r.u32()? != 0xFEED_FACE {
        bail!("not a nav file (magic is not 0xFEEDFACE)");
    }
    let version = r.u32()?;
    if !(1..=5).contains(&version) {
        bail!("nav version {version} is not the CS 1.6 format (1-5)");
    }
    if version >= 4 {
        r.u32()?; // size of the BSP it was made for
    }
    if version >= 5 {
        for _ in 0..r.u16()? {
            let len = r.u16()? as usize;
            r.take(len)?;
        }
    }
    let count = r.u32()? as usize;
    let mut areas = Vec::with_capacity(count.min(1 << 20));
    for _ in 0..count {
        r.u32()?; // id
        r.u8()?; // attribute flags
        let (lo, hi) = (r.vec3()?, r.vec3()?);
        let (ne_z, sw_z) = (r.f32()?, r.f32()?);
        for _ in 0..4 {
            let n = r.u32()? as usize;
            r.take(4 * n)?;
        }
        let spots = r.u8()? as usize;
        r.take(spots * if version == 1 { 12 } else { 17 })?;
        let approaches = r.u8()? as usize;
        r.take(approaches * 14)?;
        let encounters = r.u32()? as usize;
        for _ in 0..encounters {
            if version < 3 {
                r.take(8 + 24)?;
                let n = r.u8()? as usize;
                r.take(16 * n)?;
            } else {
                r.take(10)?;
                let n = r.u8()? as usize;
                r.take(5 * n)?;
            }
        }
        if version >= 5 {
            r.u16()?; // place
        }
        areas.push(Area { lo, hi, ne_z, sw_z });
    }
    Ok(areas)
}

/// How far a standing origin may be from the nav's ground + 36: a stair step.
const TOLERANCE: f64 = 18.0;

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 {
        bail!("usage: walkable_nav MAP.bsp MAP.nav [MAP.vdg] [N]");
    }
    let bsp = Bsp::open(&args[0]).with_context(|| format!("reading {}", args[0]))?;
    let nav = std::fs::read(&args[1]).with_context(|| format!("reading {}", args[1]))?;
    let areas = read_nav(&nav).with_context(|| format!("reading {}", args[1]))?;
    let vdg = match args.get(2).filter(|a| a.ends_with(".vdg")) {
        Some(p) => Some(vdgformat::VdgFile::open(p).with_context(|| format!("reading {p}"))?),
        None => None,
    };
    let n: usize = match args.iter().skip(2).find(|a| !a.ends_with(".vdg")) {
        Some(a) => a
            .parse()
            .with_context(|| format!("N must be a count, not {a}"))?,
        None => 20_000,
    };
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let Some(hull) = oracle.clip_hull(1) else {
        bail!("{} has no clip hulls", args[0]);
    };
    let total: f64 = areas.iter().map(Area::area).sum();
    println!(
        "{}: {} nav areas, {:.0} square units",
        args[1],
        areas.len(),
        total
    );

    // Nav points, uniform over the areas' projected area.
    let mut cumulative = Vec::with_capacity(areas.len());
    let mut acc = 0.0;
    for a in &areas {
        acc += a.area();
        cumulative.push(acc);
    }
    let mut rng = SplitMix64::new(0x4a7);
    let mut nav_points = Vec::with_capacity(n);
    for _ in 0..n {
        let k = cumulative
            .partition_point(|&w| w <= rng.next_f64() * total)
            .min(areas.len() - 1);
        let a = &areas[k];
        let x = rng.range(a.lo[0] as f64, a.hi[0] as f64);
        let y = rng.range(a.lo[1] as f64, a.hi[1] as f64);
        nav_points.push([x, y, a.ground(x, y) + ORIGIN_ABOVE_GROUND]);
    }
    let mut found = 0;
    let mut offsets = Vec::new();
    for p in &nav_points {
        let floors = column_floors(hull, &oracle, p[0], p[1], p[2] + 72.0, p[2] - 72.0);
        if let Some(d) = floors
            .iter()
            .map(|z| z - p[2])
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
            && d.abs() <= TOLERANCE
        {
            found += 1;
            offsets.push(d);
        }
    }
    // Misses: how far away horizontally the nearest standing origin is (at the nav's height).
    let mut near = [0usize; 4];
    for p in &nav_points {
        let has = |x: f64, y: f64| {
            column_floors(hull, &oracle, x, y, p[2] + 72.0, p[2] - 72.0)
                .iter()
                .any(|z| (z - p[2]).abs() <= TOLERANCE)
        };
        if has(p[0], p[1]) {
            continue;
        }
        let ring = |r: f64| {
            (0..16).any(|k| {
                let a = k as f64 * std::f64::consts::TAU / 16.0;
                has(p[0] + r * a.cos(), p[1] + r * a.sin())
            })
        };
        let k = [8.0, 16.0, 32.0].iter().position(|&r| ring(r)).unwrap_or(3);
        near[k] += 1;
    }
    println!(
        "nav points without a standing origin: {} with one within 8 units sideways, {} within 16, {} within 32, {} farther",
        near[0], near[1], near[2], near[3]
    );
    offsets.sort_by(f64::total_cmp);
    let quantile = |q: f64| {
        offsets
            .get(((offsets.len() as f64 - 1.0) * q) as usize)
            .copied()
    };
    println!(
        "nav -> sampler: {found} of {n} nav points ({:.4}) have a standing origin within {TOLERANCE} units; \
         origin - (nav ground + 36): median {:?}, 5 % {:?}, 95 % {:?}",
        found as f64 / n as f64,
        quantile(0.5),
        quantile(0.05),
        quantile(0.95)
    );

    let places = standing_places(&bsp, &oracle, n, 1);
    let over = places
        .iter()
        .filter(|s| {
            let [x, y, z] = s.origin;
            areas.iter().any(|a| {
                a.contains_xy(x, y) && (a.ground(x, y) + ORIGIN_ABOVE_GROUND - z).abs() <= TOLERANCE
            })
        })
        .count();
    println!(
        "sampler -> nav: {over} of {} standing places ({:.4}) lie over a nav area within {TOLERANCE} units",
        places.len(),
        over as f64 / places.len().max(1) as f64
    );

    if let Some(file) = &vdg {
        let g = file.graph();
        let inside = |p: [f64; 3]| g.contains(p.map(|c| c as f32));
        let nav_in = nav_points.iter().filter(|&&p| inside(p)).count();
        let sampled_in = places.iter().filter(|s| inside(s.origin)).count();
        let nav_places_in = places
            .iter()
            .filter(|s| {
                let [x, y, z] = s.origin;
                areas.iter().any(|a| {
                    a.contains_xy(x, y)
                        && (a.ground(x, y) + ORIGIN_ABOVE_GROUND - z).abs() <= TOLERANCE
                })
            })
            .map(|s| inside(s.origin) as usize)
            .sum::<usize>();
        println!(
            "walkable coverage of {}: nav points {:.4}, sampled places {:.4}, sampled places over nav areas {:.4}",
            args[2],
            nav_in as f64 / n as f64,
            sampled_in as f64 / places.len().max(1) as f64,
            nav_places_in as f64 / over.max(1) as f64
        );
    }
    Ok(())
}
