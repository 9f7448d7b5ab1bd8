//! `parol6 program run` through the built binary (issue 28): many short G-code lines run
//! headless without a step being refused for coming late, and `--start-deg` sets where the
//! simulation starts, is refused where the robot is elsewhere, and is checked like
//! `program check --start-deg`.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use std::path::{Path, PathBuf};

use cli_support::run;

fn temp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("parol6-cli-program-run-{}-{name}", std::process::id()))
}

fn s(p: &Path) -> String {
    p.display().to_string()
}

/// The pose of joints (90, −80, 170, 0, 60, 180)° (tool level, clear of the wrist singularity
/// of the standby pose), as G-code axis words.
const ABC: &str = "Z292.1 A90 B0 C130";

/// A raster of `n` `G1` lines of 2 mm in front of the arm, after a `G0` to its corner (rounded
/// with `G64 P…` when `blend_mm` is given).
fn raster(n: usize, blend_mm: Option<f64>) -> String {
    let mut g = String::from("G21 G90\nG0 X0 Y263.6 Z292.1 A90 B0 C130\n");
    if let Some(b) = blend_mm {
        g.push_str(&format!("G64 P{b}\n"));
    }
    let (mut x, mut dx, mut y) = (0.0_f64, 2.0_f64, 263.6_f64);
    for k in 0..n {
        if k % 11 == 10 {
            y += 2.0;
        } else {
            x += dx;
            if x.abs() > 10.0 + 1e-9 {
                dx = -dx;
                x += 2.0 * dx;
            }
        }
        g.push_str(&format!("G1 X{x:.3} Y{y:.3} {ABC}\n"));
    }
    g
}

/// Regression: 60 unblended 2 mm `G1` lines failed headless at the default speed ("step 44: …
/// the trajectory starts 0.0558° away from the commanded position (… that one started late,
/// the schedule was not kept)"). 300 lines, unblended and blended, run to the end.
#[test]
fn hundreds_of_short_gcode_lines_run_headless() {
    for (name, blend) in [("exact", None), ("blended", Some(0.5))] {
        let file = temp(&format!("{name}.gcode"));
        std::fs::write(&file, raster(300, blend)).unwrap();
        let out = run(&["program", "run", &s(&file)]).json(name);
        assert_eq!(out["state"], "done", "{name}: {out}");
        assert_eq!(out["steps_done"], out["steps"], "{name}: {out}");
        assert!(out["schedule_slip_s"].as_f64().is_some(), "{out}");
        let _ = std::fs::remove_file(&file);
    }
}

#[test]
fn start_deg_sets_where_the_simulation_starts() {
    // a line from the pose of (90, -80, 170, 0, 60, 180)°: from the standby pose (J5 = 0, a
    // wrist singularity) pre-flight refuses it
    let file = temp("line.gcode");
    std::fs::write(&file, format!("G1 X10 Y263.6 {ABC}\n")).unwrap();
    let out = run(&["program", "run", &s(&file), "--start-deg", "90,-80,170,0,60,180"]).json("from the start pose");
    assert_eq!(out["state"], "done", "{out}");
    let r = run(&["program", "run", &s(&file)]);
    assert_eq!(r.code(), Some(2), "from standby: {r:?}");
    assert!(r.stderr.contains("pre-flight: step 1 (line 1)"), "{r:?}");
    // checked as program check --start-deg is
    run(&["program", "run", &s(&file), "--start-deg", "90,-80,170"]).assert_refused("3 values", "--start-deg");
    run(&["program", "run", &s(&file), "--start-deg", "90,-80,170,0,60,400"])
        .assert_refused("beyond J6's limit", "outside the limits");
    // the robot (here the emulator, at standby) must already be at the start pose
    run(&["program", "run", &s(&file), "--fake-robot", "--start-deg", "90,-80,170,0,60,180"])
        .assert_refused("the arm elsewhere", "not at the start pose");
    let _ = std::fs::remove_file(&file);
}
