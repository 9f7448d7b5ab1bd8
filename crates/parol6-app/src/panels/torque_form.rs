//! The forward-dynamics form of the dynamics panel: a torque profile per joint (constant, a
//! step at a time, a sine), the run time and gravity compensation; Run sends it to the
//! simulation as one [`TorqueRun`], STOP ends it. The form says what is simulated (rigid links,
//! no friction, free or held joints), shows the run's progress and, at its end, its outcome
//! (how far each joint turned, which ended at a limit, or that STOP ended it).

use std::time::{Duration, Instant};

use eframe::egui;
use parol6_core::sim::torque_profile::{MAX_PROFILE_TORQUE_NM, MAX_RUN_S};
use parol6_core::sim::{TorqueProfile, TorqueRun};
use serde::{Deserialize, Serialize};

use super::entry::{EntryEvent, fmt_fixed, in_range, numeric_entry, ranged_entry};
use super::{AppCommand, PanelContext};

/// Shape of one joint's profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum ProfileShape {
    /// One torque throughout.
    Constant,
    /// A torque, then another from a time on.
    Step,
    /// Offset + amplitude · sin(2π t / period).
    Sine,
}

impl ProfileShape {
    const ALL: [ProfileShape; 3] = [ProfileShape::Constant, ProfileShape::Step, ProfileShape::Sine];

    fn label(self) -> &'static str {
        match self {
            ProfileShape::Constant => "constant",
            ProfileShape::Step => "step",
            ProfileShape::Sine => "sine",
        }
    }

    /// Names and units of the second and third numbers (the first is always "torque", N·m:
    /// the constant, the torque before the step, the sine's offset).
    fn extra_fields(self) -> [(&'static str, &'static str); 2] {
        match self {
            ProfileShape::Constant => [("", ""), ("", "")],
            ProfileShape::Step => [("after", "N·m"), ("at", "s")],
            ProfileShape::Sine => [("amplitude", "N·m"), ("period", "s")],
        }
    }
}

/// Shortest sine period a field takes, s.
const MIN_PERIOD_S: f64 = 0.01;

/// The range a field of the form takes, in its unit: a torque up to the core's bound either
/// way, a step time within the longest run, a period from [`MIN_PERIOD_S`] (refused when
/// typed, as the other numeric fields of the window are: "1e9" was taken and shown cut).
fn field_range(name: &str, unit: &str) -> (f64, f64) {
    match (unit, name.ends_with("period")) {
        ("N·m", _) => (-MAX_PROFILE_TORQUE_NM, MAX_PROFILE_TORQUE_NM),
        (_, true) => (MIN_PERIOD_S, MAX_RUN_S),
        _ => (0.0, MAX_RUN_S),
    }
}

/// One joint's row: its shape and three numbers (see `ProfileShape::extra_fields`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct JointRow {
    /// Shape.
    pub shape: ProfileShape,
    /// Torque, N·m (constant / before the step / the sine's offset).
    pub torque_nm: f64,
    /// After the step or the sine's amplitude, N·m.
    pub second: f64,
    /// Step time or sine period, s.
    pub third: f64,
}

impl Default for JointRow {
    fn default() -> Self {
        Self { shape: ProfileShape::Constant, torque_nm: 0.0, second: 0.0, third: 1.0 }
    }
}

impl JointRow {
    /// The core profile of this row.
    pub fn profile(&self) -> TorqueProfile {
        match self.shape {
            ProfileShape::Constant => TorqueProfile::Constant { torque_nm: self.torque_nm },
            ProfileShape::Step => {
                TorqueProfile::Step { before_nm: self.torque_nm, after_nm: self.second, at_s: self.third }
            }
            ProfileShape::Sine => {
                TorqueProfile::Sine { offset_nm: self.torque_nm, amplitude_nm: self.second, period_s: self.third }
            }
        }
    }
}

