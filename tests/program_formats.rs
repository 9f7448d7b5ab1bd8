//! The program exchange formats against their fixture corpora (`tests/fixtures/<format>/`):
//! every file in `valid/` reads and passes pre-flight, every file in `broken/` fails with
//! exactly the error text in its `.expected` file (a read error, or the pre-flight's first
//! error: `step N (line L): …`).
//!
//! Formats: `csv` (point tables, `program::table`), `commander` (PAROL commander `.txt`
//! programs, `program::commander`) and `timefn` (native program files with `time_function`
//! steps, `program::json` then `program::timefn` at compile time).
//!
//! Pre-flight starts from the Draw demo's first pose, joints (90, −80, 170, 0, 60, 180)°, near
//! the fixtures' points and away from the standby wrist singularity.
//!
//! `PAROL6_BLESS_FIXTURES=1` writes the `.expected` files from what the code says (then read
//! them before committing); without it the test only compares.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::path::{Path, PathBuf};

use parol6_core::model::RobotModel;
use parol6_core::program::check::{CheckOptions, check_program};
use parol6_core::program::{Program, commander, json, table};

const START_DEG: [f64; 6] = [90.0, -80.0, 170.0, 0.0, 60.0, 180.0];

fn fixtures(format: &str, kind: &str) -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures").join(format).join(kind);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x != "expected"))
        .collect();
    files.sort();
    files
}

fn read(format: &str, text: &str) -> Result<Program, String> {
    match format {
        "csv" => table::parse_csv_table(text).map_err(|e| e.to_string()),
        "commander" => commander::parse_commander(text).map_err(|e| e.to_string()),
        "timefn" => json::parse(text).map_err(|e| e.to_string()),
        other => panic!("no format {other}"),
    }
}

/// The file's outcome: `Ok` with the program, or the error text.
fn outcome(format: &str, path: &Path) -> Result<Program, String> {
    let text = std::fs::read_to_string(path).unwrap();
    let program = read(format, &text)?;
    let model = RobotModel::parol6();
    let start: Vec<f64> = START_DEG.iter().map(|d| d.to_radians()).collect();
    let report = check_program(&model, &program, &start, CheckOptions::default());
    match report.first_error() {
        Some(e) => Err(e),
        None => Ok(program),
    }
}

fn walk(format: &str) {
    let valid = fixtures(format, "valid");
    assert!(valid.len() >= 3, "{format}: {} valid files", valid.len());
    for path in &valid {
        if let Err(e) = outcome(format, path) {
            panic!("{}: {e}", path.display());
        }
    }
    let broken = fixtures(format, "broken");
    assert!(broken.len() >= 12, "{format}: {} broken files", broken.len());
    let bless = std::env::var_os("PAROL6_BLESS_FIXTURES").is_some();
    let mut wrong = Vec::new();
    for path in &broken {
        let got = match outcome(format, path) {
            Ok(_) => format!("(no error: {} passes)", path.display()),
            Err(e) => e,
        };
        let expected_path = PathBuf::from(format!("{}.expected", path.display()));
        if bless {
            std::fs::write(&expected_path, format!("{got}\n")).unwrap();
            continue;
        }
        let expected =
            std::fs::read_to_string(&expected_path).unwrap_or_else(|e| panic!("{}: {e}", expected_path.display()));
        if expected.trim_end_matches('\n') != got {
            wrong.push(format!("{}:\n  expected {}\n  got      {got}", path.display(), expected.trim_end()));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn csv_point_tables_match_their_fixtures() {
    walk("csv");
}

#[test]
fn commander_programs_match_their_fixtures() {
    walk("commander");
}

#[test]
fn time_functions_match_their_fixtures() {
    walk("timefn");
}

/// Every valid file survives the round trip through its format's writer.
#[test]
fn valid_files_write_back_to_the_same_steps() {
    for path in fixtures("csv", "valid") {
        let p = read("csv", &std::fs::read_to_string(&path).unwrap()).unwrap();
        let back = table::parse_csv_table(&table::program_to_csv(&p).unwrap()).unwrap();
        assert_eq!(p.steps.len(), back.steps.len(), "{}", path.display());
        for (a, b) in p.steps.iter().zip(&back.steps) {
            assert_eq!(a.step, b.step, "{}", path.display());
        }
    }
    for path in fixtures("commander", "valid") {
        let p = read("commander", &std::fs::read_to_string(&path).unwrap()).unwrap();
        let text = commander::program_to_commander(&p).unwrap();
        let back = commander::parse_commander(&text).unwrap();
        assert_eq!(p.steps.len(), back.steps.len(), "{}", path.display());
        assert_eq!(p.looping, back.looping);
        assert_eq!(json::to_string(&back).lines().count(), json::to_string(&p).lines().count());
    }
    for path in fixtures("timefn", "valid") {
        let p = read("timefn", &std::fs::read_to_string(&path).unwrap()).unwrap();
        let back = json::parse(&json::to_string(&p)).unwrap();
        let steps = |p: &Program| p.steps.iter().map(|s| s.step.clone()).collect::<Vec<_>>();
        assert_eq!(steps(&p), steps(&back), "{}", path.display());
    }
}
