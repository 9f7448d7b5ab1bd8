//! The process's own resources: handing freed memory back to the system.

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
