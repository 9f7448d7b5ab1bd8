//! `parol6 bench ui-actions` (issue 32's acceptance: nothing a user does blocks the window for
//! more than 50 ms): at a small size, the JSON names every action with its longest frame; the
//! timings themselves are not checked here (they depend on the host). Needs a render adapter
//! (lavapipe in CI).

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod cli_support;

use cli_support::{no_adapter, run};

/// Every action the bench measures, in order.
const ACTIONS: [&str; 28] = [
    "idle",
    "open_program",
    "preflight_check",
    "run_start",
    "run_pause",
    "run_step",
    "run_resume",
    "run_stop",
    "edit_duplicate_step",
    "undo",
    "redo",
    "point_table_open",
    "dynamics_open",
    "dynamics_refresh_after_home",
    "record_start",
    "record_stop",
    "replay_open",
    "replay_play",
    "replay_speed_4x",
    "replay_scrub",
    "replay_dynamics_open",
    "replay_seek",
    "replay_close",
    "file_dialog_open",
    "units_rad",
    "units_deg",
    "resize_smaller",
    "resize_back",
];

#[test]
fn bench_ui_actions_reports_the_longest_frame_of_every_action() {
    let r = run(&["bench", "ui-actions", "--steps", "20", "--minutes", "0.05", "--rate", "100", "--size", "640x400"]);
    if no_adapter(&r, "bench_ui_actions_reports_the_longest_frame_of_every_action") {
        return;
    }
    let v = r.json("bench ui-actions");
    assert_eq!(v["target"], "ui-actions", "{v}");
    assert!(v["steps"].as_u64().unwrap() >= 20, "the generated program was opened: {v}");
    assert_eq!(v["stall_ms"], 50.0, "{v}");
    let actions = v["actions"].as_array().unwrap();
    let names: Vec<&str> = actions.iter().map(|a| a["action"].as_str().unwrap()).collect();
    assert_eq!(names, ACTIONS, "{v}");
    for a in actions {
        for field in [
            "frame_ms_max",
            "app_ms_max",
            "ui_cpu_ms_max",
            "call_ms",
            "settled_s",
            "longest_frame_cpu_ms",
            "frame_cpu_ms_max",
        ] {
            assert!(a[field].as_f64().is_some_and(|x| x.is_finite() && x >= 0.0), "{field} of {a}");
        }
        // a frame's UI pass runs on the process's CPU: its CPU time is at least a part of it
        assert!(a["longest_frame_cpu_ms"].as_f64().unwrap() > 0.0, "the longest frame took some CPU: {a}");
        assert!(
            a["frame_cpu_ms_max"].as_f64().unwrap() >= a["longest_frame_cpu_ms"].as_f64().unwrap(),
            "the costliest frame took at least the longest one's CPU: {a}"
        );
        assert!(a["frames"].as_u64().unwrap() >= 1, "{a}");
        assert!(a["settled"].is_boolean(), "{a}");
    }
    let longest = actions.iter().map(|a| a["frame_ms_max"].as_f64().unwrap()).fold(0.0, f64::max);
    assert_eq!(v["frame_ms_max"].as_f64().unwrap(), longest, "{v}");
    let costliest = actions.iter().map(|a| a["frame_cpu_ms_max"].as_f64().unwrap()).fold(0.0, f64::max);
    assert_eq!(v["frame_cpu_ms_max"].as_f64().unwrap(), costliest, "{v}");
    let over: Vec<&str> = v["over_50ms"].as_array().unwrap().iter().map(|x| x.as_str().unwrap()).collect();
    let expected: Vec<&str> = actions
        .iter()
        .filter(|a| a["frame_ms_max"].as_f64().unwrap() > 50.0)
        .map(|a| a["action"].as_str().unwrap())
        .collect();
    assert_eq!(over, expected, "over_50ms lists the actions over 50 ms: {v}");
    // Linux: the host's load is read at the start and the end
    #[cfg(target_os = "linux")]
    for at in ["start", "end"] {
        assert!(v["load_average_1min"][at].as_f64().is_some_and(|x| x.is_finite() && x >= 0.0), "load at {at}: {v}");
    }
    assert_eq!(v["pass"], over.is_empty() && v["not_settled"].as_array().unwrap().is_empty(), "{v}");
}
