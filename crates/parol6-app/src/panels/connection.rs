//! Connection panel: serial port list, connect / disconnect (or the built-in emulator), LEDs for
//! link, enabled, E-stop and homed per joint, enable / disable / home, link health, and jog per
//! joint (press and hold the buttons, or select a joint with 1–6 and hold Page Up / Page Down).

use eframe::egui;

use crate::palette;
use std::time::{Duration, Instant};

use parol6_core::limits::LimitZone;

use super::entry;
use super::shortcuts::{self, Action};
use super::{AppCommand, LinkCommand, Panel, PanelContext, on_off_led, zone_color};

/// What the connection panel shows about an open serial session (built by the app from the
/// session snapshot every frame).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LinkView {
    /// Port path (or the emulator's pseudo-terminal).
    pub port: String,
    /// True when talking to the built-in emulator.
    pub emulated: bool,
    /// Status frames arrive.
    pub link_ok: bool,
    /// Link state in words.
    pub link_state: String,
    /// Drives enabled.
    pub enabled: bool,
    /// E-stop pressed.
    pub estop: bool,
    /// Homing in progress.
    pub homing: bool,
    /// Where the last homing stands, in words ("" when none was asked for).
    pub homing_text: String,
    /// Homed flag per joint.
    pub homed: Vec<bool>,
    /// Command/status loop rate, Hz.
    pub loop_rate_hz: f64,
    /// Loop period jitter, ms.
    pub jitter_ms: f64,
    /// Frames lost or corrupted.
    pub dropped_frames: u64,
    /// Status frames with physically impossible positions (rejected, never used).
    pub implausible_frames: u64,
    /// Last error reported by the session.
    pub last_error: Option<String>,
}

/// Minimum time between two port scans.
const RESCAN_INTERVAL: Duration = Duration::from_secs(2);

/// The connection panel.
#[derive(Debug, Default)]
pub struct ConnectionPanel {
    ports: Vec<(String, String)>,
    scanned_at: Option<Instant>,
    scan_error: Option<String>,
    port_text: String,
    /// Joint selected for keyboard jogging (0-based).
    key_joint: usize,
    /// The jog currently requested (joint, direction).
    jog: Option<(usize, i8)>,
    /// A link was open last frame (the section unfolds when one opens).
    was_linked: bool,
    /// The tallest the unfolded section's body has been, points: it never gets shorter while
    /// unfolded, so a disconnect (the LEDs, link health and jog give way to the shorter port
    /// list) does not pull everything above it down under the pointer when the column is
    /// scrolled to its end.
    body_height_pt: f32,
    /// When Connect or Disconnect was last clicked: the section's other face (the port list for
    /// the connected view's Disconnect, and back) stays greyed for [`SWAP_HOLD_OFF`].
    swapped_at: Option<Instant>,
    /// The jog rows were drawn this frame (the keys are disarmed while they are not).
    jog_drawn: bool,
}

/// How long the section's controls stay greyed after Connect or Disconnect swapped them: the
/// second click of a double-click on Disconnect opened the port list that took its place (trial
/// 26 m1).
const SWAP_HOLD_OFF: Duration = Duration::from_millis(800);

/// Why the section's controls are greyed just after a Connect or Disconnect.
const SWAP_HELD_OFF: &str = "just connected or disconnected: the controls take clicks again in a moment, so that \
                             a double-click does not land on what took the button's place";

impl ConnectionPanel {
    fn rescan(&mut self) {
        self.scanned_at = Some(Instant::now());
        match parol6_hw::list_ports() {
            Ok(list) => {
                self.ports = list
                    .iter()
                    .map(|p| {
                        let mut d = p.name.clone();
                        if p.is_parol6 {
                            d.push_str("  (PAROL6)");
                        } else if let Some(prod) = &p.product {
                            d.push_str(&format!("  ({prod})"));
                        }
                        (p.name.clone(), d)
                    })
                    .collect();
                self.scan_error = None;
                if self.port_text.is_empty()
                    && let Ok(p) = parol6_hw::find_parol6_port()
                {
                    self.port_text = p;
                }
            }
            Err(e) => {
                self.ports.clear();
                self.scan_error = Some(e.to_string());
            }
        }
    }

