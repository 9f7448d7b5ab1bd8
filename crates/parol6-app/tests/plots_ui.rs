//! Plots and replay, driven headless through egui's kittest harness on the full app: the plots
//! panel opens from the View menu, shows the tracking error's RMS and maximum with units while
//! a program runs, and its joint toggles take series off; a recording opens from the File
//! menu into the replay timeline, plays, and jumps to an event; an empty file is refused with
//! a message that says so; the lower panel keeps its height once the plots are shown.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use ui_support::{app_harness, click_in_view_menu, has_label, until};

use parol6_app::app::Parol6App;
use parol6_core::RobotModel;
use parol6_core::telemetry::EventKind;

fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("parol6-plots-ui-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    dir
}

/// The app at `size`, replaying a synthetic recording (`minutes` at `rate_hz`, an event every
/// 10 s) written as `file` into a temporary folder named after `name`; that folder.
fn replaying(
    name: &str,
    file: &str,
    minutes: f64,
    rate_hz: f64,
    size: egui::Vec2,
) -> (std::path::PathBuf, Harness<'static, Parol6App>) {
    let dir = temp_dir(name);
    let path = dir.join(file);
    let bytes =
        parol6_app::cli::bench_replay::synthetic_recording(&RobotModel::parol6(), minutes, rate_hz).expect("recording");
    std::fs::write(&path, bytes).expect("write");
    let mut h = app_harness(size);
    ui_support::open_recording(&mut h, &path);
    until(&mut h, "the replay", 10.0, |h| has_label(h, &format!("Replay: {file}")));
    (dir, h)
}

/// Shows `quantity`, lets the simulation fill `sim_s` seconds of the plots (a stretch many pixel
/// columns wide: a point within a column of a switch is not drawn, as it may stand for rows of
/// both sides), then connects the built-in emulator and waits for 0.3 s of the robot's rows
/// after the simulation's. Returns the first and the last time of the simulation's rows, s.
fn simulation_then_robot(
    h: &mut Harness<'_, Parol6App>,
    quantity: parol6_core::telemetry::Quantity,
    sim_s: f64,
) -> (f64, f64) {
    use parol6_app::panels::{AppCommand, LinkCommand, StateSource};
    h.state_mut().show_plot(quantity);
    until(h, "the simulation's first stretch", 15.0, |h| {
        h.state().plots_panel().store().time_range_s().is_some_and(|(first, last)| last - first > sim_s)
    });
    let (first, sim_last) = h.state().plots_panel().store().time_range_s().unwrap();
    h.state_mut().queue_command(AppCommand::Link(LinkCommand::ConnectEmulator));
    until(h, "the emulator answers", 15.0, |h| h.state().backend().state().source == StateSource::Robot);
    until(h, "rows of the robot after the simulation's", 15.0, |h| {
        let p = h.state().plots_panel();
        p.switches().len() == 1 && p.store().time_range_s().is_some_and(|(_, last)| last > sim_last + 0.3)
    });
    (first, sim_last)
}

#[test]
fn the_plots_show_the_tracking_error_with_units_and_toggle_joints() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    assert!(!has_label(&h, "cmd - meas"), "the plots start hidden");
    click_in_view_menu(&mut h, "Plots");
    // close the menu, then move the arm: a program makes the commanded and measured differ
    h.key_press(egui::Key::Escape);
    h.run_steps(2);
    // one quantity at a time: the hardware-in-the-loop view
    h.get_by_label("cmd - meas").click();
    h.run_steps(2);
    h.get_by_label("Draw").click();
    until(&mut h, "the pre-flight", 10.0, |h| has_label(h, "pre-flight: ok"));
    h.get_by_label("Run (F5)").click();
    until(&mut h, "the tracking statistics", 20.0, |h| has_label(h, "J2 RMS") && has_label(h, "J1 RMS"));
    assert!(has_label(&h, "°, max"), "RMS and max in degrees");
    // the program's steps reach the recorder as events
    until(&mut h, "a program step event", 20.0, |h| {
        h.state().live_view().events.iter().any(|e| matches!(e.kind, EventKind::ProgramStep { step: Some(_) }))
    });
    // J1's toggle in the plots panel (the joints panel's J1 label comes first)
    let j1_toggle = h.query_all_by_label("J1").last().expect("the plots' J1 toggle");
    j1_toggle.click();
    until(&mut h, "J1 taken off", 5.0, |h| !has_label(h, "J1 RMS"));
    assert!(has_label(&h, "J2 RMS"), "the other joints stay");
    // radians from the Units menu
    h.get_by_label("Units").click();
    h.run_steps(2);
    h.get_by_label("Radians").click();
    until(&mut h, "radians", 5.0, |h| has_label(h, " rad, max"));
}

