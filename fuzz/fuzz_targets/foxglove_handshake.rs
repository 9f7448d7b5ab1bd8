//! Fuzz target `foxglove_handshake`: any bytes as a WebSocket upgrade request's HTTP head,
//! through the Foxglove subprotocol renaming of the live server's front door. Body:
//! `parol6_tests::fuzz_bodies::foxglove_handshake`, replayed on stable by `tests/fuzz_corpora.rs`.
//! Run with `cargo +nightly fuzz run foxglove_handshake fuzz/corpus/foxglove_handshake fuzz/seeds/foxglove_handshake` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::foxglove_handshake(data));
