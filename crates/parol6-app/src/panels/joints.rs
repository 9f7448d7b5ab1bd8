//! Left panel: per joint a slider, numeric entry, limit LED (with predicted time to limit) and a
//! protection bar; a banner naming the joint nearest its limit; HOME / STOP; "go to joint pose".

use eframe::egui;
use egui::containers::menu::{MenuButton, MenuConfig};
use parol6_core::limits::{JointLimit, LimitZone, ZoneThresholds};

use parol6_core::motion::{MotionCommand, RobotState};

use super::entry::{self, EntryEvent};
use super::{AngleUnit, Panel, PanelContext, ProfileKindSetting, zone_color};
use crate::palette;

/// Slider range used for a joint without finite limits (rad).
const UNBOUNDED_RANGE_RAD: f64 = std::f64::consts::PI;
/// Time-to-limit values above this are not shown (s).
const TTL_SHOW_MAX_S: f64 = 10.0;
/// Smallest joint speed for which a time to a limit is shown, rad/s: below it the joint stands
/// (a speed of noise showed "limit in 0.0 s" for a joint resting at its limit).
const TTL_MIN_SPEED_RAD_S: f64 = 1e-3;
/// How close the planned end of the motion must come to the limit for its time to show, rad.
const TTL_TARGET_TOLERANCE_RAD: f64 = 0.0087;

/// The time to joint `i`'s limit worth showing, s: the joint moves toward the limit it is
/// nearest to, reaches it within `TTL_SHOW_MAX_S` at this speed, and its planned motion (the
/// state's `target_q`) ends at that limit. A joint at rest at its limit, or a move that stops
/// short of the limit, shows none (both showed a time: "limit in 0.0 s", "1.7 s" for a move
/// ending 77° short).
pub fn time_to_limit_shown_s(model: &parol6_core::RobotModel, state: &RobotState, i: usize) -> Option<f64> {
    let t = state.zones.get(i)?.time_to_nearest_limit_s.filter(|t| *t < TTL_SHOW_MAX_S)?;
    let qd = *state.qd.get(i)?;
    let l = model.limits.get(i)?;
    let target = *state.target_q.get(i)?;
    let reaches = if qd > TTL_MIN_SPEED_RAD_S {
        target >= l.max - TTL_TARGET_TOLERANCE_RAD
    } else if qd < -TTL_MIN_SPEED_RAD_S {
        target <= l.min + TTL_TARGET_TOLERANCE_RAD
    } else {
        false
    };
    reaches.then_some(t)
}
/// Height of the one-line limit status slot (points): always reserved, so nothing moves.
const STATUS_LINE_HEIGHT: f32 = 24.0;
/// Fixed widths of a joint row (points): LED, name, typed entry, unit after the entry.
const LED_W: f32 = 14.0;
const NAME_W: f32 = 26.0;
const ENTRY_W: f32 = 62.0;
const SUFFIX_W: f32 = 22.0;
/// Title of the "go to joint pose" section (in a short window, of the button that opens it).
const GOTO_TITLE: &str = "Go to joint pose";
/// Window height, points, below which that section is a button opening it over the panel
/// (the window's smallest supported size is 1024x700; 1280x800 has room for it in place).
const COMPACT_BELOW_HEIGHT_PT: f32 = 760.0;

/// The joints panel.
#[derive(Debug, Default)]
pub struct JointsPanel {
    /// Slider values (rad), following the commanded targets while no slider is held.
    edit: Vec<f64>,
    /// The "go to joint pose" entries (rad).
    goto: Vec<f64>,
    /// True while a slider or entry of this panel is being used.
    editing: bool,
    /// The slider values are kept (not replaced by the reported targets) until then, so a
    /// command just sent is not undone by a snapshot taken before it arrived.
    hold_until: Option<std::time::Instant>,
}

/// True when the backend's target is a joint goal the arm is moving to (a joint move, a slider
/// being followed): the joint fields show it and a typed joint keeps the others on it.
/// Otherwise they show, and keep, where the arm is: a held jog's target (joint or Cartesian) is
/// where it would stop at the latest (trial 15: J1's field read −123.05° while the arm was at
/// 80°), and a program's path (running or paused, trial6: a typed J4 on a paused Draw sent J1,
/// J3 and J6 7° to an earlier step's goal) is not where the arm stays.
fn joint_goal_is_set(ctx: &PanelContext<'_>, n: usize) -> bool {
    use parol6_core::motion::PlannerMode;
    ctx.robot.target_q.len() == n && matches!(ctx.robot.mode, PlannerMode::Move | PlannerMode::Follow)
}