/// The form's state.
#[derive(Debug, Clone, PartialEq)]
pub struct TorqueForm {
    /// One row per joint.
    pub rows: Vec<JointRow>,
    /// Run time, s.
    pub duration_s: f64,
    /// Add the gravity torques of the current pose (zero torques then hold the arm).
    pub gravity_compensation: bool,
    /// Keep the joints without a torque on their position motors (see [`TorqueRun::hold_others`]).
    pub hold_others: bool,
    /// The run sent last: when, for how long, from which joints.
    active: Option<ActiveRun>,
    /// What the last run did (shown under the form until the next run).
    pub outcome: Option<String>,
    /// The outcome is this refusal of the app's (`PanelContext::torque_run_refused`): it goes
    /// once the reason no longer holds (trial 22 m5: "disconnect the robot first" stayed after
    /// the disconnect).
    refused_for: Option<&'static str>,
}

/// A run the form sent and follows: its outcome is told once the simulation reported it
/// running (`AppState::torque_run`) and no longer does, or that the simulation refused it.
#[derive(Debug, Clone, PartialEq)]
struct ActiveRun {
    started: Instant,
    duration_s: f64,
    start_q: Vec<f64>,
    /// The simulation reported the run under way since it was sent.
    seen_running: bool,
    /// The id of the shown state's last refusal when the run was sent: a newer one before the
    /// run started is the simulation refusing it.
    refusal_before: Option<u64>,
}

/// How long after sending a run the form waits for the simulation to report it under way
/// (beyond the run time: a run shorter than a frame may end before the window sees it).
const START_GRACE: Duration = Duration::from_millis(500);

impl TorqueForm {
    /// All-zero constant torques for `joints` joints, 2 s, gravity compensated.
    pub fn new(joints: usize) -> Self {
        Self {
            rows: vec![JointRow::default(); joints],
            duration_s: 2.0,
            gravity_compensation: true,
            hold_others: false,
            active: None,
            outcome: None,
            refused_for: None,
        }
    }

    /// The run the form describes (checked by the core; the error names joint and field).
    pub fn run(&self) -> Result<TorqueRun, String> {
        let run = TorqueRun {
            joints: self.rows.iter().map(JointRow::profile).collect(),
            duration_s: self.duration_s,
            gravity_compensation: self.gravity_compensation,
            hold_others: self.hold_others,
        };
        run.validate(self.rows.len())?;
        Ok(run)
    }

    /// What the simulation does in a run, in words (shown above the form).
    pub fn explanation(&self) -> String {
        let gravity = if self.gravity_compensation {
            "gravity compensated (the pose's gravity torques added)"
        } else {
            "gravity acting"
        };
        let others = if self.hold_others {
            "joints without a torque held on their motors"
        } else {
            "joints without a torque are free: they swing under the others' motion"
        };
        format!(
            "Simulated: rigid links, {gravity}, no friction, motors off; {others}. Joint limits stay. After the run \
             the motors hold where the arm is."
        )
    }

