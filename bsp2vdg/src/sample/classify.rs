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
