//! The quality of a graph measured against its map's own BSP (docs/design/quality.md):
//! the figures of `vdgview check MAP.bsp FILE.vdg` and of `bsp2vdg --baseline`. It lives
//! in the compiler's library, beside the BSP reader and oracle it measures with, so that
//! both the viewer (which depends on this crate) and the compiler's CI mode call the same
//! code without a dependency cycle; `vdgview::check` re-exports it.
//!
//! - **leak**: random points of Volume(VDG) (a face by volume, a point of its triangle,
//!   a point of the ball of interpolated clearance there) that the BSP calls blocked.
//!   Must be 0: a camera placed inside the volume must never be inside a wall.
//! - **coverage**: random free points whose true clearance (exact distance to the
//!   nearest obstacle face) is at least 32 units, and the share of them inside the volume.
//! - **walkable coverage**: random places where a standing player is — the player hull
//!   (clip hull 1) free at the origin and the floor right below it (the origin dropped to
//!   the floor, 36 units above the ground) — and the share of those origins inside the
//!   volume; the same for the head (64 units above the ground, skipped where it is in
//!   solid). The camera's target is there; outside the volume it can never be visible.
//! - **crouch coverage** (GoldSrc, Quake 2 and 3): the places where a player only fits
//!   crouching (vents, crawl spaces) in random columns, and the share of their crouched
//!   eyes (the point the camera follows; GoldSrc 18 + 12 units above the ground, see
//!   [`bsp::player::Crouching`] for the others) inside the volume.
//! - **visible_fp / visible_fn**: `Visible(s, e)` against the BSP's segment test on
//!   random segments between free points; a false positive (seeing through a wall) must
//!   never happen.
//! - **visible_fn_camera**: the same test on the sight lines the camera asks about: from
//!   a point at a camera's distance (32–176 units, level to 60° above) to a standing
//!   player's origin, for every tenth standing place; misses among the BSP-free lines
//!   with both ends inside the volume, and false positives among all of them. Random
//!   segments run through the middle of rooms as often as along their walls; these
//!   start where players stand, near floors and walls.
//!
//! Every random choice comes from a seeded generator per chunk of work, so the figures
//! are the same for any thread count.

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use bsp::walls::Walls;
use rayon::prelude::*;
use toolbox::SplitMix64;
use vdgformat::Vdg;

/// What to measure and how much.
#[derive(Debug, Clone)]
pub struct CheckOptions {
    /// Random points for leak, coverage and walkable coverage each; a tenth as many segments.
    pub samples: usize,
    /// The clearance from which free points must be covered.
    pub coverage_clearance: f64,
    pub seed: u64,
    pub liquids_are_solid: bool,
    pub clip_is_solid: bool,
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions {
            samples: 1_000_000,
            coverage_clearance: 32.0,
            seed: 1,
            liquids_are_solid: false,
            clip_is_solid: false,
        }
    }
}

/// The measured figures.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CheckReport {
    pub vertices: usize,
    pub faces: usize,
    pub bytes: usize,
    pub leak_points: usize,
    pub leaked: usize,
    pub coverage_points: usize,
    pub covered: usize,
    pub segments: usize,
    pub free_segments: usize,
    pub visible: usize,
    pub false_positives: usize,
    pub false_negatives: usize,
    /// Free segments whose ends are both inside the volume, and how many of them were
    /// not seen (the misses `Visible` can be blamed for).
    pub free_segments_inside: usize,
    pub false_negatives_inside: usize,
    /// Of those misses, the ones whose whole segment stays inside the volume (sampled
    /// every [`ALONG_STEP`] units): the query's own misses. The others leave the volume
    /// between their ends — a gap of the graph, which no trace through it can cross.
    pub false_negatives_query: usize,
    /// Standing places drawn (player origins) and how many lie inside the volume.
    pub walkable_points: usize,
    pub walkable_covered: usize,
    /// Their heads that are in free space, and how many of those lie inside the volume.
    pub walkable_head_points: usize,
    pub walkable_head_covered: usize,
    /// GoldSrc, Quake 2 and 3 maps: the places where a player only fits crouching (vents, crawl
    /// spaces; [`bsp::player::Crouching::column_places`]) drawn from as many random
    /// columns as there are points, whose crouched eye (the camera's target) is in
    /// free space, and how many of those eyes lie inside the volume.
    pub crouch_points: usize,
    pub crouch_covered: usize,
    /// Camera sight lines ([`camera_lines`]): drawn, and seen by `Visible` though the
    /// BSP blocks them (must be 0).
    pub camera_lines: usize,
    pub camera_false_positives: usize,
    /// Those the BSP lets through with both ends inside the volume, and how many of
    /// them `Visible` missed.
    pub camera_lines_inside: usize,
    pub camera_false_negatives: usize,
    pub seconds: f64,
    /// Seconds of the four measurements (leak, coverage, visibility, walkable with
    /// crouch and the camera sight lines, which start at the walkable places).
    pub seconds_parts: [f64; 4],
}

