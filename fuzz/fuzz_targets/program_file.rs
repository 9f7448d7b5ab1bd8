//! Feeds arbitrary bytes to the program file parser, writes parsed programs back and reads
//! them again, and runs small ones through the pre-flight: nothing may panic.
//! Body: `parol6_tests::fuzz_bodies::program_file` (replayed on stable by `tests/fuzz_corpora.rs`).
//! Run with `cargo +nightly fuzz run program_file` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::program_file(data));
