//! Which faces bound the free space (thesis 6.1.2).
//!
//! Compilers keep some faces that are no walls: trigger and clip brushes, hint and
//! skip helpers, alpha-tested fences, liquid surfaces. Sampling those would put the
//! medial axis in the wrong place, so they are skipped by texture name. Sky faces are
//! obstacles but lie far from where cameras go, so they are sampled more sparsely.

/// What to do with a face when sampling.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FaceClass {
    /// An ordinary wall: sampled at the spacing m.
    Wall,
    /// A sky face: an obstacle, sampled at twice the spacing.
    Sky,
    /// Invisible, transparent or liquid: not sampled.
    Skip(SkipReason),
}

/// Why a face is not sampled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SkipReason {
    /// `aaatrigger`, Quake's `trigger`.
    Trigger,
    /// `clip`, `clipbevel`, ...: player clip.
    Clip,
    /// `origin`, `null`, `skip`, `hint`, `bevel`: compiler helpers.
    Helper,
    /// `{`-prefixed alpha-tested textures (fences, grates).
    Transparent,
    /// `!`-prefixed (GoldSrc) or `*`-prefixed (Quake) liquid surfaces.
    Liquid,
    /// The BSP has an obstacle in front of the face: it does not look into free space
    /// (e.g. sky-textured faces between sky and solid).
    NotFacingFree,
    /// The BSP has free space behind the face too (liquid surfaces, faces seen from
    /// inside water): no wall is there.
    FreeBehind,
}

/// Which side of a face is free, as the map's BSP says, decides whether it bounds the
/// free space. Texture names cannot tell this for every map: compilers emit faces
/// between sky and solid, both sides of liquid surfaces, and some maps ship without
/// texture names. `is_free` is the oracle's point test.
pub fn classify_by_contents(
    polygon: &[[f64; 3]],
    normal: [f64; 3],
    is_free: impl Fn([f64; 3]) -> bool,
) -> Option<SkipReason> {
    const EPS: f64 = 0.25;
    let at = |c: [f64; 3], s: f64| {
        [
            c[0] + s * normal[0],
            c[1] + s * normal[1],
            c[2] + s * normal[2],
        ]
    };
    // Several interior points: a face partly covered by another brush may have its
    // centre under it; it is a wall if free space meets an obstacle anywhere on it.
    let points = interior_points(polygon);
    if points.is_empty() {
        return None;
    }
    let mut verdict = None;
    for c in points {
        if !is_free(at(c, EPS)) {
            verdict = verdict.or(Some(SkipReason::NotFacingFree));
        } else if is_free(at(c, -EPS)) {
            verdict = verdict.or(Some(SkipReason::FreeBehind));
        } else {
            return None;
        }
    }
    verdict
}

/// The centroids of the fan triangles (of non-zero area): inside a convex polygon and,
/// for all but slivers, away from its edges where the side test would be ambiguous.
fn interior_points(p: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    for i in 1..p.len().saturating_sub(1) {
        let (a, b, c) = (p[0], p[i], p[i + 1]);
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        if n[0] * n[0] + n[1] * n[1] + n[2] * n[2] > 1e-6 {
            out.push([0, 1, 2].map(|k| (a[k] + b[k] + c[k]) / 3.0));
        }
    }
    out
}

/// Classifies a face by its texture name (case-insensitive, as the engines do).
///
/// ```
/// use bsp2vdg::sample::classify::{classify_texture, FaceClass, SkipReason};
/// assert_eq!(classify_texture("C1A0_LABFLRB"), FaceClass::Wall);
/// assert_eq!(classify_texture("sky"), FaceClass::Sky);
/// assert_eq!(classify_texture("{FENCE"), FaceClass::Skip(SkipReason::Transparent));
/// assert_eq!(classify_texture("!water1"), FaceClass::Skip(SkipReason::Liquid));
/// ```
pub fn classify_texture(name: &str) -> FaceClass {
    let lower = name.to_ascii_lowercase();
    let n = lower.as_str();
    if n.starts_with('{') {
        return FaceClass::Skip(SkipReason::Transparent);
    }
    if n.starts_with('!') || n.starts_with('*') {
        return FaceClass::Skip(SkipReason::Liquid);
    }
    if n == "aaatrigger" || n == "trigger" {
        return FaceClass::Skip(SkipReason::Trigger);
    }
    if n.starts_with("clip") {
        return FaceClass::Skip(SkipReason::Clip);
    }
    if matches!(
        n,
        "origin" | "null" | "skip" | "hint" | "hintskip" | "bevel"
    ) {
        return FaceClass::Skip(SkipReason::Helper);
    }
    if n.starts_with("sky") {
        return FaceClass::Sky;
    }
    FaceClass::Wall
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contents_decide_which_faces_bound_free_space() {
        // Free space is z > 0 and x > 0 (a wall at x = 0 and a floor at z = 0).
        let free = |p: [f64; 3]| p[2] > 0.0 && p[0] > 0.0;
        let floor = [
            [1.0, 0.0, 0.0],
            [9.0, 0.0, 0.0],
            [9.0, 9.0, 0.0],
            [1.0, 9.0, 0.0],
        ];
        assert_eq!(classify_by_contents(&floor, [0.0, 0.0, 1.0], free), None);
        assert_eq!(
            classify_by_contents(&floor, [0.0, 0.0, -1.0], free),
            Some(SkipReason::NotFacingFree)
        );
        let hanging = [
            [1.0, 0.0, 5.0],
            [9.0, 0.0, 5.0],
            [9.0, 9.0, 5.0],
            [1.0, 9.0, 5.0],
        ];
        assert_eq!(
            classify_by_contents(&hanging, [0.0, 0.0, 1.0], free),
            Some(SkipReason::FreeBehind)
        );
        let degenerate = [[1.0, 0.0, 5.0], [2.0, 0.0, 5.0], [3.0, 0.0, 5.0]];
        assert_eq!(
            classify_by_contents(&degenerate, [0.0, 0.0, 1.0], free),
            None
        );
    }

    #[test]
    fn helper_surfaces_are_skipped() {
        for (name, want) in [
            ("AAATRIGGER", FaceClass::Skip(SkipReason::Trigger)),
            ("CLIPBEVEL", FaceClass::Skip(SkipReason::Clip)),
            ("ORIGIN", FaceClass::Skip(SkipReason::Helper)),
            ("null", FaceClass::Skip(SkipReason::Helper)),
            ("SKIP", FaceClass::Skip(SkipReason::Helper)),
            ("HINT", FaceClass::Skip(SkipReason::Helper)),
            ("{grate", FaceClass::Skip(SkipReason::Transparent)),
            ("*slime0", FaceClass::Skip(SkipReason::Liquid)),
            ("sky1", FaceClass::Sky),
            ("SKY", FaceClass::Sky),
            ("skylight_white", FaceClass::Sky),
            ("crate01", FaceClass::Wall),
            ("hintwall", FaceClass::Wall),
            ("", FaceClass::Wall),
        ] {
            assert_eq!(classify_texture(name), want, "{name}");
        }
    }
}
