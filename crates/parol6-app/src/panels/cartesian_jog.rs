//! Right panel: Cartesian jog of the TCP along / about the axes of the world or tool frame,
//! on the simulation or the robot (the same [`MotionCommand`]s).
//!
//! Hold mode: hold a −/+ button (or its key) and the TCP moves until released, the dead-man
//! lapses, or it reaches the stop the core planned at jog start (a joint limit, the workspace
//! edge, a singularity, a collision in the simulation), which the panel names. Step mode: each
//! click moves exactly the typed increment (mm, or degrees for rotations).
//!
//! Keys (the table in [`super::shortcuts`]; never while a field, menu or popup has the keyboard,
//! nor with Ctrl / Alt / Cmd): A / D = −X / +X, S / W = −Y / +Y, Q / E = −Z / +Z; with Shift
//! the same keys turn about the axis (−Rx / +Rx …).

use std::sync::Arc;

use eframe::egui;
use parol6_core::collision::{CollisionGuard, FloorGuard};
use parol6_core::motion::cartesian_jog::{CartesianJogPlan, JogObstacleCheck, jog_speed};
use parol6_core::motion::{CartesianAxis, JogFrame, JogKinematics, MotionCaps, MotionCommand};

use super::angle_text::in_unit;
use super::entry::{self, EntryEvent};
use super::fixed_box;
use super::shortcuts::{self, Action};
use super::{AngleUnit, AppCommand, Panel, PanelContext};
use crate::app::remembered::CartesianJogSetting;
use crate::palette;

/// The step increments an operator may type, mm and degrees (a step is a jog: small, and
/// positive; the button says which way).
pub const STEP_MM_RANGE: (f64, f64) = (0.01, 100.0);
/// See [`STEP_MM_RANGE`].
pub const STEP_DEG_RANGE: (f64, f64) = (0.01, 90.0);

/// A typed increment inside `range`, or why not.
fn step_in_range(ev: EntryEvent, (lo, hi): (f64, f64), unit: &str) -> Result<f64, String> {
    match ev {
        EntryEvent::Committed(v) if (lo..=hi).contains(&v) => Ok(v),
        EntryEvent::Committed(v) => Err(format!("{v} is outside {lo}–{hi} {unit}")),
        EntryEvent::Invalid(e) => Err(e),
    }
}

/// What the panel knows about the jog being held, or the last one.
#[derive(Debug)]
struct JogView {
    frame: JogFrame,
    axis: CartesianAxis,
    dir: i8,
    /// The plan from where the jog started (the backend plans the same from the same pose).
    plan: Result<CartesianJogPlan, String>,
    /// TCP at jog start (position m, rotation).
    start: parol6_core::na::Isometry3<f64>,
    /// How far the jog moved (m or rad), fixed once the arm came to rest after the release: a
    /// later motion does not change what this jog did.
    moved: Option<f64>,
    /// `AppState::stops` when the jog started: a STOP or E-STOP since ended it.
    stops: u64,
    /// A STOP or E-STOP ended the jog, fixed with `moved` (a later STOP is not this jog's).
    ended_by_stop: Option<bool>,
    /// `AppState::other_motions` once the jog came to rest: another motion since (a program,
    /// HOME, a joint move) empties the line (trial 21 m1, trial 22 m4: it stayed for good).
    other_motions_at_rest: Option<u64>,
}

/// The last clicks of Step mode (the same step in a row): what the line under the buttons says.
#[derive(Debug, Clone, Copy)]
struct StepView {
    frame: JogFrame,
    axis: CartesianAxis,
    /// Signed distance, m or rad.
    distance: f64,
    /// Clicks in a row of this same step.
    count: usize,
    /// TCP (commanded) where the row of steps started.
    start: parol6_core::na::Isometry3<f64>,
    /// When the last click was.
    clicked: std::time::Instant,
    /// The arm has moved since that click.
    seen_moving: bool,
    /// `AppState::other_motions` at the first click: another motion (a program run, HOME, a
    /// joint move, a replay) ends the row.
    other_motions: u64,
}

/// Time after a click after which an arm that has not moved has not taken the step (refused).
const STEP_SETTLE: std::time::Duration = std::time::Duration::from_millis(300);

