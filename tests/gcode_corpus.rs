//! The G-code corpus (`tests/fixtures/gcode/`): every broken file gets exactly the error of its
//! `.expected` file; every valid file reads, passes pre-flight from the PAROL6 standby, and
//! keeps its path through G-code → JSON → G-code.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::path::{Path, PathBuf};

use parol6_core::model::RobotModel;
use parol6_core::motion::home_position;
use parol6_core::program::check::{CheckOptions, check_program};
use parol6_core::program::gcode::{GcodeExportOptions, GcodeImportOptions, parse_gcode, program_to_gcode};
use parol6_core::program::{Program, Step, json};

fn corpus(kind: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures").join("gcode").join(kind);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "gcode"))
        .collect();
    files.sort();
    files
}

fn setup() -> (RobotModel, Vec<f64>, GcodeImportOptions) {
    let model = RobotModel::parol6();
    let start = home_position(&model);
    let options = GcodeImportOptions::for_model(&model, &start);
    (model, start, options)
}

#[test]
fn every_broken_file_gets_its_exact_error() {
    let (_, _, options) = setup();
    let files = corpus("broken");
    assert!(files.len() >= 12, "{} broken files", files.len());
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let expected = std::fs::read_to_string(file.with_extension("expected"))
            .unwrap_or_else(|e| panic!("{}: no .expected file: {e}", file.display()));
        match parse_gcode(&text, &options) {
            Ok(p) => panic!("{} read as {} steps; expected: {expected}", file.display(), p.steps.len()),
            Err(e) => assert_eq!(e.to_string(), expected.trim_end(), "{}", file.display()),
        }
    }
}

/// Poses, speeds and the other fields of two step lists agree within 1e-6.
fn same_steps(a: &Program, b: &Program) -> bool {
    let num = |s: &Step| -> Vec<f64> {
        let v = serde_json::to_value(s).unwrap();
        let mut out = Vec::new();
        fn walk(v: &serde_json::Value, out: &mut Vec<f64>) {
            match v {
                serde_json::Value::Number(n) => out.push(n.as_f64().unwrap()),
                serde_json::Value::Array(a) => a.iter().for_each(|x| walk(x, out)),
                serde_json::Value::Object(o) => o.values().for_each(|x| walk(x, out)),
                _ => {}
            }
        }
        walk(&v, &mut out);
        out
    };
    a.steps.len() == b.steps.len()
        && a.steps.iter().zip(&b.steps).all(|(x, y)| {
            let (u, v) = (num(&x.step), num(&y.step));
            x.step.kind() == y.step.kind() && u.len() == v.len() && u.iter().zip(&v).all(|(p, q)| (p - q).abs() <= 1e-6)
        })
}

#[test]
fn every_valid_file_reads_passes_preflight_and_round_trips() {
    let (model, start, options) = setup();
    let files = corpus("valid");
    assert!(files.len() >= 5, "{} valid files", files.len());
    for file in files {
        let name = file.display().to_string();
        let text = std::fs::read_to_string(&file).unwrap();
        let program = parse_gcode(&text, &options).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(!program.steps.is_empty(), "{name}");
        // every step on a line of the file that holds a word
        let lines: Vec<&str> = text.lines().collect();
        for s in &program.steps {
            let line = lines[s.line - 1].trim_start();
            assert!(
                !line.is_empty() && !line.starts_with(';') && !line.starts_with('('),
                "{name}: step on line {}",
                s.line
            );
        }
        let report = check_program(&model, &program, &start, CheckOptions::default());
        assert!(report.ok, "{name}: pre-flight: {:?}", report.first_error());
        // G-code → JSON → G-code keeps the path
        let json_text = json::to_string(&program);
        let from_json = json::parse(&json_text).unwrap_or_else(|e| panic!("{name}: JSON: {e}"));
        let written = program_to_gcode(&from_json, &model, &GcodeExportOptions::new(&from_json, start.clone()))
            .unwrap_or_else(|e| panic!("{name}: export: {e}"));
        let again = parse_gcode(&written, &options).unwrap_or_else(|e| panic!("{name}: re-import: {e}\n{written}"));
        assert!(same_steps(&program, &again), "{name}: the path changed\n{written}");
    }
}
