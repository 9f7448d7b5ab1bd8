//! The atomic writer (`parol6_core::fsio`) under injected I/O errors: short writes, a full disk
//! at any byte, a failed fsync or rename, the encoder failing. The old file stays intact or is
//! fully replaced, never partly, and no temporary file is left.
//! Body: `parol6_tests::fuzz_bodies::atomic_writer` (replayed on stable by `tests/fuzz_corpora.rs`).
//! Run with `cargo +nightly fuzz run atomic_writer` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::atomic_writer(data));
