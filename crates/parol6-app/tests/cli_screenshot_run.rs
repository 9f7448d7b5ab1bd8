//! `parol6 screenshot --ui --run PROGRAM --plot QUANTITY`: the whole window after a built-in
//! program ran, with one plot shown (scripted pictures for the manual and the
//! simulation-vs-robot comparison of issue 31). Needs a render adapter (lavapipe in CI).

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use cli_support::{no_adapter, run};

#[test]
fn a_program_runs_before_the_picture_on_the_simulation_and_the_robot() {
    let dir = std::env::temp_dir().join(format!("parol6-shot-run-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (connect, backend) in [(None, "simulation"), (Some("--fake-robot"), "robot")] {
        let out = dir.join(format!("{backend}.png"));
        let mut args = vec!["screenshot", "--ui", "--run", "triangle", "--plot", "cmd-meas", "--size", "640x400"];
        args.extend(connect);
        args.push(out.to_str().unwrap());
        let r = run(&args);
        if no_adapter(&r, "a_program_runs_before_the_picture") {
            return;
        }
        let v = r.json("screenshot --ui --run");
        assert_eq!(v["backend"], backend, "{v}");
        assert_eq!(v["plot"], "commanded − measured", "{v}");
        let program_s = v["program_s"].as_f64().unwrap();
        assert!(program_s > 1.0, "the program ran before the picture: {v}");
        println!("{backend}: program {program_s:.1} s, longest frame {} ms", v["longest_frame_ms"]);
        assert!(std::fs::metadata(&out).map(|m| m.len() > 10_000).unwrap_or(false), "a picture");
    }
    // a program the window does not have: refused naming it, nothing written
    let missing = dir.join("missing.png");
    run(&["screenshot", "--ui", "--run", "no such program", "--size", "64x48", missing.to_str().unwrap()])
        .assert_refused("--run", "no such program");
    assert!(!missing.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn run_and_plot_need_the_window_layout_and_known_names() {
    run(&["screenshot", "--run", "draw", "x.png"]).assert_refused("--run without --ui", "--ui");
    run(&["screenshot", "--ui", "--plot", "speed", "x.png"]).assert_refused("an unknown quantity", "cmd-meas");
    run(&["screenshot", "--ui", "--plot", "cmd-meas", "--joints", "0,0,0,0,0,0", "--run", "draw", "x.png"])
        .assert_refused("--joints with --run", "--joints");
    // the controller options apply to a run only
    run(&["screenshot", "--fake-robot", "x.png"]).assert_refused("--fake-robot without --run", "--fake-robot");
}
