//! Minor defects of trials 9 and 10, driven headless through egui's kittest harness on the full
//! app: the Cartesian jog's row of steps ends when another motion starts, the point table stays
//! open (read-only) while a program runs, and notices keep clear of the open windows' title
//! bars and of an open menu.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use parol6_app::app::Parol6App;
use parol6_app::panels::AppCommand;
use parol6_core::motion::MotionCommand;
use ui_support::{app_harness, has_label, settle, until};

/// A pose away from the standby wrist singularity (J5 = 34°).
fn work_pose() -> Vec<f64> {
    let mut q = parol6_core::parol6::standby_rad().to_vec();
    q[1] += 0.2;
    q[2] -= 0.3;
    q[4] = 0.6;
    q
}

/// Every label (or text value) of the window that contains `part`.
fn labels_with(h: &Harness<'_, Parol6App>, part: &str) -> Vec<String> {
    h.query_all_by_label_contains(part).filter_map(|n| n.accesskit_node().label().or_else(|| n.value())).collect()
}

/// Waits until the simulated arm has come to rest.
fn at_rest(h: &mut Harness<'_, Parol6App>) {
    settle(h, 0.3);
    until(h, "the arm at rest", 20.0, |h| !h.state().backend().state().moving);
    settle(h, 0.2);
}

/// trial9 m1: the Step-mode line compared the TCP with where its row of steps started at every
/// frame, so after a joint move or HOME it said "+Z (world) step 1.00 mm (2 steps in a row: 2.00
/// mm): moved 77.61 mm (see the notices)", and the next step counted as the third in the row.
/// Another motion ends the row: the line empties, and the next step starts a new row.
#[test]
fn another_motion_ends_the_row_of_jog_steps() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    h.state_mut().teleport(work_pose()).expect("teleport");
    settle(&mut h, 0.3);
    h.get_by_label("Step").click();
    h.run_steps(2);
    for _ in 0..2 {
        h.get_by_label("+Z").click();
        at_rest(&mut h);
    }
    assert!(has_label(&h, "+Z (world) step 1.00 mm (2 steps in a row: 2.00 mm)"), "{:?}", labels_with(&h, "(world)"));

    // a joint move ends the row
    let mut goal = work_pose();
    goal[0] += 0.3;
    h.state_mut().queue_command(AppCommand::Motion(MotionCommand::MoveJoints {
        goal_rad: goal,
        speed_fraction: 0.5,
        profile: parol6_core::profile::ProfileKind::Trapezoidal,
    }));
    settle(&mut h, 0.2);
    assert!(!has_label(&h, "(world) step"), "the row ended with the joint move: {:?}", labels_with(&h, "(world)"));
    at_rest(&mut h);
    assert!(!has_label(&h, "(world) step"), "still empty at rest: {:?}", labels_with(&h, "(world)"));

    // the next step is the first of a new row, taken in full
    h.get_by_label("+Z").click();
    at_rest(&mut h);
    let line = labels_with(&h, "(world) step");
    assert_eq!(line, vec!["+Z (world) step 1.00 mm".to_string()], "a new row of one step");

    // HOME ends it too
    h.get_by_label("HOME").click();
    settle(&mut h, 0.2);
    assert!(!has_label(&h, "(world) step"), "the row ended with HOME: {:?}", labels_with(&h, "(world)"));
    at_rest(&mut h);
    assert!(!has_label(&h, "(world) step"), "{:?}", labels_with(&h, "(world)"));
}

/// trial10 n1: the point table vanished while a program ran (it came back after Stop) without a
/// word. It stays open, read-only, and says that editing waits for the run to end.
#[test]
fn the_point_table_stays_open_read_only_while_a_program_runs() {
    let mut h = app_harness(egui::vec2(1280.0, 1400.0));
    h.get_by_label("Draw").click();
    until(&mut h, "the pre-flight", 10.0, |h| has_label(h, "pre-flight: ok"));
    h.state_mut().program_panel_mut().table_open = true;
    h.run_steps(3);
    assert!(has_label(&h, "Type a value, then Enter or Tab"), "the table is open");
    assert!(!h.get_by_label("Add row").accesskit_node().is_disabled(), "editable before the run");
    h.get_by_label("Run (F5)").click();
    until(&mut h, "the run", 10.0, |h| has_label(h, "Draw: step"));
    h.run_steps(2);
    assert!(h.state().program_running());
    assert!(h.state().program_panel().table_open, "the table stays open during the run");
    assert!(has_label(&h, "Add row"), "and shown");
    assert!(has_label(&h, "editing waits for the run to end"), "it says why it cannot be edited");
    assert!(h.get_by_label("Add row").accesskit_node().is_disabled(), "Add row greyed during the run");
    let cells: Vec<bool> =
        h.query_all_by_label_contains("table 1 ").map(|n| n.accesskit_node().is_disabled()).collect();
    assert!(!cells.is_empty() && cells.iter().all(|d| *d), "the cells are read-only: {cells:?}");
    h.get_by_label("Stop program").click();
    until(&mut h, "the run ended", 10.0, |h| !h.state().program_running());
    h.run_steps(3);
    assert!(!has_label(&h, "editing waits for the run to end"));
    assert!(!h.get_by_label("Add row").accesskit_node().is_disabled(), "editable again after the run");
}

