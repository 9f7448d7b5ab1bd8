//! The process's own resources: how many heaps the allocator keeps, handing freed memory back
//! to the system, and the CPU time of a thread or of the whole process.

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

#[cfg(target_os = "linux")]
fn cpu_clock_ns(clock: libc::clockid_t) -> Option<u64> {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant the kernel knows.
    let rc = unsafe { libc::clock_gettime(clock, &mut ts) };
    (rc == 0).then(|| (ts.tv_sec as u64).saturating_mul(1_000_000_000).saturating_add(ts.tv_nsec as u64))
}
