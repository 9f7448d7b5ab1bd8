//! I/O & gripper panel: the two digital outputs (toggle), the two inputs (read-only LEDs), the
//! electric gripper (reported position, current and status; position / speed / current to set,
//! Move and Calibrate), Clear error and the drives' state. And the E-stop button
//! ([`estop_button`], drawn beside HOME / STOP in the joints panel so it never scrolls away).
//!
//! Everything goes through [`AppCommand::Io`] and [`AppCommand::EStop`] to the active backend's
//! one `RobotBackend::io`: the same buttons drive the simulation (which keeps an emulated gripper
//! and I/O state) and the robot.

use eframe::egui;

use parol6_core::limits::LimitZone;
use parol6_core::motion::{DIGITAL_PORTS, GRIPPER_CURRENT_MA, IoCommand};

use super::entry::{EntryEvent, in_range, ranged_entry};
use super::{AppCommand, Panel, PanelContext, on_off_led, zone_color};
use crate::palette;

/// What the section says during a replay: a recording has no I/O channel, so the live state is
/// hidden (not shown as if it were the recording's) and its controls are disabled.
pub const NOT_RECORDED: &str = "Not recorded: the live I/O and gripper are hidden during replay; close the replay to \
                                see them";

/// Why motion is refused while the E-stop is latched: the app puts it in the shown state's
/// `blocked` (see `RobotState::blocked`), every refusal names it.
/// No part of it, cut at a line, reads as the opposite (trial 29 m2: a scrolled column showed only
/// "E-stop is released" under a latched E-STOP).
pub const ESTOP_LATCHED: &str = "E-STOP latched: drives disabled, all motion refused (Release E-STOP to move again)";

/// True when the E-stop is latched: the live state's, also during replay (trial 24 D2: the
/// recording's state showed a plain "E-STOP" over a latched robot).
pub fn estop_latched(ctx: &PanelContext<'_>) -> bool {
    ctx.live_robot.blocked.as_deref() == Some(ESTOP_LATCHED)
}

/// How long *Release E-STOP* stays greyed after the latch: the second click of a hurried
/// double-click on E-STOP (the same place) does not release it (trial 21 D3: it sent ENABLE at once).
pub const ESTOP_RELEASE_HOLD_OFF: std::time::Duration = std::time::Duration::from_millis(1500);

/// Why *Release E-STOP* is greyed just after the latch.
const RELEASE_HELD_OFF: &str = "E-STOP latched just now: Release is possible 1.5 s after the latch, so that a \
                                double-click on E-STOP does not undo it";

/// The E-stop button: red "E-STOP" sends DISABLE (and STOP) and latches; while latched it
/// reads "Release E-STOP" and releasing sends ENABLE, possible [`ESTOP_RELEASE_HOLD_OFF`] after
/// the latch. `height`: its height, points.
pub fn estop_button(ui: &mut egui::Ui, ctx: &mut PanelContext<'_>, height: f32) {
    let latched = estop_latched(ctx);
    // when this window saw the latch begin (none while released)
    let latched_at_id = egui::Id::unique("parol6-estop-latched-at");
    let now = std::time::Instant::now();
    let latched_at = ui.data_mut(|d| {
        let at = d.get_temp::<Option<std::time::Instant>>(latched_at_id).flatten();
        let at = if latched { Some(at.unwrap_or(now)) } else { None };
        d.insert_temp(latched_at_id, at);
        at
    });
    let held_off = latched_at.map(|at| ESTOP_RELEASE_HOLD_OFF.saturating_sub(now - at)).filter(|d| !d.is_zero());
    if let Some(left) = held_off {
        ui.ctx().request_repaint_after(left);
    }
    let (text, hover) = if latched {
        ("Release E-STOP", "Release the E-stop latch: ENABLE the drives; motion is accepted again")
    } else {
        ("E-STOP", "Emergency stop: STOP, DISABLE the drives, and refuse all motion until released")
    };
    let button = egui::Button::new(egui::RichText::new(text).strong().color(palette::rgb(palette::STOP_TEXT)))
        .fill(if latched { palette::rgb(palette::LED_OFF) } else { palette::rgb(palette::STOP_FILL) })
        .stroke(egui::Stroke::new(2.0, zone_color(LimitZone::Critical)))
        .min_size(egui::vec2(120.0, height));
    let response =
        ui.add_enabled(held_off.is_none(), button).on_hover_text(hover).on_disabled_hover_text(RELEASE_HELD_OFF);
    if response.clicked() {
        ctx.send(AppCommand::EStop(!latched));
    }
}

