//! What every stage of a compile is handed: the options, the log, the progress display
//! and the statistics with the stages' named timers, so that timing a stage is one
//! call in the driver instead of a clock and a push in every stage.

use super::Stats;
use crate::log::Log;
use crate::options::CompileOptions;
use crate::progress::Progress;
use std::time::Instant;

/// A compile's context.
pub struct Context<'a> {
    pub options: &'a CompileOptions,
    pub log: &'a Log,
    pub progress: &'a dyn Progress,
    pub stats: Stats,
    /// The standing places the reduction kept inside the volume (player origins on the
    /// floors of its grid), for the check of the written graph's coverage; `None` until
    /// the reduction ran.
    pub standing: Option<Vec<[f64; 3]>>,
    /// The map's budget, if it has one ([`super::Budget`]).
    pub budget: Option<super::Budget>,
    /// When the compile began.
    began: Instant,
    /// When the running stage began.
    stage_began: Instant,
}

impl<'a> Context<'a> {
    pub fn new(options: &'a CompileOptions, log: &'a Log, progress: &'a dyn Progress) -> Self {
        let now = Instant::now();
        Context {
            options,
            log,
            progress,
            stats: Stats::default(),
            standing: None,
            budget: None,
            began: now,
            stage_began: now,
        }
    }

    /// Runs `stage` as the stage `name`: its seconds are recorded under that name in
    /// [`Stats::seconds`], in the order the stages ran.
    pub fn stage<T>(&mut self, name: &'static str, stage: impl FnOnce(&mut Self) -> T) -> T {
        if let Some(b) = &self.budget {
            b.check_time(name);
        }
        self.stage_began = Instant::now();
        self.progress.stage(name);
        let out = stage(self);
        self.progress.finish();
        let seconds = self.stage_seconds();
        self.stats.seconds.push((name, seconds));
        out
    }

    /// Seconds since the running stage began (for its closing log line).
    pub fn stage_seconds(&self) -> f64 {
        self.stage_began.elapsed().as_secs_f64()
    }

    /// Seconds since the compile began.
    pub fn total_seconds(&self) -> f64 {
        self.began.elapsed().as_secs_f64()
    }
}
