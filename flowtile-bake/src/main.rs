//! `flowtile-bake`: count tile sets, tile grids under boundary conditions,
//! bake tiling files, inspect and render them, edit tilings interactively.

/// `println!` that returns the write error instead of panicking, so that a
/// reader closing the pipe early (`flowtile-bake info F | head -1`) ends the
/// program quietly (see [`main`]).
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($arg)*)
    }};
}

/// `print!` counterpart of [`outln!`].
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        write!(std::io::stdout().lock(), $($arg)*)
    }};
}

mod cli;

fn main() {
    if let Err(e) = cli::run() {
        // Like other command-line tools (ripgrep, coreutils): a reader
        // that stopped reading is not an error of ours.
        if broken_pipe(&e) {
            std::process::exit(0);
        }
        toolbox::errln!("flowtile-bake: error: {e:#}");
        std::process::exit(1);
    }
}

/// True when the error comes from writing to a closed pipe.
fn broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}
