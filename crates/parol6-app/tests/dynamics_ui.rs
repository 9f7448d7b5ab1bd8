//! The dynamics panel, driven headless through egui's kittest harness on the full app: it
//! opens from the View menu with the program's joint torques against the motor limits, and a
//! torque typed for J1 runs on the simulation: the arm moves, and stands still again once the
//! run time is over.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

use std::time::Duration;

mod ui_support;

use eframe::egui;

use egui_kittest::kittest::{NodeT, Queryable};
use parol6_app::app::{LEFT_PANEL_WIDTH, RIGHT_PANEL_WIDTH};
use ui_support::{app_harness, has_label, type_into, until};

#[test]
fn the_dynamics_panel_shows_program_torques_and_runs_a_torque_on_the_simulation() {
    let mut h = app_harness(egui::vec2(1400.0, 1500.0));
    // the panel under the 3D view tall enough to show the plots and the whole form (a shorter
    // one scrolls inside)
    h.state_mut().settings_mut().lower_panel_height_pt = 1200.0;
    h.run_steps(2);
    assert!(!has_label(&h, "Run torques"), "the dynamics panel starts hidden");
    h.get_by_label("View").click();
    h.run_steps(2);
    h.get_by_label("Dynamics").click();
    h.run_steps(2);
    h.key_press(egui::Key::Escape);
    h.run_steps(1);
    // the program panel's program, from the pose the arm stands in
    until(&mut h, "the program's torques", 10.0, |h| has_label(h, "J2 peak"));
    let t = h.state().dynamics_panel().torques().expect("analysed").clone();
    assert_eq!(t.torques_nm.len(), 6);
    assert!(t.peak_abs_nm[1] > 0.5, "J2 carries the arm: {:?}", t.peak_abs_nm);
    assert!(has_label(&h, "torques within the motor limits"));

    let q0 = h.state().sim().snapshot().q.clone();
    type_into(&mut h, "J1 torque", "0.1");
    type_into(&mut h, "Run time", "0.6");
    h.get_by_label("Run torques").click();
    until(&mut h, "J1 to turn", 10.0, |h| (h.state().sim().snapshot().q[0] - q0[0]).abs() > 0.01);
    // the run ends by itself: the motors take over and the arm stands still where it got to
    until(&mut h, "the run to end", 10.0, |h| !h.state().sim().snapshot().moving);
    std::thread::sleep(Duration::from_millis(300));
    let a = h.state().sim().snapshot();
    std::thread::sleep(Duration::from_millis(200));
    let b = h.state().sim().snapshot();
    assert!(b.q[0] - q0[0] > 0.01, "J1 turned the way the torque pushed: {} → {}", q0[0], b.q[0]);
    assert!((b.q[0] - a.q[0]).abs() < 0.01, "J1 holds after the run: {} → {}", a.q[0], b.q[0]);
    assert!(h.state().notices().iter().all(|n| !n.error), "{:?}", h.state().notices());
}

