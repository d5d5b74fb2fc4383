//! Hermetic outputs and up-to-date skips for build pipelines.
//!
//! A `.vdg` records what it was built from: the XXH64 of the map's bytes, the tool's
//! name and version, and every option that changes the graph ([`recorded_options`]).
//! An output whose record matches the map and the options of this run is current
//! ([`check`]), so batch builds skip it. Paths are never recorded (the source name only
//! when asked with `--source-name`), so the same map compiled from another folder or
//! under another name gives the same bytes, as a build farm's sandboxes need.

use crate::pipeline::CompileOptions;
use std::path::Path;

/// The metadata entries written into the `.vdg` besides the source hash: the tool, the
/// options that shape the graph and, when asked, the source name. Both the writer and
/// the up-to-date check use this one list, so they cannot disagree.
///
/// ```
/// use bsp2vdg::pipeline::CompileOptions;
/// let o = CompileOptions::new("out.vdg".into());
/// let rec = bsp2vdg::uptodate::recorded_options(&o);
/// assert!(rec.iter().any(|(k, v)| k == "sd" && v == "24"));
/// assert!(rec.iter().all(|(k, _)| k != "source.name"));
/// ```
pub fn recorded_options(options: &CompileOptions) -> Vec<(String, String)> {
    let mut v: Vec<(String, String)> = [
        ("tool.name", "bsp2vdg".to_string()),
        ("tool.version", env!("CARGO_PKG_VERSION").to_string()),
        ("sd", options.sampling.spacing.to_string()),
        ("ms", options.sampling.max_samples.to_string()),
        ("rl", options.reduction_limit.to_string()),
        ("rv", options.reduction_floor.to_string()),
        ("rc", options.reduction_cost.as_str().to_string()),
        ("md", options.min_clearance.to_string()),
        ("bb", options.tree_leaf_size.to_string()),
        ("subset", options.sampling.subset.to_string()),
        ("liquids_solid", options.liquids_are_solid.to_string()),
        ("clip_solid", options.clip_is_solid.to_string()),
        ("entities", options.entity_classes.join(",")),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect();
    if let Some(name) = &options.source_name {
        v.push(("source.name".to_string(), name.clone()));
    }
    v
}

/// Whether `options.output` is a current build of a map whose bytes hash to
/// `map_hash` (XXH64, seed 0): `Ok(())` if so, else why not, in a few words for the log.
/// Outputs only the full pipeline writes count (`--stop-after reduce`), and a requested
/// samples file must exist too.
pub fn check(map_hash: u64, options: &CompileOptions) -> Result<(), String> {
    let out = &options.output;
    if options.stop_after != crate::pipeline::Stage::Reduce {
        return Err("--stop-after writes no graph".into());
    }
    if !out.is_file() {
        return Err(format!("{} does not exist", display_name(out)));
    }
    if options.save_samples && !crate::pipeline::samples_path(out).is_file() {
        return Err("its samples file is missing".into());
    }
    let file = vdgformat::VdgFile::open(out)
        .map_err(|e| format!("{} is unreadable ({e})", display_name(out)))?;
    let g = file.graph();
    if g.info().source_hash != map_hash {
        return Err("the map changed".into());
    }
    for (key, want) in recorded_options(options) {
        let have = g.metadata_value(&key);
        if have != Some(want.as_str()) {
            return Err(match key.as_str() {
                "tool.name" | "tool.version" => format!(
                    "it was built by {} {}",
                    g.metadata_value("tool.name").unwrap_or("another tool"),
                    g.metadata_value("tool.version").unwrap_or("")
                ),
                _ => format!(
                    "option {key} was {} and is now {want}",
                    have.unwrap_or("unset")
                ),
            });
        }
    }
    if options.source_name.is_none() && g.metadata_value("source.name").is_some() {
        return Err("it records a source name, this run does not".into());
    }
    Ok(())
}

fn display_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string())
}
