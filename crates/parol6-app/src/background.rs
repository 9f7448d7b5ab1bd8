//! Background threads: work that may take long and that no frame waits for (a program's
//! pre-flight and its torque pass, the Dynamics panel's analyses, reading a recording, freeing
//! large data, writing the settings) runs below the window's and the simulation's priority
//! (`parol6_core::process::run_in_background`), so that on a two-core PC it does not take the
//! CPU from a frame. Threads that move the arm, talk to it or record it keep normal priority.

use std::thread::JoinHandle;

/// Starts `work` on a thread named `name` at background priority. Where the priority cannot be
/// lowered (not Linux, or refused) the work runs at normal priority: slower frames under load,
/// nothing else.
pub fn spawn<T: Send + 'static>(
    name: &str,
    work: impl FnOnce() -> T + Send + 'static,
) -> std::io::Result<JoinHandle<T>> {
    std::thread::Builder::new().name(name.to_string()).spawn(move || {
        if let Err(e) = parol6_core::process::run_in_background() {
            let name = std::thread::current().name().map(str::to_string).unwrap_or_default();
            tracing::debug!("{name}: runs at normal priority ({e})");
        }
        work()
    })
}

#[cfg(test)]
mod tests {
    /// A background thread runs below the thread that started it (Linux, where the nice value
    /// can be read).
    #[cfg(target_os = "linux")]
    #[test]
    fn a_background_thread_runs_below_its_starter() {
        let starter = parol6_core::process::thread_nice().expect("own nice value");
        let worker = super::spawn("parol6-test-background", parol6_core::process::thread_nice)
            .expect("thread")
            .join()
            .expect("joined")
            .expect("worker's nice value");
        assert!(worker > starter || starter == 19, "worker nice {worker}, starter {starter}");
    }
}