fn area(h: &Harness<'_, Parol6App>, id: &str) -> Option<egui::Rect> {
    h.ctx.memory(|m| m.area_rect(egui::Id::unique(id)))
}

/// Raises an error notice (a recording that does not exist) and returns the notices' rectangle.
fn raise_notice(h: &mut Harness<'_, Parol6App>, tag: &str) -> egui::Rect {
    let dir = std::env::temp_dir().join(format!("parol6-trial9-10-minors-{tag}-{}", std::process::id()));
    h.state_mut().queue_command(AppCommand::OpenRecording(dir.join("no such recording.mcap")));
    until(h, "the notice", 10.0, |h| area(h, "parol6-notices").is_some() && !h.state().notices().is_empty());
    h.run_steps(3);
    area(h, "parol6-notices").expect("the notices' rectangle")
}

/// trial9 m8, trial10 n8: notices covered the title of the point table and of the save dialog,
/// and the open File menu's "Browse recordings…" at 1024×700. They keep clear of an open
/// window's title bar and of an open menu, also with the plots open under a short 3D view.
#[test]
fn notices_keep_clear_of_window_titles_and_open_menus() {
    for (size, plots) in
        [(egui::vec2(1024.0, 700.0), false), (egui::vec2(1024.0, 700.0), true), (egui::vec2(1280.0, 800.0), false)]
    {
        let mut h = app_harness(size);
        if plots {
            h.state_mut().show_plot(parol6_core::telemetry::Quantity::Position);
            h.run_steps(3);
        }
        h.state_mut().program_panel_mut().table_open = true;
        h.run_steps(3);
        let table = area(&h, parol6_app::panels::program::TABLE_ID).expect("the point table's rectangle");
        let notices = raise_notice(&mut h, "table");
        let title = egui::Rect::from_min_max(table.min, egui::pos2(table.right(), table.top() + 26.0));
        assert!(!notices.intersects(title), "at {size:?} the notices {notices:?} cover the table's title {title:?}");
        h.state_mut().program_panel_mut().table_open = false;
        h.run_steps(3);

        // the File menu, with a notice raised while it is open
        h.query_all_by_label("File").next().expect("the File menu").click();
        h.run_steps(2);
        assert!(egui::Popup::is_any_open(&h.ctx), "the File menu is open");
        let browse = h.get_by_label("Browse recordings…").rect();
        let notices = raise_notice(&mut h, "menu");
        let size = (size, plots);
        assert!(egui::Popup::is_any_open(&h.ctx), "the File menu is still open");
        assert!(
            !notices.intersects(browse),
            "at {size:?} the notices {notices:?} cover the File menu's Browse recordings… {browse:?}"
        );
        let menus: Vec<egui::Rect> = h.ctx.memory(|m| {
            m.areas()
                .visible_layer_ids()
                .into_iter()
                .filter(|l| l.order == egui::Order::Foreground)
                .filter_map(|l| m.area_rect(l.id))
                .collect()
        });
        assert!(!menus.is_empty(), "the open menu's rectangle");
        for menu in menus {
            assert!(!notices.intersects(menu), "at {size:?} the notices {notices:?} cover the open menu {menu:?}");
        }
    }
}

/// trial10 n2: "0.5A" in the gripper current field (mA) was refused ("A does not fit this
/// field"). Amperes are converted where a current is typed, without float noise (the field
/// takes whole mA); a length is still refused there, a current in a length field too.
#[test]
fn amperes_are_converted_in_a_milliampere_field() {
    use parol6_app::panels::entry::parse_in;
    assert_eq!(parse_in("0.5A", "mA"), Ok(500.0));
    assert_eq!(parse_in("1,001 A", "mA"), Ok(1001.0), "no float noise: the field takes whole mA");
    assert_eq!(parse_in("750 mA", "mA"), Ok(750.0));
    assert_eq!(parse_in("0.001 m", "mm"), Ok(1.0));
    assert_eq!(parse_in("250 mA", "A"), Ok(0.25));
    let e = parse_in("2 mm", "mA").unwrap_err();
    assert!(e.contains("mm does not fit") && e.contains("mA or A"), "{e}");
    let e = parse_in("0.5 A", "mm").unwrap_err();
    assert!(e.contains("A does not fit"), "{e}");
}
