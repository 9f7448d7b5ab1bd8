//! Feeds arbitrary text to the URDF loader (`RobotModel::from_urdf_str`) and, when a model
//! loads, runs FK, the Jacobian, seeded IK, SRDF pairs, the collision guard and the simulation.
//! Body: `parol6_tests::fuzz_bodies::urdf_loader` (replayed on stable by `tests/fuzz_corpora.rs`).
//! Run with `cargo +nightly fuzz run urdf_loader` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::urdf_loader(data));
