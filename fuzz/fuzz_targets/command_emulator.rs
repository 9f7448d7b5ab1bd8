//! Feeds arbitrary bytes as the host → controller stream to the firmware receiver
//! (`CommandParser`) and drives the emulated board (`ControllerModel`) with every accepted
//! command, checking the receiver's and the board's invariants.
//! Body: `parol6_tests::fuzz_bodies::command_emulator` (replayed on stable by `tests/fuzz_corpora.rs`).
//! Run with `cargo +nightly fuzz run command_emulator` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::command_emulator(data));
