//! The process's own resources: how many heaps the allocator keeps, handing freed memory back
//! to the system, the CPU time of a thread or of the whole process, and the priority of
//! background work.

/// Heaps (glibc "arenas") the allocator may keep; see [`limit_heap_arenas`].
pub const HEAP_ARENAS_MAX: i32 = 2;

/// Caps the allocator's heaps at [`HEAP_ARENAS_MAX`]. glibc gives a thread that allocates while
/// another holds the heap a heap of its own, up to eight per core, and keeps each for the life of
/// the process with whatever stays resident in it; a replay's decoding threads and the
/// rasterizer's threads left 10–25 MB more resident, different from run to run
/// (`bench render --plots`: 184–200 MB at the end, 173–180 MB with two heaps; frame times and
/// the replay's open time unchanged). Call first in `main`, before any thread starts. Does
/// nothing on other C libraries.
pub fn limit_heap_arenas() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets an allocator parameter; called before other threads exist.
    unsafe {
        libc::mallopt(libc::M_ARENA_MAX, HEAP_ARENAS_MAX);
    }
}

/// Hands the memory freed so far back to the system (glibc keeps freed pages of its heaps
/// resident otherwise). Loads decode and free hundreds of MB on several threads, and the first
/// frames of a window (shader compilation on a software rasterizer) leave several MB of freed
/// memory behind; called after those, not on a hot path. Does nothing on other C libraries.
pub fn release_freed_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only returns free pages of the allocator's heaps to the system.
    unsafe {
        libc::malloc_trim(0);
    }
}

/// What the allocator holds, bytes ([`heap_stats`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HeapStats {
    /// Handed out and not yet freed, in the heaps and in blocks mapped on their own.
    pub in_use_bytes: u64,
    /// Freed but kept by the heaps (resident unless handed back by [`release_freed_memory`]).
    pub free_bytes: u64,
    /// Of `in_use_bytes`, the large blocks mapped on their own.
    pub mapped_bytes: u64,
}

/// The allocator's own count of what it holds (glibc's `mallinfo2`, every heap); `None` on
/// other C libraries. Compared with the resident size over a long run, it tells memory the
/// program holds from memory freed and kept.
pub fn heap_stats() -> Option<HeapStats> {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        // SAFETY: mallinfo2 only reads the allocator's counters.
        let m = unsafe { libc::mallinfo2() };
        let bytes = |v: usize| u64::try_from(v).unwrap_or(u64::MAX);
        Some(HeapStats {
            in_use_bytes: bytes(m.uordblks).saturating_add(bytes(m.hblkhd)),
            free_bytes: bytes(m.fordblks),
            mapped_bytes: bytes(m.hblkhd),
        })
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    {
        None
    }
}

/// CPU time of the calling thread, ns.
pub fn thread_cpu_time_ns() -> Option<u64> {
    #[cfg(target_os = "linux")]
    {
        cpu_clock_ns(libc::CLOCK_THREAD_CPUTIME_ID)
    }
    #[cfg(not(target_os = "linux"))]
    {
        None
    }
}

/// CPU time of the whole process (all its threads), ns.
pub fn process_cpu_time_ns() -> Option<u64> {
    #[cfg(target_os = "linux")]
    {
        cpu_clock_ns(libc::CLOCK_PROCESS_CPUTIME_ID)
    }
    #[cfg(not(target_os = "linux"))]
    {
        None
    }
}

/// The host's 1-minute load average (Linux; `None` elsewhere or when unreadable): for reading
/// a benchmark's times, which a busy host stretches.
pub fn host_load_average_1min() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg").ok()?.split_whitespace().next()?.parse().ok()
}

/// How far below the window and the simulation background work runs: a nice value added to
/// the calling thread's own (Linux: 0 normal, 19 lowest). At +10 a busy background thread gets
/// about a tenth of a core that a window's thread wants, and the scheduler lets a waking
/// window thread run first.
pub const BACKGROUND_NICE_STEP: i32 = 10;

/// The lowest priority (highest nice value) a thread can have on Linux.
const NICE_LOWEST: i32 = 19;

