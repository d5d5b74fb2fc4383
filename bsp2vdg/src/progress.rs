//! Progress reporting for long stages, decoupled from how it is shown: the library
//! calls [`Progress`], the command line shows a bar on a terminal and plain percentage
//! lines in build logs and CI.

use std::sync::atomic::{AtomicU64, Ordering};

/// Receives progress of a stage. Implementations must be cheap to call from many threads.
pub trait Progress: Sync {
    /// A stage of the pipeline begins (a [`STAGE_SHARES`] name), whether or not it
    /// reports progress of its own: displays that estimate the time left of the whole
    /// compile weigh the stages by their shares.
    fn stage(&self, _name: &str) {}
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

/// A stage's work items, reported to a [`Progress`] a block at a time. Each worker
/// counts its own items ([`Ticker::local`]) and reports a block when it has one, and
/// the rest when it is done: the inner loop pays an increment per item and nothing is
/// shared between the workers but the reports. The reports are where a compile's time
/// budget is checked, so a stage whose every loop ticks stops within one block of its
/// deadline.
pub struct Ticker<'a> {
    progress: &'a dyn Progress,
    block: u64,
}

impl<'a> Ticker<'a> {
    /// Items a block holds unless the stage says otherwise: small enough that a block
    /// of the slowest items (a guard face, ~20 µs) takes well under a second.
    pub const BLOCK: u64 = 1024;

    /// Starts `label` with `total` items on `progress`, reported every `block` items.
    pub fn start(progress: &'a dyn Progress, label: &str, total: u64, block: u64) -> Self {
        progress.start(label, total);
        Ticker {
            progress,
            block: block.max(1),
        }
    }

    /// Counts into the stage `progress` already started (a part of its work).
    pub fn within(progress: &'a dyn Progress, block: u64) -> Self {
        Ticker {
            progress,
            block: block.max(1),
        }
    }

    /// One worker's count (for rayon's `map_init`, or a serial loop).
    pub fn local(&self) -> LocalTicker<'_> {
        LocalTicker {
            ticker: self,
            count: 0,
        }
    }
}

/// One worker's items of a [`Ticker`]: a block is reported when full, the rest when
/// the worker drops it.
pub struct LocalTicker<'t> {
    ticker: &'t Ticker<'t>,
    count: u64,
}

impl LocalTicker<'_> {
    /// One more item is done.
    pub fn tick(&mut self) {
        self.count += 1;
        if self.count == self.ticker.block {
            self.count = 0;
            self.ticker.progress.advance(self.ticker.block);
        }
    }
}

impl Drop for LocalTicker<'_> {
    fn drop(&mut self) {
        // Not while unwinding: the budget check in the report would unwind again.
        if self.count > 0 && !std::thread::panicking() {
            self.ticker.progress.advance(self.count);
        }
    }
}

/// Plain lines `label: 10%`, `label: 20%` … on stderr, for logs that are not terminals.
/// Stages shorter than a second print nothing: the log line at their end says enough.
#[derive(Debug, Default)]
pub struct PercentLines {
    state: std::sync::Mutex<(String, u64)>,
    /// The whole compile's progress, for `-estimate`.
    clock: std::sync::Mutex<CompileClock>,
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
    fn stage(&self, name: &str) {
        if let Ok(mut c) = self.clock.lock() {
            c.stage(name);
        }
    }

    fn start(&self, label: &str, total: u64) {
        if let Ok(mut c) = self.clock.lock() {
            c.start(total);
        }
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
        // The estimate is read at every report, so its smoothing sees them all.
        let left = self.clock.lock().ok().and_then(|mut c| {
            c.advance(n);
            if self.estimate {
                c.seconds_left()
            } else {
                None
            }
        });
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
            if let Some(left) = left.filter(|_| tenth < 10) {
                toolbox::errln!(
                    "{}: {}% (about {} left of the compile)",
                    s.0,
                    tenth * 10,
                    format_left(left)
                );
            } else {
                toolbox::errln!("{}: {}%", s.0, tenth * 10);
            }
        }
    }

    fn finish(&self) {}
}

