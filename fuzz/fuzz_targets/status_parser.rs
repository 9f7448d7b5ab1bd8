//! Feeds arbitrary bytes to the streaming status parser and the frame decoders: none may
//! panic, and every frame the status parser returns must re-encode to a valid frame.
//! Body: `parol6_tests::fuzz_bodies::status_parser` (replayed on stable by `tests/fuzz_corpora.rs`).
//! Run with `cargo +nightly fuzz run status_parser` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::status_parser(data));