/// Issue 32 major 10: forward dynamics said nothing of what it simulates and showed no
/// progress or outcome; 0.2 N·m on J1 whipped every other joint about. The form now says what
/// is simulated (free joints, no friction), shows the run's progress and its outcome, and
/// "hold other joints" keeps the joints without a torque on their motors.
#[test]
fn forward_dynamics_explains_itself_shows_progress_and_outcome_and_can_hold_the_other_joints() {
    let mut h = app_harness(egui::vec2(1400.0, 1500.0));
    // the panel under the 3D view tall enough to show the plots and the whole form (a shorter
    // one scrolls inside)
    h.state_mut().settings_mut().lower_panel_height_pt = 1200.0;
    h.run_steps(2);
    h.get_by_label("View").click();
    h.run_steps(2);
    h.get_by_label("Dynamics").click();
    h.run_steps(2);
    h.key_press(egui::Key::Escape);
    h.run_steps(2);
    assert!(has_label(&h, "no friction"), "what is simulated is said");
    assert!(has_label(&h, "joints without a torque are free"), "free joints are said");
    assert!(has_label(&h, "no torque run yet"));
    h.get_by_label("hold other joints").click();
    h.run_steps(2);
    assert!(has_label(&h, "joints without a torque held on their motors"), "the explanation follows the switch");

    let q0 = h.state().sim().snapshot().q.clone();
    type_into(&mut h, "J1 torque", "0.2");
    type_into(&mut h, "Run time", "1");
    h.get_by_label("Run torques").click();
    until(&mut h, "the progress bar", 5.0, |h| has_label(h, "torque run: "));
    until(&mut h, "the outcome", 10.0, |h| has_label(h, "torque run done"));
    let q = h.state().sim().snapshot().q.clone();
    assert!(q[0] - q0[0] > 0.05, "J1 turned: {} → {}", q0[0], q[0]);
    let others = q.iter().zip(&q0).skip(1).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(others < 0.02, "the other joints held within 0.02 rad: {others:.4} rad, {q0:?} → {q:?}");
    assert!(has_label(&h, "the motors hold there"), "the outcome says what happens next");
}

/// trial6: a negative or zero run time was taken by the field (shown as "-2.00") and refused
/// only at Run torques; it is refused when typed now, with the range, and the field keeps its
/// value, like the other fields of the window.
#[test]
fn a_run_time_outside_its_range_is_refused_when_typed() {
    let mut h = app_harness(egui::vec2(1400.0, 1500.0));
    h.state_mut().settings_mut().lower_panel_height_pt = 1200.0;
    h.state_mut().settings_mut().show_dynamics = true;
    h.state_mut().settings_mut().show_plots = false;
    h.run_steps(3);
    for typed in ["-2", "0", "601"] {
        type_into(&mut h, "Run time", typed);
        let said = format!("Run time: {typed} s is outside 0–600 s (above 0); it stays 2.00 s");
        assert!(h.state().notices().iter().any(|n| n.error && n.text == said), "{typed}: {:?}", h.state().notices());
        assert_eq!(h.get_by_label("Run time").value().as_deref(), Some("2.00"), "{typed} is not taken");
    }
    type_into(&mut h, "Run time", "1,5");
    assert_eq!(h.get_by_label("Run time").value().as_deref(), Some("1.50"), "a decimal comma is taken");
}

/// The rectangle of the one widget labelled `label` (a plots toggle: the panel's marker).
fn rect_of(h: &egui_kittest::Harness<'_, parol6_app::app::Parol6App>, label: &str) -> Option<egui::Rect> {
    h.query_all_by_label_contains(label).next().map(|n| n.rect())
}

/// Whether `r` lies in sight: inside the window, above its status bar.
fn in_sight(r: Option<egui::Rect>, size: egui::Vec2) -> bool {
    r.is_some_and(|r| r.top() >= 0.0 && r.bottom() <= size.y - 24.0 && r.left() >= 0.0 && r.right() <= size.x)
}

/// The app with the plots and the dynamics ticked, in a window of `size`, its settings in
/// `settings` (the remembered tab).
fn both_panels(
    size: egui::Vec2,
    settings: &std::path::Path,
) -> egui_kittest::Harness<'static, parol6_app::app::Parol6App> {
    let opts =
        parol6_app::app::LaunchOptions { settings_path: Some(settings.to_path_buf()), ..ui_support::launch_options() };
    let mut h = ui_support::harness_with(opts, size);
    {
        let s = h.state_mut().settings_mut();
        s.show_plots = true;
        s.show_dynamics = true;
    }
    h.run_steps(4);
    h
}