/// TCP travel, m, and turn, rad, away from where a jog was refused after which the refusal is
/// no longer shown (it described the pose it was asked at).
const STALE_REFUSAL_M: f64 = 0.5e-3;
const STALE_REFUSAL_RAD: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// Text rows of the jog's message: its height never changes, so nothing below it moves.
const MESSAGE_LINES: usize = 2;

/// A held jog whose planned speed stays below this fraction of the asked speed for its first
/// [`SLOW_JOG_WINDOW_S`] (and that lasts longer: not a short hop to its stop) says it is slow and why.
const SLOW_JOG_FRACTION: f64 = 0.5;

/// The start of a held jog judged for [`SLOW_JOG_FRACTION`], s.
const SLOW_JOG_WINDOW_S: f64 = 2.0;

/// The Cartesian jog panel.
#[derive(Debug)]
pub struct CartesianJogPanel {
    frame: JogFrame,
    step_mode: bool,
    /// Step increment, mm.
    step_mm: f64,
    /// Step increment, degrees.
    step_deg: f64,
    held: Option<(CartesianAxis, i8)>,
    /// The hold jog being held, or the last one (none after a step).
    view: Option<JogView>,
    /// The last step (none after a hold jog).
    stepped: Option<StepView>,
    guard: Option<Arc<CollisionGuard>>,
    caps: Option<MotionCaps>,
}

impl Default for CartesianJogPanel {
    fn default() -> Self {
        Self {
            frame: JogFrame::World,
            step_mode: false,
            step_mm: 1.0,
            step_deg: 1.0,
            held: None,
            view: None,
            stepped: None,
            guard: None,
            caps: None,
        }
    }
}

fn frame_name(f: JogFrame) -> &'static str {
    match f {
        JogFrame::World => "world",
        JogFrame::Tool => "tool",
    }
}

/// `v` of an axis in display units: mm for translations, the angle unit for rotations.
fn display(axis: CartesianAxis, v: f64, unit: AngleUnit) -> String {
    if axis.is_rotation() { unit.fmt(v) } else { format!("{} mm", entry::fmt_fixed(v * 1000.0, 2)) }
}

impl CartesianJogPanel {
    /// The frame the buttons jog in.
    pub fn frame(&self) -> JogFrame {
        self.frame
    }

    /// The increments of step mode: mm and degrees.
    pub fn step_increments(&self) -> (f64, f64) {
        (self.step_mm, self.step_deg)
    }

    /// True in step mode (each click one increment), false in hold mode.
    pub fn step_mode(&self) -> bool {
        self.step_mode
    }

    /// The frame, mode and increments, as the settings keep them.
    pub fn remembered(&self) -> CartesianJogSetting {
        CartesianJogSetting {
            frame: self.frame,
            step_mode: self.step_mode,
            step_mm: self.step_mm,
            step_deg: self.step_deg,
        }
    }

    /// Takes the frame, mode and increments remembered from the last session (checked by the
    /// caller: `CartesianJogSetting::checked`).
    pub fn restore(&mut self, s: CartesianJogSetting) {
        (self.frame, self.step_mode, self.step_mm, self.step_deg) = (s.frame, s.step_mode, s.step_mm, s.step_deg);
    }

    /// Plans the jog the backend is about to run, to show where and why it will stop.
    fn preview(&mut self, ctx: &PanelContext<'_>, axis: CartesianAxis, dir: i8) {
        let q = if ctx.robot.commanded.q.len() == ctx.model.dof() { &ctx.robot.commanded.q } else { &ctx.robot.q };
        let caps = self.caps.get_or_insert_with(|| MotionCaps::of(ctx.model)).clone();
        // the simulation stops before collisions, the robot before the floor (and at limits and
        // singularities, as both)
        let g = self.guard.get_or_insert_with(|| Arc::new(CollisionGuard::new(ctx.model)));
        let obstacles: Arc<dyn JogObstacleCheck> = if ctx.app.link.is_none() {
            Arc::clone(g) as Arc<dyn JogObstacleCheck>
        } else {
            Arc::new(FloorGuard(CollisionGuard::clone(g)))
        };
        let obstacles = Some(obstacles);
        let kin = JogKinematics { model: Arc::new(ctx.model.clone()), obstacles };
        let fraction = f64::from(dir) * ctx.settings.cartesian_jog_fraction;
        let plan = CartesianJogPlan::plan(&kin, &caps, q, self.frame, axis, fraction).map_err(|e| e.to_string());
        self.view = Some(JogView {
            frame: self.frame,
            axis,
            dir,
            plan,
            start: ctx.model.tcp_isometry(q),
            moved: None,
            stops: ctx.app.stops,
            ended_by_stop: None,
            other_motions_at_rest: None,
        });
        self.stepped = None;
    }

