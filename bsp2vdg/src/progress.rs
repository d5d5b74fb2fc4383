//! Progress reporting for long stages, decoupled from how it is shown: the library
//! calls [`Progress`], the command line shows a bar on a terminal and plain percentage
//! lines in build logs and CI.

use std::sync::atomic::{AtomicU64, Ordering};

/// Receives progress of a stage. Implementations must be cheap to call from many threads.
pub trait Progress: Sync {
    /// A new stage begins with `total` units of work.
    fn start(&self, label: &str, total: u64);
    /// `n` more units are done.
    fn advance(&self, n: u64);
    /// The stage ended.
    fn finish(&self);
}

/// Shows nothing.
#[derive(Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {
    fn start(&self, _: &str, _: u64) {}
    fn advance(&self, _: u64) {}
    fn finish(&self) {}
}

/// Plain lines `label: 10%`, `label: 20%` … on stderr, for logs that are not terminals.
/// Stages shorter than a second print nothing: the log line at their end says enough.
#[derive(Debug, Default)]
pub struct PercentLines {
    state: std::sync::Mutex<(String, u64)>,
    started: std::sync::Mutex<Option<std::time::Instant>>,
    done: AtomicU64,
    last_tenth: AtomicU64,
    /// Add the estimated time left to each line (`-estimate`).
    estimate: bool,
}

impl PercentLines {
    /// Lines `label: 30% (about 12 s left)`, as the compile tools' `-estimate` shows.
    pub fn with_estimate() -> PercentLines {
        PercentLines {
            estimate: true,
            ..PercentLines::default()
        }
    }
}

impl Progress for PercentLines {
    fn start(&self, label: &str, total: u64) {
        if let Ok(mut s) = self.state.lock() {
            *s = (label.to_string(), total.max(1));
        }
        if let Ok(mut t) = self.started.lock() {
            *t = Some(std::time::Instant::now());
        }
        self.done.store(0, Ordering::Relaxed);
        self.last_tenth.store(0, Ordering::Relaxed);
    }

    fn advance(&self, n: u64) {
        let done = self.done.fetch_add(n, Ordering::Relaxed) + n;
        let elapsed = self
            .started
            .lock()
            .map(|t| t.map_or(0.0, |t| t.elapsed().as_secs_f64()))
            .unwrap_or(0.0);
        let quick = elapsed < 1.0;
        let Ok(s) = self.state.lock() else { return };
        if quick {
            self.last_tenth.store(done * 10 / s.1, Ordering::Relaxed);
            return;
        }
        let tenth = (done * 10 / s.1).min(10);
        let last = self.last_tenth.load(Ordering::Relaxed);
        if tenth > last
            && self
                .last_tenth
                .compare_exchange(last, tenth, Ordering::Relaxed, Ordering::Relaxed)
                .is_ok()
        {
            if self.estimate && tenth < 10 {
                let left = elapsed * (s.1 as f64 / done.max(1) as f64 - 1.0);
                toolbox::errln!(
                    "{}: {}% (about {:.0} s left)",
                    s.0,
                    tenth * 10,
                    left.max(0.0)
                );
            } else {
                toolbox::errln!("{}: {}%", s.0, tenth * 10);
            }
        }
    }

    fn finish(&self) {}
}
