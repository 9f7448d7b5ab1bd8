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

/// `mcap_cut` on random inputs (seeded; a cut and 0–6 mutations each) for
/// `PAROL6_MCAP_CUT_SECONDS` (default 2 s): the stable stand-in for its libFuzzer run, which
/// prints how many inputs it ran. `cargo test --release -p parol6-tests --test fuzz_corpora --
/// --ignored mcap_cut_random_inputs --nocapture`.
#[test]
#[ignore = "a long random run; see its doc"]
fn mcap_cut_random_inputs() {
    use rand::{Rng, SeedableRng};
    let seconds: f64 = std::env::var("PAROL6_MCAP_CUT_SECONDS").ok().and_then(|s| s.parse().ok()).unwrap_or(2.0);
    let mut rng = rand::rngs::StdRng::seed_from_u64(29);
    let start = std::time::Instant::now();
    let mut n = 0u64;
    let mut input = Vec::new();
    while start.elapsed().as_secs_f64() < seconds {
        for _ in 0..100 {
            input.clear();
            let cut: u16 = if rng.random_bool(0.4) { 0xffff } else { rng.random_range(0..12_000) };
            input.extend_from_slice(&cut.to_le_bytes());
            for _ in 0..rng.random_range(0..=6) {
                let value: u64 = match rng.random_range(0..6) {
                    0 => 4 << 30,
                    1 => u64::MAX,
                    2 => rng.random_range(0..20_000),
                    3 => rng.random_range(0..300),
                    4 => [1, 2, 6, 7, 12, 15, 0x80][rng.random_range(0..7)],
                    _ => rng.random(),
                };
                input.extend_from_slice(&[rng.random(), rng.random_range(0..10)]);
                input.extend_from_slice(&value.to_le_bytes());
            }
            let case = input.clone();
            let ok = std::panic::catch_unwind(|| parol6_tests::fuzz_bodies::mcap_cut(&case)).is_ok();
            assert!(ok, "mcap_cut fails on {case:02x?}");
            n += 1;
        }
    }
    println!("mcap_cut: {n} random inputs in {:.0} s", start.elapsed().as_secs_f64());
}