    fn buttons(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) -> Option<(CartesianAxis, i8)> {
        let mut held = None;
        egui::Grid::new("cartesian_jog_buttons").num_columns(6).spacing([4.0, 2.0]).show(ui, |ui| {
            for row in 0..3 {
                for axis in [CartesianAxis::ALL[row], CartesianAxis::ALL[row + 3]] {
                    ui.label(egui::RichText::new(axis.label()).monospace());
                    for (sign, dir) in [("−", -1i8), ("+", 1i8)] {
                        let name = format!("{sign}{}", axis.label());
                        // click-and-drag: a press held on the button is the button's, not a
                        // drag of the scrolling column around it
                        let b = ui.add(
                            egui::Button::new(&name)
                                .min_size(egui::vec2(40.0, 18.0))
                                .sense(egui::Sense::click_and_drag()),
                        );
                        let b = b.on_hover_text(if self.step_mode {
                            format!("{name}: one step of the typed increment")
                        } else {
                            format!("{name}: hold to jog ({} frame)", frame_name(self.frame))
                        });
                        if self.step_mode {
                            if b.clicked() {
                                self.step(ctx, axis, dir);
                            }
                        } else if b.is_pointer_button_down_on() && b.contains_pointer() {
                            // a dead-man button: dragging the pointer off it ends the jog
                            held = Some((axis, dir));
                        }
                    }
                }
                ui.end_row();
            }
        });
        held
    }

    fn step(&mut self, ctx: &mut PanelContext<'_>, axis: CartesianAxis, dir: i8) {
        let distance =
            f64::from(dir) * if axis.is_rotation() { self.step_deg.to_radians() } else { self.step_mm / 1000.0 };
        ctx.motion(MotionCommand::CartesianStep {
            frame: self.frame,
            axis,
            distance,
            speed_fraction: ctx.settings.cartesian_jog_fraction.clamp(0.01, 1.0),
        });
        // the line says this step, not the last hold jog
        self.view = None;
        let clicked = std::time::Instant::now();
        let same = self.stepped.filter(|l| {
            l.frame == self.frame
                && l.axis == axis
                && l.distance == distance
                && l.other_motions == ctx.app.other_motions
        });
        self.stepped = Some(match same {
            Some(l) => StepView { count: l.count + 1, clicked, seen_moving: false, ..l },
            None => StepView {
                frame: self.frame,
                axis,
                distance,
                count: 1,
                start: ctx.model.tcp_isometry(&ctx.robot.commanded.q),
                clicked,
                seen_moving: false,
                other_motions: ctx.app.other_motions,
            },
        });
    }

    /// The held key, if any (see [`super::shortcuts`]: not while typing or a menu is open, not
    /// with Ctrl / Alt / Cmd, not a key that went down with one of them).
    fn key_held(ui: &egui::Ui) -> Option<(CartesianAxis, i8)> {
        CartesianAxis::ALL
            .into_iter()
            .flat_map(|axis| [(axis, -1i8), (axis, 1i8)])
            .find(|&(axis, dir)| shortcuts::held(ui.ctx(), Action::JogCartesian(axis, dir)))
    }

    /// The jog's message in [`MESSAGE_LINES`] rows (empty before the first jog).
    fn status_ui(&mut self, ui: &mut egui::Ui, ctx: &PanelContext<'_>) {
        let (text, rows) = self.status_text(ctx);
        fixed_box::message_lines(ui, text, rows);
        // a one-row refusal keeps the box's height: the rows left as space
        let row_h = ui.text_style_height(&egui::TextStyle::Body) + ui.spacing().item_spacing.y;
        ui.add_space(row_h * MESSAGE_LINES.saturating_sub(rows) as f32);
    }

