//! Face classes: which faces bound the free space (thesis 6.1.2).
//!
//! Compilers keep some faces that are no walls: trigger and clip brushes, hint and
//! skip helpers, alpha-tested fences, liquid surfaces. Sampling those would put the
//! medial axis in the wrong place, so they are skipped. GoldSrc and Quake say what a
//! face is by its texture name ([`classify_texture`]); [`crate::Bsp::face_class`]
//! asks the right source for each format. Sky faces are obstacles but lie far from
//! where cameras go, so the compiler samples them more sparsely.

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

/// Classifies a face by its texture name (case-insensitive, as the engines do).
///
/// ```
/// use bsp::faces::{classify_texture, FaceClass, SkipReason};
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

/// A face of a model as a polygon in world coordinates, with its class.
#[derive(Debug, Clone, PartialEq)]
pub struct FacePolygon {
    /// Index into [`crate::Bsp::faces`].
    pub index: u32,
    pub polygon: Vec<[f64; 3]>,
    /// Unit normal towards the side the face is seen from.
    pub normal: [f64; 3],
    pub class: FaceClass,
}

/// The faces of model `model` (0 is the world), placed at the origin of the entity
/// that uses the model.
///
/// ```no_run
/// let bsp = bsp::Bsp::open("maps/de_dust2.bsp")?;
/// let walls = bsp::faces::polygons(&bsp, 0)
///     .filter(|f| f.class == bsp::faces::FaceClass::Wall)
///     .count();
/// # Ok::<(), bsp::BspError>(())
/// ```
pub fn polygons(bsp: &crate::Bsp, model: usize) -> impl Iterator<Item = FacePolygon> + '_ {
    let m = &bsp.models[model];
    let origin = if model == 0 {
        [0.0; 3]
    } else {
        bsp.entity_of_model(model)
            .and_then(|e| e.origin())
            .unwrap_or([0.0; 3])
            .map(f64::from)
    };
    let first = m.first_face as usize;
    // Unusable faces (see `Bsp::unusable_faces`) have no edges and give no polygon.
    bsp.model_faces(m)
        .iter()
        .enumerate()
        .filter(|(_, face)| face.num_edges > 0)
        .map(move |(k, face)| FacePolygon {
            index: (first + k) as u32,
            polygon: bsp
                .face_vertices(face)
                .map(|v| [0, 1, 2].map(|i| v[i] as f64 + origin[i]))
                .collect(),
            normal: bsp.face_normal(face).map(f64::from),
            class: bsp.face_class(face),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

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
