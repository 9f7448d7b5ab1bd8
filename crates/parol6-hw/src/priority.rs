//! Scheduling priority for the real-time threads (the session and the emulator): a real-time
//! class where the OS allows it, else a raised nice value; refusals (EPERM for an ordinary
//! user) are ignored — the threads then run at normal priority.

/// Real-time priority asked for (SCHED_FIFO, 1–99; low, so it never starves the kernel).
const FIFO_PRIORITY: i32 = 10;
/// Nice value asked for when the real-time class is refused.
const RAISED_NICE: i32 = -10;

/// What the OS granted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Granted {
    /// SCHED_FIFO.
    RealTime,
    /// A lower nice value.
    Raised,
    /// Nothing (normal priority).
    Normal,
}

/// Raises the calling thread's priority as far as allowed.
pub fn raise_current_thread() -> Granted {
    #[cfg(target_os = "linux")]
    {
        let param = libc::sched_param { sched_priority: FIFO_PRIORITY };
        // SAFETY: pthread_self() is the calling thread; `param` is a valid sched_param.
        let rc = unsafe { libc::pthread_setschedparam(libc::pthread_self(), libc::SCHED_FIFO, &param) };
        if rc == 0 {
            return Granted::RealTime;
        }
        // SAFETY: gettid has no preconditions.
        let tid = unsafe { libc::gettid() };
        // SAFETY: setpriority on this thread's id (Linux: per-thread nice); no pointers.
        let rc = unsafe { libc::setpriority(libc::PRIO_PROCESS, tid as libc::id_t, RAISED_NICE) };
        if rc == 0 {
            return Granted::Raised;
        }
        tracing::debug!("thread priority not raised: {}", std::io::Error::last_os_error());
        Granted::Normal
    }
    #[cfg(not(target_os = "linux"))]
    {
        Granted::Normal
    }
}
