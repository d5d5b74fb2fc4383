//! `flowtile-bake`: count tile sets, tile grids under boundary conditions,
//! bake tiling files, inspect and render them, edit tilings interactively.

mod cli;
mod edit;

fn main() {
    if let Err(e) = cli::run() {
        eprintln!("flowtile-bake: error: {e:#}");
        std::process::exit(1);
    }
}
