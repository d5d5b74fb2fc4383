//! Printing that never decides whether the work gets done.
//!
//! `println!` panics when stdout is a closed pipe (`tool | head -1`) or a full disk
//! (`> /dev/full`), and a panic in the middle of a compile loses its output files. The
//! macros [`outln!`](crate::outln), [`out!`](crate::out) and [`errln!`](crate::errln)
//! write the same text but drop it when the stream cannot take it; the first failure
//! of each stream is remembered ([`stdout_failure`]) so a tool whose product *is* its
//! standard output (a report, a JSON object) can still say so and exit non-zero, while
//! a tool whose stdout is only a log carries on and writes its files.

use std::io::{self, Write};
use std::sync::Mutex;

/// The first error writing stdout (index 0) and stderr (index 1), as (kind, text).
static FAILED: Mutex<[Option<(io::ErrorKind, String)>; 2]> = Mutex::new([None, None]);

fn remember(stream: usize, e: &io::Error) {
    if let Ok(mut f) = FAILED.lock()
        && f[stream].is_none()
    {
        f[stream] = Some((e.kind(), e.to_string()));
    }
}

fn failed(stream: usize) -> bool {
    FAILED.lock().map(|f| f[stream].is_some()).unwrap_or(false)
}

/// Writes to stdout; after a failure every later write is skipped.
pub fn write_stdout(args: std::fmt::Arguments<'_>) {
    if failed(0) {
        return;
    }
    let mut out = io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.flush()) {
        remember(0, &e);
    }
}

/// Writes to stderr; after a failure every later write is skipped.
pub fn write_stderr(args: std::fmt::Arguments<'_>) {
    if failed(1) {
        return;
    }
    if let Err(e) = io::stderr().lock().write_fmt(args) {
        remember(1, &e);
    }
}

/// Why stdout stopped taking text, if it did: `None` while every write went through.
/// A closed pipe gives [`io::ErrorKind::BrokenPipe`]: the reader wanted no more, which
/// is no failure of the tool; anything else (a full disk) lost output.
pub fn stdout_failure() -> Option<(io::ErrorKind, String)> {
    FAILED.lock().ok().and_then(|f| f[0].clone())
}

/// For tools whose product is their stdout: an error message when the product was
/// lost for a reason other than the reader closing the pipe.
pub fn stdout_lost() -> Option<String> {
    match stdout_failure() {
        Some((io::ErrorKind::BrokenPipe, _)) | None => None,
        Some((_, text)) => Some(format!("cannot write to standard output: {text}")),
    }
}

/// `println!` that never panics (see the [module](self)).
#[macro_export]
macro_rules! outln {
    () => { $crate::console::write_stdout(format_args!("\n")) };
    ($($arg:tt)*) => {
        $crate::console::write_stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` that never panics (see the [module](self)).
#[macro_export]
macro_rules! out {
    ($($arg:tt)*) => { $crate::console::write_stdout(format_args!($($arg)*)) };
}

/// `eprintln!` that never panics (see the [module](self)).
#[macro_export]
macro_rules! errln {
    () => { $crate::console::write_stderr(format_args!("\n")) };
    ($($arg:tt)*) => {
        $crate::console::write_stderr(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `eprint!` that never panics (see the [module](self)).
#[macro_export]
macro_rules! err {
    ($($arg:tt)*) => { $crate::console::write_stderr(format_args!($($arg)*)) };
}
