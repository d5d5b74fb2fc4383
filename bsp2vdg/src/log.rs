//! The compile log, in the manner of map compile tools (hlcsg, qbsp, light): plain
//! lines on the console while the stages run, and the same lines appended to a `.log`
//! file beside the map as they are logged, so a build engineer can read what happened
//! after the fact, even when the compile was killed (out of memory, a build timeout).

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
pub struct Log {
    verbosity: Verbosity,
    /// Echo to stderr instead of stdout (when stdout carries JSON).
    to_stderr: bool,
    /// Prefix for every console line (batch mode: the map name).
    prefix: String,
    lines: Mutex<Vec<String>>,
    /// The log file lines are appended to as they are logged, with the prefix of each
    /// line there (a `-logfile` shared by the maps of a batch needs it).
    file: Option<(Mutex<std::fs::File>, String)>,
    /// Where console lines go instead of plain printing (a progress bar's
    /// `suspend`, so a line never breaks the bar or leaves a trail of it).
    console: Mutex<Option<ConsolePrinter>>,
}

/// Prints one console line.
pub type ConsolePrinter = Box<dyn Fn(&str) + Send + Sync>;

impl std::fmt::Debug for Log {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Log")
            .field("verbosity", &self.verbosity)
            .field("prefix", &self.prefix)
            .finish_non_exhaustive()
    }
}

impl Log {
    pub fn new(verbosity: Verbosity, to_stderr: bool) -> Log {
        Log {
            verbosity,
            to_stderr,
            prefix: String::new(),
            lines: Mutex::new(Vec::new()),
            file: None,
            console: Mutex::new(None),
        }
    }

    /// Prints console lines (already prefixed) through `print` from now on.
    pub fn set_console(&self, print: ConsolePrinter) {
        if let Ok(mut c) = self.console.lock() {
            *c = Some(print);
        }
    }

    /// Appends every line to `path` as it is logged (after a `---- header` line and
    /// the lines logged so far), each prefixed with `file_prefix`. The file is opened
    /// for appending, as the compile tools do: earlier runs' logs stay above.
    pub fn attach_file(
        &mut self,
        path: &Path,
        header: &str,
        file_prefix: &str,
    ) -> std::io::Result<()> {
        let mut f = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)?;
        let mut text = format!("---- {header}\n");
        for l in self.lines() {
            text.push_str(&format!("{file_prefix}{l}\n"));
        }
        f.write_all(text.as_bytes())?;
        self.file = Some((Mutex::new(f), file_prefix.to_string()));
        Ok(())
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
        let console = if show { self.console.lock().ok() } else { None };
        if let Some(console) = &console
            && let Some(print) = console.as_ref()
        {
            print(&format!("{}{line}", self.prefix));
        } else if show {
            if self.to_stderr {
                toolbox::errln!("{}{line}", self.prefix);
            } else {
                toolbox::outln!("{}{line}", self.prefix);
            }
        }
        if let Some((file, prefix)) = &self.file
            && let Ok(mut f) = file.lock()
        {
            // One write per line: a killed compile leaves every line logged so far.
            // A log that cannot be written never stops the compile.
            let _ = f.write_all(format!("{prefix}{line}\n").as_bytes());
        }
        if let Ok(mut lines) = self.lines.lock() {
            lines.push(line);
        }
    }

    /// Every line logged so far.
    pub fn lines(&self) -> Vec<String> {
        self.lines.lock().map(|l| l.clone()).unwrap_or_default()
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