    /// True while the controls that took the place of Connect / Disconnect wait
    /// ([`SWAP_HOLD_OFF`]); a repaint is asked for at its end.
    fn settling(&self, ui: &egui::Ui) -> bool {
        let left = self.swapped_at.and_then(|t| SWAP_HOLD_OFF.checked_sub(t.elapsed()));
        if let Some(left) = left {
            ui.ctx().request_repaint_after(left);
        }
        left.is_some()
    }

    fn disconnected_ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        if self.scanned_at.is_none_or(|t| t.elapsed() > RESCAN_INTERVAL * 15) {
            if self.port_text.is_empty() {
                self.port_text = ctx.settings.last_port.clone();
            }
            self.rescan();
        }
        let settling = self.settling(ui);
        let r = ui.add_enabled_ui(!settling, |ui| self.disconnected_controls(ui, ctx)).response;
        if settling {
            r.on_disabled_hover_text(SWAP_HELD_OFF);
        }
    }

    fn disconnected_controls(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        ui.horizontal(|ui| {
            ui.label("Port");
            egui::ComboBox::from_id_salt("port_list")
                .selected_text(if self.port_text.is_empty() { "select…" } else { self.port_text.as_str() })
                .width(180.0)
                .show_ui(ui, |ui| {
                    for (path, desc) in &self.ports {
                        ui.selectable_value(&mut self.port_text, path.clone(), desc);
                    }
                    if self.ports.is_empty() {
                        ui.weak("no serial ports found");
                    }
                });
            if ui.button("Rescan").on_hover_text("Rescan the serial ports").clicked()
                && self.scanned_at.is_none_or(|t| t.elapsed() > RESCAN_INTERVAL / 4)
            {
                self.rescan();
            }
        });
        ui.horizontal(|ui| {
            // "e.g.": a bare port name in grey read as filled in, and Connect looked usable (trial 29 m8)
            let example = if cfg!(windows) { "e.g. COM3" } else { "e.g. /dev/ttyACM0" };
            ui.add(egui::TextEdit::singleline(&mut self.port_text).hint_text(example).desired_width(150.0));
            let can = !self.port_text.trim().is_empty();
            let connect = ui
                .add_enabled(can, egui::Button::new("Connect"))
                .on_disabled_hover_text("type a serial port, or pick one from the list above");
            if connect.clicked() {
                let p = self.port_text.trim().to_string();
                self.swapped_at = Some(Instant::now());
                ctx.send(AppCommand::Link(LinkCommand::Connect(p)));
            }
        });
        if ui.button("Connect to the built-in emulator").on_hover_text("a fake PAROL6 controller in-process").clicked()
        {
            self.swapped_at = Some(Instant::now());
            ctx.send(AppCommand::Link(LinkCommand::ConnectEmulator));
        }
        if let Some(e) = &self.scan_error {
            ui.colored_label(palette::rgb(palette::WARN_TEXT), e);
        }
    }

    fn jog_ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>, link: &LinkView) {
        self.jog_drawn = true;
        let mut held: Option<(usize, i8)> = None;
        let n = ctx.model.dof();
        let latched = super::io_gripper::estop_latched(ctx);
        let allowed = link.link_ok && link.enabled && !link.estop && !latched;
        // the buttons are greyed during replay too, as the Cartesian jog's are (trial 26 m10); a
        // jog key is refused by the app with the reason
        let replaying = ctx.app.replaying();
        ui.label(egui::RichText::new("Jog (hold)").strong())
            .on_hover_text("Press and hold a button, or select a joint with 1–6 and hold Page Up / Page Down");
        egui::Grid::new("jog_grid").num_columns(4).spacing([6.0, 3.0]).show(ui, |ui| {
            for i in 0..n {
                let name = ctx.model.joints.get(i).map(|j| j.name.as_str()).unwrap_or("?");
                let sel = self.key_joint == i;
                if ui.selectable_label(sel, name).clicked() {
                    self.key_joint = i;
                }
                for (label, dir) in [("−", -1i8), ("+", 1i8)] {
                    // click-and-drag: a click-only button stops counting a press held past egui's
                    // click time (0.8 s) as its own, and the jog was released under a held button
                    let button =
                        egui::Button::new(label).min_size(egui::vec2(34.0, 20.0)).sense(egui::Sense::click_and_drag());
                    let mut b = ui.add_enabled(allowed && !replaying, button);
                    if replaying {
                        b = b.on_disabled_hover_text(crate::app::state::REPLAY_OPEN);
                    }
                    // a dead-man button: dragging the pointer off it ends the jog
                    if b.is_pointer_button_down_on() && b.contains_pointer() {
                        held = Some((i, dir));
                    }
                }
                let zone = ctx.robot.zones.get(i).map(|z| z.zone).unwrap_or(LimitZone::Safe);
                ui.label(
                    egui::RichText::new(ctx.settings.unit.fmt(ctx.readout.q.get(i).copied().unwrap_or(0.0)))
                        .monospace()
                        .color(zone_color(zone)),
                );
                ui.end_row();
            }
        });
        ui.horizontal(|ui| {
            ui.label("Jog speed");
            let mut pct = ctx.settings.jog_speed_fraction * 100.0;
            let (r, refused) = entry::typed_slider(ui, "Jog speed", &mut pct, 1.0..=100.0, (" %", "%"), 0);
            if r.changed() {
                ctx.settings.jog_speed_fraction = (pct / 100.0).clamp(0.01, 1.0);
            }
            if let Some(message) = refused {
                ctx.error(message);
            }
        });
        // below the rows: above them its two lines moved every jog button under the pointer
        // when E-STOP latched (trial12 n-h)
        if latched {
            ui.colored_label(palette::rgb(palette::ERROR_TEXT), super::io_gripper::ESTOP_LATCHED);
        }
        // Keyboard (the table in `shortcuts`): 1–6 select, Page Up / Page Down held = jog.
        for i in 0..n {
            if shortcuts::pressed(ui.ctx(), Action::SelectJoint(i)) {
                self.key_joint = i;
            }
        }
        if !allowed {
            // a key held while the jog is off (the drives disabled, the E-stop input, the link
            // down) does not jog once it is on again: let go and press anew (trial19 D1)
            shortcuts::disarm_held(ui.ctx());
        }
        if held.is_none() && allowed {
            if shortcuts::held(ui.ctx(), Action::JogJoint(1)) {
                held = Some((self.key_joint, 1));
            } else if shortcuts::held(ui.ctx(), Action::JogJoint(-1)) {
                held = Some((self.key_joint, -1));
            }
        }
        if held != self.jog || held.is_some() {
            // Sent every frame while held: the session's dead-man needs a steady refresh.
            ctx.send(AppCommand::Jog(held));
        }
        self.jog = held;
    }

    fn connected_ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>, link: &LinkView) {
        ui.horizontal(|ui| {
            if link.emulated {
                // its port is a local socket's path: named in plain words, the path on hover
                ui.label("built-in emulator").on_hover_text(format!("reached through {}", link.port));
            } else {
                ui.label(&link.port);
            }
            let settling = self.settling(ui);
            let b = ui.add_enabled(!settling, egui::Button::new("Disconnect"));
            if b.on_disabled_hover_text(SWAP_HELD_OFF).clicked() {
                self.swapped_at = Some(Instant::now());
                ctx.send(AppCommand::Link(LinkCommand::Disconnect));
            }
        });
        let green = zone_color(LimitZone::Safe);
        let red = zone_color(LimitZone::Critical);
        ui.horizontal(|ui| {
            on_off_led(ui, link.link_ok, green, "link").on_hover_text(&link.link_state);
            on_off_led(ui, link.enabled, green, "enabled");
            on_off_led(ui, link.estop, red, "E-stop input");
            on_off_led(ui, link.homing, zone_color(LimitZone::Warning), "homing");
        });
        // always a row, empty until a homing is asked for: its line appearing moved the jog
        // buttons below it under the pointer (trial11 n9)
        let color = if link.homing { zone_color(LimitZone::Warning) } else { ui.visuals().text_color() };
        let homing_text = if link.homing_text.is_empty() { " " } else { link.homing_text.as_str() };
        ui.add(egui::Label::new(egui::RichText::new(homing_text).color(color)).truncate())
            .on_hover_text("where the last homing stands");
        ui.horizontal(|ui| {
            ui.label("homed");
            for (i, h) in link.homed.iter().enumerate() {
                let name = ctx.model.joints.get(i).map(|j| j.name.clone()).unwrap_or_else(|| format!("J{}", i + 1));
                on_off_led(ui, *h, green, &name);
            }
        });
        // under the latched E-STOP only Release E-STOP enables, and homing moves the arm: both greyed
        // (the app refuses them too)
        let latched = super::io_gripper::estop_latched(ctx);
        ui.horizontal(|ui| {
            let enable = ui.add_enabled(link.link_ok && !link.enabled && !latched, egui::Button::new("Enable"));
            if latched_reason(enable, latched).clicked() {
                ctx.send(AppCommand::Link(LinkCommand::Enable));
            }
            if ui.add_enabled(link.link_ok && link.enabled, egui::Button::new("Disable")).clicked() {
                ctx.send(AppCommand::Link(LinkCommand::Disable));
            }
            let home = ui.add_enabled(link.link_ok && !link.estop && !latched, egui::Button::new("Home (homing)"));
            if latched_reason(home, latched).clicked() {
                ctx.send(AppCommand::Link(LinkCommand::Home));
            }
        });
        ui.separator();
        self.jog_ui(ui, ctx, link);
        // below the jog, what changes height (the health wrapping as its numbers grow, an error
        // appearing) moves no jog button
        ui.separator();
        // wraps inside the column (it was cut at the column's edge)
        let health = format!(
            "loop {:.0} Hz  jitter {:.2} ms  dropped {}  implausible {}",
            link.loop_rate_hz, link.jitter_ms, link.dropped_frames, link.implausible_frames
        );
        ui.add(egui::Label::new(egui::RichText::new(health).monospace()).wrap()).on_hover_text(
            "link health: command/status loop rate, period jitter, frames lost or corrupted, status frames \
             with impossible positions (rejected)",
        );
        if let Some(e) = &link.last_error {
            ui.colored_label(palette::rgb(palette::ERROR_TEXT), e);
        }
    }
}