impl CheckReport {
    pub fn leak(&self) -> f64 {
        ratio(self.leaked, self.leak_points)
    }
    pub fn coverage(&self) -> f64 {
        ratio(self.covered, self.coverage_points)
    }
    /// False positives among the blocked segments.
    pub fn visible_fp(&self) -> f64 {
        ratio(self.false_positives, self.segments - self.free_segments)
    }
    /// Misses among the free segments.
    pub fn visible_fn(&self) -> f64 {
        ratio(self.false_negatives, self.free_segments)
    }
    pub fn visible_fn_inside(&self) -> f64 {
        ratio(self.false_negatives_inside, self.free_segments_inside)
    }
    /// Misses among the free segments with both ends inside the volume whose whole
    /// segment stays inside it (see [`CheckReport::false_negatives_query`]).
    pub fn visible_fn_query(&self) -> f64 {
        ratio(self.false_negatives_query, self.free_segments_inside)
    }
    /// Share of the standing player origins inside the volume; `None` on a map with
    /// no place where a player stands (no clip hull 1, or no floor): there is nothing
    /// to cover, and 0.0 would read as "nothing covered" (JSON `null`, "n/a").
    pub fn walkable_coverage(&self) -> Option<f64> {
        (self.walkable_points > 0).then(|| ratio(self.walkable_covered, self.walkable_points))
    }
    /// Share of the standing players' heads (where free) inside the volume; `None`
    /// when no head was drawn (see [`CheckReport::walkable_coverage`]).
    pub fn walkable_coverage_head(&self) -> Option<f64> {
        (self.walkable_head_points > 0)
            .then(|| ratio(self.walkable_head_covered, self.walkable_head_points))
    }
    /// Share of the crouch-only places' eyes inside the volume; `None` where there is
    /// none (every non-GoldSrc map, and GoldSrc maps without low ceilings).
    pub fn crouch_coverage(&self) -> Option<f64> {
        (self.crouch_points > 0).then(|| ratio(self.crouch_covered, self.crouch_points))
    }
    /// Misses among the camera sight lines with both ends inside the volume; `None` on
    /// a map where no player stands (see [`CheckReport::walkable_coverage`]).
    pub fn visible_fn_camera(&self) -> Option<f64> {
        (self.camera_lines_inside > 0)
            .then(|| ratio(self.camera_false_negatives, self.camera_lines_inside))
    }
    /// Whether the graph passes: nothing leaks, nothing is seen through walls (on the
    /// random segments or the camera sight lines).
    pub fn passed(&self) -> bool {
        self.leaked == 0 && self.false_positives == 0 && self.camera_false_positives == 0
    }

    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "leak": self.leak(),
            "coverage": self.coverage(),
            "visible_fp": self.visible_fp(),
            "visible_fn": self.visible_fn(),
            "visible_fn_inside": self.visible_fn_inside(),
            "visible_fn_query": self.visible_fn_query(),
            "walkable_coverage": self.walkable_coverage(),
            "walkable_coverage_head": self.walkable_coverage_head(),
            "walkable_points": self.walkable_points,
            "walkable_covered": self.walkable_covered,
            "walkable_head_points": self.walkable_head_points,
            "walkable_head_covered": self.walkable_head_covered,
            "crouch_coverage": self.crouch_coverage(),
            "crouch_points": self.crouch_points,
            "crouch_covered": self.crouch_covered,
            "visible_fn_camera": self.visible_fn_camera(),
            "camera_lines": self.camera_lines,
            "camera_false_positives": self.camera_false_positives,
            "camera_lines_inside": self.camera_lines_inside,
            "camera_false_negatives": self.camera_false_negatives,
            "vertices": self.vertices,
            "faces": self.faces,
            "bytes": self.bytes,
            "leak_points": self.leak_points,
            "leaked": self.leaked,
            "coverage_points": self.coverage_points,
            "covered": self.covered,
            "segments": self.segments,
            "free_segments": self.free_segments,
            "visible": self.visible,
            "false_positives": self.false_positives,
            "false_negatives": self.false_negatives,
            "free_segments_inside": self.free_segments_inside,
            "false_negatives_inside": self.false_negatives_inside,
            "false_negatives_query": self.false_negatives_query,
            "seconds": self.seconds,
            "seconds_leak": self.seconds_parts[0],
            "seconds_coverage": self.seconds_parts[1],
            "seconds_visible": self.seconds_parts[2],
            "seconds_walkable": self.seconds_parts[3],
            "passed": self.passed(),
        })
    }
}

