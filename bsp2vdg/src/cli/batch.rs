//! Batch mode's scheduler: a fixed number of map slots, so a batch holds at most that
//! many maps in memory, whatever the maps do inside.
//!
//! A `par_iter` over the maps would not promise that: a rayon thread that waits for a
//! map's inner parallel work steals other jobs meanwhile, and the next map is such a job,
//! so a thread could start a second map on top of the one it waits for, holding both
//! maps' working sets at once. Here each slot is a plain thread that takes the next map
//! when its map is done; the maps' own parallel work still runs on rayon's pool, which
//! holds no map jobs to steal.

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Stack of each slot's thread: the same as a program's main thread gets, so a map
/// compiles in batch mode with the stack it has when compiled alone.
const SLOT_STACK_BYTES: usize = 8 << 20;

/// Runs `work` on every item, at most `slots` at a time, and returns the results in the
/// items' order. When the system refuses a thread, the slots already running take the
/// items on; when it refuses the first, that is the error. A panic in `work` is passed
/// on once every slot has stopped.
pub fn in_slots<T, R>(
    items: &[T],
    slots: usize,
    work: impl Fn(&T) -> R + Sync,
) -> std::io::Result<Vec<R>>
where
    T: Sync,
    R: Send,
{
    let slots = slots.clamp(1, items.len().max(1));
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<R>>> = Mutex::new((0..items.len()).map(|_| None).collect());
    std::thread::scope(|scope| {
        for slot in 0..slots {
            let (next, results, work) = (&next, &results, &work);
            let spawned = std::thread::Builder::new()
                .name(format!("map slot {slot}"))
                .stack_size(SLOT_STACK_BYTES)
                .spawn_scoped(scope, move || {
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(item) = items.get(i) else { break };
                        let r = work(item);
                        if let Ok(mut all) = results.lock() {
                            all[i] = Some(r);
                        }
                    }
                });
            match spawned {
                Ok(_) => {}
                Err(e) if slot == 0 => return Err(e),
                Err(_) => break,
            }
        }
        Ok(())
    })?;
    // Every slot ran until no item was left, so every result is there.
    Ok(results
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .into_iter()
        .flatten()
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;
    use std::time::Duration;

    #[test]
    fn no_more_items_run_at_once_than_there_are_slots_even_with_inner_parallel_work() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(4)
            .build()
            .unwrap();
        let running = AtomicUsize::new(0);
        let most = AtomicUsize::new(0);
        let items: Vec<u64> = (0..24).collect();
        let out = pool
            .install(|| {
                in_slots(&items, 2, |&x| {
                    let now = running.fetch_add(1, Ordering::SeqCst) + 1;
                    most.fetch_max(now, Ordering::SeqCst);
                    // Inner parallel work that waits: the moment a stealing scheduler would
                    // start another item on this thread.
                    let inner: u64 = (0..8u64)
                        .into_par_iter()
                        .map(|k| {
                            std::thread::sleep(Duration::from_millis(2));
                            k + x
                        })
                        .sum();
                    running.fetch_sub(1, Ordering::SeqCst);
                    inner
                })
            })
            .unwrap();
        assert!(
            most.load(Ordering::SeqCst) <= 2,
            "{} at once",
            most.into_inner()
        );
        let expected: Vec<u64> = items.iter().map(|x| 28 + 8 * x).collect();
        assert_eq!(out, expected, "results in the items' order");
    }

    #[test]
    fn one_slot_runs_the_items_in_order_and_an_empty_batch_is_empty() {
        let seen = Mutex::new(Vec::new());
        let out = in_slots(&[3, 1, 2], 1, |&x| {
            seen.lock().unwrap().push(x);
            x * 10
        })
        .unwrap();
        assert_eq!(out, vec![30, 10, 20]);
        assert_eq!(*seen.lock().unwrap(), vec![3, 1, 2]);
        assert!(in_slots(&[] as &[u8], 4, |&x| x).unwrap().is_empty());
    }
}
