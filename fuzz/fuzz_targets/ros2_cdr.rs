//! Fuzz target `ros2_cdr`: ROS 2 CDR payloads (`JointTrajectory`, `JointState`, `TFMessage`,
//! `String`) decoded, re-encoded and, for trajectories, validated and pre-flighted. Body:
//! `parol6_tests::fuzz_bodies::ros2_cdr`, replayed on stable by `tests/fuzz_corpora.rs`.
//! Run with `cargo +nightly fuzz run ros2_cdr fuzz/corpus/ros2_cdr fuzz/seeds/ros2_cdr` from the repository root.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| parol6_tests::fuzz_bodies::ros2_cdr(data));