/// Counters of two chunks of work added up, for the parallel measurements' reductions.
fn add_counts<const N: usize>(a: [usize; N], b: [usize; N]) -> [usize; N] {
    std::array::from_fn(|i| a[i] + b[i])
}

fn ratio(a: usize, b: usize) -> f64 {
    if b == 0 { 0.0 } else { a as f64 / b as f64 }
}

const CHUNK: usize = 4096;

/// Measures `vdg` (a file of `bytes` bytes) against `bsp`.
pub fn check(bsp: &Bsp, vdg: &Vdg<'_>, bytes: usize, options: &CheckOptions) -> CheckReport {
    let t = std::time::Instant::now();
    let oracle = Oracle::new(
        bsp,
        &OracleOptions {
            liquids_are_solid: options.liquids_are_solid,
            clip_is_solid: options.clip_is_solid,
            ..Default::default()
        },
    );
    let walls = Walls::of_map(
        bsp,
        &OracleOptions {
            liquids_are_solid: options.liquids_are_solid,
            clip_is_solid: options.clip_is_solid,
            ..Default::default()
        },
    );
    let mut r = CheckReport {
        vertices: vdg.vertices().len(),
        faces: vdg.faces().len(),
        bytes,
        ..Default::default()
    };
    let ((leak_points, leaked), s_leak) = timed(|| measure_leak(vdg, &oracle, options));
    (r.leak_points, r.leaked) = (leak_points, leaked);
    let ((points, covered), s_coverage) =
        timed(|| measure_coverage(bsp, vdg, &oracle, &walls, options));
    (r.coverage_points, r.covered) = (points, covered);
    let ((), s_visible) = timed(|| measure_visibility(bsp, vdg, &oracle, options, &mut r));
    let ((), s_walkable) = timed(|| {
        measure_walkable(bsp, vdg, &oracle, options, &mut r);
        measure_crouch(bsp, vdg, &oracle, options, &mut r);
    });
    r.seconds_parts = [s_leak, s_coverage, s_visible, s_walkable];
    r.seconds = t.elapsed().as_secs_f64();
    r
}

/// Runs `f` and returns its result with the seconds it took.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let t = std::time::Instant::now();
    let out = f();
    (out, t.elapsed().as_secs_f64())
}

/// Rounds to the f32 grid the graph's queries see, so both sides judge the same point.
fn as_f32(p: [f64; 3]) -> [f32; 3] {
    p.map(|c| c as f32)
}