/// Gripper position range (0 open … 255 closed).
const POSITION_RANGE: (f64, f64) = (0.0, 255.0);
/// Gripper speed range.
const SPEED_RANGE: (f64, f64) = (0.0, 255.0);

/// The I/O & gripper panel: the gripper values to send next.
#[derive(Debug, Clone)]
pub struct IoGripperPanel {
    /// Gripper position to send, 0–255.
    pub position: u8,
    /// Gripper speed to send, 0–255.
    pub speed: u8,
    /// Gripper current limit to send, mA.
    pub current_ma: u16,
}

impl Default for IoGripperPanel {
    fn default() -> Self {
        Self { position: 0, speed: 128, current_ma: 500 }
    }
}

impl IoGripperPanel {
    fn entry(
        ui: &mut egui::Ui,
        ctx: &mut PanelContext<'_>,
        name: &str,
        value: f64,
        unit: &str,
        range: (f64, f64),
        refused: &mut Option<String>,
    ) -> Option<f64> {
        let (_, ev) = ranged_entry(ui, name, value, (0, 60.0), (unit, unit), range);
        let why = match ev {
            Some(EntryEvent::Committed(v)) => match in_range(name, v, range, unit, true) {
                Ok(v) => return Some(v),
                Err(e) => e,
            },
            Some(EntryEvent::Invalid(e)) => format!("{name}: {e}"),
            None => return None,
        };
        ctx.error(why);
        refused.get_or_insert_with(|| name.to_string());
        None
    }

    /// The outputs, inputs and drives; `shown`: false during a replay (placeholders, no live value).
    fn io_ui(ui: &mut egui::Ui, ctx: &mut PanelContext<'_>, shown: bool) {
        let io = if shown { ctx.robot.io } else { Default::default() };
        let green = zone_color(LimitZone::Safe);
        ui.horizontal(|ui| {
            ui.label("Outputs");
            for i in 0..DIGITAL_PORTS {
                let on = io.outputs.get(i).copied().unwrap_or(false);
                let state = match (shown, on) {
                    (false, _) => "—",
                    (true, true) => "HIGH",
                    (true, false) => "LOW",
                };
                let label = format!("OUTPUT {}: {state}", i + 1);
                if ui.selectable_label(on, label).on_hover_text("Click to toggle the output").clicked() {
                    let output = u8::try_from(i + 1).unwrap_or(1);
                    ctx.send(AppCommand::Io(IoCommand::SetOutput { output, on: !on }));
                }
            }
        });
        ui.horizontal(|ui| {
            ui.label("Inputs");
            for i in 0..DIGITAL_PORTS {
                on_off_led(ui, io.inputs.get(i).copied().unwrap_or(false), green, &format!("INPUT {}", i + 1));
            }
            ui.separator();
            let disabled = io.drives_disabled;
            // off in replay: a lit LED would read as the recording's drives
            on_off_led(ui, shown && !disabled, green, "drives enabled");
        });
    }

