//! Each map's time and memory budget, so one hostile map cannot cost a batch the
//! others' results.
//!
//! A map's work grows with its size, so its budget does: a base plus a share per
//! megabyte of the BSP file, times the user's `--budget` scale. Time is checked where
//! the stages report progress and between stages: over it, the running stage is
//! abandoned (its work is dropped as the stack unwinds, with no panic message) and the
//! map fails with the stage named. Memory is checked before the stages whose working
//! set is a known multiple of their input (the Delaunay stage of its samples, the
//! reduction of its graph): a map that would need more than its budget fails before
//! allocating it. A batch compiles each map with its own budget and goes on.

use super::CompileError;
use crate::progress::Progress;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Seconds every map may take, before the share for its size.
const BASE_SECONDS: f64 = 600.0;
/// Seconds per megabyte of map file.
const SECONDS_PER_MB: f64 = 300.0;
/// Bytes every map may use, before the share for its size.
const BASE_BYTES: f64 = 4.0 * (1u64 << 30) as f64;
/// Bytes per megabyte of map file.
const BYTES_PER_MB: f64 = 1.0 * (1u64 << 30) as f64;

/// A map's budget: when it must be done, and how much memory a stage may plan for.
#[derive(Debug, Clone, Copy)]
pub struct Budget {
    pub seconds: f64,
    pub bytes: f64,
    deadline: Instant,
}

/// The payload a stage unwinds with when the map's time is up.
#[derive(Debug)]
pub(crate) struct OutOfTime {
    pub stage: String,
    pub seconds: f64,
}

impl Budget {
    /// The budget of a map of `file_size` bytes at scale `scale` (`--budget`), starting
    /// now; `None` at scale 0 (no budget).
    pub fn for_map(file_size: u64, scale: f64) -> Option<Budget> {
        if !scale.is_finite() || scale <= 0.0 {
            return None;
        }
        let mb = file_size as f64 / (1u64 << 20) as f64;
        let seconds = scale * (BASE_SECONDS + SECONDS_PER_MB * mb);
        Some(Budget {
            seconds,
            bytes: scale * (BASE_BYTES + BYTES_PER_MB * mb),
            deadline: Instant::now() + Duration::from_secs_f64(seconds.min(1e9)),
        })
    }

    /// Abandons the running stage (unwinding to [`super::compile`]) when the time is up.
    pub(crate) fn check_time(&self, stage: &str) {
        if Instant::now() > self.deadline {
            std::panic::resume_unwind(Box::new(OutOfTime {
                stage: stage.to_string(),
                seconds: self.seconds,
            }));
        }
    }

    /// Fails when a stage would need `bytes` (its planned working set) over the budget.
    pub fn check_memory(
        &self,
        stage: &'static str,
        bytes: f64,
        what: &str,
    ) -> Result<(), CompileError> {
        if bytes > self.bytes {
            return Err(CompileError::OverBudget {
                stage,
                what: format!(
                    "{what} would need about {}, the budget is {}",
                    size(bytes),
                    size(self.bytes)
                ),
            });
        }
        Ok(())
    }
}

/// `bytes` for a person: GB to a tenth from 1 GB up, MB below.
fn size(bytes: f64) -> String {
    if bytes >= 1e9 {
        format!("{:.1} GB", bytes / 1e9)
    } else {
        format!("{:.0} MB", (bytes / 1e6).ceil())
    }
}

/// The progress display, with the time budget checked at every report: the stages
/// report a block of their work at a time (see [`crate::progress::Ticker`]), so a map
/// over its time stops within a block, in whatever stage it is.
pub(crate) struct Budgeted<'a> {
    pub inner: &'a dyn Progress,
    pub budget: Option<Budget>,
    /// The running stage's name (one of [`super::STAGE_NAMES`]), as the error names it.
    pub stage: Mutex<String>,
}

impl Progress for Budgeted<'_> {
    fn stage(&self, name: &str) {
        if let Ok(mut s) = self.stage.lock() {
            name.clone_into(&mut s);
        }
        self.inner.stage(name);
    }
    fn start(&self, label: &str, total: u64) {
        self.inner.start(label, total);
    }
    fn advance(&self, n: u64) {
        self.inner.advance(n);
        if let Some(b) = &self.budget {
            let stage = self.stage.lock().map(|s| s.clone()).unwrap_or_default();
            b.check_time(&stage);
        }
    }
    fn finish(&self) {
        self.inner.finish();
    }
}

/// Runs `work` as the stage `stage` of a map whose time is already up, and returns the
/// stage it stopped in, or `None` if it ran to its end: for the tests that each costly
/// stage stops inside itself, within a block of its work.
#[cfg(test)]
pub(crate) fn stopped_in(stage: &str, work: impl FnOnce(&dyn Progress)) -> Option<String> {
    let mut budget = Budget::for_map(0, 1.0).expect("a budget");
    budget.deadline = Instant::now() - Duration::from_secs(1);
    let budgeted = Budgeted {
        inner: &crate::progress::NoProgress,
        budget: Some(budget),
        stage: Default::default(),
    };
    budgeted.stage(stage);
    let run = std::panic::AssertUnwindSafe(|| work(&budgeted));
    let payload = std::panic::catch_unwind(run).err()?;
    Some(payload.downcast::<OutOfTime>().ok()?.stage)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_budget_grows_with_the_map_and_the_scale() {
        let small = Budget::for_map(100_000, 1.0).unwrap();
        let big = Budget::for_map(10 << 20, 1.0).unwrap();
        assert!(big.seconds > small.seconds && big.bytes > small.bytes);
        let double = Budget::for_map(100_000, 2.0).unwrap();
        assert!((double.seconds - 2.0 * small.seconds).abs() < 1e-9);
        assert!(Budget::for_map(100_000, 0.0).is_none());
        assert!(Budget::for_map(100_000, f64::NAN).is_none());
        assert!(
            small
                .check_memory("delaunay", small.bytes * 2.0, "x")
                .is_err()
        );
        assert!(
            small
                .check_memory("delaunay", small.bytes * 0.5, "x")
                .is_ok()
        );
        assert_eq!(size(2.46e9), "2.5 GB");
        assert_eq!(size(19.2e6), "20 MB");
    }

    #[test]
    fn a_stage_past_its_time_unwinds_with_its_name() {
        let mut b = Budget::for_map(0, 1.0).unwrap();
        b.deadline = Instant::now() - Duration::from_secs(1);
        let caught = std::panic::catch_unwind(|| b.check_time("reduce")).unwrap_err();
        let out = caught.downcast::<OutOfTime>().unwrap();
        assert_eq!(out.stage, "reduce");
    }
}
