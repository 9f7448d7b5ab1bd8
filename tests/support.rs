//! Helpers shared by the cross-crate integration tests: locating the reference pack
//! `../shared/parol6` beside the repository, the bodies of the fuzz targets ([`fuzz_bodies`]),
//! shared by `fuzz/` and the stable corpus replay test, a fault-injecting serial peer
//! ([`fault_peer`]) with its hostile-board modes ([`hostile_board`]) for the adversarial session
//! and CLI tests, and a watch on the hypervisor's steal
//! time ([`steal_watch`]) for the timing tests.

pub mod fuzz_bodies;

use std::path::PathBuf;

#[cfg(unix)]
#[path = "support/fault_peer.rs"]
pub mod fault_peer;

#[path = "support/hostile_board.rs"]
pub mod hostile_board;

#[path = "support/steal_watch.rs"]
pub mod steal_watch;

/// The reference pack folder (`<repo>/../shared/parol6`), or `None` after printing a clear
/// skip notice when it is absent. CI always has it.
pub fn shared_dir() -> Option<PathBuf> {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let candidates =
        [std::env::var_os("PAROL6_SHARED").map(PathBuf::from), Some(repo.join("..").join("shared").join("parol6"))];
    for c in candidates.into_iter().flatten() {
        if c.join("ROBOT.md").is_file() {
            return Some(c);
        }
    }
    skip_notice(
        "SKIPPED: reference pack ../shared/parol6 not found beside the repository (set PAROL6_SHARED to its path)",
    );
    None
}

/// Prints a skip notice on the process's real stderr. The test harness captures `eprintln!`
/// of passing tests, and a skipped test must say so in the CI log.
pub fn skip_notice(message: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "{message}");
}

/// Reads and parses a JSON file of the reference pack.
pub fn read_json(path: &std::path::Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{} is not JSON: {e}", path.display()))
}
