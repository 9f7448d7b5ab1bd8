//! Fuzz target `time_function`: arbitrary bytes to the program exchange format's reader and writer.
//! Body: `parol6_tests::fuzz_bodies::time_function` (replayed on stable by `tests/fuzz_corpora.rs`).
//! Run with `cargo +nightly fuzz run time_function` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::time_function(data));
