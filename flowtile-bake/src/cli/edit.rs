//! `flowtile-bake edit`: opens a spec, a region or a baked file in the
//! editor, runs a script headless, writes screenshots, or opens the window.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

use flowtile_bake::bake::{BakedTiling, write_atomic};
use flowtile_bake::editor::commands::run_script;
use flowtile_bake::editor::model::Editor;
use flowtile_bake::editor::view::{Background, EditorView, screenshot};
use flowtile_bake::spec::Problem;

// The options of `flowtile-bake edit`; its help text is the doc comment of
// `Command::Edit` in `cli/mod.rs`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// A spec (TOML, also from `region`) or a baked tiling (.ftb); none: a blank grid.
    pub input: Option<PathBuf>,
    /// Size WxH of the blank grid (without an input).
    #[arg(long, default_value = "16x12")]
    pub grid: String,
    /// Commands to apply, one per line (see `flowtile_bake::editor::commands`).
    #[arg(long)]
    pub script: Option<PathBuf>,
    /// Write a picture of the editor (PNG) after the script, rendered without a display.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Window and screenshot size in pixels, WxH.
    #[arg(long, default_value = "1280x800")]
    pub size: String,
    /// Picture (PNG) under the grid, spanning it (default: the spec's `background`).
    #[arg(long)]
    pub background: Option<PathBuf>,
    /// Where Save writes the spec (default: the input spec; for others NAME.edited.toml).
    #[arg(long)]
    pub save_as: Option<PathBuf>,
    /// Where Bake writes the tiling (default: the spec's name with .ftb).
    #[arg(long)]
    pub bake_as: Option<PathBuf>,
    /// Open the window after a script.
    #[arg(long)]
    pub window: bool,
    /// Close the window after this many seconds.
    #[arg(long)]
    pub seconds: Option<f64>,
}

/// A size `WxH` of `what` (an option), both at least 1.
fn size(text: &str, what: &str) -> Result<(u32, u32)> {
    super::wxh(text)
        .filter(|&(w, h)| w > 0 && h > 0)
        .with_context(|| format!("{what} {text:?}: expected WxH, e.g. 1280x800"))
}

/// Opens the input: the editor, the spec's own background and the default
/// save path.
fn open(input: Option<&Path>, grid: &str) -> Result<(Editor, Option<PathBuf>, PathBuf)> {
    let Some(path) = input else {
        let (w, h) = size(grid, "--grid")?;
        let ed = Editor::blank(w, h).context("blank grid")?;
        return Ok((ed, None, PathBuf::from("untitled.toml")));
    };
    let bytes = std::fs::read(path).with_context(|| format!("{}", path.display()))?;
    if bytes.starts_with(&flowtile_bake::bake::MAGIC) {
        let b = BakedTiling::from_bytes(&bytes).with_context(|| format!("{}", path.display()))?;
        let ed = Editor::from_baked(&b).with_context(|| format!("{}", path.display()))?;
        return Ok((ed, None, path.with_extension("edited.toml")));
    }
    let text = String::from_utf8(bytes).with_context(|| {
        format!(
            "{}: neither a spec (TOML) nor a baked tiling",
            path.display()
        )
    })?;
    let problem = Problem::from_toml(&text).with_context(|| format!("{}", path.display()))?;
    let bg = problem.background.as_ref().map(|b| {
        path.parent()
            .map(|d| d.join(b))
            .unwrap_or_else(|| PathBuf::from(b))
    });
    let ed = Editor::new(problem).with_context(|| format!("{}", path.display()))?;
    Ok((ed, bg, path.to_path_buf()))
}

/// Runs `flowtile-bake edit`.
pub fn run(a: Args) -> Result<()> {
    let (w, h) = size(&a.size, "--size")?;
    let (mut ed, spec_bg, default_save) = open(a.input.as_deref(), &a.grid)?;
    let bg_path = a.background.clone().or(spec_bg);
    let background = match &bg_path {
        Some(p) => Some(Background::read_png(p).map_err(anyhow::Error::msg)?),
        None => None,
    };
    let save = a.save_as.clone().unwrap_or(default_save);
    let bake = a
        .bake_as
        .clone()
        .unwrap_or_else(|| save.with_extension("ftb"));
    let mut view = EditorView::new(save, bake, background);
    if let Some(script) = &a.script {
        let text =
            std::fs::read_to_string(script).with_context(|| format!("{}", script.display()))?;
        let log = run_script(&mut ed, &text, Some(&mut view.settings))
            .map_err(|e| anyhow::anyhow!("{}: {e}", script.display()))?;
        out!("{log}")?;
    }
    if let Some(out) = &a.screenshot {
        let png = screenshot(&mut ed, &mut view, w, h).map_err(anyhow::Error::msg)?;
        write_atomic(out, &png).with_context(|| format!("{}", out.display()))?;
        outln!("wrote {} ({w}x{h})", out.display())?;
    }
    let headless = (a.script.is_some() || a.screenshot.is_some()) && !a.window;
    if headless {
        return Ok(());
    }
    if let Some(s) = a.seconds
        && !(s.is_finite() && s > 0.0)
    {
        bail!("--seconds {s}: give a positive number");
    }
    window(ed, view, (w, h), a.seconds)
}

#[cfg(feature = "window")]
fn window(ed: Editor, view: EditorView, (w, h): (u32, u32), seconds: Option<f64>) -> Result<()> {
    flowtile_bake::editor::app::run_window(
        ed,
        view,
        "flowtile-bake edit",
        [w as f32, h as f32],
        seconds,
    )
    .map_err(anyhow::Error::msg)
}

#[cfg(not(feature = "window"))]
fn window(_: Editor, _: EditorView, _: (u32, u32), _: Option<f64>) -> Result<()> {
    bail!(
        "this flowtile-bake was built without the window (cargo feature `window`); --script and --screenshot work headless"
    )
}