    /// The message and its rows (a refusal on one row, cut with "…", whole on hover).
    fn status_text(&mut self, ctx: &PanelContext<'_>) -> (egui::RichText, usize) {
        let held = self.held.is_some();
        // a refusal is about the pose it was asked at: once the arm has moved away (a joint move,
        // HOME, a program) it no longer holds, and the line empties instead of blaming the new pose
        if let Some(v) = &self.view
            && v.plan.is_err()
            && !held
        {
            let now = ctx.model.tcp_isometry(&ctx.robot.commanded.q);
            let moved_m = (now.translation.vector - v.start.translation.vector).norm();
            if moved_m > STALE_REFUSAL_M || now.rotation.angle_to(&v.start.rotation) > STALE_REFUSAL_RAD {
                self.view = None;
            }
        }
        // another motion since the row started (or a replay opened) ends it: the line empties,
        // the next click starts a new row (it compared the TCP after a program run or HOME
        // with where the row started: trial9 m1)
        if self.stepped.is_some_and(|s| s.other_motions != ctx.app.other_motions) || ctx.app.replaying() {
            self.stepped = None;
        }
        if let Some(s) = &mut self.stepped {
            let unit = ctx.settings.unit;
            let dir = if s.distance > 0.0 { "+" } else { "−" };
            let asked = s.distance.abs() * s.count as f64;
            let mut text = format!(
                "{dir}{} ({}) step {}",
                s.axis.label(),
                frame_name(s.frame),
                display(s.axis, s.distance.abs(), unit)
            );
            if s.count > 1 {
                text.push_str(&format!(" ({} steps in a row: {})", s.count, display(s.axis, asked, unit)));
            }
            // at rest: a step refused (or cut short) is said, not claimed
            s.seen_moving |= ctx.robot.moving;
            if !ctx.robot.moving && (s.seen_moving || s.clicked.elapsed() > STEP_SETTLE) {
                let now = ctx.model.tcp_isometry(&ctx.robot.commanded.q);
                let (moved, tolerance) = if s.axis.is_rotation() {
                    (now.rotation.angle_to(&s.start.rotation), 0.01f64.to_radians())
                } else {
                    ((now.translation.vector - s.start.translation.vector).norm(), 0.01e-3)
                };
                if (moved - asked).abs() > tolerance {
                    text.push_str(&format!(": moved {} (see the notices)", display(s.axis, moved, unit)));
                    return (egui::RichText::new(text).color(palette::rgb(palette::WARN_TEXT)), MESSAGE_LINES);
                }
            }
            return (egui::RichText::new(text), MESSAGE_LINES);
        }
        if self.view.as_ref().and_then(|v| v.other_motions_at_rest).is_some_and(|n| n != ctx.app.other_motions) {
            self.view = None;
        }
        let Some(v) = &mut self.view else { return (egui::RichText::new(""), MESSAGE_LINES) };
        let dir = if v.dir > 0 { "+" } else { "−" };
        let what = format!("{dir}{} ({})", v.axis.label(), frame_name(v.frame));
        match &v.plan {
            Err(e) => {
                // one line: the reason without the planner's "cannot jog … frame: " and
                // "singularity: " prefixes (the whole text on hover)
                let why = e.split_once(" frame: ").map_or(e.as_str(), |(_, w)| w);
                let why = why.strip_prefix("singularity: ").unwrap_or(why);
                let text = format!("{what} refused: {}", in_unit(why, ctx.settings.unit));
                (egui::RichText::new(text).color(palette::rgb(palette::ERROR_TEXT)), 1)
            }
            Ok(plan) => {
                let unit = ctx.settings.unit;
                let travel = display(v.axis, plan.travel().abs(), unit);
                if held {
                    let stop = in_unit(&plan.stop_reason().to_string(), unit).into_owned();
                    // trial 25 m3: at the standby wrist the jog crept at 1.5 mm/s while the speed
                    // line said 40.8 mm/s, without a word
                    let asked = jog_speed(v.axis, ctx.settings.cartesian_jog_fraction);
                    let top = plan.top_speed_within(SLOW_JOG_WINDOW_S);
                    if top < SLOW_JOG_FRACTION * asked && plan.duration_s() > SLOW_JOG_WINDOW_S {
                        let top = format!("{}/s", display(v.axis, top, unit));
                        let text = format!(
                            "jogging {what} slowly, {top} at most: near a singular pose (a joint move is \
                             faster); stops after {travel}: {stop}"
                        );
                        return (egui::RichText::new(text).color(palette::rgb(palette::WARN_TEXT)), MESSAGE_LINES);
                    }
                    let text = format!("jogging {what}: stops after {travel} at the latest: {stop}");
                    return (egui::RichText::new(text), MESSAGE_LINES);
                }
                let moved = match v.moved {
                    Some(m) => m,
                    None => {
                        let now = ctx.model.tcp_isometry(&ctx.robot.commanded.q);
                        let m = if v.axis.is_rotation() {
                            now.rotation.angle_to(&v.start.rotation)
                        } else {
                            (now.translation.vector - v.start.translation.vector).norm()
                        };
                        if !ctx.robot.moving {
                            v.moved = Some(m); // at rest after the release: what this jog did
                            v.ended_by_stop = Some(ctx.app.stops != v.stops);
                            v.other_motions_at_rest = Some(ctx.app.other_motions);
                        }
                        m
                    }
                };
                let at_stop = (moved - plan.travel().abs()).abs() < 1e-6;
                let text = if v.ended_by_stop.unwrap_or(ctx.app.stops != v.stops) {
                    let moved = display(v.axis, moved, unit);
                    egui::RichText::new(format!("{what} ended by STOP after {moved}"))
                        .color(palette::rgb(palette::WARN_TEXT))
                } else if at_stop {
                    egui::RichText::new(format!(
                        "{what} stopped after {travel}: {}",
                        in_unit(&plan.stop_reason().to_string(), unit)
                    ))
                    .color(palette::rgb(palette::WARN_TEXT))
                } else {
                    egui::RichText::new(format!("{what} released after {}", display(v.axis, moved, unit)))
                };
                (text, MESSAGE_LINES)
            }
        }
    }
}

