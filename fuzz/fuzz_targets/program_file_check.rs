//! Fuzz target `program_file_check`: what the `program_file` target reads, checked (programs of up to 6 steps through the whole pre-flight). Body:
//! `parol6_tests::fuzz_bodies::program_file_check`, replayed on stable by `tests/fuzz_corpora.rs` over
//! the inputs of `program_file`.
//! Run with `cargo +nightly fuzz run program_file_check fuzz/corpus/program_file` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::program_file_check(data));
