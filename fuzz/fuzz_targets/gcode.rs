//! Feeds arbitrary text to the G-code import; programs it reads are exported and read again:
//! nothing may panic, errors name a line of the text, exported G-code reads back.
//! Body: `parol6_tests::fuzz_bodies::gcode` (replayed on stable by `tests/fuzz_corpora.rs`).
//! Run with `cargo +nightly fuzz run gcode` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::gcode(data));
