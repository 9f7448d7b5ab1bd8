//! Left panel: per joint a slider, numeric entry, limit LED (with predicted time to limit) and a
//! protection bar; a banner naming the joint nearest its limit; HOME / STOP; "go to joint pose".

use eframe::egui;
use parol6_core::limits::{JointLimit, LimitZone, ZoneThresholds};

use parol6_core::motion::MotionCommand;

use super::{AngleUnit, Panel, PanelContext, ProfileKindSetting, zone_color};

/// Slider range used for a joint without finite limits (rad).
const UNBOUNDED_RANGE_RAD: f64 = std::f64::consts::PI;
/// Time-to-limit values above this are not shown (s).
const TTL_SHOW_MAX_S: f64 = 10.0;

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
            self.edit = if ctx.robot.target_q.len() == n { ctx.robot.target_q.clone() } else { ctx.robot.q.clone() };
            self.edit.resize(n, 0.0);
        }
        if self.goto.len() != n {
            self.goto = ctx.robot.q.clone();
            self.goto.resize(n, 0.0);
        }
    }

    fn banner(ui: &mut egui::Ui, ctx: &PanelContext<'_>) {
        let Some((i, report)) = ctx.robot.worst_zone() else {
            return;
        };
        let unit = ctx.settings.unit;
        let name = ctx.model.joints.get(i).map(|j| j.name.as_str()).unwrap_or("?");
        let q = ctx.robot.q.get(i).copied().unwrap_or(0.0);
        let mut text = match ctx.model.limits.get(i) {
            Some(l) if l.is_bounded() => {
                let (side, left) = if q - l.min < l.max - q { ("lower", q - l.min) } else { ("upper", l.max - q) };
                format!("{name} {}: {} to its {side} limit", report.zone.label(), unit.fmt(left.max(0.0)))
            }
            _ => format!("{name} {}", report.zone.label()),
        };
        if let Some(t) = report.time_to_limit_s.filter(|t| *t < TTL_SHOW_MAX_S) {
            text.push_str(&format!(", reached in {t:.1} s at this speed"));
        }
        let color = zone_color(report.zone);
        egui::Frame::new()
            .fill(color.gamma_multiply(0.25))
            .stroke(egui::Stroke::new(1.0, color))
            .inner_margin(egui::Margin::same(6))
            .corner_radius(4.0)
            .show(ui, |ui| {
                ui.set_width(ui.available_width());
                ui.label(egui::RichText::new(text).strong());
            });
    }

    fn joint_row(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>, i: usize) {
        let unit = ctx.settings.unit;
        let name = ctx.model.joints.get(i).map(|j| j.name.clone()).unwrap_or_else(|| format!("J{}", i + 1));
        let limit = ctx.model.limits.get(i).cloned();
        let (lo, hi) = slider_range(limit.as_ref());
        let report = ctx.robot.zones.get(i).copied();
        let zone = report.map(|r| r.zone).unwrap_or(LimitZone::Safe);
        let q = ctx.robot.q.get(i).copied().unwrap_or(0.0);
        let qd = ctx.robot.qd.get(i).copied().unwrap_or(0.0);

        let mut changed = None;
        ui.horizontal(|ui| {
            let mut tip = format!("{name}: {}", zone.label());
            let ttl = report.and_then(|r| r.time_to_limit_s).filter(|t| *t < TTL_SHOW_MAX_S && qd.abs() > 1e-4);
            if let Some(t) = ttl {
                tip.push_str(&format!(" — limit in {t:.2} s"));
            }
            super::led(ui, zone_color(zone), tip);
            ui.label(egui::RichText::new(&name).strong().monospace());
            let mut v = unit.from_rad(self.edit[i]);
            let (dlo, dhi) = (unit.from_rad(lo), unit.from_rad(hi));
            let entry_w = 78.0;
            ui.spacing_mut().slider_width = (ui.available_width() - entry_w - 8.0).max(60.0);
            let s =
                ui.add(egui::Slider::new(&mut v, dlo..=dhi).show_value(false).clamping(egui::SliderClamping::Always));
            let d = ui.add_sized(
                [entry_w, 18.0],
                egui::DragValue::new(&mut v)
                    .range(dlo..=dhi)
                    .speed(if unit == AngleUnit::Deg { 0.2 } else { 0.004 })
                    .suffix(unit.suffix())
                    .max_decimals(unit.decimals()),
            );
            if s.dragged() || s.has_focus() || d.dragged() || d.has_focus() {
                self.editing = true;
            }
            if s.changed() || d.changed() {
                changed = Some(unit.to_rad(v));
            }
        });
        if let Some(v) = changed {
            self.set_joint(i, v, ctx);
        }
        // numeric text from the readout state (see `PanelContext::readout`)
        let q_text = ctx.readout.q.get(i).copied().unwrap_or(q);
        let qd_text = ctx.readout.qd.get(i).copied().unwrap_or(qd);
        let report_text = ctx.readout.zones.get(i).copied();
        ui.horizontal(|ui| {
            ui.add_space(20.0);
            let w = (ui.available_width() - 150.0).max(60.0);
            protection_bar(ui, w, limit.as_ref(), q, self.edit[i]);
            ui.label(egui::RichText::new(unit.fmt(q_text)).monospace().small()).on_hover_text("measured position");
            if let Some(t) =
                report_text.and_then(|r| r.time_to_limit_s).filter(|t| *t < TTL_SHOW_MAX_S && qd_text.abs() > 1e-4)
            {
                ui.label(egui::RichText::new(format!("limit in {t:.1} s")).small().color(zone_color(zone)))
                    .on_hover_text("predicted time to reach the limit at the current speed");
            }
        });
    }
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

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        self.sync(ctx);
        self.editing = false;
        ui.horizontal(|ui| {
            ui.heading(self.title());
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                ui.selectable_value(&mut ctx.settings.unit, AngleUnit::Rad, "rad");
                ui.selectable_value(&mut ctx.settings.unit, AngleUnit::Deg, "deg");
            });
        });
        Self::banner(ui, ctx);
        ui.add_space(4.0);
        for i in 0..self.edit.len() {
            self.joint_row(ui, ctx, i);
            ui.add_space(2.0);
        }
        ui.separator();
        ui.horizontal(|ui| {
            let home = egui::Button::new(egui::RichText::new("HOME").strong()).min_size(egui::vec2(90.0, 28.0));
            if ui.add(home).on_hover_text("Profiled move to the standby pose (H)").clicked() {
                ctx.home();
            }
            let stop = egui::Button::new(egui::RichText::new("STOP").strong().color(egui::Color32::WHITE))
                .fill(egui::Color32::from_rgb(170, 30, 30))
                .min_size(egui::vec2(90.0, 28.0));
            if ui.add(stop).on_hover_text("Stop now (Esc)").clicked() {
                ctx.stop();
            }
        });
        ui.horizontal(|ui| {
            ui.label("Speed");
            let mut pct = ctx.settings.speed_fraction * 100.0;
            if ui.add(egui::Slider::new(&mut pct, 1.0..=100.0).suffix(" %").max_decimals(0)).changed() {
                ctx.settings.speed_fraction = (pct / 100.0).clamp(0.01, 1.0);
            }
        });
        ui.horizontal(|ui| {
            ui.label("Profile");
            for k in [ProfileKindSetting::Trapezoidal, ProfileKindSetting::JerkLimited] {
                ui.selectable_value(&mut ctx.settings.profile, k, k.label());
            }
        });
        ui.separator();
        ui.label(egui::RichText::new("Go to joint pose").strong());
        let unit = ctx.settings.unit;
        ui.horizontal_wrapped(|ui| {
            for i in 0..self.goto.len() {
                let (lo, hi) = slider_range(ctx.model.limits.get(i));
                let mut v = unit.from_rad(self.goto[i]);
                let r = ui.add(
                    egui::DragValue::new(&mut v)
                        .range(unit.from_rad(lo)..=unit.from_rad(hi))
                        .speed(if unit == AngleUnit::Deg { 0.2 } else { 0.004 })
                        .suffix(unit.suffix())
                        .max_decimals(unit.decimals()),
                );
                if r.changed() {
                    self.goto[i] = unit.to_rad(v);
                }
            }
        });
        ui.horizontal(|ui| {
            if ui.button("Current").on_hover_text("Copy the current pose into the entries").clicked() {
                self.goto = ctx.robot.q.clone();
            }
            if ui.button("Park").on_hover_text("The commander's park pose").clicked() && ctx.model.is_parol6 {
                self.goto = parol6_core::parol6::park_rad().to_vec();
            }
            if ui.button("Go").on_hover_text("Profiled move to this pose").clicked() {
                match ctx.model.limits.enforce(&self.goto, parol6_core::LimitPolicy::Reject) {
                    Ok(goal) => ctx.move_to(goal),
                    Err(e) => ctx.error(format!("pose refused: {e}")),
                }
            }
        });
    }
}
