//! Replays the committed fuzz inputs on stable Rust through the same bodies the cargo-fuzz
//! targets run (`parol6_tests::fuzz_bodies`): the hand-made seeds (`fuzz/seeds/<target>/`),
//! the minimised corpora (`fuzz/corpus-min/<target>/`) and every input that once failed
//! (`fuzz/regressions/<target>/`).

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::path::{Path, PathBuf};

use parol6_tests::fuzz_bodies::TARGETS;

fn fuzz_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join("fuzz")
}

/// Files of `dir` (none when the folder does not exist), dot files left out.
fn inputs(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else { return Vec::new() };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && !p.file_name().is_some_and(|n| n.to_string_lossy().starts_with('.')))
        .collect();
    files.sort();
    files
}

fn replay(kind: &str) -> usize {
    let mut total = 0;
    for t in TARGETS {
        let (target, body) = (t.name, t.body);
        for file in inputs(&fuzz_dir().join(kind).join(t.corpus)) {
            let data = std::fs::read(&file).unwrap_or_else(|e| panic!("cannot read {}: {e}", file.display()));
            let outcome = std::panic::catch_unwind(|| body(&data));
            assert!(outcome.is_ok(), "fuzz target {target} fails on {}", file.display());
            total += 1;
        }
    }
    println!("{kind}: {total} inputs replayed");
    total
}

#[test]
fn every_target_has_seeds_and_a_minimised_corpus() {
    for t in TARGETS {
        let (target, corpus) = (t.name, t.corpus);
        assert!(fuzz_dir().join("fuzz_targets").join(format!("{target}.rs")).is_file(), "{target}: no fuzz target");
        assert!(!inputs(&fuzz_dir().join("seeds").join(corpus)).is_empty(), "{target}: no seeds");
        assert!(!inputs(&fuzz_dir().join("corpus-min").join(corpus)).is_empty(), "{target}: no minimised corpus");
    }
}

#[test]
fn seeds_replay_cleanly() {
    assert!(replay("seeds") > 0);
}

#[test]
fn minimised_corpora_replay_cleanly() {
    assert!(replay("corpus-min") > 0);
}

#[test]
fn regression_inputs_replay_cleanly() {
    // Empty until the fuzzers find something; each file there is a fixed bug.
    replay("regressions");
}