/// A button greyed by the latched E-STOP says so on hover.
fn latched_reason(button: egui::Response, latched: bool) -> egui::Response {
    if latched { button.on_disabled_hover_text(super::io_gripper::ESTOP_LATCHED) } else { button }
}

/// The link's health in the open recording at the cursor: what the read-out showed then.
fn recorded_link_ui(ui: &mut egui::Ui, h: &parol6_core::telemetry::LinkHealth) {
    let green = zone_color(LimitZone::Safe);
    let red = zone_color(LimitZone::Critical);
    // wraps inside the column (it was cut at the column's edge)
    ui.horizontal_wrapped(|ui| {
        ui.label("REPLAY link").on_hover_text("the serial link's health as recorded, at the replay cursor");
        on_off_led(ui, h.state == "Connected", green, "link").on_hover_text(&h.state);
        on_off_led(ui, h.estop_pressed, red, "E-stop input");
        ui.monospace(format!(
            "{}  loop {:.0} Hz  missing {}  losses {}",
            h.state, h.loop_rate_hz, h.missing_replies, h.link_losses
        ));
    });
}

impl Panel for ConnectionPanel {
    fn title(&self) -> &'static str {
        "Robot connection"
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        let link = ctx.app.link.clone();
        if link.is_none() && self.jog.take().is_some() {
            ctx.send(AppCommand::Jog(None));
        }
        // Folded while there is no robot; unfolds by itself when a link opens.
        let just_linked = link.is_some() && !self.was_linked;
        self.was_linked = link.is_some();
        self.jog_drawn = false;
        egui::CollapsingHeader::new(egui::RichText::new(self.title()).heading())
            .id_salt("robot_connection")
            .open(just_linked.then_some(true))
            .show(ui, |ui| {
                let top = ui.cursor().top();
                match &link {
                    Some(link) => self.connected_ui(ui, ctx, link),
                    None => self.disconnected_ui(ui, ctx),
                }
                let used = ui.cursor().top() - top;
                if used < self.body_height_pt {
                    ui.add_space(self.body_height_pt - used);
                }
                self.body_height_pt = self.body_height_pt.max(used);
            });
        if !self.jog_drawn {
            // Page Up / Down held while the jog is not on screen (no robot, the section folded)
            // does not jog the moment it is: let go and press anew (as under a refusal, trial19 D1)
            shortcuts::disarm_held_of(ui.ctx(), |a| matches!(a, Action::JogJoint(_)));
        }
        // below the section, the column's last row: opening a replay moves nothing (above the
        // heading it pushed the section down 38 px: trial9 m9)
        if let Some(h) = ctx.app.replayed_link() {
            recorded_link_ui(ui, h);
        }
    }
}
