//! Issue 32's file-dialog defects, driven headless through egui's kittest harness on the full
//! app: the Open dialog lists programs only (not the app's `settings.json`), offers no Rename /
//! New Folder, draws its icons with glyphs our fonts have (the harness refuses tofu), closes on
//! Esc, and opens next time (also after a restart) in the folder the operator last browsed to,
//! Cancel included; Save as proposes a readable file name.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test is a failed test

mod ui_support;

use eframe::egui::{self, Key};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use ui_support::{harness_with, has_label, launch_options, open_program_file, until};

use parol6_app::app::{LaunchOptions, Parol6App};
use parol6_core::program::{Program, Step, json};

fn temp_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("parol6-file-dialog-{tag}-{}", std::process::id()));
    if dir.exists() {
        std::fs::remove_dir_all(&dir).unwrap();
    }
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write_program(path: &std::path::Path) {
    let program = Program::from_steps("dwell", vec![Step::Dwell { seconds: 1.0 }]);
    std::fs::write(path, json::to_string(&program)).unwrap();
}

fn dialog_open(h: &Harness<'_, Parol6App>) -> bool {
    h.state().program_panel().file_dialog_open()
}

fn browse(h: &mut Harness<'_, Parol6App>) {
    h.get_by_label("Browse…").click();
    h.run_steps(3);
    assert!(dialog_open(h), "Browse… opens the file dialog");
}