    /// Draws the form; Run queues [`AppCommand::RunTorques`], Stop queues STOP.
    pub fn ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        ui.label(egui::RichText::new("Forward dynamics (simulation)").strong()).on_hover_text(format!(
            "Drive the simulated joints with these torques (motors off) for the run time, then the motors hold \
             where the arm is. Joint limits stay enforced; STOP ends the run. |torque| ≤ {MAX_PROFILE_TORQUE_NM} \
             N·m, run ≤ {MAX_RUN_S} s."
        ));
        ui.add(egui::Label::new(egui::RichText::new(self.explanation()).weak()).wrap());
        let mut invalid = None;
        egui::Grid::new("torque_form").num_columns(7).spacing([6.0, 2.0]).show(ui, |ui| {
            for (i, row) in self.rows.iter_mut().enumerate() {
                let j = i + 1;
                ui.label(format!("J{j}"));
                egui::ComboBox::from_id_salt(("torque_shape", i)).selected_text(row.shape.label()).width(72.0).show_ui(
                    ui,
                    |ui| {
                        for s in ProfileShape::ALL {
                            ui.selectable_value(&mut row.shape, s, s.label());
                        }
                    },
                );
                let mut field = |ui: &mut egui::Ui, name: String, v: &mut f64, unit: &str| {
                    let range = field_range(&name, unit);
                    match ranged_entry(ui, &name, *v, (3, 56.0), (unit, unit), range).1 {
                        Some(EntryEvent::Committed(x)) => match in_range(&name, x, range, unit, false) {
                            Ok(x) => *v = x,
                            Err(e) => invalid = Some(format!("{e}; it stays {} {unit}", fmt_fixed(*v, 3))),
                        },
                        Some(EntryEvent::Invalid(e)) => invalid = Some(format!("{name}: {e}")),
                        None => {}
                    }
                };
                // every number named beside it: "torque", "after" / "at", "amplitude" / "period"
                let first = if row.shape == ProfileShape::Sine { "offset" } else { "torque" };
                ui.weak(first);
                field(ui, format!("J{j} torque"), &mut row.torque_nm, "N·m");
                let [(n2, u2), (n3, u3)] = row.shape.extra_fields();
                if n2.is_empty() {
                    for _ in 0..4 {
                        ui.label("");
                    }
                } else {
                    ui.weak(n2);
                    field(ui, format!("J{j} {n2}"), &mut row.second, u2);
                    ui.weak(n3);
                    field(ui, format!("J{j} {n3}"), &mut row.third, u3);
                }
                ui.end_row();
            }
        });
        ui.horizontal_wrapped(|ui| {
            match numeric_entry(ui, "Run time", self.duration_s, 2, 56.0, "s").1 {
                // refused when typed, as the other fields' ranges are, not only at Run torques
                Some(EntryEvent::Committed(x)) if x > 0.0 && x <= MAX_RUN_S => self.duration_s = x,
                Some(EntryEvent::Committed(x)) => {
                    invalid = Some(format!(
                        "Run time: {x} s is outside 0–{MAX_RUN_S} s (above 0); it stays {:.2} s",
                        self.duration_s
                    ));
                }
                Some(EntryEvent::Invalid(e)) => invalid = Some(format!("Run time: {e}")),
                None => {}
            }
            ui.checkbox(&mut self.gravity_compensation, "gravity compensation")
                .on_hover_text("add the gravity torques of the current pose at every step");
            ui.checkbox(&mut self.hold_others, "hold other joints")
                .on_hover_text("joints without a torque (constant 0 N·m) stay on their position motors");
        });
        // a row of their own, at the column's left: at 1024 px the centre column is about 350 pt
        // wide, and at the end of the row above they lay under the right panel, out of reach
        ui.horizontal(|ui| {
            if ui.button("Run torques").clicked() {
                // a refused run is said on the form's line too, never reported as a run (trial10)
                self.refused_for = ctx.torque_run_refused();
                match self.refused_for.map(str::to_string).map_or_else(|| self.run(), Err) {
                    Ok(run) => {
                        self.active = Some(ActiveRun {
                            started: Instant::now(),
                            duration_s: run.duration_s,
                            start_q: ctx.robot.q.clone(),
                            seen_running: false,
                            refusal_before: ctx.robot.last_refusal.as_ref().map(|(id, _)| *id),
                        });
                        self.outcome = None;
                        ctx.send(AppCommand::RunTorques(run));
                    }
                    Err(e) => self.refused(ctx, &e),
                }
            }
            if ui.button("Stop torques").clicked() {
                ctx.stop();
            }
        });
        self.progress_ui(ui, ctx);
        if let Some(e) = invalid {
            ctx.error(e);
        }
    }

    /// A run not started: the notice and the form's line say why.
    fn refused(&mut self, ctx: &mut PanelContext<'_>, why: &str) {
        let text = format!("torque run refused: {why}");
        self.outcome = Some(text.clone());
        self.active = None;
        ctx.error(text);
    }

    /// The running run's progress bar, or the last run's outcome (one line each, always there).
    fn progress_ui(&mut self, ui: &mut egui::Ui, ctx: &mut PanelContext<'_>) {
        if let Some(run) = &mut self.active {
            let running = ctx.app.torque_run;
            run.seen_running |= running;
            let elapsed_s = run.started.elapsed().as_secs_f64();
            let refusal = ctx.robot.last_refusal.as_ref().filter(|(id, _)| Some(*id) != run.refusal_before);
            let waited = run.started.elapsed() > START_GRACE + Duration::from_secs_f64(run.duration_s);
            if let Some((_, why)) = refusal.filter(|_| !run.seen_running) {
                // the simulation refused it (the app shows its refusal as a notice already)
                self.outcome = Some(format!("torque run refused: {why}"));
                self.active = None;
            } else if !running && (run.seen_running || waited) {
                let stopped = elapsed_s + 0.05 < run.duration_s;
                self.outcome = Some(outcome_text(ctx, &run.start_q, elapsed_s.min(run.duration_s), stopped));
                self.active = None;
            } else {
                let fraction = (elapsed_s / run.duration_s).clamp(0.0, 1.0);
                let text = format!("torque run: {elapsed_s:.1} of {:.1} s", run.duration_s);
                ui.add(crate::theme::bar(fraction as f32).text(text));
                ui.ctx().request_repaint_after(Duration::from_millis(100));
                return;
            }
        }
        if self.refused_for.is_some() && ctx.torque_run_refused() != self.refused_for {
            self.refused_for = None;
            self.outcome = None;
        }
        match &self.outcome {
            Some(text) => ui.label(text),
            None => ui.weak("no torque run yet"),
        };
    }
}

