//! Fuzz target `commander_compile`: what the `commander` reader accepts, planned (programs of up to 3
//! steps compiled to joint trajectories). Body: `parol6_tests::fuzz_bodies::commander_compile`,
//! replayed on stable by `tests/fuzz_corpora.rs` over the inputs of `commander`.
//! Run with `cargo +nightly fuzz run commander_compile fuzz/corpus/commander` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::commander_compile(data));
