//! The conformance suite: files as PAROL6 owners bring them (`tests/conformance/<format>/`),
//! each with a sidecar `.expect` that says what the official software does with it and what we
//! do; this test checks our side.
//!
//! A case is `CASE.<ext>` (`.txt` commander, `.gcode` / `.nc` G-code, `.json` native) and
//! `CASE.expect`, plain `key: value` lines:
//!
//! | key | meaning |
//! |---|---|
//! | `official` | what the official tool does with the file, and how we know (required) |
//! | `ours` | what we do, in words (required) |
//! | `expect` | `ok` (reads and passes pre-flight: no error), `warning` (passes, with a warning on `line`), `error` (refused, naming `line`) |
//! | `line` | for `warning` / `error`: the 1-based source line named |
//! | `message` | optional: text the warning or error must contain |
//! | `start_deg` | optional: start joints, deg (default: standby 90, −90, 180, 0, 0, 180) |
//! | `abc` | optional, G-code only: `commander` or `xyz`, as `--abc` gives it (explicit: a file header that contradicts it is an error) |
//!
//! The file is read as `parol6 program check FILE` reads it (`program::files`, the format from
//! the extension), then checked from the start joints.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::collections::BTreeMap;
use std::path::PathBuf;

use parol6_core::model::RobotModel;
use parol6_core::program::check::{CheckOptions, Severity, check_program};
use parol6_core::program::files::{FormatContext, read_program};
use parol6_core::program::gcode::AbcChoice;

const STANDBY_DEG: [f64; 6] = [90.0, -90.0, 180.0, 0.0, 0.0, 180.0];

struct Case {
    file: PathBuf,
    keys: BTreeMap<String, String>,
}

fn cases() -> Vec<Case> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("conformance");
    let mut out = Vec::new();
    for format in ["commander", "gcode", "native"] {
        let dir = root.join(format);
        let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x != "expect") && p.is_file())
            .collect();
        files.sort();
        for file in files {
            let sidecar = file.with_extension("expect");
            let text = std::fs::read_to_string(&sidecar)
                .unwrap_or_else(|e| panic!("{}: every case needs its .expect ({e})", sidecar.display()));
            let mut keys = BTreeMap::new();
            for (n, line) in text.lines().enumerate() {
                let line = line.trim();
                if line.is_empty() || line.starts_with('#') {
                    continue;
                }
                let (k, v) =
                    line.split_once(':').unwrap_or_else(|| panic!("{}:{}: not `key: value`", sidecar.display(), n + 1));
                let k = k.trim().to_string();
                assert!(
                    ["official", "ours", "expect", "line", "message", "start_deg", "abc"].contains(&k.as_str()),
                    "{}:{}: unknown key {k}",
                    sidecar.display(),
                    n + 1
                );
                keys.insert(k, v.trim().to_string());
            }
            for required in ["official", "ours", "expect"] {
                assert!(
                    keys.get(required).is_some_and(|v| !v.is_empty()),
                    "{}: `{required}:` is required",
                    sidecar.display()
                );
            }
            out.push(Case { file, keys });
        }
    }
    out
}

/// True when `text` names line `n` ("line 12", not "line 123").
fn names_line(text: &str, n: usize) -> bool {
    let needle = format!("line {n}");
    text.match_indices(&needle).any(|(i, _)| !text[i + needle.len()..].starts_with(|c: char| c.is_ascii_digit()))
}

fn start_rad(case: &Case) -> Vec<f64> {
    match case.keys.get("start_deg") {
        Some(s) => {
            let q: Vec<f64> = s.split(',').map(|v| v.trim().parse::<f64>().unwrap().to_radians()).collect();
            assert_eq!(q.len(), 6, "{}: start_deg needs six values", case.file.display());
            q
        }
        None => STANDBY_DEG.iter().map(|d| d.to_radians()).collect(),
    }
}

/// Checks one case; returns what went wrong.
fn run(model: &RobotModel, case: &Case) -> Result<(), String> {
    let start = start_rad(case);
    let expect = case.keys["expect"].as_str();
    let line: Option<usize> = case.keys.get("line").map(|l| l.parse().expect("line: a number"));
    let message = case.keys.get("message").map(String::as_str).unwrap_or("");
    if expect != "ok" && line.is_none() {
        return Err(format!("expect: {expect} needs `line:`"));
    }
    let abc = match case.keys.get("abc") {
        Some(name) => AbcChoice::explicit(name.parse().map_err(|e| format!("abc: {e}"))?),
        None => AbcChoice::default(),
    };
    let ctx = FormatContext { abc, ..FormatContext::new(model, &start) };
    let program = match read_program(&case.file, &ctx) {
        Ok(p) => p,
        Err(e) => {
            let e = e.to_string();
            return match (expect, line) {
                ("error", Some(n)) if names_line(&e, n) && e.contains(message) => Ok(()),
                _ => Err(format!("read failed: {e}")),
            };
        }
    };
    let report = check_program(model, &program, &start, CheckOptions::default());
    let warnings: Vec<_> = report.issues.iter().filter(|i| i.severity == Severity::Warning).collect();
    let errors: Vec<_> = report.issues.iter().filter(|i| i.severity == Severity::Error).collect();
    let describe = || format!("{:#?}", report.issues);
    match (expect, line) {
        ("ok", _) if report.ok => Ok(()),
        ("ok", _) => Err(format!("expected ok, got {}", describe())),
        ("warning", Some(n)) if report.ok && warnings.iter().any(|w| w.line == n && w.message.contains(message)) => {
            Ok(())
        }
        ("warning", _) => Err(format!("expected a warning on line {line:?} with {message:?}, got {}", describe())),
        ("error", Some(n)) if errors.first().is_some_and(|e| e.line == n && e.message.contains(message)) => Ok(()),
        ("error", _) => Err(format!("expected an error on line {line:?} with {message:?}, got {}", describe())),
        (other, _) => Err(format!("expect: {other} is not ok | warning | error")),
    }
}

#[test]
fn every_conformance_case_does_what_its_expect_says() {
    let model = RobotModel::parol6();
    let cases = cases();
    let mut failures = Vec::new();
    for case in &cases {
        if let Err(why) = run(&model, case) {
            failures.push(format!("{}: {why}", case.file.display()));
        }
    }
    assert!(failures.is_empty(), "{} of {} cases fail:\n{}", failures.len(), cases.len(), failures.join("\n\n"));
    for format in ["commander", "gcode", "native"] {
        let n = cases.iter().filter(|c| c.file.parent().is_some_and(|p| p.ends_with(format))).count();
        assert!(n > 0, "no {format} case in tests/conformance/{format}");
    }
}

#[test]
fn names_line_is_exact() {
    assert!(names_line("line 12, MoveCart: x", 12));
    assert!(!names_line("line 123, MoveCart: x", 12));
    assert!(!names_line("line 1", 2));
}