/// How long slider values are kept after a change before following the reported targets.
const HOLD_AFTER_CHANGE: std::time::Duration = std::time::Duration::from_millis(300);

/// Display range of a joint (rad).
fn slider_range(limit: Option<&JointLimit>) -> (f64, f64) {
    match limit {
        Some(l) if l.is_bounded() => (l.min, l.max),
        Some(l) => (
            if l.min.is_finite() { l.min } else { -UNBOUNDED_RANGE_RAD },
            if l.max.is_finite() { l.max } else { UNBOUNDED_RANGE_RAD },
        ),
        None => (-UNBOUNDED_RANGE_RAD, UNBOUNDED_RANGE_RAD),
    }
}

impl JointsPanel {
    /// Moves joint `joint` (0-based) to `value_rad` exactly like its slider does: the value is
    /// clamped into the joint's limits and sent as a direct joint target. Also used by the
    /// app's test hook.
    pub fn set_joint(&mut self, joint: usize, value_rad: f64, ctx: &mut PanelContext<'_>) {
        if self.edit.len() != ctx.model.dof() {
            self.sync(ctx);
        }
        self.hold_until = Some(std::time::Instant::now() + HOLD_AFTER_CHANGE);
        if joint >= self.edit.len() || !value_rad.is_finite() {
            return;
        }
        let (lo, hi) = slider_range(ctx.model.limits.get(joint));
        self.edit[joint] = value_rad.clamp(lo, hi);
        match ctx.model.limits.enforce(&self.edit, parol6_core::LimitPolicy::Clamp) {
            Ok(q) => ctx.motion(MotionCommand::follow(q)),
            Err(e) => ctx.error(format!("joint target refused: {e}")),
        }
    }

    /// Follows the commanded targets while the operator is not editing.
    fn sync(&mut self, ctx: &PanelContext<'_>) {
        let n = ctx.model.dof();
        let held = self.editing || self.hold_until.is_some_and(|t| std::time::Instant::now() < t);
        if self.edit.len() != n || !held {
            self.edit = if joint_goal_is_set(ctx, n) { ctx.robot.target_q.clone() } else { ctx.robot.q.clone() };
            self.edit.resize(n, 0.0);
        }
        if self.goto.len() != n {
            self.goto = ctx.robot.q.clone();
            self.goto.resize(n, 0.0);
        }
    }

    /// Commits a value typed into joint `joint`'s entry (display unit), confirmed by Enter or Tab: clamps it into the
    /// joint's limits (saying so), then a profiled move of that joint, the others keeping
    /// their commanded targets.
    fn commit_joint(&mut self, joint: usize, typed: f64, ctx: &mut PanelContext<'_>) {
        let unit = ctx.settings.unit;
        let name = joint_name(ctx, joint);
        let (lo, hi) = slider_range(ctx.model.limits.get(joint));
        let wanted = unit.to_rad(typed);
        let goal_rad = wanted.clamp(lo, hi);
        if (goal_rad - wanted).abs() > 1e-12 {
            let side = if wanted > hi { "upper" } else { "lower" };
            ctx.error(format!(
                "{name}: {} is beyond its {side} limit {}; clamped to the limit",
                unit.fmt(wanted),
                unit.fmt(goal_rad)
            ));
        }
        let n = ctx.model.dof();
        let mut goal = if joint_goal_is_set(ctx, n) {
            ctx.robot.target_q.clone()
        } else if ctx.robot.commanded.q.len() == n {
            ctx.robot.commanded.q.clone()
        } else {
            ctx.robot.q.clone()
        };
        goal.resize(n, 0.0);
        if joint >= goal.len() {
            return;
        }
        goal[joint] = goal_rad;
        match ctx.model.limits.enforce(&goal, parol6_core::LimitPolicy::Clamp) {
            Ok(q) => {
                self.edit = q.clone();
                self.hold_until = Some(std::time::Instant::now() + HOLD_AFTER_CHANGE);
                ctx.typed_move_to(q);
            }
            Err(e) => ctx.error(format!("joint target refused: {e}")),
        }
    }

