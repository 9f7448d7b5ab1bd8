//! Bottom status bar: FPS, CPU time of the UI pass, physics rate and step time, command
//! latency, where the shown state comes from (SIM, ROBOT, or REPLAY while a recording is open), the
//! recording being written (a red dot, its file name and the time since it started), the *Share live*
//! toggle (with the address while on) and the remote-control banner.
//!
//! The toggles come first, at the bar's right end, each in a slot of fixed width, so no text that
//! appears or changes (*moving*, a recording, *LIVE ws://…*) moves them under the pointer; the
//! read-outs fill the rest from the left; where the window is narrow the last ones are left out
//! whole, never cut mid-word.

use super::{AppCommand, Panel, PanelContext, StateSource};
use eframe::egui;

use crate::palette;

/// The status bar.
#[derive(Debug, Default)]
pub struct StatusBar;

impl Panel for StatusBar {
    fn title(&self) -> &'static str {
        "Status"
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        ui.horizontal(|ui| {
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                live_ui(ui, ctx);
                ui.separator();
                ui.with_layout(egui::Layout::left_to_right(egui::Align::Center), |ui| {
                    // the read-outs never reach under the toggles
                    ui.set_clip_rect(ui.max_rect().intersect(ui.clip_rect()));
                    readouts_ui(ui, ctx);
                });
            });
        });
    }
}

/// The width of the slot for the text `widest` on a button (the slots do not follow the text).
fn slot_width(ui: &egui::Ui, widest: &str) -> f32 {
    let galley = egui::WidgetText::from(widest).into_galley(
        ui,
        Some(egui::TextWrapMode::Extend),
        f32::INFINITY,
        egui::TextStyle::Button,
    );
    galley.size().x + 2.0 * ui.spacing().button_padding.x
}

/// Below this many frames per second with nothing moving, the FPS read-out says "idle".
const IDLE_FPS: f64 = 5.0;

