//! Fuzz target `time_function_compile`: what the `time_function` target reads, planned (moved to start at the TCP and compiled). Body:
//! `parol6_tests::fuzz_bodies::time_function_compile`, replayed on stable by `tests/fuzz_corpora.rs` over
//! the inputs of `time_function`.
//! Run with `cargo +nightly fuzz run time_function_compile fuzz/corpus/time_function` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::time_function_compile(data));