    /// The one-line status slot under HOME / STOP. It always takes the same height, so nothing
    /// below or above it moves when a warning appears. An alarm (a joint in the red zone, or
    /// reaching a limit within the prediction horizon) is a coloured band; a joint resting in
    /// the amber band is plain information.
    fn status_line(ui: &mut egui::Ui, ctx: &PanelContext<'_>) {
        let (text, alarm) = limit_status_text(ctx);
        let (rect, resp) =
            ui.allocate_exact_size(egui::vec2(ui.available_width(), STATUS_LINE_HEIGHT), egui::Sense::hover());
        let text_color = match alarm {
            Some(zone) => {
                let color = zone_color(zone);
                ui.painter().rect_filled(rect, 4.0, color.gamma_multiply(0.25));
                ui.painter().rect_stroke(rect, 4.0, egui::Stroke::new(1.0, color), egui::StrokeKind::Inside);
                ui.visuals().strong_text_color()
            }
            None => ui.visuals().weak_text_color(),
        };
        let inner = rect.shrink2(egui::vec2(6.0, 0.0));
        ui.scope_builder(
            egui::UiBuilder::new().max_rect(inner).layout(egui::Layout::left_to_right(egui::Align::Center)),
            |ui| {
                let rich = egui::RichText::new(&text).color(text_color);
                ui.add(egui::Label::new(if alarm.is_some() { rich.strong() } else { rich }).truncate());
            },
        );
        resp.on_hover_text(text);
    }

    fn joint_row(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>, i: usize) {
        let unit = ctx.settings.unit;
        let name = joint_name(ctx, i);
        let limit = ctx.model.limits.get(i).cloned();
        let (lo, hi) = slider_range(limit.as_ref());
        let report = ctx.robot.zones.get(i).copied();
        let zone = report.map(|r| r.zone).unwrap_or(LimitZone::Safe);
        let q = ctx.robot.q.get(i).copied().unwrap_or(0.0);
        let row_w = ui.available_width();

        let mut slider_to = None;
        let mut typed = None;
        ui.horizontal(|ui| {
            let mut tip = format!("{name}: {}", zone.label());
            if let Some(t) = time_to_limit_shown_s(ctx.model, ctx.robot, i) {
                tip.push_str(&format!(" — limit in {t:.1} s"));
            }
            super::led(ui, zone_color(zone), tip);
            ui.add_sized([NAME_W, 18.0], egui::Label::new(egui::RichText::new(&name).strong().monospace()));
            let mut v = unit.from_rad(self.edit[i]);
            let (dlo, dhi) = (unit.from_rad(lo), unit.from_rad(hi));
            let spacing = ui.spacing().item_spacing.x;
            ui.spacing_mut().slider_width = (row_w - LED_W - NAME_W - ENTRY_W - SUFFIX_W - 5.0 * spacing).max(40.0);
            let s =
                ui.add(egui::Slider::new(&mut v, dlo..=dhi).show_value(false).clamping(egui::SliderClamping::Always));
            if s.dragged() || s.has_focus() {
                self.editing = true;
            }
            if s.changed() {
                slider_to = Some(unit.to_rad(v));
            }
            let (d, event) = entry::numeric_entry(
                ui,
                &format!("{name} target"),
                unit.from_rad(self.edit[i]),
                unit.decimals(),
                ENTRY_W,
                unit.suffix().trim(),
            );
            if d.has_focus() {
                self.editing = true;
            }
            typed = event;
        });
        if let Some(v) = slider_to {
            self.set_joint(i, v, ctx);
        }
        match typed {
            Some(EntryEvent::Committed(v)) if entry::left_by_key(ui) => self.commit_joint(i, v, ctx),
            Some(EntryEvent::Committed(_)) => ctx.info(format!("{name}: {TYPED_NOT_SENT}")),
            Some(EntryEvent::Invalid(why)) => ctx.error(format!("{name}: {why}")),
            None => {}
        }
        // numeric text from the readout state (see `PanelContext::readout`)
        let q_text = ctx.readout.q.get(i).copied().unwrap_or(q);
        ui.horizontal(|ui| {
            ui.add_space(LED_W + NAME_W + ui.spacing().item_spacing.x);
            let w = (row_w - LED_W - NAME_W - 150.0).max(40.0);
            protection_bar(ui, w, limit.as_ref(), q, self.edit[i]);
            ui.label(egui::RichText::new(unit.fmt(q_text)).monospace().small()).on_hover_text("measured position");
            if let Some(t) = time_to_limit_shown_s(ctx.model, ctx.readout, i) {
                ui.label(egui::RichText::new(format!("limit in {t:.1} s")).small().color(zone_color(zone)))
                    .on_hover_text("predicted time to reach the limit it is nearest to, at the current speed");
            }
        });
    }
}

