//! Fuzz target `csv_table_compile`: what the `csv_table` reader accepts, planned (programs of up to 3
//! steps compiled to joint trajectories). Body: `parol6_tests::fuzz_bodies::csv_table_compile`,
//! replayed on stable by `tests/fuzz_corpora.rs` over the inputs of `csv_table`.
//! Run with `cargo +nightly fuzz run csv_table_compile fuzz/corpus/csv_table` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::csv_table_compile(data));