#[test]
fn a_recording_opens_from_the_file_menu_plays_and_jumps_to_an_event() {
    let (dir, mut h) = replaying("replay", "short.mcap", 0.5, 250.0, egui::vec2(1280.0, 1400.0));
    let start = h.state().replay().map(|r| r.cursor_s).expect("open");
    h.get_by_label("Play").click();
    until(&mut h, "the cursor to move", 5.0, |h| h.state().replay().is_some_and(|r| r.cursor_s > start + 0.05));
    h.get_by_label("Pause").click();
    h.run_steps(2);
    // the third program step starts at 20 s
    h.get_by_label_contains("program step 3").click();
    h.run_steps(2);
    let cursor = h.state().replay().map(|r| r.cursor_s).expect("open");
    assert!((cursor - 20.0).abs() < 0.01, "the cursor jumped to the event: {cursor}");
    assert!(has_label(&h, "cmd - meas"), "the plots opened with the recording");
    // export the plots as SVG, then the visible window as CSV, to the typed path
    let out = dir.join("export.out");
    h.get_by_label("Export to").click();
    h.run_steps(1);
    h.get_by_label("Export to").type_text(&out.display().to_string());
    h.run_steps(1);
    h.get_by_label("SVG of the plots").click();
    h.run_steps(3);
    let svg = std::fs::read_to_string(&out).expect("the SVG was written");
    assert!(svg.starts_with("<svg") && svg.contains("<polyline"), "{}", &svg[..80.min(svg.len())]);
    h.get_by_label("CSV of the visible window").click();
    h.run_steps(2);
    let first = std::fs::read_to_string(&out).expect("the SVG is still there");
    assert!(first.starts_with("<svg") && has_label(&h, "export.out exists"), "the first click over a file asks");
    h.get_by_label("CSV of the visible window").click();
    h.run_steps(2);
    let text = std::fs::read_to_string(&out).expect("the CSV was written");
    assert!(text.starts_with("t_s,j1_q_rad,"), "{}", &text[..80.min(text.len())]);
    assert!(text.lines().count() > 100, "the visible window's samples: {}", text.lines().count());
    h.get_by_label("Close recording").click();
    h.run_steps(2);
    assert!(h.state().replay().is_none());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The events row lays out only the buttons it shows: one far off to the right is not laid
/// out (so not in the accessibility tree) until the row is scrolled to it, and then it jumps.
/// Laying out every button on each frame that draws the panels cost ~0.8 ms of those frames.
/// Regression: the row's floating scroll bar lay over the lower half of the buttons while the
/// pointer was on them, and a click there went to the bar.
#[test]
fn the_events_row_lays_out_only_the_buttons_it_shows() {
    // ten minutes at 10 Hz: an event every 10 s, 40 of them listed
    let (dir, mut h) = replaying("events", "long.mcap", 10.0, 10.0, egui::vec2(1280.0, 1000.0));
    h.run_steps(3);
    let first = h.get_by_label("0.0 s program step 1").rect();
    assert!(first.is_positive(), "the first event shows: {first:?}");
    assert!(
        h.query_by_label_contains("program step 40").is_none(),
        "the 40th event, far to the right, is not laid out"
    );
    assert!(has_label(&h, "… 20 more"), "the rest are counted");
    // scroll the row to its end with the wheel (sideways), over the first event
    for _ in 0..20 {
        h.event(egui::Event::PointerMoved(first.center()));
        h.event(egui::Event::MouseWheel {
            unit: egui::MouseWheelUnit::Point,
            delta: egui::vec2(-2000.0, 0.0),
            phase: egui::TouchPhase::Move,
            source: egui::MouseWheelSource::Unknown,
            modifiers: egui::Modifiers::NONE,
        });
        h.run_steps(1);
    }
    until(&mut h, "the 40th event scrolled into view", 5.0, |h| h.query_by_label_contains("program step 40").is_some());
    h.run_steps(30); // egui's smooth scrolling runs out
    assert!(h.query_by_label("0.0 s program step 1").is_none(), "the first one scrolled out");
    // in the middle of the button: the row's scroll bar does not lie over the buttons
    h.get_by_label_contains("program step 40").click();
    h.run_steps(2);
    let cursor = h.state().replay().map(|r| r.cursor_s).expect("open");
    assert!((cursor - 390.0).abs() < 0.01, "the cursor jumped to the 40th event: {cursor}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_empty_file_is_refused_with_a_clear_message() {
    let dir = temp_dir("empty");
    let path = dir.join("empty.mcap");
    std::fs::write(&path, b"").expect("write");
    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    ui_support::open_recording(&mut h, &path);
    until(&mut h, "the error notice", 10.0, |h| {
        h.state()
            .notices()
            .iter()
            .any(|n| n.error && n.text.contains("empty.mcap") && n.text.contains("empty (0 bytes)"))
    });
    assert!(h.state().replay().is_none());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Height of the panel under the 3D view (replay timeline, plots), points: from its first
/// row (the plots' quantity toggles, just below its top edge) to the status bar.
fn lower_panel_height(h: &Harness<'_, Parol6App>) -> f32 {
    let status_top = h.get_by_label("SIM").rect().top();
    status_top - h.get_by_label("position").rect().top()
}

/// Regression: the panels under the 3D view ended with a separator below the plots, which
/// fill the height left; the panel took the overflow as content and grew a few points every
/// other frame until it reached its largest height (the 3D view squeezed to ~130 px, the
/// resize handle undone, every frame of the growth redrawn whole). And a resizable panel
/// takes its content's height: with no telemetry yet it shrank to its smallest and stayed.
/// The height dragged to is kept in the settings for the next start, and comes back when a
/// window made smaller grows again.
#[test]
fn the_lower_panel_keeps_its_height_once_the_plots_are_shown() {
    let mut h = app_harness(egui::vec2(1280.0, 800.0));
    click_in_view_menu(&mut h, "Plots");
    h.key_press(egui::Key::Escape);
    // the live store fills from the simulation's tap: the plots appear
    until(&mut h, "the plots", 10.0, |h| has_label(h, "Export to"));
    h.run_steps(15);
    let first = lower_panel_height(&h);
    // the default height (LOWER_DEFAULT_HEIGHT, 360 points), not the smallest (120)
    assert!((first - 360.0).abs() < 5.0, "the default height: {first} points");
    for frame in 0..45 {
        h.run_steps(1);
        let now = lower_panel_height(&h);
        assert!((now - first).abs() < 0.5, "frame {frame}: the lower panel went from {first} to {now} points");
    }
    // dragged 100 points higher by its top edge, it stays there
    // the resize handle: the panel's top edge, just above that first row
    let edge = egui::pos2(600.0, h.get_by_label("position").rect().top() - 2.0);
    h.hover_at(edge);
    h.run_steps(1);
    h.drag_at(edge);
    h.run_steps(1);
    h.hover_at(edge - egui::vec2(0.0, 50.0));
    h.run_steps(1);
    h.hover_at(edge - egui::vec2(0.0, 100.0));
    h.run_steps(1);
    h.drop_at(edge - egui::vec2(0.0, 100.0));
    h.run_steps(30);
    let dragged = lower_panel_height(&h);
    assert!((dragged - first - 100.0).abs() < 3.0, "dragged 100 points higher: {first} → {dragged} points");
    // a window made smaller clamps it; made larger again, the panel goes back to that height
    h.set_size(egui::vec2(1280.0, 480.0));
    h.run_steps(5);
    assert!(lower_panel_height(&h) < dragged - 100.0, "clamped: {} points", lower_panel_height(&h));
    h.set_size(egui::vec2(1280.0, 800.0));
    h.run_steps(5);
    let regrown = lower_panel_height(&h);
    assert!((regrown - dragged).abs() < 1.0, "back to {dragged} points: {regrown}");
    // remembered in the settings, and the next start opens it at that height
    let saved = h.state_mut().settings_mut().clone();
    assert!((saved.lower_panel_height_pt - 460.0).abs() < 3.0, "saved {}", saved.lower_panel_height_pt);
    let mut next = app_harness(egui::vec2(1280.0, 800.0));
    *next.state_mut().settings_mut() = saved;
    until(&mut next, "the plots", 10.0, |h| has_label(h, "Export to"));
    next.run_steps(5);
    let reopened = lower_panel_height(&next);
    assert!((reopened - dragged).abs() < 1.0, "reopened at {reopened} points, dragged to {dragged}");
}

/// Regression (issue 32, major 5): a velocity or tracking-error plot had a single "0" on its
/// value axis, and hovering it showed no value. The axis now labels ticks on a 1-2-5 series at
/// every range, and the pointer's time shows each line's value with its unit.
#[test]
fn hovering_a_plot_reads_out_the_time_and_each_lines_value_with_its_unit() {
    let mut h = app_harness(egui::vec2(1280.0, 800.0));
    click_in_view_menu(&mut h, "Plots");
    h.key_press(egui::Key::Escape);
    until(&mut h, "the plots", 10.0, |h| has_label(h, "Export to"));
    h.get_by_label("velocity").click();
    h.run_steps(2);
    h.get_by_label("Draw").click();
    until(&mut h, "the pre-flight", 10.0, |h| has_label(h, "pre-flight: ok"));
    h.get_by_label("Run (F5)").click();
    until(&mut h, "4 s of samples", 20.0, |h| {
        h.state().plots_panel().store().time_range_s().is_some_and(|(first, last)| last - first > 4.0)
    });
    // inside the plot, below the export row, over the newest samples (none before the first)
    let export = h.get_by_label("Export to").rect();
    let inside = egui::pos2(1280.0 - parol6_app::app::RIGHT_PANEL_WIDTH - 40.0, export.bottom() + 80.0);
    h.hover_at(inside);
    h.run_steps(2);
    // (the status bar's simulated time reads "t = …" too)
    let readout =
        h.query_all_by_label_contains("\nJ1: ").find_map(|n| n.value().or_else(|| n.accesskit_node().label()));
    let text = readout.expect("a hover read-out");
    assert!(text.starts_with("t = ") && text.contains(" s\nJ1: ") && text.contains(" °/s"), "{text}");
    // at least two labelled ticks on the value axis (the old axis had "0" alone)
    let ticks = ["-50", "-40", "-20", "-10", "0", "10", "20", "40", "50"].iter().filter(|t| has_label(&h, t)).count();
    assert!(ticks >= 2, "{ticks} value-axis labels");
}

/// Issue 32 major 9: a remembered lower-panel height taller than the window (630 points in a
/// 1024×700 window, with the plots and the dynamics shown) is clamped to the window: the
/// replay timeline's buttons stay inside it, above the status bar, and the panel does not
/// reach into the 3D view, which keeps room above it.
#[test]
fn a_remembered_lower_panel_taller_than_the_window_is_clamped_and_the_timeline_stays_reachable() {
    let dir = temp_dir("clamp");
    let path = dir.join("clamp.mcap");
    let bytes =
        parol6_app::cli::bench_replay::synthetic_recording(&RobotModel::parol6(), 0.2, 250.0).expect("recording");
    std::fs::write(&path, bytes).expect("write");
    let mut h = app_harness(egui::vec2(1024.0, 700.0));
    {
        let s = h.state_mut().settings_mut();
        s.lower_panel_height_pt = 630.0;
        s.show_dynamics = true;
    }
    h.run_steps(3);
    ui_support::open_recording(&mut h, &path);
    until(&mut h, "the replay", 10.0, |h| has_label(h, "Replay: clamp.mcap"));
    h.key_press(egui::Key::Escape);
    h.run_steps(10);
    let play = h.get_by_label("Play").rect();
    let heading = h.get_by_label_contains("Replay: clamp.mcap").rect();
    let menu_bottom = h.query_all_by_label("File").next().expect("the File menu").rect().bottom();
    let view = h.get_by_label_contains("3D view unavailable").rect();
    assert!(
        play.top() >= 0.0 && play.bottom() <= 700.0 - 20.0,
        "Play inside the window, above the status bar: {play:?}"
    );
    assert!(
        heading.top() - menu_bottom >= 100.0,
        "the 3D view keeps room: timeline at {heading:?}, menu at {menu_bottom}"
    );
    assert!(view.bottom() <= heading.top() + 1.0, "the 3D view ends above the lower panel: {view:?} vs {heading:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 32 minor: "Switching robot ↔ simulation clears the plot history." The simulation's
/// rows stay over a connection to the robot (here the built-in emulator) and back; the robot's
/// rows continue them, and each switch is marked with the backend it switched to.
#[test]
fn switching_between_the_simulation_and_the_robot_keeps_the_plot_history() {
    use parol6_app::panels::{AppCommand, LinkCommand, StateSource};
    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    let (first, sim_last) = simulation_then_robot(&mut h, parol6_core::telemetry::Quantity::Position, 1.0);
    let p = h.state().plots_panel();
    assert_eq!(p.store().time_range_s().unwrap().0, first, "the simulation's rows are kept");
    let (at, robot) = p.switches()[0];
    assert!(robot && at >= sim_last, "marked where the robot's rows start: {:?}", p.switches());
    let robot_last = p.store().time_range_s().unwrap().1;
    h.state_mut().queue_command(AppCommand::Link(LinkCommand::Disconnect));
    until(&mut h, "the simulation again", 15.0, |h| h.state().backend().state().source == StateSource::Simulation);
    until(&mut h, "rows of the simulation after the robot's", 15.0, |h| {
        let p = h.state().plots_panel();
        p.switches().len() == 2 && p.store().time_range_s().is_some_and(|(_, last)| last > robot_last + 0.3)
    });
    let p = h.state().plots_panel();
    assert_eq!(p.store().time_range_s().unwrap().0, first, "the history is kept over both switches");
    assert!(!p.switches()[1].1, "the second mark says simulation: {:?}", p.switches());
}

/// Issue 32 minor: "The J1 plot toggle is misaligned." The plots' joint toggles wrap as one
/// group: at every window size J1 … J6 lie on one row, in order, evenly spaced (at 1280 px J1
/// stayed at the end of the quantities' row, J2 … J6 on the next).
#[test]
fn the_plots_joint_toggles_lie_on_one_row_at_every_window_size() {
    for width in [1024.0, 1280.0, 1600.0] {
        let mut h = app_harness(egui::vec2(width, 800.0));
        h.state_mut().show_plot(parol6_core::telemetry::Quantity::Position);
        until(&mut h, "rows to plot", 15.0, |h| h.state().plots_panel().store().len() > 50);
        h.run_steps(3);
        // the plots' toggles come after the joints panel's labels and entries of the same name
        let rects: Vec<egui::Rect> =
            (1..=6).map(|j| h.query_all_by_label(&format!("J{j}")).last().expect("a toggle").rect()).collect();
        for (j, r) in rects.iter().enumerate().skip(1) {
            let first = rects[0];
            assert_eq!((r.top(), r.height()), (first.top(), first.height()), "{width} px: J{} vs J1: {rects:?}", j + 1);
            let gap = r.left() - rects[j - 1].right();
            let first_gap = rects[1].left() - rects[0].right();
            assert!(gap > 0.0 && (gap - first_gap).abs() < 0.5, "{width} px: uneven toggles {rects:?}");
        }
        let panel = h.ctx.content_rect();
        assert!(rects[5].right() <= panel.right(), "{width} px: J6 inside the window");
    }
}

/// Issue 32 (torque unit across a backend switch): the drive plot's axis has the current
/// backend's unit (steps/s on the robot, N·m in the simulation). The other backend's stretch of
/// the history is not drawn under it (it was, under the wrong unit), and the plot says what it
/// leaves out; back in the simulation, the robot's stretch is left out instead.
#[test]
fn the_drive_plot_never_draws_a_stretch_under_the_other_backends_unit() {
    use parol6_app::panels::{AppCommand, LinkCommand, StateSource};
    use parol6_core::telemetry::{DriveKind, Quantity};
    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    let (first, _) = simulation_then_robot(&mut h, Quantity::Drive, 1.0);
    h.run_steps(2);
    let p = h.state().plots_panel();
    assert_eq!(p.store().drive(), DriveKind::StepsPerS, "the robot's drive is a step rate");
    assert_eq!(p.store().time_range_s().unwrap().0, first, "the simulation's rows are kept");
    let switch = p.switches()[0].0;
    let (drawn_from, _) = p.drawn_s(Quantity::Drive).expect("the robot's rows are drawn");
    assert!(drawn_from > switch, "N·m rows drawn under steps/s: from {drawn_from} s, switch at {switch} s");
    assert!(has_label(&h, "not drawn under steps/s"), "the plot says the simulation's torque is left out");

    h.state_mut().queue_command(AppCommand::Link(LinkCommand::Disconnect));
    until(&mut h, "the simulation again", 15.0, |h| h.state().backend().state().source == StateSource::Simulation);
    until(&mut h, "rows of the simulation after the robot's", 15.0, |h| {
        let p = h.state().plots_panel();
        p.switches().len() == 2 && p.store().drive() == DriveKind::TorqueNm
    });
    let back = h.state().plots_panel().switches()[1].0;
    until(&mut h, "the simulation's torque drawn after the robot's stretch", 15.0, |h| {
        h.state().plots_panel().drawn_s(Quantity::Drive).is_some_and(|(_, to)| to > back + 0.1)
    });
    assert!(has_label(&h, "not drawn under N·m"), "the plot says the robot's step rates are left out");
    let (from, _) = h.state().plots_panel().drawn_s(Quantity::Drive).unwrap();
    assert!(
        from < switch,
        "the first simulation stretch is drawn too: from {from} s (first {first}, switch {switch}, back {back}, switches {:?})",
        h.state().plots_panel().switches()
    );
}

/// Issue 32 (the plot CSV across a backend switch): the drive series hold torque (N·m) in the
/// simulation and step rates (steps/s) on the robot. The CSV wrote every row under one drive
/// column named after the current unit; now each quantity has its own columns, a row's value
/// stands only under its own unit, and a `backend` column names each row's source.
#[test]
fn the_csv_of_a_window_across_a_backend_switch_puts_each_drive_value_under_its_own_unit() {
    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    simulation_then_robot(&mut h, parol6_core::telemetry::Quantity::Drive, 0.5);
    h.run_steps(2);
    let switch = h.state().plots_panel().switches()[0].0;
    let out = temp_dir("csv-switch").join("switch.csv");
    h.get_by_label("Export to").click();
    h.run_steps(1);
    h.get_by_label("Export to").type_text(&out.display().to_string());
    h.run_steps(1);
    h.get_by_label("CSV of the visible window").click();
    h.run_steps(2);
    let text = std::fs::read_to_string(&out).expect("the CSV was written");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no {name} in {header:?}"));
    let (t, backend) = (col("t_s"), col("backend"));
    let torque: Vec<usize> = (1..=6).map(|j| col(&format!("j{j}_torque_nm"))).collect();
    let steps: Vec<usize> = (1..=6).map(|j| col(&format!("j{j}_steps_s"))).collect();
    let (mut sim_rows, mut robot_rows) = (0, 0);
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells.len(), header.len(), "plain CSV, one cell per column: {line}");
        let at: f64 = cells[t].parse().unwrap();
        let (filled, empty) = match cells[backend] {
            "simulation" => {
                sim_rows += 1;
                assert!(at <= switch, "a simulation row after the switch at {switch} s: {line}");
                (&torque, &steps)
            }
            "robot" => {
                robot_rows += 1;
                assert!(at > switch, "a robot row before the switch at {switch} s: {line}");
                (&steps, &torque)
            }
            other => panic!("backend {other:?}: {line}"),
        };
        assert!(empty.iter().all(|&c| cells[c].is_empty()), "a value under the other backend's unit: {line}");
        assert!(filled.iter().all(|&c| cells[c].parse::<f64>().is_ok()), "its own unit's values: {line}");
    }
    assert!(
        sim_rows > 100 && robot_rows > 10,
        "both stretches exported: {sim_rows} simulation, {robot_rows} robot rows"
    );
}

/// The hover read-out as painted: the rectangle of its text, the rectangle it is clipped to (the
/// plot it belongs to) and its text.
fn painted_readout(h: &Harness<'_, Parol6App>) -> Option<(egui::Rect, egui::Rect, String)> {
    fn walk(shape: &egui::Shape, clip: egui::Rect, out: &mut Option<(egui::Rect, egui::Rect, String)>) {
        match shape {
            egui::Shape::Text(t) if t.galley.text().contains("\nJ1: ") => {
                *out = Some((t.visual_bounding_rect(), clip, t.galley.text().to_string()));
            }
            egui::Shape::Vec(v) => v.iter().for_each(|s| walk(s, clip, out)),
            _ => {}
        }
    }
    let mut out = None;
    for clipped in &h.output().shapes {
        walk(&clipped.shape, clipped.clip_rect, &mut out);
    }
    out
}

/// The app at 1024×700 with the position plot alone (over the last 30 s), `s` seconds of live
/// samples in it.
fn small_window_with_positions(s: f64) -> Harness<'static, Parol6App> {
    let mut h = app_harness(egui::vec2(1024.0, 700.0));
    h.state_mut().show_plot(parol6_core::telemetry::Quantity::Position);
    until(&mut h, "live samples", 20.0, |h| {
        h.state().plots_panel().store().time_range_s().is_some_and(|(first, last)| last - first > s)
    });
    h
}

/// Hovers the points at `x` below the plots' export row, top to bottom, until a read-out shows;
/// returns it (see [`painted_readout`]).
fn hover_readout(h: &mut Harness<'_, Parol6App>, x: f32) -> Option<(egui::Rect, egui::Rect, String)> {
    let export = h.get_by_label("Export to").rect();
    let bottom = h.ctx.content_rect().bottom();
    let mut y = export.bottom() + 10.0;
    while y < bottom {
        h.hover_at(egui::pos2(x, y));
        h.run_steps(3);
        if let Some(r) = painted_readout(h) {
            return Some(r);
        }
        y += 10.0;
    }
    None
}

/// trial10 n6: at 1024×700, in replay (the timeline above the plots), the plots panel's one
/// plot is shorter than the read-out's seven rows (the time and six joints): the box was cut at
/// J3 by the plot's bottom. Where the rows do not fit its values stand side by side: the whole
/// box lies inside the plot.
#[test]
fn the_hover_readout_fits_inside_a_short_plot() {
    let (dir, mut h) = replaying("readout", "short.mcap", 0.5, 250.0, egui::vec2(1024.0, 700.0));
    h.key_press(egui::Key::Escape);
    h.run_steps(5);
    let (left, right) = (parol6_app::app::LEFT_PANEL_WIDTH, 1024.0 - parol6_app::app::RIGHT_PANEL_WIDTH);
    let (rect, plot, text) = hover_readout(&mut h, (left + right) / 2.0).expect("a read-out");
    // the values side by side: seven rows would not fit (the old box reached out of the plot)
    assert!(text.lines().count() < 7, "the test needs a plot shorter than seven rows: {plot:?}\n{text}");
    assert!(plot.contains_rect(rect.shrink(0.5)), "the read-out {rect:?} reaches out of its plot {plot:?}:\n{text}");
    for j in 1..=6 {
        assert!(text.contains(&format!("J{j}: ")), "J{j} in the read-out: {text}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// trial9 m3: hovering a plot before its first sample (or past its last) read out the nearest
/// sample's values at a time with none ("t = -4.6 s"). There is no read-out outside the data.
#[test]
fn no_hover_readout_where_the_plot_has_no_samples() {
    let mut h = small_window_with_positions(6.0);
    let (first, last) = h.state().plots_panel().store().time_range_s().unwrap();
    assert!(last - first < 10.0, "the 30 s window starts well before the data: {first}–{last}");
    let (left, right) = (parol6_app::app::LEFT_PANEL_WIDTH, 1024.0 - parol6_app::app::RIGHT_PANEL_WIDTH);
    // the middle of the window: about 15 s before the newest sample, before the first
    assert_eq!(hover_readout(&mut h, (left + right) / 2.0), None, "a read-out before the data");
    // near the right end: the newest samples
    assert!(hover_readout(&mut h, right - 30.0).is_some(), "and one over the samples");
}

/// trial9 m3: closing a replay left the live plots without their history from before it (the
/// lines started at the last disconnect); a connection and a disconnection alone kept it. The
/// live history stays over a replay, with none of the recording's samples in it.
#[test]
fn closing_a_replay_keeps_the_live_plot_history() {
    use parol6_app::panels::{AppCommand, LinkCommand, StateSource};
    let mut h = app_harness(egui::vec2(1280.0, 1000.0));
    simulation_then_robot(&mut h, parol6_core::telemetry::Quantity::Position, 1.0);
    // a recording of the robot, as the trials made it: File → Record, a program, Stop
    let dir = temp_dir("replay-history");
    let path = dir.join("r.mcap");
    h.state_mut().queue_command(AppCommand::Record(Some(path.clone())));
    h.run_steps(2);
    h.get_by_label("Draw").click();
    until(&mut h, "the pre-flight", 10.0, |h| has_label(h, "pre-flight: ok"));
    h.get_by_label("Run (F5)").click();
    let t = std::time::Instant::now();
    while t.elapsed() < std::time::Duration::from_secs(2) {
        h.run_steps(1);
        std::thread::sleep(std::time::Duration::from_millis(15));
    }
    h.state_mut().queue_command(AppCommand::Link(LinkCommand::Disconnect));
    until(&mut h, "the simulation again", 15.0, |h| h.state().backend().state().source == StateSource::Simulation);
    until(&mut h, "rows of the simulation after the robot's", 15.0, |h| h.state().plots_panel().switches().len() == 2);
    h.run_steps(20);
    let (first, before_s) = h.state().plots_panel().store().time_range_s().unwrap();
    let switches = h.state().plots_panel().switches();
    ui_support::open_recording(&mut h, &path);
    until(&mut h, "the replay", 10.0, |h| has_label(h, "Replay: r.mcap"));
    h.key_press(egui::Key::Escape);
    h.get_by_label("Play").click();
    let t = std::time::Instant::now();
    while t.elapsed() < std::time::Duration::from_secs(1) {
        h.run_steps(1);
        std::thread::sleep(std::time::Duration::from_millis(15));
    }
    h.state_mut().queue_command(AppCommand::CloseRecording);
    until(&mut h, "live rows after the replay", 10.0, |h| {
        h.state().replay().is_none()
            && h.state().plots_panel().store().time_range_s().is_some_and(|(_, last)| last > before_s + 1.0)
    });
    let p = h.state().plots_panel();
    let (first_after, _) = p.store().time_range_s().unwrap();
    assert_eq!(first_after, first, "the live history from before the replay is kept");
    assert_eq!(p.switches(), switches, "with its backend switches");
    let _ = std::fs::remove_dir_all(&dir);
}