/// What a joint's typed value left by a click elsewhere (not Enter or Tab) becomes.
pub const TYPED_NOT_SENT: &str =
    "the value typed and not confirmed with Enter was not sent (a click elsewhere never moves the arm)";

/// Height of the STOP and E-STOP buttons in the joints panel, points.
const STOP_BUTTON_HEIGHT: f32 = 28.0;

/// The red STOP button (Esc) and the E-STOP beside it, `height` points tall: in the joints
/// panel, and in the menu bar while the joints panel is hidden (View menu), so that both are
/// always on screen. While a question is open (a modal: the quit question, the torque
/// question), which dims and blocks everything under it, both are drawn once more, live, above
/// it in the same place: the first click on them acts (it used to close the question only,
/// and the arm went on moving).
pub fn stop_buttons(ui: &mut egui::Ui, ctx: &mut PanelContext<'_>, height: f32) {
    let layout = *ui.layout();
    let rect = ui.scope(|ui| stop_buttons_here(ui, ctx, height)).response.rect;
    if ui.ctx().memory(|m| m.top_modal_layer()).is_some() {
        egui::Area::new(ui.scope_id().with("stop_buttons_above_a_question"))
            .order(egui::Order::Tooltip)
            .fixed_pos(rect.min)
            .show(ui.ctx(), |ui| {
                ui.allocate_ui_with_layout(rect.size(), layout, |ui| stop_buttons_here(ui, ctx, height));
            });
    }
}

/// STOP and E-STOP, laid out by `ui`.
fn stop_buttons_here(ui: &mut egui::Ui, ctx: &mut PanelContext<'_>, height: f32) {
    let stop = egui::Button::new(egui::RichText::new("STOP").strong().color(palette::rgb(palette::STOP_TEXT)))
        .fill(palette::rgb(palette::STOP_FILL))
        .min_size(egui::vec2(90.0, height));
    if ui.add(stop).on_hover_text("Stop now (Esc)").clicked() {
        ctx.stop();
    }
    super::io_gripper::estop_button(ui, ctx, height);
}

/// A joint's name (or `J<n>`).
fn joint_name(ctx: &PanelContext<'_>, i: usize) -> String {
    ctx.model.joints.get(i).map(|j| j.name.clone()).unwrap_or_else(|| format!("J{}", i + 1))
}

