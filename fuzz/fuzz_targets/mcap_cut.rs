//! Issue 29: a valid recording of ours with chunk headers (and compressed bytes) changed and
//! cut at a byte, both chosen by the input: the MCAP reader and the replay never panic, and
//! every sample of every intact chunk is read.
//! Body: `parol6_tests::fuzz_bodies::mcap_cut` (replayed on stable by `tests/fuzz_corpora.rs`).
//! Run with `cargo +nightly fuzz run -s none -a mcap_cut` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::mcap_cut(data));
