//! Process priority, as the compile tools set it: ericw-tools runs at low priority by
//! default (`-lowpriority`) so an editor or a game stays responsive while maps compile;
//! VHLT has `-low` and `-high`. On Unix this is the nice value (low = 10, high = -5);
//! threads started afterwards (the worker pool) inherit it.

/// The requested priority.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Priority {
    Low,
    High,
}

/// Sets the priority of this process; an error says why it could not be set (raising
/// it needs privileges on Unix). Must run before the worker threads start.
#[cfg(unix)]
pub fn set(p: Priority) -> Result<(), String> {
    let nice = match p {
        Priority::Low => 10,
        Priority::High => -5,
    };
    // SAFETY: getpriority/setpriority take plain integers and touch no memory of ours.
    let current = unsafe { libc::getpriority(libc::PRIO_PROCESS, 0) };
    if p == Priority::Low && current >= nice {
        return Ok(()); // already at least as low (e.g. started under `nice -n 19`)
    }
    // SAFETY: as above.
    if unsafe { libc::setpriority(libc::PRIO_PROCESS, 0, nice) } == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error().to_string())
    }
}

/// Not supported here: the priority stays as it is.
#[cfg(not(unix))]
pub fn set(_: Priority) -> Result<(), String> {
    Err("setting the priority is not supported on this platform".into())
}
