//! Wall sampling (thesis 3.5, 6.1.2): points on every face that bounds the free space,
//! so that every point of a sampled face lies within the spacing m of a sample.
//!
//! Faces are fan-triangulated and subdivided along longest edges by an exact covering
//! criterion ([`subdivide`]). Neighbouring faces split shared edges at bit-identical
//! midpoints, and the few points that still nearly coincide (T-junctions, vertices
//! welded by the compiler) are merged within a small tolerance; the subdivision radius
//! is reduced by that tolerance, so the guarantee survives the merge.
//!
//! ```no_run
//! use bsp::Bsp;
//! use bsp2vdg::sample::{sample, SampleOptions};
//! let bsp = Bsp::open("maps/crossfire.bsp")?;
//! let s = sample(&bsp, &SampleOptions::default());
//! println!("{} samples at spacing {}", s.points.len(), s.spacing);
//! # Ok::<(), bsp::BspError>(())
//! ```

pub mod classify;
pub mod grid;
pub mod subdivide;

use bsp::Bsp;
use bsp::boundary::{self, BoundaryPolygon};
use bsp::oracle::{Oracle, OracleOptions};
use bsp::walls::Walls;
use classify::{FaceClass, SkipReason};
use grid::PointGrid;
use rayon::prelude::*;
use toolbox::SplitMix64;

/// How to sample a map.
#[derive(Debug, Clone)]
pub struct SampleOptions {
    /// The spacing m (`-sd`): every face point within m of a sample.
    pub spacing: f64,
    /// The cap on the number of samples (`-ms`); m is raised until it holds.
    pub max_samples: usize,
    /// Sky faces are sampled at this multiple of m.
    pub sky_factor: f64,
    /// Only faces whose centre lies in the central eighth of the map (`-subset`).
    pub subset: bool,
    /// Brush models `*N` to sample besides the world (e.g. chosen func_walls).
    pub models: Vec<usize>,
}

impl Default for SampleOptions {
    fn default() -> Self {
        SampleOptions {
            spacing: crate::options::defaults::SAMPLE_SPACING,
            max_samples: crate::options::defaults::MAX_SAMPLES,
            sky_factor: crate::options::defaults::SKY_FACTOR,
            subset: false,
            models: Vec::new(),
        }
    }
}

/// Faces skipped, by reason.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SkipCounts {
    pub trigger: usize,
    pub clip: usize,
    pub helper: usize,
    pub transparent: usize,
    pub liquid: usize,
    pub not_facing_free: usize,
    pub free_behind: usize,
    pub outside_subset: usize,
}

impl SkipCounts {
    pub fn total(&self) -> usize {
        self.trigger
            + self.clip
            + self.helper
            + self.transparent
            + self.liquid
            + self.not_facing_free
            + self.free_behind
            + self.outside_subset
    }
}

/// The result of sampling.
#[derive(Debug, Clone)]
pub struct Samples {
    /// The sample points, in a deterministic order.
    pub points: Vec<[f64; 3]>,
    /// For each point, the face that produced it ([`NO_FACE`] for hidden walls).
    pub source_face: Vec<u32>,
    /// The spacing finally used (larger than asked when the cap was hit).
    pub spacing: f64,
    /// The spacing asked for.
    pub requested_spacing: f64,
    /// Faces considered (world and chosen models).
    pub faces: usize,
    /// Faces that were sampled.
    pub sampled_faces: usize,
    /// Sky faces among them.
    pub sky_faces: usize,
    /// Triangles after subdivision (the thesis' "subfaces").
    pub subfaces: usize,
    /// Points dropped as (near) duplicates of others.
    pub merged: usize,
    /// Points on walls the BSP tree has but no face shows (see [`hidden_faces`]);
    /// their `source_face` is [`NO_FACE`].
    pub hidden_samples: usize,
    pub skipped: SkipCounts,
    /// The merge tolerance used.
    pub merge_tolerance: f64,
}

/// A face prepared for sampling: its polygon in world coordinates and its class.
#[derive(Debug, Clone)]
pub struct SampledFace {
    pub index: u32,
    pub polygon: Vec<[f64; 3]>,
    /// Unit normal towards the side the face is seen from.
    pub normal: [f64; 3],
    pub class: FaceClass,
    /// A piece of the BSP tree's obstacle boundary rather than a face of the map (see
    /// [`hidden_faces`]): sampled only where no visible face lies, to fill the walls
    /// the compiler left without faces.
    pub hidden: bool,
}