impl Panel for CartesianJogPanel {
    fn title(&self) -> &'static str {
        "Cartesian jog"
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        ui.heading(self.title()).on_hover_text(
            "hold a −/+ button, or A/D, S/W, Q/E (Shift: rotations); in Step mode click for one increment",
        );
        ui.horizontal(|ui| {
            ui.label("Frame");
            ui.selectable_value(&mut self.frame, JogFrame::World, "World").on_hover_text("the robot base axes");
            ui.selectable_value(&mut self.frame, JogFrame::Tool, "Tool")
                .on_hover_text("the TCP's own axes (as they are when the jog starts)");
            ui.separator();
            let hold = ui
                .selectable_value(&mut self.step_mode, false, "Hold")
                .on_hover_text("move while a button (or its key) is held");
            let step = ui
                .selectable_value(&mut self.step_mode, true, "Step")
                .on_hover_text("each click moves one increment (the jog keys act in Hold mode only)");
            if hold.changed() || step.changed() {
                // the other mode's last line no longer says what the buttons do
                self.view = None;
                self.stepped = None;
            }
        });
        // the latched E-stop, an open recording, a running program or ISO test refuses every
        // jog: the buttons and keys are off, the hover says why
        let refused = ctx.manual_motion_refused();
        let latched = refused.is_some();
        let buttons = ui.add_enabled_ui(!latched, |ui| self.buttons(ui, ctx));
        buttons.response.on_disabled_hover_text(refused.unwrap_or_default());
        let mut held = buttons.inner;
        if held.is_none() && !self.step_mode && !latched {
            held = Self::key_held(ui);
        }
        ui.horizontal(|ui| {
            ui.label("Speed");
            ui.spacing_mut().slider_width = 80.0;
            let mut pct = ctx.settings.cartesian_jog_fraction * 100.0;
            let (r, refused) = entry::typed_slider(ui, "Jog speed", &mut pct, 1.0..=100.0, (" %", "%"), 0);
            if r.changed() {
                ctx.settings.cartesian_jog_fraction = (pct / 100.0).clamp(0.01, 1.0);
            }
            if let Some(message) = refused {
                ctx.error(message);
            }
            let f = ctx.settings.cartesian_jog_fraction;
            // the turning speed in the chosen angle unit (it stayed in °/s in radians); wraps
            // within the column rather than widen it ("0.3622 rad/s" is longer than "20.75°/s")
            ui.add(
                egui::Label::new(format!(
                    "{:.1} mm/s, {}/s",
                    jog_speed(CartesianAxis::X, f) * 1000.0,
                    ctx.settings.unit.fmt(jog_speed(CartesianAxis::Rx, f))
                ))
                .wrap(),
            );
        });
        ui.horizontal(|ui| {
            ui.label("Increment");
            if let (_, Some(ev)) = entry::numeric_entry(ui, "Step mm", self.step_mm, 2, 56.0, "mm") {
                match step_in_range(ev, STEP_MM_RANGE, "mm") {
                    Ok(v) => self.step_mm = v,
                    Err(e) => ctx.error(format!("Step mm: {e}; the increment stays {:.2} mm", self.step_mm)),
                }
            }
            // the angle increment in the chosen unit, kept in degrees
            let unit = ctx.settings.unit;
            let shown = unit.from_rad(self.step_deg.to_radians());
            let suffix = unit.suffix().trim();
            if let (_, Some(ev)) = entry::numeric_entry(ui, "Step angle", shown, unit.decimals(), 56.0, suffix) {
                let in_unit = |deg: f64| entry::fmt_fixed(unit.from_rad(deg.to_radians()), unit.decimals());
                let range = (in_unit(STEP_DEG_RANGE.0), in_unit(STEP_DEG_RANGE.1));
                let ev = match ev {
                    EntryEvent::Committed(v) => EntryEvent::Committed(unit.to_rad(v).to_degrees()),
                    invalid => invalid,
                };
                match step_in_range(ev, STEP_DEG_RANGE, "°") {
                    Ok(v) => self.step_deg = v,
                    Err(_) if unit == AngleUnit::Rad => ctx.error(format!(
                        "Step angle: outside {}–{} rad; the increment stays {}",
                        range.0,
                        range.1,
                        unit.fmt(self.step_deg.to_radians())
                    )),
                    Err(e) => ctx.error(format!(
                        "Step angle: {e}; the increment stays {}",
                        unit.fmt(self.step_deg.to_radians())
                    )),
                }
            }
        });
        let tcp = ctx.readout.tcp;
        let mm = |k: usize| entry::fmt_fixed(tcp.position_m[k] * 1000.0, 1);
        let shown = ctx.settings.tcp_readout_rad(tcp.rpy_rad);
        let unit = ctx.settings.unit;
        let decimals = if unit == AngleUnit::Rad { 3 } else { 1 };
        let ang = |k: usize| entry::fmt_fixed(unit.from_rad(shown[k]), decimals);
        let [a, b, c] = ctx.settings.angle_labels();
        let (x, y, z, u) = (mm(0), mm(1), mm(2), unit.suffix());
        ui.label(format!("TCP {x}, {y}, {z} mm · {a}/{b}/{c} {}, {}, {}{u}", ang(0), ang(1), ang(2))).on_hover_text(
            format!(
                "TCP position (X, Y, Z) and orientation, {}; the TCP panel shows more digits",
                ctx.settings.readout_angle_hover()
            ),
        );
        if held != self.held
            && let Some((axis, dir)) = held
        {
            self.preview(ctx, axis, dir);
        }
        if held != self.held || held.is_some() {
            // sent every frame while held: the app refreshes the backend's dead-man from it
            let cmd = held.map(|(axis, dir)| (self.frame, axis, f64::from(dir) * ctx.settings.cartesian_jog_fraction));
            ctx.send(AppCommand::CartesianJog(cmd));
        }
        self.held = held;
        self.status_ui(ui, ctx);
    }
}