/// Issue 32 minor: "File dialog: it lists `settings.json` as a program, offers Rename/New
/// Folder while opening, and forgets the last folder after Cancel." and "The file dialog shows
/// tofu icons".
#[test]
fn the_open_dialog_lists_programs_only_offers_no_rename_and_remembers_the_folder_after_cancel() {
    let dir = temp_dir("open");
    let settings = dir.join("settings.json");
    // the app's own settings file, as it sits in ~/.config/parol6
    std::fs::write(&settings, "{\n  \"unit\": \"Deg\",\n  \"recent_programs\": []\n}\n").unwrap();
    std::fs::write(dir.join("notes.md"), "not a program").unwrap();
    write_program(&dir.join("first.json"));
    let sub = dir.join("cell-2");
    std::fs::create_dir_all(&sub).unwrap();
    write_program(&sub.join("second.json"));

    let opts = LaunchOptions { settings_path: Some(settings.clone()), ..launch_options() };
    let mut h = harness_with(opts, egui::vec2(1280.0, 800.0));
    // the dialog opens in the program's folder; the operator goes up one (⬆), then cancels
    open_program_file(&mut h, &sub.join("second.json"));
    browse(&mut h);
    assert!(has_label(&h, "second.json"), "the dialog opens in the program's folder");
    h.get_by_label("⬆").click();
    h.run_steps(3);
    assert!(has_label(&h, "first.json"), "⬆ shows the parent folder");
    assert!(has_label(&h, "🗀 cell-2"), "folders are listed, with a glyph our fonts have");
    assert!(!has_label(&h, "settings.json"), "the settings file is not offered as a program");
    assert!(!has_label(&h, "notes.md"), "a file of no program format is not listed");
    assert!(h.query_by_label("Rename").is_none(), "opening offers no Rename");
    assert!(h.query_by_label("New Folder").is_none(), "opening offers no New Folder");
    h.get_by_label("Cancel").click();
    h.run_steps(3);
    assert!(!dialog_open(&h), "Cancel closes the dialog");
    browse(&mut h);
    assert!(has_label(&h, "first.json"), "the dialog reopens in the folder browsed to before Cancel");

    // Esc closes it too (with the pointer away from the 3D view), the folder still remembered
    let at = h.get_by_label("Program file").rect().center();
    h.hover_at(at);
    h.key_press(Key::Escape);
    h.run_steps(3);
    assert!(!dialog_open(&h), "Esc closes the file dialog");

    // remembered with the other settings: a fresh start opens there too
    let dir_text = format!("{:?}", dir.display().to_string());
    until(&mut h, "the folder in the settings file", 10.0, |_| {
        std::fs::read_to_string(&settings).is_ok_and(|s| s.contains(&dir_text))
    });
    drop(h);
    let opts = LaunchOptions { settings_path: Some(settings.clone()), ..launch_options() };
    let mut h = harness_with(opts, egui::vec2(1280.0, 800.0));
    browse(&mut h);
    assert!(has_label(&h, "first.json"), "after a restart the dialog opens where it was left");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 32 minor: "The file dialog … proposes `Pick___place.json`" (and the Save dialog showed
/// tofu icons): Save as proposes a readable name.
#[test]
fn save_as_proposes_a_readable_file_name_for_pick_and_place() {
    let mut h = harness_with(launch_options(), egui::vec2(1280.0, 800.0));
    assert!(h.state_mut().load_program("Pick & place"));
    until(&mut h, "the program's check", 30.0, |h| !h.state().program_panel().checking());
    h.get_by_label("Save as…").click();
    h.run_steps(3);
    assert!(dialog_open(&h), "Save as… opens the file dialog");
    let proposed = |name| h.query_all_by_value(name).next().is_some();
    assert!(proposed("Pick_and_place.json"), "the proposed name reads as the program's name");
    assert!(!proposed("Pick___place.json"));
}

/// Trial 22 m14: a name the formats refuse (`x.xyz`) closed Save as, and the operator had to
/// open it again and find the folder. It says why and asks again, with the name typed.
#[test]
fn save_as_a_refused_extension_says_why_and_asks_again() {
    let dir = temp_dir("save-as-refused");
    let mut h = harness_with(launch_options(), egui::vec2(1280.0, 800.0));
    assert!(h.state_mut().load_program("Pick & place"));
    until(&mut h, "the program's check", 30.0, |h| !h.state().program_panel().checking());
    h.get_by_label("Save as…").click();
    h.run_steps(3);
    h.query_all_by_value("Pick_and_place.json").next().expect("the name field").click();
    h.run_steps(1);
    h.event(egui::Event::Key {
        key: egui::Key::A,
        physical_key: None,
        pressed: true,
        repeat: false,
        modifiers: egui::Modifiers::COMMAND,
    });
    h.run_steps(1);
    h.event(egui::Event::Text(format!("{}/x.xyz", dir.display())));
    h.run_steps(1);
    h.query_all_by_label("Save").last().expect("the dialog's Save").click();
    h.run_steps(3);
    let said = h.state().notices().iter().any(|n| n.text.contains("x.xyz: unknown program file extension"));
    assert!(said, "{:?}", h.state().notices().iter().map(|n| n.text.clone()).collect::<Vec<_>>());
    assert!(dialog_open(&h), "Save as asks again");
    assert!(h.query_all_by_value("x.xyz").next().is_some(), "with the name typed");
    assert!(!dir.join("x.xyz").exists(), "nothing written");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 32 minor: "The File menu has no Quit and no Browse for recordings." File → Browse
/// recordings…
/// opens a dialog in the typed path's folder that lists recordings only; picking one opens it
/// for replay.
#[test]
fn file_menu_browse_opens_a_recording_picked_in_a_dialog() {
    let dir = temp_dir("recording");
    let model = parol6_core::RobotModel::parol6();
    let bytes = parol6_app::cli::bench_replay::synthetic_recording(&model, 0.5, 5.0).expect("recording");
    std::fs::write(dir.join("run.mcap"), bytes).unwrap();
    write_program(&dir.join("not-a-recording.json"));

    let mut h = ui_support::app_harness(egui::vec2(1280.0, 800.0));
    h.query_all_by_label("File").next().expect("the File menu").click();
    h.run_steps(2);
    h.get_by_label("Recording").click();
    h.run_steps(1);
    h.get_by_label("Recording").type_text(&format!("{}/", dir.display()));
    h.run_steps(1);
    h.get_by_label("Browse recordings…").click();
    h.run_steps(3);
    assert!(h.state().file_menu().dialog_open(), "Browse recordings… opens the recording dialog");
    assert!(has_label(&h, "run.mcap"), "the dialog opens in the typed folder and lists the recording");
    assert!(!has_label(&h, "not-a-recording.json"), "only recordings are listed");
    assert!(h.query_by_label("Rename").is_none() && h.query_by_label("New Folder").is_none());
    h.get_by_label_contains("run.mcap").click();
    h.run_steps(2);
    // the dialog's Open (the program panel has one too; the dialog's window comes later)
    h.query_all_by_label("Open").last().expect("the dialog's Open").click();
    until(&mut h, "the replay", 10.0, |h| has_label(h, "Replay: run.mcap"));
    assert!(!h.state().file_menu().dialog_open(), "the dialog closed");
}

/// Trial 7: the point table and the program's file dialogs opened at the window's top left,
/// over the menu bar and the joints panel's HOME / STOP / E-STOP. At each window size of the
/// hand trial they open beside the joints panel, below the menu bar.
#[test]
fn the_point_table_and_the_file_dialog_leave_stop_the_estop_and_the_menu_bar_free() {
    use parol6_app::panels::program::{FILE_DIALOG_ID, TABLE_ID};
    for size in [egui::vec2(1024.0, 700.0), egui::vec2(1280.0, 800.0), egui::vec2(1600.0, 1000.0)] {
        let mut h = ui_support::app_harness(size);
        let keep_free = [h.get_by_label("File").rect(), h.get_by_label("STOP").rect(), h.get_by_label("E-STOP").rect()];
        let area = |h: &Harness<'_, Parol6App>, id: &str| h.ctx.memory(|m| m.area_rect(egui::Id::unique(id)));
        // by accesskit: at 1024×700 both buttons lie below the column's fold
        h.get_by_label("Table").click_accesskit();
        h.run_steps(3);
        let table = area(&h, TABLE_ID).expect("the point table's rectangle");
        h.get_by_label("Table").click_accesskit();
        h.run_steps(2);
        h.get_by_label("Browse…").click_accesskit();
        h.run_steps(3);
        assert!(dialog_open(&h), "Browse… opens the file dialog");
        let dialog = area(&h, FILE_DIALOG_ID).expect("the file dialog's rectangle");
        for (what, r) in [("point table", table), ("file dialog", dialog)] {
            for free in keep_free {
                assert!(!r.intersects(free), "at {size:?} the {what} {r:?} covers {free:?}");
            }
            assert!(h.ctx.content_rect().contains_rect(r), "at {size:?} the {what} {r:?} is in the window");
        }
    }
}
