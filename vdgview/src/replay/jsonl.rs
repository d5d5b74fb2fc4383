//! `--routes FILE.jsonl`: recorded frames of a playtest, one JSON object per line:
//! `{"t": seconds, "origin": [x, y, z], "angles": [pitch, yaw, roll]}`, optionally
//! `"crouch": true` and `"route": "name"` (a new name starts a new route). Velocities
//! are taken from the positions. Blank lines and lines starting with `#` are skipped.

use super::route::{Route, TargetState};
use bsp::Game;
use serde::Deserialize;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Line {
    t: f64,
    origin: [f32; 3],
    angles: [f32; 3],
    #[serde(default)]
    crouch: bool,
    #[serde(default)]
    route: Option<String>,
    #[serde(default)]
    #[allow(dead_code)]
    velocity: Option<[f32; 3]>,
}

/// Parses the text of a JSONL route file; `stem` names routes that carry no name,
/// `game` is the map's (the player's box and view, see [`TargetState::stance`]).
pub fn parse(text: &str, stem: &str, game: Game) -> Result<Vec<Route>, String> {
    let mut routes: Vec<Route> = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let l: Line = serde_json::from_str(line).map_err(|e| format!("line {}: {e}", n + 1))?;
        if !l.t.is_finite() || !l.origin.iter().chain(&l.angles).all(|v| v.is_finite()) {
            return Err(format!("line {}: non-finite number", n + 1));
        }
        let name = l.route.clone();
        let new_route = match (routes.last(), &name) {
            (None, _) => true,
            (Some(r), Some(nm)) => &r.name != nm,
            _ => false,
        };
        if new_route {
            routes.push(Route {
                name: name.unwrap_or_else(|| stem.to_string()),
                states: Vec::new(),
            });
        }
        let r = routes.last_mut().unwrap();
        if let Some(prev) = r.states.last()
            && l.t <= prev.t
        {
            return Err(format!(
                "line {}: time {} does not increase (previous {})",
                n + 1,
                l.t,
                prev.t
            ));
        }
        r.states.push(TargetState {
            t: l.t,
            origin: l.origin,
            angles: l.angles,
            velocity: [0.0; 3],
            crouch: l.crouch,
            game,
        });
    }
    for r in &mut routes {
        for i in 1..r.states.len() {
            let (a, b) = (r.states[i - 1], r.states[i]);
            let dt = (b.t - a.t) as f32;
            r.states[i].velocity = [0, 1, 2].map(|k| (b.origin[k] - a.origin[k]) / dt);
        }
    }
    routes.retain(|r| r.states.len() >= 2);
    if routes.is_empty() {
        return Err("no route with at least two frames".into());
    }
    Ok(routes)
}

/// Writes routes in the same format (so generated routes can be replayed elsewhere).
pub fn write(routes: &[Route]) -> String {
    let mut out = String::new();
    for r in routes {
        for s in &r.states {
            out.push_str(
                &serde_json::json!({
                    "route": r.name, "t": s.t, "origin": s.origin, "angles": s.angles, "crouch": s.crouch
                })
                .to_string(),
            );
            out.push('\n');
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_routes_and_velocities() {
        let text = "# a playtest\n{\"t\":0,\"origin\":[0,0,36],\"angles\":[0,90,0]}\n\
                    {\"t\":0.5,\"origin\":[0,100,36],\"angles\":[0,90,0],\"crouch\":true}\n\n\
                    {\"route\":\"b\",\"t\":0,\"origin\":[5,5,36],\"angles\":[0,0,0]}\n\
                    {\"route\":\"b\",\"t\":1,\"origin\":[15,5,36],\"angles\":[0,0,0]}\n";
        let r = parse(text, "rec", Game::GoldSrc).unwrap();
        assert_eq!(r.len(), 2);
        assert_eq!(r[0].name, "rec");
        assert_eq!(r[0].states[1].velocity, [0.0, 200.0, 0.0]);
        assert!(r[0].states[1].crouch);
        assert_eq!(r[1].name, "b");
        let again = parse(&write(&r), "x", Game::GoldSrc).unwrap();
        assert_eq!(again.len(), 2);
        assert_eq!(again[1].states, r[1].states);
    }

    #[test]
    fn bad_lines_are_one_line_errors() {
        for bad in [
            "{\"t\":0}",
            "not json",
            "{\"t\":1,\"origin\":[0,0,0],\"angles\":[0,0,0]}\n{\"t\":0.5,\"origin\":[0,0,0],\"angles\":[0,0,0]}",
            "",
        ] {
            let e = parse(bad, "x", Game::GoldSrc).unwrap_err();
            assert!(!e.contains('\n'), "{e}");
        }
    }
}