impl bsp::walls::WallFace for SampledFace {
    fn polygon(&self) -> &[[f64; 3]] {
        &self.polygon
    }
    fn normal(&self) -> [f64; 3] {
        self.normal
    }
    fn class(&self) -> FaceClass {
        self.class
    }
}

/// Marks the index of samples that come from a hidden (faceless) wall.
pub const NO_FACE: u32 = u32::MAX;

/// The map's obstacle boundary as found in its BSP trees ([`boundary::of_map`]), as
/// hidden faces to sample besides the visible ones.
pub fn hidden_faces(boundary: &[BoundaryPolygon]) -> Vec<SampledFace> {
    boundary
        .iter()
        .map(|b| SampledFace {
            index: NO_FACE,
            polygon: b.vertices.clone(),
            normal: b.normal,
            class: if b.obstacle == bsp::contents::SKY {
                FaceClass::Sky
            } else {
                FaceClass::Wall
            },
            hidden: true,
        })
        .collect()
}

/// The faces of the world and of the chosen brush models, with entity origins applied.
pub fn collect_faces(bsp: &Bsp, models: &[usize]) -> Vec<SampledFace> {
    let mut out = Vec::new();
    let mut model_ids = vec![0usize];
    model_ids.extend(
        models
            .iter()
            .copied()
            .filter(|&m| m > 0 && m < bsp.models.len()),
    );
    model_ids.dedup();
    for m in model_ids {
        out.extend(bsp::faces::polygons(bsp, m).map(|f| SampledFace {
            index: f.index,
            polygon: f.polygon,
            normal: f.normal,
            class: f.class,
            hidden: false,
        }));
    }
    out
}

/// Samples the map's faces that bound its free space (by texture name and by the
/// BSP's contents on either side, see [`classify::classify_by_contents`]), and the
/// walls its BSP tree has where the compiler left no face.
/// With the default oracle options; the compiler builds its oracle and boundary with
/// the user's options and calls [`wall_faces`] and [`sample_faces`] as this does.
pub fn sample(bsp: &Bsp, options: &SampleOptions) -> Samples {
    let oracle_options = OracleOptions {
        solid_models: options.models.clone(),
        ..Default::default()
    };
    let oracle = Oracle::new(bsp, &oracle_options);
    let boundary = boundary::of_map(bsp, &oracle_options);
    let faces = wall_faces(bsp, &options.models, &oracle, &boundary);
    sample_faces(&faces, options)
}

/// The faces to sample: the world's (and `models`') faces classified by name and by
/// the BSP's contents on either side, then the pieces of the tree's obstacle
/// `boundary` no face shows.
pub fn wall_faces(
    bsp: &Bsp,
    models: &[usize],
    oracle: &Oracle,
    boundary: &[BoundaryPolygon],
) -> Vec<SampledFace> {
    let mut faces = collect_faces(bsp, models);
    cull_by_contents(&mut faces, |p| oracle.is_free(p));
    faces.extend(hidden_faces(boundary));
    faces
}

/// The brush models used by entities of the given classnames, in model order.
pub fn entity_models(bsp: &Bsp, classes: &[String]) -> Vec<usize> {
    let mut models: Vec<usize> = bsp
        .entities
        .iter()
        .filter(|e| {
            classes
                .iter()
                .any(|c| c.eq_ignore_ascii_case(e.classname()))
        })
        .filter_map(|e| e.model_index())
        .filter(|&m| m > 0 && m < bsp.models.len())
        .collect();
    models.sort_unstable();
    models.dedup();
    models
}

/// Marks faces that do not separate free space from an obstacle as skipped.
pub fn cull_by_contents(faces: &mut [SampledFace], is_free: impl Fn([f64; 3]) -> bool + Sync) {
    faces.par_iter_mut().filter(|f| !f.hidden).for_each(|f| {
        let verdict = classify::classify_by_contents(&f.polygon, f.normal, &is_free);
        match (f.class, verdict) {
            (FaceClass::Wall | FaceClass::Sky, Some(r)) => f.class = FaceClass::Skip(r),
            // A name says "invisible" or "transparent", but the BSP has free space in
            // front and an obstacle behind: a solid brush with an alpha or helper
            // texture in the world is a wall all the same (cameras cannot pass it).
            (FaceClass::Skip(r), None) if r != SkipReason::Liquid => f.class = FaceClass::Wall,
            _ => {}
        }
    });
}