/// The text of the limit status line, and the zone to colour it with when it is an alarm.
pub fn limit_status_text(ctx: &PanelContext<'_>) -> (String, Option<LimitZone>) {
    if ctx.app.replaying() {
        return (crate::app::state::REPLAY_OPEN.to_string(), None);
    }
    let unit = ctx.settings.unit;
    let robot = ctx.robot;
    let distance = |i: usize| -> Option<(&'static str, f64)> {
        let l = ctx.model.limits.get(i).filter(|l| l.is_bounded())?;
        let q = robot.q.get(i).copied()?;
        Some(if q - l.min < l.max - q { ("lower", q - l.min) } else { ("upper", l.max - q) })
    };
    let alarm = robot.zones.iter().copied().enumerate().filter(|(_, z)| z.is_alarm()).max_by(|a, b| {
        a.1.zone.cmp(&b.1.zone).then_with(|| {
            let ta = a.1.time_to_nearest_limit_s.unwrap_or(f64::INFINITY);
            let tb = b.1.time_to_nearest_limit_s.unwrap_or(f64::INFINITY);
            tb.total_cmp(&ta)
        })
    });
    if let Some((i, report)) = alarm {
        let name = joint_name(ctx, i);
        let mut text = match distance(i) {
            Some((side, left)) => {
                // "at limit: 5.89° to its upper limit" read as a contradiction (trials 21 m15, 24 m3)
                let zone = if report.zone == LimitZone::Critical { "very near limit" } else { report.zone.label() };
                format!("{name} {zone}: {} to its {side} limit", unit.fmt(left.max(0.0)))
            }
            None => format!("{name} {}", report.zone.label()),
        };
        if let Some(t) = time_to_limit_shown_s(ctx.model, robot, i) {
            text.push_str(&format!(", reached in {t:.1} s at this speed"));
        }
        return (text, Some(report.zone));
    }
    // No risk: name the joint approaching a limit soonest (or else the one nearest a limit),
    // as information.
    let approaching = robot
        .zones
        .iter()
        .enumerate()
        .filter_map(|(i, _)| Some((i, time_to_limit_shown_s(ctx.model, robot, i)?)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let nearest = (0..robot.q.len())
        .filter_map(|i| {
            let l = ctx.model.limits.get(i)?;
            Some((i, l.margin_fraction(*robot.q.get(i)?)?))
        })
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let shown = approaching.map(|(i, t)| (i, Some(t))).or(nearest.map(|(i, _)| (i, None)));
    let text = match shown.and_then(|(i, t)| distance(i).map(|d| (i, d, t))) {
        Some((i, (side, left), t)) => {
            let mut text =
                format!("Nearest limit: {} is {} from its {side} limit", joint_name(ctx, i), unit.fmt(left.max(0.0)));
            if let Some(t) = t {
                text.push_str(&format!(", reached in {t:.1} s at this speed"));
            }
            text
        }
        None => "All joints are clear of their limits".to_string(),
    };
    (text, None)
}

/// Paints a joint's range with its amber / red end zones, the measured position (filled) and
/// the target (outline).
fn protection_bar(ui: &mut egui::Ui, width: f32, limit: Option<&JointLimit>, q: f64, target: f64) {
    let (rect, resp) = ui.allocate_exact_size(egui::vec2(width, 10.0), egui::Sense::hover());
    if !ui.is_rect_visible(rect) {
        return;
    }
    let p = ui.painter();
    p.rect_filled(rect, 2.0, ui.visuals().extreme_bg_color);
    let Some(l) = limit.filter(|l| l.is_bounded() && l.range() > 0.0) else {
        return;
    };
    let t = ZoneThresholds::default();
    let x = |frac: f64| rect.left() + rect.width() * frac.clamp(0.0, 1.0) as f32;
    let band = |a: f64, b: f64, zone: LimitZone| {
        let r = egui::Rect::from_x_y_ranges(x(a)..=x(b), rect.y_range());
        p.rect_filled(r, 0.0, zone_color(zone).gamma_multiply(0.55));
    };
    band(0.0, t.critical_fraction, LimitZone::Critical);
    band(t.critical_fraction, t.warning_fraction, LimitZone::Warning);
    band(t.warning_fraction, 1.0 - t.warning_fraction, LimitZone::Safe);
    band(1.0 - t.warning_fraction, 1.0 - t.critical_fraction, LimitZone::Warning);
    band(1.0 - t.critical_fraction, 1.0, LimitZone::Critical);
    let fq = (q - l.min) / l.range();
    let ft = (target - l.min) / l.range();
    let fg = ui.visuals().strong_text_color();
    p.rect_stroke(
        egui::Rect::from_center_size(egui::pos2(x(ft), rect.center().y), egui::vec2(5.0, 12.0)),
        1.0,
        egui::Stroke::new(1.0, fg),
        egui::StrokeKind::Middle,
    );
    p.rect_filled(egui::Rect::from_center_size(egui::pos2(x(fq), rect.center().y), egui::vec2(3.0, 14.0)), 0.0, fg);
    let margin = l.margin_fraction(q).unwrap_or(0.0);
    resp.on_hover_text(format!("margin to the nearest limit: {:.1} % of the range", 100.0 * margin));
}

impl Panel for JointsPanel {
    fn title(&self) -> &'static str {
        "Joints"
    }

    /// The heading and HOME / STOP / E-STOP, pinned above the left column's scroll: scrolling
    /// the column to the program, the gripper or the robot connection used to take STOP and
    /// E-STOP off the screen.
    fn pinned_ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        ui.horizontal(|ui| {
            ui.heading(self.title());
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                ui.selectable_value(&mut ctx.settings.unit, AngleUnit::Rad, "rad");
                ui.selectable_value(&mut ctx.settings.unit, AngleUnit::Deg, "deg");
            });
        });
        // HOME / STOP first: always at the same place, above anything that can change size.
        ui.horizontal(|ui| {
            let home = egui::Button::new(egui::RichText::new("HOME").strong()).min_size(egui::vec2(90.0, 28.0));
            let refused = ctx.motion_refused();
            let home = ui.add_enabled(refused.is_none(), home).on_disabled_hover_text(refused.unwrap_or_default());
            if home.on_hover_text("Profiled move to the standby pose (H)").clicked() {
                ctx.home();
            }
            stop_buttons(ui, ctx, STOP_BUTTON_HEIGHT);
        });
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        self.sync(ctx);
        self.editing = false;
        Self::status_line(ui, ctx);
        ui.add_space(4.0);
        // an open recording (or the latched E-stop) refuses motion: the rows show the recording
        // and are off, the hover says why
        let refused = ctx.motion_refused();
        ui.add_enabled_ui(refused.is_none(), |ui| {
            for i in 0..self.edit.len() {
                self.joint_row(ui, ctx, i);
                ui.add_space(2.0);
            }
        })
        .response
        .on_disabled_hover_text(refused.unwrap_or_default());
        ui.separator();
        ui.horizontal(|ui| {
            ui.label("Speed");
            let mut pct = ctx.settings.speed_fraction * 100.0;
            let (r, refused) = entry::typed_slider(ui, "Speed", &mut pct, 1.0..=100.0, (" %", "%"), 0);
            if r.changed() {
                ctx.settings.speed_fraction = (pct / 100.0).clamp(0.01, 1.0);
            }
            if let Some(message) = refused {
                ctx.error(message);
            }
        });
        ui.horizontal(|ui| {
            ui.label("Profile");
            for k in [ProfileKindSetting::Trapezoidal, ProfileKindSetting::JerkLimited] {
                ui.selectable_value(&mut ctx.settings.profile, k, k.label());
            }
        });
        ui.separator();
        ui.add_enabled_ui(refused.is_none(), |ui| {
            if ui.ctx().content_rect().height() < COMPACT_BELOW_HEIGHT_PT {
                // a short window: the section opens over the panel, so that the program's Run /
                // Pause / Step / Stop below stay in view without scrolling (hand trial, 1024x700)
                let stay_open = MenuConfig::new().close_behavior(egui::PopupCloseBehavior::CloseOnClickOutside);
                MenuButton::new(format!("{GOTO_TITLE}…"))
                    .config(stay_open)
                    .ui(ui, |ui| self.goto_ui(ui, ctx))
                    .0
                    .on_hover_text("Type a joint pose and move to it");
            } else {
                self.goto_ui(ui, ctx);
            }
        });
    }
}

