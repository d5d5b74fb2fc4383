//! Headless screenshots of the demo session and backgrounds.

use super::*;
use crate::editor::commands::run_script;
use crate::spec::Problem;

fn demo() -> (Editor, EditorView) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../testdata/flowtiles");
    let text = std::fs::read_to_string(dir.join("river.toml")).unwrap();
    let mut ed = Editor::new(Problem::from_toml(&text).unwrap()).unwrap();
    let script = std::fs::read_to_string(dir.join("editor-demo.txt")).unwrap();
    // The demo saves and bakes into the working directory: not here.
    let script: String = script
        .lines()
        .filter(|l| !l.starts_with("save") && !l.starts_with("bake"))
        .map(|l| format!("{l}\n"))
        .collect();
    let mut view = EditorView::new("unused.toml".into(), "unused.ftb".into(), None);
    run_script(&mut ed, &script, Some(&mut view.settings)).unwrap();
    (ed, view)
}

/// The demo session's screenshot: a real picture (many colours, the
/// palette panel drawn), the same bytes from two fresh runs.
#[test]
fn headless_screenshots_are_pictures_and_deterministic() {
    let (mut ed, mut view) = demo();
    assert_eq!(view.settings.selected, Some((7, 3)));
    let a = screenshot(&mut ed, &mut view, 640, 400).unwrap();
    let (mut ed2, mut view2) = demo();
    let b = screenshot(&mut ed2, &mut view2, 640, 400).unwrap();
    assert_eq!(a, b, "two runs of the same session differ");
    let dec = png::Decoder::new(std::io::Cursor::new(&a));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (640, 400));
    let mut colours: Vec<[u8; 3]> = buf.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
    colours.sort_unstable();
    colours.dedup();
    assert!(colours.len() > 200, "only {} colours", colours.len());
    // Particles move: another time gives another picture.
    view.settings.time = 0.5;
    let c = screenshot(&mut ed, &mut view, 640, 400).unwrap();
    assert_ne!(a, c);
    assert!(screenshot(&mut ed, &mut view, 0, 10).is_err());
}

#[test]
fn backgrounds_read_from_png() {
    let dir = std::env::temp_dir().join(format!("ftb-bg-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut c = crate::render::Canvas::new(4, 3, [1.0, 0.0, 0.0]);
    c.fill_rect(0.0, 0.0, 1.0, 1.0, [0.0, 0.0, 1.0], 1.0);
    std::fs::write(dir.join("bg.png"), c.to_png().unwrap()).unwrap();
    let bg = Background::read_png(&dir.join("bg.png")).unwrap();
    assert_eq!((bg.width, bg.height, bg.rgb.len()), (4, 3, 36));
    assert_eq!(&bg.rgb[..3], &[0, 0, 255]);
    std::fs::write(dir.join("bad.png"), b"not a png").unwrap();
    assert!(Background::read_png(&dir.join("bad.png")).is_err());
    assert!(Background::read_png(&dir.join("missing.png")).is_err());
    let mut ed = Editor::blank(4, 3).unwrap();
    let mut view = EditorView::new("a.toml".into(), "a.ftb".into(), Some(bg));
    let png = screenshot(&mut ed, &mut view, 500, 300).unwrap();
    assert!(png.len() > 1000);
    std::fs::remove_dir_all(&dir).unwrap();
}
