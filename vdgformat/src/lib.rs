//! The `.vdg` Voronoi Distance Graph file and its runtime queries.
//!
//! A VDG (thesis "Kameraführung in virtuellen Räumen mittels reduzierter
//! Voronoi Graphen", ch. 3) approximates the medial axis of a level's free
//! space by triangles whose vertices carry a clearance; the union of balls
//! over the triangles is free space a camera may use. This crate is what an
//! engine links: it memory-maps a `.vdg` written by `bsp2vdg`, validates it
//! once, and then answers queries straight from the mapped bytes with no
//! parsing or allocation step — clearance at a point, tracking a moving
//! point's face, nearest face via the BBox tree, line-of-sight (`Visible`),
//! Voronoi distance and paths by A*, and the reachable local vertices. The
//! writer half ([`VdgBuilder`]) precomputes everything the queries need
//! (adjacency, tree, checksum) and writes files atomically and
//! deterministically. It knows nothing about BSP maps.
//!
//! ```
//! use vdgformat::{VdgBuilder, VdgFile};
//!
//! // A strip of two triangles with clearance 32 along the x axis.
//! let mut b = VdgBuilder::new();
//! let v: Vec<u32> = [[0.0, 0.0], [256.0, 0.0], [0.0, 64.0], [256.0, 64.0]]
//!     .iter()
//!     .map(|&[x, y]| b.add_vertex([x, y, 0.0], 32.0))
//!     .collect();
//! b.add_face([v[0], v[1], v[2]]);
//! b.add_face([v[1], v[3], v[2]]);
//! let file = VdgFile::from_bytes(&b.to_bytes()?)?;
//! let g = file.graph();
//! assert!(g.visible([0.0, 10.0, 20.0], [250.0, 50.0, -20.0]));
//! assert!(!g.visible([0.0, 10.0, 20.0], [0.0, 10.0, 40.0]));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Queries at a glance (all on [`Vdg`], see [`query`]):
//!
//! | query | thesis | cost |
//! |---|---|---|
//! | [`Vdg::face_clearance`] | 3.7 | closed form, one evaluation |
//! | [`Vdg::clearance`], [`Vdg::nearest_face`] | 3.7, 5.2 | one tree leaf inside the volume |
//! | [`Vdg::track`] | 3.3, 5.2 | the hint face and its neighbours |
//! | [`Vdg::trace`], [`Vdg::visible`], [`Vdg::visible_from`] | 3.9 | a hop per face volume crossed |
//! | [`Vdg::vdistance`], [`Vdg::path`], [`query::PathFinder`] | 5.1 | A* over the vertex graph |
//! | [`Vdg::reachable`], [`Vdg::reachable_into`] | 5.3 | the face's neighbourhood |
//! | [`Vdg::advance`] | 5.3, 7.2 | a hop per face volume crossed |
//! | [`Vdg::path_with_clearance`] | — | A* over vertices with room for the agent |
//! | [`query::DistanceField`] | 5.1 | one Dijkstra from the target, grown on demand |
//!
//! The automatic camera of the thesis (ch. 5, 6.2) and its director are in
//! [`camera`].
//!
//! The feature `camera-toml` (on by default) lets [`camera::CameraParams`]
//! load from TOML, and is the only reason this crate depends on `serde` and
//! `toml`; an engine that sets its camera parameters in code turns it off
//! (`default-features = false`).
//!
//! The file layout is documented in `FORMAT.md` next to this crate.

mod build;
pub mod camera;
mod geom;
mod hash;
mod index;
pub mod layout;
pub mod query;
mod read;

pub use build::{BuildError, DEFAULT_LEAF_SIZE, VdgBuilder, WriteError};
pub use hash::xxh64;
pub use index::{FaceIter, FaceList, IndexIter, IndexList};
pub use query::{Advance, CoverBudget, CoverHint, DistanceField, FaceHit, VdgPath};
pub use read::{ReadError, Vdg, VdgFile};

/// Exact clearance of `p` for the face volume of the triangle of balls
/// `(centre, radius)`: `max_{q ∈ triangle} r(q) − |p − q|` with `r`
/// interpolated linearly (positive inside the volume). The same closed form
/// as [`Vdg::face_clearance`], in f64 and without a file, for tools that edit
/// graphs before writing them (the reduction of `bsp2vdg` proves its
/// condition A with it).
///
/// ```
/// let ball = |x: f64| ([x, 0.0, 0.0], 10.0);
/// let c = vdgformat::triangle_clearance([ball(0.0), ball(100.0), ([0.0, 100.0, 0.0], 10.0)], [50.0, 0.0, 4.0]);
/// assert!((c - 6.0).abs() < 1e-9);
/// ```
pub fn triangle_clearance(balls: [([f64; 3], f64); 3], p: [f64; 3]) -> f64 {
    geom::face_clearance(
        f64_ball(balls[0]),
        f64_ball(balls[1]),
        f64_ball(balls[2]),
        geom::V3(p[0], p[1], p[2]),
    )
}

/// Exact clearance of `p` for the volume of the segment between two balls
/// `(centre, radius)` with the radius interpolated linearly ("round cone"):
/// the clearance a triangle with this edge has at least at `p`.
///
/// ```
/// let c = vdgformat::segment_clearance([([0.0, 0.0, 0.0], 10.0), ([100.0, 0.0, 0.0], 10.0)], [50.0, 4.0, 0.0]);
/// assert!((c - 6.0).abs() < 1e-9);
/// ```
pub fn segment_clearance(balls: [([f64; 3], f64); 2], p: [f64; 3]) -> f64 {
    geom::edge_clearance(
        f64_ball(balls[0]),
        f64_ball(balls[1]),
        geom::V3(p[0], p[1], p[2]),
    )
}

fn f64_ball((c, r): ([f64; 3], f64)) -> geom::Ball {
    geom::Ball {
        c: geom::V3(c[0], c[1], c[2]),
        r,
    }
}

#[doc(hidden)]
pub mod __private {
    //! For this crate's tests and fuzz harness only.
    pub use crate::build::seal;

    /// Runs every query on a few points derived from the graph itself, so a
    /// fuzzer can check that an accepted file never makes a query panic or
    /// hang.
    pub fn exercise_queries(g: crate::Vdg<'_>) {
        let info = g.info();
        let mut pts = vec![info.volume_min, info.volume_max, [0.0; 3]];
        pts.extend(g.vertices().iter().take(4).map(|v| v.pos));
        let mut hint = 0;
        for (i, &p) in pts.iter().enumerate() {
            let q = pts[(i + 1) % pts.len()];
            let _ = g.clearance(p);
            if let Some(h) = g.track(hint, p) {
                hint = h.face;
                let _ = g.reachable(p, h.face);
                let _ = g.trace(h.face, p, q);
                let _ = g.visible_from(h.face, p, q);
            }
            let _ = g.faces_containing(p);
            let _ = g.contains(p);
            let _ = g.visible(p, q);
            let _ = g.path(p, q);
        }
        if g.vertex_count() > 1 {
            let _ = g.vertex_path(0, g.vertex_count() as u32 - 1);
        }
    }
}