/// What the `t = …` read-out is: the clock of the state shown, the plots' time axis too
/// (trial 20: it showed the simulation's clock while the robot was shown, 57 s off the plots).
fn clock_hover(ctx: &PanelContext<'_>) -> &'static str {
    match (ctx.app.replaying(), ctx.readout.source) {
        (true, _) => "the recording's time at the cursor (the plots' time axis)",
        (false, StateSource::Simulation) => "the simulation's clock (the plots' time axis)",
        (false, StateSource::Robot) => "the robot link's clock, from connecting (the plots' time axis)",
    }
}

/// Where the shown state comes from, the recording, whether the arm moves and the link's rate,
/// then the shown state's clock and the performance read-outs (left out first where the window is narrow).
fn readouts_ui(ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
    let p = ctx.perf;
    let src = crate::app::state::source_label(ctx.app, ctx.robot.source);
    let (color, hover) = match (ctx.app.replaying(), ctx.robot.source) {
        (true, _) => (palette::rgb(palette::WARN_TEXT), crate::app::state::REPLAY_OPEN),
        (false, StateSource::Simulation) => (palette::rgb(palette::SOURCE_SIM), "the 3D arm shows the simulation"),
        (false, StateSource::Robot) => (
            palette::rgb(palette::SOURCE_ROBOT),
            "the 3D arm mirrors the measured robot pose; the ghost is the commanded pose",
        ),
    };
    ui.label(egui::RichText::new(src).strong().color(color)).on_hover_text(hover);
    drive_state_ui(ui, ctx);
    ui.separator();
    recording_ui(ui, ctx);
    // a slot of its own, kept while the arm rests: the link rate after it stays in place
    let moving = egui::RichText::new("moving").color(palette::rgb(palette::MOVING_TEXT));
    let slot = egui::vec2(slot_width(ui, "moving"), ui.spacing().interact_size.y);
    ui.allocate_ui_with_layout(slot, egui::Layout::left_to_right(egui::Align::Center), |ui| {
        ui.set_min_size(slot);
        if ctx.robot.moving {
            // during replay the read-outs show the recording: say whose motion this is (trial 29 m7)
            let whose = if ctx.app.replaying() {
                "the recording shows the arm moving here; the live arm is not moving (motion is refused during replay)"
            } else {
                "the arm is moving"
            };
            ui.label(moving).on_hover_text(whose);
        }
    });
    let lat = match p.command_latency_ms {
        Some(ms) => format!("cmd latency {ms:.2} ms"),
        None => "cmd latency –".to_string(),
    };
    let readouts = [
        ctx.app.link.as_ref().map(|link| (format!("link {:.0} Hz", link.loop_rate_hz), "the serial link's loop rate")),
        Some((format!("t = {:.1} s", ctx.readout.time_s), clock_hover(ctx))),
        // idle, the window redraws only on input or change: a low count read as a frozen window
        // (trial 23 m14)
        Some(if p.fps < IDLE_FPS && !ctx.robot.moving {
            ("  idle   ".to_string(), "nothing changes: the window redraws only on input or when something moves")
        } else {
            (format!("{:5.1} FPS", p.fps), "frames per second (last second)")
        }),
        Some((format!("UI {:.2} ms", p.ui_cpu_ms), "CPU time of the last UI pass")),
        Some((lat, "time from sending the last command to the simulation applying it")),
        Some((
            format!("physics {:6.0} Hz, step {:5.1} µs", p.physics_rate_hz, p.physics_step_us),
            "simulation steps per second of wall time, and the duration of the last step",
        )),
    ];
    // whole read-outs only: where the window is narrow the last ones go, none is cut mid-word
    // (trial14 m6: "cmd laten" beside the Share live slot)
    for (text, hover) in readouts.into_iter().flatten() {
        let text = egui::RichText::new(text).monospace();
        let width = egui::WidgetText::from(text.clone())
            .into_galley(ui, Some(egui::TextWrapMode::Extend), f32::INFINITY, egui::TextStyle::Monospace)
            .size()
            .x;
        if width + 2.0 * ui.spacing().item_spacing.x + SEPARATOR_WIDTH > ui.available_width() {
            break;
        }
        ui.separator();
        ui.label(text).on_hover_text(hover);
    }
}

/// With a robot connected, the drives' state in one word after ROBOT, in a slot of its own (the
/// read-outs after it stay in place): E-STOP LATCHED (the window's), E-STOP PRESSED (the
/// robot's button), DISABLED or ENABLED. Trial 24 m4: with the drives
/// disabled or the E-stop latched, the bar said a plain "ROBOT". It reads the live link, also
/// during replay (the recording's state is in the panels).
fn drive_state_ui(ui: &mut egui::Ui, ctx: &PanelContext<'_>) {
    let Some(link) = ctx.app.link.as_ref() else { return };
    let (word, color, hover) = if super::io_gripper::estop_latched(ctx) {
        ("E-STOP LATCHED", palette::ERROR_TEXT, "the window's E-STOP is latched: no motion until it is released")
    } else if link.estop {
        ("E-STOP PRESSED", palette::ERROR_TEXT, "the robot's E-stop button is pressed: no motion until it is released")
    } else if !link.enabled {
        ("DISABLED", palette::WARN_TEXT, "the robot's drives are disabled: Enable them to move")
    } else {
        ("ENABLED", palette::SOURCE_ROBOT, "the robot's drives are enabled")
    };
    let text = egui::RichText::new(word).strong().color(palette::rgb(color));
    let slot = egui::vec2(slot_width(ui, "E-STOP PRESSED"), ui.spacing().interact_size.y);
    ui.allocate_ui_with_layout(slot, egui::Layout::left_to_right(egui::Align::Center), |ui| {
        ui.set_min_size(slot);
        ui.label(text).on_hover_text(hover);
    });
}

/// The room a separator takes between two read-outs (its line and margins), pt.
const SEPARATOR_WIDTH: f32 = 6.0;

/// While a file is written: a red dot, "REC", the file's name and the time since it started
/// (m:ss), refreshed every second; the full path on hover.
fn recording_ui(ui: &mut egui::Ui, ctx: &PanelContext<'_>) {
    let Some(r) = &ctx.app.recording else { return };
    let name = r.path.file_name().map_or_else(|| r.path.display().to_string(), |n| n.to_string_lossy().into_owned());
    let s = r.started.elapsed().as_secs();
    let red = palette::rgb(palette::ERROR_TEXT);
    let (dot, _) = ui.allocate_exact_size(egui::vec2(10.0, 10.0), egui::Sense::hover());
    ui.painter().circle_filled(dot.center(), 5.0, red);
    let text = format!("REC {name} {}:{:02}", s / 60, s % 60);
    ui.label(egui::RichText::new(text).strong().color(red))
        .on_hover_text(format!("recording to {} (File → Stop recording)", r.path.display()));
    ui.separator();
    ui.ctx().request_repaint_after(std::time::Duration::from_millis(500));
}

/// The *ROS 2* toggle at the right end, the *Share live* toggle (with the address while on; a
/// click stops it) left of it, each in a slot of fixed width, and the remote-control banner left
/// of both while network commands can move the arm (laid out right to left).
fn live_ui(ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
    let height = ui.spacing().interact_size.y;
    let (text, hover) = match (&ctx.live.ros2, ctx.live.ros2_starting) {
        (_, true) => (egui::RichText::new(ROS2_STARTING), "the Zenoh session is opening; click to cancel"),
        (Some(_), false) => (
            egui::RichText::new("ROS 2 ON").color(palette::rgb(palette::LIVE_TEXT)),
            "ROS 2 node parol6 over Zenoh (File menu: router, domain); click to stop",
        ),
        (None, false) => {
            (egui::RichText::new("ROS 2"), "start the ROS 2 node over Zenoh (File menu: router and domain)")
        }
    };
    let on = ctx.live.ros2.is_some() || ctx.live.ros2_starting;
    let hover = match &ctx.live.ros2 {
        Some(addr) => format!("{hover}\n{addr}"),
        None => hover.to_string(),
    };
    let slot = egui::vec2(slot_width(ui, ROS2_STARTING), height);
    if ui.add_sized(slot, egui::Button::selectable(on, text).truncate()).on_hover_text(hover).clicked() {
        ctx.send(AppCommand::ShareRos2(!on));
    }
    ui.separator();
    let sharing = ctx.live.sharing.clone();
    let (text, hover) = match &sharing {
        Some(addr) => (
            egui::RichText::new(format!("LIVE {addr}")).color(palette::rgb(palette::LIVE_TEXT)),
            format!(
                "sharing live at {addr} (Foxglove WebSocket: Foxglove or Lichtblick, Open connection); click to stop"
            ),
        ),
        None => (
            egui::RichText::new("Share live"),
            "share the arm live (Foxglove WebSocket; File menu: address)".to_string(),
        ),
    };
    let slot = egui::vec2(slot_width(ui, SHARE_SLOT_TEXT), height);
    let share = egui::Button::selectable(sharing.is_some(), text).truncate();
    if ui.add_sized(slot, share).on_hover_text(hover).clicked() {
        ctx.send(AppCommand::ShareLive(sharing.is_none()));
    }
    if ctx.live.remote_control {
        ui.separator();
        let banner = egui::RichText::new(" REMOTE CONTROL ON ")
            .strong()
            .color(palette::rgb(palette::REMOTE_CONTROL_TEXT))
            .background_color(palette::rgb(palette::REMOTE_CONTROL_BG));
        if ui.button(banner).on_hover_text("commands from the network can move the arm; click to turn off").clicked() {
            ctx.send(AppCommand::RemoteControl(false));
        }
    }
}

/// The *ROS 2* toggle's longest text: its slot's width.
const ROS2_STARTING: &str = "ROS 2 starting…";

/// The *Share live* slot holds the default address in full; a longer one is cut (whole on hover).
const SHARE_SLOT_TEXT: &str = "LIVE ws://127.0.0.1:65535";
