//! The compile log, in the manner of map compile tools (hlcsg, qbsp, light): plain
//! lines on the console while the stages run, and the same lines appended to a `.log`
//! file beside the map, so a build engineer can read what happened after the fact.

use std::io::Write;
use std::path::Path;
use std::sync::Mutex;

/// How much to print.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verbosity {
    Quiet,
    Normal,
    Verbose,
}

/// Collects log lines and echoes them to the console.
#[derive(Debug)]
pub struct Log {
    verbosity: Verbosity,
    /// Echo to stderr instead of stdout (when stdout carries JSON).
    to_stderr: bool,
    /// Prefix for every console line (batch mode: the map name).
    prefix: String,
    lines: Mutex<Vec<String>>,
}

impl Log {
    pub fn new(verbosity: Verbosity, to_stderr: bool) -> Log {
        Log {
            verbosity,
            to_stderr,
            prefix: String::new(),
            lines: Mutex::new(Vec::new()),
        }
    }

    /// Prefixes console lines with `[name] ` (the file log stays unprefixed).
    pub fn with_prefix(mut self, name: &str) -> Log {
        self.prefix = format!("[{name}] ");
        self
    }

    pub fn verbosity(&self) -> Verbosity {
        self.verbosity
    }

    /// A line every run shows.
    pub fn info(&self, line: impl Into<String>) {
        self.emit(line.into(), self.verbosity != Verbosity::Quiet);
    }

    /// A line shown with `-verbose` (always written to the log file).
    pub fn detail(&self, line: impl Into<String>) {
        self.emit(line.into(), self.verbosity == Verbosity::Verbose);
    }

    /// A warning: shown unless quiet.
    pub fn warn(&self, line: impl Into<String>) {
        self.emit(
            format!("WARNING: {}", line.into()),
            self.verbosity != Verbosity::Quiet,
        );
    }

    /// A line for the log file only.
    pub fn record(&self, line: impl Into<String>) {
        self.emit(line.into(), false);
    }

    fn emit(&self, line: String, show: bool) {
        if show {
            if self.to_stderr {
                eprintln!("{}{line}", self.prefix);
            } else {
                println!("{}{line}", self.prefix);
            }
        }
        if let Ok(mut lines) = self.lines.lock() {
            lines.push(line);
        }
    }

    /// Every line logged so far.
    pub fn lines(&self) -> Vec<String> {
        self.lines.lock().map(|l| l.clone()).unwrap_or_default()
    }

    /// Appends the lines to `path` under a header line with the command.
    pub fn append_to(&self, path: &Path, header: &str) -> std::io::Result<()> {
        let mut f = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)?;
        let mut text = format!("---- {header}\n");
        for l in self.lines() {
            text.push_str(&l);
            text.push('\n');
        }
        f.write_all(text.as_bytes())
    }
}

/// Formats seconds the way the log shows them.
pub fn secs(s: f64) -> String {
    if s < 10.0 {
        format!("{s:.2} s")
    } else {
        format!("{s:.1} s")
    }
}
