//! Right panel: a Cartesian TCP target (XYZ in mm + RPY) solved by IK; the operator picks the
//! configuration (previewed as the ghost arm; the nearest the current joints is offered first,
//! as a joint move to a pose in a program takes it) and runs a profiled move to it.

use eframe::egui;

use crate::palette;
use parol6_core::ik::{self, IkSolution};
use parol6_core::kinematics::iso_from_xyz_rpy;

use super::angle_text::in_unit;
use super::entry::{self, EntryEvent};
use super::fixed_box;
use super::{AngleUnit, Panel, PanelContext};

/// The Cartesian target panel.
#[derive(Debug, Default)]
pub struct CartesianTargetPanel {
    /// Target position, mm.
    xyz_mm: [f64; 3],
    /// Target RPY, rad.
    rpy: [f64; 3],
    /// True once the entries hold a target (initialised from the TCP on first show).
    initialised: bool,
    /// Result of the last solve.
    result: Option<Result<Vec<IkSolution>, String>>,
    /// Chosen solution index into the last result.
    selected: usize,
    /// Label of the chosen branch, kept across re-solves.
    selected_label: Option<String>,
    /// Entries changed since the last solve.
    dirty: bool,
    /// The joints the last solve was seeded with (the distances shown are to these).
    solved_seed: Vec<f64>,
}

/// Text rows the IK result keeps, whatever it says: the header and about two solutions (each
/// may take two rows in a narrow column); more scroll inside.
const RESULT_ROWS: usize = 5;

/// Largest orientation angle the target takes, rad (one turn, ±360°): beyond it a typed
/// angle is refused, not wrapped (45.5 rad was a slip, not 7 turns).
const MAX_TARGET_ANGLE_RAD: f64 = std::f64::consts::TAU;

/// Largest position coordinate the target takes, mm: several times any PAROL6 reach (about
/// 0.45 m), so that what lies beyond it is a slip ("1e9"), refused with the range, not a pose
/// the IK then calls unreachable while the field shows a number cut off.
const MAX_TARGET_POSITION_MM: f64 = 2000.0;

/// The refusal of an angle `v` (in `unit`) typed into the target's field `name` beyond a turn.
fn beyond_a_turn(name: &str, v: f64, unit: AngleUnit) -> String {
    let typed = unit.fmt(unit.to_rad(v));
    let turn = unit.fmt(MAX_TARGET_ANGLE_RAD);
    // radians chosen and a number of degrees typed: say how to type degrees (as "deg": the
    // notices show every "°" value in radians)
    let hint = if unit == AngleUnit::Rad { format!("; for degrees type {v}deg") } else { String::new() };
    format!("target {name}: {typed} is beyond one turn (±{turn}){hint}; the target stays as it was")
}

/// The note when the target's angles, after `name` was typed as `typed` (rad; `angles`: what
/// was asked, `shown`: what the fields now show for the same rotation, each in its
/// convention's range) read otherwise than typed; `None` when they read as typed.
fn respelled(
    name: &str,
    typed: f64,
    angles: &[f64; 3],
    shown: &[f64; 3],
    labels: &[&str; 3],
    unit: AngleUnit,
) -> Option<String> {
    let changed: Vec<String> = (0..3)
        .filter(|&j| unit.fmt(angles[j]) != unit.fmt(shown[j]))
        .map(|j| format!("{} {}", labels[j], unit.fmt(shown[j])))
        .collect();
    (!changed.is_empty())
        .then(|| format!("target {name} {}: the same rotation is shown as {}", unit.fmt(typed), changed.join(", ")))
}

fn solution_label(s: &IkSolution) -> String {
    s.branch.map(|b| b.label()).unwrap_or_else(|| "numeric".to_string())
}

impl CartesianTargetPanel {
    fn load_from_tcp(&mut self, ctx: &PanelContext<'_>) {
        // Full precision: the entries only display rounded values. Rounding the target itself
        // would move it off the current pose, and at a wrist singularity (standby) a tiny
        // orientation change splits J4/J6 arbitrarily.
        self.xyz_mm = ctx.robot.tcp.position_m.map(|v| v * 1000.0);
        self.rpy = ctx.robot.tcp.rpy_rad;
        // Offer the branch nearest the current joints, not the one picked for an older target.
        self.selected_label = None;
        self.initialised = true;
        self.dirty = true;
    }