fn widen(p: [f32; 3]) -> [f64; 3] {
    p.map(f64::from)
}

/// Random points of the volume, in chunks with their own seeds; returns (points, leaked).
fn measure_leak(vdg: &Vdg<'_>, oracle: &Oracle, options: &CheckOptions) -> (usize, usize) {
    let faces = vdg.faces();
    let verts = vdg.vertices();
    if faces.is_empty() || options.samples == 0 {
        return (0, 0);
    }
    // Weight faces by a rough volume: area times mean radius², plus a mean-radius ball.
    // The radii are the faces' own corner radii (the vertex clearances in files
    // without them): the volume the queries see.
    let mut cumulative = Vec::with_capacity(faces.len());
    let mut total = 0.0f64;
    for (k, f) in faces.iter().enumerate() {
        let [a, b, c] = f.map(|i| verts[i as usize]);
        let area = tri_area(widen(a.pos), widen(b.pos), widen(c.pos));
        let r = vdg.face_radii(k as u32).map(f64::from).iter().sum::<f64>() / 3.0;
        total += area * r * r + r * r * r;
        cumulative.push(total);
    }
    let chunks = options.samples.div_ceil(CHUNK);
    let leaked: usize = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut rng = SplitMix64::new(options.seed ^ (0x1ea << 32) ^ c as u64);
            let n = CHUNK.min(options.samples - c * CHUNK);
            (0..n)
                .filter(|_| {
                    let x = rng.next_f64() * total;
                    let k = cumulative.partition_point(|&w| w <= x).min(faces.len() - 1);
                    let [a, b, c] = faces.get(k as u32).map(|i| verts[i as usize]);
                    let radii = vdg.face_radii(k as u32).map(f64::from);
                    let (mut u, mut v) = (rng.next_f64(), rng.next_f64());
                    if u + v > 1.0 {
                        (u, v) = (1.0 - u, 1.0 - v);
                    }
                    let w = 1.0 - u - v;
                    let q = [0, 1, 2]
                        .map(|i| w * a.pos[i] as f64 + u * b.pos[i] as f64 + v * c.pos[i] as f64);
                    let r = w * radii[0] + u * radii[1] + v * radii[2];
                    let d = random_in_ball(&mut rng);
                    let p = [0, 1, 2].map(|i| q[i] + r * d[i]);
                    !oracle.is_free(widen(as_f32(p)))
                })
                .count()
        })
        .sum();
    (options.samples, leaked)
}

/// Random free points of the map with true clearance ≥ the threshold; returns
/// (such points, those inside the volume).
fn measure_coverage(
    bsp: &Bsp,
    vdg: &Vdg<'_>,
    oracle: &Oracle,
    walls: &Walls,
    options: &CheckOptions,
) -> (usize, usize) {
    let (lo, hi) = free_bounds(bsp);
    let chunks = options.samples.div_ceil(CHUNK);
    let results: Vec<(usize, usize)> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut rng = SplitMix64::new(options.seed ^ (0xc0 << 40) ^ c as u64);
            let n = CHUNK.min(options.samples - c * CHUNK);
            let (mut points, mut covered) = (0, 0);
            let mut tries = 0;
            // Draw until n points have the clearance (bounded, for maps with no such room).
            while points < n && tries < 200 * n {
                tries += 1;
                let p = widen(as_f32([0, 1, 2].map(|i| rng.range(lo[i], hi[i]))));
                if !oracle.is_free(p)
                    || walls
                        .distance_within(p, options.coverage_clearance)
                        .is_some()
                {
                    continue;
                }
                points += 1;
                covered += vdg.contains(as_f32(p)) as usize;
            }
            (points, covered)
        })
        .collect();
    results.iter().fold((0, 0), |s, r| (s.0 + r.0, s.1 + r.1))
}