/// Samples prepared faces (see [`collect_faces`]).
pub fn sample_faces(faces: &[SampledFace], options: &SampleOptions) -> Samples {
    let subset = options.subset.then(|| central_eighth(faces));
    let mut skipped = SkipCounts::default();
    let mut chosen: Vec<&SampledFace> = Vec::new();
    for f in faces {
        match f.class {
            FaceClass::Skip(r) => match r {
                SkipReason::Trigger => skipped.trigger += 1,
                SkipReason::Clip => skipped.clip += 1,
                SkipReason::Helper => skipped.helper += 1,
                SkipReason::Transparent => skipped.transparent += 1,
                SkipReason::Liquid => skipped.liquid += 1,
                SkipReason::NotFacingFree => skipped.not_facing_free += 1,
                SkipReason::FreeBehind => skipped.free_behind += 1,
            },
            _ if subset.is_some_and(|b| !inside(centroid(&f.polygon), b)) => {
                skipped.outside_subset += 1
            }
            _ => chosen.push(f),
        }
    }

    // Start from an estimate so that a tiny m on a huge map cannot allocate without
    // bound before the cap is checked: about one sample per m² of area plus one per m
    // of boundary (long slivers have no area but need samples along their length).
    let max = options.max_samples.max(1) as f64;
    let mut spacing = options.spacing;
    while estimate(&chosen, spacing, options.sky_factor) > 4.0 * max {
        spacing *= 1.25;
    }
    // Hidden walls are sampled only where no visible face lies: the visible faces'
    // distance answers that for each of their sample points.
    let visible = chosen.iter().any(|f| f.hidden).then(|| {
        Walls::new(
            chosen
                .iter()
                .filter(|f| !f.hidden && f.polygon.len() >= 3)
                .map(|f| (f.polygon.clone(), f.normal))
                .collect(),
        )
    });
    loop {
        match sample_at(
            &chosen,
            visible.as_ref(),
            spacing,
            options.sky_factor,
            16 * options.max_samples.max(1),
        ) {
            // A pass that overflowed its budget was abandoned: go coarser.
            None => spacing *= 2.0,
            Some(s) if s.points.len() <= options.max_samples => {
                return Samples {
                    requested_spacing: options.spacing,
                    faces: faces.iter().filter(|f| !f.hidden).count(),
                    skipped,
                    ..s
                };
            }
            // Sample count scales with 1/m²; aim a little below the cap.
            Some(s) => spacing *= (s.points.len() as f64 / max).sqrt() * 1.02,
        }
    }
}

/// Roughly how many samples spacing `m` yields (within a small constant factor).
fn estimate(faces: &[&SampledFace], m: f64, sky_factor: f64) -> f64 {
    faces
        .iter()
        .map(|f| {
            let s = if f.class == FaceClass::Sky {
                m * sky_factor
            } else {
                m
            };
            polygon_area(&f.polygon) / (s * s) + polygon_perimeter(&f.polygon) / s + 1.0
        })
        .sum()
}

fn polygon_perimeter(p: &[[f64; 3]]) -> f64 {
    (0..p.len())
        .map(|i| grid::dist(p[i], p[(i + 1) % p.len()]))
        .sum()
}

/// A hidden wall's sample this close to a visible face lies on that face (the two
/// come from the same f32 planes, so they agree to far less than this).
const ON_VISIBLE_FACE: f64 = 0.5;