/// The end notice of a run: how long it ran, how far each joint turned, which ended at a limit.
fn outcome_text(ctx: &PanelContext<'_>, start_q: &[f64], ran_s: f64, stopped: bool) -> String {
    let unit = ctx.settings.unit;
    let names = ctx.model.joint_names();
    let moved: Vec<String> = start_q
        .iter()
        .zip(&ctx.robot.q)
        .enumerate()
        .map(|(i, (a, b))| {
            let d = b - a;
            let sign = if unit.from_rad(d) > 0.0 { "+" } else { "" };
            format!("{} {sign}{}", names.get(i).copied().unwrap_or("?"), unit.fmt(d))
        })
        .collect();
    let at_limit: Vec<&str> = ctx
        .model
        .limits
        .iter()
        .zip(&ctx.robot.q)
        .enumerate()
        .filter(|(_, (l, q))| (**q - l.min).abs() < 1e-3 || (l.max - **q).abs() < 1e-3)
        .map(|(i, _)| names.get(i).copied().unwrap_or("?"))
        .collect();
    let how = if stopped { format!("stopped after {ran_s:.1} s") } else { format!("done ({ran_s:.1} s)") };
    let limits = if at_limit.is_empty() { String::new() } else { format!("; at a limit: {}", at_limit.join(", ")) };
    format!("torque run {how}: {}{limits}; the motors hold there", moved.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_become_core_profiles_and_bad_ones_are_refused() {
        let mut form = TorqueForm::new(2);
        form.rows[0] = JointRow { shape: ProfileShape::Step, torque_nm: 0.5, second: -0.5, third: 1.0 };
        form.rows[1] = JointRow { shape: ProfileShape::Sine, torque_nm: 0.0, second: 0.2, third: 2.0 };
        let run = form.run().expect("valid");
        assert_eq!(run.joints[0], TorqueProfile::Step { before_nm: 0.5, after_nm: -0.5, at_s: 1.0 });
        assert_eq!(run.joints[1], TorqueProfile::Sine { offset_nm: 0.0, amplitude_nm: 0.2, period_s: 2.0 });
        form.rows[1].third = 0.0;
        assert!(form.run().expect_err("zero period").contains("joint 2"));
        form.rows[1].third = 2.0;
        form.duration_s = 0.0;
        assert!(form.run().is_err());
    }
}