fn measure_visibility(
    bsp: &Bsp,
    vdg: &Vdg<'_>,
    oracle: &Oracle,
    options: &CheckOptions,
    r: &mut CheckReport,
) {
    let segments = SightSegments::new(bsp, oracle, (options.samples / 10).max(1), options.seed);
    let parts: Vec<[usize; 8]> = (0..segments.chunks())
        .into_par_iter()
        .map(|c| {
            let mut s = [0usize; 8];
            segments.for_each_in_chunk(c, |a, b| {
                let truth = oracle.segment_free(a, b);
                let seen = vdg.visible(as_f32(a), as_f32(b));
                s[0] += 1;
                s[1] += truth as usize;
                s[2] += seen as usize;
                s[3] += (seen && !truth) as usize;
                s[4] += (!seen && truth) as usize;
                if truth && vdg.contains(as_f32(a)) && vdg.contains(as_f32(b)) {
                    s[5] += 1;
                    s[6] += !seen as usize;
                    s[7] += (!seen && stays_inside(vdg, a, b)) as usize;
                }
            });
            s
        })
        .collect();
    let s = parts.into_iter().fold([0; 8], add_counts);
    r.segments = s[0];
    r.free_segments = s[1];
    r.visible = s[2];
    r.false_positives = s[3];
    r.false_negatives = s[4];
    r.free_segments_inside = s[5];
    r.false_negatives_inside = s[6];
    r.false_negatives_query = s[7];
}

/// Random free sight lines, drawn as [`check`] draws them for `Visible`
/// (with `n` = samples / 10 and the same seed), for tools that look closer at
/// the same lines. They come in chunks of 4096 with seeds of their own, so
/// chunks can run in parallel and still draw the same lines. A line's first
/// end is uniform over the map's bounds; its second end too for odd lines,
/// and within 512 units of the first for even ones (short lines, where sight
/// matters). Both ends are free in the oracle and exact in f32, the graph's
/// precision.
pub struct SightSegments<'a> {
    oracle: &'a Oracle,
    lo: [f64; 3],
    hi: [f64; 3],
    n: usize,
    seed: u64,
}

impl<'a> SightSegments<'a> {
    /// `n` lines of `bsp` (judged free by `oracle`) from seed `seed`.
    pub fn new(bsp: &Bsp, oracle: &'a Oracle, n: usize, seed: u64) -> Self {
        let (lo, hi) = free_bounds(bsp);
        SightSegments {
            oracle,
            lo,
            hi,
            n,
            seed: seed ^ (0x5e9 << 36),
        }
    }

    /// How many chunks the lines come in.
    pub fn chunks(&self) -> usize {
        self.n.div_ceil(CHUNK)
    }

    /// Calls `visit(a, b)` for each line of chunk `c` in turn.
    pub fn for_each_in_chunk(&self, c: usize, mut visit: impl FnMut([f64; 3], [f64; 3])) {
        let mut rng = SplitMix64::new(self.seed ^ c as u64);
        let free_point = |rng: &mut SplitMix64, near: Option<[f64; 3]>| loop {
            let p = match near {
                Some(a) => [0, 1, 2].map(|i| a[i] + rng.range(-512.0, 512.0)),
                None => [0, 1, 2].map(|i| rng.range(self.lo[i], self.hi[i])),
            };
            let p = widen(as_f32(p));
            if self.oracle.is_free(p) {
                return p;
            }
        };
        for k in 0..CHUNK.min(self.n.saturating_sub(c * CHUNK)) {
            let a = free_point(&mut rng, None);
            let b = free_point(&mut rng, (k % 2 == 0).then_some(a));
            visit(a, b);
        }
    }
}

use bsp::player::{HEAD_ABOVE_GROUND, ORIGIN_ABOVE_GROUND, column_floors};

/// A place where a standing player is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Standing {
    /// The player's origin: clip hull 1 free there, its floor right below.
    pub origin: [f64; 3],
    /// The head, 28 units above the origin, or `None` where that point is in solid.
    pub head: Option<[f64; 3]>,
}

