//! The help window's contents (F1 or the Help menu): what each panel does, units, mouse and
//! keys, where settings are saved and what the LEDs mean.

use eframe::egui;
use std::path::Path;

use parol6_core::limits::LimitZone;

use super::{led, zone_color};
use crate::palette;

/// What each panel is for, in the order they appear.
const PANELS: [(&str, &str); 9] = [
    (
        "Joints (left)",
        "HOME moves to the standby pose, STOP holds the arm where it is. Under them one line \
         says how close the arm is to its limits (a coloured band only when there is a real risk). \
         Per joint: a limit LED, a slider (the arm follows while you drag) and a typed entry \
         (type a value, then Enter or Tab: a profiled move at the speed below; a value beyond \
         a limit is clamped and you are told). The bar under each joint shows its range with \
         the amber / red end zones, the measured position (filled) and the target (outline).",
    ),
    ("Speed / Profile", "Speed and velocity profile of HOME, typed moves, \"Go\" and \"Move to target\"."),
    (
        "Go to joint pose",
        "Type a whole pose (each entry is kept as typed, clamped into the limits), or copy the \
         current or park pose, then Go.",
    ),
    (
        "Robot connection",
        "Open a serial port or the built-in emulator; enable / disable the drives, run homing, \
         jog a joint (hold the buttons). Folded while no robot is connected.",
    ),
    (
        "I/O & gripper",
        "OUTPUT 1 / 2 toggle on a click; INPUT 1 / 2 and the drives are LEDs. The gripper's \
         reported position, current and status; type position (0–255), speed (0–255) and current \
         (100–2800 mA), then Move gripper; Calibrate. Clear error sends CLEAR ERROR. The same \
         buttons drive the simulation (its gripper and outputs are emulated) and the robot. \
         E-STOP (beside STOP) sends STOP and DISABLE and refuses all motion until Release \
         E-STOP (which sends ENABLE); Esc stays STOP.",
    ),
    (
        "TCP (right)",
        "Tool centre point position and orientation, the 4×4 and 3×3 matrices, and how well \
         conditioned the pose is (a singular pose is information: the arm is driven joint by joint).",
    ),
    (
        "Cartesian jog",
        "Move the TCP along X / Y / Z or turn it about them, in the world (base) frame or the \
         tool frame. Hold: the arm moves while a −/+ button or its key is held and stops, \
         slowing down first, before a joint limit, the edge of the workspace, a singularity or \
         (simulation) a collision; the panel says which. Near the wrist singularity (J5 near 0) \
         it slows down. Step: each click moves exactly the typed increment (mm or °). Speed: \
         1–160 mm/s, 1–80 °/s.",
    ),
    (
        "Cartesian target",
        "Type X Y Z (mm) and roll pitch yaw, or \"From TCP\"; every IK branch within the limits \
         is listed by configuration, nearest the current joints first. Hover the panel to see the chosen one \
         as a ghost arm, then \"Move to target\".",
    ),
    (
        "Program",
        "Built-in programs or a file; pre-flight shown as a green / amber / red path. F5 run or resume, F6 pause, F10 single step; STOP or Esc ends a run.",
    ),
];

/// The mouse, and typing into fields (the keys are the table in [`super::shortcuts`]).
const MOUSE: [(&str, &str); 4] = [
    ("Enter, Tab", "commit a typed value (clicking elsewhere does too)"),
    ("left drag", "3D view: orbit"),
    ("right drag", "3D view: pan"),
    ("wheel", "3D view: zoom"),
];

/// Draws the help into `ui`; `settings_path` is where the settings are saved (`None`: they
/// are not saved in this session).
pub fn help_ui(ui: &mut egui::Ui, settings_path: Option<&Path>) {
    ui.heading("Panels");
    egui::Grid::new("help_panels").num_columns(2).spacing([12.0, 6.0]).striped(true).show(ui, |ui| {
        for (name, what) in PANELS {
            ui.label(egui::RichText::new(name).strong());
            ui.add(egui::Label::new(what).wrap());
            ui.end_row();
        }
    });
    ui.add_space(6.0);
    ui.heading("Units");
    ui.label(
        "Angles in degrees or radians (the deg / rad switch of the Joints panel, or the Units \
         menu), shown with 2 decimals in degrees and 4 in radians; positions in millimetres \
         with 2 decimals. Typed values may use a comma as decimal mark and may end with a unit, which is \
         converted: rad, deg or ° in an angle field, mm, m or in in a millimetre field (a unit that does \
         not fit the field is refused).",
    );
    ui.add_space(6.0);
    ui.heading("Mouse and keys");
    ui.label(
        "Keys that move the arm act only while no text field, menu or popup has the keyboard, and never \
         while Ctrl, Alt, Cmd or Super is held unless the table names it (Ctrl+H). A jog key counts only when \
         pressed on its own: let it go and press it again after using a modifier. Esc always stops.",
    );
    egui::Grid::new("help_keys").num_columns(3).spacing([12.0, 2.0]).striped(true).show(ui, |ui| {
        // both text columns wrap: at 1024 px the longest rows ran past the window's edge
        for (keys, what, scope) in super::shortcuts::help_rows() {
            ui.monospace(keys);
            ui.add(egui::Label::new(what).wrap());
            ui.add(egui::Label::new(egui::RichText::new(scope).weak()).wrap());
            ui.end_row();
        }
    });
    ui.add_space(4.0);
    egui::Grid::new("help_mouse").num_columns(2).spacing([12.0, 2.0]).show(ui, |ui| {
        for (k, what) in MOUSE {
            ui.monospace(k);
            ui.label(what);
            ui.end_row();
        }
    });
    ui.add_space(6.0);
    ui.heading("LEDs");
    egui::Grid::new("help_leds").num_columns(2).spacing([12.0, 4.0]).show(ui, |ui| {
        for (zone, what) in [
            (LimitZone::Safe, "joint comfortably inside its range"),
            (LimitZone::Warning, "joint in the outer 15 % of its range, or will be at a limit within 0.5 s"),
            (LimitZone::Critical, "joint in the outer 5 % of its range (or beyond), or amber and about to reach it"),
        ] {
            led(ui, zone_color(zone), zone.label());
            ui.label(what);
            ui.end_row();
        }
        led(ui, palette::rgb(palette::LED_OFF), "off");
        ui.label("connection LEDs (link, enabled, E-stop, homing, homed): grey is off");
        ui.end_row();
    });
    ui.add_space(6.0);
    ui.heading("Settings");
    match settings_path {
        Some(p) => {
            ui.label(format!(
                "Units, panel and 3D view toggles, the height of the panel under the 3D view, speeds, profile, \
                 tracking mode, the recent programs and their folder, and the last port are saved half a \
                 second after each change, and on exit, to {} (set PAROL6_SETTINGS to use another file).",
                p.display()
            ));
        }
        None => {
            ui.label("Settings are not saved in this session (no settings file); PAROL6_SETTINGS names one.");
        }
    }
}