    fn gripper_ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>, shown: bool) {
        let io = if shown { ctx.robot.io } else { Default::default() };
        let g = io.gripper();
        ui.label(egui::RichText::new("Gripper").strong());
        let reported = if shown {
            format!("position {:>3} / 255   current {:>5} mA", io.gripper_position, io.gripper_current_ma)
        } else {
            format!("position {:>3} / 255   current {:>5} mA", "—", "—")
        };
        ui.monospace(reported).on_hover_text("as reported (0 open … 255 closed)");
        let green = zone_color(LimitZone::Safe);
        let red = zone_color(LimitZone::Critical);
        ui.horizontal(|ui| {
            on_off_led(ui, g.activated, green, "active");
            on_off_led(ui, g.calibrated, green, "calibrated");
            on_off_led(ui, g.error, red, "error");
            // the object code means nothing before the gripper is activated
            ui.label(match (shown, g.activated) {
                (false, _) => "not recorded",
                (true, true) => g.object_text(),
                (true, false) => "not activated",
            });
        });
        // a field refused in this frame (left by the click on Move gripper) holds back the move:
        // it moved to the last accepted value (trial 32 D1)
        let mut refused = None;
        egui::Grid::new("gripper_set").num_columns(2).spacing([6.0, 3.0]).show(ui, |ui| {
            ui.label("Position");
            if let Some(v) =
                Self::entry(ui, ctx, "Gripper position", f64::from(self.position), "", POSITION_RANGE, &mut refused)
            {
                self.position = v as u8;
            }
            ui.end_row();
            ui.label("Speed");
            if let Some(v) = Self::entry(ui, ctx, "Gripper speed", f64::from(self.speed), "", SPEED_RANGE, &mut refused)
            {
                self.speed = v as u8;
            }
            ui.end_row();
            ui.label("Current");
            let range = (f64::from(GRIPPER_CURRENT_MA.0), f64::from(GRIPPER_CURRENT_MA.1));
            if let Some(v) =
                Self::entry(ui, ctx, "Gripper current", f64::from(self.current_ma), "mA", range, &mut refused)
            {
                self.current_ma = v as u16;
            }
            ui.end_row();
        });
        ui.horizontal(|ui| {
            let go = ui.button("Move gripper").on_hover_text("Send position, speed and current").clicked();
            if go && let Some(name) = &refused {
                ctx.error(format!("Move gripper not sent: {name} holds no valid value"));
            } else if go {
                let cmd =
                    IoCommand::Gripper { position: self.position, speed: self.speed, current_ma: self.current_ma };
                ctx.send(AppCommand::Io(cmd));
            }
            if ui.button("Calibrate").on_hover_text("One-shot gripper calibration").clicked() {
                ctx.send(AppCommand::Io(IoCommand::GripperCalibrate));
            }
        });
    }
}

impl Panel for IoGripperPanel {
    fn title(&self) -> &'static str {
        "I/O & gripper"
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        let replaying = ctx.app.replaying();
        ui.horizontal(|ui| {
            ui.heading(self.title());
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                let hover = "CLEAR ERROR to the controller (resets a failed homing and the fault text) and the \
                             gripper's clear-error";
                let b = ui.add_enabled(!replaying, egui::Button::new("Clear error"));
                if b.on_hover_text(hover).on_disabled_hover_text(NOT_RECORDED).clicked() {
                    ctx.send(AppCommand::Io(IoCommand::ClearError));
                }
            });
        });
        // two lines, empty while the E-stop is not latched and no replay is open: nothing below
        // moves when it latches or a replay opens (trial12 n-c)
        let line = if replaying {
            egui::RichText::new(NOT_RECORDED).color(palette::rgb(palette::WARN_TEXT))
        } else {
            let latched = if estop_latched(ctx) { ESTOP_LATCHED } else { "" };
            egui::RichText::new(latched).color(palette::rgb(palette::ERROR_TEXT))
        };
        super::fixed_box::message_lines(ui, line, 2);
        // the recording has no I/O channel: greyed placeholders, controls disabled with the reason
        ui.add_enabled_ui(!replaying, |ui| {
            Self::io_ui(ui, ctx, !replaying);
            ui.add_space(4.0);
            self.gripper_ui(ui, ctx, !replaying);
        })
        .response
        .on_disabled_hover_text(NOT_RECORDED);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typed_values_outside_the_range_are_refused_with_it() {
        assert_eq!(in_range("Gripper position", 200.0, POSITION_RANGE, "", true), Ok(200.0));
        // trial6: "12,5" in Gripper speed became 13 without a word
        let e = in_range("Gripper speed", 12.5, POSITION_RANGE, "", true).unwrap_err();
        assert!(e.contains("12.5 is not a whole number (0–255)"), "{e}");
        let e = in_range("Gripper position", 300.0, POSITION_RANGE, "", true).unwrap_err();
        assert!(e.contains("outside 0–255"), "{e}");
        let e = in_range("Gripper current", 5000.0, (100.0, 2800.0), "mA", true).unwrap_err();
        assert!(e.contains("5000 mA is outside 100–2800 mA"), "{e}");
    }
}