    fn solve(&mut self, ctx: &PanelContext<'_>) {
        self.dirty = false;
        self.solved_seed = ctx.robot.q.clone();
        let target = iso_from_xyz_rpy(self.xyz_mm.map(|v| v / 1000.0), self.rpy);
        let res = ik::solve(ctx.model, &target, &ctx.robot.q)
            .map(|sols| prefer_seed(ctx.model, &target, &ctx.robot.q, sols))
            .map_err(|e| e.to_string());
        self.selected = match (&res, &self.selected_label) {
            (Ok(sols), Some(label)) => sols.iter().position(|s| &solution_label(s) == label).unwrap_or(0),
            _ => 0,
        };
        self.result = Some(res);
    }

    /// The solutions of the last solve, nearest the current joints first.
    pub fn solutions(&self) -> Option<&[IkSolution]> {
        match &self.result {
            Some(Ok(s)) => Some(s),
            _ => None,
        }
    }

    /// The chosen solution, if any.
    fn chosen(&self) -> Option<&IkSolution> {
        match &self.result {
            Some(Ok(s)) => s.get(self.selected),
            _ => None,
        }
    }
}

/// Orientation and position tolerance for "the same pose" when re-splitting J4/J6 (rad, m).
const SAME_POSE_TOL: f64 = 1e-6;
/// |sin J5| below this is treated as a wrist singularity (J4 and J6 nearly coaxial).
const WRIST_SINGULAR_SIN: f64 = 1e-3;

/// Puts the solutions nearest `seed` (the current joints) first, fixing what the closed-form
/// split gets arbitrary near a wrist singularity:
///
/// * At J5 ≈ 0 only J4 + J6 is defined by the pose; the solver's split follows rounding noise
///   in the target and can twist J4 and J6 by tens of degrees (or fall outside J4's limits so
///   that only the flipped branch is left). Each such solution is re-split to keep J4 at the
///   seed, kept only if it still reaches the target within `SAME_POSE_TOL`.
/// * When the seed itself reaches the target (the target was loaded from the TCP), it is the
///   nearest solution: it replaces the solution nearest to it (keeping that branch's name).
///
/// Then sorted by distance to the seed, duplicates dropped.
pub fn prefer_seed(
    model: &parol6_core::RobotModel,
    target: &parol6_core::na::Isometry3<f64>,
    seed: &[f64],
    sols: Vec<IkSolution>,
) -> Vec<IkSolution> {
    let distance = |q: &[f64]| q.iter().zip(seed).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
    let reaches = |q: &[f64], tol: f64| {
        model.limits.contains(q) && {
            let (ep, er) = ik::pose_error(&model.tcp_isometry(q), target);
            ep <= tol && er <= tol
        }
    };
    let mut out: Vec<IkSolution> = sols
        .into_iter()
        .map(|mut s| {
            if model.is_parol6
                && s.joints_rad.len() == 6
                && seed.len() == 6
                && s.joints_rad[4].sin().abs() < WRIST_SINGULAR_SIN
            {
                let q = &s.joints_rad;
                // J5 ≈ 0: J4 + J6 fixed; J5 ≈ ±180°: J6 − J4 fixed.
                let shift = q[3] - seed[3];
                let j6 = if q[4].cos() > 0.0 { q[5] + shift } else { q[5] - shift };
                let j6 = nearest_turn(j6, seed[5], model.limits.get(5).map(|l| (l.min, l.max)));
                let mut resplit = q.clone();
                resplit[3] = seed[3];
                resplit[5] = j6;
                if distance(&resplit) < distance(q) && reaches(&resplit, SAME_POSE_TOL) {
                    s.joints_rad = resplit;
                }
            }
            s.distance_to_seed = distance(&s.joints_rad);
            s
        })
        .collect();
    if seed.len() == model.dof()
        && reaches(seed, 1e-9)
        && let Some(nearest) = out.iter_mut().min_by(|a, b| a.distance_to_seed.total_cmp(&b.distance_to_seed))
    {
        nearest.joints_rad = seed.to_vec();
        nearest.distance_to_seed = 0.0;
    }
    out.sort_by(|a, b| a.distance_to_seed.total_cmp(&b.distance_to_seed));
    let mut unique: Vec<IkSolution> = Vec::with_capacity(out.len());
    for s in out {
        let dup =
            unique.iter().any(|u| u.joints_rad.iter().zip(&s.joints_rad).all(|(a, b)| (a - b).abs() < SAME_POSE_TOL));
        if !dup {
            unique.push(s);
        }
    }
    unique
}

