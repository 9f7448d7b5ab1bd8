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
        "Built-in programs or a file; pre-flight shown as a green / amber / red path. F5 run or resume, F6 pause, \
         F10 single step; STOP or Esc ends a run. The Edit menu holds the editing actions (undo / redo, teach, \
         duplicate, delete, move a step, the point table) with their keys.",
    ),
];

/// The mouse, and typing into fields (the keys are the table in [`super::shortcuts`]).
const MOUSE: [(&str, &str); 4] = [
    (
        "Enter, Tab",
        "commit a typed value (clicking elsewhere does too, but never moves the arm: a typed joint value is then dropped)",
    ),
    ("left drag", "3D view: orbit"),
    ("right drag", "3D view: pan"),
    ("wheel", "3D view: zoom"),
];

/// Draws the help into `ui`; `settings_path` is where the settings are saved (`None`: they
/// are not saved in this session).
pub fn help_ui(ui: &mut egui::Ui, settings_path: Option<&Path>) {
    ui.heading("Panels");
    let names = PANELS.map(|(name, _)| egui::RichText::new(name).strong());
    let widths = [column_width(ui, &names, 0.35), REST];
    for (k, (name, (_, what))) in names.into_iter().zip(PANELS).enumerate() {
        table_row(ui, &widths, 6.0, k % 2 == 1, &mut [&mut |ui| text(ui, name.clone()), &mut |ui| text(ui, what)]);
    }
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
         while Ctrl, Alt, Cmd or Super is held unless the table names it (Ctrl+H); the letters that move it (the \
         Cartesian jog keys, H) act only with the pointer over the 3D view. A jog key counts only when \
         pressed on its own: let it go and press it again after using a modifier. Esc always stops.",
    );
    // both text columns wrap: at 1024 px the longest rows ran past the window's edge
    let rows = super::shortcuts::help_rows();
    let keys: Vec<egui::RichText> = rows.iter().map(|r| egui::RichText::new(&r.0).monospace()).collect();
    let scopes: Vec<egui::RichText> = rows.iter().map(|r| egui::RichText::new(r.2).weak()).collect();
    let widths = [column_width(ui, &keys, 0.3), REST, column_width(ui, &scopes, 0.3)];
    for (k, ((keys, scope), (_, what, _))) in keys.into_iter().zip(scopes).zip(&rows).enumerate() {
        let cells: [&mut dyn FnMut(&mut egui::Ui); 3] =
            [&mut |ui| text(ui, keys.clone()), &mut |ui| text(ui, *what), &mut |ui| text(ui, scope.clone())];
        table_row(ui, &widths, 2.0, k % 2 == 1, &mut { cells });
    }
    ui.add_space(4.0);
    let keys = MOUSE.map(|(k, _)| egui::RichText::new(k).monospace());
    let widths = [column_width(ui, &keys, 0.3), REST];
    for (k, (_, what)) in keys.into_iter().zip(MOUSE) {
        table_row(ui, &widths, 2.0, false, &mut [&mut |ui| text(ui, k.clone()), &mut |ui| text(ui, what)]);
    }
    ui.add_space(6.0);
    ui.heading("LEDs");
    let leds = [
        (zone_color(LimitZone::Safe), LimitZone::Safe.label(), "joint comfortably inside its range"),
        (
            zone_color(LimitZone::Warning),
            LimitZone::Warning.label(),
            "joint in the outer 15 % of its range, or will be at a limit within 0.5 s",
        ),
        (
            zone_color(LimitZone::Critical),
            LimitZone::Critical.label(),
            "joint in the outer 5 % of its range (or beyond), or amber and about to reach it",
        ),
        (palette::rgb(palette::LED_OFF), "off", "connection LEDs (link, enabled, E-stop, homing, homed): grey is off"),
    ];
    for (color, name, what) in leds {
        let cells: [&mut dyn FnMut(&mut egui::Ui); 2] = [
            &mut |ui| {
                led(ui, color, name);
            },
            &mut |ui| text(ui, what),
        ];
        table_row(ui, &[LED_COLUMN_WIDTH, REST], 4.0, false, &mut { cells });
    }
    ui.add_space(6.0);
    ui.heading("Settings");
    match settings_path {
        Some(p) => {
            ui.label(format!(
                "Units, panel and 3D view toggles, the height of the panel under the 3D view and which of the \
                 plots and dynamics is in front where they share it as tabs, speeds, profile, \
                 tracking mode, the recent programs and their folder, the last port, the program last \
                 opened, saved or picked (reopened at start), the Cartesian jog's frame, mode and \
                 increments, the forward-dynamics form and the camera are saved half a second after each \
                 change, and on exit, to {} (set PAROL6_SETTINGS to use another file).",
                p.display()
            ));
        }
        None => {
            ui.label("Settings are not saved in this session (no settings file); PAROL6_SETTINGS names one.");
        }
    }
}

/// The width of a table's column that takes what the others leave ([`table_row`]).
const REST: f32 = f32::INFINITY;

/// The LED column's width, points (an LED is 14).
const LED_COLUMN_WIDTH: f32 = 16.0;

/// Gap between a table's columns, points.
const COLUMN_GAP: f32 = 12.0;

/// The width of a column of `cells`: the widest on one line, at most `max_share` of the width.
/// Measured from the texts every frame, never remembered: the help's tables are laid out the
/// same in the first frame they are shown as in every later one. (They were egui grids, which
/// size their columns in the first frame, here the help window's sizing pass, and showed the
/// next frame with those narrow columns: tall rows, text missing, until something repainted;
/// issue 32 minor.)
fn column_width(ui: &egui::Ui, cells: &[egui::RichText], max_share: f32) -> f32 {
    let widest = cells
        .iter()
        .map(|c| {
            let text = egui::WidgetText::from(c.clone());
            text.into_galley(ui, Some(egui::TextWrapMode::Extend), f32::INFINITY, egui::TextStyle::Body).size().x
        })
        .fold(0.0, f32::max);
    widest.min(ui.available_width() * max_share).ceil()
}

/// A wrapped label.
fn text(ui: &mut egui::Ui, text: impl Into<egui::WidgetText>) {
    ui.add(egui::Label::new(text).wrap());
}

/// One row of a table: `cells` side by side, top-aligned, each in a column of `widths` (one
/// [`REST`]: the width the others leave), `row_gap` points below it; `stripe` shades it.
fn table_row(
    ui: &mut egui::Ui,
    widths: &[f32],
    row_gap: f32,
    stripe: bool,
    cells: &mut [&mut dyn FnMut(&mut egui::Ui)],
) {
    let gaps = COLUMN_GAP * widths.len().saturating_sub(1) as f32;
    let fixed: f32 = widths.iter().filter(|w| w.is_finite()).sum();
    let rest = (ui.available_width() - fixed - gaps).max(COLUMN_GAP);
    let background = ui.painter().add(egui::Shape::Noop);
    let row = ui.horizontal_top(|ui| {
        ui.spacing_mut().item_spacing.x = COLUMN_GAP;
        for (cell, w) in cells.iter_mut().zip(widths) {
            let w = if w.is_finite() { *w } else { rest };
            ui.allocate_ui_with_layout(egui::vec2(w, 0.0), egui::Layout::top_down(egui::Align::Min), |ui| {
                ui.set_width(w);
                cell(ui);
            });
        }
    });
    if stripe {
        let rect = row.response.rect.expand2(egui::vec2(2.0, row_gap / 2.0));
        ui.painter().set(background, egui::Shape::rect_filled(rect, 2.0, ui.visuals().faint_bg_color));
    }
    ui.add_space(row_gap);
}