/// `n` random standing places, drawn column by column uniformly over the world's
/// horizontal extent (every floor of a column counts, so places are uniform over the
/// walkable floor area seen from above), in chunks with their own seeds. Empty when
/// the map has no clip hulls.
pub fn standing_places(bsp: &Bsp, oracle: &Oracle, n: usize, seed: u64) -> Vec<Standing> {
    let Some(hull) = oracle.clip_hull(1) else {
        return Vec::new();
    };
    let (lo, hi) = free_bounds(bsp);
    let chunks = n.div_ceil(CHUNK);
    let parts: Vec<Vec<Standing>> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut rng = SplitMix64::new(seed ^ (0x3a1 << 44) ^ c as u64);
            let want = CHUNK.min(n - c * CHUNK);
            let mut out = Vec::with_capacity(want);
            let mut columns = 0;
            // Bounded, for maps where no player stands anywhere.
            while out.len() < want && columns < 200 * want {
                columns += 1;
                let (x, y) = (rng.range(lo[0], hi[0]), rng.range(lo[1], hi[1]));
                for z in column_floors(hull, oracle, x, y, hi[2] + 1.0, lo[2] - 1.0) {
                    let origin = widen(as_f32([x, y, z]));
                    let h = widen(as_f32([x, y, z - ORIGIN_ABOVE_GROUND + HEAD_ABOVE_GROUND]));
                    let head = oracle.is_free(h).then_some(h);
                    out.push(Standing { origin, head });
                }
            }
            out.truncate(want);
            out
        })
        .collect();
    parts.concat()
}

/// Walkable coverage: the share of standing places (origin, head) inside the volume.
fn measure_walkable(
    bsp: &Bsp,
    vdg: &Vdg<'_>,
    oracle: &Oracle,
    options: &CheckOptions,
    r: &mut CheckReport,
) {
    let places = standing_places(bsp, oracle, options.samples, options.seed);
    let counts = places
        .par_iter()
        .map(|s| {
            let head = s.head.map(|h| vdg.contains(as_f32(h)));
            [
                1,
                vdg.contains(as_f32(s.origin)) as usize,
                head.is_some() as usize,
                head.unwrap_or(false) as usize,
            ]
        })
        .reduce(|| [0; 4], add_counts);
    [
        r.walkable_points,
        r.walkable_covered,
        r.walkable_head_points,
        r.walkable_head_covered,
    ] = counts;
    measure_camera(&places, vdg, oracle, options.seed, r);
}

/// Camera sight lines ([`camera_lines`]) to every tenth of the standing places: the
/// false positives among all, the misses among the free ones with both ends inside.
fn measure_camera(
    places: &[Standing],
    vdg: &Vdg<'_>,
    oracle: &Oracle,
    seed: u64,
    r: &mut CheckReport,
) {
    let targets: Vec<[f64; 3]> = places.iter().step_by(10).map(|s| s.origin).collect();
    let lines = camera_lines(&targets, oracle, seed);
    let counts = lines
        .par_iter()
        .map(|&(camera, target, free)| {
            let seen = vdg.visible(as_f32(camera), as_f32(target));
            let inside = free && vdg.contains(as_f32(camera)) && vdg.contains(as_f32(target));
            [
                1,
                (seen && !free) as usize,
                inside as usize,
                (inside && !seen) as usize,
            ]
        })
        .reduce(|| [0; 4], add_counts);
    [
        r.camera_lines,
        r.camera_false_positives,
        r.camera_lines_inside,
        r.camera_false_negatives,
    ] = counts;
}

/// How far from its target a camera's sight line starts (units): from a little closer
/// than the camera's distance tolerance allows to the far end of it (the camera's
/// ideal distance is 80 ± 48).
pub const CAMERA_DISTANCE: (f64, f64) = (32.0, 176.0);
/// How far above the level the line comes down to the target (degrees): a chase camera
/// looks along the floor or down at the player, rarely up.
pub const CAMERA_ELEVATION_DEG: (f64, f64) = (0.0, 60.0);
/// Draws per target before giving up on a free camera point (targets in tight places
/// have few).
const CAMERA_TRIES: usize = 8;