/// `v + 2πk` nearest `near`, inside `range` when one fits (else `v` unchanged).
fn nearest_turn(v: f64, near: f64, range: Option<(f64, f64)>) -> f64 {
    let tau = std::f64::consts::TAU;
    (-3..=3)
        .map(|k| v + tau * f64::from(k))
        .filter(|c| range.is_none_or(|(lo, hi)| *c >= lo - 1e-9 && *c <= hi + 1e-9))
        .min_by(|a, b| (a - near).abs().total_cmp(&(b - near).abs()))
        .unwrap_or(v)
}

impl Panel for CartesianTargetPanel {
    fn title(&self) -> &'static str {
        "Cartesian target"
    }

    fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        let r = ui.vertical(|ui| self.body(ui, ctx));
        // The chosen branch is previewed as the ghost while the pointer is over this panel.
        if let Some(s) = r.inner
            && ctx.settings.view.show_ghost
            && r.response.contains_pointer()
            && s.joints_rad.iter().zip(&ctx.robot.q).any(|(a, b)| (a - b).abs() > 1e-3)
        {
            *ctx.preview = Some(s.joints_rad);
        }
    }
}

impl CartesianTargetPanel {
    /// The panel's widgets; returns the chosen solution.
    fn body(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) -> Option<IkSolution> {
        if !self.initialised {
            self.load_from_tcp(ctx);
        }
        let unit = ctx.settings.unit;
        ui.heading(Panel::title(self));
        let mut events = Vec::new();
        let shown = ctx.settings.tcp_readout_rad(self.rpy);
        let labels = ctx.settings.angle_labels();
        // the position's column first, then the orientation's: Tab goes X, Y, Z, Roll, Pitch,
        // Yaw (egui's Tab follows the order the fields are added; one grid went row by row)
        ui.horizontal(|ui| {
            egui::Grid::new("cart_target_xyz").num_columns(2).spacing([6.0, 2.0]).show(ui, |ui| {
                for (k, xyz) in ["X", "Y", "Z"].into_iter().enumerate() {
                    ui.label(xyz);
                    let (_, e) = entry::numeric_entry(ui, &format!("target {xyz}"), self.xyz_mm[k], 2, 70.0, "mm");
                    events.push((k, e));
                    ui.end_row();
                }
            });
            egui::Grid::new("cart_target_rpy").num_columns(2).spacing([6.0, 2.0]).show(ui, |ui| {
                for (k, rpy) in labels.into_iter().enumerate() {
                    ui.label(rpy).on_hover_text(ctx.settings.readout_angle_hover());
                    let (_, e) = entry::numeric_entry(
                        ui,
                        &format!("target {rpy}"),
                        unit.from_rad(shown[k]),
                        unit.decimals(),
                        70.0,
                        unit.suffix().trim(),
                    );
                    events.push((k + 3, e));
                    ui.end_row();
                }
            });
        });
        // a field refused in this frame (left by the click on Move to target) holds back the
        // move: it went to the last accepted target (trial 30 D1)
        let mut field_refused: Option<String> = None;
        for (k, event) in events {
            let field = if k < 3 { ["X", "Y", "Z"][k] } else { labels[k - 3] };
            match event {
                Some(EntryEvent::Committed(v)) if k < 3 => {
                    let name = format!("target {field}");
                    match entry::in_range(&name, v, (-MAX_TARGET_POSITION_MM, MAX_TARGET_POSITION_MM), "mm", false) {
                        Ok(v) => self.xyz_mm[k] = v,
                        Err(e) => {
                            ctx.error(format!("{e}; the target stays as it was"));
                            field_refused.get_or_insert_with(|| format!("target {field}"));
                            continue;
                        }
                    }
                }
                Some(EntryEvent::Committed(v)) => {
                    let name = labels[k - 3];
                    let mut angles = ctx.settings.tcp_readout_rad(self.rpy);
                    let typed = unit.to_rad(v);
                    if typed.abs() > MAX_TARGET_ANGLE_RAD + 1e-9 {
                        ctx.error(beyond_a_turn(name, v, unit));
                        field_refused.get_or_insert_with(|| format!("target {field}"));
                        continue;
                    }
                    angles[k - 3] = typed;
                    self.rpy = ctx.settings.rpy_from_shown_rad(angles);
                    // the fields show the same rotation in the convention's ranges: a typed angle
                    // shown otherwise (270° as −90°, a pitch beyond 90°) is said, never silent
                    let shown = ctx.settings.tcp_readout_rad(self.rpy);
                    if let Some(note) = respelled(name, typed, &angles, &shown, &labels, unit) {
                        ctx.info(note);
                    }
                }
                Some(EntryEvent::Invalid(why)) => {
                    ctx.error(format!("target {field}: {why}"));
                    field_refused.get_or_insert_with(|| format!("target {field}"));
                    continue;
                }
                None => continue,
            }
            self.dirty = true;
        }
        // The closed-form PAROL6 solver takes microseconds: solve as the entries change.
        // The branches are ordered by distance to the current joints: once the arm has moved
        // and stopped, order them again. Solved before *Move to target* is drawn: a value typed
        // and then left by a click on *Move to target* is the one moved to.
        let seed_moved = !ctx.robot.moving
            && self.result.is_some()
            && (self.solved_seed.len() != ctx.robot.q.len()
                || self.solved_seed.iter().zip(&ctx.robot.q).any(|(a, b)| (a - b).abs() > 1e-6));
        if (self.dirty || seed_moved) && ctx.model.is_parol6 {
            self.solve(ctx);
        }
        // *Move to target* in the row with the panel's other buttons, above the solutions: at
        // 1280×800 it sat under the status bar below them until the column was scrolled (trial13).
        ui.horizontal(|ui| {
            if ui.button("From TCP").on_hover_text("Load the current TCP pose").clicked() {
                self.load_from_tcp(ctx);
                if ctx.model.is_parol6 {
                    self.solve(ctx);
                }
            }
            if ui.button("Solve IK").clicked() {
                self.solve(ctx);
            }
            let chosen = self.chosen().cloned();
            let refused = ctx.motion_refused();
            let go = ui.add_enabled(chosen.is_some() && refused.is_none(), egui::Button::new("Move to target"));
            let go = match refused {
                Some(why) => go.on_disabled_hover_text(why),
                None => go,
            };
            let go = go.on_hover_text("Profiled joint move to the configuration chosen below").clicked();
            if go && let Some(field) = &field_refused {
                ctx.error(format!("Move to target not sent: {field} holds no valid value"));
            } else if go && let Some(s) = &chosen {
                ctx.move_to(s.joints_rad.clone());
            }
        });

        // The result has a fixed height (more solutions scroll inside): a typed value changes it
        // (two solutions, one, a "No solution" of three lines), and a height that followed it
        // moved the fields above under the pointer in a column scrolled to its end (trial9).
        let rows = RESULT_ROWS as f32;
        let result_h = rows * ui.spacing().interact_size.y + (rows - 1.0) * ui.spacing().item_spacing.y;
        fixed_box::fixed_height(ui, "cartesian-target-result", result_h, |ui| match &self.result {
            None => {
                ui.weak("Edit the target or press Solve IK.");
            }
            Some(Err(e)) => {
                ui.colored_label(palette::rgb(palette::ERROR_TEXT), format!("No solution: {}", in_unit(e, unit)));
            }
            Some(Ok(sols)) => {
                ui.label(format!(
                    "{} within the limits; pick a configuration (nearest first):",
                    parol6_core::plural::count(sols.len(), "solution")
                ));
                let mut picked = None;
                for (i, s) in sols.iter().enumerate() {
                    let text = format!(
                        "{}  Δ{}{}{}",
                        solution_label(s),
                        unit.fmt(s.distance_to_seed),
                        if s.distance_to_seed < SAME_POSE_TOL { "  (current joints)" } else { "" },
                        if s.singular { "  (target singular)" } else { "" }
                    );
                    let hover = s.joints_rad.iter().map(|v| unit.fmt(*v)).collect::<Vec<_>>().join(", ");
                    if ui.selectable_label(self.selected == i, text).on_hover_text(hover).clicked() {
                        picked = Some(i);
                    }
                }
                if let Some(i) = picked {
                    self.selected = i;
                    self.selected_label = sols.get(i).map(solution_label);
                }
            }
        });
        self.chosen().cloned()
    }
}