/// One sampling pass at spacing `m`; `visible` are the visible faces' walls when
/// hidden ones are to be sampled too.
fn sample_at(
    faces: &[&SampledFace],
    visible: Option<&Walls>,
    m: f64,
    sky_factor: f64,
    budget: usize,
) -> Option<Samples> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let tolerance = (m / 64.0).min(0.5);
    let produced = AtomicUsize::new(0);
    let per_face: Vec<(Vec<[f64; 3]>, usize)> = faces
        .par_iter()
        .map(|f| {
            if produced.load(Ordering::Relaxed) > budget {
                return (Vec::new(), 0);
            }
            let spacing = if f.class == FaceClass::Sky {
                m * sky_factor
            } else {
                m
            };
            let mut r = sample_polygon(&f.polygon, spacing - tolerance, budget);
            if let (true, Some(walls)) = (f.hidden, visible) {
                r.0.retain(|&p| walls.distance_within(p, ON_VISIBLE_FACE).is_none());
            }
            produced.fetch_add(r.0.len(), Ordering::Relaxed);
            r
        })
        .collect();
    if produced.load(Ordering::Relaxed) > budget {
        return None;
    }
    let mut grid = PointGrid::new(tolerance.max(1e-6));
    let mut source_face = Vec::new();
    let (mut subfaces, mut merged, mut hidden) = (0, 0, 0);
    for (f, (points, tris)) in faces.iter().zip(&per_face) {
        subfaces += tris;
        for &p in points {
            if grid.nearest_within(p, tolerance).is_some() {
                merged += 1;
            } else {
                grid.insert(p);
                source_face.push(f.index);
                hidden += f.hidden as usize;
            }
        }
    }
    Some(Samples {
        points: grid.points().to_vec(),
        source_face,
        spacing: m,
        requested_spacing: m,
        faces: faces.len(),
        sampled_faces: faces.iter().filter(|f| !f.hidden).count(),
        sky_faces: faces
            .iter()
            .filter(|f| !f.hidden && f.class == FaceClass::Sky)
            .count(),
        hidden_samples: hidden,
        subfaces,
        merged,
        skipped: SkipCounts::default(),
        merge_tolerance: tolerance,
    })
}

/// The polygon's corners plus every midpoint its subdivision creates (at most about
/// `budget`), and the number of final triangles.
pub fn sample_polygon(polygon: &[[f64; 3]], radius: f64, budget: usize) -> (Vec<[f64; 3]>, usize) {
    let mut points = polygon.to_vec();
    let mut tris = 0;
    for i in 1..polygon.len().saturating_sub(1) {
        let (a, b, c) = (polygon[0], polygon[i], polygon[i + 1]);
        tris += subdivide::subdivide(
            a,
            b,
            c,
            radius,
            &mut points,
            budget.saturating_add(polygon.len()),
        );
    }
    (points, tris)
}

pub use toolbox::vec3::polygon_area;

fn centroid(p: &[[f64; 3]]) -> [f64; 3] {
    let n = p.len().max(1) as f64;
    let s = p
        .iter()
        .fold([0.0; 3], |s, v| [s[0] + v[0], s[1] + v[1], s[2] + v[2]]);
    s.map(|c| c / n)
}

type Bounds = ([f64; 3], [f64; 3]);

fn inside(p: [f64; 3], (lo, hi): Bounds) -> bool {
    (0..3).all(|i| p[i] >= lo[i] && p[i] <= hi[i])
}

/// The middle box with half the extent of the faces' bounds on every axis.
fn central_eighth(faces: &[SampledFace]) -> Bounds {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for v in faces.iter().flat_map(|f| &f.polygon) {
        for i in 0..3 {
            lo[i] = lo[i].min(v[i]);
            hi[i] = hi[i].max(v[i]);
        }
    }
    let q = [0, 1, 2].map(|i| (hi[i] - lo[i]) * 0.25);
    (
        [0, 1, 2].map(|i| lo[i] + q[i]),
        [0, 1, 2].map(|i| hi[i] - q[i]),
    )
}