/// Issue 32 minor: with both Plots and Dynamics ticked, the dynamics sat below the plots in the
/// lower panel's scroll area, out of sight at 1024×700 (the user had to scroll to find it). Now
/// at every size of the hand trial both are reachable in place: side by side at 1600×1000, as
/// two tabs at 1024×700 and 1280×800, where a click on a tab shows its panel in sight and the
/// tabs stay where they are.
#[test]
fn with_plots_and_dynamics_ticked_both_are_in_sight_at_every_window_size() {
    let dir = std::env::temp_dir().join(format!("parol6-dynamics-ui-both-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (size, side_by_side) in
        [(egui::vec2(1024.0, 700.0), false), (egui::vec2(1280.0, 800.0), false), (egui::vec2(1600.0, 1000.0), true)]
    {
        let mut h = both_panels(size, &dir.join(format!("{}.json", size.x)));
        let plots = || "cmd - meas";
        let dynamics = "joint torques of";
        if side_by_side {
            let (p, d) = (rect_of(&h, plots()), rect_of(&h, dynamics));
            assert!(in_sight(p, size) && in_sight(d, size), "at {size:?} both in sight: plots {p:?}, dynamics {d:?}");
            let (p, d) = (p.unwrap(), d.unwrap());
            assert!(d.left() > p.right() - 1.0 && (d.top() - p.top()).abs() < 40.0, "side by side: {p:?} {d:?}");
            continue;
        }
        // the plots in front first (a fresh start), the dynamics' tab in sight beside its tab
        assert!(in_sight(rect_of(&h, plots()), size), "at {size:?} the plots in sight");
        let tabs = |h: &egui_kittest::Harness<'_, parol6_app::app::Parol6App>| {
            let tab = |name| h.query_all_by_label(name).map(|n| n.rect()).find(|r| r.top() > 60.0);
            (tab("Plots"), tab("Dynamics"))
        };
        let (plots_tab, dynamics_tab) = tabs(&h);
        assert!(in_sight(plots_tab, size) && in_sight(dynamics_tab, size), "at {size:?} the tabs: {:?}", tabs(&h));
        h.query_all_by_label("Dynamics").find(|n| n.rect().top() > 60.0).unwrap().click();
        h.run_steps(3);
        assert!(in_sight(rect_of(&h, dynamics), size), "at {size:?} a click on the tab shows the dynamics");
        assert_eq!(tabs(&h), (plots_tab, dynamics_tab), "at {size:?} the tabs do not move");
        h.query_all_by_label("Plots").find(|n| n.rect().top() > 60.0).unwrap().click();
        h.run_steps(3);
        assert!(in_sight(rect_of(&h, plots()), size), "at {size:?} and back to the plots");
        assert!(!in_sight(rect_of(&h, dynamics), size), "at {size:?} one tab at a time");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The tab in front survives a restart (settings), and ticking a panel in the View menu brings
/// its tab forward.
#[test]
fn the_lower_panels_tab_survives_a_restart_and_a_ticked_panel_comes_forward() {
    let dir = std::env::temp_dir().join(format!("parol6-dynamics-ui-tab-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("settings.json");
    let size = egui::vec2(1280.0, 800.0);
    let mut h = both_panels(size, &path);
    h.query_all_by_label("Dynamics").find(|n| n.rect().top() > 60.0).unwrap().click();
    until(&mut h, "the tab in the settings file", 10.0, |_| {
        parol6_app::app::load_settings(Some(&path)).lower_tab == "Dynamics"
    });
    drop(h);
    let mut h = both_panels(size, &path);
    assert!(in_sight(rect_of(&h, "joint torques of"), size), "the dynamics in front after the restart");

    // unticking and ticking the plots again brings them forward
    h.get_by_label("View").click();
    h.run_steps(2);
    for _ in 0..2 {
        h.get_by_role_and_label(egui::accesskit::Role::CheckBox, "Plots").click();
        h.run_steps(2);
    }
    h.key_press(egui::Key::Escape);
    h.run_steps(3);
    assert!(in_sight(rect_of(&h, "cmd - meas"), size), "the plots ticked come forward");
    assert!(!in_sight(rect_of(&h, "joint torques of"), size), "in front of the dynamics");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The numbers painted as text between the heights `top` and `bottom`, drawn at least at
/// 80 % opacity (egui_plot paints the labels of ticks too close together faded, down to
/// invisible): (position, value).
fn painted_numbers(
    h: &egui_kittest::Harness<'_, parol6_app::app::Parol6App>,
    top: f32,
    bottom: f32,
) -> Vec<(egui::Pos2, f64)> {
    fn walk(shape: &egui::Shape, out: &mut Vec<(egui::Pos2, String, u8)>) {
        match shape {
            egui::Shape::Text(t) => out.push((t.pos, t.galley.text().to_string(), t.fallback_color.a())),
            egui::Shape::Vec(v) => v.iter().for_each(|s| walk(s, out)),
            _ => {}
        }
    }
    let mut texts = Vec::new();
    for clipped in &h.output().shapes {
        walk(&clipped.shape, &mut texts);
    }
    texts
        .into_iter()
        .filter(|(p, _, alpha)| p.y > top && p.y < bottom && *alpha >= 204)
        .filter_map(|(p, t, _)| t.trim().parse::<f64>().ok().map(|v| (p, v)))
        .collect()
}

/// Trial 7: the program's torque plot (about ±10 N·m in 180 points) labelled its value axis
/// with "0" alone, as the plots panel did before issue 32's major 5. It now uses the plots'
/// value axis: at least two labelled ticks.
#[test]
fn the_torque_plot_labels_at_least_two_ticks_on_its_value_axis() {
    let mut h = app_harness(egui::vec2(1600.0, 1000.0));
    h.get_by_label("View").click();
    h.run_steps(2);
    h.get_by_label("Dynamics").click();
    h.run_steps(2);
    h.key_press(egui::Key::Escape);
    until(&mut h, "the program's torques", 10.0, |h| has_label(h, "J2 peak"));
    h.run_steps(3);
    let top = h.get_by_label_contains("limits: motor holding torque").rect().bottom();
    let bottom = h.get_by_label("Forward dynamics (simulation)").rect().top();
    // the lower panel's width: between the left and the right columns
    let (left, right) = (LEFT_PANEL_WIDTH, 1600.0 - RIGHT_PANEL_WIDTH);
    let numbers: Vec<_> =
        painted_numbers(&h, top, bottom).into_iter().filter(|(p, _)| p.x > left && p.x < right).collect();
    // the time axis: the row that holds the most numbers
    let row_of = |p: egui::Pos2| (p.y / 4.0).round() as i64;
    let mut rows = std::collections::HashMap::new();
    for (p, _) in &numbers {
        *rows.entry(row_of(*p)).or_insert(0) += 1;
    }
    let time_row = rows.iter().max_by_key(|(_, n)| **n).map(|(r, _)| *r).expect("the time axis' labels");
    let values: Vec<f64> = numbers.iter().filter(|(p, _)| row_of(*p) != time_row).map(|(_, v)| *v).collect();
    assert!(values.len() >= 2, "value-axis labels {values:?} (all numbers painted: {numbers:?})");
}

/// trial8: at 1024×700 the forward-dynamics row (run time, gravity compensation, hold other
/// joints, Run torques, Stop torques) was one plain row wider than the centre column: "Run
/// torques" and "Stop torques" lay under the right panel, out of reach, so the forward dynamics
/// could not be run at the smallest window size. The row wraps now; both buttons lie inside
/// the centre column at every size of the hand trial.
#[test]
fn the_torque_run_buttons_lie_inside_the_centre_column_at_every_window_size() {
    for size in [egui::vec2(1024.0, 700.0), egui::vec2(1280.0, 800.0), egui::vec2(1600.0, 1000.0)] {
        let mut h = app_harness(size);
        h.state_mut().settings_mut().show_dynamics = true;
        h.run_steps(4);
        let (left, right) = (LEFT_PANEL_WIDTH, size.x - RIGHT_PANEL_WIDTH);
        for label in ["Run torques", "Stop torques"] {
            let r = rect_of(&h, label).unwrap_or_else(|| panic!("at {size:?} no {label} button"));
            assert!(
                r.left() >= left - 1.0 && r.right() <= right + 1.0,
                "at {size:?} {label} at x {:.0}–{:.0}, the centre column is {left:.0}–{right:.0}",
                r.left(),
                r.right()
            );
        }
    }
}

/// The window at `size` with the Dynamics panel open and the program's torques drawn.
fn dynamics_at_1024(size: egui::Vec2) -> egui_kittest::Harness<'static, parol6_app::app::Parol6App> {
    let mut h = app_harness(size);
    h.state_mut().settings_mut().show_dynamics = true;
    h.run_steps(4);
    until(&mut h, "the program's torques", 20.0, |h| {
        has_label(h, "J2 peak") && !h.state().dynamics_panel().computing()
    });
    h
}

/// trial10, 1024×700: with the dynamics panel scrolled to its forward-dynamics form, each time
/// the arm stood still again (after a torque run, a jog or a program) the inverse dynamics was
/// recomputed and showed one "computing…" line instead of its plot: the panel's scroll clamped
/// and the form jumped away from the pointer (Run torques went to the top of the panel, a
/// second click landed on the torque plot). The section keeps its height while it computes.
#[test]
fn a_torque_run_ending_moves_nothing_in_the_scrolled_dynamics_panel() {
    let size = egui::vec2(1024.0, 700.0);
    let mut h = dynamics_at_1024(size);
    // the panel under the 3D view scrolled to its end: the forward-dynamics form in sight
    let over_panel = egui::pos2((LEFT_PANEL_WIDTH + size.x - RIGHT_PANEL_WIDTH) / 2.0, size.y - 60.0);
    ui_support::scroll_to_the_end(&mut h, over_panel);
    let before = h.get_by_label("Run torques").rect();
    assert!(in_sight(Some(before), size), "Run torques in sight: {before:?}");
    h.get_by_label("hold other joints").click();
    h.run_steps(2);
    type_into(&mut h, "J1 torque", "0.2");
    type_into(&mut h, "Run time", "0.6");
    let before = h.get_by_label("Run torques").rect();
    h.get_by_label("Run torques").click();
    until(&mut h, "the run to start", 10.0, |h| h.state().sim().snapshot().moving);
    let mut worst = (0.0_f32, before);
    let mut recomputed = false;
    let deadline = std::time::Instant::now() + Duration::from_secs(30);
    // through the run, its end, the new analysis and its result
    loop {
        h.run_steps(1);
        let now = h.get_by_label("Run torques").rect();
        let moved = (now.min - before.min).length();
        if moved > worst.0 {
            worst = (moved, now);
        }
        let panel = h.state().dynamics_panel();
        recomputed |= panel.computing();
        if recomputed && !panel.computing() && !h.state().sim().snapshot().moving {
            break;
        }
        assert!(std::time::Instant::now() < deadline, "timed out waiting for the new analysis");
        std::thread::sleep(Duration::from_millis(15));
    }
    h.run_steps(30);
    let after = h.get_by_label("Run torques").rect();
    assert!(has_label(&h, "torque run done"), "the run ended");
    assert!(
        worst.0 < 0.5 && (after.min - before.min).length() < 0.5,
        "Run torques moved from {before:?} to {:?} (by {:.0} pt) while the torques were recomputed, ending at {after:?}",
        worst.1,
        worst.0
    );
}

/// The app with the dynamics panel alone in a panel tall enough for the plot and the whole form.
fn dynamics_harness() -> egui_kittest::Harness<'static, parol6_app::app::Parol6App> {
    let mut h = app_harness(egui::vec2(1400.0, 1500.0));
    {
        let s = h.state_mut().settings_mut();
        s.lower_panel_height_pt = 1200.0;
        s.show_dynamics = true;
        s.show_plots = false;
    }
    h.run_steps(3);
    h
}

/// A key pressed and let go, no modifier.
fn press(h: &mut egui_kittest::Harness<'_, parol6_app::app::Parol6App>, key: egui::Key) {
    let modifiers = egui::Modifiers::NONE;
    h.event(egui::Event::Key { key, pressed: true, modifiers, repeat: false, physical_key: None });
    h.run_steps(2);
    h.event(egui::Event::Key { key, pressed: false, modifiers, repeat: false, physical_key: None });
    h.run_steps(2);
}

/// trial9 m5: during a forward-dynamics torque run, H over the 3D view homed the arm and a jog
/// key jogged it: the run ended at once without a word. Manual motion is refused during a
/// torque run as during a program, with a notice naming the run; the run goes on to its end.
#[test]
fn a_torque_run_refuses_home_jogs_and_joint_moves_with_a_notice_naming_it() {
    let mut h = dynamics_harness();
    h.get_by_label("hold other joints").click();
    h.run_steps(2);
    type_into(&mut h, "J1 torque", "0.05");
    type_into(&mut h, "Run time", "30");
    h.get_by_label("Run torques").click();
    until(&mut h, "the run to start", 10.0, |h| has_label(h, "torque run: ") && h.state().sim().snapshot().moving);
    let sent = h.state().moves_sent().count();
    let said = "refused: a forward-dynamics torque run is driving the arm";
    // a refusal raised (or renewed) since `t`
    let refused = |h: &egui_kittest::Harness<'_, parol6_app::app::Parol6App>, t: std::time::Instant| {
        h.state().notices().iter().any(|n| n.error && n.text.starts_with(said) && n.at >= t)
    };
    // H and a held jog letter with the pointer over the 3D view
    ui_support::pointer_on_view(&mut h);
    let t = std::time::Instant::now();
    press(&mut h, egui::Key::H);
    assert_eq!(h.state().moves_sent().skip(sent).collect::<Vec<_>>(), [] as [&str; 0], "H ended the torque run");
    assert!(refused(&h, t), "H: {:?}", h.state().notices());
    let t = std::time::Instant::now();
    h.event(egui::Event::Key {
        key: egui::Key::D,
        pressed: true,
        modifiers: egui::Modifiers::NONE,
        repeat: false,
        physical_key: None,
    });
    h.run_steps(4);
    assert!(refused(&h, t), "the jog key D: {:?}", h.state().notices());
    h.event(egui::Event::Key {
        key: egui::Key::D,
        pressed: false,
        modifiers: egui::Modifiers::NONE,
        repeat: false,
        physical_key: None,
    });
    h.run_steps(2);
    // the jog buttons are greyed with the reason, a typed joint target is refused
    assert!(h.get_by_label("+X").accesskit_node().is_disabled(), "+X greyed during the torque run");
    let t = std::time::Instant::now();
    type_into(&mut h, "J2 target", "10");
    assert!(refused(&h, t), "a typed joint target: {:?}", h.state().notices());
    let moved: Vec<String> = h.state().moves_sent().skip(sent).map(str::to_string).collect();
    assert!(moved.is_empty(), "motion sent during the torque run: {moved:?}");
    assert!(h.state().sim().snapshot().moving && has_label(&h, "torque run: "), "the torque run goes on");
    // STOP still ends it, and the form says so
    press(&mut h, egui::Key::Escape);
    until(&mut h, "the run to end", 10.0, |h| has_label(h, "torque run stopped after"));
}

/// trial10 n5: on the robot, Run torques was refused with a notice, yet the form's line then
/// said "torque run stopped after 0.5 s: J1 0.00°, …" as if a run had happened. A refused run
/// is said on the form's line, with the reason, and nothing else.
#[test]
fn run_torques_refused_on_the_robot_says_so_on_the_forms_line() {
    use parol6_app::panels::{AppCommand, LinkCommand, StateSource};
    let mut h = dynamics_harness();
    h.state_mut().queue_command(AppCommand::Link(LinkCommand::ConnectEmulator));
    until(&mut h, "the emulator answers", 15.0, |h| h.state().backend().state().source == StateSource::Robot);
    type_into(&mut h, "J1 torque", "0.1");
    h.get_by_label("Run torques").click();
    h.run_steps(2);
    let line = "torque run refused: torque runs drive the simulation only: disconnect the robot first";
    assert!(has_label(&h, line), "the form's line says why");
    assert!(h.state().notices().iter().any(|n| n.error && n.text == line), "{:?}", h.state().notices());
    // past the time the form waited for a run to start
    let until_s = std::time::Instant::now() + Duration::from_millis(1500);
    while std::time::Instant::now() < until_s {
        h.run_steps(1);
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(!has_label(&h, "torque run stopped") && !has_label(&h, "torque run done"), "no run was reported");
    assert!(has_label(&h, line), "the line still says why");
}

/// trial9 m4: a torque of 1e9 was taken and shown cut ("10000("), refused only at Run torques.
/// The form's numbers are refused when typed, with the field's range and unit, and keep their
/// value, as the window's other numeric fields do.
#[test]
fn a_torque_outside_its_range_is_refused_when_typed() {
    let mut h = dynamics_harness();
    for (typed, shown) in [("1e9", "1000000000"), ("-100.5", "-100.5")] {
        type_into(&mut h, "J3 torque", typed);
        let said = format!("J3 torque: {shown} N·m is outside -100–100 N·m; it stays 0.000 N·m");
        assert!(h.state().notices().iter().any(|n| n.error && n.text == said), "{typed}: {:?}", h.state().notices());
        assert_eq!(h.get_by_label("J3 torque").value().as_deref(), Some("0.000"), "{typed} is not taken");
    }
    let t = std::time::Instant::now();
    type_into(&mut h, "J3 torque", "-100");
    assert_eq!(h.get_by_label("J3 torque").value().as_deref(), Some("-100.000"), "the bound is taken");
    assert!(h.state().notices().iter().all(|n| !n.error || n.at < t), "{:?}", h.state().notices());
}

/// trial10 n6: the mouse wheel over the program's torque plot panned its value axis (−8…8 →
/// −26…−44 N·m, the lines out of sight) while the panel scrolled. The wheel scrolls the panel
/// only: the plot's value axis stays as it was.
#[test]
fn the_wheel_over_the_torque_plot_scrolls_the_panel_not_the_plot() {
    let size = egui::vec2(1024.0, 700.0);
    let mut h = dynamics_at_1024(size);
    h.run_steps(3);
    let (left, right) = (LEFT_PANEL_WIDTH, size.x - RIGHT_PANEL_WIDTH);
    let limits = h.get_by_label_contains("limits: motor holding torque").rect();
    let numbers = |h: &egui_kittest::Harness<'_, parol6_app::app::Parol6App>| {
        let mut v: Vec<f64> = painted_numbers(h, limits.bottom(), size.y)
            .into_iter()
            .filter(|(p, _)| p.x > left && p.x < right)
            .map(|(_, v)| v)
            .collect();
        v.sort_by(f64::total_cmp);
        v
    };
    let before = numbers(&h);
    assert!(before.len() >= 2, "the plot's labels: {before:?}");
    let over_plot = egui::pos2((left + right) / 2.0, limits.bottom() + 70.0);
    let run_before = h.get_by_label("Run torques").rect();
    // up, at the panel's top: the panel cannot scroll, the plot must not pan
    for dy in [300.0, 300.0] {
        h.event(egui::Event::PointerMoved(over_plot));
        h.event(egui::Event::MouseWheel {
            unit: egui::MouseWheelUnit::Point,
            delta: egui::vec2(0.0, dy),
            phase: egui::TouchPhase::Move,
            source: egui::MouseWheelSource::Unknown,
            modifiers: egui::Modifiers::NONE,
        });
        h.run_steps(1);
    }
    h.run_steps(30);
    assert_eq!(numbers(&h), before, "the wheel panned the torque plot");
    // down: the panel scrolls towards the form
    ui_support::scroll_to_the_end(&mut h, over_plot);
    let run_after = h.get_by_label("Run torques").rect();
    assert!(run_after.top() < run_before.top() - 20.0, "the panel scrolled: {run_before:?} → {run_after:?}");
}
