//! Hermetic outputs and up-to-date skips for build pipelines.
//!
//! A `.vdg` records what it was built from: the XXH64 of the map's bytes, the tool's
//! name, version and build identity (a hash of the compiler's source, so a rebuilt
//! compiler does not reuse old graphs), and every option that changes the graph ([`crate::options::recorded_options`]).
//! An output whose record matches the map and the options of this run is current
//! ([`check`]), so batch builds skip it. Paths are never recorded (the source name only
//! when asked with `--source-name`), so the same map compiled from another folder or
//! under another name gives the same bytes, as a build farm's sandboxes need.

use crate::options::{CompileOptions, Stage, recorded_options, samples_path};
use std::path::Path;

/// Whether `options.output` is a current build of a map whose bytes hash to
/// `map_hash` (XXH64, seed 0): `Ok(())` if so, else why not, in a few words for the log.
/// Outputs only the full pipeline writes count (`--stop-after reduce`), and a requested
/// samples file must exist too.
pub fn check(map_hash: u64, options: &CompileOptions) -> Result<(), String> {
    let out = &options.output;
    if options.stop_after != Stage::Reduce {
        return Err("--stop-after writes no graph".into());
    }
    if !out.is_file() {
        return Err(format!("{} does not exist", display_name(out)));
    }
    if options.save_samples && !samples_path(out).is_file() {
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
                "tool.name" | "tool.version" | "tool.build" => format!(
                    "it was built by {} {} (build {}), this is build {}",
                    g.metadata_value("tool.name").unwrap_or("another tool"),
                    g.metadata_value("tool.version").unwrap_or(""),
                    g.metadata_value("tool.build").unwrap_or("unrecorded"),
                    crate::options::BUILD
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
    // The measurement switches are recorded only when off: a file that records one
    // was built differently from a run that leaves it on.
    let recorded = recorded_options(options);
    for key in ["wall_raise", "coverage_guards"] {
        if g.metadata_value(key).is_some() && !recorded.iter().any(|(k, _)| k == key) {
            return Err(format!("it was built with {key} off"));
        }
    }
    Ok(())
}

fn display_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string())
}