/// Camera sight lines to `targets`: per target a random free point at a camera's
/// distance and elevation ([`CAMERA_DISTANCE`], [`CAMERA_ELEVATION_DEG`]), the first of
/// [`CAMERA_TRIES`] draws that is free (targets without one give no line), with whether
/// the BSP lets the line `camera → target` through. Seeded per chunk of targets, so the
/// lines are the same for any thread count.
pub fn camera_lines(
    targets: &[[f64; 3]],
    oracle: &Oracle,
    seed: u64,
) -> Vec<([f64; 3], [f64; 3], bool)> {
    let parts: Vec<Vec<_>> = targets
        .par_chunks(CHUNK)
        .enumerate()
        .map(|(c, chunk)| {
            let mut rng = SplitMix64::new(seed ^ (0xca3 << 44) ^ c as u64);
            let mut out = Vec::with_capacity(chunk.len());
            for &target in chunk {
                for _ in 0..CAMERA_TRIES {
                    let d = rng.range(CAMERA_DISTANCE.0, CAMERA_DISTANCE.1);
                    let yaw = rng.range(0.0, std::f64::consts::TAU);
                    let pitch = rng
                        .range(CAMERA_ELEVATION_DEG.0, CAMERA_ELEVATION_DEG.1)
                        .to_radians();
                    let dir = [
                        pitch.cos() * yaw.cos(),
                        pitch.cos() * yaw.sin(),
                        pitch.sin(),
                    ];
                    let camera = widen(as_f32([0, 1, 2].map(|i| target[i] + d * dir[i])));
                    if oracle.is_free(camera) {
                        out.push((camera, target, oracle.segment_free(camera, target)));
                        break;
                    }
                }
            }
            out
        })
        .collect();
    parts.concat()
}

/// The eyes of the crouch-only places ([`bsp::player::Crouching::column_places`]) in
/// `columns` random columns, drawn uniformly over the world's horizontal extent in
/// chunks with their own seeds, where the eye is in free space. Empty unless the map's
/// players crouch ([`bsp::player::Crouching::of`]).
pub fn crouch_eyes(bsp: &Bsp, oracle: &Oracle, columns: usize, seed: u64) -> Vec<[f64; 3]> {
    let Some(crouching) = bsp::player::Crouching::of(oracle, bsp.game) else {
        return Vec::new();
    };
    let (lo, hi) = free_bounds(bsp);
    let parts: Vec<Vec<[f64; 3]>> = (0..columns.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let mut rng = SplitMix64::new(seed ^ (0xc40 << 44) ^ c as u64);
            let mut out = Vec::new();
            for _ in 0..CHUNK.min(columns - c * CHUNK) {
                let (x, y) = (rng.range(lo[0], hi[0]), rng.range(lo[1], hi[1]));
                for z in crouching.column_places(x, y, hi[2] + 1.0, lo[2] - 1.0) {
                    let eye = widen(as_f32([x, y, z + crouching.eye_above_origin()]));
                    if oracle.is_free(eye) {
                        out.push(eye);
                    }
                }
            }
            out
        })
        .collect();
    parts.concat()
}

/// Crouch coverage: the share of the crouch-only places' eyes inside the volume.
fn measure_crouch(
    bsp: &Bsp,
    vdg: &Vdg<'_>,
    oracle: &Oracle,
    options: &CheckOptions,
    r: &mut CheckReport,
) {
    let eyes = crouch_eyes(bsp, oracle, options.samples, options.seed);
    r.crouch_points = eyes.len();
    r.crouch_covered = eyes
        .par_iter()
        .filter(|&&e| vdg.contains(as_f32(e)))
        .count();
}

/// Spacing (units) of the points that test whether a missed segment stays inside the
/// volume. Fine, because a coarse test blames the query for the graph's gaps: at 2 units
/// a segment that left the volume between two points (a thin gap) counted as the
/// query's miss (on a small reduced map a clear share of the segments with both ends
/// inside, every one of which leaves the volume when tested every 0.05 units). Only
/// the misses are tested, so the cost is small.
pub const ALONG_STEP: f64 = 0.25;

