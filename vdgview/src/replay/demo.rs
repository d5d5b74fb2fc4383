//! `--routes demo:FILE.dem`: a playtest recorded by the game (`record NAME` in a GoldSrc
//! console), read by the `demo` crate. Each playback segment is one route: per client
//! frame the player's simulated origin, the angles it aimed with, its velocity (from the
//! positions where the demo records none) and whether it was crouched (its view height).

use super::route::{Route, TargetState};
use bsp::Game;
use std::path::Path;

pub use ::demo::Demo;

/// Opens a demo with a one-line error naming the file.
pub fn open(path: &Path) -> Result<Demo, String> {
    Demo::open(path).map_err(|e| format!("cannot read demo {}: {e}", path.display()))
}

/// Whether a demo was recorded on the map at `map`: the demo names its map (`c1a0`),
/// the file may carry a prefix (`bspview-halflife_c1a0.bsp`), so the file's stem must be
/// the name or end with it after a separator (`-`, `_`, `.`, space). `Err` names both.
pub fn same_map(demo: &Demo, demo_path: &Path, map: &Path) -> Result<(), String> {
    let stem = map
        .file_stem()
        .map(|s| s.to_string_lossy().to_lowercase())
        .unwrap_or_default();
    let name = demo.header.map_name.to_lowercase();
    let matches = !name.is_empty()
        && (stem == name
            || stem
                .strip_suffix(&name)
                .is_some_and(|head| head.ends_with(['-', '_', '.', ' '])));
    if matches {
        Ok(())
    } else {
        Err(format!(
            "{} was recorded on map {:?}, not on {} (give that map's BSP, or --force)",
            demo_path.display(),
            demo.header.map_name,
            map.display()
        ))
    }
}

/// The demo's routes (one per playback segment with at least two frames) in the map's
/// `game`. The origins are the player's as the game moved it: already the centre of
/// its hull, crouched or standing.
pub fn routes(demo: &Demo, stem: &str, game: Game) -> Vec<Route> {
    let frames = demo.player();
    let segments: Vec<usize> = {
        let mut s: Vec<usize> = frames.iter().map(|f| f.segment).collect();
        s.dedup();
        s
    };
    let mut out = Vec::new();
    for (k, &seg) in segments.iter().enumerate() {
        let seg_frames: Vec<_> = frames.iter().filter(|f| f.segment == seg).collect();
        if seg_frames.len() < 2 {
            continue;
        }
        let t0 = seg_frames[0].t;
        let mut states: Vec<TargetState> = seg_frames
            .iter()
            .map(|f| TargetState {
                t: f.t - t0,
                origin: f.origin,
                angles: f.angles,
                velocity: f.velocity.unwrap_or([0.0; 3]),
                crouch: f.crouched(),
                game,
            })
            .collect();
        if seg_frames[0].velocity.is_none() {
            for i in 1..states.len() {
                let (a, b) = (states[i - 1], states[i]);
                let dt = (b.t - a.t) as f32;
                states[i].velocity = [0, 1, 2].map(|j| (b.origin[j] - a.origin[j]) / dt);
            }
        }
        let name = if segments.len() == 1 {
            stem.to_string()
        } else {
            format!("{stem}#{}", k + 1)
        };
        out.push(Route { name, states });
    }
    out
}

/// `vdgview demo FILE.dem`: the header and what the playback holds.
pub fn summary(demo: &Demo, path: &Path) -> String {
    let h = &demo.header;
    let player = demo.player();
    let crouched = player.iter().filter(|p| p.crouched()).count();
    let mut s = format!("demo      {}\n", path.display());
    s += &format!("map       {}\n", h.map_name);
    s += &format!("game      {}\n", h.game_dir);
    s += &format!(
        "protocol  demo {}, network {}{}\n",
        h.demo_protocol,
        h.net_protocol,
        if h.demo_protocol == 4 {
            " (Half-Life 1.0.0.5)"
        } else {
            ""
        }
    );
    if h.map_crc != 0 {
        s += &format!("map crc   {:08x}\n", h.map_crc);
    }
    s += &format!("duration  {:.2} s\n", demo.duration());
    s += &format!(
        "frames    {} client frames ({} demo frames in {} segments); player in {} frames, {} crouched\n",
        demo.client_frames(),
        demo.frame_count(),
        demo.segments.len(),
        player.len(),
        crouched
    );
    for (k, seg) in demo.segments.iter().enumerate() {
        s += &format!(
            "segment {k} {:<10} {:>6} frames  {:>8.2} s  at byte {}\n",
            seg.description,
            seg.frames.len(),
            seg.track_time,
            seg.offset
        );
    }
    s
}

/// `vdgview demo FILE.dem --json`.
pub fn summary_json(demo: &Demo) -> serde_json::Value {
    let h = &demo.header;
    let player = demo.player();
    serde_json::json!({
        "map": h.map_name,
        "game": h.game_dir,
        "demo_protocol": h.demo_protocol,
        "net_protocol": h.net_protocol,
        "map_crc": h.map_crc,
        "duration_s": demo.duration(),
        "client_frames": demo.client_frames(),
        "demo_frames": demo.frame_count(),
        "player_frames": player.len(),
        "crouched_frames": player.iter().filter(|p| p.crouched()).count(),
        "segments": demo.segments.iter().map(|s| serde_json::json!({
            "kind": s.kind, "description": s.description, "frames": s.frames.len(),
            "client_frames": s.frame_count, "seconds": s.track_time, "offset": s.offset,
        })).collect::<Vec<_>>(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn demo_on(map: &str) -> Demo {
        Demo {
            header: ::demo::Header {
                demo_protocol: 5,
                net_protocol: 48,
                map_name: map.into(),
                game_dir: "valve".into(),
                map_crc: 0,
                directory_offset: 0,
            },
            segments: Vec::new(),
        }
    }

    #[test]
    fn the_map_name_must_match_the_bsp_file() {
        let d = demo_on("c1a0");
        let p = Path::new("x.dem");
        for ok in ["c1a0.bsp", "maps/C1A0.bsp", "bspview-halflife_c1a0.bsp"] {
            assert!(same_map(&d, p, Path::new(ok)).is_ok(), "{ok}");
        }
        for bad in ["c1a0a.bsp", "xc1a0.bsp", "de_dust.bsp"] {
            let e = same_map(&d, p, Path::new(bad)).unwrap_err();
            assert!(
                e.contains("c1a0") && e.contains(bad) && !e.contains('\n'),
                "{e}"
            );
        }
    }
}