/// The stages of a compile in the order they run (the names of
/// [`crate::pipeline::Context::stage`]), each with its share of a whole compile's time:
/// the medians over the per-stage seconds measured on c1a0, lq_e0m2 and de_dust2
/// (docs/measurements/2026-12-02-compile-speed.md, "Whole compiles, per stage"); load and
/// write, not in that table, take well under a percent. The estimate of the time left
/// weighs the work done by these shares, so a stage that reports no progress of its own
/// still moves the compile on by its share when it ends.
pub const STAGE_SHARES: [(&str, f64); 10] = [
    ("load", 0.005),
    ("sample", 0.011),
    ("delaunay", 0.017),
    ("voronoi", 0.049),
    ("guard", 0.036),
    ("reduce", 0.799),
    ("wall_raise", 0.047),
    ("check", 0.011),
    ("corner_check", 0.012),
    ("write", 0.005),
];

/// The fraction of a whole compile done when `stage` is `within` (0 to 1) done: the
/// shares of the stages before it plus `within` of its own, over the sum of all shares.
/// An unknown stage counts as the last one.
pub fn compile_fraction(stage: &str, within: f64) -> f64 {
    let total: f64 = STAGE_SHARES.iter().map(|s| s.1).sum();
    let at = STAGE_SHARES
        .iter()
        .position(|s| s.0 == stage)
        .unwrap_or(STAGE_SHARES.len() - 1);
    let before: f64 = STAGE_SHARES[..at].iter().map(|s| s.1).sum();
    let within = if within.is_finite() {
        within.clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((before + within * STAGE_SHARES[at].1) / total).clamp(0.0, 1.0)
}

/// The time left of a whole compile, estimated from the work done and smoothed, so the
/// estimate a person reads moves steadily instead of jumping with every stage whose share
/// of the work differs from its share of the time on this map.
///
/// Fed readings (seconds since the compile began, fraction of the compile done), it keeps
/// an exponentially smoothed rate of work (fraction per second, time constant
/// [`TimeLeft::SMOOTHING_SHARE`] of the seconds elapsed) starting from the average rate so far, and shows
/// (1 − done) / rate, except that one shown value never differs from the previous one,
/// counted down by the seconds between them, by more than [`TimeLeft::MAX_STEP`].
/// Readings closer together than [`TimeLeft::MIN_INTERVAL`] count the shown value down
/// without a new estimate. No estimate is shown before [`TimeLeft::MIN_ELAPSED`] seconds,
/// when the rate is still mostly start-up.
#[derive(Debug, Clone, Default)]
pub struct TimeLeft {
    /// The smoothed rate of work, fraction per second.
    rate: Option<f64>,
    /// The reading the rate was last updated with.
    last: Option<(f64, f64)>,
    /// The value last shown and when.
    shown: Option<(f64, f64)>,
}

impl TimeLeft {
    /// Seconds before the first estimate.
    pub const MIN_ELAPSED: f64 = 2.0;
    /// Seconds between two estimates.
    pub const MIN_INTERVAL: f64 = 0.5;
    /// The time constant of the rate's exponential smoothing, as a share of the seconds
    /// elapsed (a 10 s compile forgets its first seconds quicker than a 10 min one),
    /// at least [`TimeLeft::MIN_INTERVAL`].
    pub const SMOOTHING_SHARE: f64 = 0.3;
    /// The factor one estimate may differ from the previous one counted down.
    pub const MAX_STEP: f64 = 1.25;

    pub fn new() -> TimeLeft {
        TimeLeft::default()
    }

    /// The seconds left after the reading (`elapsed` seconds, `fraction` of the compile
    /// done), or `None` while it is too early to say.
    pub fn update(&mut self, elapsed: f64, fraction: f64) -> Option<f64> {
        if !elapsed.is_finite() || !fraction.is_finite() {
            return self.counted_down(elapsed);
        }
        // Work done never goes back.
        let fraction = fraction.clamp(0.0, 1.0).max(self.last.map_or(0.0, |l| l.1));
        if fraction >= 1.0 {
            self.last = Some((elapsed, 1.0));
            self.shown = Some((0.0, elapsed));
            return Some(0.0);
        }
        if elapsed < Self::MIN_ELAPSED || fraction <= 0.0 {
            if self.last.is_none() {
                self.last = Some((elapsed, fraction));
            }
            return self.counted_down(elapsed);
        }
        let rate = match (self.rate, self.last) {
            (Some(rate), Some((t0, f0))) => {
                let dt = elapsed - t0;
                if dt < Self::MIN_INTERVAL {
                    return self.counted_down(elapsed);
                }
                let recent = (fraction - f0) / dt;
                let tau = (Self::SMOOTHING_SHARE * elapsed).max(Self::MIN_INTERVAL);
                rate + (1.0 - (-dt / tau).exp()) * (recent - rate)
            }
            _ => fraction / elapsed,
        };
        self.rate = Some(rate);
        self.last = Some((elapsed, fraction));
        let raw = if rate > 0.0 {
            (1.0 - fraction) / rate
        } else {
            f64::INFINITY
        };
        let left = match self.shown {
            Some((shown, at)) => {
                let expected = (shown - (elapsed - at)).max(0.0);
                raw.clamp(
                    expected / Self::MAX_STEP,
                    expected.max(1.0) * Self::MAX_STEP,
                )
            }
            None if raw.is_finite() => raw,
            None => return None,
        };
        self.shown = Some((left, elapsed));
        Some(left)
    }

    /// The last value shown, counted down to `elapsed`.
    fn counted_down(&self, elapsed: f64) -> Option<f64> {
        self.shown.map(|(shown, at)| {
            let passed = if elapsed.is_finite() {
                elapsed - at
            } else {
                0.0
            };
            (shown - passed.max(0.0)).max(0.0)
        })
    }
}

/// Seconds left as a person reads them: `12 s`, `3 min 05 s`, `1 h 02 min`.
pub fn format_left(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    if s < 60 {
        format!("{s} s")
    } else if s < 3600 {
        format!("{} min {:02} s", s / 60, s % 60)
    } else {
        format!("{} h {:02} min", s / 3600, s % 3600 / 60)
    }
}

/// Where a compile is, for the estimate of its time left: the running stage (its
/// [`STAGE_SHARES`] name), the progress within it, and the smoothed estimate.
#[derive(Debug)]
pub struct CompileClock {
    began: std::time::Instant,
    stage: String,
    total: u64,
    done: u64,
    left: TimeLeft,
}

impl Default for CompileClock {
    fn default() -> Self {
        CompileClock {
            began: std::time::Instant::now(),
            stage: String::new(),
            total: 1,
            done: 0,
            left: TimeLeft::new(),
        }
    }
}

impl CompileClock {
    /// A stage of the pipeline begins (its progress within is 0 until it reports).
    pub fn stage(&mut self, name: &str) {
        self.stage = name.to_string();
        self.total = 1;
        self.done = 0;
    }

    /// The running stage reports `total` units of work.
    pub fn start(&mut self, total: u64) {
        self.total = total.max(1);
        self.done = 0;
    }

    pub fn advance(&mut self, n: u64) {
        self.done = self.done.saturating_add(n).min(self.total);
    }

    /// The fraction of the whole compile done.
    pub fn fraction(&self) -> f64 {
        compile_fraction(&self.stage, self.done as f64 / self.total as f64)
    }

    /// The estimated seconds left of the whole compile, now.
    pub fn seconds_left(&mut self) -> Option<f64> {
        let elapsed = self.began.elapsed().as_secs_f64();
        let fraction = self.fraction();
        self.left.update(elapsed, fraction)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Readings every 0.1 s of a compile whose stages take `seconds` each (in the order of
    /// [`STAGE_SHARES`]); a stage that reports progress (`units`) moves evenly, the others
    /// only when they end, as in the pipeline.
    fn readings(seconds: &[f64; 10], reports: &[bool; 10]) -> Vec<(f64, f64)> {
        let total: f64 = seconds.iter().sum();
        let mut out = Vec::new();
        let mut t = 0.0;
        while t < total {
            let (mut at, mut begun) = (0, 0.0);
            while at < 9 && begun + seconds[at] <= t {
                begun += seconds[at];
                at += 1;
            }
            let within = if reports[at] {
                (t - begun) / seconds[at]
            } else {
                0.0
            };
            out.push((t, compile_fraction(STAGE_SHARES[at].0, within)));
            t += 0.1;
        }
        out
    }

    /// The pipeline: only sampling, the Voronoi stage and the reduction report progress,
    /// the first two as one unit.
    const REPORTS: [bool; 10] = [
        false, false, false, false, false, true, false, false, false, false,
    ];

    #[test]
    fn the_fraction_follows_the_stage_shares() {
        assert_eq!(compile_fraction("load", 0.0), 0.0);
        assert!((compile_fraction("write", 1.0) - 1.0).abs() < 1e-12);
        let before_reduce = compile_fraction("reduce", 0.0);
        let after_reduce = compile_fraction("wall_raise", 0.0);
        assert!((after_reduce - before_reduce - 0.799 / 0.992).abs() < 1e-9);
        assert_eq!(
            compile_fraction("reduce", 0.5),
            compile_fraction("reduce", 0.5)
        );
        assert_eq!(compile_fraction("reduce", f64::NAN), before_reduce);
        let mut last = 0.0;
        for (name, _) in STAGE_SHARES {
            let f = compile_fraction(name, 0.0);
            assert!(f >= last, "{name}");
            last = f;
        }
    }

    #[test]
    fn a_steady_compile_is_estimated_right() {
        // Every stage takes exactly its share of 60 s.
        let seconds = STAGE_SHARES.map(|s| s.1 * 60.0 / 0.992);
        let mut left = TimeLeft::new();
        let total: f64 = seconds.iter().sum();
        for (t, f) in readings(&seconds, &[true; 10]) {
            let shown = left.update(t, f);
            if t < TimeLeft::MIN_ELAPSED {
                assert_eq!(shown, None, "no estimate at {t:.1} s");
            } else {
                let shown = shown.expect("an estimate");
                assert!(
                    (shown - (total - t)).abs() < 0.02 * total,
                    "at {t:.1} s: {shown:.2} s left, truly {:.2}",
                    total - t
                );
            }
        }
    }

    /// The report of issue 44: an 8.8 s compile whose stages do not take their usual
    /// shares (a long Voronoi stage that reports nothing, a reduction faster than usual),
    /// estimated from each stage's own rate, jumps 64 s → 2 min → 38 s → 2 s. The estimate
    /// of the whole compile moves by at most MAX_STEP between updates and ends close.
    #[test]
    fn an_uneven_compile_is_estimated_without_jumps() {
        let mut seconds = STAGE_SHARES.map(|s| s.1 * 8.8 / 0.992);
        // Stage times within the spread of the measured ones.
        seconds[3] *= 2.0; // voronoi
        seconds[4] *= 1.5; // guard
        seconds[5] *= 0.8; // reduce
        let scale = 8.8 / seconds.iter().sum::<f64>();
        let seconds = seconds.map(|s| s * scale);
        let total: f64 = seconds.iter().sum();
        let readings = readings(&seconds, &REPORTS);
        // The naive estimate from the work done (no smoothing) jumps: the test's
        // compile is as uneven as the report's.
        let naive: Vec<f64> = readings
            .iter()
            .filter(|(t, f)| *t >= TimeLeft::MIN_ELAPSED && *f > 0.0)
            .map(|(t, f)| t * (1.0 - f) / f)
            .collect();
        let worst_naive = naive
            .windows(2)
            .map(|w| (w[1] / w[0]).max(w[0] / w[1]))
            .fold(1.0, f64::max);
        assert!(
            worst_naive > 2.0,
            "naive estimates moved by {worst_naive:.2}x at most"
        );

        let mut left = TimeLeft::new();
        let mut last: Option<(f64, f64)> = None;
        for &(t, f) in &readings {
            let Some(shown) = left.update(t, f) else {
                continue;
            };
            if let Some((before, at)) = last {
                let expected = (before - (t - at)).max(0.0);
                assert!(
                    shown <= expected.max(1.0) * TimeLeft::MAX_STEP + 1e-9
                        && shown >= expected / TimeLeft::MAX_STEP - 1e-9,
                    "at {t:.1} s the estimate went from {before:.2} s ({expected:.2} counted down) to {shown:.2} s"
                );
            }
            if t > 0.8 * total {
                assert!(
                    (shown - (total - t)).abs() < 0.15 * total,
                    "at {t:.1} s: {shown:.2} s left, truly {:.2}",
                    total - t
                );
            }
            last = Some((shown, t));
        }
        assert!(last.is_some(), "no estimate shown");
        assert_eq!(left.update(total, 1.0), Some(0.0));
    }

    #[test]
    fn odd_readings_give_no_odd_estimates() {
        let mut left = TimeLeft::new();
        assert_eq!(left.update(f64::NAN, 0.5), None);
        assert_eq!(left.update(3.0, f64::INFINITY), None);
        assert!(
            left.update(3.0, 0.5)
                .is_some_and(|s| (s - 3.0).abs() < 1e-9)
        );
        // Work done never goes back; a reading too soon counts the estimate down.
        let soon = left.update(3.2, 0.1).unwrap();
        assert!((soon - 2.8).abs() < 1e-9);
        assert!(left.update(4.0, 0.2).unwrap().is_finite());
        assert_eq!(format_left(59.4), "59 s");
        assert_eq!(format_left(125.0), "2 min 05 s");
        assert_eq!(format_left(3725.0), "1 h 02 min");
    }
}