/// Lowers the calling thread to background priority ([`BACKGROUND_NICE_STEP`] below where it
/// runs): for work that may take long and must not take the CPU from a frame or from the
/// simulation (a program's pre-flight, torque analyses, reading a recording, freeing large
/// data). Threads it starts inherit the priority. Linux only; elsewhere it does nothing and
/// returns `Ok`. Never raises a priority, so it needs no privilege.
pub fn run_in_background() -> std::io::Result<()> {
    #[cfg(target_os = "linux")]
    {
        let now = thread_nice()?;
        let lowered = (now + BACKGROUND_NICE_STEP).min(NICE_LOWEST).max(now);
        // SAFETY: gettid has no preconditions; setpriority only changes this thread's nice value
        // (on Linux a PRIO_PROCESS id that is a thread id names that thread alone).
        let rc = unsafe { libc::setpriority(libc::PRIO_PROCESS, libc::gettid() as libc::id_t, lowered) };
        if rc != 0 {
            return Err(std::io::Error::last_os_error());
        }
    }
    Ok(())
}

/// The calling thread's nice value (Linux; 0 elsewhere).
pub fn thread_nice() -> std::io::Result<i32> {
    #[cfg(target_os = "linux")]
    {
        // getpriority may return -1 as a value: errno, cleared first, tells an error
        // SAFETY: __errno_location points at this thread's errno; gettid and getpriority have
        // no preconditions.
        unsafe {
            *libc::__errno_location() = 0;
            let nice = libc::getpriority(libc::PRIO_PROCESS, libc::gettid() as libc::id_t);
            if nice == -1 && *libc::__errno_location() != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(nice)
        }
    }
    #[cfg(not(target_os = "linux"))]
    {
        Ok(0)
    }
}

#[cfg(target_os = "linux")]
fn cpu_clock_ns(clock: libc::clockid_t) -> Option<u64> {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant the kernel knows.
    let rc = unsafe { libc::clock_gettime(clock, &mut ts) };
    (rc == 0).then(|| (ts.tv_sec as u64).saturating_mul(1_000_000_000).saturating_add(ts.tv_nsec as u64))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A background thread runs lower than the thread that started it, and only it: the
    /// starter keeps its priority, and a thread the background one starts inherits the lower one.
    #[cfg(target_os = "linux")]
    #[test]
    fn background_work_runs_below_its_starter_and_passes_that_on() {
        let starter = thread_nice().expect("own nice value");
        let (own, child) = std::thread::spawn(|| {
            run_in_background().expect("lowering a thread needs no privilege");
            let own = thread_nice().expect("own nice value");
            let child = std::thread::spawn(|| thread_nice().expect("own nice value")).join().expect("child");
            (own, child)
        })
        .join()
        .expect("background thread");
        assert_eq!(own, (starter + BACKGROUND_NICE_STEP).min(NICE_LOWEST), "the background thread's nice");
        assert_eq!(child, own, "a thread started by background work inherits its priority");
        assert_eq!(thread_nice().expect("own nice value"), starter, "the starter keeps its priority");
    }

    /// The allocator's count follows a large block taken and given back (other test threads
    /// allocate too, so only the block's own size is checked, with room for their noise).
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    #[test]
    fn heap_stats_count_a_block_while_it_is_held() {
        const BLOCK: usize = 64 << 20;
        let before = heap_stats().expect("glibc counts its heaps");
        let block = vec![1u8; BLOCK];
        let held = heap_stats().expect("glibc counts its heaps");
        assert!(held.in_use_bytes >= before.in_use_bytes + BLOCK as u64 / 2, "{before:?} → {held:?}");
        assert!(held.mapped_bytes >= BLOCK as u64, "a block this large is mapped on its own: {held:?}");
        assert_eq!(block.iter().map(|&b| usize::from(b)).sum::<usize>(), BLOCK);
        drop(block);
        let after = heap_stats().expect("glibc counts its heaps");
        assert!(after.in_use_bytes + (BLOCK as u64 / 2) <= held.in_use_bytes, "{held:?} → {after:?}");
    }
}