/// Uniform random points on the given faces (area-weighted), for measurements: each
/// is returned with the index into `faces` it lies on.
pub fn random_face_points(faces: &[&SampledFace], n: usize, seed: u64) -> Vec<([f64; 3], usize)> {
    // Every fan triangle with its cumulative area.
    let mut tris: Vec<(usize, [[f64; 3]; 3])> = Vec::new();
    let mut cumulative = Vec::new();
    let mut total = 0.0;
    for (fi, f) in faces.iter().enumerate() {
        let p = &f.polygon;
        for i in 1..p.len().saturating_sub(1) {
            let t = [p[0], p[i], p[i + 1]];
            total += polygon_area(&t);
            tris.push((fi, t));
            cumulative.push(total);
        }
    }
    if tris.is_empty() || total <= 0.0 {
        return Vec::new();
    }
    let mut rng = SplitMix64::new(seed);
    (0..n)
        .map(|_| {
            let x = rng.next_f64() * total;
            let k = cumulative.partition_point(|&c| c <= x).min(tris.len() - 1);
            let (fi, [a, b, c]) = tris[k];
            let (mut u, mut v) = (rng.next_f64(), rng.next_f64());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            let p = [0, 1, 2].map(|i| a[i] + u * (b[i] - a[i]) + v * (c[i] - a[i]));
            (p, fi)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(size: f64, z: f64) -> SampledFace {
        SampledFace {
            index: 0,
            polygon: vec![
                [0.0, 0.0, z],
                [size, 0.0, z],
                [size, size, z],
                [0.0, size, z],
            ],
            normal: [0.0, 0.0, 1.0],
            class: FaceClass::Wall,
            hidden: false,
        }
    }

    #[test]
    fn covering_holds_after_merging() {
        let mut a = square(300.0, 0.0);
        // A second face sharing an edge, with a T-junction vertex on it.
        let b = SampledFace {
            index: 1,
            polygon: vec![
                [0.0, 0.0, 0.0],
                [0.0, 0.0, 200.0],
                [0.0, 300.0, 200.0],
                [0.0, 300.0, 0.0],
                [0.0, 113.0, 0.0],
            ],
            normal: [1.0, 0.0, 0.0],
            class: FaceClass::Wall,
            hidden: false,
        };
        a.index = 0;
        let faces = vec![a, b];
        let s = sample_faces(
            &faces,
            &SampleOptions {
                spacing: 24.0,
                ..Default::default()
            },
        );
        let grid = PointGrid::from_points(&s.points, 24.0);
        let refs: Vec<&SampledFace> = faces.iter().collect();
        for (p, _) in random_face_points(&refs, 20_000, 1) {
            let d = grid.nearest_within(p, 24.0).map(|(_, d)| d);
            assert!(d.is_some_and(|d| d <= 24.0), "{p:?} {d:?}");
        }
        // No two samples closer than the merge tolerance.
        for (i, &p) in s.points.iter().enumerate() {
            let (j, _) = grid.nearest_within(p, s.merge_tolerance).unwrap();
            assert_eq!(j as usize, i);
        }
    }

    #[test]
    fn skipped_classes_and_sky_spacing() {
        let mut sky = square(480.0, 0.0);
        sky.class = FaceClass::Sky;
        let mut wall = square(480.0, 10.0);
        wall.index = 1;
        let mut fence = square(480.0, 20.0);
        fence.class = FaceClass::Skip(SkipReason::Transparent);
        let s = sample_faces(&[sky, wall, fence], &SampleOptions::default());
        let on_sky = s.source_face.iter().filter(|&&f| f == 0).count();
        let on_wall = s.source_face.iter().filter(|&&f| f == 1).count();
        assert_eq!(s.sampled_faces, 2);
        assert_eq!(s.skipped.transparent, 1);
        // Twice the spacing: about a quarter of the samples.
        assert!(on_sky * 3 < on_wall, "{on_sky} vs {on_wall}");
    }

    #[test]
    fn cap_raises_the_spacing() {
        let faces = [square(2400.0, 0.0)];
        let s = sample_faces(
            &faces,
            &SampleOptions {
                max_samples: 2000,
                ..Default::default()
            },
        );
        assert!(s.points.len() <= 2000);
        assert!(s.spacing > 24.0 && s.requested_spacing == 24.0);
        let uncapped = sample_faces(&faces, &SampleOptions::default());
        assert!(uncapped.points.len() > 2000);
    }

    #[test]
    fn huge_slivers_are_capped_before_sampling() {
        let sliver = SampledFace {
            index: 0,
            polygon: vec![[0.0, 0.0, 0.0], [1e30, 0.0, 0.0], [1e30, 1e-3, 0.0]],
            normal: [0.0, 0.0, 1.0],
            class: FaceClass::Wall,
            hidden: false,
        };
        let s = sample_faces(
            &[sliver],
            &SampleOptions {
                max_samples: 1000,
                ..Default::default()
            },
        );
        assert!(s.points.len() <= 1000 && s.spacing > 1e26);
    }

    #[test]
    fn sampling_is_deterministic() {
        let faces = [square(500.0, 0.0), square(333.0, 7.0)];
        let a = sample_faces(&faces, &SampleOptions::default());
        let b = sample_faces(&faces, &SampleOptions::default());
        assert_eq!(a.points, b.points);
    }
}