impl JointsPanel {
    /// "Go to joint pose": one typed entry per joint (committed on Enter / focus loss, clamped
    /// into the limits with a notice), then a profiled move on "Go".
    fn goto_ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        ui.label(egui::RichText::new(GOTO_TITLE).strong());
        let unit = ctx.settings.unit;
        let mut events = Vec::new();
        egui::Grid::new("goto_pose").num_columns(4).spacing([6.0, 2.0]).show(ui, |ui| {
            for i in 0..self.goto.len() {
                let name = joint_name(ctx, i);
                ui.label(egui::RichText::new(&name).monospace());
                let (_, event) = entry::numeric_entry(
                    ui,
                    &format!("{name} pose"),
                    unit.from_rad(self.goto[i]),
                    unit.decimals(),
                    ENTRY_W,
                    unit.suffix().trim(),
                );
                if let Some(e) = event {
                    events.push((i, name, e));
                }
                if i % 2 == 1 {
                    ui.end_row();
                }
            }
        });
        // a field whose text was refused this frame: Go does not move with its old value (trial 29 m1)
        let mut refused = None;
        for (i, name, event) in events {
            match event {
                EntryEvent::Committed(v) => {
                    let (lo, hi) = slider_range(ctx.model.limits.get(i));
                    let wanted = unit.to_rad(v);
                    let clamped = wanted.clamp(lo, hi);
                    if (clamped - wanted).abs() > 1e-12 {
                        let side = if wanted > hi { "upper" } else { "lower" };
                        ctx.error(format!(
                            "{name}: {} is beyond its {side} limit {}; clamped to the limit",
                            unit.fmt(wanted),
                            unit.fmt(clamped)
                        ));
                    }
                    self.goto[i] = clamped;
                }
                EntryEvent::Invalid(why) => {
                    ctx.error(format!("{name}: {why}"));
                    refused = Some(name);
                }
            }
        }
        ui.horizontal(|ui| {
            if ui.button("Current").on_hover_text("Copy the current pose into the entries").clicked() {
                self.goto = ctx.robot.q.clone();
            }
            if ui.button("Park").on_hover_text("The commander's park pose").clicked() && ctx.model.is_parol6 {
                self.goto = parol6_core::parol6::park_rad().to_vec();
            }
            let go = ui.button("Go").on_hover_text("Profiled move to this pose").clicked();
            if let (true, Some(name)) = (go, &refused) {
                ctx.error(format!("Go not sent: {name} holds no number; type it again"));
            } else if go {
                match ctx.model.limits.enforce(&self.goto, parol6_core::LimitPolicy::Reject) {
                    Ok(goal) => ctx.move_to(goal),
                    Err(e) => ctx.error(format!("pose refused: {e}")),
                }
            }
        });
    }
}