/// Whether the points of `a`–`b` every [`ALONG_STEP`] units all lie inside the volume.
fn stays_inside(vdg: &Vdg<'_>, a: [f64; 3], b: [f64; 3]) -> bool {
    let len = (0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>().sqrt();
    let steps = (len / ALONG_STEP).ceil().max(1.0) as usize;
    (0..=steps).all(|j| {
        let t = j as f64 / steps as f64;
        vdg.contains(as_f32([0, 1, 2].map(|i| a[i] + t * (b[i] - a[i]))))
    })
}

/// The bounds of the world model, where free points are drawn.
fn free_bounds(bsp: &Bsp) -> ([f64; 3], [f64; 3]) {
    let w = bsp.world();
    (w.mins.map(f64::from), w.maxs.map(f64::from))
}

fn tri_area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
}

/// Uniform in the unit ball (rejection from the cube).
fn random_in_ball(rng: &mut SplitMix64) -> [f64; 3] {
    loop {
        let d = [
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        ];
        if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= 1.0 {
            return d;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two face volumes along the x axis with a half-unit gap between them (x 11.2 to
    /// 11.7): a segment across it leaves the volume, so a miss of `Visible` there is a
    /// gap of the graph, not the query's own miss. A 2-unit test (points at odd x)
    /// would step over the gap.
    #[test]
    fn a_segment_across_a_thin_gap_does_not_stay_inside() {
        let mut b = vdgformat::VdgBuilder::new();
        let mut tri = |p: [[f32; 2]; 3]| {
            let v = p.map(|[x, y]| b.add_vertex([x, y, 0.0], 1.0));
            b.add_face(v);
        };
        tri([[0.0, -5.0], [0.0, 5.0], [10.2, 0.0]]);
        tri([[12.7, 0.0], [22.0, -5.0], [22.0, 5.0]]);
        let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
        let g = file.graph();
        let (a, e) = ([1.0, 0.0, 0.0], [21.0, 0.0, 0.0]);
        assert!(g.contains([11.0, 0.0, 0.0]) && g.contains([13.0, 0.0, 0.0]));
        assert!(!g.contains([11.5, 0.0, 0.0]));
        assert!(!stays_inside(&g, a, e));
        assert!(!g.visible(as_f32(a), as_f32(e)));
        // Inside one volume the segment does stay inside.
        assert!(stays_inside(&g, a, [9.0, 0.0, 0.0]));
    }

    #[test]
    fn walkable_coverage_is_none_without_standing_places() {
        let mut r = CheckReport::default();
        assert_eq!(r.walkable_coverage(), None);
        assert_eq!(r.walkable_coverage_head(), None);
        assert!(r.to_json()["walkable_coverage"].is_null());
        assert!(r.to_json()["walkable_coverage_head"].is_null());
        (r.walkable_points, r.walkable_covered) = (4, 3);
        (r.walkable_head_points, r.walkable_head_covered) = (2, 2);
        assert_eq!(r.walkable_coverage(), Some(0.75));
        assert_eq!(r.walkable_coverage_head(), Some(1.0));
        assert_eq!(r.to_json()["walkable_coverage"], 0.75);
    }

    #[test]
    fn camera_misses_are_none_without_lines_and_a_false_positive_fails() {
        let mut r = CheckReport::default();
        assert_eq!(r.visible_fn_camera(), None);
        assert!(r.to_json()["visible_fn_camera"].is_null());
        assert!(r.passed());
        (
            r.camera_lines,
            r.camera_lines_inside,
            r.camera_false_negatives,
        ) = (10, 8, 2);
        assert_eq!(r.visible_fn_camera(), Some(0.25));
        assert_eq!(r.to_json()["visible_fn_camera"], 0.25);
        assert!(r.passed());
        r.camera_false_positives = 1;
        assert!(!r.passed());
        assert_eq!(r.to_json()["passed"], false);
    }
}
