//! `--tracking` through the built binary (issue 31): the simulation's board streams the chosen
//! mode's targets, `lead` (the default) tracks the plan within 0.3° where `official` trails it
//! by degrees, a program file's own mode applies unless `--tracking` says otherwise, and an
//! unknown mode is the user's input error.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use cli_support::run;

fn max_error_deg(out: &serde_json::Value) -> f64 {
    out["max_tracking_error_deg"].as_f64().expect("max_tracking_error_deg")
}

#[test]
fn program_run_tracking_lead_removes_the_lag_of_official() {
    let lead = run(&["program", "run", "assets/programs/draw.json"]).json("default run");
    assert_eq!(lead["tracking"], "lead", "{lead}");
    assert!(max_error_deg(&lead) < 0.3, "lead: {lead}");
    let official = run(&["program", "run", "assets/programs/draw.json", "--tracking", "official"]).json("official run");
    assert_eq!(official["tracking"], "official");
    assert!(max_error_deg(&official) > 1.0, "official trails the plan by degrees at full speed: {official}");
}

#[test]
fn program_run_takes_the_program_files_tracking_mode_unless_told() {
    let text =
        std::fs::read_to_string(cli_support::workspace_root().join("assets/programs/triangle.json")).expect("triangle");
    let with = text.replacen("\"steps\"", "\"tracking\": \"official\",\n  \"steps\"", 1);
    let path = std::env::temp_dir().join(format!("parol6-cli-tracking-{}.json", std::process::id()));
    std::fs::write(&path, with).expect("write");
    let p = path.display().to_string();
    assert_eq!(run(&["program", "run", &p]).json("file's mode")["tracking"], "official");
    // the recording carries the mode (issue 31 item 4)
    let rec = std::env::temp_dir().join(format!("parol6-cli-tracking-{}.mcap", std::process::id()));
    let r = rec.display().to_string();
    let out = run(&["program", "run", &p, "--tracking", "feedforward", "--record", &r]).json("told");
    assert_eq!(out["tracking"], "feedforward");
    assert_eq!(run(&["mcap", "info", &r]).json("mcap info")["tracking"], "feedforward");
    let _ = std::fs::remove_file(&rec);
    std::fs::remove_file(&path).expect("remove");
}

#[test]
fn an_unknown_tracking_mode_is_refused_as_input() {
    let r = run(&["program", "run", "assets/programs/draw.json", "--tracking", "fast"]);
    assert_eq!(r.code(), Some(2), "{r:?}");
    assert!(r.stderr.contains("fast") && r.stderr.contains("lead"), "{}", r.stderr);
}
